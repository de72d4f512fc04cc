// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: patchification of a triangle mesh (Ho 1999, sections 4.2.1-4.2.3).
//
// The surface is partitioned into patches, each a simply connected set of triangles (a disk:
// one simple boundary loop, no pinch points) whose normals stay within a cone around the
// patch's running (area-weighted) normal. Patches grow breadth-first from a seed triangle; the
// next seed is a free triangle next to the patch just finished. The common boundaries between
// patches (and the mesh border) are cut into chains at the vertices where the neighbouring
// patch changes ("endpoints"); chains and patches form the patch graph.
//
// Used by the SPBM level generator (slodPatchBoundaryMerge) and meant for reuse by the topology
// simplification of chapter 5 (sharp loops are cycles of chains).
#ifndef slodPatchification_h
#define slodPatchification_h

#include "slodMeshTopology.h"
#include "slodFilterContract.h"
#include "slodTriangleMesh.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT PatchificationParameters
{
  // Feasibility (b), in degrees. A free triangle T' next to T in patch P joins P when
  // angle(n_T', n_P) <= PatchAngle and angle(n_T', n_T) <= NeighborAngle. The first pair applies
  // when T' shares one edge with P, the second (looser: it fills a notch) when it shares two.
  double OneEdgePatchAngle = 25.0;
  double OneEdgeNeighborAngle = 20.0;
  double TwoEdgePatchAngle = 90.0;
  double TwoEdgeNeighborAngle = 90.0;
  // The running patch normal averages triangle normals weighted by area (else unweighted).
  bool AreaWeighted = true;
  // Extension (not in the paper; 0 = off): a triangle joins only if its new vertex lies within
  // this distance of the patch's running plane (area-weighted centroid and normal). A patch is
  // re-triangulated from its boundary alone, so this bounds the flat-patch error on curved parts.
  double MaximumPlaneDistance = 0.0;
  // Extension (issue 15, session 25; 0 = off, the paper): the growth case of a triangle with two
  // free neighbours adds both or neither (the paper keeps patches fat). On a developable surface
  // (the cylinders and cones of CAD parts) the neighbour along the ruling has the normal of the
  // triangle it grows from while the one across the curvature bends away, so that rule also stops
  // the patch along the ruling: patches stay about as long as the curvature lets them be wide
  // (the Fandisk's cylinders became grids of tiny patches whose corners took the budget). A
  // feasible neighbour whose normal is within this angle (degrees) of the triangle's joins alone
  // when the other one is infeasible.
  double RulingAngle = 0.0;
  // Extension (issue 15, session 25; off = the new vertex's distance alone): MaximumPlaneDistance
  // also bounds the patch's whole extent along its running normal (twice the distance, measured
  // over its vertices while it has at most 4096), since the running plane follows a patch as it
  // bends. Joins along a ruling are always checked this way.
  bool BoundPatchThickness = false;
  // Extension (issue 15, session 27; 0 = off): with BoundPatchThickness, while the patch has at
  // most this many triangles the new vertex may lie up to twice MaximumPlaneDistance from the
  // running plane (the span bound, which still applies). The running plane of a patch of a few
  // triangles is about that of one of them, not the middle of the patch, so the vertex's distance
  // is the span itself, and the bound on it was half the span that merges allow: thin targets left
  // most seeds alone (mc1m at 50%: 47% of 304,459 patches were single triangles, each one merged
  // again by every merging run of the target search).
  Index SmallPatchTriangles = 0;
  // Extension (issue 10, session 24; 0 = off): a triangle sharing one edge with the patch whose
  // three vertices lie within this distance of the patch's running plane, and whose normal is within
  // 60 degrees of the patch normal, joins without the angle tests of (b). On a scan isosurface
  // (marching cubes over voxels: staircase steps, noise) about a quarter of the neighbouring
  // triangles differ by more than 25 degrees while the surface stays within a voxel of a plane, so
  // the cones alone made patches of about three triangles. Such a triangle cannot move the
  // re-triangulated surface by more than this distance; the 60 degrees keep it from folding over
  // in the patch's projection.
  double NoiseTolerance = 0.0;
  // Extension (issue 15, session 31; 0 = off, the paper): a mesh-border vertex where the border
  // turns by at least this angle (degrees, between its two border edges) ends the chains there,
  // like a change of the patch across. Endpoints on the border are never removed, so a corner of
  // an open sheet stays where it is; inside a chain, the chain tolerance alone decided, and a
  // coarse target's tolerance cut the corner off (three_peaks at 10%: 1.7 against vtkQD's 0.2).
  double BorderCornerAngle = 0.0;
};

class SURFACELODFILTERS_EXPORT Patchification
{
public:
  // Optional progress (slodFilterContract.h): returning false aborts (the result is then
  // incomplete and Aborted() is true).
  void Build(const TriangleMesh& mesh, const MeshTopology& topology, const PatchificationParameters& parameters,
    const ProgressFunction& progress = nullptr);
  bool Aborted() const { return this->WasAborted; }
  // NoiseTolerance at work (issue 15, session 35): how many candidates of the growth joined by the
  // noise tolerance whose normals the angle tests (b) refuse. Next to none on smooth and CAD
  // surfaces, whose neighbouring triangles pass (b) anyway; on a scan isosurface the tolerance
  // admits a large share of the triangles (noise and staircase steps). 0 from BuildFromLabels.
  Index NoiseToleranceJoins() const { return this->NoiseJoins; }

  // Patches given by the caller instead of grown (e.g. after the topology simplification of
  // chapter 5 removed wall patches and merged the rest): patchOf[t] in [0, numberOfPatches) for
  // every triangle; each patch should be a disk (an edge-connected, consistently oriented set with
  // one simple boundary loop). Patch normals are area-weighted sums; chains, endpoints and the
  // patch graph are extracted as in Build, so SpbmLevelGenerator can run on the result.
  //
  // The oriented adjacency (three indices per triangle, read through the topology's edges: a
  // scattered pass over the whole surface) depends on the surface alone, not on the labels. With
  // KeepAdjacency on, a build keeps it, and AdjacencySource::Previous reuses it: the caller
  // promises that `mesh` has the triangles (in the same order) and `topology` the edges of the
  // surface of the previous Build or BuildFromLabels (vtkHoleBumpRemoval builds patches from
  // three label sets over one cleaned surface, session 44). A size mismatch rebuilds it.
  enum class AdjacencySource
  {
    Build,
    Previous
  };
  void BuildFromLabels(const TriangleMesh& mesh, const MeshTopology& topology, const std::vector<Index>& patchOf,
    Index numberOfPatches, AdjacencySource source = AdjacencySource::Build);
  // Keep the adjacency after each build (off: released at the end of each build, as a local).
  void SetKeepAdjacency(bool keep) { this->KeepsAdjacency = keep; }
  void ReleaseAdjacency();
  // Adjacency entries computed so far (three per triangle per build that did not reuse it).
  std::int64_t AdjacencyEntriesBuilt() const { return this->AdjacencyEntries; }

  // --- Patches ---
  Index NumberOfPatches() const { return static_cast<Index>(this->PatchAreaVector.size()); }
  // Patch of each triangle (every triangle belongs to exactly one patch).
  const std::vector<Index>& TrianglePatches() const { return this->TrianglePatch; }
  // Sum of the member triangles' normals (area vectors when AreaWeighted, unit normals otherwise).
  const Vec3& PatchNormalSum(Index p) const { return this->PatchAreaVector[p]; }
  Vec3 PatchNormal(Index p) const { return Normalized(this->PatchAreaVector[p]); }
  double PatchArea(Index p) const { return this->PatchAreaOf[p]; }
  Index PatchTriangleCount(Index p) const { return this->PatchTriangleCountOf[p]; }

  // --- Chains: maximal boundary paths with one patch on each side ---
  // A chain runs from its start to its end endpoint with LeftPatch on its left (seen from outside,
  // i.e. in LeftPatch's counter-clockwise boundary order) and RightPatch on its right
  // (InvalidIndex on the mesh border or along a non-manifold edge).
  Index NumberOfChains() const { return static_cast<Index>(this->ChainLeft.size()); }
  const Index* ChainVerticesBegin(Index c) const { return this->ChainVertexList.data() + this->ChainOffsets[c]; }
  Index ChainSize(Index c) const { return this->ChainOffsets[c + 1] - this->ChainOffsets[c]; } // vertices
  Index ChainLeftPatch(Index c) const { return this->ChainLeft[c]; }
  Index ChainRightPatch(Index c) const { return this->ChainRight[c]; }
  // True when the chain runs along non-manifold edges (then it is kept as it is).
  bool ChainIsNonManifold(Index c) const { return this->ChainFlags[c] & NonManifoldChain; }
  // Endpoint ids (index into EndpointVertex) of the chain's first and last vertex.
  Index ChainStart(Index c) const { return this->ChainEndpoints[2 * size_t(c)]; }
  Index ChainEnd(Index c) const { return this->ChainEndpoints[2 * size_t(c) + 1]; }

  // --- Endpoints: mesh vertices where chains meet ---
  Index NumberOfEndpoints() const { return static_cast<Index>(this->EndpointVertices.size()); }
  Index EndpointVertex(Index e) const { return this->EndpointVertices[e]; }
  // On the mesh border (or non-manifold): such endpoints are preserved by collapses.
  bool EndpointOnBorder(Index e) const { return this->EndpointBorder[e] != 0; }

  // --- Patch graph: the chains around each patch (unordered) ---
  const Index* PatchChainsBegin(Index p) const { return this->PatchChainList.data() + this->PatchChainOffsets[p]; }
  const Index* PatchChainsEnd(Index p) const { return this->PatchChainList.data() + this->PatchChainOffsets[p + 1]; }

  // Boundary of patch p as one closed vertex loop in counter-clockwise order (first vertex not
  // repeated). Returns false when the chains do not form a single simple loop (never for a patch
  // built here; used by tests and by consumers that check).
  bool PatchBoundaryLoop(Index p, std::vector<Index>& loop) const;

  // Heap memory of the result (bytes).
  size_t MemoryUsage() const;

private:
  enum : unsigned char
  {
    NonManifoldChain = 1
  };
  struct Adjacency;
  void BuildAdjacency(const TriangleMesh& mesh, const MeshTopology& topology);
  void FinishAdjacency();
  void Grow(const TriangleMesh& mesh, const MeshTopology& topology, const Adjacency& adjacency,
    const PatchificationParameters& parameters, const ProgressFunction& progress);
  void ExtractChains(
    const TriangleMesh& mesh, const MeshTopology& topology, const Adjacency& adjacency, double borderCornerAngle);
  void NumberEndpoints(const TriangleMesh& mesh, const MeshTopology& topology);
  void BuildPatchGraph();

  bool WasAborted = false;
  bool KeepsAdjacency = false;
  std::int64_t AdjacencyEntries = 0;
  std::vector<Index> Across; // the oriented adjacency (see BuildAdjacency)
  Index NoiseJoins = 0;
  std::vector<Index> TrianglePatch;
  std::vector<Vec3> PatchAreaVector;
  std::vector<double> PatchAreaOf;
  std::vector<Index> PatchTriangleCountOf;
  std::vector<Index> ChainOffsets, ChainVertexList, ChainLeft, ChainRight, ChainEndpoints;
  std::vector<unsigned char> ChainFlags;
  std::vector<Index> EndpointVertices;
  std::vector<unsigned char> EndpointBorder;
  std::vector<Index> PatchChainOffsets, PatchChainList;
};
} // namespace slod

#endif
