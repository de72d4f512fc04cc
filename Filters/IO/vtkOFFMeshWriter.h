// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkOFFMeshWriter
 * @brief   writes the surface of a vtkPolyData as an Object File Format (OFF) file
 *
 * Writes "OFF", the counts, one vertex per line and one face per line ("n i0 i1 ... in-1").
 * Polygons are written as they are (any size), triangle strips as triangles; vertex and line
 * cells have no OFF equivalent and are skipped. Coordinates are written in the shortest decimal
 * form that reads back to the same value in the points' precision, so a write/read round trip
 * with vtkOFFMeshReader is exact (double points), or exact after rounding to float (float
 * points: the reader stores doubles). Failures (no input, cannot open or
 * write the file) give a vtkErrorMacro naming the file, an error code and GetLastError().
 */
#ifndef vtkOFFMeshWriter_h
#define vtkOFFMeshWriter_h

#include "SurfaceLODFiltersModule.h"
#include "vtkMeshFileWriter.h"

#include <string>

class SURFACELODFILTERS_EXPORT vtkOFFMeshWriter : public vtkMeshFileWriter
{
public:
  static vtkOFFMeshWriter* New();
  vtkTypeMacro(vtkOFFMeshWriter, vtkMeshFileWriter);

protected:
  vtkOFFMeshWriter() = default;
  ~vtkOFFMeshWriter() override = default;
  std::string WriteMesh(vtkPolyData* mesh, slod::CheckedFileWriter& file) override;

private:
  vtkOFFMeshWriter(const vtkOFFMeshWriter&) = delete;
  void operator=(const vtkOFFMeshWriter&) = delete;
};

#endif
