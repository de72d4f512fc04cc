// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSimplificationAlgorithm.h"

#include "slodFilterContract.h"

vtkIdType vtkSimplificationAlgorithm::ComputeTargetNumberOfTriangles(vtkIdType inputTriangles) const
{
  return slod::TargetTriangleCount(static_cast<slod::Index>(inputTriangles), this->TargetNumberOfTriangles,
    this->TargetReduction, this->HasErrorBound());
}

void vtkSimplificationAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetNumberOfTriangles: " << this->TargetNumberOfTriangles << "\n";
  os << indent << "TargetReduction: " << this->TargetReduction << "\n";
  os << indent << "OutputPointsPrecision: " << this->OutputPointsPrecision << "\n";
}
