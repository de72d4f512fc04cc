// SPDX-License-Identifier: BSD-3-Clause
#include "slodRetileCreases.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace slod
{
namespace
{
// A slide walks at most this many segments (a move is a fraction of the spacing, but a fine
// input has many crease edges per spacing).
constexpr int MaximumSlideSegments = 4096;
} // namespace

CreasePolylines::CreasePolylines(
  const TriangleMesh& mesh, const MeshTopology& topology, const std::vector<std::vector<Index>>& lineNeighbors)
  : Mesh(mesh)
{
  this->TriangleSideSlot.assign(size_t(mesh.NumberOfTriangles()), InvalidIndex);
  this->VertexOffsets.assign(size_t(mesh.NumberOfPoints()) + 1, 0);
  auto joined = [&](Index a, Index b) {
    const std::vector<Index>& n = lineNeighbors[a];
    return std::find(n.begin(), n.end(), b) != n.end();
  };
  const bool haveLines = static_cast<Index>(lineNeighbors.size()) >= mesh.NumberOfPoints();
  for (Index e = 0; haveLines && e < topology.NumberOfEdges(); ++e)
  {
    const Index a = topology.EdgeVertex(e, 0), b = topology.EdgeVertex(e, 1);
    // Two triangles exactly: a border edge has one side, a non-manifold one no single pair.
    if (topology.EdgeTriangleCount(e) != 2 || lineNeighbors[a].empty() || !joined(a, b))
    {
      continue;
    }
    const Index s = static_cast<Index>(this->Segments.size());
    const Index* triangles = topology.EdgeTrianglesBegin(e);
    this->Segments.push_back(Segment{ { a, b }, { triangles[0], triangles[1] } });
    for (int i = 0; i < 2; ++i)
    {
      const Index t = triangles[i];
      if (this->TriangleSideSlot[t] == InvalidIndex)
      {
        this->TriangleSideSlot[t] = static_cast<Index>(this->TriangleSides.size());
        this->TriangleSides.push_back({ InvalidIndex, InvalidIndex, InvalidIndex });
      }
      // The topology's edge j joins corners j and j + 1: it is the side opposite corner j + 2.
      for (int j = 0; j < 3; ++j)
      {
        if (topology.TriangleEdge(t, j) == e)
        {
          this->TriangleSides[this->TriangleSideSlot[t]][(j + 2) % 3] = s;
        }
      }
    }
    ++this->VertexOffsets[a + 1];
    ++this->VertexOffsets[b + 1];
  }
  std::partial_sum(this->VertexOffsets.begin(), this->VertexOffsets.end(), this->VertexOffsets.begin());
  this->VertexSegments.resize(size_t(this->VertexOffsets.back()));
  std::vector<Index> filled(this->VertexOffsets.begin(), this->VertexOffsets.end() - 1);
  for (Index s = 0; s < this->NumberOfSegments(); ++s)
  {
    for (Index v : this->Segments[s].Ends)
    {
      this->VertexSegments[filled[v]++] = s;
    }
  }
}

Index CreasePolylines::SegmentAt(Index t, const Vec3& point, double tolerance) const
{
  const Index slot = t >= 0 && t < static_cast<Index>(this->TriangleSideSlot.size()) ? this->TriangleSideSlot[t] : InvalidIndex;
  if (slot == InvalidIndex)
  {
    return InvalidIndex;
  }
  const std::array<Index, 3>& sides = this->TriangleSides[slot];
  const Index* tri = this->Mesh.Triangle(t);
  for (int k = 0; k < 3; ++k)
  {
    const Index s = sides[k];
    if (s == InvalidIndex)
    {
      continue;
    }
    const Vec3 b = this->Mesh.Point(tri[(k + 1) % 3]), c = this->Mesh.Point(tri[(k + 2) % 3]);
    const double corner = Norm(Cross(c - b, this->Mesh.Point(tri[k]) - b));
    const double along = Dot(point - b, c - b) / Dot(c - b, c - b);
    if (along >= -tolerance && along <= 1 + tolerance && Norm(Cross(c - b, point - b)) <= tolerance * corner)
    {
      return s;
    }
  }
  return InvalidIndex;
}

Index CreasePolylines::Continuation(Index s, Index v) const
{
  const Index first = this->VertexOffsets[v];
  if (this->VertexOffsets[v + 1] - first != 2)
  {
    return InvalidIndex; // a line's end or a junction
  }
  return this->VertexSegments[first] == s ? this->VertexSegments[first + 1] : this->VertexSegments[first];
}

ClosestPointResult CreasePolylines::Slide(Index s, const Vec3& position, const Vec3& displacement, const Vec3& facing) const
{
  const Segment* segment = &this->Segments[s];
  const Vec3 direction = Normalized(this->Mesh.Point(segment->Ends[1]) - this->Mesh.Point(segment->Ends[0]));
  const double along = Dot(displacement, direction);
  int end = along >= 0 ? 1 : 0;
  double remaining = std::fabs(along);
  Vec3 p = position;
  for (int step = 0; step < MaximumSlideSegments; ++step)
  {
    const Vec3 target = this->Mesh.Point(segment->Ends[end]);
    const double toEnd = Norm(target - p);
    if (remaining <= toEnd)
    {
      p = p + (toEnd > 0 ? remaining / toEnd : 0.0) * (target - p);
      break;
    }
    remaining -= toEnd;
    p = target;
    const Index v = segment->Ends[end];
    const Index next = this->Continuation(s, v);
    if (next == InvalidIndex)
    {
      break; // a corner: the vertex stops there
    }
    s = next;
    segment = &this->Segments[s];
    end = segment->Ends[0] == v ? 1 : 0;
  }
  ClosestPointResult result;
  result.Point = p;
  result.Distance2 = Dot(p - position, p - position);
  const Vec3 n0 = this->Mesh.TriangleAreaVector(segment->Triangles[0]);
  const Vec3 n1 = this->Mesh.TriangleAreaVector(segment->Triangles[1]);
  result.Triangle =
    Dot(Normalized(n0), facing) >= Dot(Normalized(n1), facing) ? segment->Triangles[0] : segment->Triangles[1];
  return result;
}
} // namespace slod
