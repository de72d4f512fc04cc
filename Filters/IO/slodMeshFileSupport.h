// SPDX-License-Identifier: BSD-3-Clause
// What the mesh file readers and writers of Filters/IO share. The point / cell arrays the writers of Filters/IO give a role in their format
// (OFF's N, C and ST columns, PLY's nx / red / u properties, OBJ's vn and vt lines): one rule,
// so the writers and the tool's warning about dropped arrays agree.
#ifndef slodMeshFileSupport_h
#define slodMeshFileSupport_h

#include "vtkType.h"

#include <functional>
#include <string>
#include <string_view>
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

// The white-space separated words of a line of a text mesh file, as views into the line (no copies:
// the readers split millions of lines). `words` is cleared first.
void SplitWords(std::string_view line, std::vector<std::string_view>& words);

// A whole decimal number / a decimal real number (an optional leading '+'; "nan" and "inf" are
// reals, hexadecimal forms are not), the whole word or false. Independent of the C locale, unlike
// strtod, which reads "0,5" for one half in a German locale.
bool ParseInteger(std::string_view word, long long& value);
bool ParseReal(std::string_view word, double& value);

// Reads a whole file into memory; false (and errno set) when it cannot be read.
bool ReadWholeFile(const std::string& path, std::string& bytes);
} // namespace slod

#endif
