// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkPatchSimplificationAlgorithm
 * @brief An error-bounded simplifier over Ho's near-planar patches: their growth tolerances, once.
 *
 * Ho 1999 grows patches of near-coplanar triangles (chapter 4, feasibility (b); chapter 3 uses the
 * same patches by default) before simplifying their boundaries. A triangle sharing one edge with a
 * patch joins when its normal is within PatchAngle of the patch's normal (default 25 degrees) and
 * within NeighborAngle of the triangle it grows from (default 20); one sharing two edges uses
 * TwoEdgePatchAngle / TwoEdgeNeighborAngle (default 90 / 90). slod::PatchificationParameters
 * carries them to the core.
 */
#ifndef vtkPatchSimplificationAlgorithm_h
#define vtkPatchSimplificationAlgorithm_h

#include "SurfaceLODFiltersModule.h"
#include "vtkErrorBoundedSimplificationAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkPatchSimplificationAlgorithm : public vtkErrorBoundedSimplificationAlgorithm
{
public:
  vtkTypeMacro(vtkPatchSimplificationAlgorithm, vtkErrorBoundedSimplificationAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Patch growth tolerances in degrees (see the class description).
  vtkSetClampMacro(PatchAngle, double, 0.0, 180.0);
  vtkGetMacro(PatchAngle, double);
  vtkSetClampMacro(NeighborAngle, double, 0.0, 180.0);
  vtkGetMacro(NeighborAngle, double);
  vtkSetClampMacro(TwoEdgePatchAngle, double, 0.0, 180.0);
  vtkGetMacro(TwoEdgePatchAngle, double);
  vtkSetClampMacro(TwoEdgeNeighborAngle, double, 0.0, 180.0);
  vtkGetMacro(TwoEdgeNeighborAngle, double);
  ///@}

protected:
  vtkPatchSimplificationAlgorithm() = default;
  ~vtkPatchSimplificationAlgorithm() override = default;

  double PatchAngle = 25.0;
  double NeighborAngle = 20.0;
  double TwoEdgePatchAngle = 90.0;
  double TwoEdgeNeighborAngle = 90.0;

private:
  vtkPatchSimplificationAlgorithm(const vtkPatchSimplificationAlgorithm&) = delete;
  void operator=(const vtkPatchSimplificationAlgorithm&) = delete;
};

#endif
