// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSimplificationAlgorithm.h"

#include "slodFilterContract.h"

#include "vtkDataObject.h"
#include "vtkInformation.h"

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

void vtkSimplificationAlgorithm::AddSecondaryOutputPort(const char* dataTypeName)
{
  this->SecondaryOutputType = dataTypeName;
  this->SetNumberOfOutputPorts(2);
}

int vtkSimplificationAlgorithm::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port == 1 && this->SecondaryOutputType)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), this->SecondaryOutputType);
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}
