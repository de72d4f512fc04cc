// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPVTriangleCollapseHierarchy
 * @brief   vtkTriangleCollapseHierarchy that reports the range of its continuous level
 *
 * ParaView draws a slider for a property whose range domain has a minimum and a maximum, and it
 * takes a range that depends on the data from an information property holding both. The filter
 * reports only its number of levels, so this subclass adds ContinuousLevelRange, updated by every
 * run: [-1, n] for the levels M0..Mn of the last hierarchy (-1: no continuous level, the target
 * or Level decides). Everything else is vtkTriangleCollapseHierarchy's.
 */
#ifndef vtkPVTriangleCollapseHierarchy_h
#define vtkPVTriangleCollapseHierarchy_h

#include "SurfaceLODParaViewExtensionsModule.h"
#include "vtkTriangleCollapseHierarchy.h"

class SURFACELODPARAVIEWEXTENSIONS_EXPORT vtkPVTriangleCollapseHierarchy : public vtkTriangleCollapseHierarchy
{
public:
  static vtkPVTriangleCollapseHierarchy* New();
  vtkTypeMacro(vtkPVTriangleCollapseHierarchy, vtkTriangleCollapseHierarchy);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// [-1, last level] of the last run ([-1, 0] before the first).
  vtkGetVector2Macro(ContinuousLevelRange, double);

protected:
  vtkPVTriangleCollapseHierarchy() = default;
  ~vtkPVTriangleCollapseHierarchy() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double ContinuousLevelRange[2] = { -1.0, 0.0 };

private:
  vtkPVTriangleCollapseHierarchy(const vtkPVTriangleCollapseHierarchy&) = delete;
  void operator=(const vtkPVTriangleCollapseHierarchy&) = delete;
};

#endif
