// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD patch boundary merge (internal, not installed): the target search of an SPBM level.
// Finds parameters whose level has about `target` triangles from predicted counts (one merging
// run each, memoized): first alpha1 (the given one, or the smallest wider one that reaches the
// target, else the cost-ordered removal or the relaxed collapse conditions), then epsilon as the
// number of kept chain vertices whose count comes closest to the target from below; when one
// kept vertex jumps over the accepted band, alpha1 again at those two epsilons.
#ifndef slodSpbmTargetSearch_h
#define slodSpbmTargetSearch_h

#include "slodSpbmState.h"

namespace slod
{
class SpbmLevelGenerator::TargetSearch
{
public:
  TargetSearch(SpbmLevelGenerator& generator, Index target, const SpbmLevelParameters& base, State& s);
  SpbmLevelParameters Run(Index* predicted);

private:
  double EpsilonFor(Index k) const;
  Index CountFor(Index k, double angle);
  // alpha1.
  double SearchMergeAngle();
  bool MildTarget() const;
  bool GivenAngleReachesTarget(double angle);
  void BracketMergeAngle();
  void ReachWithRemoval(double angle);
  void ReachWithRelaxations();
  void NarrowMergeAngle();
  // epsilon: k = the number of kept chain vertices (top keys).
  Index SearchKeptVertices(double angle, Index& bestCount);
  bool BracketKeptVertices(double angle, Index& lo, Index& hi, Index& countLo, Index& countHi);
  void NarrowKeptVertices(double angle, Index& lo, Index& hi, Index& countLo, Index& countHi);
  void NarrowKeptVerticesInK(double angle, Index& lo, Index& hi, Index& countLo, Index& countHi);
  // The accepted band (ReachBandAcrossKeyJumps): kept vertices and alpha1 of one evaluation.
  struct Evaluation
  {
    Index K = 0;
    double Angle = 0;
    Index Count = 0;
  };
  bool InBand(Index count) const;
  void ReachBandAcrossKeyJump(Evaluation& best);
  bool SearchMergeAngleIntoBand(const Evaluation& from, int direction, int maximumRuns, int& runs, Evaluation& found);

  SpbmLevelGenerator& generator;
  State& s;
  const SpbmLevelParameters& base;
  const Index target;
  SpbmLevelParameters params;
  const Index nk; // finite keys
  // Counts this close below the target are good enough: each evaluation is a whole merging run.
  const Index countTolerance;
  // alpha1 bracket: count at angleLo above the target, at angleHi (when reached) not above.
  double angleLo = 0, angleHi = 0;
  Index countAngleLo = 0, countAngleHi = 0;
};
} // namespace slod

#endif
