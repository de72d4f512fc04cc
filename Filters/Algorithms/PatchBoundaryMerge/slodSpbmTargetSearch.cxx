// SPDX-License-Identifier: BSD-3-Clause
#include "slodSpbmTargetSearch.h"

#include "slodSpbmFinalCollapses.h"

#include "vtkLogger.h"

#include <atomic>
#include <cmath>

namespace slod
{
using namespace spbm;

SpbmLevelGenerator::TargetSearch::TargetSearch(
  SpbmLevelGenerator& generator_, Index target_, const SpbmLevelParameters& base_, State& state)
  : generator(generator_)
  , s(state)
  , base(base_)
  , target(target_)
  , params(base_)
  , nk(static_cast<Index>(generator_.SortedKeys.size()))
  , countTolerance(std::max<Index>(2, target_ / 50))
{
}

double SpbmLevelGenerator::TargetSearch::EpsilonFor(Index k) const
{
  return k < nk ? double(generator.SortedKeys[k]) : -1.0;
}

Index SpbmLevelGenerator::TargetSearch::CountFor(Index k, double angle)
{
  SpbmLevelParameters p = params;
  p.Epsilon = this->EpsilonFor(k);
  p.MergeAngle = angle;
  const int runs = s.Times.MergingRuns;
  const Index count = generator.PredictTriangleCountIn(p, s);
  vtkLogF(TRACE, "[spbm] search: %lld of %lld kept keys, alpha1 %.3g, removal %lld: %lld triangles (target %lld)%s",
    (long long)k, (long long)nk, angle, (long long)p.RemovalTarget, (long long)count, (long long)target,
    s.Times.MergingRuns == runs ? ", remembered" : "");
  return count;
}

SpbmLevelParameters SpbmLevelGenerator::TargetSearch::Run(Index* predicted)
{
  const double angle = this->SearchMergeAngle();
  params.MergeAngle = angle;
  Evaluation best;
  best.Angle = angle;
  best.K = this->SearchKeptVertices(angle, best.Count);
  if (base.ReachBandAcrossKeyJumps && params.RemovalTarget == 0 && best.Count < target - countTolerance)
  {
    this->ReachBandAcrossKeyJump(best);
  }
  params.MergeAngle = best.Angle;
  params.Epsilon = this->EpsilonFor(best.K);
  if (predicted)
  {
    *predicted = best.Count;
  }
  return params;
}

// Within the count tolerance of the target, either side: the filter's contract (slod::ReportTarget;
// the final collapses leave such a level as it is).
bool SpbmLevelGenerator::TargetSearch::InBand(Index count) const
{
  return count >= target - countTolerance && count <= target + countTolerance;
}

// Issue 15 (session 28): the closest count not above the target is below the band, and one or two
// kept vertices more are above the target. A kept vertex can block a whole cascade of merges,
// joins and collapses (couplingdown at 50%: 1,782 -> 1,906 triangles for one key at alpha1 20,
// target 1,857), so no epsilon lands in the band at this alpha1. The count also falls with alpha1
// at a fixed epsilon, in other steps: a narrower alpha1 at the lower count's epsilon raises it, a
// wider one at the higher count's lowers it. A count of the next two epsilons within the band
// above the target is taken as it is (the search's look-around has them: no run). Bounded: at
// most MaximumBandProbes merging runs, the narrower side first; without a count in the band the
// search's answer stays.
void SpbmLevelGenerator::TargetSearch::ReachBandAcrossKeyJump(Evaluation& best)
{
  Evaluation above = best;
  for (Index k = best.K + 1; k <= std::min(nk, best.K + 2) && above.Count <= target; ++k)
  {
    above = { k, best.Angle, this->CountFor(k, best.Angle) };
  }
  if (above.Count <= target)
  {
    return; // no jump: the finest level is below the target (the patches' tolerances decide,
            // AdaptPatchesToTarget) or the count is not monotone here (the look-around decided)
  }
  Evaluation found;
  // The narrower side first, leaving the wider one at least two runs: stepping takes three runs to
  // cross the band at most, so a fourth can bisect (poly2x^2+y^2 at 50%: 975 at alpha1 10.2, 1,045
  // at 4.19, band 1,004-1,044).
  int runs = std::max(0, base.MaximumBandProbes);
  if (this->InBand(above.Count) || this->SearchMergeAngleIntoBand(best, -1, std::max(1, runs - 2), runs, found) ||
    this->SearchMergeAngleIntoBand(above, +1, runs, runs, found))
  {
    best = this->InBand(above.Count) ? above : found;
  }
  vtkLogF(TRACE, "[spbm] search: count jump over the band at %lld kept keys, alpha1 %.3g: %lld triangles", (long long)best.K,
    best.Angle, (long long)best.Count);
}

// alpha1 from `from` (its count on one side of the band: below it for direction -1, narrower
// angles; above it for +1, wider angles) at the same kept vertices: steps by a factor growing
// 1.25, 1.56, 2.44 until the count crosses the band, then bisection in log(alpha1) between the
// last two angles; at most maximumRuns merging runs, each taken from `runs`. alpha1 stays within
// [1, RemovalMergeAngle] (90 when alpha1 is wider already).
bool SpbmLevelGenerator::TargetSearch::SearchMergeAngleIntoBand(
  const Evaluation& from, int direction, int maximumRuns, int& runs, Evaluation& found)
{
  const double widest = std::max(from.Angle, base.RemovalMergeAngle);
  double nearAngle = from.Angle, farAngle = -1.0, factor = 1.25;
  for (int run = 0; run < maximumRuns && runs > 0; ++run, --runs)
  {
    double probe = farAngle < 0 ? nearAngle * std::pow(factor, direction) : std::sqrt(nearAngle * farAngle);
    probe = std::min(widest, std::max(1.0, probe));
    if (std::fabs(probe - nearAngle) < 1e-3 || (farAngle >= 0 && std::fabs(probe - farAngle) < 1e-3))
    {
      return false; // at the end of the range, or the bracket is closed
    }
    const Index c = this->CountFor(from.K, probe);
    if (this->InBand(c))
    {
      found = { from.K, probe, c };
      return true;
    }
    const bool sameSide = direction < 0 ? c < target - countTolerance : c > target + countTolerance;
    if (sameSide)
    {
      nearAngle = probe;
      factor *= factor;
    }
    else
    {
      farAngle = probe;
    }
  }
  return false;
}

// alpha1: the given one, or (when even single-segment chains give too many triangles) the
// smallest wider one, up to 90 degrees, that reaches the target.
double SpbmLevelGenerator::TargetSearch::SearchMergeAngle()
{
  double angle = base.MergeAngle;
  if (this->MildTarget() && this->CountFor(0, angle) <= target)
  {
    return angle; // RemovalMergeAngle's count, lower still, is not needed (see MildTarget)
  }
  // With the cost-ordered removal, BracketMergeAngle probes RemovalMergeAngle first, and when
  // merging up to it leaves more than the target the removal sets the count: the given alpha1's
  // count is then never used (the count falls with alpha1), so it is not evaluated (one merging
  // run less per search; on the scan isosurfaces at 10% one of the search's three).
  const bool removalProbedFirst =
    base.CostOrderedRemoval && base.CollapseChains && base.MergePatches && angle < base.RemovalMergeAngle;
  if (removalProbedFirst && this->GivenAngleReachesTarget(angle))
  {
    return angle; // the probe at RemovalMergeAngle decides nothing then (the count falls with alpha1)
  }
  const bool removalDecides = removalProbedFirst && this->CountFor(0, base.RemovalMergeAngle) > target;
  if (!removalDecides && !(this->CountFor(0, angle) > target && (base.MergePatches || base.CollapseChains)))
  {
    return angle;
  }
  angleLo = angle;
  angleHi = std::max(90.0, angle);
  // Not evaluated when the removal decides: BracketMergeAngle then stops at RemovalMergeAngle
  // and ReachWithRemoval sets the lower count or evaluates it.
  countAngleLo = removalDecides ? 0 : this->CountFor(0, angleLo);
  countAngleHi = 0;
  this->BracketMergeAngle();
  // Even alpha1 = 90 leaves too many triangles (the Fandisk at 150): drop the epsilon bound on
  // collapses (the paper's rule), collapse longer chains (condition (c) up to the patch's
  // longest chain), and last drop the epsilon bound on joins, until the target is reached.
  // The target count wins over the profile curves' epsilon bound here, at a cost in fidelity.
  // When even the removal at 90 degrees stops above the target (rough scan surfaces: handles,
  // non-manifold and parallel chains it must keep), its level is the lowest count: the ladder
  // (the removal off) stops higher (noisy:137 at 10%: 82,458 predicted after six more merging
  // runs, the removal 62,764), so it is not run.
  if (countAngleHi > target && base.CollapseChains && base.CostOrderedRemoval)
  {
    this->ReachWithRemoval(angle);
  }
  else if (countAngleHi > target && base.CollapseChains)
  {
    this->ReachWithRelaxations();
  }
  if (countAngleHi <= target)
  {
    this->NarrowMergeAngle();
  }
  return angleHi;
}

// Issue 10 (session 34, ProbeAnglesSideBySide): whether the given alpha1 reaches the target at the
// coarsest epsilon, known without delaying the search. Remembered (a repeated search, or the side
// by side probes of an earlier one), or, with two threads and GenerateForTarget's idle second
// working state, probed beside RemovalMergeAngle: one merging run in each state, and when the given
// alpha1 reaches the target the wider run (the slower one: on the MRI at 10% 5.9 s against 2.4 s
// at alpha1 20, load 11) is cancelled, else both counts are kept and the serial order's search
// goes on from them. False otherwise (the serial order probes RemovalMergeAngle first). The answer
// does not depend on which run finishes first.
bool SpbmLevelGenerator::TargetSearch::GivenAngleReachesTarget(double angle)
{
  SpbmLevelParameters given = params;
  given.Epsilon = this->EpsilonFor(0);
  given.MergeAngle = angle;
  Index count = 0;
  if (RememberedCount(given, s, count))
  {
    return count <= target;
  }
  SpbmLevelParameters wider = given;
  wider.MergeAngle = base.RemovalMergeAngle;
  State* spare = generator.SpareState;
  if (!base.ProbeAnglesSideBySide || !spare || spare == &s || vtkSMPTools::GetEstimatedNumberOfThreads() < 2 ||
    RememberedCount(wider, s, count))
  {
    return false;
  }
  std::atomic<bool> givenReaches(false);
  Index counts[2] = { -1, -1 };
  s.Cancel = &givenReaches;
  RunTasks(2, [&](int task) {
    counts[task] = generator.PredictTriangleCountIn(task == 0 ? wider : given, task == 0 ? s : *spare);
    if (task == 1 && counts[1] <= target)
    {
      givenReaches.store(true, std::memory_order_relaxed);
    }
  });
  s.Cancel = nullptr;
  ++generator.SideBySideProbes;
  PredictionMemo remembered = PredictionMemo::Of(given);
  remembered.Count = counts[1];
  s.Memo.push_back(remembered); // the search goes on in s
  // Nothing reads the spare state's graph again: a fresh state returns its memory before the
  // level's peak (noisy137 at 10%: 30 MB of 184).
  generator.RenewHelper();
  vtkLogF(TRACE, "[spbm] search: alpha1 %.3g and %.3g side by side: %lld and %lld triangles (target %lld)%s", angle,
    wider.MergeAngle, (long long)counts[1], (long long)counts[0], (long long)target,
    counts[0] < 0 ? ", the wider run cancelled" : "");
  return counts[1] <= target;
}

// Issue 15 (session 27): whether the given alpha1 is likely to reach the target at the coarsest
// epsilon, so that it is evaluated before the probe at RemovalMergeAngle (whose count is lower:
// the count falls with alpha1, and when the given alpha1 reaches the target that probe decides
// nothing). The finest level's count is known without a merging run; the coarsest level was at
// most 0.42 of it on 22 CGAL meshes and mc1m where the removal was not needed (knot1 and helmet
// at 50%, where it was, 0.54 and 0.76: one merging run more there). At 50% of mc1m that skipped
// probe was one of five merging runs of 18 s.
bool SpbmLevelGenerator::TargetSearch::MildTarget() const
{
  SpbmLevelParameters finest = params;
  finest.Epsilon = this->EpsilonFor(nk);
  const Index count = generator.FinestLevelCountWithoutRun(finest);
  return base.MildTargetProbesMergeAngleFirst && count > 0 && 2 * static_cast<long long>(target) >= count;
}

void SpbmLevelGenerator::TargetSearch::BracketMergeAngle()
{
  // Bracket by doubling alpha1 (the count falls steeply at small angles and flattens toward
  // 90 degrees), stopping at RemovalMergeAngle on the way: the widest (and slowest) merging
  // run, at 90, is evaluated only when nothing narrower reaches the target.
  for (double probe = angleLo;;)
  {
    double next = probe <= 0 ? angleHi : std::min(angleHi, 2 * probe);
    if (base.CostOrderedRemoval && base.CollapseChains && probe < base.RemovalMergeAngle)
    {
      // With the removal, whether it is needed depends on RemovalMergeAngle's count only:
      // probe it first (the regula falsi below narrows the bracket when it is not needed).
      next = std::min(angleHi, base.RemovalMergeAngle);
    }
    probe = probe < base.RemovalMergeAngle && next > base.RemovalMergeAngle ? base.RemovalMergeAngle : next;
    const Index c = this->CountFor(0, probe);
    const bool removal = base.CostOrderedRemoval && base.CollapseChains && probe == base.RemovalMergeAngle;
    if (c <= target || probe >= angleHi || removal)
    {
      // (With the cost-ordered removal, alpha1 is not widened beyond RemovalMergeAngle: the
      // removal below reaches the count with less flattening than wider merging.)
      angleHi = probe;
      countAngleHi = c;
      break;
    }
    angleLo = probe;
    countAngleLo = c;
  }
}

void SpbmLevelGenerator::TargetSearch::ReachWithRemoval(double angle)
{
  // Remove endpoints cheapest first down to the target (the epsilon bounds stay on the rest).
  // The removal sets the count: alpha1 only bounds which unions become flat patches, and
  // merging up to RemovalMergeAngle (not 90) keeps creases sharper than that as chains.
  params.RemovalTarget = target;
  const double removalAngle = std::min(angleHi, std::max(angle, base.RemovalMergeAngle));
  const Index c = this->CountFor(0, removalAngle);
  // When final collapses finish the level (FinalCollapsesFollow) and the removal stops far above
  // the target, the widest merging run is not evaluated: a whole merging run (with its removal
  // stage), the search's third on rough scans, which lowered the removal's count by 0.5-12% where
  // measured (noisy:137 at 10%: 70,461 -> 62,331 for 25,148; cheese 1,910 -> 1,816 for 1,778;
  // bull 1,244 -> 1,238 for 1,239) and cannot reach the target from a quarter above it: the
  // collapses take the count there anyway. Closer, it may reach the target (or come within the
  // collapses' tolerance) and is still evaluated (bull: Hausdorff 2.9x without it).
  const Index margin = std::max(SpbmFinalCollapseTolerance(target), target / 4);
  const bool collapsesFollow = base.FinalCollapsesFollow && c > target + margin;
  if (c <= target || collapsesFollow)
  {
    angleLo = angleHi = removalAngle;
    countAngleLo = countAngleHi = c;
  }
  else
  {
    angleHi = std::max(90.0, angle); // the removal alone does not reach it: widest merging too
    countAngleHi = this->CountFor(0, angleHi);
    // The lower end of the bracket matters only to narrow alpha1 when the target is reached.
    countAngleLo = countAngleHi <= target ? this->CountFor(0, angleLo) : countAngleHi;
  }
}

void SpbmLevelGenerator::TargetSearch::ReachWithRelaxations()
{
  params.RemovalTarget = 0;
  struct Relaxation
  {
    bool Join, Collapse;
    double Factor;
  };
  const Relaxation relaxations[] = { { true, false, base.CollapseLengthFactor }, { true, false, 0.35 },
    { true, false, 0.5 }, { true, false, 0.75 }, { true, false, 1.0 }, { false, false, 1.0 } };
  for (const Relaxation& relaxation : relaxations)
  {
    params.JoinWithinEpsilon = base.JoinWithinEpsilon && relaxation.Join;
    params.CollapseWithinEpsilon = base.CollapseWithinEpsilon && relaxation.Collapse;
    params.CollapseLengthFactor = std::max(base.CollapseLengthFactor, relaxation.Factor);
    countAngleHi = this->CountFor(0, angleHi);
    if (countAngleHi <= target)
    {
      countAngleLo = this->CountFor(0, angleLo);
      break;
    }
  }
}

// The count falls steeply at small angles and flattens toward 90 degrees: narrow the bracket by
// doubling alpha1 first, then regula falsi (Illinois) on the count (at most 6 evaluations).
void SpbmLevelGenerator::TargetSearch::NarrowMergeAngle()
{
  while (angleLo > 1.0 && 2 * angleLo < angleHi && countAngleHi < target - countTolerance)
  {
    const Index c = this->CountFor(0, 2 * angleLo);
    if (c > target)
    {
      angleLo = 2 * angleLo;
      countAngleLo = c;
    }
    else
    {
      angleHi = 2 * angleLo;
      countAngleHi = c;
      break;
    }
  }
  int side = 0;
  Index realHi = countAngleHi; // countAngleHi is scaled by the Illinois steps
  for (int iteration = 0; iteration < 6 && angleHi - angleLo > 0.05 && realHi < target - countTolerance; ++iteration)
  {
    // Interpolated in log(alpha1): the count is about linear in it (fewer evaluations).
    const double logLo = std::log(std::max(angleLo, 1e-3)), logHi = std::log(std::max(angleHi, 1e-3));
    double mid = std::exp(
      logHi - (logHi - logLo) * double(target - countAngleHi) / std::max(1.0, double(countAngleLo - countAngleHi)));
    mid = std::min(angleHi - 0.01 * (angleHi - angleLo), std::max(angleLo + 0.01 * (angleHi - angleLo), mid));
    const Index c = this->CountFor(0, mid);
    if (c > target)
    {
      angleLo = mid;
      countAngleLo = c;
      if (side == -1)
      {
        countAngleHi = target + (countAngleHi - target) / 2;
      }
      side = -1;
    }
    else
    {
      angleHi = mid;
      countAngleHi = c;
      realHi = c;
      if (side == 1)
      {
        countAngleLo = target + (countAngleLo - target) / 2;
      }
      side = 1;
      if (c == target)
      {
        break;
      }
    }
  }
}

// epsilon: the number of kept chain vertices (top keys) whose count comes closest to the target
// from below.
Index SpbmLevelGenerator::TargetSearch::SearchKeptVertices(double angle, Index& bestCount)
{
  Index bestK = 0;
  bestCount = this->CountFor(0, angle);
  if (bestCount >= target - countTolerance)
  {
    return bestK;
  }
  Index lo = 0, hi = nk;
  Index countLo = bestCount, countHi = 0;
  if (this->BracketKeptVertices(angle, lo, hi, countLo, countHi))
  {
    this->NarrowKeptVertices(angle, lo, hi, countLo, countHi);
  }
  // The count is not strictly monotone (merges, refinements): look around, unless the count
  // found is within the tolerance below the target.
  const Index found = this->CountFor(lo, angle);
  const Index around = found <= target && found >= target - countTolerance ? 0 : 2;
  for (Index k = std::max<Index>(0, lo - around); k <= std::min<Index>(nk, lo + around); ++k)
  {
    const Index c = this->CountFor(k, angle);
    if (c <= target && (bestCount > target || c > bestCount))
    {
      bestK = k;
      bestCount = c;
    }
  }
  return bestK;
}

// Bracket from below. The full-resolution count closes the bracket without a merging run when
// it is known in closed form (FinestLevelCountWithoutRun); otherwise each kept chain vertex adds
// about two triangles (one on each side), so step by the missing count over the measured slope
// (2 at first), and the full-resolution count is evaluated only when the target is beyond every
// step. (Mild targets used to overshoot with the first step of slope 2: on mc1m at 50% it kept
// 69,063 of 123,560 keys for 699,012 triangles, where 18,601 give the target's 500,310.)
bool SpbmLevelGenerator::TargetSearch::BracketKeptVertices(
  double angle, Index& lo, Index& hi, Index& countLo, Index& countHi)
{
  SpbmLevelParameters finest = params;
  finest.Epsilon = this->EpsilonFor(nk);
  finest.MergeAngle = angle;
  const Index finestCount = base.SecantKeptVertexSearch ? generator.FinestLevelCountWithoutRun(finest) : -1;
  if (finestCount > target && lo < nk)
  {
    hi = nk;
    countHi = finestCount;
    return true;
  }
  bool bracketed = false;
  double slope = 2.0;
  for (int step = 0; step < 8 && !bracketed && lo < nk && countLo < target - countTolerance; ++step)
  {
    const Index next =
      std::min<Index>(nk, lo + std::max<Index>(1, static_cast<Index>(double(target - countLo) / slope)));
    const Index c = this->CountFor(next, angle);
    if (c > target)
    {
      hi = next;
      countHi = c;
      bracketed = true;
    }
    else
    {
      if (c > countLo)
      {
        slope = std::max(0.5, double(c - countLo) / double(next - lo));
      }
      lo = next;
      countLo = c;
    }
  }
  if (!bracketed && lo < nk && countLo < target - countTolerance)
  {
    countHi = finestCount >= 0 ? finestCount : this->CountFor(nk, angle);
    bracketed = countHi > target;
    if (!bracketed)
    {
      lo = nk;
      countLo = countHi;
    }
  }
  return bracketed;
}

// Narrows [lo, hi] (count at lo not above the target, at hi above it) by secant steps through
// the two latest evaluations, aimed at the middle of the accepted band below the target (aiming
// at the target itself lands above it half the time: another merging run). The count is
// steeply concave in the number k of kept vertices (the first, largest keys each block merges
// and collapses besides adding their two triangles) and much closer to linear in sqrt(k)
// (mc1m at 50%: about 1,010 triangles per unit of sqrt(k) from 0 to 33,407 of 123,560 keys;
// bunny00 at 50%: 560-820 from 112 to all 4,302), so the steps interpolate in sqrt(k); the
// secant through the latest points is local, and a step outside the bracket falls back to
// interpolating between its ends. (Regula falsi in k crept down from above: 4-5 merging runs
// where this takes 2-3.) Every step is strictly inside the bracket, which shrinks: at most 40.
void SpbmLevelGenerator::TargetSearch::NarrowKeptVertices(
  double angle, Index& lo, Index& hi, Index& countLo, Index& countHi)
{
  const double aim = double(target) - 0.5 * double(countTolerance);
  if (!base.SecantKeptVertexSearch)
  {
    this->NarrowKeptVerticesInK(angle, lo, hi, countLo, countHi);
    return;
  }
  auto root = [](Index k) { return std::sqrt(double(k)); };
  // The two latest evaluations, older first: the bracket's ends to begin with.
  double u1 = root(lo), u2 = root(hi);
  double c1 = double(countLo), c2 = double(countHi);
  for (int iteration = 0; iteration < 40 && hi - lo > 1 && countLo < target - countTolerance; ++iteration)
  {
    double u = -1;
    if (u1 != u2 && c1 != c2)
    {
      u = u2 + (aim - c2) * (u2 - u1) / (c2 - c1);
    }
    if (!(u > root(lo) && u < root(hi)))
    {
      u = root(lo) + (root(hi) - root(lo)) * (aim - double(countLo)) / std::max(1.0, double(countHi - countLo));
    }
    const Index mid = std::min(hi - 1, std::max(lo + 1, static_cast<Index>(std::lround(u * u))));
    const Index c = this->CountFor(mid, angle);
    if (c > target)
    {
      hi = mid;
      countHi = c;
    }
    else
    {
      lo = mid;
      countLo = c;
    }
    u1 = u2;
    c1 = c2;
    u2 = root(mid);
    c2 = double(c);
  }
}

// Regula falsi (Illinois) over the number of kept vertices (SecantKeptVertexSearch off): the
// count grows about linearly with it, so a few evaluations (at most 40) replace a binary search.
void SpbmLevelGenerator::TargetSearch::NarrowKeptVerticesInK(
  double angle, Index& lo, Index& hi, Index& countLo, Index& countHi)
{
  int side = 0;
  Index realLo = countLo; // countLo is scaled by the Illinois steps
  for (int iteration = 0; iteration < 40 && hi - lo > 1 && realLo < target - countTolerance; ++iteration)
  {
    const double spread = std::max(1.0, double(countHi - countLo));
    Index mid = lo + static_cast<Index>(double(hi - lo) * double(target - countLo) / spread);
    mid = std::min(hi - 1, std::max(lo + 1, mid));
    const Index c = this->CountFor(mid, angle);
    if (c > target)
    {
      hi = mid;
      countHi = c;
      if (side == 1)
      {
        countLo = target - (target - countLo) / 2;
      }
      side = 1;
    }
    else
    {
      lo = mid;
      countLo = c;
      realLo = c;
      if (side == -1)
      {
        countHi = target + (countHi - target) / 2;
      }
      side = -1;
      if (c == target)
      {
        break;
      }
    }
  }
}
} // namespace slod
