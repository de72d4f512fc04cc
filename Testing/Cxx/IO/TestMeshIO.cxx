// SPDX-License-Identifier: BSD-3-Clause
// OFF reading and writing: exact round trips, header variants, colour columns, polygons of any
// size, and clean failures. The tool's file checks and writers: files VTK's readers crashed on or
// misread are refused with one line naming them, and every writer reports a full disk.
#include "TestSupport.h"

#include "CliSupport.h"
#include "MeshFileChecks.h"
#include "MeshIO.h"

#include "vtkOFFMeshReader.h"
#include "vtkOFFMeshWriter.h"
#include "vtkQuadricTriangleCollapse.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkFloatArray.h"
#include "vtkIdFilter.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPointData.h"
#include "vtkPolyDataNormals.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <vector>

namespace
{
using Polygon = std::vector<vtkIdType>;

std::vector<Polygon> Polygons(vtkCellArray* cells)
{
  return slodtest::CellPointIds(cells);
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

TEST(OFFMeshIO, ColourAndNormalColumnsAreRead)
{
  // COFF: vertex colours (RGBA, integers 0-255); per-face colours (ignored); polygons of 3, 4 and 5 vertices.
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
  vtkDataArray* colors = mesh->GetPointData()->GetScalars();
  ASSERT_NE(colors, nullptr);
  ASSERT_EQ(colors->GetDataType(), VTK_UNSIGNED_CHAR);
  ASSERT_EQ(colors->GetNumberOfComponents(), 4);
  EXPECT_EQ(colors->GetTuple4(3)[1], 20.0);
  EXPECT_EQ(colors->GetTuple4(4)[0], 1.0); // integers 0-255: the file has values above 1

  // CNOFF: normal and colour columns per vertex (floats 0-1: no value above 1).
  const std::string cnoff = WriteText("colours.cnoff.off",
    "CNOFF\n3 1 0\n"
    "0 0 0  0 0 1  1 0 0 1\n"
    "2 0 0  0 0.6 0.8  0 1 0 1\n"
    "0 3 0  0 0 1  0 0 0.5 1\n"
    "3 2 1 0\n");
  mesh = Read(cnoff, &code);
  ASSERT_EQ(code, vtkErrorCode::NoError);
  ASSERT_EQ(mesh->GetNumberOfPoints(), 3);
  mesh->GetPoint(2, p);
  EXPECT_EQ(p[1], 3.0);
  EXPECT_EQ(Polygons(mesh->GetPolys()), std::vector<Polygon>({ { 2, 1, 0 } }));
  ASSERT_NE(mesh->GetPointData()->GetNormals(), nullptr);
  EXPECT_EQ(mesh->GetPointData()->GetNormals()->GetComponent(1, 2), 0.8);
  ASSERT_NE(mesh->GetPointData()->GetScalars(), nullptr);
  EXPECT_EQ(mesh->GetPointData()->GetScalars()->GetComponent(0, 0), 255.0);
  EXPECT_EQ(mesh->GetPointData()->GetScalars()->GetComponent(2, 2), 128.0); // 0.5 * 255 rounded
}

TEST(OFFMeshIO, InconsistentColourColumnsAreRefused)
{
  vtkObject::GlobalWarningDisplayOff();
  const struct
  {
    const char* Text;
    const char* Problem;
  } cases[] = {
    { "COFF\n3 1 0\n0 0 0 1 2 3\n1 0 0 1 2 3 4\n0 1 0 1 2 3\n3 0 1 2\n", ":4: vertex line has 4 colour values" },
    { "COFF\n3 1 0\n0 0 0 1 2\n1 0 0 1 2 3\n0 1 0 1 2 3\n3 0 1 2\n", ":3: vertex line has 2 colour values" },
    { "COFF\n3 1 0\n0 0 0 10 20 300\n1 0 0 1 2 3\n0 1 0 1 2 3\n3 0 1 2\n", ":3: colour value not an integer" },
    { "COFF\n3 1 0\n0 0 0 0.5 0.5 1.5\n1 0 0 1 2 3\n0 1 0 1 2 3\n3 0 1 2\n", ":3: colour value outside 0-1" },
    { "NOFF\n3 1 0\n0 0 0 0 0 x\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", ":3: malformed vertex line" },
  };
  for (const auto& c : cases)
  {
    unsigned long code = 0;
    std::string error;
    vtkSmartPointer<vtkPolyData> mesh = Read(WriteText("bad_colours.off", c.Text), &code, &error);
    EXPECT_EQ(code, vtkErrorCode::FileFormatError) << c.Text;
    EXPECT_NE(error.find(c.Problem), std::string::npos) << error;
    EXPECT_EQ(mesh->GetNumberOfPoints(), 0);
  }
  vtkObject::GlobalWarningDisplayOn();
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

// --------------------------------------------------------------- unusable files, every reader

namespace
{
// A PLY file in memory: vertices (float x y z) and faces ("list uchar int vertex_indices").
struct PlyFile
{
  std::string Format = "binary_little_endian";
  std::vector<std::array<float, 3>> Vertices = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  std::vector<std::vector<int>> Faces = { { 0, 2, 1 }, { 0, 1, 3 }, { 1, 2, 3 }, { 0, 3, 2 } };
  long long AnnouncedFaces = -1; // -1: the real count

  std::string Bytes() const
  {
    std::ostringstream out;
    out << "ply\nformat " << this->Format << " 1.0\nelement vertex " << this->Vertices.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
        << (this->AnnouncedFaces >= 0 ? this->AnnouncedFaces : static_cast<long long>(this->Faces.size()))
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    const bool ascii = this->Format == "ascii";
    for (const auto& v : this->Vertices)
    {
      if (ascii)
      {
        out << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
      }
      else
      {
        this->Put(out, v.data(), 3);
      }
    }
    for (const auto& face : this->Faces)
    {
      if (ascii)
      {
        out << face.size();
        for (int id : face)
        {
          out << ' ' << id;
        }
        out << '\n';
        continue;
      }
      out.put(static_cast<char>(face.size()));
      this->Put(out, face.data(), face.size());
    }
    return out.str();
  }

private:
  // Values in the byte order the format line announces.
  template <typename T>
  void Put(std::ostream& out, const T* values, size_t count) const
  {
    for (size_t i = 0; i < count; ++i)
    {
      char bytes[sizeof(T)];
      std::memcpy(bytes, &values[i], sizeof(T));
      if (this->Format == "binary_big_endian")
      {
        std::reverse(bytes, bytes + sizeof(T));
      }
      out.write(bytes, sizeof(T));
    }
  }
};

// ReadMesh's verdict: "" when the file reads, else the message (which must name the file).
std::string ReadProblem(const std::string& path)
{
  try
  {
    slodcli::ReadMesh(path);
    return std::string();
  }
  catch (const slodcli::CliError& e)
  {
    EXPECT_EQ(e.Code, slodcli::ExitData) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    return e.what();
  }
}
} // namespace

TEST(OFFMeshIO, CountsTheFileCannotHoldAreRefusedBeforeAllocating)
{
  vtkObject::GlobalWarningDisplayOff();
  for (const char* counts : { "2000000000 1 0", "3 2000000000 0", "9223372036854775807 1 0" })
  {
    const std::string path = WriteText("huge_counts.off",
      std::string("OFF\n") + counts + "\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    unsigned long code = 0;
    std::string error;
    vtkSmartPointer<vtkPolyData> mesh = Read(path, &code, &error);
    EXPECT_EQ(code, vtkErrorCode::PrematureEndOfFileError) << counts;
    EXPECT_NE(error.find("more than the"), std::string::npos) << error;
    EXPECT_EQ(mesh->GetNumberOfPoints(), 0);
  }
  vtkObject::GlobalWarningDisplayOn();
}

TEST(OFFMeshIO, NumbersAreDecimalAndWithinRange)
{
  // A count beyond 64 bits is a malformed count (strtoll made it the largest long long), a
  // hexadecimal coordinate is not an OFF number (strtod read it); a leading '+' is one.
  vtkObject::GlobalWarningDisplayOff();
  const struct
  {
    const char* Text;
    unsigned long Code;
    const char* Problem;
  } cases[] = {
    { "OFF\n99999999999999999999 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", vtkErrorCode::FileFormatError,
      ":2: bad vertex/face counts" },
    { "OFF\n3 1 0\n0 0 0\n0x1p0 0 0\n0 1 0\n3 0 1 2\n", vtkErrorCode::FileFormatError, ":4: malformed vertex line" },
    { "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999999999999\n", vtkErrorCode::FileFormatError,
      ":6: face refers to a vertex that does not exist" },
  };
  for (const auto& c : cases)
  {
    unsigned long code = 0;
    std::string error;
    vtkSmartPointer<vtkPolyData> mesh = Read(WriteText("bad_numbers.off", c.Text), &code, &error);
    EXPECT_EQ(code, c.Code) << c.Text;
    EXPECT_NE(error.find(c.Problem), std::string::npos) << error;
    EXPECT_EQ(mesh->GetNumberOfPoints(), 0);
  }
  vtkObject::GlobalWarningDisplayOn();
  unsigned long code = 0;
  vtkSmartPointer<vtkPolyData> mesh = Read(WriteText("plus_signs.off", "OFF\n+3 1 0\n0 0 0\n+1 0 0\n0 1.5e+0 0\n3 0 1 +2\n"), &code);
  ASSERT_EQ(code, vtkErrorCode::NoError);
  double p[3];
  mesh->GetPoint(1, p);
  EXPECT_EQ(p[0], 1.0);
  mesh->GetPoint(2, p);
  EXPECT_EQ(p[1], 1.5);
  EXPECT_EQ(Polygons(mesh->GetPolys()), std::vector<Polygon>({ { 0, 1, 2 } }));
}

TEST(OFFMeshIO, DataAfterTheAnnouncedFacesIsAWarning)
{
  const std::string path = WriteText("more_faces.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n");
  vtkNew<vtkOFFMeshReader> reader;
  vtkNew<slodtest::MessageCounter> messages;
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetErrorCode(), vtkErrorCode::NoError);
  EXPECT_EQ(messages->Warnings.size(), 1u);
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPolys(), 1); // as the header says
  EXPECT_EQ(ReadProblem(path), std::string()); // and the tool reads it (with the warning)
}

TEST(OFFMeshIO, FacesOfOneOrTwoVerticesAreVertexAndLineCells)
{
  const std::string path = WriteText("small_faces.off", "OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n1 2\n2 1 2\n");
  unsigned long code = 1;
  vtkSmartPointer<vtkPolyData> mesh = Read(path, &code);
  ASSERT_EQ(code, vtkErrorCode::NoError);
  EXPECT_EQ(mesh->GetNumberOfPolys(), 0);
  EXPECT_EQ(Polygons(mesh->GetLines()), std::vector<Polygon>({ { 0, 1 }, { 1, 2 } }));
  EXPECT_EQ(Polygons(mesh->GetVerts()), std::vector<Polygon>({ { 2 } }));
  // No surface: the tool refuses the file.
  EXPECT_NE(ReadProblem(path).find("no surface"), std::string::npos);
}

TEST(PLYMeshIO, SoundPlyFilesReadBack)
{
  for (const char* format : { "ascii", "binary_little_endian", "binary_big_endian" })
  {
    PlyFile ply;
    ply.Format = format;
    const std::string path = WriteText(std::string("tetra_") + format + ".ply", ply.Bytes());
    ASSERT_EQ(ReadProblem(path), "") << format;
    vtkSmartPointer<vtkPolyData> mesh = slodcli::ReadMesh(path);
    EXPECT_EQ(mesh->GetNumberOfPoints(), 4);
    EXPECT_EQ(Polygons(mesh->GetPolys()), std::vector<Polygon>({ { 0, 2, 1 }, { 0, 1, 3 }, { 1, 2, 3 }, { 0, 3, 2 } }));
    // Data after the last element: read as announced, with a warning naming the file.
    const std::string trailing = WriteText(std::string("trailing_") + format + ".ply", ply.Bytes() + "3 0 1 2\n");
    testing::internal::CaptureStderr();
    EXPECT_EQ(ReadProblem(trailing), "") << format;
    const std::string warnings = testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find(trailing + ": not read: data after the elements"), std::string::npos) << warnings;
  }
}

TEST(PLYMeshIO, UnsoundPlyFilesAreRefusedNamingTheProblem)
{
  struct Case
  {
    const char* Name;
    std::function<std::string()> Bytes;
    const char* Problem; // part of the expected message
  };
  auto variant = [](const char* format, const std::function<void(PlyFile&)>& change) {
    return [format, change]() {
      PlyFile ply;
      ply.Format = format;
      change(ply);
      return ply.Bytes();
    };
  };
  auto wrongByteOrder = []() {
    std::string bytes = PlyFile().Bytes();
    bytes.replace(bytes.find("binary_little_endian"), 20, "binary_big_endian");
    return bytes;
  };
  const Case cases[] = {
    { "index_out_of_range.ply", variant("binary_little_endian", [](PlyFile& p) { p.Faces[2][1] = 1000000; }),
      "refers to vertex 1000000" },
    { "negative_index.ply", variant("binary_little_endian", [](PlyFile& p) { p.Faces[0][0] = -3; }),
      "refers to vertex -3" },
    { "index_equal_to_count.ply", variant("binary_big_endian", [](PlyFile& p) { p.Faces[3][2] = 4; }),
      "refers to vertex 4" },
    { "ascii_index_out_of_range.ply", variant("ascii", [](PlyFile& p) { p.Faces[1][0] = 7; }), "refers to vertex 7" },
    { "wrong_byte_order.ply", wrongByteOrder, "refers to vertex" },
    { "count_beyond_file.ply", variant("binary_little_endian", [](PlyFile& p) { p.AnnouncedFaces = 2000000000; }),
      "more than the" },
    { "count_beyond_int.ply", variant("binary_little_endian", [](PlyFile& p) { p.AnnouncedFaces = 5000000000LL; }),
      "more than the" },
    { "truncated.ply", variant("binary_little_endian", [](PlyFile& p) { p.AnnouncedFaces = 5; }), "file ends" },
    { "ascii_truncated.ply", variant("ascii", [](PlyFile& p) { p.AnnouncedFaces = 5; }), "file ends" },
    // An ASCII value outside its type (the cast to a count or index was undefined behaviour).
    { "ascii_uchar_count_300.ply",
      []() {
        return std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n");
      },
      "malformed uchar value '300'" },
    { "ascii_index_1e300.ply",
      []() {
        return std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n3 0 1 1e300\n");
      },
      "malformed int value '1e300'" },
    { "no_end_header.ply", []() { return std::string("ply\nformat ascii 1.0\nelement vertex 1\n"); }, "end_header" },
    { "no_xyz.ply", []() { return std::string("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n"); },
      "x, y, z" },
    { "element_without_properties.ply",
      []() { return std::string("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 99999999\nend_header\n"); },
      "no vertex_indices list" },
    // Found by the fuzzer when VTK's PLY reader read the files: it freed the index list of a face
    // element that has none.
    { "face_without_indices.ply",
      []() {
        std::string bytes = PlyFile().Bytes();
        bytes.replace(bytes.find("vertex_indices"), 14, "vertex_indixes");
        return bytes;
      },
      "no vertex_indices list" },
    { "bad_element_line.ply", []() { return std::string("ply\nformat ascii 1.0\nelement vertex\nend_header\n"); },
      "bad PLY element line" },
  };
  for (const Case& c : cases)
  {
    const std::string problem = ReadProblem(WriteText(c.Name, c.Bytes()));
    EXPECT_NE(problem.find(c.Problem), std::string::npos) << c.Name << ": '" << problem << "'";
  }
}

TEST(MeshFileChecks, StlCountAgainstTheFileSize)
{
  std::string stl(84 + 3 * 50, '\0');
  auto announce = [&](unsigned count) {
    for (int b = 0; b < 4; ++b)
    {
      stl[80 + b] = static_cast<char>((count >> (8 * b)) & 0xff);
    }
  };
  announce(3);
  EXPECT_EQ(slodcli::CheckSTL(stl, true).Problem, "");
  EXPECT_EQ(slodcli::CheckSTL(stl, true).Warning, "");
  announce(4);
  EXPECT_NE(slodcli::CheckSTL(stl, true).Problem.find("truncated"), std::string::npos);
  announce(1);
  EXPECT_EQ(slodcli::CheckSTL(stl, true).Problem, "");
  EXPECT_NE(slodcli::CheckSTL(stl, true).Warning.find("2 more triangles"), std::string::npos);
  // The file check reads the header and the size only: the same verdicts on files.
  EXPECT_NE(slodcli::CheckSTLFile(WriteText("one_of_three.stl", stl)).Warning.find("2 more triangles"), std::string::npos);
  announce(4);
  EXPECT_NE(slodcli::CheckSTLFile(WriteText("four_of_three.stl", stl)).Problem.find("truncated"), std::string::npos);
  EXPECT_NE(slodcli::CheckSTLFile(WriteText("short.stl", stl.substr(0, 60))).Problem.find("too short"), std::string::npos);
  EXPECT_EQ(slodcli::CheckSTL("solid x\nendsolid x\n", false).Problem, "");
  // Found by the fuzzer: a file that starts like an ASCII STL but holds binary bytes is read as
  // binary by VTK, which allocated for the count bytes 80-83 happen to hold (text: ~1e9).
  std::string textThenZeros = "solid x\n facet normal 0 0 -1\n  outer loop\n   vertex 0 0 0\n   vertex 0 1 0\n"
                              "   vertex 1 0 0\n  endloop\n endfacet\n";
  textThenZeros.resize(300, '\0');
  const std::string path = WriteText("text_then_zeros.stl", textThenZeros);
  EXPECT_TRUE(slodcli::IsBinarySTL(path));
  EXPECT_NE(slodcli::CheckSTL(textThenZeros, true).Problem.find("truncated"), std::string::npos);
  EXPECT_NE(ReadProblem(path), "");
  EXPECT_FALSE(slodcli::IsBinarySTL(WriteText("ascii.stl", "solid x\nendsolid x\n")));
}

TEST(OBJMeshIO, CoordinatesMustBeFiniteDecimalNumbers)
{
  const std::string faces = "v 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(ReadProblem(WriteText("good.obj", "# comment\nv 0 0 0\n" + faces)), "");
  EXPECT_EQ(ReadProblem(WriteText("colours.obj", "v 0 0 0 1 0.5 0.25\n" + faces)), ""); // with colours
  for (const char* bad : { "v nan 0 0\n", "v 0 inf 0\n", "v 0 0 1e999\n", "v 0x10 0 0\n", "v 1,5 0 0\n", "v 0 0\n" })
  {
    const std::string path = WriteText("bad_vertex.obj", bad + faces);
    EXPECT_NE(ReadProblem(path).find(path + ":1: vertex does not hold finite numbers"), std::string::npos) << bad;
  }
}

TEST(MeshIO, FilesWithoutAUsableTriangleAreRefused)
{
  // Every triangle collapses once coincident points are merged: nothing to simplify or compare.
  EXPECT_NE(ReadProblem(WriteText("collapsed.off", "OFF\n4 2 0\n0 0 0\n0 0 0\n0 1 0\n0 1 0\n3 0 1 2\n3 2 3 0\n"))
              .find("no usable triangles"),
    std::string::npos);
  // One good triangle among collapsed ones is enough; so is a polygon whose first corners coincide.
  EXPECT_EQ(ReadProblem(WriteText("one_good.off", "OFF\n4 2 0\n0 0 0\n0 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 2 3\n")), "");
  EXPECT_EQ(ReadProblem(WriteText("quad.off", "OFF\n4 1 0\n0 0 0\n0 0 0\n0 1 0\n1 1 0\n4 0 1 2 3\n")), "");
  // Huge but finite coordinates are usable (their sum overflows, each is finite).
  EXPECT_EQ(ReadProblem(WriteText("huge.off", "OFF\n3 1 0\n1e308 1e308 1e308\n-1e308 0 0\n0 1e308 0\n3 0 1 2\n")), "");
}

TEST(MeshIO, EveryWriterReportsAFullDisk)
{
  ASSERT_TRUE(std::filesystem::exists("/dev/full")) << "cannot test writes to a full disk";
  vtkSmartPointer<vtkPolyData> mesh = MixedPolygons(VTK_FLOAT);
  for (const char* ext : { ".off", ".ply", ".stl", ".obj", ".vtp", ".vtk" })
  {
    const std::string path = slodtest::OutputPath(std::string("full") + ext);
    std::error_code ec;
    std::filesystem::remove(path, ec);
    std::filesystem::create_symlink("/dev/full", path);
    try
    {
      slodcli::WriteMesh(mesh, path);
      ADD_FAILURE() << ext << ": a write to a full disk reported success";
    }
    catch (const slodcli::CliError& e)
    {
      EXPECT_EQ(e.Code, slodcli::ExitData);
      EXPECT_NE(std::string(e.what()).find(path + ": cannot write"), std::string::npos) << e.what();
    }
  }
}

TEST(MeshIO, ObjFilesReadBackExactly)
{
  for (int pointType : { VTK_FLOAT, VTK_DOUBLE })
  {
    vtkSmartPointer<vtkPolyData> mesh = MixedPolygons(pointType);
    const std::string path = slodtest::OutputPath("mixed.obj");
    slodcli::WriteMesh(mesh, path);
    vtkSmartPointer<vtkPolyData> back = slodcli::ReadMesh(path);
    ASSERT_EQ(back->GetNumberOfPoints(), mesh->GetNumberOfPoints());
    EXPECT_EQ(Polygons(back->GetPolys()), Polygons(mesh->GetPolys()));
    for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
    {
      double p[3], q[3];
      mesh->GetPoint(i, p);
      back->GetPoint(i, q);
      for (int a = 0; a < 3; ++a)
      {
        // Shortest decimals of the points' precision, read as doubles: exact in that precision.
        if (pointType == VTK_FLOAT)
        {
          EXPECT_EQ(static_cast<float>(p[a]), static_cast<float>(q[a])) << i << " " << a;
        }
        else
        {
          EXPECT_EQ(p[a], q[a]) << i << " " << a;
        }
      }
    }
  }
}

namespace
{
// fandisk simplified by vtkQuadricTriangleCollapse from an input with cell data (vtkIdFilter ids, an
// int region), point normals and texture coordinates: a filter output as the tool writes it.
vtkSmartPointer<vtkPolyData> SimplifiedWithAttributes()
{
  vtkNew<vtkIdFilter> ids;
  ids->SetInputData(slodtest::LoadTestMesh("fandisk"));
  ids->PointIdsOff();
  ids->CellIdsOn();
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputConnection(ids->GetOutputPort());
  normals->SplittingOff();
  normals->ComputeCellNormalsOff();
  normals->Update();
  auto input = vtkSmartPointer<vtkPolyData>::New();
  input->DeepCopy(normals->GetOutput());
  vtkNew<vtkIntArray> region;
  region->SetName("Region");
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetName("UV");
  tcoords->SetNumberOfComponents(2);
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    region->InsertNextValue(static_cast<int>(c % 5));
  }
  for (vtkIdType p = 0; p < input->GetNumberOfPoints(); ++p)
  {
    const double* x = input->GetPoint(p);
    tcoords->InsertNextTuple2(x[0], x[1]);
  }
  input->GetCellData()->AddArray(region);
  input->GetPointData()->SetTCoords(tcoords);
  vtkNew<vtkQuadricTriangleCollapse> simplify;
  simplify->SetInputData(input);
  simplify->SetTargetReduction(0.5);
  simplify->Update();
  auto output = vtkSmartPointer<vtkPolyData>::New();
  output->ShallowCopy(simplify->GetOutput());
  return output;
}

// Whether `back` (a file read back) has `array` of `written`: by its role when it has one the
// reader gives too, else by name.
bool ReadBack(vtkDataSetAttributes* written, int index, vtkDataSetAttributes* back)
{
  const int role = written->IsArrayAnAttribute(index);
  if (role >= 0 && back->GetAttribute(role))
  {
    return true;
  }
  const char* name = written->GetArrayName(index);
  return name && back->GetAbstractArray(name);
}
} // namespace

// Every writer of the tool either keeps a point or cell array (it reads back) or names it in its
// warning; VTP keeps all of them, values and roles included.
TEST(MeshIO, WritersKeepEveryArrayOrSayWhichTheyDrop)
{
  const vtkSmartPointer<vtkPolyData> mesh = SimplifiedWithAttributes();
  ASSERT_NE(mesh->GetCellData()->GetArray("Region"), nullptr) << "premise: the simplifier carries cell data";
  ASSERT_NE(mesh->GetPointData()->GetNormals(), nullptr);
  ASSERT_NE(mesh->GetPointData()->GetTCoords(), nullptr);
  for (const char* ext : { "vtp", "vtk", "ply", "obj", "off", "stl" })
  {
    SCOPED_TRACE(ext);
    const std::string path = slodtest::OutputPath(std::string("attributes.") + ext);
    testing::internal::CaptureStderr();
    slodcli::WriteMesh(mesh, path);
    const std::string warnings = testing::internal::GetCapturedStderr();
    EXPECT_LE(std::count(warnings.begin(), warnings.end(), '\n'), 1) << "one warning at most: " << warnings;
    const vtkSmartPointer<vtkPolyData> back = slodcli::ReadMesh(path);
    for (vtkDataSetAttributes* written : { static_cast<vtkDataSetAttributes*>(mesh->GetPointData()),
           static_cast<vtkDataSetAttributes*>(mesh->GetCellData()) })
    {
      vtkDataSetAttributes* read = written == mesh->GetPointData()
        ? static_cast<vtkDataSetAttributes*>(back->GetPointData())
        : static_cast<vtkDataSetAttributes*>(back->GetCellData());
      for (int a = 0; a < written->GetNumberOfArrays(); ++a)
      {
        const std::string label = "'" + std::string(written->GetArrayName(a)) + "'";
        const bool kept = ReadBack(written, a, read);
        EXPECT_NE(kept, warnings.find(label) != std::string::npos)
          << label << (kept ? " is kept but named as dropped: " : " is dropped silently: ") << warnings;
      }
    }
  }
  const vtkSmartPointer<vtkPolyData> vtp = slodcli::ReadMesh(slodtest::OutputPath("attributes.vtp"));
  vtkDataArray* region = vtp->GetCellData()->GetArray("Region");
  ASSERT_NE(region, nullptr);
  ASSERT_NE(vtp->GetCellData()->GetScalars(), nullptr) << "vtkIdFilter's cell ids lost their role";
  for (vtkIdType c = 0; c < vtp->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(region->GetComponent(c, 0), mesh->GetCellData()->GetArray("Region")->GetComponent(c, 0));
  }
}
