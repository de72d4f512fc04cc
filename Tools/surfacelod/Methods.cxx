// SPDX-License-Identifier: BSD-3-Clause
#include "Methods.h"

#include "CliSupport.h"

#include "vtkDataArray.h"
#include "vtkDecimatePro.h"
#include "vtkFieldData.h"
#include "vtkPolyData.h"
#include "vtkQuadricDecimation.h"

// SurfaceLOD filters: add the include here and one line in the table below.
#include "vtkGreedyCutsSimplification.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkPatchBoundaryMerge.h"
#include "vtkQuadricTriangleCollapse.h"
#include "vtkRetile.h"
#include "vtkTopologicalNoiseRemoval.h"
#include "vtkTriangleCollapseHierarchy.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <strings.h>
#include <type_traits>
#include <limits>
#include <utility>

namespace slodcli
{
int ReportedTargetReached(vtkPolyData* output)
{
  vtkDataArray* reached = output->GetFieldData()->GetArray("TargetReached");
  if (!reached)
  {
    return -1;
  }
  return reached->GetNumberOfTuples() > 0 && reached->GetTuple1(0) != 0 ? 1 : 0;
}

bool TargetReached(vtkIdType outputTriangles, int reported, const MethodSettings& settings)
{
  // A filter of the project says it in its field data (it knows when an error bound stopped it
  // first); for the others a count target is reached when the count is at most the target.
  if (reported >= 0)
  {
    return reported == 1;
  }
  if (settings.Level >= 0 || (settings.HasMaximumError && settings.TargetTriangles <= 0 && settings.TargetReduction < 0))
  {
    return true;
  }
  const double target = settings.TargetTriangles > 0 ? double(settings.TargetTriangles)
                                                     : std::floor((1.0 - settings.ReductionFraction()) * settings.InputTriangles + 1e-9);
  return double(outputTriangles) <= target;
}

bool TargetReached(vtkPolyData* output, const MethodSettings& settings)
{
  return TargetReached(output->GetNumberOfPolys(), ReportedTargetReached(output), settings);
}

double MethodSettings::ReductionFraction() const
{
  if (this->TargetTriangles > 0)
  {
    if (this->InputTriangles <= 0)
    {
      return 0.0;
    }
    return std::clamp(1.0 - double(this->TargetTriangles) / double(this->InputTriangles), 0.0, 1.0);
  }
  return std::clamp(this->TargetReduction, 0.0, 1.0);
}

namespace
{
template <typename Filter, typename = void>
struct HasMaximumError : std::false_type
{
};
template <typename Filter>
struct HasMaximumError<Filter, std::void_t<decltype(std::declval<Filter&>().SetMaximumError(0.0))>>
  : std::true_type
{
};

template <typename Filter, typename = void>
struct HasController : std::false_type
{
};
template <typename Filter>
struct HasController<Filter, std::void_t<decltype(std::declval<Filter&>().SetController(nullptr))>>
  : std::true_type
{
};

// --- What `--set` may change, one line per parameter: SLOD_PARAMETER(filter class, type, property).
// The type is what the property means (a vtkTypeBool flag is Bool); the default shown by `methods
// --verbose` is read from the tool's filter. Left out: the target and error bound (-t, -r, -e, -l),
// and switches that add outputs the tool does not write (GenerateAllLevels, GenerateProgressiveMesh...).
// value in the property's type; an integer out of the type's range becomes its nearest bound (so
// that the read-back of ParseAssignments sees the difference) instead of an undefined conversion.
template <typename Value>
Value ToPropertyValue(double value)
{
  if constexpr (std::is_integral<Value>::value && !std::is_same<Value, bool>::value)
  {
    return static_cast<Value>(std::clamp(value, double(std::numeric_limits<Value>::lowest()),
      double(std::numeric_limits<Value>::max())));
  }
  return static_cast<Value>(value);
}

#define SLOD_PARAMETER(FilterClass, Kind, Property)                                                      \
  Parameter                                                                                              \
  {                                                                                                      \
    #Property, ParameterType::Kind,                                                                      \
      [](vtkPolyDataAlgorithm* filter) { return double(static_cast<FilterClass*>(filter)->Get##Property()); }, \
      [](vtkPolyDataAlgorithm* filter, double value) {                                                   \
        auto* typed = static_cast<FilterClass*>(filter);                                                 \
        typed->Set##Property(ToPropertyValue<decltype(typed->Get##Property())>(value));                  \
      }                                                                                                  \
  }

// clang-format off
std::vector<Parameter> QuadricDecimationParameters()
{
  return {
    SLOD_PARAMETER(vtkQuadricDecimation, Bool, AttributeErrorMetric),
    SLOD_PARAMETER(vtkQuadricDecimation, Bool, VolumePreservation),
    SLOD_PARAMETER(vtkQuadricDecimation, Bool, ScalarsAttribute),
    SLOD_PARAMETER(vtkQuadricDecimation, Bool, VectorsAttribute),
    SLOD_PARAMETER(vtkQuadricDecimation, Bool, NormalsAttribute),
    SLOD_PARAMETER(vtkQuadricDecimation, Bool, TCoordsAttribute),
    SLOD_PARAMETER(vtkQuadricDecimation, Bool, TensorsAttribute),
    SLOD_PARAMETER(vtkQuadricDecimation, Double, ScalarsWeight),
    SLOD_PARAMETER(vtkQuadricDecimation, Double, VectorsWeight),
    SLOD_PARAMETER(vtkQuadricDecimation, Double, NormalsWeight),
    SLOD_PARAMETER(vtkQuadricDecimation, Double, TCoordsWeight),
    SLOD_PARAMETER(vtkQuadricDecimation, Double, TensorsWeight),
  };
}

std::vector<Parameter> DecimateProParameters()
{
  return {
    SLOD_PARAMETER(vtkDecimatePro, Bool, PreserveTopology),
    SLOD_PARAMETER(vtkDecimatePro, Double, FeatureAngle),
    SLOD_PARAMETER(vtkDecimatePro, Bool, Splitting),
    SLOD_PARAMETER(vtkDecimatePro, Double, SplitAngle),
    SLOD_PARAMETER(vtkDecimatePro, Bool, PreSplitMesh),
    SLOD_PARAMETER(vtkDecimatePro, Double, MaximumError),
    SLOD_PARAMETER(vtkDecimatePro, Bool, AccumulateError),
    SLOD_PARAMETER(vtkDecimatePro, Bool, ErrorIsAbsolute),
    SLOD_PARAMETER(vtkDecimatePro, Bool, BoundaryVertexDeletion),
    SLOD_PARAMETER(vtkDecimatePro, Int, Degree),
    SLOD_PARAMETER(vtkDecimatePro, Double, InflectionPointRatio),
    SLOD_PARAMETER(vtkDecimatePro, Int, OutputPointsPrecision),
  };
}

std::vector<Parameter> QuadricTriangleCollapseParameters()
{
  return {
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, MaximumErrorIsRelative),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, BoundaryWeight),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, MaximumNormalDeviation),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, AllowTopologyChange),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, EdgeCollapses),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, EdgeCollapseBias),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, DeviationRefinement),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, FitToOriginal),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, ExactUnion),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, BatchCollapses),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, BatchCostTolerance),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Int, BatchMinimumSize),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Int, CollapseSchedule),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, PassGoalShare),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, PassErrorFactor),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, PassRemovalShare),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Int, LookAheadEvaluations),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, TriangleCostBound),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Int, FitExactAssignmentLimit),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, PreserveAttributeSeams),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Bool, AttributeErrorMetric),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, ScalarsWeight),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, VectorsWeight),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, NormalsWeight),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, TCoordsWeight),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Double, TensorsWeight),
    SLOD_PARAMETER(vtkQuadricTriangleCollapse, Int, OutputPointsPrecision),
  };
}

std::vector<Parameter> TriangleCollapseHierarchyParameters()
{
  return {
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, CurvatureWeight),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, AngleWeight),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, ValenceWeight),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, ErrorWeight),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, QuadricCollapsePoint),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, BatchFraction),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, BatchSearchDepth),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, MaximumWeight),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, ValenceNormalizer),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, RemoveCycles),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, StarShapedInStencilPlane),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, SwapBlockingEdges),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, SwapMinimumNormalDot),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, SwapMinimumNormalDotWhenBlocked),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, RelaxWhenBlocked),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Int, EdgeCollapses),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, PreferEdgeFactor),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, PreventNewValenceThree),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, VertexErrorWeight),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, BoundaryWeight),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Int, MaximumNumberOfLevels),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Int, MinimumNumberOfTriangles),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Double, MinimumNormalDot),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, ExpandFromCoarsestLevel),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, DecideAhead),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, ParallelCollapses),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Bool, ParallelBookkeeping),
    SLOD_PARAMETER(vtkTriangleCollapseHierarchy, Int, OutputPointsPrecision),
  };
}

std::vector<Parameter> PatchBoundaryMergeParameters()
{
  return {
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, PatchAngle),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, NeighborAngle),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, TwoEdgePatchAngle),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, TwoEdgeNeighborAngle),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, PatchPlaneDistance),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, PatchDeviationFactor),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, PatchNoiseTolerance),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, BorderCornerAngle),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, AdaptPatchesToTarget),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, LoosenThicknessForTarget),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, CollapseFinerLevelForTarget),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, RefineDeviatingRegions),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, MildTargetRegionAllowance),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, LateFailureShare),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, AreaWeightedNormals),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, MaximumErrorIsRelative),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, MergeAngle),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, MergePatches),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, CollapseChains),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, CollapseLengthFactor),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, SizeWeightedMerge),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, CompareCandidates),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, CostOrderedRemoval),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Double, ChainInPlaneWeight),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Bool, MinimumDeviationTriangulation),
    SLOD_PARAMETER(vtkPatchBoundaryMerge, Int, OutputPointsPrecision),
  };
}

std::vector<Parameter> HoleBumpRemovalParameters()
{
  return {
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, SharpAngle),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, MaximumSharpAngle),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, FeatureSize),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Bool, FeatureSizeIsRelative),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Bool, RemoveHoles),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Bool, RemoveBumps),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Bool, RemoveCavities),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Bool, FillCracks),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, MaximumCrackSize),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Int, MaximumPasses),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, MergeAngle),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, PatchAngle),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, NeighborAngle),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, PatchPlaneDistance),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Int, Completion),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, Epsilon),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Bool, FinalCollapses),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Bool, SingleMergeMeasure),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Double, SingleMeasureNoisyBendShare),
    SLOD_PARAMETER(vtkHoleBumpRemoval, Int, OutputPointsPrecision),
  };
}

std::vector<Parameter> TopologicalNoiseRemovalParameters()
{
  return {
    SLOD_PARAMETER(vtkTopologicalNoiseRemoval, Double, FeatureSize),
    SLOD_PARAMETER(vtkTopologicalNoiseRemoval, Bool, FeatureSizeIsRelative),
    SLOD_PARAMETER(vtkTopologicalNoiseRemoval, Bool, RemoveHandles),
    SLOD_PARAMETER(vtkTopologicalNoiseRemoval, Bool, RemoveComponents),
    SLOD_PARAMETER(vtkTopologicalNoiseRemoval, Int, MaximumPasses),
    SLOD_PARAMETER(vtkTopologicalNoiseRemoval, Int, SeparationSearchBudget),
    SLOD_PARAMETER(vtkTopologicalNoiseRemoval, Bool, SplitNonManifold),
    SLOD_PARAMETER(vtkTopologicalNoiseRemoval, Double, KeptHandleSurveyFactor),
    SLOD_PARAMETER(vtkTopologicalNoiseRemoval, Int, OutputPointsPrecision),
  };
}

std::vector<Parameter> RetileParameters()
{
  return {
    SLOD_PARAMETER(vtkRetile, Int, NumberOfPoints),
    SLOD_PARAMETER(vtkRetile, Int, RepulsionIterations),
    SLOD_PARAMETER(vtkRetile, Double, CurvatureWeight),
    SLOD_PARAMETER(vtkRetile, Bool, FilletDensity),
    SLOD_PARAMETER(vtkRetile, Int, RandomSeed),
    SLOD_PARAMETER(vtkRetile, Int, ShapeImprovementPasses),
    SLOD_PARAMETER(vtkRetile, Bool, PreserveCreases),
    SLOD_PARAMETER(vtkRetile, Bool, EnforceFacing),
    SLOD_PARAMETER(vtkRetile, Bool, RetriangulateRings),
    SLOD_PARAMETER(vtkRetile, Bool, RingSearchFacesInput),
    SLOD_PARAMETER(vtkRetile, Bool, RepairFlippedTiles),
    SLOD_PARAMETER(vtkRetile, Bool, RepairNeedleTiles),
    SLOD_PARAMETER(vtkRetile, Bool, RepelFromLineGaps),
    SLOD_PARAMETER(vtkRetile, Bool, SlideAlongCreases),
    SLOD_PARAMETER(vtkRetile, Bool, MoveRetainedVertices),
    SLOD_PARAMETER(vtkRetile, Double, FeatureAngle),
    SLOD_PARAMETER(vtkRetile, Int, OutputPointsPrecision),
  };
}

std::vector<Parameter> GreedyCutsParameters()
{
  return {
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Bool, MaximumErrorIsRelative),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Int, TargetSearchSteps),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Double, PatchAngle),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Double, NeighborAngle),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Double, TwoEdgePatchAngle),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Double, TwoEdgeNeighborAngle),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Int, BiteCandidates),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Double, MinimumTriangleAngle),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Double, ShapedTriangleAngle),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Double, EarShapeAngle),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Bool, FinalCollapses),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Bool, BorderCollapses),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Bool, EarlySliverStep),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Int, PassOrderBands),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Bool, LocalSplitRounds),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Bool, MonotoneInEpsilon),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Int, CollapseStages),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Double, LadderBottom),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Bool, LadderOwnRuns),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Bool, LadderCollapsesOnly),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Int, Patchification),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Int, MinimumPatchTriangles),
    SLOD_PARAMETER(vtkGreedyCutsSimplification, Int, OutputPointsPrecision),
  };
}
// clang-format on
#undef SLOD_PARAMETER

// Every SurfaceLOD filter follows one convention (SetTargetNumberOfTriangles, SetTargetReduction,
// SetMaximumError), so one factory serves them all.
template <typename Filter>
vtkSmartPointer<vtkPolyDataAlgorithm> CreateSurfaceLODFilter(const MethodSettings& settings)
{
  auto filter = vtkSmartPointer<Filter>::New();
  // The filters stop at whichever target is reached first (0 = unused), and their default
  // TargetReduction may be non-zero: set both, the one not asked for to 0.
  if (settings.TargetTriangles > 0)
  {
    filter->SetTargetNumberOfTriangles(settings.TargetTriangles);
    filter->SetTargetReduction(0.0);
  }
  else if (settings.TargetReduction > 0.0)
  {
    filter->SetTargetNumberOfTriangles(0);
    filter->SetTargetReduction(settings.TargetReduction);
  }
  else
  {
    // A reduction of 0 keeps every triangle.
    filter->SetTargetNumberOfTriangles(std::max<vtkIdType>(settings.InputTriangles, 1));
    filter->SetTargetReduction(0.0);
  }
  if constexpr (HasMaximumError<Filter>::value)
  {
    if (settings.HasMaximumError)
    {
      filter->SetMaximumError(settings.MaximumError);
    }
  }
  return filter;
}

// One registry entry for a SurfaceLOD filter; --max-error is offered when it has SetMaximumError.
template <typename Filter>
Method SurfaceLODMethod(const char* name, const char* description, std::vector<Parameter> parameters)
{
  Method method{ name, description, HasMaximumError<Filter>::value, &CreateSurfaceLODFilter<Filter>, parameters };
  method.SimplifiesPieces = HasController<Filter>::value;
  return method;
}

// The hierarchy also shows a (real-valued) level: M_i(t) for --level i+t.
vtkSmartPointer<vtkPolyDataAlgorithm> CreateTriangleCollapseHierarchy(const MethodSettings& settings)
{
  // The CLI writes output 0 only: no multiblock of every level (a copy of each level).
  if (settings.Level < 0)
  {
    vtkSmartPointer<vtkPolyDataAlgorithm> filter = CreateSurfaceLODFilter<vtkTriangleCollapseHierarchy>(settings);
    vtkTriangleCollapseHierarchy::SafeDownCast(filter)->GenerateAllLevelsOff();
    return filter;
  }
  auto filter = vtkSmartPointer<vtkTriangleCollapseHierarchy>::New();
  filter->GenerateAllLevelsOff();
  filter->SetContinuousLevel(settings.Level);
  return filter;
}

// Greedy cuts: --max-error is absolute (the guaranteed Hausdorff bound); a target alone searches
// epsilon up to 0.1 of the diagonal.
vtkSmartPointer<vtkPolyDataAlgorithm> CreateGreedyCuts(const MethodSettings& settings)
{
  auto generic = CreateSurfaceLODFilter<vtkGreedyCutsSimplification>(settings);
  auto* filter = vtkGreedyCutsSimplification::SafeDownCast(generic);
  if (settings.HasMaximumError)
  {
    filter->SetMaximumErrorIsRelative(false);
  }
  else
  {
    filter->SetMaximumErrorIsRelative(true);
    filter->SetMaximumError(0.1);
  }
  return generic;
}

// Topological noise removal takes a feature size, not a target: --feature-size F is absolute
// (FeatureSizeIsRelative off); without it the filter's default (0.01 of the diagonal) applies.
vtkSmartPointer<vtkPolyDataAlgorithm> CreateTopologicalNoiseRemoval(const MethodSettings& settings)
{
  auto filter = vtkSmartPointer<vtkTopologicalNoiseRemoval>::New();
  if (settings.FeatureSize >= 0)
  {
    filter->SetFeatureSize(settings.FeatureSize);
    filter->FeatureSizeIsRelativeOff();
  }
  return filter;
}

vtkSmartPointer<vtkPolyDataAlgorithm> CreateVTKQuadricDecimation(const MethodSettings& settings)
{
  auto filter = vtkSmartPointer<vtkQuadricDecimation>::New();
  filter->SetTargetReduction(settings.ReductionFraction());
  return filter;
}

vtkSmartPointer<vtkPolyDataAlgorithm> CreateVTKDecimatePro(const MethodSettings& settings)
{
  auto filter = vtkSmartPointer<vtkDecimatePro>::New();
  filter->SetTargetReduction(settings.ReductionFraction());
  filter->PreserveTopologyOn();
  if (settings.HasMaximumError)
  {
    filter->SetErrorIsAbsolute(1);
    filter->SetAbsoluteError(settings.MaximumError);
  }
  return filter;
}
} // namespace

const std::vector<Method>& Methods()
{
  // clang-format off
  static const std::vector<Method> methods = {
    { "vtk-quadric-decimation", "VTK's vtkQuadricDecimation (Garland-Heckbert edge collapse), the baseline",
      false, &CreateVTKQuadricDecimation, QuadricDecimationParameters(), false, true, /*PreparesItsInput=*/false },
    { "vtk-decimate-pro", "VTK's vtkDecimatePro with PreserveTopologyOn (vertex removal)",
      true, &CreateVTKDecimatePro, DecimateProParameters(), false, true, /*PreparesItsInput=*/false },
    // SurfaceLOD filters, one line each (and the header include above).
    SurfaceLODMethod<vtkQuadricTriangleCollapse>("quadric-triangle-collapse",
      "Pan, Zhou, Shi 2000: quadric-error triangle collapses (with edge collapses), original-surface error", QuadricTriangleCollapseParameters()),
    { "triangle-collapse-hierarchy", "Gieng et al. 1997: batches of triangle collapses on quadratic fits, "
      "levels M0..Mn with smooth blending (also --level i+t)", false, &CreateTriangleCollapseHierarchy,
      TriangleCollapseHierarchyParameters(), true },
    SurfaceLODMethod<vtkPatchBoundaryMerge>("patch-boundary-merge",
      "Ho 1999 ch. 4 (SPBM): planar patches, simplified boundaries, ear-clipped; original vertices only", PatchBoundaryMergeParameters()),
    SurfaceLODMethod<vtkHoleBumpRemoval>("hole-bump-removal",
      "Ho 1999 ch. 5: removes small holes, bumps, cavities (sharp loops below 0.05 of the diagonal) and "
      "cracks, then SPBM to the target", HoleBumpRemovalParameters()),
    SurfaceLODMethod<vtkRetile>("retile",
      "Turk 1992: re-tiling with evenly spread new vertices (point repulsion, mutual tessellation)", RetileParameters()),
    { "topological-noise-removal", "Guskov & Wood 2001: cuts and fills handles and tunnels whose shortest loop "
      "is at most pi * --feature-size long, removes smaller components and cavities (no target)",
      false, &CreateTopologicalNoiseRemoval, TopologicalNoiseRemovalParameters(), false, /*InDefaultRuns=*/false,
      /*PreparesItsInput=*/true, /*NeedsTarget=*/false },
    { "greedy-cuts", "Ho 1999 ch. 3: greedy cuts (ears, bites) per patch, output guaranteed within --max-error "
      "(two-sided Hausdorff) of the input; a target searches the error; original vertices only",
      true, &CreateGreedyCuts, GreedyCutsParameters(), false, /*InDefaultRuns=*/false },
  };
  // clang-format on
  return methods;
}

const Method* FindMethod(const std::string& name)
{
  for (const Method& m : Methods())
  {
    if (name == m.Name)
    {
      return &m;
    }
  }
  return nullptr;
}

std::string MethodNames(const std::string& separator)
{
  std::string names;
  for (const Method& m : Methods())
  {
    names += (names.empty() ? "" : separator) + std::string(m.Name);
  }
  return names;
}
} // namespace slodcli

namespace slodcli
{
namespace
{
// A --set value as the parameter's type: false when the text is not one.
bool ParseParameterValue(ParameterType type, const std::string& text, double& value)
{
  if (type == ParameterType::Bool)
  {
    for (const char* word : { "1", "true", "on", "yes" })
    {
      if (strcasecmp(text.c_str(), word) == 0)
      {
        value = 1.0;
        return true;
      }
    }
    for (const char* word : { "0", "false", "off", "no" })
    {
      if (strcasecmp(text.c_str(), word) == 0)
      {
        value = 0.0;
        return true;
      }
    }
    return false;
  }
  char* end = nullptr;
  errno = 0;
  if (type == ParameterType::Int)
  {
    const long long integer = std::strtoll(text.c_str(), &end, 10);
    value = double(integer);
    return !text.empty() && *end == '\0' && errno != ERANGE && std::llabs(integer) < (1LL << 53);
  }
  value = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && std::isfinite(value);
}

std::string FormatParameterValue(ParameterType type, double value)
{
  if (type == ParameterType::Bool)
  {
    return value != 0.0 ? "true" : "false";
  }
  if (type == ParameterType::Int)
  {
    return std::to_string(static_cast<long long>(value));
  }
  char text[64]; // the shortest text that reads back as the same double
  return std::string(text, std::to_chars(text, text + sizeof(text), value).ptr);
}

// The filter the tool makes for a method before any --set (its defaults are what --set changes).
vtkSmartPointer<vtkPolyDataAlgorithm> ToolDefaultFilter(const Method& method)
{
  MethodSettings settings;
  settings.TargetReduction = 0.5;
  return method.Create(settings);
}
} // namespace

vtkSmartPointer<vtkPolyDataAlgorithm> CreateFilter(
  const Method& method, const MethodSettings& settings, const std::vector<ParameterAssignment>& assignments)
{
  vtkSmartPointer<vtkPolyDataAlgorithm> filter = method.Create(settings);
  for (const ParameterAssignment& assignment : assignments)
  {
    assignment.Target->Set(filter, assignment.Value);
  }
  return filter;
}

std::vector<ParameterAssignment> ParseAssignments(const Method& method, const std::vector<std::string>& texts)
{
  const std::vector<Parameter>& parameters = method.Parameters;
  vtkSmartPointer<vtkPolyDataAlgorithm> probe = ToolDefaultFilter(method);
  std::vector<ParameterAssignment> assignments;
  for (const std::string& text : texts)
  {
    const size_t equals = text.find('=');
    const std::string name = text.substr(0, equals);
    auto found = std::find_if(parameters.begin(), parameters.end(),
      [&name](const Parameter& p) { return name == p.Name; });
    const std::string context = "surfacelod simplify: --set " + text + ": ";
    if (equals == std::string::npos || found == parameters.end())
    {
      throw CliError(ExitUsage, context + (equals == std::string::npos ? "expected Name=Value" :
          "method " + std::string(method.Name) + " has no parameter '" + name + "' (`surfacelod methods --verbose` lists them)"));
    }
    double value = 0.0;
    if (!ParseParameterValue(found->Type, text.substr(equals + 1), value))
    {
      throw CliError(ExitUsage, context + "'" + text.substr(equals + 1) + "' is not a " + ParameterTypeName(found->Type));
    }
    // The filters clamp a value out of their range silently: refuse it instead.
    found->Set(probe, value);
    if (found->Get(probe) != value)
    {
      throw CliError(ExitUsage, context + "out of the parameter's range (the filter would use " +
          FormatParameterValue(found->Type, found->Get(probe)) + ")");
    }
    assignments.push_back({ &*found, value });
  }
  return assignments;
}

std::string ParameterDefault(const Method& method, const Parameter& parameter)
{
  return FormatParameterValue(parameter.Type, parameter.Get(ToolDefaultFilter(method)));
}

const char* ParameterTypeName(ParameterType type)
{
  switch (type)
  {
    case ParameterType::Bool: return "bool";
    case ParameterType::Int: return "int";
    default: return "double";
  }
}
} // namespace slodcli
