// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMeshFileWriter.h"

#include "slodCheckedFile.h"

#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkPolyData.h"


void vtkMeshFileWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

int vtkMeshFileWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

vtkPolyData* vtkMeshFileWriter::GetInput()
{
  return vtkPolyData::SafeDownCast(this->Superclass::GetInput());
}

void vtkMeshFileWriter::WriteData()
{
  this->LastError.clear();
  this->SetErrorCode(vtkErrorCode::NoError);
  auto fail = [&](const std::string& message, unsigned long code) {
    this->LastError = this->FileName + ": " + message;
    vtkErrorMacro(<< this->LastError);
    this->SetErrorCode(code);
  };
  vtkPolyData* input = this->GetInput();
  if (!input)
  {
    return fail("no input to write", vtkErrorCode::UnknownError);
  }
  if (this->FileName.empty())
  {
    return fail("no file name", vtkErrorCode::NoFileNameError);
  }
  slod::CheckedFileWriter file;
  std::string problem = file.Open(this->FileName);
  if (!problem.empty())
  {
    return fail(problem, vtkErrorCode::CannotOpenFileError);
  }
  const std::string unwritable = this->WriteMesh(input, file);
  problem = file.Close();
  if (unwritable.empty() && problem.empty())
  {
    return;
  }
  slod::RemovePartialFile(this->FileName);
  fail(unwritable.empty() ? problem : unwritable,
    unwritable.empty() ? vtkErrorCode::OutOfDiskSpaceError : vtkErrorCode::UnknownError);
}
