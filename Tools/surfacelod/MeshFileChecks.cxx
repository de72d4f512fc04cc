// SPDX-License-Identifier: BSD-3-Clause
#include "MeshFileChecks.h"

#include <vtksys/SystemTools.hxx>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace slodcli
{
namespace
{
// ------------------------------------------------------------------------------------- PLY

enum class PlyFormat
{
  Ascii,
  BinaryLittleEndian,
  BinaryBigEndian
};

struct PlyScalar
{
  int Size = 0;         // bytes in a binary file
  bool Integer = false; // char .. uint
  bool Signed = false;
};

struct PlyProperty
{
  std::string Name;
  PlyScalar Value;
  PlyScalar Count; // Count.Size > 0 for a list
  bool IsList() const { return this->Count.Size > 0; }
};

struct PlyElement
{
  std::string Name;
  long long Count = 0;
  std::vector<PlyProperty> Properties;
  // Smallest size of one element in a binary file (every list empty).
  long long MinimumBinarySize() const
  {
    long long size = 0;
    for (const PlyProperty& p : this->Properties)
    {
      size += p.IsList() ? p.Count.Size : p.Value.Size;
    }
    return size;
  }
};

struct PlyHeader
{
  PlyFormat Format = PlyFormat::Ascii;
  std::vector<PlyElement> Elements;
  size_t BodyOffset = 0;
};

// VTK's PLY library reads header lines into a fixed buffer and counts in int.
constexpr size_t MaximumHeaderLine = 4000;
// vtkPLYReader keeps the length of a face's index list in an unsigned char.
constexpr long long MaximumFaceVertices = 255;

bool ScalarType(const std::string& name, PlyScalar& type)
{
  struct Known
  {
    const char* Name;
    PlyScalar Type;
  };
  static const Known known[] = { { "char", { 1, true, true } }, { "int8", { 1, true, true } },
    { "uchar", { 1, true, false } }, { "uint8", { 1, true, false } }, { "short", { 2, true, true } },
    { "int16", { 2, true, true } }, { "ushort", { 2, true, false } }, { "uint16", { 2, true, false } },
    { "int", { 4, true, true } }, { "int32", { 4, true, true } }, { "uint", { 4, true, false } },
    { "uint32", { 4, true, false } }, { "float", { 4, false, true } }, { "float32", { 4, false, true } },
    { "double", { 8, false, true } }, { "float64", { 8, false, true } } };
  for (const Known& k : known)
  {
    if (name == k.Name)
    {
      type = k.Type;
      return true;
    }
  }
  return false;
}

std::vector<std::string> Words(const std::string& line)
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

// Next '\n'-terminated line from offset (a trailing '\r' removed); false at the end of the bytes.
bool NextLine(const std::string& bytes, size_t& offset, std::string& line)
{
  if (offset >= bytes.size())
  {
    return false;
  }
  const size_t end = bytes.find('\n', offset);
  const size_t stop = end == std::string::npos ? bytes.size() : end;
  line.assign(bytes, offset, stop - offset);
  if (!line.empty() && line.back() == '\r')
  {
    line.pop_back();
  }
  offset = end == std::string::npos ? bytes.size() : end + 1;
  return true;
}

// One header line after "ply"; "" when it is sound.
std::string ParsePlyHeaderLine(const std::vector<std::string>& words, const std::string& line, PlyHeader& header,
  bool& formatSeen)
{
  const std::string& keyword = words[0];
  if (keyword == "comment" || keyword == "obj_info")
  {
    return std::string();
  }
  if (keyword == "format")
  {
    if (words.size() != 3 || formatSeen)
    {
      return "bad PLY format line '" + line + "'";
    }
    formatSeen = true;
    if (words[1] == "ascii")
    {
      header.Format = PlyFormat::Ascii;
    }
    else if (words[1] == "binary_little_endian")
    {
      header.Format = PlyFormat::BinaryLittleEndian;
    }
    else if (words[1] == "binary_big_endian")
    {
      header.Format = PlyFormat::BinaryBigEndian;
    }
    else
    {
      return "unknown PLY format '" + words[1] + "'";
    }
    return std::string();
  }
  if (keyword == "element")
  {
    PlyElement element;
    char* end = nullptr;
    errno = 0;
    element.Count = words.size() == 3 ? std::strtoll(words[2].c_str(), &end, 10) : -1;
    if (words.size() != 3 || !end || *end != '\0' || errno != 0 || element.Count < 0)
    {
      return "bad PLY element line '" + line + "'";
    }
    if (element.Count > INT_MAX)
    {
      return "PLY element '" + words[1] + "' announces " + words[2] + " items (more than a PLY reader can count)";
    }
    element.Name = words[1];
    header.Elements.push_back(element);
    return std::string();
  }
  if (keyword == "property")
  {
    if (header.Elements.empty())
    {
      return "PLY property before any element";
    }
    PlyProperty property;
    const bool list = words.size() == 5 && words[1] == "list";
    const bool scalar = words.size() == 3 && ScalarType(words[1], property.Value);
    if (list && ScalarType(words[2], property.Count) && property.Count.Integer &&
      ScalarType(words[3], property.Value))
    {
      property.Name = words[4];
    }
    else if (scalar)
    {
      property.Name = words[2];
    }
    else
    {
      return "bad PLY property line '" + line + "'";
    }
    header.Elements.back().Properties.push_back(property);
    return std::string();
  }
  return "unknown PLY header line '" + line + "'";
}

std::string ParsePlyHeader(const std::string& bytes, PlyHeader& header)
{
  size_t offset = 0;
  std::string line;
  if (!NextLine(bytes, offset, line) || line != "ply")
  {
    return "not a PLY file (first line is not 'ply')";
  }
  bool formatSeen = false;
  while (NextLine(bytes, offset, line))
  {
    if (line.size() > MaximumHeaderLine)
    {
      return "PLY header line longer than " + std::to_string(MaximumHeaderLine) + " characters";
    }
    const std::vector<std::string> words = Words(line);
    if (words.empty())
    {
      continue;
    }
    if (words[0] == "end_header")
    {
      if (!formatSeen)
      {
        return "PLY header has no format line";
      }
      header.BodyOffset = offset;
      return std::string();
    }
    const std::string problem = ParsePlyHeaderLine(words, line, header, formatSeen);
    if (!problem.empty())
    {
      return problem;
    }
  }
  return "PLY header has no end_header";
}

// The list of a face's vertex indices as vtkPLYReader reads it (checked against the vertex count).
bool IsFaceIndexList(const PlyElement& element, const PlyProperty& property)
{
  return element.Name == "face" && property.IsList() &&
    (property.Name == "vertex_indices" || property.Name == "vertex_index");
}

// The structure vtkPLYReader relies on: a vertex element with scalar x, y, z; elements with data.
std::string CheckPlyStructure(const PlyHeader& header, long long& vertexCount)
{
  vertexCount = -1;
  for (const PlyElement& e : header.Elements)
  {
    if (e.Count > 0 && e.Properties.empty())
    {
      return "PLY element '" + e.Name + "' has " + std::to_string(e.Count) + " items but no properties";
    }
    if (e.Name == "face" && e.Count > 0)
    {
      bool hasIndices = false;
      for (const PlyProperty& p : e.Properties)
      {
        hasIndices = hasIndices || IsFaceIndexList(e, p);
      }
      if (!hasIndices)
      {
        // vtkPLYReader then frees an index list it never read (a crash).
        return "PLY face element has no vertex_indices list";
      }
    }
    if (e.Name != "vertex")
    {
      continue;
    }
    if (vertexCount >= 0)
    {
      return "PLY file has two vertex elements";
    }
    int xyz = 0;
    for (const PlyProperty& p : e.Properties)
    {
      xyz += !p.IsList() && (p.Name == "x" || p.Name == "y" || p.Name == "z");
    }
    if (xyz != 3)
    {
      return "PLY vertex element lacks scalar x, y, z properties";
    }
    vertexCount = e.Count;
  }
  if (vertexCount < 0)
  {
    return "PLY file has no vertex element";
  }
  return std::string();
}

// Reads PLY values of the body, ASCII or binary, with bounds.
class PlyBodyReader
{
public:
  PlyBodyReader(const std::string& bytes, const PlyHeader& header)
    : Bytes(bytes)
    , Format(header.Format)
    , Offset(header.BodyOffset)
  {
  }

  // Starts an element: an ASCII element is one line.
  bool BeginElement()
  {
    if (this->Format != PlyFormat::Ascii)
    {
      return true;
    }
    std::string line;
    if (!NextLine(this->Bytes, this->Offset, line))
    {
      return false;
    }
    this->Tokens = Words(line);
    this->Token = 0;
    return true;
  }

  // False when the data ends or a value is malformed.
  bool Read(const PlyScalar& type, double& value)
  {
    if (this->Format == PlyFormat::Ascii)
    {
      if (this->Token >= this->Tokens.size())
      {
        return false;
      }
      const std::string& token = this->Tokens[this->Token++];
      char* end = nullptr;
      value = std::strtod(token.c_str(), &end);
      return end && *end == '\0' && (!type.Integer || (std::isfinite(value) && value == std::floor(value)));
    }
    if (this->Bytes.size() - this->Offset < size_t(type.Size))
    {
      return false;
    }
    value = this->DecodeBinary(type);
    this->Offset += size_t(type.Size);
    return true;
  }

  // Skips `count` values of a binary list at once; ASCII lists are read value by value.
  bool SkipBinary(const PlyScalar& type, long long count)
  {
    const unsigned long long bytes = static_cast<unsigned long long>(count) * unsigned(type.Size);
    if (bytes > this->Bytes.size() - this->Offset)
    {
      return false;
    }
    this->Offset += size_t(bytes);
    return true;
  }

  bool Binary() const { return this->Format != PlyFormat::Ascii; }
  size_t Remaining() const { return this->Bytes.size() - this->Offset; }
  // Data after the last element (ASCII: only blank lines may follow).
  bool HasTrailingData() const
  {
    if (this->Binary())
    {
      return this->Offset < this->Bytes.size();
    }
    return this->Bytes.find_first_not_of(" \t\r\n", this->Offset) != std::string::npos;
  }

private:
  double DecodeBinary(const PlyScalar& type) const
  {
    const unsigned char* p = reinterpret_cast<const unsigned char*>(this->Bytes.data() + this->Offset);
    std::uint64_t bits = 0;
    for (int b = 0; b < type.Size; ++b)
    {
      const int shift = 8 * (this->Format == PlyFormat::BinaryLittleEndian ? b : type.Size - 1 - b);
      bits |= std::uint64_t(p[b]) << shift;
    }
    if (!type.Integer)
    {
      if (type.Size == 4)
      {
        const std::uint32_t narrow = static_cast<std::uint32_t>(bits);
        float f;
        std::memcpy(&f, &narrow, sizeof(f));
        return f;
      }
      double d;
      std::memcpy(&d, &bits, sizeof(d));
      return d;
    }
    if (type.Signed && (bits >> (8 * type.Size - 1)) != 0)
    {
      return static_cast<double>(static_cast<long long>(bits) - (1LL << (8 * type.Size)));
    }
    return static_cast<double>(bits);
  }

  const std::string& Bytes;
  PlyFormat Format;
  size_t Offset;
  std::vector<std::string> Tokens;
  size_t Token = 0;
};

std::string Item(const PlyElement& e, long long i)
{
  return e.Name + " " + std::to_string(i) + " of " + std::to_string(e.Count);
}

// One list property of one element: its length, and the indices it holds when it has a role.
std::string CheckPlyList(PlyBodyReader& body, const PlyElement& e, long long i, const PlyProperty& p,
  long long vertexCount)
{
  double length = 0;
  if (!body.Read(p.Count, length))
  {
    return "file ends inside " + Item(e, i);
  }
  const bool indices = IsFaceIndexList(e, p);
  if (length < 0 || (indices && length > MaximumFaceVertices))
  {
    return Item(e, i) + " has a list of " + std::to_string(static_cast<long long>(length)) + " values";
  }
  const long long count = static_cast<long long>(length);
  if (!indices && body.Binary())
  {
    return body.SkipBinary(p.Value, count) ? std::string() : "file ends inside " + Item(e, i);
  }
  if (body.Binary() && static_cast<unsigned long long>(count) * unsigned(p.Value.Size) > body.Remaining())
  {
    return "file ends inside " + Item(e, i);
  }
  for (long long k = 0; k < count; ++k)
  {
    double value = 0;
    if (!body.Read(p.Value, value))
    {
      return "file ends inside " + Item(e, i) + " (or a value is malformed)";
    }
    if (indices && (!p.Value.Integer || value < 0 || value >= static_cast<double>(vertexCount)))
    {
      return Item(e, i) + " refers to vertex " + std::to_string(static_cast<long long>(value)) + " but the file has " +
        std::to_string(vertexCount) + " vertices";
    }
  }
  return std::string();
}

// The elements' data; warns about data after the last element (the reader ignores it).
std::string CheckPlyBody(const std::string& bytes, const PlyHeader& header, long long vertexCount, std::string& warning)
{
  PlyBodyReader body(bytes, header);
  for (const PlyElement& e : header.Elements)
  {
    // Every element takes at least one byte (binary) or one line of at least one character (ASCII;
    // the last line may lack its '\n'): the count must fit.
    const unsigned long long room = body.Binary() ? body.Remaining() : body.Remaining() + 1;
    const unsigned long long minimum = body.Binary() ? static_cast<unsigned long long>(e.MinimumBinarySize()) : 2;
    if (e.Count > 0 && static_cast<unsigned long long>(e.Count) > room / minimum)
    {
      return "the header announces " + std::to_string(e.Count) + " " + e.Name + " elements, more than the " +
        std::to_string(body.Remaining()) + " bytes left can hold";
    }
    for (long long i = 0; i < e.Count; ++i)
    {
      if (!body.BeginElement())
      {
        return "file ends after " + std::to_string(i) + " of " + std::to_string(e.Count) + " " + e.Name + " elements";
      }
      for (const PlyProperty& p : e.Properties)
      {
        double value = 0;
        const std::string problem = p.IsList() ? CheckPlyList(body, e, i, p, vertexCount)
          : body.Read(p.Value, value)          ? std::string()
                                               : "file ends inside " + Item(e, i) + " (or a value is malformed)";
        if (!problem.empty())
        {
          return problem;
        }
      }
    }
  }
  if (body.HasTrailingData())
  {
    warning = std::to_string(body.Remaining()) + " bytes after the elements the header announces are ignored";
  }
  return std::string();
}
} // namespace

FileCheck CheckPLY(const std::string& bytes)
{
  FileCheck result;
  PlyHeader header;
  long long vertexCount = 0;
  result.Problem = ParsePlyHeader(bytes, header);
  if (result.Problem.empty())
  {
    result.Problem = CheckPlyStructure(header, vertexCount);
  }
  if (result.Problem.empty())
  {
    result.Problem = CheckPlyBody(bytes, header, vertexCount, result.Warning);
  }
  return result;
}

FileCheck CheckSTL(const std::string& bytes, bool binary)
{
  FileCheck result;
  if (!binary)
  {
    return result; // VTK's ASCII parser reports its own errors
  }
  if (bytes.size() < 84)
  {
    result.Problem = "not an STL file (too short for a binary STL, not text)";
    return result;
  }
  const unsigned char* count = reinterpret_cast<const unsigned char*>(bytes.data()) + 80;
  const unsigned long long announced = count[0] | (count[1] << 8) | (count[2] << 16) |
    (static_cast<unsigned long long>(count[3]) << 24);
  const unsigned long long expected = 84 + 50 * announced;
  const unsigned long long size = bytes.size();
  // vtkSTLReader allocates for the announced count whatever the file holds.
  if (size < expected)
  {
    result.Problem = "truncated binary STL: the header announces " + std::to_string(announced) + " triangles (" +
      std::to_string(expected) + " bytes), the file has " + std::to_string(size) + " bytes";
  }
  else if (size >= expected + 50)
  {
    result.Warning = "binary STL holds " + std::to_string((size - expected) / 50) +
      " more triangles than the header announces (" + std::to_string(announced) + "); all are read";
  }
  return result;
}

FileCheck CheckOBJ(const std::string& bytes)
{
  FileCheck result;
  size_t offset = 0;
  std::string line;
  for (long long number = 1; NextLine(bytes, offset, line); ++number)
  {
    const std::vector<std::string> words = Words(line);
    if (words.empty() || words[0] != "v")
    {
      continue;
    }
    // x y z, then an optional w or r g b (or r g b a).
    bool numbers = words.size() >= 4 && words.size() <= 8;
    for (size_t k = 1; numbers && k < words.size(); ++k)
    {
      // Decimal only: no "nan", "inf" or hexadecimal forms.
      char* end = nullptr;
      const double value = std::strtod(words[k].c_str(), &end);
      numbers = words[k].find_first_not_of("0123456789+-.eE") == std::string::npos && end && *end == '\0' &&
        std::isfinite(value);
    }
    if (!numbers)
    {
      result.Problem = "line " + std::to_string(number) + ": vertex '" + line.substr(0, 80) +
        "' does not hold finite numbers";
      return result;
    }
  }
  return result;
}

bool IsBinarySTL(const std::string& path)
{
  // The test vtkSTLReader::GetSTLFileType makes (unknown: it attempts binary).
  return vtksys::SystemTools::DetectFileType(path.c_str()) != vtksys::SystemTools::FileTypeText;
}

bool ReadFileBytes(const std::string& path, std::string& bytes)
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
} // namespace slodcli
