// SPDX-License-Identifier: BSD-3-Clause
// Writes the seed corpus of the mesh input fuzz target into a directory: small sound files of every
// format (written by the project's and VTK's writers, ASCII and binary) and one raw vtkPolyData,
// each prefixed with the fuzz target's selector byte. Generated, never downloaded.
#include "FuzzMeshInput.h"
#include "MeshIO.h"
#include "TestSupport.h"

#include "vtkCellData.h"
#include "vtkFloatArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPLYMeshWriter.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSTLWriter.h"
#include "vtkUnsignedCharArray.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace
{
unsigned SelectorOf(const std::string& extension)
{
  for (unsigned i = 0; i < SurfaceLODFuzzFormatCount; ++i)
  {
    if (extension == SurfaceLODFuzzFormats[i])
    {
      return i;
    }
  }
  return SurfaceLODFuzzFormatCount;
}

void WriteSeed(const std::filesystem::path& directory, const std::string& name, unsigned selector, const std::string& bytes)
{
  std::ofstream out(directory / name, std::ios::binary);
  out.put(static_cast<char>(selector));
  out << bytes;
}

std::string ReadBytes(const std::filesystem::path& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The mesh written by the tool's own writer (OFF, OBJ, binary PLY and STL) plus the ASCII and
// big-endian PLY and the ASCII STL variants, each as a seed.
void WriteFileSeeds(const std::filesystem::path& directory, const std::string& shape, vtkPolyData* mesh)
{
  const std::filesystem::path scratch = directory / "scratch";
  std::filesystem::create_directories(scratch);
  for (unsigned i = 0; i < SurfaceLODFuzzFormatCount; ++i)
  {
    const std::string extension = SurfaceLODFuzzFormats[i];
    const std::filesystem::path file = scratch / (shape + extension);
    slodcli::WriteMesh(mesh, file.string());
    WriteSeed(directory, shape + extension.substr(1), i, ReadBytes(file));
  }
  for (const bool ascii : { true, false })
  {
    const std::filesystem::path file = scratch / (shape + (ascii ? "-ascii.ply" : "-big-endian.ply"));
    vtkNew<vtkPLYMeshWriter> ply;
    ply->SetFileName(file.string().c_str());
    ply->SetFileType(ascii ? VTK_ASCII : VTK_BINARY);
    ply->SetBigEndian(!ascii);
    ply->SetInputData(mesh);
    ply->Write();
    WriteSeed(directory, shape + (ascii ? "-ascii-ply" : "-big-endian-ply"), SelectorOf(".ply"), ReadBytes(file));
  }
  const std::filesystem::path asciiStl = scratch / (shape + "-ascii.stl");
  vtkNew<vtkSTLWriter> stl;
  stl->SetFileTypeToASCII();
  stl->SetFileName(asciiStl.string().c_str());
  stl->SetInputData(mesh);
  stl->Write();
  WriteSeed(directory, shape + "-ascii-stl", SelectorOf(".stl"), ReadBytes(asciiStl));
  std::filesystem::remove_all(scratch);
}

// A tetrahedron with every attribute the readers give a role or keep: normals, texture coordinates,
// RGB colours, a point scalar and a cell region id (the OFF seed becomes STCNOFF, the OBJ seed has
// vt and vn, the PLY seeds have vertex and face properties).
vtkSmartPointer<vtkPolyData> TetrahedronWithAttributes()
{
  vtkSmartPointer<vtkPolyData> mesh = slodtest::ToPolyData(slodtest::Tetrahedron());
  vtkNew<vtkFloatArray> normals, tcoords, temperature;
  vtkNew<vtkUnsignedCharArray> colors;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  tcoords->SetName("TCoords");
  tcoords->SetNumberOfComponents(2);
  colors->SetName("RGB");
  colors->SetNumberOfComponents(3);
  temperature->SetName("Temperature");
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    const double* x = mesh->GetPoint(p);
    normals->InsertNextTuple3(x[0] - 0.25, x[1] - 0.25, x[2] - 0.25);
    tcoords->InsertNextTuple2(x[0], x[1]);
    colors->InsertNextTuple3(60.0 * p, 255 - 60.0 * p, 128);
    temperature->InsertNextValue(static_cast<float>(p) / 3.0f);
  }
  mesh->GetPointData()->SetNormals(normals);
  mesh->GetPointData()->SetTCoords(tcoords);
  mesh->GetPointData()->SetScalars(colors);
  mesh->GetPointData()->AddArray(temperature);
  vtkNew<vtkIntArray> region;
  region->SetName("RegionId");
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    region->InsertNextValue(static_cast<int>(c % 2));
  }
  mesh->GetCellData()->AddArray(region);
  return mesh;
}

// A tetrahedron in the fuzz target's raw vtkPolyData encoding.
std::string RawTetrahedron()
{
  const float corners[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  std::string bytes(1, '\4');
  bytes.append(reinterpret_cast<const char*>(corners), sizeof(corners));
  const unsigned char faces[4][3] = { { 0, 2, 1 }, { 0, 1, 3 }, { 1, 2, 3 }, { 0, 3, 2 } };
  for (const auto& face : faces)
  {
    bytes += '\2'; // polygon
    bytes += '\3';
    // An id byte b stands for b % (points + 4) - 2.
    for (unsigned char v : face)
    {
      bytes += static_cast<char>(v + 2);
    }
  }
  return bytes;
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc != 2)
  {
    std::cerr << "usage: MakeFuzzSeeds DIRECTORY\n";
    return 1;
  }
  const std::filesystem::path directory(argv[1]);
  std::filesystem::create_directories(directory);
  WriteFileSeeds(directory, "tetrahedron", slodtest::ToPolyData(slodtest::Tetrahedron()));
  WriteFileSeeds(directory, "grid", slodtest::ToPolyData(slodtest::Grid(3, 2)));
  WriteFileSeeds(directory, "attributes", TetrahedronWithAttributes());
  WriteSeed(directory, "tetrahedron-raw", SurfaceLODFuzzFormatCount, RawTetrahedron());
  std::cout << "seeds written to " << directory.string() << std::endl;
  return 0;
}
