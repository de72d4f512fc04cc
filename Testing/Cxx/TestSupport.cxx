// SPDX-License-Identifier: BSD-3-Clause
#include "TestSupport.h"

#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "vtkOFFMeshReader.h"
#include "vtkScanSurfaceSource.h"
#include "vtkSyntheticIsosurfaceSource.h"
#include "vtkSurfaceDeviation.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDoubleArray.h"
#include "vtkFlyingEdges3D.h"
#include "vtkImageData.h"
#include "vtkErrorCode.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkSphereSource.h"
#include "vtkCell.h"
#include "vtkPointData.h"
#include "vtkPolyDataNormals.h"
#include "vtkSMPTools.h"
#include "vtkTexturedSphereSource.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <stdexcept>

namespace slodtest
{
std::string TestMeshPath(const std::string& name)
{
  return std::string(SURFACELOD_MESH_DIR) + "/" + name + ".off";
}

std::string OutputPath(const std::string& fileName)
{
  return std::string(SURFACELOD_TEST_OUTPUT_DIR) + "/" + fileName;
}

std::vector<std::vector<vtkIdType>> CellPointIds(vtkCellArray* cells)
{
  std::vector<std::vector<vtkIdType>> result;
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

vtkSmartPointer<vtkPolyData> LoadTestMesh(const std::string& name)
{
  const std::string path = TestMeshPath(name);
  if (!std::ifstream(path))
  {
    // Missing data is a failure, never a skip.
    throw std::runtime_error("test mesh missing: " + path + " (install libcgal-demo and reconfigure)");
  }
  vtkNew<vtkOFFMeshReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  if (reader->GetErrorCode() != vtkErrorCode::NoError)
  {
    throw std::runtime_error("cannot read test mesh " + path + ": " + reader->GetLastError());
  }
  vtkSmartPointer<vtkPolyData> out = reader->GetOutput();
  return out;
}

slod::TriangleMesh ToTriangleMesh(vtkPolyData* polyData)
{
  slod::TriangleMesh mesh;
  std::vector<slod::Index> origin;
  const slod::PreparationReport report = slod::PrepareTriangleMesh(polyData, {}, mesh, origin);
  if (!report.Valid)
  {
    throw std::runtime_error("invalid test input: " + report.Error);
  }
  return mesh;
}

vtkSmartPointer<vtkPolyData> ToPolyData(const slod::TriangleMesh& mesh)
{
  auto out = vtkSmartPointer<vtkPolyData>::New();
  slod::MeshToPolyData(mesh, out, VTK_DOUBLE);
  return out;
}

slod::TriangleMesh RawTriangleMesh(vtkPolyData* polyData)
{
  slod::TriangleMesh mesh;
  for (vtkIdType i = 0; i < polyData->GetNumberOfPoints(); ++i)
  {
    double p[3];
    polyData->GetPoint(i, p);
    mesh.AddPoint({ p[0], p[1], p[2] });
  }
  vtkIdType n;
  const vtkIdType* ids;
  vtkCellArray* polys = polyData->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
  {
    EXPECT_EQ(n, 3);
    if (n == 3)
    {
      mesh.AddTriangle(slod::Index(ids[0]), slod::Index(ids[1]), slod::Index(ids[2]));
    }
  }
  return mesh;
}

vtkSmartPointer<vtkPolyData> SyntheticIsosurface(int resolution)
{
  vtkNew<vtkSyntheticIsosurfaceSource> source;
  source->SetResolution(resolution);
  source->Update();
  vtkSmartPointer<vtkPolyData> out = source->GetOutput();
  return out;
}

vtkSmartPointer<vtkPolyData> SphereThroughSamples(int samples, double isoValue)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(samples, samples, samples);
  const double origin = -(samples / 2);
  image->SetOrigin(origin, origin, origin);
  vtkNew<vtkDoubleArray> values;
  values->SetNumberOfTuples(vtkIdType(samples) * samples * samples);
  vtkIdType i = 0;
  for (int z = 0; z < samples; ++z)
  {
    for (int y = 0; y < samples; ++y)
    {
      for (int x = 0; x < samples; ++x)
      {
        const double p[3] = { origin + x, origin + y, origin + z };
        values->SetValue(i++, p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      }
    }
  }
  image->GetPointData()->SetScalars(values);
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(image);
  contour->SetValue(0, isoValue);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  vtkSmartPointer<vtkPolyData> out = contour->GetOutput();
  return out;
}

vtkSmartPointer<vtkPolyData> NoisyScanIsosurface(int resolution, unsigned seed)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKindToNoisyIsosurface();
  source->SetResolution(resolution);
  source->SetSeed(seed);
  source->Update();
  vtkSmartPointer<vtkPolyData> out = source->GetOutput();
  return out;
}

slod::TriangleMesh Tetrahedron()
{
  slod::TriangleMesh m;
  m.Points = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  m.Triangles = { 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2 };
  return m;
}

slod::Index MaximumVertexDegree(const slod::MeshTopology& topology)
{
  slod::Index degree = 0;
  for (slod::Index v = 0; v < topology.NumberOfPoints(); ++v)
  {
    degree = std::max(degree, topology.VertexDegree(v));
  }
  return degree;
}

slod::TriangleMesh Torus(int majorSegments, int minorSegments, double majorRadius, double minorRadius)
{
  slod::TriangleMesh m;
  for (int i = 0; i < majorSegments; ++i)
  {
    const double u = 2 * M_PI * i / majorSegments;
    for (int j = 0; j < minorSegments; ++j)
    {
      const double v = 2 * M_PI * j / minorSegments;
      const double r = majorRadius + minorRadius * std::cos(v);
      m.AddPoint({ r * std::cos(u), r * std::sin(u), minorRadius * std::sin(v) });
    }
  }
  auto id = [&](int i, int j) {
    return static_cast<slod::Index>((i % majorSegments) * minorSegments + (j % minorSegments));
  };
  for (int i = 0; i < majorSegments; ++i)
  {
    for (int j = 0; j < minorSegments; ++j)
    {
      m.AddTriangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.AddTriangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return m;
}

slod::TriangleMesh Sphere(int thetaResolution, int phiResolution)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(thetaResolution);
  sphere->SetPhiResolution(phiResolution);
  sphere->Update();
  return ToTriangleMesh(sphere->GetOutput());
}

slod::TriangleMesh Disk(int rings, int segments)
{
  slod::TriangleMesh m;
  m.AddPoint({ 0, 0, 0 });
  for (int r = 1; r <= rings; ++r)
  {
    for (int s = 0; s < segments; ++s)
    {
      const double a = 2 * M_PI * s / segments;
      m.AddPoint({ r * std::cos(a) / rings, r * std::sin(a) / rings, 0 });
    }
  }
  auto id = [&](int r, int s) { return static_cast<slod::Index>(r == 0 ? 0 : 1 + (r - 1) * segments + s % segments); };
  for (int s = 0; s < segments; ++s)
  {
    m.AddTriangle(0, id(1, s), id(1, s + 1));
  }
  for (int r = 1; r < rings; ++r)
  {
    for (int s = 0; s < segments; ++s)
    {
      m.AddTriangle(id(r, s), id(r + 1, s), id(r + 1, s + 1));
      m.AddTriangle(id(r, s), id(r + 1, s + 1), id(r, s + 1));
    }
  }
  return m;
}

slod::TriangleMesh Cone(int segments, double height)
{
  slod::TriangleMesh m;
  const slod::Index apex = m.AddPoint({ 0, 0, height }), centre = m.AddPoint({ 0, 0, 0 });
  for (int s = 0; s < segments; ++s)
  {
    const double a = 2 * M_PI * s / segments;
    m.AddPoint({ std::cos(a), std::sin(a), 0 });
  }
  for (int s = 0; s < segments; ++s)
  {
    const slod::Index r0 = 2 + s, r1 = 2 + (s + 1) % segments;
    m.AddTriangle(apex, r0, r1);
    m.AddTriangle(centre, r1, r0);
  }
  return m;
}

slod::TriangleMesh Grid(int nx, int ny, double z)
{
  slod::TriangleMesh m;
  for (int j = 0; j <= ny; ++j)
  {
    for (int i = 0; i <= nx; ++i)
    {
      m.AddPoint({ double(i) / nx, double(j) / ny, z });
    }
  }
  auto id = [&](int i, int j) { return static_cast<slod::Index>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      m.AddTriangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.AddTriangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return m;
}

slod::TriangleMesh Concatenate(const slod::TriangleMesh& a, const slod::TriangleMesh& b)
{
  slod::TriangleMesh m = a;
  const slod::Index offset = a.NumberOfPoints();
  m.Points.insert(m.Points.end(), b.Points.begin(), b.Points.end());
  for (slod::Index v : b.Triangles)
  {
    m.Triangles.push_back(v + offset);
  }
  return m;
}

slod::TriangleMesh NonManifoldFan(int wings)
{
  slod::TriangleMesh m;
  m.AddPoint({ 0, 0, 0 });
  m.AddPoint({ 0, 0, 1 });
  for (int w = 0; w < wings; ++w)
  {
    const double a = 2 * M_PI * w / wings;
    const slod::Index v = m.AddPoint({ std::cos(a), std::sin(a), 0.5 });
    m.AddTriangle(0, v, 1);
  }
  return m;
}
void ExpectSameTopology(const slod::TriangleMesh& input, const slod::TriangleMesh& output)
{
  const slod::MeshStatistics in = slod::ComputeMeshStatistics(input);
  const slod::MeshStatistics out = slod::ComputeMeshStatistics(output);
  EXPECT_EQ(out.NonManifoldEdges, 0);
  EXPECT_EQ(out.NonManifoldVertices, 0);
  EXPECT_EQ(out.DegenerateTriangles, 0);
  EXPECT_EQ(out.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(out.EulerCharacteristic, in.EulerCharacteristic);
  EXPECT_EQ(out.Genus, in.Genus);
  EXPECT_EQ(out.Components, in.Components);
  EXPECT_EQ(out.BoundaryLoops, in.BoundaryLoops);
}

slod::MeshStatistics ExpectPreparedInputTopology(vtkPolyData* input, vtkPolyData* output)
{
  slod::TriangleMesh prepared;
  std::vector<slod::Index> vertexToInputPoint;
  const slod::PreparationReport report =
    slod::PrepareTriangleMesh(input, slod::PreparationOptions(), prepared, vertexToInputPoint);
  EXPECT_TRUE(report.Valid) << report.Error;
  const slod::MeshStatistics in = slod::ComputeMeshStatistics(prepared);
  const slod::TriangleMesh simplified = RawTriangleMesh(output);
  const slod::MeshStatistics out = slod::ComputeMeshStatistics(simplified);
  EXPECT_EQ(out.EulerCharacteristic, in.EulerCharacteristic);
  EXPECT_EQ(out.Components, in.Components);
  EXPECT_EQ(out.NonManifoldEdges, in.NonManifoldEdges);
  EXPECT_EQ(out.DegenerateTriangles, 0);
  return in;
}

slod::MeshStatistics SimplifyNoisyScan(vtkPolyDataAlgorithm* filter, int resolution, unsigned seed)
{
  const vtkSmartPointer<vtkPolyData> input = NoisyScanIsosurface(resolution, seed);
  filter->SetInputData(input);
  filter->Update();
  const slod::MeshStatistics in = ExpectPreparedInputTopology(input, filter->GetOutput());
  EXPECT_GT(in.NonManifoldEdges, 0) << "the test surface must have non-manifold edges";
  EXPECT_GT(in.BoundaryLoops, 0) << "the test surface must have a border";
  EXPECT_LT(in.EulerCharacteristic, 2 * in.Components - in.BoundaryLoops) << "the test surface must have handles";
  return in;
}
vtkSmartPointer<vtkPolyData> TexturedSphere(int resolution)
{
  vtkNew<vtkTexturedSphereSource> source;
  source->SetThetaResolution(resolution);
  source->SetPhiResolution(resolution / 2);
  source->Update();
  vtkPolyData* s = source->GetOutput();
  vtkNew<vtkCellArray> kept;
  for (vtkIdType c = 0; c < s->GetNumberOfCells(); ++c)
  {
    vtkCell* cell = s->GetCell(c);
    std::array<double, 3> a, b, d;
    s->GetPoint(cell->GetPointId(0), a.data());
    s->GetPoint(cell->GetPointId(1), b.data());
    s->GetPoint(cell->GetPointId(2), d.data());
    if (a != b && b != d && a != d)
    {
      kept->InsertNextCell(cell->GetPointIds());
    }
  }
  vtkNew<vtkPolyData> mesh;
  mesh->SetPoints(s->GetPoints());
  mesh->SetPolys(kept);
  mesh->GetPointData()->ShallowCopy(s->GetPointData());
  return WithPointNormals(mesh);
}

vtkSmartPointer<vtkPolyData> WithPointNormals(vtkPolyData* mesh)
{
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(mesh);
  normals->SplittingOff();
  normals->ComputeCellNormalsOff();
  normals->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(normals->GetOutput());
  return out;
}

std::pair<double, double> RelativeDeviation(vtkPolyData* reference, vtkPolyData* compared, vtkIdType samples)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(reference);
  deviation->SetComparedData(compared);
  deviation->SetNumberOfSamples(samples);
  deviation->Update();
  return { deviation->GetHausdorffRelative(), deviation->GetMeanRelative() };
}

namespace
{
// Distinct threads that run the items of one parallel loop (each item waits a little, so that
// every thread of the pool gets some).
size_t ThreadsOfOneLoop()
{
  std::mutex mutex;
  std::set<std::thread::id> threads;
  vtkSMPTools::For(0, 64, 1, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
    {
      {
        std::lock_guard<std::mutex> lock(mutex);
        threads.insert(std::this_thread::get_id());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  return threads.size();
}
} // namespace

void ForOneTwoAndEightThreads(const std::function<void(int)>& run)
{
  const std::string backend = vtkSMPTools::GetBackend();
  const int threads = vtkSMPTools::GetEstimatedNumberOfThreads();
  ASSERT_TRUE(vtkSMPTools::SetBackend("STDThread"));
  for (int n : { 1, 2, 8 })
  {
    vtkSMPTools::Initialize(n);
    const size_t used = ThreadsOfOneLoop();
    EXPECT_TRUE(n == 1 ? used == 1 : used >= 2) << n << " threads asked, " << used << " ran a loop";
    run(n);
  }
  vtkSMPTools::SetBackend(backend.c_str());
  vtkSMPTools::Initialize(threads);
}

} // namespace slodtest
