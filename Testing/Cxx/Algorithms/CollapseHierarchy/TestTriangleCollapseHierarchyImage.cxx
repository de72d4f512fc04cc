// SPDX-License-Identifier: BSD-3-Clause
// Baseline image of a blended level of the triangle-collapse hierarchy: the bunny at level 30.5
// (M_30 with its collapsing triangles half collapsed), coloured by CollapseRole (collapsing
// triangles, their stencils, the rest), like the paper's figures 14-16.
#include "RenderTestSupport.h"
#include "TestSupport.h"

#include "vtkCellData.h"
#include "vtkNew.h"
#include "vtkTriangleCollapseHierarchy.h"

#include <gtest/gtest.h>

TEST(TriangleCollapseHierarchyImage, BlendedLevelMatchesBaseline)
{
  vtkSmartPointer<vtkPolyData> bunny = slodtest::LoadTestMesh("bunny00");
  vtkNew<vtkTriangleCollapseHierarchy> hierarchy;
  hierarchy->SetInputData(bunny);
  hierarchy->GenerateAllLevelsOff();
  hierarchy->SetContinuousLevel(30.5);
  hierarchy->Update();
  vtkNew<vtkPolyData> shown;
  shown->ShallowCopy(hierarchy->GetOutput());
  ASSERT_GT(shown->GetNumberOfPolys(), 0);
  ASSERT_LT(shown->GetNumberOfPolys(), bunny->GetNumberOfPolys());
  ASSERT_EQ(shown->GetCellData()->SetActiveScalars("CollapseRole"), 2);
  const double view[3] = { 0.2, 0.3, 1.0 };
  EXPECT_TRUE(slodtest::RenderAndCompare(shown, "TestTriangleCollapseHierarchyBlend", 0.05, view));
}
