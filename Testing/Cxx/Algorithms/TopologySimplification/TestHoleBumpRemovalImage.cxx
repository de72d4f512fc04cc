// SPDX-License-Identifier: BSD-3-Clause
// Baseline-image regression test of vtkHoleBumpRemoval: the mixed block model (bumps, cavities,
// a hole) with its features removed keeping the other triangles, coloured by FilledPatch (catches
// changes in the loop search, the wall regions and the fills at once).
#include "RenderTestSupport.h"
#include "TestSupport.h"

#include "vtkBlockModelSource.h"
#include "vtkCellData.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkNew.h"

#include <gtest/gtest.h>

TEST(HoleBumpRemovalImage, MixedBlockFillsMatchBaseline)
{
  vtkNew<vtkBlockModelSource> source;
  source->SetModelToMixed();
  vtkNew<vtkHoleBumpRemoval> removal;
  removal->SetInputConnection(source->GetOutputPort());
  removal->SetFeatureSize(0.2);
  removal->SetCompletionToKeepTriangles();
  removal->Update();
  ASSERT_EQ(removal->GetNumberOfBumpsRemoved(), 6);
  ASSERT_EQ(removal->GetNumberOfCavitiesRemoved(), 2);
  ASSERT_EQ(removal->GetNumberOfHolesRemoved(), 1);
  vtkNew<vtkPolyData> result;
  result->DeepCopy(removal->GetOutput());
  result->GetCellData()->SetActiveScalars("FilledPatch");
  EXPECT_TRUE(slodtest::RenderAndCompare(result, "TestHoleBumpRemovalMixed"));
}
