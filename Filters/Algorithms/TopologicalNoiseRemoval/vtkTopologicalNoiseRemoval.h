// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkTopologicalNoiseRemoval
 * @brief   Removes handles, tunnels, cavities and specks smaller than a feature size from a
 *          manifold triangle mesh (Guskov & Wood 2001, topological noise removal)
 *
 * Isosurfaces of scans carry many tiny handles and tunnels. This filter grows geodesic regions
 * over the surface; where a region's front meets itself around a handle, the loop it closes is
 * cut when it is short (length at most pi * FeatureSize: the handle's size, length / pi, is at
 * most FeatureSize) and does not separate the mesh, and both sides of the cut are filled with
 * disks. Components whose bounding-box diagonal is below FeatureSize are removed (closed ones
 * inside the largest component count as cavities). Larger handles and components are kept.
 * Every output vertex is an input vertex or a copy of one (the two sides of a cut), so point data
 * are carried exactly; the fills move the surface by at most a quarter of the loop's length.
 * Non-manifold edges and vertices are first split into manifold sheets (SplitNonManifold, on by
 * default: the sheets that touch there are separated, no border is opened); where that is off or
 * impossible they are locked, like border vertices, and never part of a cut (with a warning).
 * Handles kept because they are larger than FeatureSize are sized by a survey in rounds at 2, 4,
 * 8 ... times FeatureSize, up to KeptHandleSurveyFactor times FeatureSize or the diagonal, and
 * reported with their sizes.
 *
 * Outputs:
 *  - port 0: the cleaned surface, point and cell data carried, field data "HandlesRemoved",
 *    "ComponentsRemoved", "CavitiesRemoved", "LoopsKept" (short loops whose separation test ran
 *    out of budget), "HandlesKept" (the output's genus, -1 when not defined), "FeatureSize",
 *    "NonManifoldEdgesSplit", "NonManifoldVerticesSplit", "KeptHandleSurveySize" (the largest
 *    size surveyed), "KeptHandleSizes" (one value per kept handle found by the survey, ascending),
 *    "HandlesNotSized" (kept handles larger than the survey reached; -1 when the output's genus
 *    is not defined) and "SurveyPassLimitReached" (1: a survey round stopped at MaximumPasses);
 *  - port 1 (GenerateCutLoops, default on): the loops as closed polylines, cell data "Removed"
 *    (1 cut, 0 kept), "Length" and "Size" (length / pi).
 * See Documentation/TopologicalNoiseRemoval.md.
 */
#ifndef vtkTopologicalNoiseRemoval_h
#define vtkTopologicalNoiseRemoval_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkTopologicalNoiseRemoval : public vtkPolyDataAlgorithm
{
public:
  static vtkTopologicalNoiseRemoval* New();
  vtkTypeMacro(vtkTopologicalNoiseRemoval, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// alpha: handles whose shortest loop is at most pi * alpha long and components whose diagonal is
  /// below alpha are removed. Relative to the input's bounding-box diagonal when
  /// FeatureSizeIsRelative is on (default 0.01 relative).
  vtkSetClampMacro(FeatureSize, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(FeatureSize, double);
  vtkSetMacro(FeatureSizeIsRelative, bool);
  vtkGetMacro(FeatureSizeIsRelative, bool);
  vtkBooleanMacro(FeatureSizeIsRelative, bool);
  ///@}

  ///@{
  /// What is removed (both on by default).
  vtkSetMacro(RemoveHandles, bool);
  vtkGetMacro(RemoveHandles, bool);
  vtkBooleanMacro(RemoveHandles, bool);
  vtkSetMacro(RemoveComponents, bool);
  vtkGetMacro(RemoveComponents, bool);
  vtkBooleanMacro(RemoveComponents, bool);
  ///@}

  ///@{
  /// Bounds of the work: detection passes (default 8; a pass after the first grows only the
  /// regions near a cut) and triangles searched per side of a loop to tell whether it separates
  /// the mesh (default 0: no limit; a loop whose search runs out is kept and reported).
  vtkSetClampMacro(MaximumPasses, int, 1, 1000);
  vtkGetMacro(MaximumPasses, int);
  vtkSetClampMacro(SeparationSearchBudget, vtkIdType, 0, VTK_INT_MAX);
  vtkGetMacro(SeparationSearchBudget, vtkIdType);
  ///@}

  ///@{
  /// SplitNonManifold (default on): split non-manifold edges and vertices into manifold sheets
  /// before the search, so that the output is manifold and handles through them can be cut.
  /// KeptHandleSurveyFactor (default 2, 0 or <= 1 for none): after the cuts, the handles kept are
  /// sized on a copy of the result in rounds at 2, 4, 8 ... times FeatureSize, up to this multiple
  /// (or the diagonal), stopping when every kept handle is sized; reported, not cut. Each round
  /// costs about as much as the cuts; the default sizes those up to twice FeatureSize, a large
  /// factor (64) all of them.
  vtkSetMacro(SplitNonManifold, bool);
  vtkGetMacro(SplitNonManifold, bool);
  vtkBooleanMacro(SplitNonManifold, bool);
  vtkSetClampMacro(KeptHandleSurveyFactor, double, 0.0, 100.0);
  vtkGetMacro(KeptHandleSurveyFactor, double);
  ///@}

  ///@{
  /// Second output with the loops (default on); output point type as
  /// vtkAlgorithm::DesiredOutputPrecision (default: the input's, float unless double).
  vtkSetMacro(GenerateCutLoops, bool);
  vtkGetMacro(GenerateCutLoops, bool);
  vtkBooleanMacro(GenerateCutLoops, bool);
  vtkSetMacro(OutputPointsPrecision, int);
  vtkGetMacro(OutputPointsPrecision, int);
  ///@}

  ///@{
  /// Results of the last update.
  vtkGetMacro(NumberOfHandlesRemoved, int);
  vtkGetMacro(NumberOfComponentsRemoved, int);
  vtkGetMacro(NumberOfCavitiesRemoved, int);
  vtkGetMacro(NumberOfLoopsKept, int);
  vtkGetMacro(NumberOfNonManifoldEdgesSplit, int);
  vtkGetMacro(NumberOfNonManifoldVerticesSplit, int);
  vtkGetMacro(NumberOfHandlesKeptAboveFeatureSize, int); // found by the survey
  vtkGetMacro(InputEulerCharacteristic, vtkIdType);
  vtkGetMacro(OutputEulerCharacteristic, vtkIdType);
  vtkGetMacro(InputGenus, int);  // -1 when not defined (non-manifold or non-orientable)
  vtkGetMacro(OutputGenus, int);
  vtkGetMacro(UsedFeatureSize, double); // alpha in absolute units
  ///@}

protected:
  vtkTopologicalNoiseRemoval();
  ~vtkTopologicalNoiseRemoval() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double FeatureSize = 0.01;
  bool FeatureSizeIsRelative = true;
  bool RemoveHandles = true;
  bool RemoveComponents = true;
  int MaximumPasses = 8;
  vtkIdType SeparationSearchBudget = 0;
  bool GenerateCutLoops = true;
  bool SplitNonManifold = true;
  double KeptHandleSurveyFactor = 2.0;
  int OutputPointsPrecision = vtkAlgorithm::DEFAULT_PRECISION;

  int NumberOfHandlesRemoved = 0, NumberOfComponentsRemoved = 0, NumberOfCavitiesRemoved = 0;
  int NumberOfLoopsKept = 0;
  int NumberOfNonManifoldEdgesSplit = 0, NumberOfNonManifoldVerticesSplit = 0;
  int NumberOfHandlesKeptAboveFeatureSize = 0;
  vtkIdType InputEulerCharacteristic = 0, OutputEulerCharacteristic = 0;
  int InputGenus = -1, OutputGenus = -1;
  double UsedFeatureSize = 0.0;

private:
  vtkTopologicalNoiseRemoval(const vtkTopologicalNoiseRemoval&) = delete;
  void operator=(const vtkTopologicalNoiseRemoval&) = delete;
};

#endif
