// SPDX-License-Identifier: BSD-3-Clause
// The shared filter contract (slodFilterContract.h): how the three stop targets resolve to a count,
// what every simplification filter gives when aborted, and that a count alone gives that count.
#include "slodFilterContract.h"

#include "TestSupport.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkGreedyCutsSimplification.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkNew.h"
#include "vtkPatchBoundaryMerge.h"
#include "vtkPolyData.h"
#include "vtkQuadricTriangleCollapse.h"
#include "vtkRetile.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkTopologicalNoiseRemoval.h"
#include "vtkTriangleCollapseHierarchy.h"

#include <gtest/gtest.h>

#include <string>

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

namespace
{
vtkSmartPointer<vtkPolyDataAlgorithm> MakeSimplifier(const std::string& name)
{
  if (name == "vtkQuadricTriangleCollapse")
    return vtkSmartPointer<vtkQuadricTriangleCollapse>::New();
  if (name == "vtkTriangleCollapseHierarchy")
    return vtkSmartPointer<vtkTriangleCollapseHierarchy>::New();
  if (name == "vtkPatchBoundaryMerge")
    return vtkSmartPointer<vtkPatchBoundaryMerge>::New();
  if (name == "vtkHoleBumpRemoval")
    return vtkSmartPointer<vtkHoleBumpRemoval>::New();
  if (name == "vtkRetile")
    return vtkSmartPointer<vtkRetile>::New();
  if (name == "vtkTopologicalNoiseRemoval")
    return vtkSmartPointer<vtkTopologicalNoiseRemoval>::New();
  return vtkSmartPointer<vtkGreedyCutsSimplification>::New();
}

// The named simplifier over a vtkSphereSource of the given resolution (its input: `sphere`).
vtkSmartPointer<vtkPolyDataAlgorithm> SimplifierOfSphere(const std::string& name, int theta, int phi, vtkPolyData*& sphere)
{
  vtkNew<vtkSphereSource> source;
  source->SetThetaResolution(theta);
  source->SetPhiResolution(phi);
  source->Update();
  vtkSmartPointer<vtkPolyDataAlgorithm> filter = MakeSimplifier(name);
  filter->SetInputData(source->GetOutput());
  sphere = source->GetOutput(); // held by the filter's input
  return filter;
}

class AbortContract : public ::testing::TestWithParam<std::string>
{
};
}

// The contract's one abort result: every simplification filter, aborted at its first progress
// report, gives an empty output and says so in a warning.
TEST_P(AbortContract, EmptyOutputAndAWarning)
{
  vtkPolyData* sphere = nullptr;
  vtkSmartPointer<vtkPolyDataAlgorithm> filter = SimplifierOfSphere(GetParam(), 48, 48, sphere);
  vtkNew<slodtest::AbortAtFirstProgress> observer;
  filter->AddObserver(vtkCommand::ProgressEvent, observer);
  filter->AddObserver(vtkCommand::WarningEvent, observer);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0) << GetParam();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0) << GetParam();
  EXPECT_EQ(observer->AbortWarnings, 1) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(EverySimplifier, AbortContract,
  ::testing::Values("vtkQuadricTriangleCollapse", "vtkTriangleCollapseHierarchy", "vtkPatchBoundaryMerge",
    "vtkHoleBumpRemoval", "vtkRetile", "vtkGreedyCutsSimplification", "vtkTopologicalNoiseRemoval"),
  [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

namespace
{
class DefaultTargetContract : public ::testing::TestWithParam<std::string>
{
};
}

// Nothing set (no count, no reduction, no error bound): the contract's default reduction in every
// simplifier that counts triangles (patch-boundary-merge used its chain tolerance 0.005 instead).
TEST_P(DefaultTargetContract, NothingSetIsTheDefaultReduction)
{
  vtkPolyData* sphere = nullptr;
  vtkSmartPointer<vtkPolyDataAlgorithm> filter = SimplifierOfSphere(GetParam(), 60, 60, sphere);
  filter->Update();
  const vtkIdType input = sphere->GetNumberOfPolys();
  const vtkIdType target = slod::TargetTriangleCount(input, 0, slod::DefaultTargetReduction, false);
  const vtkIdType output = filter->GetOutput()->GetNumberOfPolys();
  EXPECT_LE(output, target + target / 50) << GetParam();
  EXPECT_GE(output, target / 2) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(CountingSimplifiers, DefaultTargetContract,
  ::testing::Values("vtkQuadricTriangleCollapse", "vtkTriangleCollapseHierarchy", "vtkPatchBoundaryMerge"),
  [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

namespace
{
// Counts the warnings that say a target was not reached.
struct TargetWarnings : vtkCommand
{
  static TargetWarnings* New() { return new TargetWarnings; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (data && std::string(static_cast<const char*>(data)).find("not reached") != std::string::npos)
    {
      ++this->NotReached;
    }
  }
  int NotReached = 0;
};

bool SetCountAlone(vtkAlgorithm* algorithm, vtkIdType count)
{
  vtkSimplificationAlgorithm* filter = vtkSimplificationAlgorithm::SafeDownCast(algorithm);
  if (filter)
  {
    filter->SetTargetNumberOfTriangles(count);
  }
  return filter != nullptr;
}

vtkIdType FieldValue(vtkPolyData* output, const char* name)
{
  vtkDataArray* array = output->GetFieldData()->GetArray(name);
  return array && array->GetNumberOfTuples() == 1 ? static_cast<vtkIdType>(array->GetComponent(0, 0)) : -2;
}

class CountAloneContract : public ::testing::TestWithParam<std::string>
{
};
}

// TargetNumberOfTriangles alone (no reduction, no error bound): every filter that simplifies to a
// count gives that count, or says in its output's field data and in a warning that it did not.
// Given: at most the count and no fewer than half of it; either way the field data names the count.
TEST_P(CountAloneContract, ThatCountOrAnHonestNotReached)
{
  vtkPolyData* sphere = nullptr;
  vtkSmartPointer<vtkPolyDataAlgorithm> filter = SimplifierOfSphere(GetParam(), 56, 44, sphere);
  const vtkIdType count = sphere->GetNumberOfPolys() / 7;
  ASSERT_TRUE(SetCountAlone(filter, count)) << GetParam();
  vtkNew<TargetWarnings> warnings;
  filter->AddObserver(vtkCommand::WarningEvent, warnings);
  filter->Update();
  vtkPolyData* output = filter->GetOutput();
  EXPECT_EQ(FieldValue(output, "TargetNumberOfTriangles"), count) << GetParam();
  EXPECT_EQ(vtkSimplificationAlgorithm::SafeDownCast(filter)->ComputeTargetNumberOfTriangles(sphere->GetNumberOfPolys()),
    count)
    << GetParam();
  const vtkIdType reached = FieldValue(output, "TargetReached");
  ASSERT_TRUE(reached == 0 || reached == 1) << GetParam() << ": no TargetReached in the field data";
  if (reached == 1)
  {
    EXPECT_LE(output->GetNumberOfPolys(), count) << GetParam();
    EXPECT_GE(output->GetNumberOfPolys(), count / 2) << GetParam();
    EXPECT_EQ(warnings->NotReached, 0) << GetParam();
  }
  else
  {
    EXPECT_EQ(warnings->NotReached, 1) << GetParam();
  }
}

INSTANTIATE_TEST_SUITE_P(EveryCountingSimplifier, CountAloneContract,
  ::testing::Values("vtkQuadricTriangleCollapse", "vtkTriangleCollapseHierarchy", "vtkPatchBoundaryMerge",
    "vtkHoleBumpRemoval", "vtkRetile", "vtkGreedyCutsSimplification"),
  [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

namespace
{
class DeclaredOnceContract : public ::testing::TestWithParam<std::string>
{
};
}

// The targets are the base class's (vtkSimplificationAlgorithm): a reduction alone set through it
// is the count the filter reports having aimed at, and ComputeTargetNumberOfTriangles says it
// before the run. The error-bounded simplifiers share MaximumError through their own base.
TEST_P(DeclaredOnceContract, TheBaseClassTargetIsTheFiltersTarget)
{
  vtkPolyData* sphere = nullptr;
  vtkSmartPointer<vtkPolyDataAlgorithm> filter = SimplifierOfSphere(GetParam(), 52, 40, sphere);
  vtkSimplificationAlgorithm* simplifier = vtkSimplificationAlgorithm::SafeDownCast(filter);
  ASSERT_NE(simplifier, nullptr) << GetParam() << " does not derive from vtkSimplificationAlgorithm";
  const bool errorBounded = GetParam() == "vtkQuadricTriangleCollapse" || GetParam() == "vtkPatchBoundaryMerge" ||
    GetParam() == "vtkGreedyCutsSimplification";
  EXPECT_EQ(vtkErrorBoundedSimplificationAlgorithm::SafeDownCast(filter) != nullptr, errorBounded) << GetParam();
  simplifier->SetTargetReduction(0.8);
  const vtkIdType expected = simplifier->ComputeTargetNumberOfTriangles(sphere->GetNumberOfPolys());
  EXPECT_EQ(expected, slod::TargetTriangleCount(static_cast<slod::Index>(sphere->GetNumberOfPolys()), 0, 0.8, false))
    << GetParam();
  filter->Update();
  EXPECT_EQ(FieldValue(filter->GetOutput(), "TargetNumberOfTriangles"), expected) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(EveryCountingSimplifier, DeclaredOnceContract,
  ::testing::Values("vtkQuadricTriangleCollapse", "vtkTriangleCollapseHierarchy", "vtkPatchBoundaryMerge",
    "vtkHoleBumpRemoval", "vtkRetile", "vtkGreedyCutsSimplification"),
  [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });
