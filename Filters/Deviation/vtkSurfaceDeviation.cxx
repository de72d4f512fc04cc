// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSurfaceDeviation.h"

#include "slodInputPreparation.h"
#include "slodSurfaceDeviation.h"
#include "slodTriangleBVH.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSurfaceDeviation);

vtkSurfaceDeviation::vtkSurfaceDeviation()
{
  this->SetNumberOfInputPorts(2);
  this->ClearResults();
}

void vtkSurfaceDeviation::ClearResults()
{
  const double undefined = std::numeric_limits<double>::quiet_NaN();
  this->Hausdorff = this->HausdorffAB = this->HausdorffBA = undefined;
  this->Mean = this->RMS = this->MeanAB = this->MeanBA = this->RMSAB = this->RMSBA = undefined;
  this->BoundingBoxDiagonal = 0;
}

int vtkSurfaceDeviation::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

void vtkSurfaceDeviation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfSamples: " << this->NumberOfSamples << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "SampleVertices: " << (this->SampleVertices ? "On" : "Off") << "\n";
  os << indent << "Hausdorff: " << this->Hausdorff << " (AB " << this->HausdorffAB << ", BA " << this->HausdorffBA
     << ")\n";
  os << indent << "Mean: " << this->Mean << " (AB " << this->MeanAB << ", BA " << this->MeanBA << ")\n";
  os << indent << "RMS: " << this->RMS << " (AB " << this->RMSAB << ", BA " << this->RMSBA << ")\n";
  os << indent << "BoundingBoxDiagonal: " << this->BoundingBoxDiagonal << "\n";
}

namespace
{
// Both inputs prepared (orientation does not change distances, so that part is skipped); false with
// an error when one cannot be used or has no triangles: the deviations are then undefined.
bool PrepareBoth(vtkSurfaceDeviation* filter, vtkPolyData* inputA, vtkPolyData* inputB, slod::TriangleMesh& meshA,
  slod::TriangleMesh& meshB, std::vector<slod::Index>& vertexToInputB)
{
  slod::PreparationOptions options;
  options.MakeOrientationConsistent = false;
  std::vector<slod::Index> vertexToInputA;
  const slod::PreparationReport reportA = slod::PrepareTriangleMesh(inputA, options, meshA, vertexToInputA);
  const slod::PreparationReport reportB = slod::PrepareTriangleMesh(inputB, options, meshB, vertexToInputB);
  for (const auto& side : { std::make_pair("reference (port 0)", &reportA), std::make_pair("compared (port 1)", &reportB) })
  {
    if (!side.second->Valid)
    {
      vtkErrorWithObjectMacro(filter, "Invalid " << side.first << " input: " << side.second->Error << "; the output is empty.");
      return false;
    }
    for (const std::string& warning : side.second->Warnings())
    {
      vtkWarningWithObjectMacro(filter, << "Input " << side.first << ": " << warning << ".");
    }
  }
  if (meshA.NumberOfTriangles() == 0 || meshB.NumberOfTriangles() == 0)
  {
    vtkErrorWithObjectMacro(filter, << (meshA.NumberOfTriangles() == 0 ? "The reference surface (port 0)" : "The compared surface (port 1)")
                  << " has no triangles: the deviations are undefined (NaN) and the output is empty.");
    return false;
  }
  return true;
}

// Distance to A of every input point of B: mesh vertices carry their measured distance; the other
// points (merged duplicates, points of vertex or line cells, unused points) are measured directly.
vtkSmartPointer<vtkDoubleArray> PointDistances(vtkPolyData* inputB, const std::vector<slod::Index>& vertexToInputB,
  const std::vector<double>& vertexDistancesB, const slod::TriangleBVH& treeA)
{
  const vtkIdType numberOfPointsB = inputB->GetNumberOfPoints();
  vtkNew<vtkDoubleArray> distances;
  distances->SetName("Distance");
  distances->SetNumberOfTuples(numberOfPointsB);
  distances->Fill(0.0);
  std::vector<char> done(size_t(numberOfPointsB), 0);
  for (size_t v = 0; v < vertexToInputB.size(); ++v)
  {
    distances->SetValue(vertexToInputB[v], vertexDistancesB[v]);
    done[size_t(vertexToInputB[v])] = 1;
  }
  std::vector<vtkIdType> rest;
  std::vector<double> restPoints;
  for (vtkIdType i = 0; i < numberOfPointsB; ++i)
  {
    if (!done[size_t(i)])
    {
      double p[3];
      inputB->GetPoint(i, p);
      rest.push_back(i);
      restPoints.insert(restPoints.end(), p, p + 3);
    }
  }
  std::vector<double> restDistances;
  slod::ComputeDistances(treeA, restPoints, restDistances);
  for (size_t k = 0; k < rest.size(); ++k)
  {
    distances->SetValue(rest[k], restDistances[k]);
  }
  return distances;
}

// Samples of A measured to B (ab) and of B to A (ba, with B's vertex distances). False when aborted.
bool MeasureBothWays(vtkSurfaceDeviation* filter, const slod::TriangleMesh& meshA, const slod::TriangleMesh& meshB,
  const slod::TriangleBVH& treeA, const slod::TriangleBVH& treeB, slod::OneSidedDeviation& ab,
  slod::OneSidedDeviation& ba, std::vector<double>& vertexDistancesB)
{
  slod::DeviationOptions options;
  options.NumberOfSamples = filter->GetNumberOfSamples();
  options.Seed = filter->GetSeed();
  options.SampleVertices = filter->GetSampleVertices();
  if (options.NumberOfSamples == 0 && !options.SampleVertices)
  {
    vtkWarningWithObjectMacro(filter, "NumberOfSamples is 0 and SampleVertices is off: the vertices are used as samples.");
  }
  options.Stream = 0;
  if (!slod::MeasureDeviation(meshA, treeB, options, ab, nullptr, slod::FilterProgress(filter, 0.15, 0.55)))
  {
    return false;
  }
  options.Stream = 1;
  return slod::MeasureDeviation(meshB, treeA, options, ba, &vertexDistancesB, slod::FilterProgress(filter, 0.55, 0.95));
}

void AddValue(vtkFieldData* fieldData, const std::string& name, double value)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name.c_str());
  array->SetNumberOfTuples(1);
  array->SetValue(0, value);
  fieldData->AddArray(array);
}
} // namespace

int vtkSurfaceDeviation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* inputA = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* inputB = vtkPolyData::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);

  // Undefined until measured: a failed or empty comparison must never read as "identical".
  this->ClearResults();
  if (!inputA || !inputB)
  {
    vtkErrorMacro("Both the reference (port 0) and the compared surface (port 1) are required.");
    return 1;
  }
  slod::TriangleMesh meshA, meshB;
  std::vector<slod::Index> vertexToInputB;
  if (!PrepareBoth(this, inputA, inputB, meshA, meshB, vertexToInputB))
  {
    output->Initialize();
    return 1;
  }
  this->UpdateProgress(0.05);
  // Of the points the triangles use (the prepared mesh keeps only those).
  this->BoundingBoxDiagonal = meshA.BoundingBoxDiagonal();

  slod::TriangleBVH treeA(meshA), treeB(meshB);
  this->UpdateProgress(0.15);
  std::vector<double> vertexDistancesB;
  slod::OneSidedDeviation ab, ba;
  if (!MeasureBothWays(this, meshA, meshB, treeA, treeB, ab, ba, vertexDistancesB))
  {
    slod::ReportAbort(this, output);
    return 1;
  }
  this->HausdorffAB = ab.Max;
  this->HausdorffBA = ba.Max;
  this->Hausdorff = std::max(ab.Max, ba.Max);
  this->MeanAB = ab.Mean;
  this->MeanBA = ba.Mean;
  this->RMSAB = ab.RMS;
  this->RMSBA = ba.RMS;
  this->Mean = 0.5 * (ab.Mean + ba.Mean);
  this->RMS = 0.5 * (ab.RMS + ba.RMS);
  output->ShallowCopy(inputB);
  output->GetPointData()->AddArray(PointDistances(inputB, vertexToInputB, vertexDistancesB, treeA));
  this->StoreResults(inputB, output);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSurfaceDeviation::StoreResults(vtkPolyData* inputB, vtkPolyData* output)
{
  // Fresh containers so adding arrays never touches the input's.
  vtkNew<vtkFieldData> fieldData;
  if (inputB->GetFieldData())
  {
    fieldData->ShallowCopy(inputB->GetFieldData());
  }
  output->SetFieldData(fieldData);
  const std::pair<const char*, double> values[] = { { "Hausdorff", this->Hausdorff },
    { "HausdorffAB", this->HausdorffAB }, { "HausdorffBA", this->HausdorffBA }, { "Mean", this->Mean },
    { "RMS", this->RMS }, { "MeanAB", this->MeanAB }, { "MeanBA", this->MeanBA }, { "RMSAB", this->RMSAB },
    { "RMSBA", this->RMSBA } };
  for (const auto& value : values)
  {
    AddValue(fieldData, value.first, value.second);
    AddValue(fieldData, std::string(value.first) + "Relative", this->Relative(value.second));
  }
  AddValue(fieldData, "BoundingBoxDiagonal", this->BoundingBoxDiagonal);
}
