// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkRetileLevelInterpolation
 * @brief   smooth interpolation between two nested levels of detail (Turk 1992, section 6)
 *
 * Greg Turk, "Re-Tiling Polygonal Surfaces" (SIGGRAPH 1992), sections 6.2-6.3. Input port 0 is the
 * high-detail level, port 1 the low-detail level of the same surface; every low-detail vertex must
 * be a vertex of the high-detail level at the same position (the levels are nested, as those of
 * vtkRetile's output port 1 with GenerateNestedLevels: take two blocks of it).
 *
 * Every high-detail vertex absent from the low level is flattened onto the low-detail surface
 * (its closest point there), every high-detail triangle is cut by the low-detail edges that cross
 * it into polygon fragments, and the output is the fragment mesh with its vertices at
 * (1 - T) * flattened + T * original: at T = 0 it has exactly the shape of the low-detail level,
 * at T = 1 exactly that of the high-detail level, and in between it "inflates" continuously
 * (same connectivity for every T: animate by changing T, or from the point arrays directly).
 *
 * Output point data: "LowPosition" and "HighPosition" (3 doubles, the two end positions).
 * Output cell data: "HighTriangle" (the high-detail triangle a triangle is part of, in the order of
 * the high-detail input's triangles), "LowTriangle" (the low-detail triangle it lies on at T = 0)
 * and "Fragment" (its polygon fragment). Input point data are not carried.
 *
 * Two ways to find the correspondence. When the low level carries the field data RetileRemovals
 * (vtkRetile's nested levels: each coarser level is made from the next finer one by recorded
 * collapses), the fragments are tracked through those removals as the paper does (section 6.2,
 * slodFragmentTracking.h): every fragment ends inside one low triangle, so T = 0 is the low level
 * exactly. Without records (two arbitrary nested meshes, UseRemovalRecords off, or records that
 * do not replay to the low level: a warning) the correspondence is computed from the two meshes
 * alone (closest point on the low surface, then each high edge's path as the shortest strip of low
 * triangles between its ends); where that flattening folds (the low level bends sharply relative
 * to its vertex spacing) a few fragments are not inside one low triangle
 * (NumberOfInconsistentFragments) and the T = 0 shape departs from the low level there. Errors
 * (empty input, levels not nested, non-manifold low level) give an empty output.
 */
#ifndef vtkRetileLevelInterpolation_h
#define vtkRetileLevelInterpolation_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkRetileLevelInterpolation : public vtkPolyDataAlgorithm
{
public:
  static vtkRetileLevelInterpolation* New();
  vtkTypeMacro(vtkRetileLevelInterpolation, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetHighDetailConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(0, output); }
  void SetLowDetailConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetHighDetailData(vtkDataObject* input) { this->SetInputData(0, input); }
  void SetLowDetailData(vtkDataObject* input) { this->SetInputData(1, input); }

  // 0 = low-detail shape, 1 = high-detail shape.
  vtkSetClampMacro(T, double, 0.0, 1.0);
  vtkGetMacro(T, double);

  // Default DOUBLE_PRECISION: the end shapes are exact only in double.
  vtkSetMacro(OutputPointsPrecision, int);
  vtkGetMacro(OutputPointsPrecision, int);

  // Track the fragments through the low level's RetileRemovals when it has them (default on);
  // off: always the closest-point flattening.
  vtkSetMacro(UseRemovalRecords, vtkTypeBool);
  vtkGetMacro(UseRemovalRecords, vtkTypeBool);
  vtkBooleanMacro(UseRemovalRecords, vtkTypeBool);

  // Results of the last run.
  // Removals replayed by the fragment tracking (0: the closest-point flattening was used).
  vtkGetMacro(NumberOfTrackedRemovals, vtkIdType);
  vtkGetMacro(NumberOfSharedVertices, vtkIdType);
  vtkGetMacro(NumberOfFlattenedVertices, vtkIdType);
  // Low vertices missing from the high level, inserted into it at their closest point (levels that
  // are not quite nested, e.g. made by other tools; vtkRetile's nested levels need none; the
  // output then starts with the high vertices, then these).
  vtkGetMacro(NumberOfInsertedVertices, vtkIdType);
  vtkGetMacro(NumberOfCrossings, vtkIdType);
  vtkGetMacro(NumberOfFragments, vtkIdType);
  // Should be 0: high edges whose path on the low surface could not be walked, and fragments not
  // inside a single low triangle (where the T = 0 shape departs from the low level).
  vtkGetMacro(NumberOfUntracedEdges, vtkIdType);
  vtkGetMacro(NumberOfInconsistentFragments, vtkIdType);

protected:
  vtkRetileLevelInterpolation();
  ~vtkRetileLevelInterpolation() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double T = 1.0;
  int OutputPointsPrecision = vtkAlgorithm::DOUBLE_PRECISION;
  vtkTypeBool UseRemovalRecords = 1;
  vtkIdType NumberOfTrackedRemovals = 0;
  vtkIdType NumberOfSharedVertices = 0;
  vtkIdType NumberOfFlattenedVertices = 0;
  vtkIdType NumberOfInsertedVertices = 0;
  vtkIdType NumberOfCrossings = 0;
  vtkIdType NumberOfFragments = 0;
  vtkIdType NumberOfUntracedEdges = 0;
  vtkIdType NumberOfInconsistentFragments = 0;

private:
  vtkRetileLevelInterpolation(const vtkRetileLevelInterpolation&) = delete;
  void operator=(const vtkRetileLevelInterpolation&) = delete;
};

#endif
