// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPLYMeshReader
 * @brief   reads PLY surface meshes with all their vertex and face properties into vtkPolyData
 *
 * Reads ASCII and binary PLY (either byte order). The vertex element's x, y, z become the points
 * (double when any of them is double in the file, else float); nx, ny, nz the point normals;
 * uchar red, green, blue [, alpha] the point scalars (an "RGB" or "RGBA" unsigned char array);
 * u, v (or s, t, texture_u, texture_v, texture_s, texture_t) the texture coordinates. Every other
 * scalar vertex property becomes a point array of its own type and name; properties named
 * NAME_0, NAME_1, ... of one type become one array NAME with that many components (what
 * vtkPLYMeshWriter writes for arrays of several components). The face element's vertex_indices
 * (or vertex_index) list gives the polygons and its other scalar properties the cell arrays in the
 * same way (uchar red, green, blue [, alpha] as cell scalars).
 *
 * Every inconsistency (header syntax, counts the file cannot hold, truncated data, malformed
 * values, indices out of range, often the sign of a wrong byte order) gives one vtkErrorMacro
 * naming the file and the problem, sets the error code and GetLastError(), and produces an empty
 * output. What is not read (other elements, list properties besides the face indices, faces of
 * fewer than three vertices, data after the last element) is one vtkWarningMacro naming the file.
 */
#ifndef vtkPLYMeshReader_h
#define vtkPLYMeshReader_h

#include "SurfaceLODFiltersModule.h"
#include "vtkMeshFileReader.h"

class SURFACELODFILTERS_EXPORT vtkPLYMeshReader : public vtkMeshFileReader
{
public:
  static vtkPLYMeshReader* New();
  vtkTypeMacro(vtkPLYMeshReader, vtkMeshFileReader);

protected:
  vtkPLYMeshReader() = default;
  ~vtkPLYMeshReader() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkPLYMeshReader(const vtkPLYMeshReader&) = delete;
  void operator=(const vtkPLYMeshReader&) = delete;
};

#endif
