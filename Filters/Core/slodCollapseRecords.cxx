// SPDX-License-Identifier: BSD-3-Clause
#include "slodCollapseRecords.h"

#include "slodEditableMesh.h"

#include <algorithm>
#include <cassert>

namespace slod
{
void CollapseRecord::Clear()
{
  this->Vertices = { InvalidIndex, InvalidIndex, InvalidIndex };
  this->VertexCount = 0;
  this->Kept = InvalidIndex;
  this->RemovedTriangles.clear();
  this->ChangedTriangles.clear();
  this->ChangedCorner.clear();
  this->ChangedFrom.clear();
}

void CollapseRecords::Clear()
{
  CollapseRecords empty;
  empty.StorePositions = this->StorePositions;
  empty.StoreRemovedTriangleVertices = this->StoreRemovedTriangleVertices;
  empty.StoreSurrounding = this->StoreSurrounding;
  *this = std::move(empty);
}

void CollapseRecords::Reserve(size_t collapses, size_t removed, size_t changed)
{
  this->Vertices.reserve(3 * collapses);
  if (this->StorePositions)
  {
    this->OldPositions.reserve(9 * collapses);
    this->NewPositions.reserve(3 * collapses);
  }
  this->RemovedOffsets.reserve(collapses + 1);
  this->RemovedTriangles.reserve(removed);
  if (this->StoreRemovedTriangleVertices)
  {
    this->RemovedTriangleVertices.reserve(3 * removed);
  }
  this->ChangedOffsets.reserve(collapses + 1);
  this->ChangedTriangles.reserve(changed);
  this->ChangedCodes.reserve(changed);
}

void CollapseRecords::Append(
  const CollapseRecord& record, const EditableMesh& mesh, const Index* vertexId, const Index* triangleId,
  const std::vector<Index>* surrounding)
{
  auto vertex = [vertexId](Index v) { return vertexId ? vertexId[v] : v; };
  auto triangle = [triangleId](Index t) { return triangleId ? triangleId[t] : t; };
  const Index removed = static_cast<Index>(record.RemovedTriangles.size());
  const Index changed = static_cast<Index>(record.ChangedTriangles.size());
  this->AppendRoom(1, &removed, &changed);
  this->Write(this->NumberOfCollapses() - 1, record, mesh, vertex, triangle);
  if (this->StoreSurrounding)
  {
    if (surrounding)
    {
      for (Index w : *surrounding)
      {
        this->Surrounding.push_back(vertex(w));
      }
    }
    this->SurroundingOffsets.push_back(static_cast<Index>(this->Surrounding.size()));
  }
}

void CollapseRecords::AppendRoom(size_t n, const Index* removed, const Index* changed)
{
  const size_t collapses = size_t(this->NumberOfCollapses()) + n;
  this->Vertices.resize(3 * collapses);
  if (this->StorePositions)
  {
    this->OldPositions.resize(9 * collapses);
    this->NewPositions.resize(3 * collapses);
  }
  for (size_t i = 0; i < n; ++i)
  {
    this->RemovedOffsets.push_back(this->RemovedOffsets.back() + removed[i]);
    this->ChangedOffsets.push_back(this->ChangedOffsets.back() + changed[i]);
  }
  this->RemovedTriangles.resize(size_t(this->RemovedOffsets.back()));
  if (this->StoreRemovedTriangleVertices)
  {
    this->RemovedTriangleVertices.resize(3 * size_t(this->RemovedOffsets.back()));
  }
  this->ChangedTriangles.resize(size_t(this->ChangedOffsets.back()));
  this->ChangedCodes.resize(size_t(this->ChangedOffsets.back()));
}

void CollapseRecords::SetAt(Index k, const CollapseRecord& record, const EditableMesh& mesh)
{
  this->Write(k, record, mesh, [](Index v) { return v; }, [](Index t) { return t; });
}

template <typename VertexId, typename TriangleId>
void CollapseRecords::Write(
  Index k, const CollapseRecord& record, const EditableMesh& mesh, VertexId&& vertex, TriangleId&& triangle)
{
  // Kept vertex first; an edge collapse has no third vertex (-1, zero position).
  int order[3] = { 0, 1, 2 };
  for (int i = 0; i < record.VertexCount; ++i)
  {
    if (record.Vertices[i] == record.Kept)
    {
      std::swap(order[0], order[i]);
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    const bool has = order[i] < record.VertexCount;
    this->Vertices[3 * size_t(k) + i] = has ? vertex(record.Vertices[order[i]]) : InvalidIndex;
    if (this->StorePositions)
    {
      const Vec3 p = has ? record.OldPositions[order[i]] : Vec3{ 0, 0, 0 };
      std::copy(p.begin(), p.end(), this->OldPositions.begin() + 9 * size_t(k) + 3 * i);
    }
  }
  if (this->StorePositions)
  {
    std::copy(record.NewPosition.begin(), record.NewPosition.end(), this->NewPositions.begin() + 3 * size_t(k));
  }
  size_t r = size_t(this->RemovedOffsets[k]);
  for (Index t : record.RemovedTriangles)
  {
    this->RemovedTriangles[r] = triangle(t);
    if (this->StoreRemovedTriangleVertices)
    {
      const Index* tri = mesh.Triangle(t);
      for (int j = 0; j < 3; ++j)
      {
        this->RemovedTriangleVertices[3 * r + j] = vertex(tri[j]);
      }
    }
    ++r;
  }
  const size_t c = size_t(this->ChangedOffsets[k]);
  for (size_t i = 0; i < record.ChangedTriangles.size(); ++i)
  {
    this->ChangedTriangles[c + i] = triangle(record.ChangedTriangles[i]);
    this->ChangedCodes[c + i] =
      static_cast<unsigned char>(record.ChangedCorner[i] | PositionOf(record.ChangedFrom[i], record, order) << 2);
  }
}

// The position in the stored vertices (kept first: order) of a merged vertex.
int CollapseRecords::PositionOf(Index v, const CollapseRecord& record, const int* order)
{
  for (int i = 0; i < record.VertexCount; ++i)
  {
    if (record.Vertices[order[i]] == v)
    {
      return i;
    }
  }
  assert(false && "a redirected corner held one of the merged vertices");
  return 0;
}

bool CollapseRecords::AppendChanged(Index triangle, int corner, Index from)
{
  const size_t k = this->Vertices.size() / 3 - 1;
  for (int i = 0; i < 3 && !this->Vertices.empty(); ++i)
  {
    if (this->Vertices[3 * k + i] == from && from != InvalidIndex && corner >= 0 && corner < 3)
    {
      this->ChangedTriangles.push_back(triangle);
      this->ChangedCodes.push_back(static_cast<unsigned char>(corner | i << 2));
      return true;
    }
  }
  return false;
}

void CollapseRecords::AppendFlip(const FlipRecord& flip)
{
  this->Flips.push_back(flip);
  this->FlipStamps.push_back(this->NumberOfCollapses());
}

std::pair<Index, Index> CollapseRecords::FlipsAfter(Index k) const
{
  const auto range = std::equal_range(this->FlipStamps.begin(), this->FlipStamps.end(), k + 1);
  return { static_cast<Index>(range.first - this->FlipStamps.begin()),
    static_cast<Index>(range.second - this->FlipStamps.begin()) };
}

void CollapseRecords::Get(Index k, CollapseRecord& record) const
{
  record.VertexCount = this->VertexCount(k);
  record.Kept = this->Kept(k);
  record.Vertices = { InvalidIndex, InvalidIndex, InvalidIndex };
  for (int i = 0; i < record.VertexCount; ++i)
  {
    record.Vertices[i] = this->Vertices[3 * size_t(k) + i];
    if (this->StorePositions)
    {
      const double* p = &this->OldPositions[9 * size_t(k) + 3 * i];
      record.OldPositions[i] = { p[0], p[1], p[2] };
    }
  }
  if (this->StorePositions)
  {
    const double* q = &this->NewPositions[3 * size_t(k)];
    record.NewPosition = { q[0], q[1], q[2] };
  }
  record.RemovedTriangles.assign(this->RemovedTriangles.begin() + this->RemovedOffsets[k],
    this->RemovedTriangles.begin() + this->RemovedOffsets[k + 1]);
  const Index c0 = this->ChangedOffsets[k], c1 = this->ChangedOffsets[k + 1];
  record.ChangedTriangles.assign(this->ChangedTriangles.begin() + c0, this->ChangedTriangles.begin() + c1);
  record.ChangedCorner.clear();
  record.ChangedFrom.clear();
  for (Index c = c0; c < c1; ++c)
  {
    record.ChangedCorner.push_back(static_cast<unsigned char>(this->ChangedCorner(size_t(c))));
    record.ChangedFrom.push_back(this->ChangedFrom(k, size_t(c)));
  }
}

void CollapseRecords::UndoFlipsAfter(Index k, EditableMesh& mesh) const
{
  const auto range = this->FlipsAfter(k);
  for (Index f = range.second; f > range.first; --f) // newest first
  {
    mesh.Undo(this->Flips[size_t(f - 1)]);
  }
}

void CollapseRecords::RedoFlipsAfter(Index k, EditableMesh& mesh) const
{
  const auto range = this->FlipsAfter(k);
  for (Index f = range.first; f < range.second; ++f)
  {
    mesh.FlipEdge(this->Flips[size_t(f)].X, this->Flips[size_t(f)].Y);
  }
}

void CollapseRecords::Undo(Index k, EditableMesh& mesh, CollapseRecord& record) const
{
  this->UndoFlipsAfter(k, mesh);
  this->Get(k, record);
  mesh.Undo(record);
}

void CollapseRecords::Redo(Index k, EditableMesh& mesh, CollapseRecord& record) const
{
  this->Get(k, record);
  mesh.Collapse(record.Vertices.data(), record.VertexCount, record.Kept, record.NewPosition);
  this->RedoFlipsAfter(k, mesh);
}

size_t CollapseRecords::MemoryBytes() const
{
  return (this->Vertices.capacity() + this->RemovedOffsets.capacity() + this->RemovedTriangles.capacity() +
           this->RemovedTriangleVertices.capacity() + this->ChangedOffsets.capacity() +
           this->ChangedTriangles.capacity() + this->SurroundingOffsets.capacity() +
           this->Surrounding.capacity() + this->FlipStamps.capacity()) *
    sizeof(Index) +
    this->ChangedCodes.capacity() + this->Flips.capacity() * sizeof(FlipRecord) +
    (this->OldPositions.capacity() + this->NewPositions.capacity()) * sizeof(double);
}
} // namespace slod
