// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: a surface split into pieces over the processes of a
// vtkMultiProcessController (MPI ranks), each process simplifying its own piece.
//
// Two pieces meet along a seam: points that the split gave to both (bit-identical copies of one
// input point). A simplifier keeps the union crack-free by never removing or moving a seam vertex
// (TriangleCollapseOptions::LockedVertices). The seam is found with the controller's collectives
// only, and from the positions alone, so any split works (the tool's, vtkExtractPolyDataPiece,
// ParaView's redistribution) without marks from the splitter: every distinct position of a piece is
// sent to the process its hash selects, which tells each sender whether another piece holds it too.
// A point is shared even where no piece has it on its border (the two sheets of a non-manifold edge,
// or the fans of a non-manifold vertex, in different pieces).
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
  // Per vertex of the piece: 1 when another piece has a vertex at exactly its position.
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
