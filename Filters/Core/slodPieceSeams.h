// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: a surface split into pieces over the processes of a
// vtkMultiProcessController (MPI ranks), each process simplifying its own piece.
//
// Two pieces meet along a seam: border edges of both, with the same end points. A simplifier keeps
// the union crack-free by never removing or moving a seam vertex (TriangleCollapseOptions::
// LockedVertices). The seam is found with the controller's collectives only: every process gathers
// the coordinates of the other pieces' border vertices (exact doubles: the pieces of one surface
// carry bit-identical copies of a shared point) and marks its vertices found there.
//
// Every function taking a controller is collective: all processes of the controller call it, in
// the same order.
#ifndef slodPieceSeams_h
#define slodPieceSeams_h

#include "slodTriangleMesh.h"

#include "vtkSmartPointer.h"

#include <functional>
#include <vector>

class vtkMultiProcessController;
class vtkPolyData;

namespace slod
{
struct SURFACELODFILTERS_EXPORT PieceSeam
{
  // Per vertex of the piece: 1 when another piece has a border vertex at exactly its position.
  std::vector<unsigned char> SharedVertices;
  Index SharedVertexCount = 0;
  Index SeamEdges = 0; // border edges of this piece whose two ends are shared
};

// True when the controller runs more than one process (a distributed run).
SURFACELODFILTERS_EXPORT bool IsDistributed(vtkMultiProcessController* controller);

// Collective: the seam of this process's piece.
SURFACELODFILTERS_EXPORT PieceSeam FindPieceSeam(const TriangleMesh& piece, vtkMultiProcessController* controller);

// Collective: this piece's share of a count target set for the union of the pieces, proportional to
// its triangles. The shares of all processes add up to `globalTarget` exactly. `globalTriangles`
// receives the triangles of the union.
SURFACELODFILTERS_EXPORT Index PieceShareOfTarget(vtkMultiProcessController* controller, Index pieceTriangles,
  const std::function<Index(Index globalTriangles)>& globalTargetOf);

// Collective: the bounding-box diagonal of the union of the pieces (0 when all are empty).
SURFACELODFILTERS_EXPORT double UnionBoundingBoxDiagonal(const TriangleMesh& piece, vtkMultiProcessController* controller);

// A shallow copy of `input` without the cells marked as ghosts in vtkGhostType (cells another piece
// owns); `input` itself when it has no ghost cells.
SURFACELODFILTERS_EXPORT vtkSmartPointer<vtkPolyData> WithoutGhostCells(vtkPolyData* input);
} // namespace slod

#endif
