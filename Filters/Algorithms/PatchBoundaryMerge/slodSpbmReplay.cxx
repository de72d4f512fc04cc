// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD patch boundary merge: incremental fallback passes. A merging run records its edits
// (unions, chain collapses, endpoint joins, in order). When patches fail to triangulate, the next
// pass unmerges them (fallback level 1); instead of a whole new merging run, the recorded edits
// are replayed from the patchification with those patches frozen:
//  - an edit whose patches and endpoints are all "clean" (their state is the recorded run's
//    state at that edit: same tolerances, same frozen level, every earlier edit touching them
//    replayed as recorded) is applied as recorded, without its tests (they would give the same
//    answer on the same state);
//  - any other edit is tried again with its full tests (at its current place), and its patches
//    and endpoints become dirty;
//  - then merging resumes from the chains of the dirty patches (the clean ones were left with no
//    successful candidate by the recorded run), and the removal stage replays its edits the
//    same way down to the target, then continues cheapest first when the count is still above.
// The level is valid like a merging run's (every edit passed its tests on the same local state),
// but not always the same: candidates are tried in record order, not in measure order, around
// the unmerged patches.
#include "slodSpbmMerging.h"
#include "slodStageClock.h"

#include "vtkLogger.h"

namespace slod
{
using namespace spbm;

bool SpbmLevelGenerator::ReplayMerging(
  const SpbmLevelParameters& parameters, const std::vector<unsigned char>& frozen, State& s)
{
  const size_t np = size_t(this->Patches->NumberOfPatches());
  if (!s.EditsValid || !s.EditsOf.SameLevel(PredictionMemo::Of(parameters)) || s.EditsFrozen.size() != np ||
    frozen.size() != np)
  {
    return false;
  }
  for (size_t p = 0; p < np; ++p)
  {
    if (frozen[p] < s.EditsFrozen[p])
    {
      return false; // the record does not cover a patch thawed since
    }
  }
  s.HoldsPrediction = false;
  MergingRun(*this, parameters, s).Replay(frozen);
  return true;
}

void SpbmLevelGenerator::MergingRun::Record(EditKind kind, std::initializer_list<Index> values)
{
  State::Edit edit{ kind, { InvalidIndex, InvalidIndex, InvalidIndex, InvalidIndex, InvalidIndex, InvalidIndex,
                            InvalidIndex } };
  std::copy(values.begin(), values.end(), edit.V);
  s.Edits.push_back(edit);
  if (markNewEdits)
  {
    this->MarkEditDirty(edit); // not in the record: the removal edits around must be tried again
  }
}

void SpbmLevelGenerator::MergingRun::Replay(const std::vector<unsigned char>& frozen)
{
  const auto start = spbm::StageClock::now();
  slod::StageClock clock("[spbm] replay"); // TRACE: thread CPU of its stages (the wall times below are loaded)
  std::vector<State::Edit> edits; // the recorded run's; the new record takes the spare buffer
  edits.swap(s.Edits);
  s.Edits.swap(s.EditsSpare);
  s.Edits.clear();
  editsRoom = s.Edits.capacity();
  const size_t removalBegin = s.EditsRemovalBegin;
  std::vector<float> tolerance;
  std::vector<unsigned char> locked, recordedFrozen;
  tolerance.swap(s.EditsTolerance);
  locked.swap(s.EditsLocked);
  recordedFrozen.swap(s.EditsFrozen);
  this->ResetForRun(frozen);
  // Dirty from the start: the patches whose fallback level changed, and both sides of every chain
  // whose tolerance differs from the recorded run's.
  s.DirtyPatch.assign(size_t(np), 0);
  s.DirtyEnd.assign(size_t(ne), 0);
  for (Index p = 0; p < np; ++p)
  {
    s.DirtyPatch[p] = frozen[p] != recordedFrozen[p];
  }
  for (Index c = 0; c < nc; ++c)
  {
    if (s.Tolerance[c] != tolerance[c] || s.Locked[c] != locked[c])
    {
      s.DirtyPatch[s.L[c]] = 1;
      if (s.R[c] != InvalidIndex)
      {
        s.DirtyPatch[s.R[c]] = 1;
      }
      s.DirtyEnd[s.A[c]] = s.DirtyEnd[s.B[c]] = 1;
    }
  }
  // Endpoints next to a dirty (or frozen, see FrozenPatchesAreClean) patch (see EditIsClean); all
  // patches are roots here.
  s.DirtyNear.assign(size_t(ne), 0);
  for (Index c = 0; c < nc; ++c)
  {
    const Index r = s.R[c];
    if (this->NotClean(s.L[c]) || (r != InvalidIndex && this->NotClean(r)))
    {
      s.DirtyNear[s.A[c]] = s.DirtyNear[s.B[c]] = 1;
    }
  }
  const double resetSeconds = Since(start);
  clock.Lap("reset and dirty marks");
  countReachable = vtkLogger::GetCurrentVerbosityCutoff() >= vtkLogger::VERBOSITY_TRACE;
  reachedPatch.assign(countReachable ? size_t(np) : 0, 0);
  reachedEnd.assign(countReachable ? size_t(ne) : 0, 0);
  reachableEdits = 0;
  const long long dirtyAtStart = std::count(s.DirtyPatch.begin(), s.DirtyPatch.end(), 1);
  s.DirtyAtStart = dirtyAtStart;
  replaying = true;
  this->ReplayEdits(edits, 0, std::min(removalBegin, edits.size()), false);
  replaying = false;
  const double replaySeconds = Since(start);
  clock.Lap("merging edits");
  const long long reachableMerging = reachableEdits;
  markNewEdits = true;
  this->MergeAroundDirty();
  markNewEdits = false;
  const double mergingSeconds = Since(start);
  clock.Lap("merging around dirty patches");
  const long long merged = s.Total;
  s.EditsRemovalBegin = s.Edits.size();
  if (parameters.RemovalTarget > 0 && parameters.CollapseChains)
  {
    replaying = true;
    this->ReplayEdits(edits, std::min(removalBegin, edits.size()), edits.size(), true);
    replaying = false;
  }
  const double removalReplaySeconds = Since(start);
  clock.Lap("removal edits");
  const size_t removalBeginNow = s.EditsRemovalBegin;
  removalAroundDirty = true;
  this->RemoveDownToTarget();
  removalAroundDirty = false;
  s.EditsRemovalBegin = removalBeginNow;
  clock.Lap("removal");
  if (countReachable)
  {
    vtkLogF(TRACE, "[spbm] replay: %lld merging and %lld removal edits of the record reachable from those tested again (a selective undo's size)",
      reachableMerging, reachableEdits - reachableMerging);
  }
  countReachable = false;
  s.AppliedAsRecorded = replayedAsRecorded;
  s.TestedAgain = testedAgain;
  long long dirty = 0;
  for (Index p = 0; p < np; ++p)
  {
    dirty += s.Find(p) == p && s.DirtyPatch[p];
  }
  vtkLogF(TRACE,
    "[spbm] replayed %zu edits (%lld as recorded, %lld tested again, %lld dirty patches at the start) in %.4f s: reset and refinement %.4f s, merging edits %.4f s, merging around %lld "
    "dirty patches %.4f s (%lld triangles), removal edits %.4f s, removal %.4f s (%lld triangles)",
    edits.size(), replayedAsRecorded, testedAgain, dirtyAtStart, Since(start), resetSeconds, replaySeconds - resetSeconds, dirty, mergingSeconds - replaySeconds,
    merged, removalReplaySeconds - mergingSeconds, Since(start) - removalReplaySeconds, s.Total);
  edits.clear(); // its room serves the next replay's record
  s.EditsSpare.swap(edits);
}

// Calls f(true, root) for the patches an edit reads or changes and f(false, e) for its endpoints:
// its own patches, its endpoints and (aroundEnds) the patches around those endpoints (their chains
// end there).
template<typename Functor>
void SpbmLevelGenerator::MergingRun::ForEditNeighbourhood(const State::Edit& edit, bool aroundEnds, Functor&& f)
{
  const Index* v = edit.V;
  Index ends[3] = { InvalidIndex, InvalidIndex, InvalidIndex };
  switch (edit.Kind)
  {
    case UniteEdit:
      f(true, s.Find(v[1]));
      f(true, s.Find(v[2]));
      ends[0] = s.A[v[0]];
      ends[1] = s.B[v[0]];
      break;
    case CollapseEdit:
      f(true, s.Find(v[1]));
      f(true, s.Find(v[2]));
      ends[0] = v[3];
      ends[1] = v[4];
      break;
    default: // JoinEdit
      f(true, s.Find(v[4]));
      f(true, s.Find(v[5]));
      f(true, s.Find(v[6]));
      ends[0] = v[2];
      ends[1] = v[3];
      ends[2] = s.A[v[0]] == v[2] ? s.B[v[0]] : s.A[v[0]];
      break;
  }
  for (const Index e : ends)
  {
    if (e == InvalidIndex)
    {
      continue;
    }
    f(false, e);
    if (!aroundEnds)
    {
      continue;
    }
    s.ForEndChains(e, [&](Index c) {
      f(true, s.Find(s.L[c]));
      if (s.R[c] != InvalidIndex)
      {
        f(true, s.Find(s.R[c]));
      }
    });
  }
}

// Clean: no patch of the neighbourhood NotClean (dirty; frozen too without FrozenPatchesAreClean),
// no endpoint dirty. The patches around the endpoints are not walked (most of a replay's time went
// there): DirtyNear marks every endpoint of a chain of a NotClean patch, kept up to date as patches turn dirty, unite (UnitePatches)
// or endpoints collapse (ApplyCollapse). A patch never turns clean again and stays around its
// endpoints while they have chains, so the test gives the walk's answer.
bool SpbmLevelGenerator::MergingRun::EditIsClean(const State::Edit& edit)
{
  bool clean = true;
  const bool walk = parameters.WalkAroundEditEndpoints;
  this->ForEditNeighbourhood(edit, walk, [&](bool patch, Index id) {
    clean = clean && !(patch ? this->NotClean(id) : s.DirtyEnd[id] || (!walk && s.DirtyNear[id]));
  });
  return clean;
}

// Root patch p is dirty, or frozen without FrozenPatchesAreClean: an edit around it is tested again.
bool SpbmLevelGenerator::MergingRun::NotClean(Index p)
{
  return s.DirtyPatch[p] || (!parameters.FrozenPatchesAreClean && s.Frozen[p]);
}

void SpbmLevelGenerator::MergingRun::MarkEditDirty(const State::Edit& edit)
{
  this->ForEditNeighbourhood(edit, true, [&](bool patch, Index id) {
    if (patch)
    {
      this->MarkPatchDirty(id);
    }
    else
    {
      s.DirtyEnd[id] = 1;
    }
  });
}

void SpbmLevelGenerator::MergingRun::MarkPatchDirty(Index root)
{
  if (!s.DirtyPatch[root])
  {
    s.DirtyPatch[root] = 1;
    this->MarkNearPatch(root);
  }
}

// A clean edit as recorded. The checks only guard the record's consistency (false: treat the edit
// as dirty).
bool SpbmLevelGenerator::MergingRun::ApplyRecorded(const State::Edit& edit)
{
  const Index* v = edit.V;
  auto roots = [&](Index c, Index p, Index q) {
    return s.Alive[c] && s.R[c] != InvalidIndex && s.Find(p) == p && s.Find(q) == q &&
      ((s.Find(s.L[c]) == p && s.Find(s.R[c]) == q) || (s.Find(s.L[c]) == q && s.Find(s.R[c]) == p));
  };
  switch (edit.Kind)
  {
    case UniteEdit:
      if (!this->Movable(v[0]) || !roots(v[0], v[1], v[2]))
      {
        return false;
      }
      if (trackSupport && !parameters.FoldSupportsWhenRead)
      {
        this->UniteSupport(v[1], v[2]);
      }
      this->UnitePatches(v[0], v[1], v[2]); // else the supports are folded when read (FoldSupport)
      return true;
    case CollapseEdit:
      if (!this->Movable(v[0]) || !roots(v[0], v[1], v[2]) ||
        !((s.A[v[0]] == v[3] && s.B[v[0]] == v[4]) || (s.A[v[0]] == v[4] && s.B[v[0]] == v[3])))
      {
        return false;
      }
      collapseRoot = v[5]; // recorded again with the walk it came from (RetryEdit's condition (c))
      this->ApplyCollapse(v[0], v[1], v[2], v[3], v[4]);
      return true;
    default: // JoinEdit
    {
      const Index x = v[0], y = v[1], u = v[2];
      if (!s.Alive[x] || !s.Alive[y] || s.Degree[u] != 2 || !(s.A[x] == u || s.B[x] == u) ||
        this->OtherEnd(y, u) != v[3] || !roots(x, v[4], v[5]) || s.Find(s.L[y]) != v[6])
      {
        return false;
      }
      this->ApplyJoin(x, y, u, v[3], v[4], v[5], v[6]);
      return s.Degree[u] == 0;
    }
  }
}

// A dirty edit tried again with its tests, where it stands now. True when it was made as recorded
// (the same union, the same endpoint removed, the same chain kept): it then changed its
// neighbourhood as the recorded run did.
bool SpbmLevelGenerator::MergingRun::RetryEdit(const State::Edit& edit)
{
  const Index* v = edit.V;
  const Index c = v[0];
  switch (edit.Kind)
  {
    case UniteEdit:
    {
      if (!this->Movable(c))
      {
        return false;
      }
      Index p = s.Find(s.L[c]), q = s.Find(s.R[c]);
      if (p == q || s.Frozen[p] || s.Frozen[q] || this->MergeMeasure(p, q) < mergeThreshold)
      {
        return false;
      }
      if (p == v[2] && q == v[1])
      {
        std::swap(p, q); // the recorded union (same root)
      }
      else if ((p != v[1] || q != v[2]) && s.Size[p] < s.Size[q])
      {
        std::swap(p, q);
      }
      return parameters.MergePatches && this->TryMerge(c, p, q) && p == v[1] && q == v[2];
    }
    case CollapseEdit:
    {
      const bool sameRoots = s.Find(v[1]) == v[1] && s.Find(v[2]) == v[2];
      if (relaxed)
      {
        return (s.A[c] == v[3] || s.B[c] == v[3]) && this->RemovalCollapse(c, v[3]) && sameRoots;
      }
      const Index root = s.Find(v[5] != InvalidIndex ? v[5] : v[1]);
      collapseRoot = root;
      double longest = -1; // LongestChain(root), on first need
      return this->TryCollapse(c, longest) && s.Degree[v[4]] == 0 && sameRoots;
    }
    default: // JoinEdit
      if (relaxed)
      {
        this->RemovalJoin(v[2]);
      }
      else
      {
        this->TryJoin(v[2]);
      }
      return s.Degree[v[2]] == 0 && s.Alive[v[0]] && !s.Alive[v[1]];
  }
}

// Edits [begin, end) of the record: clean ones as recorded, the others tried again. The removal
// stage's stop at the target.
void SpbmLevelGenerator::MergingRun::ReplayEdits(
  const std::vector<State::Edit>& edits, size_t begin, size_t end, bool removal)
{
  for (size_t i = begin; i < end; ++i)
  {
    if (removal && s.Total <= parameters.RemovalTarget)
    {
      break;
    }
    const State::Edit& edit = edits[i];
    const bool reached = countReachable && this->ReachedBefore(edit);
    if (this->EditIsClean(edit) && this->ApplyRecorded(edit))
    {
      ++replayedAsRecorded;
      this->MarkReached(reached);
      continue;
    }
    // Tried again; the patches and endpoints around become dirty only when the outcome differs
    // from the record (an edit made as recorded changes clean neighbours as it did then).
    ++testedAgain;
    relaxed = removal; // RemovalCollapse and RemovalJoin set it themselves
    if (!this->RetryEdit(edit))
    {
      this->MarkEditDirty(edit);
    }
    relaxed = false;
    this->MarkReached(countReachable);
  }
}

// TRACE only (issue 10: the size of a selective undo, measured before building one): an edit is
// reachable when it is tested again or reads a patch or endpoint that a reachable edit before it
// in the record read or wrote; undoing the edits tested again from the end state means undoing
// the reachable ones too. ReachedBefore notes the edit's own patches (roots) and endpoints before
// it is applied; MarkReached flags them when the edit is reachable.
bool SpbmLevelGenerator::MergingRun::ReachedBefore(const State::Edit& edit)
{
  reachIds.clear();
  bool reached = false;
  this->ForEditNeighbourhood(edit, false, [&](bool patch, Index id) {
    reachIds.push_back(patch ? id : -2 - id); // endpoints as -2 - e (InvalidIndex is -1)
    reached = reached || (patch ? reachedPatch[id] : reachedEnd[id]);
  });
  return reached;
}

void SpbmLevelGenerator::MergingRun::MarkReached(bool reached)
{
  if (!reached)
  {
    return;
  }
  ++reachableEdits;
  for (const Index id : reachIds)
  {
    if (id >= 0)
    {
      reachedPatch[id] = 1;
      reachedPatch[s.Find(id)] = 1; // the root it is part of after a union
    }
    else
    {
      reachedEnd[-2 - id] = 1;
    }
  }
}

// Merging resumes from the chains of dirty patches: the clean ones are as the recorded run left
// them, with no candidate that could still merge.
void SpbmLevelGenerator::MergingRun::MergeAroundDirty()
{
  if (!parameters.MergePatches && !parameters.CollapseChains)
  {
    return;
  }
  s.MergeQueue.Reset(nc);
  for (Index c = 0; c < nc; ++c)
  {
    if (s.Alive[c] && s.R[c] != InvalidIndex && (s.DirtyPatch[s.Find(s.L[c])] || s.DirtyPatch[s.Find(s.R[c])]))
    {
      this->PushCandidate(c);
    }
  }
  this->DrainMergeQueue();
}
} // namespace slod
