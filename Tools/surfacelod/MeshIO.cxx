// SPDX-License-Identifier: BSD-3-Clause
#include "MeshIO.h"

#include "CliSupport.h"
#include "MeshFileChecks.h"
#include "PartitionedFiles.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "slodCheckedFile.h"
#include "slodMeshFileSupport.h"
#include "vtkOBJMeshReader.h"
#include "vtkOBJMeshWriter.h"
#include "vtkOFFMeshReader.h"
#include "vtkOFFMeshWriter.h"
#include "vtkPLYMeshReader.h"
#include "vtkPLYMeshWriter.h"
#include "vtkPointData.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"
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
std::vector<std::string> HeldWarningTexts; // warnings of an active capture that swallows them
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
        HeldWarningTexts.push_back(message);
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

// Cell point ids in range (readers do not all check this, and a bad id would crash a filter later);
// marks the points the cells use.
std::string CheckCellIds(vtkPolyData* mesh, std::vector<char>& used)
{
  const vtkIdType numPoints = mesh->GetNumberOfPoints();
  used.assign(static_cast<size_t>(numPoints), 0);
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
  return std::string();
}

// Finite coordinates on every used point (an unused point cannot harm: the filters never look at it).
std::string CheckUsedCoordinates(vtkPolyData* mesh, const std::vector<char>& used)
{
  vtkDataArray* coordinates = mesh->GetPoints()->GetData();
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    if (!used[static_cast<size_t>(i)])
    {
      continue;
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

// True when the cell has three points at pairwise different positions: a triangle that survives the
// filters' merging of coincident points and removal of collapsed triangles.
bool HasDistinctTriangle(vtkPoints* points, vtkIdType n, const vtkIdType* ids)
{
  auto same = [](const double* a, const double* b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; };
  double first[3], second[3], p[3];
  bool haveSecond = false;
  for (vtkIdType k = 0; k < n; ++k)
  {
    points->GetPoint(ids[k], k == 0 ? first : p);
    if (k == 0 || same(p, first) || (haveSecond && same(p, second)))
    {
      continue;
    }
    if (haveSecond)
    {
      return true; // a third position
    }
    std::copy(p, p + 3, second);
    haveSecond = true;
  }
  return false;
}

// At least one polygon or strip with a triangle the filters can use; else what the file holds.
std::string CheckUsableSurface(vtkPolyData* mesh)
{
  const vtkIdType surfaceCells = mesh->GetNumberOfPolys() + mesh->GetNumberOfStrips();
  for (vtkCellArray* cells : { mesh->GetPolys(), mesh->GetStrips() })
  {
    auto it = vtk::TakeSmartPointer(cells->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      if (HasDistinctTriangle(mesh->GetPoints(), n, ids))
      {
        return std::string();
      }
    }
  }
  if (surfaceCells > 0)
  {
    return "no usable triangles: every one of the " + std::to_string(surfaceCells) +
      " faces has fewer than three distinct vertex positions";
  }
  return "no surface in the file (0 polygons, " + std::to_string(mesh->GetNumberOfLines()) + " lines, " +
    std::to_string(mesh->GetNumberOfVerts()) + " vertex cells)";
}

std::string ValidateSurface(vtkPolyData* mesh)
{
  if (!mesh || !mesh->GetPoints() || mesh->GetNumberOfPoints() == 0)
  {
    return "no surface in the file (0 vertices)";
  }
  std::vector<char> used;
  std::string problem = CheckCellIds(mesh, used);
  if (problem.empty())
  {
    problem = CheckUsedCoordinates(mesh, used);
  }
  return problem.empty() ? CheckUsableSurface(mesh) : problem;
}

const std::vector<std::string>& KnownExtensions()
{
  static const std::vector<std::string> known = { ".off", ".ply", ".stl", ".obj", ".vtp", ".vtk", ".pvtp" };
  return known;
}

// Exists, is a readable non-empty file of a known type; throws the CliError otherwise.
void CheckReadableFile(const std::string& path, const std::string& ext)
{
  auto fail = [&](const std::string& problem) { return CliError(ExitData, path + ": " + problem); };
  if (std::find(KnownExtensions().begin(), KnownExtensions().end(), ext) == KnownExtensions().end())
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

// The byte-level check of the format whose VTK reader needs one (STL; the project's own OFF, PLY and
// OBJ readers check everything themselves).
FileCheck CheckFileBytes(const std::string& path, const std::string& ext)
{
  return ext == ".stl" ? CheckSTLFile(path) : FileCheck();
}

struct VTKReadResult
{
  vtkSmartPointer<vtkPolyData> Mesh;
  std::string Problem;               // "" when the reader succeeded; else starts with the path
  std::vector<std::string> Warnings; // the reader's own, each starting with the path
};

template <typename Reader>
vtkSmartPointer<vtkAlgorithm> NewReader(const std::string& path)
{
  auto reader = vtkSmartPointer<Reader>::New();
  reader->SetFileName(path.c_str());
  return reader;
}

// The VTK reader of the extension, its errors and warnings captured.
VTKReadResult ReadWithVTK(const std::string& path, const std::string& ext)
{
  VTKReadResult result;
  if (ext == ".pvtp")
  {
    result.Mesh = ReadPartitioned(path); // its pieces, merged where they meet; throws its problems
    return result;
  }
  const vtkSmartPointer<vtkAlgorithm> reader = ext == ".off" ? NewReader<vtkOFFMeshReader>(path)
    : ext == ".ply"                                           ? NewReader<vtkPLYMeshReader>(path)
    : ext == ".stl"                                           ? NewReader<vtkSTLReader>(path)
    : ext == ".obj"                                           ? NewReader<vtkOBJMeshReader>(path)
    : ext == ".vtp"                                           ? NewReader<vtkXMLPolyDataReader>(path)
                                                              : NewReader<vtkPolyDataReader>(path);
  MessageCapture capture;
  reader->Update();
  const char* ownError = vtkOFFMeshReader::SafeDownCast(reader) ? vtkOFFMeshReader::SafeDownCast(reader)->GetLastError()
    : vtkPLYMeshReader::SafeDownCast(reader)                    ? vtkPLYMeshReader::SafeDownCast(reader)->GetLastError()
    : vtkOBJMeshReader::SafeDownCast(reader)                    ? vtkOBJMeshReader::SafeDownCast(reader)->GetLastError()
                                                                : nullptr;
  if (ownError)
  {
    result.Problem = ownError; // already starts with the path (and line number)
  }
  else if (!capture.FirstError().empty())
  {
    result.Problem = path + ": " + capture.FirstError();
  }
  else if (reader->GetErrorCode() != vtkErrorCode::NoError)
  {
    result.Problem = path + ": read error: " + vtkErrorCode::GetStringFromErrorCode(reader->GetErrorCode());
  }
  for (const std::string& warning : capture.HeldWarnings())
  {
    result.Warnings.push_back(warning.compare(0, path.size(), path) == 0 ? warning : path + ": " + warning);
  }
  result.Mesh = vtkPolyData::SafeDownCast(reader->GetOutputDataObject(0));
  return result;
}

template <typename Writer>
vtkSmartPointer<vtkWriter> NewWriter(const std::string& path)
{
  auto writer = vtkSmartPointer<Writer>::New();
  writer->SetFileName(path.c_str());
  return writer;
}

// Writers that check their own writes: the project's OFF, PLY (binary) and OBJ writers, and
// vtkSTLWriter (binary). Returns the problem, "" on success.
std::string WriteFileWithVTK(vtkPolyData* mesh, const std::string& path, const std::string& ext)
{
  vtkSmartPointer<vtkWriter> writer = ext == ".off" ? NewWriter<vtkOFFMeshWriter>(path)
    : ext == ".ply"                                 ? NewWriter<vtkPLYMeshWriter>(path)
    : ext == ".obj"                                 ? NewWriter<vtkOBJMeshWriter>(path)
                                                    : NewWriter<vtkSTLWriter>(path);
  if (auto* stl = vtkSTLWriter::SafeDownCast(writer))
  {
    stl->SetFileTypeToBinary();
  }
  MessageCapture capture;
  writer->SetInputData(mesh);
  const int ok = writer->Write();
  if (!capture.FirstError().empty())
  {
    return capture.FirstError();
  }
  if (!ok || writer->GetErrorCode() != vtkErrorCode::NoError)
  {
    return writer->GetErrorCode() != vtkErrorCode::NoError
      ? vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode())
      : "writer failed";
  }
  return std::string();
}

// VTP (appended) and legacy VTK (binary) files made in memory by VTK's writers.
std::string SerializeWithVTK(vtkPolyData* mesh, const std::string& ext, std::string& bytes)
{
  MessageCapture capture;
  if (ext == ".vtp")
  {
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetDataModeToAppended();
    w->WriteToOutputStringOn();
    w->SetInputData(mesh);
    w->Write();
    bytes = w->GetOutputString();
  }
  else if (ext == ".vtk")
  {
    vtkNew<vtkPolyDataWriter> w;
    w->SetFileTypeToBinary();
    w->WriteToOutputStringOn();
    w->SetInputData(mesh);
    w->Write();
    bytes = w->GetOutputStdString();
  }
  else
  {
    return "unsupported file type '" + ext + "' (writable: " + WritableExtensions() + ")";
  }
  if (!capture.FirstError().empty())
  {
    return capture.FirstError();
  }
  return bytes.empty() ? "the writer produced nothing" : std::string();
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
  , WarningDepth(HeldWarningTexts.size())
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
  HeldWarningTexts.resize(this->WarningDepth);
}

std::vector<std::string> MessageCapture::HeldWarnings() const
{
  return std::vector<std::string>(
    HeldWarningTexts.begin() + static_cast<std::ptrdiff_t>(this->WarningDepth), HeldWarningTexts.end());
}

void PrintWarning(const std::string& message)
{
  std::cerr << "surfacelod: warning: " << message << std::endl;
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
  return ".off .ply .stl .obj .vtp .vtk .pvtp";
}

std::string WritableExtensions()
{
  return ReadableExtensions();
}

vtkSmartPointer<vtkPolyData> ReadMesh(const std::string& path)
{
  const std::string ext = Extension(path);
  CheckReadableFile(path, ext);
  const FileCheck check = CheckFileBytes(path, ext);
  if (!check.Problem.empty())
  {
    throw CliError(ExitData, path + ": " + check.Problem);
  }
  VTKReadResult read = ReadWithVTK(path, ext);
  if (!read.Problem.empty())
  {
    throw CliError(ExitData, read.Problem);
  }
  const std::string problem = ValidateSurface(read.Mesh);
  if (!problem.empty())
  {
    throw CliError(ExitData, path + ": " + problem);
  }
  if (!check.Warning.empty())
  {
    read.Warnings.push_back(path + ": " + check.Warning);
  }
  for (const std::string& warning : read.Warnings)
  {
    PrintWarning(warning);
  }
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->ShallowCopy(read.Mesh);
  return result;
}

std::string SurfaceProblem(vtkPolyData* mesh)
{
  return ValidateSurface(mesh);
}

void CheckWritablePath(const std::string& path)
{
  const std::string ext = Extension(path);
  if (std::find(KnownExtensions().begin(), KnownExtensions().end(), ext) == KnownExtensions().end())
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

namespace
{
// Whether a file of type `ext` keeps the array: PLY every numeric array (points and cells); OFF the
// point normals, colours and texture coordinates and the cell colours; OBJ the point normals,
// texture coordinates and colours; STL nothing. (Change this with the writers: TestMeshIO reads
// every format back.)
bool FormatKeepsArray(const std::string& ext, vtkDataSetAttributes* data, int index, bool pointData)
{
  vtkAbstractArray* array = data->GetAbstractArray(index);
  if (ext == ".ply")
  {
    return vtkPLYMeshWriter::CanWriteArray(array);
  }
  const bool normals = array == slod::FileNormals(data);
  const bool tcoords = array == slod::FileTextureCoordinates(data);
  const bool colors = array == slod::FileColors(data);
  if (!array)
  {
    return false;
  }
  if (!pointData)
  {
    return ext == ".off" && colors;
  }
  return ext == ".off" || ext == ".obj" ? normals || tcoords || colors : false;
}

// "'Name'" or, for an unnamed array, its role ("unnamed normals").
std::string ArrayLabel(vtkDataSetAttributes* data, int index)
{
  const char* name = data->GetArrayName(index);
  const int role = data->IsArrayAnAttribute(index);
  if (name)
  {
    return "'" + std::string(name) + "'";
  }
  return role >= 0 ? "unnamed " + std::string(vtkDataSetAttributes::GetAttributeTypeAsString(role)) : "unnamed";
}

// The arrays of `data` a file of type `ext` does not keep, as labels.
std::vector<std::string> DroppedArrays(vtkDataSetAttributes* data, const std::string& ext, bool pointData)
{
  std::vector<std::string> dropped;
  for (int a = 0; a < data->GetNumberOfArrays(); ++a)
  {
    if (!FormatKeepsArray(ext, data, a, pointData))
    {
      dropped.push_back(ArrayLabel(data, a));
    }
  }
  return dropped;
}

std::string JoinLabels(const std::vector<std::string>& labels)
{
  std::string joined;
  for (const std::string& label : labels)
  {
    joined += (joined.empty() ? "" : ", ") + label;
  }
  return joined;
}
} // namespace

void WarnAboutDroppedArrays(vtkPolyData* mesh, const std::string& path)
{
  const std::string ext = Extension(path);
  if (ext == ".vtp" || ext == ".vtk" || ext == ".pvtp")
  {
    return; // all keep every array
  }
  const std::vector<std::string> points = DroppedArrays(mesh->GetPointData(), ext, true);
  const std::vector<std::string> cells = DroppedArrays(mesh->GetCellData(), ext, false);
  if (points.empty() && cells.empty())
  {
    return;
  }
  std::string message = path + ": a " + ext.substr(1) + " file does not keep";
  if (!points.empty())
  {
    message += " the point array(s) " + JoinLabels(points);
  }
  if (!cells.empty())
  {
    message += std::string(points.empty() ? "" : " nor") + " the cell array(s) " + JoinLabels(cells);
  }
  PrintWarning(message + " (.vtp and .vtk keep them).");
}

void WriteMesh(vtkPolyData* mesh, const std::string& path)
{
  const std::string ext = Extension(path);
  CheckWritablePath(path);
  MessageCapture capture;
  std::string problem;
  if (ext == ".pvtp")
  {
    problem = WritePartitioned(mesh, path, nullptr); // one piece
  }
  else if (ext != ".vtp" && ext != ".vtk")
  {
    problem = WriteFileWithVTK(mesh, path, ext);
  }
  else
  {
    // VTK's XML and legacy writers do not check their writes (a full disk went unnoticed): the file
    // is made in memory and written here, every step checked.
    std::string bytes;
    problem = SerializeWithVTK(mesh, ext, bytes);
    if (problem.empty())
    {
      problem = slod::WriteWholeFile(path, bytes);
    }
  }
  if (!problem.empty())
  {
    throw CliError(ExitData, path + ": cannot write: " + problem);
  }
  WarnAboutDroppedArrays(mesh, path);
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
