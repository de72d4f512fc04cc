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
  Index SeamEdges = 0; // border edges of this piece whose two ends are shared (counted for the TRACE log only)
  Index ExchangedPositions = 0; // distinct positions this piece sent to be decided (the band along the cuts)
};

// True when the controller runs more than one process (a distributed run).
SURFACELODFILTERS_EXPORT bool IsDistributed(vtkMultiProcessController* controller);

// Collective: the seam of this process's piece.
SURFACELODFILTERS_EXPORT PieceSeam FindPieceSeam(const TriangleMesh& piece, vtkMultiProcessController* controller);

// Collective: this piece's share of a count target set for the union of the pieces, proportional to
// its triangles. The shares of all processes add up to the union's target exactly, which
// `unionTarget` (when given) receives.
SURFACELODFILTERS_EXPORT Index PieceShareOfTarget(vtkMultiProcessController* controller, Index pieceTriangles,
  const std::function<Index(Index globalTriangles)>& globalTargetOf, Index* unionTarget = nullptr);

// The pieces agree, while they collapse, on how the union's target is divided: as one process's
// single queue would, the cheapest collapses go first wherever they are, instead of fixed shares
// proportional to the pieces' sizes (a piece of smooth surface then stops early while a piece of
// detail goes too far, and the union's largest error grows). The pieces exchange their live
// triangles (one AllGather, collective) in rounds; a piece enters the next round when its cheapest
// cost passes the next of a fixed geometric sequence of levels, or when it has removed its
// allowance: half the union's excess over its target, in parts proportional to what each piece
// removed in the last round (so ties, e.g. the zero costs of flat regions, cannot take the union
// past its target). Once the excess is within twice what the last round removed, each piece takes
// a part of it proportional to what it removed in that round (the parts add up to the excess
// exactly) and the rounds stop.
class SURFACELODFILTERS_EXPORT UnionTargetAgreement
{
public:
  // `pieceTriangles` and `pieceShare`: this piece's triangles and proportional share
  // (PieceShareOfTarget), which set the first round's allowance.
  UnionTargetAgreement(vtkMultiProcessController* controller, Index unionTarget, double unionDiagonal,
    Index pieceTriangles, Index pieceShare);

  // This piece's target, or -1 while it is not settled. Collective whenever `cheapestCost` passes
  // the next level or `liveTriangles` the allowance; with +infinity (nothing left to collapse),
  // collective until settled.
  Index operator()(double cheapestCost, Index liveTriangles);
  // Collective: takes part until the target is settled (a piece that stopped early, aborted or has
  // nothing to simplify must still call it); returns the target. Nothing when already settled.
  Index Finish(Index liveTriangles);
  bool IsSettled() const { return this->Target >= 0; }
  int LevelsExchanged() const { return this->Level; }
  // Seconds spent in the rounds' exchanges: mostly waiting for the slowest piece to reach the level.
  double ExchangeSeconds() const { return this->Seconds; }

private:
  void Exchange(Index liveTriangles, bool done, double cheapestCost);

  vtkMultiProcessController* Controller;
  Index UnionTarget;
  double NextCost;
  Index Floor; // this round's allowance ends here
  int Level = 0;
  Index PreviousLive = -1;
  Index Target = -1;
  double Seconds = 0.0;
};

// Collective: the bounding-box diagonal of the union of the pieces (0 when all are empty).
SURFACELODFILTERS_EXPORT double UnionBoundingBoxDiagonal(const TriangleMesh& piece, vtkMultiProcessController* controller);

// A shallow copy of `input` without the cells marked as ghosts in vtkGhostType (cells another piece
// owns); `input` itself when it has no ghost cells.
SURFACELODFILTERS_EXPORT vtkSmartPointer<vtkPolyData> WithoutGhostCells(vtkPolyData* input);
} // namespace slod

#endif
