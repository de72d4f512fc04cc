// SPDX-License-Identifier: BSD-3-Clause
#include "vtkErrorBoundedSimplificationAlgorithm.h"

void vtkErrorBoundedSimplificationAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumError: " << this->MaximumError << "\n";
  os << indent << "MaximumErrorIsRelative: " << this->MaximumErrorIsRelative << "\n";
}
