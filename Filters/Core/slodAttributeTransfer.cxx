// SPDX-License-Identifier: BSD-3-Clause
#include "slodAttributeTransfer.h"

#include "slodTriangleBVH.h"

#include "vtkAbstractArray.h"
#include "vtkCellData.h"
#include "vtkDataSetAttributes.h"
#include "vtkLogger.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

namespace slod
{
vtkSmartPointer<vtkDataSetAttributes> CarriableArrays(vtkDataSetAttributes* attributes, vtkIdType tuples)
{
  auto carriable = vtk::TakeSmartPointer(attributes->NewInstance());
  carriable->ShallowCopy(attributes);
  for (int a = carriable->GetNumberOfArrays() - 1; a >= 0; --a)
  {
    vtkAbstractArray* array = carriable->GetAbstractArray(a);
    int sameName = -1;
    if (array && array->GetName())
    {
      carriable->GetAbstractArray(array->GetName(), sameName);
    }
    if (!array || array->GetNumberOfTuples() < tuples || (sameName >= 0 && sameName < a))
    {
      carriable->RemoveArray(a);
    }
  }
  return carriable;
}

void CopyAttributeTuples(vtkDataSetAttributes* input, vtkIdType inputTuples, const std::vector<Index>& outputToInput,
  vtkDataSetAttributes* output)
{
  if (!input || input->GetNumberOfArrays() == 0)
  {
    return;
  }
  vtkSmartPointer<vtkDataSetAttributes> source = CarriableArrays(input, inputTuples);
  // Copied into a fresh object whose flags are all on, then passed to the output: the output's own
  // copy flags (which downstream filters may rely on) stay as they were.
  auto copied = vtk::TakeSmartPointer(input->NewInstance());
  copied->CopyAllOn(vtkDataSetAttributes::COPYTUPLE);
  copied->CopyAllocate(source, static_cast<vtkIdType>(outputToInput.size()));
  for (size_t i = 0; i < outputToInput.size(); ++i)
  {
    copied->CopyData(source, outputToInput[i], static_cast<vtkIdType>(i));
  }
  output->PassData(copied);
}

std::vector<Index>* CellMapIfNeeded(vtkPolyData* input, std::vector<Index>& triangleToInputCell)
{
  triangleToInputCell.clear();
  return input && input->GetCellData()->GetNumberOfArrays() > 0 ? &triangleToInputCell : nullptr;
}

void StoreCellData(vtkPolyData* input, const std::vector<Index>& triangleToInputCell,
  const std::vector<Index>& outputToPreparedTriangle, vtkPolyData* output)
{
  if (triangleToInputCell.empty() || !input)
  {
    return;
  }
  std::vector<Index> outputToInputCell(outputToPreparedTriangle.size());
  for (size_t i = 0; i < outputToPreparedTriangle.size(); ++i)
  {
    const Index t = outputToPreparedTriangle[i];
    if (t < 0 || size_t(t) >= triangleToInputCell.size())
    {
      vtkLogF(ERROR, "Output triangle %zu names no input triangle: the cell data is not carried.", i);
      return;
    }
    outputToInputCell[i] = triangleToInputCell[size_t(t)];
  }
  CopyAttributeTuples(input->GetCellData(), input->GetNumberOfCells(), outputToInputCell, output->GetCellData());
}

void StoreNearestCellData(vtkPolyData* input, const std::vector<Index>& triangleToInputCell,
  const TriangleMesh& prepared, const std::vector<double>& points, const std::vector<Index>& triangles,
  vtkPolyData* output)
{
  if (!triangleToInputCell.empty())
  {
    StoreCellData(input, triangleToInputCell, NearestTrianglesToCentroids(prepared, points, triangles), output);
  }
}

std::vector<Index> NearestTrianglesToCentroids(
  const TriangleMesh& prepared, const std::vector<double>& points, const std::vector<Index>& triangles)
{
  if (prepared.NumberOfTriangles() == 0)
  {
    return {};
  }
  const TriangleBVH tree(prepared);
  std::vector<Index> nearest(triangles.size() / 3, InvalidIndex);
  vtkSMPTools::For(0, static_cast<vtkIdType>(nearest.size()), [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType t = begin; t < end; ++t)
    {
      Vec3 centroid{ 0, 0, 0 };
      for (int k = 0; k < 3; ++k)
      {
        const double* p = &points[3 * size_t(triangles[3 * size_t(t) + k])];
        for (int c = 0; c < 3; ++c)
        {
          centroid[c] += p[c] / 3.0;
        }
      }
      nearest[size_t(t)] = tree.ClosestPoint(centroid).Triangle;
    }
  });
  return nearest;
}
} // namespace slod
