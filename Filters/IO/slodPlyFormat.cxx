// SPDX-License-Identifier: BSD-3-Clause
#include "slodPlyFormat.h"

namespace slod
{
namespace
{
struct NamedPlyType
{
  const char* Name;
  PlyScalarType Type;
};

const NamedPlyType KnownPlyTypes[] = { { "char", { VTK_SIGNED_CHAR, 1 } }, { "uchar", { VTK_UNSIGNED_CHAR, 1 } },
  { "short", { VTK_SHORT, 2 } }, { "ushort", { VTK_UNSIGNED_SHORT, 2 } }, { "int", { VTK_INT, 4 } },
  { "uint", { VTK_UNSIGNED_INT, 4 } }, { "float", { VTK_FLOAT, 4 } }, { "double", { VTK_DOUBLE, 8 } },
  { "int8", { VTK_SIGNED_CHAR, 1 } }, { "uint8", { VTK_UNSIGNED_CHAR, 1 } }, { "int16", { VTK_SHORT, 2 } },
  { "uint16", { VTK_UNSIGNED_SHORT, 2 } }, { "int32", { VTK_INT, 4 } }, { "uint32", { VTK_UNSIGNED_INT, 4 } },
  { "float32", { VTK_FLOAT, 4 } }, { "float64", { VTK_DOUBLE, 8 } } };
} // namespace

bool PlyScalarTypeFromName(const std::string& name, PlyScalarType& type)
{
  for (const NamedPlyType& known : KnownPlyTypes)
  {
    if (name == known.Name)
    {
      type = known.Type;
      return true;
    }
  }
  return false;
}

PlyScalarType PlyScalarTypeOfVTK(int vtkType)
{
  // VTK_CHAR is signed on the platforms VTK supports for PLY data.
  const int wanted = vtkType == VTK_CHAR ? VTK_SIGNED_CHAR : vtkType;
  for (const NamedPlyType& known : KnownPlyTypes)
  {
    if (known.Type.VTKType == wanted)
    {
      return known.Type;
    }
  }
  return PlyScalarType();
}

const char* PlyScalarTypeName(int vtkType)
{
  const int wanted = PlyScalarTypeOfVTK(vtkType).VTKType;
  for (const NamedPlyType& known : KnownPlyTypes)
  {
    if (known.Type.VTKType == wanted)
    {
      return known.Name; // the first spelling: the classic names
    }
  }
  return "";
}

const std::vector<std::string>& PlyCoordinateNames()
{
  static const std::vector<std::string> names = { "x", "y", "z" };
  return names;
}

const std::vector<std::string>& PlyNormalNames()
{
  static const std::vector<std::string> names = { "nx", "ny", "nz" };
  return names;
}

const std::vector<std::string>& PlyColorNames()
{
  static const std::vector<std::string> names = { "red", "green", "blue", "alpha" };
  return names;
}

const std::vector<std::vector<std::string>>& PlyTextureNames()
{
  static const std::vector<std::vector<std::string>> names = { { "u", "v" }, { "s", "t" },
    { "texture_u", "texture_v" }, { "texture_s", "texture_t" } };
  return names;
}
} // namespace slod
