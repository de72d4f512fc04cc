// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm TriangleCollapse: quadric-error triangle collapse simplification (Pan, Zhou, Shi 2000).
//
// The operation merges the three vertices of a triangle into one new vertex, removing the
// triangle and its (up to three) edge neighbours. Each triangle's cost is the quadric of the
// planes of its interrelated triangle set evaluated at the best placement (3x3 solve, or the best
// of centroid / vertices / edge midpoints when the system is ill-conditioned). Open borders get
// extra planes through each boundary edge perpendicular to its triangle.
//
// Error propagation (paper §2.3) measures every collapse against the ORIGINAL planes: a vertex's
// logical set is the original triangles around the original vertices it descends from, and a
// triangle's set is the union of its three vertices' logical sets. Two modes:
//  - Accumulated (default, fast): each vertex carries the sum of the quadrics of its logical
//    set (a sum of original planes, so there is no accumulation of approximation error), and a
//    triangle's quadric is the sum of its three vertex quadrics. Planes shared by two or three
//    of the vertices (the triangle itself, its edge neighbours, planes common to merged
//    ancestries) are then counted two or three times instead of once: a reweighting of the same
//    original planes. Constant memory per vertex.
//  - ExactUnion: per-vertex sorted lists of original plane ids, union taken per evaluation, every
//    plane counted exactly once as in the paper. Memory grows with the merge history; meant as the
//    reference to validate the accumulated mode (see Documentation/QuadricTriangleCollapse.md).
//
// Extension (EdgeCollapses, default on): each triangle also offers its three edge collapses with
// the same quadrics; the cheapest of the four operations (edge costs times EdgeCollapseBias) is
// performed. Triangle collapses alone cannot remove a vertex whose triangles all hold two feature
// vertices without moving a feature, which costs accuracy at a given triangle count.
//
// Extension (RefineDeviation, default on): after the collapses the merged vertices of the regions
// with the largest deviation are moved within their one-ring to lower the local maximum distance
// (original vertices and triangle centroids to the output, output samples to the original), never
// raising the local sum of distances; see Documentation/QuadricTriangleCollapse.md.
//
// Performance: the mesh is renumbered in Morton order; flat arrays; an O(1) bucket queue of
// triangle costs (slod::BucketQueue); after a collapse only the operations touching the new
// vertex are re-evaluated (edge costs are cached per triangle); a rejected operation is replaced
// by the triangle's next best one, and triangles with no valid operation are retried when their
// 2-ring changes. The initial quadrics and costs are computed per vertex / triangle in parallel;
// with BatchCollapses the checks, collapses and re-evaluations of disjoint operations run in
// parallel too (same output for any thread count). Stage times and counts are logged at TRACE verbosity
// (vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_TRACE)).
#ifndef slodTriangleCollapse_h
#define slodTriangleCollapse_h

#include "slodCollapseRecords.h"
#include "slodEditableMesh.h"
#include "slodQuadric.h"
#include "slodTriangleMesh.h"

#include <functional>
#include <vector>

namespace slod
{
class PointAttributes;

// Point attributes in the cost and the placement (TriangleCollapseOptions::AttributeError; VTK's
// AttributeErrorMetric): each triangle adds, besides its plane, the squared difference of each
// attribute component from its linear interpolation over the triangle, area-weighted (Hoppe 1999's
// form of Garland and Heckbert 1998's generalized quadrics: per vertex 10 doubles and 4 per component,
// the attributes eliminated in closed form, so the placement is still a 3x3 solve). A component's
// differences count as lengths: multiplied by its Scale (the filter uses weight x diagonal / range).
struct SURFACELODFILTERS_EXPORT AttributeErrorTerms
{
  int Components = 0;
  std::vector<double> Values; // Components per vertex of the input mesh
  std::vector<double> Scales; // per component
};

// The order in which the collapses are made (TriangleCollapseOptions::Schedule).
enum class CollapseSchedule
{
  // One priority queue: always the cheapest operation left, costs re-evaluated around each collapse.
  Queue,
  // Passes (as meshoptimizer's simplifier): every triangle's cheapest operation is costed at once
  // (in parallel), the costs ranked, and the cheapest under a pass limit performed in rank order
  // as an independent set (an operation whose closed one-ring meets a collapse made earlier in
  // the pass waits for the next pass); then again. Checks and collapses of one round run in
  // parallel; the output is the same for any thread count. Not with RecordHistory, ExactUnion,
  // AttributeError or SettleTarget: those run the queue.
  Passes
};

struct SURFACELODFILTERS_EXPORT TriangleCollapseOptions
{
  // Stop when the mesh has at most this many triangles (0: no count target).
  Index TargetTriangles = 0;
  // Never perform a collapse whose error (RMS distance of the new vertex to the original planes
  // of its interrelated set) exceeds this; negative: no limit.
  double MaximumError = -1.0;
  // Weight of the boundary planes relative to the triangle planes (0 disables them).
  double BoundaryWeight = DefaultBorderPlaneWeight;
  // Reject a collapse that turns a surviving triangle's normal by more than this (degrees).
  double MaximumNormalDeviation = 45.0;
  // Allow changes of genus, boundary loops and manifoldness (off: never).
  bool AllowTopologyChange = false;
  // Also consider the three edge collapses of each triangle (2 vertices -> 1) and perform the
  // cheapest operation; off = triangle collapses only, as in the paper. An edge collapse's cost
  // is multiplied by EdgeCollapseBias before the comparison (it removes half as many triangles).
  bool EdgeCollapses = true;
  double EdgeCollapseBias = 2.0;
  // Place a triangle's own collapse only when it can be the cheapest of its operations by a bound
  // from its edges' costs (its quadric is at least half the sum of its edges' quadrics and at
  // least each of them); otherwise its key is its cheapest edge's. Changes outputs (the bound is
  // exact only without rounding and fallback placements); judged by quality, off by default.
  bool TriangleCostBound = false;
  // Exact union semantics of the interrelated sets (slow reference mode, see above).
  bool ExactUnion = false;
  // Departure from the paper: after the collapses, the merged vertices of the regions with the
  // largest deviation (original vertices far from the output, output surface far from the
  // original) are moved within their one-ring to lower the local maximum distance (a few of the
  // worst regions only; connectivity unchanged, no triangle turned beyond MaximumNormalDeviation).
  bool RefineDeviation = true;
  // Departure from the paper: before that, every merged interior vertex is moved to the
  // least-squares fit of the original surface near it (distances of the original's vertices and
  // triangle centroids to the output along its normals, closest points held fixed, two sweeps).
  // It lowers the mean distance; connectivity and records are unchanged.
  bool FitToOriginal = true;
  // Up to this many input vertices the fit assigns every original vertex to its closest output
  // triangle (one BVH query each) to know exactly whom a move can affect; above, it watches the
  // original vertices of the moved vertex's neighbourhood (cheaper, may miss a few).
  Index FitExactAssignmentLimit = 300000;
  // Collapses in batches: the cheapest operations whose costs are within BatchCostTolerance
  // (relative) of the cheapest, with pairwise disjoint one-rings, are checked and performed in
  // parallel, their queue updates in cost order. The output is the same for any number of
  // threads. Off (default): the strict greedy order, one operation at a time (on a loaded 2-core
  // machine the batches were not faster yet: half of the popped operations overlap an earlier one
  // and are popped again, and 18 % of the batch loop is sequential).
  bool BatchCollapses = false;
  double BatchCostTolerance = 0.01;
  // A batch that will hold fewer entries than this (the queued costs within the tolerance of its
  // first, counted before it is formed) is performed as a lone pop, the strict order's path: a
  // batch of up to 16 entries runs its steps as one task on any number of threads, so it only adds
  // its claims and per-entry bookkeeping (session 42). 1: every batch as selected (session 41's
  // outputs).
  int BatchMinimumSize = 16;
  // The strict order prefetches, at each pop, the neighbourhoods of this many more entries of the
  // queue's lowest bucket (pops of the near future), in stages one pop apart; 0: none. Hints
  // only: the same output for any value (session 31).
  int UpcomingPrefetches = 8;
  // With more than one thread the strict order may also evaluate (pick and check) up to this many
  // upcoming pops ahead in parallel, those whose rings no earlier one of them touches; a pop that
  // is one of them takes its evaluation, the one it would get at its turn, and its collapse the new
  // keys computed with it (session 36). The same output for any value and thread count. 0
  // (default): none. Session 37: the evaluations run on one worker thread beside the loop for the
  // whole run (no parallel loop per look-ahead); see QuadricTriangleCollapse.md for its figures.
  int LookAheadEvaluations = 0;
  // The order of the collapses (see CollapseSchedule).
  CollapseSchedule Schedule = CollapseSchedule::Queue;
  // The pass schedule's limit: PassErrorFactor times the cost of rank PassGoalShare x (triangles
  // still to remove) among the candidates (smaller share or factor: more passes, closer to the
  // queue's order). The ranking holds about twice what the pass removes (PassRemovalShare).
  double PassGoalShare = 0.2;
  double PassErrorFactor = 1.5;
  // A pass ends once it removed this share of the triangles still to remove at its start (1: it
  // runs through its ranking). Session 26: passes that ran through a ranking of half of what was
  // left took collapses far past the queue's order (Hausdorff up to 1.7x the queue's per mesh);
  // 0.1 (with PassGoalShare 0.2) gave a geometric mean of 0.96x the queue's over the CGAL meshes.
  double PassRemovalShare = 0.1;
  // The pass schedule's costs are computed again only for the triangles a pass changed (around its
  // collapses, and those with an excluded operation; session 27). On: every triangle is visited
  // each pass, as before session 27 (the same keys; a reference for the tests).
  bool PassCostSweepsEveryTriangle = false;
  // The adjacency lists of the stages around the collapses (the triangle order of the reordering,
  // the editable mesh's vertex -> triangle blocks, the ancestry of the fit and the refinement):
  // on, built in parallel (GroupByKey: the same lists for any thread count); off (default), by the
  // serial loops. Session 28 measured the parallel form at 1.7x their CPU time for no gain of the
  // calling thread at load 20 on 2 cores (and at most about 10 % of those stages' 0.3 s on mc1m on
  // an idle machine), so it is kept for a quiet machine's measurement and as the tests' reference.
  bool ParallelStages = false;
  // Record every collapse for progressive meshes (TriangleCollapseResult::History).
  bool RecordHistory = false;
  // Optional: per vertex of the input mesh, 1 when non-manifold (the input preparation's
  // PreparationReport::NonManifoldVertexFlags); computed here when null. Read once by the
  // preparation and then released (swapped empty: a byte per vertex not held through the
  // collapses, session 43).
  std::vector<unsigned char>* NonManifoldVertices = nullptr;
  // Optional: per vertex of the input mesh, 1 when on a border edge (an edge of one triangle: the
  // input preparation's PreparationReport::BoundaryVertexFlags, the same definition as the border
  // edges the quadrics add). When given, the quadrics look for border edges at these vertices only
  // (on a closed mesh at none): the fan of every interior vertex was sorted for nothing. Read once
  // by the preparation and then released (swapped empty: not held through the collapses).
  // Ignored when its size is not the mesh's.
  std::vector<unsigned char>* BorderVertices = nullptr;
  // Optional: per vertex of the input mesh, 1 when the vertex must stay exactly as it is (never
  // removed, never moved), whatever AllowTopologyChange says: e.g. the seam of a piece of a
  // distributed surface, shared with other pieces. Ignored when its size is not the mesh's.
  const std::vector<unsigned char>* LockedVertices = nullptr;
  // Optional: per vertex of the input mesh, 1 when the vertex is a feature kept exactly in place
  // with its point data (an attribute seam, a region border: slod::AttributeSeamVertexFlags,
  // RegionBorderVertexFlags). Unlike a locked vertex, other vertices may merge into it (the merged
  // vertex is then where it is, with its attributes); two pinned vertices never merge, so the
  // polyline of a seam stays as it is on both sides. When nothing else is left above the target
  // (after the normal limit's relaxation) they are released (TriangleCollapseResult::
  // PinnedVerticesReleased). Ignored when its size is not the mesh's.
  const std::vector<unsigned char>* PinnedVertices = nullptr;
  // Optional: attributes in the cost (see AttributeErrorTerms), used unless Components is 0, the
  // sizes do not match the mesh or ExactUnion is on. The attribute values of every merged vertex
  // then come from its quadric's minimiser at its final position (TriangleCollapseResult::
  // AttributeValues); the error bounded by MaximumError and reported stays the geometric one.
  const AttributeErrorTerms* AttributeError = nullptr;
  // Called about every 1% of the work with the fraction done; return false to abort.
  std::function<bool(double)> Progress;
  // Optional (a piece of a distributed surface, slod::UnionTargetAgreement): the target is settled
  // while collapsing. Called before each batch of collapses with the cheapest cost left (+infinity
  // when nothing is left or the loop stops) and the live triangles; returns the target, or a
  // negative value while it is not settled (TargetTriangles then only scales the progress). It must
  // return a target when called with +infinity.
  std::function<Index(double cheapestCost, Index liveTriangles)> SettleTarget;
  // Optional: fills `mesh` with the input mesh again, exactly as it was given (the same points and
  // triangles in the same ids), e.g. from the caller's vtkPolyData when its preparation changed
  // nothing. The passes after the collapses (FitToOriginal, RefineDeviation) then read the input
  // from it once the collapses end, and no copy of the input is held through them, where the
  // working set peaks (its packed copy: 14.6 bytes per input vertex on mc1m). A mesh of other
  // sizes is refused (an error; the passes are skipped).
  std::function<void(TriangleMesh& mesh)> ReloadInput;
};

// Visits of a pass after the collapses (FitToOriginal, RefineDeviation), for the thread tests:
// all of them, those that were visited again in order (a concurrent result not taken: only where
// the work budget ran out), and those whose concurrent visit waited for an earlier member of their
// chunk within two edges (a later step of ChunkedSweep).
struct SweepCounts
{
  Index Visits = 0;
  Index InOrder = 0;
  Index AfterEarlier = 0;
};

struct SURFACELODFILTERS_EXPORT TriangleCollapseResult
{
  TriangleMesh Mesh;                 // simplified mesh (compact)
  std::vector<Index> OutputToInput;  // input vertex id of each output vertex (the kept id)
  std::vector<Index> OutputTriangleIds; // input triangle id of each output triangle
  std::vector<double> VertexError;   // per output vertex: RMS distance to its original planes
  double MaximumError = 0.0;         // largest error of a performed collapse or output vertex
  Index Collapses = 0;
  Index EdgeCollapses = 0;           // of Collapses, those that merged two vertices (the rest: three)
  Index FittedVertices = 0;          // vertices moved by FitToOriginal
  Index RefinedVertices = 0;         // vertex moves of RefineDeviation (a vertex may count in several rounds)
  Index RejectedCollapses = 0;       // validity test failures (each retried later)
  bool Aborted = false;
  bool StoppedByError = false;       // a collapse was refused for exceeding MaximumError
  bool WorkBoundReached = false;     // stopped by the bound on queue pops or passes
  Index Passes = 0;                  // passes of the pass schedule (0: the queue ran)
  // Diagnostics for the thread tests: the threads that took part in the pass schedule's rounds and
  // in the fit's concurrent visits (1: the work was not split), and whether the fit stopped at its
  // work budget (where it stops then depends on the order of its moves).
  int PassThreads = 0;
  int FitThreads = 0;
  // The pass schedule's window fills: the ranked entries they tested (Blocked; one tested past a
  // full window is tested again by the next fill), the threads that tested them, and the entries
  // that waited for the next pass (a vertex of their triangle moved in the pass).
  long long WindowTests = 0;
  // The strict order's look-ahead (LookAheadEvaluations): entries evaluated ahead (those that held
  // their rings) and pops that took such an evaluation.
  long long LookAheadEvaluated = 0, LookAheadTaken = 0;
  // Collapses whose new keys (UpdateAround's costs) were computed ahead, in the look-ahead's
  // parallel evaluation (session 36).
  long long LookAheadKeysTaken = 0;
  // Session 37: the parallel regions the look-ahead started (one per collapse loop that runs it,
  // with its worker beside the loop), and the look-ahead's evaluations made by that worker (the
  // rest by the loop itself; the split depends on timing, the results do not).
  long long LookAheadRegions = 0, LookAheadWorkerEvaluations = 0;
  // Session 38: the queue keys the loop rewrote after its collapses (strict order and batches; the
  // pass schedule has no queue). Each collapse re-keys exactly the triangles around its new vertex,
  // each once, so this is the sum of those fans: the work per collapse, without re-evaluations.
  long long KeyUpdates = 0;
  // Session 39: the placements (quadric solves) made for those keys, i.e. per collapse each
  // triangle of the fan once and each spoke (kept vertex, neighbour) once (with the edge cache; the
  // four operations of each triangle without it); and the operations whose validity was tested
  // (EditableMesh's checks reached the loop's settling: each one a collapse or a rejection, or an
  // alternative placement deferred).
  long long FanPlacements = 0, ValidityTests = 0;
  // Session 41: the entries the loop popped (each batch's selection; one per pop in the strict
  // order), those that ran (held their claims; the strict order's lone entries always do), and of
  // the others those whose winning edge was not placed (a batch entry's claims need its operation
  // only; the placement waits until it holds them).
  long long SelectedEntries = 0, RanEntries = 0, PlacementsNotMade = 0;
  // Session 42: the batches' walks of an entry's ring (its claims, and the holders' check of them
  // when the claims were made concurrently): two per entry of a larger batch before, one where
  // the claims are made in selection order (one thread, or a batch of one task).
  long long RingWalks = 0;
  // Session 42: the batches performed as lone pops because the queue showed that they would hold
  // fewer than TriangleCollapseOptions::BatchMinimumSize entries.
  long long BatchesPoppedAlone = 0;
  // Session 45: the batches' work that several threads share when there are several: the batches
  // whose steps split (more than 16 entries), their entries (pick, claims and check in split
  // steps), and the collapses performed in split steps (more than 4 collapses of such a batch). Everything else
  // of the loop (lone pops, selection, settling, queue updates) runs on the calling thread:
  // Collapses - SharedStepCollapses is the count of collapses performed there. Counted from the
  // batches' sizes, so the same for any thread count; 0 in the strict order.
  long long SharedStepBatches = 0, SharedStepEntries = 0, SharedStepCollapses = 0;
  // Session 44: the validity tests (counted in ValidityTests) that the strict order answered
  // without EditableMesh's check: a set that failed its topology (or held a locked vertex) was
  // tested again with no collapse in between (the two triangles of an edge whose collapse would
  // make a non-manifold edge hold the same key and are popped one after the other).
  long long TopologyTestsReused = 0;
  // Session 44: the gatherings of a set's triangles (its one-ring) by the loop's validity tests:
  // one per EditableMesh check that reaches its topology (not a dead or locked vertex). Before,
  // the alternative placements of a folding optimum gathered the set again (and tested its
  // topology again), and a repeated failed set was gathered each time.
  long long OneRingGathers = 0;
  // Vertices whose fan the quadrics searched for border edges: every vertex without
  // TriangleCollapseOptions::BorderVertices, the flagged ones with them.
  long long BorderSearches = 0;
  // Triangle planes the quadrics computed (accumulated mode): each triangle's once per block of
  // vertices holding its corners (session 43; before, once per corner, three per triangle).
  long long TrianglePlanes = 0;
  int WindowTestThreads = 0;
  long long WaitingEntries = 0;
  // Triangles the pass schedule's cost steps visited, over all passes (every triangle in the first
  // pass; afterwards those the last pass changed).
  long long CostPassVisits = 0;
  bool FitBudgetReached = false;
  SweepCounts FitVisits, RefinementVisits;
  bool PinnedVerticesReleased = false; // the target needed collapses of pinned vertices (PinnedVertices)
  // Bytes of the algorithm's own arrays at the start or the end of the collapses, the larger
  // (their capacities: the editable mesh, the input kept for the passes after the collapses and
  // the ids back to the input, both packed through the collapses, quadrics, queue, per-triangle
  // and per-vertex state, history; an estimate: scratch and the passes' own arrays are left out).
  size_t PeakWorkingBytes = 0;
  // The same after the collapses, where the passes after them start (the fit and the refinement:
  // the input unpacked, its ancestry built; 0 without them) or the extraction (the input ids
  // unpacked), the larger: since session 32 the quadrics of the surviving vertices only.
  size_t PassesWorkingBytes = 0;
  // With TriangleCollapseOptions::AttributeError: per output vertex, 1 when its attribute values
  // come from the metric (a merged vertex, not pinned), and then its Components values (the
  // minimiser of its attribute quadric at its position; unscaled, normals not renormalised).
  std::vector<unsigned char> AttributeValuesSet;
  std::vector<double> AttributeValues;
  // When RecordHistory: every collapse, in the input mesh's vertex and triangle ids (positions,
  // removed triangles' vertices and surrounding vertices stored), to split them again.
  CollapseRecords History;
};

// Simplifies `mesh` (consumed: its arrays are released to save memory). `attributes`, when given
// and not empty, has one row per input vertex and is merged as vertices merge (rows of output
// vertices are OutputToInput).
SURFACELODFILTERS_EXPORT void SimplifyByTriangleCollapse(TriangleMesh& mesh, const TriangleCollapseOptions& options,
  TriangleCollapseResult& result, PointAttributes* attributes = nullptr);
} // namespace slod

#endif
