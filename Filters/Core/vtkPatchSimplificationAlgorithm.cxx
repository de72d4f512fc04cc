// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPatchSimplificationAlgorithm.h"

void vtkPatchSimplificationAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PatchAngle: " << this->PatchAngle << "\n";
  os << indent << "NeighborAngle: " << this->NeighborAngle << "\n";
  os << indent << "TwoEdgePatchAngle: " << this->TwoEdgePatchAngle << "\n";
  os << indent << "TwoEdgeNeighborAngle: " << this->TwoEdgeNeighborAngle << "\n";
}
