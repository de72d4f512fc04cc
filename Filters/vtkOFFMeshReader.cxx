#include "vtkOFFMeshReader.h"

#include "vtkCellArray.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkOFFMeshReader);

namespace
{
// Reads whitespace-separated tokens line by line, skipping comments and blank lines.
class OffTokenizer
{
public:
  explicit OffTokenizer(std::istream& in)
    : In(in)
  {
  }
  // Next non-empty line with comments stripped, split into tokens. False at end of file.
  bool NextLine(std::vector<std::string>& tokens)
  {
    std::string line;
    while (std::getline(this->In, line))
    {
      ++this->LineNumber;
      const size_t hash = line.find('#');
      if (hash != std::string::npos)
      {
        line.erase(hash);
      }
      std::istringstream s(line);
      tokens.clear();
      std::string token;
      while (s >> token)
      {
        tokens.push_back(token);
      }
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
};

bool ParseInteger(const std::string& token, long long& value)
{
  char* end = nullptr;
  value = std::strtoll(token.c_str(), &end, 10);
  return end && *end == '\0' && !token.empty();
}

bool ParseReal(const std::string& token, double& value)
{
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return end && *end == '\0' && !token.empty();
}
} // namespace

vtkOFFMeshReader::vtkOFFMeshReader()
{
  this->SetNumberOfInputPorts(0);
}

void vtkOFFMeshReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

int vtkOFFMeshReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->LastError.clear();
  this->SetErrorCode(vtkErrorCode::NoError);
  auto fail = [&](const std::string& message, unsigned long code, long long line) {
    std::ostringstream s;
    s << this->FileName;
    if (line > 0)
    {
      s << ':' << line;
    }
    s << ": " << message;
    this->LastError = s.str();
    vtkErrorMacro(<< this->LastError);
    this->SetErrorCode(code);
    output->Initialize();
    return 1; // a defined (empty) output; the error code tells callers
  };

  std::ifstream in(this->FileName, std::ios::binary);
  if (this->FileName.empty() || !in)
  {
    return fail("cannot open file", vtkErrorCode::CannotOpenFileError, 0);
  }
  OffTokenizer tokenizer(in);
  std::vector<std::string> tokens;
  if (!tokenizer.NextLine(tokens))
  {
    return fail("empty file, expected an OFF header", vtkErrorCode::PrematureEndOfFileError, 0);
  }
  // Header keyword: [ST][C][N][4][n]OFF; we accept the 3D variants.
  std::string keyword = tokens[0];
  size_t countsAt = 1;
  if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0)
  {
    return fail("not an OFF file (header '" + keyword + "')", vtkErrorCode::UnrecognizedFileTypeError,
      tokenizer.LineNumber);
  }
  if (keyword.find('4') != std::string::npos || keyword.find('n') != std::string::npos)
  {
    return fail("only 3D OFF files are supported (header '" + keyword + "')",
      vtkErrorCode::UnrecognizedFileTypeError, tokenizer.LineNumber);
  }
  const bool hasNormals = keyword.find('N') != std::string::npos;
  const bool hasTexture = keyword.find("ST") != std::string::npos;
  if (tokens.size() == 1)
  {
    if (!tokenizer.NextLine(tokens))
    {
      return fail("missing vertex/face counts", vtkErrorCode::PrematureEndOfFileError, tokenizer.LineNumber);
    }
    countsAt = 0;
  }
  long long numPoints = 0, numFaces = 0;
  if (tokens.size() < countsAt + 2 || !ParseInteger(tokens[countsAt], numPoints) ||
    !ParseInteger(tokens[countsAt + 1], numFaces) || numPoints < 0 || numFaces < 0)
  {
    return fail("bad vertex/face counts", vtkErrorCode::FileFormatError, tokenizer.LineNumber);
  }
  const size_t minimumColumns = 3 + (hasNormals ? 3 : 0) + (hasTexture ? 2 : 0);

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(numPoints);
  for (long long i = 0; i < numPoints; ++i)
  {
    if (!tokenizer.NextLine(tokens))
    {
      return fail("file ends after " + std::to_string(i) + " of " + std::to_string(numPoints) + " vertices",
        vtkErrorCode::PrematureEndOfFileError, tokenizer.LineNumber);
    }
    double xyz[3];
    if (tokens.size() < minimumColumns || !ParseReal(tokens[0], xyz[0]) || !ParseReal(tokens[1], xyz[1]) ||
      !ParseReal(tokens[2], xyz[2]))
    {
      return fail("malformed vertex line", vtkErrorCode::FileFormatError, tokenizer.LineNumber);
    }
    points->SetPoint(i, xyz);
  }
  vtkNew<vtkCellArray> polys;
  std::vector<vtkIdType> ids;
  for (long long f = 0; f < numFaces; ++f)
  {
    if (!tokenizer.NextLine(tokens))
    {
      return fail("file ends after " + std::to_string(f) + " of " + std::to_string(numFaces) + " faces",
        vtkErrorCode::PrematureEndOfFileError, tokenizer.LineNumber);
    }
    long long count = 0;
    if (!ParseInteger(tokens[0], count) || count < 1 || tokens.size() < size_t(count) + 1)
    {
      return fail("malformed face line", vtkErrorCode::FileFormatError, tokenizer.LineNumber);
    }
    ids.resize(size_t(count));
    for (long long k = 0; k < count; ++k)
    {
      long long id = 0;
      if (!ParseInteger(tokens[size_t(k) + 1], id) || id < 0 || id >= numPoints)
      {
        return fail("face refers to a vertex that does not exist", vtkErrorCode::FileFormatError,
          tokenizer.LineNumber);
      }
      ids[size_t(k)] = static_cast<vtkIdType>(id);
    }
    // Columns after the indices are colors: ignored.
    polys->InsertNextCell(count, ids.data());
  }
  output->SetPoints(points);
  output->SetPolys(polys);
  return 1;
}
