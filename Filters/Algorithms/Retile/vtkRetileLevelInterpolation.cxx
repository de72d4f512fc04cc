// SPDX-License-Identifier: BSD-3-Clause
#include "vtkRetileLevelInterpolation.h"

#include "slodAttributeTransfer.h"
#include "slodFragmentTracking.h"
#include "slodInputPreparation.h"
#include "slodLevelInterpolation.h"
#include "slodRetiling.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

vtkStandardNewMacro(vtkRetileLevelInterpolation);

namespace
{
// The points at t (exact ends at 0 and 1) with their low and high positions as point data.
void StorePoints(const slod::LevelInterpolation& result, double t, int precision, vtkPolyData* output)
{
  const vtkIdType n = result.NumberOfPoints();
  vtkNew<vtkPoints> points;
  points->SetDataType(precision == vtkAlgorithm::SINGLE_PRECISION ? VTK_FLOAT : VTK_DOUBLE);
  points->SetNumberOfPoints(n);
  vtkNew<vtkDoubleArray> lowPositions, highPositions;
  lowPositions->SetName("LowPosition");
  highPositions->SetName("HighPosition");
  lowPositions->SetNumberOfComponents(3);
  highPositions->SetNumberOfComponents(3);
  lowPositions->SetNumberOfTuples(n);
  highPositions->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double* lo = &result.LowPositions[3 * i];
    const double* hi = &result.HighPositions[3 * i];
    // Exact ends: no rounding of (1 - t) * a + t * b at t = 0 or 1.
    const double p[3] = { t == 0 ? lo[0] : (t == 1 ? hi[0] : (1 - t) * lo[0] + t * hi[0]),
      t == 0 ? lo[1] : (t == 1 ? hi[1] : (1 - t) * lo[1] + t * hi[1]),
      t == 0 ? lo[2] : (t == 1 ? hi[2] : (1 - t) * lo[2] + t * hi[2]) };
    points->SetPoint(i, p);
    lowPositions->SetTypedTuple(i, lo);
    highPositions->SetTypedTuple(i, hi);
  }
  output->SetPoints(points);
  output->GetPointData()->AddArray(lowPositions);
  output->GetPointData()->AddArray(highPositions);
}

// The triangles with their high-detail triangle, low-detail triangle and fragment as cell data.
void StoreTriangles(const slod::LevelInterpolation& result, vtkPolyData* output)
{
  const vtkIdType m = result.NumberOfTriangles();
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(m, 3 * m);
  vtkNew<vtkIdTypeArray> highTriangle, lowTriangle, fragment;
  highTriangle->SetName("HighTriangle");
  lowTriangle->SetName("LowTriangle");
  fragment->SetName("Fragment");
  highTriangle->SetNumberOfTuples(m);
  lowTriangle->SetNumberOfTuples(m);
  fragment->SetNumberOfTuples(m);
  for (vtkIdType c = 0; c < m; ++c)
  {
    const vtkIdType ids[3] = { result.Triangles[3 * c], result.Triangles[3 * c + 1], result.Triangles[3 * c + 2] };
    polys->InsertNextCell(3, ids);
    highTriangle->SetValue(c, result.HighTriangle[c]);
    lowTriangle->SetValue(c, result.LowTriangle[c]);
    fragment->SetValue(c, result.Fragment[c]);
  }
  output->SetPolys(polys);
  output->GetCellData()->AddArray(highTriangle);
  output->GetCellData()->AddArray(lowTriangle);
  output->GetCellData()->AddArray(fragment);
}
// Where the low level's removal records (field data RetileRemovals of vtkRetile's nested levels)
// start for a high level of `highPoints` points: the records chain every finer level's removals,
// finest first; RetileRemovalsFinerPoints gives the point count of the level each run starts from
// and RetileRemovalsStart its first record (one run from record 0 when absent). -1 when the records
// start from no level of that size (not meant for this pair: not tried).
vtkIdType RecordStart(vtkPolyData* lowInput, vtkIdType highPoints)
{
  vtkFieldData* fieldData = lowInput->GetFieldData();
  vtkIdTypeArray* finerPoints = vtkIdTypeArray::SafeDownCast(fieldData->GetAbstractArray("RetileRemovalsFinerPoints"));
  vtkIdTypeArray* starts = vtkIdTypeArray::SafeDownCast(fieldData->GetAbstractArray("RetileRemovalsStart"));
  if (!finerPoints)
  {
    return 0;
  }
  for (vtkIdType i = 0; i < finerPoints->GetNumberOfValues(); ++i)
  {
    if (finerPoints->GetValue(i) == highPoints)
    {
      return starts && i < starts->GetNumberOfValues() ? starts->GetValue(i) : (i == 0 ? 0 : -1);
    }
  }
  return -1;
}

// The low level's removal records from record `start` on, in the prepared high mesh's vertex ids;
// false when there are none or one names no high vertex.
bool RemovalRecords(vtkIdTypeArray* records, vtkIdType start, const std::vector<slod::Index>& highToInput,
  vtkIdType highInputPoints, std::vector<slod::Index>& removals)
{
  if (!records || records->GetNumberOfComponents() != 2 || start < 0 || start > records->GetNumberOfTuples())
  {
    return false;
  }
  std::vector<slod::Index> inputToHigh(static_cast<size_t>(highInputPoints), slod::InvalidIndex);
  for (size_t v = 0; v < highToInput.size(); ++v)
  {
    inputToHigh[highToInput[v]] = static_cast<slod::Index>(v);
  }
  removals.resize(static_cast<size_t>(2 * (records->GetNumberOfTuples() - start)));
  bool valid = true;
  for (size_t i = 0; i < removals.size(); ++i)
  {
    // (-1 - x, y) is the flip of edge (x, y) (so -1 is a valid first value).
    const vtkIdType value = records->GetValue(2 * start + static_cast<vtkIdType>(i));
    const vtkIdType id = value >= 0 ? value : -1 - value;
    const slod::Index mapped = id < highInputPoints ? inputToHigh[id] : slod::InvalidIndex;
    valid = valid && mapped != slod::InvalidIndex && (value >= 0 || i % 2 == 0);
    removals[i] = value >= 0 || mapped == slod::InvalidIndex ? mapped : -1 - mapped;
  }
  return valid;
}
} // namespace

vtkRetileLevelInterpolation::vtkRetileLevelInterpolation()
{
  this->SetNumberOfInputPorts(2);
}

int vtkRetileLevelInterpolation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* highInput = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* lowInput = vtkPolyData::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->NumberOfSharedVertices = this->NumberOfFlattenedVertices = this->NumberOfCrossings = 0;
  this->NumberOfInsertedVertices = this->NumberOfTrackedRemovals = 0;
  this->NumberOfFragments = this->NumberOfUntracedEdges = this->NumberOfInconsistentFragments = 0;
  if (!highInput || !lowInput || !output)
  {
    vtkErrorMacro(<< "Needs the high-detail level (port 0) and the low-detail level (port 1).");
    return 1;
  }
  if (highInput->GetNumberOfPolys() + highInput->GetNumberOfStrips() == 0 ||
    lowInput->GetNumberOfPolys() + lowInput->GetNumberOfStrips() == 0)
  {
    vtkErrorMacro(<< "Both levels need triangles (high: " << highInput->GetNumberOfCells()
                  << " cells, low: " << lowInput->GetNumberOfCells() << " cells).");
    return 1;
  }
  slod::TriangleMesh high, low;
  std::vector<slod::Index> highToInput, lowToInput, highTriangleToCell;
  if (!slod::PrepareFilterInput(this, highInput, slod::PreparationOptions(), high, highToInput, nullptr,
        slod::CellMapIfNeeded(highInput, highTriangleToCell)) ||
    !slod::PrepareFilterInput(this, lowInput, slod::PreparationOptions(), low, lowToInput))
  {
    return 1;
  }
  for (const slod::TriangleMesh* level : { &high, &low })
  {
    const double extent = slod::ExtentPerMedianEdge(*level);
    if (!(extent <= slod::MaximumRetilingExtentPerEdge))
    {
      vtkErrorMacro(<< "A level's extent is " << extent << " times its median edge length (more than "
                    << slod::MaximumRetilingExtentPerEdge << "): its edges cannot be traced at that scale "
                    << "(a part far away from the others?).");
      return 1;
    }
  }
  this->UpdateProgress(0.1);
  slod::LevelInterpolation result;
  // Section 6.2 when the low level says how it came from the high one; else closest points.
  std::vector<slod::Index> removals;
  vtkIdTypeArray* records = vtkIdTypeArray::SafeDownCast(lowInput->GetFieldData()->GetAbstractArray("RetileRemovals"));
  // Records that start from no level of the high level's size are meant for another pair.
  const vtkIdType start = records ? RecordStart(lowInput, highInput->GetNumberOfPoints()) : -1;
  const bool recorded = this->UseRemovalRecords && start >= 0;
  if (recorded && RemovalRecords(records, start, highToInput, highInput->GetNumberOfPoints(), removals))
  {
    slod::TrackLevels(high, low, removals, result, slod::FilterProgress(this, 0.1, 0.9));
  }
  if (recorded && !result.Valid && !result.Aborted)
  {
    vtkWarningMacro(<< "The low-detail level's RetileRemovals do not turn the high-detail level into it ("
                    << (result.Error.empty() ? std::string("ids out of range") : result.Error)
                    << "): closest-point flattening is used instead.");
  }
  this->NumberOfTrackedRemovals = 0;
  for (size_t i = 0; result.Valid && i < removals.size(); i += 2)
  {
    this->NumberOfTrackedRemovals += removals[i] >= 0 ? 1 : 0; // (-1 - x, y): a flip
  }
  if (!result.Valid && !result.Aborted)
  {
    slod::InterpolateLevels(high, low, result, slod::FilterProgress(this, 0.1, 0.9));
  }
  if (result.Aborted)
  {
    slod::ReportAbort(this, output);
    return 1;
  }
  if (!result.Valid)
  {
    vtkErrorMacro(<< "Cannot interpolate: " << result.Error << ".");
    return 1;
  }
  this->UpdateProgress(0.9);
  this->NumberOfSharedVertices = result.SharedVertices;
  this->NumberOfFlattenedVertices = result.FlattenedVertices;
  this->NumberOfInsertedVertices = result.InsertedVertices;
  this->NumberOfCrossings = result.Crossings;
  this->NumberOfFragments = result.Fragments;
  this->NumberOfUntracedEdges = result.UntracedEdges;
  this->NumberOfInconsistentFragments = result.InconsistentFragments;
  if (result.UntracedEdges > 0 || result.InconsistentFragments > 0)
  {
    vtkWarningMacro(<< result.UntracedEdges << " high-detail edges could not be traced on the low-detail surface and "
                    << result.InconsistentFragments
                    << " fragments are not inside one low-detail triangle: the T = 0 shape departs from the low level there.");
  }

  StorePoints(result, this->T, this->OutputPointsPrecision, output);
  // Each fragment carries the cell data of the high-detail triangle it is part of.
  slod::StoreCellData(highInput, highTriangleToCell, result.HighTriangle, output);
  StoreTriangles(result, output);
  return 1;
}

void vtkRetileLevelInterpolation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "T: " << this->T << "\n";
  os << indent << "OutputPointsPrecision: " << this->OutputPointsPrecision << "\n";
  os << indent << "UseRemovalRecords: " << this->UseRemovalRecords << "\n";
  os << indent << "NumberOfTrackedRemovals: " << this->NumberOfTrackedRemovals << "\n";
  os << indent << "NumberOfSharedVertices: " << this->NumberOfSharedVertices << "\n";
  os << indent << "NumberOfFlattenedVertices: " << this->NumberOfFlattenedVertices << "\n";
  os << indent << "NumberOfInsertedVertices: " << this->NumberOfInsertedVertices << "\n";
  os << indent << "NumberOfCrossings: " << this->NumberOfCrossings << "\n";
  os << indent << "NumberOfFragments: " << this->NumberOfFragments << "\n";
  os << indent << "NumberOfUntracedEdges: " << this->NumberOfUntracedEdges << "\n";
  os << indent << "NumberOfInconsistentFragments: " << this->NumberOfInconsistentFragments << "\n";
}
