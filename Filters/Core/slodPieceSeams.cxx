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
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace slod
{
namespace
{
using Position = std::array<double, 3>;

// The exact coordinates of a vertex, with -0.0 written as 0.0 (they compare equal, so they must hash
// alike).
Position PositionOf(const TriangleMesh& piece, Index v)
{
  const double* p = piece.Points.data() + 3 * size_t(v);
  return { p[0] + 0.0, p[1] + 0.0, p[2] + 0.0 };
}

// The process that decides whether a position is shared: a hash of its bits, the same on every
// process (no std::hash: it need not agree between builds).
int DecidingProcess(const Position& p, int processes)
{
  std::uint64_t h = 0x9e3779b97f4a7c15ull;
  for (double c : p)
  {
    std::uint64_t bits;
    std::memcpy(&bits, &c, sizeof bits);
    h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xbf58476d1ce4e5b9ull;
  }
  h ^= h >> 29;
  return static_cast<int>(h % static_cast<std::uint64_t>(processes));
}

// Collective all-to-all over the controller's collectives (VTK 9.1 has no AllToAllV): process q
// receives outgoing[q] of every process r as incoming[r]. Items travel as arrays of Scalar (a type
// the controller sends). One AllGather of the lengths, then one ScatterV per source process.
template <typename Scalar, typename Item>
std::vector<std::vector<Item>> ExchangeBuckets(
  vtkMultiProcessController* controller, const std::vector<std::vector<Item>>& outgoing)
{
  static_assert(sizeof(Item) % sizeof(Scalar) == 0, "an item is a whole number of scalars");
  constexpr vtkIdType width = static_cast<vtkIdType>(sizeof(Item) / sizeof(Scalar));
  const int processes = controller->GetNumberOfProcesses(), me = controller->GetLocalProcessId();
  const size_t n = static_cast<size_t>(processes);
  std::vector<vtkIdType> myLengths(n), lengths(n * n); // lengths[r * n + q]: scalars from r to q
  std::vector<Item> packed;
  for (size_t q = 0; q < n; ++q)
  {
    myLengths[q] = width * static_cast<vtkIdType>(outgoing[q].size());
    packed.insert(packed.end(), outgoing[q].begin(), outgoing[q].end());
  }
  controller->AllGather(myLengths.data(), lengths.data(), static_cast<vtkIdType>(n));
  std::vector<std::vector<Item>> incoming(n);
  for (int r = 0; r < processes; ++r)
  {
    std::vector<vtkIdType> row(lengths.begin() + r * n, lengths.begin() + (r + 1) * n), offsets(n, 0);
    for (size_t q = 1; q < n; ++q)
    {
      offsets[q] = offsets[q - 1] + row[q - 1];
    }
    const vtkIdType mine = row[static_cast<size_t>(me)];
    incoming[r].resize(static_cast<size_t>(mine / width));
    controller->ScatterV(reinterpret_cast<const Scalar*>(packed.data()), reinterpret_cast<Scalar*>(incoming[r].data()),
      row.data(), offsets.data(), mine, r);
  }
  return incoming;
}

// A coarse grid over the union of the pieces, each cell with the number of pieces that have a vertex
// in it. A position another piece also holds lies in a cell of two or more pieces (equal positions
// fall in the same cell on every process: same bounds, same arithmetic), so only the vertices in
// such cells, a band along the cuts between the pieces, need to be exchanged, instead of all.
class OccupiedCells
{
public:
  // Collective.
  OccupiedCells(const std::vector<Position>& positions, vtkMultiProcessController* controller)
  {
    std::array<double, 6> box{ inf, inf, inf, inf, inf, inf }, unionBox{}; // low, then -high
    for (const Position& p : positions)
    {
      for (int k = 0; k < 3; ++k)
      {
        box[k] = std::min(box[k], p[k]);
        box[3 + k] = std::min(box[3 + k], -p[k]);
      }
    }
    controller->AllReduce(box.data(), unionBox.data(), 6, vtkCommunicator::MIN_OP);
    long long count = static_cast<long long>(positions.size()), total = 0;
    controller->AllReduce(&count, &total, 1, vtkCommunicator::SUM_OP);
    bool usable = controller->GetNumberOfProcesses() < std::numeric_limits<unsigned short>::max();
    for (int k = 0; k < 3; ++k)
    {
      this->Low[k] = unionBox[k];
      const double extent = -unionBox[3 + k] - unionBox[k];
      usable = usable && std::isfinite(extent) && std::isfinite(this->Low[k]);
      this->Scale[k] = extent > 0 ? 1.0 / extent : 0.0;
    }
    if (!usable)
    {
      return; // every position is a candidate
    }
    // About one vertex per cell of the union, at most 128^3 cells (4 MB of counts to reduce).
    this->Cells = static_cast<int>(std::clamp(std::ceil(std::cbrt(double(total))), 1.0, 128.0));
    std::vector<unsigned short> mine(size_t(this->Cells) * size_t(this->Cells) * size_t(this->Cells), 0);
    for (const Position& p : positions)
    {
      mine[this->CellOf(p)] = 1;
    }
    this->Pieces.resize(mine.size());
    controller->AllReduce(mine.data(), this->Pieces.data(), static_cast<vtkIdType>(mine.size()), vtkCommunicator::SUM_OP);
  }

  bool MayBeShared(const Position& p) const { return this->Pieces.empty() || this->Pieces[this->CellOf(p)] >= 2; }

private:
  static constexpr double inf = std::numeric_limits<double>::infinity();
  size_t CellOf(const Position& p) const
  {
    size_t cell = 0;
    for (int k = 0; k < 3; ++k)
    {
      const double t = (p[k] - this->Low[k]) * this->Scale[k] * this->Cells;
      cell = cell * size_t(this->Cells) + size_t(std::clamp(static_cast<int>(t), 0, this->Cells - 1));
    }
    return cell;
  }

  std::array<double, 3> Low{}, Scale{};
  int Cells = 1;
  std::vector<unsigned short> Pieces; // empty: the grid could not be made
};

// Collective: the positions of this piece's vertices that one or more other pieces also hold. Every
// distinct position that may be shared (OccupiedCells) goes to its deciding process, which counts
// the processes holding it and answers each sender; the work and the traffic per process are
// proportional to its part of the band along the cuts, whatever the split.
std::vector<Position> PositionsOtherPiecesHold(
  const TriangleMesh& piece, vtkMultiProcessController* controller, Index& exchanged)
{
  const int processes = controller->GetNumberOfProcesses();
  std::vector<Position> mine(size_t(piece.NumberOfPoints()));
  for (Index v = 0; v < piece.NumberOfPoints(); ++v)
  {
    mine[v] = PositionOf(piece, v);
  }
  const OccupiedCells cells(mine, controller);
  mine.erase(std::remove_if(mine.begin(), mine.end(), [&cells](const Position& p) { return !cells.MayBeShared(p); }),
    mine.end());
  std::sort(mine.begin(), mine.end());
  mine.erase(std::unique(mine.begin(), mine.end()), mine.end()); // each process sends a position once
  exchanged = static_cast<Index>(mine.size());
  std::vector<std::vector<Position>> asked(static_cast<size_t>(processes));
  for (const Position& p : mine)
  {
    asked[DecidingProcess(p, processes)].push_back(p);
  }
  std::vector<std::vector<Position>> toDecide = ExchangeBuckets<double>(controller, asked);

  // Deciding: a position sent by two or more processes is shared.
  std::vector<Position> heard;
  for (const auto& bucket : toDecide)
  {
    heard.insert(heard.end(), bucket.begin(), bucket.end());
  }
  std::sort(heard.begin(), heard.end());
  std::vector<Position> shared;
  for (size_t i = 0; i + 1 < heard.size(); ++i)
  {
    if (heard[i] == heard[i + 1] && (shared.empty() || shared.back() != heard[i]))
    {
      shared.push_back(heard[i]);
    }
  }
  std::vector<std::vector<unsigned char>> answers(toDecide.size());
  for (size_t r = 0; r < toDecide.size(); ++r)
  {
    for (const Position& p : toDecide[r])
    {
      answers[r].push_back(std::binary_search(shared.begin(), shared.end(), p) ? 1 : 0);
    }
  }
  const std::vector<std::vector<unsigned char>> answered = ExchangeBuckets<unsigned char>(controller, answers);

  std::vector<Position> held;
  for (size_t q = 0; q < asked.size(); ++q)
  {
    for (size_t i = 0; i < asked[q].size(); ++i)
    {
      if (answered[q][i])
      {
        held.push_back(asked[q][i]);
      }
    }
  }
  std::sort(held.begin(), held.end());
  return held;
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

namespace
{
// `amount` in parts proportional to weights: the part of the weight `mine` that follows the weights
// `before` of a total `total`, from two rounded prefixes, so the parts add up to `amount` exactly.
Index PartOf(Index amount, long long before, long long mine, long long total)
{
  const auto prefixPart = [&](long long prefix) { return std::llround(double(amount) * double(prefix) / double(total)); };
  return static_cast<Index>(prefixPart(before + mine) - prefixPart(before));
}

// The levels of UnionTargetAgreement: relative to the union's diagonal^4, steps of 2^(1/4).
constexpr double FirstLevel = 1e-24;
constexpr double LevelRatio = 1.189207115002721;
constexpr int MaximumLevels = 480; // rounds
constexpr int MaximumLevelSkip = 4096;
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
  // Any vertex, not only a border one: the sheets of a non-manifold edge, or the fans of a
  // non-manifold vertex, may fall into different pieces, where that edge or vertex is interior.
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Position> held = PositionsOtherPiecesHold(piece, controller, seam.ExchangedPositions);
  const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
  for (Index v = 0; v < piece.NumberOfPoints(); ++v)
  {
    if (std::binary_search(held.begin(), held.end(), PositionOf(piece, v)))
    {
      seam.SharedVertices[v] = 1;
      ++seam.SharedVertexCount;
    }
  }
  // The seam edges only for the trace: counting them builds the piece's whole topology (a third
  // of a second per million triangles), which nothing else here needs.
  if (vtkLogger::GetCurrentVerbosityCutoff() >= vtkLogger::VERBOSITY_TRACE)
  {
    const MeshTopology topology(piece);
    seam.SeamEdges = CountSeamEdges(topology, seam.SharedVertices);
    vtkLogF(TRACE, "piece %d: %lld shared vertices, %lld seam edges; %lld of %lld positions exchanged, %.3f s",
      controller->GetLocalProcessId(), static_cast<long long>(seam.SharedVertexCount),
      static_cast<long long>(seam.SeamEdges), static_cast<long long>(seam.ExchangedPositions),
      static_cast<long long>(piece.NumberOfPoints()), seconds.count());
  }
  return seam;
}

Index PieceShareOfTarget(vtkMultiProcessController* controller, Index pieceTriangles,
  const std::function<Index(Index globalTriangles)>& globalTargetOf, Index* unionTarget)
{
  if (!IsDistributed(controller))
  {
    const Index target = globalTargetOf(pieceTriangles);
    if (unionTarget)
    {
      *unionTarget = target;
    }
    return target;
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
  const Index target = total == 0 ? 0 : globalTargetOf(static_cast<Index>(total));
  if (unionTarget)
  {
    *unionTarget = target;
  }
  return total == 0 ? 0 : PartOf(target, before, mine, total);
}

UnionTargetAgreement::UnionTargetAgreement(vtkMultiProcessController* controller, Index unionTarget,
  double unionDiagonal, Index pieceTriangles, Index pieceShare)
  : Controller(controller)
  , UnionTarget(unionTarget)
  // Costs are area-weighted squared distances (length^4); the first level is far below any cost
  // that matters, the last (MaximumLevels) far above.
  , NextCost(FirstLevel * std::pow(unionDiagonal > 0 ? unionDiagonal : 1.0, 4))
  , Floor(pieceTriangles - std::max<Index>(1, (pieceTriangles - pieceShare) / 2))
{
}

Index UnionTargetAgreement::operator()(double cheapestCost, Index liveTriangles)
{
  const bool done = !std::isfinite(cheapestCost);
  while (this->Target < 0 && (done || cheapestCost > this->NextCost || liveTriangles <= this->Floor))
  {
    this->Exchange(liveTriangles, done, cheapestCost);
  }
  return this->Target;
}

Index UnionTargetAgreement::Finish(Index liveTriangles)
{
  return (*this)(std::numeric_limits<double>::infinity(), liveTriangles);
}

void UnionTargetAgreement::Exchange(Index liveTriangles, bool done, double cheapestCost)
{
  const int processes = this->Controller->GetNumberOfProcesses(), me = this->Controller->GetLocalProcessId();
  const Index previous = this->PreviousLive < 0 ? liveTriangles : this->PreviousLive;
  // Per process: live triangles, removed since the last round, 1 when nothing is left to collapse
  // (all exact as doubles), and the cheapest cost left.
  constexpr int Width = 4;
  const double mine[Width] = { double(liveTriangles), double(previous - liveTriangles), done ? 1.0 : 0.0,
    done ? std::numeric_limits<double>::max() : cheapestCost };
  std::vector<double> gathered(Width * static_cast<size_t>(processes));
  const auto started = std::chrono::steady_clock::now();
  this->Controller->AllGather(mine, gathered.data(), Width);
  this->Seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const auto all = [&](size_t i) { return static_cast<long long>(gathered[i / 3 * Width + i % 3]); };
  this->PreviousLive = liveTriangles;
  ++this->Level;
  long long live = 0, removed = 0, allDone = 1;
  double cheapest = std::numeric_limits<double>::max();
  for (int r = 0; r < processes; ++r)
  {
    live += all(3 * r);
    removed += all(3 * r + 2) ? 0 : all(3 * r + 1);
    allDone &= all(3 * r + 2);
    cheapest = std::min(cheapest, gathered[Width * r + 3]);
  }
  // The next level above every piece's cheapest cost: each round is a wait for the slowest piece,
  // so levels no piece has anything below are skipped. (Coarser steps far from the target, ratio 2
  // while the excess is over 8 rounds' removal, cut the rounds on mri at N=2 from 183 to 47 but
  // doubled the distance on the flat and bumpy halves at N=4.)
  const long long excessNow = live - this->UnionTarget;
  this->NextCost *= LevelRatio;
  for (int step = 0; step < MaximumLevelSkip && this->NextCost < cheapest; ++step)
  {
    this->NextCost *= LevelRatio;
  }
  const long long excess = excessNow;
  if (excess <= 0 || allDone || this->Level >= MaximumLevels)
  {
    this->Target = liveTriangles; // on target, or nothing more can be agreed on
    return;
  }
  const bool settle = excess <= 2 * removed;
  // The excess (settled) or half of it (the next round's allowance) in parts proportional to what
  // each process still collapsing removed in this round (plus one, so that every one may go on).
  const auto weight = [&](int r) { return all(3 * r + 2) ? 0 : all(3 * r + 1) + (settle ? 0 : 1); };
  long long before = 0, total = 0;
  for (int r = 0; r < processes; ++r)
  {
    before += r < me ? weight(r) : 0;
    total += weight(r);
  }
  const Index amount = static_cast<Index>(settle ? excess : std::max(1LL, excess / 2));
  const Index part = done || total == 0 ? 0 : PartOf(amount, before, weight(me), total);
  if (settle)
  {
    this->Target = std::max<Index>(0, liveTriangles - part);
  }
  else
  {
    this->Floor = liveTriangles - std::max<Index>(1, part);
  }
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
