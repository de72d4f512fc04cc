// SPDX-License-Identifier: BSD-3-Clause
#include "slodCollapseRecordTable.h"

#include "slodInputPreparation.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"

#include <algorithm>

namespace slod
{
namespace
{
// The ragged arrays and the input's size, in the table's field data.
void StoreFieldArrays(const CollapseRecords& r, Index inputPoints, Index inputTriangles, vtkTable* table)
{
  vtkFieldData* fd = table->GetFieldData();
  auto changed = NewIdArray("Changed", 3, static_cast<vtkIdType>(r.ChangedTriangles.size()));
  for (Index k = 0; k < r.NumberOfCollapses(); ++k)
  {
    for (size_t c = size_t(r.ChangedOffsets[k]); c < size_t(r.ChangedOffsets[k + 1]); ++c)
    {
      changed->SetTypedComponent(vtkIdType(c), 0, r.ChangedTriangles[c]);
      changed->SetTypedComponent(vtkIdType(c), 1, r.ChangedCorner(c));
      changed->SetTypedComponent(vtkIdType(c), 2, r.ChangedFrom(k, c));
    }
  }
  fd->AddArray(changed);
  auto surrounding = NewIdArray("Surrounding", 1, static_cast<vtkIdType>(r.Surrounding.size()));
  std::copy(r.Surrounding.begin(), r.Surrounding.end(), surrounding->GetPointer(0));
  fd->AddArray(surrounding);
  auto points = NewIdArray("NumberOfInputPoints", 1, 1);
  points->SetValue(0, inputPoints);
  fd->AddArray(points);
  auto triangles = NewIdArray("NumberOfInputTriangles", 1, 1);
  triangles->SetValue(0, inputTriangles);
  fd->AddArray(triangles);
}

// One collapse's removed triangles (and their vertices) from row k of the table.
bool ReadRemoved(vtkDataArray* removed, vtkDataArray* removedVertices, vtkIdType k, Index triangles, CollapseRecords& r)
{
  for (int i = 0; i < 4; ++i)
  {
    const auto t = static_cast<Index>(removed->GetComponent(k, i));
    if (t < 0)
    {
      continue;
    }
    if (t >= triangles)
    {
      return false;
    }
    r.RemovedTriangles.push_back(t);
    for (int j = 0; j < 3; ++j)
    {
      r.RemovedTriangleVertices.push_back(static_cast<Index>(removedVertices->GetComponent(k, 3 * i + j)));
    }
  }
  r.RemovedOffsets.push_back(static_cast<Index>(r.RemovedTriangles.size()));
  return true;
}

// One collapse's redirected corners, tuples [begin, end) of the Changed array (false: a corner
// not redirected from one of the collapse's vertices).
bool ReadChanged(vtkDataArray* changed, vtkIdType begin, vtkIdType end, CollapseRecords& r)
{
  for (vtkIdType c = begin; c < end; ++c)
  {
    if (!r.AppendChanged(static_cast<Index>(changed->GetComponent(c, 0)), static_cast<int>(changed->GetComponent(c, 1)),
          static_cast<Index>(changed->GetComponent(c, 2))))
    {
      return false;
    }
  }
  r.ChangedOffsets.push_back(static_cast<Index>(r.ChangedTriangles.size()));
  return true;
}
} // namespace

void CollapseRecordsToTable(const CollapseRecords& r, Index inputPoints, Index inputTriangles, vtkTable* table)
{
  const vtkIdType n = r.NumberOfCollapses();
  auto vertices = NewIdArray("Vertices", 3, n);
  auto oldPositions = NewDoubleArray("OldPositions", 9, n);
  auto newPosition = NewDoubleArray("NewPosition", 3, n);
  auto removed = NewIdArray("RemovedTriangles", 4, n);
  auto removedVertices = NewIdArray("RemovedTriangleVertices", 12, n);
  auto changedOffset = NewIdArray("ChangedOffset", 1, n);
  auto surroundingOffset = NewIdArray("SurroundingOffset", 1, n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    for (int i = 0; i < 3; ++i)
    {
      vertices->SetTypedComponent(k, i, r.Vertices[3 * k + i]);
      newPosition->SetTypedComponent(k, i, r.NewPositions[3 * k + i]);
    }
    for (int i = 0; i < 9; ++i)
    {
      oldPositions->SetTypedComponent(k, i, r.OldPositions[9 * k + i]);
    }
    const Index r0 = r.RemovedOffsets[k], r1 = r.RemovedOffsets[k + 1];
    for (int i = 0; i < 4; ++i)
    {
      const bool has = r0 + i < r1;
      removed->SetTypedComponent(k, i, has ? r.RemovedTriangles[size_t(r0 + i)] : -1);
      for (int j = 0; j < 3; ++j)
      {
        removedVertices->SetTypedComponent(k, 3 * i + j, has ? r.RemovedTriangleVertices[3 * size_t(r0 + i) + j] : -1);
      }
    }
    changedOffset->SetValue(k, r.ChangedOffsets[k]);
    surroundingOffset->SetValue(k, r.StoreSurrounding ? r.SurroundingOffsets[k] : 0);
  }
  for (vtkDataArray* column : { static_cast<vtkDataArray*>(vertices), static_cast<vtkDataArray*>(oldPositions),
         static_cast<vtkDataArray*>(newPosition), static_cast<vtkDataArray*>(removed),
         static_cast<vtkDataArray*>(removedVertices), static_cast<vtkDataArray*>(changedOffset),
         static_cast<vtkDataArray*>(surroundingOffset) })
  {
    table->AddColumn(column);
  }
  StoreFieldArrays(r, inputPoints, inputTriangles, table);
}

bool TableToCollapseRecords(vtkTable* table, CollapseRecords& r, Index& points, Index& triangles)
{
  r.StorePositions = r.StoreRemovedTriangleVertices = true;
  r.StoreSurrounding = false;
  r.Clear();
  auto column = [&](const char* name, int components) -> vtkDataArray* {
    vtkDataArray* a = vtkDataArray::SafeDownCast(table->GetColumnByName(name));
    return a && a->GetNumberOfComponents() == components ? a : nullptr;
  };
  vtkDataArray* vertices = column("Vertices", 3);
  vtkDataArray* oldPositions = column("OldPositions", 9);
  vtkDataArray* newPosition = column("NewPosition", 3);
  vtkDataArray* removed = column("RemovedTriangles", 4);
  vtkDataArray* removedVertices = column("RemovedTriangleVertices", 12);
  vtkDataArray* changedOffset = column("ChangedOffset", 1);
  vtkFieldData* fd = table->GetFieldData();
  vtkDataArray* changed = vtkDataArray::SafeDownCast(fd->GetAbstractArray("Changed"));
  vtkDataArray* np = vtkDataArray::SafeDownCast(fd->GetAbstractArray("NumberOfInputPoints"));
  vtkDataArray* nt = vtkDataArray::SafeDownCast(fd->GetAbstractArray("NumberOfInputTriangles"));
  if (!vertices || !oldPositions || !newPosition || !removed || !removedVertices || !changedOffset || !changed ||
    changed->GetNumberOfComponents() != 3 || !np || !nt)
  {
    return false;
  }
  points = static_cast<Index>(np->GetComponent(0, 0));
  triangles = static_cast<Index>(nt->GetComponent(0, 0));
  const vtkIdType n = table->GetNumberOfRows();
  for (vtkIdType k = 0; k < n; ++k)
  {
    for (int i = 0; i < 3; ++i)
    {
      const auto v = static_cast<Index>(vertices->GetComponent(k, i));
      const bool edgeCollapse = i == 2 && v == InvalidIndex; // two vertices merged
      if (!edgeCollapse && (v < 0 || v >= points))
      {
        return false;
      }
      r.Vertices.push_back(v);
      r.NewPositions.push_back(newPosition->GetComponent(k, i));
    }
    for (int i = 0; i < 9; ++i)
    {
      r.OldPositions.push_back(oldPositions->GetComponent(k, i));
    }
    if (!ReadRemoved(removed, removedVertices, k, triangles, r))
    {
      return false;
    }
    const vtkIdType end =
      k + 1 < n ? static_cast<vtkIdType>(changedOffset->GetComponent(k + 1, 0)) : changed->GetNumberOfTuples();
    const auto begin = static_cast<vtkIdType>(changedOffset->GetComponent(k, 0));
    if (begin < 0 || end < begin || end > changed->GetNumberOfTuples())
    {
      return false;
    }
    if (!ReadChanged(changed, begin, end, r))
    {
      return false;
    }
  }
  return true;
}
} // namespace slod
