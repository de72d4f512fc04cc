// SPDX-License-Identifier: BSD-3-Clause
// The point / cell arrays the mesh file writers of Filters/IO give a role in their format
// (OFF's N, C and ST columns, PLY's nx / red / u properties, OBJ's vn and vt lines): one rule,
// so the writers and the tool's warning about dropped arrays agree.
#ifndef slodMeshFileArrays_h
#define slodMeshFileArrays_h

#include "vtkType.h"

#include <functional>

class vtkDataArray;
class vtkDataSetAttributes;
class vtkPolyData;

namespace slod
{
// The normals of three components, or nullptr.
vtkDataArray* FileNormals(vtkDataSetAttributes* data);
// The texture coordinates of two components, or nullptr.
vtkDataArray* FileTextureCoordinates(vtkDataSetAttributes* data);
// The scalars when they are unsigned char colours of three or four components (RGB, RGBA), or nullptr.
vtkDataArray* FileColors(vtkDataSetAttributes* data);

// The faces a mesh file holds: every polygon as it is, then every triangle of every strip (its
// winding alternated so each keeps the strip's orientation). `visit` gets the face's size, point
// ids and the id of the cell it comes from (cell data rows).
using FaceVisitor = std::function<void(vtkIdType size, const vtkIdType* ids, vtkIdType cell)>;
void ForEachSurfaceFace(vtkPolyData* mesh, const FaceVisitor& visit);
vtkIdType CountSurfaceFaces(vtkPolyData* mesh);
} // namespace slod

#endif
