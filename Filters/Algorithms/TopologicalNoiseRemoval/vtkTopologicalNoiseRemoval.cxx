// SPDX-License-Identifier: BSD-3-Clause
#include "vtkTopologicalNoiseRemoval.h"

#include "slodAttributeTransfer.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodTopologicalNoiseRemoval.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkLogger.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <initializer_list>
#include <numeric>
#include <utility>

vtkStandardNewMacro(vtkTopologicalNoiseRemoval);

namespace
{
// The filter's counts as one-value integer arrays of the output's field data.
void StoreCounts(vtkFieldData* fd, std::initializer_list<std::pair<const char*, int>> counts)
{
  for (const auto& count : counts)
  {
    vtkNew<vtkIntArray> array;
    array->SetName(count.first);
    array->InsertNextValue(count.second);
    fd->AddArray(array);
  }
}

// The cleaned mesh as the output: every vertex copies an input point (with its point data), every
// triangle carries its source triangle's cell data.
void StoreSurface(vtkPolyData* input, const slod::TopologicalNoiseResult& result,
  const std::vector<slod::Index>& vertexToInput, const std::vector<slod::Index>& triangleToCell,
  int outputPointsPrecision, vtkPolyData* output)
{
  const slod::TriangleMesh& mesh = result.Mesh;
  std::vector<slod::Index> identity(size_t(mesh.NumberOfPoints())), pointSource(identity.size());
  std::iota(identity.begin(), identity.end(), 0);
  for (size_t i = 0; i < identity.size(); ++i)
  {
    pointSource[i] = vertexToInput[result.VertexSource[i]];
  }
  slod::StoreUsedPoints(input, mesh, identity, pointSource, outputPointsPrecision, output);
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(mesh.NumberOfTriangles(), 3 * vtkIdType(mesh.NumberOfTriangles()));
  for (slod::Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const vtkIdType ids[3] = { mesh.Triangle(t)[0], mesh.Triangle(t)[1], mesh.Triangle(t)[2] };
    polys->InsertNextCell(3, ids);
  }
  output->SetPolys(polys);
  slod::StoreCellData(input, triangleToCell, result.TriangleSource, output);
}

// Output port 1: the loops as closed polylines.
void StoreLoops(const slod::TopologicalNoiseResult& result, vtkPolyData* loopsOutput)
{
  vtkNew<vtkPoints> points;
  points->SetDataType(VTK_DOUBLE);
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> removed;
  removed->SetName("Removed");
  vtkNew<vtkDoubleArray> length;
  length->SetName("Length");
  vtkNew<vtkDoubleArray> size;
  size->SetName("Size");
  for (const slod::NoiseLoop& loop : result.Loops)
  {
    const vtkIdType first = points->GetNumberOfPoints();
    lines->InsertNextCell(static_cast<vtkIdType>(loop.Points.size() + 1));
    for (const slod::Vec3& p : loop.Points)
    {
      lines->InsertCellPoint(points->InsertNextPoint(p.data()));
    }
    lines->InsertCellPoint(first);
    removed->InsertNextValue(loop.Removed ? 1 : 0);
    length->InsertNextValue(loop.Length);
    size->InsertNextValue(loop.Length / vtkMath::Pi());
  }
  loopsOutput->SetPoints(points);
  loopsOutput->SetLines(lines);
  loopsOutput->GetCellData()->AddArray(removed);
  loopsOutput->GetCellData()->AddArray(length);
  loopsOutput->GetCellData()->AddArray(size);
}

vtkSmartPointer<vtkDoubleArray> DoubleArray(const char* name, const std::vector<double>& values)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  for (double value : values)
  {
    array->InsertNextValue(value);
  }
  return array;
}

slod::MeshStatistics Statistics(const slod::TriangleMesh& mesh)
{
  return slod::MeshTopology(mesh).Statistics(mesh);
}
} // namespace

vtkTopologicalNoiseRemoval::vtkTopologicalNoiseRemoval()
{
  this->SetNumberOfOutputPorts(2);
}

int vtkTopologicalNoiseRemoval::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* loopsOutput = vtkPolyData::GetData(outputVector, 1);
  if (!input || !output || !loopsOutput)
  {
    return 0;
  }
  this->NumberOfHandlesRemoved = this->NumberOfComponentsRemoved = this->NumberOfCavitiesRemoved = 0;
  this->NumberOfLoopsKept = 0;
  this->NumberOfNonManifoldEdgesSplit = this->NumberOfNonManifoldVerticesSplit = 0;
  this->NumberOfHandlesKeptAboveFeatureSize = 0;
  this->InputEulerCharacteristic = this->OutputEulerCharacteristic = 0;
  this->InputGenus = this->OutputGenus = -1;
  this->UsedFeatureSize = 0.0;

  slod::PreparedTriangles prepared;
  if (!slod::PrepareFilterTriangles(this, input, prepared))
  {
    return 1; // error or warning reported; empty output
  }
  auto& [mesh, vertexToInput, triangleToCell, report] = prepared;
  if (!this->SplitNonManifold && (report.NonManifoldEdges > 0 || report.NonManifoldVertices > 0))
  {
    vtkWarningMacro("Non-manifold edges and vertices are left alone (SplitNonManifold is off): no loop "
                    "through them is cut.");
  }
  slod::TopologicalNoiseParameters parameters;
  this->UsedFeatureSize = this->FeatureSize * (this->FeatureSizeIsRelative ? mesh.BoundingBoxDiagonal() : 1.0);
  parameters.FeatureSize = this->UsedFeatureSize;
  parameters.RemoveHandles = this->RemoveHandles;
  parameters.RemoveComponents = this->RemoveComponents;
  parameters.MaximumPasses = this->MaximumPasses;
  parameters.SeparationSearchBudget = static_cast<slod::Index>(this->SeparationSearchBudget);
  parameters.SplitNonManifold = this->SplitNonManifold;
  parameters.KeptHandleSurveyFactor = this->KeptHandleSurveyFactor;
  slod::TopologicalNoiseResult result;
  const bool done = slod::RemoveTopologicalNoise(mesh, parameters, result, slod::FilterProgress(this, 0.05, 0.95));
  const slod::MeshStatistics& before = result.InputStatistics;
  this->InputEulerCharacteristic = before.EulerCharacteristic;
  this->InputGenus = static_cast<int>(before.Genus);
  if (!done)
  {
    slod::ReportAbort(this, output);
    return 1;
  }
  this->NumberOfHandlesRemoved = static_cast<int>(result.HandlesRemoved);
  this->NumberOfComponentsRemoved = static_cast<int>(result.ComponentsRemoved);
  this->NumberOfCavitiesRemoved = static_cast<int>(result.CavitiesRemoved);
  this->NumberOfLoopsKept = static_cast<int>(result.LoopsKept);
  this->NumberOfNonManifoldEdgesSplit = static_cast<int>(result.NonManifoldEdgesSplit);
  this->NumberOfNonManifoldVerticesSplit = static_cast<int>(result.NonManifoldVerticesSplit);
  this->NumberOfHandlesKeptAboveFeatureSize = static_cast<int>(result.KeptHandleSizes.size());
  if (result.NonManifoldEdgesLeft > 0)
  {
    vtkWarningMacro(<< result.NonManifoldEdgesLeft
                    << " non-manifold edges could not be split into sheets (an odd number of triangles, or "
                       "orientations that do not alternate around them): no loop through them is cut.");
  }
  if (result.PassLimitReached)
  {
    vtkWarningMacro("MaximumPasses (" << this->MaximumPasses
                                      << ") reached while the last pass still cut handles: handles below the "
                                         "feature size may remain near its cuts.");
  }
  if (result.SurveyPassLimitReached)
  {
    vtkWarningMacro("MaximumPasses (" << this->MaximumPasses
                                      << ") reached by the survey of the kept handles: some kept handles may be "
                                         "missing from KeptHandleSizes.");
  }
  StoreSurface(input, result, vertexToInput, triangleToCell, this->OutputPointsPrecision, output);

  const slod::MeshStatistics after = Statistics(result.Mesh);
  this->OutputEulerCharacteristic = after.EulerCharacteristic;
  this->OutputGenus = static_cast<int>(after.Genus);
  if (after.NonManifoldEdges > before.NonManifoldEdges)
  {
    vtkWarningMacro("The output has " << after.NonManifoldEdges << " non-manifold edges (input "
                                      << before.NonManifoldEdges << ").");
  }
  StoreCounts(output->GetFieldData(),
    { { "HandlesRemoved", this->NumberOfHandlesRemoved }, { "ComponentsRemoved", this->NumberOfComponentsRemoved },
      { "CavitiesRemoved", this->NumberOfCavitiesRemoved }, { "LoopsKept", this->NumberOfLoopsKept },
      { "HandlesKept", this->OutputGenus }, { "NonManifoldEdgesSplit", this->NumberOfNonManifoldEdgesSplit },
      { "NonManifoldVerticesSplit", this->NumberOfNonManifoldVerticesSplit },
      { "HandlesNotSized", static_cast<int>(result.HandlesNotSized) },
      { "SurveyPassLimitReached", result.SurveyPassLimitReached ? 1 : 0 } });
  output->GetFieldData()->AddArray(DoubleArray("FeatureSize", { this->UsedFeatureSize }));
  output->GetFieldData()->AddArray(DoubleArray("KeptHandleSurveySize", { result.SurveySize }));
  output->GetFieldData()->AddArray(DoubleArray("KeptHandleSizes", result.KeptHandleSizes));
  if (this->GenerateCutLoops)
  {
    StoreLoops(result, loopsOutput);
  }
  vtkLogF(TRACE,
    "topological noise removal: %d handles cut (%d found by the survey) in %d passes, %d candidate loops (%d outdated; tests: %d "
    "non-separating, %d separating, %d undetermined, %d invalid; %d cuts refused, %d centre fans), chi %lld -> %lld",
    this->NumberOfHandlesRemoved, int(result.HandlesRemovedBySurvey), result.Passes, int(result.CandidateLoops), int(result.Outdated),
    int(result.Tests[0]), int(result.Tests[1]), int(result.Tests[2]), int(result.Tests[3]), int(result.CutsRefused),
    int(result.CentreFans), before.EulerCharacteristic, after.EulerCharacteristic);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkTopologicalNoiseRemoval::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FeatureSize: " << this->FeatureSize << (this->FeatureSizeIsRelative ? " (relative)" : " (absolute)")
     << "\n";
  os << indent << "RemoveHandles: " << this->RemoveHandles << "\n";
  os << indent << "RemoveComponents: " << this->RemoveComponents << "\n";
  os << indent << "MaximumPasses: " << this->MaximumPasses << "\n";
  os << indent << "SeparationSearchBudget: " << this->SeparationSearchBudget << "\n";
  os << indent << "SplitNonManifold: " << this->SplitNonManifold << "\n";
  os << indent << "KeptHandleSurveyFactor: " << this->KeptHandleSurveyFactor << "\n";
  os << indent << "GenerateCutLoops: " << this->GenerateCutLoops << "\n";
  os << indent << "OutputPointsPrecision: " << this->OutputPointsPrecision << "\n";
  os << indent << "Handles removed: " << this->NumberOfHandlesRemoved << ", loops kept: " << this->NumberOfLoopsKept
     << "\n";
  os << indent << "Non-manifold edges / vertices split: " << this->NumberOfNonManifoldEdgesSplit << " / "
     << this->NumberOfNonManifoldVerticesSplit << "\n";
  os << indent << "Handles kept above the feature size (surveyed): " << this->NumberOfHandlesKeptAboveFeatureSize
     << "\n";
  os << indent << "Components / cavities removed: " << this->NumberOfComponentsRemoved << " / "
     << this->NumberOfCavitiesRemoved << "\n";
  os << indent << "Euler characteristic: " << this->InputEulerCharacteristic << " -> "
     << this->OutputEulerCharacteristic << "\n";
  os << indent << "Genus: " << this->InputGenus << " -> " << this->OutputGenus << "\n";
}
