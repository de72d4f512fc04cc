// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target: mesh files from bytes through exactly what `surfacelod` does with a file
// (slodcli::ReadMesh: byte checks, VTK reader, validation), then the shared input preparation
// (slod::PrepareTriangleMesh); and arbitrary vtkPolyData straight into the preparation.
//
// The first byte picks the path: 0-3 a file (.off .ply .stl .obj) made of the remaining bytes,
// 4 a vtkPolyData decoded from them. A crash, a sanitizer report, a timeout, an allocation over
// libFuzzer's limit, or a prepared mesh that breaks its contract (index outside the points,
// non-finite coordinate) is a finding.
#include "FuzzMeshInput.h"

#include "CliSupport.h"
#include "MeshIO.h"
#include "slodInputPreparation.h"

#include "vtkCellArray.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <unistd.h>
#include <vector>

const char* const SurfaceLODFuzzFormats[SurfaceLODFuzzFormatCount] = { ".off", ".ply", ".stl", ".obj" };

namespace
{
[[noreturn]] void Finding(const std::string& what)
{
  std::fprintf(stderr, "surfacelod fuzz finding: %s\n", what.c_str());
  std::abort();
}

// The prepared mesh's contract, relied on by every filter.
void CheckPreparedMesh(vtkPolyData* input)
{
  slod::TriangleMesh mesh;
  std::vector<slod::Index> origin;
  const slod::PreparationReport report = slod::PrepareTriangleMesh(input, slod::PreparationOptions(), mesh, origin);
  if (!report.Valid)
  {
    return; // refused with a reason: a defined outcome
  }
  const size_t vertices = mesh.Points.size() / 3;
  if (origin.size() != vertices || mesh.Triangles.size() % 3 != 0)
  {
    Finding("prepared mesh sizes disagree");
  }
  for (slod::Index v : mesh.Triangles)
  {
    if (static_cast<size_t>(v) >= vertices)
    {
      Finding("prepared triangle refers to vertex " + std::to_string(v) + " of " + std::to_string(vertices));
    }
  }
  for (double x : mesh.Points)
  {
    if (!std::isfinite(x))
    {
      Finding("prepared mesh has a non-finite coordinate");
    }
  }
  for (slod::Index o : origin)
  {
    if (o < 0 || static_cast<vtkIdType>(o) >= input->GetNumberOfPoints())
    {
      Finding("prepared vertex maps to input point " + std::to_string(o));
    }
  }
}

// A private directory for the input files of this process.
const std::string& WorkDirectory()
{
  static const std::string directory = []() {
    const char* tmp = std::getenv("TMPDIR");
    const std::string path =
      std::string(tmp && *tmp ? tmp : "/tmp") + "/surfacelod-fuzz-" + std::to_string(static_cast<long>(getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  return directory;
}

void FuzzFile(const uint8_t* data, size_t size, const char* extension)
{
  const std::string path = WorkDirectory() + "/input" + extension;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  vtkSmartPointer<vtkPolyData> mesh;
  try
  {
    mesh = slodcli::ReadMesh(path);
  }
  catch (const slodcli::CliError& e)
  {
    if (e.Code != slodcli::ExitData || std::string(e.what()).find(path) == std::string::npos)
    {
      Finding(std::string("refusal without the file's name or with the wrong code: ") + e.what());
    }
    return;
  }
  CheckPreparedMesh(slodcli::TriangulatedSurface(mesh));
}

// Bytes as a vtkPolyData: a point count, float coordinates (any bit pattern), then cells as
// (kind, size, ids...) with ids anywhere in [-2, points + 2).
void FuzzPolyData(const uint8_t* data, size_t size)
{
  size_t at = 0;
  auto next = [&]() -> int { return at < size ? data[at++] : -1; };
  const int numberOfPoints = next();
  if (numberOfPoints < 0)
  {
    return;
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  for (int i = 0; i < numberOfPoints && at + 12 <= size; ++i)
  {
    float xyz[3];
    std::memcpy(xyz, data + at, sizeof(xyz));
    at += sizeof(xyz);
    points->InsertNextPoint(xyz[0], xyz[1], xyz[2]);
  }
  vtkNew<vtkCellArray> verts, lines, polys, strips;
  vtkCellArray* kinds[4] = { verts, lines, polys, strips };
  std::vector<vtkIdType> ids;
  for (int kind = next(), count = next(); kind >= 0 && count >= 0; kind = next(), count = next())
  {
    ids.clear();
    for (int k = 0; k < count % 12; ++k)
    {
      const int id = next();
      if (id < 0)
      {
        break;
      }
      ids.push_back(static_cast<vtkIdType>(id) % (points->GetNumberOfPoints() + 4) - 2);
    }
    kinds[kind % 4]->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  vtkNew<vtkPolyData> mesh;
  mesh->SetPoints(points);
  mesh->SetVerts(verts);
  mesh->SetLines(lines);
  mesh->SetPolys(polys);
  mesh->SetStrips(strips);
  CheckPreparedMesh(mesh);
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  static const bool quiet = []() {
    slodcli::InstallMessageHandler();
    std::cerr.rdbuf(nullptr); // the tool's warning lines (sanitizers write to fd 2 directly)
    return true;
  }();
  (void)quiet;
  if (size == 0)
  {
    return 0;
  }
  const unsigned selector = data[0] % (SurfaceLODFuzzFormatCount + 1);
  if (selector < SurfaceLODFuzzFormatCount)
  {
    FuzzFile(data + 1, size - 1, SurfaceLODFuzzFormats[selector]);
  }
  else
  {
    FuzzPolyData(data + 1, size - 1);
  }
  return 0;
}
