// SPDX-License-Identifier: BSD-3-Clause
// The synthetic benchmark surface: closed, manifold, one component, genus 1, deterministic.
#include "TestSupport.h"

#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "vtkSyntheticIsosurfaceSource.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace
{
vtkSmartPointer<vtkPolyData> Generate(int resolution)
{
  vtkNew<vtkSyntheticIsosurfaceSource> source;
  source->SetResolution(resolution);
  source->Update();
  vtkSmartPointer<vtkPolyData> out = source->GetOutput();
  return out;
}
} // namespace

TEST(SyntheticIsosurfaceSource, ClosedManifoldGenusOne)
{
  vtkSmartPointer<vtkPolyData> surface = Generate(112);
  // Documented: about 50,000 triangles at resolution 112 (49,692 measured).
  EXPECT_GE(surface->GetNumberOfPolys(), 45000);
  EXPECT_LE(surface->GetNumberOfPolys(), 55000);
  EXPECT_EQ(surface->GetNumberOfVerts() + surface->GetNumberOfLines() + surface->GetNumberOfStrips(), 0);
  EXPECT_EQ(surface->GetPolys()->IsHomogeneous(), 3);
  EXPECT_EQ(surface->GetPoints()->GetDataType(), VTK_FLOAT);

  // Statistics of the mesh as produced (no preparation that could hide defects).
  slod::TriangleMesh mesh;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    double p[3];
    surface->GetPoint(i, p);
    mesh.Points.insert(mesh.Points.end(), p, p + 3);
  }
  vtkIdType n;
  const vtkIdType* ids;
  for (surface->GetPolys()->InitTraversal(); surface->GetPolys()->GetNextCell(n, ids);)
  {
    ASSERT_EQ(n, 3);
    mesh.Triangles.insert(mesh.Triangles.end(), { slod::Index(ids[0]), slod::Index(ids[1]), slod::Index(ids[2]) });
  }
  const slod::MeshStatistics s = slod::ComputeMeshStatistics(mesh);
  EXPECT_EQ(s.Vertices, surface->GetNumberOfPoints()); // no unused points
  EXPECT_EQ(s.BoundaryEdges, 0);
  EXPECT_EQ(s.NonManifoldEdges, 0);
  EXPECT_EQ(s.NonManifoldVertices, 0);
  EXPECT_EQ(s.Components, 1);
  EXPECT_EQ(s.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(s.DegenerateTriangles, 0);
  EXPECT_EQ(s.EulerCharacteristic, 0);
  EXPECT_EQ(s.Genus, 1);

  // The surface lies inside the documented domain, around the ring of radius 0.6.
  double bounds[6];
  surface->GetBounds(bounds);
  EXPECT_GT(bounds[0], -1.0);
  EXPECT_LT(bounds[1], 1.0);
  EXPECT_GT(bounds[4], -0.5);
  EXPECT_LT(bounds[5], 0.5);
  EXPECT_LT(bounds[0], -0.6);
  EXPECT_GT(bounds[1], 0.6);
}

TEST(SyntheticIsosurfaceSource, NoCoincidentPointsOrDegenerateTriangles)
{
  // Without the snapping of near-contour samples these resolutions give coincident points.
  for (int resolution : { 183, 246 })
  {
    vtkSmartPointer<vtkPolyData> surface = Generate(resolution);
    std::vector<std::array<float, 3>> points(surface->GetNumberOfPoints());
    for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
    {
      double p[3];
      surface->GetPoint(i, p);
      points[i] = { float(p[0]), float(p[1]), float(p[2]) };
    }
    std::sort(points.begin(), points.end());
    EXPECT_EQ(std::adjacent_find(points.begin(), points.end()), points.end())
      << "coincident points at resolution " << resolution;
    // Prepared as the filters prepare their input: nothing merged or removed.
    slod::TriangleMesh mesh;
    std::vector<slod::Index> origin;
    const slod::PreparationReport report = slod::PrepareTriangleMesh(surface, {}, mesh, origin);
    EXPECT_TRUE(report.Warnings().empty()) << "resolution " << resolution << ": " << report.Warnings().front();
    EXPECT_EQ(slod::ComputeMeshStatistics(mesh).Genus, 1);
  }
}

TEST(SyntheticIsosurfaceSource, VerticesLieOnTheDocumentedIsosurface)
{
  vtkSmartPointer<vtkPolyData> surface = Generate(64);
  // Linear interpolation along grid edges: f at a vertex is close to the contour value 0.5.
  double worst = 0.0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    double p[3];
    surface->GetPoint(i, p);
    const double f = vtkSyntheticIsosurfaceSource::EvaluateField(p[0], p[1], p[2]);
    worst = std::max(worst, std::abs(f - vtkSyntheticIsosurfaceSource::GetIsoValue()));
  }
  EXPECT_LT(worst, 0.05);
  // Far from the ring the field is below the contour value (the surface is closed).
  EXPECT_LT(vtkSyntheticIsosurfaceSource::EvaluateField(0, 0, 0), 0.5);
  EXPECT_LT(vtkSyntheticIsosurfaceSource::EvaluateField(1, 0, 0), 0.5);
  EXPECT_GT(vtkSyntheticIsosurfaceSource::EvaluateField(0.6, 0, 0), 0.5);
}

TEST(SyntheticIsosurfaceSource, DeterministicAndScalesWithResolution)
{
  vtkSmartPointer<vtkPolyData> a = Generate(80);
  vtkSmartPointer<vtkPolyData> b = Generate(80);
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  ASSERT_EQ(a->GetNumberOfPolys(), b->GetNumberOfPolys());
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    double p[3], q[3];
    a->GetPoint(i, p);
    b->GetPoint(i, q);
    ASSERT_TRUE(p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) << "point " << i;
  }
  vtkDataArray* ca = a->GetPolys()->GetConnectivityArray();
  vtkDataArray* cb = b->GetPolys()->GetConnectivityArray();
  ASSERT_EQ(ca->GetNumberOfTuples(), cb->GetNumberOfTuples());
  for (vtkIdType i = 0; i < ca->GetNumberOfTuples(); ++i)
  {
    ASSERT_EQ(ca->GetTuple1(i), cb->GetTuple1(i)) << "connectivity " << i;
  }
  // Triangle count grows as resolution^2: doubling the resolution gives about 4x.
  vtkSmartPointer<vtkPolyData> c = Generate(160);
  const double ratio = double(c->GetNumberOfPolys()) / double(a->GetNumberOfPolys());
  EXPECT_GT(ratio, 3.6);
  EXPECT_LT(ratio, 4.4);
}
