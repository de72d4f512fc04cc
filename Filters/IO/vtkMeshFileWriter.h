// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMeshFileWriter
 * @brief   what the mesh file writers of SurfaceLOD share: the checked file and the failure report
 *
 * WriteData checks the input and the file name, opens the file, lets the format write the mesh
 * through a buffered writer whose every write, flush and close is checked, and reports a failure
 * (no input, cannot open, disk full) as one vtkErrorMacro naming the file, an error code and
 * GetLastError(); a partly written file is removed.
 */
#ifndef vtkMeshFileWriter_h
#define vtkMeshFileWriter_h

#include "SurfaceLODFiltersModule.h"
#include "vtkWriter.h"

#include <string>

class vtkPolyData;
namespace slod
{
class CheckedFileWriter;
}

class SURFACELODFILTERS_EXPORT vtkMeshFileWriter : public vtkWriter
{
public:
  vtkTypeMacro(vtkMeshFileWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);

  /// Description of the last failure ("" when the last write succeeded).
  const char* GetLastError() const { return this->LastError.c_str(); }

  vtkPolyData* GetInput();

protected:
  vtkMeshFileWriter() = default;
  ~vtkMeshFileWriter() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  /// The format: writes the mesh into the open file; returns "" or what makes the mesh unwritable.
  virtual std::string WriteMesh(vtkPolyData* mesh, slod::CheckedFileWriter& file) = 0;

  std::string FileName;
  std::string LastError;

private:
  vtkMeshFileWriter(const vtkMeshFileWriter&) = delete;
  void operator=(const vtkMeshFileWriter&) = delete;
};

#endif
