// SPDX-License-Identifier: BSD-3-Clause
// Randomised robustness test of every simplification filter (a deterministic fuzzer): small
// meshes corrupted by random combinations of the defects users feed in (duplicate and coincident
// points, degenerate and duplicate triangles, flipped triangles, holes, non-manifold edges, lines,
// vertices and quads among the triangles, NaN coordinates) must give a defined output: no crash,
// finite points, triangles only, valid indices, never more triangles than the input, and an
// empty output with an error for non-finite input.
#include "TestSupport.h"

#include "vtkGreedyCutsSimplification.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkPatchBoundaryMerge.h"
#include "vtkQuadricTriangleCollapse.h"
#include "vtkRetile.h"
#include "vtkSurfaceDeviation.h"
#include "vtkTriangleCollapseHierarchy.h"

#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataAlgorithm.h"
#include "vtkSmartPointer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

using slod::Index;
using slod::TriangleMesh;

namespace
{
struct FuzzCase
{
  vtkSmartPointer<vtkPolyData> Input;
  vtkIdType InputTriangles = 0; // after triangulating quads
  bool NonFinite = false;
  std::string Description;
};

// A base shape with random defects; deterministic for a seed.
FuzzCase MakeCase(unsigned seed)
{
  std::mt19937 random(seed);
  auto pick = [&](int n) { return static_cast<int>(random() % static_cast<unsigned>(n)); };
  auto chance = [&](double p) { return std::uniform_real_distribution<double>(0, 1)(random) < p; };
  TriangleMesh mesh;
  switch (pick(5))
  {
    case 0: mesh = slodtest::Sphere(10 + pick(8), 8 + pick(6)); break;
    case 1: mesh = slodtest::Torus(10 + pick(10), 6 + pick(6)); break;
    case 2: mesh = slodtest::Grid(5 + pick(8), 5 + pick(8)); break;
    case 3: mesh = slodtest::Disk(3 + pick(4), 8 + pick(8)); break;
    default: mesh = slodtest::Concatenate(slodtest::Sphere(12, 8), slodtest::NonManifoldFan(3 + pick(3))); break;
  }
  FuzzCase c;
  c.Description = "seed " + std::to_string(seed) + ":";
  auto triangleCount = [&]() { return static_cast<int>(mesh.Triangles.size() / 3); };
  if (chance(0.4)) // jitter
  {
    std::normal_distribution<double> noise(0.0, 0.01);
    for (double& x : mesh.Points)
    {
      x += noise(random);
    }
    c.Description += " jitter";
  }
  if (chance(0.4)) // duplicate points: some corners re-pointed to a copy
  {
    for (int k = 0; k < 1 + pick(5); ++k)
    {
      const int corner = pick(static_cast<int>(mesh.Triangles.size()));
      const Index v = mesh.Triangles[corner];
      mesh.Points.insert(mesh.Points.end(), { mesh.Points[3 * v], mesh.Points[3 * v + 1], mesh.Points[3 * v + 2] });
      mesh.Triangles[corner] = static_cast<Index>(mesh.Points.size() / 3 - 1);
    }
    c.Description += " duplicate-points";
  }
  if (chance(0.4)) // flipped triangles
  {
    for (int k = 0; k < 1 + pick(6); ++k)
    {
      const int t = pick(triangleCount());
      std::swap(mesh.Triangles[3 * t + 1], mesh.Triangles[3 * t + 2]);
    }
    c.Description += " flipped";
  }
  if (chance(0.4)) // holes
  {
    for (int k = 0; k < 1 + pick(4) && triangleCount() > 8; ++k)
    {
      const int t = pick(triangleCount());
      mesh.Triangles.erase(mesh.Triangles.begin() + 3 * t, mesh.Triangles.begin() + 3 * t + 3);
    }
    c.Description += " holes";
  }
  if (chance(0.3)) // degenerate: repeated vertex, and three collinear points
  {
    const int t = pick(triangleCount());
    mesh.Triangles.insert(mesh.Triangles.end(), { mesh.Triangles[3 * t], mesh.Triangles[3 * t], mesh.Triangles[3 * t + 1] });
    const Index a = mesh.Triangles[3 * t], b = mesh.Triangles[3 * t + 1];
    mesh.Points.insert(mesh.Points.end(), { 0.5 * (mesh.Points[3 * a] + mesh.Points[3 * b]),
      0.5 * (mesh.Points[3 * a + 1] + mesh.Points[3 * b + 1]), 0.5 * (mesh.Points[3 * a + 2] + mesh.Points[3 * b + 2]) });
    mesh.Triangles.insert(mesh.Triangles.end(), { a, b, static_cast<Index>(mesh.Points.size() / 3 - 1) });
    c.Description += " degenerate";
  }
  if (chance(0.3)) // duplicate triangle and an extra wing on an edge (non-manifold)
  {
    const int t = pick(triangleCount());
    const Index a = mesh.Triangles[3 * t], b = mesh.Triangles[3 * t + 1], d = mesh.Triangles[3 * t + 2];
    mesh.Triangles.insert(mesh.Triangles.end(), { a, b, d });
    mesh.Points.insert(mesh.Points.end(), { mesh.Points[3 * d] + 0.3, mesh.Points[3 * d + 1] - 0.2, mesh.Points[3 * d + 2] + 0.25 });
    mesh.Triangles.insert(mesh.Triangles.end(), { b, a, static_cast<Index>(mesh.Points.size() / 3 - 1) });
    c.Description += " duplicate-triangle non-manifold-edge";
  }
  c.Input = slodtest::ToPolyData(mesh);
  c.InputTriangles = c.Input->GetNumberOfPolys();
  if (chance(0.3)) // lines, vertices and a quad among the triangles
  {
    vtkNew<vtkCellArray> lines, verts;
    const vtkIdType line[2] = { 0, 1 }, vertex[1] = { 2 };
    lines->InsertNextCell(2, line);
    verts->InsertNextCell(1, vertex);
    c.Input->SetLines(lines);
    c.Input->SetVerts(verts);
    const vtkIdType quad[4] = { 0, 1, 2, 3 };
    c.Input->GetPolys()->InsertNextCell(4, quad);
    c.InputTriangles += 2;
    c.Description += " lines-verts-quad";
  }
  if (chance(0.1)) // a non-finite coordinate: the input cannot be used
  {
    c.Input->GetPoints()->SetPoint(pick(static_cast<int>(c.Input->GetNumberOfPoints())), std::nan(""), 0.0, 1.0);
    c.NonFinite = true;
    c.Description += " NaN";
  }
  return c;
}

struct FilterUnderTest
{
  const char* Name;
  std::function<vtkSmartPointer<vtkPolyDataAlgorithm>(unsigned)> Make;
};

// Seeds alternate between a reduction of a half and extreme targets (1 or 4 triangles).
template <typename Filter>
FilterUnderTest Simplifier(const char* name)
{
  return { name, [](unsigned seed) {
            vtkSmartPointer<Filter> filter = vtkSmartPointer<Filter>::New();
            if (seed % 3 == 0)
            {
              filter->SetTargetNumberOfTriangles(seed % 2 ? 1 : 4);
              filter->SetTargetReduction(0);
            }
            else
            {
              filter->SetTargetReduction(0.5);
            }
            return vtkSmartPointer<vtkPolyDataAlgorithm>(filter);
          } };
}

class Messages : public vtkCommand
{
public:
  static Messages* New() { return new Messages; }
  void Execute(vtkObject*, unsigned long event, void*) override { (event == vtkCommand::ErrorEvent ? this->Errors : this->Warnings)++; }
  int Errors = 0, Warnings = 0;
};
} // namespace

TEST(RobustnessFuzz, EveryFilterGivesADefinedOutputOnCorruptedInput)
{
  const FilterUnderTest filters[] = { Simplifier<vtkQuadricTriangleCollapse>("vtkQuadricTriangleCollapse"),
    Simplifier<vtkTriangleCollapseHierarchy>("vtkTriangleCollapseHierarchy"),
    Simplifier<vtkPatchBoundaryMerge>("vtkPatchBoundaryMerge"), Simplifier<vtkHoleBumpRemoval>("vtkHoleBumpRemoval"),
    Simplifier<vtkRetile>("vtkRetile"), Simplifier<vtkGreedyCutsSimplification>("vtkGreedyCutsSimplification") };
  int nonFiniteCases = 0;
  for (unsigned seed = 1; seed <= 40; ++seed)
  {
    const FuzzCase c = MakeCase(seed);
    nonFiniteCases += c.NonFinite ? 1 : 0;
    for (const auto& f : filters)
    {
      SCOPED_TRACE(std::string(f.Name) + " on " + c.Description);
      vtkSmartPointer<vtkPolyDataAlgorithm> filter = f.Make(seed);
      vtkNew<Messages> messages;
      filter->AddObserver(vtkCommand::ErrorEvent, messages);
      filter->AddObserver(vtkCommand::WarningEvent, messages);
      filter->SetInputData(c.Input);
      const auto start = std::chrono::steady_clock::now();
      filter->Update();
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (seconds > 0.5)
      {
        std::printf("[fuzz] %s on %s (%lld triangles): %.2f s\n", f.Name, c.Description.c_str(), (long long)c.InputTriangles, seconds);
      }
      vtkPolyData* out = filter->GetOutput();
      ASSERT_NE(out, nullptr);
      if (c.NonFinite)
      {
        EXPECT_EQ(out->GetNumberOfCells(), 0);
        EXPECT_GE(messages->Errors, 1);
        continue;
      }
      for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
      {
        double p[3];
        out->GetPoint(i, p);
        ASSERT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
      }
      EXPECT_EQ(out->GetNumberOfCells(), out->GetNumberOfPolys()); // triangles only
      EXPECT_LE(out->GetNumberOfPolys(), c.InputTriangles);
      vtkIdType npts;
      const vtkIdType* pts;
      vtkCellArray* polys = out->GetPolys();
      for (polys->InitTraversal(); polys->GetNextCell(npts, pts);)
      {
        ASSERT_EQ(npts, 3);
        for (int k = 0; k < 3; ++k)
        {
          ASSERT_GE(pts[k], 0);
          ASSERT_LT(pts[k], out->GetNumberOfPoints());
        }
      }
    }
    // The measure every test relies on, against the corrupted input.
    if (!c.NonFinite)
    {
      vtkNew<vtkSurfaceDeviation> deviation;
      deviation->SetReferenceData(c.Input);
      deviation->SetComparedData(c.Input);
      deviation->SetNumberOfSamples(2000);
      deviation->SetGlobalWarningDisplay(0);
      deviation->Update();
      EXPECT_LT(deviation->GetHausdorffRelative(), 1e-9) << c.Description;
      deviation->SetGlobalWarningDisplay(1);
    }
  }
  // The seeds cover the non-finite path too.
  EXPECT_GE(nonFiniteCases, 1);
}
