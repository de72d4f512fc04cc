// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPVTriangleCollapseHierarchy.h"

#include "vtkObjectFactory.h"

#include <algorithm>

vtkStandardNewMacro(vtkPVTriangleCollapseHierarchy);

int vtkPVTriangleCollapseHierarchy::RequestData(
  vtkInformation* request, vtkInformationVector** inputs, vtkInformationVector* outputs)
{
  const int result = this->Superclass::RequestData(request, inputs, outputs);
  this->ContinuousLevelRange[1] = std::max(0, this->GetNumberOfLevels() - 1);
  return result;
}

void vtkPVTriangleCollapseHierarchy::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ContinuousLevelRange: " << this->ContinuousLevelRange[0] << " "
     << this->ContinuousLevelRange[1] << "\n";
}
