// SPDX-License-Identifier: BSD-3-Clause
// Point data through every simplifier: a textured sphere (vtkTexturedSphereSource leaves its normals
// and texture coordinates unnamed) with a named scalar array. Every array comes out, named or not,
// with its attribute role; normals are unit length, texture coordinates stay in the input's range;
// the texture seam (coincident points with other coordinates) is never welded.
#include "TestSupport.h"

#include "vtkGreedyCutsSimplification.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkPatchBoundaryMerge.h"
#include "vtkQuadricTriangleCollapse.h"
#include "vtkRetile.h"
#include "vtkTriangleCollapseHierarchy.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTexturedSphereSource.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace
{
vtkSmartPointer<vtkPolyData> TexturedSphere()
{
  vtkNew<vtkTexturedSphereSource> source;
  source->SetThetaResolution(48);
  source->SetPhiResolution(48);
  source->Update();
  auto sphere = vtkSmartPointer<vtkPolyData>::New();
  sphere->DeepCopy(source->GetOutput());
  vtkNew<vtkDoubleArray> height;
  height->SetName("Height");
  height->SetNumberOfTuples(sphere->GetNumberOfPoints());
  for (vtkIdType i = 0; i < sphere->GetNumberOfPoints(); ++i)
  {
    height->SetValue(i, sphere->GetPoint(i)[2]);
  }
  sphere->GetPointData()->AddArray(height);
  return sphere;
}

void ExpectPointDataCarried(vtkPolyData* output)
{
  ASSERT_GT(output->GetNumberOfPolys(), 0);
  vtkPointData* pd = output->GetPointData();
  vtkDataArray* normals = pd->GetNormals();
  vtkDataArray* tcoords = pd->GetTCoords();
  ASSERT_NE(normals, nullptr) << "normals (unnamed in the input) lost";
  ASSERT_NE(tcoords, nullptr) << "texture coordinates (unnamed in the input) lost";
  ASSERT_NE(pd->GetArray("Height"), nullptr);
  EXPECT_EQ(normals->GetNumberOfComponents(), 3);
  EXPECT_EQ(tcoords->GetNumberOfComponents(), 2);
  EXPECT_EQ(normals->GetNumberOfTuples(), output->GetNumberOfPoints());
  EXPECT_EQ(tcoords->GetNumberOfTuples(), output->GetNumberOfPoints());
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i)
  {
    const double* n = normals->GetTuple3(i);
    EXPECT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0, 1e-5) << "normal " << i;
    for (int c = 0; c < 2; ++c)
    {
      EXPECT_GE(tcoords->GetComponent(i, c), -1e-6) << "point " << i;
      EXPECT_LE(tcoords->GetComponent(i, c), 1.0 + 1e-6) << "point " << i;
    }
  }
}

struct Simplifier
{
  const char* Name;
  std::function<vtkSmartPointer<vtkPolyDataAlgorithm>()> Make;
  // The seam is a border of the prepared input: filters that keep borders keep it open. The
  // triangle collapse also keeps the whole prepared topology and removes the zero-area triangles of
  // the poles (their corners are coincident copies with other texture coordinates).
  bool KeepsBorders;
  bool KeepsTopology;
};

template <class Filter>
vtkSmartPointer<vtkPolyDataAlgorithm> Reducing()
{
  auto filter = vtkSmartPointer<Filter>::New();
  filter->SetTargetReduction(0.75);
  return filter;
}
} // namespace

TEST(PointDataCarried, EveryArrayWithItsRoleAndTheSeamKept)
{
  const vtkSmartPointer<vtkPolyData> sphere = TexturedSphere();
  ASSERT_EQ(sphere->GetPointData()->GetNormals()->GetName(), nullptr) << "premise: unnamed normals";
  ASSERT_EQ(sphere->GetPointData()->GetTCoords()->GetName(), nullptr) << "premise: unnamed texture coordinates";
  const Simplifier simplifiers[] = {
    { "vtkQuadricTriangleCollapse", Reducing<vtkQuadricTriangleCollapse>, true, true },
    { "vtkTriangleCollapseHierarchy", Reducing<vtkTriangleCollapseHierarchy>, true, false },
    { "vtkPatchBoundaryMerge", Reducing<vtkPatchBoundaryMerge>, false, false },
    { "vtkGreedyCutsSimplification", Reducing<vtkGreedyCutsSimplification>, false, false },
    { "vtkHoleBumpRemoval", Reducing<vtkHoleBumpRemoval>, false, false },
    { "vtkRetile", Reducing<vtkRetile>, false, false },
  };
  for (const Simplifier& simplifier : simplifiers)
  {
    SCOPED_TRACE(simplifier.Name);
    vtkSmartPointer<vtkPolyDataAlgorithm> filter = simplifier.Make();
    vtkNew<slodtest::MessageCounter> messages;
    filter->AddObserver(vtkCommand::WarningEvent, messages);
    filter->AddObserver(vtkCommand::ErrorEvent, messages);
    filter->SetInputData(sphere);
    filter->Update();
    EXPECT_TRUE(messages->Errors.empty());
    ExpectPointDataCarried(filter->GetOutput());
    if (simplifier.KeepsTopology)
    {
      const slod::MeshStatistics in = slodtest::ExpectPreparedInputTopology(sphere, filter->GetOutput());
      EXPECT_GT(in.BoundaryEdges, 0) << "premise: the seam is a border of the prepared input";
    }
    if (simplifier.KeepsBorders)
    {
      // Welding the seam would close the surface.
      EXPECT_GT(slod::ComputeMeshStatistics(slodtest::ToTriangleMesh(filter->GetOutput())).BoundaryEdges, 0);
    }
  }
}
