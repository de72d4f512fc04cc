// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkOBJMeshWriter
 * @brief   writes the surface of a vtkPolyData as Wavefront OBJ with normals and texture coordinates
 *
 * Writes "v" lines (the shortest decimals that read back to the same value in the points'
 * precision), "vt" lines for point texture coordinates of two components, "vn" lines for point
 * normals, and "f" lines (polygons as they are, strips as triangles) whose corners use the same
 * number for position, texture coordinate and normal. vtkOBJMeshReader reads it back with the
 * same points, polygons and values. Other arrays, cell data, vertex and line cells have no OBJ
 * form and are not written. Failures (no input, cannot open or write the file) give a
 * vtkErrorMacro naming the file, an error code and GetLastError().
 */
#ifndef vtkOBJMeshWriter_h
#define vtkOBJMeshWriter_h

#include "SurfaceLODFiltersModule.h"
#include "vtkMeshFileWriter.h"

#include <string>

class SURFACELODFILTERS_EXPORT vtkOBJMeshWriter : public vtkMeshFileWriter
{
public:
  static vtkOBJMeshWriter* New();
  vtkTypeMacro(vtkOBJMeshWriter, vtkMeshFileWriter);

protected:
  vtkOBJMeshWriter() = default;
  ~vtkOBJMeshWriter() override = default;
  std::string WriteMesh(vtkPolyData* mesh, slod::CheckedFileWriter& file) override;

private:
  vtkOBJMeshWriter(const vtkOBJMeshWriter&) = delete;
  void operator=(const vtkOBJMeshWriter&) = delete;
};

#endif
