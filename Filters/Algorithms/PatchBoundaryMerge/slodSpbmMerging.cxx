// SPDX-License-Identifier: BSD-3-Clause
#include "slodSpbmMerging.h"

#include "slodCounterHash.h"
#include "slodStageClock.h"
#include "vtkLogger.h"
#include "vtkMath.h"

#include <mutex>

namespace slod
{
using namespace spbm;

namespace
{
using Point2 = std::array<double, 2>;

// The index after i in a closed polygon of n vertices (i < n), without the division of (i + 1) % n:
// the simplicity tests below take it for every segment, in the sweep's comparisons too.
inline size_t NextIndex(size_t i, size_t n)
{
  return i + 1 == n ? 0 : i + 1;
}

int Orientation(const Point2& o, const Point2& a, const Point2& b)
{
  const double d = (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  return (d > 0) - (d < 0);
}

bool OnSegment(const Point2& a, const Point2& b, const Point2& q)
{
  return std::min(a[0], b[0]) <= q[0] && q[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= q[1] &&
    q[1] <= std::max(a[1], b[1]);
}

// Segments i (p[i] -> p[i+1]) and j of the closed polygon p cross or touch;
// adjacent segments share a vertex and do not count.
bool SegmentsCross(const std::vector<Point2>& p, size_t i, size_t j)
{
  const size_t n = p.size();
  if (i > j)
  {
    std::swap(i, j);
  }
  if (j == i + 1 || (i == 0 && j == n - 1) || i == j)
  {
    return false;
  }
  const Point2& a = p[i];
  const Point2& b = p[NextIndex(i, n)];
  const Point2& c = p[j];
  const Point2& d = p[NextIndex(j, n)];
  const int o1 = Orientation(a, b, c), o2 = Orientation(a, b, d), o3 = Orientation(c, d, a), o4 = Orientation(c, d, b);
  if (o1 != o2 && o3 != o4)
  {
    return true;
  }
  return (o1 == 0 && OnSegment(a, b, c)) || (o2 == 0 && OnSegment(a, b, d)) || (o3 == 0 && OnSegment(c, d, a)) ||
    (o4 == 0 && OnSegment(c, d, b));
}

// Fast accept in O(n): every edge turns strictly counter-clockwise around the
// vertex centroid c and winds around it once, so the polygon is star-shaped
// from it, hence simple (most patch boundaries are; the general tests run only
// for the others).
bool StarShapedFrom(const std::vector<Point2>& p, const Point2& c)
{
  const size_t n = p.size();
  int winding = 0;
  for (size_t i = 0; i < n; ++i)
  {
    const Point2& a = p[i];
    const Point2& b = p[NextIndex(i, n)];
    if (Orientation(c, a, b) <= 0)
    {
      return false;
    }
    // With every edge CCW around c, an upward crossing of the line y = c.y
    // passes angle 0.
    winding += (a[1] < c[1] && b[1] >= c[1]) ? 1 : 0;
  }
  return winding == 1;
}

// Any two segments cross: a sweep along x compares only segments whose x-ranges
// overlap.
bool AnySegmentsCross(const std::vector<Point2>& p, std::vector<size_t>& order)
{
  const size_t n = p.size();
  order.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    order[i] = i;
  }
  auto minX = [&](size_t i) { return std::min(p[i][0], p[NextIndex(i, n)][0]); };
  auto maxX = [&](size_t i) { return std::max(p[i][0], p[NextIndex(i, n)][0]); };
  std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return minX(x) < minX(y); });
  for (size_t a = 0; a < n; ++a)
  {
    const size_t i = order[a];
    const double reach = maxX(i);
    const double lowY = std::min(p[i][1], p[NextIndex(i, n)][1]), highY = std::max(p[i][1], p[NextIndex(i, n)][1]);
    for (size_t b = a + 1; b < n && minX(order[b]) <= reach; ++b)
    {
      const size_t j = order[b];
      if (std::max(p[j][1], p[NextIndex(j, n)][1]) < lowY || std::min(p[j][1], p[NextIndex(j, n)][1]) > highY)
      {
        continue;
      }
      if (SegmentsCross(p, i, j))
      {
        return true;
      }
    }
  }
  return false;
}
} // namespace

// O(n^2) at worst: used on merged patch boundaries, which are short at the
// levels where merging happens; the star test and the sweep make most calls
// linear.
bool spbm::ProjectsToSimplePolygon(
  const std::vector<Vec3>& polygon, const Vec3& normal, PolygonScratch& scratch, size_t changed)
{
  const size_t n = polygon.size();
  if (n < 3)
  {
    return false;
  }
  const Vec3 w = Normalized(normal);
  const Vec3 helper = std::fabs(w[0]) < 0.9 ? Vec3{ 1, 0, 0 } : Vec3{ 0, 1, 0 };
  const Vec3 u = Normalized(Cross(helper, w));
  const Vec3 v = Cross(w, u);
  std::vector<Point2>& p = scratch.Projected;
  p.resize(n);
  double area = 0;
  double cx = 0, cy = 0;
  for (size_t i = 0; i < n; ++i)
  {
    p[i] = { Dot(polygon[i], u), Dot(polygon[i], v) };
    cx += p[i][0];
    cy += p[i][1];
  }
  for (size_t i = 0; i < n; ++i)
  {
    const auto& a = p[i];
    const auto& b = p[NextIndex(i, n)];
    area += a[0] * b[1] - a[1] * b[0];
  }
  if (area <= 0)
  {
    return false;
  }
  if (StarShapedFrom(p, { cx / double(n), cy / double(n) }))
  {
    return true;
  }
  if (changed < n)
  {
    // Only the two segments at the changed vertex are new.
    for (const size_t i : { (changed + n - 1) % n, changed })
    {
      for (size_t j = 0; j < n; ++j)
      {
        if (SegmentsCross(p, i, j))
        {
          return false;
        }
      }
    }
    return true;
  }
  return !AnySegmentsCross(p, scratch.Order);
}

void SpbmLevelGenerator::RunMerging(
  const SpbmLevelParameters& parameters, const std::vector<unsigned char>& frozen, State& s)
{
  s.HoldsPrediction = false;
  MergingRun(*this, parameters, s).Run(frozen);
}

void SpbmLevelGenerator::ContinueWithRemoval(const SpbmLevelParameters& parameters, State& s)
{
  s.HoldsPrediction = false;
  MergingRun(*this, parameters, s).RemoveDownToTarget();
}

void SpbmLevelGenerator::RefineFrozenInPlace(
  const SpbmLevelParameters& parameters, const std::vector<unsigned char>& frozen, State& s)
{
  s.HoldsPrediction = false;
  MergingRun(*this, parameters, s).RefineFrozenInPlace(frozen);
}

SpbmLevelGenerator::MergingRun::MergingRun(
  SpbmLevelGenerator& generator_, const SpbmLevelParameters& parameters_, State& state)
  : generator(generator_)
  , parameters(parameters_)
  , s(state)
  , P(*generator_.Patches)
  , mesh(*generator_.Mesh)
  , np(P.NumberOfPatches())
  , nc(P.NumberOfChains())
  , ne(P.NumberOfEndpoints())
  , eps(static_cast<float>(parameters_.Epsilon))
  , base(nc > 0 ? P.ChainVerticesBegin(0) : nullptr)
  , flatness(parameters_.FlatnessMerge)
  , trackSupport(parameters_.FlatnessMerge || parameters_.MaximumPatchThickness > 0)
  , cosMerge(std::cos(Radians(parameters_.MergeAngle)))
  , inverseDiagonal(generator_.Diagonal > 0 ? 1.0 / generator_.Diagonal : 1.0)
  , removalQueue(state.RemovalQueue)
  , editsRoom(state.Edits.capacity())
{
}

SpbmLevelGenerator::MergingRun::~MergingRun()
{
  s.WorkspaceAllocations += s.Edits.capacity() > editsRoom; // the record outgrew its buffer
}

// Walk the alive chains of root patch p, unlinking dead ones on the way (merged
// patches would otherwise drag every chain they ever absorbed through each
// walk: quadratic on large merges). The order of the alive chains is kept. `f`
// must not relink patch lists. Returns the last alive slot (the list's tail after the walk).
template<typename Functor>
Index SpbmLevelGenerator::MergingRun::ForPatchChains(Index p, Functor&& f)
{
  Index previous = InvalidIndex;
  for (Index slot = s.PatchHead[p]; slot != InvalidIndex;)
  {
    const Index c = slot / 2;
    const Index next = s.PatchSlotNext[slot];
    if (s.Alive[c])
    {
      f(c);
      previous = slot;
    }
    else if (previous == InvalidIndex)
    {
      s.PatchHead[p] = next;
    }
    else
    {
      s.PatchSlotNext[previous] = next;
    }
    slot = next;
  }
  return previous;
}

void SpbmLevelGenerator::MergingRun::Run(const std::vector<unsigned char>& frozen)
{
  const auto runStart = spbm::StageClock::now();
  s.Cancelled = false;
  this->ResetForRun(frozen);
  const double refinementSeconds = Since(runStart);
  if (!parameters.MergePatches && !parameters.CollapseChains)
  {
    return;
  }
  const auto mergingStart = spbm::StageClock::now();
  this->MergeInMeasureOrder();
  const double mergingSeconds = Since(mergingStart);
  if (s.Cancelled)
  {
    s.EditsValid = false; // the record stops midway: no replay from it
    vtkLogF(TRACE, "[spbm] merging run cancelled after %.4f s", Since(runStart));
    return;
  }
  const long long merged = s.Total;
  const auto removalStart = spbm::StageClock::now();
  this->RemoveDownToTarget();
  // Profiling aid: where a level's merging runs spend their time (search, fallback passes, tries).
  vtkLogF(TRACE,
    "[spbm] merging run %.4f s: reset and refinement %.4f s, merging %.4f s (%lld triangles), removal %.4f s (%lld "
    "triangles), %lld merge and %lld collapse tries",
    Since(runStart), refinementSeconds, mergingSeconds, merged, Since(removalStart), s.Total, mergeTries, collapseTries);
}

// Stages 1-2: the chain graph of the patchification with the kept vertices of every chain's
// tolerance (a prefix of its key order) and the patch sizes; the edit record starts empty.
void SpbmLevelGenerator::MergingRun::ResetForRun(const std::vector<unsigned char>& frozen)
{
  slod::StageClock clock("[spbm] reset for a run"); // TRACE: a replay's fixed cost, stage by stage
  this->ResetChainGraph(frozen);
  if (trackSupport)
  {
    this->CopyPatchSupport();
  }
  this->RebuildKept(true);
  this->ComputeMergeThreshold();
  clock.Lap("chain graph and kept vertices");
  const auto refinementStart = spbm::StageClock::now();
  this->RefineNonSimplePatches(frozen);
  s.Times.Refinement += Since(refinementStart);
  clock.Lap("non-simple patch refinement");
  s.Total = 0;
  for (Index p = 0; p < np; ++p)
  {
    s.Total += s.Size[p] - 2;
  }
  s.Edits.clear();
  s.EditsRemovalBegin = 0;
  s.EditsValid = true;
  s.EditsOf = PredictionMemo::Of(parameters);
  s.EditsTolerance = s.Tolerance;
  s.LockedInto(s.EditsLocked);
  s.EditsFrozen = frozen;
  s.DirtyPatch.clear();
  s.DirtyNear.clear();
}

void SpbmLevelGenerator::MergingRun::RemoveDownToTarget()
{
  s.EditsRemovalBegin = s.Edits.size();
  s.EditsOf = PredictionMemo::Of(parameters);
  if (parameters.RemovalTarget > 0 && s.Total > parameters.RemovalTarget && parameters.CollapseChains)
  {
    this->RemoveCheapest();
  }
  s.EditsReachedTarget = parameters.RemovalTarget <= 0 || s.Total <= parameters.RemovalTarget;
}

void SpbmLevelGenerator::MergingRun::ResetChainGraph(const std::vector<unsigned char>& frozen)
{
  s.Patches.resize(size_t(np));
  s.AbsorbedFirst.assign(size_t(np), InvalidIndex);
  s.AbsorbedNext.assign(size_t(np), InvalidIndex);
  s.AbsorbedLast.assign(size_t(np), InvalidIndex);
  s.SupportFolded.assign(size_t(np), InvalidIndex);
  s.Frozen = frozen;
  s.PatchStamp.resize(size_t(np), 0);
  for (Index p = 0; p < np; ++p)
  {
    State::PatchRecord& patch = s.Patches[p];
    patch.Parent = p;
    patch.PatchHead = InvalidIndex;
    patch.Size = 0;
    patch.Version = 0;
    patch.Normal = P.PatchNormalSum(p);
    patch.UnitNormal = Normalized(patch.Normal);
  }
  s.EndHead.assign(size_t(ne), InvalidIndex);
  s.Degree.assign(size_t(ne), 0);
  s.EndStamp.resize(size_t(ne), 0);
  s.EndLocal.resize(size_t(ne), 0);
  s.Chains.resize(size_t(nc));
  s.Tolerance.resize(size_t(nc));
  s.Tries.assign(size_t(nc), State::TriedRecord{ -1, -1, -1, -1 });
  s.CollapsesWalkedSize.assign(size_t(np), 0);
  s.CandidatesPushedSize.assign(size_t(np), 0);
  s.JointBefore.assign(size_t(nc), InvalidIndex);
  s.EndSlotNext.resize(2 * size_t(nc));
  s.PatchSlotNext.resize(2 * size_t(nc));
  if (s.KeptTolerance.size() != size_t(nc))
  {
    // Positions for another chain hierarchy (or none): every chain is rebuilt. Each chain has
    // room for all its interior vertices.
    s.Parts.resize(size_t(nc));
    s.KeptTolerance.assign(size_t(nc), std::numeric_limits<float>::quiet_NaN()); // never equal
    s.KeptLocked.assign(size_t(nc), 0);
    size_t room = 0;
    for (Index c = 0; c < nc; ++c)
    {
      s.KeptOffsets[c] = s.KeptEnd[c] = static_cast<Index>(room);
      room += size_t(std::max<Index>(0, P.ChainSize(c) - 2));
    }
    s.KeptPositions.assign(room, 0);
  }
  for (Index c = 0; c < nc; ++c)
  {
    const Index a = P.ChainStart(c), b = P.ChainEnd(c), l = P.ChainLeftPatch(c), r = P.ChainRightPatch(c);
    s.A[c] = a;
    s.B[c] = b;
    s.L[c] = l;
    s.R[c] = r;
    s.PartFirst[c] = s.PartLast[c] = c;
    s.PartNext[c] = InvalidIndex;
    s.PartReversed[c] = 0;
    s.Alive[c] = 1;
    s.Locked[c] = P.ChainIsNonManifold(c) || this->FallbackLevel(c, frozen) >= FullResolutionLevel;
    s.Tolerance[c] = this->FallbackTolerance(this->FallbackLevel(c, frozen));
    s.EndSlotNext[2 * size_t(c)] = s.EndHead[a];
    s.EndHead[a] = 2 * c;
    s.EndSlotNext[2 * size_t(c) + 1] = s.EndHead[b];
    s.EndHead[b] = 2 * c + 1;
    ++s.Degree[a];
    ++s.Degree[b];
    s.PatchSlotNext[2 * size_t(c)] = s.PatchHead[l];
    s.PatchHead[l] = 2 * c;
    if (r != InvalidIndex)
    {
      s.PatchSlotNext[2 * size_t(c) + 1] = s.PatchHead[r];
      s.PatchHead[r] = 2 * c + 1;
    }
  }
}

// FlatnessMerge: the extreme vertices of every patch in the support directions,
// computed on first use (shared by the candidate threads, hence the lock) and
// copied into the working state.
void SpbmLevelGenerator::MergingRun::CopyPatchSupport()
{
  std::lock_guard<std::mutex> lock(generator.LazyMutex);
  std::vector<Index>& support = generator.PatchSupport;
  if (support.size() != size_t(np) * SupportSize)
  {
    ++generator.PatchSupportBuilds;
    support.assign(size_t(np) * SupportSize, InvalidIndex);
    std::vector<double> extreme(size_t(np) * SupportSize, -std::numeric_limits<double>::infinity());
    const std::vector<Index>& patchOf = P.TrianglePatches();
    // A vertex met again for the patch it was last met for changes nothing (the comparisons are
    // strict): skipped (a quarter of this loop's instructions on an MRI crop, whose small patches
    // make most vertices alternate between patches).
    std::vector<Index> lastPatch(size_t(mesh.NumberOfPoints()), InvalidIndex);
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      const size_t first = size_t(patchOf[t]) * SupportSize;
      for (int k = 0; k < 3; ++k)
      {
        const Index v = mesh.Triangle(t)[k];
        if (lastPatch[size_t(v)] == patchOf[t])
        {
          continue;
        }
        lastPatch[size_t(v)] = patchOf[t];
        const Vec3 x = mesh.Point(v);
        for (int d = 0; d < SupportDirections; ++d)
        {
          const double h = x[0] * SupportAxes[d][0] + x[1] * SupportAxes[d][1] + x[2] * SupportAxes[d][2];
          if (h > extreme[first + 2 * d])
          {
            extreme[first + 2 * d] = h;
            support[first + 2 * d] = v;
          }
          if (-h > extreme[first + 2 * d + 1])
          {
            extreme[first + 2 * d + 1] = -h;
            support[first + 2 * d + 1] = v;
          }
        }
      }
    }
  }
  if (s.SupportBuild == generator.PatchSupportBuilds && s.Support.size() == support.size() &&
    s.SupportWrittenFlag.size() == size_t(np))
  {
    for (const Index p : s.SupportWritten) // the entries written since the last reset
    {
      std::copy_n(support.begin() + std::ptrdiff_t(size_t(p) * SupportSize), SupportSize,
        s.Support.begin() + std::ptrdiff_t(size_t(p) * SupportSize));
      s.SupportWrittenFlag[p] = 0;
    }
  }
  else
  {
    s.Support = support;
    s.SupportWrittenFlag.assign(size_t(np), 0);
    s.SupportBuild = generator.PatchSupportBuilds;
  }
  s.SupportWritten.clear();
}

// Merge measure (larger = merge sooner) and its threshold. Plain: the cosine of
// the normals' angle against cos(alpha1). Size-weighted: flattening the smaller
// patch of the pair onto the union's plane moves it by about its extent times
// sin(angle), so the angle is weighted by the smaller patch's extent relative
// to an average patch: small patches merge at wider angles, large ones at
// narrower angles, for the same alpha1. Flatness: minus the union's thickness.
void SpbmLevelGenerator::MergingRun::ComputeMergeThreshold()
{
  if (parameters.SizeWeightedMerge)
  {
    for (Index p = 0; p < np; ++p)
    {
      meanSize += Norm(s.Normal[p]);
    }
    meanSize = std::max(meanSize / std::max<Index>(1, np), std::numeric_limits<double>::min());
  }
  mergeThreshold = flatness
    ? (parameters.MergeAngle >= 90.0
          ? -std::numeric_limits<double>::max() / 4
          : -parameters.FlatnessScale * std::tan(Radians(std::max(0.0, parameters.MergeAngle))))
    : parameters.SizeWeightedMerge ? -std::sin(Radians(std::min(90.0, parameters.MergeAngle)))
                                   : cosMerge;
}

// Method (3) of section 4.2.8 for the patches themselves: a patch whose
// simplified boundary does not project to a simple polygon gets finer chains
// (epsilon / 4 per round, then full resolution) before anything else, so that
// predictions include it and triangulation succeeds. The refinement depends on
// epsilon only (not on alpha1): searches over alpha1 reuse it.
void SpbmLevelGenerator::MergingRun::RefineNonSimplePatches(const std::vector<unsigned char>& frozen)
{
  // Unmerged patches (fallback level 1) keep epsilon on their chains: the refinement is the same
  // as without them. Finer levels change the tolerances it starts from.
  const bool anyFrozen = std::any_of(frozen.begin(), frozen.end(), [](unsigned char f) { return f > 1; });
  const bool reuse = !anyFrozen && s.RefinedValid && s.RefinedEpsilon == eps;
  if (reuse)
  {
    s.Tolerance = s.RefinedTolerance;
    s.LockedFrom(s.RefinedLocked);
    this->RebuildKept(false);
  }
  if (s.SimpleSignature.size() != size_t(np))
  {
    s.SimpleSignature.assign(size_t(np), 0);
    s.BoundaryOutcomes.Clear(); // of another patchification
  }
  // After the first round only the patches on a chain refined by the previous round can change:
  // any other one has the signature it had then (simple, or every chain locked already), so the
  // later rounds visit those, in the same order.
  std::vector<Index>& visit = refinePatches;
  std::vector<Index> next;
  long long tested = 0, nonSimple = 0, checkedVertices = 0, rounds = 0;
  for (int round = 0; round < 8 && !reuse; ++round)
  {
    bool refined = false;
    next.clear();
    refinedChains.clear();
    const Index count = round == 0 ? np : static_cast<Index>(visit.size());
    for (Index i = 0; i < count; ++i)
    {
      const Index p = round == 0 ? i : visit[size_t(i)];
      if (s.Size[p] > MaximumCheckedBoundary || s.Frozen[p] >= FullResolutionLevel)
      {
        continue;
      }
      // The boundary is determined by how many vertices each of its chains
      // keeps (a prefix of the chain's key order, or all): remember the
      // signatures of boundaries found simple, so that the searches' many runs
      // at nearby epsilons test only the patches whose boundary changed.
      uint64_t signature = 0;
      this->ForPatchChains(p, [&](Index c) {
        uint64_t x = (uint64_t(uint32_t(c)) << 32) ^ (uint64_t(uint32_t(s.Interior[c])) << 1) ^ uint64_t(s.Locked[c]);
        x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull; // splitmix64 finalizer
        x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
        signature += x ^ (x >> 31);
      });
      if (s.SimpleSignature[p] == signature)
      {
        continue;
      }
      // The test's answer depends on the boundary only (its signature; the patch is unmerged here,
      // so its normal is its own): one seen before is not tested again.
      const uint64_t key = signature ^ Finalise(uint64_t(uint32_t(p)) + Golden);
      int simple = parameters.RememberBoundaryOutcomes ? s.BoundaryOutcomes.Find(key) : -1;
      if (simple < 0)
      {
        ++tested;
        checkedVertices += s.Size[p];
        simple = this->BoundaryPoints(p, InvalidIndex, InvalidIndex, checkPoints) &&
          ProjectsToSimplePolygon(checkPoints, s.Normal[p], s.SimplePolygonScratch);
        s.BoundaryOutcomes.Insert(key, simple != 0, 4 * size_t(np) + 1024);
      }
      if (simple)
      {
        s.SimpleSignature[p] = signature;
        continue;
      }
      ++nonSimple;
      this->ForPatchChains(p, [&](Index c) {
        if (!s.Locked[c])
        {
          refined = true;
          refinedChains.push_back(c);
          next.push_back(s.L[c]);
          if (s.R[c] != InvalidIndex)
          {
            next.push_back(s.R[c]);
          }
          if (round >= 5 || s.Tolerance[c] <= 0)
          {
            s.Locked[c] = 1; // full resolution
          }
          else
          {
            s.Tolerance[c] *= 0.25f;
          }
        }
      });
    }
    ++rounds;
    if (!refined)
    {
      break;
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    visit.swap(next);
    this->RebuildKept(false, &refinedChains);
  }
  s.BoundariesTested = reuse ? -1 : tested;
  vtkLogF(TRACE, "[spbm] non-simple patch refinement: %s, %lld rounds, %lld boundaries tested (%lld vertices), %lld not simple",
    reuse ? "reused" : "made", rounds, tested, checkedVertices, nonSimple);
  if (!anyFrozen && !reuse)
  {
    s.RefinedValid = true;
    s.RefinedEpsilon = eps;
    s.RefinedTolerance = s.Tolerance;
    s.LockedInto(s.RefinedLocked);
  }
}

// Patch merging (4.2.6) in merge-measure order; before a chain's patches merge,
// the short chains of both patches try to collapse. Work bound: a chain is
// pushed when its patches merge or its measure changed, and a popped entry is
// tried at most once per pair of patch versions; the smaller patch of a merge
// joins the larger (union by size), and a large patch walks all its chains
// again only after its boundary grew by half (WalkDue).
void SpbmLevelGenerator::MergingRun::MergeInMeasureOrder()
{
  s.MergeQueue.Reset(nc);
  for (Index c = 0; c < nc; ++c)
  {
    this->PushCandidate(c);
  }
  this->DrainMergeQueue();
}

// Pops merge candidates until none is left (see MergeInMeasureOrder).
void SpbmLevelGenerator::MergingRun::DrainMergeQueue()
{
  for (unsigned pops = 0; !s.MergeQueue.Empty(); ++pops)
  {
    if (pops % 1024 == 0 && s.CancelRequested())
    {
      s.Cancelled = true;
      return;
    }
    const double queued = -s.MergeQueue.TopKey();
    const Index c = s.MergeQueue.Pop();
    if (!this->Movable(c))
    {
      continue;
    }
    Index p = s.Find(s.L[c]), q = s.Find(s.R[c]);
    if (p == q || s.Frozen[p] || s.Frozen[q])
    {
      continue;
    }
    const double d = this->MergeMeasure(p, q);
    if (d < queued - 1e-12)
    {
      this->PushCandidate(c); // normals changed since: requeue with the current value
      continue;
    }
    if (s.MergeTriedP[c] == s.Version[p] && s.MergeTriedQ[c] == s.Version[q])
    {
      continue; // a duplicate entry: tried before (collapses and merge) and
                // neither patch changed since
    }
    if (parameters.CollapseChains)
    {
      for (const Index x : { p, q })
      {
        if (this->WalkDue(x, s.CollapsesWalkedSize))
        {
          this->TryCollapses(x, c);
        }
      }
      if (!this->Movable(c))
      {
        continue;
      }
    }
    s.MergeTriedP[c] = s.Version[p];
    s.MergeTriedQ[c] = s.Version[q];
    if (s.Size[p] < s.Size[q])
    {
      std::swap(p, q); // q joins p
    }
    absorbedChains.clear();
    this->ForPatchChains(q, [&](Index x) { absorbedChains.push_back(x); });
    if (parameters.MergePatches && this->TryMerge(c, p, q))
    {
      // The union's normal changed the measure of all its chains; requeue those of the absorbed
      // patch, and all of them when the union is small or has grown enough since the last time.
      if (this->WalkDue(p, s.CandidatesPushedSize))
      {
        this->ForPatchChains(p, [&](Index x) { this->PushCandidate(x); });
      }
      else
      {
        for (const Index x : absorbedChains)
        {
          this->PushCandidate(x);
        }
      }
    }
  }
}

// Whether root patch x walks all its chains again (see FullRetryBoundary); records the walk.
bool SpbmLevelGenerator::MergingRun::WalkDue(Index x, std::vector<Index>& walkedSize)
{
  if (s.Size[x] > FullRetryBoundary && 2 * s.Size[x] < 3 * walkedSize[x])
  {
    return false;
  }
  walkedSize[x] = s.Size[x];
  return true;
}

// Fallback level of chain c: the higher of its two patches'.
int SpbmLevelGenerator::MergingRun::FallbackLevel(Index c, const std::vector<unsigned char>& frozen) const
{
  const Index r = P.ChainRightPatch(c);
  return std::max<int>(frozen[P.ChainLeftPatch(c)], r != InvalidIndex ? frozen[r] : 0);
}

// Chain tolerance at a fallback level: levels 2.. divide epsilon by 4 each.
float SpbmLevelGenerator::MergingRun::FallbackTolerance(int level) const
{
  return spbm::FallbackTolerance(eps, level);
}

// Fallback levels 2..7 of patches that were already frozen in the merging run the state holds.
// A frozen patch takes part in no merge, collapse or join, so its chains are still the
// patchification's own, alive, with their original endpoints: a finer level changes only the
// vertices those chains keep. That is applied to the held chain graph (a new run would redo every
// merge of the level for one patch: 6 of 9 passes on noisy:137 were for a single patch); the
// patches around see the finer chains in their boundaries, and one that cannot be triangulated
// with them fails and goes to the next fallback (a whole run when it must be unmerged).
void SpbmLevelGenerator::MergingRun::RefineFrozenInPlace(const std::vector<unsigned char>& frozen)
{
  ++graphEdits;
  std::vector<Index> changed;
  for (Index c = 0; c < nc; ++c)
  {
    const int level = this->FallbackLevel(c, frozen);
    if (level != this->FallbackLevel(c, s.Frozen))
    {
      changed.push_back(c);
      s.Locked[c] = s.Locked[c] || level >= FullResolutionLevel;
      s.Tolerance[c] = std::min(s.Tolerance[c], this->FallbackTolerance(level)); // never coarser than refined
    }
  }
  s.Frozen = frozen;
  this->RebuildKeptPositions();
  for (const Index c : changed)
  {
    const Index interior = s.KeptEnd[c] - s.KeptOffsets[c];
    const Index added = interior - s.Interior[c];
    s.Interior[c] = interior;
    for (const Index side : { P.ChainLeftPatch(c), P.ChainRightPatch(c) })
    {
      if (side != InvalidIndex)
      {
        s.Size[s.Find(side)] += added;
        s.Total += added;
      }
    }
  }
}

// The kept vertices of every chain at its tolerance, and the boundary sizes of the (original, all
// root) patches. `all`: every chain counts (after ResetChainGraph); otherwise the sizes are those
// of the kept vertices before and only the chains rebuilt now change them (the refinement rounds
// rebuild a few chains; the sums over every chain read the patch records in scattered order, a
// whole-level step per round and per replayed pass). `changed`: the only chains whose tolerance or
// locking may have changed (all when null).
void SpbmLevelGenerator::MergingRun::RebuildKept(bool all, const std::vector<Index>* changed)
{
  this->RebuildKeptPositions(changed);
  if (all)
  {
    for (State::PatchRecord& patch : s.Patches)
    {
      patch.Size = 0;
    }
  }
  auto count = [&](Index c) {
    const Index interior = s.KeptEnd[c] - s.KeptOffsets[c];
    const Index added = all ? interior + 1 : interior - s.Interior[c];
    s.Interior[c] = interior;
    s.Size[s.L[c]] += added;
    if (s.R[c] != InvalidIndex)
    {
      s.Size[s.R[c]] += added;
    }
  };
  if (all)
  {
    for (Index c = 0; c < nc; ++c)
    {
      count(c);
    }
  }
  else
  {
    for (const Index c : rebuiltChains)
    {
      count(c);
    }
  }
}

// The kept interior positions of every (original) chain at its tolerance, ascending: a prefix of
// its key order, or all when locked. They depend on the chain's tolerance and locking only, so a
// chain whose positions were made for the same ones keeps them (the refinement rounds change a
// few chains; most runs of a level start from the tolerances of the run before).
void SpbmLevelGenerator::MergingRun::RebuildKeptPositions(const std::vector<Index>* changed)
{
  ++graphEdits; // the kept boundary walks are stale
  rebuiltChains.clear();
  const bool some = changed && parameters.RebuildOnlyChangedChains;
  const Index count = some ? static_cast<Index>(changed->size()) : nc;
  for (Index k = 0; k < count; ++k)
  {
    const Index c = some ? (*changed)[size_t(k)] : k;
    if (parameters.RebuildOnlyChangedChains && s.KeptTolerance[c] == s.Tolerance[c] && s.KeptLocked[c] == s.Locked[c])
    {
      continue;
    }
    ++s.Times.ChainRebuilds;
    rebuiltChains.push_back(c);
    s.KeptTolerance[c] = s.Tolerance[c];
    s.KeptLocked[c] = s.Locked[c];
    const Index n = P.ChainSize(c);
    const Index first = s.KeptOffsets[c];
    Index* kept = s.KeptPositions.data() + first;
    if (s.Locked[c])
    {
      for (Index i = 1; i + 1 < n; ++i)
      {
        *kept++ = i;
      }
    }
    else
    {
      const Index interior = generator.KeptInterior(c, s.Tolerance[c]);
      const Index* order = generator.KeyOrder.data() + (P.ChainVerticesBegin(c) - base);
      kept = std::copy(order, order + interior, kept);
      std::sort(kept - interior, kept);
    }
    s.KeptEnd[c] = static_cast<Index>(kept - s.KeptPositions.data());
  }
}

double SpbmLevelGenerator::MergingRun::SideDot(Index p, Index q)
{
  return Dot(s.Patches[p].UnitNormal, s.Patches[q].UnitNormal);
}

double SpbmLevelGenerator::MergingRun::Thickness(Index p, Index q)
{
  this->FoldSupport(p);
  this->FoldSupport(q);
  const Vec3 n = Normalized(s.Normal[p] + s.Normal[q]);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Index root : { p, q })
  {
    const Index* support = s.Support.data() + size_t(root) * SupportSize;
    for (int k = 0; k < SupportSize; ++k)
    {
      const double h = Dot(n, mesh.Point(support[k]));
      lo = std::min(lo, h);
      hi = std::max(hi, h);
    }
  }
  return (hi - lo) * inverseDiagonal;
}

double SpbmLevelGenerator::MergingRun::MergeMeasure(Index p, Index q)
{
  const double d = this->SideDot(p, q);
  if (flatness)
  {
    return d <= 0 ? -std::numeric_limits<double>::max() : -this->Thickness(p, q);
  }
  if (!parameters.SizeWeightedMerge)
  {
    return d;
  }
  if (d <= 0)
  {
    return -std::numeric_limits<double>::max();
  }
  const double weight = std::sqrt(std::min(Norm(s.Normal[p]), Norm(s.Normal[q])) / meanSize);
  return -std::sqrt(std::max(0.0, 1.0 - d * d)) * weight;
}

Index SpbmLevelGenerator::MergingRun::OtherEnd(Index c, Index e)
{
  return s.A[c] == e ? s.B[c] : s.A[c];
}

const Vec3& SpbmLevelGenerator::MergingRun::EndpointPoint(Index e)
{
  return generator.EndpointPoints[e];
}

bool SpbmLevelGenerator::MergingRun::Movable(Index c)
{
  const State::ChainRecord& chain = s.Chains[c];
  return chain.Alive && !chain.Locked && chain.Interior == 0 && chain.R != InvalidIndex;
}

void SpbmLevelGenerator::MergingRun::PushCandidate(Index c)
{
  if (!this->Movable(c))
  {
    return;
  }
  const Index p = s.Find(s.L[c]), q = s.Find(s.R[c]);
  if (p == q || s.Frozen[p] || s.Frozen[q])
  {
    return;
  }
  const double d = this->MergeMeasure(p, q);
  // One entry per chain (slod::IndexedHeap, keyed by minus the measure): a higher measure moves
  // it up, a lower one leaves it (re-evaluated when it pops). Equal measures pop by chain id, the
  // lower first (the explicit tie-break).
  if (d >= mergeThreshold)
  {
    s.MergeQueue.Lower(c, -d);
  }
}

void SpbmLevelGenerator::MergingRun::SpliceEndList(Index from, Index to)
{
  if (s.EndHead[from] == InvalidIndex)
  {
    return;
  }
  Index tail = s.EndHead[from];
  while (s.EndSlotNext[tail] != InvalidIndex)
  {
    tail = s.EndSlotNext[tail];
  }
  s.EndSlotNext[tail] = s.EndHead[to];
  s.EndHead[to] = s.EndHead[from];
  s.EndHead[from] = InvalidIndex;
}

void SpbmLevelGenerator::MergingRun::ReverseParts(Index c)
{
  // p1..pm with joints J2..Jm (J_i before p_i) becomes pm..p1 with J_{i+1}
  // before p_i.
  Index previous = InvalidIndex;
  Index part = s.PartFirst[c];
  while (part != InvalidIndex)
  {
    const Index following = s.PartNext[part];
    const Index joint = s.JointBefore[part];
    s.PartNext[part] = previous;
    s.PartReversed[part] ^= 1;
    if (previous != InvalidIndex)
    {
      s.JointBefore[previous] = joint;
    }
    previous = part;
    part = following;
  }
  std::swap(s.PartFirst[c], s.PartLast[c]);
  s.JointBefore[s.PartFirst[c]] = InvalidIndex;
}

// Boundary points of root patch `x` (plus `y` when merging along chain `skip`),
// in order, with the chain vertices the current tolerances keep. False when
// they do not close. The walk follows linked chain lists into the mesh's
// points; between two edits of the chain graph the same boundaries are asked
// for again and again (every collapse try checks the patches on both sides),
// so the last few walks are kept until the next edit.
bool SpbmLevelGenerator::MergingRun::BoundaryPoints(Index x, Index y, Index skip, std::vector<Vec3>& points)
{
  for (BoundaryWalk& walk : boundaryWalks)
  {
    if (walk.Edit == graphEdits && walk.X == x && walk.Y == y && walk.Skip == skip)
    {
      points.assign(walk.Points.begin(), walk.Points.end());
      return walk.Closed;
    }
  }
  BoundaryWalk& walk = boundaryWalks[nextBoundaryWalk];
  nextBoundaryWalk = (nextBoundaryWalk + 1) % boundaryWalks.size();
  walk.Closed = this->WalkBoundaryPoints(x, y, skip, points);
  walk.Points.assign(points.begin(), points.end());
  walk.X = x;
  walk.Y = y;
  walk.Skip = skip;
  walk.Edit = graphEdits;
  return walk.Closed;
}

bool SpbmLevelGenerator::MergingRun::WalkBoundaryPoints(Index x, Index y, Index skip, std::vector<Vec3>& points)
{
  points.clear();
  orientedChains.clear();
  const Index stamp = s.NextStamp();
  for (const Index root : { x, y })
  {
    if (root == InvalidIndex)
    {
      continue;
    }
    for (Index slot = s.PatchHead[root]; slot != InvalidIndex; slot = s.PatchSlotNext[slot])
    {
      const Index c = slot / 2;
      const State::ChainRecord& chain = s.Chains[c];
      if (!chain.Alive || c == skip)
      {
        continue;
      }
      // Slot 2c stays in the list of the root of c's left patch (unions splice whole lists), so an
      // even slot is never reversed: the Find through the patch records (a scattered read per chain
      // and walk) is only needed for the right side's slot.
      const bool odd = slot % 2 == 1;
      const bool reversed = odd && s.Find(chain.L) != root;
      ++s.Times.WalkedChains;
      s.Times.WalkSideFinds += odd;
      const Index start = reversed ? chain.B : chain.A;
      if (s.EndStamp[start] == stamp)
      {
        return false;
      }
      s.EndStamp[start] = stamp;
      s.EndLocal[start] = static_cast<Index>(orientedChains.size());
      orientedChains.push_back(reversed ? -1 - c : c);
    }
  }
  if (orientedChains.empty())
  {
    return false;
  }
  Index current = 0;
  for (size_t step = 0; step < orientedChains.size(); ++step)
  {
    const Index o = orientedChains[current];
    const State::ChainRecord& chain = s.Chains[o >= 0 ? o : -1 - o];
    // The chain's start (in the walk's direction), then its kept interior vertices written
    // forward and turned around in place when the walk runs the chain backwards.
    points.push_back(this->EndpointPoint(o >= 0 ? chain.A : chain.B));
    const size_t interiorBegin = points.size();
    for (Index part = chain.PartFirst; part != InvalidIndex; part = s.Parts[part].PartNext)
    {
      const Index* v = P.ChainVerticesBegin(part);
      const State::PartRecord& record = s.Parts[part];
      const Index first = record.KeptOffsets, last = record.KeptEnd;
      if (record.PartReversed)
      {
        for (Index i = last; i > first; --i)
        {
          points.push_back(mesh.Point(v[s.KeptPositions[i - 1]]));
        }
      }
      else
      {
        for (Index i = first; i < last; ++i)
        {
          points.push_back(mesh.Point(v[s.KeptPositions[i]]));
        }
      }
    }
    if (o < 0)
    {
      std::reverse(points.begin() + std::ptrdiff_t(interiorBegin), points.end());
    }
    const Index end = o >= 0 ? chain.B : chain.A;
    if (s.EndStamp[end] != stamp)
    {
      return false;
    }
    current = s.EndLocal[end];
  }
  return current == 0;
}

// Would patch x still project to a simple polygon once endpoint `gone` is
// dropped (replace == InvalidIndex) or replaced by `replace`?
bool SpbmLevelGenerator::MergingRun::SimpleAfter(Index x, Index gone, Index replace)
{
  if (s.Size[x] > MaximumCheckedBoundary)
  {
    return true; // left to the triangulation fallback
  }
  if (!this->BoundaryPoints(x, InvalidIndex, InvalidIndex, checkPoints))
  {
    return false;
  }
  const Vec3 g = this->EndpointPoint(gone);
  const auto at = std::find(checkPoints.begin(), checkPoints.end(), g);
  if (at == checkPoints.end())
  {
    return true;
  }
  size_t changed = size_t(at - checkPoints.begin());
  if (replace == InvalidIndex)
  {
    checkPoints.erase(at);
    changed = changed == 0 ? checkPoints.size() - 1 : changed - 1; // the new segment starts here
  }
  else
  {
    *at = this->EndpointPoint(replace);
  }
  return ProjectsToSimplePolygon(checkPoints, s.Normal[x], s.SimplePolygonScratch, changed);
}

// Chain collapse (4.2.6 (a)-(c), 4.2.7): one-edge chain e shrinks to one
// endpoint, toward the border, else toward the larger normal variation. Relaxed
// (cost-ordered removal): without the length and epsilon bounds, toward
// forcedKeep. A negative `longest` stands for LongestChain(collapseRoot), computed only when a
// chain gets as far as condition (c) (most tries stop at the version check before), and then kept
// for the rest of the walk: no collapse has changed the patch before its first use.
bool SpbmLevelGenerator::MergingRun::TryCollapse(Index e, double& longest)
{
  ++collapseTries;
  if (!this->Movable(e))
  {
    return false;
  }
  const Index p = s.Find(s.L[e]), q = s.Find(s.R[e]);
  if (p == q || s.Frozen[p] || s.Frozen[q] || (!relaxed && this->SideDot(p, q) < cosMerge)) // (b)
  {
    return false;
  }
  if (s.TriedP[e] == s.Version[p] && s.TriedQ[e] == s.Version[q])
  {
    return false; // failed before and neither patch changed since
  }
  s.TriedP[e] = s.Version[p];
  s.TriedQ[e] = s.Version[q];
  const Index a = s.A[e], b = s.B[e];
  const Vec3 pa = this->EndpointPoint(a), pb = this->EndpointPoint(b);
  if (!relaxed && longest < 0)
  {
    longest = this->LongestChain(collapseRoot);
  }
  if (!relaxed && Norm(pb - pa) >= parameters.CollapseLengthFactor * longest) // (c)
  {
    return false;
  }
  if (!relaxed && parameters.CollapseWithinEpsilon &&
    Norm(pb - pa) > std::min(s.Tolerance[e], float(parameters.Epsilon)))
  {
    return false; // moving an endpoint farther than epsilon would break the
                  // chain bound
  }
  const bool borderA = P.EndpointOnBorder(a), borderB = P.EndpointOnBorder(b);
  if (borderA && borderB)
  {
    return false;
  }
  // Toward the border vertex, else toward the larger normal variation.
  Index keep = borderA ? a : (borderB ? b : (generator.EndpointVariation[a] >= generator.EndpointVariation[b] ? a : b));
  if (forcedKeep != InvalidIndex)
  {
    if ((forcedKeep == a && borderB) || (forcedKeep == b && borderA))
    {
      return false;
    }
    keep = forcedKeep;
  }
  const Index gone = keep == a ? b : a;
  if (s.Size[p] < 4 || s.Size[q] < 4 || !this->CollapseKeepsTopology(e, p, q, keep, gone) ||
    !this->CollapseKeepsSimple(p, q, keep, gone))
  {
    return false;
  }
  this->ApplyCollapse(e, p, q, keep, gone);
  return true;
}

// Condition (a): no third patch has both endpoints (and no frozen patch is
// touched), and no two chains would become parallel edges.
bool SpbmLevelGenerator::MergingRun::CollapseKeepsTopology(Index e, Index p, Index q, Index keep, Index gone)
{
  const Index stamp = s.NextStamp();
  s.ForEndChains(keep, [&](Index c) {
    s.PatchStamp[s.Find(s.L[c])] = stamp;
    if (s.R[c] != InvalidIndex)
    {
      s.PatchStamp[s.Find(s.R[c])] = stamp;
    }
    s.EndStamp[this->OtherEnd(c, keep)] = stamp;
  });
  bool ok = true;
  s.ForEndChains(gone, [&](Index c) {
    if (c == e || !ok)
    {
      return;
    }
    const Index sides[2] = { s.Find(s.L[c]), s.R[c] == InvalidIndex ? InvalidIndex : s.Find(s.R[c]) };
    for (const Index side : sides)
    {
      if (side == InvalidIndex)
      {
        continue;
      }
      if (s.Frozen[side] || (side != p && side != q && s.PatchStamp[side] == stamp)) // (a)
      {
        ok = false;
      }
    }
    const Index o = this->OtherEnd(c, gone);
    if (s.Locked[c] || o == keep || s.EndStamp[o] == stamp) // would make parallel edges
    {
      ok = false;
    }
  });
  return ok;
}

// The patches around `gone` must stay simple in projection.
bool SpbmLevelGenerator::MergingRun::CollapseKeepsSimple(Index p, Index q, Index keep, Index gone)
{
  if (!this->SimpleAfter(p, gone, InvalidIndex) || !this->SimpleAfter(q, gone, InvalidIndex))
  {
    return false;
  }
  bool ok = true;
  const Index around = s.NextStamp();
  s.PatchStamp[p] = s.PatchStamp[q] = around;
  s.ForEndChains(gone, [&](Index c) {
    for (const Index side : { s.L[c], s.R[c] })
    {
      if (ok && side != InvalidIndex && s.PatchStamp[s.Find(side)] != around)
      {
        s.PatchStamp[s.Find(side)] = around;
        ok = this->SimpleAfter(s.Find(side), gone, keep);
      }
    }
  });
  return ok;
}

void SpbmLevelGenerator::MergingRun::ApplyCollapse(Index e, Index p, Index q, Index keep, Index gone)
{
  ++graphEdits; // the kept boundary walks are stale
  this->Record(CollapseEdit, { e, p, q, keep, gone, collapseRoot });
  s.Alive[e] = 0;
  // The patches around the collapse keep their versions, so their failed tries are not retried.
  // (Until session 22 a second walk meant to bump them found nothing: the chains were renamed
  // already. Bumping them costs 8% more CPU on noisy:546, for the same counts and distances on
  // the MRI, noisy:137 and 22 CGAL meshes at 10%.)
  s.ForEndChains(gone, [&](Index c) {
    if (s.A[c] == gone)
    {
      s.A[c] = keep;
    }
    if (s.B[c] == gone)
    {
      s.B[c] = keep;
    }
  });
  this->SpliceEndList(gone, keep);
  if (!s.DirtyPatch.empty())
  {
    s.DirtyNear[keep] |= s.DirtyNear[gone]; // gone's chains and patches are keep's now
  }
  s.Degree[keep] += s.Degree[gone] - 2;
  s.Degree[gone] = 0;
  --s.Size[p];
  --s.Size[q];
  s.Total -= 2;
}

// Length of the longest chain (endpoint to endpoint) of root patch x: condition (c)'s scale. It
// runs inside walks of x's chain list (TryCollapse), so it leaves the list as it is.
double SpbmLevelGenerator::MergingRun::LongestChain(Index x)
{
  double longest = 0;
  for (Index slot = s.PatchHead[x]; slot != InvalidIndex; slot = s.PatchSlotNext[slot])
  {
    const Index c = slot / 2;
    if (s.Alive[c])
    {
      longest = std::max(longest, Norm(this->EndpointPoint(s.B[c]) - this->EndpointPoint(s.A[c])));
    }
  }
  return longest;
}

void SpbmLevelGenerator::MergingRun::TryCollapses(Index x, Index exclude)
{
  collapseRoot = x;
  double longest = -1; // LongestChain(x), on first need
  this->ForPatchChains(x, [&](Index c) {
    if (c != exclude)
    {
      this->TryCollapse(c, longest);
    }
  });
}

// All vertices of chain c from endpoint `from` to the other one, with kept
// flags, appended to chainPoints / chainKept.
void SpbmLevelGenerator::MergingRun::AppendChain(Index c, Index from, bool skipFirst)
{
  const size_t start = chainPoints.size();
  chainPoints.push_back(this->EndpointPoint(s.A[c]));
  chainKept.push_back(1);
  for (Index part = s.PartFirst[c]; part != InvalidIndex; part = s.PartNext[part])
  {
    if (part != s.PartFirst[c])
    {
      chainPoints.push_back(this->EndpointPoint(s.JointBefore[part]));
      chainKept.push_back(0);
    }
    const Index* v = P.ChainVerticesBegin(part);
    const Index n = P.ChainSize(part);
    const bool reversed = s.PartReversed[part];
    const size_t partStart = chainPoints.size();
    for (Index i = 1; i + 1 < n; ++i)
    {
      chainPoints.push_back(mesh.Point(v[reversed ? n - 1 - i : i]));
      chainKept.push_back(0);
    }
    for (Index j = s.KeptOffsets[part]; j < s.KeptEnd[part]; ++j)
    {
      const Index k = s.KeptPositions[j];
      chainKept[partStart + size_t(reversed ? n - 1 - k : k) - 1] = 1;
    }
  }
  chainPoints.push_back(this->EndpointPoint(s.B[c]));
  chainKept.push_back(1);
  if (s.A[c] != from)
  {
    std::reverse(chainPoints.begin() + std::ptrdiff_t(start), chainPoints.end());
    std::reverse(chainKept.begin() + std::ptrdiff_t(start), chainKept.end());
  }
  if (skipFirst)
  {
    chainPoints.erase(chainPoints.begin() + std::ptrdiff_t(start));
    chainKept.erase(chainKept.begin() + std::ptrdiff_t(start));
  }
}

// The chains x and y joined at their common endpoint u (dropped), and the kept
// vertices a < b that become the ends of the segment replacing u.
void SpbmLevelGenerator::MergingRun::JoinAround(Index x, Index y, Index u, size_t& a, size_t& b)
{
  chainPoints.clear();
  chainKept.clear();
  this->AppendChain(x, this->OtherEnd(x, u), false);
  const size_t joint = chainPoints.size() - 1;
  this->AppendChain(y, u, true);
  chainKept[joint] = 0;
  a = joint;
  b = joint;
  while (!chainKept[a])
  {
    --a;
  }
  while (!chainKept[b])
  {
    ++b;
  }
}

// Dropping endpoint u between chains x and y keeps the chain within its
// tolerance: every vertex between the kept neighbours of u stays within epsilon
// of the new segment.
bool SpbmLevelGenerator::MergingRun::JoinWithinTolerance(Index x, Index y, Index u)
{
  size_t a, b;
  this->JoinAround(x, y, u, a, b);
  const double tolerance = std::min(s.Tolerance[x], s.Tolerance[y]);
  for (size_t i = a + 1; i < b; ++i)
  {
    if (PointSegmentDistance2(chainPoints[i], chainPoints[a], chainPoints[b]) > tolerance * tolerance || tolerance < 0)
    {
      return false;
    }
  }
  return true;
}

// An endpoint left between exactly two one-edge chains of the same two patches
// disappears.
void SpbmLevelGenerator::MergingRun::TryJoin(Index u)
{
  if (s.Degree[u] != 2 || P.EndpointOnBorder(u))
  {
    return;
  }
  Index pair[2];
  const bool two = s.TwoChainsAt(u, pair);
  auto joinable = [&](Index c) {
    return s.Alive[c] && !s.Locked[c] && s.R[c] != InvalidIndex && !s.Frozen[s.Find(s.L[c])] &&
      !s.Frozen[s.Find(s.R[c])];
  };
  if (!two || !joinable(pair[0]) || !joinable(pair[1]))
  {
    return;
  }
  const Index x = pair[0], y = pair[1];
  const Index xl = s.Find(s.L[x]), xr = s.Find(s.R[x]), yl = s.Find(s.L[y]), yr = s.Find(s.R[y]);
  if (!((xl == yl && xr == yr) || (xl == yr && xr == yl)) || xl == xr)
  {
    return;
  }
  const Index ox = this->OtherEnd(x, u), oy = this->OtherEnd(y, u);
  if (ox == oy || s.Size[xl] < 4 || s.Size[xr] < 4)
  {
    return;
  }
  bool parallel = false;
  s.ForEndChains(ox, [&](Index c) { parallel = parallel || this->OtherEnd(c, ox) == oy; });
  if (parallel || (parameters.JoinWithinEpsilon && !relaxed && !this->JoinWithinTolerance(x, y, u)) ||
    !this->SimpleAfter(xl, u, InvalidIndex) || !this->SimpleAfter(xr, u, InvalidIndex))
  {
    return;
  }
  this->ApplyJoin(x, y, u, oy, xl, xr, yl);
}

// Chain y is appended to x (in x's direction) and endpoint u between them
// disappears.
void SpbmLevelGenerator::MergingRun::ApplyJoin(Index x, Index y, Index u, Index oy, Index xl, Index xr, Index yl)
{
  ++graphEdits; // the kept boundary walks are stale
  if (s.B[x] == u)
  {
    // x runs ox -> u; append y oriented u -> oy.
    const bool forward = s.A[y] == u;
    if (forward != (yl == xl))
    {
      return; // inconsistent sides (cannot happen for oriented input)
    }
    if (!forward)
    {
      this->ReverseParts(y);
    }
    s.JointBefore[s.PartFirst[y]] = u;
    s.PartNext[s.PartLast[x]] = s.PartFirst[y];
    s.PartLast[x] = s.PartLast[y];
    s.B[x] = oy;
    s.EndSlotNext[2 * size_t(x) + 1] = s.EndHead[oy];
    s.EndHead[oy] = 2 * x + 1;
  }
  else
  {
    // x runs u -> ox; prepend y oriented oy -> u.
    const bool forward = s.B[y] == u;
    if (forward != (yl == xl))
    {
      return;
    }
    if (!forward)
    {
      this->ReverseParts(y);
    }
    s.JointBefore[s.PartFirst[x]] = u;
    s.PartNext[s.PartLast[y]] = s.PartFirst[x];
    s.PartFirst[x] = s.PartFirst[y];
    s.A[x] = oy;
    s.EndSlotNext[2 * size_t(x)] = s.EndHead[oy];
    s.EndHead[oy] = 2 * x;
  }
  s.Interior[x] += s.Interior[y];
  ++s.Version[xl];
  ++s.Version[xr];
  s.Alive[y] = 0;
  s.Degree[u] = 0;
  --s.Size[xl];
  --s.Size[xr];
  s.Total -= 2;
  this->Record(JoinEdit, { x, y, u, oy, xl, xr, yl });
}

bool SpbmLevelGenerator::MergingRun::TryMerge(Index c, Index p, Index q)
{
  ++mergeTries;
  // The paper also asks every chain of both patches to be one segment; only the
  // common one has to be (the union of two disks glued along one segment is a
  // disk either way), which lets small patches merge into large curved ones.
  if (s.Size[p] + s.Size[q] - 2 < 3)
  {
    return false;
  }
  if (!this->SharesOnlyChain(c, p, q))
  {
    return false;
  }
  if (parameters.MaximumPatchThickness > 0 && this->Thickness(p, q) > parameters.MaximumPatchThickness)
  {
    return false;
  }
  // Method (3) of section 4.2.8: no merge whose boundary would not project to a
  // simple polygon on the merged normal (it could not be triangulated without
  // flips). Long boundaries are left to the triangulation fallback.
  if (s.Size[p] + s.Size[q] <= MaximumCheckedBoundary &&
    (!this->BoundaryPoints(p, q, c, mergedPoints) ||
      !ProjectsToSimplePolygon(mergedPoints, s.Normal[p] + s.Normal[q], s.SimplePolygonScratch)))
  {
    return false;
  }
  if (trackSupport)
  {
    this->UniteSupport(p, q);
  }
  this->UnitePatches(c, p, q);
  return true;
}

// Common boundary of patches p and q = chain c, and no other common vertex (the
// union stays a disk).
bool SpbmLevelGenerator::MergingRun::SharesOnlyChain(Index c, Index p, Index q)
{
  const Index stamp = s.NextStamp();
  bool ok = true;
  this->ForPatchChains(q, [&](Index x) {
    if (x != c)
    {
      const Index other =
        s.Find(s.L[x]) == q ? (s.R[x] == InvalidIndex ? InvalidIndex : s.Find(s.R[x])) : s.Find(s.L[x]);
      ok = ok && other != p;
      s.EndStamp[s.A[x]] = stamp;
      s.EndStamp[s.B[x]] = stamp;
    }
  });
  if (!ok)
  {
    return false;
  }
  this->ForPatchChains(p, [&](Index x) {
    if (x != c)
    {
      for (const Index e : { s.A[x], s.B[x] })
      {
        if (e != s.A[c] && e != s.B[c] && s.EndStamp[e] == stamp)
        {
          ok = false;
        }
      }
    }
  });
  return ok;
}

// FlatnessMerge: the union's extreme vertices, the more extreme of the two in
// each direction.
void SpbmLevelGenerator::MergingRun::UniteSupport(Index p, Index q)
{
  this->FoldSupport(p);
  this->FoldSupport(q);
  this->CombineSupport(s.Support.data() + size_t(p) * SupportSize, s.Support.data() + size_t(q) * SupportSize);
  s.SupportFolded[p] = q; // UnitePatches appends q to p's absorbed patches next
}

// The more extreme of two supports in each direction (ties keep `into`'s).
void SpbmLevelGenerator::MergingRun::CombineSupport(Index* into, const Index* from)
{
  ++s.Times.SupportUnions;
  const size_t p = size_t(into - s.Support.data()) / SupportSize;
  if (p >= s.SupportWrittenFlag.size())
  {
    s.SupportBuild = -1; // not tracked: the next run resets the whole array
  }
  else if (!s.SupportWrittenFlag[p])
  {
    s.SupportWrittenFlag[p] = 1;
    s.SupportWritten.push_back(Index(p));
  }
  for (int d = 0; d < SupportDirections; ++d)
  {
    const Vec3 axis{ SupportAxes[d][0], SupportAxes[d][1], SupportAxes[d][2] };
    if (Dot(axis, mesh.Point(from[2 * d])) > Dot(axis, mesh.Point(into[2 * d])))
    {
      into[2 * d] = from[2 * d];
    }
    if (Dot(axis, mesh.Point(from[2 * d + 1])) < Dot(axis, mesh.Point(into[2 * d + 1])))
    {
      into[2 * d + 1] = from[2 * d + 1];
    }
  }
}

// Brings the support of `root` up to date: the patches it absorbed since its support was last
// united are folded in, in the order of their unions, each after its own absorbed patches (all
// absorbed before it). Each absorbed patch is folded once per run (an explicit stack: the union
// tree's depth is not bounded).
void SpbmLevelGenerator::MergingRun::FoldSupport(Index root)
{
  if (s.SupportFolded[root] == s.AbsorbedLast[root])
  {
    return;
  }
  std::vector<Index>& stack = foldStack;
  stack.assign(1, root);
  while (!stack.empty())
  {
    const Index x = stack.back();
    if (s.SupportFolded[x] == s.AbsorbedLast[x])
    {
      stack.pop_back();
      continue;
    }
    const Index next = s.SupportFolded[x] == InvalidIndex ? s.AbsorbedFirst[x] : s.AbsorbedNext[s.SupportFolded[x]];
    if (s.SupportFolded[next] != s.AbsorbedLast[next])
    {
      stack.push_back(next); // its own absorbed patches first
      continue;
    }
    this->CombineSupport(s.Support.data() + size_t(x) * SupportSize, s.Support.data() + size_t(next) * SupportSize);
    s.SupportFolded[x] = next;
    ++s.Times.SupportFolds;
  }
}

// The endpoints of root patch x's chains are next to a dirty patch (DirtyNear).
void SpbmLevelGenerator::MergingRun::MarkNearPatch(Index x)
{
  this->ForPatchChains(x, [&](Index c) { s.DirtyNear[s.A[c]] = s.DirtyNear[s.B[c]] = 1; });
}

// Patch q joins p along chain c (removed); the endpoints of c may disappear by
// joins.
void SpbmLevelGenerator::MergingRun::UnitePatches(Index c, Index p, Index q)
{
  ++graphEdits; // the kept boundary walks are stale
  this->Record(UniteEdit, { c, p, q });
  if (!s.DirtyPatch.empty() && s.DirtyPatch[p] != s.DirtyPatch[q])
  {
    this->MarkNearPatch(s.DirtyPatch[p] ? q : p); // the clean one's endpoints are next to a dirty patch now
    s.DirtyPatch[p] = 1;
  }
  s.Parent[q] = p;
  (s.AbsorbedLast[p] == InvalidIndex ? s.AbsorbedFirst[p] : s.AbsorbedNext[s.AbsorbedLast[p]]) = q;
  s.AbsorbedLast[p] = q;
  s.Version[p] += s.Version[q] + 1;
  s.Normal[p] = s.Normal[p] + s.Normal[q];
  s.UnitNormal[p] = Normalized(s.Normal[p]);
  s.Size[p] += s.Size[q] - 2;
  // Splice q's chain list into p's; the walk that drops q's dead chains ends on its tail.
  const Index tail = this->ForPatchChains(q, [](Index) {});
  if (s.PatchHead[q] != InvalidIndex)
  {
    s.PatchSlotNext[tail] = s.PatchHead[p];
    s.PatchHead[p] = s.PatchHead[q];
    s.PatchHead[q] = InvalidIndex;
  }
  s.Alive[c] = 0;
  --s.Degree[s.A[c]];
  --s.Degree[s.B[c]];
  if (!replaying)
  {
    this->TryJoin(s.A[c]);
    this->TryJoin(s.B[c]);
  }
}

// --- Cost-ordered removal (RemovalTarget) ---
// Endpoints are removed cheapest first until the level has at most
// RemovalTarget triangles: collapses of one-edge chains toward either end and
// joins of degree-two endpoints, without the length and epsilon bounds.
// Operations: 2c (collapse chain c into its start), 2c + 1 (into its end),
// joinBase + u (join at u). Work bound: every successful operation removes an
// endpoint and pushes a bounded number of neighbours; a requeued entry is
// pushed only when its cost rose.
void SpbmLevelGenerator::MergingRun::RemoveCheapest()
{
  joinBase = 2 * nc;
  const size_t queueRoom = removalQueue.MemoryBytes();
  removalQueue.Reset(joinBase + ne);
  s.WorkspaceAllocations += removalQueue.MemoryBytes() > queueRoom;
  // A replay around dirty patches whose recorded run ran out of removals above the target: the
  // clean rest had none left then (unreachable targets, rough scans), so only the dirty
  // neighbourhoods are queued.
  const bool recordedRanOut = removalAroundDirty && !s.EditsReachedTarget;
  this->SeedRemovals(removalAroundDirty);
  this->PopRemovals();
  if (removalAroundDirty && !recordedRanOut && s.Total > parameters.RemovalTarget)
  {
    this->SeedRemovals(false); // the dirty neighbourhoods ran out of removals: everywhere
    this->PopRemovals();
  }
}

// Queues the removal operations of every chain and endpoint, or (aroundDirty, a replayed pass)
// only those of the chains of dirty patches and their endpoints: the clean rest is as the
// recorded run left it, whose removal stopped at the target, and the removals still missing are
// those the dirty patches did not make as recorded. (Queuing every chain and endpoint after each
// replay was a sixth of a replayed pass on the MRI and the noisy scans.)
void SpbmLevelGenerator::MergingRun::SeedRemovals(bool aroundDirty)
{
  for (Index c = 0; c < nc; ++c)
  {
    if (aroundDirty &&
      !(s.Alive[c] && s.R[c] != InvalidIndex && (s.DirtyPatch[s.Find(s.L[c])] || s.DirtyPatch[s.Find(s.R[c])])))
    {
      continue;
    }
    if (this->RemovableChain(c))
    {
      this->PushRemoval(2 * c);
      this->PushRemoval(2 * c + 1);
    }
    if (aroundDirty)
    {
      this->PushRemoval(joinBase + s.A[c]);
      this->PushRemoval(joinBase + s.B[c]);
    }
  }
  for (Index u = 0; u < ne; ++u)
  {
    if (!aroundDirty || s.DirtyEnd[u])
    {
      this->PushRemoval(joinBase + u);
    }
  }
}

// Pops removals cheapest first until the level is at the target or none is left.
void SpbmLevelGenerator::MergingRun::PopRemovals()
{
  const long long target = parameters.RemovalTarget;
  const double infinite = std::numeric_limits<double>::infinity();
  while (s.Total > target && !removalQueue.Empty())
  {
    const double queued = removalQueue.TopKey();
    const Index op = removalQueue.Pop();
    const double cost = this->RemovalCost(op);
    if (cost == infinite)
    {
      continue;
    }
    if (cost > queued * (1 + 1e-9) + 1e-300)
    {
      removalQueue.Set(op, cost); // the neighbourhood changed: requeue at its current cost
      continue;
    }
    Index touched[2] = { InvalidIndex, InvalidIndex };
    if (!this->ApplyRemoval(op, touched))
    {
      continue;
    }
    // Requeue what the change can make possible or cheaper: the chains and
    // joins around it.
    for (const Index e : touched)
    {
      if (e == InvalidIndex)
      {
        continue;
      }
      this->PushRemoval(joinBase + e);
      s.ForEndChains(e, [&](Index c) {
        if (this->RemovableChain(c))
        {
          this->PushRemoval(2 * c);
          this->PushRemoval(2 * c + 1);
        }
        this->PushRemoval(joinBase + (s.A[c] == e ? s.B[c] : s.A[c]));
      });
    }
  }
}

// Performs removal operation `op`; `touched` gets the endpoints whose
// neighbourhood changed.
bool SpbmLevelGenerator::MergingRun::ApplyRemoval(Index op, Index (&touched)[2])
{
  if (op >= joinBase)
  {
    const Index u = op - joinBase;
    Index ends[2] = { InvalidIndex, InvalidIndex };
    int k = 0;
    s.ForEndChains(u, [&](Index c) {
      if (k < 2)
      {
        ends[k++] = s.A[c] == u ? s.B[c] : s.A[c];
      }
    });
    if (!this->RemovalJoin(u))
    {
      return false;
    }
    touched[0] = ends[0];
    touched[1] = ends[1];
    return true;
  }
  const Index c = op / 2;
  const Index keep = op % 2 == 0 ? s.A[c] : s.B[c];
  if (!this->RemovalCollapse(c, keep))
  {
    return false;
  }
  touched[0] = keep;
  return true;
}

bool SpbmLevelGenerator::MergingRun::RemovableChain(Index c)
{
  return s.Alive[c] && !s.Locked[c] && s.Interior[c] == 0 && s.R[c] != InvalidIndex &&
    s.Find(s.L[c]) != s.Find(s.R[c]) && !s.Frozen[s.Find(s.L[c])] && !s.Frozen[s.Find(s.R[c])];
}

// Moving endpoint `gone` onto `keep` moves the patches around `gone` by the
// displacement's component along their normals (and, weighted, along the
// surface).
double SpbmLevelGenerator::MergingRun::CollapseCost(Index c, Index keep)
{
  const double infinite = std::numeric_limits<double>::infinity();
  if (!this->RemovableChain(c))
  {
    return infinite;
  }
  const Index gone = s.A[c] == keep ? s.B[c] : s.A[c];
  // A triangle patch on a side cannot lose a corner (TryCollapse refuses it), and patches only
  // shrink during the removal: such a collapse is never queued. On noisy scans most collapses
  // end like this (noisy:137 at 10%: 123,544 of 140,196 directions when the removal ran out),
  // each popped and retried whenever a neighbour changed.
  if (P.EndpointOnBorder(gone) || s.Size[s.Find(s.L[c])] < 4 || s.Size[s.Find(s.R[c])] < 4)
  {
    return infinite;
  }
  const Vec3 d = this->EndpointPoint(gone) - this->EndpointPoint(keep);
  double cost = generator.InPlaneWeight * Norm(d);
  s.ForEndChains(gone, [&](Index x) {
    for (const Index side : { s.L[x], s.R[x] })
    {
      if (side != InvalidIndex)
      {
        cost = std::max(cost, std::fabs(Dot(s.UnitNormal[s.Find(side)], d)));
      }
    }
  });
  return cost;
}

double SpbmLevelGenerator::MergingRun::JoinCost(Index u)
{
  const double infinite = std::numeric_limits<double>::infinity();
  Index pair[2];
  if (s.Degree[u] != 2 || P.EndpointOnBorder(u) || !s.TwoChainsAt(u, pair) || s.Locked[pair[0]] || s.Locked[pair[1]] ||
    s.R[pair[0]] == InvalidIndex || s.R[pair[1]] == InvalidIndex)
  {
    return infinite;
  }
  const Index xl = s.Find(s.L[pair[0]]), xr = s.Find(s.R[pair[0]]);
  const Index yl = s.Find(s.L[pair[1]]), yr = s.Find(s.R[pair[1]]);
  if (!((xl == yl && xr == yr) || (xl == yr && xr == yl)) || xl == xr || s.Size[xl] < 4 || s.Size[xr] < 4)
  {
    return infinite; // (TryJoin's own tests; patches only shrink during the removal)
  }
  return this->JoinDeviation(pair[0], pair[1], u);
}

// Largest surface-weighted distance of the chain vertices between u's kept
// neighbours from the segment that replaces them.
double SpbmLevelGenerator::MergingRun::JoinDeviation(Index x, Index y, Index u)
{
  size_t a, b;
  this->JoinAround(x, y, u, a, b);
  const Vec3 n1 = s.UnitNormal[s.Find(s.L[x])], n2 = s.UnitNormal[s.Find(s.R[x])];
  const double w2 = generator.InPlaneWeight * generator.InPlaneWeight;
  double worst = 0;
  for (size_t i = a + 1; i < b; ++i)
  {
    worst = std::max(worst, SurfaceWeightedDistance2(chainPoints[i], chainPoints[a], chainPoints[b], n1, n2, w2));
  }
  return std::sqrt(worst);
}

double SpbmLevelGenerator::MergingRun::RemovalCost(Index op)
{
  if (op >= joinBase)
  {
    return this->JoinCost(op - joinBase);
  }
  const Index c = op / 2;
  return this->CollapseCost(c, op % 2 == 0 ? s.A[c] : s.B[c]);
}

void SpbmLevelGenerator::MergingRun::PushRemoval(Index op)
{
  const double cost = this->RemovalCost(op);
  // One entry per operation at its current cost (slod::IndexedHeap); equal costs pop by operation
  // id, the lower first (the explicit tie-break).
  if (cost < std::numeric_limits<double>::infinity())
  {
    removalQueue.Set(op, cost);
  }
  else
  {
    removalQueue.Remove(op);
  }
}

bool SpbmLevelGenerator::MergingRun::RemovalCollapse(Index e, Index keep)
{
  relaxed = true;
  forcedKeep = keep;
  s.TriedP[e] = s.TriedQ[e] = -1;
  double unbounded = std::numeric_limits<double>::infinity(); // relaxed: no condition (c)
  const bool done = this->TryCollapse(e, unbounded);
  forcedKeep = InvalidIndex;
  relaxed = false;
  return done;
}

bool SpbmLevelGenerator::MergingRun::RemovalJoin(Index u)
{
  relaxed = true;
  this->TryJoin(u);
  relaxed = false;
  return s.Degree[u] == 0;
}
} // namespace slod
