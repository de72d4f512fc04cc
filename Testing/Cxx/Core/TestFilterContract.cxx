// SPDX-License-Identifier: BSD-3-Clause
// The shared filter contract (slodFilterContract.h): how the three stop targets resolve to a count.
#include "slodFilterContract.h"

#include <gtest/gtest.h>

namespace
{
constexpr slod::Index Input = 79200;
}

TEST(FilterContract, CountAloneGivesThatCount)
{
  EXPECT_EQ(slod::TargetTriangleCount(Input, 500, 0.0, false), 500);
  EXPECT_EQ(slod::TargetTriangleCount(Input, 500, 0.0, true), 500);
}

TEST(FilterContract, ReductionAloneRemovesAtLeastThatFraction)
{
  EXPECT_EQ(slod::TargetTriangleCount(Input, 0, 0.9, false), 7920);
  // 12946 * 0.1 = 1294.6: 1294 triangles remove at least 90%.
  EXPECT_EQ(slod::TargetTriangleCount(12946, 0, 0.9, false), 1294);
  EXPECT_EQ(slod::TargetTriangleCount(4015000, 0, 0.9, false), 401500);
  EXPECT_EQ(slod::TargetTriangleCount(Input, 0, 1.0, false), 0);
}

TEST(FilterContract, WhicheverIsReachedFirstIsTheLargerCount)
{
  EXPECT_EQ(slod::TargetTriangleCount(Input, 500, 0.9, false), 7920);
  EXPECT_EQ(slod::TargetTriangleCount(Input, 20000, 0.9, false), 20000);
}

TEST(FilterContract, DefaultsAndErrorBound)
{
  // No target at all: the default reduction, as vtkQuadricDecimation.
  EXPECT_EQ(slod::TargetTriangleCount(Input, 0, 0.0, false), slod::TargetTriangleCount(Input, 0, 0.9, false));
  // Only an error bound: no count target.
  EXPECT_EQ(slod::TargetTriangleCount(Input, 0, 0.0, true), 0);
}

TEST(FilterContract, NeverAboveTheInput)
{
  EXPECT_EQ(slod::TargetTriangleCount(100, 500, 0.0, false), 100);
  EXPECT_EQ(slod::TargetTriangleCount(0, 0, 0.5, false), 0);
}
