// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: the VTK edge. Turns any vtkPolyData into a clean slod::TriangleMesh
// (with a report of what was changed, for the filter to warn about) and meshes back into
// vtkPolyData with the point data carried through.
//
// What preparation does, in order:
//  - point ids outside the points (or negative) in a polygon or strip, or cells without points:
//    error, nothing else is done;
//  - non-finite (NaN/Inf) coordinates used by a cell: error, nothing else is done;
//  - vertices and lines: ignored (counted); polygons (> 3 points) and strips: triangulated (counted);
//  - exactly coincident points: merged only where they seal an open border (two border edges
//    with pairwise coincident ends); elsewhere kept apart (counted), so merging never makes a
//    non-manifold vertex or edge, joins components or closes a handle; points whose point data
//    differ (an attribute seam: texture coordinates, normals of a crease) are never merged;
//  - triangles with a repeated vertex (after merging): removed (counted); zero-area triangles
//    without one are kept;
//  - with CollapseZeroLengthEdges (off by default): edges whose ends coincide exactly are
//    collapsed where the topology allows it and the ends' point data are equal
//    (slodZeroLengthEdges.h; counted): the surface keeps its shape and topology, its triangles on
//    those edges go (marching cubes' vertices at a sample equal to the iso-value);
//  - repeated triangles (same three vertices, same winding): removed (counted); a triangle and
//    its mirror image are both kept (two sides of a sheet touching itself);
//  - orientation: made consistent across manifold edges per component, keeping the majority
//    orientation of each component (counted); non-orientable components are reported;
//  - non-manifold edges and vertices: counted; each filter says what it does with them.
#ifndef slodInputPreparation_h
#define slodInputPreparation_h

#include "slodFilterContract.h"
#include "slodTriangleMesh.h"

#include <string>
#include <vector>

#include "vtkSmartPointer.h"

class vtkAlgorithm;
class vtkDoubleArray;
class vtkIdTypeArray;
class vtkDataArray;
class vtkObject;
class vtkPolyData;
class vtkPointData;

namespace slod
{
struct SURFACELODFILTERS_EXPORT PreparationOptions
{
  bool MergeDuplicatePoints = true;
  bool RemoveDegenerateTriangles = true;
  bool RemoveDuplicateTriangles = true;
  bool MakeOrientationConsistent = true;
  // Merge the ends of edges of length zero (slodZeroLengthEdges.h): for filters that keep input
  // vertices in their output (vtkRetile), where such ends would make tiles of zero area.
  bool CollapseZeroLengthEdges = false;
};

struct SURFACELODFILTERS_EXPORT PreparationReport
{
  bool Valid = true;          // false: the input cannot be used (Error says why)
  std::string Error;
  long long NonFinitePoints = 0;
  long long IgnoredVertexCells = 0;
  long long IgnoredLineCells = 0;
  long long TriangulatedPolygons = 0;
  long long TriangulatedStrips = 0;
  long long MergedPoints = 0;
  long long CoincidentPointsKeptApart = 0; // coincident with another point, not merged (see below)
  long long AttributeSeamPoints = 0;       // coincident with another point but other point data: kept apart
  long long RemovedDegenerateTriangles = 0;
  long long CollapsedZeroLengthEdges = 0;  // vertices merged away (PreparationOptions::CollapseZeroLengthEdges)
  long long RemovedDuplicateTriangles = 0;
  long long FlippedTriangles = 0;
  long long NonOrientableComponents = 0;
  long long NonManifoldEdges = 0;
  long long NonManifoldVertices = 0;
  // Per vertex of the prepared mesh: 1 when non-manifold (as NonManifoldVertexFlags), handed to
  // the collapse filters so that they need not classify the mesh a second time.
  std::vector<unsigned char> NonManifoldVertexFlags;
  // Per vertex of the prepared mesh: 1 when on a border edge (an edge of one triangle), from the
  // same classification (for AttributeSeamVertexFlags).
  std::vector<unsigned char> BoundaryVertexFlags;
  // One human-readable sentence per non-zero count above (for vtkWarningMacro).
  std::vector<std::string> Warnings() const;
};

// vertexToInputPoint[i] is the input point id of mesh vertex i (the first of merged duplicates).
// triangleToInputCell (when given) gets the input cell id of each mesh triangle (the polygon or
// strip it was cut from; ids count vertices and lines first, as vtkPolyData does).
SURFACELODFILTERS_EXPORT PreparationReport PrepareTriangleMesh(vtkPolyData* input,
  const PreparationOptions& options, TriangleMesh& mesh, std::vector<Index>& vertexToInputPoint,
  std::vector<Index>* triangleToInputCell = nullptr);

// Per vertex of a prepared mesh: 1 when it is non-manifold (on an edge with more than two
// triangles, or joining several fans), else 0. Collapse filters lock these vertices.
SURFACELODFILTERS_EXPORT std::vector<unsigned char> NonManifoldVertexFlags(const TriangleMesh& mesh);

// Per vertex of a prepared mesh: 1 on an attribute seam, i.e. a border vertex (`borderVertices`, as
// PreparationReport::BoundaryVertexFlags) with another border
// vertex within `tolerance` (e.g. 1e-6 of the diagonal: float rounding can part the two sides of a
// seam, as vtkTexturedSphereSource's u = 0 and u = 1 meridians) whose point data differ (input
// points vertexToInputPoint[v]), except the ends of edges shorter than the tolerance (a pole of copies). All zero
// without point arrays. Collapse filters keep these vertices
// in place (PreserveAttributeSeams).
SURFACELODFILTERS_EXPORT std::vector<unsigned char> AttributeSeamVertexFlags(const TriangleMesh& mesh,
  const std::vector<unsigned char>& borderVertices, vtkPointData* pointData,
  const std::vector<Index>& vertexToInputPoint, double tolerance);

// Per vertex of a prepared mesh: 1 where triangles of different values of `regions` (a cell array
// of the input, component 0; cell triangleToInputCell[t] of triangle t, or t when null) meet.
SURFACELODFILTERS_EXPORT std::vector<unsigned char> RegionBorderVertexFlags(
  const TriangleMesh& mesh, vtkDataArray* regions, const std::vector<Index>* triangleToInputCell);

// PrepareTriangleMesh for a filter: reports each warning with vtkWarningWithObjectMacro and an invalid
// input with vtkErrorWithObjectMacro on `filter`. Returns false when the input cannot be used (the
// filter then produces an empty output).
SURFACELODFILTERS_EXPORT bool PrepareFilterInput(vtkObject* filter, vtkPolyData* input,
  const PreparationOptions& options, TriangleMesh& mesh, std::vector<Index>& vertexToInputPoint,
  PreparationReport* report = nullptr, std::vector<Index>* triangleToInputCell = nullptr);

// How a filter that needs triangles answers a prepared input without any: an error or a warning
// on the filter, with the filter's own sentence.
struct SURFACELODFILTERS_EXPORT NoTrianglesMessage
{
  bool IsError = false;
  const char* Text = "The input has no triangles: the output is empty.";
};

// PrepareFilterInput, then `noTriangles` reported and false when the prepared mesh has no
// triangles (the filter then produces an empty output).
SURFACELODFILTERS_EXPORT bool PrepareFilterTriangles(vtkObject* filter, vtkPolyData* input,
  const PreparationOptions& options, TriangleMesh& mesh, std::vector<Index>& vertexToInputPoint,
  PreparationReport* report, std::vector<Index>* triangleToInputCell,
  const NoTrianglesMessage& noTriangles = NoTrianglesMessage());

// What a filter with the default preparation works on: the mesh, its maps back to the input (the
// cell map only when the input has cell data to carry, slod::CellMapIfNeeded) and the report.
struct PreparedTriangles
{
  TriangleMesh Mesh;
  std::vector<Index> VertexToInput, TriangleToCell;
  PreparationReport Report;
};

// PrepareFilterTriangles with the default PreparationOptions into `prepared`.
SURFACELODFILTERS_EXPORT bool PrepareFilterTriangles(vtkObject* filter, vtkPolyData* input, PreparedTriangles& prepared,
  const NoTrianglesMessage& noTriangles = NoTrianglesMessage());

// The progress of `filter` from `from` to `to` as a ProgressFunction (slodFilterContract.h): each
// call updates the filter's progress and returns false once the filter was asked to abort.
SURFACELODFILTERS_EXPORT ProgressFunction FilterProgress(vtkAlgorithm* filter, double from = 0.0, double to = 1.0);

// The result of an aborted filter, the same in every filter: a warning and an empty output.
SURFACELODFILTERS_EXPORT void ReportAbort(vtkAlgorithm* filter, vtkPolyData* output);

// The honest-target contract of every simplifier: field data "TargetNumberOfTriangles" (the
// resolved count target, -1 when only an error bound was given) and "TargetReached" (1/0) on the
// output, and a warning naming the count reached and why when the target was missed (e.g. the
// topology that is kept needs more triangles).
SURFACELODFILTERS_EXPORT void ReportTarget(vtkObject* filter, vtkPolyData* output, long long targetTriangles,
  bool reached, const char* reason);

// Writes the mesh as points (same precision as `pointsLike` when given, else float) + triangles.
SURFACELODFILTERS_EXPORT void MeshToPolyData(const TriangleMesh& mesh, vtkPolyData* output, int pointDataType = 10 /*VTK_FLOAT*/);

// Output points over the mesh vertices `used` (output point i is mesh vertex used[i]), with the
// input's point data copied from input point vertexToInputPoint[used[i]], of the type
// OutputPointType gives. For filters whose outputs keep original vertices only.
SURFACELODFILTERS_EXPORT void StoreUsedPoints(vtkPolyData* input, const TriangleMesh& mesh,
  const std::vector<Index>& used, const std::vector<Index>& vertexToInputPoint, int outputPointsPrecision,
  vtkPolyData* output);

// The output's point type (VTK_FLOAT or VTK_DOUBLE) for a filter's OutputPointsPrecision
// (vtkAlgorithm::DEFAULT_PRECISION: the input's type, float unless double).
SURFACELODFILTERS_EXPORT int OutputPointType(vtkPolyData* input, int outputPointsPrecision);

// A named array of `tuples` tuples of `components` components (values to be set), for the
// filters' extra outputs (field data, record tables).
SURFACELODFILTERS_EXPORT vtkSmartPointer<vtkIdTypeArray> NewIdArray(const char* name, int components, vtkIdType tuples);
SURFACELODFILTERS_EXPORT vtkSmartPointer<vtkDoubleArray> NewDoubleArray(const char* name, int components, vtkIdType tuples);
} // namespace slod

#endif
