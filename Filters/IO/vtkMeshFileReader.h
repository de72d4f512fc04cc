// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkMeshFileReader
 * @brief   what the mesh file readers of SurfaceLOD share: the file name and the failure report
 *
 * A failure is one vtkErrorMacro "FILE[:LINE]: problem", an error code, GetLastError() and an
 * empty output (a defined result: the pipeline goes on, the error code tells callers).
 */
#ifndef vtkMeshFileReader_h
#define vtkMeshFileReader_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <string>

class SURFACELODFILTERS_EXPORT vtkMeshFileReader : public vtkPolyDataAlgorithm
{
public:
  vtkTypeMacro(vtkMeshFileReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);

  /// Description of the last failure ("" when the last read succeeded).
  const char* GetLastError() const { return this->LastError.c_str(); }

protected:
  vtkMeshFileReader();
  ~vtkMeshFileReader() override = default;

  /// Clears the last failure (at the start of a read).
  void StartRead();
  /// Reports a failure of the file (line 0: none) and empties the output; returns 1 for RequestData.
  int FailRead(vtkPolyData* output, const std::string& message, unsigned long errorCode, long long line = 0);
  /// Reports what the file holds but the reader does not read, as one warning naming the file (and line).
  void WarnNotRead(const std::string& what, long long line = 0);

  // "FILE: " or "FILE:LINE: ".
  std::string Where(long long line) const;

  std::string FileName;
  std::string LastError;

private:
  vtkMeshFileReader(const vtkMeshFileReader&) = delete;
  void operator=(const vtkMeshFileReader&) = delete;
};

#endif
