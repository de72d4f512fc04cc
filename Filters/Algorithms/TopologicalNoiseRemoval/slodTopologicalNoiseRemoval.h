// SPDX-License-Identifier: BSD-3-Clause
// Topological noise removal after Guskov & Wood 2001 ("Topological noise removal", Graphics
// Interface): handles and tunnels whose shortest loop is short, and components (specks, cavities)
// that are small, are removed from a manifold triangle mesh; larger ones are kept.
//
// Stages (Documentation/TopologicalNoiseRemoval.md):
//  1. components: every component whose bounding-box diagonal is below the feature size alpha is
//     removed (a closed one inside the largest component's box counts as a cavity); the largest
//     component is always kept;
//  2. seeds: vertices whose geodesic balls of radius pi alpha / 2 cover the surface;
//  3. passes (at most MaximumPasses): from every active seed a geodesic region grows to radius
//     pi alpha and records the loops where its front meets itself (slodHandleDetection.h),
//     in parallel; then, shortest loop first, each loop no longer than pi alpha that does not
//     separate the mesh (slodCuttableMesh.h) is cut and both sides are filled with disks; the
//     next pass grows again only the seeds near a cut.
// The size of a handle is the length of its shortest loop divided by pi (the diameter of a round
// hole), so alpha is compared with hole diameters. Border and non-manifold vertices are never on a
// cut. Fills use only the loop's vertices, so every output vertex copies an input vertex.
#ifndef slodTopologicalNoiseRemoval_h
#define slodTopologicalNoiseRemoval_h

#include "slodCuttableMesh.h"
#include "slodMeshTopology.h"
#include "slodFilterContract.h"
#include "slodTriangleMesh.h"

#include <vector>

namespace slod
{
struct TopologicalNoiseParameters
{
  double FeatureSize = 0.0; // alpha, absolute
  bool RemoveHandles = true;
  bool RemoveComponents = true; // small components and cavities
  int MaximumPasses = 8;
  // Triangles searched on each side of a loop before its separation is left undetermined (and
  // the loop kept); 0: no limit.
  Index SeparationSearchBudget = 0;
  // Non-manifold edges and vertices split into manifold sheets first (slodManifoldSplit.h), so
  // that loops through them can be cut too; off: they are locked and left as they are.
  bool SplitNonManifold = true;
  // After the cuts, the handles kept are sized on a copy of the result (cut there only), in rounds
  // at 2, 4, 8 ... times alpha up to this multiple of alpha (or the diagonal), until the copy has
  // no handle left; 0 or <= 1: no survey. Its wider regions can find a shorter loop around a
  // handle than the cut passes did (they measure a loop through the point where a front met
  // itself): a surveyed loop within pi alpha is then cut on the result too.
  double KeptHandleSurveyFactor = 2.0;
};

struct NoiseLoop
{
  std::vector<Index> Vertices; // in the mesh it was found on
  std::vector<Vec3> Points;
  double Length = 0.0;
  bool Removed = false; // cut and filled; false: kept (see Undetermined)
  bool Undetermined = false; // kept because its separation test ran out (else: above alpha, surveyed)
};

struct TopologicalNoiseResult
{
  TriangleMesh Mesh;
  MeshStatistics InputStatistics; // of the input mesh, before anything is removed
  std::vector<Index> VertexSource;   // per output vertex: the input vertex it copies
  std::vector<Index> TriangleSource; // per output triangle: its input triangle (fills: one next to the loop)
  Index HandlesRemoved = 0;
  Index HandlesRemovedBySurvey = 0; // of HandlesRemoved: found within alpha by the survey
  Index ComponentsRemoved = 0;
  Index CavitiesRemoved = 0;
  Index LoopsKept = 0;
  Index LockedVertices = 0;       // border and non-manifold vertices, never cut
  Index NonManifoldEdgesSplit = 0;    // resolved into pairs of sheets before the search
  Index NonManifoldEdgesLeft = 0;     // left non-manifold (odd or not alternating): locked
  Index NonManifoldVerticesSplit = 0; // input vertices given copies by the split
  // Handles larger than alpha found by the survey (KeptHandleSurveyFactor): their sizes
  // (shortest loop length / pi) ascending; their loops are in Loops with Removed false.
  std::vector<double> KeptHandleSizes;
  double SurveySize = 0.0; // the largest size the survey ran at (0: no survey)
  int SurveyRounds = 0;
  bool SurveyPassLimitReached = false; // a round stopped at MaximumPasses: sizes may be missing
  // Handles of the result the survey did not size (larger than SurveySize); -1: unknown (the
  // result is not manifold, so its genus is not defined).
  long long HandlesNotSized = 0;
  Index CentreFans = 0;           // fills around a new centre vertex (ear clipping found no disk)
  Index CandidateLoops = 0;       // recorded by the region growths, all passes
  Index Tests[4] = { 0, 0, 0, 0 }; // separation tests by LoopSeparation value
  Index Outdated = 0;             // candidates through a vertex a cut of the same pass changed
  Index CutsRefused = 0;         // non-separating loops whose vertices do not split into two sides
  int Passes = 0;
  bool PassLimitReached = false;  // the last pass still cut: seeds near its cuts were not grown again
  std::vector<NoiseLoop> Loops;
};

// False when aborted through `progress` (the result is then incomplete).
SURFACELODFILTERS_EXPORT bool RemoveTopologicalNoise(const TriangleMesh& mesh,
  const TopologicalNoiseParameters& parameters, TopologicalNoiseResult& result,
  const ProgressFunction& progress = nullptr);
} // namespace slod

#endif
