// SPDX-License-Identifier: BSD-3-Clause
#include "vtkGreedyCutsSimplification.h"

#include "slodAttributeTransfer.h"
#include "slodGreedyCuts.h"
#include "slodInputPreparation.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkGreedyCutsSimplification);

namespace
{
// The simplified surface over the original vertices that are used (in order of first use), its
// triangles' patch ids and the error bound (absolute and relative to the bounding-box diagonal).
void StoreSimplification(vtkPolyData* input, const slod::TriangleMesh& mesh,
  const std::vector<slod::Index>& vertexToInput, const std::vector<slod::Index>& triangleToCell,
  const slod::GreedyCutsResult& result, int outputPointsPrecision, vtkPolyData* output)
{
  const double diagonal = mesh.BoundingBoxDiagonal();
  slod::FirstUseNumbering numbering(mesh.NumberOfPoints());
  const std::vector<slod::Index>& used = numbering.Used;
  vtkNew<vtkCellArray> polys;
  const vtkIdType nt = static_cast<vtkIdType>(result.TrianglePatch.size());
  polys->AllocateExact(nt, 3 * nt);
  for (vtkIdType t = 0; t < nt; ++t)
  {
    vtkIdType ids[3];
    for (int k = 0; k < 3; ++k)
    {
      ids[k] = numbering(result.Triangles[3 * size_t(t) + k]);
    }
    polys->InsertNextCell(3, ids);
  }
  slod::StoreUsedPoints(input, mesh, used, vertexToInput, outputPointsPrecision, output);
  vtkNew<vtkIntArray> patchIds;
  patchIds->SetName("PatchId");
  patchIds->SetNumberOfValues(nt);
  for (vtkIdType t = 0; t < nt; ++t)
  {
    patchIds->SetValue(t, result.TrianglePatch[size_t(t)]);
  }
  output->SetPolys(polys);
  slod::StoreNearestCellData(input, triangleToCell, mesh, mesh.Points, result.Triangles, output);
  output->GetCellData()->AddArray(patchIds);
  vtkNew<vtkDoubleArray> boundArray;
  boundArray->SetName("MaximumErrorBound");
  boundArray->InsertNextValue(result.ErrorBound);
  vtkNew<vtkDoubleArray> relativeArray;
  relativeArray->SetName("MaximumErrorBoundRelative");
  relativeArray->InsertNextValue(diagonal > 0 ? result.ErrorBound / diagonal : 0.0);
  output->GetFieldData()->AddArray(boundArray);
  output->GetFieldData()->AddArray(relativeArray);
  // Patches whose greedy triangulation failed even after the front repairs and refined chains:
  // kept as their original triangles (the goal is none), and the repairs done (section 3.4.3).
  for (const auto& [name, value] : { std::pair<const char*, long long>{ "FallbackPatches", result.OriginalPatches },
         { "FrontRepairs", result.Repairs }, { "EdgeSwaps", result.EdgeSwaps }, { "FaceSplits", result.FaceSplits },
         { "VertexDeletions", result.VertexDeletions }, { "FinalCollapses", result.FinalCollapses } })
  {
    vtkNew<vtkIdTypeArray> counter;
    counter->SetName(name);
    counter->InsertNextValue(static_cast<vtkIdType>(value));
    output->GetFieldData()->AddArray(counter);
  }
}
} // namespace

// Ho's epsilon is the filter's whole point: bounded by default, relative to the diagonal (0.005).
vtkGreedyCutsSimplification::vtkGreedyCutsSimplification()
{
  this->MaximumError = 0.005;
  this->MaximumErrorIsRelative = true;
}

int vtkGreedyCutsSimplification::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!input || !output)
  {
    return 0;
  }
  this->UsedMaximumError = 0;
  this->NumberOfPatches = this->RefinedPatches = this->OriginalPatches = 0;
  this->NumberOfEars = this->NumberOfBites = this->NumberOfRepairs = this->NumberOfFinalCollapses = 0;

  slod::TriangleMesh mesh;
  std::vector<slod::Index> vertexToInput, triangleToCell;
  // Non-manifold input is accepted: the triangles at its non-manifold vertices are kept as they are
  // (slod::GreedyCuts::Initialize), so no non-manifold edge is cut open or closed.
  if (!slod::PrepareFilterTriangles(this, input, slod::PreparationOptions(), mesh, vertexToInput, nullptr,
        slod::CellMapIfNeeded(input, triangleToCell), { /*IsError=*/true }))
  {
    return 1;
  }
  const double diagonal = mesh.BoundingBoxDiagonal();

  // 1. Patchification.
  slod::PatchificationParameters patchParameters;
  patchParameters.OneEdgePatchAngle = this->PatchAngle;
  patchParameters.OneEdgeNeighborAngle = this->NeighborAngle;
  patchParameters.TwoEdgePatchAngle = this->TwoEdgePatchAngle;
  patchParameters.TwoEdgeNeighborAngle = this->TwoEdgeNeighborAngle;
  slod::TerrainPatchificationParameters terrain;
  terrain.MinimumPatchTriangles = this->MinimumPatchTriangles;
  slod::GreedyCuts cuts;
  cuts.Initialize(mesh, patchParameters, slod::FilterProgress(this, 0.0, 0.1),
    this->Patchification == CHAPTER3_TERRAIN_PATCHES ? &terrain : nullptr);
  if (cuts.Aborted())
  {
    slod::ReportAbort(this, output);
    return 1;
  }

  // 2. Greedy cuts at epsilon, or the epsilon search for a target.
  slod::GreedyCutsParameters parameters;
  parameters.BiteCandidates = this->BiteCandidates;
  parameters.MinimumAngle = this->MinimumTriangleAngle;
  parameters.ShapedAngle = this->ShapedTriangleAngle;
  parameters.EarShapeAngle = this->EarShapeAngle;
  parameters.FinalCollapses = this->FinalCollapses;
  parameters.BorderCollapses = this->BorderCollapses;
  parameters.EarlySliverStep = this->EarlySliverStep;
  parameters.PassOrderBands = this->PassOrderBands;
  parameters.LocalSplitRounds = this->LocalSplitRounds;
  parameters.CollapseStages = this->CollapseStages;
  parameters.LadderBottom = this->LadderBottom;
  parameters.LadderOwnRuns = this->LadderOwnRuns;
  parameters.LadderCollapsesOnly = this->LadderCollapsesOnly;
  const double bound = this->AbsoluteMaximumError(diagonal);
  vtkIdType target = 0;
  // The filter contract's targets (slodFilterContract.h); MaximumError is always a bound here, so
  // no target at all means the simplification within it (the paper's use).
  target = this->ComputeTargetNumberOfTriangles(mesh.NumberOfTriangles());
  slod::GreedyCutsResult result;
  const slod::ProgressFunction stage = slod::FilterProgress(this, 0.1, 0.95);
  if (target > 0 && target < mesh.NumberOfTriangles())
  {
    const double hi = bound > 0 ? bound : 0.1 * diagonal;
    const double lo = std::min(hi, 1e-5 * diagonal);
    if (!cuts.RunForTarget(static_cast<slod::Index>(std::min<vtkIdType>(target, VTK_INT_MAX)), parameters, lo, hi,
          this->TargetSearchSteps, result, stage))
    {
      slod::ReportAbort(this, output);
      return 1;
    }
    if (cuts.WorkBoundReached())
    {
      vtkWarningMacro(<< "The search for the target's tolerance stopped at its work bound; the smallest tolerance "
                      << "tried within the target is used.");
    }
  }
  else
  {
    parameters.Epsilon = target >= mesh.NumberOfTriangles() ? 0.0 : bound;
    const bool monotone = this->MonotoneInEpsilon && parameters.Epsilon > 0;
    if (!(monotone ? cuts.RunMonotone(parameters, result, stage) : cuts.Run(parameters, result, stage)))
    {
      slod::ReportAbort(this, output);
      return 1;
    }
    if (cuts.WorkBoundReached())
    {
      vtkWarningMacro(<< "The nested run over the tolerance ladder stopped at its work bound; the coarser levels "
                      << "keep the last finished one (still within the bound, never more triangles).");
    }
  }
  this->UsedMaximumError = result.ErrorBound;
  this->NumberOfPatches = result.NumberOfPatches;
  this->RefinedPatches = result.RefinedPatches;
  this->OriginalPatches = result.OriginalPatches;
  this->NumberOfEars = result.Ears;
  this->NumberOfBites = result.Bites + result.WideBites;
  this->NumberOfRepairs = result.Repairs;
  this->NumberOfFinalCollapses = result.FinalCollapses;

  // 3. Output.
  StoreSimplification(input, mesh, vertexToInput, triangleToCell, result, this->OutputPointsPrecision, output);
  if (target > 0 && target < mesh.NumberOfTriangles())
  {
    // The error bound wins over the target: the search never tries a larger tolerance.
    slod::ReportTarget(this, output, target, output->GetNumberOfPolys() <= target,
      "no tolerance tried up to the error bound (MaximumError, the upper end of the tolerance search) "
      "gave a coarser result");
  }
  this->UpdateProgress(1.0);
  return 1;
}

void vtkGreedyCutsSimplification::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetSearchSteps: " << this->TargetSearchSteps << "\n";
  os << indent << "Patchification: "
     << (this->Patchification == CHAPTER3_TERRAIN_PATCHES ? "chapter 3 terrain patches" : "chapter 4 patches") << "\n";
  os << indent << "MinimumPatchTriangles: " << this->MinimumPatchTriangles << "\n";
  os << indent << "BiteCandidates: " << this->BiteCandidates << "\n";
  os << indent << "MinimumTriangleAngle: " << this->MinimumTriangleAngle << "\n";
  os << indent << "ShapedTriangleAngle: " << this->ShapedTriangleAngle << "\n";
  os << indent << "EarShapeAngle: " << this->EarShapeAngle << "\n";
  os << indent << "FinalCollapses: " << (this->FinalCollapses ? "on" : "off") << "\n";
  os << indent << "BorderCollapses: " << (this->BorderCollapses ? "on" : "off") << "\n";
  os << indent << "EarlySliverStep: " << (this->EarlySliverStep ? "on" : "off") << "\n";
  os << indent << "PassOrderBands: " << this->PassOrderBands << "\n";
  os << indent << "LocalSplitRounds: " << (this->LocalSplitRounds ? "on" : "off") << "\n";
  os << indent << "CollapseStages: " << this->CollapseStages << "\n";
  os << indent << "MonotoneInEpsilon: " << (this->MonotoneInEpsilon ? "on" : "off") << "\n";
  os << indent << "LadderBottom: " << this->LadderBottom << "\n";
  os << indent << "LadderOwnRuns: " << (this->LadderOwnRuns ? "on" : "off") << "\n";
  os << indent << "LadderCollapsesOnly: " << (this->LadderCollapsesOnly ? "on" : "off") << "\n";
  os << indent << "UsedMaximumError: " << this->UsedMaximumError << "\n";
  os << indent << "NumberOfPatches: " << this->NumberOfPatches << "\n";
  os << indent << "RefinedPatches: " << this->RefinedPatches << "\n";
  os << indent << "OriginalPatches: " << this->OriginalPatches << "\n";
  os << indent << "NumberOfEars: " << this->NumberOfEars << "\n";
  os << indent << "NumberOfBites: " << this->NumberOfBites << "\n";
  os << indent << "NumberOfRepairs: " << this->NumberOfRepairs << "\n";
  os << indent << "NumberOfFinalCollapses: " << this->NumberOfFinalCollapses << "\n";
}
