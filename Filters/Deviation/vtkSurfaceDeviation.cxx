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

  // Orientation does not change distances: skip that part of the preparation.
  slod::PreparationOptions options;
  options.MakeOrientationConsistent = false;
  slod::TriangleMesh meshA, meshB;
  std::vector<slod::Index> vertexToInputA, vertexToInputB;
  const slod::PreparationReport reportA = slod::PrepareTriangleMesh(inputA, options, meshA, vertexToInputA);
  const slod::PreparationReport reportB = slod::PrepareTriangleMesh(inputB, options, meshB, vertexToInputB);
  for (const auto& side : { std::make_pair("reference (port 0)", &reportA), std::make_pair("compared (port 1)", &reportB) })
  {
    if (!side.second->Valid)
    {
      vtkErrorMacro("Invalid " << side.first << " input: " << side.second->Error << "; the output is empty.");
      output->Initialize();
      return 1;
    }
    for (const std::string& warning : side.second->Warnings())
    {
      vtkWarningMacro(<< "Input " << side.first << ": " << warning << ".");
    }
  }
  if (meshA.NumberOfTriangles() == 0 || meshB.NumberOfTriangles() == 0)
  {
    vtkErrorMacro(<< (meshA.NumberOfTriangles() == 0 ? "The reference surface (port 0)" : "The compared surface (port 1)")
                  << " has no triangles: the deviations are undefined (NaN) and the output is empty.");
    output->Initialize();
    return 1;
  }
  this->UpdateProgress(0.05);

  output->ShallowCopy(inputB);
  // Fresh containers so adding arrays never touches the input's.
  vtkNew<vtkFieldData> fieldData;
  if (inputB->GetFieldData())
  {
    fieldData->ShallowCopy(inputB->GetFieldData());
  }
  output->SetFieldData(fieldData);

  // Of the points the triangles use (the prepared mesh keeps only those).
  this->BoundingBoxDiagonal = meshA.BoundingBoxDiagonal();
  const vtkIdType numberOfPointsB = inputB->GetNumberOfPoints();
  vtkNew<vtkDoubleArray> distanceArray;
  distanceArray->SetName("Distance");
  distanceArray->SetNumberOfTuples(numberOfPointsB);
  distanceArray->Fill(0.0);

  bool aborted = false;
  {
    slod::TriangleBVH treeA(meshA), treeB(meshB);
    this->UpdateProgress(0.15);

    slod::DeviationOptions deviationOptions;
    deviationOptions.NumberOfSamples = this->NumberOfSamples;
    deviationOptions.Seed = this->Seed;
    deviationOptions.SampleVertices = this->SampleVertices;
    if (this->NumberOfSamples == 0 && !this->SampleVertices)
    {
      vtkWarningMacro("NumberOfSamples is 0 and SampleVertices is off: the vertices are used as samples.");
    }
    slod::OneSidedDeviation ab, ba;
    std::vector<double> vertexDistancesB;
    deviationOptions.Stream = 0;
    aborted = !slod::MeasureDeviation(meshA, treeB, deviationOptions, ab, nullptr, slod::FilterProgress(this, 0.15, 0.55));
    if (!aborted)
    {
      deviationOptions.Stream = 1;
      aborted = !slod::MeasureDeviation(meshB, treeA, deviationOptions, ba, &vertexDistancesB, slod::FilterProgress(this, 0.55, 0.95));
    }
    if (!aborted)
    {
      this->HausdorffAB = ab.Max;
      this->HausdorffBA = ba.Max;
      this->Hausdorff = std::max(ab.Max, ba.Max);
      this->MeanAB = ab.Mean;
      this->MeanBA = ba.Mean;
      this->RMSAB = ab.RMS;
      this->RMSBA = ba.RMS;
      this->Mean = 0.5 * (ab.Mean + ba.Mean);
      this->RMS = 0.5 * (ab.RMS + ba.RMS);

      // Per input point of B: mesh vertices carry their distance; other points (merged duplicates,
      // points of vertex/line cells or unused points) are measured directly.
      std::vector<char> done(size_t(numberOfPointsB), 0);
      for (size_t v = 0; v < vertexToInputB.size(); ++v)
      {
        distanceArray->SetValue(vertexToInputB[v], vertexDistancesB[v]);
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
        distanceArray->SetValue(rest[k], restDistances[k]);
      }
    }
  }
  if (aborted)
  {
    slod::ReportAbort(this, output);
    return 1;
  }
  output->GetPointData()->AddArray(distanceArray);

  auto addValue = [&](const char* name, double value) {
    vtkNew<vtkDoubleArray> array;
    array->SetName(name);
    array->SetNumberOfTuples(1);
    array->SetValue(0, value);
    fieldData->AddArray(array);
    vtkNew<vtkDoubleArray> relative;
    relative->SetName((std::string(name) + "Relative").c_str());
    relative->SetNumberOfTuples(1);
    relative->SetValue(0, this->Relative(value));
    fieldData->AddArray(relative);
  };
  addValue("Hausdorff", this->Hausdorff);
  addValue("HausdorffAB", this->HausdorffAB);
  addValue("HausdorffBA", this->HausdorffBA);
  addValue("Mean", this->Mean);
  addValue("RMS", this->RMS);
  addValue("MeanAB", this->MeanAB);
  addValue("MeanBA", this->MeanBA);
  addValue("RMSAB", this->RMSAB);
  addValue("RMSBA", this->RMSBA);
  vtkNew<vtkDoubleArray> diagonal;
  diagonal->SetName("BoundingBoxDiagonal");
  diagonal->SetNumberOfTuples(1);
  diagonal->SetValue(0, this->BoundingBoxDiagonal);
  fieldData->AddArray(diagonal);
  this->UpdateProgress(1.0);
  return 1;
}
