// SPDX-License-Identifier: BSD-3-Clause
#include "vtkOFFMeshReader.h"

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

// The per-vertex attributes a COFF / NOFF / STOFF file holds, as read.
struct OffVertexAttributes
{
  vtkNew<vtkDoubleArray> Normals, TCoords;
  // Colour values as written: floats 0-1 when any has a decimal point or exponent or none is above 1
  // (integer colours of 0 and 1 only would be black), else integers 0-255.
  std::vector<double> ColorValues;
  int ColorComponents = 0;
  bool FractionalToken = false;
  double LargestColorValue = 0;
  bool FloatColors() const { return this->FractionalToken || this->LargestColorValue <= 1; }
  long long FirstLineAbove1 = 0, FirstLineOutside255 = 0; // 0: none
};

bool LooksFractional(std::string_view token)
{
  return token.find_first_of(".eE") != std::string_view::npos;
}

// Columns of one vertex line after the coordinates: normals, colours, texture coordinates.
OffProblem ReadOffVertexAttributes(const Tokens& tokens, const OffHeader& header, long long line,
  vtkIdType vertex, OffVertexAttributes& attributes)
{
  const size_t colorColumns = tokens.size() - header.VertexColumns();
  if (header.HasColors && (colorColumns < 3 || colorColumns > 4 ||
        (attributes.ColorComponents != 0 && int(colorColumns) != attributes.ColorComponents)))
  {
    return { "vertex line has " + std::to_string(colorColumns) + " colour values (expected " +
        (attributes.ColorComponents ? std::to_string(attributes.ColorComponents) : std::string("3 or 4")) + ")",
      vtkErrorCode::FileFormatError, line };
  }
  size_t column = 3;
  double values[4];
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
    attributes.ColorComponents = static_cast<int>(colorColumns);
    for (size_t k = 0; k < colorColumns; ++k)
    {
      attributes.FractionalToken = attributes.FractionalToken || LooksFractional(tokens[column + k]);
    }
    ok = parse(attributes.ColorComponents);
    for (int k = 0; ok && k < attributes.ColorComponents; ++k)
    {
      attributes.ColorValues.push_back(values[k]);
      attributes.LargestColorValue = std::max(attributes.LargestColorValue, values[k]);
      const bool above1 = !(values[k] >= 0 && values[k] <= 1);
      const bool outside255 = !(values[k] >= 0 && values[k] <= 255 && values[k] == std::floor(values[k]));
      attributes.FirstLineAbove1 = above1 && !attributes.FirstLineAbove1 ? line : attributes.FirstLineAbove1;
      attributes.FirstLineOutside255 =
        outside255 && !attributes.FirstLineOutside255 ? line : attributes.FirstLineOutside255;
    }
  }
  if (ok && header.HasTextures && parse(2))
  {
    attributes.TCoords->SetTypedTuple(vertex, values);
  }
  return ok ? OffProblem() : OffProblem{ "malformed vertex line", vtkErrorCode::FileFormatError, line };
}

// The colours as unsigned char RGB(A): floats 0-1 scaled to 0-255, integers kept.
OffProblem MakeOffColors(const OffVertexAttributes& attributes, vtkUnsignedCharArray* colors)
{
  const long long badLine = attributes.FloatColors() ? attributes.FirstLineAbove1 : attributes.FirstLineOutside255;
  if (badLine)
  {
    return { attributes.FloatColors() ? "colour value outside 0-1 (the file's colours have decimal points: floats)"
                                    : "colour value not an integer in 0-255",
      vtkErrorCode::FileFormatError, badLine };
  }
  colors->SetName(attributes.ColorComponents == 4 ? "RGBA" : "RGB");
  colors->SetNumberOfComponents(attributes.ColorComponents);
  colors->SetNumberOfValues(static_cast<vtkIdType>(attributes.ColorValues.size()));
  for (size_t k = 0; k < attributes.ColorValues.size(); ++k)
  {
    const double value = attributes.ColorValues[k];
    colors->SetValue(static_cast<vtkIdType>(k),
      static_cast<unsigned char>(attributes.FloatColors() ? std::lround(value * 255.0) : value));
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

// Faces of three or more vertices are polygons; faces of two are lines and of one vertices (kept,
// so nothing in the file is lost; the filters ignore them).
OffProblem ReadOffFaces(OffTokenizer& tokenizer, const OffHeader& header, vtkCellArray* polys, vtkCellArray* lines,
  vtkCellArray* verts)
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
    // Columns after the indices are colors: ignored.
    vtkCellArray* cells = count >= 3 ? polys : count == 2 ? lines : verts;
    cells->InsertNextCell(count, ids.data());
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
    problem = MakeOffColors(attributes, colors);
  }
  if (!problem)
  {
    problem = ReadOffFaces(tokenizer, header, polys, lines, verts);
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
  return 1;
}
