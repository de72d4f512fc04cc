// SPDX-License-Identifier: BSD-3-Clause
#include "slodPointAttributes.h"

#include "vtkDataArray.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <cmath>

namespace slod
{
void PointAttributes::Load(vtkPointData* input, const std::vector<Index>& rowToInputPoint)
{
  this->Arrays.clear();
  this->Values.clear();
  this->Width = 0;
  if (!input)
  {
    return;
  }
  const Index rowsRead =
    rowToInputPoint.empty() ? 0 : 1 + *std::max_element(rowToInputPoint.begin(), rowToInputPoint.end());
  for (int a = 0; a < input->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = input->GetArray(a);
    int sameName = -1;
    if (array && array->GetName())
    {
      input->GetAbstractArray(array->GetName(), sameName);
    }
    if (!array || array->GetNumberOfTuples() < rowsRead || (array->GetName() && sameName < a))
    {
      // String arrays, arrays of too few tuples and a second array of the same name (an output can
      // hold only one) are not interpolated. Unnamed arrays are (sources such as
      // vtkTexturedSphereSource leave their normals and texture coordinates unnamed).
      continue;
    }
    ArrayInfo info;
    info.InputIndex = a;
    info.Named = array->GetName() != nullptr;
    info.Name = info.Named ? array->GetName() : "";
    info.DataType = array->GetDataType();
    info.Components = array->GetNumberOfComponents();
    info.Offset = this->Width;
    info.AttributeType = input->IsArrayAnAttribute(a);
    this->Width += info.Components;
    this->Arrays.push_back(info);
  }
  if (this->Width == 0)
  {
    return;
  }
  this->Values.resize(rowToInputPoint.size() * size_t(this->Width));
  for (const ArrayInfo& info : this->Arrays)
  {
    vtkDataArray* array = input->GetArray(info.InputIndex);
    for (size_t r = 0; r < rowToInputPoint.size(); ++r)
    {
      for (int c = 0; c < info.Components; ++c)
      {
        this->Values[r * this->Width + info.Offset + c] = array->GetComponent(rowToInputPoint[r], c);
      }
    }
  }
}

void PointAttributes::Merge(Index target, const Index* sources, const double* weights, int count)
{
  if (this->Width == 0)
  {
    return;
  }
  this->Temp.assign(this->Width, 0.0);
  double total = 0;
  for (int i = 0; i < count; ++i)
  {
    total += weights[i];
  }
  for (int i = 0; i < count; ++i)
  {
    const double w = total > 0 ? weights[i] / total : 1.0 / count;
    const double* row = this->Row(sources[i]);
    for (int c = 0; c < this->Width; ++c)
    {
      this->Temp[c] += w * row[c];
    }
  }
  std::copy(this->Temp.begin(), this->Temp.end(), this->Values.begin() + size_t(target) * this->Width);
}

Index PointAttributes::AddInterpolated(const Index* sources, const double* weights, int count)
{
  const Index row = this->NumberOfRows();
  this->Values.resize(this->Values.size() + this->Width, 0.0);
  this->Merge(row, sources, weights, count);
  return row;
}

void PointAttributes::Store(vtkPointData* output, const std::vector<Index>& outputToRow) const
{
  for (const ArrayInfo& info : this->Arrays)
  {
    vtkSmartPointer<vtkDataArray> array = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(info.DataType));
    if (info.Named)
    {
      array->SetName(info.Name.c_str());
    }
    array->SetNumberOfComponents(info.Components);
    array->SetNumberOfTuples(static_cast<vtkIdType>(outputToRow.size()));
    for (size_t i = 0; i < outputToRow.size(); ++i)
    {
      const double* row = this->Row(outputToRow[i]) + info.Offset;
      for (int c = 0; c < info.Components; ++c)
      {
        array->SetComponent(static_cast<vtkIdType>(i), c, row[c]);
      }
    }
    if (info.AttributeType == vtkDataSetAttributes::NORMALS && info.Components == 3)
    {
      // Averaged unit normals are shorter than one: renormalise.
      for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
      {
        double n[3];
        array->GetTuple(i, n);
        const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (length > 0)
        {
          array->SetTuple3(i, n[0] / length, n[1] / length, n[2] / length);
        }
      }
    }
    const int index = output->AddArray(array);
    if (info.AttributeType >= 0)
    {
      output->SetActiveAttribute(index, info.AttributeType);
    }
  }
}
} // namespace slod
