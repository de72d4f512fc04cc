// SPDX-License-Identifier: BSD-3-Clause
#include "vtkOFFMeshWriter.h"

#include "slodCheckedFile.h"
#include "slodMeshFileSupport.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <string>

vtkStandardNewMacro(vtkOFFMeshWriter);

namespace
{
// The optional vertex columns of the file: normals (N), colours (C), texture coordinates (ST).
struct OffVertexArrays
{
  vtkDataArray* Normals = nullptr;
  vtkDataArray* Colors = nullptr;
  vtkDataArray* TCoords = nullptr;
  bool FractionalColors = false; // every colour value is 0 or 1: written as floats 0-1 (see the reader)

  std::string Keyword() const
  {
    return std::string(this->TCoords ? "ST" : "") + (this->Colors ? "C" : "") + (this->Normals ? "N" : "") + "OFF";
  }
};

// Colours of only 0 and 1 are written as fractions 0-1 (as integers the reader would take them
// for floats 0-1, see the reader).
bool HasFractionalColors(vtkDataArray* colors)
{
  double largest = 0;
  for (int c = 0; colors && c < colors->GetNumberOfComponents(); ++c)
  {
    largest = std::max(largest, colors->GetRange(c)[1]);
  }
  return largest <= 1;
}

OffVertexArrays FindOffVertexArrays(vtkPolyData* input)
{
  OffVertexArrays arrays;
  arrays.Normals = slod::FileNormals(input->GetPointData());
  arrays.Colors = slod::FileColors(input->GetPointData());
  arrays.TCoords = slod::FileTextureCoordinates(input->GetPointData());
  arrays.FractionalColors = arrays.Colors && HasFractionalColors(arrays.Colors);
  return arrays;
}

// The components of one tuple, each after a space, in the array's precision.
void WriteTuple(slod::CheckedFileWriter& file, vtkDataArray* array, vtkIdType i)
{
  for (int c = 0; c < array->GetNumberOfComponents(); ++c)
  {
    file.WriteChar(' ');
    const double value = array->GetComponent(i, c);
    array->GetDataType() == VTK_FLOAT ? file.WriteReal(static_cast<float>(value)) : file.WriteReal(value);
  }
}

void WriteColor(slod::CheckedFileWriter& file, vtkDataArray* colors, bool fractional, vtkIdType i)
{
  for (int c = 0; c < colors->GetNumberOfComponents(); ++c)
  {
    file.WriteChar(' ');
    const double value = colors->GetComponent(i, c);
    fractional ? file.WriteReal(value / 255.0) : file.WriteInteger(static_cast<long long>(value));
  }
}

void WriteVertices(slod::CheckedFileWriter& file, vtkPolyData* input, const OffVertexArrays& arrays)
{
  vtkDataArray* coordinates = input->GetPoints() ? input->GetPoints()->GetData() : nullptr;
  const bool floatPoints = coordinates && coordinates->GetDataType() == VTK_FLOAT;
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    double p[3];
    coordinates->GetTuple(i, p);
    for (int a = 0; a < 3; ++a)
    {
      if (a > 0)
      {
        file.WriteChar(' ');
      }
      floatPoints ? file.WriteReal(static_cast<float>(p[a])) : file.WriteReal(p[a]);
    }
    if (arrays.Normals)
    {
      WriteTuple(file, arrays.Normals, i);
    }
    if (arrays.Colors)
    {
      WriteColor(file, arrays.Colors, arrays.FractionalColors, i);
    }
    if (arrays.TCoords)
    {
      WriteTuple(file, arrays.TCoords, i);
    }
    file.WriteChar('\n');
  }
}

// A face's indices, then its cell's colour when the cells have colours (r g b [a] after the indices).
void WriteFace(slod::CheckedFileWriter& file, vtkIdType n, const vtkIdType* ids, vtkDataArray* colors,
  bool fractional, vtkIdType cell)
{
  file.WriteInteger(n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    file.WriteChar(' ');
    file.WriteInteger(ids[k]);
  }
  if (colors)
  {
    WriteColor(file, colors, fractional, cell);
  }
  file.WriteChar('\n');
}

} // namespace

std::string vtkOFFMeshWriter::WriteMesh(vtkPolyData* input, slod::CheckedFileWriter& file)
{
  const OffVertexArrays arrays = FindOffVertexArrays(input);
  file.WriteText(arrays.Keyword() + "\n" + std::to_string(input->GetNumberOfPoints()) + " " +
    std::to_string(slod::CountSurfaceFaces(input)) + " 0\n");
  WriteVertices(file, input, arrays);
  vtkDataArray* faceColors = slod::FileColors(input->GetCellData());
  const bool fractional = faceColors && HasFractionalColors(faceColors);
  slod::ForEachSurfaceFace(input, [&](vtkIdType n, const vtkIdType* ids, vtkIdType cell) {
    WriteFace(file, n, ids, faceColors, fractional, cell);
  });
  return std::string();
}
