// SPDX-License-Identifier: BSD-3-Clause
#include "slodMeshFileSupport.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkPolyData.h"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <filesystem>

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

namespace
{
bool IsWordSeparator(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

// The number of from_chars without its one refusal that files use: a leading '+'.
template <typename T>
bool ParseWhole(std::string_view word, T& value)
{
  const char* first = word.data() + (!word.empty() && word[0] == '+' ? 1 : 0);
  const char* last = word.data() + word.size();
  if (first == last || (*first == '-' && first != word.data()))
  {
    return false; // "+" alone, "+-1"
  }
  const auto parsed = std::from_chars(first, last, value);
  return parsed.ec == std::errc() && parsed.ptr == last;
}
} // namespace

void SplitWords(std::string_view line, std::vector<std::string_view>& words)
{
  words.clear();
  size_t at = 0;
  while (at < line.size())
  {
    while (at < line.size() && IsWordSeparator(line[at]))
    {
      ++at;
    }
    const size_t start = at;
    while (at < line.size() && !IsWordSeparator(line[at]))
    {
      ++at;
    }
    if (at > start)
    {
      words.push_back(line.substr(start, at - start));
    }
  }
}

bool ParseInteger(std::string_view word, long long& value)
{
  return ParseWhole(word, value);
}

bool ParseReal(std::string_view word, double& value)
{
  return ParseWhole(word, value);
}

bool ReadWholeFile(const std::string& path, std::string& bytes)
{
  // One allocation of the file's size and one read: a string stream would hold the file twice.
  FILE* file = std::fopen(path.c_str(), "rb");
  if (!file)
  {
    return false;
  }
  std::string contents;
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec))
  {
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    contents.reserve(ec ? 0 : static_cast<size_t>(size));
  }
  char chunk[1 << 16];
  size_t got;
  while ((got = std::fread(chunk, 1, sizeof(chunk), file)) > 0)
  {
    contents.append(chunk, got);
  }
  const bool failed = std::ferror(file) != 0;
  const int readErrno = errno;
  std::fclose(file);
  if (failed)
  {
    errno = readErrno;
    return false;
  }
  bytes.swap(contents);
  return true;
}
} // namespace slod
