// SPDX-License-Identifier: BSD-3-Clause
#include "vtkHoleBumpRemoval.h"

#include "slodAttributeTransfer.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodStageClock.h"
#include "slodTopologySimplification.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cmath>

vtkStandardNewMacro(vtkHoleBumpRemoval);

namespace
{
void AddCount(vtkFieldData* fd, const char* name, int value)
{
  vtkNew<vtkIntArray> a;
  a->SetName(name);
  a->SetNumberOfValues(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

// The parameters of the simplification from the filter's settings; the size parameters are
// relative to the mesh's diagonal where the filter says so.
slod::TopologySimplificationParameters SimplificationParameters(vtkHoleBumpRemoval* filter, const slod::TriangleMesh& mesh)
{
  slod::TopologySimplificationParameters parameters;
  parameters.Patches.OneEdgePatchAngle = filter->GetPatchAngle();
  parameters.Patches.OneEdgeNeighborAngle = filter->GetNeighborAngle();
  parameters.SharpMaximumDot = std::cos(slod::Radians(filter->GetSharpAngle()));
  parameters.SharpMinimumDot = std::cos(slod::Radians(filter->GetMaximumSharpAngle()));
  const double diagonal = mesh.BoundingBoxDiagonal();
  parameters.Patches.MaximumPlaneDistance = filter->GetPatchPlaneDistance() * diagonal;
  const double scale = filter->GetFeatureSizeIsRelative() ? diagonal : 1.0;
  parameters.FeatureSize = filter->GetFeatureSize() * scale;
  parameters.MaximumCrackSize = filter->GetMaximumCrackSize() < 0 ? -1.0 : filter->GetMaximumCrackSize() * scale;
  parameters.FillCracks = filter->GetFillCracks();
  parameters.RemoveHoles = filter->GetRemoveHoles();
  parameters.RemoveBumps = filter->GetRemoveBumps();
  parameters.RemoveCavities = filter->GetRemoveCavities();
  parameters.MergeAngle = filter->GetMergeAngle();
  parameters.MaximumPasses = filter->GetMaximumPasses();
  parameters.Completion = static_cast<slod::TopologyCompletion>(filter->GetCompletion());
  parameters.Spbm.Epsilon = filter->GetEpsilon() * diagonal;
  parameters.Spbm.MergeAngle = filter->GetMergeAngle() > 0 ? filter->GetMergeAngle() : 20.0;
  // The filter contract's targets (slodFilterContract.h) for the SPBM completion; without one the
  // completion uses Epsilon (removing features is the filter's purpose, not a reduction).
  const vtkIdType target = filter->ComputeTargetNumberOfTriangles(mesh.NumberOfTriangles());
  if (target >= mesh.NumberOfTriangles())
  {
    parameters.Completion = slod::TopologyCompletion::KeepTriangles; // no reduction asked for
  }
  else if (target > 0)
  {
    parameters.Completion = slod::TopologyCompletion::Spbm;
    parameters.SpbmTargetTriangles = static_cast<slod::Index>(std::min<vtkIdType>(target, VTK_INT_MAX));
    parameters.FinalCollapses = filter->GetFinalCollapses();
    parameters.SingleMeasureNoisyBendShare = filter->GetSingleMeasureNoisyBendShare();
    if (filter->GetSingleMergeMeasure())
    {
      parameters.Spbm.CompareCandidates = false;
      parameters.Spbm.SizeWeightedMerge = true;
    }
  }
  return parameters;
}

// The result's triangles over the used input vertices, with their patch and fill arrays; outMesh
// gets the same triangles (for the topology check).
void StoreTriangles(const slod::TopologySimplificationResult& result, const slod::TriangleMesh& mesh, vtkPolyData* input,
  const std::vector<slod::Index>& vertexToInput, const std::vector<slod::Index>& triangleToCell, int outputPointsPrecision,
  vtkPolyData* output, slod::TriangleMesh& outMesh)
{
  slod::FirstUseNumbering numbering(mesh.NumberOfPoints());
  const std::vector<slod::Index>& used = numbering.Used;
  auto use = [&](slod::Index v) { return static_cast<vtkIdType>(numbering(v)); };
  const vtkIdType nt = static_cast<vtkIdType>(result.TrianglePatch.size());
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(nt, 3 * nt);
  vtkNew<vtkIntArray> patchIds;
  patchIds->SetName("PatchId");
  patchIds->SetNumberOfValues(nt);
  vtkNew<vtkIntArray> filled; // int, not unsigned char: mappers would take 0/1 bytes as colours
  filled->SetName("FilledPatch");
  filled->SetNumberOfValues(nt);
  for (vtkIdType t = 0; t < nt; ++t)
  {
    const vtkIdType ids[3] = { use(result.Triangles[3 * t]), use(result.Triangles[3 * t + 1]),
      use(result.Triangles[3 * t + 2]) };
    polys->InsertNextCell(3, ids);
    patchIds->SetValue(t, result.TrianglePatch[t]);
    filled->SetValue(t, result.TriangleFill[t]);
    outMesh.AddTriangle(static_cast<slod::Index>(ids[0]), static_cast<slod::Index>(ids[1]), static_cast<slod::Index>(ids[2]));
  }
  slod::StoreUsedPoints(input, mesh, used, vertexToInput, outputPointsPrecision, output);
  outMesh.Points.resize(3 * used.size());
  for (size_t i = 0; i < used.size(); ++i)
  {
    outMesh.SetPoint(static_cast<slod::Index>(i), mesh.Point(used[i]));
  }
  output->SetPolys(polys);
  slod::StoreNearestCellData(input, triangleToCell, mesh, mesh.Points, result.Triangles, output);
  output->GetCellData()->AddArray(patchIds);
  output->GetCellData()->AddArray(filled);
}

void AddFeatureCounts(vtkHoleBumpRemoval* filter, vtkFieldData* fd)
{
  AddCount(fd, "HolesRemoved", filter->GetNumberOfHolesRemoved());
  AddCount(fd, "BumpsRemoved", filter->GetNumberOfBumpsRemoved());
  AddCount(fd, "CavitiesRemoved", filter->GetNumberOfCavitiesRemoved());
  AddCount(fd, "CracksFilled", filter->GetNumberOfCracksFilled());
  AddCount(fd, "HolesDetected", filter->GetNumberOfHolesDetected());
  AddCount(fd, "BumpsDetected", filter->GetNumberOfBumpsDetected());
  AddCount(fd, "CavitiesDetected", filter->GetNumberOfCavitiesDetected());
  AddCount(fd, "CracksDetected", filter->GetNumberOfCracksDetected());
}

// Output port 1: the sharp loops and the crack loops as closed polylines with their feature's
// kind, whether it was removed, and the loop's orientation.
void StoreSharpLoops(const slod::TopologySimplificationResult& result, const slod::TriangleMesh& mesh, vtkPolyData* loopsOutput)
{
  using Kind = slod::TopologyFeatureKind;
  vtkNew<vtkPoints> loopPoints;
  loopPoints->SetDataType(VTK_DOUBLE);
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> kind, removed, clockwise;
  kind->SetName("FeatureKind");
  removed->SetName("Removed");
  clockwise->SetName("Clockwise");
  auto addLine = [&](const std::vector<slod::Index>& loop, int k, int r, int cw) {
    lines->InsertNextCell(static_cast<vtkIdType>(loop.size() + 1));
    const vtkIdType first = loopPoints->GetNumberOfPoints();
    for (slod::Index v : loop)
    {
      lines->InsertCellPoint(loopPoints->InsertNextPoint(&mesh.Points[3 * size_t(v)]));
    }
    lines->InsertCellPoint(first);
    kind->InsertNextValue(k);
    removed->InsertNextValue(r);
    clockwise->InsertNextValue(cw);
  };
  for (const slod::SharpLoop& loop : result.Loops)
  {
    const slod::TopologyFeature* f = loop.Feature >= 0 ? &result.Features[loop.Feature] : nullptr;
    addLine(loop.Vertices, f ? int(f->Kind) : -1, f && f->Removed, loop.Clockwise);
  }
  for (const slod::TopologyFeature& f : result.Features)
  {
    if (f.Kind == Kind::Crack)
    {
      addLine(f.CrackLoop, int(Kind::Crack), f.Removed, 0);
    }
  }
  loopsOutput->SetPoints(loopPoints);
  loopsOutput->SetLines(lines);
  loopsOutput->GetCellData()->AddArray(kind);
  loopsOutput->GetCellData()->AddArray(removed);
  loopsOutput->GetCellData()->AddArray(clockwise);
}
} // namespace

vtkHoleBumpRemoval::vtkHoleBumpRemoval()
{
  this->SetNumberOfOutputPorts(2);
}

int vtkHoleBumpRemoval::RequestData(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* loopsOutput = vtkPolyData::GetData(outputVector, 1);
  if (!input || !output || !loopsOutput)
  {
    return 0;
  }
  this->NumberOfHolesDetected = this->NumberOfBumpsDetected = this->NumberOfCavitiesDetected = 0;
  this->NumberOfCracksDetected = 0;
  this->NumberOfHolesRemoved = this->NumberOfBumpsRemoved = this->NumberOfCavitiesRemoved = 0;
  this->NumberOfCracksFilled = 0;
  this->NumberOfSharpEdges = this->NumberOfSharpLoops = this->NumberOfPatches = this->NumberOfMergedPatches = 0;
  this->FinalCollapseCount = 0;
  this->InputGenus = this->OutputGenus = -1;
  this->UsedFeatureSize = 0;

  slod::PreparedTriangles prepared;
  if (!slod::PrepareFilterTriangles(this, input, prepared))
  {
    return 1; // error or warning reported; empty output
  }
  auto& [mesh, vertexToInput, triangleToCell, report] = prepared;
  if (report.NonManifoldEdges > 0)
  {
    vtkWarningMacro("Non-manifold edges are never part of a removed feature; features next to them are kept.");
  }
  slod::StageClock stages("vtkHoleBumpRemoval"); // CPU per stage at TRACE (--log-verbosity 9)
  // The input's topology serves the statistics, then the first detection pass (taken over by Run).
  slod::MeshTopology inputTopology(mesh);
  const slod::MeshStatistics before = inputTopology.Statistics(mesh);
  stages.Lap("input statistics");
  this->InputGenus = static_cast<int>(before.Genus);
  this->UpdateProgress(0.05);

  const slod::TopologySimplificationParameters parameters = SimplificationParameters(this, mesh);
  this->UsedFeatureSize = parameters.FeatureSize;

  slod::TopologySimplificationResult result;
  slod::TopologySimplifier simplifier;
  if (!simplifier.Run(mesh, parameters, result, slod::FilterProgress(this, 0.05, 0.9), &inputTopology))
  {
    slod::ReportAbort(this, output);
    return 1;
  }
  stages.Lap("topology simplification");
  using Kind = slod::TopologyFeatureKind;
  this->NumberOfHolesDetected = result.Detected[int(Kind::Hole)];
  this->NumberOfBumpsDetected = result.Detected[int(Kind::Bump)];
  this->NumberOfCavitiesDetected = result.Detected[int(Kind::Cavity)];
  this->NumberOfCracksDetected = result.Detected[int(Kind::Crack)];
  this->NumberOfHolesRemoved = result.Removed[int(Kind::Hole)];
  this->NumberOfBumpsRemoved = result.Removed[int(Kind::Bump)];
  this->NumberOfCavitiesRemoved = result.Removed[int(Kind::Cavity)];
  this->NumberOfCracksFilled = result.Removed[int(Kind::Crack)];
  this->NumberOfSharpEdges = result.SharpEdges;
  this->NumberOfSharpLoops = static_cast<int>(result.Loops.size());
  this->NumberOfPatches = result.InitialPatches;
  this->NumberOfMergedPatches = result.MergedPatches;
  this->FinalCollapseCount = result.FinalCollapses;
  this->NoisyBendShare = result.NoisyBendShare;
  this->SingleMergeMeasureUsed = result.SingleMergeMeasure;

  // Output over the used input vertices.
  slod::TriangleMesh outMesh;
  StoreTriangles(result, mesh, input, vertexToInput, triangleToCell, this->OutputPointsPrecision, output, outMesh);
  AddFeatureCounts(this, output->GetFieldData());
  stages.Lap("output");
  if (parameters.Completion == slod::TopologyCompletion::Spbm && parameters.SpbmTargetTriangles > 0)
  {
    slod::ReportTarget(this, output, parameters.SpbmTargetTriangles,
      output->GetNumberOfPolys() <= parameters.SpbmTargetTriangles,
      "the completion keeps the borders of the removed features and the remaining topology");
  }

  const slod::MeshStatistics after = slod::MeshTopology(outMesh).Statistics(outMesh);
  this->OutputGenus = static_cast<int>(after.Genus);
  if (before.Genus >= 0 && after.Genus >= 0 && before.Components == after.Components &&
    after.Genus != before.Genus - this->NumberOfHolesRemoved)
  {
    vtkWarningMacro("Output genus " << after.Genus << " differs from input genus " << before.Genus << " minus "
                                    << this->NumberOfHolesRemoved << " removed holes.");
  }
  if (after.NonManifoldEdges > before.NonManifoldEdges)
  {
    vtkWarningMacro("The output has " << after.NonManifoldEdges << " non-manifold edges.");
  }

  if (this->GenerateSharpLoops)
  {
    StoreSharpLoops(result, mesh, loopsOutput);
  }
  stages.Lap("output statistics and sharp loops");
  this->UpdateProgress(1.0);
  return 1;
}

void vtkHoleBumpRemoval::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SharpAngle: " << this->SharpAngle << "\n";
  os << indent << "MaximumSharpAngle: " << this->MaximumSharpAngle << "\n";
  os << indent << "FeatureSize: " << this->FeatureSize
     << (this->FeatureSizeIsRelative ? " (relative)" : " (absolute)") << "\n";
  os << indent << "RemoveHoles: " << this->RemoveHoles << "\n";
  os << indent << "RemoveBumps: " << this->RemoveBumps << "\n";
  os << indent << "RemoveCavities: " << this->RemoveCavities << "\n";
  os << indent << "FillCracks: " << this->FillCracks << "\n";
  os << indent << "FinalCollapses: " << this->FinalCollapses << "\n";
  os << indent << "SingleMergeMeasure: " << this->SingleMergeMeasure << "\n";
  os << indent << "SingleMeasureNoisyBendShare: " << this->SingleMeasureNoisyBendShare << "\n";
  os << indent << "MaximumCrackSize: " << this->MaximumCrackSize << "\n";
  os << indent << "MergeAngle: " << this->MergeAngle << "\n";
  os << indent << "MaximumPasses: " << this->MaximumPasses << "\n";
  os << indent << "PatchAngle: " << this->PatchAngle << "\n";
  os << indent << "NeighborAngle: " << this->NeighborAngle << "\n";
  os << indent << "PatchPlaneDistance: " << this->PatchPlaneDistance << "\n";
  os << indent << "Completion: " << this->Completion << "\n";
  os << indent << "Epsilon: " << this->Epsilon << "\n";
  os << indent << "GenerateSharpLoops: " << this->GenerateSharpLoops << "\n";
  os << indent << "Holes detected/removed: " << this->NumberOfHolesDetected << "/" << this->NumberOfHolesRemoved << "\n";
  os << indent << "Bumps detected/removed: " << this->NumberOfBumpsDetected << "/" << this->NumberOfBumpsRemoved << "\n";
  os << indent << "Cavities detected/removed: " << this->NumberOfCavitiesDetected << "/"
     << this->NumberOfCavitiesRemoved << "\n";
  os << indent << "Cracks detected/filled: " << this->NumberOfCracksDetected << "/" << this->NumberOfCracksFilled << "\n";
  os << indent << "InputGenus: " << this->InputGenus << "\n";
  os << indent << "OutputGenus: " << this->OutputGenus << "\n";
}
