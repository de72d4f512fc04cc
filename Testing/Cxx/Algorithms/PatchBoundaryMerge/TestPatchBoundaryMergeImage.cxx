// SPDX-License-Identifier: BSD-3-Clause
// Baseline-image regression test of vtkPatchBoundaryMerge: the Fandisk at 460 triangles coloured
// by merged patch (catches changes in patchification, merging and triangulation at once).
#include "RenderTestSupport.h"
#include "TestSupport.h"

#include "vtkCellData.h"
#include "vtkNew.h"
#include "vtkPatchBoundaryMerge.h"

#include <gtest/gtest.h>

TEST(PatchBoundaryMergeImage, FandiskLevel460MatchesBaseline)
{
  vtkSmartPointer<vtkPolyData> fandisk = slodtest::LoadTestMesh("fandisk");
  vtkNew<vtkPatchBoundaryMerge> spbm;
  spbm->SetInputData(fandisk);
  spbm->SetTargetNumberOfTriangles(460);
  spbm->Update();
  vtkNew<vtkPolyData> result;
  result->DeepCopy(spbm->GetOutput());
  ASSERT_LE(result->GetNumberOfPolys(), 460);
  ASSERT_GE(result->GetNumberOfPolys(), 460 - 460 / 50); // the count contract: within 2%
  result->GetCellData()->SetActiveScalars("PatchId");
  EXPECT_TRUE(slodtest::RenderAndCompare(result, "TestPatchBoundaryMergeFandisk"));
}
