// SPDX-License-Identifier: BSD-3-Clause
// vtkTriangleCollapseHierarchy and its core (Gieng et al. 1997): quadratic fits and curvature on
// analytic surfaces, stencil classification and collapsibility rules, hierarchy invariants on real
// meshes (manifold, genus, no flips, exact vertex splits, blends), the filter's caching and
// outputs, and quality against vtkQuadricDecimation / vtkDecimatePro.
#include "TestSupport.h"

#include "slodCollapseHierarchy.h"
#include "slodEditableMesh.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodQuadraticFit.h"
#include "slodQuadricPoint.h"
#include "slodTriangleStencil.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDecimatePro.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkQuadricDecimation.h"
#include "vtkSMPTools.h"
#include "vtkScanSurfaceSource.h"
#include "vtkStaticCellLocator.h"
#include "vtkSurfaceDeviation.h"

#include <iterator>
#include "vtkTriangleCollapseHierarchy.h"

#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <random>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>

using namespace slod;
using namespace slodtest;

namespace
{
// Samples z = height(u, v) on a small disc around the origin, in the frame's local coordinates.
template <typename F>
std::vector<double> SamplePatch(F height, double radius, int rings = 4, int segments = 12)
{
  std::vector<double> uvh{ 0, 0, height(0.0, 0.0) };
  for (int r = 1; r <= rings; ++r)
  {
    for (int s = 0; s < segments; ++s)
    {
      const double a = 2 * M_PI * (s + 0.5 * r) / segments;
      const double u = radius * r / rings * std::cos(a), v = radius * r / rings * std::sin(a);
      uvh.insert(uvh.end(), { u, v, height(u, v) });
    }
  }
  return uvh;
}

// Index of a triangle of Grid(nx, ny) in cell (i, j) (two triangles per cell).
Index GridTriangle(int nx, int i, int j, int which) { return 2 * (j * nx + i) + which; }
} // namespace

// ---------------------------------------------------------------------------------------------
// Quadratic fit and curvature.

TEST(QuadraticFit, SaddleIsExact)
{
  QuadraticFitter fitter;
  const QuadraticPatch p = fitter.Fit(SamplePatch([](double u, double v) { return u * u - v * v; }, 0.5));
  ASSERT_EQ(p.Degree, 6);
  EXPECT_NEAR(p.C[3], 1.0, 1e-10);
  EXPECT_NEAR(p.C[5], -1.0, 1e-10);
  EXPECT_NEAR(p.C[0], 0.0, 1e-12);
  const PatchCurvature k = EvaluateCurvature(p, 0, 0);
  EXPECT_NEAR(k.K1, 2.0, 1e-9);
  EXPECT_NEAR(k.K2, -2.0, 1e-9);
  EXPECT_NEAR(k.Gaussian, -4.0, 1e-9);
  EXPECT_NEAR(k.Mean, 0.0, 1e-9);
  EXPECT_NEAR(k.Absolute(), 4.0, 1e-9);
}

TEST(QuadraticFit, SphereAndCylinder)
{
  for (double R : { 0.01, 1.0, 250.0 })
  {
    QuadraticFitter fitter;
    // Sphere seen from outside (normal +z at the top): z = sqrt(R^2 - u^2 - v^2) - R.
    const QuadraticPatch s = fitter.Fit(SamplePatch(
      [R](double u, double v) { return std::sqrt(R * R - u * u - v * v) - R; }, 0.02 * R));
    ASSERT_EQ(s.Degree, 6);
    const PatchCurvature ks = EvaluateCurvature(s, 0, 0);
    EXPECT_NEAR(ks.K1 * R, -1.0, 1e-3) << R;
    EXPECT_NEAR(ks.K2 * R, -1.0, 1e-3) << R;
    EXPECT_NEAR(ks.Gaussian * R * R, 1.0, 2e-3) << R;
    EXPECT_NEAR(ks.Mean * R, -1.0, 1e-3) << R;
    // Cylinder along u: curvature 1/R across, 0 along.
    const QuadraticPatch c = fitter.Fit(SamplePatch(
      [R](double, double v) { return std::sqrt(R * R - v * v) - R; }, 0.02 * R));
    ASSERT_EQ(c.Degree, 6);
    const PatchCurvature kc = EvaluateCurvature(c, 0, 0);
    EXPECT_NEAR(kc.K1 * R, 0.0, 1e-3) << R;
    EXPECT_NEAR(kc.K2 * R, -1.0, 1e-3) << R;
    EXPECT_NEAR(kc.Gaussian * R * R, 0.0, 1e-3) << R;
    EXPECT_NEAR(kc.Absolute() * R, 1.0, 2e-3) << R;
  }
}

TEST(QuadraticFit, SlopeEntersThroughFirstFundamentalForm)
{
  // z = a u + b u^2: a curve of curvature 2b / (1 + a^2)^(3/2) at u = 0, straight along v.
  const double a = 0.75, b = 0.4;
  QuadraticFitter fitter;
  const QuadraticPatch p = fitter.Fit(SamplePatch([&](double u, double) { return a * u + b * u * u; }, 1.0));
  ASSERT_EQ(p.Degree, 6);
  const PatchCurvature k = EvaluateCurvature(p, 0, 0);
  const double expected = 2 * b / std::pow(1 + a * a, 1.5);
  EXPECT_NEAR(std::max(k.K1, k.K2), expected, 1e-9);
  EXPECT_NEAR(std::min(k.K1, k.K2), 0.0, 1e-9);
  EXPECT_NEAR(k.Mean, expected / 2, 1e-9);
  // Also at an offset point (u, v) = (0.3, 0): slope a + 2 b u.
  const PatchCurvature k2 = EvaluateCurvature(p, 0.3, 0);
  const double slope = a + 2 * b * 0.3;
  EXPECT_NEAR(std::max(k2.K1, k2.K2), 2 * b / std::pow(1 + slope * slope, 1.5), 1e-9);
}

TEST(QuadraticFit, DegenerateInputsFallBack)
{
  QuadraticFitter fitter;
  // Points on a line: neither a quadratic nor a plane is determined.
  std::vector<double> line;
  for (int i = 0; i < 10; ++i)
  {
    line.insert(line.end(), { 0.1 * i, 0.0, 0.05 * i });
  }
  EXPECT_EQ(fitter.Fit(line).Degree, 0);
  // Four points: a plane only.
  const std::vector<double> four{ 0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1 };
  const QuadraticPatch plane = fitter.Fit(four);
  EXPECT_EQ(plane.Degree, 3);
  EXPECT_NEAR(plane.Evaluate(0.5, 0.5), 1.0, 1e-12);
  EXPECT_EQ(EvaluateCurvature(plane, 0, 0).Absolute(), 0.0);
}

TEST(QuadraticFit, LocalFrameIsOrthonormal)
{
  LocalFrame f;
  ASSERT_TRUE(f.Set({ 1, 2, 3 }, { 0, 0, 5 }, { 0, 0, 1 })); // direction along the normal
  EXPECT_NEAR(Dot(f.U, f.V), 0, 1e-15);
  EXPECT_NEAR(Dot(f.U, f.Normal), 0, 1e-15);
  EXPECT_NEAR(Norm(f.U), 1, 1e-15);
  EXPECT_NEAR(Dot(Cross(f.U, f.V), f.Normal), 1, 1e-15);
  const Vec3 p{ 2.5, -1, 7 };
  const Vec3 l = f.ToLocal(p);
  const Vec3 back = f.ToWorld(l[0], l[1], l[2]);
  EXPECT_NEAR(Norm(back - p), 0, 1e-14);
  EXPECT_FALSE(f.Set({ 0, 0, 0 }, { 0, 0, 0 }, { 1, 0, 0 }));
}

// The evaluations without a fit set only the origin and the normal: they must be Set's, bit for
// bit (the hierarchy's order depends on them), the plane axes left as they were, and a zero normal
// refused as Set refuses it.
TEST(QuadraticFit, SetNormalGivesSetsOriginAndNormal)
{
  std::mt19937 random(35);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> scale(-30, 30);
  for (int i = 0; i < 1000; ++i)
  {
    const double s = std::pow(10.0, scale(random) / 10); // lengths from 1e-3 to 1e3
    const Vec3 origin{ normal(random), normal(random), normal(random) };
    const Vec3 n{ s * normal(random), s * normal(random), s * normal(random) };
    const Vec3 direction{ normal(random), normal(random), normal(random) };
    LocalFrame full, partial;
    partial.U = { 0.5, 0.25, 0.125 };
    partial.V = { -1, -2, -4 };
    ASSERT_TRUE(full.Set(origin, n, direction));
    ASSERT_TRUE(partial.SetNormal(origin, n));
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_EQ(full.Origin[k], partial.Origin[k]);
      EXPECT_EQ(full.Normal[k], partial.Normal[k]);
    }
    EXPECT_EQ(partial.U, (Vec3{ 0.5, 0.25, 0.125 }));
    EXPECT_EQ(partial.V, (Vec3{ -1, -2, -4 }));
  }
  LocalFrame zero;
  EXPECT_FALSE(zero.SetNormal({ 1, 1, 1 }, { 0, 0, 0 }));
  EXPECT_EQ(zero.Normal, (Vec3{ 0, 0, 1 })); // unchanged, as Set leaves it
}

// ---------------------------------------------------------------------------------------------
// Stencils and collapsibility.

// The quadric point without an eigen decomposition must be the pseudo-inverse point (eigenvalues at
// most 1e-3 of the largest dropped) that Eigen's decomposition gives, up to rounding: on random
// rotations of spectra far from the threshold (one, two, three directions kept; a double largest
// eigenvalue; the well-conditioned-but-small-determinant case) and on sums of plane quadrics.
namespace
{
Vec3 EigenPseudoInversePoint(const Quadric& q, const Vec3& center)
{
  Eigen::Matrix3d A;
  A << q.Axx, q.Axy, q.Axz, q.Axy, q.Ayy, q.Ayz, q.Axz, q.Ayz, q.Azz;
  const Eigen::Vector3d c(center[0], center[1], center[2]);
  const Eigen::Vector3d g = A * c + Eigen::Vector3d(q.Bx, q.By, q.Bz);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(A);
  const Eigen::Vector3d lambda = eigen.eigenvalues();
  const double top = lambda.cwiseAbs().maxCoeff();
  Eigen::Vector3d x = c;
  for (int i = 0; i < 3; ++i)
  {
    if (lambda[i] > 1e-3 * top)
    {
      x -= (eigen.eigenvectors().col(i).dot(g) / lambda[i]) * eigen.eigenvectors().col(i);
    }
  }
  return { x[0], x[1], x[2] };
}

Quadric QuadricWithSpectrum(const double (&lambda)[3], std::mt19937& random)
{
  std::normal_distribution<double> normal;
  const Eigen::Matrix3d R = Eigen::Quaterniond(normal(random), normal(random), normal(random), normal(random))
                              .normalized()
                              .toRotationMatrix();
  const Eigen::Matrix3d A = R * Eigen::Vector3d(lambda[0], lambda[1], lambda[2]).asDiagonal() * R.transpose();
  Quadric q;
  q.Axx = A(0, 0);
  q.Axy = A(0, 1);
  q.Axz = A(0, 2);
  q.Ayy = A(1, 1);
  q.Ayz = A(1, 2);
  q.Azz = A(2, 2);
  q.Bx = normal(random);
  q.By = normal(random);
  q.Bz = normal(random);
  return q;
}
}

TEST(QuadricPoint, MatchesTheEigenPseudoInverse)
{
  std::mt19937 random(12);
  std::normal_distribution<double> normal;
  const double spectra[][3] = { { 1, 1e-6, 0 }, { 3, 1e-5, 1e-9 }, { 1, 0.3, 1e-7 }, { 1, 1, 1e-8 },
    { 1, 0.5, 0.02 }, { 2, 0.05, 0.01 }, { 1, 1, 1 }, { 5, 4, 3 }, { 1, 1e-5, 1e-5 } };
  for (const auto& spectrum : spectra)
  {
    for (int trial = 0; trial < 200; ++trial)
    {
      const Quadric q = QuadricWithSpectrum(spectrum, random);
      double lambda[3];
      QuadricEigenvalues(q, lambda);
      const double largest = std::max({ spectrum[0], spectrum[1], spectrum[2] });
      EXPECT_NEAR(lambda[0], largest, 1e-5 * largest); // a double root converges to about 1e-6
      const Vec3 center{ normal(random), normal(random), normal(random) };
      const Vec3 expected = EigenPseudoInversePoint(q, center);
      const Vec3 point = QuadricPointNear(q, center);
      const double scale = 1 + Norm(expected - center);
      ASSERT_LT(Norm(point - expected), 1e-8 * scale)
        << "spectrum " << spectrum[0] << " " << spectrum[1] << " " << spectrum[2] << " trial " << trial;
    }
  }
  // Spectra on both sides of the rank threshold (1e-3 of the largest eigenvalue): the kept
  // directions must be Eigen's (on mc1m the 15.9 million eigen-path quadrics of a build all agree).
  const double nearThreshold[][3] = { { 1, 0.95e-3, 0 }, { 1, 1.05e-3, 0 }, { 1, 1, 0.95e-3 }, { 1, 1, 1.05e-3 },
    { 2, 0.3, 1.9e-3 }, { 2, 0.3, 2.1e-3 } };
  for (const auto& spectrum : nearThreshold)
  {
    for (int trial = 0; trial < 200; ++trial)
    {
      const Quadric q = QuadricWithSpectrum(spectrum, random);
      const Vec3 center{ normal(random), normal(random), normal(random) };
      const Vec3 expected = EigenPseudoInversePoint(q, center);
      ASSERT_LT(Norm(QuadricPointNear(q, center) - expected), 1e-8 * (1 + Norm(expected - center)))
        << "spectrum " << spectrum[0] << " " << spectrum[1] << " " << spectrum[2] << " trial " << trial;
    }
  }
  // Sums of plane quadrics as the hierarchy builds them: nearly one plane, a crease, a corner.
  for (int trial = 0; trial < 300; ++trial)
  {
    const int kind = trial % 3;
    Quadric q;
    for (int plane = 0; plane < 12; ++plane)
    {
      Vec3 n{ 0.001 * normal(random), 0.001 * normal(random), 1 };
      if (kind >= 1 && plane % 2 == 1)
      {
        n = { 1, 0.001 * normal(random), 0.001 * normal(random) };
      }
      if (kind == 2 && plane % 3 == 2)
      {
        n = { 0.001 * normal(random), 1, 0.001 * normal(random) };
      }
      const Vec3 p{ normal(random), normal(random), normal(random) };
      q += Quadric::FromPointNormal(p, Normalized(n), 1 + std::abs(normal(random)));
    }
    const Vec3 center{ normal(random), normal(random), normal(random) };
    const Vec3 expected = EigenPseudoInversePoint(q, center);
    ASSERT_LT(Norm(QuadricPointNear(q, center) - expected), 1e-8 * (1 + Norm(expected - center))) << "trial " << trial;
  }
  // Degenerate input gives the center back.
  const Vec3 center{ 1, 2, 3 };
  EXPECT_EQ(QuadricPointNear(Quadric(), center), center);
}

TEST(TriangleStencil, InteriorTriangleOfRegularGridIsComplete)
{
  const int n = 6;
  EditableMesh mesh(Grid(n, n));
  StencilBuilder builder;
  TriangleStencil s;
  const Index t = GridTriangle(n, 3, 3, 0);
  builder.Build(mesh, t, s);
  EXPECT_TRUE(s.Connected);
  EXPECT_FALSE(s.Cyclic);
  EXPECT_TRUE(s.Complete);
  EXPECT_EQ(s.Triangles.size(), 12u); // 3 x valence 6, minus T counted thrice and 3 neighbours twice
  EXPECT_EQ(s.Neighbors.size(), 3u);
  EXPECT_EQ(s.BoundaryPolygon.size(), 9u);
  for (Index v : s.BoundaryPolygon)
  {
    EXPECT_TRUE(v != s.Vertices[0] && v != s.Vertices[1] && v != s.Vertices[2]);
  }
  // The polygon runs counter-clockwise around T (seen along +z).
  double area2 = 0;
  for (size_t i = 0; i < s.BoundaryPolygon.size(); ++i)
  {
    const Vec3 a = mesh.Point(s.BoundaryPolygon[i]), b = mesh.Point(s.BoundaryPolygon[(i + 1) % s.BoundaryPolygon.size()]);
    area2 += a[0] * b[1] - a[1] * b[0];
  }
  EXPECT_GT(area2, 0);
  const Index* tri = mesh.Triangle(t);
  const Vec3 c = (1.0 / 3.0) * (mesh.Point(tri[0]) + mesh.Point(tri[1]) + mesh.Point(tri[2]));
  EXPECT_EQ(builder.CheckCollapsible(mesh, s, c, { 0, 0, 1 }), CollapsibleStatus::Ok);
  CollapseOptions options;
  EXPECT_EQ(builder.CheckCollapsible(mesh, s, c, { 0, 0, 1 }, &options), CollapsibleStatus::Ok);
}

TEST(TriangleStencil, BoundaryTriangleIsIncomplete)
{
  const int n = 6;
  EditableMesh mesh(Grid(n, n));
  StencilBuilder builder;
  TriangleStencil s;
  builder.Build(mesh, GridTriangle(n, 0, 3, 1), s); // touches the left border
  EXPECT_TRUE(s.Connected);
  EXPECT_FALSE(s.Complete);
  const Index* tri = mesh.Triangle(s.Triangle);
  const Vec3 c = (1.0 / 3.0) * (mesh.Point(tri[0]) + mesh.Point(tri[1]) + mesh.Point(tri[2]));
  EXPECT_EQ(builder.CheckCollapsible(mesh, s, c, { 0, 0, 1 }), CollapsibleStatus::IncompleteStencil);
}

TEST(TriangleStencil, DisconnectedStencil)
{
  // T = (0,1,2); A touches T only at vertex 0, B only at vertex 1 (Fig. 2b).
  TriangleMesh m;
  for (const Vec3& p : std::vector<Vec3>{ { 0, 0, 0 }, { 1, 0, 0 }, { 0.5, 1, 0 }, { -1, -0.5, 0 }, { -0.2, -1, 0 },
         { 1.2, -1, 0 }, { 2, -0.5, 0 } })
  {
    m.AddPoint(p);
  }
  m.AddTriangle(0, 1, 2);
  m.AddTriangle(0, 3, 4);
  m.AddTriangle(1, 5, 6);
  EditableMesh mesh(m);
  StencilBuilder builder;
  TriangleStencil s;
  builder.Build(mesh, 0, s);
  EXPECT_EQ(s.Triangles.size(), 2u);
  EXPECT_FALSE(s.Connected);
  EXPECT_FALSE(s.Complete);
  EXPECT_TRUE(s.Neighbors.empty());
}

TEST(TriangleStencil, TetrahedronIsCyclic)
{
  EditableMesh mesh(Tetrahedron());
  StencilBuilder builder;
  TriangleStencil s;
  builder.Build(mesh, 0, s);
  EXPECT_EQ(s.Triangles.size(), 3u);
  EXPECT_TRUE(s.Connected);
  EXPECT_TRUE(s.Cyclic);
  EXPECT_FALSE(s.Complete);
}

TEST(TriangleStencil, ValenceThreeVertexMakesNeighbourStencilCyclic)
{
  // Split one grid triangle at its centroid: the new vertex has valence three, and the triangle
  // across one of the split triangle's edges sees the three small triangles as a cycle.
  const int n = 6;
  TriangleMesh grid = Grid(n, n);
  const Index split = GridTriangle(n, 3, 3, 0);
  const Index a = grid.Triangles[3 * split], b = grid.Triangles[3 * split + 1], c = grid.Triangles[3 * split + 2];
  const Index q = grid.AddPoint((1.0 / 3.0) * (grid.Point(a) + grid.Point(b) + grid.Point(c)));
  grid.Triangles[3 * split + 2] = q; // (a, b, q)
  grid.AddTriangle(b, c, q);
  grid.AddTriangle(c, a, q);
  EditableMesh mesh(grid);
  // The other triangle of the cell shares edge (a, c) with the split triangle.
  StencilBuilder builder;
  TriangleStencil s;
  builder.Build(mesh, GridTriangle(n, 3, 3, 1), s);
  EXPECT_TRUE(s.Cyclic);
  EXPECT_FALSE(s.Complete);
  EXPECT_EQ(builder.CheckCollapsible(mesh, s, mesh.Point(q), { 0, 0, 1 }), CollapsibleStatus::CyclicStencil);
}

TEST(TriangleStencil, RulesOnARealMesh)
{
  // Every rule, checked independently on every triangle of an irregular mesh: a triangle is
  // collapsible exactly when its stencil is complete, no opposite vertex has valence four and
  // the polygon is star-shaped around the collapse point (here the centroid) in T's plane.
  const TriangleMesh bunny = ToTriangleMesh(LoadTestMesh("bunny00"));
  EditableMesh mesh(bunny);
  StencilBuilder builder;
  TriangleStencil s;
  std::map<CollapsibleStatus, int> seen;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    builder.Build(mesh, t, s);
    const Index* tri = mesh.Triangle(t);
    const Vec3 a = mesh.Point(tri[0]), b = mesh.Point(tri[1]), c = mesh.Point(tri[2]);
    const Vec3 centroid = (1.0 / 3.0) * (a + b + c);
    const Vec3 normal = TriangleNormal(a, b, c);
    const CollapsibleStatus status = builder.CheckCollapsible(mesh, s, centroid, normal);
    ++seen[status];
    bool valenceFour = false;
    for (Index q : s.OppositeVertices)
    {
      valenceFour = valenceFour || mesh.VertexDegree(q) == 4;
    }
    bool star = !s.BoundaryPolygon.empty();
    for (size_t i = 0; i < s.BoundaryPolygon.size(); ++i)
    {
      const Vec3 x = mesh.Point(s.BoundaryPolygon[i]) - centroid;
      const Vec3 y = mesh.Point(s.BoundaryPolygon[(i + 1) % s.BoundaryPolygon.size()]) - centroid;
      star = star && Dot(Cross(x, y), normal) > 0;
    }
    const bool expected = s.Complete && s.Neighbors.size() == 3 && !valenceFour && star;
    ASSERT_EQ(status == CollapsibleStatus::Ok, expected) << "triangle " << t << ": " << ToString(status);
    if (s.Complete)
    {
      ASSERT_FALSE(s.Cyclic);
      ASSERT_TRUE(s.Connected);
    }
  }
  // The mesh exercises every rule.
  EXPECT_GT(seen[CollapsibleStatus::Ok], 20000);
  EXPECT_GT(seen[CollapsibleStatus::CreatesCycle], 0);
  EXPECT_GT(seen[CollapsibleStatus::NotStarShaped], 0);
}

TEST(TriangleStencil, StarShapedTestRejectsPointOutsideKernel)
{
  const int n = 6;
  EditableMesh mesh(Grid(n, n));
  StencilBuilder builder;
  TriangleStencil s;
  builder.Build(mesh, GridTriangle(n, 3, 3, 0), s);
  // Far outside the stencil polygon: the fan would fold.
  EXPECT_EQ(builder.CheckCollapsible(mesh, s, { 0.9, 0.1, 0 }, { 0, 0, 1 }), CollapsibleStatus::NotStarShaped);
  // Heights along the normal do not matter for the projected test.
  EXPECT_EQ(builder.CheckCollapsible(mesh, s, { 0.61, 0.56, 0.3 }, { 0, 0, 1 }), CollapsibleStatus::Ok);
}

namespace
{
// The stencil's classification straight from its definition (pairwise, O(m^2)), for stencil s's
// gathered triangles: connected, cyclic, and the boundary polygon when it is one simple loop
// avoiding T (from the first boundary edge of T, then of the triangles in order), else empty.
struct PairwiseStencil
{
  bool Connected = false, Cyclic = false, Complete = false;
  std::vector<Index> Polygon;
};

PairwiseStencil ClassifyPairwise(const EditableMesh& mesh, const TriangleStencil& s)
{
  PairwiseStencil r;
  const size_t n = s.Triangles.size();
  const auto shared = [&](Index a, Index b) {
    int count = 0;
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        count += mesh.Triangle(a)[i] == mesh.Triangle(b)[j] ? 1 : 0;
      }
    }
    return count;
  };
  std::vector<std::vector<bool>> adjacent(n, std::vector<bool>(n, false));
  for (size_t i = 0; i < n; ++i)
  {
    for (size_t j = 0; j < n; ++j)
    {
      adjacent[i][j] = i != j && shared(s.Triangles[i], s.Triangles[j]) == 2;
    }
  }
  std::vector<bool> reached(n, false);
  std::vector<size_t> stack{ 0 };
  reached[0] = true;
  while (!stack.empty())
  {
    const size_t i = stack.back();
    stack.pop_back();
    for (size_t j = 0; j < n; ++j)
    {
      if (adjacent[i][j] && !reached[j])
      {
        reached[j] = true;
        stack.push_back(j);
      }
    }
  }
  r.Connected = std::all_of(reached.begin(), reached.end(), [](bool b) { return b; });
  for (size_t i = 0; i < n; ++i)
  {
    for (size_t j = i + 1; j < n; ++j)
    {
      for (size_t k = j + 1; k < n; ++k)
      {
        r.Cyclic = r.Cyclic || (adjacent[i][j] && adjacent[j][k] && adjacent[i][k]);
      }
    }
  }
  std::vector<std::pair<Index, Index>> edges;
  std::vector<Index> region{ s.Triangle };
  region.insert(region.end(), s.Triangles.begin(), s.Triangles.end());
  for (Index x : region)
  {
    for (int k = 0; k < 3; ++k)
    {
      edges.emplace_back(mesh.Triangle(x)[k], mesh.Triangle(x)[(k + 1) % 3]);
    }
  }
  std::vector<std::pair<Index, Index>> border;
  for (const auto& e : edges)
  {
    if (std::find(edges.begin(), edges.end(), std::make_pair(e.second, e.first)) == edges.end())
    {
      border.push_back(e);
    }
  }
  bool simple = border.size() >= 3, touches = false;
  for (const auto& e : border)
  {
    simple = simple && std::count_if(border.begin(), border.end(), [&](const auto& f) { return f.first == e.first; }) == 1;
    for (int k = 0; k < 3; ++k)
    {
      touches = touches || e.first == s.Vertices[k] || e.second == s.Vertices[k];
    }
  }
  const Index start = border.empty() ? InvalidIndex : border[0].first;
  Index v = start;
  for (size_t step = 0; simple && step < border.size(); ++step)
  {
    r.Polygon.push_back(v);
    const auto next = std::find_if(border.begin(), border.end(), [&](const auto& f) { return f.first == v; });
    simple = next != border.end();
    v = simple ? next->second : v;
    simple = simple && (v != start || step + 1 == border.size());
  }
  simple = simple && v == start && r.Polygon.size() == border.size();
  if (!simple)
  {
    r.Polygon.clear();
  }
  r.Complete = r.Connected && !r.Cyclic && simple && !touches;
  return r;
}
} // namespace

// Build classifies by hashing the region's edges (it sorted them): on irregular meshes (a noisy
// scan isosurface with borders and handles, a torus and bunny00 after greedy triangle collapses,
// which leave valence-3 vertices and cyclic stencils) every live triangle's stencil is what the
// definition gives pair by pair, Gather then Classify is Build, and a stencil that
// FailsBeforeClassifying is never collapsible (under the paper's rules and the relaxed ones).
TEST(TriangleStencil, ClassificationMatchesThePairwiseDefinition)
{
  std::map<std::string, int> seen;
  for (const TriangleMesh& input : { ToTriangleMesh(NoisyScanIsosurface(30, 7)), Torus(40, 16),
         ToTriangleMesh(LoadTestMesh("bunny00")) })
  {
    EditableMesh mesh(input);
    for (Index t = 0, done = 0; t < mesh.NumberOfTriangles() && done < input.NumberOfTriangles() / 40; t += 3)
    {
      const Index* tri = mesh.Triangle(t);
      const Index set[3] = { tri[0], tri[1], tri[2] };
      const Vec3 c = (1.0 / 3) * (mesh.Point(set[0]) + mesh.Point(set[1]) + mesh.Point(set[2]));
      if (mesh.IsTriangleAlive(t) && mesh.CheckCollapse(set, 3, c) == CollapseStatus::Ok)
      {
        mesh.Collapse(set, 3, set[0], c, nullptr);
        ++done;
      }
    }
    StencilBuilder built, stepped;
    TriangleStencil s, g;
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      if (!mesh.IsTriangleAlive(t))
      {
        continue;
      }
      built.Build(mesh, t, s);
      stepped.Gather(mesh, t, g);
      ASSERT_FALSE(g.Connected || g.Cyclic || g.Complete);
      ASSERT_EQ(g.Triangles, s.Triangles);
      ASSERT_EQ(g.Neighbors, s.Neighbors);
      ASSERT_EQ(g.OppositeVertices, s.OppositeVertices);
      stepped.Classify(mesh, g);
      ASSERT_EQ(g.Connected, s.Connected);
      ASSERT_EQ(g.Cyclic, s.Cyclic);
      ASSERT_EQ(g.Complete, s.Complete);
      ASSERT_EQ(g.BoundaryPolygon, s.BoundaryPolygon);
      const PairwiseStencil r = ClassifyPairwise(mesh, s);
      ASSERT_EQ(s.Connected, r.Connected) << "triangle " << t;
      ASSERT_EQ(s.Cyclic, r.Cyclic) << "triangle " << t;
      ASSERT_EQ(s.Complete, r.Complete) << "triangle " << t;
      ASSERT_EQ(s.BoundaryPolygon, r.Polygon) << "triangle " << t;
      seen["complete"] += s.Complete ? 1 : 0;
      seen["cyclic"] += s.Cyclic ? 1 : 0;
      seen["open or pinched"] += s.Connected && !s.Cyclic && !s.Complete ? 1 : 0;
      const Index* tri = mesh.Triangle(t);
      const Vec3 a = mesh.Point(tri[0]), b = mesh.Point(tri[1]), c = mesh.Point(tri[2]);
      CollapsibleOptions relaxed;
      relaxed.AllowNewCycles = true;
      for (const CollapsibleOptions& options : { CollapsibleOptions(), relaxed })
      {
        if (StencilBuilder::FailsBeforeClassifying(mesh, s, options))
        {
          ++seen[options.AllowNewCycles ? "fails early, relaxed" : "fails early"];
          ASSERT_NE(built.CheckCollapsible(mesh, s, (1.0 / 3) * (a + b + c), TriangleNormal(a, b, c), nullptr, options),
            CollapsibleStatus::Ok);
        }
      }
    }
  }
  for (const char* what : { "complete", "cyclic", "open or pinched", "fails early", "fails early, relaxed" })
  {
    EXPECT_GT(seen[what], 0) << what;
  }
  EXPECT_GT(seen["fails early"], seen["fails early, relaxed"]);
}

// ---------------------------------------------------------------------------------------------
// Hierarchy invariants on real meshes.

namespace
{
TriangleMesh ToMesh(const HierarchyMesh& h)
{
  TriangleMesh m;
  m.Points = h.Points;
  m.Triangles = h.Triangles;
  return m;
}

// Triangles turned over: their normal opposes both the input triangle they descend from and the
// input triangle closest to their centroid. (Either alone misfires: triangles legitimately turn
// on strongly curved parts, and the closest triangle can lie across a sharp crease.)
int CountFlippedTriangles(const TriangleMesh& input, const TriangleMesh& level, const std::vector<Index>& origin)
{
  vtkSmartPointer<vtkPolyData> reference = ToPolyData(input);
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(reference);
  locator->BuildLocator();
  int flipped = 0;
  for (Index t = 0; t < level.NumberOfTriangles(); ++t)
  {
    const Index* tri = level.Triangle(t);
    const Vec3 c = (1.0 / 3.0) * (level.Point(tri[0]) + level.Point(tri[1]) + level.Point(tri[2]));
    double q[3] = { c[0], c[1], c[2] }, closest[3], distance2;
    vtkIdType cell;
    int subId;
    locator->FindClosestPoint(q, closest, cell, subId, distance2);
    const Vec3 n = level.TriangleAreaVector(t);
    flipped += (Dot(n, input.TriangleAreaVector(static_cast<Index>(cell))) < 0 &&
                 Dot(n, input.TriangleAreaVector(origin[t])) < 0)
      ? 1
      : 0;
  }
  return flipped;
}

CollapseHierarchyParameters DefaultParameters()
{
  // The filter's defaults.
  vtkNew<vtkTriangleCollapseHierarchy> f;
  CollapseHierarchyParameters p;
  p.CurvatureWeight = f->GetCurvatureWeight();
  p.AngleWeight = f->GetAngleWeight();
  p.ValenceWeight = f->GetValenceWeight();
  p.ErrorWeight = f->GetErrorWeight();
  p.QuadricCollapsePoint = f->GetQuadricCollapsePoint();
  p.RelaxWhenBlocked = f->GetRelaxWhenBlocked();
  p.PreventNewValenceThree = f->GetPreventNewValenceThree();
  p.EdgeCollapses = static_cast<CollapseHierarchyParameters::EdgeFallback>(f->GetEdgeCollapses());
  p.PreferEdgeFactor = f->GetPreferEdgeFactor();
  p.VertexErrorWeight = f->GetVertexErrorWeight();
  p.StarShapedInStencilPlane = f->GetStarShapedInStencilPlane();
  p.SwapBlockingEdges = f->GetSwapBlockingEdges();
  p.SwapMinimumNormalDot = f->GetSwapMinimumNormalDot();
  p.SwapMinimumNormalDotWhenBlocked = f->GetSwapMinimumNormalDotWhenBlocked();
  p.BatchFraction = f->GetBatchFraction();
  p.BatchSearchDepth = f->GetBatchSearchDepth();
  p.MinimumNormalDot = f->GetMinimumNormalDot();
  return p;
}

using CanonicalTriangle = std::array<double, 9>;
// Non-degenerate triangles as coordinate triples, rotated to start at the smallest corner.
std::vector<CanonicalTriangle> CanonicalTriangles(const HierarchyMesh& h)
{
  std::vector<CanonicalTriangle> out;
  for (size_t t = 0; t < h.Triangles.size() / 3; ++t)
  {
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k)
    {
      for (int j = 0; j < 3; ++j)
      {
        c[k][j] = h.Points[3 * size_t(h.Triangles[3 * t + k]) + j];
      }
    }
    if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0])
    {
      continue;
    }
    const int first = static_cast<int>(std::min_element(c.begin(), c.end()) - c.begin());
    CanonicalTriangle r;
    for (int k = 0; k < 3; ++k)
    {
      std::copy(c[(first + k) % 3].begin(), c[(first + k) % 3].end(), r.begin() + 3 * k);
    }
    out.push_back(r);
  }
  std::sort(out.begin(), out.end());
  return out;
}
} // namespace

// A noisy scan isosurface of the given resolution.
static TriangleMesh NoisyScanMesh(int resolution)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
  source->SetResolution(resolution);
  source->Update();
  return ToTriangleMesh(source->GetOutput());
}

static void ExpectExactlyReversible(const CollapseHierarchy& h, const TriangleMesh& input)
{
  EditableMesh mesh = h.CoarsestMesh();
  for (Index k = h.NumberOfCollapses() - 1; k >= 0; --k)
  {
    h.Refine(mesh, k);
  }
  ASSERT_TRUE(mesh.CheckInvariants());
  ASSERT_EQ(mesh.NumberOfLiveTriangles(), input.NumberOfTriangles());
  ASSERT_EQ(mesh.NumberOfLiveVertices(), input.NumberOfPoints());
  for (Index t = 0; t < input.NumberOfTriangles(); ++t)
  {
    ASSERT_TRUE(mesh.IsTriangleAlive(t));
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_EQ(mesh.Triangle(t)[k], input.Triangles[3 * t + k]);
    }
  }
  for (Index v = 0; v < input.NumberOfPoints(); ++v)
  {
    ASSERT_EQ(mesh.Point(v), input.Point(v));
  }
}

class HierarchyOnMesh : public ::testing::TestWithParam<const char*>
{
};

TEST_P(HierarchyOnMesh, LevelsAreManifoldSameGenusUnflippedAndExactlyReversible)
{
  const TriangleMesh input = ToTriangleMesh(LoadTestMesh(GetParam()));
  const MeshStatistics in = ComputeMeshStatistics(input);
  // The defaults but PreferEdgeFactor 0.1 (the default before session 16): a triangle collapse
  // is then taken unless its cheapest edge collapse costs under a tenth, so both kinds share the
  // levels (with the default 0.5 nearly every collapse is an edge collapse).
  CollapseHierarchyParameters mixed = DefaultParameters();
  mixed.PreferEdgeFactor = 0.1;
  CollapseHierarchy h;
  ASSERT_TRUE(h.Build(input, mixed));
  const int levels = h.NumberOfLevels();
  ASSERT_GT(levels, 10);
  // Down to 2% of the input at least (the quality goal's coarsest target).
  EXPECT_LT(h.LevelTriangleCount(levels - 1), input.NumberOfTriangles() / 50) << GetParam();
  // Both kinds of collapse (edge collapses where triangles are blocked or much dearer).
  EXPECT_GT(h.NumberOfEdgeCollapses(), 0) << GetParam();
  EXPECT_GT(h.NumberOfCollapses() - h.NumberOfEdgeCollapses(), 0) << GetParam();
  HierarchyMesh level;
  for (int i = 0; i < levels; ++i)
  {
    h.ExtractLevel(i, level);
    const TriangleMesh m = ToMesh(level);
    ASSERT_EQ(m.NumberOfTriangles(), h.LevelTriangleCount(i));
    const MeshStatistics s = ComputeMeshStatistics(m);
    ASSERT_EQ(s.NonManifoldEdges, 0) << GetParam() << " level " << i;
    ASSERT_EQ(s.NonManifoldVertices, 0) << GetParam() << " level " << i;
    ASSERT_EQ(s.InconsistentlyOrientedEdges, 0) << GetParam() << " level " << i;
    ASSERT_EQ(s.BoundaryLoops, in.BoundaryLoops) << GetParam() << " level " << i;
    ASSERT_EQ(s.Components, in.Components) << GetParam() << " level " << i;
    ASSERT_EQ(s.EulerCharacteristic, in.EulerCharacteristic) << GetParam() << " level " << i;
    ASSERT_EQ(s.Genus, in.Genus) << GetParam() << " level " << i;
    ASSERT_EQ(s.DegenerateTriangles, 0) << GetParam() << " level " << i;
    if (m.NumberOfTriangles() >= input.NumberOfTriangles() / 50)
    {
      ASSERT_EQ(CountFlippedTriangles(input, m, level.TriangleOrigin), 0) << GetParam() << " level " << i;
    }
  }
  // Level 0 is the input, triangle for triangle.
  h.ExtractLevel(0, level);
  ASSERT_EQ(level.Triangles.size(), input.Triangles.size());
  for (size_t i = 0; i < input.Triangles.size(); ++i)
  {
    ASSERT_EQ(level.PointGlobal[level.Triangles[i]], input.Triangles[i]);
  }

  // Expanding every vertex of the coarsest mesh back (vertex splits, newest first, undoing the
  // edge swaps between levels) gives the input exactly: same triangles, same vertex ids, bitwise
  // the same coordinates. With the defaults (no swaps) and with the swaps between levels on.
  ExpectExactlyReversible(h, input);
  if (std::string(GetParam()) == "fandisk")
  {
    CollapseHierarchyParameters swapping = DefaultParameters();
    swapping.SwapBlockingEdges = true;
    swapping.SwapMinimumNormalDot = 0.9999;
    CollapseHierarchy s;
    ASSERT_TRUE(s.Build(input, swapping));
    EXPECT_GT(s.NumberOfSwaps(), 0); // its flat faces have blocking valence-4 vertices
    ExpectExactlyReversible(s, input);
  }
}

// Expand(k) (vertex splits from the coarsest mesh) and Extract(k) (the stored triangle versions)
// give the same mesh: the same M0 triangle slots with the same global vertices in the same corner
// order, bitwise the same coordinates and the same collapse levels.
static void ExpectExpansionEqualsExtraction(const CollapseHierarchy& h, Index collapses, const std::string& what)
{
  HierarchyMesh expanded, extracted;
  h.Expand(collapses, expanded);
  h.Extract(collapses, collapses, 0.0, extracted);
  ASSERT_EQ(expanded.Triangles.size(), extracted.Triangles.size()) << what;
  ASSERT_EQ(expanded.Triangles.size() / 3, size_t(h.NumberOfTrianglesAfter(collapses))) << what;
  std::map<Index, size_t> extractedAt;
  for (size_t t = 0; t < extracted.TriangleOrigin.size(); ++t)
  {
    ASSERT_TRUE(extractedAt.emplace(extracted.TriangleOrigin[t], t).second) << what;
  }
  for (size_t t = 0; t < expanded.TriangleOrigin.size(); ++t)
  {
    const auto it = extractedAt.find(expanded.TriangleOrigin[t]);
    ASSERT_NE(it, extractedAt.end()) << what << " triangle " << expanded.TriangleOrigin[t];
    const size_t u = it->second;
    for (int k = 0; k < 3; ++k)
    {
      const Index a = expanded.Triangles[3 * t + k], b = extracted.Triangles[3 * u + k];
      ASSERT_EQ(expanded.PointGlobal[a], extracted.PointGlobal[b]) << what;
      for (int j = 0; j < 3; ++j)
      {
        ASSERT_EQ(expanded.Points[3 * size_t(a) + j], extracted.Points[3 * size_t(b) + j]) << what;
      }
    }
    ASSERT_EQ(expanded.TriangleCollapseLevel[t], extracted.TriangleCollapseLevel[u]) << what;
  }
}

TEST_P(HierarchyOnMesh, ExpandingTheCoarsestMeshGivesEveryLevel)
{
  const TriangleMesh input = ToTriangleMesh(LoadTestMesh(GetParam()));
  CollapseHierarchyParameters parameters = DefaultParameters();
  for (const bool swaps : { false, true })
  {
    // Also with the edge swaps between levels (undone by the expansion).
    parameters.SwapBlockingEdges = swaps;
    parameters.SwapMinimumNormalDot = 0.9999;
    CollapseHierarchy h;
    ASSERT_TRUE(h.Build(input, parameters));
    for (int i = 0; i < h.NumberOfLevels(); ++i)
    {
      ExpectExpansionEqualsExtraction(h, h.LevelStart(i), std::string(GetParam()) + " level " + std::to_string(i));
    }
    // A cut inside a batch (a triangle-count target), and the input itself.
    const Index cut = h.CollapsesForTriangleCount(input.NumberOfTriangles() / 7);
    ExpectExpansionEqualsExtraction(h, cut, std::string(GetParam()) + " cut");
    HierarchyMesh m0;
    h.Expand(0, m0);
    ASSERT_EQ(m0.Triangles.size(), input.Triangles.size());
    for (size_t k = 0; k < input.Triangles.size(); ++k)
    {
      ASSERT_EQ(m0.PointGlobal[m0.Triangles[k]], input.Triangles[k]);
    }
  }
}

// The blend is continuous between levels with the defaults: M_i(0) is M_i and M_i(1) is M_i+1,
// triangle for triangle (no edge swap between the levels), on every level.
class BlendOnMesh : public ::testing::TestWithParam<const char*>
{
};

TEST_P(BlendOnMesh, BlendsMatchTheLevels)
{
  const TriangleMesh input = ToTriangleMesh(LoadTestMesh(GetParam()));
  CollapseHierarchy h;
  ASSERT_TRUE(h.Build(input, DefaultParameters()));
  ASSERT_GT(h.NumberOfLevels(), 10) << GetParam();
  HierarchyMesh a, b;
  for (int i = 0; i + 1 < h.NumberOfLevels(); ++i)
  {
    // t = 0 is M_i itself.
    h.ExtractLevel(i, a);
    h.Extract(h.LevelStart(i), h.LevelStart(i + 1), 0.0, b);
    ASSERT_EQ(a.Points, b.Points);
    ASSERT_EQ(a.Triangles, b.Triangles);
    // t = 1 is M_i+1 (collapsed triangles become degenerate and are dropped): the same triangles
    // with bitwise the same corners.
    h.Extract(h.LevelStart(i), h.LevelStart(i + 1), 1.0, a);
    h.ExtractLevel(i + 1, b);
    ASSERT_EQ(h.SwapsAfter(h.LevelStart(i + 1)), 0) << GetParam() << " level " << i;
    ASSERT_EQ(CanonicalTriangles(a), CanonicalTriangles(b)) << GetParam() << " level " << i;
    ASSERT_EQ(b.Triangles.size() / 3, size_t(h.LevelTriangleCount(i + 1))) << GetParam() << " level " << i;
    // In between, every moving point lies on its segment, and the roles mark the batch.
    h.ExtractLevel(i + 0.25, a);
    int collapsing = 0;
    for (unsigned char role : a.TriangleRole)
    {
      collapsing += role == 2 ? 1 : 0;
    }
    // One collapsing triangle per triangle collapse, two (the edge's triangles) per edge collapse.
    int expected = 0;
    for (Index k = h.LevelStart(i); k < h.LevelStart(i + 1); ++k)
    {
      expected += h.GetCollapse(k).Count == 3 ? 1 : 2;
    }
    ASSERT_EQ(collapsing, expected);
    for (size_t p = 0; p < a.PointGlobal.size(); ++p)
    {
      const Vec3 from = h.Vertex(a.PointGlobal[p]);
      const Vec3 to = a.PointTarget[p] == InvalidIndex ? from : h.Vertex(a.PointTarget[p]);
      const Vec3 expected = from + 0.25 * (to - from);
      ASSERT_NEAR(Norm(Vec3{ a.Points[3 * p], a.Points[3 * p + 1], a.Points[3 * p + 2] } - expected), 0, 1e-12);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, HierarchyOnMesh, ::testing::Values("fandisk", "femur", "bunny00", "armadillo"));
// bull and knot1 (genus 1) are used by no other test.
INSTANTIATE_TEST_SUITE_P(RealMeshes, BlendOnMesh, ::testing::Values("fandisk", "femur", "bunny00", "armadillo", "bull", "knot1"));

TEST(CollapseHierarchy, BatchesHaveDisjointStencilsAndRespectTheFraction)
{
  const TriangleMesh input = ToTriangleMesh(LoadTestMesh("bunny00"));
  CollapseHierarchy h;
  CollapseHierarchyParameters p = DefaultParameters();
  ASSERT_TRUE(h.Build(input, p));
  HierarchyMesh m;
  for (int i = 0; i + 1 < h.NumberOfLevels(); ++i)
  {
    const Index batch = h.LevelStart(i + 1) - h.LevelStart(i);
    ASSERT_GE(batch, 1);
    // Counted in triangle collapses: an edge collapse counts half.
    Index halves = 0;
    for (Index k = h.LevelStart(i); k < h.LevelStart(i + 1); ++k)
    {
      halves += h.GetCollapse(k).Count == 3 ? 2 : 1;
    }
    ASSERT_LE(halves, 2 * std::max<Index>(1, static_cast<Index>(p.BatchFraction * h.LevelTriangleCount(i))) + 1);
    // Every triangle holds vertices of at most one collapsing triangle.
    h.Extract(h.LevelStart(i), h.LevelStart(i + 1), 0.5, m);
    std::vector<Index> owner(h.NumberOfVertices(), InvalidIndex);
    for (Index k = h.LevelStart(i); k < h.LevelStart(i + 1); ++k)
    {
      const HierarchyCollapse& c = h.GetCollapse(k);
      ASSERT_TRUE(c.Count == 3 || (c.Count == 2 && c.Sources[2] == InvalidIndex));
      for (int j = 0; j < c.Count; ++j)
      {
        ASSERT_EQ(owner[c.Sources[j]], InvalidIndex);
        owner[c.Sources[j]] = k;
      }
      ASSERT_EQ(h.LevelOfCollapse(k), i);
      // A triangle collapse removes T and its three neighbours, an edge collapse its two triangles.
      ASSERT_EQ(h.NumberOfTrianglesAfter(k + 1), h.NumberOfTrianglesAfter(k) - (c.Count == 3 ? 4 : 2));
    }
    for (size_t t = 0; t < m.Triangles.size() / 3; ++t)
    {
      Index seen = InvalidIndex;
      for (int j = 0; j < 3; ++j)
      {
        const Index o = owner[m.PointGlobal[m.Triangles[3 * t + j]]];
        ASSERT_TRUE(o == InvalidIndex || seen == InvalidIndex || o == seen);
        seen = o == InvalidIndex ? seen : o;
      }
    }
  }
}

// femur (genus 2, thin parts): with triangle collapses only the hierarchy stops above 5% (the
// remaining triangles have incomplete or cyclic stencils); edge collapses in the blocked final
// levels reach 2%, keeping the genus and manifoldness.
TEST(CollapseHierarchy, EdgeCollapsesWhenBlockedReachTheTarget)
{
  const TriangleMesh input = ToTriangleMesh(LoadTestMesh("femur"));
  const MeshStatistics in = ComputeMeshStatistics(input);
  CollapseHierarchyParameters p = DefaultParameters();
  p.PreferEdgeFactor = 0;
  p.EdgeCollapses = CollapseHierarchyParameters::EdgeFallback::Off;
  CollapseHierarchy off;
  ASSERT_TRUE(off.Build(input, p));
  EXPECT_EQ(off.NumberOfEdgeCollapses(), 0);
  EXPECT_GT(off.LevelTriangleCount(off.NumberOfLevels() - 1), input.NumberOfTriangles() / 20);

  p.EdgeCollapses = CollapseHierarchyParameters::EdgeFallback::WhenBlocked;
  CollapseHierarchy blocked;
  ASSERT_TRUE(blocked.Build(input, p));
  EXPECT_GT(blocked.NumberOfEdgeCollapses(), 0);
  EXPECT_LT(blocked.LevelTriangleCount(blocked.NumberOfLevels() - 1), input.NumberOfTriangles() / 50);
  // The levels before the first blocked one are the same as without edge collapses.
  Index firstEdge = 0;
  while (firstEdge < blocked.NumberOfCollapses() && blocked.GetCollapse(firstEdge).Count == 3)
  {
    ++firstEdge;
  }
  EXPECT_GE(firstEdge, off.NumberOfCollapses());
  HierarchyMesh m;
  blocked.ExtractLevel(blocked.NumberOfLevels() - 1, m);
  const MeshStatistics out = ComputeMeshStatistics(ToMesh(m));
  EXPECT_EQ(out.Genus, in.Genus);
  EXPECT_EQ(out.NonManifoldEdges, 0);
  EXPECT_EQ(out.NonManifoldVertices, 0);
  EXPECT_EQ(out.DegenerateTriangles, 0);
  EditableMesh mesh = blocked.CoarsestMesh();
  for (Index k = blocked.NumberOfCollapses() - 1; k >= 0; --k)
  {
    blocked.Refine(mesh, k);
  }
  ASSERT_TRUE(mesh.CheckInvariants());
  for (Index t = 0; t < input.NumberOfTriangles(); ++t)
  {
    ASSERT_TRUE(mesh.IsTriangleAlive(t));
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_EQ(mesh.Triangle(t)[k], input.Triangles[3 * t + k]);
    }
  }
}

TEST(CollapseHierarchy, PaperSettingsReachFivePercentInFewLevels)
{
  // The paper's configuration (weights 1/3 each, 2.5% per batch, its rules only): the bunny
  // needed 29 of 48 levels to get below 5% of the triangles.
  const TriangleMesh input = ToTriangleMesh(LoadTestMesh("bunny00"));
  CollapseHierarchy h;
  const CollapseHierarchyParameters paper;
  ASSERT_FALSE(paper.SwapBlockingEdges); // the core's defaults are the paper's rules
  ASSERT_FALSE(paper.StarShapedInStencilPlane);
  ASSERT_TRUE(h.Build(input, paper));
  EXPECT_EQ(h.NumberOfSwaps(), 0);
  int level = 0;
  while (level < h.NumberOfLevels() && h.LevelTriangleCount(level) >= 0.05 * input.NumberOfTriangles())
  {
    ++level;
  }
  ASSERT_LT(level, h.NumberOfLevels());
  std::printf("[ measure  ] bunny00, paper settings: %d levels to < 5%% (%d triangles), %d levels in all\n",
    level, h.LevelTriangleCount(level), h.NumberOfLevels());
  EXPECT_LE(level, 32);
}

// The paper's configuration fits every collapse point c + f(0,0) n to the original (ancestral)
// points of the stencil. On a noisy sphere (radius 1, radial noise uniform in [-a, a]) the fit
// averages the noise: the collapse points of the coarse levels lie closer to the sphere than
// the input's own vertices do on average (the stencil's few current vertices alone would carry
// their noise into the fit).
TEST(CollapseHierarchy, PaperFitsToAncestralPointsAverageTheNoise)
{
  TriangleMesh sphere = Sphere(96, 96);
  const double a = 0.01;
  double inputDeviation = 0;
  for (Index v = 0; v < sphere.NumberOfPoints(); ++v)
  {
    // A fixed pseudo-random radial offset per vertex (deterministic).
    const double u = std::fmod(std::sin(12.9898 * v + 78.233) * 43758.5453, 1.0);
    const double r = 1.0 + a * (2 * std::fabs(u) - 1);
    const Vec3 p = Normalized(sphere.Point(v));
    for (int j = 0; j < 3; ++j)
    {
      sphere.Points[3 * size_t(v) + j] = r * p[j];
    }
    inputDeviation += std::fabs(r - 1) / sphere.NumberOfPoints();
  }
  CollapseHierarchy h;
  const CollapseHierarchyParameters paper;
  ASSERT_TRUE(h.Build(sphere, paper));
  ASSERT_EQ(h.NumberOfEdgeCollapses(), 0);
  double coarse = 0, worst = 0;
  Index coarseCount = 0;
  for (Index k = 0; k < h.NumberOfCollapses(); ++k)
  {
    const double d = std::fabs(Norm(h.Vertex(h.GetCollapse(k).Point)) - 1);
    worst = std::max(worst, d);
    if (h.LevelOfCollapse(k) >= h.NumberOfLevels() / 2) // the coarse half of the levels
    {
      coarse += d;
      ++coarseCount;
    }
  }
  ASSERT_GT(coarseCount, 50);
  coarse /= coarseCount;
  std::printf("[ measure  ] noisy sphere, paper settings: mean |r - 1| of the input %.2e, of the collapse points "
              "of the coarse half of the %d levels %.2e (%lld, down to %lld triangles of %lld), largest %.2e\n",
    inputDeviation, h.NumberOfLevels(), coarse, static_cast<long long>(coarseCount),
    static_cast<long long>(h.LevelTriangleCount(h.NumberOfLevels() - 1)),
    static_cast<long long>(sphere.NumberOfTriangles()), worst);
  EXPECT_LT(coarse, 0.5 * inputDeviation);
  // Every collapse point stays within twice the noise's amplitude of the sphere: the fit takes only
  // the ancestors over the stencil's footprint (ancestors trailing over a cap of half the sphere
  // put points 4.5 a away).
  EXPECT_LT(worst, 2 * a);
}

TEST(CollapseHierarchy, Deterministic)
{
  const TriangleMesh input = ToTriangleMesh(LoadTestMesh("fandisk"));
  CollapseHierarchy a, b;
  ASSERT_TRUE(a.Build(input, DefaultParameters()));
  ASSERT_TRUE(b.Build(input, DefaultParameters()));
  ASSERT_EQ(a.NumberOfLevels(), b.NumberOfLevels());
  ASSERT_EQ(a.NumberOfCollapses(), b.NumberOfCollapses());
  HierarchyMesh ma, mb;
  a.ExtractLevel(a.NumberOfLevels() - 1, ma);
  b.ExtractLevel(b.NumberOfLevels() - 1, mb);
  EXPECT_EQ(ma.Points, mb.Points);
  EXPECT_EQ(ma.Triangles, mb.Triangles);
  // The same from a moved mesh (M0 taken, not copied), and from a hierarchy object built before
  // (its records are cleared, not appended to).
  CollapseHierarchy c;
  TriangleMesh moved = input;
  ASSERT_TRUE(c.Build(std::move(moved), DefaultParameters()));
  ASSERT_TRUE(b.Build(input, DefaultParameters()));
  for (const CollapseHierarchy* other : { &b, &c })
  {
    ASSERT_EQ(a.NumberOfCollapses(), other->NumberOfCollapses());
    EXPECT_EQ(a.NumberOfSwaps(), other->NumberOfSwaps());
    HierarchyMesh mo;
    other->ExtractLevel(other->NumberOfLevels() - 1, mo);
    EXPECT_EQ(ma.Points, mo.Points);
    EXPECT_EQ(ma.Triangles, mo.Triangles);
    // Exact vertex splits from the coarsest mesh: the records (old positions from the global
    // vertices) give back M0.
    EditableMesh refined = other->CoarsestMesh();
    for (Index k = other->NumberOfCollapses() - 1; k >= 0; --k)
    {
      other->Refine(refined, k);
    }
    ASSERT_EQ(refined.NumberOfLiveTriangles(), input.NumberOfTriangles());
    for (Index t = 0; t < input.NumberOfTriangles(); ++t)
    {
      ASSERT_TRUE(refined.IsTriangleAlive(t));
      ASSERT_TRUE(std::equal(refined.Triangle(t), refined.Triangle(t) + 3, input.Triangle(t)));
    }
    for (Index v = 0; v < input.NumberOfPoints(); ++v)
    {
      ASSERT_EQ(refined.Point(v), input.Point(v));
    }
  }
}

// The evaluations run in parallel (vtkSMPTools): one thread, two and eight must build the same
// hierarchy, bit for bit (every collapse, its point and level, every level's mesh).
// The same hierarchy: every collapse (kind, level, triangle, weight, point) and every seventh
// level blended at 0.5, bit for bit.
static void ExpectSameHierarchy(const CollapseHierarchy& a, const CollapseHierarchy& b, const std::string& what)
{
  ASSERT_EQ(a.NumberOfLevels(), b.NumberOfLevels()) << what;
  ASSERT_EQ(a.NumberOfCollapses(), b.NumberOfCollapses()) << what;
  EXPECT_EQ(a.NumberOfSwaps(), b.NumberOfSwaps()) << what;
  for (Index k = 0; k < a.NumberOfCollapses(); ++k)
  {
    const HierarchyCollapse& x = a.GetCollapse(k);
    const HierarchyCollapse& y = b.GetCollapse(k);
    ASSERT_EQ(x.Count, y.Count) << "collapse " << k << ", " << what;
    ASSERT_EQ(x.Level, y.Level) << "collapse " << k << ", " << what;
    ASSERT_EQ(x.Triangle, y.Triangle) << "collapse " << k << ", " << what;
    ASSERT_EQ(x.Weight, y.Weight) << "collapse " << k << ", " << what;
    ASSERT_EQ(a.Vertex(x.Point), b.Vertex(y.Point)) << "collapse " << k << ", " << what;
  }
  for (int level = 0; level < a.NumberOfLevels(); level += 7)
  {
    HierarchyMesh x, y;
    a.ExtractLevel(level + 0.5, x);
    b.ExtractLevel(level + 0.5, y);
    EXPECT_EQ(x.Points, y.Points) << "level " << level << ", " << what;
    EXPECT_EQ(x.Triangles, y.Triangles) << "level " << level << ", " << what;
  }
}

TEST(CollapseHierarchy, SameHierarchyOnOneTwoAndEightThreads)
{
  const TriangleMesh input = ToTriangleMesh(LoadTestMesh("bunny00"));
  CollapseHierarchy serial;
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ 1 }, [&]() { ASSERT_TRUE(serial.Build(input, DefaultParameters())); });
  ASSERT_GT(serial.NumberOfCollapses(), input.NumberOfTriangles() / 4);
  for (int threads : { 2, 8 })
  {
    CollapseHierarchy parallel;
    vtkSMPTools::LocalScope(
      vtkSMPTools::Config{ threads }, [&]() { ASSERT_TRUE(parallel.Build(input, DefaultParameters())); });
    ExpectSameHierarchy(serial, parallel, std::to_string(threads) + " threads");
  }
}

// Session 41's cheaper stages give the hierarchy of before, bit for bit:
// * the edge pricing does not compute the vertex term of an end point whose quadric sum alone is
//   above the cheapest placement before it (that end point cannot be the cheapest nor tie with
//   it): with VerifyBoundedPricing every pricing of the build (M0's edges and every level's
//   spokes) also computes the exact errors, and the costs both ways must agree bit for bit while
//   most end points were bounded; the hierarchy is the one built without the verification;
// * the build takes the input preparation's non-manifold vertex flags (noisy scan: locked
//   vertices) instead of classifying M0 again: the same hierarchy as without them, and flags of
//   the wrong size or with RemoveCycles (which changes M0 first) are computed again.
TEST(CollapseHierarchy, BoundedPricingAndPreparedFlagsGiveTheSameHierarchy)
{
  vtkSmartPointer<vtkPolyData> scanData = NoisyScanIsosurface(45, 3);
  slod::TriangleMesh scan;
  std::vector<Index> origin;
  const slod::PreparationReport report = slod::PrepareTriangleMesh(scanData, {}, scan, origin);
  ASSERT_TRUE(report.Valid);
  ASSERT_GT(report.NonManifoldVertices, 0); // (the flags matter)
  const TriangleMesh bunny = ToTriangleMesh(LoadTestMesh("bunny00"));
  for (const TriangleMesh* input : { static_cast<const TriangleMesh*>(&scan), &bunny })
  {
    const std::string what = std::to_string(input->NumberOfTriangles()) + " triangles";
    CollapseHierarchy plain, verified;
    ASSERT_TRUE(plain.Build(*input, DefaultParameters()));
    CollapseHierarchyParameters verify = DefaultParameters();
    verify.VerifyBoundedPricing = true;
    ASSERT_TRUE(verified.Build(*input, verify));
    ExpectSameHierarchy(plain, verified, what);
    EXPECT_EQ(verified.NumberOfPricingMismatches(), 0) << what;
    EXPECT_EQ(plain.NumberOfBoundedEndPoints(), 0) << what; // (counted only when verifying)
    // Two end points per pricing (3 or 2 placements each): most of them are bounded.
    EXPECT_GT(verified.NumberOfBoundedEndPoints(), input->NumberOfTriangles()) << what;
    EXPECT_EQ(plain.NumberOfBuildsWithGivenFlags(), 0) << what;
  }
  CollapseHierarchy computed, given, wrongSize, cycles, cyclesGiven;
  ASSERT_TRUE(computed.Build(scan, DefaultParameters()));
  ASSERT_TRUE(given.Build(TriangleMesh(scan), std::vector<unsigned char>(report.NonManifoldVertexFlags), DefaultParameters()));
  EXPECT_EQ(given.NumberOfBuildsWithGivenFlags(), 1);
  ExpectSameHierarchy(computed, given, "flags given");
  std::vector<unsigned char> shorter(report.NonManifoldVertexFlags.begin(), report.NonManifoldVertexFlags.end() - 1);
  ASSERT_TRUE(wrongSize.Build(TriangleMesh(scan), std::move(shorter), DefaultParameters()));
  EXPECT_EQ(wrongSize.NumberOfBuildsWithGivenFlags(), 0);
  ExpectSameHierarchy(computed, wrongSize, "flags of the wrong size");
  CollapseHierarchyParameters removeCycles = DefaultParameters();
  removeCycles.RemoveCycles = true;
  ASSERT_TRUE(cycles.Build(scan, removeCycles));
  ASSERT_TRUE(cyclesGiven.Build(TriangleMesh(scan), std::vector<unsigned char>(report.NonManifoldVertexFlags), removeCycles));
  EXPECT_EQ(cyclesGiven.NumberOfBuildsWithGivenFlags(), 0);
  ExpectSameHierarchy(cycles, cyclesGiven, "RemoveCycles");
}

// Session 43: when a triangle's known cheapest edge collapse fails, FindEdgeCollapse tries the
// other points of its edges (by error), each edge's trial testing the edge's topology (link
// condition, borders) before any point's geometry. On a noisy scan isosurface (handles, borders,
// locked non-manifold vertices: many of the edges tried there fail the link condition) no point
// is tested on an edge that no point passes, while with the geometry first (the order before,
// TopologyBeforeTrialPoints off) a good share of the points are, and no point is tested that the
// geometry first did not test; the hierarchy is the same bit for bit, also with
// the choices decided ahead on two threads (the counters then add up from both).
TEST(CollapseHierarchy, TrialPointsAreTestedOnlyOnEdgesWhoseTopologyPasses)
{
  const TriangleMesh scan = ToTriangleMesh(NoisyScanIsosurface(45, 3));
  CollapseHierarchyParameters geometryFirst = DefaultParameters();
  geometryFirst.TopologyBeforeTrialPoints = false;
  CollapseHierarchy topologyFirst, before;
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ 1 }, [&]() {
    ASSERT_TRUE(topologyFirst.Build(scan, DefaultParameters()));
    ASSERT_TRUE(before.Build(scan, geometryFirst));
  });
  ExpectSameHierarchy(topologyFirst, before, "geometry first");
  ASSERT_GT(topologyFirst.NumberOfTrialPoints(), 0);
  EXPECT_EQ(topologyFirst.NumberOfTrialPointsOnRefusedEdges(), 0);
  EXPECT_GT(before.NumberOfTrialPointsOnRefusedEdges(), before.NumberOfTrialPoints() / 10);
  // (Geometry first, a point of a refused edge is counted so only once one of the edge's points
  // passed the geometry: the others tested before stay among the rest.)
  EXPECT_LE(topologyFirst.NumberOfTrialPoints(), before.NumberOfTrialPoints() - before.NumberOfTrialPointsOnRefusedEdges());
  CollapseHierarchyParameters ahead = DefaultParameters();
  ahead.DecideAhead = true;
  CollapseHierarchy twoThreads;
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ 2 }, [&]() { ASSERT_TRUE(twoThreads.Build(scan, ahead)); });
  ExpectSameHierarchy(topologyFirst, twoThreads, "two threads, choices decided ahead");
  EXPECT_EQ(twoThreads.NumberOfTrialPointsOnRefusedEdges(), 0);
}

// The batch selection decides the coming candidates' choices ahead, in parallel (DecideAhead,
// ChooseAhead), and uses them in the order: on a noisy scan isosurface (borders, handles, locked non-manifold
// vertices) with the defaults, and on bunny00 with triangle collapses preferred (PreferEdgeFactor
// 0: the stencil rules and their blocked stamps), two and four threads build the hierarchy of one
// thread bit for bit; with one thread every choice is made in the order, with more most of them
// ahead (the old selection made all in the order), and little of what is decided ahead is wasted
// (neighbouring candidates are left to the selection).
TEST(CollapseHierarchy, ChoicesDecidedAheadGiveTheSameHierarchy)
{
  const TriangleMesh scan = ToTriangleMesh(NoisyScanIsosurface(45, 3));
  const TriangleMesh bunny = ToTriangleMesh(LoadTestMesh("bunny00"));
  CollapseHierarchyParameters edges = DefaultParameters();
  edges.DecideAhead = true;
  CollapseHierarchyParameters triangles = edges;
  triangles.PreferEdgeFactor = 0;
  for (const auto& run : { std::make_pair(&scan, edges), std::make_pair(&bunny, triangles) })
  {
    CollapseHierarchy serial;
    vtkSMPTools::LocalScope(vtkSMPTools::Config{ 1 }, [&]() { ASSERT_TRUE(serial.Build(*run.first, run.second)); });
    ASSERT_GT(serial.NumberOfCollapses(), run.first->NumberOfTriangles() / 4);
    EXPECT_EQ(serial.NumberOfChoicesAhead(), 0);
    EXPECT_EQ(serial.NumberOfChoicesDecidedAhead(), 0);
    EXPECT_GE(serial.NumberOfChoicesInOrder(), serial.NumberOfCollapses());
    for (int threads : { 2, 4 })
    {
      const std::string what = std::to_string(run.first->NumberOfTriangles()) + " triangles, " + std::to_string(threads) + " threads";
      CollapseHierarchy parallel;
      vtkSMPTools::LocalScope(
        vtkSMPTools::Config{ threads }, [&]() { ASSERT_TRUE(parallel.Build(*run.first, run.second)); });
      ExpectSameHierarchy(serial, parallel, what);
      const Index ahead = parallel.NumberOfChoicesAhead(), inOrder = parallel.NumberOfChoicesInOrder();
      EXPECT_EQ(ahead + inOrder, serial.NumberOfChoicesInOrder()) << what; // the same choices
      EXPECT_GT(ahead, 4 * inOrder) << what;
      EXPECT_LT(parallel.NumberOfChoicesDecidedAhead() - ahead, ahead / 4) << what;
    }
  }
}

// Every level (points, triangles, their M0 slots and collapse levels), the vertex splits (the
// expansion of the coarsest mesh at every fifth level) and the coarsest editable mesh down to the
// order of each vertex's triangles are the same.
static void ExpectSameLevelsAndRecords(const CollapseHierarchy& a, const CollapseHierarchy& b, const std::string& what)
{
  ExpectSameHierarchy(a, b, what);
  ASSERT_EQ(a.NumberOfEdgeCollapses(), b.NumberOfEdgeCollapses()) << what;
  ASSERT_EQ(a.NumberOfBatchRechecks(), b.NumberOfBatchRechecks()) << what;
  for (int level = 0; level < a.NumberOfLevels(); ++level)
  {
    HierarchyMesh x, y;
    a.Extract(a.LevelStart(level), a.LevelStart(level), 0.0, x);
    b.Extract(b.LevelStart(level), b.LevelStart(level), 0.0, y);
    ASSERT_EQ(x.Points, y.Points) << "level " << level << ", " << what;
    ASSERT_EQ(x.Triangles, y.Triangles) << "level " << level << ", " << what;
    ASSERT_EQ(x.TriangleOrigin, y.TriangleOrigin) << "level " << level << ", " << what;
    ASSERT_EQ(x.TriangleCollapseLevel, y.TriangleCollapseLevel) << "level " << level << ", " << what;
    if (level % 5 == 0)
    {
      a.Expand(a.LevelStart(level), x);
      b.Expand(b.LevelStart(level), y);
      ASSERT_EQ(x.Triangles, y.Triangles) << "expanded level " << level << ", " << what;
      ASSERT_EQ(x.PointGlobal, y.PointGlobal) << "expanded level " << level << ", " << what;
      ASSERT_EQ(x.TriangleCollapseLevel, y.TriangleCollapseLevel) << "expanded level " << level << ", " << what;
    }
  }
  const EditableMesh& m = a.CoarsestMesh();
  const EditableMesh& n = b.CoarsestMesh();
  ASSERT_EQ(m.NumberOfLiveTriangles(), n.NumberOfLiveTriangles()) << what;
  for (Index v = 0; v < m.NumberOfPoints(); ++v)
  {
    std::vector<Index> around, aroundToo;
    m.ForEachTriangle(v, [&](Index t) { around.push_back(t); });
    n.ForEachTriangle(v, [&](Index t) { aroundToo.push_back(t); });
    ASSERT_EQ(around, aroundToo) << "vertex " << v << ", " << what;
  }
}

// The batch's edge collapses are applied in runs, concurrently, each in the slots that prefix sums
// of the run's counts give it (ParallelCollapses); the one-by-one application stays as the
// reference (off). On a smooth closed isosurface (nearly all edge collapses, runs of thousands),
// a noisy scan isosurface (borders: edge collapses next to them go one by one, with their checks)
// and bunny00 with PreferEdgeFactor 0.1 (many triangle collapses, which cut the runs): with one,
// two and eight threads, the runs build the reference hierarchy bit for bit, levels and records,
// and most of the isosurface's collapses are applied in runs.
TEST(CollapseHierarchy, CollapsesAppliedInRunsGiveTheSerialHierarchy)
{
  CollapseHierarchyParameters runs = DefaultParameters();
  ASSERT_TRUE(runs.ParallelCollapses); // (the default)
  const std::pair<const char*, TriangleMesh> meshes[] = {
    { "isosurface 80", ToTriangleMesh(SyntheticIsosurface(80)) },
    { "noisy scan 45", ToTriangleMesh(NoisyScanIsosurface(45, 3)) },
    { "bunny00, PreferEdgeFactor 0.1", ToTriangleMesh(LoadTestMesh("bunny00")) } };
  for (const auto& named : meshes)
  {
    CollapseHierarchyParameters parameters = runs;
    parameters.PreferEdgeFactor = named.first[0] == 'b' ? 0.1 : runs.PreferEdgeFactor;
    CollapseHierarchyParameters reference = parameters;
    reference.ParallelCollapses = false; // (the one-by-one reference)
    CollapseHierarchy one;
    vtkSMPTools::LocalScope(vtkSMPTools::Config{ 1 }, [&]() { ASSERT_TRUE(one.Build(named.second, reference)); });
    ASSERT_GT(one.NumberOfCollapses(), named.second.NumberOfTriangles() / 4) << named.first;
    EXPECT_EQ(one.NumberOfCollapsesInRuns(), 0) << named.first;
    for (int threads : { 1, 2, 8 })
    {
      const std::string what = std::string(named.first) + ", " + std::to_string(threads) + " threads";
      CollapseHierarchy inRuns;
      vtkSMPTools::LocalScope(vtkSMPTools::Config{ threads },
        [&]() { ASSERT_TRUE(inRuns.Build(named.second, parameters)); });
      std::printf("[ measure  ] %s: %lld of %lld collapses in runs (%lld edge collapses)\n", what.c_str(),
        static_cast<long long>(inRuns.NumberOfCollapsesInRuns()), static_cast<long long>(inRuns.NumberOfCollapses()),
        static_cast<long long>(inRuns.NumberOfEdgeCollapses()));
      EXPECT_GT(inRuns.NumberOfCollapsesInRuns(), 0) << what;
      if (named.first[0] == 'i')
      {
        EXPECT_GT(inRuns.NumberOfCollapsesInRuns(), 3 * inRuns.NumberOfCollapses() / 4) << what;
      }
      ExpectSameLevelsAndRecords(one, inRuns, what);
    }
  }
  CollapseHierarchy iso;
  const TriangleMesh isosurface = ToTriangleMesh(SyntheticIsosurface(80));
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ 2 }, [&]() { ASSERT_TRUE(iso.Build(isosurface, runs)); });
  ExpectExactlyReversible(iso, isosurface);
}

// The edge collapse costs kept per triangle edge (ReuseEdgeCosts) must be those a new pricing
// gives: a cost kept after one of its ends moved, or after an edge swap gave its triangle other
// corners, would change the order or the choice of an edge. The same hierarchy with and without
// them, with the defaults and with swaps between levels (fandisk's flat faces have many).
TEST(CollapseHierarchy, KeptEdgeCostsGiveTheSameHierarchy)
{
  for (const char* name : { "bunny00", "fandisk" })
  {
    const TriangleMesh input = ToTriangleMesh(LoadTestMesh(name));
    for (bool swaps : { false, true })
    {
      CollapseHierarchyParameters parameters = DefaultParameters();
      parameters.SwapBlockingEdges = swaps;
      parameters.SwapMinimumNormalDot = 0.9999;
      CollapseHierarchy kept, priced;
      ASSERT_TRUE(kept.Build(input, parameters));
      parameters.ReuseEdgeCosts = false;
      ASSERT_TRUE(priced.Build(input, parameters));
      ASSERT_GT(kept.NumberOfCollapses(), input.NumberOfTriangles() / 4) << name;
      EXPECT_TRUE(!swaps || kept.NumberOfSwaps() > 0) << name;
      ExpectSameHierarchy(kept, priced, std::string(name) + (swaps ? " with swaps" : ""));
    }
  }
}

// The kept edge costs are floats (session 26; doubles took 27 bytes per triangle) and their kinds
// 2 bits each (session 34; a byte each before): at most 13 bytes per triangle row (15 before) at
// every progress call of a noisy scan's build, and since every cost is
// rounded up where it is made, a kept one is what a new pricing gives (the same hierarchy without
// them, KeptEdgeCostsGiveTheSameHierarchy) and the selection still takes the edge collapses it
// was ordered by: most collapses are edge collapses, and the levels reach a tenth of the input.
TEST(CollapseHierarchy, EdgeCostsAreKeptAsFloats)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
  source->SetResolution(45);
  source->Update();
  const TriangleMesh scan = ToTriangleMesh(source->GetOutput());
  const size_t nt = size_t(scan.NumberOfTriangles());
  CollapseHierarchy h;
  size_t largest = 0;
  int calls = 0;
  ASSERT_TRUE(h.Build(scan, DefaultParameters(), [&](double) {
    for (const CollapseHierarchy::StorageShare& s : h.Storage())
    {
      if (std::string(s.Name) == "edge costs")
      {
        largest = std::max(largest, s.Bytes);
        ++calls;
      }
    }
    return true;
  }));
  ASSERT_GT(calls, 1);
  EXPECT_GT(largest, 12 * nt); // kept (3 per triangle of M0)
  EXPECT_LE(largest, 13 * nt);
  EXPECT_GT(2 * h.NumberOfEdgeCollapses(), h.NumberOfCollapses());
  EXPECT_LE(h.LevelTriangleCount(h.NumberOfLevels() - 1), Index(nt / 10));
}

// M0's points are held for the life of the hierarchy (issue 12): in floats when every coordinate
// is one (a float input read into doubles: the same values), else in doubles. A noisy scan with its
// coordinates rounded to floats takes at most 12 bytes per point and 12 per triangle for M0 (24 per
// point before), the same scan with one coordinate off a float keeps doubles; both hand back their
// input's points exactly (BaseMesh, the global vertices) and build their levels.
TEST(CollapseHierarchy, M0PointsAreHeldAsFloatsWhenEveryCoordinateIsOne)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
  source->SetResolution(45);
  source->Update();
  TriangleMesh floats = ToTriangleMesh(source->GetOutput());
  for (double& x : floats.Points)
  {
    x = static_cast<float>(x);
  }
  TriangleMesh doubles = floats;
  doubles.Points[4] += std::ldexp(std::fabs(doubles.Points[4]) + 1.0, -40);
  const size_t np = size_t(floats.NumberOfPoints()), nt = size_t(floats.NumberOfTriangles());
  const auto m0Bytes = [](const CollapseHierarchy& h) {
    for (const CollapseHierarchy::StorageShare& s : h.Storage())
    {
      if (std::string(s.Name).rfind("M0", 0) == 0)
      {
        return s.Bytes;
      }
    }
    return size_t(0);
  };
  for (const TriangleMesh* input : { &floats, &doubles })
  {
    const bool exact = input == &floats;
    CollapseHierarchy h;
    ASSERT_TRUE(h.Build(*input, DefaultParameters()));
    if (exact)
    {
      EXPECT_LE(m0Bytes(h), 12 * np + 12 * nt);
    }
    else
    {
      EXPECT_GE(m0Bytes(h), 24 * np + 12 * nt);
    }
    const TriangleMesh base = h.BaseMesh();
    EXPECT_EQ(base.Points, input->Points) << (exact ? "floats" : "doubles");
    EXPECT_EQ(base.Triangles, input->Triangles);
    for (Index v = 0; v < Index(np); v += 97)
    {
      EXPECT_EQ(h.Vertex(v), input->Point(v));
    }
    EXPECT_GT(h.NumberOfLevels(), 5);
    EXPECT_LE(h.LevelTriangleCount(h.NumberOfLevels() - 1), Index(nt / 10));
  }
}

// Edge costs are priced before the evaluations, once per edge for its two triangles (M0's edges,
// then the spokes of each level's new vertices, in parallel): on a noisy scan isosurface (borders,
// handles, non-manifold edges whose vertices are locked) the same hierarchy as with every edge
// priced in each evaluation. A hierarchy built again on the same object, after its first build
// released its working data, is the same as one built once.
TEST(CollapseHierarchy, SpokePricingAndRebuildGiveTheSameHierarchy)
{
  const TriangleMesh scan = NoisyScanMesh(40);
  const TriangleMesh bunny = ToTriangleMesh(LoadTestMesh("bunny00"));
  CollapseHierarchyParameters parameters = DefaultParameters();
  CollapseHierarchy kept, reused, priced;
  ASSERT_TRUE(kept.Build(scan, parameters));
  ASSERT_TRUE(reused.Build(bunny, parameters));
  ASSERT_TRUE(reused.Build(scan, parameters));
  parameters.ReuseEdgeCosts = false;
  ASSERT_TRUE(priced.Build(scan, parameters));
  ASSERT_GT(kept.NumberOfEdgeCollapses(), scan.NumberOfTriangles() / 8);
  ExpectSameHierarchy(kept, priced, "noisy scan, costs kept");
  ExpectSameHierarchy(kept, reused, "noisy scan, built again");
}

// The peak working bytes the build reports (issue 12) within the layout of its arrays. At the end
// of M0's evaluation (the last progress call before the levels) every structure is at full size
// and the hierarchy empty: each share within its layout per input vertex and triangle, the
// editable mesh's references within 9/8 of the three per triangle (EditableMesh's least room;
// 1.25 before session 31, twice that before session 29), no per-vertex link marks (12 bytes per
// vertex before session 31), the rows of the triangles and the quadrics a bit per element and a
// 4-byte base per 64 (4 bytes per element before), the vertex marks in 2 bytes (4 before). The
// peak is at least what every progress call sees, and at most that start, plus what the hierarchy
// grew to, plus the level's selection data at their largest (the order and sample of every live triangle, doubled by
// their growth; marks, batch and re-evaluation lists).
// The accounted peak is kept with its parts (session 39): PeakStorage() is Storage() at that moment
// plus the level state, its parts add up to PeakWorkingBytes(), the level it names was built, and a
// later build starts the record afresh (a smaller input gives a smaller peak, not the old one).
TEST(CollapseHierarchy, PeakStorageAddsUpToThePeak)
{
  CollapseHierarchy h;
  std::vector<size_t> peaks;
  for (const int resolution : { 45, 25 })
  {
    const TriangleMesh scan = NoisyScanMesh(resolution);
    ASSERT_TRUE(h.Build(scan, DefaultParameters()));
    const std::vector<CollapseHierarchy::StorageShare> peak = h.PeakStorage(), after = h.Storage();
    ASSERT_EQ(peak.size(), after.size() + 1);
    size_t sum = 0;
    for (size_t i = 0; i < peak.size(); ++i)
    {
      sum += peak[i].Bytes;
      if (i < after.size())
      {
        EXPECT_EQ(std::string(peak[i].Name), std::string(after[i].Name));
      }
    }
    EXPECT_EQ(std::string(peak.back().Name), "level state (selection)");
    EXPECT_EQ(sum, h.PeakWorkingBytes());
    EXPECT_GE(h.PeakLevel(), -1);
    EXPECT_LT(h.PeakLevel(), h.NumberOfLevels());
    peaks.push_back(sum);
  }
  EXPECT_LT(peaks[1], peaks[0]);
}

// Session 40: the selection's order is given back once a level's batch is chosen, and in the first
// levels (the rows over a quarter of the slots) the working data's rows are compacted at any dead
// row and once more after two thirds of a batch's collapses. So at the peak, once the batch is
// chosen, the level state holds no order (only the marks, a byte per slot, the batch, its survey
// and the kept vertices); and in the first levels the rows are the level's live triangles until
// the compaction inside the batch, and at its end hold fewer dead rows than half the level removed
// (all of them before).
TEST(CollapseHierarchy, ThePeakHoldsNoOrderAfterTheSelectionNorTheWholeBatchsDeadRows)
{
  for (const int resolution : { 45, 60 })
  {
    const TriangleMesh scan = NoisyScanMesh(resolution);
    CollapseHierarchy h;
    ASSERT_TRUE(h.Build(scan, DefaultParameters()));
    const int level = h.PeakLevel();
    const std::string moment = h.PeakMoment();
    // (The levels' selection data come on top of M0's evaluation: the peak is in a level.)
    ASSERT_GE(level, 0) << moment;
    ASSERT_LT(level + 1, h.NumberOfLevels()) << "the peak's level made no collapse";
    const double nt = double(scan.NumberOfTriangles());
    double rowBytes = -1, levelState = -1;
    for (const CollapseHierarchy::StorageShare& share : h.PeakStorage())
    {
      // (the rows counted by the edge costs: 12 bytes of errors and a byte of kinds per row)
      rowBytes = std::string(share.Name) == "edge costs" ? double(share.Bytes) : rowBytes;
      levelState = std::string(share.Name) == "level state (selection)" ? double(share.Bytes) : levelState;
    }
    ASSERT_GE(rowBytes, 0);
    ASSERT_GE(levelState, 0);
    ASSERT_GT(rowBytes, 0);
    const double rows = rowBytes / 13;
    const double atStart = double(h.LevelTriangleCount(level)), atEnd = double(h.LevelTriangleCount(level + 1));
    double largestBatch = 0; // (the batch's arrays keep the room of the largest so far)
    for (int i = 0; i <= level; ++i)
    {
      largestBatch = std::max(largestBatch, double(h.LevelStart(i + 1) - h.LevelStart(i)));
    }
    std::printf("[peak] resolution %d: level %d (%s), %.0f rows, %.0f -> %.0f triangles, level state %.0f bytes\n",
      resolution, level, moment.c_str(), rows, atStart, atEnd, levelState);
    if (moment != "its batch chosen")
    {
      // Marks, the batch (triangle, edge, point: 32 bytes, room up to twice), its survey (13 bytes
      // and a start per collapse, room up to twice), the kept vertices, the re-evaluation's chunk
      // and a vertex's ring (4,096 ids each at most).
      const double bound = nt + 2 * 32 * largestBatch + 13 * largestBatch + 2 * 4 * (largestBatch + 1) +
        2 * 4 * largestBatch + 2 * 4 * 4096.0;
      EXPECT_LE(levelState, bound) << moment;
    }
    if (4 * atStart <= nt)
    {
      continue; // (a later level: its rows are compacted at half, as before)
    }
    if (moment == "its end")
    {
      EXPECT_LT(2 * (rows - atEnd), atStart - atEnd) << "dead rows at the end of level " << level;
    }
    else
    {
      EXPECT_EQ(rows, atStart) << moment;
    }
  }
}

TEST(CollapseHierarchy, PeakWorkingBytesWithinTheLayoutOfItsArrays)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
  source->SetResolution(60);
  source->Update();
  TriangleMesh scan = ToTriangleMesh(source->GetOutput());
  for (double& x : scan.Points)
  {
    x = static_cast<float>(x); // M0 held in floats (12 bytes per point)
  }
  const double nv = scan.NumberOfPoints(), nt = scan.NumberOfTriangles();
  const double references = 4 * (9.0 / 8.0 * 3 * nt + 1024 + 4096);
  // The mesh's scratch lists and its link table (12 bytes a slot, four slots per triangle): a few fans.
  const double meshScratch = 2 * 4096 * sizeof(Index) + 4096 * 12.0;
  const auto rows = [](double n) { return 12 * std::ceil(n / 64); }; // a rank word per 64 elements
  // EvaluateChunk's evaluations of at most 4,096 triangles (16,384 before session 36: 1.9 MB)
  const double evaluationScratch = 4096 * 160.0;
  const std::map<std::string, double> layout = { { "M0 (points, triangles)", 12 * nv + 12 * nt },
    { "editable mesh (coarsest)", nv * (24 + 1 + 4 + 4) + nt * (12 + 1) + references + meshScratch },
    { "collapse points", 0 }, { "collapses", 0 }, { "levels", sizeof(Index) },
    // (versions: M0's deaths are derived when the build ends, 4 bytes per triangle on base)
    { "triangle versions", sizeof(Index) }, { "collapse records", 2 * sizeof(Index) },
    // (evaluations: 12 bytes per row since session 41, the error of the triangle collapse
    // recomputed where read; 20 on base-s41)
    { "vertex ids, flags", 6 * nv }, { "evaluations", 12 * nt + 28 * nt / 16 },
    { "evaluation scratch", evaluationScratch }, { "paper's terms", 0 }, { "quadrics", 80 * nv + rows(nv) },
    // (evaluations: 20 bytes per row and the kept points' entries, 24 before session 32; stamps:
    // the blocked ones 1 byte per row, 2 before session 36, 4 before session 30; their epochs)
    // (edge costs: 12 bytes of errors and one of kinds per row, 15 on base; stamps: a vertex's
    // change stamp, valence and mark in 8 bytes, 10 on base)
    { "edge costs", 13 * nt }, { "stamps, degrees, marks", 8 * nv + 1 * nt + 4096 }, { "ancestors", 0 },
    // (rows: the rank words only since session 45; a current version per row, 4 bytes, before)
    { "rows", rows(nt) } };
  CollapseHierarchy h;
  std::vector<CollapseHierarchy::StorageShare> start;
  size_t seen = 0;
  ASSERT_TRUE(h.Build(scan, DefaultParameters(), [&](double progress) {
    const std::vector<CollapseHierarchy::StorageShare> shares = h.Storage();
    size_t sum = 0;
    for (const CollapseHierarchy::StorageShare& share : shares)
    {
      sum += share.Bytes;
    }
    seen = std::max(seen, sum);
    if (progress <= 0.1 + 1e-9)
    {
      start = shares;
    }
    return true;
  }));
  ASSERT_FALSE(start.empty());
  double startLayout = 0, grown = 0;
  for (size_t i = 0; i < start.size(); ++i)
  {
    const auto bound = layout.find(start[i].Name);
    ASSERT_NE(bound, layout.end()) << start[i].Name << ": a share the test does not know";
    std::printf("[start] %s: %.1f bytes per input vertex, layout %.1f\n", start[i].Name, start[i].Bytes / nv,
      bound->second / nv);
    EXPECT_LE(double(start[i].Bytes), bound->second) << start[i].Name;
    startLayout += bound->second;
  }
  for (const CollapseHierarchy::StorageShare& share : h.Storage())
  {
    grown += share.BuildOnly ? 0.0 : double(share.Bytes); // the hierarchy only grows
  }
  grown += 4.0 * double(h.NumberOfCollapses()); // the ancestors' counts (released at the end)
  const double levelState = nt * (1 + 2 * 12 + 2 * 12.0 / 16 + 1.0 / 8 + 2 * 4) + 2 * 4 * nt + 4096;
  const double peak = double(h.PeakWorkingBytes());
  std::printf("[peak] %.1f bytes per input vertex (progress calls %.1f), bound %.1f\n", peak / nv, seen / nv,
    (startLayout + grown + levelState) / nv);
  EXPECT_GE(peak, double(seen));
  EXPECT_LE(peak, startLayout + grown + levelState);
  EXPECT_LE(h.LevelTriangleCount(h.NumberOfLevels() - 1), Index(nt / 10));
}

// Session 45: a row's M0 slot is read off the rank words in row order (ForEachRowSlot), so no row
// keeps its current version (4 bytes per row, 8 per input vertex at the build's peak, whose only
// use was the slot in its code). At every progress call and at the peak the rows' share is the
// rank words alone, and the peak less that share is the same sum of the other shares: the
// peak per input vertex is below the one the same arrays make with 4 bytes per row more.
TEST(CollapseHierarchy, RowsKeepNoSlotSoThePeakHoldsOnlyTheirRankWords)
{
  const TriangleMesh scan = NoisyScanMesh(60);
  const double nv = scan.NumberOfPoints(), nt = scan.NumberOfTriangles();
  const double rankWords = 12 * std::ceil(nt / 64);
  // (found by the word: its name until session 45 was "current versions, rows")
  const auto rowShare = [](const std::vector<CollapseHierarchy::StorageShare>& shares, double& edgeCosts) {
    double rows = -1;
    for (const CollapseHierarchy::StorageShare& share : shares)
    {
      const std::string name = share.Name;
      rows = name.find("rows") != std::string::npos && name.find("level state") == std::string::npos
        ? double(share.Bytes) : rows;
      edgeCosts = name == "edge costs" ? double(share.Bytes) : edgeCosts;
    }
    return rows;
  };
  CollapseHierarchy h;
  int calls = 0;
  ASSERT_TRUE(h.Build(scan, DefaultParameters(), [&](double) {
    double edgeCosts = 0;
    const double rows = rowShare(h.Storage(), edgeCosts);
    EXPECT_GE(rows, 0);
    EXPECT_LE(rows, rankWords) << "progress call " << calls << ", " << edgeCosts / 13 << " rows";
    ++calls;
    return true;
  }));
  EXPECT_GT(calls, 2);
  double edgeCosts = 0;
  const std::vector<CollapseHierarchy::StorageShare> peak = h.PeakStorage();
  const double rows = rowShare(peak, edgeCosts), liveRows = edgeCosts / 13;
  ASSERT_GT(liveRows, 0);
  double others = 0;
  for (const CollapseHierarchy::StorageShare& share : peak)
  {
    others += double(share.Bytes);
  }
  others -= rows;
  std::printf("[peak] %.1f bytes per input vertex (level %d, %s), rows %.0f bytes for %.0f rows; with a version "
              "per row %.1f\n", double(h.PeakWorkingBytes()) / nv, h.PeakLevel(), h.PeakMoment(), rows, liveRows,
    (others + rankWords + 4 * liveRows) / nv);
  EXPECT_LE(rows, rankWords);
  EXPECT_LE(double(h.PeakWorkingBytes()), others + rankWords);
  EXPECT_LT(double(h.PeakWorkingBytes()) / nv, (others + rankWords + 4 * liveRows) / nv);
}

// Session 45: a cut's extraction (collapses = blend end, the filter's output for a target or a
// level) keeps only the replay's corners and the map to output points; the blend's targets and
// batches come with the first blended extraction (4 bytes per global vertex each), and the meshes
// extracted are the same either way.
TEST(CollapseHierarchy, ACutsExtractionHoldsNoBlendArrays)
{
  const TriangleMesh scan = NoisyScanMesh(45);
  CollapseHierarchy h;
  ASSERT_TRUE(h.Build(scan, DefaultParameters()));
  ASSERT_GT(h.NumberOfLevels(), 3);
  const Index k = h.LevelStart(2);
  HierarchyMesh cut, blended, cutAgain;
  EXPECT_EQ(h.ExtractionScratchBytes(), size_t(0));
  h.Extract(k, k, 0.0, cut);
  const double corners = 3.0 * scan.NumberOfTriangles() * sizeof(Index);
  const double map = double(h.NumberOfVertices()) * sizeof(Index);
  EXPECT_LE(double(h.ExtractionScratchBytes()), corners + map);
  h.Extract(k, h.LevelStart(3), 0.5, blended);
  EXPECT_GE(double(h.ExtractionScratchBytes()), corners + 3 * map);
  h.Extract(k, k, 0.0, cutAgain);
  EXPECT_EQ(cut.Triangles, cutAgain.Triangles);
  EXPECT_EQ(cut.Points, cutAgain.Points);
  EXPECT_EQ(cut.PointTarget, cutAgain.PointTarget);
  EXPECT_EQ(cut.TriangleBatch, cutAgain.TriangleBatch);
  EXPECT_EQ(cut.TriangleRole, cutAgain.TriangleRole);
  for (const Index target : cut.PointTarget)
  {
    EXPECT_EQ(target, InvalidIndex);
  }
  EXPECT_EQ(cut.Triangles.size(), 3 * size_t(h.LevelTriangleCount(2)));
}

// M0's versions' deaths are derived when the build ends, also when it is aborted: the levels
// built until then extract with their counts, and every M0 triangle that a collapse changed has
// the level of that collapse (its death), the others none.
TEST(CollapseHierarchy, AnAbortedBuildKeepsItsLevelsAndDeaths)
{
  const TriangleMesh scan = NoisyScanMesh(40);
  CollapseHierarchy h;
  int calls = 0;
  ASSERT_FALSE(h.Build(scan, DefaultParameters(), [&](double) { return ++calls < 4; }));
  ASSERT_GT(h.NumberOfLevels(), 1);
  HierarchyMesh m;
  for (int i = 0; i < h.NumberOfLevels(); ++i)
  {
    h.ExtractLevel(i, m);
    ASSERT_EQ(m.Triangles.size() / 3, size_t(h.LevelTriangleCount(i))) << "level " << i;
  }
  h.ExtractLevel(0, m);
  std::vector<int> changedAt(size_t(scan.NumberOfTriangles()), -1);
  const CollapseRecords& r = h.SplitRecords();
  for (Index k = h.NumberOfCollapses() - 1; k >= 0; --k) // (the earliest change last)
  {
    const int level = h.LevelOfCollapse(k);
    for (Index i = r.RemovedOffsets[size_t(k)]; i < r.RemovedOffsets[size_t(k) + 1]; ++i)
    {
      changedAt[size_t(r.RemovedTriangles[size_t(i)])] = level;
    }
    for (Index i = r.ChangedOffsets[size_t(k)]; i < r.ChangedOffsets[size_t(k) + 1]; ++i)
    {
      changedAt[size_t(r.ChangedTriangles[size_t(i)])] = level;
    }
  }
  size_t dying = 0;
  for (size_t t = 0; t < changedAt.size(); ++t)
  {
    ASSERT_EQ(m.TriangleOrigin[t], Index(t));
    dying += m.TriangleCollapseLevel[t] >= 0 ? 1 : 0;
  }
  ASSERT_GT(dying, changedAt.size() / 20);
  for (size_t t = 0; t < changedAt.size(); ++t)
  {
    if (m.TriangleCollapseLevel[t] != changedAt[t])
    {
      // (a triangle around the kept vertex gets a new version without a redirected corner)
      ASSERT_GE(m.TriangleCollapseLevel[t], 0) << "triangle " << t;
      ASSERT_TRUE(changedAt[t] < 0 || changedAt[t] > m.TriangleCollapseLevel[t]) << "triangle " << t;
    }
  }
}

// The records of the vertex splits keep a redirected corner in 5 bytes (its triangle, and its
// corner packed with the position of the vertex it had among the collapse's sources: 9 before,
// a 4-byte id), about 15 bytes per input vertex less in the finished hierarchy on mc1m; the splits
// still give back M0 (every level expanded equals the stored one, checked by the Expand tests).
TEST(CollapseHierarchy, SplitRecordsKeepARedirectedCornerInFiveBytes)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
  source->SetResolution(45);
  source->Update();
  const TriangleMesh scan = ToTriangleMesh(source->GetOutput());
  CollapseHierarchy h;
  ASSERT_TRUE(h.Build(scan, DefaultParameters()));
  const CollapseRecords& r = h.SplitRecords();
  const size_t n = size_t(h.NumberOfCollapses()), removed = r.RemovedTriangles.size();
  const size_t changed = r.ChangedTriangles.size(), flips = size_t(r.NumberOfFlips());
  ASSERT_EQ(size_t(r.NumberOfCollapses()), n);
  ASSERT_GT(changed, 2 * n);
  for (Index k = 0; k < Index(n); ++k)
  {
    const HierarchyCollapse c = h.GetCollapse(k);
    for (size_t i = size_t(r.ChangedOffsets[k]); i < size_t(r.ChangedOffsets[k + 1]); ++i)
    {
      // (the corner held a merged vertex other than the kept one; the sources are global ids,
      // the records' editable ones: compare through the kept vertex's count)
      ASSERT_NE(r.ChangedFrom(k, i), r.Kept(k));
      ASSERT_TRUE(r.ChangedFrom(k, i) == r.Vertices[3 * size_t(k) + 1] ||
        (c.Count == 3 && r.ChangedFrom(k, i) == r.Vertices[3 * size_t(k) + 2]));
    }
  }
  size_t records = 0;
  for (const CollapseHierarchy::StorageShare& share : h.Storage())
  {
    records += std::string(share.Name) == "collapse records" ? share.Bytes : 0;
  }
  const size_t layout = (3 * n + 2 * (n + 1) + removed + changed + flips) * sizeof(Index) + changed +
    flips * sizeof(FlipRecord);
  std::printf("collapse records: %.2f bytes per collapse, layout %.2f\n", double(records) / n, double(layout) / n);
  EXPECT_LE(records, layout);
}

// The accounting of the hierarchy's memory (issue 12): during the build the working structures
// hold memory, after it only the hierarchy does (the working data is released), and the levels
// read back from the compact versions are those the build made (the replay of changed corners:
// every level manifold with the input's Euler characteristic and unflipped). Prints the shares in
// bytes per input vertex at the end of the build, where the peak is.
TEST(CollapseHierarchy, WorkingDataIsReleasedAndTheAccountingAddsUp)
{
  const TriangleMesh scan = NoisyScanMesh(40);
  CollapseHierarchy h;
  std::vector<CollapseHierarchy::StorageShare> during;
  ASSERT_TRUE(h.Build(scan, DefaultParameters(), [&](double) {
    during = h.Storage();
    return true;
  }));
  const std::vector<CollapseHierarchy::StorageShare> after = h.Storage();
  ASSERT_EQ(during.size(), after.size());
  const double nv = scan.NumberOfPoints();
  size_t working = 0, kept = 0;
  for (size_t i = 0; i < after.size(); ++i)
  {
    std::cout << "  " << after[i].Name << (after[i].BuildOnly ? " (build)" : "") << ": "
              << during[i].Bytes / nv << " bytes per input vertex at the last level, " << after[i].Bytes / nv
              << " after\n";
    EXPECT_EQ(during[i].BuildOnly, after[i].BuildOnly);
    if (after[i].BuildOnly)
    {
      EXPECT_EQ(after[i].Bytes, 0u) << after[i].Name;
      working += during[i].Bytes;
    }
    else
    {
      EXPECT_GT(after[i].Bytes, 0u) << after[i].Name;
      if (std::string(after[i].Name) == "triangle versions")
      {
        // Every version's death is derived when the build ends (M0's since session 32, the later
        // ones' since session 41), and all versions are then packed in the bits their counts need
        // (session 37): below the build's codes with the 4-byte deaths base-s41 held beside them.
        EXPECT_LT(after[i].Bytes, during[i].Bytes + 4 * size_t(h.NumberOfTriangleVersions()))
          << "triangle versions not packed after the build";
      }
      else
      {
        EXPECT_EQ(after[i].Bytes, during[i].Bytes) << after[i].Name << " changed after the last level";
      }
      kept += after[i].Bytes;
    }
  }
  std::cout << "  working " << working / nv << ", hierarchy " << kept / nv << " bytes per input vertex\n";
  EXPECT_GT(working, 0u);
  const MeshStatistics in = ComputeMeshStatistics(scan);
  for (int level = 0; level < h.NumberOfLevels(); level += 5)
  {
    HierarchyMesh m;
    h.ExtractLevel(level, m);
    const TriangleMesh mesh = ToMesh(m);
    const MeshStatistics s = ComputeMeshStatistics(mesh);
    EXPECT_EQ(s.EulerCharacteristic, in.EulerCharacteristic) << "level " << level;
    EXPECT_EQ(s.NonManifoldEdges, in.NonManifoldEdges) << "level " << level;
    EXPECT_EQ(s.BoundaryLoops, in.BoundaryLoops) << "level " << level;
    EXPECT_EQ(CountFlippedTriangles(scan, mesh, m.TriangleOrigin), 0) << "level " << level;
    EXPECT_EQ(Index(m.Triangles.size() / 3), h.LevelTriangleCount(level)) << "level " << level;
  }
}

// What follows from an index is not stored (session 23): a collapse keeps 24 bytes (its point,
// count and level follow from its index, its sources and the level starts; HierarchyCollapse took
// 40), M0's versions keep only their deaths (4 bytes per input triangle, the code is Base's
// triangle; 8 before; derived when the build ends since session 32), and the ancestors of a vertex are walked through the collapses' sources
// (4 bytes per collapse for their counts instead of 16 per input vertex for linked lists), and no
// triangle count is kept per collapse (4 bytes each before). Checked
// at every progress call of the build against bounds from the counts, and the collapses handed
// out agree with the levels and the global vertices (points after the input's, in order).
TEST(CollapseHierarchy, CollapsesAndVersionsKeepOnlyWhatTheirIndexCannotGive)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
  source->SetResolution(45);
  source->Update();
  const TriangleMesh scan = ToTriangleMesh(source->GetOutput());
  const size_t nt = size_t(scan.NumberOfTriangles()), np = size_t(scan.NumberOfPoints());
  CollapseHierarchy h;
  const auto share = [&h](const std::string& name) {
    for (const CollapseHierarchy::StorageShare& s : h.Storage())
    {
      if (name == s.Name)
      {
        return s.Bytes;
      }
    }
    ADD_FAILURE() << "no share " << name;
    return size_t(0);
  };
  int calls = 0, beforeAnyCollapse = 0;
  ASSERT_TRUE(h.Build(scan, DefaultParameters(), [&](double) {
    ++calls;
    const size_t collapses = size_t(h.NumberOfCollapses());
    EXPECT_LE(share("collapses"), 24 * collapses);
    EXPECT_LE(share("ancestors"), 4 * collapses);
    // During the build a version keeps its code only (the versions after M0's: 4 bytes each), with
    // the birth counts and the swapped triangles' vertices: no death is written before the build
    // ends (base-s41 held 4 bytes more per version born, a sixth of the peak on mc1m at level 25).
    const size_t later = size_t(h.NumberOfTriangleVersions()) - nt;
    EXPECT_LE(share("triangle versions"),
      4 * later + sizeof(Index) * (collapses + 1) + 2 * 3 * sizeof(Index) * size_t(h.NumberOfSwaps()))
      << "after " << collapses << " collapses";
    if (collapses == 0)
    {
      ++beforeAnyCollapse;
      // M0's versions: nothing but the birth count of the empty hierarchy (their deaths are
      // derived when the build ends; 4 bytes each during the build before session 32).
      EXPECT_EQ(share("triangle versions"), sizeof(Index));
    }
    return true;
  }));
  EXPECT_GT(calls, beforeAnyCollapse);
  EXPECT_GT(beforeAnyCollapse, 0);
  ASSERT_GT(h.NumberOfCollapses(), Index(nt / 4));
  EXPECT_EQ(share("collapses"), 24 * size_t(h.NumberOfCollapses()));
  for (Index k = 0; k < h.NumberOfCollapses(); ++k)
  {
    const HierarchyCollapse c = h.GetCollapse(k);
    ASSERT_EQ(c.Point, Index(np) + k);
    ASSERT_EQ(c.Count, c.Sources[2] == InvalidIndex ? 2 : 3);
    ASSERT_LE(h.LevelStart(c.Level), k);
    ASSERT_LT(k, h.LevelStart(c.Level + 1));
    for (int i = 0; i < c.Count; ++i)
    {
      ASSERT_GE(c.Sources[i], 0);
      ASSERT_LT(c.Sources[i], c.Point); // a source exists before the collapse
    }
  }
  // No triangle count per collapse: the counts (M0's less the records' removed triangles) are
  // those of the cuts.
  EXPECT_EQ(share("levels"), sizeof(Index) * size_t(h.NumberOfLevels()));
  // Once built, every version keeps its death in the bits of the collapse count (Never and the
  // counts), each later one its slot and changed corner in the bits of four times the triangles,
  // besides the birth counts and the swapped triangles' three vertices (32 bits each of the two
  // fields on base, 4 bytes for M0's deaths).
  const auto bits = [](size_t largest) {
    size_t b = 1;
    while (b < 64 && (largest >> b) != 0)
    {
      ++b;
    }
    return b;
  };
  const size_t versions = size_t(h.NumberOfTriangleVersions());
  ASSERT_GT(versions, nt);
  const size_t packedBits = versions * bits(size_t(h.NumberOfCollapses()) + 1) + (versions - nt) * bits(4 * nt - 1);
  const size_t births = sizeof(Index) * size_t(h.NumberOfCollapses() + 1);
  const size_t swapped = 2 * 3 * sizeof(Index) * size_t(h.NumberOfSwaps());
  EXPECT_GE(share("triangle versions"), packedBits / 8 + births + swapped);
  EXPECT_LE(share("triangle versions"), packedBits / 8 + 16 + births + swapped);
  HierarchyMesh cut;
  for (Index k = 0; k <= h.NumberOfCollapses(); k += 1 + h.NumberOfCollapses() / 40)
  {
    h.Extract(k, k, 0.0, cut);
    ASSERT_EQ(Index(cut.Triangles.size() / 3), h.NumberOfTrianglesAfter(k)) << "after " << k << " collapses";
  }
}

// The build's working data shrink with the mesh (CompactRows, CompactQuadrics): after every level
// the edge costs (a fixed number of bytes per triangle row) and the quadrics (per vertex row) hold
// at most 8/7 rows per live triangle and vertex (2 once under a quarter of the input's), not one
// per input triangle and vertex as before,
// so that they no longer add to the hierarchy at the end of the build, where it is largest.
TEST(CollapseHierarchy, WorkingDataShrinkWithTheMesh)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
  source->SetResolution(50);
  source->Update();
  const TriangleMesh scan = ToTriangleMesh(source->GetOutput());
  const auto share = [](const std::vector<CollapseHierarchy::StorageShare>& storage, const std::string& name) {
    for (const CollapseHierarchy::StorageShare& s : storage)
    {
      if (name == s.Name)
      {
        return double(s.Bytes);
      }
    }
    ADD_FAILURE() << "no storage share " << name;
    return 0.0;
  };
  CollapseHierarchy h;
  double edgeCostsPerTriangle = 0, fullQuadrics = 0;
  int levelsSeen = 0;
  ASSERT_TRUE(h.Build(scan, DefaultParameters(), [&](double) {
    const std::vector<CollapseHierarchy::StorageShare> storage = h.Storage();
    const double edgeCosts = share(storage, "edge costs"), quadrics = share(storage, "quadrics");
    if (h.NumberOfLevels() == 1)
    {
      edgeCostsPerTriangle = edgeCosts / scan.NumberOfTriangles(); // M0's evaluation: every row
      fullQuadrics = quadrics;
      return true;
    }
    ++levelsSeen;
    const double live = h.LevelTriangleCount(h.NumberOfLevels() - 1) / double(scan.NumberOfTriangles());
    const double rowsAllowed = std::max(8.0 / 7.0 * live, std::min(2 * live, 0.25)); // per input triangle
    EXPECT_LE(edgeCosts, edgeCostsPerTriangle * (rowsAllowed * scan.NumberOfTriangles() + 1))
      << "level " << h.NumberOfLevels() - 1;
    // The live vertices follow the live triangles (about half as many on a closed surface).
    EXPECT_LE(quadrics, fullQuadrics * (rowsAllowed + 0.1)) << "level " << h.NumberOfLevels() - 1;
    return true;
  }));
  EXPECT_GT(edgeCostsPerTriangle, 0);
  EXPECT_GT(levelsSeen, 20);
  EXPECT_LT(h.LevelTriangleCount(h.NumberOfLevels() - 1), scan.NumberOfTriangles() / 10);
}

// A batch's collapses passed their checks when they were selected; only a collapse whose region
// an earlier collapse of the batch touched (a shared boundary vertex) is checked again when the
// batch is collapsed. Replayed on M0 in their order, every collapse of the hierarchy still passes
// the mesh check on the mesh it was applied to, and the re-checks are fewer than the collapses
// (every collapse was checked twice before).
namespace
{
// Every collapse of the hierarchy, replayed on M0 in its order, passes CheckCollapse on the mesh it
// is applied to, and the replay ends at the coarsest level's count.
void ExpectEveryCollapseValidWhenReplayed(const CollapseHierarchy& h, const CollapseHierarchyParameters& parameters)
{
  ASSERT_EQ(h.NumberOfSwaps(), 0); // (the replay applies collapses only)
  // Global vertex -> editable vertex (a collapse keeps its first source's vertex).
  EditableMesh mesh(h.BaseMesh());
  std::vector<Index> vertexOf(size_t(h.NumberOfVertices()), InvalidIndex);
  std::iota(vertexOf.begin(), vertexOf.begin() + h.BaseMesh().NumberOfPoints(), 0);
  CollapseOptions options;
  options.MinimumNormalDot = parameters.MinimumNormalDot;
  Index failed = 0;
  for (Index k = 0; k < h.NumberOfCollapses(); ++k)
  {
    const HierarchyCollapse& c = h.GetCollapse(k);
    Index vertices[3];
    for (int i = 0; i < c.Count; ++i)
    {
      vertices[i] = vertexOf[size_t(c.Sources[i])];
    }
    const Vec3 point = h.Vertex(c.Point);
    failed += mesh.CheckCollapse(vertices, c.Count, point, options) == CollapseStatus::Ok ? 0 : 1;
    mesh.Collapse(vertices, c.Count, vertices[0], point);
    vertexOf[size_t(c.Point)] = vertices[0];
  }
  EXPECT_EQ(failed, 0);
  EXPECT_EQ(mesh.NumberOfLiveTriangles(), h.LevelTriangleCount(h.NumberOfLevels() - 1));
}
} // namespace

TEST(CollapseHierarchy, BatchCollapsesAreCheckedAgainOnlyWhereAnEarlierOneTouchedThem)
{
  for (const int resolution : { 45, 70 })
  {
    SCOPED_TRACE(resolution);
    vtkNew<vtkScanSurfaceSource> source;
    source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
    source->SetResolution(resolution);
    source->Update();
    const TriangleMesh scan = ToTriangleMesh(source->GetOutput());
    const CollapseHierarchyParameters parameters = DefaultParameters();
    CollapseHierarchy h;
    ASSERT_TRUE(h.Build(scan, parameters));
    std::printf("[ measure  ] resolution %d: %lld of %lld collapses checked again\n", resolution,
      static_cast<long long>(h.NumberOfBatchRechecks()), static_cast<long long>(h.NumberOfCollapses()));
    EXPECT_GT(h.NumberOfCollapses(), scan.NumberOfTriangles() / 4);
    EXPECT_LT(h.NumberOfBatchRechecks(), h.NumberOfCollapses());
    ExpectEveryCollapseValidWhenReplayed(h, parameters);
  }
}

// An edge collapse's check reads, beyond its own region (which the batch's other collapses do not
// touch), only the stars of the border vertices opposite its edge: on closed meshes no edge
// collapse of a batch is checked again, only triangle collapses (rule (2): their opposite
// vertices' valences), and every collapse is still valid on the mesh it is applied to. (Before,
// any collapse whose stars shared a vertex with an earlier region was checked again: about 60% of
// the collapses, most of them edge collapses.)
TEST(CollapseHierarchy, EdgeCollapsesOfClosedMeshesAreNotCheckedAgain)
{
  const std::pair<const char*, TriangleMesh> meshes[] = { { "isosurface 40", ToTriangleMesh(SyntheticIsosurface(40)) },
    { "torus", Torus(120, 40) } };
  for (const auto& named : meshes)
  {
    SCOPED_TRACE(named.first);
    ASSERT_EQ(ComputeMeshStatistics(named.second).BoundaryEdges, 0);
    const CollapseHierarchyParameters parameters = DefaultParameters();
    CollapseHierarchy h;
    ASSERT_TRUE(h.Build(named.second, parameters));
    const Index triangleCollapses = h.NumberOfCollapses() - h.NumberOfEdgeCollapses();
    std::printf("[ measure  ] %s: %lld of %lld collapses checked again (%lld edge collapses)\n", named.first,
      static_cast<long long>(h.NumberOfBatchRechecks()), static_cast<long long>(h.NumberOfCollapses()),
      static_cast<long long>(h.NumberOfEdgeCollapses()));
    EXPECT_GT(h.NumberOfEdgeCollapses(), h.NumberOfCollapses() / 2);
    EXPECT_LE(h.NumberOfBatchRechecks(), triangleCollapses);
    ExpectEveryCollapseValidWhenReplayed(h, parameters);
  }
}

// An evaluation keeps its collapse point only when it cannot be recomputed from T's vertices and
// their quadrics (the fit's point, a fold-free alternative): with the defaults most points are
// the quadric's, and the kept evaluations take at most 32 bytes per triangle (56 when every point
// was stored). The paper's configuration takes every point from the fit: all are kept, and the
// hierarchy still reaches its levels.
TEST(CollapseHierarchy, EvaluationsKeepOnlyThePointsTheyCannotRecompute)
{
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
  source->SetResolution(60);
  source->Update();
  const TriangleMesh scan = ToTriangleMesh(source->GetOutput());
  const double nt = scan.NumberOfTriangles();
  const auto evaluationBytes = [](const CollapseHierarchy& h) {
    for (const CollapseHierarchy::StorageShare& s : h.Storage())
    {
      if (std::string(s.Name) == "evaluations")
      {
        return double(s.Bytes);
      }
    }
    ADD_FAILURE() << "no evaluations share";
    return 0.0;
  };
  for (const bool paper : { false, true })
  {
    SCOPED_TRACE(paper ? "paper" : "defaults");
    CollapseHierarchy h;
    double largest = 0, atM0 = 0;
    ASSERT_TRUE(h.Build(scan, paper ? CollapseHierarchyParameters() : DefaultParameters(), [&](double) {
      const double bytes = evaluationBytes(h);
      largest = std::max(largest, bytes);
      atM0 = h.NumberOfLevels() == 1 ? bytes : atM0;
      return true;
    }));
    std::printf("[ measure  ] %s: evaluations %.1f bytes per input triangle after M0's evaluation\n",
      paper ? "paper" : "defaults", atM0 / nt);
    EXPECT_GT(atM0, 0);
    EXPECT_LE(largest, atM0) << "the evaluations grew after M0's";
    if (!paper)
    {
      EXPECT_LE(atM0, 32 * nt);
    }
    EXPECT_GT(h.NumberOfLevels(), 10);
  }
}

namespace
{
// input with T-junction repairs every 97th triangle: a vertex m inserted in edge (a, b) splits the
// triangle on one side and the other side's gap is filled with the zero-area triangle (a, m, b).
// Returns the zero-area triangles' ids.
std::vector<Index> AddTJunctions(TriangleMesh& input)
{
  const Index nt = input.NumberOfTriangles();
  std::map<std::pair<Index, Index>, Index> edgeTriangle; // directed edge -> its triangle
  for (Index t = 0; t < nt; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      edgeTriangle[{ input.Triangles[3 * t + k], input.Triangles[3 * t + (k + 1) % 3] }] = t;
    }
  }
  std::vector<unsigned char> used(size_t(nt), 0);
  std::vector<Index> zeroArea;
  for (Index t = 0; t < nt; t += 97)
  {
    const Index a = input.Triangles[3 * t], b = input.Triangles[3 * t + 1];
    const auto across = edgeTriangle.find({ b, a });
    if (used[t] || across == edgeTriangle.end() || used[across->second])
    {
      continue;
    }
    const Index n = across->second;
    used[t] = used[n] = 1;
    Index* o = &input.Triangles[3 * n];
    const int corner = o[0] == b ? 0 : (o[1] == b ? 1 : 2); // o runs b -> a -> d
    const Index d = o[(corner + 2) % 3];
    const Index m = input.AddPoint(0.5 * (input.Point(a) + input.Point(b)));
    o[0] = b;
    o[1] = m;
    o[2] = d;
    input.AddTriangle(m, a, d);
    zeroArea.push_back(input.NumberOfTriangles());
    input.AddTriangle(a, m, b);
  }
  return zeroArea;
}
} // namespace

// Zero-area triangles, as T-junction repairs leave them: a vertex m inserted in edge (a, b) splits
// the triangle on one side and fills the other side's gap with the triangle (a, m, b). Such a
// triangle has no plane of its own (its stencil's stands in for its normal, kept apart from the
// per-triangle evaluations): the hierarchy must take them away, keep every level a manifold of the
// same topology and be exactly reversible.
TEST(CollapseHierarchy, ZeroAreaTrianglesOfTJunctionsCollapse)
{
  TriangleMesh input = ToTriangleMesh(LoadTestMesh("bunny00"));
  const std::vector<Index> zeroArea = AddTJunctions(input);
  ASSERT_GT(zeroArea.size(), 100u);
  const MeshStatistics in = ComputeMeshStatistics(input);
  ASSERT_EQ(in.NonManifoldEdges, 0);
  ASSERT_GE(in.DegenerateTriangles, Index(zeroArea.size()));

  CollapseHierarchy h;
  ASSERT_TRUE(h.Build(input, DefaultParameters()));
  const int levels = h.NumberOfLevels();
  EXPECT_LT(h.LevelTriangleCount(levels - 1), input.NumberOfTriangles() / 50);
  HierarchyMesh level;
  for (int i = 1; i < levels; ++i)
  {
    h.ExtractLevel(i, level);
    const MeshStatistics s = ComputeMeshStatistics(ToMesh(level));
    ASSERT_EQ(s.NonManifoldEdges, 0) << "level " << i;
    ASSERT_EQ(s.NonManifoldVertices, 0) << "level " << i;
    ASSERT_EQ(s.InconsistentlyOrientedEdges, 0) << "level " << i;
    ASSERT_EQ(s.EulerCharacteristic, in.EulerCharacteristic) << "level " << i;
  }
  // None of the zero-area triangles is left at 10% of the input.
  const Index tenth = h.CollapsesForTriangleCount(input.NumberOfTriangles() / 10);
  h.Extract(tenth, tenth, 0.0, level);
  EXPECT_EQ(ComputeMeshStatistics(ToMesh(level)).DegenerateTriangles, 0);
  ExpectExactlyReversible(h, input);
}

// The blocked stamps are 1-byte indices of a selection pass until 255 passes have run, then
// full stamps (WidenBlocked). Widening after 0, 1 or 2 passes must give the same hierarchy, and
// the wide columns must really be in use (their stamps take more bytes than the narrow ones).
TEST(CollapseHierarchy, BlockedStampsWidenedEarlyGiveTheSameHierarchy)
{
  TriangleMesh junctions = ToTriangleMesh(LoadTestMesh("bunny00"));
  ASSERT_GT(AddTJunctions(junctions).size(), 100u); // (choices blocked by the mesh check)
  const std::pair<const char*, TriangleMesh> meshes[] = { { "noisy scan 40", ToTriangleMesh(NoisyScanIsosurface(40, 5)) },
    { "bunny00 with T-junctions", junctions } };
  const auto stampBytes = [](const CollapseHierarchy& h) {
    size_t bytes = 0;
    for (const CollapseHierarchy::StorageShare& share : h.Storage())
    {
      bytes += std::string(share.Name) == "stamps, degrees, marks" ? share.Bytes : 0;
    }
    return bytes;
  };
  for (const auto& named : meshes)
  {
    const CollapseHierarchyParameters narrow = DefaultParameters();
    ASSERT_EQ(narrow.NarrowBlockedEpochs, 255);
    CollapseHierarchy reference;
    std::vector<size_t> narrowStamps; // at every progress call
    ASSERT_TRUE(reference.Build(named.second, narrow, [&](double) {
      narrowStamps.push_back(stampBytes(reference));
      return true;
    }));
    ASSERT_GT(reference.NumberOfLevels(), 10) << named.first;
    for (int epochs : { 0, 1, 2 })
    {
      const std::string what = std::string(named.first) + ", widened after " + std::to_string(epochs) + " passes";
      CollapseHierarchyParameters early = narrow;
      early.NarrowBlockedEpochs = epochs;
      CollapseHierarchy widened;
      std::vector<size_t> wideStamps;
      ASSERT_TRUE(widened.Build(named.second, early, [&](double) {
        wideStamps.push_back(stampBytes(widened));
        return true;
      })) << what;
      ExpectSameLevelsAndRecords(reference, widened, what);
      ASSERT_EQ(wideStamps.size(), narrowStamps.size()) << what;
      size_t wider = 0;
      for (size_t i = 0; i < wideStamps.size(); ++i)
      {
        EXPECT_GE(wideStamps[i], narrowStamps[i]) << what << ", progress call " << i;
        wider += wideStamps[i] > narrowStamps[i] ? 1 : 0;
      }
      EXPECT_GT(wider, 0u) << what; // (the wide columns were in use)
    }
  }
}

// The working data's upkeep runs concurrently (ParallelBookkeeping): CompactRows' ten compactions
// as tasks, and the test of each evaluation's normal against its triangle's own (kept as Own,
// Zero or Stored) in the concurrent evaluation. On bunny00 with T-junction repairs (zero-area
// triangles: stored stencil normals, and kept points released at the compactions), a noisy scan
// isosurface (borders) and a smooth isosurface, one, two and eight threads build the serial
// reference's hierarchy (ParallelBookkeeping off, one thread) bit for bit, levels and records,
// with the working data of the same sizes at every level.
TEST(CollapseHierarchy, ConcurrentBookkeepingGivesTheSerialHierarchy)
{
  TriangleMesh junctions = ToTriangleMesh(LoadTestMesh("bunny00"));
  ASSERT_GT(AddTJunctions(junctions).size(), 100u);
  const std::pair<const char*, TriangleMesh> meshes[] = { { "bunny00 with T-junctions", junctions },
    { "noisy scan 45", ToTriangleMesh(NoisyScanIsosurface(45, 3)) },
    { "isosurface 60", ToTriangleMesh(SyntheticIsosurface(60)) } };
  CollapseHierarchyParameters parallel = DefaultParameters();
  ASSERT_TRUE(parallel.ParallelBookkeeping); // (the default)
  CollapseHierarchyParameters reference = parallel;
  reference.ParallelBookkeeping = false;
  const auto build = [](const TriangleMesh& mesh, const CollapseHierarchyParameters& parameters, int threads,
                       CollapseHierarchy& h, std::vector<size_t>& sizes) {
    vtkSMPTools::LocalScope(vtkSMPTools::Config{ threads }, [&]() {
      ASSERT_TRUE(h.Build(mesh, parameters, [&](double) {
        for (const CollapseHierarchy::StorageShare& share : h.Storage())
        {
          sizes.push_back(share.Bytes);
        }
        return true;
      }));
    });
  };
  for (const auto& named : meshes)
  {
    CollapseHierarchy one;
    std::vector<size_t> oneSizes;
    build(named.second, reference, 1, one, oneSizes);
    ASSERT_GT(one.NumberOfCollapses(), named.second.NumberOfTriangles() / 4) << named.first;
    ASSERT_GT(one.NumberOfLevels(), 20) << named.first; // (compacted many times)
    for (int threads : { 1, 2, 8 })
    {
      const std::string what = std::string(named.first) + ", " + std::to_string(threads) + " threads";
      CollapseHierarchy concurrent;
      std::vector<size_t> sizes;
      build(named.second, parallel, threads, concurrent, sizes);
      ExpectSameLevelsAndRecords(one, concurrent, what);
      EXPECT_EQ(oneSizes, sizes) << what;
    }
  }
}

TEST(CollapseHierarchy, CycleRemovalBySwapping)
{
  // A valence-3 vertex in a grid: edge swapping raises it to four, keeping the surface.
  const int n = 6;
  TriangleMesh grid = Grid(n, n);
  const Index split = GridTriangle(n, 3, 3, 0);
  const Index a = grid.Triangles[3 * split], b = grid.Triangles[3 * split + 1], c = grid.Triangles[3 * split + 2];
  const Index q = grid.AddPoint((1.0 / 3.0) * (grid.Point(a) + grid.Point(b) + grid.Point(c)));
  grid.Triangles[3 * split + 2] = q;
  grid.AddTriangle(b, c, q);
  grid.AddTriangle(c, a, q);
  CollapseHierarchyParameters p;
  p.RemoveCycles = true;
  p.MaximumNumberOfLevels = 1;
  CollapseHierarchy h;
  ASSERT_TRUE(h.Build(grid, p));
  const TriangleMesh& base = h.BaseMesh();
  ASSERT_EQ(base.NumberOfTriangles(), grid.NumberOfTriangles());
  MeshTopology topology(base);
  EXPECT_EQ(topology.Valence(q), 4);
  const MeshStatistics s = ComputeMeshStatistics(base);
  EXPECT_EQ(s.NonManifoldEdges, 0);
  EXPECT_EQ(s.InconsistentlyOrientedEdges, 0);
  EXPECT_NEAR(base.TotalArea(), 1.0, 1e-12); // same flat square, no fold
}

TEST(CollapseHierarchy, SmallOpenAndNonManifoldMeshes)
{
  CollapseHierarchyParameters p = DefaultParameters();
  HierarchyMesh m;
  // A tetrahedron has no collapsible triangle (every stencil is cyclic): one level, unchanged.
  {
    CollapseHierarchy h;
    ASSERT_TRUE(h.Build(Tetrahedron(), p));
    EXPECT_EQ(h.NumberOfLevels(), 1);
    h.ExtractLevel(5.5, m);
    EXPECT_EQ(m.Triangles.size(), 12u);
  }
  // An open disk: the border collapses too (edge collapses along it), keeping its one loop.
  {
    const TriangleMesh disk = Disk(12, 32);
    const MeshStatistics in = ComputeMeshStatistics(disk);
    CollapseHierarchy h;
    ASSERT_TRUE(h.Build(disk, p));
    ASSERT_GT(h.NumberOfLevels(), 2);
    h.ExtractLevel(h.NumberOfLevels() - 1, m);
    const MeshStatistics out = ComputeMeshStatistics(ToMesh(m));
    EXPECT_LT(out.Triangles, in.Triangles / 2);
    EXPECT_EQ(out.BoundaryLoops, 1);
    EXPECT_LT(out.BoundaryEdges, in.BoundaryEdges / 2);
    EXPECT_GE(out.BoundaryEdges, 3);
    EXPECT_EQ(out.EulerCharacteristic, in.EulerCharacteristic);
    EXPECT_EQ(out.NonManifoldEdges, 0);
  }
  // Two components keep their identity; a non-manifold fan is left alone where it is not a disc.
  {
    const TriangleMesh two = Concatenate(Sphere(24, 24), Torus(32, 16));
    CollapseHierarchy h;
    ASSERT_TRUE(h.Build(two, p));
    h.ExtractLevel(h.NumberOfLevels() - 1, m);
    const MeshStatistics out = ComputeMeshStatistics(ToMesh(m));
    EXPECT_EQ(out.Components, 2);
    EXPECT_EQ(out.Genus, ComputeMeshStatistics(two).Genus);
    EXPECT_EQ(out.NonManifoldEdges, 0);
    CollapseHierarchy fan;
    ASSERT_TRUE(fan.Build(NonManifoldFan(5), p));
    fan.ExtractLevel(fan.NumberOfLevels() - 1, m);
    EXPECT_EQ(ComputeMeshStatistics(ToMesh(m)).NonManifoldEdges, ComputeMeshStatistics(NonManifoldFan(5)).NonManifoldEdges);
  }
}

// ---------------------------------------------------------------------------------------------
// The VTK filter.

// A closed cone whose apex and base centre are on 5,000 triangles each: every triangle touches one
// of them. Collapses merging such a hub are no candidates (each check would cost 5,000); the rim
// edges still collapse in full batches, so the levels keep their size (before, the hubs' stencils
// overlapped every candidate: one collapse per level, 45 s) and the surface stays on the cone.
TEST(CollapseHierarchy, HighValenceVerticesKeepTheBatchesFull)
{
  const int segments = 5000;
  const TriangleMesh input = Cone(segments, 1.0);
  const CollapseHierarchyParameters p = DefaultParameters();
  CollapseHierarchy h;
  ASSERT_TRUE(h.Build(input, p));
  // A level removes at least a quarter of its batch (4 x BatchFraction of the triangles) while
  // disjoint candidates remain, and a third of the rim edges have disjoint regions.
  const int halving = static_cast<int>(std::ceil(std::log(2.0) / -std::log(1.0 - p.BatchFraction)));
  int level = 0;
  while (level < h.NumberOfLevels() && h.LevelTriangleCount(level) > input.NumberOfTriangles() / 2)
  {
    ++level;
  }
  ASSERT_LT(level, h.NumberOfLevels());
  EXPECT_LE(level, halving + 1);
  HierarchyMesh m;
  h.ExtractLevel(level, m);
  const TriangleMesh output = ToMesh(m);
  ExpectSameTopology(input, output);
  for (Index v = 0; v < output.NumberOfPoints(); ++v)
  {
    const Vec3 x = output.Point(v);
    const double r = std::hypot(x[0], x[1]);
    const bool onBase = std::abs(x[2]) < 1e-6 && r < 1 + 1e-6;
    const bool onSide = std::abs(r - (1 - x[2])) < 1e-6 && x[2] > -1e-6 && x[2] < 1 + 1e-6;
    ASSERT_TRUE(onBase || onSide) << "vertex " << v << " off the cone";
  }
}

TEST(vtkTriangleCollapseHierarchy, LevelsTargetsCachingAndArrays)
{
  vtkSmartPointer<vtkPolyData> bunny = LoadTestMesh("bunny00");
  // A linear point field to check the interpolation.
  vtkNew<vtkDoubleArray> field;
  field->SetName("X");
  for (vtkIdType i = 0; i < bunny->GetNumberOfPoints(); ++i)
  {
    field->InsertNextValue(bunny->GetPoint(i)[0]);
  }
  bunny->GetPointData()->AddArray(field);
  const vtkIdType n0 = bunny->GetNumberOfPolys();

  vtkNew<vtkTriangleCollapseHierarchy> filter;
  filter->SetInputData(bunny);
  filter->SetTargetNumberOfTriangles(n0 / 10);
  filter->Update();
  EXPECT_EQ(filter->GetNumberOfHierarchyBuilds(), 1);
  EXPECT_NEAR(double(filter->GetOutput()->GetNumberOfPolys()), double(n0 / 10), 2.0);
  const int levels = filter->GetNumberOfLevels();
  ASSERT_GT(levels, 20);

  // All levels on port 1.
  vtkMultiBlockDataSet* all = filter->GetLevelsOutput();
  ASSERT_EQ(static_cast<int>(all->GetNumberOfBlocks()), levels);
  for (int i = 0; i < levels; ++i)
  {
    vtkPolyData* block = vtkPolyData::SafeDownCast(all->GetBlock(i));
    ASSERT_NE(block, nullptr);
    ASSERT_EQ(block->GetNumberOfPolys(), filter->GetLevelNumberOfTriangles(i));
  }
  EXPECT_EQ(filter->GetLevelNumberOfTriangles(0), n0);

  // Changing the level or the blend parameter does not rebuild.
  filter->SetLevel(5);
  filter->Update();
  vtkNew<vtkPolyData> level5;
  level5->DeepCopy(filter->GetOutput());
  EXPECT_EQ(level5->GetNumberOfPolys(), filter->GetLevelNumberOfTriangles(5));
  filter->SetContinuousLevel(5.0);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPolys(), level5->GetNumberOfPolys());
  for (vtkIdType i = 0; i < level5->GetNumberOfPoints(); ++i)
  {
    ASSERT_EQ(level5->GetPoint(i)[0], filter->GetOutput()->GetPoint(i)[0]);
  }
  for (double t : { 0.1, 0.5, 0.9, 3.7, 12.25 })
  {
    filter->SetContinuousLevel(t);
    filter->Update();
    EXPECT_DOUBLE_EQ(filter->GetShownLevel(), t);
  }
  EXPECT_EQ(filter->GetNumberOfHierarchyBuilds(), 1);

  // Blended output: cell arrays like the paper's figures, interpolated point data.
  filter->SetContinuousLevel(2.5);
  filter->Update();
  vtkPolyData* out = filter->GetOutput();
  vtkDataArray* role = out->GetCellData()->GetArray("CollapseRole");
  vtkDataArray* batch = out->GetCellData()->GetArray("CollapseBatch");
  vtkDataArray* when = out->GetCellData()->GetArray("CollapseLevel");
  ASSERT_TRUE(role && batch && when);
  // Per collapse of the batch: one collapsing triangle (triangle collapse: T and its three
  // neighbours go) or two (edge collapse: both go).
  std::map<int, int> collapsingOf;
  int stencil = 0;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    const int r = static_cast<int>(role->GetTuple1(c));
    if (r == 2)
    {
      ++collapsingOf[static_cast<int>(batch->GetTuple1(c))];
    }
    stencil += r == 1;
    ASSERT_EQ(r > 0, batch->GetTuple1(c) >= 0);
    ASSERT_TRUE(when->GetTuple1(c) >= 2 || when->GetTuple1(c) == -1);
  }
  vtkIdType removed = 0;
  for (const auto& entry : collapsingOf)
  {
    ASSERT_TRUE(entry.second == 1 || entry.second == 2);
    removed += entry.second == 1 ? 4 : 2;
  }
  EXPECT_EQ(removed, filter->GetLevelNumberOfTriangles(2) - filter->GetLevelNumberOfTriangles(3));
  EXPECT_GT(stencil, 4 * static_cast<int>(collapsingOf.size()));
  vtkDataArray* x = out->GetPointData()->GetArray("X");
  ASSERT_NE(x, nullptr);
  ASSERT_EQ(x->GetNumberOfTuples(), out->GetNumberOfPoints());
  double range[2];
  field->GetRange(range);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    // A linear field is reproduced up to the collapse points' offset from the centroid.
    ASSERT_GE(x->GetTuple1(i), range[0]);
    ASSERT_LE(x->GetTuple1(i), range[1]);
    ASSERT_NEAR(x->GetTuple1(i), out->GetPoint(i)[0], 0.02);
  }
  ASSERT_NE(out->GetFieldData()->GetArray("HierarchyLevel"), nullptr);

  // A hierarchy parameter or new input data rebuilds.
  filter->SetBatchFraction(0.05);
  filter->Update();
  EXPECT_EQ(filter->GetNumberOfHierarchyBuilds(), 2);
  EXPECT_LT(filter->GetNumberOfLevels(), levels);
  bunny->Modified();
  filter->Update();
  EXPECT_EQ(filter->GetNumberOfHierarchyBuilds(), 3);
}

namespace
{
// The cells of a filter output as (corner coordinates from the smallest corner, CollapseLevel),
// sorted: equal for the same mesh whatever the order of its points and cells.
std::vector<std::array<double, 10>> CellsWithLevels(vtkPolyData* mesh)
{
  std::vector<std::array<double, 10>> cells;
  vtkDataArray* level = mesh->GetCellData()->GetArray("CollapseLevel");
  for (vtkIdType c = 0; c < mesh->GetNumberOfPolys(); ++c)
  {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    mesh->GetCellPoints(c, n, ids);
    EXPECT_EQ(n, 3);
    std::array<std::array<double, 3>, 3> corners;
    for (int k = 0; k < 3; ++k)
    {
      mesh->GetPoint(ids[k], corners[k].data());
    }
    const int first = static_cast<int>(std::min_element(corners.begin(), corners.end()) - corners.begin());
    std::array<double, 10> cell;
    for (int k = 0; k < 3; ++k)
    {
      std::copy(corners[(first + k) % 3].begin(), corners[(first + k) % 3].end(), cell.begin() + 3 * k);
    }
    cell[9] = level ? level->GetTuple1(c) : -2;
    cells.push_back(cell);
  }
  std::sort(cells.begin(), cells.end());
  return cells;
}
} // namespace

TEST(vtkTriangleCollapseHierarchy, ExpandFromCoarsestLevelGivesEveryLevelAndTarget)
{
  // The reverse of the hierarchy through the VTK API: the coarsest mesh plus the collapse records
  // give level k and any triangle count exactly as the stored levels do, without a rebuild.
  for (const char* name : { "femur", "bull" })
  {
    vtkSmartPointer<vtkPolyData> input = LoadTestMesh(name);
    vtkNew<vtkTriangleCollapseHierarchy> stored, expanded;
    stored->SetInputData(input);
    expanded->SetInputData(input);
    expanded->ExpandFromCoarsestLevelOn();
    stored->SetLevel(0);
    stored->Update();
    const int levels = stored->GetNumberOfLevels();
    ASSERT_GT(levels, 10) << name;
    for (const int level : { 0, 1, levels / 3, levels / 2, levels - 2, levels - 1 })
    {
      stored->SetLevel(level);
      stored->Update();
      expanded->SetLevel(level);
      expanded->Update();
      ASSERT_EQ(expanded->GetOutput()->GetNumberOfPolys(), stored->GetLevelNumberOfTriangles(level)) << name;
      ASSERT_EQ(expanded->GetOutput()->GetNumberOfPoints(), stored->GetOutput()->GetNumberOfPoints()) << name;
      ASSERT_EQ(CellsWithLevels(expanded->GetOutput()), CellsWithLevels(stored->GetOutput())) << name << " level " << level;
    }
    // Triangle counts (cuts inside a batch).
    stored->SetLevel(-1);
    expanded->SetLevel(-1);
    for (const vtkIdType target : { input->GetNumberOfPolys() / 3, input->GetNumberOfPolys() / 20 + 1 })
    {
      stored->SetTargetNumberOfTriangles(target);
      stored->Update();
      expanded->SetTargetNumberOfTriangles(target);
      expanded->Update();
      ASSERT_NEAR(double(expanded->GetOutput()->GetNumberOfPolys()), double(target), 3.0) << name;
      ASSERT_EQ(CellsWithLevels(expanded->GetOutput()), CellsWithLevels(stored->GetOutput())) << name << " target " << target;
    }
    EXPECT_EQ(expanded->GetNumberOfHierarchyBuilds(), 1) << name;
  }
}

TEST(vtkTriangleCollapseHierarchy, TargetOnlyBuildsDownToTheTargetWithTheSameMesh)
{
  // Without the levels output, a level or a blend, only the target is asked for: the hierarchy
  // stops at the level reaching it, and the mesh is the whole hierarchy's cut (same levels).
  vtkSmartPointer<vtkPolyData> input = LoadTestMesh("fandisk");
  vtkNew<vtkTriangleCollapseHierarchy> whole;
  whole->SetInputData(input);
  whole->SetTargetReduction(0.8);
  whole->Update();
  vtkNew<vtkTriangleCollapseHierarchy> toTarget;
  toTarget->SetInputData(input);
  toTarget->GenerateAllLevelsOff();
  toTarget->SetTargetReduction(0.8);
  toTarget->Update();
  EXPECT_LT(toTarget->GetNumberOfLevels(), whole->GetNumberOfLevels() / 2);
  vtkPolyData* a = whole->GetOutput();
  vtkPolyData* b = toTarget->GetOutput();
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  ASSERT_EQ(a->GetNumberOfPolys(), b->GetNumberOfPolys());
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    for (int j = 0; j < 3; ++j)
    {
      ASSERT_EQ(a->GetPoint(i)[j], b->GetPoint(i)[j]);
    }
  }
  vtkIdType na = 0, nb = 0;
  const vtkIdType *pa = nullptr, *pb = nullptr;
  for (vtkIdType c = 0; c < a->GetNumberOfPolys(); ++c)
  {
    a->GetCellPoints(c, na, pa);
    b->GetCellPoints(c, nb, pb);
    ASSERT_TRUE(na == 3 && nb == 3 && std::equal(pa, pa + 3, pb));
  }
  // A higher target uses the cache; a lower one or a level rebuilds.
  EXPECT_EQ(toTarget->GetNumberOfHierarchyBuilds(), 1);
  toTarget->SetTargetReduction(0.7);
  toTarget->Update();
  EXPECT_EQ(toTarget->GetNumberOfHierarchyBuilds(), 1);
  toTarget->SetTargetReduction(0.95);
  toTarget->Update();
  EXPECT_EQ(toTarget->GetNumberOfHierarchyBuilds(), 2);
  EXPECT_NEAR(double(toTarget->GetOutput()->GetNumberOfPolys()), 0.05 * input->GetNumberOfPolys(), 2.0);
  toTarget->SetLevel(3);
  toTarget->Update();
  EXPECT_EQ(toTarget->GetNumberOfHierarchyBuilds(), 3);
  EXPECT_EQ(toTarget->GetNumberOfLevels(), whole->GetNumberOfLevels());
}

TEST(vtkTriangleCollapseHierarchy, TargetCountsAreReachedFromBelow)
{
  // A closed surface has an even number of triangles and a triangle collapse removes four: an
  // odd target, or one between two cuts, has no cut of exactly its count. The output takes the
  // first cut at or below it (as vtkQuadricDecimation reaches at least the reduction asked),
  // says it is reached, and stops within one collapse of it; with and without the levels output.
  for (const char* name : { "mushroom", "elephant", "cow" })
  {
    vtkSmartPointer<vtkPolyData> input = LoadTestMesh(name);
    const vtkIdType n0 = input->GetNumberOfPolys();
    for (const vtkIdType target : { n0 / 2 + 1, n0 / 5 - 1, n0 / 10 + 3, n0 / 20 + 1 })
    {
      for (const bool allLevels : { true, false })
      {
        vtkNew<vtkTriangleCollapseHierarchy> filter;
        filter->SetInputData(input);
        filter->SetTargetNumberOfTriangles(target);
        filter->SetGenerateAllLevels(allLevels);
        filter->Update();
        vtkPolyData* out = filter->GetOutput();
        const std::string what = std::string(name) + " target " + std::to_string(target);
        vtkDataArray* reached = out->GetFieldData()->GetArray("TargetReached");
        ASSERT_NE(reached, nullptr) << what;
        EXPECT_EQ(reached->GetTuple1(0), 1.0) << what;
        EXPECT_LE(out->GetNumberOfPolys(), target) << what;
        // One collapse removes at most the triangles around the vertices it merges.
        EXPECT_GT(out->GetNumberOfPolys(), target - 12) << what;
      }
    }
  }
}

TEST(vtkTriangleCollapseHierarchy, NoisyScanKeepsNonManifoldEdgesBordersAndHandles)
{
  // Like an MRI isosurface: handles, a border, non-manifold edges. A collapse of a non-manifold
  // edge passes the link condition yet cuts the sheets apart (fewer non-manifold edges, more
  // border loops, another Euler characteristic): such an edge must stay one edge in every level.
  for (const unsigned seed : { 1u, 2u, 3u })
  {
    SCOPED_TRACE(seed);
    vtkNew<vtkTriangleCollapseHierarchy> filter;
    filter->SetTargetReduction(0.9);
    const MeshStatistics in = slodtest::SimplifyNoisyScan(filter, 40, seed);
    vtkPolyData* output = filter->GetOutput();
    // The border is collapsed too, but never cut open: fewer border edges, at least three per
    // loop (the Euler characteristic and the non-manifold edges are checked by SimplifyNoisyScan).
    const MeshStatistics out = ComputeMeshStatistics(slodtest::RawTriangleMesh(output));
    EXPECT_LT(out.BoundaryEdges, in.BoundaryEdges);
    EXPECT_GE(out.BoundaryEdges, 3 * out.BoundaryLoops);
    EXPECT_EQ(out.NonManifoldVertices, in.NonManifoldVertices);
    EXPECT_LT(output->GetNumberOfPolys(), in.Triangles / 5); // locked vertices leave most of it collapsible
  }
}

TEST(vtkTriangleCollapseHierarchy, BordersCollapseKeepingTheirLoops)
{
  // Open meshes: edges along the borders collapse (border planes in the quadrics keep their line),
  // every border loop stays (at least three edges), with the Euler characteristic and no
  // non-manifold edge, on every level. elephant-with-holes (106 loops, Euler characteristic -110)
  // cannot reach 89 triangles: every loop at three edges on its own vertices needs at least
  // 3 b - 2 chi = 538; the filter gets there up to a few triangles and says why in its warning.
  for (const char* name : { "elephant-with-holes", "mech-holes-shark", "mask_cone" })
  {
    SCOPED_TRACE(name);
    vtkSmartPointer<vtkPolyData> input = LoadTestMesh(name);
    const MeshStatistics in = ComputeMeshStatistics(slodtest::RawTriangleMesh(input));
    ASSERT_GT(in.BoundaryLoops, 0);
    vtkNew<vtkTriangleCollapseHierarchy> filter;
    filter->SetInputData(input);
    filter->SetTargetNumberOfTriangles(89);
    vtkNew<slodtest::MessageCounter> messages;
    filter->AddObserver(vtkCommand::WarningEvent, messages);
    filter->Update();
    const MeshStatistics out = ComputeMeshStatistics(slodtest::RawTriangleMesh(filter->GetOutput()));
    EXPECT_EQ(out.BoundaryLoops, in.BoundaryLoops);
    EXPECT_EQ(out.EulerCharacteristic, in.EulerCharacteristic);
    EXPECT_EQ(out.Components, in.Components);
    EXPECT_EQ(out.NonManifoldEdges, 0);
    EXPECT_EQ(out.NonManifoldVertices, 0);
    EXPECT_GE(out.BoundaryEdges, 3 * out.BoundaryLoops);
    const long long fewest = 3 * in.BoundaryLoops - 2 * in.EulerCharacteristic;
    const long long count = filter->GetOutput()->GetNumberOfPolys();
    std::printf("[ measure  ] %s to 89: %lld triangles (bound %lld), %lld border edges in %lld loops (input %lld, %lld)\n",
      name, count, fewest, static_cast<long long>(out.BoundaryEdges), static_cast<long long>(out.BoundaryLoops),
      static_cast<long long>(in.BoundaryEdges), static_cast<long long>(in.BoundaryLoops));
    if (count > 92)
    {
      // Not reached: within 2% of the topological bound, and the warning says why.
      EXPECT_LE(count, std::max<long long>(92, fewest + fewest / 50));
      const std::string why = "needs at least about " + std::to_string(fewest) + " triangles";
      EXPECT_EQ(std::count_if(messages->Warnings.begin(), messages->Warnings.end(),
                  [&](const std::string& w) { return w.find(why) != std::string::npos; }),
        1);
    }
    // Every level keeps the loops.
    for (int level = 0; level < filter->GetNumberOfLevels(); level += 5)
    {
      vtkPolyData* block = vtkPolyData::SafeDownCast(filter->GetLevelsOutput()->GetBlock(level));
      const MeshStatistics s = ComputeMeshStatistics(slodtest::RawTriangleMesh(block));
      ASSERT_EQ(s.BoundaryLoops, in.BoundaryLoops) << level;
      ASSERT_EQ(s.EulerCharacteristic, in.EulerCharacteristic) << level;
      ASSERT_EQ(s.NonManifoldEdges, 0) << level;
    }
  }
}

namespace
{
// How far the outline was cut: the largest distance of a border vertex of `input` to the border
// edges (edges of one triangle) of `simplified`.
double OutlineCut(const TriangleMesh& input, const TriangleMesh& simplified)
{
  auto borderEdges = [](const TriangleMesh& m) {
    std::map<std::pair<Index, Index>, int> uses;
    for (Index t = 0; t < m.NumberOfTriangles(); ++t)
    {
      const Index* tri = m.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        ++uses[std::minmax(tri[k], tri[(k + 1) % 3])];
      }
    }
    std::vector<std::pair<Index, Index>> border;
    for (const auto& use : uses)
    {
      if (use.second == 1)
      {
        border.push_back(use.first);
      }
    }
    return border;
  };
  const std::vector<std::pair<Index, Index>> outline = borderEdges(simplified);
  double worst = 0;
  for (const auto& edge : borderEdges(input))
  {
    for (const Index v : { edge.first, edge.second })
    {
      const Vec3 p = input.Point(v);
      double nearest = std::numeric_limits<double>::max();
      for (const auto& o : outline)
      {
        const Vec3 a = simplified.Point(o.first), ab = simplified.Point(o.second) - a;
        const double s = std::clamp(Dot(p - a, ab) / std::max(Dot(ab, ab), 1e-300), 0.0, 1.0);
        nearest = std::min(nearest, Norm(p - (a + s * ab)));
      }
      worst = std::max(worst, nearest);
    }
  }
  return worst;
}
} // namespace

// BoundaryWeight, as on vtkQuadricTriangleCollapse: the border planes' weight in the quadrics. Its
// default is the core's constant; it is part of the hierarchy's cache key (changing it rebuilds);
// on open scans with holes the output changes with it, and with free borders (0) the 10% level
// cuts the outline and the holes' rims deeper than with the default (its border vertices hold
// their border planes).
TEST(vtkTriangleCollapseHierarchy, BoundaryWeightHoldsTheBorders)
{
  vtkNew<vtkTriangleCollapseHierarchy> filter;
  EXPECT_EQ(filter->GetBoundaryWeight(), DefaultBorderPlaneWeight);
  EXPECT_EQ(CollapseHierarchyParameters().BoundaryWeight, DefaultBorderPlaneWeight);
  int builds = filter->GetNumberOfHierarchyBuilds();
  for (const int resolution : { 70, 90 })
  {
    SCOPED_TRACE(resolution);
    vtkNew<vtkScanSurfaceSource> source;
    source->SetKindToOpenScan();
    source->SetResolution(resolution);
    source->Update();
    vtkPolyData* input = source->GetOutput();
    const TriangleMesh in = RawTriangleMesh(input);
    ASSERT_GT(ComputeMeshStatistics(in).BoundaryLoops, 1);
    filter->SetInputData(input);
    filter->SetTargetReduction(0.9);
    std::map<double, double> cut;
    std::map<double, TriangleMesh> outputs;
    for (const double weight : { 0.0, DefaultBorderPlaneWeight })
    {
      filter->SetBoundaryWeight(weight);
      filter->Update();
      EXPECT_EQ(filter->GetNumberOfHierarchyBuilds(), ++builds) << weight;
      outputs[weight] = RawTriangleMesh(filter->GetOutput());
      cut[weight] = OutlineCut(in, outputs[weight]);
      std::printf("[ measure  ] open scan %d, BoundaryWeight %g: %lld triangles, outline cut %.4g\n", resolution,
        weight, static_cast<long long>(outputs[weight].NumberOfTriangles()), cut[weight]);
    }
    EXPECT_NE(outputs[0.0].Points, outputs[DefaultBorderPlaneWeight].Points);
    EXPECT_GT(cut[0.0], cut[DefaultBorderPlaneWeight]);
  }
}

TEST(vtkTriangleCollapseHierarchy, InvalidAndEmptyInputs)
{
  vtkNew<vtkTriangleCollapseHierarchy> filter;
  vtkNew<vtkPolyData> empty;
  filter->SetInputData(empty);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);

  vtkSmartPointer<vtkPolyData> bad = ToPolyData(Sphere(8, 8));
  bad->GetPoints()->SetPoint(3, std::numeric_limits<double>::quiet_NaN(), 0, 0);
  filter->SetInputData(bad);
  filter->SetGlobalWarningDisplay(0);
  filter->Update();
  filter->SetGlobalWarningDisplay(1);
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
}

// ---------------------------------------------------------------------------------------------
// Quality at equal triangle counts, measured in the same run.

namespace
{
struct Distances
{
  double Hausdorff = 0, Mean = 0;
};

Distances Measure(vtkPolyData* reference, vtkPolyData* simplified)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(reference);
  deviation->SetComparedData(simplified);
  deviation->SetNumberOfSamples(100000);
  deviation->Update();
  return { deviation->GetHausdorffRelative(), deviation->GetMeanRelative() };
}

bool DeviationAvailable()
{
  // The distance filter works: it measures a positive distance between two different spheres (a
  // quality test must fail, not skip, when it cannot measure).
  vtkSmartPointer<vtkPolyData> a = ToPolyData(Sphere(16, 16));
  vtkSmartPointer<vtkPolyData> b = ToPolyData(Sphere(6, 6));
  return Measure(a, b).Hausdorff > 0;
}

// vtkQuadricDecimation and vtkDecimatePro (without topology preservation, as it cannot reach
// low counts otherwise) of input to the same reduction.
struct References
{
  vtkNew<vtkQuadricDecimation> Quadric;
  vtkNew<vtkDecimatePro> Pro;
  References(vtkPolyData* input, double reduction)
  {
    this->Quadric->SetInputData(input);
    this->Quadric->SetTargetReduction(reduction);
    this->Quadric->Update();
    this->Pro->SetInputData(input);
    this->Pro->SetTargetReduction(reduction);
    this->Pro->PreserveTopologyOff();
    this->Pro->SplittingOn();
    this->Pro->BoundaryVertexDeletionOn();
    this->Pro->Update();
  }
};
} // namespace

// The goal, asserted on every mesh at 10% and 2% of the triangles: the target count is reached
// (within 3 triangles), the Hausdorff distance is below vtkDecimatePro's and within 1.5x of
// vtkQuadricDecimation's, all measured in this run.
const double QualityFractions[] = { 0.10, 0.02 };
constexpr double MaximumRatioToQuadric = 1.5;

class HierarchyQuality : public ::testing::TestWithParam<const char*>
{
};

TEST_P(HierarchyQuality, VersusQuadricDecimationAndDecimatePro)
{
  ASSERT_TRUE(DeviationAvailable()) << "vtkSurfaceDeviation measured no distance between two different spheres";
  const std::string name = GetParam();
  vtkSmartPointer<vtkPolyData> input = LoadTestMesh(name);
  const vtkIdType n0 = input->GetNumberOfPolys();
  vtkNew<vtkTriangleCollapseHierarchy> hierarchy;
  hierarchy->SetInputData(input);
  hierarchy->GenerateAllLevelsOff();
  for (const double fraction : QualityFractions)
  {
    const vtkIdType target = static_cast<vtkIdType>(std::llround(fraction * n0));
    hierarchy->SetTargetNumberOfTriangles(target);
    hierarchy->Update();
    vtkPolyData* ours = hierarchy->GetOutput();

    References references(input, 1.0 - double(target) / n0);
    vtkQuadricDecimation* quadric = references.Quadric;
    vtkDecimatePro* pro = references.Pro;

    const Distances d = Measure(input, ours), q = Measure(input, quadric->GetOutput()),
                    p = Measure(input, pro->GetOutput());
    std::printf("[ measure  ] %s %.0f%%: triangles %lld / quadric %lld / pro %lld; Hausdorff %.3e / %.3e / %.3e "
                "(x%.2f / x%.2f); mean %.3e / %.3e / %.3e (x%.2f / x%.2f)\n",
      name.c_str(), 100 * fraction, static_cast<long long>(ours->GetNumberOfPolys()),
      static_cast<long long>(quadric->GetOutput()->GetNumberOfPolys()),
      static_cast<long long>(pro->GetOutput()->GetNumberOfPolys()), d.Hausdorff, q.Hausdorff, p.Hausdorff,
      d.Hausdorff / q.Hausdorff, d.Hausdorff / p.Hausdorff, d.Mean, q.Mean, p.Mean, d.Mean / q.Mean,
      d.Mean / p.Mean);
    const vtkIdType count = ours->GetNumberOfPolys();
    EXPECT_NEAR(double(count), double(target), 3.0) << name << " " << fraction;
    EXPECT_LT(d.Hausdorff, p.Hausdorff) << name << " " << fraction;
    EXPECT_LT(d.Hausdorff, MaximumRatioToQuadric * q.Hausdorff) << name << " " << fraction;
  }
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, HierarchyQuality, ::testing::Values("fandisk", "femur", "bunny00", "armadillo"));

// Issue 12's quality goal on the kind of surface users shrink (marching-cubes isosurfaces of noisy
// scans, with handles, border loops and non-manifold edges): at 10% of the triangles the Hausdorff
// distance is at most 1.2x vtkQuadricDecimation's, on each of three resolutions, measured in this
// run. (Before session 16 the defaults accepted a triangle collapse up to ten times dearer than
// its cheapest edge collapse, and the noisy surface of resolution 60 was at 1.24x.)
constexpr double IssueRatioToQuadric = 1.2;

class HierarchyIssueQuality : public ::testing::TestWithParam<int>
{
};

TEST_P(HierarchyIssueQuality, NoisyIsosurfaceAtTenPercentWithinTheIssueBound)
{
  ASSERT_TRUE(DeviationAvailable()) << "vtkSurfaceDeviation measured no distance between two different spheres";
  vtkNew<vtkScanSurfaceSource> source;
  source->SetKind(vtkScanSurfaceSource::NoisyIsosurface);
  source->SetResolution(GetParam());
  source->Update();
  vtkPolyData* input = source->GetOutput();
  vtkNew<vtkTriangleCollapseHierarchy> hierarchy;
  hierarchy->SetInputData(input);
  hierarchy->GenerateAllLevelsOff();
  hierarchy->SetTargetReduction(0.9);
  hierarchy->Update();
  vtkPolyData* ours = hierarchy->GetOutput();
  const vtkIdType n0 = input->GetNumberOfPolys();
  vtkNew<vtkQuadricDecimation> quadric;
  quadric->SetInputData(input);
  quadric->SetTargetReduction(1.0 - double(ours->GetNumberOfPolys()) / n0);
  quadric->Update();
  const Distances d = Measure(input, ours), q = Measure(input, quadric->GetOutput());
  std::printf("[ measure  ] noisy %d (%lld triangles) 10%%: triangles %lld / quadric %lld; Hausdorff %.3e / %.3e "
              "(x%.2f); mean %.3e / %.3e (x%.2f)\n",
    GetParam(), static_cast<long long>(n0), static_cast<long long>(ours->GetNumberOfPolys()),
    static_cast<long long>(quadric->GetOutput()->GetNumberOfPolys()), d.Hausdorff, q.Hausdorff,
    d.Hausdorff / q.Hausdorff, d.Mean, q.Mean, d.Mean / q.Mean);
  EXPECT_NEAR(double(ours->GetNumberOfPolys()), 0.1 * n0, 3.0);
  EXPECT_LE(d.Hausdorff, IssueRatioToQuadric * q.Hausdorff);
}

INSTANTIATE_TEST_SUITE_P(NoisyScans, HierarchyIssueQuality, ::testing::Values(50, 60, 70));

// The paper's configuration, measured: levels to below 5% (the paper: 29 of 48 on its skull) and
// the distance at about 10% against vtkQuadricDecimation and vtkDecimatePro at the same count.
TEST(CollapseHierarchy, PaperConfigurationQuality)
{
  ASSERT_TRUE(DeviationAvailable()) << "vtkSurfaceDeviation measured no distance between two different spheres";
  for (const char* name : { "bunny00", "bull" })
  {
    SCOPED_TRACE(name);
    vtkSmartPointer<vtkPolyData> input = LoadTestMesh(name);
    const TriangleMesh mesh = ToTriangleMesh(input);
    CollapseHierarchy h;
    const CollapseHierarchyParameters paper;
    ASSERT_TRUE(h.Build(mesh, paper));
    ASSERT_EQ(h.NumberOfEdgeCollapses(), 0);
    int below5 = 0;
    while (below5 < h.NumberOfLevels() && h.LevelTriangleCount(below5) >= 0.05 * mesh.NumberOfTriangles())
    {
      ++below5;
    }
    int level10 = 0;
    while (level10 + 1 < h.NumberOfLevels() && h.LevelTriangleCount(level10) > 0.10 * mesh.NumberOfTriangles())
    {
      ++level10;
    }
    HierarchyMesh level;
    h.ExtractLevel(level10, level);
    const TriangleMesh ours = ToMesh(level);
    const MeshStatistics in = ComputeMeshStatistics(mesh), out = ComputeMeshStatistics(ours);
    EXPECT_EQ(out.EulerCharacteristic, in.EulerCharacteristic);
    EXPECT_EQ(out.BoundaryLoops, in.BoundaryLoops);
    EXPECT_EQ(out.NonManifoldEdges, 0);
    EXPECT_EQ(CountFlippedTriangles(mesh, ours, level.TriangleOrigin), 0);
    const double reduction = 1.0 - double(ours.NumberOfTriangles()) / mesh.NumberOfTriangles();
    References references(input, reduction);
    const Distances d = Measure(input, ToPolyData(ours)), q = Measure(input, references.Quadric->GetOutput()),
                    p = Measure(input, references.Pro->GetOutput());
    std::printf("[ measure  ] %s, paper settings: %d of %d levels to < 5%%; level %d (%lld triangles): Hausdorff "
                "%.3e (x%.2f vtkQD, x%.2f vtkDecimatePro), mean %.3e (x%.2f, x%.2f)\n",
      name, below5, h.NumberOfLevels(), level10, static_cast<long long>(ours.NumberOfTriangles()), d.Hausdorff,
      d.Hausdorff / q.Hausdorff, d.Hausdorff / p.Hausdorff, d.Mean, d.Mean / q.Mean, d.Mean / p.Mean);
    // (The paper's level count, 29 to below 5%, is asserted on bunny00 by
    // PaperSettingsReachFivePercentInFewLevels; bull's paper hierarchy stops above 5%.)
    // The paper's order (area, curvature, angles, valence; no error term) is not error-driven:
    // within an order of magnitude of vtkQuadricDecimation's Hausdorff distance, and the
    // defaults (error-driven order, edge collapses) must be closer at the same count.
    EXPECT_LT(d.Hausdorff, 10 * q.Hausdorff);
    vtkNew<vtkTriangleCollapseHierarchy> defaults;
    defaults->SetInputData(input);
    defaults->GenerateAllLevelsOff();
    defaults->SetTargetNumberOfTriangles(ours.NumberOfTriangles());
    defaults->Update();
    const Distances e = Measure(input, defaults->GetOutput());
    std::printf("[ measure  ] %s, defaults at %lld triangles: Hausdorff %.3e, mean %.3e\n", name,
      static_cast<long long>(defaults->GetOutput()->GetNumberOfPolys()), e.Hausdorff, e.Mean);
    EXPECT_LT(e.Hausdorff, d.Hausdorff);
    EXPECT_LT(e.Mean, d.Mean);
  }
}

// ---------------------------------------------------------------------------------------------
// Valence-3 vertices (session 43, issue 15): an interior vertex of valence three makes needle and
// cap triangles and blocks its neighbours' triangle collapses. The edge collapses made them
// before PreventNewValenceThree (elephant at 10%: none in the input, 5 in the output; blade 28).

namespace
{
// The valence of every interior vertex, counted on the triangles as stored (0 for the vertices on
// an edge with other than two triangles, borders and non-manifold edges, and for unused points).
std::vector<int> InteriorValences(vtkPolyData* polyData)
{
  const TriangleMesh mesh = RawTriangleMesh(polyData);
  std::map<std::pair<Index, Index>, int> edges;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index a = tri[k], b = tri[(k + 1) % 3];
      if (a != b)
      {
        ++edges[{ std::min(a, b), std::max(a, b) }];
      }
    }
  }
  std::vector<int> valence(size_t(mesh.NumberOfPoints()), 0);
  std::vector<char> open(size_t(mesh.NumberOfPoints()), 0);
  for (const auto& [edge, count] : edges)
  {
    for (Index v : { edge.first, edge.second })
    {
      ++valence[size_t(v)];
      open[size_t(v)] = open[size_t(v)] || count != 2;
    }
  }
  for (size_t v = 0; v < valence.size(); ++v)
  {
    valence[v] = open[v] ? 0 : valence[v];
  }
  return valence;
}

// The defaults' output at `target` triangles, the valence rule on or off (no levels kept).
vtkSmartPointer<vtkPolyData> ValenceRuleOutput(vtkPolyData* input, bool prevent, vtkIdType target)
{
  vtkNew<vtkTriangleCollapseHierarchy> hierarchy;
  hierarchy->SetInputData(input);
  hierarchy->GenerateAllLevelsOff();
  hierarchy->SetPreventNewValenceThree(prevent);
  hierarchy->SetTargetNumberOfTriangles(target);
  hierarchy->Update();
  return hierarchy->GetOutput();
}

// Interior vertices of valence three or less.
int InteriorLowValenceVertices(vtkPolyData* polyData)
{
  const std::vector<int> valence = InteriorValences(polyData);
  return static_cast<int>(std::count_if(valence.begin(), valence.end(), [](int d) { return d > 0 && d <= 3; }));
}
} // namespace

// With the defaults no level down to 10% has more interior vertices of valence three than the
// input (none, on elephant: not one of the quality meshes), and the 10% level keeps the quality
// goal of HierarchyQuality against vtkQuadricDecimation and vtkDecimatePro, measured here. (The
// levels below the target may have some: the rule yields where nothing else can collapse.)
TEST(vtkTriangleCollapseHierarchy, NoLevelHasNewInteriorVerticesOfValenceThree)
{
  ASSERT_TRUE(DeviationAvailable()) << "vtkSurfaceDeviation measured no distance between two different spheres";
  vtkSmartPointer<vtkPolyData> input = LoadTestMesh("elephant");
  const int before = InteriorLowValenceVertices(input);
  const vtkIdType n0 = input->GetNumberOfPolys();
  vtkNew<vtkTriangleCollapseHierarchy> hierarchy;
  hierarchy->SetInputData(input);
  hierarchy->SetTargetReduction(0.9);
  hierarchy->PreventNewValenceThreeOn();
  hierarchy->Update();
  vtkMultiBlockDataSet* all = hierarchy->GetLevelsOutput();
  ASSERT_GT(all->GetNumberOfBlocks(), 10u);
  vtkPolyData* ours = hierarchy->GetOutput();
  int worst = 0, checked = 0;
  for (unsigned int i = 0; i < all->GetNumberOfBlocks(); ++i)
  {
    vtkPolyData* level = vtkPolyData::SafeDownCast(all->GetBlock(i));
    ASSERT_NE(level, nullptr);
    if (level->GetNumberOfPolys() < ours->GetNumberOfPolys())
    {
      continue;
    }
    ++checked;
    const int low = InteriorLowValenceVertices(level);
    worst = std::max(worst, low);
    EXPECT_LE(low, before) << "level " << i << " of " << all->GetNumberOfBlocks();
  }
  EXPECT_GT(checked, 10);
  EXPECT_LE(InteriorLowValenceVertices(ours), before);
  References references(input, 1.0 - double(ours->GetNumberOfPolys()) / double(n0));
  const Distances d = Measure(input, ours), q = Measure(input, references.Quadric->GetOutput()),
                  p = Measure(input, references.Pro->GetOutput());
  std::printf("[ measure  ] elephant 10%%: interior valence <= 3: input %d, worst level %d; Hausdorff %.3e / quadric "
              "%.3e / pro %.3e (x%.2f / x%.2f)\n",
    before, worst, d.Hausdorff, q.Hausdorff, p.Hausdorff, d.Hausdorff / q.Hausdorff, d.Hausdorff / p.Hausdorff);
  EXPECT_LT(d.Hausdorff, p.Hausdorff);
  EXPECT_LT(d.Hausdorff, MaximumRatioToQuadric * q.Hausdorff);
}

// The rule against the behaviour before it (PreventNewValenceThreeOff), measured in the same run:
// off makes new valence-3 vertices on this mesh (so the case is real), on makes none, and the
// distances stay close to those of off at the same triangle count.
TEST(vtkTriangleCollapseHierarchy, PreventNewValenceThreeCostsLittleDistance)
{
  ASSERT_TRUE(DeviationAvailable()) << "vtkSurfaceDeviation measured no distance between two different spheres";
  vtkSmartPointer<vtkPolyData> input = LoadTestMesh("elephant");
  const int before = InteriorLowValenceVertices(input);
  const vtkIdType n0 = input->GetNumberOfPolys();
  for (const double fraction : { 0.5, 0.1 })
  {
    Distances distances[2];
    int low[2] = { 0, 0 };
    vtkIdType counts[2] = { 0, 0 };
    for (int prevent = 0; prevent < 2; ++prevent)
    {
      vtkSmartPointer<vtkPolyData> output =
        ValenceRuleOutput(input, prevent == 1, static_cast<vtkIdType>(std::llround(fraction * double(n0))));
      low[prevent] = InteriorLowValenceVertices(output);
      counts[prevent] = output->GetNumberOfPolys();
      distances[prevent] = Measure(input, output);
    }
    std::printf("[ measure  ] elephant %.0f%%: interior valence <= 3 input %d, off %d, on %d; triangles %lld / %lld; "
                "Hausdorff %.3e / %.3e (x%.2f), mean %.3e / %.3e (x%.2f)\n",
      100 * fraction, before, low[0], low[1], static_cast<long long>(counts[0]), static_cast<long long>(counts[1]),
      distances[0].Hausdorff, distances[1].Hausdorff, distances[1].Hausdorff / distances[0].Hausdorff,
      distances[0].Mean, distances[1].Mean, distances[1].Mean / distances[0].Mean);
    EXPECT_GT(low[0], before) << fraction;
    EXPECT_LE(low[1], before) << fraction;
    EXPECT_NEAR(double(counts[1]), double(counts[0]), 3.0) << fraction; // (a cut: within one collapse)
    // (Hausdorff is one maximum: over 140 meshes the ratio's geometric mean was 1.03 at 10% and
    // 0.99 at 50%, single meshes up to 1.58; the mean distance moves far less.)
    EXPECT_LT(distances[1].Hausdorff, MaximumRatioToQuadric * distances[0].Hausdorff) << fraction;
    EXPECT_LT(distances[1].Mean, 1.1 * distances[0].Mean) << fraction;
  }
}

// ---------------------------------------------------------------------------------------------
// Session 44 (issue 15): under PreventNewValenceThree an interior vertex of valence four can no
// longer go down to three, and it blocks the edges opposite it; before ValenceDiscount such
// vertices piled up (a noisy sphere at 10%: more with the rule than without it; noisy137 a
// quarter of the output's vertices, against 5% without the rule) and jammed the last levels.

namespace
{
// Interior vertices (on no border or non-manifold edge) of exactly this valence.
int InteriorVerticesOfValence(vtkPolyData* polyData, int valence)
{
  const std::vector<int> valences = InteriorValences(polyData);
  return static_cast<int>(std::count(valences.begin(), valences.end(), valence));
}
} // namespace

// A sphere with radial noise (generated here) to
// 10%: without the rule the hierarchy makes new valence-3 vertices (so the case is real); with it,
// none, and no more interior vertices of valence four than without it (base-s44: more).
TEST(vtkTriangleCollapseHierarchy, ValenceRuleLeavesNoPileOfValenceFourVertices)
{
  TriangleMesh sphere = Sphere(120, 120);
  std::mt19937 random(44);
  std::uniform_real_distribution<double> noise(-0.01, 0.01); // (relative to the radius)
  for (size_t v = 0; v < sphere.Points.size(); v += 3) // (a radial offset: the point's coordinates scaled)
  {
    const double scale = 1.0 + noise(random);
    std::transform(sphere.Points.begin() + long(v), sphere.Points.begin() + long(v) + 3, sphere.Points.begin() + long(v),
      [scale](double c) { return scale * c; });
  }
  vtkSmartPointer<vtkPolyData> input = ToPolyData(sphere);
  const int before = InteriorLowValenceVertices(input);
  int low[2] = { 0, 0 }, four[2] = { 0, 0 };
  vtkIdType counts[2] = { 0, 0 };
  for (int prevent = 0; prevent < 2; ++prevent)
  {
    vtkSmartPointer<vtkPolyData> output =
      ValenceRuleOutput(input, prevent == 1, static_cast<vtkIdType>(std::llround(0.1 * double(input->GetNumberOfPolys()))));
    low[prevent] = InteriorLowValenceVertices(output);
    four[prevent] = InteriorVerticesOfValence(output, 4);
    counts[prevent] = output->GetNumberOfPolys();
  }
  std::printf("[ measure  ] noisy sphere (%lld triangles) 10%%: interior valence <= 3 input %d, off %d, on %d; "
              "valence 4 off %d, on %d (of %lld / %lld triangles)\n",
    static_cast<long long>(input->GetNumberOfPolys()), before, low[0], low[1], four[0], four[1],
    static_cast<long long>(counts[0]), static_cast<long long>(counts[1]));
  EXPECT_GT(low[0], before);
  EXPECT_LE(low[1], before);
  EXPECT_NEAR(double(counts[1]), double(counts[0]), 3.0);
  EXPECT_LE(four[1], four[0]);
}
