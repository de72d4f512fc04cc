// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPLYMeshReader.h"

#include "slodMeshFileSupport.h"
#include "slodPlyFormat.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <cerrno>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

vtkStandardNewMacro(vtkPLYMeshReader);

namespace
{
using slod::PlyEncoding;
using slod::PlyScalarType;

using PlyProblem = slod::MeshFileProblem;

PlyProblem FormatProblem(const std::string& message)
{
  return { message, vtkErrorCode::FileFormatError };
}

struct PlyProperty
{
  std::string Name;
  PlyScalarType Value;
  PlyScalarType Count; // VTKType VTK_VOID for a scalar property
  bool IsList() const { return this->Count.VTKType != VTK_VOID; }
};

struct PlyElement
{
  std::string Name;
  long long Count = 0;
  std::vector<PlyProperty> Properties;

  // Smallest room one item takes: binary, its scalars and list counts; ASCII, one character and
  // one separator per value (lists empty).
  long long MinimumItemSize(bool binary) const
  {
    long long size = 0;
    for (const PlyProperty& p : this->Properties)
    {
      size += binary ? (p.IsList() ? p.Count.Size : p.Value.Size) : 2;
    }
    return size;
  }
};

struct PlyHeader
{
  PlyEncoding Encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> Elements;
  size_t BodyOffset = 0;
};

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

PlyProblem ParseFormatLine(const std::vector<std::string>& words, PlyHeader& header)
{
  if (words.size() != 3)
  {
    return FormatProblem("bad PLY format line (expected 'format ENCODING 1.0')");
  }
  if (words[1] == "ascii")
  {
    header.Encoding = PlyEncoding::Ascii;
  }
  else if (words[1] == "binary_little_endian")
  {
    header.Encoding = PlyEncoding::BinaryLittleEndian;
  }
  else if (words[1] == "binary_big_endian")
  {
    header.Encoding = PlyEncoding::BinaryBigEndian;
  }
  else
  {
    return FormatProblem("unknown PLY format '" + words[1] + "'");
  }
  return {};
}

PlyProblem ParseElementLine(const std::vector<std::string>& words, const std::string& line, PlyHeader& header)
{
  PlyElement element;
  const char* first = words.size() == 3 ? words[2].data() : nullptr;
  const char* last = first ? first + words[2].size() : nullptr;
  const auto parsed = first ? std::from_chars(first, last, element.Count) : std::from_chars_result{ nullptr, {} };
  if (!first || parsed.ec != std::errc() || parsed.ptr != last || element.Count < 0)
  {
    return FormatProblem("bad PLY element line '" + line + "'");
  }
  element.Name = words[1];
  header.Elements.push_back(element);
  return {};
}

PlyProblem ParsePropertyLine(const std::vector<std::string>& words, const std::string& line, PlyHeader& header)
{
  if (header.Elements.empty())
  {
    return FormatProblem("PLY property before any element");
  }
  PlyProperty property;
  if (words.size() == 5 && words[1] == "list" && slod::PlyScalarTypeFromName(words[2], property.Count) &&
    property.Count.IsInteger() && slod::PlyScalarTypeFromName(words[3], property.Value))
  {
    property.Name = words[4];
  }
  else if (words.size() == 3 && slod::PlyScalarTypeFromName(words[1], property.Value))
  {
    property.Name = words[2];
  }
  else
  {
    return FormatProblem("bad PLY property line '" + line + "'");
  }
  for (const PlyProperty& other : header.Elements.back().Properties)
  {
    if (other.Name == property.Name)
    {
      return FormatProblem("PLY element '" + header.Elements.back().Name + "' has two properties '" +
        property.Name + "'");
    }
  }
  header.Elements.back().Properties.push_back(property);
  return {};
}

PlyProblem ReadPlyHeader(const std::string& bytes, PlyHeader& header)
{
  size_t offset = 0;
  std::string line;
  if (!NextLine(bytes, offset, line) || line != "ply")
  {
    return { "not a PLY file (first line is not 'ply')", vtkErrorCode::UnrecognizedFileTypeError };
  }
  bool formatSeen = false;
  std::vector<std::string_view> views;
  while (NextLine(bytes, offset, line))
  {
    slod::SplitWords(line, views);
    const std::vector<std::string> words(views.begin(), views.end());
    PlyProblem problem;
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info")
    {
      continue;
    }
    if (words[0] == "end_header")
    {
      header.BodyOffset = offset;
      return formatSeen ? PlyProblem() : FormatProblem("PLY header has no format line");
    }
    if (words[0] == "format")
    {
      problem = formatSeen ? FormatProblem("PLY header has two format lines") : ParseFormatLine(words, header);
      formatSeen = true;
    }
    else if (words[0] == "element")
    {
      problem = ParseElementLine(words, line, header);
    }
    else if (words[0] == "property")
    {
      problem = ParsePropertyLine(words, line, header);
    }
    else
    {
      problem = FormatProblem("unknown PLY header line '" + line.substr(0, 80) + "'");
    }
    if (problem)
    {
      return problem;
    }
  }
  return { "PLY header has no end_header", vtkErrorCode::PrematureEndOfFileError };
}

// A whole number within the range of the PLY integer type (binary values are by construction).
bool IsIntegerOfType(double value, const PlyScalarType& type)
{
  if (!std::isfinite(value) || value != std::floor(value))
  {
    return false;
  }
  const bool isSigned = type.VTKType == VTK_SIGNED_CHAR || type.VTKType == VTK_SHORT || type.VTKType == VTK_INT;
  const double span = std::ldexp(1.0, 8 * type.Size); // 2^bits
  return isSigned ? value >= -span / 2 && value < span / 2 : value >= 0 && value < span;
}

// The values of the body in file order, ASCII tokens or binary scalars of either byte order.
class PlyValueStream
{
public:
  PlyValueStream(const std::string& bytes, const PlyHeader& header)
    : Bytes(bytes)
    , Encoding(header.Encoding)
    , Offset(header.BodyOffset)
  {
  }

  // False at the end of the data (AtEnd()) or on a malformed ASCII value (MalformedToken()).
  bool Read(const PlyScalarType& type, double& value)
  {
    this->LastTypeRead = type.VTKType;
    if (this->Encoding != PlyEncoding::Ascii)
    {
      if (this->Remaining() < size_t(type.Size))
      {
        return false;
      }
      value = this->DecodeBinary(type);
      this->Offset += size_t(type.Size);
      return true;
    }
    if (!this->NextToken())
    {
      return false;
    }
    const auto parsed = std::from_chars(this->Token.data(), this->Token.data() + this->Token.size(), value);
    const bool number = parsed.ec == std::errc() && parsed.ptr == this->Token.data() + this->Token.size();
    // A value its type cannot hold is malformed (float: beyond FLT_MAX, but inf and nan are values).
    const bool fits = type.IsInteger() ? IsIntegerOfType(value, type)
                                       : type.VTKType != VTK_FLOAT || !std::isfinite(value) || std::fabs(value) <= FLT_MAX;
    this->Malformed = !number || !fits;
    return !this->Malformed;
  }

  // Skips `count` values (a list nobody reads); false when the data ends or a value is malformed.
  bool Skip(const PlyScalarType& type, long long count)
  {
    if (this->Binary())
    {
      const unsigned long long bytes = static_cast<unsigned long long>(count) * unsigned(type.Size);
      if (bytes > this->Remaining())
      {
        return false;
      }
      this->Offset += size_t(bytes);
      return true;
    }
    double ignored = 0;
    for (long long k = 0; k < count; ++k)
    {
      if (!this->Read(type, ignored))
      {
        return false;
      }
    }
    return true;
  }

  bool Binary() const { return this->Encoding != PlyEncoding::Ascii; }
  size_t Remaining() const { return this->Bytes.size() - this->Offset; }
  bool MalformedToken() const { return this->Malformed; }
  std::string LastToken() const { return std::string(this->Token); }
  int LastType() const { return this->LastTypeRead; }
  // Data after the last element (ASCII: anything but white space).
  bool HasTrailingData() const
  {
    return this->Binary() ? this->Offset < this->Bytes.size()
                          : this->Bytes.find_first_not_of(" \t\r\n", this->Offset) != std::string::npos;
  }

private:
  static bool IsSeparator(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

  // The next value's characters, a view into the file (no copy per value).
  bool NextToken()
  {
    const size_t size = this->Bytes.size();
    size_t start = this->Offset;
    while (start < size && IsSeparator(this->Bytes[start]))
    {
      ++start;
    }
    size_t stop = start;
    while (stop < size && !IsSeparator(this->Bytes[stop]))
    {
      ++stop;
    }
    this->Offset = stop;
    this->Token = std::string_view(this->Bytes).substr(start, stop - start);
    return stop > start;
  }

  double DecodeBinary(const PlyScalarType& type) const
  {
    const unsigned char* p = reinterpret_cast<const unsigned char*>(this->Bytes.data() + this->Offset);
    std::uint64_t bits = 0;
    for (int b = 0; b < type.Size; ++b)
    {
      const int shift = 8 * (this->Encoding == PlyEncoding::BinaryLittleEndian ? b : type.Size - 1 - b);
      bits |= std::uint64_t(p[b]) << shift;
    }
    if (type.VTKType == VTK_FLOAT)
    {
      const std::uint32_t narrow = static_cast<std::uint32_t>(bits);
      float f;
      std::memcpy(&f, &narrow, sizeof(f));
      return f;
    }
    if (type.VTKType == VTK_DOUBLE)
    {
      double d;
      std::memcpy(&d, &bits, sizeof(d));
      return d;
    }
    const bool negative = (type.VTKType == VTK_SIGNED_CHAR || type.VTKType == VTK_SHORT || type.VTKType == VTK_INT) &&
      (bits >> (8 * type.Size - 1)) != 0;
    return negative ? static_cast<double>(static_cast<long long>(bits) - (1LL << (8 * type.Size)))
                    : static_cast<double>(bits);
  }

  const std::string& Bytes;
  PlyEncoding Encoding;
  size_t Offset;
  std::string_view Token;
  bool Malformed = false;
  int LastTypeRead = VTK_VOID;
};

// Where each property of an element goes: a component of an output array, or nowhere.
struct PropertyTarget
{
  vtkDataArray* Array = nullptr;
  int Component = 0;
};

// The arrays made for one element and where its properties go.
struct ElementArrays
{
  std::vector<PropertyTarget> Targets;
  vtkSmartPointer<vtkDataArray> Points, Normals, Colors, TCoords;
  std::vector<vtkSmartPointer<vtkDataArray>> Others;
  int IndexList = -1;                    // the face's vertex index list (-1: none)
  std::vector<std::string> IgnoredLists; // other list properties, skipped
};

int FindScalarProperty(const PlyElement& element, const std::string& name)
{
  for (size_t p = 0; p < element.Properties.size(); ++p)
  {
    if (element.Properties[p].Name == name && !element.Properties[p].IsList())
    {
      return static_cast<int>(p);
    }
  }
  return -1;
}

// The properties of `names` (all of them, or at least `required` leading ones), not yet taken.
std::vector<int> FindPropertyGroup(const PlyElement& element, const std::vector<std::string>& names, size_t required,
  const ElementArrays& arrays)
{
  std::vector<int> found;
  for (const std::string& name : names)
  {
    const int p = FindScalarProperty(element, name);
    if (p < 0 || arrays.Targets[size_t(p)].Array)
    {
      break;
    }
    found.push_back(p);
  }
  return found.size() >= required ? found : std::vector<int>();
}

// Double when any property of the group is double; else float.
int RealTypeOf(const PlyElement& element, const std::vector<int>& group)
{
  for (int p : group)
  {
    if (element.Properties[size_t(p)].Value.VTKType == VTK_DOUBLE)
    {
      return VTK_DOUBLE;
    }
  }
  return VTK_FLOAT;
}

bool AllOfType(const PlyElement& element, const std::vector<int>& group, int vtkType)
{
  for (int p : group)
  {
    if (element.Properties[size_t(p)].Value.VTKType != vtkType)
    {
      return false;
    }
  }
  return !group.empty();
}

// A new array of the group's components whose properties now go to it.
vtkSmartPointer<vtkDataArray> TakeGroup(const std::vector<int>& group, int vtkType, const std::string& name,
  vtkIdType tuples, ElementArrays& arrays)
{
  auto array = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(vtkType));
  array->SetName(name.c_str());
  array->SetNumberOfComponents(static_cast<int>(group.size()));
  array->SetNumberOfTuples(tuples);
  for (size_t k = 0; k < group.size(); ++k)
  {
    arrays.Targets[size_t(group[k])] = { array, static_cast<int>(k) };
  }
  return array;
}

// The properties NAME_0, NAME_1, ... of one type that follow property `first` (named NAME_0).
std::vector<int> NumberedGroup(const PlyElement& element, int first, std::string& base)
{
  const std::string& name = element.Properties[size_t(first)].Name;
  std::vector<int> group{ first };
  if (name.size() < 3 || name.compare(name.size() - 2, 2, "_0") != 0)
  {
    return group;
  }
  base = name.substr(0, name.size() - 2);
  for (size_t p = size_t(first) + 1; p < element.Properties.size(); ++p)
  {
    const PlyProperty& next = element.Properties[p];
    if (next.IsList() || next.Value.VTKType != element.Properties[size_t(first)].Value.VTKType ||
      next.Name != base + "_" + std::to_string(group.size()))
    {
      break;
    }
    group.push_back(static_cast<int>(p));
  }
  if (group.size() == 1)
  {
    base = name; // a lone NAME_0 keeps its name
  }
  return group;
}

// Colours, then every scalar property not taken yet as an array of its own (grouped by NAME_k).
void TakeColorsAndOtherScalars(const PlyElement& element, ElementArrays& arrays)
{
  const std::vector<int> colors = FindPropertyGroup(element, slod::PlyColorNames(), 3, arrays);
  if (AllOfType(element, colors, VTK_UNSIGNED_CHAR))
  {
    arrays.Colors = TakeGroup(colors, VTK_UNSIGNED_CHAR, colors.size() == 4 ? "RGBA" : "RGB", element.Count, arrays);
  }
  for (size_t p = 0; p < element.Properties.size(); ++p)
  {
    const PlyProperty& property = element.Properties[p];
    if (property.IsList() || arrays.Targets[p].Array)
    {
      continue;
    }
    std::string name = property.Name;
    const std::vector<int> group = NumberedGroup(element, static_cast<int>(p), name);
    arrays.Others.push_back(TakeGroup(group, property.Value.VTKType, name, element.Count, arrays));
  }
}

bool IsFaceIndexList(const PlyProperty& property)
{
  return property.IsList() && (property.Name == "vertex_indices" || property.Name == "vertex_index");
}

// Where the properties of the vertex element (with the points) or of the face element (with the
// vertex index list) go: the roles first, then every other scalar property as an array of its own.
ElementArrays PlanElementArrays(const PlyElement& element, bool isVertex)
{
  ElementArrays arrays;
  arrays.Targets.resize(element.Properties.size());
  const std::vector<int> xyz = FindPropertyGroup(element, slod::PlyCoordinateNames(), 3, arrays);
  if (isVertex && xyz.size() == 3)
  {
    arrays.Points = TakeGroup(xyz, RealTypeOf(element, xyz), "Points", element.Count, arrays);
  }
  const std::vector<int> normals = FindPropertyGroup(element, slod::PlyNormalNames(), 3, arrays);
  if (normals.size() == 3)
  {
    arrays.Normals = TakeGroup(normals, RealTypeOf(element, normals), "Normals", element.Count, arrays);
  }
  for (const std::vector<std::string>& names : slod::PlyTextureNames())
  {
    const std::vector<int> uv = FindPropertyGroup(element, names, 2, arrays);
    if (uv.size() == 2 && !arrays.TCoords)
    {
      arrays.TCoords = TakeGroup(uv, RealTypeOf(element, uv), "TCoords", element.Count, arrays);
    }
  }
  for (size_t p = 0; p < element.Properties.size(); ++p)
  {
    if (!isVertex && IsFaceIndexList(element.Properties[p]) && arrays.IndexList < 0)
    {
      arrays.IndexList = static_cast<int>(p);
    }
    else if (element.Properties[p].IsList())
    {
      arrays.IgnoredLists.push_back(element.Properties[p].Name);
    }
  }
  TakeColorsAndOtherScalars(element, arrays);
  return arrays;
}

std::string Item(const PlyElement& element, long long i)
{
  return element.Name + " " + std::to_string(i) + " of " + std::to_string(element.Count);
}

// "file ends inside ..." or "malformed value ..." for a failed read of an item's property.
PlyProblem ReadFailure(const PlyValueStream& values, const PlyElement& element, long long i, const PlyProperty& p)
{
  if (values.MalformedToken())
  {
    return FormatProblem(Item(element, i) + ": malformed " + slod::PlyScalarTypeName(values.LastType()) + " value '" +
      values.LastToken().substr(0, 40) + "' for property '" + p.Name + "'");
  }
  return { "file ends inside " + Item(element, i) + " (property '" + p.Name + "')",
    vtkErrorCode::PrematureEndOfFileError };
}

// The room the rest of the file has for the element's items: counts it cannot hold are refused
// before anything is allocated.
PlyProblem CheckCountFits(const PlyValueStream& values, const PlyElement& element)
{
  const long long minimum = std::max(1LL, element.MinimumItemSize(values.Binary()));
  const unsigned long long room = values.Remaining() + (values.Binary() ? 0 : 1);
  if (element.Count > 0 && static_cast<unsigned long long>(element.Count) > room / static_cast<unsigned long long>(minimum))
  {
    return { "the header announces " + std::to_string(element.Count) + " " + element.Name + " elements, more than the " +
        std::to_string(values.Remaining()) + " bytes left can hold",
      vtkErrorCode::PrematureEndOfFileError };
  }
  return {};
}

const char* ByteOrderHint(const PlyValueStream& values)
{
  return values.Binary() ? " (a wrong byte order in the format line?)" : "";
}

// One face's vertex indices, each checked against the vertex count.
PlyProblem ReadFaceIndices(PlyValueStream& values, const PlyElement& element, long long i, const PlyProperty& list,
  long long vertexCount, std::vector<vtkIdType>& ids)
{
  double length = 0;
  if (!values.Read(list.Count, length))
  {
    return ReadFailure(values, element, i, list);
  }
  const long long count = static_cast<long long>(length);
  if (count < 0 || (values.Binary() && static_cast<unsigned long long>(count) * unsigned(list.Value.Size) > values.Remaining()))
  {
    return { Item(element, i) + " announces " + std::to_string(count) + " vertices, more than the file holds" +
        ByteOrderHint(values),
      vtkErrorCode::PrematureEndOfFileError };
  }
  ids.clear();
  if (!list.Value.IsInteger())
  {
    return FormatProblem(Item(element, i) + ": the vertex index list holds " +
      slod::PlyScalarTypeName(list.Value.VTKType) + " values, not integers");
  }
  for (long long k = 0; k < count; ++k)
  {
    double id = 0;
    if (!values.Read(list.Value, id))
    {
      return ReadFailure(values, element, i, list);
    }
    if (id < 0 || id >= static_cast<double>(vertexCount))
    {
      return FormatProblem(Item(element, i) + " refers to vertex " + std::to_string(static_cast<long long>(id)) +
        " but the file has " + std::to_string(vertexCount) + " vertices" + ByteOrderHint(values));
    }
    ids.push_back(static_cast<vtkIdType>(id));
  }
  return {};
}

// What the reading of the body produces.
struct PlyContent
{
  ElementArrays Vertices, Faces;
  vtkNew<vtkCellArray> Polygons;
  long long VertexCount = -1;
  long long SmallFaces = 0;            // faces of fewer than three vertices, skipped
  std::vector<std::string> Unread;     // elements and list properties not read, for the warning
};

// The values of one item into row `row` of the element's arrays (its index list into `ids`).
PlyProblem ReadItem(PlyValueStream& values, const PlyElement& element, long long i, vtkIdType row,
  const ElementArrays& arrays, long long vertexCount, std::vector<vtkIdType>& ids)
{
  for (size_t p = 0; p < element.Properties.size(); ++p)
  {
    const PlyProperty& property = element.Properties[p];
    PlyProblem problem;
    double value = 0;
    if (static_cast<int>(p) == arrays.IndexList)
    {
      problem = ReadFaceIndices(values, element, i, property, vertexCount, ids);
    }
    else if (property.IsList())
    {
      problem = values.Read(property.Count, value) && value >= 0 && values.Skip(property.Value, static_cast<long long>(value))
        ? PlyProblem()
        : ReadFailure(values, element, i, property);
    }
    else if (!values.Read(property.Value, value))
    {
      problem = ReadFailure(values, element, i, property);
    }
    else if (const PropertyTarget& target = arrays.Targets[p]; target.Array)
    {
      target.Array->SetComponent(row, target.Component, value);
    }
    if (problem)
    {
      return problem;
    }
  }
  return {};
}

// Faces of fewer than three vertices take no row: the arrays end at the last face kept.
void TrimRows(ElementArrays& arrays, vtkIdType rows)
{
  for (vtkDataArray* array : { arrays.Normals.Get(), arrays.TCoords.Get(), arrays.Colors.Get() })
  {
    if (array)
    {
      array->SetNumberOfTuples(rows);
    }
  }
  for (const auto& array : arrays.Others)
  {
    array->SetNumberOfTuples(rows);
  }
}

PlyProblem ReadElement(PlyValueStream& values, const PlyElement& element, PlyContent& content)
{
  const bool isVertex = element.Name == "vertex" && content.VertexCount < 0;
  const bool isFace = element.Name == "face" && content.Faces.Targets.empty() && content.VertexCount >= 0;
  PlyProblem problem = CheckCountFits(values, element);
  if (problem)
  {
    return problem;
  }
  ElementArrays none;
  none.Targets.resize(element.Properties.size());
  if (isVertex)
  {
    content.Vertices = PlanElementArrays(element, true);
    content.VertexCount = element.Count;
  }
  else if (isFace)
  {
    content.Faces = PlanElementArrays(element, false);
  }
  else
  {
    content.Unread.push_back("element '" + element.Name + "' (" + std::to_string(element.Count) + " items)");
  }
  const ElementArrays& arrays = isVertex ? content.Vertices : isFace ? content.Faces : none;
  std::vector<vtkIdType> ids;
  vtkIdType row = 0;
  for (long long i = 0; i < element.Count && !problem; ++i)
  {
    problem = ReadItem(values, element, i, row, arrays, content.VertexCount, ids);
    if (!isFace || ids.size() >= 3)
    {
      ++row;
    }
    if (isFace && ids.size() >= 3)
    {
      content.Polygons->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
    }
    content.SmallFaces += isFace && ids.size() < 3 ? 1 : 0;
  }
  if (isFace && !problem)
  {
    TrimRows(content.Faces, row);
  }
  return problem;
}

// The structure the reader needs before the body: a vertex element with scalar x, y, z before
// any face element, and a face element with an index list.
PlyProblem CheckPlyStructure(const PlyHeader& header)
{
  bool vertexSeen = false;
  for (const PlyElement& element : header.Elements)
  {
    if (element.Name == "vertex" && !vertexSeen)
    {
      vertexSeen = true;
      int xyz = 0;
      for (const std::string& name : slod::PlyCoordinateNames())
      {
        xyz += FindScalarProperty(element, name) >= 0 ? 1 : 0;
      }
      if (xyz != 3)
      {
        return FormatProblem("PLY vertex element lacks scalar x, y, z properties");
      }
    }
    if (element.Name == "face" && !vertexSeen)
    {
      return FormatProblem("PLY face element comes before the vertex element");
    }
    bool hasIndices = false;
    for (const PlyProperty& property : element.Properties)
    {
      hasIndices = hasIndices || IsFaceIndexList(property);
    }
    if (element.Name == "face" && element.Count > 0 && !hasIndices)
    {
      return FormatProblem("PLY face element has no vertex_indices list");
    }
  }
  return vertexSeen ? PlyProblem() : FormatProblem("PLY file has no vertex element");
}

void AddArrays(vtkDataSetAttributes* data, const ElementArrays& arrays)
{
  if (arrays.Normals)
  {
    data->SetNormals(arrays.Normals);
  }
  if (arrays.TCoords)
  {
    data->SetTCoords(arrays.TCoords);
  }
  if (arrays.Colors)
  {
    data->SetScalars(arrays.Colors);
  }
  for (const auto& array : arrays.Others)
  {
    data->AddArray(array);
  }
}

// What was read, and not read, of the file, as one sentence ("" when everything was read).
std::string UnreadSummary(const PlyContent& content, bool trailingData)
{
  std::vector<std::string> parts = content.Unread;
  for (const std::string& name : content.Vertices.IgnoredLists)
  {
    parts.push_back("vertex list property '" + name + "'");
  }
  for (const std::string& name : content.Faces.IgnoredLists)
  {
    parts.push_back("face list property '" + name + "'");
  }
  if (content.SmallFaces > 0)
  {
    parts.push_back(std::to_string(content.SmallFaces) + " faces of fewer than three vertices");
  }
  if (trailingData)
  {
    parts.push_back("data after the elements the header announces");
  }
  std::string summary;
  for (const std::string& part : parts)
  {
    summary += (summary.empty() ? "" : ", ") + part;
  }
  return summary.empty() ? summary : "not read: " + summary;
}
} // namespace

int vtkPLYMeshReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->StartRead();
  auto fail = [&](const PlyProblem& problem) { return this->FailRead(output, problem.Message, problem.Code); };
  std::string bytes;
  if (this->FileName.empty() || !slod::ReadWholeFile(this->FileName, bytes))
  {
    return fail({ std::string("cannot open file (") + std::strerror(errno) + ")", vtkErrorCode::CannotOpenFileError });
  }
  PlyHeader header;
  PlyProblem problem = ReadPlyHeader(bytes, header);
  problem = problem ? problem : CheckPlyStructure(header);
  PlyValueStream values(bytes, header);
  PlyContent content;
  for (size_t e = 0; e < header.Elements.size() && !problem; ++e)
  {
    problem = ReadElement(values, header.Elements[e], content);
  }
  if (problem)
  {
    return fail(problem);
  }
  const std::string unread = UnreadSummary(content, values.HasTrailingData());
  if (!unread.empty())
  {
    this->WarnNotRead(unread);
  }
  vtkNew<vtkPoints> points;
  points->SetData(content.Vertices.Points);
  output->SetPoints(points);
  output->SetPolys(content.Polygons);
  AddArrays(output->GetPointData(), content.Vertices);
  AddArrays(output->GetCellData(), content.Faces);
  return 1;
}
