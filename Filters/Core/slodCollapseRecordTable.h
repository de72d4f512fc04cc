// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core, VTK edge: collapse records (slodCollapseRecords.h) as a vtkTable, the
// form in which vtkQuadricTriangleCollapse hands them to vtkProgressiveMeshReconstruction and
// vtkLODInterpolation (one row per collapse, ragged arrays in the field data; the columns are
// listed in Documentation/QuadricTriangleCollapse.md).
#ifndef slodCollapseRecordTable_h
#define slodCollapseRecordTable_h

#include "slodCollapseRecords.h"

class vtkTable;

namespace slod
{
// Writes records that store positions and removed triangle vertices (at most four removed
// triangles per collapse) over a mesh of inputPoints points and inputTriangles triangles.
SURFACELODFILTERS_EXPORT void CollapseRecordsToTable(
  const CollapseRecords& records, Index inputPoints, Index inputTriangles, vtkTable* table);
// Reads them back (without the surrounding vertices); false when the table is malformed (a
// column missing or of the wrong shape, an id out of range). points / triangles: of the input.
SURFACELODFILTERS_EXPORT bool TableToCollapseRecords(
  vtkTable* table, CollapseRecords& records, Index& points, Index& triangles);
} // namespace slod

#endif
