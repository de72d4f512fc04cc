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
  // (The count was compared with a figure copied from a run, 798; the front repair of section
  // 3.4.3 changed it. What matters here is the picture, and that the reduction happened.)
  ASSERT_LT(result->GetNumberOfPolys(), fandisk->GetNumberOfPolys() / 10);
  result->GetCellData()->SetActiveScalars("PatchId");
  EXPECT_TRUE(slodtest::RenderAndCompare(result, "TestGreedyCutsSimplificationFandisk"));
}
