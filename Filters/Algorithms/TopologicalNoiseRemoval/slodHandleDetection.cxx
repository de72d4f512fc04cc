// SPDX-License-Identifier: BSD-3-Clause
#include "slodHandleDetection.h"

#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <array>
#include <functional>
#include <limits>
#include <utility>

namespace slod
{
void GeodesicRegion::Reset(const CuttableMesh& mesh)
{
  for (Index v : this->TouchedVertices)
  {
    this->State[v] = 0;
  }
  this->TouchedVertices.clear();
  this->Heap.Clear();
  const size_t points = size_t(mesh.NumberOfPoints());
  this->Heap.Reserve(static_cast<Index>(points));
  if (this->State.size() < points)
  {
    this->State.resize(points, 0);
    this->Dist.resize(points, 0.0);
    this->Parent.resize(points, InvalidIndex);
  }
}

template <typename Settle>
Index GeodesicRegion::Grow(const CuttableMesh& mesh, const std::vector<Index>& sources, double radius,
  Index maximumSettled, Settle&& settle)
{
  this->Reset(mesh);
  auto queue = [&](Index w, double d, Index parent) {
    if (!(this->State[w] & QueuedFlag))
    {
      this->State[w] |= QueuedFlag;
      this->TouchedVertices.push_back(w);
    }
    else if (d >= this->Dist[w])
    {
      return;
    }
    this->Dist[w] = d;
    this->Parent[w] = parent;
    this->Heap.Set(w, d);
  };
  for (Index s : sources)
  {
    if (!mesh.IsLocked(s))
    {
      queue(s, 0.0, InvalidIndex);
    }
  }
  Index settled = 0;
  while (!this->Heap.Empty() && settled < maximumSettled)
  {
    const double distance = this->Heap.TopKey();
    if (distance > radius)
    {
      break;
    }
    const Index v = this->Heap.Pop();
    this->State[v] |= SettledFlag;
    ++settled;
    if (!settle(v))
    {
      break;
    }
    const Vec3 p = mesh.Point(v);
    mesh.ForEachTriangle(v, [&](Index t) {
      for (int k = 0; k < 3; ++k)
      {
        const Index w = mesh.Triangle(t)[k];
        if (w != v && !mesh.IsLocked(w) && !this->Settled(w))
        {
          queue(w, distance + Norm(mesh.Point(w) - p), v);
        }
      }
    });
  }
  return settled;
}

// v's link (its neighbours in counter-clockwise order) splits into arcs of settled neighbours
// (nearer to the seed) and unsettled ones. One settled arc: the region grows across v as a disk
// does. Two or more: two parts of the front meet at v (a saddle of the distance), which closes a
// cycle. Returns a settled neighbour on another arc than v's parent, or InvalidIndex.
Index GeodesicRegion::FrontMeeting(const CuttableMesh& mesh, Index v)
{
  const Index parent = this->Parent[v];
  if (parent == InvalidIndex)
  {
    return InvalidIndex;
  }
  // Nearly every settled vertex has one arc: count the arcs first and store the link only at a
  // meeting (this runs for every vertex of every region).
  auto farEdge = [v](const Index* tri) {
    const int k = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    return std::make_pair(tri[(k + 1) % 3], tri[(k + 2) % 3]);
  };
  int arcs = 0;
  mesh.ForEachTriangle(v, [&](Index t) {
    const std::pair<Index, Index> edge = farEdge(mesh.Triangle(t));
    arcs += (!this->Settled(edge.first) && this->Settled(edge.second)) ? 1 : 0;
  });
  if (arcs < 2)
  {
    return InvalidIndex;
  }
  this->Link.clear();
  mesh.ForEachTriangle(v, [&](Index t) { this->Link.push_back(farEdge(mesh.Triangle(t))); });
  // Mark the parent's arc by walking the link both ways from it (at most its length each way).
  auto step = [&](Index from, bool forward) {
    for (const auto& edge : this->Link)
    {
      if ((forward ? edge.first : edge.second) == from)
      {
        return forward ? edge.second : edge.first;
      }
    }
    return InvalidIndex;
  };
  this->ParentArc.assign(1, parent);
  for (bool forward : { true, false })
  {
    Index w = step(parent, forward);
    for (size_t n = 0; n < this->Link.size() && w != InvalidIndex && w != parent && this->Settled(w); ++n)
    {
      this->ParentArc.push_back(w);
      w = step(w, forward);
    }
  }
  for (const auto& edge : this->Link)
  {
    const Index w = edge.first;
    if (this->Settled(w) && std::find(this->ParentArc.begin(), this->ParentArc.end(), w) == this->ParentArc.end())
    {
      return w;
    }
  }
  return InvalidIndex;
}

// The cycle of the shortest-path tree closed by the edge (a, b): a's path up to the paths'
// common vertex and down b's path.
bool GeodesicRegion::LoopThrough(Index a, Index b, const CuttableMesh& mesh, CandidateLoop& loop) const
{
  std::vector<Index> upFromA, upFromB;
  for (Index v = a; v != InvalidIndex; v = this->Parent[v])
  {
    upFromA.push_back(v);
  }
  for (Index v = b; v != InvalidIndex; v = this->Parent[v])
  {
    upFromB.push_back(v);
  }
  Index common = InvalidIndex;
  while (!upFromA.empty() && !upFromB.empty() && upFromA.back() == upFromB.back())
  {
    common = upFromA.back();
    upFromA.pop_back();
    upFromB.pop_back();
  }
  if (common == InvalidIndex || upFromA.size() + upFromB.size() < 2)
  {
    return false;
  }
  loop.Vertices = upFromA;
  loop.Vertices.push_back(common);
  loop.Vertices.insert(loop.Vertices.end(), upFromB.rbegin(), upFromB.rend());
  loop.Length = this->Dist[a] + this->Dist[b] - 2.0 * this->Dist[common] + Norm(mesh.Point(a) - mesh.Point(b));
  return true;
}

void GeodesicRegion::FindLoops(
  const CuttableMesh& mesh, Index seed, const RegionGrowthLimits& limits, std::vector<CandidateLoop>& loops)
{
  int found = 0;
  this->Grow(mesh, { seed }, limits.Radius, limits.MaximumSettled, [&](Index v) {
    const Index other = this->FrontMeeting(mesh, v);
    CandidateLoop loop;
    if (other != InvalidIndex && this->LoopThrough(v, other, mesh, loop) && loop.Length <= limits.MaximumLoopLength)
    {
      loops.push_back(std::move(loop));
      ++found;
    }
    return found < limits.MaximumLoops;
  });
}

std::vector<Index> CoveringSeeds(const CuttableMesh& mesh, double spacing)
{
  std::vector<unsigned char> covered(size_t(mesh.NumberOfPoints()), 0);
  std::vector<Index> seeds;
  GeodesicRegion region;
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    if (covered[v] || mesh.IsLocked(v))
    {
      continue;
    }
    seeds.push_back(v);
    region.Grow(mesh, { v }, spacing, mesh.NumberOfPoints(), [&](Index w) {
      covered[w] = 1;
      return true;
    });
  }
  return seeds;
}

namespace
{
// vtkSMPTools functor: each thread grows its regions in its own GeodesicRegion; results are stored
// per seed, so they do not depend on the scheduling.
struct CandidateSearch
{
  const CuttableMesh& Mesh;
  const std::vector<Index>& Seeds;
  const RegionGrowthLimits& Limits;
  std::vector<std::vector<CandidateLoop>>& Loops;
  vtkSMPThreadLocal<GeodesicRegion> Regions;

  void Initialize() {}
  void operator()(vtkIdType begin, vtkIdType end)
  {
    GeodesicRegion& region = this->Regions.Local();
    for (vtkIdType i = begin; i < end; ++i)
    {
      region.FindLoops(this->Mesh, this->Seeds[i], this->Limits, this->Loops[i]);
    }
  }
  void Reduce() {}
};
} // namespace

std::vector<std::vector<CandidateLoop>> FindCandidateLoops(
  const CuttableMesh& mesh, const std::vector<Index>& seeds, const RegionGrowthLimits& limits)
{
  std::vector<std::vector<CandidateLoop>> loops(seeds.size());
  CandidateSearch search{ mesh, seeds, limits, loops, {} };
  vtkSMPTools::For(0, static_cast<vtkIdType>(seeds.size()), 64, search);
  return loops;
}

std::vector<Index> SeedsNear(
  const CuttableMesh& mesh, const std::vector<Index>& seeds, const std::vector<Index>& changed, double radius)
{
  std::vector<unsigned char> near(size_t(mesh.NumberOfPoints()), 0);
  GeodesicRegion region;
  region.Grow(mesh, changed, radius, mesh.NumberOfPoints(), [&](Index v) {
    near[v] = 1;
    return true;
  });
  std::vector<Index> result;
  for (Index s : seeds)
  {
    if (near[s])
    {
      result.push_back(s);
    }
  }
  return result;
}
} // namespace slod
