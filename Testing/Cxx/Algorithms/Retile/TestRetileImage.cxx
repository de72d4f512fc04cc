// SPDX-License-Identifier: BSD-3-Clause
// Baseline-image regression test: bunny00 re-tiled with 1500 vertices (curvature-weighted),
// rendered offscreen and compared with Testing/Data/Baseline/TestRetileBunny.png.
#include "RenderTestSupport.h"
#include "TestSupport.h"

#include "vtkRetile.h"

#include <gtest/gtest.h>

TEST(RetileImage, Bunny1500PointsMatchesBaseline)
{
  vtkSmartPointer<vtkPolyData> bunny = slodtest::LoadTestMesh("bunny00");
  vtkNew<vtkRetile> filter;
  filter->SetInputData(bunny);
  filter->SetNumberOfPoints(1500);
  filter->SetCurvatureWeight(1.0);
  filter->Update();
  ASSERT_EQ(filter->GetOutput()->GetNumberOfPoints(), 1500 + filter->GetNumberOfRetainedVertices());
  const double front[3] = { 0.0, 0.0, 1.0 };
  EXPECT_TRUE(slodtest::RenderAndCompare(filter->GetOutput(), "TestRetileBunny", 0.05, front));
}
