#include "MeshIO.h"

#include "CliSupport.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkOBJReader.h"
#include "vtkOBJWriter.h"
#include "vtkOFFMeshReader.h"
#include "vtkOFFMeshWriter.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"
#include "vtkPLYReader.h"
#include "vtkPLYWriter.h"
#include "vtkPoints.h"
#include "vtkPolyDataReader.h"
#include "vtkPolyDataWriter.h"
#include "vtkSTLReader.h"
#include "vtkSTLWriter.h"
#include "vtkTriangleFilter.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkWriter.h"
#include "vtkXMLPolyDataWriter.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

namespace slodcli
{
namespace
{
// "ERROR: In /path/file.cxx, line 12\nvtkPLYReader (0x1234): Could not open\n\n" -> "Could not open".
std::string CleanVTKMessage(const std::string& text)
{
  static const std::regex location("^(ERROR|Warning|Generic Warning|Debug): In .*, line [0-9]+$");
  static const std::regex sender("^[A-Za-z0-9_:]+ \\(0x[0-9a-fA-F]+\\): ");
  std::string result;
  std::string line;
  std::istringstream lines(text);
  while (std::getline(lines, line))
  {
    if (line.empty() || std::regex_match(line, location))
    {
      continue;
    }
    line = std::regex_replace(line, sender, "");
    result += (result.empty() ? "" : "; ") + line;
  }
  return result;
}

std::vector<std::string> CapturedMessages;
size_t CaptureDepth = 0;
bool SwallowWarnings = false;

class CliOutputWindow : public vtkOutputWindow
{
public:
  static CliOutputWindow* New();
  vtkTypeMacro(CliOutputWindow, vtkOutputWindow);

  void DisplayErrorText(const char* text) override { this->Handle("error", text); }
  void DisplayWarningText(const char* text) override { this->Handle("warning", text); }
  void DisplayGenericWarningText(const char* text) override { this->Handle("warning", text); }
  void DisplayDebugText(const char*) override {}
  void DisplayText(const char* text) override { std::cerr << text; }

private:
  void Handle(const char* kind, const char* text)
  {
    const std::string message = CleanVTKMessage(text ? text : "");
    if (CaptureDepth > 0)
    {
      if (std::strcmp(kind, "error") == 0)
      {
        CapturedMessages.push_back(message);
        return;
      }
      if (SwallowWarnings)
      {
        return;
      }
    }
    std::cerr << "surfacelod: " << kind << ": " << message << std::endl;
  }
};
vtkStandardNewMacro(CliOutputWindow);

std::string Extension(const std::string& path)
{
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// Cell point ids in range and finite coordinates of the used points: readers do not all check this, and a bad id
// would crash a filter later.
std::string ValidateSurface(vtkPolyData* mesh)
{
  const vtkIdType numPoints = mesh->GetNumberOfPoints();
  const vtkIdType numSurfaceCells = mesh->GetNumberOfPolys() + mesh->GetNumberOfStrips();
  if (numSurfaceCells == 0)
  {
    return "no surface in the file (0 polygons)";
  }
  std::vector<char> used(static_cast<size_t>(numPoints), 0);
  for (vtkCellArray* cells : { mesh->GetVerts(), mesh->GetLines(), mesh->GetPolys(), mesh->GetStrips() })
  {
    if (!cells)
    {
      continue;
    }
    auto it = vtk::TakeSmartPointer(cells->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      for (vtkIdType k = 0; k < n; ++k)
      {
        if (ids[k] < 0 || ids[k] >= numPoints)
        {
          return "a face refers to vertex " + std::to_string(ids[k]) + " but the file has " +
            std::to_string(numPoints) + " vertices";
        }
        used[static_cast<size_t>(ids[k])] = 1;
      }
    }
  }
  vtkDataArray* coordinates = mesh->GetPoints()->GetData();
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    if (!used[static_cast<size_t>(i)])
    {
      continue; // an unused point cannot harm: the filters never look at it
    }
    double p[3];
    coordinates->GetTuple(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      return "vertex " + std::to_string(i) + " has a NaN or infinite coordinate";
    }
  }
  return std::string();
}

// vtkPLYReader reads past the end of truncated files (and crashes): check the structure first.
// Returns "" when the header is sound and the body holds every element the header announces.
std::string ValidatePLY(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::string line;
  auto nextHeaderLine = [&]() -> bool {
    if (!std::getline(in, line))
    {
      return false;
    }
    if (!line.empty() && line.back() == '\r')
    {
      line.pop_back();
    }
    return true;
  };
  if (!nextHeaderLine() || line != "ply")
  {
    return "not a PLY file (first line is not 'ply')";
  }
  struct Property
  {
    int Size = 0;      // scalar size, or item size of a list
    int CountSize = 0; // > 0 for lists
    std::string Name;
  };
  struct Element
  {
    std::string Name;
    long long Count = 0;
    std::vector<Property> Properties;
  };
  auto typeSize = [](const std::string& t) -> int {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
  };
  std::string format;
  std::vector<Element> elements;
  bool ended = false;
  while (nextHeaderLine())
  {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "end_header")
    {
      ended = true;
      break;
    }
    if (keyword == "format")
    {
      words >> format;
    }
    else if (keyword == "element")
    {
      Element e;
      if (!(words >> e.Name >> e.Count) || e.Count < 0)
      {
        return "bad PLY element line '" + line + "'";
      }
      elements.push_back(e);
    }
    else if (keyword == "property")
    {
      if (elements.empty())
      {
        return "PLY property before any element";
      }
      Property p;
      std::string type;
      words >> type;
      if (type == "list")
      {
        std::string countType, itemType;
        words >> countType >> itemType;
        p.CountSize = typeSize(countType);
        p.Size = typeSize(itemType);
        if (p.CountSize == 0 || p.Size == 0)
        {
          return "bad PLY property line '" + line + "'";
        }
      }
      else if ((p.Size = typeSize(type)) == 0)
      {
        return "bad PLY property line '" + line + "'";
      }
      if (!(words >> p.Name))
      {
        return "bad PLY property line '" + line + "'";
      }
      elements.back().Properties.push_back(p);
    }
    else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty())
    {
      return "unknown PLY header line '" + line + "'";
    }
  }
  if (!ended)
  {
    return "PLY header has no end_header";
  }
  bool hasVertex = false;
  for (const Element& e : elements)
  {
    if (e.Name == "vertex")
    {
      int xyz = 0;
      for (const Property& p : e.Properties)
      {
        xyz += p.CountSize == 0 && (p.Name == "x" || p.Name == "y" || p.Name == "z");
      }
      hasVertex = xyz == 3;
    }
  }
  if (!hasVertex)
  {
    return "PLY file has no vertex element with x, y, z";
  }
  if (format == "ascii")
  {
    for (const Element& e : elements)
    {
      for (long long i = 0; i < e.Count; ++i)
      {
        if (!std::getline(in, line))
        {
          return "file ends after " + std::to_string(i) + " of " + std::to_string(e.Count) + " " + e.Name +
            " elements";
        }
        std::istringstream words(line);
        for (const Property& p : e.Properties)
        {
          double value;
          long long count = 1;
          if (p.CountSize > 0 && (!(words >> count) || count < 0))
          {
            return "malformed " + e.Name + " " + std::to_string(i) + " (bad list count)";
          }
          for (long long k = 0; k < count; ++k)
          {
            if (!(words >> value))
            {
              return "malformed " + e.Name + " " + std::to_string(i) + " (too few values)";
            }
          }
        }
      }
    }
    return std::string();
  }
  const bool little = format == "binary_little_endian";
  if (!little && format != "binary_big_endian")
  {
    return "unknown PLY format '" + format + "'";
  }
  for (const Element& e : elements)
  {
    for (long long i = 0; i < e.Count; ++i)
    {
      for (const Property& p : e.Properties)
      {
        long long count = 1;
        if (p.CountSize > 0)
        {
          unsigned char bytes[8] = {};
          if (!in.read(reinterpret_cast<char*>(bytes), p.CountSize))
          {
            return "file ends inside " + e.Name + " " + std::to_string(i) + " of " + std::to_string(e.Count);
          }
          unsigned long long value = 0;
          for (int b = 0; b < p.CountSize; ++b)
          {
            const int shift = 8 * (little ? b : p.CountSize - 1 - b);
            value |= static_cast<unsigned long long>(bytes[b]) << shift;
          }
          count = static_cast<long long>(value);
        }
        in.seekg(count * p.Size, std::ios::cur);
        if (!in || in.peek() == std::ifstream::traits_type::eof())
        {
          in.clear();
          // The last value of the last element may end exactly at the end of the file.
          const std::streamoff position = in.tellg();
          in.seekg(0, std::ios::end);
          if (!in || position < 0 || position > in.tellg())
          {
            return "file ends inside " + e.Name + " " + std::to_string(i) + " of " + std::to_string(e.Count);
          }
          in.seekg(position);
        }
      }
    }
  }
  return std::string();
}

// vtkSTLReader silently reads a truncated binary STL: compare the size with the announced count.
std::string ValidateSTL(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  unsigned char header[84] = {};
  in.read(reinterpret_cast<char*>(header), sizeof(header));
  const std::streamsize got = in.gcount();
  in.clear();
  in.seekg(0, std::ios::end);
  const unsigned long long size = static_cast<unsigned long long>(in.tellg());
  const bool startsWithSolid = got >= 5 && std::string(reinterpret_cast<char*>(header), 5) == "solid";
  if (got == 84)
  {
    const unsigned long long count = header[80] | (header[81] << 8) | (header[82] << 16) |
      (static_cast<unsigned long long>(header[83]) << 24);
    const unsigned long long expected = 84 + 50 * count;
    if (size >= expected && (!startsWithSolid || size == expected))
    {
      return std::string(); // binary
    }
    if (!startsWithSolid)
    {
      return "truncated binary STL: the header announces " + std::to_string(count) + " triangles (" +
        std::to_string(expected) + " bytes), the file has " + std::to_string(size) + " bytes";
    }
  }
  return startsWithSolid ? std::string() : std::string("not an STL file (too short)");
}
} // namespace

void InstallMessageHandler()
{
  // Errors are reported once, through our output window, not a second time by the logger.
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  vtkNew<CliOutputWindow> window;
  vtkOutputWindow::SetInstance(window);
}

MessageCapture::MessageCapture(bool swallowWarnings)
  : Depth(CapturedMessages.size())
  , PreviousSwallow(SwallowWarnings)
{
  ++CaptureDepth;
  SwallowWarnings = swallowWarnings;
}

MessageCapture::~MessageCapture()
{
  --CaptureDepth;
  SwallowWarnings = this->PreviousSwallow;
  CapturedMessages.resize(this->Depth);
}

const std::vector<std::string>& MessageCapture::Errors() const
{
  return CapturedMessages;
}

std::string MessageCapture::FirstError() const
{
  return CapturedMessages.size() > this->Depth ? CapturedMessages[this->Depth] : std::string();
}

std::string ReadableExtensions()
{
  return ".off .ply .stl .obj .vtp .vtk";
}

std::string WritableExtensions()
{
  return ".off .ply .stl .obj .vtp .vtk";
}

vtkSmartPointer<vtkPolyData> ReadMesh(const std::string& path)
{
  auto fail = [&](const std::string& problem) { return CliError(ExitData, path + ": " + problem); };
  const std::string ext = Extension(path);
  static const std::vector<std::string> known = { ".off", ".ply", ".stl", ".obj", ".vtp", ".vtk" };
  if (std::find(known.begin(), known.end(), ext) == known.end())
  {
    throw fail("unsupported file type '" + ext + "' (readable: " + ReadableExtensions() + ")");
  }
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
  {
    throw fail("no such file");
  }
  if (std::filesystem::is_directory(path, ec))
  {
    throw fail("is a directory, not a mesh file");
  }
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
    {
      throw fail(std::string("cannot open file (") + std::strerror(errno) + ")");
    }
    if (probe.peek() == std::ifstream::traits_type::eof())
    {
      throw fail("empty file");
    }
  }

  MessageCapture capture;
  vtkSmartPointer<vtkPolyData> mesh;
  std::string problem;
  if (ext == ".off")
  {
    vtkNew<vtkOFFMeshReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    if (reader->GetErrorCode() != vtkErrorCode::NoError)
    {
      // The reader's message already starts with the path (and line number).
      throw CliError(ExitData, reader->GetLastError());
    }
    mesh = reader->GetOutput();
  }
  else
  {
    vtkSmartPointer<vtkAlgorithm> reader;
    if (ext == ".ply")
    {
      const std::string plyProblem = ValidatePLY(path);
      if (!plyProblem.empty())
      {
        throw fail(plyProblem);
      }
      auto r = vtkSmartPointer<vtkPLYReader>::New();
      r->SetFileName(path.c_str());
      reader = r;
    }
    else if (ext == ".stl")
    {
      const std::string stlProblem = ValidateSTL(path);
      if (!stlProblem.empty())
      {
        throw fail(stlProblem);
      }
      auto r = vtkSmartPointer<vtkSTLReader>::New();
      r->SetFileName(path.c_str());
      reader = r;
    }
    else if (ext == ".obj")
    {
      auto r = vtkSmartPointer<vtkOBJReader>::New();
      r->SetFileName(path.c_str());
      reader = r;
    }
    else if (ext == ".vtp")
    {
      auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
      r->SetFileName(path.c_str());
      reader = r;
    }
    else
    {
      auto r = vtkSmartPointer<vtkPolyDataReader>::New();
      r->SetFileName(path.c_str());
      reader = r;
    }
    reader->Update();
    mesh = vtkPolyData::SafeDownCast(reader->GetOutputDataObject(0));
    if (!capture.FirstError().empty())
    {
      problem = capture.FirstError();
    }
    else if (reader->GetErrorCode() != vtkErrorCode::NoError)
    {
      problem = std::string("read error: ") + vtkErrorCode::GetStringFromErrorCode(reader->GetErrorCode());
    }
  }
  if (problem.empty() && (!mesh || !mesh->GetPoints()))
  {
    problem = "no surface in the file (0 vertices)";
  }
  if (problem.empty())
  {
    problem = ValidateSurface(mesh);
  }
  if (!problem.empty())
  {
    throw fail(problem);
  }
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->ShallowCopy(mesh);
  return result;
}

void CheckWritablePath(const std::string& path)
{
  static const std::vector<std::string> known = { ".off", ".ply", ".stl", ".obj", ".vtp", ".vtk" };
  const std::string ext = Extension(path);
  if (std::find(known.begin(), known.end(), ext) == known.end())
  {
    throw CliError(ExitData, path + ": unsupported file type '" + ext + "' (writable: " + WritableExtensions() + ")");
  }
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
  {
    throw CliError(ExitData, path + ": directory " + parent.string() + " does not exist");
  }
}

void WriteMesh(vtkPolyData* mesh, const std::string& path)
{
  auto fail = [&](const std::string& problem) { return CliError(ExitData, path + ": " + problem); };
  const std::string ext = Extension(path);
  // vtkXMLWriter is not a vtkWriter: keep the algorithm and its Write().
  vtkSmartPointer<vtkAlgorithm> writer;
  std::function<int()> write;
  if (ext == ".off")
  {
    auto w = vtkSmartPointer<vtkOFFMeshWriter>::New();
    w->SetFileName(path.c_str());
    writer = w;
    write = [w]() { return w->Write(); };
  }
  else if (ext == ".ply")
  {
    auto w = vtkSmartPointer<vtkPLYWriter>::New();
    w->SetFileName(path.c_str());
    w->SetFileTypeToBinary();
    writer = w;
    write = [w]() { return w->Write(); };
  }
  else if (ext == ".stl")
  {
    auto w = vtkSmartPointer<vtkSTLWriter>::New();
    w->SetFileName(path.c_str());
    w->SetFileTypeToBinary();
    writer = w;
    write = [w]() { return w->Write(); };
  }
  else if (ext == ".obj")
  {
    auto w = vtkSmartPointer<vtkOBJWriter>::New();
    w->SetFileName(path.c_str());
    writer = w;
    write = [w]() { return w->Write(); };
  }
  else if (ext == ".vtp")
  {
    auto w = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
    w->SetFileName(path.c_str());
    w->SetDataModeToAppended();
    writer = w;
    write = [w]() { return w->Write(); };
  }
  else if (ext == ".vtk")
  {
    auto w = vtkSmartPointer<vtkPolyDataWriter>::New();
    w->SetFileName(path.c_str());
    w->SetFileTypeToBinary();
    writer = w;
    write = [w]() { return w->Write(); };
  }
  else
  {
    throw fail("unsupported file type '" + ext + "' (writable: " + WritableExtensions() + ")");
  }
  CheckWritablePath(path);
  MessageCapture capture;
  writer->SetInputDataObject(0, mesh);
  const int ok = write();
  if (!capture.FirstError().empty())
  {
    throw fail("cannot write: " + capture.FirstError());
  }
  if (!ok || writer->GetErrorCode() != vtkErrorCode::NoError)
  {
    throw fail(std::string("cannot write: ") +
      (writer->GetErrorCode() != vtkErrorCode::NoError ? vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode())
                                                        : "writer failed"));
  }
}

vtkSmartPointer<vtkPolyData> TriangulatedSurface(vtkPolyData* mesh)
{
  bool trianglesOnly = mesh->GetNumberOfStrips() == 0 && mesh->GetNumberOfVerts() == 0 &&
    mesh->GetNumberOfLines() == 0;
  if (trianglesOnly)
  {
    vtkCellArray* polys = mesh->GetPolys();
    trianglesOnly = polys->IsHomogeneous() == 3 || polys->GetNumberOfCells() == 0;
  }
  if (trianglesOnly)
  {
    return mesh;
  }
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  triangulate->SetInputData(mesh);
  triangulate->Update();
  vtkSmartPointer<vtkPolyData> out = triangulate->GetOutput();
  return out;
}

vtkIdType CountTriangles(vtkPolyData* triangles)
{
  return triangles->GetNumberOfPolys();
}
} // namespace slodcli
