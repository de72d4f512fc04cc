// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkHoleBumpRemoval
 * @brief   Topology simplification (Ho 1999, chapter 5): removes small holes (tunnels), bumps
 *          and cavities bounded by sharp edges, closes small cracks, and re-triangulates
 *
 * The surface is patchified as in SPBM (slod::Patchification). Patch-boundary edges whose two
 * triangle normals have a dot product inside (cos MaximumSharpAngle, cos SharpAngle) are sharp
 * (default (-0.3, 0.7), the dissertation's interval). Closed loops of sharp chains are searched
 * (convex hole chains first); each loop has a flat side and a wall side and is clockwise when the
 * flat side lies outside it. A clockwise loop's wall patches lead to its partner loop: two
 * clockwise loops bound a hole, a clockwise loop alone or with a counter-clockwise partner a bump
 * or a cavity. A feature is removed when all its loops are smaller than FeatureSize
 * (sampled diameter, alpha): the wall patches are discarded and every clockwise loop becomes a new
 * patch (ear-clipped). Cracks (loops of border edges smaller than MaximumCrackSize) are closed the
 * same way. Nearly coplanar neighbouring patches then merge (MergeAngle, alpha1, patches stay
 * disks) and the result is completed according to Completion:
 *  - KEEP_TRIANGLES: only the features change, every other input triangle is kept;
 *  - TRIANGULATE_PATCHES (default, option (2) of the chapter): every patch is re-triangulated from
 *    its exact boundary (profile curves are kept; only exactly collinear boundary vertices go), so
 *    a box with holes becomes 12 triangles;
 *  - SPBM (option (1)): the SPBM phases (chain simplification within Epsilon or to a target,
 *    patch merging, triangulation) run on the cleaned patches. Setting TargetNumberOfTriangles
 *    or TargetReduction selects this completion with that target.
 * Removing a hole lowers the genus by one; the output is a manifold over input vertices.
 *
 * Outputs:
 *  - port 0: the simplified mesh, cell data "PatchId" and "FilledPatch" (0 input surface, 1 filled
 *    feature loop, 2 closed crack), input point data carried, field data "HolesRemoved",
 *    "BumpsRemoved", "CavitiesRemoved", "CracksFilled" and the *Detected counts;
 *  - port 1: when GenerateSharpLoops is on, the sharp loops and closed cracks as polylines with cell
 *    data "FeatureKind" (0 hole, 1 bump, 2 cavity, 3 crack, -1 no feature), "Removed", "Clockwise".
 */
#ifndef vtkHoleBumpRemoval_h
#define vtkHoleBumpRemoval_h

#include "SurfaceLODFiltersModule.h"
#include "vtkSimplificationAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkHoleBumpRemoval : public vtkSimplificationAlgorithm
{
public:
  static vtkHoleBumpRemoval* New();
  vtkTypeMacro(vtkHoleBumpRemoval, vtkSimplificationAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum CompletionModes
  {
    KEEP_TRIANGLES = 0,
    TRIANGULATE_PATCHES = 1,
    SPBM = 2
  };

  ///@{
  /// Sharp edges: normals between SharpAngle (default 45.57, dot 0.7) and MaximumSharpAngle
  /// (default 107.46, dot -0.3) degrees apart.
  vtkSetClampMacro(SharpAngle, double, 0.0, 180.0);
  vtkGetMacro(SharpAngle, double);
  vtkSetClampMacro(MaximumSharpAngle, double, 0.0, 180.0);
  vtkGetMacro(MaximumSharpAngle, double);
  ///@}

  ///@{
  /// alpha: features whose loops all have a smaller (sampled) diameter are removed. Relative to
  /// the bounding-box diagonal when FeatureSizeIsRelative is on (default 0.05 relative).
  vtkSetClampMacro(FeatureSize, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(FeatureSize, double);
  vtkSetMacro(FeatureSizeIsRelative, bool);
  vtkGetMacro(FeatureSizeIsRelative, bool);
  vtkBooleanMacro(FeatureSizeIsRelative, bool);
  ///@}

  ///@{
  /// Former names of FeatureSize and FeatureSizeIsRelative (before 2026-12), kept so that
  /// existing scripts run: the concept has vtkTopologicalNoiseRemoval's name now.
  void SetMaximumFeatureSize(double size) { this->SetFeatureSize(size); }
  double GetMaximumFeatureSize() { return this->GetFeatureSize(); }
  void SetMaximumFeatureSizeIsRelative(bool relative) { this->SetFeatureSizeIsRelative(relative); }
  bool GetMaximumFeatureSizeIsRelative() { return this->GetFeatureSizeIsRelative(); }
  ///@}

  ///@{
  /// Which features go (all on by default).
  vtkSetMacro(RemoveHoles, bool);
  vtkGetMacro(RemoveHoles, bool);
  vtkBooleanMacro(RemoveHoles, bool);
  vtkSetMacro(RemoveBumps, bool);
  vtkGetMacro(RemoveBumps, bool);
  vtkBooleanMacro(RemoveBumps, bool);
  vtkSetMacro(RemoveCavities, bool);
  vtkGetMacro(RemoveCavities, bool);
  vtkBooleanMacro(RemoveCavities, bool);
  ///@}

  ///@{
  /// Crack repair (default on): border loops with a diameter below MaximumCrackSize (same units
  /// as FeatureSize; negative = FeatureSize, the default) are closed.
  vtkSetMacro(FillCracks, bool);
  vtkGetMacro(FillCracks, bool);
  vtkBooleanMacro(FillCracks, bool);
  vtkSetMacro(MaximumCrackSize, double);
  vtkGetMacro(MaximumCrackSize, double);
  ///@}

  ///@{
  /// Detection runs again on the cleaned surface while a pass removes something, at most this
  /// many times (default 4): a removal can expose a feature (a stepped hole's counterbore is a
  /// cavity once the hole is filled).
  vtkSetClampMacro(MaximumPasses, int, 1, 100);
  vtkGetMacro(MaximumPasses, int);
  ///@}

  ///@{
  /// alpha1 of the clean-up merge, degrees (default 20; 0 = no merge). Also SPBM's merge angle.
  vtkSetClampMacro(MergeAngle, double, 0.0, 90.0);
  vtkGetMacro(MergeAngle, double);
  ///@}

  ///@{
  /// Patch growth angles (degrees, default 25 / 20), as in vtkPatchBoundaryMerge.
  vtkSetClampMacro(PatchAngle, double, 0.0, 180.0);
  vtkGetMacro(PatchAngle, double);
  vtkSetClampMacro(NeighborAngle, double, 0.0, 180.0);
  vtkGetMacro(NeighborAngle, double);
  /// Patches also stay within this distance of their running plane, relative to the bounding-box
  /// diagonal (default 0.004 as in vtkPatchBoundaryMerge; 0 = the paper's normal-only growth).
  vtkSetClampMacro(PatchPlaneDistance, double, 0.0, 1.0);
  vtkGetMacro(PatchPlaneDistance, double);
  ///@}

  ///@{
  /// Completion (default TRIANGULATE_PATCHES).
  vtkSetClampMacro(Completion, int, KEEP_TRIANGLES, SPBM);
  vtkGetMacro(Completion, int);
  void SetCompletionToKeepTriangles() { this->SetCompletion(KEEP_TRIANGLES); }
  void SetCompletionToTriangulatePatches() { this->SetCompletion(TRIANGULATE_PATCHES); }
  void SetCompletionToSpbm() { this->SetCompletion(SPBM); }
  /// ContinueWithSimplification on = SPBM completion, off = TRIANGULATE_PATCHES.
  void SetContinueWithSimplification(bool on) { this->SetCompletion(on ? SPBM : TRIANGULATE_PATCHES); }
  bool GetContinueWithSimplification() { return this->Completion == SPBM; }
  ///@}

  ///@{
  /// SPBM completion: chain tolerance relative to the bounding-box diagonal (default 0.005), or a
  /// triangle target (TargetNumberOfTriangles, 0 = unused; TargetReduction, fraction removed).
  vtkSetClampMacro(Epsilon, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Epsilon, double);
  ///@}

  ///@{
  /// SPBM completion to a triangle target: when the level stays above it (rough scans, whose
  /// fallback passes unmerge patches), its vertices are collapsed as vtkPatchBoundaryMerge's
  /// FinalCollapses do (default on; the removed features stay removed, the topology the level's).
  /// FinalCollapseCount is the number performed.
  vtkSetMacro(FinalCollapses, bool);
  vtkGetMacro(FinalCollapses, bool);
  vtkBooleanMacro(FinalCollapses, bool);
  vtkGetMacro(FinalCollapseCount, vtkIdType);
  ///@}

  ///@{
  /// SPBM completion to a triangle target: generate the size-weighted merge measure's level only
  /// (as vtkPatchBoundaryMerge does) instead of two whole levels, the plain and the size-weighted
  /// measure's, compared by their sampled deviation before the final collapses (default off: the
  /// comparison). On the noisy scans the plain level is the larger cost and is discarded at 1M and
  /// 4M triangles (HoleBumpRemoval.md, session 40); at 0.25M it is kept, so outputs can differ.
  vtkSetMacro(SingleMergeMeasure, bool);
  vtkGetMacro(SingleMergeMeasure, bool);
  vtkBooleanMacro(SingleMergeMeasure, bool);
  ///@}

  ///@{
  /// SPBM completion to a triangle target, SingleMergeMeasure off (session 41): the size-weighted
  /// level alone when more than this share of the input's interior edges are noisy bends, i.e.
  /// bent by more than NeighborAngle while each triangle's third vertex stays within
  /// PatchPlaneDistance of the other's plane (a scan's noise; see HoleBumpRemoval.md). There the
  /// plain measure's level is discarded by the comparison; elsewhere both are compared. Clamped to
  /// [0, 1]; 1: always compared (the rule of session 40). NoisyBendShare is the share measured (-1
  /// when not), SingleMergeMeasureUsed whether the level was the size-weighted one alone.
  vtkSetClampMacro(SingleMeasureNoisyBendShare, double, 0.0, 1.0);
  vtkGetMacro(SingleMeasureNoisyBendShare, double);
  vtkGetMacro(NoisyBendShare, double);
  vtkGetMacro(SingleMergeMeasureUsed, bool);
  ///@}

  ///@{
  /// Second output with the sharp loops (default on); double precision points (default: as input).
  vtkSetMacro(GenerateSharpLoops, bool);
  vtkGetMacro(GenerateSharpLoops, bool);
  vtkBooleanMacro(GenerateSharpLoops, bool);
  ///@}

  ///@{
  /// Results of the last update.
  vtkGetMacro(NumberOfHolesDetected, int);
  vtkGetMacro(NumberOfBumpsDetected, int);
  vtkGetMacro(NumberOfCavitiesDetected, int);
  vtkGetMacro(NumberOfCracksDetected, int);
  vtkGetMacro(NumberOfHolesRemoved, int);
  vtkGetMacro(NumberOfBumpsRemoved, int);
  vtkGetMacro(NumberOfCavitiesRemoved, int);
  vtkGetMacro(NumberOfCracksFilled, int);
  vtkGetMacro(NumberOfSharpEdges, int);
  vtkGetMacro(NumberOfSharpLoops, int);
  vtkGetMacro(NumberOfPatches, int);
  vtkGetMacro(NumberOfMergedPatches, int);
  vtkGetMacro(InputGenus, int);  // -1 when not defined (non-manifold or non-orientable)
  vtkGetMacro(OutputGenus, int);
  vtkGetMacro(UsedFeatureSize, double); // alpha in absolute units
  ///@}

protected:
  vtkHoleBumpRemoval();
  ~vtkHoleBumpRemoval() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // Epsilon always bounds the completion: removing features is the purpose, not a reduction.
  bool HasErrorBound() const override { return true; }

  double SharpAngle = 45.572996; // acos(0.7)
  double MaximumSharpAngle = 107.457603; // acos(-0.3)
  double FeatureSize = 0.05;
  bool FeatureSizeIsRelative = true;
  bool RemoveHoles = true;
  bool RemoveBumps = true;
  bool RemoveCavities = true;
  bool FillCracks = true;
  bool FinalCollapses = true;
  bool SingleMergeMeasure = false;
  double SingleMeasureNoisyBendShare = 0.35;
  double NoisyBendShare = -1.0;
  bool SingleMergeMeasureUsed = false;
  vtkIdType FinalCollapseCount = 0;
  double MaximumCrackSize = -1.0;
  double MergeAngle = 20.0;
  int MaximumPasses = 4;
  double PatchAngle = 25.0;
  double NeighborAngle = 20.0;
  double PatchPlaneDistance = 0.004;
  int Completion = TRIANGULATE_PATCHES;
  double Epsilon = 0.005;
  bool GenerateSharpLoops = true;

  int NumberOfHolesDetected = 0, NumberOfBumpsDetected = 0, NumberOfCavitiesDetected = 0, NumberOfCracksDetected = 0;
  int NumberOfHolesRemoved = 0, NumberOfBumpsRemoved = 0, NumberOfCavitiesRemoved = 0, NumberOfCracksFilled = 0;
  int NumberOfSharpEdges = 0, NumberOfSharpLoops = 0, NumberOfPatches = 0, NumberOfMergedPatches = 0;
  int InputGenus = -1, OutputGenus = -1;
  double UsedFeatureSize = 0.0;

private:
  vtkHoleBumpRemoval(const vtkHoleBumpRemoval&) = delete;
  void operator=(const vtkHoleBumpRemoval&) = delete;
};

#endif
