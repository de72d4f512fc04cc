#include "vtkQuadricTriangleCollapse.h"

#include "slodInputPreparation.h"
#include "slodPointAttributes.h"
#include "slodTriangleCollapse.h"

#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTable.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>

vtkStandardNewMacro(vtkQuadricTriangleCollapse);

namespace
{
vtkSmartPointer<vtkIdTypeArray> MakeIdArray(const char* name, int components, vtkIdType tuples)
{
  auto a = vtkSmartPointer<vtkIdTypeArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}
vtkSmartPointer<vtkDoubleArray> MakeDoubleArray(const char* name, int components, vtkIdType tuples)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}
void AddScalar(vtkFieldData* fd, const char* name, double value)
{
  auto a = MakeDoubleArray(name, 1, 1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

// The history as a table: one row per collapse plus ragged arrays in the field data.
void HistoryToTable(const slod::CollapseHistory& h, slod::Index inputPoints, slod::Index inputTriangles, vtkTable* table)
{
  const vtkIdType n = h.NumberOfCollapses();
  auto vertices = MakeIdArray("Vertices", 3, n);
  auto oldPositions = MakeDoubleArray("OldPositions", 9, n);
  auto newPosition = MakeDoubleArray("NewPosition", 3, n);
  auto removed = MakeIdArray("RemovedTriangles", 4, n);
  auto removedVertices = MakeIdArray("RemovedTriangleVertices", 12, n);
  auto changedOffset = MakeIdArray("ChangedOffset", 1, n);
  auto surroundingOffset = MakeIdArray("SurroundingOffset", 1, n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    for (int i = 0; i < 3; ++i)
    {
      vertices->SetTypedComponent(k, i, h.Vertices[3 * k + i]);
      newPosition->SetTypedComponent(k, i, h.NewPositions[3 * k + i]);
    }
    for (int i = 0; i < 9; ++i)
    {
      oldPositions->SetTypedComponent(k, i, h.OldPositions[9 * k + i]);
    }
    const slod::Index r0 = h.RemovedOffsets[k], r1 = h.RemovedOffsets[k + 1];
    for (int i = 0; i < 4; ++i)
    {
      const bool has = r0 + i < r1;
      removed->SetTypedComponent(k, i, has ? h.RemovedTriangles[4 * size_t(r0 + i)] : -1);
      for (int j = 0; j < 3; ++j)
      {
        removedVertices->SetTypedComponent(k, 3 * i + j, has ? h.RemovedTriangles[4 * size_t(r0 + i) + 1 + j] : -1);
      }
    }
    changedOffset->SetValue(k, h.ChangedOffsets[k]);
    surroundingOffset->SetValue(k, h.SurroundingOffsets[k]);
  }
  table->AddColumn(vertices);
  table->AddColumn(oldPositions);
  table->AddColumn(newPosition);
  table->AddColumn(removed);
  table->AddColumn(removedVertices);
  table->AddColumn(changedOffset);
  table->AddColumn(surroundingOffset);

  vtkFieldData* fd = table->GetFieldData();
  auto changed = MakeIdArray("Changed", 3, static_cast<vtkIdType>(h.Changed.size() / 3));
  std::copy(h.Changed.begin(), h.Changed.end(), changed->GetPointer(0));
  fd->AddArray(changed);
  auto surrounding = MakeIdArray("Surrounding", 1, static_cast<vtkIdType>(h.Surrounding.size()));
  std::copy(h.Surrounding.begin(), h.Surrounding.end(), surrounding->GetPointer(0));
  fd->AddArray(surrounding);
  auto counts = MakeIdArray("NumberOfInputPoints", 1, 1);
  counts->SetValue(0, inputPoints);
  fd->AddArray(counts);
  auto tcounts = MakeIdArray("NumberOfInputTriangles", 1, 1);
  tcounts->SetValue(0, inputTriangles);
  fd->AddArray(tcounts);
}
} // namespace

vtkQuadricTriangleCollapse::vtkQuadricTriangleCollapse()
{
  this->SetNumberOfOutputPorts(2);
}

int vtkQuadricTriangleCollapse::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

vtkTable* vtkQuadricTriangleCollapse::GetCollapseRecords()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(1));
}

int vtkQuadricTriangleCollapse::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkTable* records = vtkTable::GetData(outputVector, 1);
  this->ActualReduction = 0.0;
  this->NumberOfCollapses = 0;
  this->MaximumSimplificationError = 0.0;
  if (!input || !output)
  {
    return 1;
  }

  const bool verbose = std::getenv("SLOD_VERBOSE") != nullptr;
  std::clock_t clock = std::clock();
  auto lap = [&](const char* what) {
    if (verbose)
    {
      const std::clock_t now = std::clock();
      long peakKB = 0; // peak resident memory so far (Linux), to see which stage sets it
      if (FILE* status = std::fopen("/proc/self/status", "r"))
      {
        char line[256];
        while (std::fgets(line, sizeof(line), status))
        {
          if (std::sscanf(line, "VmHWM: %ld", &peakKB) == 1)
          {
            break;
          }
        }
        std::fclose(status);
      }
      std::fprintf(stderr, "[vtkQuadricTriangleCollapse] %s: %.3f s CPU, peak RSS %.1f MB\n", what,
        double(now - clock) / CLOCKS_PER_SEC, peakKB / 1024.0);
      clock = now;
    }
  };
  slod::TriangleMesh mesh;
  std::vector<slod::Index> vertexToInput;
  if (!slod::PrepareFilterInput(this, input, slod::PreparationOptions(), mesh, vertexToInput))
  {
    return 1;
  }
  lap("input preparation");
  const slod::Index inputTriangles = mesh.NumberOfTriangles();
  const slod::Index inputPoints = mesh.NumberOfPoints();
  if (inputTriangles == 0)
  {
    return 1;
  }

  // Stop criteria: the larger triangle count is reached first.
  slod::TriangleCollapseOptions options;
  slod::Index target = 0;
  if (this->TargetNumberOfTriangles > 0)
  {
    target = static_cast<slod::Index>(std::min<vtkIdType>(this->TargetNumberOfTriangles, inputTriangles));
  }
  if (this->TargetReduction > 0)
  {
    const auto byReduction = static_cast<slod::Index>(std::floor((1.0 - this->TargetReduction) * inputTriangles + 1e-9));
    target = std::max(target, byReduction);
  }
  const double diagonal = mesh.BoundingBoxDiagonal();
  options.TargetTriangles = target;
  options.MaximumError = this->MaximumError < 0 ? -1.0
    : (this->MaximumErrorIsRelative ? this->MaximumError * diagonal : this->MaximumError);
  options.BoundaryWeight = this->BoundaryWeight;
  options.MaximumNormalDeviation = this->MaximumNormalDeviation;
  options.AllowTopologyChange = this->AllowTopologyChange;
  options.ExactUnion = this->ExactUnion;
  options.RefineDeviation = this->DeviationRefinement;
  options.FitToOriginal = this->FitToOriginal;
  options.EdgeCollapses = this->EdgeCollapses;
  options.EdgeCollapseBias = this->EdgeCollapseBias;
  options.RecordHistory = this->GenerateProgressiveMesh;
  options.Progress = [this](double fraction) {
    this->UpdateProgress(fraction);
    return !this->GetAbortExecute(); // VTK 9.1 has no CheckAbort()
  };

  int pointType = input->GetPoints() ? input->GetPoints()->GetDataType() : VTK_FLOAT;
  if (this->OutputPointsPrecision == vtkAlgorithm::SINGLE_PRECISION)
  {
    pointType = VTK_FLOAT;
  }
  else if (this->OutputPointsPrecision == vtkAlgorithm::DOUBLE_PRECISION)
  {
    pointType = VTK_DOUBLE;
  }
  else if (pointType != VTK_DOUBLE)
  {
    pointType = VTK_FLOAT;
  }

  slod::PointAttributes attributes;
  attributes.Load(input->GetPointData(), vertexToInput);
  std::vector<slod::Index>().swap(vertexToInput);

  slod::TriangleCollapseResult result;
  slod::SimplifyByTriangleCollapse(mesh, options, result, &attributes);

  lap("simplification");
  slod::MeshToPolyData(result.Mesh, output, pointType);
  attributes.Store(output->GetPointData(), result.OutputToInput);
  const vtkIdType outPoints = static_cast<vtkIdType>(result.OutputToInput.size());
  auto error = MakeDoubleArray("SimplificationError", 1, outPoints);
  std::copy(result.VertexError.begin(), result.VertexError.end(), error->GetPointer(0));
  output->GetPointData()->AddArray(error);
  AddScalar(output->GetFieldData(), "MaximumSimplificationError", result.MaximumError);
  AddScalar(output->GetFieldData(), "MaximumSimplificationErrorRelative", diagonal > 0 ? result.MaximumError / diagonal : 0.0);

  if (this->GenerateProgressiveMesh)
  {
    auto vertexIds = MakeIdArray("OriginalVertexId", 1, outPoints);
    std::copy(result.OutputToInput.begin(), result.OutputToInput.end(), vertexIds->GetPointer(0));
    output->GetPointData()->AddArray(vertexIds);
    auto triangleIds = MakeIdArray("OriginalTriangleId", 1, static_cast<vtkIdType>(result.OutputTriangleIds.size()));
    std::copy(result.OutputTriangleIds.begin(), result.OutputTriangleIds.end(), triangleIds->GetPointer(0));
    output->GetCellData()->AddArray(triangleIds);
    if (records)
    {
      HistoryToTable(result.History, inputPoints, inputTriangles, records);
    }
  }

  lap("output");
  this->NumberOfCollapses = result.Collapses;
  this->MaximumSimplificationError = result.MaximumError;
  this->ActualReduction = 1.0 - double(result.Mesh.NumberOfTriangles()) / double(inputTriangles);
  if (result.Aborted)
  {
    vtkWarningMacro(<< "Aborted after " << result.Collapses << " collapses.");
  }
  if (result.WorkBoundReached)
  {
    vtkWarningMacro(<< "Stopped by the bound on the collapse loop's work after " << result.Collapses << " collapses.");
  }
  // A maximum error that stops the collapses first is a target met, not missed.
  const bool stoppedByError = options.MaximumError >= 0 && result.StoppedByError;
  slod::ReportTarget(this, output, target, result.Mesh.NumberOfTriangles() <= target || stoppedByError || result.Aborted,
    "every further collapse would change the topology, fold a triangle or leave a locked non-manifold vertex");
  return 1;
}

void vtkQuadricTriangleCollapse::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetNumberOfTriangles: " << this->TargetNumberOfTriangles << "\n";
  os << indent << "TargetReduction: " << this->TargetReduction << "\n";
  os << indent << "MaximumError: " << this->MaximumError << "\n";
  os << indent << "MaximumErrorIsRelative: " << this->MaximumErrorIsRelative << "\n";
  os << indent << "BoundaryWeight: " << this->BoundaryWeight << "\n";
  os << indent << "MaximumNormalDeviation: " << this->MaximumNormalDeviation << "\n";
  os << indent << "AllowTopologyChange: " << this->AllowTopologyChange << "\n";
  os << indent << "ExactUnion: " << this->ExactUnion << "\n";
  os << indent << "DeviationRefinement: " << this->DeviationRefinement << "\n";
  os << indent << "FitToOriginal: " << this->FitToOriginal << "\n";
  os << indent << "EdgeCollapses: " << this->EdgeCollapses << "\n";
  os << indent << "EdgeCollapseBias: " << this->EdgeCollapseBias << "\n";
  os << indent << "GenerateProgressiveMesh: " << this->GenerateProgressiveMesh << "\n";
  os << indent << "OutputPointsPrecision: " << this->OutputPointsPrecision << "\n";
  os << indent << "ActualReduction: " << this->ActualReduction << "\n";
  os << indent << "NumberOfCollapses: " << this->NumberOfCollapses << "\n";
  os << indent << "MaximumSimplificationError: " << this->MaximumSimplificationError << "\n";
}
