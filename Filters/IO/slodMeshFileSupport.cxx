// SPDX-License-Identifier: BSD-3-Clause
#include "slodMeshFileSupport.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkPolyData.h"

#include <fstream>
#include <sstream>

namespace slod
{
vtkDataArray* FileNormals(vtkDataSetAttributes* data)
{
  vtkDataArray* normals = data ? data->GetNormals() : nullptr;
  return normals && normals->GetNumberOfComponents() == 3 ? normals : nullptr;
}

vtkDataArray* FileTextureCoordinates(vtkDataSetAttributes* data)
{
  vtkDataArray* tcoords = data ? data->GetTCoords() : nullptr;
  return tcoords && tcoords->GetNumberOfComponents() == 2 ? tcoords : nullptr;
}

vtkDataArray* FileColors(vtkDataSetAttributes* data)
{
  vtkDataArray* scalars = data ? data->GetScalars() : nullptr;
  const bool colors = scalars && scalars->GetDataType() == VTK_UNSIGNED_CHAR &&
    (scalars->GetNumberOfComponents() == 3 || scalars->GetNumberOfComponents() == 4);
  return colors ? scalars : nullptr;
}

void ForEachSurfaceFace(vtkPolyData* mesh, const FaceVisitor& visit)
{
  vtkIdType cell = mesh->GetNumberOfVerts() + mesh->GetNumberOfLines();
  auto polygons = vtk::TakeSmartPointer(mesh->GetPolys()->NewIterator());
  for (polygons->GoToFirstCell(); !polygons->IsDoneWithTraversal(); polygons->GoToNextCell(), ++cell)
  {
    vtkIdType n;
    const vtkIdType* ids;
    polygons->GetCurrentCell(n, ids);
    visit(n, ids, cell);
  }
  auto strips = vtk::TakeSmartPointer(mesh->GetStrips()->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell(), ++cell)
  {
    vtkIdType n;
    const vtkIdType* ids;
    strips->GetCurrentCell(n, ids);
    for (vtkIdType k = 0; k + 2 < n; ++k)
    {
      const vtkIdType triangle[3] = { ids[k], ids[k + 1 + (k & 1)], ids[k + 2 - (k & 1)] };
      visit(3, triangle, cell);
    }
  }
}

vtkIdType CountSurfaceFaces(vtkPolyData* mesh)
{
  vtkIdType faces = mesh->GetPolys()->GetNumberOfCells();
  auto strips = vtk::TakeSmartPointer(mesh->GetStrips()->NewIterator());
  for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    strips->GetCurrentCell(n, ids);
    faces += n > 2 ? n - 2 : 0;
  }
  return faces;
}

std::vector<std::string> SplitWords(const std::string& line)
{
  std::vector<std::string> words;
  std::istringstream in(line);
  std::string word;
  while (in >> word)
  {
    words.push_back(word);
  }
  return words;
}

bool ReadWholeFile(const std::string& path, std::string& bytes)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    return false;
  }
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad())
  {
    return false;
  }
  bytes = contents.str();
  return true;
}
} // namespace slod
