// SPDX-License-Identifier: BSD-3-Clause
// Every attribute kind written and read back by each file format: PLY (ASCII and both binary byte
// orders: every point and cell array, double coordinates exact), OFF (normals, colours, texture
// coordinates: STCNOFF; face colours), OBJ (normals, texture coordinates, vertex colours; positions
// split at attribute seams),
// VTP (everything, roles included), and through the tool's ReadMesh / WriteMesh.
#include "TestSupport.h"

#include "CliSupport.h"
#include "MeshIO.h"

#include "vtkOBJMeshReader.h"
#include "vtkOBJMeshWriter.h"
#include "vtkOFFMeshReader.h"
#include "vtkOFFMeshWriter.h"
#include "vtkPLYMeshReader.h"
#include "vtkPLYMeshWriter.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkShortArray.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

namespace
{
std::vector<std::vector<vtkIdType>> Faces(vtkCellArray* cells)
{
  return slodtest::CellPointIds(cells);
}

template <typename Array>
vtkSmartPointer<Array> NewArray(const char* name, int components, vtkIdType tuples)
{
  auto array = vtkSmartPointer<Array>::New();
  if (name)
  {
    array->SetName(name);
  }
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  return array;
}

// A 5 x 4 grid of double points at values no decimal holds exactly, triangles and one quad, with
// an unnamed array first (PLY names it "array0"), normals, texture coordinates, RGB colours,
// arrays of several types and components, and cell arrays: region ids, vtkIdType ids, an unnamed
// double array.
vtkSmartPointer<vtkPolyData> MeshWithEveryAttribute()
{
  const int nx = 5, ny = 4;
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      points->InsertNextPoint(i / 3.0 + 1e-13 * j, j / 7.0, std::sin(i * 0.7 + j) / 11.0);
    }
  }
  mesh->SetPoints(points);
  vtkNew<vtkCellArray> polys;
  for (int j = 0; j + 1 < ny; ++j)
  {
    for (int i = 0; i + 1 < nx; ++i)
    {
      const vtkIdType a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
      if (i == 0 && j == 0)
      {
        const vtkIdType quad[4] = { a, b, d, c };
        polys->InsertNextCell(4, quad);
        continue;
      }
      const vtkIdType first[3] = { a, b, d }, second[3] = { a, d, c };
      polys->InsertNextCell(3, first);
      polys->InsertNextCell(3, second);
    }
  }
  mesh->SetPolys(polys);
  const vtkIdType n = mesh->GetNumberOfPoints(), cells = mesh->GetNumberOfCells();
  auto unnamed = NewArray<vtkFloatArray>(nullptr, 1, n);
  auto normals = NewArray<vtkFloatArray>("Normals", 3, n);
  auto uv = NewArray<vtkFloatArray>("UV", 2, n);
  auto rgb = NewArray<vtkUnsignedCharArray>("RGB", 3, n);
  auto velocity = NewArray<vtkDoubleArray>("Flow velocity", 3, n);
  auto label = NewArray<vtkShortArray>("Label", 1, n);
  for (vtkIdType p = 0; p < n; ++p)
  {
    const double* x = points->GetPoint(p);
    const double length = std::sqrt(1 + x[0] * x[0] + x[1] * x[1]);
    unnamed->SetValue(p, static_cast<float>(p) / 3.0f);
    normals->SetTuple3(p, -x[0] / length, -x[1] / length, 1 / length);
    uv->SetTuple2(p, x[0] / 1.3, x[1] * 1.7);
    rgb->SetTuple3(p, (p * 37) % 256, (p * 91) % 256, 255 - p);
    velocity->SetTuple3(p, x[0] / 9.0, -x[1], 1e-300 * p);
    label->SetValue(p, static_cast<short>(p * 1000 - 9000));
  }
  mesh->GetPointData()->AddArray(unnamed);
  mesh->GetPointData()->SetNormals(normals);
  mesh->GetPointData()->SetTCoords(uv);
  mesh->GetPointData()->SetScalars(rgb);
  mesh->GetPointData()->AddArray(velocity);
  mesh->GetPointData()->AddArray(label);
  auto region = NewArray<vtkIntArray>("RegionId", 1, cells);
  auto ids = NewArray<vtkIdTypeArray>("CellIds", 1, cells);
  auto area = NewArray<vtkDoubleArray>(nullptr, 1, cells);
  for (vtkIdType c = 0; c < cells; ++c)
  {
    region->SetValue(c, static_cast<int>(c % 3) - 1);
    ids->SetValue(c, c * 100003);
    area->SetValue(c, 1.0 / (c + 3));
  }
  mesh->GetCellData()->AddArray(region);
  mesh->GetCellData()->AddArray(ids);
  mesh->GetCellData()->AddArray(area);
  return mesh;
}

// Same tuples, each value equal in the written array's precision (float arrays compared as floats).
void ExpectSameValues(vtkDataArray* written, vtkDataArray* read, const std::string& what)
{
  ASSERT_NE(read, nullptr) << what << " not read back";
  ASSERT_EQ(read->GetNumberOfTuples(), written->GetNumberOfTuples()) << what;
  ASSERT_EQ(read->GetNumberOfComponents(), written->GetNumberOfComponents()) << what;
  const bool single = written->GetDataType() == VTK_FLOAT;
  for (vtkIdType t = 0; t < written->GetNumberOfTuples(); ++t)
  {
    for (int c = 0; c < written->GetNumberOfComponents(); ++c)
    {
      const double a = written->GetComponent(t, c), b = read->GetComponent(t, c);
      if (single)
      {
        ASSERT_EQ(static_cast<float>(a), static_cast<float>(b)) << what << " tuple " << t << " component " << c;
      }
      else
      {
        ASSERT_EQ(a, b) << what << " tuple " << t << " component " << c;
      }
    }
  }
}

void ExpectSameGeometry(vtkPolyData* written, vtkPolyData* read)
{
  ExpectSameValues(written->GetPoints()->GetData(), read->GetPoints()->GetData(), "points");
  EXPECT_EQ(Faces(read->GetPolys()), Faces(written->GetPolys()));
}

// The point normals, texture coordinates and colours, by role.
void ExpectSameRoles(vtkPolyData* written, vtkPolyData* read, bool colors)
{
  ExpectSameValues(written->GetPointData()->GetNormals(), read->GetPointData()->GetNormals(), "normals");
  ExpectSameValues(written->GetPointData()->GetTCoords(), read->GetPointData()->GetTCoords(), "tcoords");
  if (colors)
  {
    ExpectSameValues(written->GetPointData()->GetScalars(), read->GetPointData()->GetScalars(), "colours");
    EXPECT_EQ(read->GetPointData()->GetScalars()->GetDataType(), VTK_UNSIGNED_CHAR);
  }
}

template <typename Reader>
vtkSmartPointer<vtkPolyData> ReadWith(const std::string& path)
{
  vtkNew<Reader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetErrorCode(), vtkErrorCode::NoError) << reader->GetLastError();
  vtkSmartPointer<vtkPolyData> out = reader->GetOutput();
  return out;
}

std::string FirstLine(const std::string& path)
{
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

std::string WriteText(const std::string& name, const std::string& text)
{
  const std::string path = slodtest::OutputPath(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}
} // namespace

TEST(AttributeRoundTrip, PlyKeepsEveryPointAndCellArrayInEveryEncoding)
{
  const vtkSmartPointer<vtkPolyData> mesh = MeshWithEveryAttribute();
  struct Encoding
  {
    const char* Name;
    int FileType;
    bool BigEndian;
  };
  for (const Encoding& encoding : { Encoding{ "ascii", VTK_ASCII, false }, Encoding{ "little", VTK_BINARY, false },
         Encoding{ "big", VTK_BINARY, true } })
  {
    SCOPED_TRACE(encoding.Name);
    const std::string path = slodtest::OutputPath(std::string("every_attribute_") + encoding.Name + ".ply");
    vtkNew<vtkPLYMeshWriter> writer;
    writer->SetFileName(path.c_str());
    writer->SetFileType(encoding.FileType);
    writer->SetBigEndian(encoding.BigEndian);
    writer->SetInputData(mesh);
    ASSERT_EQ(writer->Write(), 1);
    ASSERT_EQ(writer->GetErrorCode(), vtkErrorCode::NoError) << writer->GetLastError();
    const vtkSmartPointer<vtkPolyData> back = ReadWith<vtkPLYMeshReader>(path);
    EXPECT_EQ(back->GetPoints()->GetDataType(), VTK_DOUBLE);
    ExpectSameGeometry(mesh, back);
    ExpectSameRoles(mesh, back, true);
    vtkPointData* pd = back->GetPointData();
    ExpectSameValues(mesh->GetPointData()->GetArray(0), pd->GetArray("array0"), "unnamed point array");
    ExpectSameValues(mesh->GetPointData()->GetArray("Flow velocity"), pd->GetArray("Flow_velocity"), "velocity");
    ExpectSameValues(mesh->GetPointData()->GetArray("Label"), pd->GetArray("Label"), "label");
    ASSERT_NE(pd->GetArray("Label"), nullptr);
    EXPECT_EQ(pd->GetArray("Label")->GetDataType(), VTK_SHORT);
    vtkCellData* cd = back->GetCellData();
    ExpectSameValues(mesh->GetCellData()->GetArray("RegionId"), cd->GetArray("RegionId"), "region ids");
    ASSERT_NE(cd->GetArray("RegionId"), nullptr);
    EXPECT_EQ(cd->GetArray("RegionId")->GetDataType(), VTK_INT);
    ExpectSameValues(mesh->GetCellData()->GetArray("CellIds"), cd->GetArray("CellIds"), "cell ids (as int)");
    ExpectSameValues(mesh->GetCellData()->GetArray(2), cd->GetArray("array2"), "unnamed cell array");
  }
}

TEST(AttributeRoundTrip, PlyFloatPointsStayFloat)
{
  const vtkSmartPointer<vtkPolyData> mesh = MeshWithEveryAttribute();
  auto floatMesh = vtkSmartPointer<vtkPolyData>::New();
  floatMesh->ShallowCopy(mesh);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    points->InsertNextPoint(mesh->GetPoint(p));
  }
  floatMesh->SetPoints(points);
  const std::string path = slodtest::OutputPath("float_points.ply");
  vtkNew<vtkPLYMeshWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(floatMesh);
  ASSERT_EQ(writer->Write(), 1);
  const vtkSmartPointer<vtkPolyData> back = ReadWith<vtkPLYMeshReader>(path);
  EXPECT_EQ(back->GetPoints()->GetDataType(), VTK_FLOAT);
  ExpectSameGeometry(floatMesh, back);
}

TEST(AttributeRoundTrip, OffKeepsNormalsColoursAndTextureCoordinates)
{
  const vtkSmartPointer<vtkPolyData> mesh = MeshWithEveryAttribute();
  const std::string path = slodtest::OutputPath("every_attribute.off");
  vtkNew<vtkOFFMeshWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(mesh);
  ASSERT_EQ(writer->Write(), 1);
  EXPECT_EQ(FirstLine(path), "STCNOFF");
  const vtkSmartPointer<vtkPolyData> back = ReadWith<vtkOFFMeshReader>(path);
  ExpectSameGeometry(mesh, back);
  ExpectSameRoles(mesh, back, true);

  // RGBA, and colours of only 0 and 1 (written as fractions so that they do not read as floats 0-1).
  auto dark = vtkSmartPointer<vtkPolyData>::New();
  dark->ShallowCopy(mesh);
  auto rgba = NewArray<vtkUnsignedCharArray>("RGBA", 4, mesh->GetNumberOfPoints());
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    rgba->SetTuple4(p, p % 2, (p / 2) % 2, 1, 0);
  }
  vtkNew<vtkPointData> onlyColors;
  onlyColors->SetScalars(rgba);
  dark->GetPointData()->ShallowCopy(onlyColors);
  writer->SetInputData(dark);
  ASSERT_EQ(writer->Write(), 1);
  EXPECT_EQ(FirstLine(path), "COFF");
  const vtkSmartPointer<vtkPolyData> darkBack = ReadWith<vtkOFFMeshReader>(path);
  ExpectSameValues(rgba, darkBack->GetPointData()->GetScalars(), "RGBA of 0 and 1");
}

TEST(AttributeRoundTrip, ObjKeepsNormalsTextureCoordinatesAndColoursWithTheSamePoints)
{
  const vtkSmartPointer<vtkPolyData> mesh = MeshWithEveryAttribute();
  const std::string path = slodtest::OutputPath("every_attribute.obj");
  vtkNew<vtkOBJMeshWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(mesh);
  ASSERT_EQ(writer->Write(), 1);
  const vtkSmartPointer<vtkPolyData> back = ReadWith<vtkOBJMeshReader>(path);
  ASSERT_EQ(back->GetNumberOfPoints(), mesh->GetNumberOfPoints()) << "no point split without a seam";
  ExpectSameGeometry(mesh, back);
  ExpectSameRoles(mesh, back, true);
}

// Face colours after the indices (r g b [a]) become cell colours in vtkPolyData's cell order
// (vertices, then lines, then polygons), and are written back after each face's indices.
TEST(AttributeRoundTrip, OffKeepsFaceColoursInCellOrder)
{
  const std::string path = WriteText("face_colours.off",
    "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
    "3 0 1 2 255 0 0\n2 0 3 0 255 0\n3 1 3 2 0 0 255\n1 3 9 9 9\n");
  const vtkSmartPointer<vtkPolyData> read = ReadWith<vtkOFFMeshReader>(path);
  vtkDataArray* colours = read->GetCellData()->GetScalars();
  ASSERT_NE(colours, nullptr);
  ASSERT_EQ(colours->GetNumberOfTuples(), 4);
  const double expected[4][3] = { { 9, 9, 9 }, { 0, 255, 0 }, { 255, 0, 0 }, { 0, 0, 255 } }; // vert, line, polys
  for (vtkIdType c = 0; c < 4; ++c)
  {
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_EQ(colours->GetComponent(c, k), expected[c][k]) << "cell " << c;
    }
  }

  // Written back: a surface's faces with their colours, float 0-1 colours as integers 0-255.
  const vtkSmartPointer<vtkPolyData> mesh = MeshWithEveryAttribute();
  auto faceRgb = NewArray<vtkUnsignedCharArray>("FaceRGB", 3, mesh->GetNumberOfCells());
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    faceRgb->SetTuple3(c, (c * 53) % 256, 255 - c, (c * 7) % 256);
  }
  mesh->GetCellData()->SetScalars(faceRgb);
  const std::string out = slodtest::OutputPath("face_colours_back.off");
  vtkNew<vtkOFFMeshWriter> writer;
  writer->SetFileName(out.c_str());
  writer->SetInputData(mesh);
  ASSERT_EQ(writer->Write(), 1);
  const vtkSmartPointer<vtkPolyData> back = ReadWith<vtkOFFMeshReader>(out);
  ExpectSameGeometry(mesh, back);
  ExpectSameValues(faceRgb, back->GetCellData()->GetScalars(), "face colours");
}

// OBJ vertex colours ("v x y z r g b", 0-1) are read only when every vertex has the same number
// of them: otherwise the reader says they were not read.
TEST(AttributeRoundTrip, ObjVertexColoursReadOnlyWhenComplete)
{
  const vtkSmartPointer<vtkPolyData> full =
    ReadWith<vtkOBJMeshReader>(WriteText("rgb.obj", "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 0.5\nf 1 2 3\n"));
  vtkDataArray* colours = full->GetPointData()->GetScalars();
  ASSERT_NE(colours, nullptr);
  EXPECT_EQ(colours->GetNumberOfComponents(), 3);
  EXPECT_EQ(colours->GetComponent(0, 0), 255);
  EXPECT_EQ(colours->GetComponent(1, 1), 255);
  EXPECT_EQ(colours->GetComponent(2, 2), 128);

  vtkNew<vtkOBJMeshReader> reader;
  reader->SetFileName(WriteText("rgb_partial.obj", "v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 0 0 1\nf 1 2 3\n").c_str());
  vtkNew<slodtest::MessageCounter> messages;
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetPointData()->GetScalars(), nullptr);
  ASSERT_EQ(messages->Warnings.size(), 1u);
  EXPECT_NE(messages->Warnings[0].find("vertex colours"), std::string::npos) << messages->Warnings[0];
}

// OBJ numbers positions, texture coordinates and normals separately: a position used with two
// texture coordinates (a UV seam) becomes two points, each with its own; nothing is averaged away.
TEST(AttributeRoundTrip, ObjPositionsAreSplitWhereTheirAttributesDiffer)
{
  const std::string path = WriteText("seam.obj",
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
    "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvt 0.5 0.5\n"
    "vn 0 0 1\n"
    "f 1/1/1 2/2/1 3/3/1\n"
    "f -3/5/1 -1/4/1 -2/-3/1\n"); // position 2 with texture 5: a seam; negative indices count back
  const vtkSmartPointer<vtkPolyData> mesh = ReadWith<vtkOBJMeshReader>(path);
  ASSERT_EQ(mesh->GetNumberOfPoints(), 5) << "4 positions + 1 split at the seam";
  EXPECT_EQ(Faces(mesh->GetPolys()), std::vector<std::vector<vtkIdType>>({ { 0, 1, 2 }, { 4, 3, 2 } }));
  vtkDataArray* tcoords = mesh->GetPointData()->GetTCoords();
  ASSERT_NE(tcoords, nullptr);
  EXPECT_EQ(tcoords->GetComponent(1, 0), 1.0);
  EXPECT_EQ(tcoords->GetComponent(4, 0), 0.5);
  double p[3];
  mesh->GetPoint(4, p);
  EXPECT_EQ(p[0], 1.0);
  EXPECT_EQ(p[1], 0.0);
  ASSERT_NE(mesh->GetPointData()->GetNormals(), nullptr);
  EXPECT_EQ(mesh->GetPointData()->GetNormals()->GetComponent(4, 2), 1.0);
}

TEST(AttributeRoundTrip, ObjIndicesOutOfRangeAreRefusedNamingTheLine)
{
  for (const char* face : { "f 1/1 2/2 3/5\n", "f 1//2 2//1 3//1\n", "f 1 2 0\n", "f 1 2\n", "f 1/x 2 3\n", "f -4 2 3\n" })
  {
    const std::string path = WriteText("bad_face.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n") + face);
    vtkNew<vtkOBJMeshReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    EXPECT_EQ(reader->GetErrorCode(), vtkErrorCode::FileFormatError) << face;
    EXPECT_NE(std::string(reader->GetLastError()).find(path + ":6: "), std::string::npos) << reader->GetLastError();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0) << face;
  }
}

// Properties of other types, face properties, lists and elements nobody reads, small faces: read
// as announced with one warning, the face data kept in step with the faces.
TEST(AttributeRoundTrip, PlyOtherPropertiesElementsAndSmallFaces)
{
  const std::string path = WriteText("other_properties.ply",
    "ply\nformat ascii 1.0\ncomment made by the test\n"
    "element vertex 4\nproperty double x\nproperty double y\nproperty double z\nproperty uint id\n"
    "property list uchar float extra\nproperty float s\nproperty float t\n"
    "element face 3\nproperty list uchar int vertex_index\nproperty char material\nproperty ushort w_0\n"
    "property ushort w_1\n"
    "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
    "end_header\n"
    "0 0 0 7 0 0.5 0.5\n1 0 0 8 2 1 2 0 0\n0 1 0 9 1 1 0 1\n0 0 1 4294967295 0 1 1\n"
    "3 0 1 2 -5 1 2\n2 0 3 6 3 4\n3 0 3 1 -7 5 6\n"
    "0 1\n");
  vtkNew<vtkPLYMeshReader> reader;
  vtkNew<slodtest::MessageCounter> messages;
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->SetFileName(path.c_str());
  reader->Update();
  ASSERT_EQ(reader->GetErrorCode(), vtkErrorCode::NoError) << reader->GetLastError();
  EXPECT_EQ(messages->Warnings.size(), 1u);
  vtkPolyData* mesh = reader->GetOutput();
  EXPECT_EQ(mesh->GetPoints()->GetDataType(), VTK_DOUBLE);
  EXPECT_EQ(Faces(mesh->GetPolys()), std::vector<std::vector<vtkIdType>>({ { 0, 1, 2 }, { 0, 3, 1 } }));
  vtkDataArray* id = mesh->GetPointData()->GetArray("id");
  ASSERT_NE(id, nullptr);
  EXPECT_EQ(id->GetDataType(), VTK_UNSIGNED_INT);
  EXPECT_EQ(id->GetComponent(3, 0), 4294967295.0);
  ASSERT_NE(mesh->GetPointData()->GetTCoords(), nullptr);
  EXPECT_EQ(mesh->GetPointData()->GetTCoords()->GetComponent(3, 0), 1.0);
  vtkDataArray* material = mesh->GetCellData()->GetArray("material");
  vtkDataArray* weights = mesh->GetCellData()->GetArray("w");
  ASSERT_NE(material, nullptr);
  ASSERT_NE(weights, nullptr);
  EXPECT_EQ(material->GetNumberOfTuples(), 2);
  EXPECT_EQ(material->GetComponent(1, 0), -7.0) << "the face of two vertices took its row along";
  EXPECT_EQ(weights->GetNumberOfComponents(), 2);
  EXPECT_EQ(weights->GetComponent(1, 1), 6.0);
}

// What the tool writes for a mesh with every attribute: PLY keeps every array without a warning;
// OFF and OBJ keep the roles they have columns for and name the rest in one warning; VTP keeps
// all, unnamed arrays and roles included.
TEST(AttributeRoundTrip, TheToolKeepsWhatEachFormatCanHold)
{
  const vtkSmartPointer<vtkPolyData> mesh = MeshWithEveryAttribute();
  for (const char* ext : { ".ply", ".off", ".obj", ".vtp" })
  {
    SCOPED_TRACE(ext);
    const std::string path = slodtest::OutputPath(std::string("tool_attributes") + ext);
    testing::internal::CaptureStderr();
    slodcli::WriteMesh(mesh, path);
    const std::string warnings = testing::internal::GetCapturedStderr();
    const vtkSmartPointer<vtkPolyData> back = slodcli::ReadMesh(path);
    ExpectSameGeometry(mesh, back);
    ExpectSameRoles(mesh, back, true);
    const bool keepsAll = std::string(ext) == ".ply" || std::string(ext) == ".vtp";
    EXPECT_EQ(warnings.empty(), keepsAll) << warnings;
    if (!keepsAll)
    {
      EXPECT_NE(warnings.find("'RegionId'"), std::string::npos) << warnings;
      EXPECT_EQ(warnings.find("'UV'"), std::string::npos) << "texture coordinates are kept: " << warnings;
      EXPECT_EQ(warnings.find("'Normals'"), std::string::npos) << "normals are kept: " << warnings;
    }
  }
  const vtkSmartPointer<vtkPolyData> vtp = slodcli::ReadMesh(slodtest::OutputPath("tool_attributes.vtp"));
  ExpectSameValues(mesh->GetPointData()->GetArray(0), vtp->GetPointData()->GetArray(0), "unnamed (vtp)");
  ExpectSameValues(mesh->GetCellData()->GetArray("CellIds"), vtp->GetCellData()->GetArray("CellIds"), "ids (vtp)");
}
