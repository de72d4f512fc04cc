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

// Cell point ids in range and finite coordinates: readers do not all check this, and a bad id
// would crash a filter later.
std::string ValidateSurface(vtkPolyData* mesh)
{
  const vtkIdType numPoints = mesh->GetNumberOfPoints();
  const vtkIdType numSurfaceCells = mesh->GetNumberOfPolys() + mesh->GetNumberOfStrips();
  if (numSurfaceCells == 0)
  {
    return "no surface in the file (0 polygons)";
  }
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
      }
    }
  }
  vtkDataArray* coordinates = mesh->GetPoints()->GetData();
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    double p[3];
    coordinates->GetTuple(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      return "vertex " + std::to_string(i) + " has a NaN or infinite coordinate";
    }
  }
  return std::string();
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
      auto r = vtkSmartPointer<vtkPLYReader>::New();
      r->SetFileName(path.c_str());
      reader = r;
    }
    else if (ext == ".stl")
    {
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
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
  {
    throw fail("directory " + parent.string() + " does not exist");
  }
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
