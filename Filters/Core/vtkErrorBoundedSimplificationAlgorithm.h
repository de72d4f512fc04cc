// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkErrorBoundedSimplificationAlgorithm
 * @brief A simplifier whose result can also be bounded by an error: the contract's third target.
 *
 * MaximumError (0 = unused) bounds how far the surface may move, in the input's units or, when
 * MaximumErrorIsRelative, as a fraction of the input's bounding-box diagonal. Simplification stops
 * at whichever target is reached first (vtkSimplificationAlgorithm). Each filter's page says how it
 * measures the error (a quadric error, a proved Hausdorff bound, a patch's planarity).
 */
#ifndef vtkErrorBoundedSimplificationAlgorithm_h
#define vtkErrorBoundedSimplificationAlgorithm_h

#include "SurfaceLODFiltersModule.h"
#include "vtkSimplificationAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkErrorBoundedSimplificationAlgorithm : public vtkSimplificationAlgorithm
{
public:
  vtkTypeMacro(vtkErrorBoundedSimplificationAlgorithm, vtkSimplificationAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Largest allowed error (0 = unused); relative to the bounding-box diagonal when
  /// MaximumErrorIsRelative. The defaults are each filter's.
  vtkSetClampMacro(MaximumError, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumError, double);
  vtkSetMacro(MaximumErrorIsRelative, bool);
  vtkGetMacro(MaximumErrorIsRelative, bool);
  vtkBooleanMacro(MaximumErrorIsRelative, bool);
  ///@}

protected:
  vtkErrorBoundedSimplificationAlgorithm() = default;
  ~vtkErrorBoundedSimplificationAlgorithm() override = default;

  bool HasErrorBound() const override { return this->MaximumError > 0; }

  /// MaximumError in the input's units for a surface of this diagonal; 0 when unused.
  double AbsoluteMaximumError(double diagonal) const
  {
    return this->MaximumErrorIsRelative ? this->MaximumError * diagonal : this->MaximumError;
  }

  double MaximumError = 0.0;
  bool MaximumErrorIsRelative = false;

private:
  vtkErrorBoundedSimplificationAlgorithm(const vtkErrorBoundedSimplificationAlgorithm&) = delete;
  void operator=(const vtkErrorBoundedSimplificationAlgorithm&) = delete;
};

#endif
