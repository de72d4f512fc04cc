// SPDX-License-Identifier: BSD-3-Clause
#include "slodPieceSeams.h"

#include "slodMeshTopology.h"

#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkDataSetAttributes.h"
#include "vtkLogger.h"
#include "vtkMultiProcessController.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace slod
{
namespace
{
using Position = std::array<double, 3>;

// Every process's border-vertex coordinates, except this process's own (3 doubles each, sorted).
std::vector<Position> OtherPiecesBorderPositions(
  const TriangleMesh& piece, const std::vector<unsigned char>& border, vtkMultiProcessController* controller)
{
  std::vector<double> mine;
  for (Index v = 0; v < piece.NumberOfPoints(); ++v)
  {
    if (border[v])
    {
      const double* p = piece.Points.data() + 3 * size_t(v);
      mine.insert(mine.end(), p, p + 3);
    }
  }
  const int processes = controller->GetNumberOfProcesses();
  const vtkIdType myLength = static_cast<vtkIdType>(mine.size());
  std::vector<vtkIdType> lengths(static_cast<size_t>(processes)), offsets(static_cast<size_t>(processes) + 1, 0);
  controller->AllGather(&myLength, lengths.data(), 1);
  for (int r = 0; r < processes; ++r)
  {
    offsets[r + 1] = offsets[r] + lengths[r];
  }
  std::vector<double> all(static_cast<size_t>(offsets[processes]));
  controller->AllGatherV(mine.data(), all.data(), myLength, lengths.data(), offsets.data());

  const int me = controller->GetLocalProcessId();
  std::vector<Position> others;
  others.reserve(size_t(offsets[processes] - myLength) / 3);
  for (int r = 0; r < processes; ++r)
  {
    for (vtkIdType i = offsets[r]; r != me && i < offsets[r + 1]; i += 3)
    {
      others.push_back({ all[i], all[i + 1], all[i + 2] });
    }
  }
  std::sort(others.begin(), others.end());
  return others;
}

// Border edges of the piece (used by one triangle) whose two ends another piece shares.
Index CountSeamEdges(const MeshTopology& topology, const std::vector<unsigned char>& shared)
{
  Index seamEdges = 0;
  for (Index e = 0; e < topology.NumberOfEdges(); ++e)
  {
    seamEdges += topology.IsBoundaryEdge(e) && shared[topology.EdgeVertex(e, 0)] && shared[topology.EdgeVertex(e, 1)];
  }
  return seamEdges;
}
} // namespace

bool IsDistributed(vtkMultiProcessController* controller)
{
  return controller && controller->GetNumberOfProcesses() > 1;
}

PieceSeam FindPieceSeam(const TriangleMesh& piece, vtkMultiProcessController* controller)
{
  PieceSeam seam;
  seam.SharedVertices.assign(size_t(piece.NumberOfPoints()), 0);
  if (!IsDistributed(controller))
  {
    return seam;
  }
  const MeshTopology topology(piece);
  std::vector<unsigned char> border(size_t(piece.NumberOfPoints()));
  for (Index v = 0; v < piece.NumberOfPoints(); ++v)
  {
    border[v] = topology.IsBoundaryVertex(v) ? 1 : 0;
  }
  const std::vector<Position> others = OtherPiecesBorderPositions(piece, border, controller);
  // Any vertex, not only a border one: a piece may hold an edge as interior that another piece has
  // on its border (a non-manifold edge split between pieces).
  for (Index v = 0; v < piece.NumberOfPoints(); ++v)
  {
    const double* p = piece.Points.data() + 3 * size_t(v);
    if (std::binary_search(others.begin(), others.end(), Position{ p[0], p[1], p[2] }))
    {
      seam.SharedVertices[v] = 1;
      ++seam.SharedVertexCount;
    }
  }
  seam.SeamEdges = CountSeamEdges(topology, seam.SharedVertices);
  vtkLogF(TRACE, "piece %d: %lld shared vertices, %lld seam edges (%zu border vertices of other pieces)",
    controller->GetLocalProcessId(), static_cast<long long>(seam.SharedVertexCount),
    static_cast<long long>(seam.SeamEdges), others.size());
  return seam;
}

Index PieceShareOfTarget(vtkMultiProcessController* controller, Index pieceTriangles,
  const std::function<Index(Index globalTriangles)>& globalTargetOf)
{
  if (!IsDistributed(controller))
  {
    return globalTargetOf(pieceTriangles);
  }
  const int processes = controller->GetNumberOfProcesses();
  const vtkIdType mine = pieceTriangles;
  std::vector<vtkIdType> counts(static_cast<size_t>(processes));
  controller->AllGather(&mine, counts.data(), 1);
  long long before = 0, total = 0;
  for (int r = 0; r < processes; ++r)
  {
    before += r < controller->GetLocalProcessId() ? counts[r] : 0;
    total += counts[r];
  }
  if (total == 0)
  {
    return 0;
  }
  // Rounded cumulative shares: each process gets the difference of two rounded prefixes, so the
  // shares add up to the global target exactly.
  const double target = static_cast<double>(globalTargetOf(static_cast<Index>(total)));
  const auto prefixShare = [&](long long prefix) { return std::llround(target * double(prefix) / double(total)); };
  return static_cast<Index>(prefixShare(before + mine) - prefixShare(before));
}

double UnionBoundingBoxDiagonal(const TriangleMesh& piece, vtkMultiProcessController* controller)
{
  if (!IsDistributed(controller))
  {
    return piece.BoundingBoxDiagonal();
  }
  const bool empty = piece.NumberOfPoints() == 0;
  const auto bounds = piece.Bounds();
  // Minima and negated maxima, so one MIN reduction gives the union's box.
  double mine[6], box[6];
  for (int i = 0; i < 3; ++i)
  {
    mine[i] = empty ? VTK_DOUBLE_MAX : bounds[2 * i];
    mine[3 + i] = empty ? VTK_DOUBLE_MAX : -bounds[2 * i + 1];
  }
  controller->AllReduce(mine, box, 6, vtkCommunicator::MIN_OP);
  if (box[0] > -box[3])
  {
    return 0.0;
  }
  return std::sqrt((box[0] + box[3]) * (box[0] + box[3]) + (box[1] + box[4]) * (box[1] + box[4]) +
    (box[2] + box[5]) * (box[2] + box[5]));
}

vtkSmartPointer<vtkPolyData> WithoutGhostCells(vtkPolyData* input)
{
  vtkUnsignedCharArray* ghosts = input->GetCellGhostArray();
  const bool anyGhost = ghosts &&
    std::any_of(ghosts->GetPointer(0), ghosts->GetPointer(0) + ghosts->GetNumberOfValues(),
      [](unsigned char g) { return (g & vtkDataSetAttributes::DUPLICATECELL) != 0; });
  if (!anyGhost)
  {
    return input;
  }
  auto owned = vtkSmartPointer<vtkPolyData>::New();
  owned->ShallowCopy(input);
  owned->RemoveGhostCells(); // new cell arrays: the input is left as it is
  return owned;
}
} // namespace slod
