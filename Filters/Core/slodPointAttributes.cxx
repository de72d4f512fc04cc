// SPDX-License-Identifier: BSD-3-Clause
#include "slodPointAttributes.h"

#include "slodAttributeTransfer.h"

#include "vtkAbstractArray.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkPointData.h"

#include <cmath>
#include <cstring>

namespace slod
{
PointAttributes::PointAttributes() = default;
PointAttributes::~PointAttributes() = default;

bool PointAttributes::Empty() const
{
  return this->GetNumberOfArrays() == 0;
}

int PointAttributes::GetNumberOfArrays() const
{
  return this->Data ? this->Data->GetNumberOfArrays() : 0;
}

namespace
{
// Which array of `scratch` (made by scratch->InterpolateAllocate(data)) receives each array of
// `data`: InterpolateAllocate keeps the order of the arrays it takes and leaves out only the ones
// VTK does not interpolate (vtkIdType arrays), which get -1. Checked by name, type and components.
std::vector<int> InterpolatedArrayMap(vtkPointData* data, vtkPointData* scratch)
{
  std::vector<int> map(size_t(data->GetNumberOfArrays()), -1);
  int next = 0;
  for (int a = 0; a < data->GetNumberOfArrays() && next < scratch->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* from = data->GetAbstractArray(a);
    vtkAbstractArray* to = scratch->GetAbstractArray(next);
    const bool sameName = (!from->GetName() && !to->GetName()) ||
      (from->GetName() && to->GetName() && std::strcmp(from->GetName(), to->GetName()) == 0);
    if (sameName && from->GetDataType() == to->GetDataType() &&
      from->GetNumberOfComponents() == to->GetNumberOfComponents())
    {
      map[size_t(a)] = next++;
    }
  }
  return map;
}
} // namespace

void PointAttributes::Load(vtkPointData* input, const std::vector<Index>& rowToInputPoint)
{
  this->Data = nullptr;
  this->Scratch = nullptr;
  this->ScratchArrayOf.clear();
  this->Rows = 0;
  if (!input || input->GetNumberOfArrays() == 0 || rowToInputPoint.empty())
  {
    return;
  }
  Index inputPoints = 0;
  for (Index p : rowToInputPoint)
  {
    inputPoints = std::max(inputPoints, p + 1);
  }
  this->Data = vtkSmartPointer<vtkPointData>::New();
  CopyAttributeTuples(input, inputPoints, rowToInputPoint, this->Data);
  this->Rows = static_cast<Index>(rowToInputPoint.size());
  // Interpolation flags: every attribute weighted, except the ids, which are labels (VTK's
  // nearest-neighbour mode, 2) rather than left out as VTK's defaults would. InterpolateAllocate
  // resets the flags to VTK's defaults once it has chosen the arrays, and InterpolatePoint reads
  // them again: they are set before (all arrays taken) and after (the ids' mode).
  this->Scratch = vtkSmartPointer<vtkPointData>::New();
  this->Scratch->CopyAllOn(vtkDataSetAttributes::INTERPOLATE);
  this->Scratch->InterpolateAllocate(this->Data, 1);
  this->Scratch->SetCopyAttribute(vtkDataSetAttributes::GLOBALIDS, 2, vtkDataSetAttributes::INTERPOLATE);
  this->Scratch->SetCopyAttribute(vtkDataSetAttributes::PEDIGREEIDS, 2, vtkDataSetAttributes::INTERPOLATE);
  this->ScratchArrayOf = InterpolatedArrayMap(this->Data, this->Scratch);
}

void PointAttributes::InterpolateInto(Index target, const Index* sources, const double* weights, int count)
{
  if (this->Empty() || count <= 0)
  {
    return;
  }
  double total = 0;
  for (int i = 0; i < count; ++i)
  {
    total += weights[i];
  }
  this->Weights.resize(size_t(count));
  this->Ids->SetNumberOfIds(count);
  int heaviest = 0;
  for (int i = 0; i < count; ++i)
  {
    this->Weights[size_t(i)] = total > 0 ? weights[i] / total : 1.0 / count;
    this->Ids->SetId(i, sources[i]);
    heaviest = this->Weights[size_t(i)] > this->Weights[size_t(heaviest)] ? i : heaviest;
  }
  // VTK 9.1's nearest-neighbour mode compares the weights with an integer (0), so it takes the last
  // positive weight: the heaviest source goes last.
  std::swap(this->Weights[size_t(heaviest)], this->Weights.back());
  const vtkIdType heaviestId = this->Ids->GetId(heaviest);
  this->Ids->SetId(heaviest, this->Ids->GetId(count - 1));
  this->Ids->SetId(count - 1, heaviestId);

  // Into the scratch tuple first (target may be a source), then into the row.
  this->Scratch->InterpolatePoint(this->Data, 0, this->Ids, this->Weights.data());
  for (int a = 0; a < this->Data->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = this->Data->GetAbstractArray(a);
    const int interpolated = this->ScratchArrayOf[size_t(a)];
    if (interpolated >= 0)
    {
      array->InsertTuple(target, 0, this->Scratch->GetAbstractArray(interpolated));
    }
    else
    {
      array->InsertTuple(target, heaviestId, array);
    }
  }
}

void PointAttributes::Merge(Index target, const Index* sources, const double* weights, int count)
{
  this->InterpolateInto(target, sources, weights, count);
}

Index PointAttributes::AddInterpolated(const Index* sources, const double* weights, int count)
{
  const Index row = this->Rows;
  if (!this->Empty())
  {
    this->InterpolateInto(row, sources, weights, count);
    ++this->Rows;
  }
  return row;
}

void PointAttributes::RemoveRowsFrom(Index rows)
{
  if (this->Empty() || rows < 0 || rows >= this->Rows)
  {
    return;
  }
  for (int a = 0; a < this->Data->GetNumberOfArrays(); ++a)
  {
    this->Data->GetAbstractArray(a)->SetNumberOfTuples(rows);
  }
  this->Rows = rows;
}

void PointAttributes::Store(vtkPointData* output, const std::vector<Index>& outputToRow) const
{
  if (this->Empty())
  {
    return;
  }
  CopyAttributeTuples(this->Data, this->Rows, outputToRow, output);
  RenormalizeNormals(output);
}

void PointAttributes::RenormalizeNormals(vtkPointData* pointData)
{
  vtkDataArray* normals = pointData ? pointData->GetNormals() : nullptr;
  if (!normals || normals->GetNumberOfComponents() != 3)
  {
    return;
  }
  for (vtkIdType i = 0; i < normals->GetNumberOfTuples(); ++i)
  {
    double n[3];
    normals->GetTuple(i, n);
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (length > 0)
    {
      normals->SetTuple3(i, n[0] / length, n[1] / length, n[2] / length);
    }
  }
}
} // namespace slod
