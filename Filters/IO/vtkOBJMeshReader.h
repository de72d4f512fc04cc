// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkOBJMeshReader
 * @brief   reads the polygons of a Wavefront OBJ file with their normals and texture coordinates
 *
 * Reads "v" (double precision points), "vt" (texture coordinates u, v), "vn" (normals) and "f"
 * (polygons; corners v, v/vt, v//vn or v/vt/vn, negative indices counted back from the last
 * item). OBJ indexes positions, texture coordinates and normals separately; VTK keeps one set of
 * attributes per point, so a position used with different texture coordinates or normals (a UV
 * seam, a crease) becomes one point per distinct combination: the first combination keeps the
 * position's number, the others are appended after the file's positions. A file that uses one
 * combination per position (as vtkOBJMeshWriter writes) is read back with the same point ids.
 *
 * Every inconsistency (a malformed or non-finite number, an index out of range or zero, a face of
 * fewer than three corners) gives one vtkErrorMacro naming the file and line, sets the error code
 * and GetLastError(), and produces an empty output. Statements it does not read (lines, points,
 * curves, vertex colours; materials and groups carry no geometry) are one vtkWarningMacro.
 */
#ifndef vtkOBJMeshReader_h
#define vtkOBJMeshReader_h

#include "SurfaceLODFiltersModule.h"
#include "vtkMeshFileReader.h"

class SURFACELODFILTERS_EXPORT vtkOBJMeshReader : public vtkMeshFileReader
{
public:
  static vtkOBJMeshReader* New();
  vtkTypeMacro(vtkOBJMeshReader, vtkMeshFileReader);

protected:
  vtkOBJMeshReader() = default;
  ~vtkOBJMeshReader() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkOBJMeshReader(const vtkOBJMeshReader&) = delete;
  void operator=(const vtkOBJMeshReader&) = delete;
};

#endif
