// SPDX-License-Identifier: BSD-3-Clause
// vtkQuadricTriangleCollapse with PreserveAttributeSeams (issue 13): the texture seam of a textured
// sphere stays the same polyline on both sides with the input's texture coordinates, and every
// output vertex's u agrees with its azimuth (before the option, a seam vertex slid across the seam
// plane and carried u = 0 where the surface has u = 1: a texture-coordinate error of 1); the
// borders between the regions of a cell array stay exactly; meshes without seams are unchanged.
#include "TestSupport.h"

#include "vtkQuadricTriangleCollapse.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkTriangleFilter.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>

namespace
{
using Position = std::array<double, 3>;

Position PointOf(vtkPolyData* mesh, vtkIdType i)
{
  Position p;
  mesh->GetPoint(i, p.data());
  return p;
}

vtkSmartPointer<vtkPolyData> Collapse(vtkPolyData* input, double keep, bool preserve, const char* regions = nullptr)
{
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->SetInputData(input);
  filter->SetTargetNumberOfTriangles(static_cast<vtkIdType>(keep * input->GetNumberOfPolys()));
  filter->SetPreserveAttributeSeams(preserve);
  filter->SetRegionArrayName(regions);
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

// u of the sphere's parameterisation at p: azimuth / 2 pi in [0, 1). At the seam (y = 0, x > 0)
// both 0 and 1 are right; `u` picks the nearer one.
double AzimuthError(const Position& p, double u)
{
  double azimuth = std::atan2(p[1], p[0]) / (2.0 * vtkMath::Pi());
  azimuth = azimuth < 0 ? azimuth + 1.0 : azimuth;
  const double e = std::fabs(u - azimuth);
  return p[1] == 0.0 || std::fabs(p[1]) < 1e-6 * std::fabs(p[0]) ? std::min(e, 1.0 - e) : e;
}
} // namespace

// Fails without the option: a seam vertex is placed a little across the seam plane with the
// texture coordinates of its own side (u = 0 at an azimuth of nearly 2 pi).
TEST(AttributeSeams, TexturedSphereSeamStaysClosedAndTexturedRight)
{
  for (int resolution : { 80, 120 })
  {
    SCOPED_TRACE(resolution);
    const vtkSmartPointer<vtkPolyData> sphere = slodtest::TexturedSphere(resolution);
    const vtkSmartPointer<vtkPolyData> out = Collapse(sphere, 0.1, true);
    ASSERT_GT(out->GetNumberOfPolys(), 0);
    EXPECT_LE(out->GetNumberOfPolys(), sphere->GetNumberOfPolys() / 10) << "the target is reached";
    vtkDataArray* tcoords = out->GetPointData()->GetTCoords();
    vtkDataArray* inputTCoords = sphere->GetPointData()->GetTCoords();
    ASSERT_NE(tcoords, nullptr);
    // Every seam point of the input (u = 0 or 1, off the poles) is in the output at its exact
    // position with its exact texture coordinates: both sides keep the same polyline.
    std::map<Position, std::set<std::pair<double, double>>> outputAt;
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
    {
      outputAt[PointOf(out, i)].insert({ tcoords->GetComponent(i, 0), tcoords->GetComponent(i, 1) });
    }
    int seamPoints = 0;
    for (vtkIdType i = 0; i < sphere->GetNumberOfPoints(); ++i)
    {
      const double u = inputTCoords->GetComponent(i, 0), v = inputTCoords->GetComponent(i, 1);
      if ((u == 0.0 || u == 1.0) && v > 0.0 && v < 1.0)
      {
        ++seamPoints;
        const auto found = outputAt.find(PointOf(sphere, i));
        ASSERT_NE(found, outputAt.end()) << "seam point " << i << " (u " << u << ", v " << v << ") moved or removed";
        EXPECT_EQ(found->second.count({ u, v }), 1u) << "seam point " << i << " lost its texture coordinates";
      }
    }
    EXPECT_EQ(seamPoints, 2 * (resolution / 2 - 1));
    // No output vertex lies on the wrong side of the seam: its u agrees with its azimuth. The
    // arc along its parallel between the azimuth and u (u error times the parallel's radius) stays
    // below two input columns at the equator (a merged vertex interpolates its neighbours' u); a
    // vertex on the wrong side is a whole turn off. Vertices within 0.1 of the axis are skipped.
    const double column = 1.0 / resolution, radius = 0.5;
    for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
    {
      const Position p = PointOf(out, i);
      const double parallel = std::hypot(p[0], p[1]);
      if (parallel > 0.1)
      {
        EXPECT_LT(AzimuthError(p, tcoords->GetComponent(i, 0)) * parallel / radius, 2.0 * column)
          << "point " << i << " at (" << p[0] << ", " << p[1] << ", " << p[2] << ")";
      }
    }
  }
}

// A sphere cut in two regions along its equator: with RegionArrayName every output triangle stays
// on its region's side and the border is the input's polyline, edge for edge.
TEST(AttributeSeams, RegionBordersStayExactly)
{
  vtkNew<vtkSphereSource> source;
  source->SetThetaResolution(48);
  source->SetPhiResolution(31); // rows at the poles and 29 between: one row on the equator
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(source->GetOutputPort());
  triangles->Update();
  vtkSmartPointer<vtkPolyData> sphere = vtkSmartPointer<vtkPolyData>::New();
  sphere->DeepCopy(triangles->GetOutput());
  sphere->GetPointData()->Initialize(); // no point data: only the region border is a feature
  vtkNew<vtkIntArray> region;
  region->SetName("Region");
  region->SetNumberOfTuples(sphere->GetNumberOfCells());
  for (vtkIdType c = 0; c < sphere->GetNumberOfCells(); ++c)
  {
    vtkCell* cell = sphere->GetCell(c);
    double z = 0;
    for (int k = 0; k < 3; ++k)
    {
      z += sphere->GetPoint(cell->GetPointId(k))[2] / 3.0;
    }
    region->SetValue(c, z > 0 ? 1 : 0);
  }
  sphere->GetCellData()->AddArray(region);

  // The border edges between the regions, by end positions.
  auto borderEdges = [](vtkPolyData* mesh) {
    vtkDataArray* r = mesh->GetCellData()->GetArray("Region");
    std::map<std::pair<Position, Position>, std::set<int>> sides;
    for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
    {
      vtkCell* cell = mesh->GetCell(c);
      for (int k = 0; k < 3; ++k)
      {
        Position a = PointOf(mesh, cell->GetPointId(k)), b = PointOf(mesh, cell->GetPointId((k + 1) % 3));
        sides[{ std::min(a, b), std::max(a, b) }].insert(static_cast<int>(r->GetComponent(c, 0)));
      }
    }
    std::set<std::pair<Position, Position>> border;
    for (const auto& e : sides)
    {
      if (e.second.size() == 2)
      {
        border.insert(e.first);
      }
    }
    return border;
  };
  const auto inputBorder = borderEdges(sphere);
  ASSERT_EQ(inputBorder.size(), 48u) << "premise: one border around the equator";
  double borderHigh = -1, borderLow = 1;
  for (const auto& e : inputBorder)
  {
    borderHigh = std::max({ borderHigh, e.first[2], e.second[2] });
    borderLow = std::min({ borderLow, e.first[2], e.second[2] });
  }

  const vtkSmartPointer<vtkPolyData> out = Collapse(sphere, 0.1, true, "Region");
  ASSERT_GT(out->GetNumberOfPolys(), 0);
  EXPECT_LE(out->GetNumberOfPolys(), sphere->GetNumberOfPolys() / 10) << "the target is reached";
  ASSERT_NE(out->GetCellData()->GetArray("Region"), nullptr);
  EXPECT_EQ(borderEdges(out), inputBorder);
  vtkDataArray* r = out->GetCellData()->GetArray("Region");
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    vtkCell* cell = out->GetCell(c);
    for (int k = 0; k < 3; ++k)
    {
      const double z = out->GetPoint(cell->GetPointId(k))[2];
      if (r->GetComponent(c, 0) == 1)
      {
        EXPECT_GE(z, borderLow) << "a northern triangle reaches south of the border";
      }
      else
      {
        EXPECT_LE(z, borderHigh) << "a southern triangle reaches north of the border";
      }
    }
  }
  // Without the array name nothing holds the border (the premise of the test): some vertex of it
  // is removed or moved.
  EXPECT_NE(borderEdges(Collapse(sphere, 0.1, true)), inputBorder);
}

// Nothing to keep, nothing changed: a closed sphere with normals (no seam) and a textured sphere's
// collapse without a region array give the same output with the option on and off.
TEST(AttributeSeams, NoSeamNoChange)
{
  vtkNew<vtkSphereSource> source;
  source->SetThetaResolution(40);
  source->SetPhiResolution(21);
  source->Update();
  vtkPolyData* sphere = source->GetOutput();
  ASSERT_NE(sphere->GetPointData()->GetNormals(), nullptr) << "premise: point data without a seam";
  const vtkSmartPointer<vtkPolyData> on = Collapse(sphere, 0.2, true);
  const vtkSmartPointer<vtkPolyData> off = Collapse(sphere, 0.2, false);
  ASSERT_EQ(on->GetNumberOfPoints(), off->GetNumberOfPoints());
  ASSERT_EQ(on->GetNumberOfPolys(), off->GetNumberOfPolys());
  for (vtkIdType i = 0; i < on->GetNumberOfPoints(); ++i)
  {
    EXPECT_EQ(PointOf(on, i), PointOf(off, i));
  }
}
