// SPDX-License-Identifier: BSD-3-Clause
// The baseline-image pattern every filter's image test follows: render a real mesh offscreen and
// compare with a stored baseline through vtkTesting.
#include "RenderTestSupport.h"
#include "TestSupport.h"

#include <gtest/gtest.h>

TEST(RenderBaseline, FandiskMatchesBaseline)
{
  vtkSmartPointer<vtkPolyData> fandisk = slodtest::LoadTestMesh("fandisk");
  ASSERT_EQ(fandisk->GetNumberOfPolys(), 12946);
  EXPECT_TRUE(slodtest::RenderAndCompare(fandisk, "TestRenderFandisk"));
}
