// SPDX-License-Identifier: BSD-3-Clause
// Baseline-image regression test: bunny00 simplified by triangle collapses to 97 % reduction,
// rendered offscreen and compared with Testing/Data/Baseline/TestQuadricTriangleCollapseBunny.png.
#include "RenderTestSupport.h"
#include "TestSupport.h"

#include "vtkQuadricTriangleCollapse.h"

#include <gtest/gtest.h>

TEST(QuadricTriangleCollapseImage, Bunny97PercentMatchesBaseline)
{
  vtkSmartPointer<vtkPolyData> bunny = slodtest::LoadTestMesh("bunny00");
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->SetInputData(bunny);
  filter->SetTargetReduction(0.97);
  filter->Update();
  ASSERT_LE(filter->GetOutput()->GetNumberOfPolys(), 2263);
  const double front[3] = { 0.0, 0.0, 1.0 };
  EXPECT_TRUE(slodtest::RenderAndCompare(filter->GetOutput(), "TestQuadricTriangleCollapseBunny", 0.05, front));
}
