// SPDX-License-Identifier: BSD-3-Clause
#include "vtkQuadricTriangleCollapse.h"

#include "slodInputPreparation.h"
#include "slodAttributeTransfer.h"
#include "slodCollapseRecordTable.h"
#include "slodHugePages.h"
#include "slodPieceSeams.h"
#include "slodPointAttributes.h"
#include "slodStageClock.h"
#include "slodTriangleCollapse.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLogger.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTable.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>

vtkStandardNewMacro(vtkQuadricTriangleCollapse);

namespace
{
void AddScalar(vtkFieldData* fd, const char* name, double value)
{
  auto a = slod::NewDoubleArray(name, 1, 1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

// Stop criteria of the filter contract (slodFilterContract.h): whichever target is reached first.
slod::Index TargetTriangles(vtkQuadricTriangleCollapse* filter, slod::Index inputTriangles)
{
  return static_cast<slod::Index>(filter->ComputeTargetNumberOfTriangles(inputTriangles));
}

// What the other pieces of a distributed surface impose on this process's piece (see the header);
// for a single process, the filter's own target and the mesh's diagonal.
struct PieceSetting
{
  slod::Index Target = 0;
  slod::Index UnionTarget = 0;
  slod::Index UnionTriangles = 0;
  double Diagonal = 0.0;
  slod::PieceSeam Seam;
};

// Collective when the controller runs several processes: every process calls it, whatever its piece.
PieceSetting SettleWithOtherPieces(vtkQuadricTriangleCollapse* filter, const slod::TriangleMesh& mesh)
{
  vtkLogScopeF(TRACE, "vtkQuadricTriangleCollapse: settle with the other pieces");
  vtkMultiProcessController* controller = filter->GetController();
  PieceSetting setting;
  setting.Target = slod::PieceShareOfTarget(controller, mesh.NumberOfTriangles(),
    [filter, &setting](slod::Index total) {
      setting.UnionTriangles = total;
      return TargetTriangles(filter, total);
    },
    &setting.UnionTarget);
  setting.Diagonal = slod::UnionBoundingBoxDiagonal(mesh, controller);
  if (slod::IsDistributed(controller))
  {
    setting.Seam = slod::FindPieceSeam(mesh, controller);
  }
  return setting;
}

slod::TriangleCollapseOptions CollapseOptions(vtkQuadricTriangleCollapse* filter, slod::Index target, double diagonal)
{
  slod::TriangleCollapseOptions options;
  options.TargetTriangles = target;
  const double maximumError = filter->GetMaximumError();
  options.MaximumError =
    maximumError <= 0 ? -1.0 : (filter->GetMaximumErrorIsRelative() ? maximumError * diagonal : maximumError);
  options.BoundaryWeight = filter->GetBoundaryWeight();
  options.MaximumNormalDeviation = filter->GetMaximumNormalDeviation();
  options.AllowTopologyChange = filter->GetAllowTopologyChange();
  options.ExactUnion = filter->GetExactUnion();
  options.RefineDeviation = filter->GetDeviationRefinement();
  options.FitToOriginal = filter->GetFitToOriginal();
  options.EdgeCollapses = filter->GetEdgeCollapses();
  options.EdgeCollapseBias = filter->GetEdgeCollapseBias();
  options.RecordHistory = filter->GetGenerateProgressiveMesh();
  options.BatchCollapses = filter->GetBatchCollapses();
  options.BatchCostTolerance = filter->GetBatchCostTolerance();
  options.BatchMinimumSize = filter->GetBatchMinimumSize();
  options.LookAheadEvaluations = filter->GetLookAheadEvaluations();
  options.TriangleCostBound = filter->GetTriangleCostBound();
  options.FitExactAssignmentLimit = filter->GetFitExactAssignmentLimit();
  options.Schedule = filter->GetCollapseSchedule() == vtkQuadricTriangleCollapse::PASSES ? slod::CollapseSchedule::Passes
                                                                                          : slod::CollapseSchedule::Queue;
  options.PassGoalShare = filter->GetPassGoalShare();
  options.PassErrorFactor = filter->GetPassErrorFactor();
  options.PassRemovalShare = filter->GetPassRemovalShare();
  options.Progress = slod::FilterProgress(filter);
  return options;
}

// Copies n values of a typed array (by pointer: the reload runs at the collapses' end, on every
// run of the filter).
template <typename From, typename To>
void CopyValues(const From* from, size_t n, To* to)
{
  std::transform(from, from + n, to, [](From x) { return static_cast<To>(x); });
}

// The input's points and triangles as a mesh, when every cell of the input is a triangle (false
// otherwise, `mesh` then unspecified).
bool InputAsMesh(vtkPolyData* input, slod::TriangleMesh& mesh)
{
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nv = input->GetNumberOfPoints(), nt = polys ? polys->GetNumberOfCells() : 0;
  if (!polys || nv > vtkIdType(std::numeric_limits<slod::Index>::max()) ||
    input->GetNumberOfVerts() + input->GetNumberOfLines() + input->GetNumberOfStrips() > 0 ||
    polys->GetNumberOfConnectivityIds() != 3 * nt)
  {
    return false;
  }
  for (vtkIdType t = 0; t < nt; ++t)
  {
    if (polys->GetCellSize(t) != 3)
    {
      return false;
    }
  }
  slod::AssignOnHugePages(mesh.Points, 3 * size_t(nv), 0.0);
  vtkDataArray* coordinates = nv > 0 ? input->GetPoints()->GetData() : nullptr;
  if (auto* floats = vtkArrayDownCast<vtkFloatArray>(coordinates))
  {
    CopyValues(floats->GetPointer(0), mesh.Points.size(), mesh.Points.data());
  }
  else if (auto* doubles = vtkArrayDownCast<vtkDoubleArray>(coordinates))
  {
    CopyValues(doubles->GetPointer(0), mesh.Points.size(), mesh.Points.data());
  }
  else
  {
    for (vtkIdType i = 0; i < nv; ++i)
    {
      input->GetPoint(i, &mesh.Points[3 * size_t(i)]);
    }
  }
  slod::AssignOnHugePages(mesh.Triangles, 3 * size_t(nt), slod::Index(0));
  if (polys->IsStorage64Bit())
  {
    CopyValues(polys->GetConnectivityArray64()->GetPointer(0), mesh.Triangles.size(), mesh.Triangles.data());
  }
  else
  {
    CopyValues(polys->GetConnectivityArray32()->GetPointer(0), mesh.Triangles.size(), mesh.Triangles.data());
  }
  return true;
}

// Whether the prepared mesh holds exactly (bit for bit) the input's points and triangles in the
// input's ids: nothing was merged, removed, flipped or triangulated. Checked, not assumed: the
// collapser then reads the input again after the collapses (InputAsMesh) instead of holding a
// copy of it through them.
bool PreparedMeshIsInput(vtkPolyData* input, const slod::TriangleMesh& mesh)
{
  if (input->GetNumberOfPoints() != vtkIdType(mesh.NumberOfPoints()) ||
    !input->GetPolys() || input->GetPolys()->GetNumberOfCells() != vtkIdType(mesh.NumberOfTriangles()))
  {
    return false;
  }
  slod::TriangleMesh again;
  return InputAsMesh(input, again) && again.Triangles == mesh.Triangles && mesh.Points.size() == again.Points.size() &&
    (mesh.Points.empty() ||
      std::memcmp(mesh.Points.data(), again.Points.data(), mesh.Points.size() * sizeof(double)) == 0);
}

// PreserveAttributeSeams: per prepared vertex, 1 on an attribute seam or a region border (empty
// when the option is off or there is nothing to keep).
std::vector<unsigned char> FeatureVertices(vtkQuadricTriangleCollapse* filter, vtkPolyData* input,
  const slod::TriangleMesh& mesh, const std::vector<unsigned char>& borderVertices,
  const std::vector<slod::Index>& vertexToInput,
  const std::vector<slod::Index>& triangleToCell)
{
  std::vector<unsigned char> pinned;
  if (!filter->GetPreserveAttributeSeams())
  {
    return pinned;
  }
  pinned = slod::AttributeSeamVertexFlags(
    mesh, borderVertices, input->GetPointData(), vertexToInput, 1e-6 * mesh.BoundingBoxDiagonal());
  const char* name = filter->GetRegionArrayName();
  if (name && *name)
  {
    vtkDataArray* regions = input->GetCellData()->GetArray(name);
    if (!regions)
    {
      vtkWarningWithObjectMacro(filter, << "RegionArrayName '" << name << "': the input has no such cell array; no region border is kept.");
    }
    const std::vector<unsigned char> borders =
      slod::RegionBorderVertexFlags(mesh, regions, triangleToCell.empty() ? nullptr : &triangleToCell);
    for (size_t v = 0; v < pinned.size() && v < borders.size(); ++v)
    {
      pinned[v] |= borders[v];
    }
  }
  if (std::find(pinned.begin(), pinned.end(), 1) == pinned.end())
  {
    pinned.clear();
  }
  return pinned;
}

// AttributeErrorMetric: the active point attributes in the metric, their components' place among
// the values, and the values and scales the algorithm takes.
struct MetricArray
{
  int Attribute, First, Components;
};
struct AttributeMetricSetting
{
  slod::AttributeErrorTerms Terms;
  std::vector<MetricArray> Arrays;
};

// The largest component range of `array` over the mesh's points (2 for unit normals); -1 when a
// value is not finite.
double AttributeRange(vtkDataArray* array, int attribute, const std::vector<slod::Index>& vertexToInput)
{
  double largest = 0.0;
  for (int c = 0; c < array->GetNumberOfComponents(); ++c)
  {
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (slod::Index p : vertexToInput)
    {
      const double value = array->GetComponent(p, c);
      if (!std::isfinite(value))
      {
        return -1.0;
      }
      low = std::min(low, value);
      high = std::max(high, value);
    }
    largest = std::max(largest, high - low);
  }
  return attribute == vtkDataSetAttributes::NORMALS && largest > 0 ? 2.0 : largest;
}

AttributeMetricSetting AttributeMetric(vtkQuadricTriangleCollapse* filter, vtkPointData* pointData,
  const std::vector<slod::Index>& vertexToInput, double diagonal)
{
  AttributeMetricSetting setting;
  if (!filter->GetAttributeErrorMetric() || !pointData || vertexToInput.empty())
  {
    return setting;
  }
  if (filter->GetExactUnion())
  {
    vtkWarningWithObjectMacro(filter, << "AttributeErrorMetric is not combined with ExactUnion: geometry only.");
    return setting;
  }
  const std::pair<int, double> kinds[5] = { { vtkDataSetAttributes::SCALARS, filter->GetScalarsWeight() },
    { vtkDataSetAttributes::VECTORS, filter->GetVectorsWeight() },
    { vtkDataSetAttributes::NORMALS, filter->GetNormalsWeight() },
    { vtkDataSetAttributes::TCOORDS, filter->GetTCoordsWeight() },
    { vtkDataSetAttributes::TENSORS, filter->GetTensorsWeight() } };
  const slod::Index needed = *std::max_element(vertexToInput.begin(), vertexToInput.end()) + 1;
  std::vector<vtkDataArray*> arrays;
  for (const auto& kind : kinds)
  {
    vtkDataArray* array = pointData->GetAttribute(kind.first);
    if (!array || !(kind.second > 0) || array->GetNumberOfTuples() < needed)
    {
      continue;
    }
    const double range = AttributeRange(array, kind.first, vertexToInput);
    if (range < 0)
    {
      vtkWarningWithObjectMacro(filter, << "AttributeErrorMetric: the " << vtkDataSetAttributes::GetAttributeTypeAsString(kind.first)
                                        << " have values that are not finite: left out of the metric.");
    }
    if (!(range > 0))
    {
      continue; // constant (nothing to keep) or not finite
    }
    const int components = array->GetNumberOfComponents();
    setting.Arrays.push_back({ kind.first, setting.Terms.Components, components });
    setting.Terms.Components += components;
    setting.Terms.Scales.insert(setting.Terms.Scales.end(), size_t(components), kind.second * diagonal / range);
    arrays.push_back(array);
  }
  const int m = setting.Terms.Components;
  setting.Terms.Values.resize(size_t(m) * vertexToInput.size());
  for (size_t v = 0; v < vertexToInput.size(); ++v)
  {
    double* values = setting.Terms.Values.data() + size_t(m) * v;
    for (size_t a = 0; a < arrays.size(); ++a)
    {
      for (int c = 0; c < setting.Arrays[a].Components; ++c)
      {
        values[setting.Arrays[a].First + c] = arrays[a]->GetComponent(vertexToInput[v], c);
      }
    }
  }
  return setting;
}

// The metric's values of the merged vertices into the output's attributes (integers rounded and
// clamped to their type, normals renormalised).
void StoreMetricValues(const AttributeMetricSetting& setting, const slod::TriangleCollapseResult& result, vtkPointData* pointData)
{
  const int m = setting.Terms.Components;
  if (result.AttributeValuesSet.empty() || m == 0)
  {
    return;
  }
  for (const MetricArray& entry : setting.Arrays)
  {
    vtkDataArray* array = pointData->GetAttribute(entry.Attribute);
    if (!array || array->GetNumberOfComponents() != entry.Components)
    {
      continue;
    }
    const bool integral = array->GetDataType() != VTK_FLOAT && array->GetDataType() != VTK_DOUBLE;
    for (size_t i = 0; i < result.AttributeValuesSet.size(); ++i)
    {
      for (int c = 0; result.AttributeValuesSet[i] && c < entry.Components; ++c)
      {
        double value = result.AttributeValues[i * size_t(m) + size_t(entry.First + c)];
        if (integral)
        {
          value = std::min(array->GetDataTypeMax(), std::max(array->GetDataTypeMin(), std::round(value)));
        }
        array->SetComponent(static_cast<vtkIdType>(i), c, value);
      }
    }
  }
  slod::PointAttributes::RenormalizeNormals(pointData);
}

// The simplified mesh, its merged point data and the per-vertex and maximum errors.
void StoreSimplifiedMesh(const slod::TriangleCollapseResult& result, const slod::PointAttributes& attributes,
  int pointType, double diagonal, vtkPolyData* output)
{
  vtkLogScopeF(TRACE, "vtkQuadricTriangleCollapse: output");
  slod::MeshToPolyData(result.Mesh, output, pointType);
  attributes.Store(output->GetPointData(), result.OutputToInput);
  const vtkIdType outPoints = static_cast<vtkIdType>(result.OutputToInput.size());
  auto error = slod::NewDoubleArray("SimplificationError", 1, outPoints);
  std::copy(result.VertexError.begin(), result.VertexError.end(), error->GetPointer(0));
  output->GetPointData()->AddArray(error);
  AddScalar(output->GetFieldData(), "MaximumSimplificationError", result.MaximumError);
  AddScalar(output->GetFieldData(), "MaximumSimplificationErrorRelative", diagonal > 0 ? result.MaximumError / diagonal : 0.0);
}

// The ids that tie the output to the input, and the collapse records (port 1).
void StoreProgressiveMesh(const slod::TriangleCollapseResult& result, slod::Index inputPoints,
  slod::Index inputTriangles, vtkPolyData* output, vtkTable* records)
{
  auto vertexIds = slod::NewIdArray("OriginalVertexId", 1, static_cast<vtkIdType>(result.OutputToInput.size()));
  std::copy(result.OutputToInput.begin(), result.OutputToInput.end(), vertexIds->GetPointer(0));
  output->GetPointData()->AddArray(vertexIds);
  auto triangleIds = slod::NewIdArray("OriginalTriangleId", 1, static_cast<vtkIdType>(result.OutputTriangleIds.size()));
  std::copy(result.OutputTriangleIds.begin(), result.OutputTriangleIds.end(), triangleIds->GetPointer(0));
  output->GetCellData()->AddArray(triangleIds);
  if (records)
  {
    slod::CollapseRecordsToTable(result.History, inputPoints, inputTriangles, records);
  }
}
} // namespace

vtkQuadricTriangleCollapse::vtkQuadricTriangleCollapse()
{
  this->AddSecondaryOutputPort("vtkTable");
  this->SetController(vtkMultiProcessController::GetGlobalController());
}

vtkQuadricTriangleCollapse::~vtkQuadricTriangleCollapse()
{
  this->SetController(nullptr);
  this->SetRegionArrayName(nullptr);
}

vtkCxxSetObjectMacro(vtkQuadricTriangleCollapse, Controller, vtkMultiProcessController);

vtkTable* vtkQuadricTriangleCollapse::GetCollapseRecords()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(1));
}

int vtkQuadricTriangleCollapse::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkSmartPointer<vtkPolyData> input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkTable* records = vtkTable::GetData(outputVector, 1);
  this->ActualReduction = 0.0;
  this->NumberOfCollapses = 0;
  this->NumberOfEdgeCollapses = 0;
  this->NumberOfFittedVertices = 0;
  this->NumberOfRefinedVertices = 0;
  this->MaximumSimplificationError = 0.0;
  if (!input || !output)
  {
    return 1;
  }
  // A piece of a distributed surface: the cells other pieces own are theirs to simplify.
  if (slod::IsDistributed(this->Controller))
  {
    input = slod::WithoutGhostCells(input);
  }
  slod::StageClock stages("vtkQuadricTriangleCollapse");
  slod::TriangleMesh mesh;
  std::vector<slod::Index> vertexToInput, triangleToCell;
  slod::PreparationReport report;
  bool prepared = false;
  {
    vtkLogScopeF(TRACE, "vtkQuadricTriangleCollapse: input preparation");
    prepared = slod::PrepareFilterInput(this, input, slod::PreparationOptions(), mesh, vertexToInput, &report,
      slod::CellMapIfNeeded(input, triangleToCell));
  }
  stages.Lap("input preparation");
  const PieceSetting piece = SettleWithOtherPieces(this, mesh); // collective: before any return
  const slod::Index inputTriangles = mesh.NumberOfTriangles();
  const slod::Index inputPoints = mesh.NumberOfPoints();
  // Collective while collapsing: every process takes part until the pieces' targets are settled.
  std::unique_ptr<slod::UnionTargetAgreement> agreement;
  if (slod::IsDistributed(this->Controller))
  {
    agreement.reset(new slod::UnionTargetAgreement(
      this->Controller, piece.UnionTarget, piece.Diagonal, mesh.NumberOfTriangles(), piece.Target));
  }
  if (!prepared || inputTriangles == 0)
  {
    if (agreement)
    {
      agreement->Finish(0);
    }
    return 1;
  }
  const double diagonal = piece.Diagonal;
  slod::TriangleCollapseOptions options = CollapseOptions(this, piece.Target, diagonal);
  options.NonManifoldVertices = &report.NonManifoldVertexFlags;
  options.LockedVertices = piece.Seam.SharedVertices.empty() ? nullptr : &piece.Seam.SharedVertices;
  if (piece.UnionTriangles > inputTriangles)
  {
    // The fit's exact assignment is chosen by the size of the whole surface, as in one process,
    // not by the piece's: pieces of a large surface would otherwise each pay for the exact one.
    options.FitExactAssignmentLimit = static_cast<slod::Index>(
      double(options.FitExactAssignmentLimit) * double(inputTriangles) / double(piece.UnionTriangles));
  }
  if (agreement)
  {
    options.SettleTarget = std::ref(*agreement);
  }
  const std::vector<unsigned char> pinned = FeatureVertices(this, input, mesh, report.BoundaryVertexFlags, vertexToInput, triangleToCell);
  options.PinnedVertices = pinned.empty() ? nullptr : &pinned;
  // Read by FeatureVertices and by the collapses' preparation, which releases them (1 byte per
  // vertex not held through the collapses): the quadrics then search only these vertices' fans
  // for border edges.
  options.BorderVertices = &report.BoundaryVertexFlags;
  slod::PointAttributes attributes;
  attributes.Load(input->GetPointData(), vertexToInput);
  const AttributeMetricSetting metric = AttributeMetric(this, input->GetPointData(), vertexToInput, diagonal);
  options.AttributeError = metric.Terms.Components > 0 ? &metric.Terms : nullptr;
  std::vector<slod::Index>().swap(vertexToInput);
  stages.Lap("seams and point data");

  if ((options.RefineDeviation || options.FitToOriginal) && !slod::IsDistributed(this->Controller) &&
    PreparedMeshIsInput(input, mesh))
  {
    options.ReloadInput = [input](slod::TriangleMesh& original) { InputAsMesh(input, original); };
  }

  slod::TriangleCollapseResult result;
  slod::SimplifyByTriangleCollapse(mesh, options, result, &attributes);
  stages.Lap("simplification");
  const slod::Index target = agreement ? agreement->Finish(result.Mesh.NumberOfTriangles()) : piece.Target;
  if (agreement)
  {
    vtkLogF(TRACE, "piece %d: target %lld agreed in %d rounds (proportional share %lld), %.3f s in the rounds",
      this->Controller->GetLocalProcessId(), static_cast<long long>(target), agreement->LevelsExchanged(),
      static_cast<long long>(piece.Target), agreement->ExchangeSeconds());
  }
  if (result.Aborted)
  {
    slod::ReportAbort(this, output);
    return 1;
  }

  StoreSimplifiedMesh(result, attributes, slod::OutputPointType(input, this->OutputPointsPrecision), diagonal, output);
  StoreMetricValues(metric, result, output->GetPointData());
  // Each surviving triangle keeps its own input cell's data.
  slod::StoreCellData(input, triangleToCell, result.OutputTriangleIds, output);
  if (this->GenerateProgressiveMesh)
  {
    StoreProgressiveMesh(result, inputPoints, inputTriangles, output, records);
  }
  stages.Lap("output");
  this->NumberOfCollapses = result.Collapses;
  this->NumberOfEdgeCollapses = result.EdgeCollapses;
  this->NumberOfFittedVertices = result.FittedVertices;
  this->NumberOfRefinedVertices = result.RefinedVertices;
  this->MaximumSimplificationError = result.MaximumError;
  this->ActualReduction = 1.0 - double(result.Mesh.NumberOfTriangles()) / double(inputTriangles);
  if (result.PinnedVerticesReleased)
  {
    vtkWarningMacro(<< "The target needed collapses of attribute-seam or region-border vertices: they were released "
                       "(PreserveAttributeSeams holds only as long as the target allows).");
  }
  if (result.WorkBoundReached)
  {
    vtkWarningMacro(<< "Stopped by the bound on the collapse loop's work after " << result.Collapses << " collapses.");
  }
  // A maximum error that stops the collapses first is a target met, not missed.
  const bool stoppedByError = options.MaximumError >= 0 && result.StoppedByError;
  slod::ReportTarget(this, output, target, result.Mesh.NumberOfTriangles() <= target || stoppedByError,
    "every further collapse would change the topology, fold a triangle or touch a locked vertex (non-manifold, or "
    "on the seam with another piece)");
  return 1;
}

void vtkQuadricTriangleCollapse::UsePaperConfiguration()
{
  this->SetEdgeCollapses(false);
  this->SetExactUnion(true);
  this->SetFitToOriginal(false);
  this->SetDeviationRefinement(false);
}

void vtkQuadricTriangleCollapse::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "BoundaryWeight: " << this->BoundaryWeight << "\n";
  os << indent << "MaximumNormalDeviation: " << this->MaximumNormalDeviation << "\n";
  os << indent << "AllowTopologyChange: " << this->AllowTopologyChange << "\n";
  os << indent << "ExactUnion: " << this->ExactUnion << "\n";
  os << indent << "DeviationRefinement: " << this->DeviationRefinement << "\n";
  os << indent << "FitToOriginal: " << this->FitToOriginal << "\n";
  os << indent << "EdgeCollapses: " << this->EdgeCollapses << "\n";
  os << indent << "EdgeCollapseBias: " << this->EdgeCollapseBias << "\n";
  os << indent << "GenerateProgressiveMesh: " << this->GenerateProgressiveMesh << "\n";
  os << indent << "BatchCollapses: " << this->BatchCollapses << "\n";
  os << indent << "BatchCostTolerance: " << this->BatchCostTolerance << "\n";
  os << indent << "BatchMinimumSize: " << this->BatchMinimumSize << "\n";
  os << indent << "LookAheadEvaluations: " << this->LookAheadEvaluations << "\n";
  os << indent << "TriangleCostBound: " << this->TriangleCostBound << "\n";
  os << indent << "FitExactAssignmentLimit: " << this->FitExactAssignmentLimit << "\n";
  os << indent << "CollapseSchedule: " << (this->CollapseSchedule == PASSES ? "Passes" : "Queue") << "\n";
  os << indent << "PassGoalShare: " << this->PassGoalShare << "\n";
  os << indent << "PassErrorFactor: " << this->PassErrorFactor << "\n";
  os << indent << "PassRemovalShare: " << this->PassRemovalShare << "\n";
  os << indent << "PreserveAttributeSeams: " << this->PreserveAttributeSeams << "\n";
  os << indent << "RegionArrayName: " << (this->RegionArrayName ? this->RegionArrayName : "(none)") << "\n";
  os << indent << "AttributeErrorMetric: " << this->AttributeErrorMetric << "\n";
  os << indent << "ScalarsWeight: " << this->ScalarsWeight << "\n";
  os << indent << "VectorsWeight: " << this->VectorsWeight << "\n";
  os << indent << "NormalsWeight: " << this->NormalsWeight << "\n";
  os << indent << "TCoordsWeight: " << this->TCoordsWeight << "\n";
  os << indent << "TensorsWeight: " << this->TensorsWeight << "\n";
  os << indent << "Controller: " << this->Controller << "\n";
  os << indent << "ActualReduction: " << this->ActualReduction << "\n";
  os << indent << "NumberOfCollapses: " << this->NumberOfCollapses << "\n";
  os << indent << "NumberOfEdgeCollapses: " << this->NumberOfEdgeCollapses << "\n";
  os << indent << "NumberOfFittedVertices: " << this->NumberOfFittedVertices << "\n";
  os << indent << "NumberOfRefinedVertices: " << this->NumberOfRefinedVertices << "\n";
  os << indent << "MaximumSimplificationError: " << this->MaximumSimplificationError << "\n";
}
