// SPDX-License-Identifier: BSD-3-Clause
#include "slodRetileCreases.h"

#include <algorithm>
#include <cmath>

namespace slod
{
namespace
{
// A slide walks at most this many segments (a move is a fraction of the spacing, but a fine
// input has many crease edges per spacing).
constexpr int MaximumSlideSegments = 4096;
} // namespace

CreasePolylines::CreasePolylines(const TriangleMesh& mesh, const std::vector<std::vector<Index>>& lineNeighbors)
  : Mesh(mesh)
{
  auto joined = [&](Index a, Index b) {
    const std::vector<Index>& n = lineNeighbors[a];
    return std::find(n.begin(), n.end(), b) != n.end();
  };
  std::unordered_map<std::uint64_t, Index> ids;
  for (Index t = 0; t < mesh.NumberOfTriangles() && !lineNeighbors.empty(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
      if (lineNeighbors[a].empty() || !joined(a, b))
      {
        continue;
      }
      auto inserted = ids.emplace(EdgeKey(a, b), static_cast<Index>(this->Segments.size()));
      if (inserted.second)
      {
        this->Segments.push_back(Segment{ { a, b }, { t, InvalidIndex } });
      }
      else
      {
        this->Segments[inserted.first->second].Triangles[1] = t;
      }
    }
  }
  // Border edges (one triangle) and non-manifold ones are not creases: renumber the others.
  std::vector<Index> renumbered(this->Segments.size(), InvalidIndex);
  std::vector<Segment> kept;
  for (size_t s = 0; s < this->Segments.size(); ++s)
  {
    if (this->Segments[s].Triangles[1] != InvalidIndex)
    {
      renumbered[s] = static_cast<Index>(kept.size());
      kept.push_back(this->Segments[s]);
    }
  }
  this->Segments.swap(kept);
  for (const auto& entry : ids)
  {
    const Index s = renumbered[entry.second];
    if (s == InvalidIndex)
    {
      continue;
    }
    for (Index t : this->Segments[s].Triangles)
    {
      const Index* tri = mesh.Triangle(t);
      auto sides = this->TriangleSides.emplace(t, std::array<Index, 3>{ InvalidIndex, InvalidIndex, InvalidIndex });
      for (int k = 0; k < 3; ++k)
      {
        if (EdgeKey(tri[(k + 1) % 3], tri[(k + 2) % 3]) == entry.first)
        {
          sides.first->second[k] = s;
        }
      }
    }
    this->VertexSegments[this->Segments[s].Ends[0]].push_back(s);
    this->VertexSegments[this->Segments[s].Ends[1]].push_back(s);
  }
}

Index CreasePolylines::SegmentAt(Index t, const Vec3& point, double tolerance) const
{
  const auto sides = this->TriangleSides.find(t);
  if (sides == this->TriangleSides.end())
  {
    return InvalidIndex;
  }
  const Index* tri = this->Mesh.Triangle(t);
  for (int k = 0; k < 3; ++k)
  {
    const Index s = sides->second[k];
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
  const auto at = this->VertexSegments.find(v);
  if (at == this->VertexSegments.end() || at->second.size() != 2)
  {
    return InvalidIndex;
  }
  return at->second[0] == s ? at->second[1] : at->second[0];
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
