// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPatchBoundaryMerge
 * @brief   Simplified Patch Boundary Merging (SPBM, Ho 1999, chapter 4): fast level-of-detail
 *          generation from a patchification of the surface
 *
 * The input surface is partitioned once into patches (simply connected sets of triangles whose
 * normals stay within a cone: slod::Patchification). A level of detail is then generated from the
 * patch boundaries only: the boundary chains are simplified to a tolerance epsilon (divide and
 * conquer, the whole hierarchy is stored), nearly coplanar neighbouring patches merge (alpha1),
 * short chains collapse, and every patch is re-triangulated from its simplified boundary by
 * prioritised ear clipping in the plane orthogonal to its normal. Output vertices are original
 * input vertices (no Steiner points); a closed manifold input gives a closed manifold output of
 * the same genus (patches that cannot be triangulated validly from their simplified boundary fall
 * back to their full-resolution boundary, then to their original triangles).
 *
 * The patchification is cached (keyed on the input's modification time and the patch
 * parameters): changing MaximumError, MergeAngle or the target re-generates a level in a small fraction
 * of the first run's time.
 *
 * Outputs:
 *  - port 0: the simplified mesh, cell data "PatchId" (merged patch), input point data carried;
 *  - port 1: the profile curves (simplified patch boundaries) as polylines over the same points;
 *  - port 2: when GeneratePatchColoredInput is on, the (prepared) input with cell data "PatchId"
 *    of the patchification (empty otherwise).
 *
 * Target: SetTargetNumberOfTriangles (0 = unused) or SetTargetReduction (fraction removed) search
 * epsilon over the stored chain hierarchy (and widen alpha1 when needed) without repeating the
 * patchification; otherwise MaximumError (epsilon) and MergeAngle are used as given. A target
 * of at least the input's triangle count returns the (prepared) input unchanged. MaximumError is
 * the chain tolerance epsilon, the paper's parameter (0 = unused, the default; the paper's
 * configuration: 0.005 relative); with a target too, the filter stops at whichever is reached
 * first. Targets, MaximumError, OutputPointsPrecision and the patch angles are declared by the
 * base classes (vtkPatchSimplificationAlgorithm).
 */
#ifndef vtkPatchBoundaryMerge_h
#define vtkPatchBoundaryMerge_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPatchSimplificationAlgorithm.h"

#include <memory>

class SURFACELODFILTERS_EXPORT vtkPatchBoundaryMerge : public vtkPatchSimplificationAlgorithm
{
public:
  static vtkPatchBoundaryMerge* New();
  vtkTypeMacro(vtkPatchBoundaryMerge, vtkPatchSimplificationAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Extension of feasibility (b) (not in the paper): a triangle joins a patch only when its new
  /// vertex lies within this distance of the patch's running plane, relative to the bounding-box
  /// diagonal (default 0.004; 0 = off, the paper's normal-only test). Patches are re-triangulated
  /// from their boundary alone, so this bounds the error of flat patches on curved parts.
  vtkSetClampMacro(PatchPlaneDistance, double, 0.0, 1.0);
  vtkGetMacro(PatchPlaneDistance, double);
  ///@}

  ///@{
  /// SPBM keeps no vertex inside a patch, so its finest level (every chain vertex kept) has far
  /// fewer triangles than the input, and a mild target (50%, or 10% of a smooth surface) may need
  /// more. With AdaptPatchesToTarget (default on) the patches are then grown again with
  /// PatchAngle, NeighborAngle and PatchPlaneDistance scaled down (at most four times) until the
  /// finest level reaches the target; PatchToleranceScale is the scale used (1: the settings).
  vtkSetMacro(AdaptPatchesToTarget, bool);
  vtkGetMacro(AdaptPatchesToTarget, bool);
  vtkBooleanMacro(AdaptPatchesToTarget, bool);
  vtkGetMacro(PatchToleranceScale, double);
  ///@}

  ///@{
  /// Extension (issue 15) [4]: with a count target, no patch (grown or merged) may be thicker than
  /// this factor times the deviation expected at the target, kappa * s^2 / 8 (kappa the input's
  /// mean absolute curvature without its creases, edges bent by more than 60 degrees: they stay
  /// patch boundaries; s the edge of an equilateral triangle of the input's area divided
  /// by the target): SPBM re-triangulates each patch flat from its boundary, so a patch much
  /// larger than the target's triangles lies far off the surface (mc1m at 10%: 43x
  /// vtkQuadricDecimation's Hausdorff distance). 0 = unbounded (patch size from the angles and
  /// PatchPlaneDistance only). PatchThicknessBound is the bound used (relative to the diagonal).
  vtkSetClampMacro(PatchDeviationFactor, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(PatchDeviationFactor, double);
  vtkGetMacro(PatchThicknessBound, double);
  ///@}

  ///@{
  /// Extension (issue 15, session 29) [on]: when the level of a count target deviates from the
  /// input by several times PatchThicknessBound while its chain tolerance (UsedEpsilon) is well
  /// above that bound too, the patches were too small for the target: their corners took the
  /// budget and the search had to drop chain vertices instead (poly2x^2+y^2 at 50%: epsilon 33x
  /// the bound). The patches are then grown again with the bound doubled (at most twice) and the
  /// level with the smaller sampled deviation (two-sided, as CompareCandidates) is kept.
  /// PatchThicknessScale is the scale of the bound used (1: PatchDeviationFactor as given).
  /// Session 30: when the automatic PatchNoiseTolerance (-1) grew the patches (a coarse target),
  /// the first such try is the same bound without it; NoiseToleranceWithheld is true when that
  /// level was kept (the cached patches keep the decision).
  vtkSetMacro(LoosenThicknessForTarget, bool);
  vtkGetMacro(LoosenThicknessForTarget, bool);
  vtkBooleanMacro(LoosenThicknessForTarget, bool);
  vtkGetMacro(PatchThicknessScale, double);
  vtkGetMacro(NoiseToleranceWithheld, bool);
  ///@}

  ///@{
  /// Extension (issue 15, session 33) [on; needs FinalCollapses]: when the level of a count target
  /// deviates from the input by more than its patches were allowed to lie from their planes (the
  /// plane-distance cap, 1/2 of the thickness bound as given, plus the noise tolerance: 1/2 of the
  /// bound without one, 2x the deviation expected of any simplification to that count with
  /// PatchDeviationFactor 4; the whole bound with the automatic one of coarse targets; session 36,
  /// was 1/2 or, on patches a noise tolerance grew over a quarter of the input, 1.5x; measured
  /// without the farthest 1/10,000 of the input's vertices since session 38, so that a noisy
  /// scan's extreme samples do not decide it at one sampling density and not at another), a level of
  /// 1.5x the target is made from patches grown for that count and brought down to the target by
  /// the final collapses (quadric order); the level with the smaller deviation (every input vertex
  /// sampled) is kept. FinalCollapseCount then counts its collapses; FinerLevelTried says whether
  /// the finer level was made and LevelDeviationShare what the level deviated (over the thickness
  /// bound as given, -1 when not measured; LevelTailDeviationShare the same without those vertices).
  vtkSetMacro(CollapseFinerLevelForTarget, bool);
  vtkGetMacro(CollapseFinerLevelForTarget, bool);
  vtkBooleanMacro(CollapseFinerLevelForTarget, bool);
  ///@}

  ///@{
  /// Extension (issue 15, session 37) [off; needs FinalCollapses]: when the finer level of
  /// CollapseFinerLevelForTarget was not made, the patches whose own vertices deviate from the
  /// count target's level by more than half the thickness bound as given (the worst first, their
  /// triangles at most 3% of the input's) are kept as their original triangles in one more
  /// generation pass, and the final collapses bring the level back to the target; the level with
  /// the smaller deviation (every input vertex) is kept. RegionRefinedPatches counts the patches so
  /// refined in the kept level (0 otherwise; also the output's field-data array
  /// "RegionRefinedPatches" when above 0, with the pass's work: "RegionInputTriangles", the refined
  /// patches' input triangles, and "RegionRetriangulatedTriangles", the level triangles it made
  /// again; also GetRegionInputTriangles / GetRegionRetriangulatedTriangles, -1 when it did not
  /// run). Session 38: the pass goes on from the level's own last pass (the patches untouched by the
  /// refined ones keep their triangles) and the refined level is measured only near the triangles
  /// that changed: same levels, about half the added cost. Still off by default: at 10%, +17-28%
  /// CPU on the segmentation mask, +42-59% on the open scan, +16-24% on mc1m (PatchBoundaryMerge.md).
  vtkSetMacro(RefineDeviatingRegions, bool);
  vtkGetMacro(RefineDeviatingRegions, bool);
  vtkBooleanMacro(RefineDeviatingRegions, bool);
  ///@}

  ///@{
  /// Extension (issue 15, session 45) [0.125; 0 = off]: at mild count targets (at least a fifth of
  /// the input kept, where no noise tolerance grows the patches), the region refinement of
  /// RefineDeviatingRegions runs whatever that option says, with this share of the thickness bound
  /// as given as its allowance (instead of half of it), also after the finer level of
  /// CollapseFinerLevelForTarget. At those targets the bound (PatchDeviationFactor times the mean
  /// curvature's sag) is far above what vtkQuadricDecimation deviates on CAD meshes, whose flat
  /// faces absorb the removals: the curved patches flattened up to the bound set SPBM's error
  /// (ALSTOM_TEST4, handle, turbine at 50%: 3x). Coarse targets (the scans' 10%) are unchanged.
  vtkSetClampMacro(MildTargetRegionAllowance, double, 0.0, 1.0);
  vtkGetMacro(MildTargetRegionAllowance, double);
  ///@}

  ///@{
  /// Extension (issue 10, sessions 24 and 28) [-1: automatic]: a triangle whose three vertices lie
  /// within this fraction of the patch growth's plane distance (PatchPlaneDistance, capped by
  /// PatchDeviationFactor, scaled with AdaptPatchesToTarget) from the patch's running plane joins
  /// without the PatchAngle / NeighborAngle tests (its normal within 60 degrees of the patch's).
  /// On a scan isosurface (voxel staircase, noise) a quarter of the neighbouring triangles differ
  /// by more than 25 degrees while the surface stays flat, so the cones alone made patches of about
  /// three triangles, and each level paid for merging them again. -1 (the default) follows the
  /// target: 1 when a count target keeps less than a fifth of the input (the MRI at 10%: 488k ->
  /// 40k patches, 2.3x less CPU, Hausdorff 0.69x, RMS 1.10x; 26 CGAL meshes: Hausdorff x0.97, RMS
  /// x1.01), 0 at milder targets (worse there: the MRI at 50%, Hausdorff 1.3x) and with an error
  /// bound alone. Decided when the patches are grown (a cached patchification keeps it). 0 = off
  /// (the former default).
  vtkSetClampMacro(PatchNoiseTolerance, double, -1.0, 1.0);
  vtkGetMacro(PatchNoiseTolerance, double);
  ///@}

  ///@{
  /// Extension (issue 15, session 31) [60]: a vertex of the mesh border where the border turns by at
  /// least this angle (degrees) is a corner: the chains end there and it is never removed. The
  /// paper's chains end only where the patch across changes, so a coarse target's chain tolerance
  /// cut the corners of an open sheet (three_peaks at 10%: Hausdorff 8.4x vtkQuadricDecimation's,
  /// all of it at one corner). 0 = off (the paper).
  vtkSetClampMacro(BorderCornerAngle, double, 0.0, 180.0);
  vtkGetMacro(BorderCornerAngle, double);
  ///@}

  ///@{
  /// Area-weighted running patch normal (default on).
  vtkSetMacro(AreaWeightedNormals, bool);
  vtkGetMacro(AreaWeightedNormals, bool);
  vtkBooleanMacro(AreaWeightedNormals, bool);
  ///@}

  ///@{
  /// alpha1, degrees: patches merge and chains collapse when the patch normals agree within it
  /// (default 20). With a target it is the starting value (widened when needed).
  vtkSetClampMacro(MergeAngle, double, 0.0, 180.0);
  vtkGetMacro(MergeAngle, double);
  ///@}

  ///@{
  /// Stages of patch merging (default on) and the chain-collapse length factor (default 0.2).
  vtkSetMacro(MergePatches, bool);
  vtkGetMacro(MergePatches, bool);
  vtkBooleanMacro(MergePatches, bool);
  vtkSetMacro(CollapseChains, bool);
  vtkGetMacro(CollapseChains, bool);
  vtkBooleanMacro(CollapseChains, bool);
  vtkSetClampMacro(CollapseLengthFactor, double, 0.0, 1.0);
  vtkGetMacro(CollapseLengthFactor, double);
  ///@}

  ///@{
  /// Merge measure [on]: a pair merges when sin(angle) * sqrt(smaller patch area / mean patch
  /// area) <= sin(alpha1), smallest first (flattening the smaller patch moves it by about its
  /// extent times sin(angle)); off = the paper's angle <= alpha1, most parallel first. The
  /// size-weighted measure was as close or closer to the input on every Fandisk and bunny00
  /// Table 1 level except bunny00 at 525, where the cost-ordered removal compares the measures.
  vtkSetMacro(SizeWeightedMerge, bool);
  vtkGetMacro(SizeWeightedMerge, bool);
  vtkBooleanMacro(SizeWeightedMerge, bool);
  ///@}

  ///@{
  /// With a target size: also search the level with the other merge measure (on a second
  /// thread) and with half alpha1 (when alpha1 need not be widened), and keep the one with the
  /// smallest sampled distance from the input [off]. Costs a second search (about twice the
  /// level's CPU time); on the Table 1 levels of the Fandisk and bunny00 it chose the same
  /// levels as the default.
  vtkSetMacro(CompareCandidates, bool);
  vtkGetMacro(CompareCandidates, bool);
  vtkBooleanMacro(CompareCandidates, bool);
  ///@}

  ///@{
  /// Extension [on]: when even alpha1 = 90 degrees leaves more triangles than the target, remove
  /// patch corners (endpoints) cheapest first until the target is reached: chain collapses and
  /// joins ordered by how far they move the surface (displacement along the adjacent patch
  /// normals). With CompareCandidates, the merge measures (angle, size-weighted, flatness) and
  /// several alpha1 values are then compared at the target. Off = the fixed relaxation ladder
  /// (wider collapse length factor, then no epsilon bounds), as before.
  vtkSetMacro(CostOrderedRemoval, bool);
  vtkGetMacro(CostOrderedRemoval, bool);
  vtkBooleanMacro(CostOrderedRemoval, bool);
  ///@}

  ///@{
  /// Extension (1 = the paper's Euclidean chain tolerance): a chain vertex's offset from its
  /// simplified segment counts by its components along the two adjacent patch normals, but at
  /// least this fraction of its length [0.42]. An offset within both patch planes barely moves the
  /// surface, so the vertex budget goes to creases (Fandisk at 460 triangles: Hausdorff 7.4e-3 ->
  /// 4.4e-3, with MinimumDeviationTriangulation). MaximumError is then a bound in this measure. Changing it rebuilds only the chain
  /// hierarchy, not the patchification.
  vtkSetClampMacro(ChainInPlaneWeight, double, 0.0, 1.0);
  vtkGetMacro(ChainInPlaneWeight, double);
  ///@}

  ///@{
  /**
   * Extension (not in the paper): patches whose boundary is not planar (up to 48 boundary
   * vertices) are triangulated with the valid diagonals closest to the original surface (an
   * exact minimum over all triangulations, by dynamic programming) instead of smallest-angle ear
   * clipping. Same triangle counts; on by default. Off = the paper's ear clipping everywhere.
   * Session 34: a triangle turned by more than 75 degrees from its patch's normal (three vertices
   * of a curved crease chain, lying on the face beyond the crease) counts its height along that
   * normal as a cost, which the diagonals' distances from the input do not see.
   */
  vtkSetMacro(MinimumDeviationTriangulation, bool);
  vtkGetMacro(MinimumDeviationTriangulation, bool);
  vtkBooleanMacro(MinimumDeviationTriangulation, bool);
  ///@}

  ///@{
  /**
   * Extension (issue 15, not in the paper): when a count target is beyond what the patches reach
   * (rough scans: the removal turns most patches into triangles, which cannot lose a corner), the
   * level is finished by half-edge collapses onto its own vertices (output vertices stay input
   * vertices), cheapest first by the quadric of the level's and the input's planes, each keeping
   * the topology (link condition; non-manifold and pinch vertices locked, border vertices only
   * along their border) and turning no triangle by more than 60 degrees, then 90. Triangles keep
   * their PatchId, the profile curves follow the collapses. Default on; off = SPBM's level alone
   * (the target may then stay unreached). FinalCollapseCount is the number performed.
   */
  vtkSetMacro(FinalCollapses, bool);
  vtkGetMacro(FinalCollapses, bool);
  vtkBooleanMacro(FinalCollapses, bool);
  ///@}

  ///@{
  /**
   * Extension (issue 10, session 42) [1e-4; needs FinalCollapses]: the level's fallback passes go
   * on while a patch that failed to triangulate can still change. A pass whose such failures are
   * at most this share of the input patches is a late pass: its failed patches go straight to
   * their original triangles (merged ones too, not unmerged first), so that the tail of a few
   * failures does not cost more whole-level passes on a larger input (noisy scans: 8 passes at 4M
   * triangles against 6 at 1M before). 0 = one fallback level per pass, as before.
   */
  vtkSetClampMacro(LateFailureShare, double, 0.0, 1.0);
  vtkGetMacro(LateFailureShare, double);
  ///@}

  ///@{
  /// Fill output port 2 with the input coloured by patch (default off).
  vtkSetMacro(GeneratePatchColoredInput, bool);
  vtkGetMacro(GeneratePatchColoredInput, bool);
  vtkBooleanMacro(GeneratePatchColoredInput, bool);
  ///@}

  /// Drops the cached patchification (the next update recomputes it).
  void ReleaseCache();

  ///@{
  /// Results of the last update.
  vtkGetMacro(NumberOfPatches, vtkIdType);        // patchification
  vtkGetMacro(NumberOfChains, vtkIdType);         // patchification
  vtkGetMacro(NumberOfMergedPatches, vtkIdType);  // in the output level
  vtkGetMacro(UsedEpsilon, double);               // absolute
  vtkGetMacro(UsedMergeAngle, double);
  // Fallbacks (in patches of the patchification) for boundaries that could not be triangulated
  // validly: kept unmerged, refined (finer epsilon up to full resolution), original triangles.
  vtkGetMacro(UnmergedPatches, vtkIdType);
  vtkGetMacro(RefinedPatches, vtkIdType);
  vtkGetMacro(OriginalPatches, vtkIdType);
  // The output level's generation passes (1 without fallback) and the input patches its late
  // passes sent from merged to original triangles (LateFailureShare).
  vtkGetMacro(GenerationPasses, int);
  vtkGetMacro(LateOriginalPatches, vtkIdType);
  // Work of the output level's late replays (issue 10, session 43): the replays after the first
  // that refined the non-simple patches again (some patch at a finer fallback level), the root
  // patches that had changed when each began (summed), and the patch boundaries they tested for
  // simplicity (summed).
  vtkGetMacro(LateReplays, int);
  vtkGetMacro(LateReplayChangedPatches, vtkIdType);
  vtkGetMacro(LateReplayBoundaryTests, vtkIdType);
  vtkGetMacro(FinalCollapseCount, vtkIdType);     // FinalCollapses performed
  vtkGetMacro(FinerLevelTried, bool);             // CollapseFinerLevelForTarget made its level
  vtkGetMacro(LevelDeviationShare, double);       // of the target's level, over the bound as given
  // The same without the farthest 1/10,000 of the input's vertices (what the finer level's trigger
  // compares; -1 when only the strided samples were measured).
  vtkGetMacro(LevelTailDeviationShare, double);
  vtkGetMacro(RegionRefinedPatches, vtkIdType);   // RefineDeviatingRegions' patches in the kept level
  // The work of RefineDeviatingRegions' pass (-1 when it did not run): the input triangles of the
  // patches it made original, and the level triangles it triangulated again (the rest are kept).
  vtkGetMacro(RegionInputTriangles, vtkIdType);
  vtkGetMacro(RegionRetriangulatedTriangles, vtkIdType);
  vtkGetMacro(PatchificationReused, bool);        // the cache was hit
  vtkGetMacro(PatchificationTime, double);        // seconds (input preparation + patches + hierarchy)
  vtkGetMacro(LevelTime, double);                 // seconds (search + level generation + output)
  vtkGetMacro(CacheMemory, vtkIdType);            // bytes held between updates
  ///@}

protected:
  vtkPatchBoundaryMerge();
  ~vtkPatchBoundaryMerge() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  bool AreaWeightedNormals = true;
  double PatchPlaneDistance = 0.004;
  bool AdaptPatchesToTarget = true;
  double PatchToleranceScale = 1.0;
  double PatchDeviationFactor = 4.0;
  double PatchThicknessBound = 0.0;
  bool LoosenThicknessForTarget = true;
  double PatchThicknessScale = 1.0;
  bool NoiseToleranceWithheld = false;
  bool CollapseFinerLevelForTarget = true;
  bool RefineDeviatingRegions = false;
  double MildTargetRegionAllowance = 0.125;
  double PatchNoiseTolerance = -1.0;
  double BorderCornerAngle = 60.0;
  double MergeAngle = 20.0;
  bool MergePatches = true;
  bool CollapseChains = true;
  double CollapseLengthFactor = 0.2;
  bool SizeWeightedMerge = true;
  bool CompareCandidates = false;
  bool CostOrderedRemoval = true;
  double ChainInPlaneWeight = 0.42;
  bool MinimumDeviationTriangulation = true;
  bool GeneratePatchColoredInput = false;
  bool FinalCollapses = true;
  double LateFailureShare = 1e-4;

  vtkIdType NumberOfPatches = 0;
  vtkIdType NumberOfChains = 0;
  vtkIdType NumberOfMergedPatches = 0;
  double UsedEpsilon = 0.0;
  double UsedMergeAngle = 0.0;
  vtkIdType UnmergedPatches = 0;
  vtkIdType RefinedPatches = 0;
  vtkIdType OriginalPatches = 0;
  int GenerationPasses = 0;
  vtkIdType LateOriginalPatches = 0;
  int LateReplays = 0;
  vtkIdType LateReplayChangedPatches = 0;
  vtkIdType LateReplayBoundaryTests = 0;
  vtkIdType FinalCollapseCount = 0;
  bool FinerLevelTried = false;
  double LevelDeviationShare = -1.0;
  double LevelTailDeviationShare = -1.0;
  vtkIdType RegionRefinedPatches = 0;
  vtkIdType RegionInputTriangles = -1;
  vtkIdType RegionRetriangulatedTriangles = -1;
  bool PatchificationReused = false;
  double PatchificationTime = 0.0;
  double LevelTime = 0.0;
  vtkIdType CacheMemory = 0;

private:
  vtkPatchBoundaryMerge(const vtkPatchBoundaryMerge&) = delete;
  void operator=(const vtkPatchBoundaryMerge&) = delete;

  struct Cache;
  std::unique_ptr<Cache> Cached;
  void ReportRefinedRegions(vtkPolyData* output) const;
};

#endif
