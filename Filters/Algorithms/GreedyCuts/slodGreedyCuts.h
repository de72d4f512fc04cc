// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm GreedyCuts: bounded-error simplification by greedy cuts (Ho 1999, chapter 3, after Silva et
// al.'s terrain greedy cuts), on a patchification of the surface (chapter 4's slod::Patchification).
//
// Stages of one run at tolerance epsilon:
//  1. the boundary chains between patches are simplified (Douglas-Peucker, slod::SimplifyChain) to
//     ChainTolerance * epsilon; two chains that would give the same segment keep a vertex apart;
//  2. each patch is triangulated inward from its simplified boundary polygon (in the plane
//     orthogonal to its normal): repeatedly the feasible ear of largest area is cut; when no ear is
//     feasible, greedy biting adds a triangle from a polygon edge to an original vertex inside the
//     patch (the candidates nearest the apex of the equilateral triangle on the edge first, i.e.
//     aspect ratio near 1; the bite of largest area over the edges wins); when no such bite is
//     feasible either, every inner vertex is tried for the longest edges first (our stand-in for
//     edge splitting: no Steiner points exist); when stuck, front repair (3.4.3) at the sharpest
//     corners first: edge swap, face split or vertex deletion, then the triangle behind the longest
//     front edge is put back (every triangle put back is never cut again);
//  3. a patch that stays stuck is retried in careful mode (ears may not swallow unused inner
//     vertices while a bite exists), then with its chains at full resolution, then replaced by its
//     original triangles (always feasible), so the run always terminates with a valid mesh; when
//     some patch ended there, it is split in two and the whole run repeated (bounded);
//  4. the whole result is verified: every original triangle within epsilon of the output
//     (rigorous, see below) and every edge used by at most two triangles; patches of failing
//     triangles are escalated as in 3 and the run repeats from there;
//  5. optionally (FinalCollapses) half-edge collapses that keep the bound proved remove vertices
//     the patches' boundaries forced (slodProvedCollapses.h).
//
// Feasibility of a candidate triangle Q (section 3.3, a robust equivalent of the two-phase BFS):
//  (a) d(Q, original) <= epsilon, rigorously: Q is subdivided adaptively; a piece whose centroid
//      lies at distance d from the original surface (BVH closest point) and whose vertices lie
//      within R of its centroid is accepted when d + R <= epsilon (the distance is 1-Lipschitz),
//      rejected when d > epsilon, else split in four (depth and number of pieces limited: then
//      rejected);
//  (b) d(P, Q) <= epsilon for the part of every original triangle P of the patch that lies under
//      Q (P clipped to Q's prism along the patch normal; the clipped polygon's corners are tested
//      against Q, which bounds the whole piece because the distance to a convex set is convex),
//      and no such P faces away from Q (no flipped triangle);
//  the global verification of stage 4 makes (b) rigorous for the whole surface (every original
//  triangle, subdivided adaptively, against a BVH of the output).
// Hence the two-sided Hausdorff distance between input and output is at most epsilon.
#ifndef slodGreedyCuts_h
#define slodGreedyCuts_h

#include "slodMeshTopology.h"
#include "slodPatchification.h"
#include "slodProvedCollapses.h"
#include "slodTerrainPatchification.h"
#include "slodTriangleBVH.h"
#include "slodTriangleMesh.h"

#include <functional>
#include <memory>
#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT GreedyCutsParameters
{
  double Epsilon = 0.0;          // absolute error bound (> 0)
  double ChainTolerance = 0.8;   // chains are simplified to this fraction of epsilon
  double LocalTolerance = 0.97;  // test (b) uses this fraction of epsilon (margin for stage 4)
  int BiteCandidates = 8;        // inner vertices tried per edge in greedy biting
  double MinimumAngle = 0.5;     // degrees: thinner candidate triangles are rejected
  // Degrees: a patch's first attempt also rejects triangles thinner than this (fewer slivers);
  // a patch that gets stuck is retried at MinimumAngle (the paper's gradual release). 0 = off.
  double ShapedAngle = 0.0;
  // Degrees: ears thinner than this rank below their area (weight (angle / EarShapeAngle)^2) in
  // the choice of the next ear, so the largest-area rule no longer cuts fans of caps on flat parts;
  // feasibility (the bound) is unchanged. 0 = the chapter's pure largest-area rule.
  double EarShapeAngle = 15.0;
  int SubdivisionDepth = 10;     // adaptive distance test depth
  // A final pass of half-edge collapses whose bound is proved (slodProvedCollapses.h) removes
  // the output vertices the bound does not need; it keeps the two-sided bound.
  bool FinalCollapses = true;
  bool BorderCollapses = true; // the final collapses also move border vertices along their loops
  bool EarlySliverStep = false; // the final collapses begin with a sliver step (ProvedCollapseParameters)
  // Staged final collapses (session 26; 0 = off): before the final collapses at Epsilon, this many
  // collapse-only stages accept just the collapses whose new triangles lie within Epsilon / 2^k of
  // the input (k = CollapseStages .. 1), so the collapses that move the surface least come first.
  int CollapseStages = 0;
  // RunMonotone and the target search walk a fixed ladder of tolerances (relative to the bounding
  // box diagonal, 10 round values per decade: 1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8) from this one up.
  double LadderBottom = 0.004;
  // RunMonotone (session 30): true, every level above the bottom also runs its own cuts (the
  // first level, and 1, 2, 5 times 10^k with their collapses, kept when fewer); false, the cheap
  // chain: each level above the bottom is the finer level's output collapsed at its own tolerance
  // (one collapse phase per level, on a mesh already coarse).
  bool LadderOwnRuns = true;
  // RunMonotone's cheap chain (LadderOwnRuns false, session 36): every level, the bottom's too, runs
  // only the collapse passes at its tolerance (no flips, no sliver step), and the level returned is
  // then finished by flips alone (proved at its tolerance; they keep the count). The chain is still
  // one sequence whatever epsilon, so the count never rises; a level costs one step instead of four.
  bool LadderCollapsesOnly = false;
  // A bite's walk along the front passes each front vertex's sides of the bite's new edges on to
  // the next front edge (session 29: the walk is about half of an open scan's cuts). false: the
  // reference walk, which computes them twice; the same decisions either way.
  bool CarryFrontSides = true;
  // The final collapses recall the new triangles' answers of this object's earlier collapses over
  // the same input (CarriedTriangleProofs: proved within a smaller tolerance, or not facing the
  // input), so a chain of ladder levels (RunLevels, RunMonotone) and a target's staged collapses,
  // both at rising tolerances, do not prove them again at each step (session 35; only those calls
  // keep them). The same outputs; false: each call proves its own.
  bool CarryProofs = true;
  // The final collapses' passes visit their vertices in bands of the shortest edge (this many per
  // doubling), in spatial (Morton) order within a band, so consecutive tries read nearby memory
  // (ProvedCollapseParameters::PassOrderBands, session 36; opt-in: it changes the greedy order,
  // hence the outputs, with counts up on some meshes and down on more). 0: the exact order.
  int PassOrderBands = 0;
  // A split round goes on from the run before it (session 42): only the split patches' pieces and
  // the patches sharing a chain with them are cut again (the others keep their triangulation, their
  // escalations and their chains), and the verification proves again only the input near the
  // triangles taken out. false: each split round is a whole new run (before session 42), whose cost
  // is the input's however small the split patches (on the 4M noisy scan two whole runs per level
  // for one fallback patch of 3 triangles).
  bool LocalSplitRounds = true;
};

struct SURFACELODFILTERS_EXPORT GreedyCutsResult
{
  std::vector<Index> Triangles;     // 3 original vertex ids per triangle
  std::vector<Index> TrianglePatch; // patch of each triangle
  Index NumberOfPatches = 0;
  double ErrorBound = 0;            // the guaranteed two-sided Hausdorff bound (= epsilon)
  // Statistics.
  long long Ears = 0, Bites = 0, WideBites = 0, Repairs = 0, FeasibilityTests = 0;
  long long EdgeSwaps = 0, FaceSplits = 0, VertexDeletions = 0; // front repairs by kind (3.4.3)
  Index RefinedPatches = 0;  // patches re-run with full-resolution chains
  Index OriginalPatches = 0; // patches kept as their original triangles
  std::vector<Index> FallbackPatchIds; // ... which ones
  int SplitRounds = 0;       // runs repeated after splitting patches that fell back
  // Work of the split rounds: the input triangles of the patches they cut again (with
  // LocalSplitRounds off, every patch: the input's count per round), the input triangles of the
  // patches split (the work's cause), and the input triangles their local verification proved again.
  long long SplitRoundTriangles = 0, SplitPatchTriangles = 0, LocallyVerifiedTriangles = 0;
  long long FinalCollapses = 0; // vertices removed by the final proved collapses
  long long FinalFlips = 0;     // edges flipped between them (fatter triangles)
  bool StartedFromFinerLevel = false; // RunLevels: this level began as the previous one
  int Rounds = 0;
  int ChainPasses = 0; // passes of the chain simplification over every chain (at most Rounds)
  bool Aborted = false;
};

// Rigorous adaptive test: every point of triangle (a,b,c) within epsilon of the BVH's surface
// (false also when depth runs out, or a bounded number of pieces is examined, before a proof).
// The pieces examined are added to *examinedPieces when given (the caller's work account).
SURFACELODFILTERS_EXPORT bool TriangleWithinDistance(const TriangleBVH& bvh, const Vec3& a, const Vec3& b,
  const Vec3& c, double epsilon, int depth, long long* examinedPieces = nullptr);

// TriangleWithinDistance for every triangle of `corners` (3 points each), all of them: the first
// piece (the whole triangle) of every proof is examined before any subdivision, so a set that fails
// at one triangle's first piece (a collapse's new triangles or the input triangles that rely on
// its old star) costs no other triangle's subdivisions. The same answer and, for a set proved, the
// same pieces charged. On a refusal, *refused (when given) is the triangle whose proof failed (its
// position in `corners` / 3).
SURFACELODFILTERS_EXPORT bool TrianglesWithinDistance(const TriangleBVH& bvh, const std::vector<Vec3>& corners,
  double epsilon, int depth, long long* examinedPieces = nullptr, size_t* refused = nullptr);

class SURFACELODFILTERS_EXPORT GreedyCuts
{
public:
  // Progress (slodFilterContract.h): returning false aborts.
  GreedyCuts();
  ~GreedyCuts();
  GreedyCuts(const GreedyCuts&) = delete;
  GreedyCuts& operator=(const GreedyCuts&) = delete;

  // Patchifies the mesh (which must outlive this object; closed or with borders):
  // chapter 4's small near-planar patches (slod::Patchification with `patches`), or, when
  // `terrain` is given, chapter 3's own terrain-like patches (section 3.4.1,
  // slod::BuildTerrainPatches), each triangulated in the plane orthogonal to its height direction.
  // Non-manifold input: every triangle at a non-manifold vertex (on an edge of more than two
  // triangles, or joining several fans) is a seam triangle, its own patch, kept as it is by the
  // cuts; the other patches are cut at them (edge-connected disks). The final collapses lock the
  // non-manifold vertices (EditableMesh's link condition assumes one fan per vertex) and keep the
  // topology as everywhere. So each non-manifold edge stays one edge with its triangles, and the
  // Euler characteristic and the border loops are kept.
  void Initialize(const TriangleMesh& mesh, const PatchificationParameters& patches,
    const ProgressFunction& progress = nullptr, const TerrainPatchificationParameters* terrain = nullptr);
  bool Aborted() const { return this->WasAborted; }
  bool WorkBoundReached() const { return this->SearchStoppedByWorkBound; }
  // Levels run (cuts and collapses) by the last target search with the final collapses, the top's
  // included.
  int TargetLevelsRun() const { return this->LevelsRun; }
  // Distance-proof pieces examined so far by this object's runs (cuts and collapses): the work.
  long long ProofPiecesExamined() const { return this->ProofPieces; }
  const Patchification& GetPatches() const { return this->Patches; }
  // Direction each patch is triangulated along (its height direction; chapter 4: its mean normal).
  const std::vector<Vec3>& GetHeightDirections() const { return this->HeightDirection; }
  bool TerrainPatchesUsed() const { return this->Terrain; }
  // Input triangles kept as they are because they touch a non-manifold vertex (see Initialize).
  Index NumberOfSeamTriangles() const { return this->SeamTriangles; }

  // One run at parameters.Epsilon. Returns false when aborted.
  bool Run(const GreedyCutsParameters& parameters, GreedyCutsResult& result,
    const ProgressFunction& progress = nullptr);

  // One result per epsilon (ascending order: results[i] for the i-th smallest), each within its
  // own epsilon. A level starts from its own run or the previous (finer) level, whichever has
  // fewer triangles (the finer one is within the larger bound too), before the final collapses
  // (which only remove triangles): the counts never rise along the levels, by construction.
  // With `freshRuns` (one flag per epsilon in ascending order), a flagged level also runs its own
  // cuts with their collapses and keeps them when they have fewer triangles.
  bool RunLevels(const std::vector<double>& epsilons, const GreedyCutsParameters& base,
    std::vector<GreedyCutsResult>& results, const ProgressFunction& progress = nullptr,
    const std::vector<bool>* freshRuns = nullptr);

  // One result at the largest ladder tolerance at most parameters.Epsilon (ErrorBound says which),
  // the last level of RunLevels over the ladder from parameters.LadderBottom up to it: for a fixed
  // mesh and bottom, the levels below are the same whatever epsilon, so the count never rises when
  // epsilon rises (from LadderBottom up; below it, one run at the ladder tolerance). Work bound:
  // MaximumLadderPiecesPerTriangle distance-proof pieces per input triangle for all the levels;
  // past it every further level is the finer one (WorkBoundReached() tells), a point of the same
  // deterministic sequence whatever epsilon, so the count still never rises.
  bool RunMonotone(const GreedyCutsParameters& parameters, GreedyCutsResult& result,
    const ProgressFunction& progress = nullptr);

  // Ladder tolerances (relative) in [bottom, top], ascending; the largest one at most x.
  static std::vector<double> ToleranceLadder(double bottom, double top);
  static double LadderFloor(double x);
  // Ladder levels (1, 2, 5 times a power of ten) where RunMonotone also tries the level's own cuts
  // with their collapses (a function of the level only, so the nesting stays the same).
  static bool IsFreshLevel(double relative);
  // The next level a target search tries strictly between `down` (more than `target` triangles:
  // `countDown`; -1 is the input, at tolerance 0) and `up` (within it: `countUp`), down + 1 < up:
  // the smallest level at or above the tolerance where the count is predicted to reach the target,
  // the count taken as a power of the tolerance through the two results (as 1/epsilon, a surface's
  // rate, from `up` alone when down is the input).
  static int PredictedLevel(const std::vector<double>& ladder, int down, int up, Index countDown, Index countUp,
    Index target);

  // With the final collapses (base.FinalCollapses): a search over the ladder's levels from
  // base.LadderBottom to hi (absolute; the predicted level, PredictedLevel, and a bisection after
  // a prediction that halved nothing), each one run with its collapses (at most `steps` runs after
  // the top level's), finds the smallest level `within` the target found and the next finer one
  // tried with more triangles (the input itself when none); that finer result is then collapsed at
  // the level's tolerance, stopping at the target: target or target - 1 triangles (a collapse
  // removes one or two), within that level's tolerance; fewer only when the collapses get stuck
  // (then the level's own result). A top level over the target (the count can rise with the
  // tolerance) sends the search to finer levels, halving the level index, until one is within
  // (or one does not lower the count), unless the top removed less than 1% of the input (then it
  // is kept); more only when no level tried is (then the fewest tried).
  // Work bound: the
  // runs, and then the final collapses, MaximumLadderPiecesPerTriangle distance-proof pieces per
  // input triangle each (WorkBoundReached() tells).
  // Without the final collapses:
  // Smallest epsilon (searched in [lo, hi] with `steps` runs: halving from hi while the count stays
  // within the target, then bisection on log(epsilon)) whose result has at most `target`
  // triangles; the result of that epsilon is returned (that of hi when even hi gives more). The
  // search's work is bounded: once its distance proofs have examined MaximumProofPiecesPerTriangle
  // pieces per input triangle, no further tolerance is tried and the best result so far is returned
  // (WorkBoundReached() tells).
  bool RunForTarget(Index target, const GreedyCutsParameters& base, double lo, double hi, int steps,
    GreedyCutsResult& result, const ProgressFunction& progress = nullptr);

private:
  struct Worker;
  void BuildPatchData();
  void AbsorbPatchesWithoutNormal();
  bool CollapseFinal(const GreedyCutsParameters& parameters, GreedyCutsResult& result, const ProgressFunction& progress,
    Index target = 0);
  bool FlipFinal(const GreedyCutsParameters& parameters, GreedyCutsResult& result, const ProgressFunction& progress);
  bool NextLevel(const GreedyCutsParameters& parameters, const GreedyCutsResult* finer, bool collapses, bool fresh,
    GreedyCutsResult& level, const ProgressFunction& startProgress, const ProgressFunction& collapseProgress);
  bool StartLevel(const GreedyCutsParameters& parameters, const GreedyCutsResult* finer, bool collapses,
    GreedyCutsResult& level, const ProgressFunction& progress);
  bool SearchCollapsedForTarget(Index target, const GreedyCutsParameters& base, double hi, int steps,
    GreedyCutsResult& result, const ProgressFunction& progress);
  using LevelRun = std::function<bool(int level, GreedyCutsResult& result)>;
  bool DescendBelowTop(Index target, const LevelRun& evaluate, int steps, int& evaluation, int& up,
    GreedyCutsResult& within);
  bool CollapseToTarget(Index target, GreedyCutsResult& within, GreedyCutsResult& finer, double finerBound,
    GreedyCutsParameters prm, const ProgressFunction& progress, GreedyCutsResult& result);
  // The work account of a nested run or a target search: ProofPieces past which no further level,
  // run or collapse is started (0: none open).
  void OpenWorkAccount(long long piecesPerTriangle);
  bool WorkSpent() const;
  long long WorkLimit = 0;
  bool SearchCutsForTarget(Index target, const GreedyCutsParameters& base, double lo, double hi, int steps,
    GreedyCutsResult& result, const ProgressFunction& progress);
  bool SplitPatches(const std::vector<Index>& patches);
  bool CutWithSplitRounds(const GreedyCutsParameters& parameters, GreedyCutsResult& result, const ProgressFunction& progress);
  size_t WrappedFan(Index p, const std::vector<Index>& inPatch, const std::vector<Index>& label,
    std::vector<Index>& fan) const;
  void IsolateSeamTriangles();
  void UseOwnNormals(const std::vector<Index>& pieces);
  bool IsSeamPatch(Index p) const { return !this->SeamPatch.empty() && this->SeamPatch[p]; }
  // Non-manifold input (Initialize): per vertex, 1 when non-manifold (locked in the final
  // collapses); per patch, 1 for a seam triangle's own patch. Both empty for a manifold input.
  std::vector<unsigned char> SeamVertex, SeamPatch;
  Index SeamTriangles = 0;
  // New triangles' answers kept across this object's final collapses (CarryProofs); cleared by
  // Initialize (they hold for one input), before a call at a smaller tolerance than the last, and
  // when they grow past MaximumCarriedProofs.
  CarriedTriangleProofs CarriedProofs;
  double CarriedEpsilon = 0; // the tolerance of the last call that carried its answers
  // True while CollapseFinal is called at rising tolerances (RunLevels, CollapseToTarget's stages):
  // only then can a later call recall the answers, so only then are they kept (a plain run, or the
  // target search's levels from the top down, would hold them for nothing).
  bool RisingTolerances = false;
  // True while RunMonotone's chain runs in collapse-only steps (LadderCollapsesOnly).
  bool CollapseStepsOnly = false;
  std::vector<Index> InitialLabels; // the patchification's labels (splits are undone per run)
  std::vector<Vec3> InitialHeights;
  const TriangleMesh* Mesh = nullptr;
  MeshTopology Topology;
  Patchification Patches;
  std::vector<Vec3> HeightDirection;
  bool Terrain = false;
  TriangleBVH Bvh;
  bool WasAborted = false;
  mutable long long ProofPieces = 0; // pieces examined by the distance proofs (work account)
  bool SearchStoppedByWorkBound = false;
  int LevelsRun = 0;
  // Per patch: its triangles, its inner vertices (on no chain), its boundary loop.
  std::vector<Index> PatchTriangleOffsets, PatchTriangleList;
  std::vector<Index> PatchInnerOffsets, PatchInnerList;
  std::vector<std::vector<Index>> PatchLoops;
  std::vector<unsigned char> LoopValid;
};
} // namespace slod

#endif
