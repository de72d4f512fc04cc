// SPDX-License-Identifier: BSD-3-Clause
#include "vtkOBJMeshWriter.h"

#include "slodCheckedFile.h"
#include "slodMeshFileSupport.h"

#include "vtkDataArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

vtkStandardNewMacro(vtkOBJMeshWriter);

namespace
{
// " c0 c1 ..." of one tuple, in the array's precision, each divided by `scale`.
void WriteTuple(slod::CheckedFileWriter& file, vtkDataArray* array, vtkIdType i, double scale = 1.0)
{
  const bool single = array->GetDataType() == VTK_FLOAT;
  for (int c = 0; c < array->GetNumberOfComponents(); ++c)
  {
    file.WriteChar(' ');
    const double value = array->GetComponent(i, c) / scale;
    single ? file.WriteReal(static_cast<float>(value)) : file.WriteReal(value);
  }
}

// "KEYWORD c0 c1 ..." for every tuple of the array.
void WriteTupleLines(slod::CheckedFileWriter& file, const char* keyword, vtkDataArray* array)
{
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
  {
    file.WriteText(keyword);
    WriteTuple(file, array, i);
    file.WriteChar('\n');
  }
}

// "v x y z", with the point's colour as r g b [a] in 0-1 when the points have colours (the
// common extension MeshLab and others read).
void WriteVertexLines(slod::CheckedFileWriter& file, vtkDataArray* coordinates, vtkDataArray* colours)
{
  for (vtkIdType i = 0; i < coordinates->GetNumberOfTuples(); ++i)
  {
    file.WriteChar('v');
    WriteTuple(file, coordinates, i);
    if (colours)
    {
      WriteTuple(file, colours, i, 255.0);
    }
    file.WriteChar('\n');
  }
}

// "f" with corners v, v/vt, v//vn or v/vt/vn: one number for all three (1-based).
void WriteFace(slod::CheckedFileWriter& file, vtkIdType n, const vtkIdType* ids, bool tcoords, bool normals)
{
  file.WriteChar('f');
  for (vtkIdType k = 0; k < n; ++k)
  {
    const long long number = static_cast<long long>(ids[k]) + 1;
    file.WriteChar(' ');
    file.WriteInteger(number);
    if (tcoords || normals)
    {
      file.WriteChar('/');
    }
    if (tcoords)
    {
      file.WriteInteger(number);
    }
    if (normals)
    {
      file.WriteChar('/');
      file.WriteInteger(number);
    }
  }
  file.WriteChar('\n');
}
} // namespace

std::string vtkOBJMeshWriter::WriteMesh(vtkPolyData* input, slod::CheckedFileWriter& file)
{
  vtkDataArray* tcoords = slod::FileTextureCoordinates(input->GetPointData());
  vtkDataArray* normals = slod::FileNormals(input->GetPointData());
  file.WriteText("# written by SurfaceLOD vtkOBJMeshWriter\n");
  if (input->GetPoints())
  {
    WriteVertexLines(file, input->GetPoints()->GetData(), slod::FileColors(input->GetPointData()));
  }
  if (tcoords)
  {
    WriteTupleLines(file, "vt", tcoords);
  }
  if (normals)
  {
    WriteTupleLines(file, "vn", normals);
  }
  slod::ForEachSurfaceFace(input, [&](vtkIdType n, const vtkIdType* ids, vtkIdType) {
    WriteFace(file, n, ids, tcoords != nullptr, normals != nullptr);
  });
  return std::string();
}
