// SPDX-License-Identifier: BSD-3-Clause
// Baseline-image regression test of vtkGreedyCutsSimplification: the Fandisk at epsilon 0.01 of
// the diagonal coloured by patch (catches changes in chains, ears, bites and repairs at once).
#include "RenderTestSupport.h"
#include "TestSupport.h"

#include "vtkCellData.h"
#include "vtkGreedyCutsSimplification.h"
#include "vtkNew.h"

#include <gtest/gtest.h>

TEST(GreedyCutsSimplificationImage, FandiskAtOnePercentMatchesBaseline)
{
  vtkSmartPointer<vtkPolyData> fandisk = slodtest::LoadTestMesh("fandisk");
  vtkNew<vtkGreedyCutsSimplification> cuts;
  cuts->SetInputData(fandisk);
  cuts->SetMaximumError(0.01);
  cuts->Update();
  vtkNew<vtkPolyData> result;
  result->DeepCopy(cuts->GetOutput());
  ASSERT_EQ(result->GetNumberOfPolys(), 798);
  result->GetCellData()->SetActiveScalars("PatchId");
  EXPECT_TRUE(slodtest::RenderAndCompare(result, "TestGreedyCutsSimplificationFandisk"));
}
