// SPDX-License-Identifier: BSD-3-Clause
// What vtkPLYMeshReader and vtkPLYMeshWriter share: the PLY scalar types and their VTK array types,
// and the vertex / face properties that carry an attribute role (coordinates, normals, colours,
// texture coordinates) rather than a plain named array.
#ifndef slodPlyFormat_h
#define slodPlyFormat_h

#include "vtkType.h"

#include <string>
#include <vector>

namespace slod
{
enum class PlyEncoding
{
  Ascii,
  BinaryLittleEndian,
  BinaryBigEndian
};

struct PlyScalarType
{
  int VTKType = VTK_VOID; // VTK_SIGNED_CHAR .. VTK_DOUBLE; VTK_VOID: not a PLY type
  int Size = 0;           // bytes in a binary file
  bool IsInteger() const { return this->VTKType != VTK_FLOAT && this->VTKType != VTK_DOUBLE; }
};

// "char", "uchar", ..., "double" and their sized aliases ("int8" ... "float64"); false otherwise.
bool PlyScalarTypeFromName(const std::string& name, PlyScalarType& type);

// The PLY type for values of a VTK array type (64-bit and id types have none: VTK_VOID), and its name.
PlyScalarType PlyScalarTypeOfVTK(int vtkType);
const char* PlyScalarTypeName(int vtkType);

// Property names of the attribute roles, in file order. Texture coordinates have several spellings.
const std::vector<std::string>& PlyCoordinateNames();           // x y z
const std::vector<std::string>& PlyNormalNames();               // nx ny nz
const std::vector<std::string>& PlyColorNames();                // red green blue alpha
const std::vector<std::vector<std::string>>& PlyTextureNames(); // {u v} {s t} {texture_u texture_v} ...
} // namespace slod

#endif
