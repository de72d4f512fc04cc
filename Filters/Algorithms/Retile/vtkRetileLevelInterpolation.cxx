// SPDX-License-Identifier: BSD-3-Clause
#include "vtkRetileLevelInterpolation.h"

#include "slodAttributeTransfer.h"
#include "slodInputPreparation.h"
#include "slodLevelInterpolation.h"
#include "slodRetiling.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
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
  this->NumberOfInsertedVertices = 0;
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
  slod::InterpolateLevels(high, low, result);
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
  os << indent << "NumberOfSharedVertices: " << this->NumberOfSharedVertices << "\n";
  os << indent << "NumberOfFlattenedVertices: " << this->NumberOfFlattenedVertices << "\n";
  os << indent << "NumberOfInsertedVertices: " << this->NumberOfInsertedVertices << "\n";
  os << indent << "NumberOfCrossings: " << this->NumberOfCrossings << "\n";
  os << indent << "NumberOfFragments: " << this->NumberOfFragments << "\n";
  os << indent << "NumberOfUntracedEdges: " << this->NumberOfUntracedEdges << "\n";
  os << indent << "NumberOfInconsistentFragments: " << this->NumberOfInconsistentFragments << "\n";
}
