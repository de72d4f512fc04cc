// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMeshFileReader.h"

#include "vtkErrorCode.h"
#include "vtkPolyData.h"

vtkMeshFileReader::vtkMeshFileReader()
{
  this->SetNumberOfInputPorts(0);
}

void vtkMeshFileReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

void vtkMeshFileReader::StartRead()
{
  this->LastError.clear();
  this->SetErrorCode(vtkErrorCode::NoError);
}

std::string vtkMeshFileReader::Where(long long line) const
{
  return this->FileName + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": ";
}

int vtkMeshFileReader::FailRead(vtkPolyData* output, const std::string& message, unsigned long errorCode, long long line)
{
  this->LastError = this->Where(line) + message;
  vtkErrorMacro(<< this->LastError);
  this->SetErrorCode(errorCode);
  output->Initialize();
  return 1;
}

void vtkMeshFileReader::WarnNotRead(const std::string& what, long long line)
{
  vtkWarningMacro(<< this->Where(line) << what);
}
