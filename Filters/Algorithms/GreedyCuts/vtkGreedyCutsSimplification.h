// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkGreedyCutsSimplification
 * @brief   bounded-error simplification by greedy cuts (Ho 1999, chapter 3): the output is
 *          guaranteed epsilon-close to the input (two-sided Hausdorff) and uses original
 *          vertices only
 *
 * The surface is partitioned into terrain-like patches (disks whose normals stay within a cone,
 * the shared slod::Patchification); the chains between patches are simplified to a fraction of
 * epsilon; each patch is then triangulated inward from its simplified boundary by greedy cuts:
 * the feasible ear of largest area is cut, else a feasible greedy bite (a triangle from a boundary
 * edge to an original vertex inside the patch, the best-shaped candidates first) is taken, else
 * every inner vertex is tried (edge splitting without Steiner points). A triangle is feasible when
 * it lies within epsilon of the original surface (rigorous adaptive test against a BVH) and the
 * original triangles under it lie within epsilon of it and face the same way. A stuck front is
 * repaired (section 3.4.3: edge swap, face split, vertex deletion at its sharpest corners); a
 * patch that stays stuck is retried with full-resolution chains, then split in two and the run
 * repeated (bounded), and only then kept as its original triangles (field data
 * "FallbackPatches"), so the filter always terminates. A final verification proves that every original triangle lies within
 * epsilon of the output. See slodGreedyCuts.h for the details.
 *
 * Guarantees: output vertices are a subset of the (prepared) input's; a closed manifold input
 * gives a closed manifold output of the same genus; the two-sided Hausdorff distance between input
 * and output is at most the used epsilon, stored in the output's field data
 * ("MaximumErrorBound", absolute, and "MaximumErrorBoundRelative", divided by the input's bounding
 * box diagonal) and returned by GetUsedMaximumError().
 *
 * Parameters: MaximumError (epsilon; absolute, or relative to the input's bounding box diagonal
 * when MaximumErrorIsRelative is on, the default), the patch angle tolerances of
 * vtkPatchBoundaryMerge, and the project's target convention: SetTargetNumberOfTriangles (0 =
 * unused) or SetTargetReduction (fraction removed) searches the tolerance ladder's levels (see
 * MonotoneInEpsilon) from LadderBottom to MaximumError (each step the level where the count is
 * predicted to reach the target, a bisection step after a poor prediction), one run with its collapses per level tried
 * (at most TargetSearchSteps after the top one), for the smallest level within the target; the
 * next finer level tried (the input itself when none) is then collapsed at that level's tolerance
 * down to the target: the target count or one below (a top level over the target sends the
 * search to finer levels, since the count can rise with the tolerance, unless it removed under 1%
 * of the input; more only when no level tried is within it; fewer when the collapses get stuck).
 * Work bound: 2,000 distance-proof pieces per input triangle for the runs and again for the final
 * collapses (a warning when reached).
 * Without FinalCollapses: the earlier search on the cuts' counts (TargetSearchSteps runs of
 * halving, then bisection on log(epsilon)). MaximumError still bounds the error (the bound wins
 * over the target, with a warning); raise it (e.g. 0.1 relative) to let the target decide.
 * MaximumError 0 with a target searches up to 0.1 of the diagonal.
 *
 * Output: the simplified mesh with cell data "PatchId" and the input's point data; invalid input
 * (empty, NaN/Inf coordinates) gives an error and an empty output. Non-manifold input is simplified
 * with the triangles at its non-manifold vertices kept (each non-manifold edge stays one edge with
 * its triangles; Euler characteristic and border loops kept).
 */
#ifndef vtkGreedyCutsSimplification_h
#define vtkGreedyCutsSimplification_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPatchSimplificationAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkGreedyCutsSimplification : public vtkPatchSimplificationAlgorithm
{
public:
  static vtkGreedyCutsSimplification* New();
  vtkTypeMacro(vtkGreedyCutsSimplification, vtkPatchSimplificationAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** Target triangle count (0 = unused) or reduction (fraction removed): epsilon is searched. */
  vtkSetClampMacro(TargetSearchSteps, int, 1, 40);
  vtkGetMacro(TargetSearchSteps, int);
  ///@}

  /**
   * The patchification: CHAPTER4_PATCHES (default), chapter 4's small near-planar patches grown
   * with the angle tolerances below (slod::Patchification); CHAPTER3_TERRAIN_PATCHES, the
   * chapter's own (section 3.4.1): large terrain-like patches of 26 normal classes, each a height
   * field over its height direction, small ones merged (slod::BuildTerrainPatches, with
   * MinimumPatchTriangles).
   */
  enum PatchificationModes
  {
    CHAPTER4_PATCHES = 0,
    CHAPTER3_TERRAIN_PATCHES = 1
  };
  vtkSetClampMacro(Patchification, int, CHAPTER4_PATCHES, CHAPTER3_TERRAIN_PATCHES);
  vtkGetMacro(Patchification, int);
  vtkSetClampMacro(MinimumPatchTriangles, int, 1, VTK_INT_MAX);
  vtkGetMacro(MinimumPatchTriangles, int);

  ///@{
  /** Greedy biting: inner vertices tried per edge; smallest angle of a created triangle (degrees). */
  vtkSetClampMacro(BiteCandidates, int, 1, 1000);
  vtkGetMacro(BiteCandidates, int);
  vtkSetClampMacro(MinimumTriangleAngle, double, 0.0, 30.0);
  vtkGetMacro(MinimumTriangleAngle, double);
  /**
   * Smallest angle (degrees) asked of a patch's triangles on its first attempt; a patch whose
   * front gets stuck there is retried at MinimumTriangleAngle (section 3.4.3's gradual release of
   * the shape bound). 0 = off.
   */
  vtkSetClampMacro(ShapedTriangleAngle, double, 0.0, 30.0);
  vtkGetMacro(ShapedTriangleAngle, double);
  /**
   * Ears thinner than this (degrees) rank below their area in the choice of the next ear (weight
   * (angle / EarShapeAngle)^2), so flat parts are not cut into fans of caps; the bound and the
   * feasibility test are unchanged (default 15; 0 = the chapter's pure largest-area rule).
   */
  vtkSetClampMacro(EarShapeAngle, double, 0.0, 60.0);
  vtkGetMacro(EarShapeAngle, double);
  ///@}
  ///@{
  /**
   * A final pass of half-edge collapses onto output vertices, each accepted only when the error
   * bound is proved again for the triangles it changes (both ways): fewer triangles, same bound
   * (default on). With ShapedTriangleAngle set, no collapse makes a triangle thinner than that.
   */
  vtkSetMacro(FinalCollapses, bool);
  vtkGetMacro(FinalCollapses, bool);
  vtkBooleanMacro(FinalCollapses, bool);
  /**
   * The final collapses also remove border vertices, each onto a neighbour along its border loop
   * (the loops and their number are kept; no loop gets under four vertices), proved like the
   * others, and guarded: none leaves a border vertex with more than 12 triangles or makes a
   * triangle under 5 degrees (unless its star had one as thin), and none is tried next to a fan
   * of more than 128 triangles (default on). Off: every border vertex the cuts kept stays.
   */
  // Staged final collapses (session 26, 0 = off): collapse-only stages first accept only the
  // collapses whose new triangles lie within MaximumError / 2^k of the input, k = CollapseStages..1.
  vtkSetClampMacro(CollapseStages, int, 0, 4);
  vtkGetMacro(CollapseStages, int);
  vtkSetMacro(BorderCollapses, bool);
  vtkGetMacro(BorderCollapses, bool);
  vtkBooleanMacro(BorderCollapses, bool);
  // Session 31: the final collapses start with a sliver step on the cuts' output (the slivers'
  // edges flipped, or a vertex collapsed where the smallest angle around rises, each proved), while
  // the collapses have not yet used the bound up around them.
  vtkSetMacro(EarlySliverStep, bool);
  vtkGetMacro(EarlySliverStep, bool);
  vtkBooleanMacro(EarlySliverStep, bool);
  // Session 36: the final collapses' passes take their vertices by bands of the shortest incident
  // edge (this many per doubling of its length), in spatial (Morton) order within a band: on large
  // inputs consecutive tries then read nearby memory (e.g. 2). 0 (default): the exact
  // shortest-edge-first order (the banded one changes the outputs: fewer triangles on most CGAL
  // meshes, more on some).
  vtkSetClampMacro(PassOrderBands, int, 0, 64);
  vtkGetMacro(PassOrderBands, int);
  // Session 42: a split round (a patch fell back, is split in two and cut again) goes on from the
  // run before it and cuts again only the pieces and the patches sharing a chain with them, with a
  // local verification (default on). Off: each split round is a whole new run over the input.
  vtkSetMacro(LocalSplitRounds, bool);
  vtkGetMacro(LocalSplitRounds, bool);
  vtkBooleanMacro(LocalSplitRounds, bool);
  ///@}
  ///@{
  /**
   * Monotone in the error bound (default off: it costs 3-14x the CPU of one run): a run at MaximumError is the last level of a nested
   * run over a fixed ladder of tolerances (relative to the bounding box diagonal, 10 round values
   * per decade: 1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 times a power of ten) from LadderBottom
   * (relative, default 0.004) up to the largest ladder value at most MaximumError, which is the
   * bound used (GetUsedMaximumError). Each level starts from the finer one when that has fewer
   * triangles and the collapses only remove, so for one mesh the count never rises when
   * MaximumError rises (from LadderBottom up). Off: one run at MaximumError itself.
   */
  vtkSetMacro(MonotoneInEpsilon, bool);
  vtkGetMacro(MonotoneInEpsilon, bool);
  vtkBooleanMacro(MonotoneInEpsilon, bool);
  vtkSetClampMacro(LadderBottom, double, 1e-6, 1.0);
  vtkGetMacro(LadderBottom, double);
  // The nested run's levels above the bottom also run their own cuts (default on: the first level
  // and 1, 2, 5 times 10^k). Off (session 30): each level is the finer level's output collapsed at
  // its own tolerance, one collapse phase per level on an already coarse mesh (cheaper).
  vtkSetMacro(LadderOwnRuns, bool);
  vtkGetMacro(LadderOwnRuns, bool);
  vtkBooleanMacro(LadderOwnRuns, bool);
  // With LadderOwnRuns off (session 36, default off): every level of the chain, the bottom's too,
  // runs only the collapse passes, and the level returned is then finished by proved flips (the
  // count stays): still monotone, one collapse step per level instead of four.
  vtkSetMacro(LadderCollapsesOnly, bool);
  vtkGetMacro(LadderCollapsesOnly, bool);
  vtkBooleanMacro(LadderCollapsesOnly, bool);
  ///@}

  ///@{
  /** Results of the last update. */
  vtkGetMacro(UsedMaximumError, double); // absolute: the guaranteed Hausdorff bound
  vtkGetMacro(NumberOfPatches, int);
  vtkGetMacro(RefinedPatches, int);
  vtkGetMacro(OriginalPatches, int);
  vtkGetMacro(NumberOfEars, vtkIdType);
  vtkGetMacro(NumberOfBites, vtkIdType);
  vtkGetMacro(NumberOfRepairs, vtkIdType);
  vtkGetMacro(NumberOfFinalCollapses, vtkIdType);
  ///@}

protected:
  vtkGreedyCutsSimplification();
  ~vtkGreedyCutsSimplification() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // Epsilon always bounds the cuts: without a count target the result is epsilon's, not 0.9.
  bool HasErrorBound() const override { return true; }

  int TargetSearchSteps = 10;
  int Patchification = CHAPTER4_PATCHES;
  int MinimumPatchTriangles = 32;
  int BiteCandidates = 8;
  double MinimumTriangleAngle = 0.5;
  double ShapedTriangleAngle = 0.0;
  double EarShapeAngle = 15.0;
  bool FinalCollapses = true;
  bool BorderCollapses = true;
  bool EarlySliverStep = false;
  int PassOrderBands = 0;
  bool LocalSplitRounds = true;
  int CollapseStages = 0;
  bool MonotoneInEpsilon = false;
  double LadderBottom = 0.004;
  bool LadderOwnRuns = true;
  bool LadderCollapsesOnly = false;

  double UsedMaximumError = 0;
  int NumberOfPatches = 0;
  int RefinedPatches = 0;
  int OriginalPatches = 0;
  vtkIdType NumberOfEars = 0;
  vtkIdType NumberOfBites = 0;
  vtkIdType NumberOfRepairs = 0;
  vtkIdType NumberOfFinalCollapses = 0;

private:
  vtkGreedyCutsSimplification(const vtkGreedyCutsSimplification&) = delete;
  void operator=(const vtkGreedyCutsSimplification&) = delete;
};

#endif
