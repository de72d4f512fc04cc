// SPDX-License-Identifier: BSD-3-Clause
// What the mesh file readers and writers of Filters/IO share. The point / cell arrays the writers of Filters/IO give a role in their format
// (OFF's N, C and ST columns, PLY's nx / red / u properties, OBJ's vn and vt lines): one rule,
// so the writers and the tool's warning about dropped arrays agree.
#ifndef slodMeshFileSupport_h
#define slodMeshFileSupport_h

#include "vtkType.h"

#include <functional>
#include <string>
#include <vector>

class vtkDataArray;
class vtkDataSetAttributes;
class vtkPolyData;

namespace slod
{
// A failure of one stage of a mesh file reader: message, VTK error code (vtkErrorCode), line (0: none).
struct MeshFileProblem
{
  std::string Message;
  unsigned long Code = 0; // vtkErrorCode::NoError
  long long Line = 0;
  explicit operator bool() const { return this->Code != 0; }
};

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

// The white-space separated words of a line of a text mesh file.
std::vector<std::string> SplitWords(const std::string& line);

// Reads a whole file into memory; false (and errno set) when it cannot be read.
bool ReadWholeFile(const std::string& path, std::string& bytes);
} // namespace slod

#endif
