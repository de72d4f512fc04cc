// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: point and cell data carried from a filter's input to its output through
// VTK's own vtkDataSetAttributes copy machinery (CopyAllocate / CopyData), so that every array
// keeps its name, type, number of components and attribute role (scalars, normals, global ids...).
//
// Cell data rule (every filter): each output triangle carries the data of one input cell it
// descends from.
//  - Filters that keep triangles or collapse them (vtkQuadricTriangleCollapse,
//    vtkTriangleCollapseHierarchy, vtkLODInterpolation, vtkProgressiveMeshReconstruction): the
//    triangle's own original triangle (a collapse keeps the ids of the triangles that survive it).
//  - Filters that retriangulate (vtkPatchBoundaryMerge, vtkGreedyCutsSimplification,
//    vtkHoleBumpRemoval, vtkRetile): the input triangle closest to the output triangle's centroid
//    (slod::TriangleBVH), so a region's output triangles lie on or next to that region.
// Input polygons and strips are triangulated by the input preparation; each of their triangles
// carries its polygon's or strip's data (PrepareTriangleMesh's triangleToInputCell).
#ifndef slodAttributeTransfer_h
#define slodAttributeTransfer_h

#include "slodTriangleMesh.h"

#include "vtkSmartPointer.h"

#include <vector>

class vtkDataSetAttributes;
class vtkPolyData;

namespace slod
{
// The arrays of `attributes` that can be carried for `tuples` points or cells (shallow copies,
// roles kept): arrays with fewer tuples and a second array of one name (an output holds only
// one per name) are left out.
SURFACELODFILTERS_EXPORT vtkSmartPointer<vtkDataSetAttributes> CarriableArrays(
  vtkDataSetAttributes* attributes, vtkIdType tuples);

// Output tuple i := input tuple outputToInput[i], for every carriable array of `input` (which has
// `inputTuples` tuples), with every copy flag on: global and pedigree ids are copied too (VTK
// leaves them out of CopyData by default because a copy may repeat an id; here an output element
// names the input element it comes from, which is what the ids are for).
SURFACELODFILTERS_EXPORT void CopyAttributeTuples(vtkDataSetAttributes* input, vtkIdType inputTuples,
  const std::vector<Index>& outputToInput, vtkDataSetAttributes* output);

// &triangleToInputCell when `input` has cell data to carry (pass it to PrepareFilterInput), else
// nullptr: the map costs nothing when there is nothing to carry.
SURFACELODFILTERS_EXPORT std::vector<Index>* CellMapIfNeeded(vtkPolyData* input, std::vector<Index>& triangleToInputCell);

// The output's cell data: output cell i gets the data of input cell
// triangleToInputCell[outputToPreparedTriangle[i]]. Nothing when the map is empty (no cell data).
// Call it before adding the filter's own cell arrays (an input array of the same name is replaced).
SURFACELODFILTERS_EXPORT void StoreCellData(vtkPolyData* input, const std::vector<Index>& triangleToInputCell,
  const std::vector<Index>& outputToPreparedTriangle, vtkPolyData* output);

// StoreCellData for filters that retriangulate: output triangle i = (points, triangles)'s triangle i
// carries the data of the input cell of the prepared triangle closest to its centroid.
SURFACELODFILTERS_EXPORT void StoreNearestCellData(vtkPolyData* input, const std::vector<Index>& triangleToInputCell,
  const TriangleMesh& prepared, const std::vector<double>& points, const std::vector<Index>& triangles,
  vtkPolyData* output);

// For filters that retriangulate: per triangle of (points, triangles), the triangle of `prepared`
// closest to its centroid. Empty when `prepared` has no triangles.
SURFACELODFILTERS_EXPORT std::vector<Index> NearestTrianglesToCentroids(
  const TriangleMesh& prepared, const std::vector<double>& points, const std::vector<Index>& triangles);
} // namespace slod

#endif
