// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPLYMeshWriter.h"

#include "slodCheckedFile.h"
#include "slodMeshFileSupport.h"
#include "slodPlyFormat.h"

#include "vtkBitArray.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdint>
#include <cstring>
#include <set>
#include <type_traits>
#include <vector>

vtkStandardNewMacro(vtkPLYMeshWriter);

namespace
{
// One property of an element: a component of an array, written as a PLY type.
struct PlyColumn
{
  vtkDataArray* Array = nullptr;
  int Component = 0;
  int PlyType = VTK_FLOAT; // a VTK type with a PLY equivalent
  std::string Name;
};

// The PLY type that holds every value of the array: its own, or for 64-bit integers int when every
// value fits, else double.
int PlyTypeForArray(vtkDataArray* array)
{
  const int own = slod::PlyScalarTypeOfVTK(array->GetDataType()).VTKType;
  if (own != VTK_VOID)
  {
    return own;
  }
  for (int c = 0; c < array->GetNumberOfComponents(); ++c)
  {
    double range[2];
    array->GetRange(range, c);
    if (range[0] < INT_MIN || range[1] > INT_MAX)
    {
      return VTK_DOUBLE;
    }
  }
  return VTK_INT;
}

int RealPlyType(vtkDataArray* array)
{
  return array->GetDataType() == VTK_DOUBLE ? VTK_DOUBLE : VTK_FLOAT;
}

void AddNamedColumns(std::vector<PlyColumn>& columns, vtkDataArray* array, int plyType,
  const std::vector<std::string>& names)
{
  for (size_t k = 0; k < names.size() && int(k) < array->GetNumberOfComponents(); ++k)
  {
    columns.push_back({ array, static_cast<int>(k), plyType, names[k] });
  }
}

// Names the reader gives a role: never used for a plain array.
std::set<std::string> ReservedNames()
{
  std::set<std::string> reserved = { "vertex_indices", "vertex_index" };
  for (const auto* names : { &slod::PlyCoordinateNames(), &slod::PlyNormalNames(), &slod::PlyColorNames() })
  {
    reserved.insert(names->begin(), names->end());
  }
  for (const auto& names : slod::PlyTextureNames())
  {
    reserved.insert(names.begin(), names.end());
  }
  return reserved;
}

// The array's name with white space as '_'; an unnamed array is named after its role or its index.
std::string PropertyBaseName(vtkDataSetAttributes* data, int index)
{
  const char* name = data->GetArrayName(index);
  const int role = data->IsArrayAnAttribute(index);
  std::string base = name && *name ? name
    : role >= 0                    ? vtkDataSetAttributes::GetAttributeTypeAsString(role)
                                   : "array" + std::to_string(index);
  std::transform(base.begin(), base.end(), base.begin(),
    [](unsigned char c) { return std::isspace(c) || !std::isprint(c) ? '_' : static_cast<char>(c); });
  if (!name || !*name)
  {
    std::transform(base.begin(), base.end(), base.begin(), [](unsigned char c) { return std::tolower(c); });
  }
  return base;
}

// Property names of a plain array: BASE, or BASE_0, BASE_1, ... for several components; a base name
// taken already (or reserved for a role) gets "_array" appended until it is free.
std::vector<std::string> PlainPropertyNames(std::string base, int components, std::set<std::string>& used)
{
  auto taken = [&](const std::string& candidate) {
    if (components == 1)
    {
      return used.count(candidate) > 0;
    }
    for (int k = 0; k < components; ++k)
    {
      if (used.count(candidate + "_" + std::to_string(k)))
      {
        return true;
      }
    }
    return false;
  };
  while (taken(base))
  {
    base += "_array";
  }
  std::vector<std::string> names;
  for (int k = 0; k < components; ++k)
  {
    names.push_back(components == 1 ? base : base + "_" + std::to_string(k));
    used.insert(names.back());
  }
  return names;
}

// The properties of an element: the points (vertex element only), the arrays with a PLY role, then
// every other array the writer can keep.
std::vector<PlyColumn> ElementColumns(vtkDataSetAttributes* data, vtkPoints* points)
{
  std::vector<PlyColumn> columns;
  std::vector<vtkDataArray*> taken;
  if (points)
  {
    AddNamedColumns(columns, points->GetData(), points->GetDataType() == VTK_FLOAT ? VTK_FLOAT : VTK_DOUBLE,
      slod::PlyCoordinateNames());
  }
  if (vtkDataArray* normals = slod::FileNormals(data))
  {
    AddNamedColumns(columns, normals, RealPlyType(normals), slod::PlyNormalNames());
    taken.push_back(normals);
  }
  if (vtkDataArray* tcoords = slod::FileTextureCoordinates(data))
  {
    AddNamedColumns(columns, tcoords, RealPlyType(tcoords), slod::PlyTextureNames()[0]);
    taken.push_back(tcoords);
  }
  if (vtkDataArray* colors = slod::FileColors(data))
  {
    AddNamedColumns(columns, colors, VTK_UNSIGNED_CHAR, slod::PlyColorNames());
    taken.push_back(colors);
  }
  std::set<std::string> used = ReservedNames();
  for (int a = 0; a < data->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = data->GetArray(a);
    if (!array || std::find(taken.begin(), taken.end(), array) != taken.end() ||
      !vtkPLYMeshWriter::CanWriteArray(array))
    {
      continue;
    }
    const std::vector<std::string> names =
      PlainPropertyNames(PropertyBaseName(data, a), array->GetNumberOfComponents(), used);
    AddNamedColumns(columns, array, PlyTypeForArray(array), names);
  }
  return columns;
}

// The faces to write: polygons as they are, strips as triangles, each with the cell it comes from.
struct PlyFaces
{
  vtkNew<vtkCellArray> Cells;
  std::vector<vtkIdType> SourceCell;
  vtkIdType LargestFace = 0;
};

void CollectFaces(vtkPolyData* input, PlyFaces& faces)
{
  slod::ForEachSurfaceFace(input, [&](vtkIdType n, const vtkIdType* ids, vtkIdType cell) {
    faces.Cells->InsertNextCell(n, ids);
    faces.SourceCell.push_back(cell);
    faces.LargestFace = std::max(faces.LargestFace, n);
  });
}

std::string HeaderText(bool ascii, bool bigEndian, vtkIdType vertexCount, const std::vector<PlyColumn>& vertexColumns,
  const PlyFaces& faces, const std::vector<PlyColumn>& faceColumns)
{
  std::string header = "ply\nformat ";
  header += ascii ? "ascii" : bigEndian ? "binary_big_endian" : "binary_little_endian";
  header += " 1.0\ncomment written by SurfaceLOD vtkPLYMeshWriter\nelement vertex " + std::to_string(vertexCount) + "\n";
  for (const PlyColumn& column : vertexColumns)
  {
    header += "property " + std::string(slod::PlyScalarTypeName(column.PlyType)) + " " + column.Name + "\n";
  }
  header += "element face " + std::to_string(faces.SourceCell.size()) + "\n";
  header += faces.LargestFace > 255 ? "property list int int vertex_indices\n" : "property list uchar int vertex_indices\n";
  for (const PlyColumn& column : faceColumns)
  {
    header += "property " + std::string(slod::PlyScalarTypeName(column.PlyType)) + " " + column.Name + "\n";
  }
  return header + "end_header\n";
}

// Values of one element in the file's encoding.
class PlyValueWriter
{
public:
  PlyValueWriter(slod::CheckedFileWriter& file, bool ascii, bool bigEndian)
    : File(file)
    , Ascii(ascii)
    , Swap(bigEndian != IsHostBigEndian())
  {
  }

  void Write(double value, int plyType, bool last)
  {
    switch (plyType)
    {
      case VTK_SIGNED_CHAR: this->Put(static_cast<std::int8_t>(value)); break;
      case VTK_UNSIGNED_CHAR: this->Put(static_cast<std::uint8_t>(value)); break;
      case VTK_SHORT: this->Put(static_cast<std::int16_t>(value)); break;
      case VTK_UNSIGNED_SHORT: this->Put(static_cast<std::uint16_t>(value)); break;
      case VTK_INT: this->Put(static_cast<std::int32_t>(value)); break;
      case VTK_UNSIGNED_INT: this->Put(static_cast<std::uint32_t>(value)); break;
      case VTK_FLOAT: this->Put(static_cast<float>(value)); break;
      default: this->Put(value); break;
    }
    if (this->Ascii)
    {
      this->File.WriteChar(last ? '\n' : ' ');
    }
  }

private:
  static bool IsHostBigEndian()
  {
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    return first == 0;
  }

  template <typename T>
  void Put(T value)
  {
    if (this->Ascii)
    {
      if constexpr (std::is_floating_point<T>::value)
      {
        this->File.WriteReal(value);
      }
      else
      {
        this->File.WriteInteger(static_cast<long long>(value));
      }
      return;
    }
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (this->Swap)
    {
      std::reverse(bytes, bytes + sizeof(T));
    }
    this->File.WriteBytes(bytes, sizeof(T));
  }

  slod::CheckedFileWriter& File;
  bool Ascii;
  bool Swap;
};

void WriteRow(PlyValueWriter& values, const std::vector<PlyColumn>& columns, vtkIdType row)
{
  for (size_t c = 0; c < columns.size(); ++c)
  {
    const PlyColumn& column = columns[c];
    values.Write(column.Array->GetComponent(row, column.Component), column.PlyType, c + 1 == columns.size());
  }
}

void WriteFaces(PlyValueWriter& values, const PlyFaces& faces, const std::vector<PlyColumn>& columns)
{
  const int countType = faces.LargestFace > 255 ? VTK_INT : VTK_UNSIGNED_CHAR;
  auto it = vtk::TakeSmartPointer(faces.Cells->NewIterator());
  size_t face = 0;
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++face)
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    values.Write(static_cast<double>(n), countType, false);
    for (vtkIdType k = 0; k < n; ++k)
    {
      values.Write(static_cast<double>(ids[k]), VTK_INT, k + 1 == n && columns.empty());
    }
    WriteRow(values, columns, faces.SourceCell[face]);
  }
}
} // namespace

bool vtkPLYMeshWriter::CanWriteArray(vtkAbstractArray* array)
{
  return vtkDataArray::SafeDownCast(array) && !vtkBitArray::SafeDownCast(array) &&
    array->GetNumberOfComponents() > 0;
}

void vtkPLYMeshWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileType: " << (this->FileType == VTK_ASCII ? "ASCII" : "Binary") << "\n";
  os << indent << "BigEndian: " << this->BigEndian << "\n";
}

std::string vtkPLYMeshWriter::WriteMesh(vtkPolyData* input, slod::CheckedFileWriter& file)
{
  if (!input->GetPoints())
  {
    return "no points to write";
  }
  if (input->GetNumberOfPoints() > INT_MAX)
  {
    return "more points than PLY's int vertex indices can refer to";
  }
  PlyFaces faces;
  CollectFaces(input, faces);
  const std::vector<PlyColumn> vertexColumns = ElementColumns(input->GetPointData(), input->GetPoints());
  const std::vector<PlyColumn> faceColumns = ElementColumns(input->GetCellData(), nullptr);
  const bool ascii = this->FileType == VTK_ASCII;
  file.WriteText(HeaderText(ascii, this->BigEndian, input->GetNumberOfPoints(), vertexColumns, faces, faceColumns));
  PlyValueWriter values(file, ascii, this->BigEndian);
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    WriteRow(values, vertexColumns, i);
  }
  WriteFaces(values, faces, faceColumns);
  return std::string();
}
