// SPDX-License-Identifier: BSD-3-Clause
#include "BadInputCorpus.h"

#include "TestSupport.h"

#include "vtkBitArray.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCharArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkLongArray.h"
#include "vtkLongLongArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkShortArray.h"
#include "vtkSignedCharArray.h"
#include "vtkStringArray.h"
#include "vtkStripper.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedIntArray.h"
#include "vtkUnsignedLongArray.h"
#include "vtkUnsignedLongLongArray.h"
#include "vtkUnsignedShortArray.h"
#include "vtkPolyDataWriter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>

namespace slodtest
{
namespace
{
using Cell = std::vector<vtkIdType>;
using slod::Index;
using slod::TriangleMesh;

// ---------------------------------------------------------------------------------------------
// Building blocks

vtkSmartPointer<vtkPolyData> Surface(const TriangleMesh& mesh)
{
  return ToPolyData(mesh);
}

vtkSmartPointer<vtkPolyData> FromPoints(const std::vector<std::array<double, 3>>& points)
{
  auto out = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  for (const auto& p : points)
  {
    pts->InsertNextPoint(p.data());
  }
  out->SetPoints(pts);
  return out;
}

vtkSmartPointer<vtkCellArray> Cells(const std::vector<Cell>& cells)
{
  auto array = vtkSmartPointer<vtkCellArray>::New();
  for (const Cell& c : cells)
  {
    array->InsertNextCell(static_cast<vtkIdType>(c.size()), c.data());
  }
  return array;
}

// A small sphere, the base shape of most categories (closed, genus 0).
TriangleMesh BaseSphere()
{
  return Sphere(16, 12);
}

TriangleMesh Scaled(TriangleMesh mesh, double factor, double offsetX = 0.0)
{
  for (size_t i = 0; i < mesh.Points.size(); ++i)
  {
    mesh.Points[i] = mesh.Points[i] * factor + (i % 3 == 0 ? offsetX : 0.0);
  }
  return mesh;
}

// Tetrahedron with corner 0 at `apex`, scaled by `size`, its other corners on the side of `direction`.
TriangleMesh TetrahedronAt(const std::array<double, 3>& apex, double direction)
{
  TriangleMesh t = Tetrahedron();
  for (size_t i = 0; i < t.Points.size(); ++i)
  {
    t.Points[i] = apex[i % 3] + direction * t.Points[i];
  }
  if (direction < 0) // mirrored: keep the outward orientation
  {
    for (size_t k = 0; k < t.Triangles.size(); k += 3)
    {
      std::swap(t.Triangles[k + 1], t.Triangles[k + 2]);
    }
  }
  return t;
}

// The faces of the voxels inside `inside` on an n^3 lattice that touch an empty voxel, as quads
// over shared lattice points (outward orientation); unused lattice points are left out.
vtkSmartPointer<vtkPolyData> VoxelSurface(int n, const std::function<bool(int, int, int)>& inside)
{
  auto filled = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < n && j < n && k < n && inside(i, j, k);
  };
  std::map<std::array<int, 3>, vtkIdType> ids;
  std::vector<std::array<double, 3>> points;
  auto point = [&](int i, int j, int k) {
    auto it = ids.emplace(std::array<int, 3>{ i, j, k }, static_cast<vtkIdType>(points.size()));
    if (it.second)
    {
      points.push_back({ double(i), double(j), double(k) });
    }
    return it.first->second;
  };
  std::vector<Cell> quads;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
      {
        if (!filled(i, j, k))
          continue;
        for (int axis = 0; axis < 3; ++axis)
          for (int side = 0; side < 2; ++side)
          {
            std::array<int, 3> d = { 0, 0, 0 };
            d[axis] = side ? 1 : -1;
            if (filled(i + d[0], j + d[1], k + d[2]))
              continue;
            // The face's corners: the two other axes span it; order gives the outward normal.
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            std::array<int, 3> base = { i, j, k };
            base[axis] += side;
            Cell quad;
            const int order[4][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } };
            for (int c = 0; c < 4; ++c)
            {
              const int oc = side ? c : 3 - c;
              std::array<int, 3> q = base;
              q[u] += order[oc][0];
              q[v] += order[oc][1];
              quad.push_back(point(q[0], q[1], q[2]));
            }
            quads.push_back(quad);
          }
      }
  vtkSmartPointer<vtkPolyData> out = FromPoints(points);
  out->SetPolys(Cells(quads));
  return out;
}

vtkSmartPointer<vtkPolyData> AsTriangles(vtkPolyData* quadSurface)
{
  std::vector<Cell> triangles;
  vtkIdType n;
  const vtkIdType* ids;
  vtkCellArray* polys = quadSurface->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
  {
    for (vtkIdType k = 1; k + 1 < n; ++k)
    {
      triangles.push_back({ ids[0], ids[k], ids[k + 1] });
    }
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(quadSurface->GetPoints());
  out->SetPolys(Cells(triangles));
  return out;
}

std::vector<std::array<double, 3>> Circle(int n, double radius, double z = 0.0)
{
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < n; ++i)
  {
    const double a = 2 * M_PI * i / n;
    points.push_back({ radius * std::cos(a), radius * std::sin(a), z });
  }
  return points;
}

// ---------------------------------------------------------------------------------------------
// Categories: no surface, cell kinds

BadInput Empty()
{
  return { "", vtkSmartPointer<vtkPolyData>::New() };
}

BadInput PointsOnly()
{
  return { "", FromPoints(Circle(100, 1.0)) };
}

BadInput VerticesOnly()
{
  BadInput c = PointsOnly();
  std::vector<Cell> verts;
  for (vtkIdType i = 0; i < 100; ++i)
  {
    verts.push_back({ i });
  }
  c.Surface->SetVerts(Cells(verts));
  return c;
}

BadInput LinesOnly()
{
  BadInput c = PointsOnly();
  Cell polyline;
  for (vtkIdType i = 0; i <= 100; ++i)
  {
    polyline.push_back(i % 100);
  }
  c.Surface->SetLines(Cells({ polyline, { 0, 50 }, { 10, 60 } }));
  return c;
}

BadInput SingleTriangle()
{
  BadInput c{ "", FromPoints({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } }) };
  c.Surface->SetPolys(Cells({ { 0, 1, 2 } }));
  return c;
}

BadInput TwoSidedPillow() // the same three vertices in both orientations: a closed 2-triangle surface
{
  BadInput c = SingleTriangle();
  c.Surface->SetPolys(Cells({ { 0, 1, 2 }, { 0, 2, 1 } }));
  return c;
}

BadInput QuadCube()
{
  return { "", VoxelSurface(4, [](int, int, int) { return true; }) };
}

BadInput NgonPrism() // two 24-gon caps and 24 quads: closed, no triangle at all
{
  std::vector<std::array<double, 3>> points = Circle(24, 1.0, 0.0);
  const std::vector<std::array<double, 3>> top = Circle(24, 1.0, 1.0);
  points.insert(points.end(), top.begin(), top.end());
  Cell bottomCap, topCap;
  std::vector<Cell> cells;
  for (vtkIdType i = 0; i < 24; ++i)
  {
    bottomCap.insert(bottomCap.begin(), i);
    topCap.push_back(24 + i);
    cells.push_back({ i, (i + 1) % 24, 24 + (i + 1) % 24, 24 + i });
  }
  cells.push_back(bottomCap);
  cells.push_back(topCap);
  BadInput c{ "", FromPoints(points) };
  c.Surface->SetPolys(Cells(cells));
  return c;
}

BadInput TriangleStrips()
{
  vtkNew<vtkStripper> stripper;
  stripper->SetInputData(Surface(BaseSphere()));
  stripper->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(stripper->GetOutput());
  return { "", out };
}

BadInput StripWithRepeatedIds()
{
  BadInput c = TriangleStrips();
  c.Surface->GetStrips()->InsertNextCell({ 0, 1, 1, 2, 2, 3, 0 });
  return c;
}

BadInput MixedCells() // vertices, lines, triangles, quads and strips together
{
  BadInput c = QuadCube();
  vtkPolyData* s = c.Surface;
  s->SetVerts(Cells({ { 0 }, { 1 } }));
  s->SetLines(Cells({ { 0, 1, 2 } }));
  vtkIdType n;
  const vtkIdType* ids;
  std::vector<Cell> polys, strips;
  int k = 0;
  vtkCellArray* quads = s->GetPolys();
  for (quads->InitTraversal(); quads->GetNextCell(n, ids); ++k)
  {
    if (k % 3 == 0)
      polys.push_back({ ids[0], ids[1], ids[2], ids[3] });
    else if (k % 3 == 1)
      polys.insert(polys.end(), { { ids[0], ids[1], ids[2] }, { ids[0], ids[2], ids[3] } });
    else
      strips.push_back({ ids[1], ids[2], ids[0], ids[3] });
  }
  s->SetPolys(Cells(polys));
  s->SetStrips(Cells(strips));
  return c;
}

BadInput ShortCells() // polygons of 0, 1 and 2 points among the triangles
{
  BadInput c{ "", Surface(BaseSphere()) };
  vtkCellArray* polys = c.Surface->GetPolys();
  polys->InsertNextCell(0, static_cast<const vtkIdType*>(nullptr));
  polys->InsertNextCell({ 3 });
  polys->InsertNextCell({ 4, 5 });
  return c;
}

BadInput PolygonWithRepeatedIds()
{
  BadInput c{ "", FromPoints(Circle(8, 1.0)) };
  c.Surface->SetPolys(Cells({ { 0, 1, 1, 2, 3, 3, 4, 5, 6, 7, 0 } }));
  return c;
}

// ---------------------------------------------------------------------------------------------
// Categories: topology

BadInput NonManifoldEdgeOnSphere() // a fin: a third triangle on an edge of a closed sphere
{
  TriangleMesh m = BaseSphere();
  const Index a = m.Triangles[0], b = m.Triangles[1];
  const Index fin = m.AddPoint({ 2.0, 0.1, 0.2 });
  m.AddTriangle(a, b, fin);
  return { "", Surface(m) };
}

BadInput NonManifoldFanOfEight()
{
  return { "", Surface(NonManifoldFan(8)) };
}

BadInput BowTieVertex() // two closed tetrahedra sharing one vertex
{
  TriangleMesh a = TetrahedronAt({ 0, 0, 0 }, 1.0);
  TriangleMesh b = TetrahedronAt({ 0, 0, 0 }, -1.0);
  TriangleMesh m = Concatenate(a, b);
  for (size_t k = a.Triangles.size(); k < m.Triangles.size(); ++k)
  {
    m.Triangles[k] = m.Triangles[k] == a.NumberOfPoints() ? 0 : m.Triangles[k];
  }
  return { "", Surface(m) };
}

BadInput CoincidentSeparateVertices() // two tetrahedra touching at a point, each with its own vertex there
{
  return { "", Surface(Concatenate(TetrahedronAt({ 0, 0, 0 }, 1.0), TetrahedronAt({ 0, 0, 0 }, -1.0))) };
}

BadInput TriangleSoup() // every triangle of a closed sphere with its own three points
{
  const TriangleMesh sphere = BaseSphere();
  TriangleMesh soup;
  for (Index corner : sphere.Triangles)
  {
    soup.AddPoint(sphere.Point(corner));
  }
  for (Index t = 0; t < sphere.NumberOfTriangles(); ++t)
  {
    soup.AddTriangle(3 * t, 3 * t + 1, 3 * t + 2);
  }
  return { "", Surface(soup) };
}

BadInput DegenerateTriangles()
{
  TriangleMesh m = BaseSphere();
  const Index a = m.Triangles[0], b = m.Triangles[1];
  const slod::Vec3 pa = m.Point(a), pb = m.Point(b);
  const Index middle = m.AddPoint({ 0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2]) });
  m.AddTriangle(a, a, b);
  m.AddTriangle(b, b, b);
  m.AddTriangle(a, b, middle);
  return { "", Surface(m) };
}

BadInput DuplicateTriangles() // every third triangle twice, every seventh also reversed
{
  TriangleMesh m = BaseSphere();
  const Index n = m.NumberOfTriangles();
  for (Index t = 0; t < n; t += 3)
  {
    const Index* tri = m.Triangle(t);
    const Index a = tri[0], b = tri[1], d = tri[2];
    m.AddTriangle(a, b, d);
    if (t % 7 == 0)
    {
      m.AddTriangle(a, d, b);
    }
  }
  return { "", Surface(m) };
}

BadInput InconsistentOrientation()
{
  TriangleMesh m = BaseSphere();
  for (size_t k = 0; k < m.Triangles.size(); k += 6)
  {
    std::swap(m.Triangles[k + 1], m.Triangles[k + 2]);
  }
  return { "", Surface(m) };
}

BadInput MoebiusStrip()
{
  const int segments = 48, across = 4;
  TriangleMesh m;
  for (int i = 0; i < segments; ++i)
  {
    const double u = 2 * M_PI * i / segments;
    for (int j = 0; j <= across; ++j)
    {
      const double w = -0.3 + 0.6 * j / across;
      m.AddPoint({ (1 + w * std::cos(u / 2)) * std::cos(u), (1 + w * std::cos(u / 2)) * std::sin(u), w * std::sin(u / 2) });
    }
  }
  auto id = [&](int i, int j) {
    // Going once around turns the strip over: column j meets column `across - j`.
    return i < segments ? Index(i * (across + 1) + j) : Index(across - j);
  };
  for (int i = 0; i < segments; ++i)
  {
    for (int j = 0; j < across; ++j)
    {
      m.AddTriangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.AddTriangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return { "", Surface(m) };
}

BadInput SelfIntersectingTorus() // a spindle torus: the tube passes through the axis
{
  return { "", Surface(Torus(32, 16, 0.3, 0.6)) };
}

BadInput OverlappingSpheres() // two closed spheres that intersect each other
{
  return { "", Surface(Concatenate(BaseSphere(), Scaled(BaseSphere(), 1.0, 0.5))) };
}

BadInput ManyHoles() // a 40 x 40 grid with 100 square holes
{
  const TriangleMesh grid = Grid(40, 40);
  TriangleMesh m;
  m.Points = grid.Points;
  for (Index t = 0; t < grid.NumberOfTriangles(); ++t)
  {
    const int cell = t / 2, i = cell % 40, j = cell / 40;
    if (i % 4 == 1 && j % 4 == 1)
    {
      continue;
    }
    const Index* tri = grid.Triangle(t);
    m.AddTriangle(tri[0], tri[1], tri[2]);
  }
  return { "", Surface(m) };
}

BadInput ManyTinyComponents() // 10,000 separate triangles
{
  TriangleMesh m;
  for (int k = 0; k < 10000; ++k)
  {
    const double x = k % 100, y = k / 100;
    const Index a = m.AddPoint({ x, y, 0 });
    m.AddPoint({ x + 0.01, y, 0 });
    m.AddPoint({ x, y + 0.01, 0.001 * (k % 7) });
    m.AddTriangle(a, a + 1, a + 2);
  }
  return { "", Surface(m) };
}

BadInput HighValenceFanDisk() // one vertex of valence 5,000 in a flat open disk
{
  return { "", Surface(Disk(1, 5000)) };
}

BadInput HighValenceClosedCone() // apex and base centre of valence 5,000: closed
{
  TriangleMesh m;
  const Index apex = m.AddPoint({ 0, 0, 1 }), centre = m.AddPoint({ 0, 0, 0 });
  for (const auto& p : Circle(5000, 1.0))
  {
    m.AddPoint({ p[0], p[1], p[2] });
  }
  for (Index i = 0; i < 5000; ++i)
  {
    const Index a = 2 + i, b = 2 + (i + 1) % 5000;
    m.AddTriangle(apex, a, b);
    m.AddTriangle(centre, b, a);
  }
  return { "", Surface(m) };
}

// One polygon through all `points` in order.
BadInput OnePolygon(const std::vector<std::array<double, 3>>& points)
{
  BadInput c{ "", FromPoints(points) };
  Cell polygon(points.size());
  std::iota(polygon.begin(), polygon.end(), 0);
  c.Surface->SetPolys(Cells({ polygon }));
  return c;
}

BadInput FlatNgon() // one 1000-gon
{
  return OnePolygon(Circle(1000, 1.0));
}

BadInput ConcaveStarNgon() // one flat 200-gon with 100 spikes
{
  std::vector<std::array<double, 3>> points = Circle(200, 1.0);
  for (size_t i = 1; i < points.size(); i += 2)
  {
    points[i][0] *= 0.3;
    points[i][1] *= 0.3;
  }
  return OnePolygon(points);
}

BadInput NonPlanarNgon() // one 300-gon zig-zagging up and down
{
  std::vector<std::array<double, 3>> points = Circle(300, 1.0);
  for (size_t i = 0; i < points.size(); ++i)
  {
    points[i][2] = (i % 2) ? 0.5 : -0.5;
  }
  return OnePolygon(points);
}

BadInput FlatFanDisk()
{
  return { "", Surface(Disk(1, 64)) };
}

BadInput PlanarGrid()
{
  return { "", Surface(Grid(30, 30)) };
}

BadInput Staircase() // the voxel surface of a ball (triangulated)
{
  const double c = 6.5;
  vtkSmartPointer<vtkPolyData> voxels = VoxelSurface(14, [c](int i, int j, int k) {
    return (i + 0.5 - c) * (i + 0.5 - c) + (j + 0.5 - c) * (j + 0.5 - c) + (k + 0.5 - c) * (k + 0.5 - c) < 36.0;
  });
  return { "", AsTriangles(voxels) };
}

// ---------------------------------------------------------------------------------------------
// Categories: coordinates

BadInput NaNCoordinates()
{
  BadInput c{ "", Surface(BaseSphere()) };
  c.Surface->GetPoints()->SetPoint(5, std::nan(""), 0.0, 0.0);
  c.Unusable = true;
  return c;
}

BadInput InfCoordinates()
{
  BadInput c{ "", Surface(BaseSphere()) };
  const double inf = std::numeric_limits<double>::infinity();
  c.Surface->GetPoints()->SetPoint(5, inf, 0.0, 0.0);
  c.Surface->GetPoints()->SetPoint(9, 0.0, -inf, 0.0);
  c.Unusable = true;
  return c;
}

BadInput UnusedNaNPoint()
{
  BadInput c{ "", Surface(BaseSphere()) };
  c.Surface->GetPoints()->InsertNextPoint(std::nan(""), std::nan(""), std::nan(""));
  return c;
}

BadInput HugeCoordinates()
{
  return { "", Surface(Scaled(BaseSphere(), 1e30)) };
}

// Double coordinates beyond the float range: a filter that narrows them to float (to save memory,
// as the triangle collapse's kept input may) must test the range first (undefined otherwise).
BadInput BeyondFloatCoordinates()
{
  return { "", Surface(Scaled(BaseSphere(), 1e39)) };
}

BadInput TinyCoordinates()
{
  return { "", Surface(Scaled(BaseSphere(), 1e-30)) };
}

BadInput HugeSpread() // a unit sphere at the origin and one 1e15 away
{
  return { "", Surface(Concatenate(BaseSphere(), Scaled(BaseSphere(), 1.0, 1e15))) };
}

BadInput LargeOffset() // a unit sphere 1e8 from the origin (float cannot tell its points apart)
{
  return { "", Surface(Scaled(BaseSphere(), 1.0, 1e8)) };
}

BadInput CollinearEverywhere() // every triangle of zero area
{
  std::vector<std::array<double, 3>> points;
  std::vector<Cell> triangles;
  for (vtkIdType i = 0; i < 50; ++i)
  {
    points.push_back({ double(i), 2.0 * i, -1.0 * i });
    if (i >= 2)
    {
      triangles.push_back({ i - 2, i - 1, i });
    }
  }
  BadInput c{ "", FromPoints(points) };
  c.Surface->SetPolys(Cells(triangles));
  return c;
}

BadInput AllPointsIdentical()
{
  BadInput c = CollinearEverywhere();
  for (vtkIdType i = 0; i < c.Surface->GetNumberOfPoints(); ++i)
  {
    c.Surface->GetPoints()->SetPoint(i, 1.0, 2.0, 3.0);
  }
  return c;
}

BadInput IsolatedVertices() // a sphere and 1,000 points no cell uses
{
  BadInput c{ "", Surface(BaseSphere()) };
  for (int i = 0; i < 1000; ++i)
  {
    c.Surface->GetPoints()->InsertNextPoint(std::sin(i) * 3, std::cos(3 * i) * 3, i * 0.001);
  }
  return c;
}

BadInput IntegerPoints() // vtkPoints of type int
{
  const TriangleMesh m = Scaled(BaseSphere(), 100.0);
  BadInput c{ "", vtkSmartPointer<vtkPolyData>::New() };
  vtkNew<vtkPoints> points;
  points->SetDataType(VTK_INT);
  for (Index v = 0; v < m.NumberOfPoints(); ++v)
  {
    const slod::Vec3 p = m.Point(v);
    points->InsertNextPoint(std::round(p[0]), std::round(p[1]), std::round(p[2]));
  }
  c.Surface->SetPoints(points);
  c.Surface->SetPolys(Surface(m)->GetPolys());
  return c;
}

// ---------------------------------------------------------------------------------------------
// Categories: point and cell data, cell ids

template <typename ArrayType>
void AddArray(vtkFieldData* data, vtkIdType tuples, int components, const char* name)
{
  vtkNew<ArrayType> array;
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  if (name)
  {
    array->SetName(name);
  }
  for (vtkIdType i = 0; i < tuples; ++i)
  {
    for (int c = 0; c < components; ++c)
    {
      array->SetComponent(i, c, (i * 7 + c * 3) % 100);
    }
  }
  data->AddArray(array);
}

BadInput PointDataOfEveryType()
{
  BadInput c{ "", Surface(BaseSphere()) };
  vtkPointData* pd = c.Surface->GetPointData();
  const vtkIdType n = c.Surface->GetNumberOfPoints();
  AddArray<vtkCharArray>(pd, n, 1, "char");
  AddArray<vtkSignedCharArray>(pd, n, 2, "signed char");
  AddArray<vtkUnsignedCharArray>(pd, n, 3, "unsigned char");
  AddArray<vtkShortArray>(pd, n, 4, "short");
  AddArray<vtkUnsignedShortArray>(pd, n, 5, "unsigned short");
  AddArray<vtkIntArray>(pd, n, 6, "int");
  AddArray<vtkUnsignedIntArray>(pd, n, 7, "unsigned int");
  AddArray<vtkLongArray>(pd, n, 8, "long");
  AddArray<vtkUnsignedLongArray>(pd, n, 9, "unsigned long");
  AddArray<vtkLongLongArray>(pd, n, 1, "long long");
  AddArray<vtkUnsignedLongLongArray>(pd, n, 2, "unsigned long long");
  AddArray<vtkIdTypeArray>(pd, n, 1, "vtkIdType");
  AddArray<vtkDoubleArray>(pd, n, 9, "double 9");
  AddArray<vtkBitArray>(pd, n, 1, "bit");
  vtkNew<vtkFloatArray> normals, tcoords;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  tcoords->SetName("TCoords");
  tcoords->SetNumberOfComponents(2);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    c.Surface->GetPoint(i, p);
    normals->InsertNextTuple(p);
    tcoords->InsertNextTuple2(p[0], p[1]);
  }
  pd->SetNormals(normals);
  pd->SetTCoords(tcoords);
  vtkNew<vtkStringArray> labels;
  labels->SetName("labels");
  labels->SetNumberOfValues(n);
  pd->AddArray(labels);
  return c;
}

BadInput UnnamedPointData()
{
  BadInput c{ "", Surface(BaseSphere()) };
  vtkPointData* pd = c.Surface->GetPointData();
  const vtkIdType n = c.Surface->GetNumberOfPoints();
  AddArray<vtkFloatArray>(pd, n, 3, nullptr);
  AddArray<vtkIntArray>(pd, n, 1, nullptr);
  AddArray<vtkDoubleArray>(pd, n, 2, "named");
  vtkNew<vtkFloatArray> normals;
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(n);
  normals->Fill(0.5);
  pd->SetNormals(normals);
  return c;
}

BadInput ShortPointDataArray() // arrays of fewer tuples than points
{
  BadInput c{ "", Surface(BaseSphere()) };
  AddArray<vtkFloatArray>(c.Surface->GetPointData(), 3, 2, "short");
  AddArray<vtkIntArray>(c.Surface->GetPointData(), 0, 1, "empty");
  AddArray<vtkDoubleArray>(c.Surface->GetPointData(), c.Surface->GetNumberOfPoints(), 1, "complete");
  return c;
}

BadInput DuplicateArrayNames()
{
  BadInput c{ "", Surface(BaseSphere()) };
  // vtkFieldData::AddArray replaces an array of the same name: append the second one by hand.
  AddArray<vtkIntArray>(c.Surface->GetPointData(), c.Surface->GetNumberOfPoints(), 1, "same");
  AddArray<vtkFloatArray>(c.Surface->GetPointData(), c.Surface->GetNumberOfPoints(), 3, "other");
  c.Surface->GetPointData()->GetAbstractArray("other")->SetName("same");
  return c;
}

BadInput CellData()
{
  BadInput c{ "", Surface(BaseSphere()) };
  vtkCellData* cd = c.Surface->GetCellData();
  const vtkIdType n = c.Surface->GetNumberOfCells();
  AddArray<vtkIntArray>(cd, n, 1, "material");
  AddArray<vtkDoubleArray>(cd, n, 3, "cell vector");
  AddArray<vtkFloatArray>(cd, n, 3, nullptr);
  AddArray<vtkFloatArray>(cd, 2, 4, "short cell array");
  return c;
}

BadInput CellIdsOutOfRange()
{
  BadInput c{ "", Surface(BaseSphere()) };
  const vtkIdType n = c.Surface->GetNumberOfPoints();
  c.Surface->GetPolys()->InsertNextCell({ 0, 1, n + 5 });
  c.Surface->GetPolys()->InsertNextCell({ 2, vtkIdType(1) << 40, 3 });
  c.InvalidCellIds = true;
  return c;
}

BadInput NegativeCellIds()
{
  BadInput c{ "", Surface(BaseSphere()) };
  c.Surface->GetPolys()->InsertNextCell({ 0, -1, 2 });
  c.Surface->GetPolys()->InsertNextCell({ -7, 3, 4, 5 });
  c.InvalidCellIds = true;
  return c;
}

BadInput Tetra()
{
  return { "", Surface(Tetrahedron()) };
}

struct Category
{
  const char* Name;
  BadInput (*Make)();
};

const std::vector<Category>& Categories()
{
  static const std::vector<Category> categories = { { "empty", Empty }, { "points-only", PointsOnly },
    { "vertices-only", VerticesOnly }, { "lines-only", LinesOnly }, { "single-triangle", SingleTriangle },
    { "tetrahedron", Tetra }, { "two-sided-pillow", TwoSidedPillow }, { "quad-cube", QuadCube },
    { "ngon-prism", NgonPrism }, { "triangle-strips", TriangleStrips },
    { "strip-repeated-ids", StripWithRepeatedIds }, { "mixed-cells", MixedCells }, { "short-cells", ShortCells },
    { "polygon-repeated-ids", PolygonWithRepeatedIds }, { "non-manifold-fin", NonManifoldEdgeOnSphere },
    { "non-manifold-fan-8", NonManifoldFanOfEight }, { "bow-tie-vertex", BowTieVertex },
    { "coincident-separate-vertices", CoincidentSeparateVertices }, { "triangle-soup", TriangleSoup },
    { "degenerate-triangles", DegenerateTriangles }, { "duplicate-triangles", DuplicateTriangles },
    { "inconsistent-orientation", InconsistentOrientation }, { "moebius-strip", MoebiusStrip },
    { "self-intersecting-torus", SelfIntersectingTorus }, { "overlapping-spheres", OverlappingSpheres },
    { "many-holes", ManyHoles }, { "10000-components", ManyTinyComponents },
    { "valence-5000-fan-disk", HighValenceFanDisk }, { "valence-5000-closed-cone", HighValenceClosedCone },
    { "flat-ngon-1000", FlatNgon }, { "concave-star-ngon", ConcaveStarNgon }, { "non-planar-ngon", NonPlanarNgon },
    { "flat-fan-disk", FlatFanDisk }, { "planar-grid", PlanarGrid }, { "staircase", Staircase },
    { "nan-coordinates", NaNCoordinates }, { "inf-coordinates", InfCoordinates },
    { "unused-nan-point", UnusedNaNPoint }, { "coordinates-1e30", HugeCoordinates },
    { "coordinates-1e39", BeyondFloatCoordinates },
    { "coordinates-1e-30", TinyCoordinates }, { "huge-spread", HugeSpread }, { "large-offset", LargeOffset },
    { "collinear-everywhere", CollinearEverywhere }, { "all-points-identical", AllPointsIdentical },
    { "isolated-vertices", IsolatedVertices }, { "integer-points", IntegerPoints },
    { "point-data-every-type", PointDataOfEveryType }, { "point-data-unnamed", UnnamedPointData },
    { "point-data-short-arrays", ShortPointDataArray }, { "point-data-duplicate-names", DuplicateArrayNames },
    { "cell-data", CellData }, { "cell-ids-out-of-range", CellIdsOutOfRange },
    { "cell-ids-negative", NegativeCellIds } };
  return categories;
}
} // namespace

std::vector<std::string> BadInputNames()
{
  std::vector<std::string> names;
  for (const Category& c : Categories())
  {
    names.push_back(c.Name);
  }
  return names;
}

BadInput MakeBadInput(const std::string& name)
{
  for (const Category& c : Categories())
  {
    if (name == c.Name)
    {
      BadInput input = c.Make();
      input.Name = name;
      return input;
    }
  }
  throw std::invalid_argument("unknown bad-input category: " + name);
}

// ---------------------------------------------------------------------------------------------
// Census and output checks

namespace
{
// Triangles of the polygons and strips of `surface` (fan / strip order), cells with an invalid id skipped.
std::vector<std::array<vtkIdType, 3>> SurfaceTriangles(vtkPolyData* surface)
{
  std::vector<std::array<vtkIdType, 3>> triangles;
  const vtkIdType points = surface->GetNumberOfPoints();
  auto valid = [points](vtkIdType n, const vtkIdType* ids) {
    for (vtkIdType k = 0; k < n; ++k)
    {
      if (ids[k] < 0 || ids[k] >= points)
        return false;
    }
    return true;
  };
  vtkIdType n;
  const vtkIdType* ids;
  vtkCellArray* polys = surface->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
  {
    for (vtkIdType k = 1; k + 1 < n && valid(n, ids); ++k)
    {
      triangles.push_back({ ids[0], ids[k], ids[k + 1] });
    }
  }
  vtkCellArray* strips = surface->GetStrips();
  for (strips->InitTraversal(); strips->GetNextCell(n, ids);)
  {
    for (vtkIdType k = 0; k + 2 < n && valid(n, ids); ++k)
    {
      triangles.push_back(k % 2 ? std::array<vtkIdType, 3>{ ids[k + 1], ids[k], ids[k + 2] }
                                : std::array<vtkIdType, 3>{ ids[k], ids[k + 1], ids[k + 2] });
    }
  }
  return triangles;
}
} // namespace

SurfaceCensus CountSurface(vtkPolyData* surface)
{
  // Points merged by exact coordinates (non-finite points stay apart: they have no order).
  std::map<std::array<double, 3>, vtkIdType> byPosition;
  auto merged = [&](vtkIdType id) {
    std::array<double, 3> p;
    surface->GetPoint(id, p.data());
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      return -1 - id;
    return byPosition.emplace(p, id).first->second;
  };
  auto zeroArea = [&](const std::array<vtkIdType, 3>& t) {
    double a[3], b[3], c[3];
    surface->GetPoint(t[0], a);
    surface->GetPoint(t[1], b);
    surface->GetPoint(t[2], c);
    const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    return u[1] * v[2] - u[2] * v[1] == 0 && u[2] * v[0] - u[0] * v[2] == 0 && u[0] * v[1] - u[1] * v[0] == 0;
  };
  std::set<std::array<vtkIdType, 3>> seen, seenCycles;
  std::map<std::pair<vtkIdType, vtkIdType>, int> edgeUses;
  SurfaceCensus census;
  for (const auto& raw : SurfaceTriangles(surface))
  {
    // The bound on the output: distinct point ids, exact repeats (same cycle) counted once.
    std::array<vtkIdType, 3> cycle = raw;
    std::rotate(cycle.begin(), std::min_element(cycle.begin(), cycle.end()), cycle.end());
    if (cycle[0] != cycle[1] && cycle[1] != cycle[2] && cycle[0] != cycle[2] && seenCycles.insert(cycle).second)
      ++census.DistinctTriangles;
    const std::array<vtkIdType, 3> t = { merged(raw[0]), merged(raw[1]), merged(raw[2]) };
    std::array<vtkIdType, 3> key = t;
    std::sort(key.begin(), key.end());
    if (key[0] == key[1] || key[1] == key[2] || !seen.insert(key).second)
      continue;
    ++census.Triangles;
    census.TrianglesWithArea += zeroArea(raw) ? 0 : 1;
    for (int k = 0; k < 3; ++k)
    {
      ++edgeUses[{ std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]) }];
    }
  }
  for (const auto& edge : edgeUses)
  {
    census.BorderEdges += edge.second == 1 ? 1 : 0;
    census.NonManifoldEdges += edge.second > 2 ? 1 : 0;
  }
  return census;
}

namespace
{
// Every named numeric point array of the input (of one value per point; the first of one name) must
// be in the output with its component count; every output array must have one tuple per output point.
void CheckPointData(vtkPolyData* input, vtkPolyData* output, bool carried, std::vector<std::string>& problems)
{
  vtkPointData* out = output->GetPointData();
  for (int a = 0; a < out->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = out->GetAbstractArray(a);
    if (array->GetNumberOfTuples() != output->GetNumberOfPoints())
    {
      problems.push_back(std::string("point array '") + (array->GetName() ? array->GetName() : "") + "' has " +
        std::to_string(array->GetNumberOfTuples()) + " tuples for " + std::to_string(output->GetNumberOfPoints()) + " points");
    }
  }
  vtkPointData* in = input->GetPointData();
  for (int a = 0; carried && output->GetNumberOfPoints() > 0 && a < in->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = in->GetArray(a);
    int first = -1; // an output holds one array of a name: the first of several is required
    if (array && array->GetName())
      in->GetAbstractArray(array->GetName(), first);
    if (!array || !array->GetName() || array->GetNumberOfTuples() != input->GetNumberOfPoints() || first != a)
      continue;
    bool found = false;
    for (int b = 0; b < out->GetNumberOfArrays(); ++b)
    {
      vtkDataArray* candidate = out->GetArray(b);
      found = found || (candidate && candidate->GetName() && std::strcmp(candidate->GetName(), array->GetName()) == 0 &&
                         candidate->GetNumberOfComponents() == array->GetNumberOfComponents());
    }
    if (!found)
    {
      problems.push_back(std::string("point array '") + array->GetName() + "' (" +
        std::to_string(array->GetNumberOfComponents()) + " components) is missing from the output");
    }
  }
}

// Finite points, triangles only, ids in range; false when the ids cannot be used for more checks.
bool CheckCells(vtkPolyData* output, std::vector<std::string>& problems)
{
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i)
  {
    double p[3];
    output->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      problems.push_back("point " + std::to_string(i) + " is not finite");
      break;
    }
  }
  const vtkIdType others = output->GetNumberOfVerts() + output->GetNumberOfLines() + output->GetNumberOfStrips();
  if (others > 0)
  {
    problems.push_back(std::to_string(others) + " vertex, line or strip cells in the output");
  }
  vtkIdType n;
  const vtkIdType* ids;
  vtkCellArray* polys = output->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
  {
    if (n != 3)
    {
      problems.push_back("a polygon of " + std::to_string(n) + " points in the output");
      return false;
    }
    for (int k = 0; k < 3; ++k)
    {
      if (ids[k] < 0 || ids[k] >= output->GetNumberOfPoints())
      {
        problems.push_back("point id " + std::to_string(ids[k]) + " out of range");
        return false;
      }
    }
  }
  return true;
}
} // namespace

std::vector<std::string> CheckFilterOutput(const BadInput& input, vtkPolyData* output, int errors,
  const OutputExpectations& expectations)
{
  std::vector<std::string> problems;
  if (!output)
  {
    return { "no output" };
  }
  if (errors > 0)
  {
    if (output->GetNumberOfCells() > 0)
    {
      problems.push_back("an error was reported but the output has " + std::to_string(output->GetNumberOfCells()) + " cells");
    }
    return problems;
  }
  if (input.Unusable)
  {
    problems.push_back("no error on an input with non-finite coordinates");
  }
  if (!CheckCells(output, problems))
  {
    return problems;
  }
  CheckPointData(input.Surface, output, expectations.CarriesPointData, problems);
  if (input.InvalidCellIds || input.Unusable)
  {
    return problems;
  }
  const SurfaceCensus in = CountSurface(input.Surface), out = CountSurface(output);
  const long long triangles = output->GetNumberOfPolys();
  if (expectations.MayNotGrow && triangles > in.DistinctTriangles)
  {
    problems.push_back("grew: " + std::to_string(triangles) + " triangles from " + std::to_string(in.DistinctTriangles));
  }
  if (in.TrianglesWithArea > 0 && triangles == 0)
  {
    problems.push_back("emptied: no triangle left of " + std::to_string(in.TrianglesWithArea) + " of non-zero area, and no error");
  }
  if (out.NonManifoldEdges > in.NonManifoldEdges && !expectations.MayAddNonManifoldEdges)
  {
    problems.push_back("new non-manifold edges: " + std::to_string(out.NonManifoldEdges) + " (input " +
      std::to_string(in.NonManifoldEdges) + ")");
  }
  if (in.Closed() && !expectations.MayOpen && out.BorderEdges > 0)
  {
    problems.push_back("opened a closed surface: " + std::to_string(out.BorderEdges) + " border edges");
  }
  return problems;
}

// ---------------------------------------------------------------------------------------------
// Files

namespace
{
void WriteBytes(const std::string& path, const std::string& bytes)
{
  std::ofstream file(path, std::ios::binary);
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!file)
  {
    throw std::runtime_error("cannot write " + path);
  }
}

template <typename T>
std::string LittleEndian(T value)
{
  std::string bytes(sizeof(T), '\0');
  std::memcpy(&bytes[0], &value, sizeof(T));
  return bytes; // the test machines are little-endian (x86-64, arm64)
}

// A binary little-endian PLY tetrahedron, and the same bytes declared big-endian.
std::string TetrahedronPLY(const char* format)
{
  std::string ply = std::string("ply\nformat ") + format + " 1.0\nelement vertex 4\nproperty float x\n"
    "property float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  const float corners[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  for (const auto& corner : corners)
    for (float x : corner)
      ply += LittleEndian(x);
  const int faces[4][3] = { { 0, 2, 1 }, { 0, 1, 3 }, { 1, 2, 3 }, { 0, 3, 2 } };
  for (const auto& face : faces)
  {
    ply += LittleEndian<unsigned char>(3);
    for (int v : face)
      ply += LittleEndian(v);
  }
  return ply;
}

std::string BinarySTLClaiming(std::uint32_t triangles)
{
  std::string stl(80, ' ');
  stl += LittleEndian(triangles);
  for (int k = 0; k < 12; ++k) // one facet: normal and three corners
    stl += LittleEndian(float(k % 3 == 0 ? 1 : 0));
  stl += std::string(2, '\0');
  return stl;
}

// The broken files: name -> bytes. Every one must be refused with a clear message naming it.
std::vector<std::pair<std::string, std::string>> BrokenFiles()
{
  const std::string tetraOFF = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::string plyHeader = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  std::string garbage;
  for (int i = 0; i < 4096; ++i)
    garbage += static_cast<char>((i * 2654435761u) >> 13);
  return { { "empty.off", "" }, { "empty.ply", "" }, { "empty.stl", "" }, { "empty.obj", "" }, { "empty.vtp", "" },
    { "empty.vtk", "" }, { "header-only.off", "OFF\n" }, { "header-only.ply", plyHeader },
    { "header-only.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n" },
    { "truncated.off", tetraOFF + "3 0 2 1\n3 0 1" },
    { "truncated-binary.ply", TetrahedronPLY("binary_little_endian").substr(0, 250) },
    { "wrong-counts-too-many.off", "OFF\n40 40 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n" },
    { "huge-counts.off", "OFF\n4000000000000 4000000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n" },
    { "huge-polygon-size.off", tetraOFF + "2000000000 0 1 2\n3 0 1 3\n3 1 2 3\n3 0 3 2\n" },
    { "negative-index.off", tetraOFF + "3 0 2 1\n3 0 -1 3\n3 1 2 3\n3 0 3 2\n" },
    { "huge-index.off", tetraOFF + "3 0 2 1\n3 0 1 4294967296\n3 1 2 3\n3 0 3 2\n" },
    { "overflowing-index.off", tetraOFF + "3 0 2 1\n3 0 1 99999999999999999999999\n3 1 2 3\n3 0 3 2\n" },
    { "text-in-numbers.off", "OFF\n3 1 0\n0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n" },
    { "inf-coordinate.off", "OFF\n3 1 0\n0 0 0\ninf 0 0\n0 1 0\n3 0 1 2\n" },
    { "garbage.off", garbage }, { "garbage.ply", "ply\n" + garbage }, { "garbage.stl", garbage },
    { "negative-index.ply", plyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 -2 1\n" },
    { "wrong-byte-order.ply", TetrahedronPLY("binary_big_endian") },
    { "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n" },
    { "zero-index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n" },
    { "relative-index-out-of-range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n" },
    { "nan.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\nvertex 0 1 0\n"
                 "endloop\nendfacet\nendsolid x\n" },
    { "wrong-count-binary.stl", BinarySTLClaiming(1000) },
    { "truncated.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n0 0 0 1 0 0\n" },
    { "truncated.vtp", "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\">\n<PolyData>\n"
                       "<Piece NumberOfPoints=\"3\" NumberOfPolys=\"1\">\n" } };
}
} // namespace

std::vector<std::string> WriteBadInputFiles(const std::string& directory)
{
  std::vector<std::string> paths;
  for (const std::string& name : BadInputNames())
  {
    // Legacy binary: it stores the cells as they are (the XML writer refuses cells of 0 points) and
    // the coordinates bit for bit (NaN included).
    const std::string path = directory + "/" + name + ".vtk";
    vtkNew<vtkPolyDataWriter> writer;
    writer->SetInputData(MakeBadInput(name).Surface);
    writer->SetFileName(path.c_str());
    writer->SetFileTypeToBinary();
    if (writer->Write() != 1)
    {
      throw std::runtime_error("cannot write " + path);
    }
    paths.push_back(path);
  }
  for (const auto& file : BrokenFiles())
  {
    const std::string path = directory + "/broken-" + file.first;
    WriteBytes(path, file.second);
    paths.push_back(path);
  }
  return paths;
}
} // namespace slodtest
