// OFF reading and writing: exact round trips, header variants, colour columns, polygons of any
// size, and clean failures.
#include "TestSupport.h"

#include "vtkOFFMeshReader.h"
#include "vtkOFFMeshWriter.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <fstream>
#include <vector>

namespace
{
using Polygon = std::vector<vtkIdType>;

std::vector<Polygon> Polygons(vtkCellArray* cells)
{
  std::vector<Polygon> result;
  auto it = vtk::TakeSmartPointer(cells->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    result.emplace_back(ids, ids + n);
  }
  return result;
}

std::string WriteText(const std::string& name, const std::string& text)
{
  const std::string path = slodtest::OutputPath(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

vtkSmartPointer<vtkPolyData> Read(const std::string& path, unsigned long* errorCode = nullptr,
  std::string* error = nullptr)
{
  vtkNew<vtkOFFMeshReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  if (errorCode)
  {
    *errorCode = reader->GetErrorCode();
  }
  if (error)
  {
    *error = reader->GetLastError();
  }
  vtkSmartPointer<vtkPolyData> out = reader->GetOutput();
  return out;
}

// Points with awkward values (not exactly representable in decimal) and mixed polygon sizes.
vtkSmartPointer<vtkPolyData> MixedPolygons(int pointType)
{
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataType(pointType);
  const double coordinates[][3] = { { 0.1, 0.2, 0.3 }, { 1.0 / 3.0, -2.0 / 7.0, 1e-9 }, { 12345.678901, 0, -0.0 },
    { 1e20, -1e-20, 3.14159265358979 }, { 2, 2, 2 }, { -1, 0.5, 0.25 }, { 0.7, 0.7, 0.7 } };
  for (const auto& c : coordinates)
  {
    points->InsertNextPoint(c);
  }
  mesh->SetPoints(points);
  vtkNew<vtkCellArray> polys;
  const vtkIdType tri[] = { 0, 1, 2 };
  const vtkIdType quad[] = { 1, 2, 3, 4 };
  const vtkIdType hept[] = { 0, 1, 2, 3, 4, 5, 6 };
  polys->InsertNextCell(3, tri);
  polys->InsertNextCell(4, quad);
  polys->InsertNextCell(7, hept);
  mesh->SetPolys(polys);
  return mesh;
}

void ExpectRoundTrip(int pointType, const std::string& name)
{
  vtkSmartPointer<vtkPolyData> original = MixedPolygons(pointType);
  const std::string path = slodtest::OutputPath(name);
  vtkNew<vtkOFFMeshWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(original);
  ASSERT_EQ(writer->Write(), 1);
  ASSERT_EQ(writer->GetErrorCode(), vtkErrorCode::NoError) << writer->GetLastError();

  unsigned long code = 0;
  vtkSmartPointer<vtkPolyData> back = Read(path, &code);
  ASSERT_EQ(code, vtkErrorCode::NoError);
  ASSERT_EQ(back->GetNumberOfPoints(), original->GetNumberOfPoints());
  for (vtkIdType i = 0; i < original->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    original->GetPoint(i, p);
    back->GetPoint(i, q);
    for (int a = 0; a < 3; ++a)
    {
      // Exact in the stored precision: the shortest decimal that reads back to the same value.
      if (pointType == VTK_FLOAT)
      {
        EXPECT_EQ(static_cast<float>(p[a]), static_cast<float>(q[a])) << "point " << i << " axis " << a;
      }
      else
      {
        EXPECT_EQ(p[a], q[a]) << "point " << i << " axis " << a;
      }
    }
  }
  EXPECT_EQ(Polygons(back->GetPolys()), Polygons(original->GetPolys()));
}
} // namespace

TEST(OFFMeshIO, RoundTripDoublePointsIsExact)
{
  ExpectRoundTrip(VTK_DOUBLE, "roundtrip_double.off");
}

TEST(OFFMeshIO, RoundTripFloatPointsIsExact)
{
  ExpectRoundTrip(VTK_FLOAT, "roundtrip_float.off");
}

TEST(OFFMeshIO, RoundTripRealMesh)
{
  vtkSmartPointer<vtkPolyData> fandisk = slodtest::LoadTestMesh("fandisk");
  const std::string path = slodtest::OutputPath("fandisk_roundtrip.off");
  vtkNew<vtkOFFMeshWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(fandisk);
  ASSERT_EQ(writer->Write(), 1);
  vtkSmartPointer<vtkPolyData> back = Read(path);
  ASSERT_EQ(back->GetNumberOfPoints(), 6475);
  ASSERT_EQ(back->GetNumberOfPolys(), 12946);
  EXPECT_EQ(Polygons(back->GetPolys()), Polygons(fandisk->GetPolys()));
  for (vtkIdType i = 0; i < back->GetNumberOfPoints(); i += 97)
  {
    double p[3], q[3];
    fandisk->GetPoint(i, p);
    back->GetPoint(i, q);
    EXPECT_EQ(p[0], q[0]);
    EXPECT_EQ(p[1], q[1]);
    EXPECT_EQ(p[2], q[2]);
  }
}

TEST(OFFMeshIO, StripsAreWrittenAsConsistentlyOrientedTriangles)
{
  vtkSmartPointer<vtkPolyData> mesh = MixedPolygons(VTK_DOUBLE);
  mesh->SetPolys(vtkSmartPointer<vtkCellArray>::New());
  vtkNew<vtkCellArray> strips;
  const vtkIdType strip[] = { 0, 1, 2, 3, 4 };
  strips->InsertNextCell(5, strip);
  mesh->SetStrips(strips);
  const std::string path = slodtest::OutputPath("strip.off");
  vtkNew<vtkOFFMeshWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(mesh);
  ASSERT_EQ(writer->Write(), 1);
  vtkSmartPointer<vtkPolyData> back = Read(path);
  // Strip triangles alternate their winding: (0 1 2), (1 3 2) = (2 1 3), (2 3 4).
  const std::vector<Polygon> expected = { { 0, 1, 2 }, { 1, 3, 2 }, { 2, 3, 4 } };
  EXPECT_EQ(Polygons(back->GetPolys()), expected);
}

TEST(OFFMeshIO, CommentsBlankLinesAndCountsOnTheHeaderLine)
{
  const std::string path = WriteText("comments.off",
    "# a comment before the header\n"
    "OFF 4 2 0   # counts on the header line\n"
    "\n"
    "0 0 0 # vertex 0\n"
    "1 0 0\n"
    "   # indented comment\n"
    "0 1 0\n"
    "0 0 1\n"
    "3 0 1 2\n"
    "\n"
    "3 0 1 3 # trailing comment\n");
  unsigned long code = 1;
  vtkSmartPointer<vtkPolyData> mesh = Read(path, &code);
  ASSERT_EQ(code, vtkErrorCode::NoError);
  EXPECT_EQ(mesh->GetNumberOfPoints(), 4);
  const std::vector<Polygon> expected = { { 0, 1, 2 }, { 0, 1, 3 } };
  EXPECT_EQ(Polygons(mesh->GetPolys()), expected);
  double p[3];
  mesh->GetPoint(3, p);
  EXPECT_EQ(p[2], 1.0);
}

TEST(OFFMeshIO, ColourAndNormalColumnsAreIgnored)
{
  // COFF: vertex colours (RGBA); per-face colours; polygons of 3, 4 and 5 vertices.
  const std::string coff = WriteText("colours.coff.off",
    "COFF\n5 3 0\n"
    "0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 10 20 30 255\n0.5 1.5 0 1 1 1 1\n"
    "3 0 1 2 255 0 0\n4 0 1 2 3 0.1 0.2 0.3 1.0\n5 0 1 4 2 3\n");
  unsigned long code = 1;
  vtkSmartPointer<vtkPolyData> mesh = Read(coff, &code);
  ASSERT_EQ(code, vtkErrorCode::NoError);
  ASSERT_EQ(mesh->GetNumberOfPoints(), 5);
  const std::vector<Polygon> expected = { { 0, 1, 2 }, { 0, 1, 2, 3 }, { 0, 1, 4, 2, 3 } };
  EXPECT_EQ(Polygons(mesh->GetPolys()), expected);
  double p[3];
  mesh->GetPoint(4, p);
  EXPECT_EQ(p[0], 0.5);
  EXPECT_EQ(p[1], 1.5);

  // CNOFF: colour and normal columns per vertex.
  const std::string cnoff = WriteText("colours.cnoff.off",
    "CNOFF\n3 1 0\n"
    "0 0 0  0 0 1  1 0 0 1\n"
    "2 0 0  0 0 1  0 1 0 1\n"
    "0 3 0  0 0 1  0 0 1 1\n"
    "3 2 1 0\n");
  mesh = Read(cnoff, &code);
  ASSERT_EQ(code, vtkErrorCode::NoError);
  ASSERT_EQ(mesh->GetNumberOfPoints(), 3);
  mesh->GetPoint(2, p);
  EXPECT_EQ(p[1], 3.0);
  EXPECT_EQ(Polygons(mesh->GetPolys()), std::vector<Polygon>({ { 2, 1, 0 } }));
}

TEST(OFFMeshIO, MalformedFilesFailWithTheFileNameAndAnEmptyOutput)
{
  vtkObject::GlobalWarningDisplayOff(); // the reader's vtkErrorMacro is expected here
  struct Case
  {
    const char* Name;
    const char* Text;
    unsigned long Code;
  };
  const Case cases[] = {
    { "bad_header.off", "OFX\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", vtkErrorCode::UnrecognizedFileTypeError },
    { "truncated.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n", vtkErrorCode::PrematureEndOfFileError },
    { "out_of_range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", vtkErrorCode::FileFormatError },
    { "bad_counts.off", "OFF\nthree 1 0\n", vtkErrorCode::FileFormatError },
    { "bad_vertex.off", "OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", vtkErrorCode::FileFormatError },
    { "short_face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", vtkErrorCode::FileFormatError },
    { "empty.off", "", vtkErrorCode::PrematureEndOfFileError },
  };
  for (const Case& c : cases)
  {
    const std::string path = WriteText(c.Name, c.Text);
    unsigned long code = 0;
    std::string error;
    vtkSmartPointer<vtkPolyData> mesh = Read(path, &code, &error);
    EXPECT_EQ(code, c.Code) << c.Name;
    EXPECT_NE(error.find(path), std::string::npos) << c.Name << ": " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << "one line: " << error;
    EXPECT_EQ(mesh->GetNumberOfPoints(), 0) << c.Name;
    EXPECT_EQ(mesh->GetNumberOfCells(), 0) << c.Name;
  }
  unsigned long code = 0;
  std::string error;
  Read(slodtest::OutputPath("does_not_exist.off"), &code, &error);
  EXPECT_EQ(code, vtkErrorCode::CannotOpenFileError);
  EXPECT_NE(error.find("does_not_exist.off"), std::string::npos);
  vtkObject::GlobalWarningDisplayOn();
}

TEST(OFFMeshIO, WriterReportsAnUnwritablePath)
{
  vtkObject::GlobalWarningDisplayOff();
  vtkNew<vtkOFFMeshWriter> writer;
  const std::string path = slodtest::OutputPath("no_such_directory/out.off");
  writer->SetFileName(path.c_str());
  writer->SetInputData(MixedPolygons(VTK_FLOAT));
  writer->Write();
  EXPECT_EQ(writer->GetErrorCode(), vtkErrorCode::CannotOpenFileError);
  EXPECT_NE(std::string(writer->GetLastError()).find(path), std::string::npos);
  vtkObject::GlobalWarningDisplayOn();
}
