// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD patch boundary merge (internal, not installed): one merging run of
// an SPBM level (Ho 1999, sections 4.2.5-4.2.7) over a working state. Stages,
// in order:
//  1. ResetChainGraph: the patchification's chains, patches and endpoints as
//  linked lists, chain
//     tolerances from epsilon and the patches frozen by the triangulation
//     fallback;
//  2. RebuildKept + RefineNonSimplePatches: the chain vertices each tolerance
//  keeps, finer chains
//     around patches whose boundary would not project to a simple polygon;
//  3. MergeInMeasureOrder: patch merges in merge-measure order, with the chain
//  collapses and
//     endpoint joins they make possible;
//  4. RemoveCheapest (RemovalTarget only): endpoints removed cheapest first
//  down to the target.
// The run object holds the run's constants, its scratch and the relaxation
// flags of stage 4; all results are in the working state.
#ifndef slodSpbmMerging_h
#define slodSpbmMerging_h

#include "slodIndexedHeap.h"
#include "slodSpbmState.h"

#include <initializer_list>

namespace slod
{
class SpbmLevelGenerator::MergingRun
{
public:
  MergingRun(SpbmLevelGenerator& generator, const SpbmLevelParameters& parameters, State& s);
  ~MergingRun();
  MergingRun(const MergingRun&) = delete;
  MergingRun& operator=(const MergingRun&) = delete;
  void Run(const std::vector<unsigned char>& frozen);
  // Stage 4 alone, on a state that holds stages 1-3 of the same parameters (RemovalTarget aside).
  void RemoveDownToTarget();
  // Fallback levels beyond the first of patches frozen in the held run, without a new run.
  void RefineFrozenInPlace(const std::vector<unsigned char>& frozen);
  // The same level as the recorded run with more patches frozen: the recorded edits replayed,
  // then the merging and removal redone around the patches where the two runs differ.
  void Replay(const std::vector<unsigned char>& frozen);

private:
  // Stages.
  void ResetChainGraph(const std::vector<unsigned char>& frozen);
  void CopyPatchSupport();
  void RebuildKept(bool all, const std::vector<Index>* changed = nullptr);
  void RebuildKeptPositions(const std::vector<Index>* changed = nullptr);
  int FallbackLevel(Index c, const std::vector<unsigned char>& frozen) const;
  float FallbackTolerance(int level) const;
  void RefineNonSimplePatches(const std::vector<unsigned char>& frozen);
  void ComputeMergeThreshold();
  void MergeInMeasureOrder();
  void RemoveCheapest();
  void SeedRemovals(bool aroundDirty);
  void PopRemovals();

  // Chain graph walks and edits.
  template<typename Functor>
  Index ForPatchChains(Index p, Functor&& f); // returns the last alive slot
  Index OtherEnd(Index c, Index e);
  const Vec3& EndpointPoint(Index e);
  void SpliceEndList(Index from, Index to);
  void ReverseParts(Index c);
  bool BoundaryPoints(Index x, Index y, Index skip, std::vector<Vec3>& points);
  bool WalkBoundaryPoints(Index x, Index y, Index skip, std::vector<Vec3>& points);
  bool SimpleAfter(Index x, Index gone, Index replace);

  // Merging (4.2.6).
  double SideDot(Index p, Index q);
  double Thickness(Index p, Index q);
  double MergeMeasure(Index p, Index q);
  bool Movable(Index c);
  bool WalkDue(Index x, std::vector<Index>& walkedSize);
  void PushCandidate(Index c);
  bool TryMerge(Index c, Index p, Index q);
  bool SharesOnlyChain(Index c, Index p, Index q);
  void UniteSupport(Index p, Index q);
  void CombineSupport(Index* into, const Index* from);
  void FoldSupport(Index root);
  void UnitePatches(Index c, Index p, Index q);

  // Chain collapses and endpoint joins (4.2.6 (a)-(c), 4.2.7).
  bool TryCollapse(Index e, double& longest);
  bool CollapseKeepsTopology(Index e, Index p, Index q, Index keep, Index gone);
  bool CollapseKeepsSimple(Index p, Index q, Index keep, Index gone);
  void ApplyCollapse(Index e, Index p, Index q, Index keep, Index gone);
  double LongestChain(Index x);
  void TryCollapses(Index x, Index exclude);
  void AppendChain(Index c, Index from, bool skipFirst);
  void JoinAround(Index x, Index y, Index u, size_t& a, size_t& b);
  bool JoinWithinTolerance(Index x, Index y, Index u);
  void TryJoin(Index u);
  void ApplyJoin(Index x, Index y, Index u, Index oy, Index xl, Index xr, Index yl);

  // Recorded edits and their replay (slodSpbmReplay.cxx).
  enum EditKind : unsigned char
  {
    UniteEdit,
    CollapseEdit,
    JoinEdit
  };
  void Record(EditKind kind, std::initializer_list<Index> values);
  void ResetForRun(const std::vector<unsigned char>& frozen);
  template<typename Functor>
  void ForEditNeighbourhood(const State::Edit& edit, bool aroundEnds, Functor&& f);
  bool EditIsClean(const State::Edit& edit);
  bool NotClean(Index p);
  void MarkEditDirty(const State::Edit& edit);
  void MarkPatchDirty(Index root);
  void MarkNearPatch(Index x);
  bool ApplyRecorded(const State::Edit& edit);
  bool RetryEdit(const State::Edit& edit);
  void ReplayEdits(const std::vector<State::Edit>& edits, size_t begin, size_t end, bool removal);
  bool ReachedBefore(const State::Edit& edit);
  void MarkReached(bool reached);
  void MergeAroundDirty();
  void DrainMergeQueue();

  // Cost-ordered removal.
  bool RemovableChain(Index c);
  double CollapseCost(Index c, Index keep);
  double JoinCost(Index u);
  double JoinDeviation(Index x, Index y, Index u);
  double RemovalCost(Index op);
  void PushRemoval(Index op);
  bool ApplyRemoval(Index op, Index (&touched)[2]);
  bool RemovalCollapse(Index e, Index keep);
  bool RemovalJoin(Index u);

  SpbmLevelGenerator& generator;
  const SpbmLevelParameters& parameters;
  State& s;
  const Patchification& P;
  const TriangleMesh& mesh;
  const Index np, nc, ne;
  const float eps;
  const Index* const base; // first chain vertex: chain offsets into the generator's key arrays
  const bool flatness;
  const bool trackSupport; // the patches' extreme vertices are kept (flatness measure, thickness bound)
  const double cosMerge;
  const double inverseDiagonal;
  double meanSize = 0;       // size-weighted measure: mean patch normal-sum length
  double mergeThreshold = 0; // merge measure threshold
  // Stage 4 relaxes the collapse and join conditions and chooses the kept
  // endpoint.
  bool relaxed = false;
  Index forcedKeep = InvalidIndex;
  // Scratch.
  std::vector<Index> orientedChains, absorbedChains, refinePatches, foldStack;
  std::vector<Index> rebuiltChains; // the chains RebuildKeptPositions rebuilt last
  std::vector<Index> refinedChains; // the chains a refinement round made finer
  std::vector<Vec3> checkPoints, chainPoints, mergedPoints;
  std::vector<unsigned char> chainKept;
  IndexedHeap<double>& removalQueue; // removal operations by cost (the state's, see State::RemovalQueue)
  size_t editsRoom; // capacity of the record the run writes, when it started writing it
  // The last boundary walks (BoundaryPoints), valid while no edit of the chain graph happened.
  struct BoundaryWalk
  {
    Index X = InvalidIndex, Y = InvalidIndex, Skip = InvalidIndex;
    long long Edit = -1;
    bool Closed = false;
    std::vector<Vec3> Points;
  };
  std::array<BoundaryWalk, 4> boundaryWalks;
  size_t nextBoundaryWalk = 0;
  long long graphEdits = 0;
  long long mergeTries = 0, collapseTries = 0; // profiling aid (the run's trace line)
  bool replaying = false;             // nested joins of a union are replayed from their own records
  Index collapseRoot = InvalidIndex; // the patch whose chains TryCollapses walks (recorded)
  long long replayedAsRecorded = 0;
  long long testedAgain = 0;
  // TRACE: the record's edits reachable from those tested again (ReachedBefore), flags per patch
  // and endpoint, and the current edit's patches and endpoints.
  bool countReachable = false;
  long long reachableEdits = 0;
  std::vector<unsigned char> reachedPatch, reachedEnd;
  std::vector<Index> reachIds;
  bool markNewEdits = false; // Replay: edits made while merging around the dirty patches
  bool removalAroundDirty = false; // Replay: the removal continues around the dirty patches first
  Index joinBase = 0;                                // removal operations: 2c / 2c + 1 collapse chain c,
                                                     // joinBase + u joins at u
};
} // namespace slod

#endif
