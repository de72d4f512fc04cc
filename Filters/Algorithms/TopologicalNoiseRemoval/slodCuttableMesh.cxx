// SPDX-License-Identifier: BSD-3-Clause
#include "slodCuttableMesh.h"

#include "slodPolygonTriangulation.h"

#include <algorithm>
#include <numeric>

namespace slod
{
namespace
{
// True when the triangle holds the directed edge a -> b (counter-clockwise order).
bool HasDirectedEdge(const Index* tri, Index a, Index b)
{
  for (int k = 0; k < 3; ++k)
  {
    if (tri[k] == a && tri[(k + 1) % 3] == b)
    {
      return true;
    }
  }
  return false;
}

std::vector<std::uint64_t> SortedLoopEdges(const std::vector<Index>& loop)
{
  std::vector<std::uint64_t> keys(loop.size());
  for (size_t i = 0; i < loop.size(); ++i)
  {
    keys[i] = EdgeKey(loop[i], loop[(i + 1) % loop.size()]);
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}
} // namespace

// Per loop edge i (loop[i] -> loop[i + 1]): the triangle on its left (holding the directed edge)
// and the one on its right (holding the reverse).
struct CuttableMesh::LoopSides
{
  std::vector<Index> Left, Right;
};

CuttableMesh::CuttableMesh(TriangleMesh mesh)
  : Mesh(std::move(mesh))
{
  this->Base.Build(this->Mesh);
  this->LockAndIndex();
}

CuttableMesh::CuttableMesh(TriangleMesh mesh, MeshTopology topology)
  : Mesh(std::move(mesh))
  , Base(std::move(topology))
{
  this->LockAndIndex();
}

void CuttableMesh::LockAndIndex()
{
  this->BaseVertices = this->Mesh.NumberOfPoints();
  this->Locked.assign(size_t(this->BaseVertices), 0);
  this->HasOverlay.assign(size_t(this->BaseVertices), 0);
  for (Index v = 0; v < this->BaseVertices; ++v)
  {
    // Borders and non-manifold vertices are left alone: a loop through them has no two sides.
    if (this->Base.VertexDegree(v) == 0 || this->Base.IsBoundaryVertex(v) || this->Base.IsNonManifoldVertex(v))
    {
      this->Locked[v] = 1;
      ++this->LockedCount;
    }
  }
  this->VertexSource.resize(size_t(this->BaseVertices));
  std::iota(this->VertexSource.begin(), this->VertexSource.end(), 0);
  this->TriangleSource.resize(size_t(this->Mesh.NumberOfTriangles()));
  std::iota(this->TriangleSource.begin(), this->TriangleSource.end(), 0);
}

bool CuttableMesh::HasEdge(Index a, Index b) const
{
  bool found = false;
  this->ForEachTriangle(a, [&](Index t) { found = found || HasVertex(this->Triangle(t), b); });
  return found;
}

bool CuttableMesh::FindLoopSides(const std::vector<Index>& loop, LoopSides& sides) const
{
  const size_t n = loop.size();
  if (n < 3)
  {
    return false;
  }
  sides.Left.assign(n, InvalidIndex);
  sides.Right.assign(n, InvalidIndex);
  for (size_t i = 0; i < n; ++i)
  {
    const Index a = loop[i], b = loop[(i + 1) % n];
    if (this->IsLocked(a) || a == b)
    {
      return false;
    }
    int count = 0;
    this->ForEachTriangle(a, [&](Index t) {
      const Index* tri = this->Triangle(t);
      if (HasVertex(tri, b))
      {
        ++count;
        (HasDirectedEdge(tri, a, b) ? sides.Left[i] : sides.Right[i]) = t;
      }
    });
    if (count != 2 || sides.Left[i] == InvalidIndex || sides.Right[i] == InvalidIndex)
    {
      return false; // border, non-manifold or inconsistently oriented edge
    }
  }
  return true;
}

LoopSeparation CuttableMesh::TestSeparation(const std::vector<Index>& loop, Index budget) const
{
  LoopSides sides;
  if (!this->FindLoopSides(loop, sides))
  {
    return LoopSeparation::Invalid;
  }
  const std::vector<std::uint64_t> loopEdges = SortedLoopEdges(loop);
  this->VisitStamp.resize(size_t(this->NumberOfTriangles()), 0);
  this->VisitSide.resize(size_t(this->NumberOfTriangles()), 0);
  if (++this->Stamp == 0)
  {
    std::fill(this->VisitStamp.begin(), this->VisitStamp.end(), 0);
    this->Stamp = 1;
  }
  std::vector<Index> queue[2];
  const std::vector<Index>* seeds[2] = { &sides.Left, &sides.Right };
  for (unsigned char s = 0; s < 2; ++s)
  {
    for (Index t : *seeds[s])
    {
      if (this->VisitStamp[t] == this->Stamp && this->VisitSide[t] != s)
      {
        return LoopSeparation::Invalid; // one triangle on both sides: not a cut
      }
      if (this->VisitStamp[t] != this->Stamp)
      {
        this->VisitStamp[t] = this->Stamp;
        this->VisitSide[t] = s;
        queue[s].push_back(t);
      }
    }
  }
  // Both sides advance one triangle in turn, so the work is about twice the smaller search. A
  // triangle is queued at most once (its stamp), so neither side pops more than every triangle.
  size_t head[2] = { 0, 0 };
  for (Index round = 0; round <= this->NumberOfTriangles(); ++round)
  {
    for (unsigned char s = 0; s < 2; ++s)
    {
      if (head[s] == queue[s].size())
      {
        return LoopSeparation::Separating; // this side is closed off by the loop
      }
      if (static_cast<Index>(queue[s].size()) > budget)
      {
        return LoopSeparation::Undetermined;
      }
      const Index t = queue[s][head[s]++];
      const Index* tri = this->Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        const Index a = tri[k], b = tri[(k + 1) % 3];
        if (std::binary_search(loopEdges.begin(), loopEdges.end(), EdgeKey(a, b)))
        {
          continue;
        }
        bool met = false;
        this->ForEachTriangleAcross(t, a, b, [&](Index u) {
          if (this->VisitStamp[u] != this->Stamp)
          {
            this->VisitStamp[u] = this->Stamp;
            this->VisitSide[u] = s;
            queue[s].push_back(u);
          }
          met = met || this->VisitSide[u] != s;
        });
        if (met)
        {
          return LoopSeparation::NonSeparating;
        }
      }
    }
  }
  return LoopSeparation::Undetermined; // not reached: a side runs out of triangles first
}

// The triangles around loop[i] on the loop's right: a flood through the vertex's fan from
// `start` that never crosses the loop's two edges there. False when it reaches a triangle on the
// left (`avoid`), i.e. the vertex does not split into two sides.
bool CuttableMesh::RightFan(const std::vector<Index>& loop, size_t i, Index start, Index avoid,
  std::vector<Index>& fan) const
{
  const size_t n = loop.size();
  const Index v = loop[i], previous = loop[(i + n - 1) % n], next = loop[(i + 1) % n];
  fan.assign(1, start);
  const Index limit = this->Base.NumberOfTriangles() + this->NumberOfTriangles(); // bounds the flood
  for (size_t k = 0; k < fan.size() && static_cast<Index>(fan.size()) < limit; ++k)
  {
    const Index* tri = this->Triangle(fan[k]);
    for (int c = 0; c < 3; ++c)
    {
      const Index w = tri[c];
      if (w == v || w == previous || w == next)
      {
        continue;
      }
      bool ok = true;
      this->ForEachTriangleAcross(fan[k], v, w, [&](Index u) {
        ok = ok && u != avoid;
        if (std::find(fan.begin(), fan.end(), u) == fan.end())
        {
          fan.push_back(u);
        }
      });
      if (!ok)
      {
        return false;
      }
    }
  }
  return true;
}

std::vector<Index>& CuttableMesh::EditableTriangles(Index v)
{
  if (v < this->BaseVertices && !this->HasOverlay[v])
  {
    this->HasOverlay[v] = 1;
    this->Overlay[v].assign(this->Base.VertexTrianglesBegin(v), this->Base.VertexTrianglesEnd(v));
  }
  return this->Overlay[v];
}

bool CuttableMesh::CutAndFill(const std::vector<Index>& loop, std::vector<Index>& changed)
{
  LoopSides sides;
  if (!this->FindLoopSides(loop, sides))
  {
    return false;
  }
  const size_t n = loop.size();
  std::vector<std::vector<Index>> fans(n);
  for (size_t i = 0; i < n; ++i)
  {
    // The fan must reach the right triangle of the previous edge and none of the left ones.
    if (!this->RightFan(loop, i, sides.Right[i], sides.Left[i], fans[i]) ||
      std::find(fans[i].begin(), fans[i].end(), sides.Left[(i + n - 1) % n]) != fans[i].end() ||
      std::find(fans[i].begin(), fans[i].end(), sides.Right[(i + n - 1) % n]) == fans[i].end())
    {
      return false;
    }
  }
  // Left triangles hold loop[i] -> loop[i + 1], so the left fill runs the loop backwards; the
  // right triangles hold the reverse, so the right fill runs it forwards (over the copies).
  std::vector<Index> backwards(loop.rbegin(), loop.rend());
  std::vector<std::array<Index, 3>> leftFill, rightFill;
  const bool leftClipped = this->PlanFill(backwards, leftFill), rightClipped = this->PlanFill(loop, rightFill);
  std::vector<Index> copies(n);
  for (size_t i = 0; i < n; ++i)
  {
    const Index v = loop[i];
    copies[i] = this->Mesh.AddPoint(this->Point(v));
    this->VertexSource.push_back(this->VertexSource[v]);
    std::vector<Index>& around = this->EditableTriangles(v);
    for (Index t : fans[i])
    {
      around.erase(std::remove(around.begin(), around.end(), t), around.end());
      Index* tri = &this->Mesh.Triangles[3 * size_t(t)];
      std::replace(tri, tri + 3, v, copies[i]);
    }
    this->Overlay[copies[i]] = fans[i];
  }
  if (!leftClipped)
  {
    leftFill = this->CentreFan(backwards);
  }
  if (!rightClipped)
  {
    rightFill = this->CentreFan(copies);
  }
  this->CentreFans += (leftClipped ? 0 : 1) + (rightClipped ? 0 : 1);
  this->AddFill(backwards, leftFill, sides.Left[0]);
  this->AddFill(copies, rightFill, sides.Right[0]);
  changed = backwards;
  changed.insert(changed.end(), copies.begin(), copies.end());
  return true;
}

// Ear clipping of the loop (polygon: mesh vertices in order). Before the cut the mesh joins two
// loop vertices when either side will, so refusing every existing edge as a diagonal is safe for
// both sides' fills. False when no such triangulation is found.
bool CuttableMesh::PlanFill(const std::vector<Index>& polygon, std::vector<std::array<Index, 3>>& fill) const
{
  std::vector<Vec3> points;
  for (Index v : polygon)
  {
    points.push_back(this->Point(v));
  }
  PolygonTriangulationOptions options;
  options.AcceptEar = [&](Index previous, Index, Index next) { return !this->HasEdge(polygon[previous], polygon[next]); };
  options.AllowFallback = false;
  PolygonTriangulationResult result = TriangulatePolygon(points, PolygonNormal(points), options);
  fill = std::move(result.Triangles);
  return !result.Failed;
}

// When ear clipping finds no disk (a loop far from planar, or whose diagonals are all edges
// already): a fan around a new vertex at the loop's centroid, which can join no existing edge.
// Appends that vertex to `polygon` (it copies the data of the loop vertex nearest to it).
std::vector<std::array<Index, 3>> CuttableMesh::CentreFan(std::vector<Index>& polygon)
{
  Vec3 centre{ 0, 0, 0 };
  for (Index v : polygon)
  {
    centre = centre + (1.0 / polygon.size()) * this->Point(v);
  }
  Index nearest = polygon[0];
  for (Index v : polygon)
  {
    nearest = Norm(this->Point(v) - centre) < Norm(this->Point(nearest) - centre) ? v : nearest;
  }
  const Index n = static_cast<Index>(polygon.size());
  polygon.push_back(this->Mesh.AddPoint(centre));
  this->VertexSource.push_back(this->VertexSource[nearest]);
  this->Overlay[polygon.back()];
  std::vector<std::array<Index, 3>> fan;
  for (Index i = 0; i < n; ++i)
  {
    fan.push_back({ i, (i + 1) % n, n });
  }
  return fan;
}

void CuttableMesh::AddFill(const std::vector<Index>& polygon, const std::vector<std::array<Index, 3>>& fill, Index source)
{
  for (const auto& corners : fill)
  {
    const Index a = polygon[corners[0]], b = polygon[corners[1]], c = polygon[corners[2]];
    const Index t = this->Mesh.AddTriangle(a, b, c);
    this->TriangleSource.push_back(this->TriangleSource[source]);
    for (Index v : { a, b, c })
    {
      this->EditableTriangles(v).push_back(t);
    }
  }
}
} // namespace slod
