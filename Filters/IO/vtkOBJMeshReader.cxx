// SPDX-License-Identifier: BSD-3-Clause
#include "vtkOBJMeshReader.h"

#include "slodMeshFileSupport.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <string_view>
#include <tuple>
#include <vector>

vtkStandardNewMacro(vtkOBJMeshReader);

namespace
{
using ObjProblem = slod::MeshFileProblem;

// One corner of a face: 0-based position, texture coordinate and normal numbers (-1: none).
struct ObjCorner
{
  long long Position = -1, Texture = -1, Normal = -1;
  bool operator<(const ObjCorner& o) const
  {
    return std::tie(this->Position, this->Texture, this->Normal) < std::tie(o.Position, o.Texture, o.Normal);
  }
  bool operator==(const ObjCorner& o) const
  {
    return this->Position == o.Position && this->Texture == o.Texture && this->Normal == o.Normal;
  }
};

// The file as read: the three index spaces and the faces' corners.
struct ObjContent
{
  std::vector<double> Positions, Textures, Normals; // 3, 2 and 3 values per item
  std::vector<ObjCorner> Corners;
  std::vector<vtkIdType> FaceSizes;
  std::vector<long long> FaceLines;
  // "v x y z r g b [a]" colours (0-1), read when every "v" line has the same number of them.
  std::vector<double> Colours;
  int ColourComponents = 0;
  long long VertexColours = 0;   // "v" lines with a colour
  bool ColoursReadable = true;    // same count on every coloured line, each value in 0-1
  std::map<std::string, long long> Unread; // other statements not read, by keyword
};

using Words = std::vector<std::string_view>;

// A finite decimal number (a leading '+' allowed; no "nan", "inf" or hexadecimal forms).
bool ParseFinite(std::string_view word, double& value)
{
  return slod::ParseReal(word, value) && std::isfinite(value);
}

// Numbers words[1..count] appended to `values` (the missing ones of an optional tail as 0).
bool AppendNumbers(const Words& words, size_t count, std::vector<double>& values)
{
  for (size_t k = 1; k <= count; ++k)
  {
    double value = 0;
    if (k < words.size() && !ParseFinite(words[k], value))
    {
      return false;
    }
    values.push_back(value);
  }
  return true;
}

// An OBJ index (1-based, or negative: counted back from the items defined so far) as 0-based.
bool ParseIndex(std::string_view text, long long definedSoFar, long long& index)
{
  long long value = 0;
  const auto parsed = std::from_chars(text.data(), text.data() + text.size(), value);
  if (parsed.ec != std::errc() || parsed.ptr != text.data() + text.size() || value == 0)
  {
    return false;
  }
  index = value > 0 ? value - 1 : definedSoFar + value;
  return index >= 0; // a negative number reaching before the first item is malformed
}

// "v", "v/vt", "v//vn" or "v/vt/vn".
bool ParseCorner(std::string_view word, const ObjContent& content, ObjCorner& corner)
{
  const size_t slash = word.find('/');
  const size_t second = slash == std::string_view::npos ? std::string_view::npos : word.find('/', slash + 1);
  const std::string_view position = word.substr(0, slash);
  const std::string_view texture = slash == std::string_view::npos
    ? std::string_view()
    : word.substr(slash + 1, second == std::string_view::npos ? std::string_view::npos : second - slash - 1);
  const std::string_view normal = second == std::string_view::npos ? std::string_view() : word.substr(second + 1);
  bool ok = ParseIndex(position, static_cast<long long>(content.Positions.size() / 3), corner.Position);
  ok = ok && (texture.empty() || ParseIndex(texture, static_cast<long long>(content.Textures.size() / 2), corner.Texture));
  ok = ok && (normal.empty() || ParseIndex(normal, static_cast<long long>(content.Normals.size() / 3), corner.Normal));
  // "v/" or "v//" without a normal is malformed.
  return ok && !(slash != std::string_view::npos && texture.empty() && normal.empty());
}

ObjProblem ReadFace(const Words& words, long long line, ObjContent& content)
{
  if (words.size() < 4)
  {
    return { "face of fewer than three corners", vtkErrorCode::FileFormatError, line };
  }
  for (size_t k = 1; k < words.size(); ++k)
  {
    ObjCorner corner;
    if (!ParseCorner(words[k], content, corner))
    {
      return { "malformed face corner '" + std::string(words[k].substr(0, 40)) + "'", vtkErrorCode::FileFormatError,
        line };
    }
    content.Corners.push_back(corner);
  }
  content.FaceSizes.push_back(static_cast<vtkIdType>(words.size() - 1));
  content.FaceLines.push_back(line);
  return {};
}

// The r g b [a] after a vertex's coordinates (words 4...), kept while they are consistent.
ObjProblem ReadVertexColour(const Words& words, long long line, ObjContent& content)
{
  const int components = static_cast<int>(words.size()) - 4;
  ++content.VertexColours;
  content.ColoursReadable = content.ColoursReadable && (content.ColourComponents == 0 || components == content.ColourComponents);
  content.ColourComponents = components;
  for (size_t k = 4; k < words.size(); ++k)
  {
    double value = 0;
    if (!ParseFinite(words[k], value))
    {
      return { "vertex colour does not hold finite numbers", vtkErrorCode::FileFormatError, line };
    }
    content.ColoursReadable = content.ColoursReadable && value >= 0 && value <= 1;
    content.Colours.push_back(value);
  }
  return {};
}

ObjProblem ReadStatement(const Words& words, long long line, ObjContent& content)
{
  const std::string_view keyword = words[0];
  auto malformed = [&](const char* what) {
    return ObjProblem{ std::string(what) + " does not hold finite numbers", vtkErrorCode::FileFormatError, line };
  };
  if (keyword == "v")
  {
    // x y z, then an optional w or a colour r g b [a].
    if (words.size() < 4 || words.size() > 8 || !AppendNumbers(words, 3, content.Positions))
    {
      return malformed("vertex");
    }
    return words.size() >= 7 ? ReadVertexColour(words, line, content) : ObjProblem();
  }
  if (keyword == "vt")
  {
    return words.size() >= 2 && words.size() <= 4 && AppendNumbers(words, 2, content.Textures)
      ? ObjProblem()
      : malformed("texture coordinate");
  }
  if (keyword == "vn")
  {
    return words.size() == 4 && AppendNumbers(words, 3, content.Normals) ? ObjProblem() : malformed("normal");
  }
  if (keyword == "f")
  {
    return ReadFace(words, line, content);
  }
  static const char* const withoutGeometry[] = { "g", "o", "s", "usemtl", "mtllib", "mg" };
  for (const char* silent : withoutGeometry)
  {
    if (keyword == silent)
    {
      return {};
    }
  }
  ++content.Unread["'" + std::string(keyword) + "' statements"];
  return {};
}

// Every corner refers to an item the file defines.
ObjProblem CheckCornerIndices(const ObjContent& content)
{
  const long long counts[3] = { static_cast<long long>(content.Positions.size() / 3),
    static_cast<long long>(content.Textures.size() / 2), static_cast<long long>(content.Normals.size() / 3) };
  size_t corner = 0;
  for (size_t f = 0; f < content.FaceSizes.size(); ++f)
  {
    for (vtkIdType k = 0; k < content.FaceSizes[f]; ++k, ++corner)
    {
      const ObjCorner& c = content.Corners[corner];
      const long long indices[3] = { c.Position, c.Texture, c.Normal };
      static const char* const kinds[3] = { "vertex", "texture coordinate", "normal" };
      for (int kind = 0; kind < 3; ++kind)
      {
        const bool absent = kind > 0 && indices[kind] == -1;
        if (!absent && (indices[kind] < 0 || indices[kind] >= counts[kind]))
        {
          return { std::string("face refers to ") + kinds[kind] + " " + std::to_string(indices[kind] + 1) +
              " but the file has " + std::to_string(counts[kind]),
            vtkErrorCode::FileFormatError, content.FaceLines[f] };
        }
      }
    }
  }
  return {};
}

// One output point per distinct (position, texture, normal) combination: the first combination of a
// position keeps its number, the others are appended. Returns the point id of every corner.
std::vector<vtkIdType> AssignPoints(const ObjContent& content, std::vector<ObjCorner>& pointCorners)
{
  const size_t positions = content.Positions.size() / 3;
  pointCorners.assign(positions, ObjCorner());
  std::map<ObjCorner, vtkIdType> extra;
  std::vector<vtkIdType> ids;
  ids.reserve(content.Corners.size());
  for (const ObjCorner& corner : content.Corners)
  {
    ObjCorner& first = pointCorners[size_t(corner.Position)];
    if (first.Position < 0 || first == corner)
    {
      first = corner;
      ids.push_back(static_cast<vtkIdType>(corner.Position));
      continue;
    }
    auto inserted = extra.emplace(corner, static_cast<vtkIdType>(pointCorners.size()));
    if (inserted.second)
    {
      pointCorners.push_back(corner);
    }
    ids.push_back(inserted.first->second);
  }
  return ids;
}

bool HasReadableColours(const ObjContent& content)
{
  return content.VertexColours > 0 && content.ColoursReadable &&
    content.VertexColours == static_cast<long long>(content.Positions.size() / 3);
}

// Each output point's colour is its position's, as unsigned char RGB(A).
vtkSmartPointer<vtkUnsignedCharArray> PointColours(const ObjContent& content, const std::vector<ObjCorner>& pointCorners)
{
  const size_t positions = content.Positions.size() / 3;
  const int components = content.ColourComponents;
  auto colours = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colours->SetName(components == 4 ? "RGBA" : "RGB");
  colours->SetNumberOfComponents(components);
  colours->SetNumberOfTuples(static_cast<vtkIdType>(pointCorners.size()));
  for (size_t p = 0; p < pointCorners.size(); ++p)
  {
    const size_t position = p < positions ? p : size_t(pointCorners[p].Position);
    for (int c = 0; c < components; ++c)
    {
      colours->SetValue(static_cast<vtkIdType>(p * components + c),
        static_cast<unsigned char>(std::lround(255.0 * content.Colours[position * components + c])));
    }
  }
  return colours;
}

// The output: points (double), polygons, and texture coordinates / normals when any corner has them.
void BuildOutput(const ObjContent& content, vtkPolyData* output)
{
  std::vector<ObjCorner> pointCorners;
  const std::vector<vtkIdType> ids = AssignPoints(content, pointCorners);
  bool anyTexture = false, anyNormal = false;
  for (const ObjCorner& corner : content.Corners)
  {
    anyTexture = anyTexture || corner.Texture >= 0;
    anyNormal = anyNormal || corner.Normal >= 0;
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(pointCorners.size()));
  vtkNew<vtkDoubleArray> tcoords, normals;
  tcoords->SetName("TCoords");
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(anyTexture ? points->GetNumberOfPoints() : 0);
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(anyNormal ? points->GetNumberOfPoints() : 0);
  for (size_t p = 0; p < pointCorners.size(); ++p)
  {
    // A position no face uses keeps its own number and no attributes (zeros).
    const size_t position = p < content.Positions.size() / 3 ? p : size_t(pointCorners[p].Position);
    const ObjCorner& corner = pointCorners[p];
    points->SetPoint(static_cast<vtkIdType>(p), &content.Positions[3 * position]);
    const double none[3] = { 0, 0, 0 };
    if (anyTexture)
    {
      tcoords->SetTypedTuple(static_cast<vtkIdType>(p), corner.Texture >= 0 ? &content.Textures[2 * size_t(corner.Texture)] : none);
    }
    if (anyNormal)
    {
      normals->SetTypedTuple(static_cast<vtkIdType>(p), corner.Normal >= 0 ? &content.Normals[3 * size_t(corner.Normal)] : none);
    }
  }
  vtkNew<vtkCellArray> polys;
  size_t at = 0;
  for (vtkIdType size : content.FaceSizes)
  {
    polys->InsertNextCell(size, ids.data() + at);
    at += size_t(size);
  }
  output->SetPoints(points);
  output->SetPolys(polys);
  if (HasReadableColours(content))
  {
    output->GetPointData()->SetScalars(PointColours(content, pointCorners));
  }
  if (anyTexture)
  {
    output->GetPointData()->SetTCoords(tcoords);
  }
  if (anyNormal)
  {
    output->GetPointData()->SetNormals(normals);
  }
}

std::string UnreadSummary(const ObjContent& content)
{
  std::map<std::string, long long> unreadByName = content.Unread;
  unreadByName["vertex colours (not on every vertex, or in different counts, or outside 0-1)"] =
    HasReadableColours(content) ? 0 : content.VertexColours;
  std::string summary;
  for (const auto& unread : unreadByName)
  {
    if (unread.second > 0)
    {
      summary += (summary.empty() ? "not read: " : ", ") + std::to_string(unread.second) + " " + unread.first;
    }
  }
  return summary;
}
} // namespace

int vtkOBJMeshReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->StartRead();
  auto fail = [&](const ObjProblem& problem) {
    return this->FailRead(output, problem.Message, problem.Code, problem.Line);
  };
  std::ifstream in(this->FileName, std::ios::binary);
  if (this->FileName.empty() || !in)
  {
    return fail({ "cannot open file", vtkErrorCode::CannotOpenFileError, 0 });
  }
  ObjContent content;
  std::string line;
  Words words;
  for (long long number = 1; std::getline(in, line); ++number)
  {
    slod::SplitWords(std::string_view(line).substr(0, line.find('#')), words);
    const ObjProblem problem = words.empty() ? ObjProblem() : ReadStatement(words, number, content);
    if (problem)
    {
      return fail(problem);
    }
  }
  if (const ObjProblem problem = CheckCornerIndices(content))
  {
    return fail(problem);
  }
  const std::string unread = UnreadSummary(content);
  if (!unread.empty())
  {
    this->WarnNotRead(unread);
  }
  BuildOutput(content, output);
  return 1;
}
