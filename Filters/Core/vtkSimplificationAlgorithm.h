// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkSimplificationAlgorithm
 * @brief The stop targets and output precision every SurfaceLOD simplifier shares.
 *
 * The filter contract (slodFilterContract.h, Documentation/Architecture.md) as properties, declared
 * once: TargetNumberOfTriangles (a count, 0 = unused) and TargetReduction (the fraction of the
 * input's triangles to remove, 0 = unused), with the larger count winning when both are set and a
 * reduction of 0.9 when neither is (as vtkQuadricDecimation); OutputPointsPrecision as
 * vtkAlgorithm::DesiredOutputPrecision (default: the input's, float unless double).
 * Simplifiers whose error can also be bounded derive from vtkErrorBoundedSimplificationAlgorithm.
 */
#ifndef vtkSimplificationAlgorithm_h
#define vtkSimplificationAlgorithm_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkSimplificationAlgorithm : public vtkPolyDataAlgorithm
{
public:
  vtkTypeMacro(vtkSimplificationAlgorithm, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Stop at this many triangles (0 = unused, the default).
  vtkSetClampMacro(TargetNumberOfTriangles, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(TargetNumberOfTriangles, vtkIdType);
  ///@}

  ///@{
  /// Fraction of the input's triangles to remove, 0..1 (0 = unused, the default).
  vtkSetClampMacro(TargetReduction, double, 0.0, 1.0);
  vtkGetMacro(TargetReduction, double);
  ///@}

  ///@{
  /// Output point type, as vtkAlgorithm::DesiredOutputPrecision (default: the input's).
  vtkSetMacro(OutputPointsPrecision, int);
  vtkGetMacro(OutputPointsPrecision, int);
  ///@}

  /// The triangle count at which this filter, as set, stops simplifying `inputTriangles`
  /// triangles (slod::TargetTriangleCount); 0 when only an error bound is set.
  vtkIdType ComputeTargetNumberOfTriangles(vtkIdType inputTriangles) const;

protected:
  vtkSimplificationAlgorithm() = default;
  ~vtkSimplificationAlgorithm() override = default;

  /// Whether an error bound is set, so that no count target at all is not the default reduction.
  virtual bool HasErrorBound() const { return false; }

  /// Adds output port 1 holding a `dataTypeName` (e.g. "vtkMultiBlockDataSet" for levels,
  /// "vtkTable" for collapse records): called once from the constructor of a filter with such a
  /// second output; port 0 stays the simplified vtkPolyData.
  void AddSecondaryOutputPort(const char* dataTypeName);
  int FillOutputPortInformation(int port, vtkInformation* info) override;

  vtkIdType TargetNumberOfTriangles = 0;
  double TargetReduction = 0.0;
  int OutputPointsPrecision = vtkAlgorithm::DEFAULT_PRECISION;

private:
  const char* SecondaryOutputType = nullptr; // a string literal naming port 1's data type

  vtkSimplificationAlgorithm(const vtkSimplificationAlgorithm&) = delete;
  void operator=(const vtkSimplificationAlgorithm&) = delete;
};

#endif
