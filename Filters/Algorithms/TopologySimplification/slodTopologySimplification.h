// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm TopologySimplification: topology simplification of Ho 1999, chapter 5 — removal of small
// holes (tunnels), bumps and cavities bounded by sharp edges, and repair of cracks, on top of
// the SPBM patchification (slodPatchification) and its level generator (slodPatchBoundaryMerge).
//
// Stages:
//  1. patchification (4.2.1-4.2.3);
//  2. sharp edges: patch-boundary edges whose two triangle normals have a dot product inside
//     (SharpMinimumDot, SharpMaximumDot) (default (-0.3, 0.7): normals 45..107 degrees apart);
//     sharp chains: runs of sharp edges along one patch chain (one patch on each side);
//  3. flat / wall side of each sharp chain (5.3.1): type (1) chains compare the plane of their
//     first (else last) three vertices with the normals on both sides; type (2) chains (one edge
//     or collinear start) borrow the next vertices of incident sharp chains;
//  4. sharp loops (5.3.1): searches start from type (1) "convex hole" chains, then other type (1),
//     then type (2) chains; a search extends the chain sequence at its end by the incident sharp
//     chain that keeps the flat side on the same side (depth first, backtracking), closes a loop
//     or marks its chains DONE (never a start again); every loop is traversed with its flat side
//     on the left and is clockwise when its flat side lies outside it (hole rim, bump base,
//     cavity rim) and counter-clockwise otherwise (bump top, cavity bottom);
//  5. partner loops (5.3.2): for a clockwise loop L the wall patches (those on its wall side and
//     the patches joined to them by non-sharp chains) are searched for a loop L' disjoint from
//     L (first among the loops found, else by a new search from their sharp chains);
//     L and L' clockwise: a hole; L' counter-clockwise or none: a bump or a cavity (told apart
//     by which side of L's flat side the removed wall lies);
//  6. removal (5.3.3) when every loop of the feature is small (sampled diameter < alpha): the
//     wall region (triangles reached from L's wall side without crossing the feature's loops;
//     it must close there, touch no border and be the smaller part of its component) is
//     discarded and each clockwise loop becomes a new patch, triangulated by the shared ear
//     clipping (no diagonal that is already an edge, no non-simple projection: else the feature
//     is kept);
//  7. cracks (5.3.4): directed loops of border edges smaller than the crack size are closed as
//     new patches the same way;
//  8. clean-up merge: adjacent patches whose (area-weighted) group normals agree within alpha1
//     merge when they share exactly one boundary arc (no islands, patches stay disks);
//  9. completion: keep the triangles (only the features change), or option (2) of the chapter:
//     triangulate every patch from its boundary keeping the profiles (only exactly collinear
//     profile vertices go), or option (1): the SPBM phases (chain simplification within
//     epsilon or to a triangle target, merging, triangulation) on the cleaned patchification.
// Removing a hole lowers the genus by one; bumps, cavities and cracks keep it.
#ifndef slodTopologySimplification_h
#define slodTopologySimplification_h

#include "slodPatchBoundaryMerge.h"
#include "slodPatchification.h"
#include "slodTriangleMesh.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace slod
{
enum class TopologyCompletion : int
{
  KeepTriangles = 0,      // only the removed features change
  TriangulatePatches = 1, // option (2): patches re-triangulated from their exact boundaries
  Spbm = 2                // option (1): SPBM simplification of the cleaned patches
};

struct SURFACELODFILTERS_EXPORT TopologySimplificationParameters
{
  PatchificationParameters Patches;
  double SharpMinimumDot = -0.3; // an edge is sharp when the normals' dot product is inside
  double SharpMaximumDot = 0.7;  // (SharpMinimumDot, SharpMaximumDot)
  double FeatureSize = 0; // alpha (absolute): features whose loops are all smaller go
  bool RemoveHoles = true;
  bool RemoveBumps = true;
  bool RemoveCavities = true;
  bool FillCracks = true;
  double MaximumCrackSize = -1; // crack loops with a smaller diameter are closed; < 0: alpha
  double MergeAngle = 20.0;     // alpha1 of the clean-up merge (degrees); <= 0: no merge
  // Detection runs again on the cleaned surface while a pass removes something (a removal can
  // expose a feature: a stepped hole's counterbore is a cavity once the hole is filled).
  int MaximumPasses = 4;
  TopologyCompletion Completion = TopologyCompletion::TriangulatePatches;
  double CollinearTolerance = 1e-9; // TriangulatePatches: profile vertices within this (relative
                                    // to the bbox diagonal) of the line of their neighbours go
  SpbmLevelParameters Spbm;         // Completion == Spbm (Epsilon absolute)
  Index SpbmTargetTriangles = 0;    // Completion == Spbm: > 0 aims at this count
  bool FinalCollapses = true;       // ... and the level's vertices collapsed when it stays above it
  // Completion == Spbm to a target with Spbm.CompareCandidates (session 41, issue 10): when more
  // than this share of the input's interior edges are noisy bends (slod::NoisyBendShare at the
  // patch growth's neighbour angle and plane distance: a scan's noise), the level is generated
  // with the size-weighted merge measure alone, as SPBM does, instead of the plain and the
  // size-weighted levels compared by their sampled deviation. On such surfaces the plain level
  // needs fallback passes and ends far above the target, and the comparison discards it. >= 1
  // (or no plane distance): always compared (the rule before session 41).
  double SingleMeasureNoisyBendShare = 1.0;
};

enum class TopologyFeatureKind : int
{
  Hole = 0,
  Bump = 1,
  Cavity = 2,
  Crack = 3
};

struct SharpLoop
{
  std::vector<Index> Vertices; // in order, flat side on the left (first vertex not repeated)
  bool Clockwise = false;      // flat side outside the loop
  double Diameter = 0;         // sampled estimate
  Index Feature = InvalidIndex; // feature it bounds, if any
};

struct TopologyFeature
{
  TopologyFeatureKind Kind = TopologyFeatureKind::Hole;
  Index Loops[2] = { InvalidIndex, InvalidIndex }; // sharp loops (cracks: none)
  std::vector<Index> CrackLoop;                    // cracks: the border loop
  double Size = 0;                                 // largest loop diameter
  bool Removed = false;
  std::string Reason; // why a detected feature was kept (empty when removed)
  Index RemovedTriangles = 0;
  Index FillTriangles = 0;
};

struct SURFACELODFILTERS_EXPORT TopologySimplificationResult
{
  // The output over the input mesh's vertex ids (no new vertices).
  std::vector<Index> Triangles;
  std::vector<Index> TrianglePatch; // final patch per triangle
  std::vector<unsigned char> TriangleFill; // 0 original surface, 1 filled feature loop, 2 filled crack
  Index NumberOfPatches = 0;

  Index InitialPatches = 0, SharpEdges = 0, SharpChains = 0;
  Index FinalCollapses = 0; // half-edge collapses after the SPBM completion (its target)
  std::vector<SharpLoop> Loops;
  std::vector<TopologyFeature> Features;
  Index Detected[4] = { 0, 0, 0, 0 }; // per TopologyFeatureKind
  Index Removed[4] = { 0, 0, 0, 0 };
  Index MergedPatches = 0; // patches before completion (after the clean-up merge)
  // The cleaned mesh before completion (features removed, patches merged): its triangles and
  // patches; SpbmLevel fields of the completion.
  std::vector<Index> CleanedTriangles;
  SpbmLevel Level;
  double PatchificationSeconds = 0, DetectionSeconds = 0, CompletionSeconds = 0;
  // Work of the partner searches (5.3.2), all passes: the sharp chains and loops examined as
  // seeds or partners. Only those on each loop's wall patches are, so it grows with the loops'
  // walls, not with (loops x chains).
  std::int64_t PartnerSearchWork = 0;
  // Work of the clean-up merge (8.): chain list entries, chain vertices and vertex-chain
  // incidences visited by its merge tests and joins. Each test walks the smaller group's
  // boundary, so a group that grows by many small joins does not cost its whole boundary each.
  std::int64_t CleanUpMergeWork = 0;
  // Detection passes after the first whose large arrays (normals, patchification) needed more
  // room than the earlier passes left in the run's workspace.
  Index DetectionWorkspaceAllocations = 0;
  // Whole-surface rebuilds of the cleaned surface after the detection passes (session 44):
  // triangles whose edges and incidences MeshTopology::Build indexed again (since session 45 the
  // last pass updates its topology instead: the incidences examined around its changed triangles,
  // MeshTopologyUpdateWork::LocalIncidences), and oriented-adjacency
  // entries (three per triangle) computed again for the patchifications from labels (the clean-up
  // merge's, the completion's, the unmerged fallback's). Both 0 when the last pass kept the surface
  // as it found it (then its topology and adjacency are the cleaned surface's); otherwise one
  // topology and one adjacency, however many label sets are built over them.
  std::int64_t CleanedTopologyTriangles = 0;
  // Triangles indexed by the detection passes' MeshTopology::Build (all passes; the first pass's
  // are not counted when Run was given the mesh's topology), plus the local incidences of the
  // updates that carry a pass's topology to the next pass's surface (session 45).
  std::int64_t DetectionTopologyTriangles = 0;
  std::int64_t CleanedAdjacencyEntries = 0;
  int DetectionPasses = 0;
  // The input's NoisyBendShare when SingleMeasureNoisyBendShare applied (else -1), and whether
  // the SPBM completion generated the size-weighted level alone (by that rule or as set).
  double NoisyBendShare = -1.0;
  bool SingleMergeMeasure = false;
};

class SURFACELODFILTERS_EXPORT TopologySimplifier
{
public:
  // Progress (slodFilterContract.h): returning false aborts (Run then returns false).
  // mesh: consistently oriented; non-manifold edges are never part of a feature.
  // meshTopology (optional): the caller's MeshTopology built over `mesh` (vtkHoleBumpRemoval's
  // input statistics), taken over by the first detection pass instead of indexing the same
  // triangles again; it is left empty. Ignored when its triangle count is not the mesh's.
  bool Run(const TriangleMesh& mesh, const TopologySimplificationParameters& parameters,
    TopologySimplificationResult& result, const ProgressFunction& progress = nullptr,
    MeshTopology* meshTopology = nullptr);
};

// Diameter estimate of a closed vertex loop (section 5.3.3): evenly spaced sample pairs and
// triples (circumscribed circle), capped by the loop's bounding-box diagonal (slots): O(1)
// samples plus one O(n) pass for the box.
SURFACELODFILTERS_EXPORT double EstimateLoopDiameter(const TriangleMesh& mesh, const std::vector<Index>& loop);
} // namespace slod

#endif
