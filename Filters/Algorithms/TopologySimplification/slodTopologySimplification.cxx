// SPDX-License-Identifier: BSD-3-Clause
#include "slodTopologySimplification.h"

#include "slodMeshTopology.h"
#include "slodPolygonTriangulation.h"
#include "slodSpbmFinalCollapses.h"
#include "slodStageClock.h"
#include "slodUnionFind.h"

#include "vtkMath.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <memory>
#include <cmath>
#include <functional>
#include <numeric>
#include <unordered_set>

namespace slod
{
namespace
{
// Internal progress report: the fraction done -> true when the run is aborted (the inverse of the
// public ProgressFunction, so that stages read `if (aborted(f)) return`).
using AbortCheck = std::function<bool(double)>;

// Circumscribed circle diameter of a triangle (infinite when collinear).
double CircumDiameter(const Vec3& a, const Vec3& b, const Vec3& c)
{
  const double ab = Norm(b - a), bc = Norm(c - b), ca = Norm(a - c);
  const double twiceArea = Norm(Cross(b - a, c - a));
  return twiceArea > 0 ? ab * bc * ca / twiceArea : HUGE_VAL;
}

// A sharp chain oriented for traversal.
struct Oriented
{
  Index Chain;
  bool Reversed;
};

} // namespace

double EstimateLoopDiameter(const TriangleMesh& mesh, const std::vector<Index>& loop)
{
  const size_t n = loop.size();
  if (n < 2)
  {
    return 0.0;
  }
  // Evenly spaced samples: pairs half a loop apart (the convex case) and triples a third apart
  // (circumscribed circle); a few rotations so that the estimate does not hinge on the start.
  double diameter = 0.0, circle = 0.0;
  const size_t rotations = std::min<size_t>(n, 4);
  for (size_t r = 0; r < rotations; ++r)
  {
    const size_t i = r * n / (2 * rotations);
    const Vec3 a = mesh.Point(loop[i]);
    diameter = std::max(diameter, Norm(mesh.Point(loop[(i + n / 2) % n]) - a));
    if (n >= 3)
    {
      circle = std::max(circle, CircumDiameter(a, mesh.Point(loop[(i + n / 3) % n]), mesh.Point(loop[(i + 2 * n / 3) % n])));
    }
  }
  // The circle of a near-collinear triple overshoots (slots): cap by the bounding box.
  Vec3 lo = mesh.Point(loop[0]), hi = lo;
  for (Index v : loop)
  {
    const Vec3 p = mesh.Point(v);
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  return std::min(std::max(diameter, circle), Norm(hi - lo));
}

namespace
{
// The arrays of a detection pass sized by the surface (topology, patchification, normals), kept
// across the passes and the clean-up merge and rebuilt within their capacity: above glibc's mmap
// threshold (32 MB, a 4M-triangle scan's) an array allocated afresh is a new mapping, faulted in
// page by page, and every pass paid that again (session 35: 0.57 minor faults per input triangle
// at 4M against 0.30 at 1M).
struct DetectionWorkspace
{
  MeshTopology Topology;
  Patchification Patches;
  std::vector<Vec3> Normal;
  // Passes after the first whose normals or patchification needed more room than the passes
  // before (an array allocated anew): none while the later surfaces are no larger (tests assert it).
  Index Allocations = 0;
  // Topology already indexes the surface of the next pass (the caller's topology of the input,
  // or the previous pass's topology updated to its cleaned surface).
  bool TopologyCurrent = false;
  // Topology work of the passes: triangles of their whole builds plus the local incidences of
  // their updates (MeshTopologyUpdateWork::LocalIncidences); the last pass's update of the
  // cleaned surface apart.
  std::int64_t TopologyTriangles = 0;
  std::int64_t CleanedTopologyWork = 0;
  bool LastSurfaceKept = false; // the last pass left its surface as it found it
  size_t Bytes() const { return this->Normal.capacity() * sizeof(Vec3) + this->Patches.MemoryUsage(); }
};

// The whole run as one object: every stage is a member working on the shared arrays.
struct Simplification
{
  const TriangleMesh& Mesh;
  const TopologySimplificationParameters& P;
  TopologySimplificationResult& R;
  MeshTopology& Topology; // the run's DetectionWorkspace's
  Patchification& Patches;
  std::vector<Vec3>& Normal; // unit triangle normals

  // Sharp chains: vertices [Offset[c], Offset[c+1]); edge i of chain c (between vertices i and
  // i+1) has left triangle EdgeLeft[Offset[c] + i] and right triangle EdgeRight[...].
  std::vector<Index> Offset{ 0 }, Vertex, EdgeLeft, EdgeRight, Left, Right;
  std::vector<Vec3> LeftNormal, RightNormal; // length-weighted average normals along the chain
  std::vector<signed char> FlatLeft;          // 1 left, 0 right, -1 undetermined
  std::vector<unsigned char> Type, Convex, InLoop, Done;
  std::vector<Index> IncidenceOffset, Incidence; // per vertex: 2*chain + end
  std::vector<unsigned char> PatchChainSharp;    // per chain of the patchification
  // Per patch: the sharp chains on its boundary (CSR), so that a loop's partner search visits the
  // chains of its wall patches instead of every chain; per sharp chain: the loop it is part of
  // (a chain joins at most one loop: searches skip chains InLoop).
  std::vector<Index> PatchSharpOffset, PatchSharp, ChainLoop;
  std::vector<unsigned char> InWall; // per patch, cleared after each partner search
  // A partner search's wall patches, their sharp chains and the loops on them (reused per loop).
  std::vector<Index> WallScratch, WallChainScratch, OnWallScratch;
  std::vector<std::vector<Oriented>> LoopChains;

  std::vector<Index> ComponentSize;   // triangles per component
  std::vector<Index> Forbidden;       // per vertex: stamp of the loop whose partner is searched
  std::vector<unsigned char> Removed; // per triangle
  std::vector<Index> FillTriangles;   // 3 per triangle
  std::vector<Index> FillPatch;       // per fill triangle: index of its fill polygon
  std::vector<unsigned char> FillKind;
  Index FillPolygons = 0;
  std::unordered_set<std::uint64_t> FillEdges;
  std::vector<std::uint64_t> FillEdgeLog; // insertion order, to roll a feature back

  Simplification(const TriangleMesh& mesh, const TopologySimplificationParameters& p, TopologySimplificationResult& r,
    DetectionWorkspace& workspace)
    : Mesh(mesh)
    , P(p)
    , R(r)
    , Topology(workspace.Topology)
    , Patches(workspace.Patches)
    , Normal(workspace.Normal)
  {
    if (!workspace.TopologyCurrent)
    {
      this->Topology.Build(mesh);
      workspace.TopologyTriangles += mesh.NumberOfTriangles();
    }
    else
    {
      this->Topology.Rebind(mesh); // the same triangles, in the pass's copy
    }
    workspace.TopologyCurrent = false;
  }

  Index NumberOfChains() const { return static_cast<Index>(this->Left.size()); }
  Index Size(Index c) const { return this->Offset[c + 1] - this->Offset[c]; }
  Index At(const Oriented& o, Index i) const
  {
    return o.Reversed ? this->Vertex[this->Offset[o.Chain + 1] - 1 - i] : this->Vertex[this->Offset[o.Chain] + i];
  }
  Index First(const Oriented& o) const { return this->At(o, 0); }
  Index Last(const Oriented& o) const { return this->At(o, this->Size(o.Chain) - 1); }
  const Vec3& LeftOf(const Oriented& o) const
  {
    return o.Reversed ? this->RightNormal[o.Chain] : this->LeftNormal[o.Chain];
  }
  const Vec3& RightOf(const Oriented& o) const
  {
    return o.Reversed ? this->LeftNormal[o.Chain] : this->RightNormal[o.Chain];
  }
  Index LeftPatchOf(const Oriented& o) const { return o.Reversed ? this->Right[o.Chain] : this->Left[o.Chain]; }
  Index RightPatchOf(const Oriented& o) const { return o.Reversed ? this->Left[o.Chain] : this->Right[o.Chain]; }
  // Triangle on the left / right of edge i of an oriented chain.
  Index LeftTriangle(const Oriented& o, Index i) const
  {
    const Index e = o.Reversed ? this->Offset[o.Chain + 1] - 2 - i : this->Offset[o.Chain] + i;
    return o.Reversed ? this->EdgeRight[e] : this->EdgeLeft[e];
  }
  Index RightTriangle(const Oriented& o, Index i) const
  {
    const Index e = o.Reversed ? this->Offset[o.Chain + 1] - 2 - i : this->Offset[o.Chain] + i;
    return o.Reversed ? this->EdgeLeft[e] : this->EdgeRight[e];
  }

  // The triangles left and right of the directed edge a -> b (InvalidIndex when missing).
  void EdgeSides(Index a, Index b, Index& left, Index& right) const
  {
    left = right = InvalidIndex;
    const Index e = this->Topology.FindEdge(a, b);
    if (e == InvalidIndex || this->Topology.EdgeTriangleCount(e) != 2)
    {
      return;
    }
    for (const Index* t = this->Topology.EdgeTrianglesBegin(e); t != this->Topology.EdgeTrianglesEnd(e); ++t)
    {
      const Index* tri = this->Mesh.Triangle(*t);
      bool forward = false;
      for (int k = 0; k < 3; ++k)
      {
        forward = forward || (tri[k] == a && tri[(k + 1) % 3] == b);
      }
      (forward ? left : right) = *t;
    }
  }

  // --- 2. Sharp edges and sharp chains ---
  void BuildSharpChains()
  {
    const Index nt = this->Mesh.NumberOfTriangles();
    this->Normal.resize(size_t(nt));
    for (Index t = 0; t < nt; ++t)
    {
      this->Normal[t] = Normalized(this->Mesh.TriangleAreaVector(t));
    }
    const Patchification& pa = this->Patches;
    this->PatchChainSharp.assign(size_t(pa.NumberOfChains()), 0);
    for (Index c = 0; c < pa.NumberOfChains(); ++c)
    {
      if (pa.ChainRightPatch(c) == InvalidIndex || pa.ChainIsNonManifold(c))
      {
        continue;
      }
      const Index* v = pa.ChainVerticesBegin(c);
      const Index n = pa.ChainSize(c);
      bool open = false;
      for (Index i = 0; i + 1 < n; ++i)
      {
        Index lt, rt;
        this->EdgeSides(v[i], v[i + 1], lt, rt);
        bool sharp = false;
        if (lt != InvalidIndex && rt != InvalidIndex)
        {
          const double d = Dot(this->Normal[lt], this->Normal[rt]);
          sharp = d > this->P.SharpMinimumDot && d < this->P.SharpMaximumDot;
        }
        if (sharp)
        {
          ++this->R.SharpEdges;
          this->PatchChainSharp[c] = 1;
          if (!open)
          {
            this->Vertex.push_back(v[i]);
            this->Left.push_back(pa.ChainLeftPatch(c));
            this->Right.push_back(pa.ChainRightPatch(c));
            open = true;
          }
          // Edge slot = position of its first vertex.
          this->EdgeLeft.resize(this->Vertex.size());
          this->EdgeRight.resize(this->Vertex.size());
          this->EdgeLeft.back() = lt;
          this->EdgeRight.back() = rt;
          this->Vertex.push_back(v[i + 1]);
        }
        if (open && (!sharp || i + 2 == n))
        {
          this->Offset.push_back(static_cast<Index>(this->Vertex.size()));
          open = false;
        }
      }
    }
    this->EdgeLeft.resize(this->Vertex.size(), InvalidIndex);
    this->EdgeRight.resize(this->Vertex.size(), InvalidIndex);
    const Index nc = this->NumberOfChains();
    this->R.SharpChains = nc;
    this->LeftNormal.assign(size_t(nc), Vec3{ 0, 0, 0 });
    this->RightNormal.assign(size_t(nc), Vec3{ 0, 0, 0 });
    for (Index c = 0; c < nc; ++c)
    {
      for (Index e = this->Offset[c]; e + 1 < this->Offset[c + 1]; ++e)
      {
        const double length = Norm(this->Mesh.Point(this->Vertex[e + 1]) - this->Mesh.Point(this->Vertex[e]));
        this->LeftNormal[c] = this->LeftNormal[c] + length * this->Normal[this->EdgeLeft[e]];
        this->RightNormal[c] = this->RightNormal[c] + length * this->Normal[this->EdgeRight[e]];
      }
      this->LeftNormal[c] = Normalized(this->LeftNormal[c]);
      this->RightNormal[c] = Normalized(this->RightNormal[c]);
    }
    // Incidence of chain ends on vertices (CSR).
    const Index nv = this->Mesh.NumberOfPoints();
    this->IncidenceOffset.assign(size_t(nv) + 1, 0);
    for (Index c = 0; c < nc; ++c)
    {
      ++this->IncidenceOffset[this->Vertex[this->Offset[c]] + 1];
      ++this->IncidenceOffset[this->Vertex[this->Offset[c + 1] - 1] + 1];
    }
    for (Index v = 0; v < nv; ++v)
    {
      this->IncidenceOffset[v + 1] += this->IncidenceOffset[v];
    }
    this->Incidence.resize(size_t(this->IncidenceOffset[nv]));
    std::vector<Index> fill(this->IncidenceOffset.begin(), this->IncidenceOffset.end() - 1);
    for (Index c = 0; c < nc; ++c)
    {
      this->Incidence[fill[this->Vertex[this->Offset[c]]]++] = 2 * c;
      this->Incidence[fill[this->Vertex[this->Offset[c + 1] - 1]]++] = 2 * c + 1;
    }
    this->BuildPatchSharpChains();
  }

  // PatchSharpOffset / PatchSharp: the sharp chains with the patch on their left or right.
  void BuildPatchSharpChains()
  {
    const Index np = this->Patches.NumberOfPatches();
    const Index nc = this->NumberOfChains();
    this->PatchSharpOffset.assign(size_t(np) + 1, 0);
    auto sides = [&](Index c) { return std::array<Index, 2>{ this->Left[c], this->Right[c] }; };
    for (Index c = 0; c < nc; ++c)
    {
      for (Index p : sides(c))
      {
        this->PatchSharpOffset[size_t(p) + 1] += p != InvalidIndex ? 1 : 0;
      }
    }
    std::partial_sum(this->PatchSharpOffset.begin(), this->PatchSharpOffset.end(), this->PatchSharpOffset.begin());
    this->PatchSharp.resize(size_t(this->PatchSharpOffset[np]));
    std::vector<Index> next(this->PatchSharpOffset.begin(), this->PatchSharpOffset.end() - 1);
    for (Index c = 0; c < nc; ++c)
    {
      for (Index p : sides(c))
      {
        if (p != InvalidIndex)
        {
          this->PatchSharp[next[p]++] = c;
        }
      }
    }
    this->ChainLoop.assign(size_t(nc), InvalidIndex);
    this->InWall.assign(size_t(np), 0);
  }

  // --- 3. Flat and wall sides (5.3.1) ---
  // Unit normal of the plane through the first non-collinear consecutive triple of `points`.
  bool PlaneNormal(const std::vector<Index>& points, Vec3& normal) const
  {
    for (size_t i = 0; i + 2 < points.size(); ++i)
    {
      const Vec3 a = this->Mesh.Point(points[i]), b = this->Mesh.Point(points[i + 1]),
                 c = this->Mesh.Point(points[i + 2]);
      const Vec3 n = Cross(b - a, c - b);
      if (Norm(n) > 0.1 * Norm(b - a) * Norm(c - b)) // not within ~6 degrees of collinear
      {
        normal = Normalized(n);
        return true;
      }
    }
    return false;
  }

  // Flat side from the plane normal and the two sides' normals: the closer one, when decisive.
  static signed char Side(const Vec3& plane, const Vec3& left, const Vec3& right)
  {
    const double l = std::fabs(Dot(plane, left)), r = std::fabs(Dot(plane, right));
    if (std::max(l, r) < 0.9 || std::fabs(l - r) < 0.2)
    {
      return -1;
    }
    return l > r ? 1 : 0;
  }

  // Which side of each sharp chain is flat (FlatLeft: 1 left, 0 right, -1 open), its type and
  // whether it is a convex hole chain.
  void ClassifySides()
  {
    const Index nc = this->NumberOfChains();
    this->FlatLeft.assign(size_t(nc), -1);
    this->Type.assign(size_t(nc), 2);
    this->Convex.assign(size_t(nc), 0);
    std::vector<Index> points;
    for (Index c = 0; c < nc; ++c)
    {
      this->ClassifyByOwnPlane(c, points);
      if (this->FlatLeft[c] < 0)
      {
        this->ClassifyByNeighbours(c, points);
      }
    }
  }

  // Type (1): the first three (else the last three) vertices span a plane.
  void ClassifyByOwnPlane(Index c, std::vector<Index>& points)
  {
    const Index b = this->Offset[c], n = this->Size(c);
    for (int attempt = 0; attempt < 2 && this->FlatLeft[c] < 0 && n >= 3; ++attempt)
    {
      const Index s = attempt == 0 ? b : b + n - 3;
      points.assign(this->Vertex.begin() + s, this->Vertex.begin() + s + 3);
      Vec3 plane;
      if (!this->PlaneNormal(points, plane))
      {
        continue;
      }
      const Vec3 left = Normalized(this->Normal[this->EdgeLeft[s]] + this->Normal[this->EdgeLeft[s + 1]]);
      const Vec3 right = Normalized(this->Normal[this->EdgeRight[s]] + this->Normal[this->EdgeRight[s + 1]]);
      this->FlatLeft[c] = Side(plane, left, right);
      if (this->FlatLeft[c] >= 0)
      {
        this->Type[c] = 1;
        // Convex hole chain: it turns toward the wall side, seen along the flat normal.
        const Vec3 flat = this->FlatLeft[c] ? left : right;
        const double turn = Dot(Cross(this->Mesh.Point(points[1]) - this->Mesh.Point(points[0]),
                                  this->Mesh.Point(points[2]) - this->Mesh.Point(points[1])),
          flat);
        this->Convex[c] = this->FlatLeft[c] ? turn < 0 : turn > 0;
      }
    }
  }

  void ClassifyByNeighbours(Index c, std::vector<Index>& points)
  {
    const Index b = this->Offset[c], n = this->Size(c);
    // Type (2): continue with the sharp chains incident on either end, one by one. Each
    // combination that spans a plane votes for a side; when they disagree (at a corner of a
    // square hole the wall's vertical edge spans the wall plane) the combinations that make
    // the chain a convex hole chain decide (the paper's preference), else it stays open.
    int votes[2][2] = { { 0, 0 }, { 0, 0 } }; // [side][convex]
    for (int end = 0; end < 2; ++end)
    {
      const Index v = end == 0 ? this->Vertex[b] : this->Vertex[b + n - 1];
      for (Index k = this->IncidenceOffset[v]; k < this->IncidenceOffset[v + 1]; ++k)
      {
        const Index other = this->Incidence[k] / 2;
        if (other == c)
        {
          continue;
        }
        const Oriented away{ other, (this->Incidence[k] & 1) != 0 };
        points.clear();
        // This chain toward v, then the other chain away from v.
        for (Index i = 0; i < n; ++i)
        {
          points.push_back(end == 1 ? this->Vertex[b + i] : this->Vertex[b + n - 1 - i]);
        }
        for (Index i = 1; i < this->Size(other); ++i)
        {
          points.push_back(this->At(away, i));
        }
        Vec3 plane;
        if (!this->PlaneNormal(points, plane))
        {
          continue;
        }
        const signed char side = Side(plane, this->LeftNormal[c], this->RightNormal[c]);
        if (side < 0)
        {
          continue;
        }
        // Turn at the junction, seen along the flat normal, in traversal order.
        const Vec3 a = this->Mesh.Point(points[n - 2]), m = this->Mesh.Point(points[n - 1]),
                   z = this->Mesh.Point(points[n]);
        const Vec3 flat = side ? this->LeftNormal[c] : this->RightNormal[c];
        const double turn = Dot(Cross(m - a, z - m), flat);
        const bool flatOnTraversalLeft = (end == 1) == (side == 1);
        const bool convex = flatOnTraversalLeft ? turn < 0 : turn > 0;
        ++votes[side][convex ? 1 : 0];
      }
    }
    const int left = votes[1][0] + votes[1][1], right = votes[0][0] + votes[0][1];
    if (left > 0 && right == 0)
    {
      this->FlatLeft[c] = 1;
      this->Convex[c] = votes[1][1] > 0;
    }
    else if (right > 0 && left == 0)
    {
      this->FlatLeft[c] = 0;
      this->Convex[c] = votes[0][1] > 0;
    }
    else if ((votes[1][1] > 0) != (votes[0][1] > 0))
    {
      this->FlatLeft[c] = votes[1][1] > 0 ? 1 : 0;
      this->Convex[c] = 1;
    }
  }

  // --- 4. Loop search ---
  // Depth-first extension of `seed` (flat side on its left) into a closed loop of sharp chains,
  // avoiding chains in loops, vertices in `forbidden` (stamp == forbiddenStamp). `explored` gets
  // every chain tried. Returns the loop's chains or an empty vector.
  std::vector<Index> VertexStamp;
  Index Stamp = 0;
  std::vector<unsigned char> InSequence;

  // One level of the depth-first search: the chains that may follow `current`, best first, are
  // Candidates[Next, End) of the search's candidate stack (one stack for every level and search:
  // no allocation per step; a level's candidates, from Begin, are dropped with the level).
  struct SearchFrame
  {
    size_t Begin = 0, Next = 0, End = 0;
  };
  std::vector<Oriented> Candidates;
  std::vector<SearchFrame> Frames;
  std::vector<std::pair<double, Oriented>> Scored;
  bool Blocked(Index v, Index stamp, const std::vector<Index>* forbidden, Index forbiddenStamp) const
  {
    return this->VertexStamp[v] == stamp || (forbidden && (*forbidden)[v] == forbiddenStamp);
  }
  // A chain closing the loop ends on `start`, which is stamped: allowed only as the last vertex.
  // Candidates keep the flat side on the left and continue it (score: alignment, +2 on the
  // same flat patch).
  SearchFrame Continuations(const Oriented& current, Index start, Index stamp, const std::vector<Index>* forbidden,
    Index forbiddenStamp)
  {
    std::vector<std::pair<double, Oriented>>& scored = this->Scored;
    scored.clear();
    const Index v = this->Last(current);
    for (Index k = this->IncidenceOffset[v]; k < this->IncidenceOffset[v + 1]; ++k)
    {
      const Index c = this->Incidence[k] / 2;
      if (this->InSequence[c] || this->InLoop[c])
      {
        continue;
      }
      const Oriented o{ c, (this->Incidence[k] & 1) != 0 };
      if (this->FlatLeft[c] >= 0 && (this->FlatLeft[c] == 1) == o.Reversed)
      {
        continue; // its flat side would be on the right
      }
      bool free = true;
      for (Index i = 1; i + 1 < this->Size(c) && free; ++i)
      {
        free = !this->Blocked(this->At(o, i), stamp, forbidden, forbiddenStamp);
      }
      const Index last = this->Last(o);
      if (!free || (last != start && this->Blocked(last, stamp, forbidden, forbiddenStamp)))
      {
        continue;
      }
      const double along = Dot(this->LeftOf(o), this->LeftOf(current));
      if (along < 0.5 || Dot(this->LeftOf(o), this->LeftOf(current)) <= Dot(this->RightOf(o), this->LeftOf(current)))
      {
        continue; // the flat side does not continue
      }
      const double score = along + (this->LeftPatchOf(o) == this->LeftPatchOf(current) ? 2.0 : 0.0);
      scored.emplace_back(score, o);
    }
    std::stable_sort(scored.begin(), scored.end(),
      [](const std::pair<double, Oriented>& a, const std::pair<double, Oriented>& b) { return a.first > b.first; });
    SearchFrame frame;
    frame.Begin = frame.Next = this->Candidates.size();
    for (const auto& candidate : scored)
    {
      this->Candidates.push_back(candidate.second);
    }
    frame.End = this->Candidates.size();
    return frame;
  }

  std::vector<Oriented> Search(const Oriented& seed, const std::vector<Index>* forbidden, Index forbiddenStamp,
    std::vector<Index>& explored)
  {
    std::vector<Oriented> sequence{ seed };
    std::vector<SearchFrame>& frames = this->Frames;
    frames.clear();
    this->Candidates.clear();
    ++this->Stamp;
    const Index stamp = this->Stamp;
    const Index start = this->First(seed);
    auto occupy = [&](const Oriented& o, Index value) {
      for (Index i = 1; i < this->Size(o.Chain); ++i)
      {
        this->VertexStamp[this->At(o, i)] = value;
      }
      this->InSequence[o.Chain] = value == stamp;
    };
    this->VertexStamp[start] = stamp;
    occupy(seed, stamp);
    explored.push_back(seed.Chain);
    auto candidates = [&](const Oriented& current) {
      return this->Continuations(current, start, stamp, forbidden, forbiddenStamp);
    };
    frames.push_back(candidates(seed));
    int budget = 4096;
    bool closed = this->Last(seed) == start;
    while (!closed && !frames.empty() && budget-- > 0)
    {
      SearchFrame& top = frames.back();
      if (top.Next >= top.End)
      {
        this->Candidates.resize(top.Begin);
        frames.pop_back();
        occupy(sequence.back(), 0);
        sequence.pop_back();
        if (sequence.empty())
        {
          break;
        }
        continue;
      }
      const Oriented next = this->Candidates[top.Next++];
      sequence.push_back(next);
      explored.push_back(next.Chain);
      if (this->Last(next) == start)
      {
        closed = true;
        break;
      }
      occupy(next, stamp);
      frames.push_back(candidates(next));
    }
    for (const Oriented& o : sequence)
    {
      this->InSequence[o.Chain] = 0;
    }
    if (!closed || sequence.empty())
    {
      return {};
    }
    // A loop needs at least three distinct vertices.
    Index vertices = 0;
    for (const Oriented& o : sequence)
    {
      vertices += this->Size(o.Chain) - 1;
    }
    if (vertices < 3)
    {
      return {};
    }
    return sequence;
  }

  Index AddLoop(const std::vector<Oriented>& chains)
  {
    SharpLoop loop;
    Vec3 flat{ 0, 0, 0 };
    for (const Oriented& o : chains)
    {
      this->InLoop[o.Chain] = 1;
      for (Index i = 0; i + 1 < this->Size(o.Chain); ++i)
      {
        loop.Vertices.push_back(this->At(o, i));
        const double length = Norm(this->Mesh.Point(this->At(o, i + 1)) - this->Mesh.Point(this->At(o, i)));
        flat = flat + length * this->Normal[this->LeftTriangle(o, i)];
      }
    }
    std::vector<Vec3> polygon;
    for (Index v : loop.Vertices)
    {
      polygon.push_back(this->Mesh.Point(v));
    }
    loop.Clockwise = Dot(PolygonNormal(polygon), flat) < 0;
    loop.Diameter = EstimateLoopDiameter(this->Mesh, loop.Vertices);
    this->R.Loops.push_back(std::move(loop));
    this->LoopChains.push_back(chains);
    const Index index = static_cast<Index>(this->R.Loops.size()) - 1;
    for (const Oriented& o : chains)
    {
      this->ChainLoop[o.Chain] = index;
    }
    return index;
  }

  void FindLoops()
  {
    const Index nc = this->NumberOfChains();
    this->InLoop.assign(size_t(nc), 0);
    this->Done.assign(size_t(nc), 0);
    this->InSequence.assign(size_t(nc), 0);
    this->VertexStamp.assign(size_t(this->Mesh.NumberOfPoints()), 0);
    // Seeds: convex type (1) chains, then other type (1) chains, then type (2) ones.
    std::vector<Index> order;
    for (Index c = 0; c < nc; ++c)
    {
      if (this->FlatLeft[c] >= 0)
      {
        order.push_back(c);
      }
    }
    auto rank = [&](Index c) { return (this->Type[c] == 1 ? 0 : 2) + (this->Convex[c] ? 0 : 1); };
    std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return rank(a) < rank(b); });
    std::vector<Index> explored;
    for (Index c : order)
    {
      if (this->InLoop[c] || this->Done[c])
      {
        continue;
      }
      explored.clear();
      const std::vector<Oriented> loop = this->Search({ c, this->FlatLeft[c] == 0 }, nullptr, 0, explored);
      if (loop.empty())
      {
        for (Index e : explored)
        {
          this->Done[e] = 1; // never a start again (may still extend other searches)
        }
        continue;
      }
      this->AddLoop(loop);
    }
  }

  // --- 5. Partner loops (5.3.2) ---
  // The wall patches of loop l, marked in InWall (the caller clears them): right of l, plus those
  // joined to them by non-sharp chains (at most about 512).
  void WallPatches(Index l, std::vector<Index>& wall)
  {
    const Patchification& pa = this->Patches;
    std::vector<unsigned char>& inWall = this->InWall;
    wall.clear();
    for (const Oriented& o : this->LoopChains[l])
    {
      const Index p = this->RightPatchOf(o);
      if (p != InvalidIndex && !inWall[p])
      {
        inWall[p] = 1;
        wall.push_back(p);
      }
    }
    for (size_t i = 0; i < wall.size() && wall.size() < 512; ++i)
    {
      for (const Index* c = pa.PatchChainsBegin(wall[i]); c != pa.PatchChainsEnd(wall[i]); ++c)
      {
        if (this->PatchChainSharp[*c])
        {
          continue;
        }
        for (Index q : { pa.ChainLeftPatch(*c), pa.ChainRightPatch(*c) })
        {
          if (q != InvalidIndex && !inWall[q])
          {
            inWall[q] = 1;
            wall.push_back(q);
          }
        }
      }
    }
  }

  // The sharp chains with a wall patch on either side, in increasing order (the order in which
  // a scan over every chain would meet them: the partner found does not depend on the index).
  void WallChains(const std::vector<Index>& wall, std::vector<Index>& chains) const
  {
    chains.clear();
    for (Index p : wall)
    {
      chains.insert(chains.end(), this->PatchSharp.begin() + this->PatchSharpOffset[p],
        this->PatchSharp.begin() + this->PatchSharpOffset[p + 1]);
    }
    std::sort(chains.begin(), chains.end());
    chains.erase(std::unique(chains.begin(), chains.end()), chains.end());
  }

  // A new loop seeded by a sharp chain of the wall patches that avoids the forbidden vertices.
  Index SearchPartner(const std::vector<Index>& wallChains, Index forbiddenStamp)
  {
    const std::vector<Index>& forbidden = this->Forbidden;
    std::vector<Index> explored;
    for (Index c : wallChains)
    {
      if (this->InLoop[c] || this->FlatLeft[c] < 0)
      {
        continue;
      }
      bool touches = false;
      for (Index i = this->Offset[c]; i < this->Offset[c + 1]; ++i)
      {
        touches = touches || forbidden[this->Vertex[i]] == forbiddenStamp;
      }
      if (touches)
      {
        continue;
      }
      explored.clear();
      const std::vector<Oriented> loop = this->Search({ c, this->FlatLeft[c] == 0 }, &forbidden, forbiddenStamp, explored);
      if (!loop.empty())
      {
        return this->AddLoop(loop);
      }
    }
    return InvalidIndex;
  }

  // The loop that bounds the other end of l's wall: among the loops already found (clockwise
  // ones first: holes before bumps), else a new search over the wall's sharp chains. Only the
  // chains of the wall patches are visited (not every chain and loop: that made the detection
  // quadratic in the number of loops on noisy scans).
  Index FindPartner(Index l)
  {
    std::vector<Index>& wall = this->WallScratch;
    this->WallPatches(l, wall);
    std::vector<Index>& wallChains = this->WallChainScratch;
    this->WallChains(wall, wallChains);
    for (Index p : wall)
    {
      this->InWall[p] = 0;
    }
    // Vertices of L are forbidden in the partner.
    ++this->Stamp;
    const Index forbiddenStamp = this->Stamp;
    std::vector<Index>& forbidden = this->Forbidden;
    forbidden.resize(size_t(this->Mesh.NumberOfPoints()), 0);
    for (Index v : this->R.Loops[l].Vertices)
    {
      forbidden[v] = forbiddenStamp;
    }
    auto disjoint = [&](Index other) {
      for (Index v : this->R.Loops[other].Vertices)
      {
        if (forbidden[v] == forbiddenStamp)
        {
          return false;
        }
      }
      return true;
    };
    // The loops on the wall: those with a chain on a wall patch.
    std::vector<Index>& onWall = this->OnWallScratch;
    onWall.clear();
    for (Index c : wallChains)
    {
      if (this->ChainLoop[c] != InvalidIndex)
      {
        onWall.push_back(this->ChainLoop[c]);
      }
    }
    std::sort(onWall.begin(), onWall.end());
    onWall.erase(std::unique(onWall.begin(), onWall.end()), onWall.end());
    this->R.PartnerSearchWork += static_cast<std::int64_t>(wallChains.size() + onWall.size());
    // First among the loops already found, clockwise ones first (holes before bumps).
    Index best = InvalidIndex;
    for (Index other : onWall)
    {
      if (other == l || this->R.Loops[other].Feature != InvalidIndex || !disjoint(other))
      {
        continue;
      }
      if (best == InvalidIndex || (this->R.Loops[other].Clockwise && !this->R.Loops[best].Clockwise))
      {
        best = other;
      }
    }
    return best != InvalidIndex ? best : this->SearchPartner(wallChains, forbiddenStamp);
  }

  // --- 6. Wall region and removal ---
  // Triangles reached from the wall side of `loop` without crossing the barrier edges; empty
  // when the region leaks (reaches a flat-side triangle, the border, a non-manifold edge, an
  // already removed triangle) or is not the smaller part of its component.
  std::unordered_set<std::uint64_t> BarrierEdges(const std::vector<Index>& barrierLoops) const
  {
    std::unordered_set<std::uint64_t> barrier;
    for (Index b : barrierLoops)
    {
      const std::vector<Index>& v = this->R.Loops[b].Vertices;
      for (size_t i = 0; i < v.size(); ++i)
      {
        barrier.insert(EdgeKey(v[i], v[(i + 1) % v.size()]));
      }
    }
    return barrier;
  }

  // Marks the flat-side triangles of the barrier loops with 2 (listed in flatSide).
  void MarkFlatSide(const std::vector<Index>& barrierLoops, std::vector<unsigned char>& mark, std::vector<Index>& flatSide) const
  {
    for (Index b : barrierLoops)
    {
      for (const Oriented& o : this->LoopChains[b])
      {
        for (Index i = 0; i + 1 < this->Size(o.Chain); ++i)
        {
          const Index t = this->LeftTriangle(o, i);
          if (!mark[t])
          {
            mark[t] = 2;
            flatSide.push_back(t);
          }
        }
      }
    }
  }

  bool WallRegion(Index loop, const std::vector<Index>& barrierLoops, std::vector<Index>& region,
    std::vector<unsigned char>& mark, std::string& reason)
  {
    region.clear();
    const std::unordered_set<std::uint64_t> barrier = this->BarrierEdges(barrierLoops);
    // Flat-side triangles of the barrier loops: 2; region: 1.
    std::vector<Index> flatSide;
    this->MarkFlatSide(barrierLoops, mark, flatSide);
    bool ok = true;
    for (const Oriented& o : this->LoopChains[loop])
    {
      for (Index i = 0; i + 1 < this->Size(o.Chain) && ok; ++i)
      {
        const Index t = this->RightTriangle(o, i);
        if (mark[t] == 2)
        {
          ok = false;
          reason = "the wall touches the flat side";
        }
        else if (!mark[t])
        {
          mark[t] = 1;
          region.push_back(t);
        }
      }
    }
    if (this->ComponentSize.empty())
    {
      this->ComponentSize.assign(size_t(this->Topology.NumberOfComponents()), 0);
      for (Index c : this->Topology.TriangleComponents())
      {
        ++this->ComponentSize[c];
      }
    }
    const Index componentSize = region.empty() ? 0 : this->ComponentSize[this->Topology.TriangleComponents()[region[0]]];
    for (size_t i = 0; i < region.size() && ok; ++i)
    {
      const Index t = region[i];
      if (this->Removed[t])
      {
        ok = false;
        reason = "overlaps a removed feature";
        break;
      }
      const Index* tri = this->Mesh.Triangle(t);
      for (int k = 0; k < 3 && ok; ++k)
      {
        if (barrier.count(EdgeKey(tri[k], tri[(k + 1) % 3])))
        {
          continue;
        }
        const Index n = this->Topology.EdgeNeighbor(t, k);
        if (n == InvalidIndex)
        {
          ok = false;
          reason = "the wall reaches the mesh border or a non-manifold edge";
        }
        else if (mark[n] == 2)
        {
          ok = false;
          reason = "the wall region is not closed by the loops";
        }
        else if (!mark[n])
        {
          mark[n] = 1;
          region.push_back(n);
        }
      }
      if (2 * static_cast<Index>(region.size()) > componentSize)
      {
        ok = false;
        reason = "the wall region is not the smaller side of its component";
      }
    }
    for (Index t : region)
    {
      mark[t] = 0;
    }
    for (Index t : flatSide)
    {
      mark[t] = 0;
    }
    if (!ok)
    {
      region.clear();
    }
    return ok;
  }

  // Whether the flat sides of loops a and b stay connected over the patches outside `region`
  // (and outside removed features): removing the tube between them then lowers the genus instead
  // of splitting the surface. Breadth-first over the patch graph, stopping when b is reached.
  std::vector<Index> PatchStamp;
  std::vector<unsigned char> PatchRemoved;
  bool JoinedWithout(Index a, Index b, const std::vector<Index>& region)
  {
    const Patchification& pa = this->Patches;
    const std::vector<Index>& patchOf = pa.TrianglePatches();
    ++this->Stamp;
    const Index blocked = this->Stamp;
    for (Index t : region)
    {
      this->PatchStamp[patchOf[t]] = blocked;
    }
    ++this->Stamp;
    const Index goal = this->Stamp;
    for (const Oriented& o : this->LoopChains[b])
    {
      const Index p = this->LeftPatchOf(o);
      if (this->PatchStamp[p] != blocked)
      {
        this->PatchStamp[p] = goal;
      }
    }
    ++this->Stamp;
    const Index seen = this->Stamp;
    std::vector<Index> queue;
    for (const Oriented& o : this->LoopChains[a])
    {
      const Index p = this->LeftPatchOf(o);
      if (this->PatchStamp[p] == goal)
      {
        return true;
      }
      if (this->PatchStamp[p] != blocked && this->PatchStamp[p] != seen && !this->PatchRemoved[p])
      {
        this->PatchStamp[p] = seen;
        queue.push_back(p);
      }
    }
    for (size_t i = 0; i < queue.size(); ++i)
    {
      for (const Index* c = pa.PatchChainsBegin(queue[i]); c != pa.PatchChainsEnd(queue[i]); ++c)
      {
        for (Index q : { pa.ChainLeftPatch(*c), pa.ChainRightPatch(*c) })
        {
          if (q == InvalidIndex || this->PatchRemoved[q] || this->PatchStamp[q] == blocked || this->PatchStamp[q] == seen)
          {
            continue;
          }
          if (this->PatchStamp[q] == goal)
          {
            return true;
          }
          this->PatchStamp[q] = seen;
          queue.push_back(q);
        }
      }
    }
    return false;
  }

  // Ear clipping of a polygon (already in the orientation of the new triangles) as a new patch;
  // refuses diagonals that are edges of the kept surface or of earlier fills and non-simple
  // projections. On success the triangles are appended to the fill list.
  bool Fill(const std::vector<Index>& polygon, const Vec3& normal, unsigned char kind,
    const std::function<bool(Index, Index)>& edgeExists)
  {
    std::vector<Vec3> points;
    for (Index v : polygon)
    {
      points.push_back(this->Mesh.Point(v));
    }
    PolygonTriangulationOptions options;
    options.AllowFallback = false;
    options.AcceptEar = [&](Index a, Index, Index c) {
      const Index u = polygon[a], w = polygon[c];
      return !edgeExists(u, w) && !this->FillEdges.count(EdgeKey(u, w));
    };
    const PolygonTriangulationResult triangulation = TriangulatePolygon(points, normal, options);
    if (triangulation.Failed || triangulation.UsedFallback ||
      triangulation.Triangles.size() + 2 != polygon.size())
    {
      return false;
    }
    for (const auto& t : triangulation.Triangles)
    {
      for (int k = 0; k < 3; ++k)
      {
        this->FillTriangles.push_back(polygon[t[k]]);
        if (this->FillEdges.insert(EdgeKey(polygon[t[k]], polygon[t[(k + 1) % 3]])).second)
        {
          this->FillEdgeLog.push_back(EdgeKey(polygon[t[k]], polygon[t[(k + 1) % 3]]));
        }
      }
      this->FillPatch.push_back(this->FillPolygons);
      this->FillKind.push_back(kind);
    }
    ++this->FillPolygons;
    return true;
  }

  // The polygon that fills a clockwise loop: reversed (the loop has its flat side on the left).
  std::vector<Index> FillPolygonOf(Index loop) const
  {
    std::vector<Index> polygon(this->R.Loops[loop].Vertices.rbegin(), this->R.Loops[loop].Vertices.rend());
    return polygon;
  }
  Vec3 FlatNormalOf(Index loop) const
  {
    Vec3 flat{ 0, 0, 0 };
    for (const Oriented& o : this->LoopChains[loop])
    {
      for (Index i = 0; i + 1 < this->Size(o.Chain); ++i)
      {
        flat = flat + this->Normal[this->LeftTriangle(o, i)];
      }
    }
    return Normalized(flat);
  }

  // Whether the kept surface has the edge (u, w): a triangle of it that is not removed.
  bool EdgeKept(Index u, Index w) const
  {
    const Index e = this->Topology.FindEdge(u, w);
    if (e == InvalidIndex)
    {
      return false;
    }
    for (const Index* t = this->Topology.EdgeTrianglesBegin(e); t != this->Topology.EdgeTrianglesEnd(e); ++t)
    {
      if (!this->Removed[*t])
      {
        return true;
      }
    }
    return false;
  }

  // The wall that clockwise loop l cuts off (a hole's tube between l and its partner, or a bump's
  // or cavity's wall behind l alone) into region; barrier gets the loops that bound it. False
  // when l bounds no small wall.
  bool FindWall(Index l, TopologyFeature& feature, std::vector<Index>& barrier, std::vector<Index>& region,
    std::vector<unsigned char>& mark)
  {
    const Index partner = this->FindPartner(l);
    feature.Loops[0] = l;
    feature.Loops[1] = partner;
    bool hole = partner != InvalidIndex && this->R.Loops[partner].Clockwise;
    barrier.assign(1, l);
    if (hole)
    {
      barrier.push_back(partner);
    }
    std::string reason;
    bool closed = this->WallRegion(l, barrier, region, mark, reason);
    if (closed && hole && !this->JoinedWithout(l, partner, region))
    {
      closed = false; // a tube that holds two parts together (a dumbbell's bar), not a handle
    }
    if (!closed && hole)
    {
      // Two clockwise loops that do not bound a tube: L may still close a bump or a cavity.
      hole = false;
      barrier.pop_back();
      feature.Loops[1] = InvalidIndex;
      closed = this->WallRegion(l, barrier, region, mark, reason);
    }
    if (closed)
    {
      feature.Kind = hole ? TopologyFeatureKind::Hole : this->BumpOrCavity(l, region);
    }
    return closed;
  }

  // Bump or cavity: the side of the flat plane on which the wall lies.
  TopologyFeatureKind BumpOrCavity(Index l, const std::vector<Index>& region) const
  {
    const std::vector<Index>& v = this->R.Loops[l].Vertices;
    Vec3 centroid{ 0, 0, 0 };
    for (Index i : v)
    {
      centroid = centroid + this->Mesh.Point(i);
    }
    centroid = (1.0 / double(v.size())) * centroid;
    const Vec3 flat = this->FlatNormalOf(l);
    double offset = 0;
    for (Index t : region)
    {
      const Index* tri = this->Mesh.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        offset += Dot(this->Mesh.Point(tri[k]) - centroid, flat);
      }
    }
    return offset >= 0 ? TopologyFeatureKind::Bump : TopologyFeatureKind::Cavity;
  }

  // Why a detected feature is kept, or nothing when it may be removed.
  const char* KeepReason(const TopologyFeature& feature) const
  {
    const bool enabled = (feature.Kind == TopologyFeatureKind::Hole && this->P.RemoveHoles) ||
      (feature.Kind == TopologyFeatureKind::Bump && this->P.RemoveBumps) ||
      (feature.Kind == TopologyFeatureKind::Cavity && this->P.RemoveCavities);
    if (!enabled)
    {
      return "removal of this kind is off";
    }
    if (!(feature.Size < this->P.FeatureSize))
    {
      return "larger than the maximum feature size";
    }
    return nullptr;
  }

  // Removes the wall and fills its clockwise loops; when a loop cannot be filled, everything is
  // put back as it was and false is returned.
  bool RemoveWall(const std::vector<Index>& barrier, const std::vector<Index>& region, TopologyFeature& feature)
  {
    for (Index t : region)
    {
      this->Removed[t] = 1;
    }
    const size_t fillMark = this->FillTriangles.size();
    const Index polygonMark = this->FillPolygons;
    const size_t edgesMark = this->FillEdgeLog.size();
    const auto edgeKept = [this](Index u, Index w) { return this->EdgeKept(u, w); };
    bool filled = true;
    for (Index b : barrier)
    {
      if (this->R.Loops[b].Clockwise)
      {
        filled = filled && this->Fill(this->FillPolygonOf(b), this->FlatNormalOf(b), 1, edgeKept);
      }
    }
    if (filled)
    {
      for (Index t : region)
      {
        this->PatchRemoved[this->Patches.TrianglePatches()[t]] = 1;
      }
      feature.RemovedTriangles = static_cast<Index>(region.size());
      feature.FillTriangles = static_cast<Index>((this->FillTriangles.size() - fillMark) / 3);
      return true;
    }
    for (Index t : region)
    {
      this->Removed[t] = 0;
    }
    this->FillTriangles.resize(fillMark);
    this->FillPatch.resize(fillMark / 3);
    this->FillKind.resize(fillMark / 3);
    this->FillPolygons = polygonMark;
    for (size_t e = edgesMark; e < this->FillEdgeLog.size(); ++e)
    {
      this->FillEdges.erase(this->FillEdgeLog[e]);
    }
    this->FillEdgeLog.resize(edgesMark);
    return false;
  }

  // Section 5.3: every unclaimed clockwise loop that cuts off a small wall is a feature (hole,
  // bump or cavity); the enabled ones below the size limit are removed and their loops filled.
  void DetectAndRemove(const AbortCheck& progress)
  {
    const Index nt = this->Mesh.NumberOfTriangles();
    this->Removed.assign(size_t(nt), 0);
    this->PatchRemoved.assign(size_t(this->Patches.NumberOfPatches()), 0);
    this->PatchStamp.assign(size_t(this->Patches.NumberOfPatches()), 0);
    std::vector<unsigned char> mark(size_t(nt), 0);
    std::vector<Index> region, barrier;
    for (Index l = 0; l < static_cast<Index>(this->R.Loops.size()); ++l)
    {
      if (progress && (l % 64) == 0 && progress(double(l) / double(this->R.Loops.size())))
      {
        return;
      }
      if (!this->R.Loops[l].Clockwise || this->R.Loops[l].Feature != InvalidIndex)
      {
        continue;
      }
      TopologyFeature feature;
      if (!this->FindWall(l, feature, barrier, region, mark))
      {
        continue; // not a feature: the loop does not cut off a small wall
      }
      const Index partner = feature.Loops[1];
      feature.Size = this->R.Loops[l].Diameter;
      if (partner != InvalidIndex)
      {
        feature.Size = std::max(feature.Size, this->R.Loops[partner].Diameter);
      }
      const Index index = static_cast<Index>(this->R.Features.size());
      this->R.Loops[l].Feature = index;
      if (partner != InvalidIndex)
      {
        this->R.Loops[partner].Feature = index;
      }
      ++this->R.Detected[int(feature.Kind)];
      if (const char* reason = this->KeepReason(feature))
      {
        feature.Reason = reason;
      }
      else if (this->RemoveWall(barrier, region, feature))
      {
        feature.Removed = true;
        ++this->R.Removed[int(feature.Kind)];
      }
      else
      {
        feature.Reason = "its loops cannot be filled without folds or duplicate edges";
      }
      this->R.Features.push_back(std::move(feature));
    }
  }

  // --- 7. Cracks (5.3.4) ---
  // Bounding box (low, high) of each edge-connected component.
  static std::vector<std::array<Vec3, 2>> ComponentBoxes(const TriangleMesh& mesh, const MeshTopology& topology)
  {
    const double huge = std::numeric_limits<double>::infinity();
    std::vector<std::array<Vec3, 2>> boxes(size_t(topology.NumberOfComponents()),
      std::array<Vec3, 2>{ Vec3{ huge, huge, huge }, Vec3{ -huge, -huge, -huge } });
    const std::vector<Index>& component = topology.TriangleComponents();
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      std::array<Vec3, 2>& box = boxes[component[t]];
      for (int k = 0; k < 3; ++k)
      {
        const Vec3 x = mesh.Point(mesh.Triangles[3 * size_t(t) + k]);
        for (int j = 0; j < 3; ++j)
        {
          box[0][j] = std::min(box[0][j], x[j]);
          box[1][j] = std::max(box[1][j], x[j]);
        }
      }
    }
    return boxes;
  }

  // A crack is a gap in a surface that goes on beyond it. A loop whose component lies within the
  // loop's own bounding box (a separate triangle, a small flat piece) is that piece's outline:
  // closing it would lay a second copy of the piece over it (10,000 separate triangles became
  // 20,000).
  static bool IsOutlineOfItsComponent(const TriangleMesh& mesh, const std::array<Vec3, 2>& componentBox,
    const std::vector<Index>& loop)
  {
    Vec3 low = mesh.Point(loop[0]), high = low;
    for (Index v : loop)
    {
      const Vec3 x = mesh.Point(v);
      for (int j = 0; j < 3; ++j)
      {
        low[j] = std::min(low[j], x[j]);
        high[j] = std::max(high[j], x[j]);
      }
    }
    const double slack = 1e-9 * Norm(high - low);
    for (int j = 0; j < 3; ++j)
    {
      if (componentBox[0][j] < low[j] - slack || componentBox[1][j] > high[j] + slack)
      {
        return false;
      }
    }
    return true;
  }

  // `topology`: of `current` as it is before the cracks are closed.
  void FillCracks(TriangleMesh& current, const MeshTopology& topology)
  {
    const double limit = this->P.MaximumCrackSize >= 0 ? this->P.MaximumCrackSize : this->P.FeatureSize;
    auto edgeExists = [&](Index u, Index w) { return topology.FindEdge(u, w) != InvalidIndex; };
    const std::vector<std::array<Vec3, 2>> componentBoxes = ComponentBoxes(current, topology);
    for (const std::vector<Index>& loop : topology.BoundaryLoops())
    {
      if (loop.size() < 3)
      {
        continue;
      }
      std::vector<Index> sorted(loop);
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      {
        continue; // pinched border: not a simple crack
      }
      const double size = EstimateLoopDiameter(current, loop);
      if (!(size < limit) || IsOutlineOfItsComponent(current,
            componentBoxes[topology.TriangleComponents()[*topology.VertexTrianglesBegin(loop[0])]], loop))
      {
        continue;
      }
      TopologyFeature feature;
      feature.Kind = TopologyFeatureKind::Crack;
      feature.Size = size;
      // The border triangle runs the loop's first edge: if forwards, the fill runs it backwards.
      std::vector<Index> polygon(loop);
      const Index e = topology.FindEdge(loop[0], loop[1]);
      const Index* tri = current.Triangle(*topology.EdgeTrianglesBegin(e));
      bool forward = false;
      for (int k = 0; k < 3; ++k)
      {
        forward = forward || (tri[k] == loop[0] && tri[(k + 1) % 3] == loop[1]);
      }
      if (forward)
      {
        std::reverse(polygon.begin(), polygon.end());
      }
      std::vector<Vec3> points;
      for (Index v : polygon)
      {
        points.push_back(current.Point(v));
      }
      ++this->R.Detected[int(TopologyFeatureKind::Crack)];
      const size_t fillMark = this->FillTriangles.size();
      if (this->Fill(polygon, Normalized(PolygonNormal(points)), 2, edgeExists))
      {
        feature.Removed = true;
        feature.FillTriangles = static_cast<Index>((this->FillTriangles.size() - fillMark) / 3);
        ++this->R.Removed[int(TopologyFeatureKind::Crack)];
        for (size_t i = fillMark; i < this->FillTriangles.size(); i += 3)
        {
          current.AddTriangle(this->FillTriangles[i], this->FillTriangles[i + 1], this->FillTriangles[i + 2]);
        }
      }
      else
      {
        feature.Reason = "the crack cannot be closed without folds or duplicate edges";
      }
      feature.CrackLoop = std::move(polygon);
      this->R.Features.push_back(std::move(feature));
    }
  }
};

// --- 8. Clean-up merge of nearly coplanar patches into disks ---
// The chains between two patches whose normals are within the limit, most parallel first.
std::vector<std::pair<double, Index>> MergeCandidates(const Patchification& pa, double cosLimit)
{
  std::vector<std::pair<double, Index>> candidates;
  for (Index c = 0; c < pa.NumberOfChains(); ++c)
  {
    const Index a = pa.ChainLeftPatch(c), b = pa.ChainRightPatch(c);
    if (b == InvalidIndex || pa.ChainIsNonManifold(c) || a == b)
    {
      continue;
    }
    const double d = Dot(pa.PatchNormal(a), pa.PatchNormal(b));
    if (d >= cosLimit)
    {
      candidates.emplace_back(-d, c);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

// The state of the clean-up merge: the groups of patches and, at each group's root, its normal
// sum and its boundary chains. The decisions are those of the plain formulation (up to session
// 42: each group's chain list filtered of its internal chains at every join, the larger group's
// whole boundary marked for every pinch test), which made a group that grows by many small joins
// cost its whole boundary per join. The arc and pinch tests are symmetric in the two groups and
// the labels are compacted afterwards, so which list is walked or kept changes no decision. Here
// the work of a candidate follows the smaller group:
//  - a list may keep stale entries (chains a later join made internal), counted: they are
//    skipped when read, dropped when the list moves or when they are half of it; a join appends
//    the shorter list to the longer one;
//  - the pinch test walks the shorter list's boundary vertices and asks the chains at each
//    vertex whether the other group's boundary passes there (or, when the two lists are alike,
//    stamps the other's vertices as before).
// The plain lists' lengths are kept as counts (Size): they choose, as before, which group's list
// was filtered before a merge test, which decides whether a patch's seams (chains with that patch
// on both sides, never merge candidates) still count as its boundary.
struct PatchGroups
{
  PatchGroups(const Patchification& pa, Index nv)
    : Patches(pa)
    , Groups(pa.NumberOfPatches())
    , NormalSum(size_t(pa.NumberOfPatches()))
    , ListIndex(size_t(pa.NumberOfPatches()), InvalidIndex)
    , Size(size_t(pa.NumberOfPatches()), 0)
    , SeamEntries(size_t(pa.NumberOfPatches()), 0)
    , Stale(size_t(pa.NumberOfPatches()), 0)
    , StampArc(size_t(nv), -1)
    , StampOther(size_t(nv), -1)
  {
    for (Index p = 0; p < pa.NumberOfPatches(); ++p)
    {
      this->NormalSum[p] = pa.PatchNormalSum(p);
      this->Size[p] = static_cast<Index>(pa.PatchChainsEnd(p) - pa.PatchChainsBegin(p));
      for (Index c : this->ListOf(p))
      {
        this->SeamEntries[p] += pa.ChainRightPatch(c) == p && pa.ChainLeftPatch(c) == p;
      }
    }
    this->IndexVertexChains(nv);
  }

  // Per vertex, the chains through it (each chain vertex once per chain).
  void IndexVertexChains(Index nv)
  {
    const Patchification& pa = this->Patches;
    this->VertexChainOffsets.assign(size_t(nv) + 1, 0);
    for (Index c = 0; c < pa.NumberOfChains(); ++c)
    {
      for (Index i = 0; i < pa.ChainSize(c); ++i)
      {
        ++this->VertexChainOffsets[pa.ChainVerticesBegin(c)[i] + 1];
      }
    }
    for (Index v = 0; v < nv; ++v)
    {
      this->VertexChainOffsets[v + 1] += this->VertexChainOffsets[v];
    }
    this->VertexChainList.resize(size_t(this->VertexChainOffsets[nv]));
    std::vector<Index> fill(this->VertexChainOffsets.begin(), this->VertexChainOffsets.end() - 1);
    for (Index c = 0; c < pa.NumberOfChains(); ++c)
    {
      for (Index i = 0; i < pa.ChainSize(c); ++i)
      {
        this->VertexChainList[fill[pa.ChainVerticesBegin(c)[i]]++] = c;
      }
    }
  }

  // Root g's chain list: the patchification's own while g is a single patch (no copy per patch).
  struct ChainSpan
  {
    const Index* First;
    const Index* Last;
    const Index* begin() const { return this->First; }
    const Index* end() const { return this->Last; }
    size_t size() const { return size_t(this->Last - this->First); }
  };
  Index NewList()
  {
    if (this->FreeLists.empty())
    {
      this->Lists.emplace_back();
      return static_cast<Index>(this->Lists.size()) - 1;
    }
    const Index slot = this->FreeLists.back();
    this->FreeLists.pop_back();
    return slot;
  }
  ChainSpan ListOf(Index g) const
  {
    if (this->ListIndex[g] != InvalidIndex)
    {
      const std::vector<Index>& list = this->Lists[this->ListIndex[g]];
      return { list.data(), list.data() + list.size() };
    }
    return { this->Patches.PatchChainsBegin(g), this->Patches.PatchChainsEnd(g) };
  }

  Index RightGroup(Index c)
  {
    const Index r = this->Patches.ChainRightPatch(c);
    return r == InvalidIndex ? InvalidIndex : this->Groups.Find(r);
  }
  // Whether chain c is in root g's plain list: a side in g and not internal, or a seam of a
  // single patch whose list was never filtered.
  bool Listed(Index c, Index g)
  {
    const Index l = this->Groups.Find(this->Patches.ChainLeftPatch(c));
    const Index r = this->RightGroup(c);
    return (l == g || r == g) && (l != r || this->SeamEntries[g] > 0);
  }

  // The plain formulation filtered g's list of its internal chains before each merge test (only
  // a single patch's seams can be there): they stay as stale entries.
  void Filter(Index g)
  {
    this->Stale[g] += this->SeamEntries[g];
    this->Size[g] -= this->SeamEntries[g];
    this->SeamEntries[g] = 0;
  }

  // The chains between g1 and g2, read from the shorter list.
  void SharedChains(Index g1, Index g2, std::vector<Index>& shared)
  {
    shared.clear();
    const Index g = this->ListOf(g1).size() < this->ListOf(g2).size() ? g1 : g2;
    this->Work += static_cast<std::int64_t>(this->ListOf(g).size());
    for (Index c : this->ListOf(g))
    {
      const Index l = this->Groups.Find(this->Patches.ChainLeftPatch(c));
      const Index r = this->RightGroup(c);
      if ((l == g1 && r == g2) || (l == g2 && r == g1))
      {
        shared.push_back(c);
      }
    }
  }

  // Whether the shared chains form one arc: their endpoints make a single path (V - E == 1,
  // degrees <= 2, connected).
  bool IsSingleArc(const std::vector<Index>& shared)
  {
    auto& ends = this->Ends;
    ends.clear();
    for (Index c : shared)
    {
      ends.push_back(this->Patches.ChainVerticesBegin(c)[0]);
      ends.push_back(this->Patches.ChainVerticesBegin(c)[this->Patches.ChainSize(c) - 1]);
    }
    std::vector<Index>& distinct = this->Distinct; // reused: no allocation per candidate
    distinct.assign(ends.begin(), ends.end());
    std::sort(distinct.begin(), distinct.end());
    bool arc = !shared.empty();
    Index degreeOne = 0;
    for (size_t i = 0; i < distinct.size() && arc;)
    {
      size_t j = i;
      while (j < distinct.size() && distinct[j] == distinct[i])
      {
        ++j;
      }
      arc = (j - i) <= 2;
      degreeOne += (j - i) == 1;
      i = j;
    }
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    if (!(arc && distinct.size() == shared.size() + 1 && degreeOne == 2))
    {
      return false;
    }
    // Connected: walk from a degree-one end (each step uses one chain: at most shared.size()).
    Index at = *std::find_if(distinct.begin(), distinct.end(), [&](Index v) { return std::count(ends.begin(), ends.end(), v) == 1; });
    std::vector<unsigned char>& used = this->Used;
    used.assign(shared.size(), 0);
    size_t walked = 0;
    for (bool moved = true; moved;)
    {
      moved = false;
      for (size_t k = 0; k < shared.size(); ++k)
      {
        if (!used[k] && (ends[2 * k] == at || ends[2 * k + 1] == at))
        {
          used[k] = 1;
          at = ends[2 * k] == at ? ends[2 * k + 1] : ends[2 * k];
          ++walked;
          moved = true;
          break;
        }
      }
    }
    return walked == shared.size();
  }

  // Whether the boundaries of g1 and g2 meet anywhere off the shared arc (the arc's vertices
  // stamped). Two groups of similar list lengths: the other's listed vertices are stamped and the
  // shorter list's looked up, as before. Else only the shorter boundary is walked, and the chains
  // through each of its vertices (off the arc) are asked whether they are the other group's.
  bool Pinches(Index g1, Index g2, const std::vector<Index>& shared)
  {
    const Patchification& pa = this->Patches;
    ++this->Stamp;
    for (Index c : shared)
    {
      this->Work += pa.ChainSize(c);
      for (Index i = 0; i < pa.ChainSize(c); ++i)
      {
        this->StampArc[pa.ChainVerticesBegin(c)[i]] = this->Stamp;
      }
    }
    const bool firstShorter = this->ListOf(g1).size() < this->ListOf(g2).size();
    const Index walked = firstShorter ? g1 : g2, other = firstShorter ? g2 : g1;
    const bool stampOther = this->ListOf(other).size() <= 4 * this->ListOf(walked).size();
    if (stampOther)
    {
      for (Index c : this->ListOf(other))
      {
        this->Work += 1 + pa.ChainSize(c);
        if (this->ListedEntry(c, other))
        {
          for (Index i = 0; i < pa.ChainSize(c); ++i)
          {
            this->StampOther[pa.ChainVerticesBegin(c)[i]] = this->Stamp;
          }
        }
      }
    }
    for (Index c : this->ListOf(walked))
    {
      ++this->Work;
      if (!this->ListedEntry(c, walked))
      {
        continue;
      }
      for (Index i = 0; i < pa.ChainSize(c); ++i)
      {
        const Index v = pa.ChainVerticesBegin(c)[i];
        if (this->StampArc[v] != this->Stamp &&
          (stampOther ? this->StampOther[v] == this->Stamp : this->OtherChainThrough(v, c, other)))
        {
          return true;
        }
      }
    }
    return false;
  }

  // Whether a chain of group g other than c (which is not g's: a chain of both groups is
  // shared, its vertices stamped) passes through v.
  bool OtherChainThrough(Index v, Index c, Index g)
  {
    this->Work += 1 + this->VertexChainOffsets[v + 1] - this->VertexChainOffsets[v];
    for (Index k = this->VertexChainOffsets[v]; k < this->VertexChainOffsets[v + 1]; ++k)
    {
      const Index d = this->VertexChainList[k];
      if (d != c && this->Listed(d, g))
      {
        return true;
      }
    }
    return false;
  }

  // Whether c, an entry of g's list, is listed (no stale entry: without asking).
  bool ListedEntry(Index c, Index g) { return this->Stale[g] == 0 || this->Listed(c, g); }

  // g2 joins g1 across `shared`; the group's data moves to the root of the union. The shorter
  // list is appended to the longer one without its now internal chains; the longer one's shared
  // chains (and a single patch's seams) stay as stale entries until they are half of it.
  void Join(Index g1, Index g2, Index shared)
  {
    const Vec3 sum = this->NormalSum[g1] + this->NormalSum[g2];
    const Index size = this->Size[g1] - this->SeamEntries[g1] + this->Size[g2] - this->SeamEntries[g2] - 2 * shared;
    const bool firstLonger = this->ListOf(g1).size() >= this->ListOf(g2).size();
    const Index kept = firstLonger ? g1 : g2, moved = firstLonger ? g2 : g1;
    const Index stale = this->Stale[kept] + shared + this->SeamEntries[kept];
    Index slot = this->ListIndex[kept];
    if (slot == InvalidIndex) // a single patch's first join: its list leaves the patchification's
    {
      const ChainSpan span = this->ListOf(kept);
      slot = this->NewList();
      this->Lists[slot].reserve(span.size() + this->ListOf(moved).size());
      this->Lists[slot].assign(span.begin(), span.end());
    }
    std::vector<Index>& list = this->Lists[slot];
    const ChainSpan moving = this->ListOf(moved);
    this->Groups.Union(g1, g2);
    const Index root = this->Groups.Find(g1);
    this->Work += static_cast<std::int64_t>(moving.size());
    for (Index c : moving)
    {
      if (!this->IsInternal(c))
      {
        list.push_back(c);
      }
    }
    if (this->ListIndex[moved] != InvalidIndex)
    {
      std::vector<Index>().swap(this->Lists[this->ListIndex[moved]]);
      this->FreeLists.push_back(this->ListIndex[moved]);
    }
    this->ListIndex[g1] = this->ListIndex[g2] = InvalidIndex;
    this->ListIndex[root] = slot;
    this->NormalSum[root] = sum;
    this->Size[root] = size;
    this->Stale[root] = stale;
    this->SeamEntries[g1] = this->SeamEntries[g2] = 0;
    if (2 * size_t(stale) > list.size())
    {
      this->DropStaleEntries(root);
    }
  }

  // Drops the entries of root g's list that are no longer its boundary (paid for by the joins
  // that made them stale: at least half the list).
  void DropStaleEntries(Index g)
  {
    std::vector<Index>& chains = this->Lists[this->ListIndex[g]];
    this->Work += static_cast<std::int64_t>(chains.size());
    chains.erase(std::remove_if(chains.begin(), chains.end(), [&](Index c) { return this->IsInternal(c); }), chains.end());
    this->Stale[g] = 0;
  }

  // Whether chain c now lies inside one group.
  bool IsInternal(Index c)
  {
    const Index r = this->RightGroup(c);
    return r != InvalidIndex && this->Groups.Find(this->Patches.ChainLeftPatch(c)) == r;
  }

  const Patchification& Patches;
  UnionFind Groups;
  std::vector<Vec3> NormalSum;
  std::vector<Index> ListIndex; // at a merged group's root: its list in Lists (else its patch's)
  std::vector<std::vector<Index>> Lists; // merged groups' boundary chains and stale entries
  std::vector<Index> FreeLists;          // slots of Lists no group uses
  std::vector<Index> Size;                  // at the root: the plain list's length
  std::vector<Index> SeamEntries;           // seam entries a single patch's plain list still has
  std::vector<Index> Stale;                 // at the root: entries of its list no longer listed
  std::vector<Index> VertexChainOffsets, VertexChainList;
  std::vector<Index> StampArc, StampOther, Ends, Distinct;
  std::vector<unsigned char> Used;
  Index Stamp = 0;
  std::int64_t Work = 0; // list entries, chain vertices and vertex-chain incidences visited
};

// Per patch, the group it merges into: neighbouring patches within MergeAngle of each other
// join, the most parallel first, when their common boundary is one arc and they touch nowhere
// else (the union stays a disk).
std::vector<Index> CleanUpMerge(
  const TopologySimplificationParameters& P, const TriangleMesh& mesh, const Patchification& pa, std::int64_t& work)
{
  const Index np = pa.NumberOfPatches();
  std::vector<Index> group(static_cast<size_t>(np));
  std::iota(group.begin(), group.end(), 0);
  if (P.MergeAngle <= 0)
  {
    return group;
  }
  const double cosLimit = std::cos(Radians(P.MergeAngle));
  PatchGroups groups(pa, mesh.NumberOfPoints());
  std::vector<Index> shared;
  for (const auto& candidate : MergeCandidates(pa, cosLimit))
  {
    const Index c0 = candidate.second;
    Index g1 = groups.Groups.Find(pa.ChainLeftPatch(c0)), g2 = groups.Groups.Find(pa.ChainRightPatch(c0));
    if (g1 == g2 || Dot(Normalized(groups.NormalSum[g1]), Normalized(groups.NormalSum[g2])) < cosLimit)
    {
      continue;
    }
    if (groups.Size[g1] < groups.Size[g2])
    {
      std::swap(g1, g2);
    }
    groups.Filter(g2);
    groups.SharedChains(g1, g2, shared);
    if (groups.IsSingleArc(shared) && !groups.Pinches(g1, g2, shared))
    {
      groups.Join(g1, g2, static_cast<Index>(shared.size()));
    }
  }
  for (Index p = 0; p < np; ++p)
  {
    group[p] = groups.Groups.Find(p);
  }
  work = groups.Work;
  return group;
}


// Dense 0..n-1 labels in order of first appearance.
Index Compact(std::vector<Index>& labels)
{
  std::vector<Index> map;
  Index next = 0;
  for (Index& l : labels)
  {
    if (size_t(l) >= map.size())
    {
      map.resize(size_t(l) + 1, InvalidIndex);
    }
    if (map[l] == InvalidIndex)
    {
      map[l] = next++;
    }
    l = map[l];
  }
  return next;
}
// The cleaned surface of a detection pass: kept triangles, filled loops and filled cracks over
// the input vertices, with a patch label and a fill kind per triangle.
struct CleanedSurface
{
  TriangleMesh Mesh;
  std::vector<Index> Labels;
  std::vector<unsigned char> Fill; // 0 original surface, 1 filled feature loop, 2 filled crack
  Index LabelCount = 0;
};

// The cleaned mesh of one pass: the triangles the pass kept and the fills it made.
void CollectCleaned(const Simplification& run, const TriangleMesh& current, const std::vector<unsigned char>& currentFill,
  const std::vector<double>& points, CleanedSurface& cleaned)
{
  cleaned.Mesh.Points = points; // within the capacity of the previous pass's copy
  cleaned.Mesh.Triangles.clear();
  cleaned.Labels.clear();
  cleaned.Fill.clear();
  const size_t kept = size_t(current.NumberOfTriangles()) + run.FillPatch.size();
  cleaned.Mesh.Triangles.reserve(3 * kept); // no growth by doubling, each a fresh mapping when large
  cleaned.Labels.reserve(kept);
  cleaned.Fill.reserve(kept);
  const std::vector<Index>& patchOf = run.Patches.TrianglePatches();
  const Index np = run.Patches.NumberOfPatches();
  for (Index t = 0; t < current.NumberOfTriangles(); ++t)
  {
    if (!run.Removed[t])
    {
      const Index* tri = current.Triangle(t);
      cleaned.Mesh.AddTriangle(tri[0], tri[1], tri[2]);
      cleaned.Labels.push_back(patchOf[t]);
      cleaned.Fill.push_back(currentFill[t]);
    }
  }
  for (size_t i = 0; i < run.FillPatch.size(); ++i)
  {
    cleaned.Mesh.AddTriangle(run.FillTriangles[3 * i], run.FillTriangles[3 * i + 1], run.FillTriangles[3 * i + 2]);
    cleaned.Labels.push_back(np + run.FillPatch[i]);
    cleaned.Fill.push_back(run.FillKind[i]);
  }
}

// The cracks of the cleaned mesh, closed (first pass only); `topology` is the cleaned mesh's.
void CloseCracks(Simplification& run, CleanedSurface& cleaned, const MeshTopology& topology)
{
  const Index np = run.Patches.NumberOfPatches();
  const size_t before = run.FillPatch.size();
  run.FillCracks(cleaned.Mesh, topology); // adds the crack triangles to the cleaned mesh itself
  for (size_t i = before; i < run.FillPatch.size(); ++i)
  {
    cleaned.Labels.push_back(np + run.FillPatch[i]);
    cleaned.Fill.push_back(run.FillKind[i]);
  }
}

// Accumulate: removed features of every pass, detected-but-kept ones of the last pass only
// (with their loops; the last pass's loops all).
void AccumulateFindings(TopologySimplificationResult& found, bool last, TopologySimplificationResult& result)
{
  std::vector<Index> featureIndex(found.Features.size(), InvalidIndex);
  Index nextFeature = static_cast<Index>(result.Features.size());
  for (size_t f = 0; f < found.Features.size(); ++f)
  {
    if (found.Features[f].Removed || last)
    {
      featureIndex[f] = nextFeature++;
    }
  }
  std::vector<Index> loopIndex(found.Loops.size(), InvalidIndex);
  Index nextLoop = static_cast<Index>(result.Loops.size());
  for (size_t l = 0; l < found.Loops.size(); ++l)
  {
    const Index f = found.Loops[l].Feature;
    if (last || (f != InvalidIndex && featureIndex[f] != InvalidIndex))
    {
      loopIndex[l] = nextLoop++;
    }
  }
  for (size_t f = 0; f < found.Features.size(); ++f)
  {
    if (featureIndex[f] != InvalidIndex)
    {
      TopologyFeature& feature = found.Features[f];
      for (Index& l : feature.Loops)
      {
        l = l == InvalidIndex ? InvalidIndex : loopIndex[l];
      }
      result.Features.push_back(std::move(feature));
    }
  }
  for (size_t l = 0; l < found.Loops.size(); ++l)
  {
    if (loopIndex[l] != InvalidIndex)
    {
      SharpLoop& loop = found.Loops[l];
      loop.Feature = loop.Feature == InvalidIndex ? InvalidIndex : featureIndex[loop.Feature];
      result.Loops.push_back(std::move(loop));
    }
  }
  result.PartnerSearchWork += found.PartnerSearchWork;
  for (int k = 0; k < 4; ++k)
  {
    result.Removed[k] += found.Removed[k];
    result.Detected[k] += last ? found.Detected[k] : found.Removed[k];
  }
}

enum class PassOutcome
{
  Aborted,
  Again, // something was removed: detect again on the cleaned surface
  Last
};

// Whether the SPBM completion's merge measure is decided from the input's noisy bends
// (SingleMeasureNoisyBendShare): a target, the comparison on, a threshold below 1 and a plane
// distance to measure the bends against.
bool DecidesMergeMeasureFromNoise(const TopologySimplificationParameters& parameters)
{
  return parameters.Completion == TopologyCompletion::Spbm && parameters.SpbmTargetTriangles > 0 &&
    parameters.Spbm.CompareCandidates && parameters.SingleMeasureNoisyBendShare < 1.0 &&
    parameters.Patches.MaximumPlaneDistance > 0;
}

// The topology of `current` made `cleaned`'s: `cleaned` is `current` without the triangles flagged
// in `removed` (their order kept) and with the pass's fills appended, which change about 0.1 % of
// a scan's triangles per pass; a whole Build was a scattered pass over the surface for each
// (session 45). Returns the update's local work.
std::int64_t UpdateTopology(MeshTopology& topology, const std::vector<Index>& currentTriangles,
  const std::vector<unsigned char>& removed, const TriangleMesh& cleaned, int pass)
{
  topology.Update(currentTriangles, removed, cleaned);
  const MeshTopologyUpdateWork& work = topology.LastUpdateWork();
  vtkLogF(TRACE,
    "[hbr] pass %d: topology updated: %lld removed, %lld appended, %lld touched vertices, %lld local "
    "incidences, %lld entries carried over",
    pass + 1, static_cast<long long>(work.RemovedTriangles), static_cast<long long>(work.AppendedTriangles),
    static_cast<long long>(work.TouchedVertices), static_cast<long long>(work.LocalIncidences),
    static_cast<long long>(work.CarriedEntries));
  return work.LocalIncidences;
}

// One detection pass over `current` (the input's vertices, the previous pass's triangles).
PassOutcome DetectionPass(int pass, int passes, const TriangleMesh& input, const TriangleMesh& current,
  const std::vector<unsigned char>& currentFill, const TopologySimplificationParameters& parameters,
  const AbortCheck& report, TopologySimplificationResult& result, CleanedSurface& cleaned, StageClock& stages,
  DetectionWorkspace& workspace)
{
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  TopologySimplificationResult found;
  const size_t room = workspace.Bytes();
  Simplification run(current, parameters, found, workspace);
  stages.Lap("detection pass: topology");
  const double base = pass == 0 ? 0.0 : 0.7;
  const double span = pass == 0 ? 0.4 : 0.02;
  run.Patches.Build(current, run.Topology, parameters.Patches, [&](double f) { return !report(base + span * f); });
  if (run.Patches.Aborted())
  {
    return PassOutcome::Aborted;
  }
  const auto t1 = Clock::now();
  result.PatchificationSeconds += std::chrono::duration<double>(t1 - t0).count();
  stages.Lap("detection pass: patchification");
  if (pass == 0 && DecidesMergeMeasureFromNoise(parameters))
  {
    result.NoisyBendShare = NoisyBendShare(current, run.Topology, Radians(parameters.Patches.OneEdgeNeighborAngle),
      parameters.Patches.MaximumPlaneDistance);
    vtkLogF(TRACE, "[hbr] noisy bend share %.4f (threshold %.3f)", result.NoisyBendShare,
      parameters.SingleMeasureNoisyBendShare);
    stages.Lap("detection pass: noisy bends");
  }
  run.BuildSharpChains();
  run.ClassifySides();
  run.FindLoops();
  if (report(pass == 0 ? 0.5 : 0.72))
  {
    return PassOutcome::Aborted;
  }
  bool aborted = false;
  run.DetectAndRemove([&](double f) { return aborted = aborted || report(pass == 0 ? 0.5 + 0.2 * f : 0.72); });
  if (aborted)
  {
    return PassOutcome::Aborted;
  }
  stages.Lap("detection pass: sharp chains, loops, removal");
  workspace.Allocations += pass > 0 && workspace.Bytes() > room;
  if (pass == 0)
  {
    result.InitialPatches = run.Patches.NumberOfPatches();
    result.SharpEdges = found.SharpEdges;
    result.SharpChains = found.SharpChains;
  }
  CollectCleaned(run, current, currentFill, input.Points, cleaned);
  const Index removedNow = found.Removed[0] + found.Removed[1] + found.Removed[2];
  const bool last = removedNow == 0 || pass + 1 == passes;
  std::int64_t& topologyWork = last ? workspace.CleanedTopologyWork : workspace.TopologyTriangles;
  if (pass == 0 && parameters.FillCracks)
  {
    stages.Lap("detection pass: cleaned copy");
    // The cracks are looked for on the cleaned surface: the pass's topology, edited.
    topologyWork += UpdateTopology(workspace.Topology, current.Triangles, run.Removed, cleaned.Mesh, pass);
    CloseCracks(run, cleaned, workspace.Topology);
    stages.Lap("detection pass: cracks");
    // The crack fills appended (no triangle removed).
    topologyWork += UpdateTopology(workspace.Topology, {}, {}, cleaned.Mesh, pass);
  }
  workspace.LastSurfaceKept = cleaned.Mesh.Triangles == current.Triangles; // one sequential pass
  if (!(pass == 0 && parameters.FillCracks) && !workspace.LastSurfaceKept)
  {
    topologyWork += UpdateTopology(workspace.Topology, current.Triangles, run.Removed, cleaned.Mesh, pass);
  }
  workspace.TopologyCurrent = true; // the next pass's, and the clean-up merge's after the last
  stages.Lap("detection pass: topology update");
  cleaned.LabelCount = Compact(cleaned.Labels);
  vtkLogF(TRACE, "[hbr] pass %d: %lld of %lld triangles kept, %lld fill triangles", pass + 1,
    static_cast<long long>(cleaned.Mesh.NumberOfTriangles()) - static_cast<long long>(run.FillPatch.size()),
    static_cast<long long>(current.NumberOfTriangles()), static_cast<long long>(run.FillPatch.size()));
  AccumulateFindings(found, last, result);
  stages.Lap("detection pass: cleaned surface");
  result.DetectionSeconds += std::chrono::duration<double>(Clock::now() - t1).count();
  return last ? PassOutcome::Last : PassOutcome::Again;
}

// The fill kind of each patch: the largest of its triangles'.
std::vector<unsigned char> FillOfPatches(
  const std::vector<Index>& patchLabels, Index count, const std::vector<unsigned char>& fill)
{
  std::vector<unsigned char> patchFill(size_t(count), 0);
  for (size_t t = 0; t < patchLabels.size(); ++t)
  {
    patchFill[patchLabels[t]] = std::max(patchFill[patchLabels[t]], fill[t]);
  }
  return patchFill;
}

// Completion by SPBM (TriangulatePatches or Spbm): the level's triangles, patches and fills.
bool CompleteBySpbm(const TriangleMesh& input, const TopologySimplificationParameters& parameters,
  const CleanedSurface& cleaned, const MeshTopology& cleanedTopology, Patchification& merged /* rebuilt here */,
  const CleanedSurface& unmerged /* labels only */, const AbortCheck& report, TopologySimplificationResult& result,
  StageClock& stages)
{
  // Same surface as the clean-up merge's patches: only the labels differ (merged groups).
  merged.BuildFromLabels(
    cleaned.Mesh, cleanedTopology, cleaned.Labels, cleaned.LabelCount, Patchification::AdjacencySource::Previous);
  const bool unmergedMayFollow =
    parameters.Completion != TopologyCompletion::TriangulatePatches && parameters.SpbmTargetTriangles > 0;
  if (!unmergedMayFollow)
  {
    merged.ReleaseAdjacency(); // not needed by the level generator
  }
  std::vector<unsigned char> patchFill = FillOfPatches(cleaned.Labels, cleaned.LabelCount, cleaned.Fill);
  auto generator = std::make_unique<SpbmLevelGenerator>();
  generator->Initialize(cleaned.Mesh, merged);
  stages.Lap("completion: merged patches, level generator");
  SpbmLevelParameters level = parameters.Spbm;
  auto abort = [&]() { return report(0.85); };
  bool ok = true;
  if (parameters.Completion == TopologyCompletion::TriangulatePatches)
  {
    level.Epsilon = parameters.CollinearTolerance * input.BoundingBoxDiagonal();
    level.MergePatches = false;
    level.CollapseChains = false;
    level.CompareCandidates = false;
    ok = generator->Generate(level, result.Level, abort);
  }
  else if (parameters.SpbmTargetTriangles > 0)
  {
    // The clean-up merge may leave too few patch boundaries for the target (SPBM keeps no
    // vertex inside a patch): then SPBM starts from the unmerged patches (it merges itself).
    SpbmLevelParameters finest = level;
    finest.Epsilon = -1.0;
    finest.MergePatches = false;
    finest.CollapseChains = false;
    if (generator->PredictTriangleCount(finest) < parameters.SpbmTargetTriangles)
    {
      merged.BuildFromLabels(cleaned.Mesh, cleanedTopology, unmerged.Labels, unmerged.LabelCount,
        Patchification::AdjacencySource::Previous);
      patchFill = FillOfPatches(unmerged.Labels, unmerged.LabelCount, cleaned.Fill);
      generator = std::make_unique<SpbmLevelGenerator>();
      generator->Initialize(cleaned.Mesh, merged);
    }
    merged.ReleaseAdjacency(); // before the level's own large arrays
    stages.Lap("completion: unmerged patches, level generator");
    // The final collapses below take the level to the target, so SPBM need not fight for the
    // count itself (as vtkPatchBoundaryMerge): failed patches that are unmerged already go
    // straight to their original triangles (no pass per finer-chain level, each one triangulating
    // the whole level again) and the target search skips the widest merging run (and the fallback
    // passes and replays of its level) when the removal stops far above the target.
    level.FinalCollapsesFollow = parameters.FinalCollapses;
    if (DecidesMergeMeasureFromNoise(parameters) && result.NoisyBendShare > parameters.SingleMeasureNoisyBendShare)
    {
      // A scan: the plain measure's level would be generated only to be discarded (session 40).
      level.CompareCandidates = false;
      level.SizeWeightedMerge = true;
    }
    result.SingleMergeMeasure = !level.CompareCandidates && level.SizeWeightedMerge;
    vtkLogF(TRACE, "[hbr] SPBM completion: %s",
      result.SingleMergeMeasure ? "size-weighted level alone" : "merge measures compared");
    ok = generator->GenerateForTarget(parameters.SpbmTargetTriangles, level, result.Level, nullptr, abort);
    stages.Lap("completion: SPBM level for the target");
    if (ok && parameters.FinalCollapses)
    {
      // As vtkPatchBoundaryMerge does: on rough scans the fallback passes unmerge patches and the
      // level stops far above the target (noisy:273 at 10%: 255,841 for 100,036), so the level's
      // own vertices are collapsed, keeping its topology (the removed features stay removed).
      // SpbmFinalCollapses itself leaves a level within its tolerance of the target as it is.
      SpbmFinalCollapseStatistics statistics;
      SpbmFinalCollapses(cleaned.Mesh, parameters.SpbmTargetTriangles, result.Level, statistics);
      result.FinalCollapses = statistics.Collapses;
      stages.Lap("completion: final collapses");
    }
  }
  else
  {
    ok = generator->Generate(level, result.Level, abort);
  }
  if (!ok)
  {
    return false;
  }
  result.Triangles = result.Level.Triangles;
  result.TrianglePatch = result.Level.TrianglePatch;
  result.NumberOfPatches = result.Level.NumberOfPatches;
  std::vector<unsigned char> levelFill(size_t(result.Level.NumberOfPatches), 0);
  for (size_t p = 0; p < result.Level.MergedPatchOf.size(); ++p)
  {
    const Index q = result.Level.MergedPatchOf[p];
    if (q != InvalidIndex)
    {
      levelFill[q] = std::max(levelFill[q], patchFill[p]);
    }
  }
  result.TriangleFill.resize(result.TrianglePatch.size());
  for (size_t t = 0; t < result.TrianglePatch.size(); ++t)
  {
    result.TriangleFill[t] = levelFill[result.TrianglePatch[t]];
  }
  return true;
}
} // namespace

bool TopologySimplifier::Run(const TriangleMesh& mesh, const TopologySimplificationParameters& parameters,
  TopologySimplificationResult& result, const ProgressFunction& progress, MeshTopology* meshTopology)
{
  using Clock = std::chrono::steady_clock;
  result = TopologySimplificationResult();
  StageClock stages("hole-bump removal"); // CPU per stage at TRACE (--log-verbosity 9)
  const AbortCheck report = [&](double f) { return progress && !progress(f); };
  // Detection passes: a removal can expose a new feature (the counterbore of a stepped hole is a
  // cavity once its hole is filled), so detection runs again on the cleaned surface while it
  // removes something, at most MaximumPasses times. Cracks are closed in the first pass only.
  TriangleMesh current = mesh;
  std::vector<unsigned char> currentFill(size_t(mesh.NumberOfTriangles()), 0);
  CleanedSurface cleaned;
  DetectionWorkspace workspace; // the passes' large arrays, then the clean-up merge's and completion's
  workspace.Patches.SetKeepAdjacency(true); // reused within its capacity; released before the SPBM level
  if (meshTopology && meshTopology->NumberOfTriangles() == mesh.NumberOfTriangles() &&
    meshTopology->NumberOfPoints() == mesh.NumberOfPoints())
  {
    // The first pass's surface is `mesh` itself (`current` is its copy): its topology as given.
    std::swap(workspace.Topology, *meshTopology);
    *meshTopology = MeshTopology();
    workspace.TopologyCurrent = true;
  }
  const int passes = std::max(1, parameters.MaximumPasses);
  for (int pass = 0; pass < passes; ++pass)
  {
    const PassOutcome outcome =
      DetectionPass(pass, passes, mesh, current, currentFill, parameters, report, result, cleaned, stages, workspace);
    result.DetectionPasses = pass + 1;
    if (outcome == PassOutcome::Aborted)
    {
      return false;
    }
    if (outcome == PassOutcome::Last)
    {
      break;
    }
    current.Triangles = cleaned.Mesh.Triangles;
    currentFill = cleaned.Fill;
  }
  const auto t2 = Clock::now();
  if (report(0.75))
  {
    return false;
  }

  stages.Lap("detection passes' copies");
  // Clean-up merge on the patchification of the cleaned mesh.
  result.DetectionWorkspaceAllocations = workspace.Allocations;
  result.DetectionTopologyTriangles = workspace.TopologyTriangles;
  workspace.Normal = std::vector<Vec3>(); // not used after the passes
  MeshTopology& cleanedTopology = workspace.Topology;
  Patchification& cleanedPatches = workspace.Patches;
  const std::int64_t adjacencyBefore = cleanedPatches.AdjacencyEntriesBuilt();
  // The last pass usually finds the surface it leaves (it removed nothing, or refilled what it
  // removed the same way): then the workspace's topology and adjacency, built over `current` by
  // that pass, are the cleaned surface's, and rebuilding them is a whole-surface pass of scattered
  // accesses for nothing. Comparing the triangles is one sequential pass.
  // Otherwise the last pass updated that topology to the cleaned surface (session 45: only
  // around the changed triangles; before, a whole Build here).
  const bool surfaceKept = workspace.LastSurfaceKept;
  cleanedTopology.Rebind(cleaned.Mesh);
  cleanedTopology.ReleaseUpdateBuffers();
  if (!surfaceKept)
  {
    result.CleanedTopologyTriangles = workspace.CleanedTopologyWork;
  }
  cleanedPatches.BuildFromLabels(cleaned.Mesh, cleanedTopology, cleaned.Labels, cleaned.LabelCount,
    surfaceKept ? Patchification::AdjacencySource::Previous : Patchification::AdjacencySource::Build);
  CleanedSurface unmerged;
  unmerged.Labels = cleaned.Labels;
  unmerged.LabelCount = cleaned.LabelCount;
  const std::vector<Index> group = CleanUpMerge(parameters, cleaned.Mesh, cleanedPatches, result.CleanUpMergeWork);
  for (Index& l : cleaned.Labels)
  {
    l = group[l];
  }
  cleaned.LabelCount = Compact(cleaned.Labels);
  result.MergedPatches = cleaned.LabelCount;
  result.CleanedTriangles = cleaned.Mesh.Triangles;
  stages.Lap("clean-up merge");
  vtkLogF(TRACE, "[hbr] cleaned surface %s: %lld topology triangles and %lld adjacency entries rebuilt so far",
    surfaceKept ? "kept by the last pass" : "changed by the last pass",
    static_cast<long long>(result.CleanedTopologyTriangles),
    static_cast<long long>(cleanedPatches.AdjacencyEntriesBuilt() - adjacencyBefore));
  if (report(0.8))
  {
    return false;
  }

  // Completion.
  if (parameters.Completion == TopologyCompletion::KeepTriangles)
  {
    result.Triangles = cleaned.Mesh.Triangles;
    result.TrianglePatch = cleaned.Labels;
    result.TriangleFill = cleaned.Fill;
    result.NumberOfPatches = cleaned.LabelCount;
  }
  else if (!CompleteBySpbm(mesh, parameters, cleaned, cleanedTopology, cleanedPatches, unmerged, report, result, stages))
  {
    return false;
  }
  result.CleanedAdjacencyEntries = cleanedPatches.AdjacencyEntriesBuilt() - adjacencyBefore;
  result.CompletionSeconds = std::chrono::duration<double>(Clock::now() - t2).count();
  report(1.0);
  return true;
}
} // namespace slod
