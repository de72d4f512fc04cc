// SPDX-License-Identifier: BSD-3-Clause
#include "vtkOFFMeshReader.h"

#include "slodMeshFileSupport.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string_view>
#include <vector>

vtkStandardNewMacro(vtkOFFMeshReader);

namespace
{
using slod::ParseInteger;
using slod::ParseReal;
using Tokens = std::vector<std::string_view>;

// Reads whitespace-separated tokens line by line, skipping comments and blank lines.
class OffTokenizer
{
public:
  explicit OffTokenizer(std::istream& in)
    : In(in)
  {
  }
  // Next non-empty line with comments stripped, split into tokens (views into the tokenizer's
  // line, valid until the next call). False at end of file.
  bool NextLine(Tokens& tokens)
  {
    while (std::getline(this->In, this->Line))
    {
      ++this->LineNumber;
      slod::SplitWords(std::string_view(this->Line).substr(0, this->Line.find('#')), tokens);
      if (!tokens.empty())
      {
        return true;
      }
    }
    return false;
  }
  long long LineNumber = 0;

private:
  std::istream& In;
  std::string Line;
};

using OffProblem = slod::MeshFileProblem;

struct OffHeader
{
  long long NumberOfPoints = 0;
  long long NumberOfFaces = 0;
  bool HasNormals = false;  // N: nx ny nz after the coordinates
  bool HasColors = false;   // C: r g b [a] after the normals
  bool HasTextures = false; // ST: s t after the colours
  // Coordinates, then the normals and texture coordinates the keyword announces (colours: 3 or 4 more).
  size_t VertexColumns() const { return 3 + (this->HasNormals ? 3 : 0) + (this->HasTextures ? 2 : 0); }
};

OffProblem ReadOffHeader(OffTokenizer& tokenizer, OffHeader& header)
{
  Tokens tokens;
  if (!tokenizer.NextLine(tokens))
  {
    return { "empty file, expected an OFF header", vtkErrorCode::PrematureEndOfFileError, 0 };
  }
  // Header keyword: [ST][C][N][4][n]OFF; we accept the 3D variants.
  const std::string keyword(tokens[0]);
  if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0)
  {
    return { "not an OFF file (header '" + keyword + "')", vtkErrorCode::UnrecognizedFileTypeError,
      tokenizer.LineNumber };
  }
  const std::string prefix = keyword.substr(0, keyword.size() - 3);
  if (prefix.find('4') != std::string::npos || prefix.find('n') != std::string::npos)
  {
    return { "only 3D OFF files are supported (header '" + keyword + "')", vtkErrorCode::UnrecognizedFileTypeError,
      tokenizer.LineNumber };
  }
  header.HasTextures = prefix.find("ST") != std::string::npos;
  header.HasColors = prefix.find('C') != std::string::npos;
  header.HasNormals = prefix.find('N') != std::string::npos;
  size_t countsAt = 1;
  if (tokens.size() == 1)
  {
    if (!tokenizer.NextLine(tokens))
    {
      return { "missing vertex/face counts", vtkErrorCode::PrematureEndOfFileError, tokenizer.LineNumber };
    }
    countsAt = 0;
  }
  if (tokens.size() < countsAt + 2 || !ParseInteger(tokens[countsAt], header.NumberOfPoints) ||
    !ParseInteger(tokens[countsAt + 1], header.NumberOfFaces) || header.NumberOfPoints < 0 ||
    header.NumberOfFaces < 0)
  {
    return { "bad vertex/face counts", vtkErrorCode::FileFormatError, tokenizer.LineNumber };
  }
  return {};
}

// A vertex line holds at least VertexColumns() one-character numbers and separators, a face line
// at least "1 0": counts the rest of the file cannot hold are refused before anything is allocated.
OffProblem CheckOffCountsFit(const OffHeader& header, long long bytesLeft, long long line)
{
  const double needed = static_cast<double>(header.NumberOfPoints) * 2.0 * static_cast<double>(header.VertexColumns()) +
    static_cast<double>(header.NumberOfFaces) * 4.0;
  if (needed > static_cast<double>(bytesLeft) + 1.0)
  {
    return { "the header announces " + std::to_string(header.NumberOfPoints) + " vertices and " +
        std::to_string(header.NumberOfFaces) + " faces, more than the " + std::to_string(bytesLeft) +
        " bytes after it can hold",
      vtkErrorCode::PrematureEndOfFileError, line };
  }
  return {};
}

bool LooksFractional(std::string_view token)
{
  return token.find_first_of(".eE") != std::string_view::npos;
}

// Colour columns as written (of the vertices of a COFF file, or after the indices of the faces):
// floats 0-1 when any has a decimal point or exponent or none is above 1 (integer colours of 0 and
// 1 only would be black), else integers 0-255.
struct OffColors
{
  std::vector<double> Values;
  int Components = 0;
  bool FractionalToken = false;
  double LargestValue = 0;
  long long FirstLineAbove1 = 0, FirstLineOutside255 = 0; // 0: none
  bool Floats() const { return this->FractionalToken || this->LargestValue <= 1; }

  // One item's `count` (3 or 4) colour values from tokens[first...]; false: not numbers.
  bool Add(const Tokens& tokens, size_t first, size_t count, long long line)
  {
    this->Components = static_cast<int>(count);
    for (size_t k = 0; k < count; ++k)
    {
      double value = 0;
      if (!ParseReal(tokens[first + k], value))
      {
        return false;
      }
      this->FractionalToken = this->FractionalToken || LooksFractional(tokens[first + k]);
      this->Values.push_back(value);
      this->LargestValue = std::max(this->LargestValue, value);
      const bool above1 = !(value >= 0 && value <= 1);
      const bool outside255 = !(value >= 0 && value <= 255 && value == std::floor(value));
      this->FirstLineAbove1 = above1 && !this->FirstLineAbove1 ? line : this->FirstLineAbove1;
      this->FirstLineOutside255 = outside255 && !this->FirstLineOutside255 ? line : this->FirstLineOutside255;
    }
    return true;
  }
};

// The per-vertex attributes a COFF / NOFF / STOFF file holds, as read.
struct OffVertexAttributes
{
  vtkNew<vtkDoubleArray> Normals, TCoords;
  OffColors Colors;
};

// Columns of one vertex line after the coordinates: normals, colours, texture coordinates.
OffProblem ReadOffVertexAttributes(const Tokens& tokens, const OffHeader& header, long long line,
  vtkIdType vertex, OffVertexAttributes& attributes)
{
  const size_t colorColumns = tokens.size() - header.VertexColumns();
  const int components = attributes.Colors.Components;
  if (header.HasColors && (colorColumns < 3 || colorColumns > 4 || (components != 0 && int(colorColumns) != components)))
  {
    return { "vertex line has " + std::to_string(colorColumns) + " colour values (expected " +
        (components ? std::to_string(components) : std::string("3 or 4")) + ")",
      vtkErrorCode::FileFormatError, line };
  }
  size_t column = 3;
  double values[3];
  auto parse = [&](int count) {
    bool ok = true;
    for (int k = 0; k < count; ++k, ++column)
    {
      ok = ok && ParseReal(tokens[column], values[k]);
    }
    return ok;
  };
  bool ok = !header.HasNormals || parse(3);
  if (ok && header.HasNormals)
  {
    attributes.Normals->SetTypedTuple(vertex, values);
  }
  if (ok && header.HasColors)
  {
    ok = attributes.Colors.Add(tokens, column, colorColumns, line);
    column += colorColumns;
  }
  if (ok && header.HasTextures && parse(2))
  {
    attributes.TCoords->SetTypedTuple(vertex, values);
  }
  return ok ? OffProblem() : OffProblem{ "malformed vertex line", vtkErrorCode::FileFormatError, line };
}

// The colours as unsigned char RGB(A): floats 0-1 scaled to 0-255, integers kept.
OffProblem MakeOffColors(const OffColors& read, vtkUnsignedCharArray* colors)
{
  const long long badLine = read.Floats() ? read.FirstLineAbove1 : read.FirstLineOutside255;
  if (badLine)
  {
    return { read.Floats() ? "colour value outside 0-1 (the file's colours have decimal points: floats)"
                           : "colour value not an integer in 0-255",
      vtkErrorCode::FileFormatError, badLine };
  }
  colors->SetName(read.Components == 4 ? "RGBA" : "RGB");
  colors->SetNumberOfComponents(read.Components);
  colors->SetNumberOfValues(static_cast<vtkIdType>(read.Values.size()));
  for (size_t k = 0; k < read.Values.size(); ++k)
  {
    const double value = read.Values[k];
    colors->SetValue(static_cast<vtkIdType>(k), static_cast<unsigned char>(read.Floats() ? std::lround(value * 255.0) : value));
  }
  return {};
}

OffProblem ReadOffVertices(OffTokenizer& tokenizer, const OffHeader& header, vtkPoints* points,
  OffVertexAttributes& attributes)
{
  Tokens tokens;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(header.NumberOfPoints);
  attributes.Normals->SetNumberOfComponents(3);
  attributes.Normals->SetNumberOfTuples(header.HasNormals ? header.NumberOfPoints : 0);
  attributes.TCoords->SetNumberOfComponents(2);
  attributes.TCoords->SetNumberOfTuples(header.HasTextures ? header.NumberOfPoints : 0);
  for (long long i = 0; i < header.NumberOfPoints; ++i)
  {
    if (!tokenizer.NextLine(tokens))
    {
      return { "file ends after " + std::to_string(i) + " of " + std::to_string(header.NumberOfPoints) + " vertices",
        vtkErrorCode::PrematureEndOfFileError, tokenizer.LineNumber };
    }
    double xyz[3];
    if (tokens.size() < header.VertexColumns() || !ParseReal(tokens[0], xyz[0]) || !ParseReal(tokens[1], xyz[1]) ||
      !ParseReal(tokens[2], xyz[2]))
    {
      return { "malformed vertex line", vtkErrorCode::FileFormatError, tokenizer.LineNumber };
    }
    points->SetPoint(i, xyz);
    const OffProblem problem = ReadOffVertexAttributes(tokens, header, tokenizer.LineNumber, i, attributes);
    if (problem)
    {
      return problem;
    }
  }
  return {};
}

// Colours after the faces' indices (r g b [a], as the vertices' colours); a face with another
// number of values (a colour-map index) makes them unread.
struct OffFaceColors
{
  OffColors Colors;
  std::vector<unsigned char> Kind; // per face: 0 vertex, 1 line, 2 polygon (cell data order)
  long long Faces = 0, FacesWithOtherColumns = 0;
  bool Readable() const { return this->FacesWithOtherColumns == 0 && this->Colors.Components != 0; }
};

OffProblem AddFaceColor(const Tokens& tokens, long long count, long long line, OffFaceColors& faceColors)
{
  const size_t columns = tokens.size() - size_t(count) - 1;
  ++faceColors.Faces;
  faceColors.Kind.push_back(static_cast<unsigned char>(count >= 3 ? 2 : count == 2 ? 1 : 0));
  const int components = faceColors.Colors.Components;
  if (columns < 3 || columns > 4 || (components != 0 && int(columns) != components) ||
    faceColors.FacesWithOtherColumns > 0)
  {
    faceColors.FacesWithOtherColumns += columns > 0 || components != 0 ? 1 : 0;
    return {};
  }
  return faceColors.Colors.Add(tokens, size_t(count) + 1, columns, line)
    ? OffProblem()
    : OffProblem{ "malformed face colour", vtkErrorCode::FileFormatError, line };
}

// Faces of three or more vertices are polygons; faces of two are lines and of one vertices (kept,
// so nothing in the file is lost; the filters ignore them).
OffProblem ReadOffFaces(OffTokenizer& tokenizer, const OffHeader& header, vtkCellArray* polys, vtkCellArray* lines,
  vtkCellArray* verts, OffFaceColors& faceColors)
{
  Tokens tokens;
  std::vector<vtkIdType> ids;
  for (long long f = 0; f < header.NumberOfFaces; ++f)
  {
    if (!tokenizer.NextLine(tokens))
    {
      return { "file ends after " + std::to_string(f) + " of " + std::to_string(header.NumberOfFaces) + " faces",
        vtkErrorCode::PrematureEndOfFileError, tokenizer.LineNumber };
    }
    long long count = 0;
    if (!ParseInteger(tokens[0], count) || count < 1 || tokens.size() < size_t(count) + 1)
    {
      return { "malformed face line", vtkErrorCode::FileFormatError, tokenizer.LineNumber };
    }
    ids.resize(size_t(count));
    for (long long k = 0; k < count; ++k)
    {
      long long id = 0;
      if (!ParseInteger(tokens[size_t(k) + 1], id) || id < 0 || id >= header.NumberOfPoints)
      {
        return { "face refers to a vertex that does not exist", vtkErrorCode::FileFormatError, tokenizer.LineNumber };
      }
      ids[size_t(k)] = static_cast<vtkIdType>(id);
    }
    if (const OffProblem problem = AddFaceColor(tokens, count, tokenizer.LineNumber, faceColors))
    {
      return problem;
    }
    vtkCellArray* cells = count >= 3 ? polys : count == 2 ? lines : verts;
    cells->InsertNextCell(count, ids.data());
  }
  return {};
}

// The faces' colours as cell data: vertices' first, then lines', then polygons' (vtkPolyData's
// cell order), as unsigned char RGB(A).
OffProblem MakeOffFaceColors(const OffFaceColors& faceColors, vtkUnsignedCharArray* colors)
{
  vtkNew<vtkUnsignedCharArray> inFileOrder;
  if (const OffProblem problem = MakeOffColors(faceColors.Colors, inFileOrder))
  {
    return problem;
  }
  colors->SetName(inFileOrder->GetName());
  colors->SetNumberOfComponents(inFileOrder->GetNumberOfComponents());
  colors->SetNumberOfTuples(inFileOrder->GetNumberOfTuples());
  vtkIdType next = 0;
  for (unsigned char kind = 0; kind < 3; ++kind)
  {
    for (size_t f = 0; f < faceColors.Kind.size(); ++f)
    {
      if (faceColors.Kind[f] == kind)
      {
        colors->SetTuple(next++, static_cast<vtkIdType>(f), inFileOrder);
      }
    }
  }
  return {};
}

long long BytesLeft(std::ifstream& in)
{
  const std::streamoff here = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff end = in.tellg();
  in.seekg(here);
  return here >= 0 && end >= here ? static_cast<long long>(end - here) : 0;
}
} // namespace

int vtkOFFMeshReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->StartRead();
  auto fail = [&](const OffProblem& problem) {
    return this->FailRead(output, problem.Message, problem.Code, problem.Line);
  };

  std::ifstream in(this->FileName, std::ios::binary);
  if (this->FileName.empty() || !in)
  {
    return fail({ "cannot open file", vtkErrorCode::CannotOpenFileError, 0 });
  }
  OffTokenizer tokenizer(in);
  OffHeader header;
  OffVertexAttributes attributes;
  vtkNew<vtkUnsignedCharArray> colors;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> polys, lines, verts;
  OffProblem problem = ReadOffHeader(tokenizer, header);
  if (!problem)
  {
    problem = CheckOffCountsFit(header, BytesLeft(in), tokenizer.LineNumber);
  }
  if (!problem)
  {
    problem = ReadOffVertices(tokenizer, header, points, attributes);
  }
  if (!problem && header.HasColors)
  {
    problem = MakeOffColors(attributes.Colors, colors);
  }
  OffFaceColors faceColors;
  vtkNew<vtkUnsignedCharArray> cellColors;
  if (!problem)
  {
    problem = ReadOffFaces(tokenizer, header, polys, lines, verts, faceColors);
  }
  if (!problem && faceColors.Readable())
  {
    problem = MakeOffFaceColors(faceColors, cellColors);
  }
  if (problem)
  {
    return fail(problem);
  }
  Tokens tokens;
  if (tokenizer.NextLine(tokens))
  {
    this->WarnNotRead("data after the " + std::to_string(header.NumberOfFaces) +
        " faces the header announces; it is ignored (a wrong face count?)",
      tokenizer.LineNumber);
  }
  output->SetPoints(points);
  output->SetPolys(polys);
  output->SetLines(lines);
  output->SetVerts(verts);
  if (header.HasNormals)
  {
    attributes.Normals->SetName("Normals");
    output->GetPointData()->SetNormals(attributes.Normals);
  }
  if (header.HasTextures)
  {
    attributes.TCoords->SetName("TCoords");
    output->GetPointData()->SetTCoords(attributes.TCoords);
  }
  if (header.HasColors)
  {
    output->GetPointData()->SetScalars(colors);
  }
  if (faceColors.Readable())
  {
    output->GetCellData()->SetScalars(cellColors);
  }
  else if (faceColors.FacesWithOtherColumns > 0)
  {
    this->WarnNotRead("face colours (" + std::to_string(faceColors.FacesWithOtherColumns) +
        " faces with a colour-map index or another number of colour values than the first)",
      0);
  }
  return 1;
}
