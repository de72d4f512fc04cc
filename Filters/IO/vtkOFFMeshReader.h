// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkOFFMeshReader
 * @brief   reads Object File Format (OFF) surface meshes into vtkPolyData
 *
 * Accepts the OFF header variants OFF, COFF, NOFF, CNOFF (the header keyword may be followed by
 * the counts on the same line), '#' comments anywhere, blank lines, polygons of any size (kept as
 * polygons; SurfaceLOD filters triangulate them; faces of two vertices become line cells and of
 * one vertex vertex cells), and ignores per-vertex or per-face color columns. A malformed file
 * gives a vtkErrorMacro naming the file and the problem, sets the error code, and produces an
 * empty output; vertex / face counts the rest of the file cannot hold are refused before anything
 * is allocated. Data after the faces the header announces is a vtkWarningMacro naming the file
 * and line (the output holds the announced faces).
 */
#ifndef vtkOFFMeshReader_h
#define vtkOFFMeshReader_h

#include "SurfaceLODFiltersModule.h"
#include "vtkMeshFileReader.h"

class SURFACELODFILTERS_EXPORT vtkOFFMeshReader : public vtkMeshFileReader
{
public:
  static vtkOFFMeshReader* New();
  vtkTypeMacro(vtkOFFMeshReader, vtkMeshFileReader);

protected:
  vtkOFFMeshReader() = default;
  ~vtkOFFMeshReader() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkOFFMeshReader(const vtkOFFMeshReader&) = delete;
  void operator=(const vtkOFFMeshReader&) = delete;
};

#endif
