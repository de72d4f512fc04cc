// SPDX-License-Identifier: BSD-3-Clause
#include "slodPatchification.h"

#include "vtkMath.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace slod
{
namespace
{

} // namespace

// The adjacency the growth needs, as one flat array: the triangle across edge k of t when that
// edge is manifold and consistently oriented (the neighbour runs it the other way), else
// InvalidIndex. Growing only across such edges keeps every patch an orientable disk. Kept as a
// member only while KeepAdjacency is on (filled within its capacity), else released after each build.
struct Patchification::Adjacency
{
  const std::vector<Index>& Across;

  Index Neighbor(Index t, int k) const { return this->Across[3 * size_t(t) + k]; }
};

// Fills the oriented adjacency of `mesh` (three entries per triangle) within its capacity.
void Patchification::BuildAdjacency(const TriangleMesh& mesh, const MeshTopology& topology)
{
  const Index nt = mesh.NumberOfTriangles();
  this->Across.resize(3 * size_t(nt));
  for (Index t = 0; t < nt; ++t)
  {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      Index n = topology.EdgeNeighbor(t, k);
      if (n != InvalidIndex)
      {
        const Index a = tri[k], b = tri[(k + 1) % 3];
        const Index* other = mesh.Triangle(n);
        const bool consistent =
          (other[0] == b && other[1] == a) || (other[1] == b && other[2] == a) || (other[2] == b && other[0] == a);
        n = consistent ? n : InvalidIndex;
      }
      this->Across[3 * size_t(t) + k] = n;
    }
  }
  this->AdjacencyEntries += 3 * std::int64_t(nt);
}

// Releases the adjacency unless the caller keeps it for the next build over the same surface.
void Patchification::FinishAdjacency()
{
  if (!this->KeepsAdjacency)
  {
    this->ReleaseAdjacency();
  }
}

void Patchification::ReleaseAdjacency()
{
  this->Across = std::vector<Index>();
}

void Patchification::Build(const TriangleMesh& mesh, const MeshTopology& topology,
  const PatchificationParameters& parameters, const ProgressFunction& progress)
{
  this->WasAborted = false;
  this->NoiseJoins = 0;
  this->BuildAdjacency(mesh, topology);
  const Adjacency adjacency{ this->Across };
  this->Grow(mesh, topology, adjacency, parameters, progress);
  if (!this->WasAborted)
  {
    this->ExtractChains(mesh, topology, adjacency, parameters.BorderCornerAngle);
  }
  this->FinishAdjacency();
}

void Patchification::BuildFromLabels(const TriangleMesh& mesh, const MeshTopology& topology,
  const std::vector<Index>& patchOf, Index numberOfPatches, AdjacencySource source)
{
  this->WasAborted = false;
  this->NoiseJoins = 0;
  if (source == AdjacencySource::Build || this->Across.size() != 3 * size_t(mesh.NumberOfTriangles()))
  {
    this->BuildAdjacency(mesh, topology);
  }
  const Adjacency adjacency{ this->Across };
  this->TrianglePatch = patchOf;
  this->PatchAreaVector.assign(size_t(numberOfPatches), Vec3{ 0.0, 0.0, 0.0 });
  this->PatchAreaOf.assign(size_t(numberOfPatches), 0.0);
  this->PatchTriangleCountOf.assign(size_t(numberOfPatches), 0);
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    const Vec3 a = mesh.Point(tri[0]), b = mesh.Point(tri[1]), c = mesh.Point(tri[2]);
    const Vec3 areaVector = 0.5 * Cross(b - a, c - a);
    const Index p = patchOf[t];
    this->PatchAreaVector[p] = this->PatchAreaVector[p] + areaVector;
    this->PatchAreaOf[p] += Norm(areaVector);
    ++this->PatchTriangleCountOf[p];
  }
  this->ExtractChains(mesh, topology, adjacency, 0.0);
  this->FinishAdjacency();
}

namespace
{
// State of the patch growth (Ho 1999, section 4.2.2): the patch of each triangle, the running sums
// of the patch being grown, and the seed candidates. Neighbours come from Patchification's
// consistently oriented adjacency (`across`, three entries per triangle).
struct PatchGrowth
{
  const TriangleMesh& Mesh;
  const MeshTopology& Topology;
  const std::vector<Index>& Across;
  const PatchificationParameters& Parameters;
  std::vector<Index>& TrianglePatch;
  double CosOnePatch, CosOneNeighbor, CosTwoPatch, CosTwoNeighbor;
  double CosRuling; // above 1 when RulingAngle is off

  // Membership of vertices in the patch being grown: stamp + number of its triangles there.
  std::vector<Index> VertexStamp, VertexCount;
  // Patch that last owned a triangle: a triangle removed from P never rejoins P (termination).
  std::vector<Index> TriedStamp;
  std::vector<Index> Queue;
  std::vector<Index> PatchVertices; // of the patch being grown (some may have left it: InPatch)
  static constexpr size_t ThicknessCheckVertices = 4096;
  std::vector<Index> Rejected;   // free neighbours met by the current patch: next seeds
  std::vector<Index> Candidates; // older seed candidates
  Index Scan = 0;
  Index Assigned = 0;
  mutable Index NoiseJoins = 0; // Patchification::NoiseToleranceJoins

  // The patch being grown.
  Index Patch = InvalidIndex;
  Index Seed = InvalidIndex;
  Vec3 Sum{ 0, 0, 0 };
  Vec3 CentroidSum{ 0, 0, 0 }; // area-weighted
  double Area = 0;
  Index Count = 0;

  PatchGrowth(const TriangleMesh& mesh, const MeshTopology& topology, const std::vector<Index>& across,
    const PatchificationParameters& parameters, std::vector<Index>& trianglePatch)
    : Mesh(mesh)
    , Topology(topology)
    , Across(across)
    , Parameters(parameters)
    , TrianglePatch(trianglePatch)
    , CosOnePatch(std::cos(Radians(parameters.OneEdgePatchAngle)))
    , CosOneNeighbor(std::cos(Radians(parameters.OneEdgeNeighborAngle)))
    , CosTwoPatch(std::cos(Radians(parameters.TwoEdgePatchAngle)))
    , CosTwoNeighbor(std::cos(Radians(parameters.TwoEdgeNeighborAngle)))
    , CosRuling(parameters.RulingAngle > 0 ? std::cos(Radians(parameters.RulingAngle)) : 2.0)
    , VertexStamp(size_t(mesh.NumberOfPoints()), InvalidIndex)
    , VertexCount(size_t(mesh.NumberOfPoints()), 0)
    , TriedStamp(size_t(mesh.NumberOfTriangles()), InvalidIndex)
  {
  }

  Index Neighbor(Index t, int k) const { return this->Across[3 * size_t(t) + k]; }
  Vec3 WeightOf(Index t, Vec3& areaVector) const
  {
    areaVector = this->Mesh.TriangleAreaVector(t);
    return this->Parameters.AreaWeighted ? areaVector : Normalized(areaVector);
  }
  bool InPatch(Index v) const { return this->VertexStamp[v] == this->Patch && this->VertexCount[v] > 0; }
  bool IsFree(Index t) const { return this->TrianglePatch[t] == InvalidIndex; }

  void Add(Index t)
  {
    this->TrianglePatch[t] = this->Patch;
    this->TriedStamp[t] = this->Patch;
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      if (this->VertexStamp[tri[k]] != this->Patch)
      {
        this->VertexStamp[tri[k]] = this->Patch;
        this->VertexCount[tri[k]] = 0;
        this->PatchVertices.push_back(tri[k]);
      }
      ++this->VertexCount[tri[k]];
    }
    Vec3 av;
    this->Sum = this->Sum + this->WeightOf(t, av);
    this->Area += 0.5 * Norm(av);
    this->CentroidSum = this->CentroidSum +
      (Norm(av) / 6.0) * (this->Mesh.Point(tri[0]) + this->Mesh.Point(tri[1]) + this->Mesh.Point(tri[2]));
    ++this->Count;
    ++this->Assigned;
    this->Queue.push_back(t);
  }

  void Remove(Index t)
  {
    this->TrianglePatch[t] = InvalidIndex;
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      --this->VertexCount[tri[k]];
    }
    Vec3 av;
    this->Sum = this->Sum - this->WeightOf(t, av);
    this->Area -= 0.5 * Norm(av);
    this->CentroidSum = this->CentroidSum -
      (Norm(av) / 6.0) * (this->Mesh.Point(tri[0]) + this->Mesh.Point(tri[1]) + this->Mesh.Point(tri[2]));
    --this->Count;
    --this->Assigned;
  }

  // Edges of t shared with the current patch; `opposite` gets the vertex opposite the shared
  // edge when there is exactly one, and with two the vertex they have in common.
  int SharedEdges(Index t, Index& opposite) const
  {
    int shared = 0, free = 0;
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index n = this->Neighbor(t, k);
      if (n != InvalidIndex && this->TrianglePatch[n] == this->Patch)
      {
        ++shared;
        opposite = tri[(k + 2) % 3];
      }
      else
      {
        free = k;
      }
    }
    if (shared == 2)
    {
      opposite = tri[(free + 2) % 3];
    }
    return shared;
  }

  // NoiseTolerance: every vertex of t within that distance of the plane through `centroid`
  // with normal `normal`.
  bool WithinNoise(Index t, const Vec3& centroid, const Vec3& normal) const
  {
    const double tolerance = this->Parameters.NoiseTolerance;
    if (!(tolerance > 0))
    {
      return false;
    }
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      if (std::fabs(Dot(this->Mesh.Point(tri[k]) - centroid, normal)) > tolerance)
      {
        return false;
      }
    }
    return true;
  }

  // Feasibility tests (a) and (b) of section 4.2.2 (and the plane-distance extension) for the
  // free triangle `candidate` next to t in the current patch.
  bool Feasible(Index t, Index candidate) const
  {
    Index opposite = InvalidIndex;
    const int shared = this->SharedEdges(candidate, opposite);
    if (shared >= 3 || shared == 0)
    {
      return false;
    }
    if (this->TriedStamp[candidate] == this->Patch && shared < 2)
    {
      // Removed from this patch before: it may come back only to fill a notch (two shared
      // edges), after which it can never be removed again (termination).
      return false;
    }
    if (shared == 1 && this->InPatch(opposite))
    {
      return false; // (a) would pinch the patch boundary
    }
    if (shared == 2 && this->Topology.IsNonManifoldVertex(opposite))
    {
      // Would close a fan of a non-manifold vertex (a pinch of several fans) inside the patch:
      // SPBM keeps no vertex inside a patch, so the other fans would lose it (Euler + 1).
      return false;
    }
    const Vec3 nc = Normalized(this->Mesh.TriangleAreaVector(candidate));
    const Vec3 nt = Normalized(this->Mesh.TriangleAreaVector(t));
    const Vec3 np = Normalized(this->Sum);
    if (shared == 1 && this->Area > 0)
    {
      const Vec3 centroid = (1.0 / this->Area) * this->CentroidSum;
      const double maximumDistance = this->Parameters.MaximumPlaneDistance;
      const bool small = this->Parameters.BoundPatchThickness && this->Count <= this->Parameters.SmallPatchTriangles;
      if (maximumDistance > 0 &&
        std::fabs(Dot(this->Mesh.Point(opposite) - centroid, np)) > (small ? 2 : 1) * maximumDistance)
      {
        return false; // the patch would bend away from its plane
      }
      if (this->Parameters.BoundPatchThickness && maximumDistance > 0 &&
        this->PatchVertices.size() <= ThicknessCheckVertices && !this->StaysThin(candidate))
      {
        return false; // the running plane has followed the patch as it bent
      }
      if (this->WithinNoise(candidate, centroid, np) && Dot(nc, np) >= 0.5) // cos 60 degrees
      {
        // Within the noise of a plane: its normal says nothing about the surface.
        this->NoiseJoins += !(Dot(nc, np) >= this->CosOnePatch && Dot(nc, nt) >= this->CosOneNeighbor);
        return true;
      }
    }
    const double cosPatch = shared == 1 ? this->CosOnePatch : this->CosTwoPatch;
    const double cosNeighbor = shared == 1 ? this->CosOneNeighbor : this->CosTwoNeighbor;
    return Dot(nc, np) >= cosPatch && Dot(nc, nt) >= cosNeighbor; // (b)
  }

  // RulingAngle: the surface does not bend from t to its neighbour n (their normals within that
  // angle), as along a ruling of a developable surface.
  bool AlongRuling(Index t, Index n) const
  {
    return this->CosRuling <= 1.0 &&
      Dot(Normalized(this->Mesh.TriangleAreaVector(t)), Normalized(this->Mesh.TriangleAreaVector(n))) >= this->CosRuling;
  }

  // Whether the patch with the new vertex of `candidate` stays within twice the plane distance
  // along the patch normal, measured over the patch's vertices (at most ThicknessCheckVertices of
  // them, which bounds the work per join; a larger patch does not stay thin here). The running
  // plane follows a long patch as it bends: on mc1m 1% of the patches grew 1.5-4.8 times thicker
  // than twice the plane distance; joins along a ruling (RulingAngle) lengthen patches more (10x).
  bool StaysThin(Index candidate) const
  {
    const double maximumDistance = this->Parameters.MaximumPlaneDistance;
    if (!(maximumDistance > 0))
    {
      return true;
    }
    if (this->PatchVertices.size() > ThicknessCheckVertices)
    {
      return false;
    }
    Index opposite = InvalidIndex;
    this->SharedEdges(candidate, opposite);
    const Vec3 normal = Normalized(this->Sum);
    double lo = Dot(normal, this->Mesh.Point(opposite)), hi = lo;
    for (const Index v : this->PatchVertices)
    {
      if (this->InPatch(v))
      {
        const double h = Dot(normal, this->Mesh.Point(v));
        lo = std::min(lo, h);
        hi = std::max(hi, h);
      }
    }
    return hi - lo <= 2 * maximumDistance;
  }

  // One step of the growth front: the free neighbours of t in the current patch are added or
  // rejected (the four cases of section 4.2.2).
  void Expand(Index t)
  {
    Index freeNeighbors[3];
    int freeCount = 0;
    for (int k = 0; k < 3; ++k)
    {
      const Index n = this->Neighbor(t, k);
      if (n != InvalidIndex && this->IsFree(n))
      {
        freeNeighbors[freeCount++] = n;
      }
    }
    if (freeCount == 1 || freeCount == 3 || t == this->Seed)
    {
      // One free neighbour; or a seed (three free neighbours in the paper's first patch; a
      // later seed next to a finished patch has one or two): add each feasible one. Treating
      // a two-neighbour seed like the paper's case 2 would leave it alone, and its rejected
      // neighbour would seed the next single-triangle patch along every crease.
      bool ok[3];
      for (int i = 0; i < freeCount; ++i)
      {
        ok[i] = this->Feasible(t, freeNeighbors[i]);
      }
      for (int i = 0; i < freeCount; ++i)
      {
        if (ok[i] && this->IsFree(freeNeighbors[i]))
        {
          this->Add(freeNeighbors[i]);
        }
        else
        {
          this->Rejected.push_back(freeNeighbors[i]);
        }
      }
    }
    else if (freeCount == 2)
    {
      this->ExpandTwo(t, freeNeighbors[0], freeNeighbors[1]);
    }
  }

  // Two free neighbours: both join or neither does.
  void ExpandTwo(Index t, Index first, Index second)
  {
    const bool firstFeasible = this->Feasible(t, first), secondFeasible = this->Feasible(t, second);
    if (firstFeasible && secondFeasible)
    {
      this->Add(first);
      this->Add(second);
      return;
    }
    const Index alone = firstFeasible ? first : second;
    if ((firstFeasible || secondFeasible) && this->AlongRuling(t, alone) && this->StaysThin(alone))
    {
      this->Add(alone);
      this->Rejected.push_back(alone == first ? second : first);
      return;
    }
    this->Rejected.push_back(first);
    this->Rejected.push_back(second);
    // Neither: drop T itself to keep the patch fat, when that keeps it a disk.
    Index opposite = InvalidIndex;
    if (t != this->Seed && this->SharedEdges(t, opposite) == 1 && this->VertexCount[opposite] == 1)
    {
      this->Remove(t);
      this->Rejected.push_back(t);
    }
  }

  // Grows patch `patch` breadth-first from `seed` until its front is exhausted. Each triangle
  // is queued once per join, and a removed triangle rejoins only through a notch (never removed
  // again), so the queue is bounded.
  void GrowPatch(Index patch, Index seed)
  {
    this->Patch = patch;
    this->Seed = seed;
    this->Sum = { 0, 0, 0 };
    this->CentroidSum = { 0, 0, 0 };
    this->Area = 0;
    this->Count = 0;
    this->Queue.clear();
    this->Rejected.clear();
    this->PatchVertices.clear();
    this->Add(seed);
    for (size_t head = 0; head < this->Queue.size(); ++head)
    {
      const Index t = this->Queue[head];
      if (this->TrianglePatch[t] == this->Patch) // else removed meanwhile
      {
        this->Expand(t);
      }
    }
  }

  // Next seed: a free triangle next to the patch just finished, else an older candidate, else
  // the next free triangle in index order (a new component); InvalidIndex when none is left.
  Index NextSeed()
  {
    Index seed = InvalidIndex;
    for (const Index t : this->Rejected)
    {
      if (this->IsFree(t))
      {
        if (seed == InvalidIndex)
        {
          seed = t;
        }
        else
        {
          this->Candidates.push_back(t);
        }
      }
    }
    while (seed == InvalidIndex && !this->Candidates.empty())
    {
      const Index t = this->Candidates.back();
      this->Candidates.pop_back();
      if (this->IsFree(t))
      {
        seed = t;
      }
    }
    const Index nt = this->Mesh.NumberOfTriangles();
    while (seed == InvalidIndex && this->Scan < nt)
    {
      if (this->IsFree(this->Scan))
      {
        seed = this->Scan;
      }
      ++this->Scan;
    }
    return seed;
  }
};
} // namespace

// Breadth-first growth with the four cases of section 4.2.2. The disk invariant is kept exactly:
// a triangle sharing one edge with P joins only when its third vertex is not yet in P (no pinch,
// feasibility test (a)); one sharing two edges closes a notch; one sharing three never joins; a
// triangle is removed again (case "two free neighbours, infeasible") only when it hangs on P by
// one edge and its opposite vertex belongs to no other triangle of P. A removed triangle may
// rejoin P later only through two shared edges (a notch).
void Patchification::Grow(const TriangleMesh& mesh, const MeshTopology& topology, const Adjacency& adjacency,
  const PatchificationParameters& parameters, const ProgressFunction& progress)
{
  const Index nt = mesh.NumberOfTriangles();
  this->TrianglePatch.assign(size_t(nt), InvalidIndex);
  this->PatchAreaVector.clear();
  this->PatchAreaOf.clear();
  this->PatchTriangleCountOf.clear();

  PatchGrowth growth(mesh, topology, adjacency.Across, parameters, this->TrianglePatch);
  Index nextReport = 65536;
  Index seed = nt > 0 ? 0 : InvalidIndex;
  while (seed != InvalidIndex)
  {
    growth.GrowPatch(this->NumberOfPatches(), seed);
    this->PatchAreaVector.push_back(growth.Sum);
    this->PatchAreaOf.push_back(growth.Area);
    this->PatchTriangleCountOf.push_back(growth.Count);

    if (progress && growth.Assigned >= nextReport)
    {
      nextReport = growth.Assigned + 65536;
      if (!progress(0.9 * double(growth.Assigned) / double(nt)))
      {
        this->WasAborted = true;
        return;
      }
    }
    seed = growth.NextSeed();
  }
  this->NoiseJoins = growth.NoiseJoins;
}

namespace
{
// Half-edge h = 3 t + k is edge k of triangle t. The walk sees the patch boundaries: a half-edge
// is on a boundary when the triangle across (in the oriented adjacency) is missing or in
// another patch.
struct BoundaryWalk
{
  const TriangleMesh& Mesh;
  const MeshTopology& Topology;
  const std::vector<Index>& Across;
  const std::vector<Index>& PatchOf;

  Index Neighbor(Index h) const { return this->Across[size_t(h)]; }
  bool IsBoundary(Index h) const
  {
    const Index n = this->Neighbor(h);
    return n == InvalidIndex || this->PatchOf[n] != this->PatchOf[h / 3];
  }
  // The patch across h (InvalidIndex on the border or along a non-manifold edge).
  Index RightOf(Index h) const
  {
    const Index n = this->Neighbor(h);
    return n == InvalidIndex ? InvalidIndex : this->PatchOf[n];
  }
  bool NonManifold(Index h) const
  {
    return this->Topology.IsNonManifoldEdge(this->Topology.TriangleEdge(h / 3, h % 3));
  }
  Index Origin(Index h) const { return this->Mesh.Triangles[size_t(h)]; }
  Index Target(Index h) const { return this->Mesh.Triangles[size_t(h - h % 3 + (h % 3 + 1) % 3)]; }
  // Each two-sided chain is emitted once, from its lower patch.
  bool Owns(Index h) const
  {
    const Index r = this->RightOf(h);
    return r == InvalidIndex || this->PatchOf[h / 3] < r;
  }
  // Next boundary half-edge of the same patch, leaving the target of h (rotate inside the patch;
  // at most the vertex degree steps).
  Index Next(Index h) const
  {
    const Index b = this->Target(h);
    Index g = h - h % 3 + (h % 3 + 1) % 3;
    for (Index guard = this->Topology.VertexDegree(b) + 1; guard > 0; --guard)
    {
      if (this->IsBoundary(g))
      {
        return g;
      }
      const Index n = this->Neighbor(g);
      const Index* tri = this->Mesh.Triangle(n);
      const int j = tri[0] == b ? 0 : (tri[1] == b ? 1 : 2);
      g = 3 * n + j;
    }
    return InvalidIndex; // not a fan (cannot happen for a disk patch of an oriented mesh)
  }
};

// Endpoints: where the patch across changes along a patch boundary, plus non-manifold vertices.
// A mesh-border vertex between border half-edges h and g (in and out) where the border turns by
// more than the angle whose cosine is given.
bool BorderCorner(const BoundaryWalk& walk, Index h, Index g, double cosine)
{
  if (walk.Neighbor(h) != InvalidIndex || walk.Neighbor(g) != InvalidIndex || walk.NonManifold(h) || walk.NonManifold(g))
  {
    return false;
  }
  const Vec3 a = walk.Mesh.Point(walk.Origin(h)), b = walk.Mesh.Point(walk.Target(h)), c = walk.Mesh.Point(walk.Target(g));
  const Vec3 in = b - a, out = c - b;
  const double lengths = Norm(in) * Norm(out);
  return lengths > 0 && Dot(in, out) <= cosine * lengths;
}

std::vector<unsigned char> MarkChainEnds(const BoundaryWalk& walk, double borderCornerAngle)
{
  const double cornerCosine = std::cos(vtkMath::RadiansFromDegrees(borderCornerAngle));
  const Index nv = walk.Mesh.NumberOfPoints();
  std::vector<unsigned char> isEnd(size_t(nv), 0);
  for (Index v = 0; v < nv; ++v)
  {
    if (walk.Topology.IsNonManifoldVertex(v))
    {
      isEnd[v] = 1;
    }
  }
  const Index nh = 3 * walk.Mesh.NumberOfTriangles();
  for (Index h = 0; h < nh; ++h)
  {
    if (!walk.IsBoundary(h))
    {
      continue;
    }
    const Index g = walk.Next(h);
    if (g == InvalidIndex || walk.RightOf(g) != walk.RightOf(h) || walk.NonManifold(g) != walk.NonManifold(h) ||
      (borderCornerAngle > 0 && BorderCorner(walk, h, g, cornerCosine)))
    {
      isEnd[walk.Target(h)] = 1;
    }
  }
  return isEnd;
}

// The chain lists being filled (Patchification's members): a chain's vertices are appended to
// Vertices, then Emit closes it.
struct ChainLists
{
  std::vector<Index>& Offsets;
  std::vector<Index>& Vertices;
  std::vector<Index>& Left;
  std::vector<Index>& Right;
  std::vector<unsigned char>& Flags;
  unsigned char NonManifoldFlag;

  void Emit(Index left, Index right, bool nonManifold)
  {
    this->Offsets.push_back(static_cast<Index>(this->Vertices.size()));
    this->Left.push_back(left);
    this->Right.push_back(right);
    this->Flags.push_back(nonManifold ? this->NonManifoldFlag : 0);
  }
};

// Chains that start at an endpoint: follow the boundary until the next endpoint. Every
// half-edge is visited at most once.
void TraceChainsFromEnds(const BoundaryWalk& walk, const std::vector<unsigned char>& isEnd,
  std::vector<unsigned char>& visited, ChainLists& chains)
{
  const Index nh = static_cast<Index>(visited.size());
  for (Index h0 = 0; h0 < nh; ++h0)
  {
    if (visited[h0] || !isEnd[walk.Origin(h0)] || !walk.IsBoundary(h0) || !walk.Owns(h0))
    {
      continue;
    }
    const Index left = walk.PatchOf[h0 / 3], right = walk.RightOf(h0);
    const bool nm = walk.NonManifold(h0);
    chains.Vertices.push_back(walk.Origin(h0));
    Index h = h0;
    while (h != InvalidIndex && !visited[h])
    {
      visited[h] = 1;
      const Index b = walk.Target(h);
      chains.Vertices.push_back(b);
      if (isEnd[b])
      {
        break;
      }
      h = walk.Next(h);
    }
    chains.Emit(left, right, nm);
  }
}

// Closed boundary loops without endpoints (e.g. a sphere cut in two): cut at three vertices,
// which become endpoints.
void CutClosedLoops(
  const BoundaryWalk& walk, std::vector<unsigned char>& isEnd, std::vector<unsigned char>& visited, ChainLists& chains)
{
  const Index nh = static_cast<Index>(visited.size());
  std::vector<Index> loop;
  for (Index h0 = 0; h0 < nh; ++h0)
  {
    if (visited[h0] || !walk.IsBoundary(h0) || !walk.Owns(h0))
    {
      continue;
    }
    loop.clear();
    Index h = h0;
    while (h != InvalidIndex && !visited[h])
    {
      visited[h] = 1;
      loop.push_back(walk.Origin(h));
      h = walk.Next(h);
    }
    const Index left = walk.PatchOf[h0 / 3], right = walk.RightOf(h0);
    const bool nm = walk.NonManifold(h0);
    const size_t n = loop.size();
    const size_t cut[4] = { 0, n / 3, (2 * n) / 3, n };
    for (int part = 0; part < 3; ++part)
    {
      if (cut[part + 1] == cut[part])
      {
        continue;
      }
      isEnd[loop[cut[part]]] = 1;
      for (size_t i = cut[part]; i <= cut[part + 1]; ++i)
      {
        chains.Vertices.push_back(loop[i % n]);
      }
      chains.Emit(left, right, nm);
    }
  }
}
} // namespace

// Chains: boundary half-edges of each patch (edges whose other side is another patch, the border
// or a non-manifold edge) are followed counter-clockwise around the patch; a chain ends where the
// patch on the other side changes. Closed loops without such a vertex (e.g. a patch inside a
// single other patch's hole... on a sphere cut in two) are cut into three chains.
void Patchification::ExtractChains(
  const TriangleMesh& mesh, const MeshTopology& topology, const Adjacency& adjacency, double borderCornerAngle)
{
  const BoundaryWalk walk{ mesh, topology, adjacency.Across, this->TrianglePatch };
  std::vector<unsigned char> isEnd = MarkChainEnds(walk, borderCornerAngle);

  this->ChainOffsets.assign(1, 0);
  this->ChainVertexList.clear();
  this->ChainLeft.clear();
  this->ChainRight.clear();
  this->ChainFlags.clear();
  ChainLists chains{ this->ChainOffsets, this->ChainVertexList, this->ChainLeft, this->ChainRight, this->ChainFlags,
    NonManifoldChain };
  std::vector<unsigned char> visited(3 * size_t(mesh.NumberOfTriangles()), 0);
  TraceChainsFromEnds(walk, isEnd, visited, chains);
  CutClosedLoops(walk, isEnd, visited, chains);

  this->NumberEndpoints(mesh, topology);
  this->BuildPatchGraph();
}

// Endpoint ids, in the order chains first reach them.
void Patchification::NumberEndpoints(const TriangleMesh& mesh, const MeshTopology& topology)
{
  std::vector<Index> endpointOf(size_t(mesh.NumberOfPoints()), InvalidIndex);
  this->EndpointVertices.clear();
  this->EndpointBorder.clear();
  const Index nc = this->NumberOfChains();
  this->ChainEndpoints.resize(2 * size_t(nc));
  for (Index c = 0; c < nc; ++c)
  {
    for (int end = 0; end < 2; ++end)
    {
      const Index v = end == 0 ? this->ChainVertexList[this->ChainOffsets[c]]
                               : this->ChainVertexList[this->ChainOffsets[c + 1] - 1];
      if (endpointOf[v] == InvalidIndex)
      {
        endpointOf[v] = static_cast<Index>(this->EndpointVertices.size());
        this->EndpointVertices.push_back(v);
        this->EndpointBorder.push_back(topology.IsBoundaryVertex(v) || topology.IsNonManifoldVertex(v));
      }
      this->ChainEndpoints[2 * size_t(c) + end] = endpointOf[v];
    }
  }
}

// Patch graph (CSR): the chains around each patch.
void Patchification::BuildPatchGraph()
{
  const Index nc = this->NumberOfChains();
  const Index np = this->NumberOfPatches();
  this->PatchChainOffsets.assign(size_t(np) + 1, 0);
  for (Index c = 0; c < nc; ++c)
  {
    ++this->PatchChainOffsets[this->ChainLeft[c] + 1];
    if (this->ChainRight[c] != InvalidIndex)
    {
      ++this->PatchChainOffsets[this->ChainRight[c] + 1];
    }
  }
  for (Index p = 0; p < np; ++p)
  {
    this->PatchChainOffsets[p + 1] += this->PatchChainOffsets[p];
  }
  this->PatchChainList.resize(this->PatchChainOffsets[np]);
  std::vector<Index> fill(this->PatchChainOffsets.begin(), this->PatchChainOffsets.end() - 1);
  for (Index c = 0; c < nc; ++c)
  {
    this->PatchChainList[fill[this->ChainLeft[c]]++] = c;
    if (this->ChainRight[c] != InvalidIndex)
    {
      this->PatchChainList[fill[this->ChainRight[c]]++] = c;
    }
  }
}

bool Patchification::PatchBoundaryLoop(Index p, std::vector<Index>& loop) const
{
  loop.clear();
  struct Oriented
  {
    Index Chain;
    bool Reversed;
  };
  std::vector<Oriented> chains;
  for (const Index* c = this->PatchChainsBegin(p); c != this->PatchChainsEnd(p); ++c)
  {
    if (this->ChainLeft[*c] == p)
    {
      chains.push_back({ *c, false });
    }
    if (this->ChainRight[*c] == p)
    {
      chains.push_back({ *c, true });
    }
  }
  if (chains.empty())
  {
    return false;
  }
  auto first = [&](const Oriented& o) { return o.Reversed ? this->ChainEnd(o.Chain) : this->ChainStart(o.Chain); };
  auto last = [&](const Oriented& o) { return o.Reversed ? this->ChainStart(o.Chain) : this->ChainEnd(o.Chain); };
  std::vector<char> used(chains.size(), 0);
  size_t current = 0;
  used[0] = 1;
  for (size_t step = 0; step < chains.size(); ++step)
  {
    const Oriented& o = chains[current];
    const Index* v = this->ChainVerticesBegin(o.Chain);
    const Index n = this->ChainSize(o.Chain);
    for (Index i = 0; i + 1 < n; ++i) // the last vertex starts the next chain
    {
      loop.push_back(o.Reversed ? v[n - 1 - i] : v[i]);
    }
    if (step + 1 == chains.size())
    {
      if (last(o) != first(chains[0]))
      {
        return false; // does not close
      }
      break;
    }
    size_t following = chains.size();
    for (size_t j = 0; j < chains.size(); ++j)
    {
      if (!used[j] && first(chains[j]) == last(o))
      {
        if (following != chains.size())
        {
          return false; // two ways on: not a simple loop
        }
        following = j;
      }
    }
    if (following == chains.size())
    {
      return false;
    }
    used[following] = 1;
    current = following;
  }
  // Simple: no vertex twice.
  std::vector<Index> sorted(loop);
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end() && loop.size() >= 3;
}

size_t Patchification::MemoryUsage() const
{
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(this->TrianglePatch) + bytes(this->PatchAreaVector) + bytes(this->PatchAreaOf) +
    bytes(this->PatchTriangleCountOf) + bytes(this->ChainOffsets) + bytes(this->ChainVertexList) +
    bytes(this->ChainLeft) + bytes(this->ChainRight) + bytes(this->ChainEndpoints) + bytes(this->ChainFlags) +
    bytes(this->EndpointVertices) + bytes(this->EndpointBorder) + bytes(this->PatchChainOffsets) +
    bytes(this->PatchChainList);
}
} // namespace slod
