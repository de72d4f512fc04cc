#include "Methods.h"

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
#include "vtkTriangleCollapseHierarchy.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

namespace slodcli
{
bool TargetReached(vtkPolyData* output, const MethodSettings& settings)
{
  // A filter of the project says it in its field data (it knows when an error bound stopped it
  // first); for the others a count target is reached when the count is at most the target.
  if (vtkDataArray* reached = output->GetFieldData()->GetArray("TargetReached"))
  {
    return reached->GetNumberOfTuples() > 0 && reached->GetTuple1(0) != 0;
  }
  if (settings.Level >= 0 || (settings.HasMaximumError && settings.TargetTriangles <= 0 && settings.TargetReduction < 0))
  {
    return true;
  }
  const double target = settings.TargetTriangles > 0 ? double(settings.TargetTriangles)
                                                     : std::floor((1.0 - settings.ReductionFraction()) * settings.InputTriangles + 1e-9);
  return double(output->GetNumberOfPolys()) <= target;
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
Method SurfaceLODMethod(const char* name, const char* description)
{
  return { name, description, HasMaximumError<Filter>::value, &CreateSurfaceLODFilter<Filter> };
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
    filter->SetMaximumErrorRelative(false);
  }
  else
  {
    filter->SetMaximumErrorRelative(true);
    filter->SetMaximumError(0.1);
  }
  return generic;
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
      false, &CreateVTKQuadricDecimation, false, true, /*PreparesItsInput=*/false },
    { "vtk-decimate-pro", "VTK's vtkDecimatePro with PreserveTopologyOn (vertex removal)",
      true, &CreateVTKDecimatePro, false, true, /*PreparesItsInput=*/false },
    // SurfaceLOD filters, one line each (and the header include above).
    SurfaceLODMethod<vtkQuadricTriangleCollapse>("quadric-triangle-collapse",
      "Pan, Zhou, Shi 2000: quadric-error triangle collapses (with edge collapses), original-surface error"),
    { "triangle-collapse-hierarchy", "Gieng et al. 1997: batches of triangle collapses on quadratic fits, "
      "levels M0..Mn with smooth blending (also --level i+t)", false, &CreateTriangleCollapseHierarchy, true },
    SurfaceLODMethod<vtkPatchBoundaryMerge>("patch-boundary-merge",
      "Ho 1999 ch. 4 (SPBM): planar patches, simplified boundaries, ear-clipped; original vertices only"),
    SurfaceLODMethod<vtkHoleBumpRemoval>("hole-bump-removal",
      "Ho 1999 ch. 5: removes small holes, bumps, cavities (sharp loops below 0.05 of the diagonal) and "
      "cracks, then SPBM to the target"),
    SurfaceLODMethod<vtkRetile>("retile",
      "Turk 1992: re-tiling with evenly spread new vertices (point repulsion, mutual tessellation)"),
    { "greedy-cuts", "Ho 1999 ch. 3: greedy cuts (ears, bites) per patch, output guaranteed within --max-error "
      "(two-sided Hausdorff) of the input; a target searches the error; original vertices only",
      true, &CreateGreedyCuts, false, /*InDefaultRuns=*/false },
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
