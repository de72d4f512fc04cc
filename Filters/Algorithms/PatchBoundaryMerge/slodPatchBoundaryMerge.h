// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm PatchBoundaryMerge: level-of-detail generation of the Simplified Patch Boundary Merging
// method (Ho 1999, sections 4.2.4-4.2.8) on top of a slod::Patchification.
//
// Stages of one level:
//  1. chain simplification (4.2.5): every chain is approximated by divide-and-conquer refinement
//     (split at the farthest vertex, Douglas-Peucker, while the sub-chain is farther than epsilon from its segment).
//     The whole refinement tree is stored once as one tolerance per chain vertex ("keep me when
//     epsilon < key"; keys decrease down the tree), so any epsilon is a threshold on stored keys
//     and several levels come from one patchification (4.2.4);
//  2. patch merging (4.2.6): pairs whose common boundary is a single chain of one segment and
//     whose normals agree within alpha1 merge (most parallel first); endpoints left with two
//     chains of the same two patches are dropped (when the joined chain stays within epsilon);
//     short one-segment chains collapse into the endpoint with the larger normal variation when
//     (a) no third patch has both endpoints, (b) the normals agree within alpha1, (c) the chain is
//     shorter than a factor (1/5) of the patch's longest chain (and than epsilon). Extensions:
//     size-weighted and flatness merge measures; below the count that merging reaches, endpoints
//     are removed cheapest first (by how far the surface moves) down to the target
//     (SpbmLevelParameters::RemovalTarget, set by the target search);
//  3. boundary preservation (4.2.7): chains with an endpoint on the mesh border collapse only
//     toward it; chains on the border and endpoints on it are never removed;
//  4. triangulation (4.2.8): each patch's simplified boundary, projected on the plane orthogonal
//     to its normal, is ear-clipped smallest angle first (slod::TriangulatePolygon) with valid
//     diagonals only, no diagonal that is already an edge elsewhere, and the double-ear normal
//     rule (a corner that is an ear on both sides of its chain goes to the side whose normal fits).
//     Extension: non-planar patches (up to MinimumDeviationMaxVertices boundary vertices) are
//     triangulated with the valid diagonals closest to the original surface instead
//     (slod::TriangulatePolygonMinimumCost, distances from a BVH over the input).
// Method (3) of 4.2.8 keeps boundaries triangulable: a patch whose simplified boundary does not
// project to a simple polygon gets finer chains (epsilon / 4 per round, then full resolution)
// before merging, and merges, joins and collapses that would make a boundary non-simple are
// refused. Robust fallback for whatever still fails (every remaining ear would duplicate an edge,
// numerically degenerate corners): the level is regenerated with the failed patch frozen: first
// unmerged, then with finer chains around it (epsilon / 4 per level, then full resolution), then
// as its original triangles. The output is therefore always a valid mesh over original vertices
// with the topology of the input (closed manifold in -> closed manifold out, same genus).
#ifndef slodPatchBoundaryMerge_h
#define slodPatchBoundaryMerge_h

#include "slodPatchification.h"
#include "slodTriangleMesh.h"

#include <functional>
#include <memory>
#include <mutex>
#include <vector>

namespace slod
{
class DeviationTally; // EstimateDeviation's running tally (slodPatchBoundaryMerge.cxx)
class TriangleBVH;

struct SURFACELODFILTERS_EXPORT SpbmLevelParameters
{
  double Epsilon = 0.0;     // absolute chain tolerance; negative keeps every chain vertex
  double MergeAngle = 20.0; // alpha1 in degrees (patch merging and chain collapse)
  bool MergePatches = true;
  bool CollapseChains = true;
  double CollapseLengthFactor = 0.2; // condition (c)
  // Keep every chain within epsilon of the original boundary through merging too: an endpoint is
  // dropped (degree two after a merge) only when the joined chain stays within epsilon, and a
  // chain collapses only when it is shorter than epsilon. The paper does neither (merging is
  // bounded by alpha1 only); both are on by default because they bound the profile-curve error.
  bool JoinWithinEpsilon = true;
  bool CollapseWithinEpsilon = true;
  // Merge threshold weighted by patch size: a pair merges when sin(angle) * sqrt(smaller patch
  // area / mean patch area) <= sin(alpha1) (alpha1 <= 90), smallest first, instead of when
  // angle <= alpha1, most parallel first.
  bool SizeWeightedMerge = false;
  // Extension: flatness-driven merging. A flat re-triangulation of a curved patch is what makes
  // SPBM's error, so a pair merges in the order of the thickness of their union (its extent
  // along the union's normal, from the patches' extreme vertices in 13 directions), thinnest
  // first, while that thickness is at most FlatnessScale * diagonal * tan(alpha1) (unbounded at
  // alpha1 = 90, so the target search over alpha1 still applies). Normals more than 90 degrees
  // apart never merge. Takes precedence over SizeWeightedMerge.
  bool FlatnessMerge = false;
  double FlatnessScale = 0.03;
  // Extension (issue 15): a merge is refused when its union's thickness (as FlatnessMerge
  // estimates it, relative to the bbox diagonal) exceeds this: the union is re-triangulated flat
  // from its boundary, so the thickness bounds how far its original vertices end up from it.
  // 0 = unbounded (the paper). The filter sets it from the target count.
  double MaximumPatchThickness = 0.0;
  // Extension: cost-ordered endpoint removal. With RemovalTarget > 0, after merging, endpoints
  // are removed cheapest first until the level has at most RemovalTarget triangles: chain
  // collapses (conditions (a)-(b) only: no epsilon or length bound) and joins of degree-two
  // endpoints (no epsilon bound). The cost is how far the surface moves: for a collapse, the
  // displacement of the dropped endpoint along the normals of the patches around it (at least
  // the chain in-plane weight times its length), toward whichever end costs less (the border
  // rule still applies); for a join, the largest such distance of the chain vertices from the
  // new segment. Set by the target search (FindParameters) when merging up to RemovalMergeAngle
  // does not reach the target and CostOrderedRemoval is on (off: alpha1 up to 90, then the fixed
  // relaxation ladder of condition (c) and the epsilon bounds).
  Index RemovalTarget = 0;
  bool CostOrderedRemoval = true;
  // alpha1 used with the removal (when at least the given alpha1): merging across creases sharper
  // than this makes large flat patches, while the removal alone reaches the count. 60 measured
  // best of 25/40/60/90 on the Fandisk at 150 and bunny00 at 525 triangles.
  double RemovalMergeAngle = 60.0;
  // Target search (session 26): epsilon (the number k of kept chain vertices) is bracketed by the
  // full-resolution count when it is known without a merging run, and narrowed by secant steps in
  // sqrt(k) aimed inside the accepted band (mc1m at 50%: 7 merging runs -> 5). Off: the former
  // steps of two triangles per key and regula falsi in k (the reference).
  bool SecantKeptVertexSearch = true;
  // Target search (session 27): when the target is at least half the finest level's count, the
  // given alpha1 is evaluated first, and RemovalMergeAngle is not probed when it reaches the
  // target (the same parameters, one merging run fewer). Off: the probe first (the reference).
  bool MildTargetProbesMergeAngleFirst = true;
  // Target search (session 34, issue 10), GenerateForTarget with two threads and the second working
  // state idle (CompareCandidates off or not applicable): the given alpha1 and RemovalMergeAngle
  // are probed side by side, one per working state, and when the given alpha1 reaches the target
  // the probe at RemovalMergeAngle (the wider, slower merging run) is cancelled. The same
  // parameters as the serial order (RemovalMergeAngle first), unless the count rises with alpha1
  // there. Off, or on one thread: the serial order (the reference).
  bool ProbeAnglesSideBySide = true;
  // Target search (session 28, issue 15): when one more kept chain vertex takes the count from
  // below the accepted band (2% of the target, at least 2 triangles) to above the target, the
  // count above is taken when it is within the band above the target, and otherwise alpha1 is
  // searched at those two epsilons (narrower at the lower count, wider at the higher one, at most
  // MaximumBandProbes merging runs) for a count within the band either side of the target; the
  // closest one below stays when none is. A kept vertex can block a cascade of merges and
  // collapses (couplingdown at 50%: 1,782 -> 1,906 triangles for one key, band 1,820-1,894).
  // Off: the closest count not above the target (the reference).
  bool ReachBandAcrossKeyJumps = true;
  int MaximumBandProbes = 6;
  // GenerateForTarget only: also search the other merge measure (on a second thread) and half
  // alpha1 at the same target, and keep the level with the smallest EstimateDeviation. Without
  // it, the other measures are still compared when the count comes from the removal (no search).
  bool CompareCandidates = true;
  // A fallback pass that unmerges patches replays the previous pass's recorded merging edits with
  // them frozen and merges again only around them (off: a whole merging run per such pass).
  bool ReplayFallbackPasses = true;
  // Replay: whether an edit is clean is tested by walking the patches around its endpoints (the
  // reference, session 15) instead of the endpoints' DirtyNear flags (same answer, cheaper).
  bool WalkAroundEditEndpoints = false;
  // Replay: a patch frozen at the same fallback level as in the recorded run is clean (session 25):
  // it took part in no edit then and takes part in none now, so the edits around it read the state
  // the recorded run read. Off: every edit next to a frozen patch is tested again in every pass
  // (the reference: the same levels; noisy scans: a tenth of a late pass's edits).
  bool FrozenPatchesAreClean = true;
  // The kept vertices of a chain are rebuilt only when its tolerance or locking changed since they
  // were made (session 22): the refinement rounds change a few chains, and most runs and replayed
  // passes start from the tolerances of the one before. Off: every chain at every rebuild (the
  // reference: the same levels).
  bool RebuildOnlyChangedChains = true;
  // A replayed pass applies its clean unions without uniting the patches' supports (the extreme
  // vertices of FlatnessMerge and MaximumPatchThickness: 52 scattered vertex reads per union, most
  // never read again); a support is brought up to date when read (session 22). Off: united at
  // every union (the reference: the same levels).
  bool FoldSupportsWhenRead = true;
  // Fallback passes in which no failed patch would keep a vertex more (or be unmerged) repeat the
  // pass before them: skipped (the same level in fewer passes); off: one level per pass.
  bool SkipIneffectiveFallbackLevels = true;
  // Set when the caller finishes a level that ends beyond SpbmFinalCollapseTolerance of
  // RemovalTarget with final collapses (vtkPatchBoundaryMerge's FinalCollapses): once a pass's
  // count is beyond it, a patch that is unmerged already and still fails goes straight to its
  // original triangles instead of through the finer-chain levels. Those levels keep the count near
  // the prediction, each one a pass that triangulates the whole level again (noisy scans: up to six
  // such passes for the same hundred patches), while the collapses take any count down anyway.
  // The target search then also stops at RemovalMergeAngle when the removal there stops more than
  // a quarter above the target (no merging run at 90 degrees: see TargetSearch::ReachWithRemoval).
  bool FinalCollapsesFollow = false;
  // With FinalCollapsesFollow (session 42, issue 10): a pass whose failed root patches that another
  // pass can change are at most this share of the input patches is a late pass, and its failed
  // patches go straight to their original triangles, merged ones included, instead of through the
  // unmerged level. The fallback passes end when no failure is left to change (a fixed point), and
  // the failures shrink about fourfold per pass from a number proportional to the input: without a
  // share the tail of a handful of patches took 2 more whole-level passes at 4M than at 1M triangles
  // (noisy scans); with it, the pass that leaves few failures (relative to n) is followed by one
  // more. 0: off (every failure goes one level further per pass); vtkPatchBoundaryMerge sets
  // its LateFailureShare.
  double LateFailureShare = 0;
  // A patch that fails to triangulate (not unmerged yet) first keeps one more boundary vertex (the
  // hidden chain vertex farthest from its kept segment, else one hidden by a chain segment
  // elsewhere that joins two of its corners) and the patches on both sides of that chain are
  // triangulated again, up to this many rounds per pass, before it goes to the fallback levels:
  // unmerging needs another merging pass (a replay of the whole record), a round re-triangulates a
  // few patches. On scan isosurfaces the failures are patches whose every diagonal is already an
  // edge, which a further corner often avoids. The kept vertices stay kept in the later passes,
  // and add about two triangles each to the predicted count (GenerateForTarget does not aim
  // again for them). 0: the fallback levels only.
  int FailedPatchRefinementRounds = 3;
  // A fallback pass triangulates again only the patches that may have changed since the pass
  // before (session 24): walking the patches in the whole pass's order, a patch keeps its
  // triangles when it has the same original patches and chains (same kept vertices), no patch
  // across its chains changed, it did not fail, its polygon starts at the same vertex, and the
  // level has the same edges between its vertices as when they were made: its triangulation would
  // be the same, so the level is the whole-level passes' level. Every pass used to triangulate the
  // whole level again for the few patches that failed. Off: every patch in every pass (the
  // reference).
  bool LocalFallbackTriangulation = true;
  // With LocalFallbackTriangulation (session 31, issue 10): the edge context of an unchanged
  // patch is compared only when one of its vertices is touched by a patch or chain that may have
  // changed since the pass before (a changed, failed, refined or original patch, a patch
  // triangulated again earlier in this pass, a chain whose kept vertices changed): elsewhere the
  // level has the same edges between its vertices, made in the same order, so the context is the
  // same. The same level; a late pass no longer hashes every pair of corners of every patch. Off:
  // the context of every unchanged patch is compared (the reference).
  bool ReuseUntouchedPatches = true;
  // With LocalFallbackTriangulation (session 33, issue 10): an original patch (fallback level
  // OriginalLevel) that was one in the pass before too counts as unchanged, as do the patches
  // across its chains; off: every original patch counts as changed in every pass (the reference).
  bool KeptOriginalPatchesUnchanged = true;
  // Session 43 (issue 10): a merging run's refinement of non-simple patches (every run and replay
  // with a patch at a finer fallback level makes it from scratch) remembers whether each boundary
  // it tested was simple, by the boundary's signature (its chains and how many vertices each
  // keeps), and does not test a boundary seen before again: the same level; a late pass's replay
  // tests about as many boundaries as it has patches that changed, not every one that is not
  // simple and those around them. Off: each boundary whose signature is not the last one found
  // simple is tested (the reference).
  bool RememberBoundaryOutcomes = true;
  // Extension (not in the paper): a patch whose boundary is not planar (a vertex farther than
  // NonPlanarTolerance, relative to the bbox diagonal, from the plane through the boundary's
  // centroid along the patch normal) with at most MinimumDeviationMaxVertices boundary vertices
  // is triangulated by slod::TriangulatePolygonMinimumCost: among all valid triangulations, the
  // one whose diagonals stay closest to the original surface (largest sampled distance, then
  // the sum) instead of smallest-angle ear clipping. Planar patches and larger polygons keep the
  // ear clipping. Does not change triangle counts.
  bool MinimumDeviationTriangulation = true;
  Index MinimumDeviationMaxVertices = 48;
  double NonPlanarTolerance = 1e-4;
  // Session 29 (issue 10): a whole-level pass measures the diagonal costs its minimum-deviation
  // triangulations may read first, over threads (vtkSMPTools, one slot per diagonal, cached in
  // the serial order); the same level (a cost depends on the diagonal's two vertices only). Off:
  // each measured when the triangulation asks for it, on the level's thread (the reference, and
  // the default: the list ahead holds about 45% more diagonals than the passes ask for, and on the
  // MRI at 10% it cost 10-23% more CPU for no shorter wall time, quiet machine, session 29).
  bool MeasureDiagonalsAhead = false;
  // Session 33 (issue 10): the first pass of a level runs the minimum-deviation triangulations of
  // its patches over threads (vtkSMPTools) against the level's edges before the pass, then walks
  // the patches in order as before and takes a patch's triangles from there unless a diagonal the
  // pass added earlier joins two of its corners (then it is triangulated again on the spot): the
  // same level (a triangulation depends on its polygon, its normal and which pairs of its corners
  // are edges already). On the MRI at 10% the pass was about a quarter of the wall time, all on
  // one thread while the other idled. Off: each patch on the level's thread (the reference).
  bool TriangulateAheadOverThreads = true;
};

struct SURFACELODFILTERS_EXPORT SpbmLevel
{
  std::vector<Index> Triangles;     // 3 original vertex ids per triangle
  std::vector<Index> TrianglePatch; // merged patch of each triangle, 0..NumberOfPatches-1
  Index NumberOfPatches = 0;
  std::vector<Index> MergedPatchOf; // per patch of the patchification: its merged patch (or -1)
  // Profile curves: the simplified chains as polylines of original vertex ids.
  std::vector<Index> CurveOffsets;
  std::vector<Index> CurveVertices;
  Index PredictedTriangles = 0; // sum over patches of (boundary vertices - 2) before fallbacks
  // Fallbacks, counted in patches of the patchification: patches that could not be triangulated
  // are regenerated (1) unmerged, then (2) with full-resolution chains, then (3) as their
  // original triangles.
  Index UnmergedPatches = 0;
  Index RefinedPatches = 0;
  Index OriginalPatches = 0;
  Index DiagonalsMeasured = 0;      // diagonal costs measured (distance queries) by the passes
  Index DiagonalsMeasuredAhead = 0; // of which before the triangulations asked (MeasureDiagonalsAhead)
  Index TriangulatedAhead = 0;      // patches whose triangles came from TriangulateAheadOverThreads
  Index TriangulatedAgain = 0;      // of those run ahead, patches a diagonal of the pass made triangulate again
  int Passes = 0;               // generation passes (1 without fallback)
  int ReplayedPasses = 0;       // passes that replayed the previous pass's merging (ReplayFallbackPasses)
  long long EditsAppliedAsRecorded = 0; // edits those passes applied without their tests (clean)
  long long EditsTestedAgain = 0;       // edits those passes tested again (FrozenPatchesAreClean)
  // Per pass (issue 10, session 43): the root patches a replay started with as dirty (their
  // fallback level or the tolerance of one of their chains changed since the recorded run: what
  // changed; -1 when the pass did not replay), and the patch boundaries the pass's merging run or
  // replay tested for simplicity when it refined the non-simple patches (RememberBoundaryOutcomes;
  // -1 when it reused the refinement of the level's search or ran none).
  std::vector<long long> PassDirtyPatches, PassBoundaryTests;
  long long ChainRebuilds = 0;  // chains whose kept vertices the passes' merging rebuilt (RebuildOnlyChangedChains)
  long long SupportUnions = 0;  // supports the passes' merging united (FoldSupportsWhenRead)
  long long SupportFolds = 0;   // of them, folded in when a support was read after replayed unions
  long long WalkedChains = 0;   // chains the merging runs' boundary walks went along (issue 10, session 39)
  long long WalkSideFinds = 0;  // of them, those whose side needed a Find through the patch records
  // Merging runs and replays of the passes whose edit record or removal queue needed more room than
  // the working state held (State::WorkspaceAllocations): bounded by the record's growth, not by
  // the number of passes.
  long long WorkspaceAllocations = 0;
  Index FailedPatches = 0;      // root patches that went to a fallback level, summed over the passes
  // Per pass, the failed root patches that a further pass can change (an input patch of theirs
  // below the original level): the generation's fixed-point test (another pass while one is left).
  std::vector<Index> ChangeableFailures;
  Index LateOriginalPatches = 0; // input patches a late pass sent from merged to original (LateFailureShare)
  Index RefinedInPass = 0;      // vertices kept by FailedPatchRefinementRounds, summed over the passes
  Index RetriangulatedPatches = 0; // root patches triangulated from their boundary in the passes after the first
  Index ContextsCompared = 0; // unchanged root patches whose edge context the passes after the first computed
  Index ReusedUntouched = 0;  // unchanged root patches those passes kept without it (ReuseUntouchedPatches)
  // The generation that made the level (SpbmLevelGenerator's serial): which kept last pass is its.
  long long Generation = 0;
  // Triangles those passes made from boundaries (the work of a further pass: the reused ones are not).
  Index RetriangulatedTriangles = 0;
};

class SURFACELODFILTERS_EXPORT SpbmLevelGenerator
{
public:
  SpbmLevelGenerator();
  ~SpbmLevelGenerator();
  SpbmLevelGenerator(const SpbmLevelGenerator&) = delete;
  SpbmLevelGenerator& operator=(const SpbmLevelGenerator&) = delete;

  // Builds the chain hierarchy. Both objects must outlive the generator.
  void Initialize(const TriangleMesh& mesh, const Patchification& patches);
  // The same with the chain deviation measured as the surface sees it (extension, not in the
  // paper): the offset of a dropped vertex from its segment counts by its components along the
  // normals of the chain's two patches, but at least `inPlaneWeight` (0..1) times its length
  // (1 = plain Euclidean distance, the paper's measure; border chains always use it). An offset
  // within both patch planes barely moves the surface, so the same vertex budget goes to creases.
  // Keys (and epsilon) are then in this measure.
  void Initialize(const TriangleMesh& mesh, const Patchification& patches, double inPlaneWeight);

  // Builds the BVH of `mesh` used by the minimum-deviation triangulation (the first level needs
  // it) while `work` runs (the caller's patchification): two vtkSMPTools tasks. `mesh` must not
  // change while the generator uses it; the next Initialize with the same mesh keeps the tree
  // (any other Initialize drops it).
  void BuildInputTreeDuring(const TriangleMesh& mesh, const std::function<void()>& work);

  // Triangle count of the level (before fallbacks) without triangulating: cheap, for searches.
  Index PredictTriangleCount(const SpbmLevelParameters& parameters);

  // A lower bound of the finest level's count (every chain vertex kept) without a merging run:
  // at full resolution only one-segment chains merge or collapse, joins keep every interior
  // chain vertex, and each collapse or join removes one endpoint off the border.
  Index FinestLevelLowerBound() const;

  // The finest level's count: at full resolution (Epsilon < 0) with the epsilon bounds on joins
  // and collapses and no removal, no join or collapse is within epsilon and merges keep the
  // count, so it is the patchification's sum of (boundary size - 2), computed without a merging
  // run; otherwise the merging run's prediction.
  Index FinestLevelCount(const SpbmLevelParameters& parameters);
  // That count when it needs no merging run (Epsilon < 0, the epsilon bounds on, no removal),
  // else -1. The target search takes it as the upper end of its epsilon bracket for free.
  Index FinestLevelCountWithoutRun(const SpbmLevelParameters& parameters) const;
  // Merging runs of the first working state so far (searches and generation passes; a
  // remembered prediction runs none): the work of a level.
  int MergingRunCount() const;
  // Target searches of GenerateForTarget whose alpha1 probes ran side by side (ProbeAnglesSideBySide).
  int SideBySideProbeCount() const;

  // Generates the level. Returns false only when aborted through `abort`.
  bool Generate(const SpbmLevelParameters& parameters, SpbmLevel& level,
    const std::function<bool()>& abort = nullptr);
  // The same level with the patches marked in `original` (per patch of the patchification, nonzero
  // = marked) kept as their original triangles from the first pass on, as a fallback keeps them
  // (issue 15, session 37: the per-region finer level). The other patches merge as in Generate; a
  // held run of the same parameters is replayed with the marked patches frozen.
  // With `from` a level whose last triangulation pass is kept (KeepLastPass), the generation goes on
  // from that pass instead (session 38): one more fallback pass with the marked patches original,
  // in which every patch untouched by them keeps its triangles (LocalFallbackTriangulation), so its
  // cost follows the marked share, not the level.
  bool GenerateWithOriginalPatches(const SpbmLevelParameters& parameters, const std::vector<unsigned char>& original,
    SpbmLevel& level, const std::function<bool()>& abort = nullptr, const SpbmLevel* from = nullptr);
  // Whether the levels of the first working state (not the budgeted tries) keep their last
  // triangulation pass for GenerateWithOriginalPatches (memory: the pass's per-patch records and a
  // copy of the level); off by default. Dropped by Initialize and by DropKeptPass.
  void KeepLastPass(bool keep);
  void DropKeptPass();

  // Parameters whose level has about `target` triangles: the number of kept chain vertices (i.e.
  // epsilon) is searched over the stored hierarchy; when even single-segment chains give too
  // many triangles, the merge angle alpha1 is widened (up to 90 degrees). Prefers the closest
  // count not above the target. `predicted` gets the predicted count.
  SpbmLevelParameters FindParameters(Index target, const SpbmLevelParameters& base, Index* predicted = nullptr);

  // FindParameters + Generate, re-aiming when fallbacks pushed the count above the target. The
  // level budget can be spent on finer chains (smaller epsilon) or on fewer, flatter merges
  // (smaller alpha1, size-weighted merging): with CompareCandidates, both merge measures and
  // (when alpha1 did not have to be widened) half and a quarter of alpha1 are tried, and the
  // level with the smallest EstimateDeviation is kept.
  bool GenerateForTarget(Index target, const SpbmLevelParameters& base, SpbmLevel& level,
    SpbmLevelParameters* used = nullptr, const std::function<bool()>& abort = nullptr);

  // Deviation estimate of a level: the largest distance from samples of the original triangles
  // (vertices and centroids, about `samples` of them) to the level (a BVH over the level, which
  // is small; each query bounded by the current maximum), and, once the input's BVH exists, from
  // points inside the level's 160 largest triangles (barycentric grid of step 1/3) to the input. The sampled
  // two-sided Hausdorff distance; compares candidates. With everyVertex, every input vertex is a
  // sample too (the search's epsilon drops a few chain vertices, where a level's largest error
  // often sits, and a strided sample misses them; O(input vertices) bounded queries).
  // With `beyond` (and everyVertex), also each input vertex's distance from the level where it is
  // beyond `allowance` (0 elsewhere), for PatchDeviationsFromVertices, in the same pass; the
  // estimate is the same. With `withoutFarthest` (and everyVertex), also the estimate with the
  // `farthestLeftOut` input samples (vertices, strided centroids) farthest from the level left
  // out: the tail of their distances, which does not grow with the sampling density of a noisy
  // surface as the largest does (the same estimate when none is left out).
  double EstimateDeviation(const SpbmLevel& level, Index samples = 3000, bool everyVertex = false,
    std::vector<float>* beyond = nullptr, double allowance = 0, Index farthestLeftOut = 0,
    double* withoutFarthest = nullptr) const;
  // EstimateDeviation(level, samples, true) of a level that differs from `from` in a few places
  // (issue 15, session 38), `fromBeyond` being EstimateDeviation's `beyond` output for `from` at
  // `allowance`: the input vertices beyond the allowance from `from` are measured, and of the others
  // only those within the allowance of a triangle of `from` that `level` does not have (every other
  // one is still within the allowance of a triangle of both). So the estimate is EstimateDeviation's
  // whenever that is above the allowance (below it, it may be lower), at the cost of the changed
  // places. `measured` (optional): the number of vertices measured.
  double EstimateDeviationNear(const SpbmLevel& level, const SpbmLevel& from, const std::vector<float>& fromBeyond,
    double allowance, Index samples = 3000, Index* measured = nullptr) const;
  // The level's side of the deviation over the triangles of `level` that `other` does not have
  // (issue 15, session 45): each sampled on the barycentric grid of step 1/3 against the input, as
  // EstimateDeviation samples the level's largest triangles (0 without the input's BVH). Two levels
  // that differ in a few places compare by it where EstimateDeviation's 160 largest triangles miss
  // the changed ones.
  double ChangedTriangleDeviation(const SpbmLevel& level, const SpbmLevel& other) const;
  // Per patch of the patchification, the largest distance of its triangles' vertices from a level
  // where that is beyond an allowance (0 elsewhere), from the per-vertex distances beyond it of
  // EstimateDeviation's `beyond`: where the level misses what its patches allow. Returns the number
  // of patches beyond it.
  Index PatchDeviationsFromVertices(const std::vector<float>& beyond, std::vector<double>& patchDeviation) const;

  // Hierarchy key of the i-th vertex of chain c: kept when epsilon < key (infinite at endpoints).
  double ChainVertexKey(Index c, Index i) const;
  size_t MemoryUsage() const;

private:
  struct StageTimes // of one working state (logged at verbosity TRACE)
  {
    double Merging = 0, Generate = 0, Tree = 0, Triangulation = 0, Refinement = 0;
    int MergingRuns = 0;
    long long ChainRebuilds = 0, SupportUnions = 0, SupportFolds = 0, WalkedChains = 0, WalkSideFinds = 0;
  };
  static void LogStageTimes(const char* what, double seconds, const StageTimes& times);
  struct State;
  // Stages of GenerateForTarget over the candidates of one call (defined in the .cxx).
  struct TargetCandidates;
  void DescribeCandidate(const char* what, const SpbmLevelParameters& p, Index produced, double deviation) const;
  void GenerateOtherMeasure(const SpbmLevelParameters& base, TargetCandidates& run);
  bool PlanRemovalTries(const SpbmLevelParameters& base, TargetCandidates& run);
  void RunPlannedTries(TargetCandidates& run, State& s);
  void RunPlannedTriesAfter(const SpbmLevel& firstLevel, TargetCandidates& run);
  bool TryNarrowerAngle(const SpbmLevelParameters& base, SpbmLevel& level, TargetCandidates& run);
  void KeepOtherMeasure(SpbmLevel& level, TargetCandidates& run);
  bool TryOtherMeasureForUnreachedTarget(const SpbmLevelParameters& base, SpbmLevel& level, TargetCandidates& run);
  bool KeepClosestTry(const SpbmLevelParameters& first, SpbmLevel& level, TargetCandidates& run);
  // With a budget (> 0) every generation is GenerateIn's budgeted try: a level that needs a
  // fallback pass or whose count is above the budget is left without triangles.
  bool GenerateForTargetAndAngle(Index target, const SpbmLevelParameters& base, SpbmLevel& level,
    SpbmLevelParameters* used, const std::function<bool()>& abort, State& s, Index budget = 0);
  // The same as the public functions, on a given working state (one per candidate thread).
  // -1 when the run was cancelled (State::Cancel): nothing is remembered then.
  Index PredictTriangleCountIn(const SpbmLevelParameters& parameters, State& s);
  // The remembered prediction of `parameters` in `s`, without a run; false when there is none.
  static bool RememberedCount(const SpbmLevelParameters& parameters, const State& s, Index& count);
  SpbmLevelParameters FindParametersIn(Index target, const SpbmLevelParameters& base, Index* predicted, State& s);
  // With a budget (> 0), a candidate whose count after a pass's merging is above it is abandoned:
  // `level` is left without triangles (fallback passes only add triangles); so is one whose first
  // pass leaves patches that fail to triangulate (a budgeted try gets no fallback pass).
  // `original` (when given): patches kept as their original triangles from the first pass on.
  // `resume` (with `original`): the kept last pass of the level to go on from (GenerateWithOriginalPatches).
  struct KeptPass;
  bool GenerateIn(const SpbmLevelParameters& parameters, SpbmLevel& level, const std::function<bool()>& abort, State& s,
    Index budget = 0, const std::vector<unsigned char>* original = nullptr, KeptPass* resume = nullptr);
  // EstimateDeviation's samples: the strided ones of the input against `bvh` (over the level; with
  // `centroidsOnly`, the strided vertices are left to an every-vertex pass), and the level's
  // largest triangles against the input (when its BVH exists); both add to `tally`.
  void StridedDeviation(const TriangleBVH& bvh, Index samples, bool centroidsOnly, DeviationTally& tally) const;
  void LevelSideDeviation(const SpbmLevel& level, DeviationTally& tally) const;
  const TriangleBVH& GetInputTree(StageTimes& times);
  // Stages of Initialize.
  void BuildChainKeys(size_t totalVertices);
  void OrderChainKeys(size_t totalVertices);
  void MarkParallelChains();
  void MeasureEndpointVariation();
  // How many interior vertices (original) chain c keeps at `tolerance`: a prefix of its key order.
  Index KeptInterior(Index c, float tolerance) const;
  // One merging run (slodSpbmMerging.cxx) leaves the level's chain graph in `s`.
  class MergingRun;
  // Triangulation passes of a level (slodSpbmTriangulation.cxx).
  class LevelTriangulation;
  // The search of FindParameters (slodSpbmTargetSearch.cxx).
  class TargetSearch;
  void RunMerging(const SpbmLevelParameters& parameters, const std::vector<unsigned char>& frozen, State& s);
  // A fallback pass that unmerged patches: the held run's edits replayed with them frozen
  // (slodSpbmReplay.cxx); false when `s` holds no recorded run of these parameters.
  bool ReplayMerging(const SpbmLevelParameters& parameters, const std::vector<unsigned char>& frozen, State& s);
  // The cost-ordered removal of `parameters` on a state that holds the merging run of the same
  // parameters without it (the merging stages do not depend on RemovalTarget).
  void ContinueWithRemoval(const SpbmLevelParameters& parameters, State& s);
  // Fallback levels beyond the first (finer chains, original triangles) of patches that the
  // merging run held by `s` already kept unmerged, applied to that run's chain graph.
  void RefineFrozenInPlace(const SpbmLevelParameters& parameters, const std::vector<unsigned char>& frozen, State& s);

  const TriangleMesh* Mesh = nullptr;
  const Patchification* Patches = nullptr;
  std::vector<float> Keys;                 // per chain vertex (Patchification's chain vertex list)
  std::vector<float> SortedKeys;           // finite keys, descending
  std::vector<Index> KeyOrder;             // per chain: interior positions by decreasing key
  std::vector<float> OrderedKeys;          // the keys in that order
  std::vector<unsigned char> MinimumInterior; // chains that must keep one interior vertex
  std::vector<double> EndpointVariation;   // normal variation around each endpoint
  std::vector<Vec3> EndpointPoints;        // coordinates of each endpoint (read by every merge and collapse try)
  std::vector<Index> PatchSupport;         // per patch: its extreme vertices in the 26 support directions
  long long PatchSupportBuilds = 0;        // how many times PatchSupport was built (which one a state holds)
  struct PredictionMemo
  {
    float Epsilon;
    double MergeAngle;
    bool MergePatches, CollapseChains;
    double CollapseLengthFactor;
    bool JoinWithinEpsilon, CollapseWithinEpsilon, SizeWeightedMerge, FlatnessMerge;
    double FlatnessScale, MaximumPatchThickness;
    Index RemovalTarget;
    Index Count;
    // The memo entry of `parameters` (Count left 0) and whether an entry is of the same level.
    static PredictionMemo Of(const SpbmLevelParameters& parameters);
    bool SameLevel(const PredictionMemo& other) const;
  };
  std::unique_ptr<State> Work;
  std::unique_ptr<State> Helper; // second working state: candidates run on two threads
  // Helper while a target search in Work may use it (GenerateForTarget without CompareCandidates).
  State* SpareState = nullptr;
  // Replaces Helper by a fresh working state (its memory returned; SpareState follows it).
  void RenewHelper();
  int SideBySideProbes = 0;
  long long Generations = 0;          // GenerateIn calls so far (SpbmLevel::Generation)
  bool KeepPasses = false;            // KeepLastPass
  std::unique_ptr<KeptPass> LastPass; // the last pass of the latest kept level
  mutable std::mutex LazyMutex;  // guards the lazily built InputTree and PatchSupport
  std::unique_ptr<TriangleBVH> InputTree; // over Mesh, taken or built on first use (non-planar patches)
  std::unique_ptr<TriangleBVH> BuiltTree; // over TreeMesh by BuildInputTreeDuring, not used yet
  const TriangleMesh* TreeMesh = nullptr;
  double Diagonal = 0;
  double InPlaneWeight = 1.0;
};
} // namespace slod

#endif
