// SPDX-License-Identifier: BSD-3-Clause
#include "slodTriangleCollapse.h"

#include "slodBucketQueue.h"
#include "slodCollapsePasses.h"
#include "slodFreedMemory.h"
#include "slodGroupByKey.h"
#include "slodHugePages.h"
#include "slodInputPreparation.h"
#include "slodPointAttributes.h"
#include "slodPointStore.h"
#include "slodQuadric.h"
#include "slodStageClock.h"
#include "slodTriangleBVH.h"

#include "vtkLogger.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include <cassert>
#include <algorithm>
#include <atomic>
#include <iterator>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <system_error>
#include <thread>
#include <type_traits>


namespace slod
{
namespace
{
// Work budgets of the passes after the collapses, in point-triangle distance tests. The collapses
// cost about 2 us per input triangle and vtkQuadricDecimation 5-10 us: a share per input triangle
// keeps small inputs fast, and beyond a few 100,000 triangles the budget grows by only a little
// per triangle (a fixed allowance), so that the 1M-triangle case stays 3x faster than
// vtkQuadricDecimation. Within a budget the worst places come first.
struct PassBudget
{
  double PerTriangle, Allowance, PerTriangleBeyond;
  size_t For(Index triangles) const
  {
    return static_cast<size_t>(std::min(this->PerTriangle * triangles, this->Allowance + this->PerTriangleBeyond * triangles));
  }
};
constexpr PassBudget RefinementBudget{ 40, 3.0e6, 10 };
constexpr PassBudget FitBudget{ 40, 1.0e6, 0 };
// Refinement: rounds of screening and moves, and how much a move may raise the local sum of
// distances.
constexpr int RefinementRounds = 4;
constexpr double RefinementSumSlack = 1.05;
// Candidates screened: a tenth of the output vertices (the quadric error that picks them is only
// loosely tied to the distance), at most this many.
constexpr size_t RefinementPoolLimit = 600;
// Candidates screened per parallel step (the budget is checked between steps).
constexpr size_t ScreenChunk = 64;
// Vertices of the fit and the refinement visited per parallel step (ChunkedSweep): members within
// two edges of an earlier one are visited in a later step, so small chunks keep the steps few.
constexpr size_t SweepChunkSize = 32;
// The editable mesh's references stay within this factor of their size at the start
// (EditableMesh::SetReferenceRoomFactor; the mesh still gives an eighth of the live size as room).
// The room fills within the loop's first few percent, so it is part of the peak: 1.1 instead of
// EditableMesh::ShrinkingMeshRoomFactor (1.25) is 3 bytes per input vertex less on mc1m and the
// MRI, for more compactions in the blocks' order, which move no output (+0.16 % instructions).
// Not 1.125: on mc1m a reallocation of the references late in the loop then raised the peak by
// 4 MB (session 37).
constexpr double ReferenceRoomFactor = 1.1;
// Bound on the collapse loop's queue pops, per input triangle (see the loop).
constexpr long long MaximumPopsPerTriangle = 100;
// Largest batch of disjoint collapses (TriangleCollapseOptions::BatchCollapses): enough entries to
// keep the threads busy between two sequential phases, few enough that the queue stays fresh.
constexpr size_t MaximumBatchSize = 1024;
// Entries whose data the batch phases prefetch together (enough misses in flight, few enough
// that the lines stay in the cache until used).
constexpr vtkIdType PrefetchWindow = 32;
// The pass schedule: the window of ranked entries decided together. The window is the prefix of
// the undecided entries in rank order: after each round the decided entries leave and the next
// ranked ones fill it up, so every round has a full window (fixed chunks of 512 ended in rounds of
// a few entries: 7,000 rounds on mc1m, each four parallel loops). An undecided entry is walked
// again in every round, so the window stays small enough that few entries wait long.
constexpr size_t PassWindowSize = 512;
// A round that decides fewer than 1 / SlowRoundRatio of its entries hands the window to a walk one
// entry at a time (RunPass).
constexpr size_t SlowRoundRatio = 16;

// A vtkSMPTools functor that hands its range to Derived::Window in windows of PrefetchWindow.
template <typename Derived>
struct WindowedFunctor
{
  void operator()(vtkIdType first, vtkIdType last) const
  {
    for (vtkIdType begin = first; begin < last; begin += PrefetchWindow)
    {
      static_cast<const Derived*>(this)->Window(begin, std::min(last, begin + PrefetchWindow));
    }
  }
};
// The batches' parallel steps (picks, claims, checks, collapses: four Fors a batch). On one
// thread, or for one grain of entries, the functor runs on the caller directly: the SMP backend
// still makes tasks, 77 M instructions of TBB's own over mc250k's 3,336 batches and 205 M over
// noisy137's 140,427 (4.8 entries each) on one thread (session 41). The functors' results do
// not depend on how the range is split.
constexpr vtkIdType BatchGrain = 16;
// The perform step's grain (session 45): a collapse with the re-keying of its fan costs about
// 7,000 instructions (mc250k), 30 times an entry's pick and claims, so a step of 5 to 16
// collapses is worth a task per few of them (a vtkSMPTools::For costs about 6,000 instructions
// of TBB's own, session 41). With the batch grain, the performed collapses of the batches that
// ran at most 16 stayed on the calling thread: sequential work on two threads.
constexpr vtkIdType PerformGrain = 4;
inline bool OnCaller(bool oneThread, vtkIdType first, vtkIdType last, vtkIdType grain = BatchGrain)
{
  return oneThread || last - first <= grain;
}
template <typename Functor>
void ForEntries(bool oneThread, vtkIdType first, vtkIdType last, Functor& functor, vtkIdType grain = BatchGrain)
{
  if (OnCaller(oneThread, first, last, grain))
  {
    functor(first, last);
  }
  else
  {
    vtkSMPTools::For(first, last, grain, functor);
  }
}
constexpr int FitIterations = 2;
// The attribute metric may move a new vertex as long as its RMS distance to its planes stays
// within this factor of the geometric optimum's (PlaceWithAttributes).
constexpr double AttributePlacementReach = 2.0;
constexpr double FitRidge = 0.02;

// Integers held in fewer bytes while nobody reads them: each value is written as the LEB128 varint
// (7 bits a byte) of the zigzagged difference to a prediction the caller gives again when reading
// (a neighbouring value: the Morton order of the vertices and the triangles' order by their
// smallest vertex make most differences a few bytes). Lossless for any 64-bit values (differences
// modulo 2^64); read back in the order written.
class PackedIntegers
{
public:
  void Put(std::uint64_t value, std::uint64_t prediction)
  {
    const std::uint64_t difference = value - prediction;
    std::uint64_t z = (difference << 1) ^ (std::uint64_t(0) - (difference >> 63));
    while (z >= 0x80)
    {
      this->Bytes.push_back(static_cast<unsigned char>(z | 0x80));
      z >>= 7;
    }
    this->Bytes.push_back(static_cast<unsigned char>(z));
  }
  // Reads the value at `at` (advanced past it); at most 10 bytes a value.
  std::uint64_t Get(size_t& at, std::uint64_t prediction) const
  {
    std::uint64_t z = 0;
    for (int shift = 0; shift < 64; shift += 7)
    {
      const unsigned char byte = this->Bytes[at++];
      z |= std::uint64_t(byte & 0x7f) << shift;
      if (!(byte & 0x80))
      {
        break;
      }
    }
    return prediction + ((z >> 1) ^ (std::uint64_t(0) - (z & 1)));
  }
  void Finish() { this->Bytes.shrink_to_fit(); }
  void Release() { std::vector<unsigned char>().swap(this->Bytes); }
  size_t MemoryBytes() const { return this->Bytes.capacity(); }

private:
  std::vector<unsigned char> Bytes;
};

inline std::uint64_t IndexBits(Index i)
{
  return static_cast<std::uint64_t>(static_cast<std::int64_t>(i));
}
inline Index BitsIndex(std::uint64_t bits)
{
  return static_cast<Index>(static_cast<std::int64_t>(bits));
}
template <typename T>
std::uint64_t ValueBits(T x)
{
  typename std::conditional<sizeof(T) == 4, std::uint32_t, std::uint64_t>::type bits;
  std::memcpy(&bits, &x, sizeof(T));
  return bits;
}
template <typename T>
T BitsValue(std::uint64_t bits)
{
  typename std::conditional<sizeof(T) == 4, std::uint32_t, std::uint64_t>::type narrow =
    static_cast<decltype(narrow)>(bits);
  T x;
  std::memcpy(&x, &narrow, sizeof(T));
  return x;
}

// A list of ids packed while nobody reads it (each after the previous one), and unpacked again.
struct PackedIds
{
  PackedIntegers Packed;
  size_t Count = 0;
  bool Held = false;
  void Pack(std::vector<Index>& ids)
  {
    for (size_t i = 0; i < ids.size(); ++i)
    {
      this->Packed.Put(IndexBits(ids[i]), i > 0 ? IndexBits(ids[i - 1]) : 0);
    }
    this->Packed.Finish();
    this->Count = ids.size();
    this->Held = true;
    std::vector<Index>().swap(ids);
  }
  void Unpack(std::vector<Index>& ids)
  {
    if (!this->Held)
    {
      return;
    }
    ids.resize(this->Count);
    size_t at = 0;
    for (size_t i = 0; i < this->Count; ++i)
    {
      ids[i] = BitsIndex(this->Packed.Get(at, i > 0 ? IndexBits(ids[i - 1]) : 0));
    }
    this->Packed.Release();
    this->Held = false;
  }
};

// The input surface the passes after the collapses measure against (FitToOriginal,
// RefineDeviation), in the collapser's vertex ids. It is kept through the collapses, so its points
// are held as floats when every coordinate is one (a float input, read into doubles: the same
// values in half the bytes, so the passes see the same surface), and nobody reads it before they
// end: it is packed (PackedIntegers) from the set-up to the end of the collapses, where the
// working set peaks (session 24), and unpacked to the same values for the passes.
struct OriginalSurface
{
  std::vector<double> Points; // empty when FloatPoints holds them
  std::vector<float> FloatPoints;
  std::vector<Index> Triangles;
  PackedIntegers Packed;
  size_t PackedPoints = 0, PackedTriangles = 0; // coordinates and corners held in Packed
  bool PackedFloats = false;
  // Triangles: corner 0 after the previous triangle's corner 0, corners 1 and 2 after corner 0;
  // points: each coordinate's bits after the previous point's.
  void Pack()
  {
    this->PackedTriangles = this->Triangles.size();
    for (size_t i = 0; i < this->Triangles.size(); i += 3)
    {
      const std::uint64_t first = IndexBits(this->Triangles[i]);
      this->Packed.Put(first, i > 0 ? IndexBits(this->Triangles[i - 3]) : 0);
      this->Packed.Put(IndexBits(this->Triangles[i + 1]), first);
      this->Packed.Put(IndexBits(this->Triangles[i + 2]), first);
    }
    this->PackedFloats = this->Points.empty();
    this->PackedPoints = this->PackedFloats ? this->FloatPoints.size() : this->Points.size();
    if (this->PackedFloats)
    {
      this->PackPoints(this->FloatPoints);
    }
    else
    {
      this->PackPoints(this->Points);
    }
    this->Packed.Finish();
    std::vector<Index>().swap(this->Triangles);
    std::vector<double>().swap(this->Points);
    std::vector<float>().swap(this->FloatPoints);
  }
  template <typename T>
  void PackPoints(const std::vector<T>& points)
  {
    for (size_t i = 0; i < points.size(); ++i)
    {
      this->Packed.Put(ValueBits(points[i]), i >= 3 ? ValueBits(points[i - 3]) : 0);
    }
  }
  void Unpack()
  {
    size_t at = 0;
    this->Triangles.resize(this->PackedTriangles);
    for (size_t i = 0; i < this->PackedTriangles; i += 3)
    {
      const std::uint64_t first = this->Packed.Get(at, i > 0 ? IndexBits(this->Triangles[i - 3]) : 0);
      this->Triangles[i] = BitsIndex(first);
      this->Triangles[i + 1] = BitsIndex(this->Packed.Get(at, first));
      this->Triangles[i + 2] = BitsIndex(this->Packed.Get(at, first));
    }
    if (this->PackedFloats)
    {
      this->UnpackPoints(at, this->FloatPoints);
    }
    else
    {
      this->UnpackPoints(at, this->Points);
    }
    this->Packed.Release();
    this->PackedPoints = this->PackedTriangles = 0;
  }
  template <typename T>
  void UnpackPoints(size_t& at, std::vector<T>& points)
  {
    points.resize(this->PackedPoints);
    for (size_t i = 0; i < points.size(); ++i)
    {
      points[i] = BitsValue<T>(this->Packed.Get(at, i >= 3 ? ValueBits(points[i - 3]) : 0));
    }
  }
  // Takes the mesh's arrays (the mesh is left empty).
  void Take(TriangleMesh& mesh)
  {
    this->Triangles.swap(mesh.Triangles);
    this->Points.swap(mesh.Points);
    std::vector<double>().swap(mesh.Points);
    std::vector<Index>().swap(mesh.Triangles);
    if (PointStore::AllFloats(this->Points))
    {
      this->FloatPoints.assign(this->Points.begin(), this->Points.end());
      std::vector<double>().swap(this->Points);
    }
  }
  void Release()
  {
    std::vector<double>().swap(this->Points);
    std::vector<float>().swap(this->FloatPoints);
    std::vector<Index>().swap(this->Triangles);
    this->Packed.Release();
  }
  Index NumberOfPoints() const
  {
    return static_cast<Index>((this->Points.empty() ? this->FloatPoints.size() : this->Points.size()) / 3);
  }
  Index NumberOfTriangles() const { return static_cast<Index>(this->Triangles.size() / 3); }
  Vec3 Point(Index v) const
  {
    const size_t i = 3 * size_t(v);
    if (this->Points.empty())
    {
      return Vec3{ this->FloatPoints[i], this->FloatPoints[i + 1], this->FloatPoints[i + 2] };
    }
    return Vec3{ this->Points[i], this->Points[i + 1], this->Points[i + 2] };
  }
  size_t MemoryBytes() const
  {
    return this->Points.capacity() * sizeof(double) + this->FloatPoints.capacity() * sizeof(float) +
      this->Triangles.capacity() * sizeof(Index) + this->Packed.MemoryBytes();
  }
};

// Who descends from whom, for the passes that measure against the original surface: the
// original vertices merged into each surviving vertex and the original triangles of each
// original vertex (both CSR).
struct Ancestry
{
  std::vector<Index> AncestorStart, Ancestors, OriginalStart, OriginalTriangles;
};

// Candidates of the passes after the collapses: the larger value first, ties by vertex id.
bool WorseFirst(const std::pair<double, Index>& a, const std::pair<double, Index>& b)
{
  return a.first > b.first || (a.first == b.first && a.second < b.second);
}

class Neighbourhood;
struct ClosestAssignment;
struct MoveGuard;

// Triangles of the queue's lowest bucket (the pops of the near future) whose neighbourhoods the
// strict loop prefetches in stages one pop apart: corners and state, then the vertices' records,
// then their reference blocks, so that each stage reads only what the one before brought in and
// the misses overlap the current collapse instead of following one another at the next pops
// (session 31). Hints only: no result reads them.
struct UpcomingPrefetch
{
  static constexpr int MaximumWidth = 16;
  int Width = 0;                         // entries taken per pop (Options.UpcomingPrefetches)
  Index Cornered[MaximumWidth] = {};     // stage 1 done at the last pop
  Index Recorded[MaximumWidth] = {};     // stage 2 done at the last pop
  int CorneredCount = 0, RecordedCount = 0;
  size_t Cursor = 0;                     // where the next entries are taken in the lowest bucket
};

// The collapse loop's settings and counters (see TriangleCollapser::CollapseToTarget).
struct CollapseLoop
{
  CollapseOptions Check;      // the validity test, with the current normal limit
  double Deviation = 0.0;     // the current normal limit, degrees (relaxed when nothing is left)
  Index Target = 0, StartTriangles = 0, ToRemove = 1, ProgressStep = 1, NextProgress = 1;
  bool Settling = false;      // Options.SettleTarget has not given the target yet: Target is not a stop
  long long MaximumPops = 0, Pops = 0, Replaced = 0, Batches = 0, Selected = 0, Ran = 0;
  long long PlacementsDeferred = 0; // entries that lost their claims before their edge was placed
  long long RingWalks = 0; // TriangleCollapseResult::RingWalks
  long long Gathers = 0;   // TriangleCollapseResult::OneRingGathers
  long long LoneBatches = 0; // TriangleCollapseResult::BatchesPoppedAlone
  long long SharedBatches = 0, SharedEntries = 0, SharedCollapses = 0; // TriangleCollapseResult::SharedStep*
  // Wall time of the batches' phases: select, evaluate, apply; the parallel apply splits the last
  // into its sequential settle, its concurrent collapses and its sequential queue updates.
  // Timed only when TRACE is logged: the clock read costs about 25 ns, four reads per batch, and
  // the queue's batches are single collapses (mc1m to 10 %: 1.5 million batches, 4 % of the run).
  double PhaseSeconds[5] = { 0, 0, 0, 0, 0 };
  bool TimePhases = false;
  double* PhaseTotals() { return this->TimePhases ? this->PhaseSeconds : nullptr; }
  long long StatusCounts[static_cast<int>(CollapseStatus::Locked) + 1] = {};
  CollapseRecord Record;      // the last collapse
  std::vector<Index> Neighbors; // the link of the last collapse's vertex (when needed)
  UpcomingPrefetch Upcoming;    // the strict order's prefetches of the next pops
};

// Adds the wall time of consecutive phases to their totals (diagnostics of the batch loop); does
// nothing without totals.
class PhaseClock
{
public:
  explicit PhaseClock(double* totals)
    : Totals(totals)
    , Start(totals ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point())
  {
  }
  void Next()
  {
    if (!this->Totals)
    {
      return;
    }
    const auto now = std::chrono::steady_clock::now();
    this->Totals[this->Phase++] += std::chrono::duration<double>(now - this->Start).count();
    this->Start = now;
  }

private:
  double* Totals;
  std::chrono::steady_clock::time_point Start;
  int Phase = 0;
};

// The operation picked for a popped triangle: the set of 2 or 3 vertices and where they go.
struct Candidate
{
  Index Triangle = InvalidIndex;
  Index Set[3] = { InvalidIndex, InvalidIndex, InvalidIndex };
  int Count = 0;
  int Operation = -1; // 0 = triangle collapse, k = 1..3 = edge k-1 of the triangle
  Vec3 Local{ 0, 0, 0 }, Position{ 0, 0, 0 }; // the placement, relative to Origin and in world
  double Error = 0.0;
  // The triangle operation's cost as PopCost placed it (when it was allowed): a rejection of an
  // edge operation then re-keys the triangle without placing it again (KeyFromCache).
  std::optional<double> TriangleCost;
};

// The sets whose validity test failed on the topology (or a locked vertex) since the mesh's last
// edit, for the strict order's lone pops (session 44). Such a status depends only on the mesh and
// on the set as a set (EditableMesh::CheckCollapse tests it before the point, and its topological
// tests do not depend on the order of the set's vertices), so a set tested again before any
// collapse gets the same status without a test: on noisy scans an edge whose collapse would make a
// non-manifold edge is tried by both of its triangles, one pop after the other (both hold the same
// cached key). The mesh's live triangle count is the edit stamp: every collapse removes at least
// the popped triangle. A few entries, overwritten in turn: bounded work per pop.
struct FailedTopologies
{
  static constexpr int Capacity = 8;
  Index Sets[Capacity][3];
  CollapseStatus Status[Capacity];
  int Size = 0, Next = 0;
  Index Stamp = InvalidIndex;
  long long Reused = 0; // tests answered here (TriangleCollapseResult::TopologyTestsReused)

  static bool IsTopological(CollapseStatus status)
  {
    return status == CollapseStatus::NonManifold || status == CollapseStatus::BoundaryChange ||
      status == CollapseStatus::TooSmall || status == CollapseStatus::IsolatedVertex ||
      status == CollapseStatus::Locked || status == CollapseStatus::DeadVertex;
  }
  // The set sorted, an edge's third entry InvalidIndex (the key of a set as a set).
  static void Key(const Candidate& c, Index (&key)[3])
  {
    key[0] = c.Set[0];
    key[1] = c.Set[1];
    key[2] = c.Count == 3 ? c.Set[2] : InvalidIndex;
    std::sort(key, key + c.Count);
  }
  bool Find(const Candidate& c, Index stamp, CollapseStatus& status)
  {
    if (stamp != this->Stamp)
    {
      this->Size = 0;
      this->Next = 0;
      this->Stamp = stamp;
      return false;
    }
    Index key[3];
    Key(c, key);
    for (int i = 0; i < this->Size; ++i)
    {
      if (std::equal(key, key + 3, this->Sets[i]))
      {
        status = this->Status[i];
        ++this->Reused;
        return true;
      }
    }
    return false;
  }
  void Add(const Candidate& c, CollapseStatus status)
  {
    Key(c, this->Sets[this->Next]);
    this->Status[this->Next] = status;
    this->Next = (this->Next + 1) % Capacity;
    this->Size = std::min(this->Size + 1, Capacity);
  }
};

// One operation of a batch: picked and checked in parallel (EvaluateEntry), settled and performed
// in selection order (ApplyBatch).
struct BatchEntry
{
  enum class Outcome : unsigned char
  {
    NoOperation, // every operation of the triangle is excluded
    OverError,   // the cheapest operation exceeds MaximumError
    Valid,
    Alternative, // the optimum folds a triangle; an alternative placement passes
    Invalid
  };
  Candidate C;
  Outcome Result = Outcome::NoOperation;
  CollapseStatus Status = CollapseStatus::Ok;
  Vec3 Alternative{ 0, 0, 0 };
  double AlternativeError = 0.0, AlternativeCost = 0.0;
  bool Runs = false; // no earlier entry of the batch overlaps it
  unsigned char Walks = 0; // walks of its ring by the claims and the holders' check (RingWalks)
  unsigned char Gathers = 0; // gatherings of its set's triangles by its checks (OneRingGathers)
  bool Picked = false; // its operation is chosen (PickOperation) and it goes on to the check
  bool PlacementPending = false; // its operation is chosen, its placement waits for FinishPick
  Index Removes = 0, Survives = 0; // triangles the operation removes and keeps (parallel performing)
};

// A collapse performed concurrently with the others of its batch (TriangleCollapser::
// ParallelApply): its record, its new vertex, its part of the reserved reference room, and the
// triangles around the new vertex with their new queue keys (queued afterwards, in order).
struct PerformedCollapse
{
  CollapseRecord Record;
  Index Kept = InvalidIndex, Block = 0;
  std::vector<Index> Around;
  std::vector<float> Keys;
};

// Scratch of UpdateAround's cost computation: the edges (kept, x) already costed.
struct SpokeScratch
{
  std::vector<Index> Vertex;
  std::vector<float> Cost;
  long long TrianglePlacements = 0; // the fan triangles' own placements (TriangleCostBound skips some)
};

// What UpdateAround will write after a collapse, computed before it (KeysBeforeCollapse, in the
// look-ahead's parallel evaluation): the surviving triangles in the order the new vertex will list
// them, their new queue keys and their three cached edge costs each.
struct KeysAhead
{
  bool Ready = false;
  std::vector<Index> Around;
  std::vector<float> Keys;
  std::vector<float> EdgeCosts;
};

// The batches of the collapse loop: the popped entries and their queue keys, per vertex the
// smallest stamp of an entry whose ring holds it (see ClaimRingsFunctor), and a check scratch
// per thread.
struct PassState;
struct CollapseBatch
{
  size_t MaximumSize = 1;
  // The size the next selection aims at (1..MaximumSize): halved when fewer than a quarter of a
  // batch ran, doubled back when more than half did (AdaptSize).
  size_t Size = 1;
  double CostTolerance = 0.0;
  size_t MinimumSize = 1; // TriangleCollapseOptions::BatchMinimumSize (1 in the strict order)
  std::vector<BatchEntry> Entries;
  std::vector<float> Keys;
  std::vector<std::uint64_t> Owner;
  std::uint32_t Number = 0;
  vtkSMPThreadLocal<std::vector<Index>> Scratch;
  // The calling thread's check scratch when the batch is evaluated there (a lone entry, the
  // exact union): a thread-local lookup per pop cost about 100 instructions in the strict loop.
  std::vector<Index> SerialScratch;
  // The pass schedule's window fill: the ranked triangles of a fill, whether each waits for the
  // next pass (WaitsFunctor), and per thread the triangles tested (TriangleCollapseResult::WindowTests).
  std::vector<Index> Ranked;
  std::vector<unsigned char> Waits;
  long long FillTested = 0, FillAdmitted = 0; // ranked entries consumed by the fills, and admitted
  vtkSMPThreadLocal<long long> WindowTests{ 0LL };
  // Performing in parallel (ParallelApply): per entry the set's triangles from its check; the
  // entries performed (indices, in selection order) and what each did.
  bool Parallel = false;
  bool OneThread = false; // the SMP backend runs one thread: the steps run without it (ForEntries)
  // The batch's steps run on the calling thread (one thread, or a batch of one task): the claims
  // decide Runs in selection order (ClaimRingsFunctor::InOrder), so the evaluation does not walk
  // the rings again, and the collapses follow their settling in order (CollapseInOrder), so the
  // checks need not count their removals beforehand (session 42).
  bool InOrder = false;
  std::vector<std::vector<Index>> Gathered;
  std::vector<size_t> Order;
  std::vector<PerformedCollapse> Performed;
  vtkSMPThreadLocal<SpokeScratch> Spokes;
  // The pass schedule: every entry claims its ring, a lone one too; the collapses mark what they
  // changed (PassState::Change) instead of re-costing their surroundings.
  bool Passes = false;
  PassState* PassesState = nullptr;
  // The strict order's look-ahead (see LookAhead): an entry evaluated ahead keeps its set's
  // triangles (Gathered, EvaluateSlot); a lone entry taken from it reads them.
  struct LookAhead* Ahead = nullptr;
  const std::vector<Index>* LoneGathered = nullptr;
  const KeysAhead* LoneKeys = nullptr; // the lone entry's new keys computed ahead (or null)
  std::uint64_t Stamp(size_t entry) const;
  void AdaptSize(size_t ran);
  // The entries are performed together (ParallelApply, or a pass round), each keeping its set's
  // triangles from its check; a lone entry of the queue is performed as the strict order's
  // (ApplyBatch: the same collapse, queue writes and reference layout, without the batch's
  // per-entry bookkeeping).
  bool PerformsTogether() const { return this->Parallel && (this->Entries.size() > 1 || this->Passes); }
  // Each entry of Order gets its part of the reference room (Performed[k].Block); returns the room.
  size_t PlaceBlocks();
};

// TriangleCollapseOptions::LookAheadEvaluations: the upcoming pops named by the queue (ordered as
// Pop orders a scanned bucket), evaluated ahead where their closed rings are disjoint from every
// earlier one's (the batches' claims). Until a collapse touches its ring an entry's evaluation is
// the one it would get at its turn: the rings of the entries performed before it are disjoint from
// its ring, and what else could change it ends the look-ahead (a pop evaluated without it whose
// ring meets a ring still to take, a retried triangle, a compaction of the mesh's references, a
// change of the limits).
//
// Session 37: the evaluations run on one long-lived worker (LookAheadWorker) while the loop
// performs, instead of a vtkSMPTools::For per look-ahead (33k per mc1m run, each as long as its
// work). Each entry is a slot: the worker claims posted slots from the back, the loop takes them
// from the front and evaluates any slot still posted itself, so the split never changes a result.
// The loop writes only the rings of the entries it performs (disjoint from the rings still to
// take); whatever else it would write (a foreign pop's ring, a retry, a compaction, the limits)
// comes after End, which waits for the slot the worker holds.
// The worker's back-off while no slot is posted, in empty scans: pause, then yield, then sleep.
constexpr int IdleYieldAfter = 512, IdleSleepAfter = 2048;
inline void CpuRelax()
{
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}
enum : unsigned char
{
  SlotIdle,   // not posted (not running, cancelled, or taken)
  SlotPosted, // claims done, to be evaluated by whoever claims it
  SlotWorker, // the worker evaluates it
  SlotDone,   // evaluated by the worker
  SlotLoop    // evaluated by the loop itself
};
struct LookAhead
{
  LookAhead(int maximumWidth)
    : MaximumWidth(maximumWidth)
    , Slots(new std::atomic<unsigned char>[size_t(maximumWidth)])
  {
    for (int i = 0; i < maximumWidth; ++i)
    {
      this->Slots[i].store(SlotIdle, std::memory_order_relaxed);
    }
  }
  CollapseBatch Batch;
  std::vector<unsigned char> Taken; // per entry: a pop took its evaluation
  std::vector<KeysAhead> NewKeys;   // per entry: the new keys of its collapse (when valid)
  size_t Remaining = 0;             // entries that hold their ring and were not taken
  bool Live = false;
  size_t ReferenceRoom = 0;  // EditableMesh::ReferencesBeforeCompaction after the last collapse
  long long Updates = 0;     // TriangleCollapser::Updates at the evaluation
  int Width = 0, MaximumWidth = 0; // entries evaluated: halved after a look-ahead of little use
  std::vector<Index> Ids;
  std::vector<float> Keys;
  std::vector<size_t> Order;
  long long Evaluated = 0, TakenCount = 0; // TriangleCollapseResult::LookAheadEvaluated, LookAheadTaken
  std::unique_ptr<std::atomic<unsigned char>[]> Slots;
  std::atomic<int> SlotCount{ 0 };          // slots of the current look-ahead
  // The claims of the current look-ahead, a task in the same states as a slot: the worker makes them
  // while the loop evaluates the first entry (reserved to the loop); the loop settles them (Runs,
  // Remaining) before its next write to the mesh (SettleClaims).
  std::atomic<unsigned char> Claims{ SlotIdle };
  bool ClaimsSettled = true;
  std::atomic<bool> Finished{ false };       // the loop has ended: the worker leaves
  const CollapseOptions* Check = nullptr;    // the loop's limits (constant while Live)
  long long WorkerEvaluations = 0, WorkerClaims = 0; // slots and claims the worker made (diagnostics)
  // Takes back every posted slot and waits for the one the worker may hold: after it the loop may
  // write anywhere.
  void End()
  {
    this->Live = false;
    unsigned char claims = SlotPosted;
    if (!this->Claims.compare_exchange_strong(claims, SlotIdle, std::memory_order_acquire))
    {
      WaitWhileWorker(this->Claims);
    }
    if (!this->ClaimsSettled)
    {
      // Ended before its first pop: counted as wholly used and never evaluated, whether or not the
      // worker made its claims (the counts must not depend on timing).
      this->Claims.store(SlotIdle, std::memory_order_relaxed);
      this->ClaimsSettled = true;
      this->Remaining = 0;
    }
    const int n = this->SlotCount.load(std::memory_order_relaxed);
    for (int i = 0; i < n; ++i)
    {
      unsigned char state = SlotPosted;
      if (!this->Slots[i].compare_exchange_strong(state, SlotIdle, std::memory_order_acquire))
      {
        WaitWhileWorker(this->Slots[i]);
      }
    }
  }
  bool Exhausted() const { return !this->Live || this->Remaining == 0; }
  // A slot the worker holds is finished within one evaluation: spin briefly, then yield the core.
  static void WaitWhileWorker(const std::atomic<unsigned char>& slot)
  {
    for (long long spins = 0; slot.load(std::memory_order_acquire) == SlotWorker; ++spins)
    {
      if (spins > 64)
      {
        std::this_thread::yield();
      }
    }
  }
};

// The pass schedule's state (CollapseSchedule::Passes): per triangle the key of its cheapest
// operation (kept between passes while none of its vertices is in the ring of a collapse), the
// ranking of the current pass and the window of entries still undecided (RunPass).
constexpr unsigned char VertexInRing = 1, VertexMoved = 2;
struct PassState
{
  std::vector<float> Key;
  bool AllStale = true;     // every key is recomputed at the next pass (first pass, relaxed limits)
  PassRanking Ranking;
  float Floor = 0.0f;       // the costliest key performed so far (cheaper ones always pass)
  // Passes in a row that performed nothing under their limit: each doubles the next pass's goal
  // rank (RankPass), so that the limit rises only as far as something can be performed.
  int Widen = 0;
  // Per vertex, what the pass did to it: nothing, in the closed ring of a collapse (the triangles
  // around it are costed again next pass), or moved (the kept vertex of a collapse: the entries of
  // its triangles wait for the next pass).
  std::vector<unsigned char> Change;
  // Per triangle, what CostPass's first step did: bit 0 its key is computed again, bit k + 1 edge
  // k's cost is copied from its twin in the second step (EdgeOwnerCost).
  std::vector<unsigned char> Recost;
  // One bit per triangle: those whose key or state the next CostPass may change, which it then
  // visits alone (unless AllStale): the triangles around the kept vertices of this pass's
  // collapses, those it removed, and every live triangle with an excluded operation (costed afresh
  // once a vertex of its closed ring changes). Before session 27 every pass visited every
  // triangle, which made the finer passes of session 26 cost a sweep each. Bits, not a list: no
  // duplicates, read in index (memory) order, set concurrently by the collapses (atomic or).
  std::vector<std::uint64_t> Listed;
  std::vector<Index> Visit; // CostPass's triangles, in index order
  void List(Index t) { this->Listed[size_t(t) >> 6] |= std::uint64_t(1) << (t & 63); }
  void ListConcurrently(Index t)
  {
    __atomic_fetch_or(&this->Listed[size_t(t) >> 6], std::uint64_t(1) << (t & 63), __ATOMIC_RELAXED);
  }
  Index Performed = 0;      // collapses of the current pass
  long long Visits = 0;     // TriangleCollapseResult::CostPassVisits
  long long Rounds = 0;
};

// The working state of one simplification. Coordinates of quadrics are relative to Origin (the
// bounding-box centre) so that plane offsets stay small and the 4x4 sums do not cancel.
class TriangleCollapser
{
public:
  TriangleCollapser(const TriangleCollapseOptions& options, PointAttributes* attributes)
    : Options(options)
    , Attributes(attributes && !attributes->Empty() ? attributes : nullptr)
  {
  }

  void Run(TriangleMesh& mesh, TriangleCollapseResult& result);

private:
  // The stages of Run, in order.
  void Prepare(TriangleMesh& input, bool refine);
  // Adds the caller's TriangleCollapseOptions::LockedVertices to Locked, and takes its
  // PinnedVertices into Pinned (after Reorder).
  void LockCallersVertices(Index numberOfPoints);
  // Takes the caller's TriangleCollapseOptions::BorderVertices into Boundary (after Reorder) and
  // releases them.
  void TakeBorderFlags(Index numberOfPoints);
  // The pinned vertex of a set (InvalidIndex when none); `pinned` gets how many there are.
  Index PinnedIn(const Index* set, int count, int& pinned) const
  {
    pinned = 0;
    Index which = InvalidIndex;
    for (int i = 0; !this->Pinned.empty() && i < count; ++i)
    {
      if (this->Pinned[set[i]])
      {
        ++pinned;
        which = set[i];
      }
    }
    return which;
  }
  bool IsPinned(Index v) const { return !this->Pinned.empty() && this->Pinned[v]; }
  void InitializeQueue();
  // InitializeQueue with the edge cache: every triangle's key, each edge placed once.
  void InitialKeys(std::vector<float>& keys);
  void StartLoop(CollapseLoop& loop) const;
  void CollapseToTarget(CollapseLoop& loop, TriangleCollapseResult& result);
  // The pass schedule (CollapseSchedule::Passes), its stages in order: keys of the triangles
  // whose vertices changed (parallel), ranking, then rounds of claims,
  // checks and collapses (parallel) over a window of the ranking until every entry is decided.
  bool UsesPasses() const;
  void InitializePasses();
  struct CostPassFunctor;
  void CostPass(PassState& passes);
  // CostPass's first step for a live triangle: the triangle collapse's key (returned) and the
  // costs of the edges it owns (all, or those at a moved vertex); returns PassState::Recost's flags.
  unsigned char CostOwnedEdges(Index t, const std::vector<unsigned char>& change, bool all, float& key) const;
  struct EdgeCopyFunctor;
  // The cost of edge (a, b) of triangle t from the triangle that owns it, placed when none does.
  float EdgeOwnerCost(Index t, Index a, Index b) const;
  void RankPass(const CollapseLoop& loop, PassState& passes) const;
  bool RunPass(CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result);
  bool PassRound(CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result);
  bool DecideOneByOne(CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result);
  bool SettlePassRound(CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result);
  struct PerformPassFunctor;
  void CollapseInPasses(CollapseLoop& loop, TriangleCollapseResult& result);
  // After a collapse into `kept`: kept moved, its ring's triangles changed (PassState::Change).
  // The triangles around kept and those the collapse removed are listed for the next CostPass.
  void MarkChanged(Index kept, const CollapseRecord& record, PassState& passes) const;
  // An entry whose triangle has a vertex moved in this pass waits for the next (stale cost).
  bool Blocked(Index t, const PassState& passes) const
  {
    const Index* tri = this->Mesh.Triangle(t);
    return !this->Mesh.IsTriangleAlive(t) || passes.Change[tri[0]] == VertexMoved ||
      passes.Change[tri[1]] == VertexMoved || passes.Change[tri[2]] == VertexMoved;
  }
  // Appends the ranked entries from `next` on to the window until it is full; returns the next.
  size_t FillWindow(size_t next, CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result);
  // Raises the normal limit by a step, and releases the pinned vertices at 90 degrees; false
  // when nothing can be relaxed any more (or the target is met).
  bool LoosenLimits(CollapseLoop& loop, TriangleCollapseResult& result);
  void MoveTowardOriginal(const OriginalSurface& original, TriangleCollapseResult& result);
  // The steps of one pass of the collapse loop.
  bool RelaxNormalLimit(CollapseLoop& loop, TriangleCollapseResult& result);
  template <typename Functor>
  void ForEachRingVertex(const BatchEntry& entry, Functor&& f) const;
  template <typename Predicate>
  bool AllRingVertices(const BatchEntry& entry, Predicate&& p) const;
  struct PickFunctor;
  struct WaitsFunctor;
  // deferEdge: an edge operation's placement waits for FinishPick (the entry may lose its claims).
  bool PickOperation(BatchEntry& entry, bool deferEdge = false) const;
  bool FinishPick(BatchEntry& entry) const;
  struct ClaimRingsFunctor;
  void SelectBatch(CollapseLoop& loop, CollapseBatch& batch);
  // Whether the batch being selected (its first entry popped) will hold fewer than MinimumSize
  // entries: it is then performed as a lone pop.
  bool StaysSmall(const CollapseBatch& batch, size_t limit, float bound) const;
  void PrefetchUpcoming(UpcomingPrefetch& ahead) const;
  // picked: PickOperation ran already (batches of more than one entry).
  void EvaluateEntry(BatchEntry& entry, const CollapseOptions& check, std::vector<Index>& scratch, bool picked,
    FailedTopologies* failed = nullptr) const;
  // Whether the set fails whatever its point: a dead or locked vertex (EditableMesh's first test) or
  // a topology that failed since the last collapse (`failed`); then `status` is that test's.
  bool KnownToFail(const Candidate& c, const CollapseOptions& check, FailedTopologies& failed, CollapseStatus& status) const;
  struct EvaluateBatchFunctor;
  void EvaluateBatch(CollapseLoop& loop, CollapseBatch& batch);
  void EvaluateAhead(CollapseLoop& loop, LookAhead& ahead);
  // The claims of the look-ahead's first n entries in order, on the calling thread: an entry runs
  // when no earlier entry claimed a vertex of its ring (what the atomic minimum of the parallel
  // claims gives).
  void ClaimInOrder(CollapseBatch& batch, size_t n) const;
  // The look-ahead's claims and the posting of the slots that hold their rings (any thread), and
  // the loop's wait for them (made by itself if the worker has not started them).
  void MakeClaims(LookAhead& ahead) const;
  void SettleClaims(LookAhead& ahead) const;
  // The pop takes slot i's evaluation (done) and its new keys.
  bool TakeSlot(CollapseBatch& lone, size_t i) const;
  // One look-ahead slot: the check of entry i and, when valid, its new keys (any thread).
  void EvaluateSlot(LookAhead& ahead, size_t i) const;
  // The worker's side: evaluates posted slots until the loop has finished.
  void LookAheadWorker(LookAhead& ahead) const;
  // The collapse loop with the look-ahead's worker beside it (one parallel region per run).
  void CollapseWithWorker(CollapseLoop& loop, CollapseBatch& batch, LookAhead& ahead, TriangleCollapseResult& result);
  void CollapseSteps(CollapseLoop& loop, CollapseBatch& batch, LookAhead* ahead, TriangleCollapseResult& result);
  bool TakeFromLookAhead(CollapseBatch& batch) const;
  void ForeignPop(const CollapseBatch& lone) const;
  void CheckLookAhead(LookAhead& ahead) const;
  enum class Validity { Valid, Invalid, Deferred };
  Validity Settle(BatchEntry& entry, CollapseLoop& loop, TriangleCollapseResult& result);
  bool ApplyBatch(CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result);
  // The batch's disjoint collapses and their re-evaluations in parallel, the queue updates after
  // them in selection order (the same output for any thread count).
  bool ParallelApply(CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result, PhaseClock& clock);
  template <typename PerformEntry>
  void SettleInOrder(CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result, bool& more, PerformEntry&& perform);
  size_t SettleForParallel(CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result, bool& more);
  // ParallelApply on the calling thread (CollapseBatch::InOrder): settled and collapsed entry by
  // entry; then the queue updates (QueueInOrder, both ways).
  void CollapseInOrder(CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result, bool& more);
  bool QueueInOrder(CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result);
  struct PerformBatchFunctor;
  void QueuePerformed(const BatchEntry& entry, PerformedCollapse& done, CollapseLoop& loop, TriangleCollapseResult& result);
  void Reject(const Candidate& c, TriangleCollapseResult& result);
  // gathered: the set's triangles from its check (null: gathered again).
  // keys: its new keys computed ahead (or null).
  Index Perform(const Candidate& c, const std::vector<Index>* gathered, CollapseLoop& loop, TriangleCollapseResult& result,
    const KeysAhead* keys = nullptr);
  void MergeAttributes(const Candidate& c, Index kept);
  void MergeAttributeTerms(const Candidate& c, Index kept);
  void MergeVertexState(const Candidate& c, Index kept);
  void RetryPendingAround(Index kept, CollapseLoop& loop);
  void AppendHistory(const CollapseRecord& record, const CollapseLoop& loop, TriangleCollapseResult& result) const;
  bool ReportProgress(CollapseLoop& loop, TriangleCollapseResult& result) const;
  // Options.SettleTarget at the cheapest cost left (or with nothing left): the target once settled.
  void AskForTarget(CollapseLoop& loop, bool nothingLeft);
  // Diagnostics (vtkLogF at TRACE verbosity).
  // Bytes of the arrays held through the collapses (capacities, TriangleCollapseResult::PeakWorkingBytes).
  size_t WorkingBytes() const;
  void TraceWorkingParts(const char* when) const; // WorkingBytes's arrays at TRACE
  void TraceStatistics(const CollapseLoop& loop, const TriangleCollapseResult& result) const;
  Vec3 Local(Index v) const { return this->Mesh.Point(v) - this->Origin; }
  void InitializeQuadrics();
  // A border edge as it runs in its triangle.
  struct BorderEdge
  {
    Index Tail, Head, Triangle;
  };
  struct VertexQuadricsFunctor;
  double TrianglePlane(Index t, Quadric& q) const;
  bool BorderPlane(const BorderEdge& edge, Quadric& q) const;
  void BorderEdgesAt(Index x, std::vector<Index>& around, std::vector<BorderEdge>& out) const;
  // BorderEdgesAt where the caller's flags allow a border edge (all vertices without them), and
  // Boundary[x] set from it; returns whether the fan was searched.
  bool SearchBorderEdgesAt(Index x, std::vector<Index>& around, std::vector<BorderEdge>& out);
  void InitializePlaneSets();
  void SumLogicalSet(Index v); // exact mode: LogicalSum[v] from LogicalSet[v]
  // Options.AttributeError: the per-vertex attribute terms (AttributeQuadric, AttributeGradient).
  void InitializeAttributeTerms();
  void AddTriangleAttributeTerms(Index t, Quadric& q, double* gradient) const;
  // The quadric a set's operation is costed and placed with: SetQuadric, and with the attribute
  // metric the attribute terms at their optimum (eliminated in closed form).
  Quadric CostQuadric(const Index* set, int count, double& weight) const;
  // Placement with the attribute metric: the minimiser of the set's CostQuadric `q` while its
  // distance to the set's planes stays within AttributePlacementReach times that of the geometric
  // optimum, else the geometric optimum; returns q there.
  double PlaceWithAttributes(const Index* set, int count, const Quadric& q, Vec3& local) const;
  // RMS distance of `local` to the set's planes (the attribute terms left out).
  double GeometricError(const Index* set, int count, const Vec3& local) const;
  // With the attribute metric: the minimiser's attribute values of every merged output vertex.
  void StoreAttributeValues(const std::vector<Index>& newToOld, TriangleCollapseResult& result) const;
  // Quadric of the interrelated set of 2 (edge) or 3 (triangle) vertices.
  Quadric SetQuadric(const Index* v, int count, double& weight) const;
  // Best placement (local coordinates) and its cost for the set's quadric.
  double Place(const Index* v, int count, const Quadric& q, Vec3& local) const;
  // Place's part after the pinned vertices: the set's points given (c == b for an edge), so that a
  // placement can be made for a vertex not yet moved there (KeysBeforeCollapse).
  static double PlaceAmong(const Vec3& a, const Vec3& b, const Vec3& c, int count, const Quadric& q, Vec3& local);
  // Cheapest operation of triangle t: 0 = collapse the triangle, k = 1..3 = collapse its edge
  // (corner k-1, corner k % 3) when edge collapses are enabled.
  double Cost(Index t, Vec3& local, double& error, int& operation) const;
  void Update(Index t);
  void MarkPending(const Index* tri)
  {
    for (int k = 0; k < 3; ++k)
    {
      this->PendingCount += this->Pending[tri[k]] ? 0 : 1;
      this->Pending[tri[k]] = 1;
    }
  }
  // Update of every triangle around the new vertex v0: only the operations that involve v0 are
  // re-evaluated (each edge (v0, x) once); the edge opposite v0 keeps its cached cost.
  void UpdateAround(Index kept);
  // Accumulated mode: the cost and placement of collapsing the triangle (its vertex quadrics summed).
  double TriangleOperationCost(const Index* tri, Vec3& local) const;
  // Its cost part: the triangles around kept and their new keys (writes only their states).
  void AroundKeys(Index kept, std::vector<Index>& around, std::vector<float>& keys, SpokeScratch& spokes) const;
  // One triangle of a new vertex's fan, for AroundKeys after the collapse and KeysBeforeCollapse
  // before it: its new key and its cached edge costs (`cache`, read and written). The Fan gives
  // the corners' quadrics (Q) and the placements (Place) as they are after the collapse.
  // Bound: TriangleCostBound (a template argument, so that the default loop's code stays as it was).
  template <bool Bound, class Fan>
  float FanTriangleKey(const Fan& fan, const Index* tri, Index kept, const Quadric& qk, float* cache,
    SpokeScratch& spokes) const;
  template <bool Bound>
  __attribute__((noinline)) void FanKeys(Index kept, const std::vector<Index>& around, std::vector<float>& keys, SpokeScratch& spokes) const;
  struct MeshFan;
  struct PendingFan;
  void RequeueAround(const std::vector<Index>& around, const std::vector<float>& keys);
  // AroundKeys of a checked collapse before it is performed (the set's vertices seen as the kept
  // one at the new position with the summed quadric); false where it cannot be (see there).
  bool KeysBeforeCollapse(const Candidate& c, const std::vector<Index>& gathered, KeysAhead& out,
    SpokeScratch& spokes) const;
  // UpdateAround from keys computed ahead; false (nothing done) unless the new vertex lists
  // exactly their triangles in their order.
  bool RequeueKeysAhead(Index kept, const KeysAhead& ahead);
  // Cost at pop time: the triangle operation is evaluated, the edges come from the cache and
  // only the winning edge is placed again.
  // triangleCost: set to the triangle operation's cost when it is placed (the edge cache's path).
  double PopCost(Index t, Vec3& local, double& error, int& operation, std::optional<double>* triangleCost = nullptr) const;
  // Session 41: PopCost without the winning edge's placement (operation chosen, local and error
  // not set when an edge wins: PlaceEdge gives them). A batch entry's ring depends on its
  // operation only, and the entries that lose their claims never use the placement.
  double PopOperation(Index t, Vec3& local, double& error, int& operation, std::optional<double>* triangleCost) const;
  template <bool PlaceWinningEdge>
  double PopCostOf(Index t, Vec3& local, double& error, int& operation, std::optional<double>* triangleCost) const;
  double PlaceEdge(const Index* tri, int edge, Vec3& local, double& error) const;
  // TriangleCollapseOptions::TriangleCostBound: whether the triangle's own collapse cannot beat
  // its cheapest allowed edge by the bound from its cached edge costs (then it is not placed).
  bool TriangleCannotWin(const float* cache, unsigned excluded) const;
  // The key Cost would give triangle t, from its cached edge costs and the triangle operation's
  // cost (`triangle`, placed here when absent and the operation allowed): three placements fewer
  // for a rejection or a retry. False (the caller then runs Cost) when the cache is off or not
  // current, or when no allowed operation has a finite key.
  bool KeyFromCache(Index t, const std::optional<double>& triangle, float& key) const;
  // The cheapest valid one of the fallback placements of the set (world coordinates in p).
  bool AlternativePlacement(const Index* set, int count, const CollapseOptions& check, std::vector<Index>& scratch,
    Vec3& p, double& error, double& cost) const;
  void ExtractResult(TriangleCollapseResult& result);
  void BuildAncestry(const OriginalSurface& original, Ancestry& ancestry);
  // The FitToOriginal pass (see the header): returns the number of vertices moved.
  Index FitToOriginal(const OriginalSurface& original, const Ancestry& ancestry);
  std::vector<std::pair<double, Index>> FitOrder(const Ancestry& ancestry) const;
  void AssignClosest(const OriginalSurface& original, ClosestAssignment& assignment) const;
  bool FitStep(const Neighbourhood& region, const OriginalSurface& original, const Ancestry& ancestry, Index v, Vec3& step) const;
  void WatchMove(Neighbourhood& region, const ClosestAssignment& assignment, MoveGuard& guard) const;
  bool MoveKeepsBounds(const Neighbourhood& region, Index v, double reach, double minimumDot, MoveGuard& guard) const;
  struct ChunkedSweep;
  bool FitVertex(Neighbourhood& region, MoveGuard& guard, const ClosestAssignment& assignment, Index v, double minimumDot);
  int SweepLevel(Index v, const ChunkedSweep& sweep, std::uint32_t base, std::uint32_t own) const;
  template <typename Visit, typename OnMoved>
  void SweepChunk(ChunkedSweep& sweep, const std::vector<Index>& chunk, Visit&& visit, OnMoved&& onMoved);
  // The RefineDeviation pass (see the header); original = the input mesh in this mesh's ids.
  Index RefineDeviation(const OriginalSurface& original, const Ancestry& ancestry);
  std::vector<std::pair<double, Index>> RefinementPool(const Ancestry& ancestry) const;
  double ScreenDeviation(Neighbourhood& region, const std::vector<std::pair<double, Index>>& pool, size_t workBudget,
    std::vector<std::pair<double, Index>>& screen) const;
  double ScreenVertex(Neighbourhood& region, Index v) const;
  double LocalDeviation(const Neighbourhood& region, Index v, const Vec3& p, Vec3& step, double& sum);
  bool RefineVertex(Neighbourhood& region, Index v, double minimumDot, size_t workBudget);
  void PoolAroundMoved(const std::vector<Index>& movedVertices, const Ancestry& ancestry,
    std::vector<std::pair<double, Index>>& pool) const;
  // A maximum error is a promise about every output vertex: the passes that move vertices keep it.
  bool WithinMaximumError(Index v) const
  {
    const WeightedQuadric& q = this->QuadricOf(v);
    return this->Options.MaximumError < 0 || !(q.W > 0) ||
      std::sqrt(q.Q.Evaluate(this->Local(v)) / q.W) <= this->Options.MaximumError;
  }
  // Progressive records: the last collapse that produced a moved vertex now places it there.
  void StoreMovedPositions(TriangleCollapseResult& result);

  const TriangleCollapseOptions& Options;
  PointAttributes* Attributes;
  void Reorder(TriangleMesh& mesh);
  void SortTrianglesBySmallestVertex(TriangleMesh& mesh, const std::vector<Index>& newId);

  EditableMesh Mesh;
  // The input surface, kept for the passes after the collapses (empty without them).
  OriginalSurface Original;
  // The mesh is renumbered in spatial (Morton) order for cache locality; these map back. Read
  // only after the collapses unless the history or the point data need them: then packed
  // through the collapses (PackInputIds).
  std::vector<Index> VertexInput, TriangleInput;
  PackedIds VertexInputPacked, TriangleInputPacked;
  void PackInputIds();
  void UnpackInputIds();
  Vec3 Origin{ 0, 0, 0 };
  StageClock Stages{ "triangle collapse" }; // wall and CPU time per stage at TRACE
  double CostScale = 1.0; // makes float heap keys well scaled
  double Diagonal = 0.0;
  // Accumulated mode: per vertex the sum of its logical set's planes and of their weights,
  // side by side (one cache line pair per vertex instead of two separate misses).
  struct WeightedQuadric
  {
    Quadric Q;
    double W = 0.0;
  };
  std::vector<WeightedQuadric> Vertex;
  // Per triangle, in one 16-byte record (one cache miss instead of three): the cached keys of its
  // edge collapses, the operations that failed validity (bit k), and whether it waits for a change
  // of its neighbourhood (1: failed validity, retried when the 2-ring changes; 2: over MaximumError).
  // Its last two bytes, padding before session 44, hold the queue's bucket number of the triangle
  // (BasicBucketQueue::LendBucketIds: written by the queue only, so a whole record is never
  // assigned while the queue runs): the queue's own array of them was 4 bytes per input vertex at
  // the working set's peak.
  struct TriangleState
  {
    float EdgeCost[3] = { 0, 0, 0 };
    unsigned char Excluded = 0;
    unsigned char Rejected = 0;
    std::uint16_t QueueBucket = 0;
  };
  static_assert(sizeof(TriangleState) == 16, "the triangle state is one 16-byte record");
  mutable std::vector<TriangleState> State;
  bool CacheEdges = false;
  // The queue's edge caches hold what Cost would compute now: they are costed again around every
  // collapse (the only change of a vertex's quadric or position) until a release of the pinned
  // vertices changes the placements of the sets that held them. Off in the pass schedule.
  bool EdgeCachesCurrent = false;
  SpokeScratch Spokes;                  // UpdateAround scratch: edges (kept, x) already costed
  std::vector<Index> AroundScratch;     // UpdateAround scratch: the triangles around the new vertex
  std::vector<float> AroundKeyScratch;       // UpdateAround scratch: the new keys of those triangles
  mutable vtkSMPThreadLocal<EditableMesh::SetTrial> Trials; // AlternativePlacement's, per thread
  // The link tests' marks in a small table per thread (EditableMesh::CheckScratch) instead of the
  // mesh's per-vertex marks, which are then never allocated (EditableMesh::SetVertexLinkMarks; 12
  // bytes per input vertex through the collapses and the passes after them; the serial Neighbors
  // and IsBoundaryVertex use the mesh's own table). Not with AllowTopologyChange.
  bool LinkTables = false;
  mutable vtkSMPThreadLocal<EditableMesh::CheckScratch> LinkScratch;
  EditableMesh::CheckScratch* LinkTable() const { return this->LinkTables ? &this->LinkScratch.Local() : nullptr; }
  // The strict order's memory of the sets that failed their topology (its lone pops only: the
  // batches' and the look-ahead's evaluations run concurrently).
  mutable FailedTopologies FailedSets;
  CollapseStatus CheckSet(const Candidate& c, const CollapseOptions& check, std::vector<Index>& gathered) const;
  // RefineDeviation's tree of merges: a vertex merged away keeps, in its quadric's weight (never
  // read again; a weight is a sum of areas, never negative), -(1 + the vertex it merged into), so
  // no array of parents is held through the collapses (4 bytes per input vertex).
  // After the collapses only the survivors' quadrics are read (CompactQuadrics): Link then holds,
  // per vertex, its parent (>= 0) when merged away, or -(1 + its slot in Vertex) when it survived.
  Index ParentOf(Index v) const
  {
    if (!this->Link.empty())
    {
      return this->Link[v] >= 0 ? this->Link[v] : v;
    }
    const double w = this->Vertex[v].W;
    return w < 0 ? static_cast<Index>(-1.0 - w) : v;
  }
  void SetParent(Index v, Index parent)
  {
    if (!this->Link.empty())
    {
      this->Link[v] = parent; // (only vertices merged away are re-parented)
      return;
    }
    this->Vertex[v].W = -1.0 - double(parent);
  }
  // A surviving vertex's quadric, before or after CompactQuadrics.
  const WeightedQuadric& QuadricOf(Index v) const
  {
    assert(this->Link.empty() || this->Link[v] < 0); // (merged-away vertices have no slot)
    return this->Link.empty() ? this->Vertex[v] : this->Vertex[size_t(-1 - this->Link[v])];
  }
  void CompactQuadrics();
  // The original surface for the passes after the collapses: unpacked, or read again from
  // Options.ReloadInput (false when that failed).
  bool RestoreOriginal();
  std::vector<Index> Link;
  int FitThreads = 0;                  // FitToOriginal's diagnostics (TriangleCollapseResult)
  bool FitBudgetReached = false;
  SweepCounts FitVisits, RefinementVisits; // the passes' diagnostics (TriangleCollapseResult)
  std::vector<unsigned char> Boundary; // per vertex: on a border (maintained, see CollapseOptions)
  // Boundary holds the caller's border flags (Options.BorderVertices) before the quadrics: only
  // the flagged vertices' fans are searched for border edges.
  bool BorderFlagsGiven = false;
  long long BorderSearches = 0; // vertices whose fan was searched for border edges (the quadrics)
  long long TrianglePlanes = 0; // triangle planes computed by the quadrics (accumulated mode)
  std::vector<unsigned char> Locked;   // per vertex: non-manifold in the input or locked by the caller, never collapsed
  std::vector<unsigned char> Pinned;   // per vertex: kept exactly in place (see PinnedVertices); empty when none
  long long Updates = 0;               // triangles re-costed by Update (it ends a look-ahead)
  long long KeysAheadTaken = 0;        // collapses re-keyed from KeysBeforeCollapse's keys
  long long KeyUpdates = 0;            // queue keys rewritten after collapses (TriangleCollapseResult)
  long long FanPlacements = 0;         // placements made for those keys (TriangleCollapseResult)
  LookAhead* WorkerAhead = nullptr;    // the look-ahead beside the loop (ended before a retry)
  Index PendingCount = 0;              // vertices with Pending set
  std::vector<unsigned char> Pending;  // per vertex: a triangle of it was rejected for validity
  BasicBucketQueue<sizeof(TriangleState)> Heap; // (its bucket numbers in State: InitializeQueue)
  // Exact mode: original planes and, per vertex, the sorted ids of its logical set and their sum.
  std::vector<Quadric> PlaneQuadric;
  std::vector<double> PlaneWeight;
  std::vector<std::vector<Index>> LogicalSet;
  std::vector<WeightedQuadric> LogicalSum;
  std::vector<Index> MergeScratch;
  // Options.AttributeError (accumulated mode only): the components in the metric (0: off); per
  // vertex the sum of its triangles' attribute terms: their squares folded into a quadric of the
  // position, and 4 doubles per component (area-weighted gradient and offset); per vertex whether
  // it absorbed another one (its attribute values then come from the minimiser).
  int AttributeComponents = 0;
  std::vector<Quadric> AttributeQuadric;
  std::vector<double> AttributeGradient;
  std::vector<unsigned char> Merged;
};

void TriangleCollapser::Reorder(TriangleMesh& mesh)
{
  // Vertices in Morton order of their position, triangles by their smallest new vertex id: the
  // neighbourhoods that every collapse reads then sit close together in memory.
  const Index nv = mesh.NumberOfPoints(), nt = mesh.NumberOfTriangles();
  const auto b = mesh.Bounds();
  const double extent = std::max({ b[1] - b[0], b[3] - b[2], b[5] - b[4], 1e-300 });
  const double scale = double((1 << 21) - 1) / extent;
  auto keys = MakeOnHugePages<std::pair<std::uint64_t, Index>>(static_cast<size_t>(nv));
  // Independent per vertex, and the keys are distinct (they hold the id): the same order for
  // any thread count.
  vtkSMPTools::For(0, nv, 16384, [&](vtkIdType begin, vtkIdType end) {
    for (Index v = static_cast<Index>(begin); v < static_cast<Index>(end); ++v)
    {
      const double* p = &mesh.Points[3 * size_t(v)];
      const auto q = [&](int k) { return static_cast<std::uint64_t>(std::max(0.0, (p[k] - b[2 * k]) * scale)); };
      keys[v] = { SpreadBits21(q(0)) | SpreadBits21(q(1)) << 1 | SpreadBits21(q(2)) << 2, v };
    }
  });
  vtkSMPTools::Sort(keys.begin(), keys.end());
  this->VertexInput.resize(static_cast<size_t>(nv));
  std::vector<Index> newId(static_cast<size_t>(nv));
  auto points = MakeOnHugePages<double>(mesh.Points.size());
  // Each new id writes its own slots (and newId of a distinct old id): in parallel.
  vtkSMPTools::For(0, nv, 16384, [&](vtkIdType begin, vtkIdType end) {
    for (Index i = static_cast<Index>(begin); i < static_cast<Index>(end); ++i)
    {
      const Index v = keys[i].second;
      this->VertexInput[i] = v;
      newId[v] = i;
      std::copy(&mesh.Points[3 * size_t(v)], &mesh.Points[3 * size_t(v)] + 3, &points[3 * size_t(i)]);
    }
  });
  std::vector<std::pair<std::uint64_t, Index>>().swap(keys);
  mesh.Points.swap(points);
  std::vector<double>().swap(points);
  this->SortTrianglesBySmallestVertex(mesh, newId);
}

void TriangleCollapser::SortTrianglesBySmallestVertex(TriangleMesh& mesh, const std::vector<Index>& newId)
{
  // A counting sort by smallest new vertex, ties by input id (GroupByKey; with ParallelStages in
  // parallel, the order of the serial sort for any thread count).
  const Index nv = mesh.NumberOfPoints(), nt = mesh.NumberOfTriangles();
  auto smallest = [&](Index t) {
    const Index* tri = mesh.Triangle(t);
    return std::min({ newId[tri[0]], newId[tri[1]], newId[tri[2]] });
  };
  std::vector<Index> first(static_cast<size_t>(nv)), count(static_cast<size_t>(nv), 0);
  GroupByKey(
    nt, nv, smallest, [](Index t) { return t; }, first.data(), count.data(), this->TriangleInput,
    this->Options.ParallelStages);
  auto triangles = MakeOnHugePages<Index>(mesh.Triangles.size());
  vtkSMPTools::For(0, nt, 16384, [&](vtkIdType begin, vtkIdType end) {
    for (Index slot = static_cast<Index>(begin); slot < static_cast<Index>(end); ++slot)
    {
      const Index* tri = mesh.Triangle(this->TriangleInput[slot]);
      for (int k = 0; k < 3; ++k)
      {
        triangles[3 * size_t(slot) + k] = newId[tri[k]];
      }
    }
  });
  mesh.Triangles.swap(triangles);
}

// Area-weighted plane of triangle t (in local coordinates); returns the weight (the area).
double TriangleCollapser::TrianglePlane(Index t, Quadric& q) const
{
  const Index* tri = this->Mesh.Triangle(t);
  return TrianglePlaneQuadric(this->Local(tri[0]), this->Local(tri[1]), this->Local(tri[2]), q);
}

// Boundary plane (paper 2.3) of the border edge (tail, head) of triangle t: through the edge,
// perpendicular to its triangle, weighted by the squared edge length (same units as the areas)
// times the user weight. False when the weight vanishes.
bool TriangleCollapser::BorderPlane(const BorderEdge& edge, Quadric& q) const
{
  const Index* tri = this->Mesh.Triangle(edge.Triangle);
  const Vec3 tn = Normalized(Cross(this->Local(tri[1]) - this->Local(tri[0]), this->Local(tri[2]) - this->Local(tri[0])));
  return BorderEdgeQuadric(this->Local(edge.Tail), this->Local(edge.Head), tn, this->Options.BoundaryWeight, q);
}

// The border edges at x (directed as in their triangle), ordered by (tail, triangle): the order
// in which a sweep over the tails in id order meets them. An edge (u, v) is on the border when
// v is a neighbour of u through one triangle only.
void TriangleCollapser::BorderEdgesAt(Index x, std::vector<Index>& around, std::vector<BorderEdge>& out) const
{
  out.clear();
  // A neighbour met once in the fan is the far end of a border edge. Most vertices are interior
  // (every neighbour met twice): a sorted copy of a small fan's neighbours (insertion sort on the
  // stack) tells that without counting each of them.
  constexpr int smallFan = 32;
  Index sorted[2 * smallFan];
  int n = 0;
  this->Mesh.ForEachTriangle(x, [&](Index t) {
    const Index* tri = this->Mesh.Triangle(t);
    const int k = tri[0] == x ? 0 : (tri[1] == x ? 1 : 2);
    for (int step = 1; step < 3 && n < 2 * smallFan; ++step)
    {
      const Index value = tri[(k + step) % 3];
      int j = n++;
      for (; j > 0 && sorted[j - 1] > value; --j)
      {
        sorted[j] = sorted[j - 1];
      }
      sorted[j] = value;
    }
  });
  bool single = n == 2 * smallFan; // a large fan (or a full buffer): count below
  for (int i = 0; i < n && !single; i += 2)
  {
    // Pairs of equal neighbours: a single one shifts the pairing.
    single = i + 1 == n || sorted[i] != sorted[i + 1] || (i + 2 < n && sorted[i + 2] == sorted[i]);
  }
  if (!single)
  {
    return;
  }
  around.clear();
  this->Mesh.ForEachTriangle(x, [&](Index t) {
    const Index* tri = this->Mesh.Triangle(t);
    const int k = tri[0] == x ? 0 : (tri[1] == x ? 1 : 2);
    around.push_back(tri[(k + 1) % 3]);
    around.push_back(tri[(k + 2) % 3]);
  });
  this->Mesh.ForEachTriangle(x, [&](Index t) {
    const Index* tri = this->Mesh.Triangle(t);
    const int k = tri[0] == x ? 0 : (tri[1] == x ? 1 : 2);
    const Index next = tri[(k + 1) % 3], previous = tri[(k + 2) % 3];
    if (std::count(around.begin(), around.end(), next) == 1)
    {
      out.push_back({ x, next, t });
    }
    if (std::count(around.begin(), around.end(), previous) == 1)
    {
      out.push_back({ previous, x, t });
    }
  });
  std::sort(out.begin(), out.end(),
    [](const BorderEdge& a, const BorderEdge& b) { return a.Tail < b.Tail || (a.Tail == b.Tail && a.Triangle < b.Triangle); });
}

// Accumulated mode, one vertex range: each vertex sums the planes of its triangles and of its
// border edges itself (in the order a sweep over triangles, then border tails, would add them),
// so vertices are independent and the sums are the same for any thread count.
struct TriangleCollapser::VertexQuadricsFunctor
{
  TriangleCollapser& Self;
  vtkSMPThreadLocal<std::vector<Index>> Around;
  vtkSMPThreadLocal<std::vector<BorderEdge>> Edges;
  vtkSMPThreadLocal<long long> Searches;
  // Each triangle's plane is needed by its three corners (session 43: computed three times, 2.9 %
  // of mc1m's instructions). Per block of vertices, the planes of the triangles whose smallest
  // vertex lies in the block (a contiguous range: Reorder sorts the triangles by smallest vertex)
  // are kept for the block's other corners; the same values, summed in the same order.
  struct PlaneCache
  {
    Index First = 0, Block = -1;
    std::vector<Quadric> Q;
    std::vector<double> Area;
    std::vector<unsigned char> Held;
  };
  vtkSMPThreadLocal<PlaneCache> Planes;
  vtkSMPThreadLocal<long long> PlanesComputed;
  static constexpr Index CacheBlock = 4096;
  double Plane(PlaneCache& cache, Index t, Quadric& q, long long& computed) const
  {
    // Any triangle may take its own slot (t alone decides it); the order only decides how many hit.
    const Index slot = t - cache.First;
    if (slot < 0 || size_t(slot) >= cache.Held.size())
    {
      ++computed;
      return this->Self.TrianglePlane(t, q);
    }
    if (!cache.Held[slot])
    {
      ++computed;
      cache.Area[slot] = this->Self.TrianglePlane(t, cache.Q[slot]);
      cache.Held[slot] = 1;
    }
    q = cache.Q[slot];
    return cache.Area[slot];
  }
  // The triangles whose smallest vertex is in [blockBegin, blockEnd).
  void StartBlock(PlaneCache& cache, Index blockBegin, Index blockEnd) const
  {
    const auto smallestFrom = [&](Index v) {
      Index low = 0, high = this->Self.Mesh.NumberOfTriangles();
      while (low < high) // first triangle whose smallest vertex is at least v
      {
        const Index mid = low + (high - low) / 2;
        const Index* tri = this->Self.Mesh.Triangle(mid);
        if (std::min({ tri[0], tri[1], tri[2] }) < v)
        {
          low = mid + 1;
        }
        else
        {
          high = mid;
        }
      }
      return low;
    };
    cache.First = smallestFrom(blockBegin);
    const size_t n = size_t(smallestFrom(blockEnd) - cache.First);
    cache.Q.resize(n);
    cache.Area.resize(n);
    cache.Held.assign(n, 0);
  }
  void operator()(vtkIdType begin, vtkIdType end)
  {
    auto& around = this->Around.Local();
    auto& edges = this->Edges.Local();
    PlaneCache& cache = this->Planes.Local();
    long long& computed = this->PlanesComputed.Local();
    Index blockBegin = static_cast<Index>(begin);
    for (Index x = static_cast<Index>(begin); x < static_cast<Index>(end); ++x)
    {
      if (x == blockBegin || x - blockBegin == CacheBlock)
      {
        blockBegin = x;
        this->StartBlock(cache, x, std::min(static_cast<Index>(end), x + CacheBlock));
      }
      WeightedQuadric sum;
      this->Self.Mesh.ForEachTriangle(x, [&](Index t) {
        Quadric q;
        sum.W += this->Plane(cache, t, q, computed);
        sum.Q += q;
      });
      if (this->Self.SearchBorderEdgesAt(x, around, edges))
      {
        ++this->Searches.Local();
      }
      for (const BorderEdge& edge : edges)
      {
        Quadric q;
        if (this->Self.BorderPlane(edge, q))
        {
          sum.Q += q;
        }
      }
      this->Self.Vertex[x] = sum;
    }
  }
};

bool TriangleCollapser::SearchBorderEdgesAt(Index x, std::vector<Index>& around, std::vector<BorderEdge>& out)
{
  if (this->BorderFlagsGiven && !this->Boundary[x])
  {
    // Not on an edge of one triangle (the caller's classification of this mesh): no border edge.
    out.clear();
    return false;
  }
  this->BorderEdgesAt(x, around, out);
  this->Boundary[x] = out.empty() ? 0 : 1;
  return true;
}

// Exact mode: every plane gets an id (in triangle order, then border tails in id order) and the
// sorted ids of each vertex's logical set. Sequential: the ids are shared by the vertices.
void TriangleCollapser::InitializePlaneSets()
{
  const Index nv = this->Mesh.NumberOfPoints(), nt = this->Mesh.NumberOfTriangles();
  this->LogicalSet.assign(size_t(nv), {});
  auto addPlane = [&](const Quadric& q, double w, const Index* vertices, int count) {
    const Index id = static_cast<Index>(this->PlaneQuadric.size());
    this->PlaneQuadric.push_back(q);
    this->PlaneWeight.push_back(w);
    for (int i = 0; i < count; ++i)
    {
      this->LogicalSet[vertices[i]].push_back(id);
    }
  };
  for (Index t = 0; t < nt; ++t)
  {
    Quadric q;
    const double area = this->TrianglePlane(t, q);
    addPlane(q, area, this->Mesh.Triangle(t), 3);
  }
  std::vector<Index> around;
  std::vector<BorderEdge> edges;
  for (Index u = 0; u < nv; ++u)
  {
    this->BorderSearches += this->SearchBorderEdgesAt(u, around, edges) ? 1 : 0;
    for (const BorderEdge& edge : edges)
    {
      Quadric q;
      if (edge.Tail == u && this->BorderPlane(edge, q))
      {
        const Index ends[2] = { edge.Tail, edge.Head };
        addPlane(q, 0.0, ends, 2);
      }
    }
  }
  this->LogicalSum.assign(size_t(nv), WeightedQuadric());
  for (Index v = 0; v < nv; ++v)
  {
    std::sort(this->LogicalSet[v].begin(), this->LogicalSet[v].end());
    this->SumLogicalSet(v);
  }
}

void TriangleCollapser::SumLogicalSet(Index v)
{
  WeightedQuadric& sum = this->LogicalSum[v];
  sum = WeightedQuadric();
  for (Index id : this->LogicalSet[v])
  {
    sum.Q += this->PlaneQuadric[id];
    sum.W += this->PlaneWeight[id];
  }
}

void TriangleCollapser::InitializeQuadrics()
{
  const Index nv = this->Mesh.NumberOfPoints();
  if (!this->BorderFlagsGiven)
  {
    this->Boundary.assign(size_t(nv), 0);
  }
  this->BorderSearches = 0;
  if (this->Options.ExactUnion)
  {
    this->InitializePlaneSets();
    return;
  }
  AssignOnHugePages(this->Vertex, size_t(nv), WeightedQuadric());
  VertexQuadricsFunctor functor{ *this, {}, {}, {}, {}, {} };
  vtkSMPTools::For(0, nv, 4096, functor);
  for (long long searches : functor.Searches)
  {
    this->BorderSearches += searches;
  }
  this->TrianglePlanes = 0;
  for (long long planes : functor.PlanesComputed)
  {
    this->TrianglePlanes += planes;
  }
  this->InitializeAttributeTerms();
}

// The attribute terms of triangle t added to q and gradient (4 per component): for each component
// s (scaled to a length), area * (s - g.p - d)^2 where g.p + d interpolates the corners' values
// linearly over the triangle (g in its plane). Expanded in s, the terms that hold p only go to q;
// g and d, area-weighted, are what the elimination of s needs. A triangle without area adds nothing.
void TriangleCollapser::AddTriangleAttributeTerms(Index t, Quadric& q, double* gradient) const
{
  const Index* tri = this->Mesh.Triangle(t);
  const Vec3 a = this->Local(tri[0]), e1 = this->Local(tri[1]) - a, e2 = this->Local(tri[2]) - a;
  const Vec3 n2 = Cross(e1, e2);
  const double length = Norm(n2);
  if (!(length > 0))
  {
    return;
  }
  const double area = 0.5 * length;
  const Vec3 n = (1.0 / length) * n2;
  // Dual basis of (e1, e2) in the plane: g = (s1 - s0) u + (s2 - s0) v has g.e1 = s1 - s0, g.e2 = s2 - s0.
  const Vec3 u = (1.0 / length) * Cross(e2, n), v = (1.0 / length) * Cross(n, e1);
  const AttributeErrorTerms& terms = *this->Options.AttributeError;
  const int m = this->AttributeComponents;
  const double* s[3];
  for (int k = 0; k < 3; ++k)
  {
    s[k] = terms.Values.data() + size_t(m) * size_t(this->VertexInput[tri[k]]);
  }
  for (int j = 0; j < m; ++j)
  {
    const double scale = terms.Scales[size_t(j)];
    const double s0 = scale * s[0][j];
    const Vec3 g = (scale * s[1][j] - s0) * u + (scale * s[2][j] - s0) * v;
    const double d = s0 - Dot(g, a);
    q += Quadric::FromPlane(g, d, area);
    double* sum = gradient + 4 * j;
    sum[0] += area * g[0];
    sum[1] += area * g[1];
    sum[2] += area * g[2];
    sum[3] += area * d;
  }
}

void TriangleCollapser::InitializeAttributeTerms()
{
  const AttributeErrorTerms* terms = this->Options.AttributeError;
  const Index nv = this->Mesh.NumberOfPoints();
  if (!terms || terms->Components <= 0 || terms->Scales.size() != size_t(terms->Components) ||
    terms->Values.size() != size_t(terms->Components) * size_t(nv))
  {
    return;
  }
  const int m = this->AttributeComponents = terms->Components;
  this->AttributeQuadric.assign(size_t(nv), Quadric());
  this->AttributeGradient.assign(size_t(nv) * 4 * size_t(m), 0.0);
  this->Merged.assign(size_t(nv), 0);
  // Per vertex over its own triangles, in their order: the same sums for any thread count.
  vtkSMPTools::For(0, nv, 4096, [this, m](vtkIdType begin, vtkIdType end) {
    for (Index x = static_cast<Index>(begin); x < static_cast<Index>(end); ++x)
    {
      double* gradient = this->AttributeGradient.data() + size_t(x) * 4 * size_t(m);
      this->Mesh.ForEachTriangle(x, [&](Index t) { this->AddTriangleAttributeTerms(t, this->AttributeQuadric[x], gradient); });
    }
  });
}

Quadric TriangleCollapser::CostQuadric(const Index* set, int count, double& weight) const
{
  Quadric q = this->SetQuadric(set, count, weight);
  const int m = this->AttributeComponents;
  if (m == 0 || !(weight > 0))
  {
    return q;
  }
  for (int i = 0; i < count; ++i)
  {
    q += this->AttributeQuadric[set[i]];
  }
  // Minimum over each component s of sum area * (s - g.p - d)^2 = W s^2 - 2 s (G.p + D) + ...:
  // s = (G.p + D) / W, which takes (G.p + D)^2 / W off the folded terms.
  for (int j = 0; j < m; ++j)
  {
    double sum[4] = { 0, 0, 0, 0 };
    for (int i = 0; i < count; ++i)
    {
      const double* g = this->AttributeGradient.data() + (size_t(set[i]) * size_t(m) + size_t(j)) * 4;
      sum[0] += g[0];
      sum[1] += g[1];
      sum[2] += g[2];
      sum[3] += g[3];
    }
    q += Quadric::FromPlane(Vec3{ sum[0], sum[1], sum[2] }, sum[3], -1.0 / weight);
  }
  return q;
}

double TriangleCollapser::PlaceWithAttributes(const Index* set, int count, const Quadric& q, Vec3& local) const
{
  double weight = 0;
  const Quadric geometric = this->SetQuadric(set, count, weight);
  const double best = this->Place(set, count, geometric, local);
  if (!std::isfinite(best))
  {
    return best; // two pinned vertices
  }
  // Where attributes are discontinuous (a merged seam, the copies of a pole), their linear
  // predictions disagree, and the full minimiser would move the vertex off the surface to
  // reconcile them (seen: 0.14 of the radius on a 40 x 20 textured sphere at 10 %).
  Vec3 withAttributes;
  this->Place(set, count, q, withAttributes);
  const double reach = AttributePlacementReach * AttributePlacementReach;
  const double slack = weight * 1e-12 * this->Diagonal * this->Diagonal;
  if (geometric.Evaluate(withAttributes) <= reach * best + slack)
  {
    local = withAttributes;
  }
  return q.Evaluate(local);
}

double TriangleCollapser::GeometricError(const Index* set, int count, const Vec3& local) const
{
  double weight = 0;
  const Quadric q = this->SetQuadric(set, count, weight);
  return weight > 0 ? std::sqrt(q.Evaluate(local) / weight) : 0.0;
}

void TriangleCollapser::StoreAttributeValues(const std::vector<Index>& newToOld, TriangleCollapseResult& result) const
{
  const int m = this->AttributeComponents;
  result.AttributeValuesSet.assign(m > 0 ? newToOld.size() : 0, 0);
  result.AttributeValues.assign(m > 0 ? newToOld.size() * size_t(m) : 0, 0.0);
  for (size_t i = 0; m > 0 && i < newToOld.size(); ++i)
  {
    const Index v = newToOld[i];
    const double w = this->QuadricOf(v).W;
    if (!this->Merged[v] || this->IsPinned(v) || !(w > 0))
    {
      continue; // its own values, or a pinned vertex's
    }
    const Vec3 p = this->Local(v);
    result.AttributeValuesSet[i] = 1;
    for (int j = 0; j < m; ++j)
    {
      const double* g = this->AttributeGradient.data() + (size_t(v) * size_t(m) + size_t(j)) * 4;
      const double scaled = (g[0] * p[0] + g[1] * p[1] + g[2] * p[2] + g[3]) / w;
      result.AttributeValues[i * size_t(m) + size_t(j)] = scaled / this->Options.AttributeError->Scales[size_t(j)];
    }
  }
}

Quadric TriangleCollapser::SetQuadric(const Index* tri, int count, double& weight) const
{
  if (!this->Options.ExactUnion)
  {
    Quadric q = this->Vertex[tri[0]].Q;
    weight = this->Vertex[tri[0]].W;
    for (int i = 1; i < count; ++i)
    {
      q += this->Vertex[tri[i]].Q;
      weight += this->Vertex[tri[i]].W;
    }
    return q;
  }
  // Union of the sorted logical sets, each plane once: the largest set's sum, plus the planes of
  // the others that no set before them holds (binary searches). An evaluation costs the smaller
  // sets only, so a vertex with thousands of planes (a high-valence fan) is not summed again for
  // each of its triangles.
  int largest = 0;
  for (int i = 1; i < count; ++i)
  {
    largest = this->LogicalSet[tri[i]].size() > this->LogicalSet[tri[largest]].size() ? i : largest;
  }
  Quadric q = this->LogicalSum[tri[largest]].Q;
  weight = this->LogicalSum[tri[largest]].W;
  auto holds = [&](int i, Index id) {
    const auto& s = this->LogicalSet[tri[i]];
    return std::binary_search(s.begin(), s.end(), id);
  };
  for (int i = 0; i < count; ++i)
  {
    if (i == largest)
    {
      continue;
    }
    for (Index id : this->LogicalSet[tri[i]])
    {
      bool seen = holds(largest, id);
      for (int j = 0; j < i && !seen; ++j)
      {
        seen = j != largest && holds(j, id);
      }
      if (!seen)
      {
        q += this->PlaneQuadric[id];
        weight += this->PlaneWeight[id];
      }
    }
  }
  return q;
}

double TriangleCollapser::Place(const Index* tri, int count, const Quadric& q, Vec3& local) const
{
  int pinned = 0;
  const Index pin = this->PinnedIn(tri, count, pinned);
  if (pinned > 0)
  {
    // A pinned vertex stays where it is: the others merge into it; two pinned vertices never
    // merge (the seam or region border between them would lose a vertex).
    if (pinned > 1)
    {
      return std::numeric_limits<double>::infinity();
    }
    local = this->Local(pin);
    return q.Evaluate(local);
  }
  const Vec3 a = this->Local(tri[0]), b = this->Local(tri[1]);
  return PlaceAmong(a, b, count == 3 ? this->Local(tri[2]) : b, count, q, local);
}

// Inlined into Place, whose code it was: a call there cost the default loop 30 M instructions on
// mc250k (session 36).
inline __attribute__((always_inline)) double TriangleCollapser::PlaceAmong(
  const Vec3& a, const Vec3& b, const Vec3& c, int count, const Quadric& q, Vec3& local)
{
  if (q.Minimize(local, 1e-10))
  {
    // A well-conditioned optimum far outside the neighbourhood still means a near-singular
    // system in practice (long thin features); keep it only within reach of the set.
    const Vec3 centroid = count == 3 ? (1.0 / 3.0) * (a + b + c) : 0.5 * (a + b);
    // For an edge (c == b) the sum's terms are |a-b|^2, 0 and |b-a|^2, so it is ab + ab to the
    // bit (b - a is -(a - b) exactly; the points are finite): two dot products fewer per edge.
    const double ab = Dot(a - b, a - b);
    const double reach = count == 3 ? ab + Dot(b - c, b - c) + Dot(c - a, c - a) : ab + ab;
    const Vec3 d = local - centroid;
    if (Dot(d, d) <= 4.0 * reach)
    {
      return q.Evaluate(local);
    }
  }
  // Fallback (§2.2): the best of the centroid, the vertices and the edge midpoints.
  const Vec3 candidates[7] = { (1.0 / 3.0) * (a + b + c), a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a) };
  double best = std::numeric_limits<double>::infinity();
  const int first = count == 3 ? 0 : 1, last = count == 3 ? 7 : 5; // edge: a, b, b, midpoint
  for (int i = first; i < last; ++i)
  {
    const Vec3& p = candidates[i];
    const double e = q.Evaluate(p);
    if (e < best)
    {
      best = e;
      local = p;
    }
  }
  return best;
}

double TriangleCollapser::Cost(Index t, Vec3& local, double& error, int& operation) const
{
  const Index* tri = this->Mesh.Triangle(t);
  const unsigned excluded = this->State[t].Excluded; // operations that failed the validity test
  operation = -1;
  double cost = std::numeric_limits<double>::infinity();
  error = 0.0;
  // An edge collapse removes half as many triangles: it wins only when its cost times the bias
  // is below the triangle collapse's.
  const double bias = this->Options.EdgeCollapseBias;
  const bool edges = this->Options.EdgeCollapses;
  double bestFactor = 1.0, bestWeight = 0.0;
  auto consider = [&](int op, const Index* set, int count, const Quadric& q, double weight, double factor, bool allowed) {
    Vec3 p;
    const double c =
      (this->AttributeComponents > 0 ? this->PlaceWithAttributes(set, count, q, p) : this->Place(set, count, q, p)) * factor;
    if (allowed && c < cost)
    {
      cost = c;
      local = p;
      bestFactor = factor;
      bestWeight = weight;
      operation = op;
    }
    return c;
  };
  // The error (RMS distance to the set's planes) of the winner only.
  auto finish = [&]() {
    error = bestWeight > 0 && operation >= 0 ? std::sqrt(cost / bestFactor / bestWeight) : 0.0;
    if (this->AttributeComponents > 0 && operation > 0)
    {
      const Index edge[2] = { tri[operation - 1], tri[operation % 3] };
      error = this->GeometricError(edge, 2, local);
    }
    else if (this->AttributeComponents > 0 && operation == 0)
    {
      error = this->GeometricError(tri, 3, local);
    }
    return cost;
  };
  // The exact union and the attribute metric: each set's quadric on its own.
  if (this->Options.ExactUnion || this->AttributeComponents > 0)
  {
    double weight = 0;
    if (!(excluded & 1u))
    {
      const Quadric q = this->CostQuadric(tri, 3, weight);
      consider(0, tri, 3, q, weight, 1.0, true);
    }
    for (int k = 0; edges && k < 3; ++k)
    {
      if (!(excluded & (2u << k)))
      {
        const Index edge[2] = { tri[k], tri[(k + 1) % 3] };
        const Quadric qe = this->CostQuadric(edge, 2, weight);
        consider(k + 1, edge, 2, qe, weight, bias, true);
      }
    }
    return finish();
  }
  // Accumulated mode: the set quadrics are sums of the three vertex quadrics, shared below.
  const Quadric& qa = this->Vertex[tri[0]].Q;
  const Quadric& qb = this->Vertex[tri[1]].Q;
  const Quadric& qc = this->Vertex[tri[2]].Q;
  const double wa = this->Vertex[tri[0]].W, wb = this->Vertex[tri[1]].W, wc = this->Vertex[tri[2]].W;
  const Quadric qab = qa + qb;
  if (!(excluded & 1u))
  {
    consider(0, tri, 3, qab + qc, wa + wb + wc, 1.0, true);
  }
  if (edges)
  {
    // All three edge costs are computed and cached (UpdateAround reuses the edge that does not
    // touch the new vertex).
    const Index e0[2] = { tri[0], tri[1] }, e1[2] = { tri[1], tri[2] }, e2[2] = { tri[2], tri[0] };
    float* cache = this->State[t].EdgeCost;
    cache[0] = static_cast<float>(consider(1, e0, 2, qab, wa + wb, bias, !(excluded & 2u)) * this->CostScale);
    cache[1] = static_cast<float>(consider(2, e1, 2, qb + qc, wb + wc, bias, !(excluded & 4u)) * this->CostScale);
    cache[2] = static_cast<float>(consider(3, e2, 2, qc + qa, wc + wa, bias, !(excluded & 8u)) * this->CostScale);
  }
  return finish();
}

bool TriangleCollapser::AlternativePlacement(const Index* set, int count, const CollapseOptions& check,
  std::vector<Index>& scratch, Vec3& p, double& error, double& cost) const
{
  double weight = 0;
  const Quadric q = this->CostQuadric(set, count, weight);
  int pinned = 0;
  if (this->PinnedIn(set, count, pinned) != InvalidIndex)
  {
    return false; // a pinned set has only one placement, the one already checked
  }
  const Vec3 a = this->Local(set[0]), b = this->Local(set[1]), c = count == 3 ? this->Local(set[2]) : b;
  std::pair<double, Vec3> candidates[7];
  int n = 0;
  const Vec3 all[7] = { a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a), (1.0 / 3.0) * (a + b + c) };
  const int used[2][7] = { { 0, 1, 3, -1, -1, -1, -1 }, { 0, 1, 2, 3, 4, 5, 6 } };
  for (int i : used[count == 3 ? 1 : 0])
  {
    if (i >= 0)
    {
      candidates[n++] = { q.Evaluate(all[i]), all[i] };
    }
  }
  std::sort(candidates, candidates + n, [](const auto& x, const auto& y) { return x.first < y.first; });
  // One trial of the set for all its points (session 27): its triangles gathered and its topology
  // tested once, where a CheckCollapse per point did both again; a point passes exactly when
  // CheckCollapse would pass it. `scratch` keeps the set's triangles from the check of the
  // optimum (the same set, gathered before its geometric test failed) for the collapse. Since
  // session 44 the trial borrows them, and the topology that check passed is not tested again
  // (a geometric status comes only after the topology when the geometry is not tested first).
  EditableMesh::SetTrial& trial = this->Trials.Local();
  const bool borrowed = !check.GeometryFirst;
  if (borrowed)
  {
    this->Mesh.PrepareTrialAfterGeometry(set, count, check, scratch, trial);
  }
  else
  {
    this->Mesh.PrepareTrial(set, count, check, trial);
  }
  bool found = false;
  for (int i = 0; i < n && !found; ++i)
  {
    const Vec3 world = candidates[i].second + this->Origin;
    if (this->Mesh.CheckTrial(world, check, trial, this->LinkTable()) == CollapseStatus::Ok)
    {
      p = world;
      cost = candidates[i].first;
      error = this->AttributeComponents > 0 ? this->GeometricError(set, count, candidates[i].second)
                                            : (weight > 0 ? std::sqrt(cost / weight) : 0.0);
      found = true;
    }
  }
  if (borrowed)
  {
    EditableMesh::ReturnGathered(trial, scratch);
  }
  return found;
}

double TriangleCollapser::PopCost(
  Index t, Vec3& local, double& error, int& operation, std::optional<double>* triangleCost) const
{
  return this->PopCostOf<true>(t, local, error, operation, triangleCost);
}

double TriangleCollapser::PopOperation(
  Index t, Vec3& local, double& error, int& operation, std::optional<double>* triangleCost) const
{
  return this->PopCostOf<false>(t, local, error, operation, triangleCost);
}

template <bool PlaceWinningEdge>
inline __attribute__((always_inline)) double TriangleCollapser::PopCostOf(
  Index t, Vec3& local, double& error, int& operation, std::optional<double>* triangleCost) const
{
  if (!this->CacheEdges)
  {
    return this->Cost(t, local, error, operation);
  }
  const Index* tri = this->Mesh.Triangle(t);
  const unsigned excluded = this->State[t].Excluded;
  const float* cache = this->State[t].EdgeCost;
  operation = -1;
  double best = std::numeric_limits<double>::infinity();
  if (!(excluded & 1u) && !this->TriangleCannotWin(cache, excluded))
  {
    Quadric q = this->Vertex[tri[0]].Q;
    q += this->Vertex[tri[1]].Q;
    q += this->Vertex[tri[2]].Q;
    best = this->Place(tri, 3, q, local);
    if (triangleCost)
    {
      *triangleCost = best;
    }
    operation = std::isfinite(best) ? 0 : -1;
    const double w = this->Vertex[tri[0]].W + this->Vertex[tri[1]].W + this->Vertex[tri[2]].W;
    error = w > 0 ? std::sqrt(best / w) : 0.0;
  }
  int edge = -1;
  for (int k = 0; k < 3; ++k)
  {
    if (!(excluded & (2u << k)) && double(cache[k]) / this->CostScale < best)
    {
      best = double(cache[k]) / this->CostScale;
      edge = k;
    }
  }
  if (edge >= 0)
  {
    operation = edge + 1;
    best = PlaceWinningEdge ? this->PlaceEdge(tri, edge, local, error) : best;
  }
  return best;
}

// The winning edge's placement (as PopCost's cost: biased) and its error.
inline __attribute__((always_inline)) double TriangleCollapser::PlaceEdge(
  const Index* tri, int edge, Vec3& local, double& error) const
{
  const Index e[2] = { tri[edge], tri[(edge + 1) % 3] };
  const double bias = this->Options.EdgeCollapseBias;
  const double cost = this->Place(e, 2, this->Vertex[e[0]].Q + this->Vertex[e[1]].Q, local) * bias;
  const double w = this->Vertex[e[0]].W + this->Vertex[e[1]].W;
  error = w > 0 && bias > 0 ? std::sqrt(cost / bias / w) : 0.0;
  return cost;
}

bool TriangleCollapser::KeyFromCache(Index t, const std::optional<double>& triangle, float& key) const
{
  if (!this->EdgeCachesCurrent)
  {
    return false;
  }
  // Cost's key is the float of its cheapest allowed operation's cost; the cast is monotone, so it
  // is the smallest of the operations' float keys, which the cache holds for the edges (the same
  // expression). Each operation's placement reads only its vertices' quadrics and positions.
  const TriangleState& state = this->State[t];
  float best = std::numeric_limits<float>::infinity();
  if (!(state.Excluded & 1u) && !this->TriangleCannotWin(state.EdgeCost, state.Excluded))
  {
    double cost = triangle ? *triangle : 0.0;
    if (!triangle)
    {
      // (PopCost's sum and placement)
      const Index* tri = this->Mesh.Triangle(t);
      Quadric q = this->Vertex[tri[0]].Q;
      q += this->Vertex[tri[1]].Q;
      q += this->Vertex[tri[2]].Q;
      Vec3 p;
      cost = this->Place(tri, 3, q, p);
    }
    best = static_cast<float>(cost * this->CostScale);
  }
  for (int k = 0; k < 3; ++k)
  {
    if (!(state.Excluded & (2u << k)) && state.EdgeCost[k] < best)
    {
      best = state.EdgeCost[k];
    }
  }
  key = best;
  return best < std::numeric_limits<float>::infinity();
}

bool TriangleCollapser::TriangleCannotWin(const float* cache, unsigned excluded) const
{
  if (!this->Options.TriangleCostBound)
  {
    return false;
  }
  // The cache holds bias x scale x each edge's cost. The triangle's quadric is the sum of its
  // corners', i.e. half the sum of its edges' quadrics, so (minima of quadrics, no rounding) its
  // cost is at least half the sum of the edge costs and at least the largest of them.
  double largest = 0.0, sum = 0.0, cheapest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
  {
    largest = std::max(largest, double(cache[k]));
    sum += double(cache[k]);
    if (!(excluded & (2u << k)))
    {
      cheapest = std::min(cheapest, double(cache[k]));
    }
  }
  return std::max(largest, 0.5 * sum) >= this->Options.EdgeCollapseBias * cheapest;
}

double TriangleCollapser::TriangleOperationCost(const Index* tri, Vec3& local) const
{
  Quadric q = this->Vertex[tri[0]].Q;
  q += this->Vertex[tri[1]].Q;
  q += this->Vertex[tri[2]].Q;
  return this->Place(tri, 3, q, local);
}

void TriangleCollapser::UpdateAround(Index kept)
{
  if (!this->CacheEdges)
  {
    const long long perTriangle = this->Options.EdgeCollapses ? 4 : 1; // Cost places every operation
    this->Mesh.ForEachTriangle(kept, [&](Index s) {
      this->Update(s);
      ++this->KeyUpdates;
      this->FanPlacements += perTriangle;
    });
    return;
  }
  this->AroundKeys(kept, this->AroundScratch, this->AroundKeyScratch, this->Spokes);
  const size_t triangles = this->Options.TriangleCostBound ? size_t(this->Spokes.TrianglePlacements) : this->AroundScratch.size();
  this->FanPlacements += static_cast<long long>(triangles + this->Spokes.Vertex.size());
  this->RequeueAround(this->AroundScratch, this->AroundKeyScratch);
}

// The fan as the mesh holds it, after the collapse (AroundKeys).
struct TriangleCollapser::MeshFan
{
  const TriangleCollapser& Self;
  const Quadric& Q(Index v) const { return this->Self.Vertex[v].Q; }
  double Place(const Index* set, int count, const Quadric& q, Vec3& p) const
  {
    return this->Self.Place(set, count, q, p);
  }
};

// The fan before the collapse (KeysBeforeCollapse): the set's member replaced in the corners by
// the kept vertex, with the set's summed quadric and the new position (no pinned vertices).
struct TriangleCollapser::PendingFan
{
  const TriangleCollapser& Self;
  Index Kept;
  const Quadric& KeptQuadric;
  Vec3 KeptLocal;
  const Quadric& Q(Index v) const { return v == this->Kept ? this->KeptQuadric : this->Self.Vertex[v].Q; }
  double Place(const Index* set, int count, const Quadric& q, Vec3& p) const
  {
    Vec3 local[3];
    for (int i = 0; i < count; ++i)
    {
      local[i] = set[i] == this->Kept ? this->KeptLocal : this->Self.Local(set[i]);
    }
    return PlaceAmong(local[0], local[1], count == 3 ? local[2] : local[1], count, q, p);
  }
};

// A fan triangle's own collapse: its corners' quadrics summed and placed.
template <class Fan>
inline __attribute__((always_inline)) double PlaceFanTriangle(const Fan& fan, const Index* tri, Vec3& p)
{
  Quadric q = fan.Q(tri[0]);
  q += fan.Q(tri[1]);
  q += fan.Q(tri[2]);
  return fan.Place(tri, 3, q, p);
}

// Inlined into AroundKeys' loop, whose code it was (an outlined call per triangle cost the loop
// 41-63 M instructions on mc250k, session 39; inlined, 11 M, from the spokes' search, which is
// inlined now; an outlined search cost 29 M).
template <bool Bound, class Fan>
inline __attribute__((always_inline)) float TriangleCollapser::FanTriangleKey(
  const Fan& fan, const Index* tri, Index kept, const Quadric& qk, float* cache, SpokeScratch& spokes) const
{
  Vec3 p;
  // Without the bound the triangle is placed first, as before session 40; with it, after its
  // edges and only when it can win.
  double best = Bound ? std::numeric_limits<double>::infinity() : PlaceFanTriangle(fan, tri, p);
  const double bias = this->Options.EdgeCollapseBias;
  // The corner after k from a table: (k + 1) % 3 took a multiply and four more instructions per
  // edge, 2.35 million edges on mc250k (session 44).
  constexpr int next[3] = { 1, 2, 0 };
  for (int k = 0; k < 3; ++k)
  {
    const Index u = tri[k], v = tri[next[k]];
    if (u == kept || v == kept)
    {
      // A spoke (kept, x): placed once per fan, at its first triangle in the fan's order.
      const Index x = u == kept ? v : u;
      const auto found = std::find(spokes.Vertex.begin(), spokes.Vertex.end(), x);
      if (found != spokes.Vertex.end())
      {
        cache[k] = spokes.Cost[found - spokes.Vertex.begin()];
      }
      else
      {
        const Index edge[2] = { u, v };
        cache[k] = static_cast<float>(fan.Place(edge, 2, qk + fan.Q(x), p) * bias * this->CostScale);
        spokes.Vertex.push_back(x);
        spokes.Cost.push_back(cache[k]);
      }
    }
    best = std::min(best, double(cache[k]) / this->CostScale);
  }
  if (Bound && !this->TriangleCannotWin(cache, 0))
  {
    ++spokes.TrianglePlacements;
    best = std::min(PlaceFanTriangle(fan, tri, p), best);
  }
  return static_cast<float>(best * this->CostScale);
}

void TriangleCollapser::AroundKeys(
  Index kept, std::vector<Index>& around, std::vector<float>& keys, SpokeScratch& spokes) const
{
  around.clear();
  keys.clear();
  this->Mesh.ForEachTriangle(kept, [&](Index t) { around.push_back(t); });
  if (!this->CacheEdges)
  {
    for (Index t : around)
    {
      Vec3 p;
      double error;
      int operation;
      this->State[t].Excluded = 0; // as Update: every operation may be valid again
      keys.push_back(static_cast<float>(this->Cost(t, p, error, operation) * this->CostScale));
      this->State[t].Rejected = 0;
    }
    return;
  }
  spokes.Vertex.clear();
  spokes.Cost.clear();
  spokes.TrianglePlacements = 0;
  // Prefetch what the updates read (corners, vertex quadrics, cached edge costs, queue slots):
  // the loop is bound by memory latency, and independent prefetches overlap where the loop's
  // dependent loads would follow one another.
  for (Index t : around)
  {
    __builtin_prefetch(this->Mesh.Triangle(t));
    __builtin_prefetch(this->State[t].EdgeCost);
    this->Heap.Prefetch(t);
  }
  for (Index t : around)
  {
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const char* q = reinterpret_cast<const char*>(&this->Vertex[tri[k]]);
      __builtin_prefetch(q);
      __builtin_prefetch(q + 64);
    }
    this->Heap.PrefetchBucket(t);
  }
  if (this->Options.TriangleCostBound)
  {
    this->FanKeys<true>(kept, around, keys, spokes);
  }
  else
  {
    this->FanKeys<false>(kept, around, keys, spokes);
  }
}

// AroundKeys' keys, one instantiation per TriangleCostBound: both inlined into AroundKeys, the
// default loop took 4-7 % more instructions in AroundKeys on mc250k (session 40).
template <bool Bound>
__attribute__((noinline)) void TriangleCollapser::FanKeys(
  Index kept, const std::vector<Index>& around, std::vector<float>& keys, SpokeScratch& spokes) const
{
  const MeshFan fan{ *this };
  const Quadric& qk = this->Vertex[kept].Q;
  for (Index t : around)
  {
    this->State[t].Excluded = 0;
    this->State[t].Rejected = 0;
    const float key = this->FanTriangleKey<Bound>(fan, this->Mesh.Triangle(t), kept, qk, this->State[t].EdgeCost, spokes);
    keys.push_back(key);
  }
}

void TriangleCollapser::RequeueAround(const std::vector<Index>& around, const std::vector<float>& keys)
{
  this->KeyUpdates += static_cast<long long>(around.size());
  // The queue updates come after all the costs, in the same order: each removal swaps in the
  // last entry of its bucket and rewrites that entry's slot (dependent misses at random places),
  // so the chain is prefetched one level at a time for all the triangles before any update.
  for (size_t i = 0; i < around.size(); ++i)
  {
    this->Heap.PrefetchEntries(around[i]);
    this->Heap.PrefetchBucketOf(keys[i]);
  }
  for (size_t i = 0; i < around.size(); ++i)
  {
    this->Heap.PrefetchMoved(around[i]);
    this->Heap.PrefetchEnd(keys[i]);
  }
  for (size_t i = 0; i < around.size(); ++i)
  {
    this->Heap.Set(around[i], keys[i]);
  }
}

bool TriangleCollapser::KeysBeforeCollapse(
  const Candidate& c, const std::vector<Index>& gathered, KeysAhead& out, SpokeScratch& spokes) const
{
  // AroundKeys' arithmetic on the same operands: the surviving triangles' corners with the set's
  // member replaced in place by the kept vertex, whose quadric is SetQuadric's sum (as
  // MergeVertexState will store it) and whose point is the new position (Local's difference),
  // through the same FanTriangleKey. Only the edge cache's path, without pinned vertices.
  out.Ready = false;
  // (Not with TriangleCostBound: the loop then keys the fan after the collapse. A third
  // instantiation of FanTriangleKey left Quadric::operator+= out of line in the default loop.)
  if (!this->CacheEdges || this->Options.ExactUnion || !this->Pinned.empty() || this->Options.TriangleCostBound)
  {
    return false;
  }
  out.Around.clear();
  out.Keys.clear();
  out.EdgeCosts.clear();
  spokes.Vertex.clear();
  spokes.Cost.clear();
  spokes.TrianglePlacements = 0;
  const Index kept = *std::min_element(c.Set, c.Set + c.Count);
  double weight = 0;
  const Quadric qk = this->SetQuadric(c.Set, c.Count, weight);
  const PendingFan fan{ *this, kept, qk, c.Position - this->Origin };
  for (Index t : gathered)
  {
    Index tri[3];
    int members = 0;
    for (int k = 0; k < 3; ++k)
    {
      tri[k] = this->Mesh.Triangle(t)[k];
      const bool member = std::find(c.Set, c.Set + c.Count, tri[k]) != c.Set + c.Count;
      members += member ? 1 : 0;
      tri[k] = member ? kept : tri[k];
    }
    if (members != 1)
    {
      if (members == 0)
      {
        return false; // not a triangle of the set (not expected from a gathering)
      }
      continue; // removed by the collapse
    }
    float cache[3] = { this->State[t].EdgeCost[0], this->State[t].EdgeCost[1], this->State[t].EdgeCost[2] };
    const float key = this->FanTriangleKey<false>(fan, tri, kept, qk, cache, spokes);
    out.Around.push_back(t);
    out.Keys.push_back(key);
    out.EdgeCosts.insert(out.EdgeCosts.end(), cache, cache + 3);
  }
  out.Ready = true;
  return true;
}

bool TriangleCollapser::RequeueKeysAhead(Index kept, const KeysAhead& ahead)
{
  // A compaction during the collapse may reorder the new vertex's list, whose order is that of
  // the queue's writes (part of the output): take the keys only for the very same list.
  size_t i = 0;
  bool same = true;
  this->Mesh.ForEachTriangle(kept, [&](Index t) {
    same = same && i < ahead.Around.size() && ahead.Around[i] == t;
    ++i;
  });
  if (!same || i != ahead.Around.size())
  {
    return false;
  }
  for (size_t j = 0; j < ahead.Around.size(); ++j)
  {
    TriangleState& state = this->State[ahead.Around[j]];
    state.Excluded = 0;
    state.Rejected = 0;
    std::copy(&ahead.EdgeCosts[3 * j], &ahead.EdgeCosts[3 * j] + 3, state.EdgeCost);
  }
  this->RequeueAround(ahead.Around, ahead.Keys);
  ++this->KeysAheadTaken;
  return true;
}

void TriangleCollapser::Update(Index t)
{
  ++this->Updates;
  this->State[t].Excluded = 0; // its neighbourhood changed: every operation may be valid again
  float key = 0.0f;
  if (!this->KeyFromCache(t, std::nullopt, key))
  {
    Vec3 p;
    double error;
    int operation;
    key = static_cast<float>(this->Cost(t, p, error, operation) * this->CostScale);
  }
  this->Heap.Set(t, key);
  this->State[t].Rejected = 0;
}

double NormalLimitDot(double degrees)
{
  return std::cos(Radians(std::min(90.0, std::max(0.0, degrees))));
}

void TriangleCollapser::TraceWorkingParts(const char* when) const
{
  // Every array of WorkingBytes, per input vertex (the peak's parts: at the loop's start the queue
  // is largest, at its end the references and the history may have grown).
  if (vtkLogger::GetCurrentVerbosityCutoff() < vtkLogger::VERBOSITY_TRACE)
  {
    return;
  }
  const double perVertex = 1.0 / std::max<double>(1.0, double(this->Mesh.NumberOfPoints()));
  const size_t flags = this->Boundary.capacity() + this->Locked.capacity() + this->Pinned.capacity() +
    this->Pending.capacity() + this->Merged.capacity();
  const size_t ids = this->VertexInputPacked.Packed.MemoryBytes() + this->TriangleInputPacked.Packed.MemoryBytes() +
    (this->VertexInput.capacity() + this->TriangleInput.capacity()) * sizeof(Index);
  const size_t attributes = this->AttributeQuadric.capacity() * sizeof(Quadric) +
    this->AttributeGradient.capacity() * sizeof(double);
  vtkLogF(TRACE,
    "triangle collapse: working bytes per input vertex %s: %.1f (editable mesh %.1f, quadrics %.1f, triangle state "
    "%.1f, queue %.1f, input ids %.1f, input kept %.1f, vertex flags %.1f, parents %.1f, attribute terms %.1f)",
    when, perVertex * double(this->WorkingBytes()), perVertex * double(this->Mesh.MemoryBytes()),
    perVertex * double(this->Vertex.capacity() * sizeof(WeightedQuadric)),
    perVertex * double(this->State.capacity() * sizeof(TriangleState)), perVertex * double(this->Heap.MemoryBytes()),
    perVertex * double(ids), perVertex * double(this->Original.MemoryBytes()), perVertex * double(flags),
    perVertex * double(this->Link.capacity() * sizeof(Index)), perVertex * double(attributes));
}

size_t TriangleCollapser::WorkingBytes() const
{
  const size_t perVertex = this->VertexInput.capacity() * sizeof(Index) +
    this->Boundary.capacity() + this->Locked.capacity() + this->Pinned.capacity() + this->Pending.capacity() +
    this->Merged.capacity();
  return this->Mesh.MemoryBytes() + this->Original.MemoryBytes() + this->VertexInputPacked.Packed.MemoryBytes() +
    this->TriangleInputPacked.Packed.MemoryBytes() + this->Heap.MemoryBytes() +
    this->Vertex.capacity() * sizeof(WeightedQuadric) + this->State.capacity() * sizeof(TriangleState) +
    this->TriangleInput.capacity() * sizeof(Index) + perVertex + this->Link.capacity() * sizeof(Index) +
    this->AttributeQuadric.capacity() * sizeof(Quadric) +
    this->AttributeGradient.capacity() * sizeof(double);
}

void TriangleCollapser::Prepare(TriangleMesh& input, bool refine)
{
  const auto bounds = input.Bounds();
  this->Origin = { 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5]) };
  const double diagonal = input.BoundingBoxDiagonal();
  // Costs are area * distance^2 ~ length^4: normalise by the diagonal so float keys keep range.
  this->CostScale = diagonal > 0 ? 1.0 / (diagonal * diagonal * diagonal * diagonal) : 1.0;
  this->Diagonal = diagonal;
  std::vector<unsigned char>* const callers = this->Options.NonManifoldVertices;
  const std::vector<unsigned char>* given = callers;
  if (given && given->size() != size_t(input.NumberOfPoints()))
  {
    given = nullptr; // not this mesh's flags: classify it here
  }
  this->Reorder(input);
  this->Stages.Lap("reorder");
  if (!this->Options.AllowTopologyChange)
  {
    if (given)
    {
      // Vertex i of the reordered mesh is input vertex VertexInput[i].
      this->Locked.resize(size_t(input.NumberOfPoints()));
      for (Index v = 0; v < input.NumberOfPoints(); ++v)
      {
        this->Locked[v] = (*given)[this->VertexInput[v]];
      }
    }
    else
    {
      this->Locked = NonManifoldVertexFlags(input);
    }
  }
  if (callers)
  {
    std::vector<unsigned char>().swap(*callers); // read: not held through the collapses
  }
  this->LockCallersVertices(input.NumberOfPoints());
  this->TakeBorderFlags(input.NumberOfPoints());
  if (std::none_of(this->Locked.begin(), this->Locked.end(), [](unsigned char locked) { return locked != 0; }))
  {
    // No vertex locked (a manifold input, no caller's locks): the checks need no flags, and the
    // collapses do not hold a byte per vertex for them.
    std::vector<unsigned char>().swap(this->Locked);
  }
  this->Stages.Lap("locked vertices");
  this->Mesh.SetReferenceRoomFactor(ReferenceRoomFactor);
  this->LinkTables = !this->Options.AllowTopologyChange;
  this->Mesh.SetVertexLinkMarks(!this->LinkTables);
  this->Mesh.SetParallelRebuild(this->Options.ParallelStages);
  this->Mesh.Reset(input);
  if (refine && !this->Options.ReloadInput)
  {
    // The refinement measures against the original surface: keep it (who merged into whom is in
    // the quadrics, ParentOf). With ReloadInput it is read again after the collapses instead.
    this->Original.Take(input);
    this->Original.Pack();
  }
  // The editable mesh holds its own copy: release the input's arrays (peak memory).
  std::vector<double>().swap(input.Points);
  std::vector<Index>().swap(input.Triangles);
  ReturnFreedMemory();
  this->Stages.Lap("editable mesh");
}

void TriangleCollapser::TakeBorderFlags(Index numberOfPoints)
{
  std::vector<unsigned char>* given = this->Options.BorderVertices;
  this->BorderFlagsGiven = given && given->size() == size_t(numberOfPoints);
  if (this->BorderFlagsGiven)
  {
    // Vertex i of the reordered mesh is input vertex VertexInput[i].
    this->Boundary.resize(size_t(numberOfPoints));
    for (Index v = 0; v < numberOfPoints; ++v)
    {
      this->Boundary[v] = (*given)[this->VertexInput[v]] ? 1 : 0;
    }
  }
  if (given)
  {
    std::vector<unsigned char>().swap(*given); // read: not held through the collapses
  }
}

void TriangleCollapser::LockCallersVertices(Index numberOfPoints)
{
  const std::vector<unsigned char>* pinned = this->Options.PinnedVertices;
  if (pinned && pinned->size() == size_t(numberOfPoints) &&
    std::find(pinned->begin(), pinned->end(), 1) != pinned->end())
  {
    this->Pinned.resize(size_t(numberOfPoints));
    for (Index v = 0; v < numberOfPoints; ++v)
    {
      this->Pinned[v] = (*pinned)[this->VertexInput[v]];
    }
  }
  const std::vector<unsigned char>* given = this->Options.LockedVertices;
  if (!given || given->size() != size_t(numberOfPoints))
  {
    return;
  }
  this->Locked.resize(size_t(numberOfPoints), 0);
  for (Index v = 0; v < numberOfPoints; ++v)
  {
    // Vertex v of the reordered mesh is input vertex VertexInput[v].
    this->Locked[v] |= (*given)[this->VertexInput[v]];
  }
}

void TriangleCollapser::PackInputIds()
{
  if (this->Options.RecordHistory)
  {
    return; // every record stores input ids
  }
  this->TriangleInputPacked.Pack(this->TriangleInput);
  if (!this->Attributes)
  {
    this->VertexInputPacked.Pack(this->VertexInput); // (the point data merge by input id)
  }
  ReturnFreedMemory();
}

void TriangleCollapser::UnpackInputIds()
{
  this->TriangleInputPacked.Unpack(this->TriangleInput);
  this->VertexInputPacked.Unpack(this->VertexInput);
}

void TriangleCollapser::InitializeQueue()
{
  const Index nt = this->Mesh.NumberOfTriangles();
  AssignOnHugePages(this->State, size_t(nt), TriangleState());
  // The edge cache sums vertex quadrics; the attribute metric's set quadrics are not sums.
  this->CacheEdges = this->Options.EdgeCollapses && !this->Options.ExactUnion && this->AttributeComponents == 0;
  this->Pending.assign(size_t(this->Mesh.NumberOfPoints()), 0);
  // Every triangle's cost depends only on its own vertices and writes only its own cache
  // entries: computed in parallel (vtkSMPTools), the same result for any thread count. The
  // exact-union mode shares a scratch buffer: sequential.
  auto keys = MakeOnHugePages<float>(static_cast<size_t>(nt));
  if (nt > 0)
  {
    this->Heap.LendBucketIds(&this->State[0].QueueBucket, nt);
  }
  if (this->CacheEdges)
  {
    this->InitialKeys(keys);
    this->Heap.Build(keys.data(), nt);
    this->EdgeCachesCurrent = true;
    return;
  }
  auto costs = [&](vtkIdType begin, vtkIdType end) {
    for (Index t = static_cast<Index>(begin); t < static_cast<Index>(end); ++t)
    {
      Vec3 p;
      double error;
      int operation;
      keys[t] = static_cast<float>(this->Cost(t, p, error, operation) * this->CostScale);
    }
  };
  if (this->Options.ExactUnion)
  {
    costs(0, nt);
  }
  else
  {
    vtkSMPTools::For(0, nt, 4096, costs);
  }
  this->Heap.Build(keys.data(), nt);
}

void TriangleCollapser::StartLoop(CollapseLoop& loop) const
{
  loop.Target = std::max<Index>(this->Options.TargetTriangles, 0);
  loop.Check.AllowTopologyChange = this->Options.AllowTopologyChange;
  loop.Check.BoundaryVertices = this->Options.AllowTopologyChange ? nullptr : this->Boundary.data();
  loop.Check.LockedVertices = this->Locked.empty() ? nullptr : this->Locked.data();
  loop.Deviation = std::min(90.0, std::max(0.0, this->Options.MaximumNormalDeviation));
  loop.Check.MinimumNormalDot = NormalLimitDot(loop.Deviation);
  loop.StartTriangles = this->Mesh.NumberOfLiveTriangles();
  loop.ToRemove = std::max<Index>(1, loop.StartTriangles - loop.Target);
  loop.ProgressStep = std::max<Index>(1, loop.ToRemove / 100);
  loop.NextProgress = loop.ProgressStep;
  // A bound on the work of the loop, whatever the costs' ties: each pop either collapses, excludes
  // one of a triangle's four operations until its neighbourhood changes, or defers a placement
  // once. Measured at 10 %: 0.49 pops per input triangle on two MRI isosurfaces (2.1M and 1.8M
  // triangles), 0.70-0.75 on fandisk at 10 % and 1 %; the bound is 100.
  loop.MaximumPops = MaximumPopsPerTriangle * static_cast<long long>(loop.StartTriangles) + 1024;
  loop.TimePhases = vtkLogger::GetCurrentVerbosityCutoff() >= vtkLogger::VERBOSITY_TRACE;
  loop.Upcoming.Width = std::min(std::max(0, this->Options.UpcomingPrefetches), UpcomingPrefetch::MaximumWidth);
}

bool TriangleCollapser::RelaxNormalLimit(CollapseLoop& loop, TriangleCollapseResult& result)
{
  if (!this->LoosenLimits(loop, result))
  {
    return false;
  }
  for (Index s = 0; s < this->Mesh.NumberOfTriangles(); ++s)
  {
    if (this->State[s].Rejected == 1 && this->Mesh.IsTriangleAlive(s))
    {
      this->Update(s);
    }
  }
  return true;
}

bool TriangleCollapser::LoosenLimits(CollapseLoop& loop, TriangleCollapseResult& result)
{
  // When every remaining collapse fails the normal test, the limit is relaxed step by step (up
  // to 90 degrees, beyond which a triangle would turn over) so that the target is still reached;
  // the strict limit applies as long as it can. Last, the pinned vertices are released (the
  // target comes before the seams, as before the topology only).
  const bool canRelease = !this->Pinned.empty() && loop.Deviation >= 90.0;
  if (this->Mesh.NumberOfLiveTriangles() <= loop.Target || (loop.Deviation >= 90.0 && !canRelease) ||
    result.Aborted)
  {
    return false;
  }
  if (canRelease)
  {
    std::vector<unsigned char>().swap(this->Pinned);
    result.PinnedVerticesReleased = true;
    this->EdgeCachesCurrent = false;
  }
  loop.Deviation = std::min(90.0, loop.Deviation + 20.0);
  loop.Check.MinimumNormalDot = NormalLimitDot(loop.Deviation);
  return true;
}

void TriangleCollapser::Reject(const Candidate& c, TriangleCollapseResult& result)
{
  ++result.RejectedCollapses;
  // Requeue the triangle with its next best operation; when none is left it waits for a change
  // of its neighbourhood.
  const Index t = c.Triangle;
  this->State[t].Excluded |= static_cast<unsigned char>(1u << c.Operation);
  float key = 0.0f;
  if (this->KeyFromCache(t, c.TriangleCost, key))
  {
    this->Heap.Set(t, key);
    return;
  }
  Vec3 next;
  double nextError;
  int nextOperation;
  const double nextCost = this->Cost(t, next, nextError, nextOperation);
  if (nextOperation >= 0)
  {
    this->Heap.Set(t, static_cast<float>(nextCost * this->CostScale));
  }
  else
  {
    this->State[t].Rejected = 1;
    this->MarkPending(this->Mesh.Triangle(t));
  }
}

void TriangleCollapser::MergeAttributes(const Candidate& c, Index kept)
{
  // Point data: barycentric weights of the new vertex projected onto the triangle (edge).
  double w[3] = { 1.0 / 3, 1.0 / 3, 1.0 / 3 };
  const Vec3 a = this->Local(c.Set[0]), b = this->Local(c.Set[1]);
  const Vec3& local = c.Local;
  if (c.Count == 3)
  {
    const Vec3 d = this->Local(c.Set[2]);
    const Vec3 n = Cross(b - a, d - a);
    const double nn = Dot(n, n);
    if (nn > 0)
    {
      w[0] = std::max(0.0, Dot(Cross(d - b, local - b), n) / nn);
      w[1] = std::max(0.0, Dot(Cross(a - d, local - d), n) / nn);
      w[2] = std::max(0.0, Dot(Cross(b - a, local - a), n) / nn);
    }
  }
  else
  {
    const double ll = Dot(b - a, b - a);
    const double s01 = ll > 0 ? std::min(1.0, std::max(0.0, Dot(local - a, b - a) / ll)) : 0.5;
    w[0] = 1.0 - s01;
    w[1] = s01;
  }
  Index rows[3];
  for (int i = 0; i < c.Count; ++i)
  {
    rows[i] = this->VertexInput[c.Set[i]];
    if (this->IsPinned(c.Set[i]))
    {
      // The pinned vertex keeps its own attributes (a seam keeps its texture coordinates).
      w[0] = w[1] = w[2] = 0.0;
      w[i] = 1.0;
      rows[0] = rows[i];
      this->Attributes->Merge(this->VertexInput[kept], rows, w, 1);
      return;
    }
  }
  this->Attributes->Merge(this->VertexInput[kept], rows, w, c.Count);
}

// The attribute metric's sums of the new vertex: those of the set (as the vertex quadrics).
void TriangleCollapser::MergeAttributeTerms(const Candidate& c, Index kept)
{
  const size_t stride = 4 * size_t(this->AttributeComponents);
  this->Merged[kept] = 1;
  for (int i = 0; i < c.Count; ++i)
  {
    const Index v = c.Set[i];
    if (v == kept)
    {
      continue;
    }
    this->AttributeQuadric[kept] += this->AttributeQuadric[v];
    const double* from = this->AttributeGradient.data() + size_t(v) * stride;
    double* to = this->AttributeGradient.data() + size_t(kept) * stride;
    for (size_t k = 0; k < stride; ++k)
    {
      to[k] += from[k];
    }
  }
}

void TriangleCollapser::MergeVertexState(const Candidate& c, Index kept)
{
  unsigned char boundary = 0;
  for (int i = 0; i < c.Count; ++i)
  {
    boundary |= this->Boundary[c.Set[i]];
  }
  this->Boundary[kept] = boundary;
  if (!this->Pinned.empty())
  {
    unsigned char pinned = 0;
    for (int i = 0; i < c.Count; ++i)
    {
      pinned |= this->Pinned[c.Set[i]];
    }
    this->Pinned[kept] = pinned;
  }
  if (!this->Options.ExactUnion)
  {
    double weight = 0;
    this->Vertex[kept].Q = this->SetQuadric(c.Set, c.Count, weight);
    this->Vertex[kept].W = weight;
    if (this->AttributeComponents > 0)
    {
      this->MergeAttributeTerms(c, kept);
    }
    for (int i = 0; i < c.Count; ++i)
    {
      if (c.Set[i] != kept)
      {
        this->SetParent(c.Set[i], kept); // (their quadrics were read above)
      }
    }
    return;
  }
  auto& s = this->LogicalSet[kept];
  for (int i = 0; i < c.Count; ++i)
  {
    const Index v = c.Set[i];
    if (v != kept)
    {
      auto& m = this->MergeScratch;
      m.clear();
      std::set_union(s.begin(), s.end(), this->LogicalSet[v].begin(), this->LogicalSet[v].end(), std::back_inserter(m));
      s.swap(m);
      std::vector<Index>().swap(this->LogicalSet[v]);
    }
  }
  this->SumLogicalSet(kept);
}

Index TriangleCollapser::Perform(const Candidate& c, const std::vector<Index>* gathered, CollapseLoop& loop,
  TriangleCollapseResult& result, const KeysAhead* keys)
{
  const Index kept = *std::min_element(c.Set, c.Set + c.Count);
  if (this->Attributes)
  {
    this->MergeAttributes(c, kept);
  }
  if (gathered)
  {
    this->Mesh.Collapse(c.Set, c.Count, kept, c.Position, *gathered, &loop.Record);
  }
  else
  {
    this->Mesh.Collapse(c.Set, c.Count, kept, c.Position, &loop.Record);
  }
  this->MergeVertexState(c, kept);
  result.MaximumError = std::max(result.MaximumError, c.Error);
  ++result.Collapses;
  result.EdgeCollapses += c.Count == 2 ? 1 : 0;
  for (Index r : loop.Record.RemovedTriangles)
  {
    this->Heap.Remove(r);
  }
  // Error propagation: the triangles around v0 get the quadric of their new logical sets.
  if (!(keys && keys->Ready && this->RequeueKeysAhead(kept, *keys)))
  {
    this->UpdateAround(kept);
  }
  return kept;
}

void TriangleCollapser::RetryPendingAround(Index kept, CollapseLoop& loop)
{
  // Collapses rejected for validity may have become valid: retry those in the 2-ring.
  // (Skipped while no vertex is pending, the common case.)
  loop.Neighbors.clear();
  const auto retry = [&](Index w) {
    if (this->Pending[w])
    {
      this->Pending[w] = 0;
      --this->PendingCount;
      this->Mesh.ForEachTriangle(w, [&](Index s) {
        if (this->State[s].Rejected == 1)
        {
          if (this->WorkerAhead)
          {
            this->WorkerAhead->End(); // s may lie in a ring evaluated ahead (2-ring of kept)
          }
          this->Update(s);
        }
      });
    }
  };
  if (this->Options.RecordHistory)
  {
    this->Mesh.Neighbors(kept, loop.Neighbors); // (the record lists them)
    std::for_each(loop.Neighbors.begin(), loop.Neighbors.end(), retry);
    return;
  }
  // Without the records the fan's corners are walked as Neighbors walks them (triangle by
  // triangle, corner by corner): a neighbour's first corner is its place in Neighbors' list, and a
  // later one finds it no longer pending (Update marks nothing pending), so the retries are the
  // same, in the same order, without Neighbors' table of distinct vertices (81 M instructions on
  // noisy137, 2.4 % of its loop; session 44).
  if (this->PendingCount > 0)
  {
    this->Mesh.ForEachTriangle(kept, [&](Index t) {
      const Index* tri = this->Mesh.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        if (tri[k] != kept)
        {
          retry(tri[k]);
        }
      }
    });
  }
}

void TriangleCollapser::AppendHistory(
  const CollapseRecord& record, const CollapseLoop& loop, TriangleCollapseResult& result) const
{
  result.History.Append(record, this->Mesh, this->VertexInput.data(), this->TriangleInput.data(), &loop.Neighbors);
}

bool TriangleCollapser::ReportProgress(CollapseLoop& loop, TriangleCollapseResult& result) const
{
  const Index removed = loop.StartTriangles - this->Mesh.NumberOfLiveTriangles();
  if (removed >= loop.NextProgress)
  {
    loop.NextProgress = removed + loop.ProgressStep;
    if (this->Options.Progress && !this->Options.Progress(double(removed) / double(loop.ToRemove)))
    {
      result.Aborted = true;
      return false;
    }
  }
  return true;
}

void TriangleCollapser::SelectBatch(CollapseLoop& loop, CollapseBatch& batch)
{
  // The cheapest operations in cost order, up to a cost bound relative to the first and to a
  // quarter of the triangles still to remove (a collapse removes up to four), so that the batches
  // shrink to single operations near the target as the strict order would end.
  batch.Entries.clear();
  batch.Keys.clear();
  if (++batch.Number == 0)
  {
    std::fill(batch.Owner.begin(), batch.Owner.end(), ~std::uint64_t(0));
    batch.Number = 1;
  }
  const Index room = std::max<Index>(1, (this->Mesh.NumberOfLiveTriangles() - loop.Target) / 4);
  const size_t limit = std::min<size_t>(size_t(room), batch.Size);
  float bound = 0.0f;
  bool alone = false;
  while (batch.Entries.size() < limit && !this->Heap.Empty() && loop.Pops < loop.MaximumPops)
  {
    float key = 0.0f;
    const Index t = this->Heap.Pop(&key);
    ++loop.Pops;
    if (!batch.Entries.empty() && key > bound)
    {
      this->Heap.Set(t, key);
      break;
    }
    if (batch.Entries.empty())
    {
      bound = static_cast<float>(key * (1.0 + batch.CostTolerance));
      alone = batch.MaximumSize > 1 && this->StaysSmall(batch, limit, bound);
    }
    batch.Entries.emplace_back();
    batch.Entries.back().C.Triangle = t;
    batch.Keys.push_back(key);
    if (alone)
    {
      ++loop.LoneBatches;
      break;
    }
  }
  // While a look-ahead is live its evaluations have brought the next pops' neighbourhoods in.
  if (batch.MaximumSize == 1 && loop.Upcoming.Width > 0 && !(batch.Ahead && !batch.Ahead->Exhausted()))
  {
    this->PrefetchUpcoming(loop.Upcoming);
  }
}

bool TriangleCollapser::StaysSmall(const CollapseBatch& batch, size_t limit, float bound) const
{
  // The entries still queued within the bound, counted up to what a batch of MinimumSize needs
  // besides the first (already popped): a read of the lowest buckets, no pop.
  if (batch.MinimumSize <= 1)
  {
    return false;
  }
  if (limit < batch.MinimumSize)
  {
    return true;
  }
  const int needed = static_cast<int>(batch.MinimumSize - 1);
  return this->Heap.CountAtMost(bound, needed) < needed;
}

void TriangleCollapser::PrefetchUpcoming(UpcomingPrefetch& ahead) const
{
  // Stage 3: the reference blocks of the vertices whose records stage 2 asked for at the last pop.
  for (int i = 0; i < ahead.RecordedCount; ++i)
  {
    const Index* tri = this->Mesh.Triangle(ahead.Recorded[i]);
    for (int k = 0; k < 3; ++k)
    {
      this->Mesh.PrefetchBlock(tri[k]);
    }
  }
  // Stage 2: the vertices' quadrics, points and block bounds of the triangles of stage 1.
  for (int i = 0; i < ahead.CorneredCount; ++i)
  {
    const Index* tri = this->Mesh.Triangle(ahead.Cornered[i]);
    for (int k = 0; k < 3; ++k)
    {
      const char* q = reinterpret_cast<const char*>(&this->Vertex[tri[k]]);
      __builtin_prefetch(q);
      __builtin_prefetch(q + 64);
      this->Mesh.PrefetchVertex(tri[k]);
    }
    ahead.Recorded[i] = ahead.Cornered[i];
  }
  ahead.RecordedCount = ahead.CorneredCount;
  // Stage 1: the next entries of the lowest bucket, their corners, states and queue slots.
  ahead.CorneredCount = this->Heap.Upcoming(ahead.Cursor, ahead.Width, ahead.Cornered);
  ahead.Cursor += size_t(ahead.Width);
  for (int i = 0; i < ahead.CorneredCount; ++i)
  {
    const Index t = ahead.Cornered[i];
    __builtin_prefetch(this->Mesh.Triangle(t));
    __builtin_prefetch(&this->State[t]);
    this->Heap.Prefetch(t);
  }
}

// Which entries of a batch run: an entry claims the closed one-ring of its triangle's vertices
// (every vertex of their triangles) by an atomic minimum of its stamp per vertex, and runs when it
// holds all of them, i.e. when no earlier entry of the batch overlaps it. Operations with
// disjoint rings neither read nor write each other's triangles, vertices or queue entries, so
// they are checked concurrently and their order does not change the result. The minimum does
// not depend on the order of the writes: the same selection for any thread count.
std::uint64_t CollapseBatch::Stamp(size_t entry) const
{
  // Later batches get smaller stamps, so a stale stamp never wins.
  return (std::uint64_t(~this->Number) << 32) | std::uint64_t(entry);
}

// Entries that overlap an earlier one are popped again later: where the cheapest operations are
// neighbours (ties on flat regions, in Morton order) most of a large batch would be wasted pops
// (a 400x400 plane: 86 pops per input triangle at 1024, close to the loop's bound of 100).
// Shrinking the batch keeps at least a quarter of the popped entries running. It depends only
// on counts: the same sizes for any thread count.
void CollapseBatch::AdaptSize(size_t ran)
{
  const size_t selected = this->Entries.size();
  if (4 * ran < selected)
  {
    this->Size = std::max<size_t>(1, this->Size / 2);
  }
  else if (2 * ran > selected)
  {
    this->Size = std::min(this->MaximumSize, 2 * this->Size);
  }
}

// The vertices of the closed one-ring of the entry's operation (of its triangle when it has none):
// an edge collapse, most of the operations, claims only its edge's ring, so fewer entries overlap.
template <typename Functor>
void TriangleCollapser::ForEachRingVertex(const BatchEntry& entry, Functor&& f) const
{
  this->AllRingVertices(entry, [&](Index w) {
    f(w);
    return true;
  });
}

// Whether p holds for every vertex of that ring (in ForEachRingVertex's order); stops at the
// first that fails: an entry that lost its claims finds it out without walking the rest of its
// ring (session 41).
template <typename Predicate>
bool TriangleCollapser::AllRingVertices(const BatchEntry& entry, Predicate&& p) const
{
  const bool picked = entry.C.Operation >= 0;
  const Index* set = picked ? entry.C.Set : this->Mesh.Triangle(entry.C.Triangle);
  const int count = picked ? entry.C.Count : 3;
  for (int k = 0; k < count; ++k)
  {
    if (!this->Mesh.AllTriangles(set[k], [&](Index s) {
          const Index* around = this->Mesh.Triangle(s);
          return p(around[0]) && p(around[1]) && p(around[2]);
        }))
    {
      return false;
    }
  }
  return true;
}

struct TriangleCollapser::ClaimRingsFunctor : WindowedFunctor<TriangleCollapser::ClaimRingsFunctor>
{
  const TriangleCollapser& Self;
  CollapseBatch& Batch;
  // Claims made one entry after the other in selection order (one thread, or a batch of one
  // task): each entry then knows at once whether an earlier one holds a vertex of its ring, and
  // the holders' check does not walk the rings a second time (session 42).
  bool InOrder = false;
  void Window(vtkIdType begin, vtkIdType end) const
  {
    // The rings' reference blocks first, for the whole window (see PickFunctor).
    for (vtkIdType i = begin; i < end; ++i)
    {
      const BatchEntry& entry = this->Batch.Entries[size_t(i)];
      const bool picked = entry.C.Operation >= 0;
      const Index* set = picked ? entry.C.Set : this->Self.Mesh.Triangle(entry.C.Triangle);
      for (int k = 0, n = picked ? entry.C.Count : 3; k < n; ++k)
      {
        this->Self.Mesh.PrefetchBlock(set[k]);
      }
    }
    for (vtkIdType i = begin; i < end; ++i)
    {
      BatchEntry& entry = this->Batch.Entries[size_t(i)];
      const std::uint64_t stamp = this->Batch.Stamp(size_t(i));
      ++entry.Walks;
      if (this->InOrder)
      {
        entry.Runs = this->ClaimInOrder(entry, stamp, size_t(i) + 1 == this->Batch.Entries.size());
        continue;
      }
      this->Self.ForEachRingVertex(entry, [&](Index w) {
        std::uint64_t* owner = &this->Batch.Owner[w];
        std::uint64_t seen = __atomic_load_n(owner, __ATOMIC_RELAXED);
        while (stamp < seen && !__atomic_compare_exchange_n(owner, &seen, stamp, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
        {
        }
      });
    }
  }
  // In selection order a vertex already holds a smaller stamp of this batch only when an earlier
  // entry's ring has it (older batches' stamps are larger, later entries have not claimed yet):
  // the same Runs as the atomic minimum's. A loser still claims its whole ring, as the minimum
  // would; the last entry only reads (nothing after it), so it stops at its first lost vertex.
  bool ClaimInOrder(const BatchEntry& entry, std::uint64_t stamp, bool last) const
  {
    std::vector<std::uint64_t>& owner = this->Batch.Owner;
    if (last)
    {
      return this->Self.AllRingVertices(entry, [&](Index w) { return owner[w] >= stamp; });
    }
    bool holds = true;
    this->Self.ForEachRingVertex(entry, [&](Index w) {
      holds = holds && owner[w] >= stamp;
      owner[w] = std::min(owner[w], stamp);
    });
    return holds;
  }
};

bool TriangleCollapser::PickOperation(BatchEntry& entry, bool deferEdge) const
{
  // Read-only on the mesh and the queue (and on this triangle's own state): safe for the
  // entries of a batch in parallel.
  Candidate& c = entry.C;
  const Index t = c.Triangle;
  c.TriangleCost.reset();
  if (deferEdge)
  {
    this->PopOperation(t, c.Local, c.Error, c.Operation, &c.TriangleCost);
  }
  else
  {
    this->PopCost(t, c.Local, c.Error, c.Operation, &c.TriangleCost);
  }
  if (c.Operation < 0)
  {
    entry.Result = BatchEntry::Outcome::NoOperation;
    return false;
  }
  const Index* tri = this->Mesh.Triangle(t);
  c.Count = c.Operation == 0 ? 3 : 2;
  c.Set[0] = c.Operation == 0 ? tri[0] : tri[c.Operation - 1];
  c.Set[1] = c.Operation == 0 ? tri[1] : tri[c.Operation % 3];
  c.Set[2] = c.Operation == 0 ? tri[2] : InvalidIndex;
  // (Without the edge cache PopCost placed every operation.)
  entry.PlacementPending = deferEdge && c.Operation > 0 && this->CacheEdges;
  return entry.PlacementPending || this->FinishPick(entry);
}

// The rest of the pick, on the entry's own data: the winning edge's placement when it was
// deferred (it reads what the batch does not write before its collapses), the error bound, the
// position.
inline __attribute__((always_inline)) bool TriangleCollapser::FinishPick(BatchEntry& entry) const
{
  Candidate& c = entry.C;
  if (entry.PlacementPending)
  {
    this->PlaceEdge(this->Mesh.Triangle(c.Triangle), c.Operation - 1, c.Local, c.Error);
    entry.PlacementPending = false;
  }
  if (this->Options.MaximumError >= 0 && c.Error > this->Options.MaximumError)
  {
    entry.Result = BatchEntry::Outcome::OverError;
    return false;
  }
  c.Position = c.Local + this->Origin;
  int pinned = 0;
  const Index pin = this->PinnedIn(c.Set, c.Count, pinned);
  if (pin != InvalidIndex)
  {
    c.Position = this->Mesh.Point(pin); // exactly, not through the local coordinates
  }
  entry.Picked = true;
  return true;
}

// The entries of a larger batch pick their operations before they claim its ring.
struct TriangleCollapser::PickFunctor : WindowedFunctor<TriangleCollapser::PickFunctor>
{
  const TriangleCollapser& Self;
  CollapseBatch& Batch;
  bool DeferEdge = false; // the entries that hold their claims finish their picks (FinishPick)
  void Window(vtkIdType begin, vtkIdType end) const
  {
    // The entries lie at scattered places of the mesh: their triangles, states and vertex data
    // are prefetched in stages for a window of entries, so that the misses overlap.
    const EditableMesh& mesh = this->Self.Mesh;
    for (vtkIdType i = begin; i < end; ++i)
    {
      const Index t = this->Batch.Entries[size_t(i)].C.Triangle;
      __builtin_prefetch(mesh.Triangle(t));
      __builtin_prefetch(&this->Self.State[t]);
    }
    for (vtkIdType i = begin; i < end; ++i)
    {
      const Index* tri = mesh.Triangle(this->Batch.Entries[size_t(i)].C.Triangle);
      for (int k = 0; k < 3; ++k)
      {
        const char* q = reinterpret_cast<const char*>(&this->Self.Vertex[tri[k]]);
        __builtin_prefetch(q);
        __builtin_prefetch(q + 64);
        mesh.PrefetchVertex(tri[k]);
      }
    }
    for (vtkIdType i = begin; i < end; ++i)
    {
      this->Self.PickOperation(this->Batch.Entries[size_t(i)], this->DeferEdge);
    }
  }
};

// The pass schedule's window fill: which of the next ranked triangles wait for the next pass
// (Blocked). The test reads only what no collapse changes during a fill, so it runs in parallel
// rather than in the fill's walk in rank order, whose reads of random places of the mesh were the
// largest serial part of the pass schedule (session 25).
struct TriangleCollapser::WaitsFunctor : WindowedFunctor<TriangleCollapser::WaitsFunctor>
{
  const TriangleCollapser& Self;
  const PassState& Passes;
  CollapseBatch& Batch;
  void Window(vtkIdType begin, vtkIdType end) const
  {
    const EditableMesh& mesh = this->Self.Mesh;
    const std::vector<Index>& ranked = this->Batch.Ranked;
    for (vtkIdType i = begin; i < end; ++i)
    {
      __builtin_prefetch(mesh.Triangle(ranked[size_t(i)]));
    }
    for (vtkIdType i = begin; i < end; ++i)
    {
      const Index* tri = mesh.Triangle(ranked[size_t(i)]);
      for (int k = 0; k < 3; ++k)
      {
        __builtin_prefetch(&this->Passes.Change[tri[k]]);
      }
    }
    for (vtkIdType i = begin; i < end; ++i)
    {
      this->Batch.Waits[size_t(i)] = this->Self.Blocked(ranked[size_t(i)], this->Passes) ? 1 : 0;
    }
    this->Batch.WindowTests.Local() += end - begin;
  }
};

CollapseStatus TriangleCollapser::CheckSet(
  const Candidate& c, const CollapseOptions& check, std::vector<Index>& gathered) const
{
  EditableMesh::CheckScratch* table = this->LinkTable();
  if (!table)
  {
    return this->Mesh.CheckCollapse(c.Set, c.Count, c.Position, check, gathered);
  }
  table->Gathered.swap(gathered); // the set's triangles end in `gathered`, as without the table
  const CollapseStatus status = this->Mesh.CheckCollapse(c.Set, c.Count, c.Position, check, *table);
  table->Gathered.swap(gathered);
  return status;
}

bool TriangleCollapser::KnownToFail(
  const Candidate& c, const CollapseOptions& check, FailedTopologies& failed, CollapseStatus& status) const
{
  // EditableMesh::CheckCollapse's first test, which does not depend on the point, in its order.
  for (int i = 0; i < c.Count; ++i)
  {
    if (!this->Mesh.IsVertexAlive(c.Set[i]))
    {
      status = CollapseStatus::DeadVertex;
      return true;
    }
    if (check.LockedVertices && check.LockedVertices[c.Set[i]])
    {
      status = CollapseStatus::Locked;
      return true;
    }
  }
  return failed.Find(c, this->Mesh.NumberOfLiveTriangles(), status);
}

void TriangleCollapser::EvaluateEntry(BatchEntry& entry, const CollapseOptions& check, std::vector<Index>& scratch,
  bool picked, FailedTopologies* failed) const
{
  failed = check.GeometryFirst ? nullptr : failed; // (then a topological status depends on the point)
  // The strict order's lone pop (`failed` given) places a winning edge only once its set may pass
  // (session 44): a set with a locked vertex, or remembered in `failed`, is rejected whatever the
  // point, and its rejection reads only the triangle's own cost. Not with an error bound, which
  // FinishPick tests before the validity (OverError, not a rejection).
  const bool defer = failed && !picked && this->Options.MaximumError < 0;
  if (!(picked ? (entry.PlacementPending ? this->FinishPick(entry) : entry.Picked) : this->PickOperation(entry, defer)))
  {
    return; // no operation to check
  }
  Candidate& c = entry.C;
  if (failed && this->KnownToFail(c, check, *failed, entry.Status))
  {
    entry.PlacementPending = false; // never placed (not counted as PlacementsNotMade, a batch figure)
    entry.Result = BatchEntry::Outcome::Invalid;
    return;
  }
  if (entry.PlacementPending)
  {
    this->FinishPick(entry); // (PopCost's placement of the edge; no error bound to fail)
  }
  entry.Status = this->CheckSet(c, check, scratch);
  // (EditableMesh's check gathers the set's triangles unless a vertex is dead or locked)
  entry.Gathers += entry.Status == CollapseStatus::DeadVertex || entry.Status == CollapseStatus::Locked ? 0 : 1;
  if (failed && FailedTopologies::IsTopological(entry.Status))
  {
    failed->Add(c, entry.Status);
  }
  entry.Result = entry.Status == CollapseStatus::Ok ? BatchEntry::Outcome::Valid : BatchEntry::Outcome::Invalid;
  if (entry.Status == CollapseStatus::Flip || entry.Status == CollapseStatus::Degenerate ||
    entry.Status == CollapseStatus::BadShape)
  {
    // The optimum folds a triangle: try the paper's other placements (vertices, midpoints,
    // centroid) of the same set, cheapest first.
    const double maxError = this->Options.MaximumError;
    entry.Gathers += check.GeometryFirst ? 1 : 0; // (AlternativePlacement's own gathering)
    if (this->AlternativePlacement(c.Set, c.Count, check, scratch, entry.Alternative, entry.AlternativeError,
          entry.AlternativeCost) &&
      !(maxError >= 0 && entry.AlternativeError > maxError))
    {
      entry.Result = BatchEntry::Outcome::Alternative;
    }
  }
}

// The parallel part of a batch: every entry evaluated and checked with a scratch per thread.
struct TriangleCollapser::EvaluateBatchFunctor
{
  const TriangleCollapser& Self;
  CollapseBatch& Batch;
  const CollapseOptions& Check;
  vtkSMPThreadLocal<std::vector<Index>>& Scratch;
  std::vector<Index>* Serial = nullptr; // the scratch when run on the calling thread only
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    auto& local = this->Serial ? *this->Serial : this->Scratch.Local();
    for (vtkIdType i = begin; i < end; ++i)
    {
      BatchEntry& entry = this->Batch.Entries[size_t(i)];
      // Performed in parallel, an entry keeps its set's triangles for the collapse.
      auto& scratch = this->Batch.PerformsTogether() ? this->Batch.Gathered[size_t(i)] : local;
      const std::uint64_t stamp = this->Batch.Stamp(size_t(i));
      if (!this->Batch.InOrder)
      {
        entry.Runs = this->Batch.Entries.size() == 1 && !this->Batch.Passes;
      }
      if (!entry.Runs && !this->Batch.InOrder)
      {
        ++entry.Walks;
        entry.Runs = this->Self.AllRingVertices(entry, [&](Index w) { return this->Batch.Owner[w] == stamp; });
      }
      if (entry.Runs)
      {
        const bool lone = this->Batch.Entries.size() == 1 && !this->Batch.Passes;
        this->Self.EvaluateEntry(entry, this->Check, scratch, !lone, lone ? &this->Self.FailedSets : nullptr);
      }
      if (entry.Runs && this->Batch.PerformsTogether() && !this->Batch.InOrder &&
        (entry.Result == BatchEntry::Outcome::Valid || entry.Result == BatchEntry::Outcome::Alternative))
      {
        const Candidate& c = entry.C;
        entry.Removes = this->Self.Mesh.RemovedBy(c.Set, c.Count, scratch);
        entry.Survives = static_cast<Index>(scratch.size()) - entry.Removes;
      }
    }
  }
};

void TriangleCollapser::EvaluateBatch(CollapseLoop& loop, CollapseBatch& batch)
{
  batch.LoneGathered = nullptr;
  batch.LoneKeys = nullptr;
  if (batch.Ahead && batch.Entries.size() == 1)
  {
    if (this->TakeFromLookAhead(batch))
    {
      loop.Gathers += batch.Entries[0].Gathers;
      batch.AdaptSize(1);
      ++loop.Ran;
      return;
    }
    this->ForeignPop(batch); // before the evaluation writes the triangle's edge caches
  }
  const vtkIdType n = static_cast<vtkIdType>(batch.Entries.size());
  // An entry takes up to eight checks (the optimum and seven alternative placements).
  if (!this->LinkTables)
  {
    this->Mesh.ReserveEpochs(static_cast<std::uint32_t>(8 * n));
  }
  if (batch.PerformsTogether() && batch.Gathered.size() < batch.Entries.size())
  {
    batch.Gathered.resize(batch.Entries.size());
  }
  EvaluateBatchFunctor functor{ *this, batch, loop.Check, batch.Scratch };
  batch.InOrder = false;
  if (n > 1)
  {
    PickFunctor pick{ {}, *this, batch, true };
    if (this->Options.ExactUnion)
    {
      pick(0, n); // the union buffer is shared
    }
    else
    {
      ForEntries(batch.OneThread, 0, n, pick);
    }
    ClaimRingsFunctor claim{ {}, *this, batch, OnCaller(batch.OneThread, 0, n) };
    if (claim.InOrder)
    {
      claim(0, n);
    }
    else
    {
      ForEntries(batch.OneThread, 0, n, claim);
    }
    batch.InOrder = claim.InOrder;
  }
  // The entries whose pick, claims and check run in steps that several threads share when there
  // are several (TriangleCollapseResult::SharedStepEntries; from sizes only, as the steps split).
  if (n > 1 && !this->Options.ExactUnion && !OnCaller(false, 0, n))
  {
    ++loop.SharedBatches;
    loop.SharedEntries += n;
  }
  // The exact-union mode shares a union buffer between evaluations: sequential.
  if (n == 1 || this->Options.ExactUnion)
  {
    functor.Serial = &batch.SerialScratch;
    functor(0, n);
  }
  else
  {
    ForEntries(batch.OneThread, 0, n, functor);
  }
  // The entries that overlap an earlier one go back to the queue unchanged, before the others are
  // performed (an alternative placement is judged against the queue as it would be).
  size_t ran = 0;
  for (size_t i = 0; i < batch.Entries.size(); ++i)
  {
    if (!batch.Entries[i].Runs)
    {
      this->Heap.Set(batch.Entries[i].C.Triangle, batch.Keys[i]);
    }
    ran += batch.Entries[i].Runs ? 1 : 0;
    loop.RingWalks += batch.Entries[i].Walks;
    loop.Gathers += batch.Entries[i].Gathers;
    loop.PlacementsDeferred += batch.Entries[i].PlacementPending ? 1 : 0;
  }
  batch.AdaptSize(ran);
  loop.Ran += static_cast<long long>(ran);
}

void TriangleCollapser::EvaluateAhead(CollapseLoop& loop, LookAhead& ahead)
{
  ahead.End(); // no slot of the last look-ahead is still held (its vectors are rewritten here)
  // Adapt the width to the use of the last look-ahead (a pop of another triangle ends it early
  // where the queue's order moves fast, e.g. on ties).
  const size_t used = ahead.Batch.Entries.size() - ahead.Remaining;
  ahead.Width = used * 4 < ahead.Batch.Entries.size() ? std::max(2, ahead.Width / 2)
                                                      : std::min(ahead.MaximumWidth, 2 * ahead.Width);
  // The next pops in Pop's order (key, then id): the queue's pop cache lists them (at least eight
  // where the bucket holds as many; session 36); else the whole lowest bucket (a scanned one, up to
  // the queue's scan limit) is named and its first pops sorted out (77 M instructions on mc250k).
  constexpr int named = 512;
  ahead.Ids.resize(size_t(named));
  ahead.Keys.resize(size_t(named));
  int inBucket = this->Heap.Listed(ahead.Width, ahead.Ids.data(), ahead.Keys.data());
  const bool listed = inBucket > 0;
  inBucket = listed ? inBucket : this->Heap.Upcoming(0, named, ahead.Ids.data(), ahead.Keys.data());
  ahead.Order.resize(size_t(inBucket));
  for (size_t i = 0; i < size_t(inBucket); ++i)
  {
    ahead.Order[i] = i;
  }
  const int n = std::min(inBucket, ahead.Width);
  if (!listed)
  {
    std::partial_sort(ahead.Order.begin(), ahead.Order.begin() + n, ahead.Order.end(), [&](size_t a, size_t b) {
      return ahead.Keys[a] < ahead.Keys[b] || (ahead.Keys[a] == ahead.Keys[b] && ahead.Ids[a] < ahead.Ids[b]);
    });
  }
  CollapseBatch& batch = ahead.Batch;
  batch.Entries.assign(size_t(n), BatchEntry());
  batch.Keys.resize(size_t(n));
  for (size_t i = 0; i < size_t(n); ++i)
  {
    batch.Entries[i].C.Triangle = ahead.Ids[ahead.Order[i]];
    batch.Keys[i] = ahead.Keys[ahead.Order[i]];
  }
  if (batch.Gathered.size() < size_t(n))
  {
    batch.Gathered.resize(size_t(n));
  }
  ahead.NewKeys.resize(std::max(ahead.NewKeys.size(), size_t(n)));
  ahead.Taken.assign(size_t(n), 0);
  ahead.Remaining = size_t(n); // until the claims are settled: not exhausted
  ahead.Live = true;
  ahead.ReferenceRoom = this->Mesh.ReferencesBeforeCompaction();
  ahead.Updates = this->Updates;
  ahead.Check = &loop.Check;
  // The first entry is the next pop (usually): the loop keeps it and evaluates it while the worker
  // makes the claims of all (read-only on the mesh, both). Posted last (release): whoever makes the
  // claims sees the entries and the limits.
  ahead.SlotCount.store(n, std::memory_order_relaxed);
  for (int i = 0; i < n; ++i)
  {
    ahead.Slots[i].store(i == 0 ? SlotLoop : SlotIdle, std::memory_order_relaxed);
  }
  ahead.ClaimsSettled = false;
  ahead.Claims.store(SlotPosted, std::memory_order_release);
}

void TriangleCollapser::MakeClaims(LookAhead& ahead) const
{
  // The claims of each triangle's three fans (which hold the ring of any of its operations), then
  // the slots of the entries that hold their rings (the first stays the loop's).
  const int n = ahead.SlotCount.load(std::memory_order_relaxed);
  this->ClaimInOrder(ahead.Batch, size_t(n));
  for (int i = 1; i < n; ++i)
  {
    if (ahead.Batch.Entries[size_t(i)].Runs)
    {
      ahead.Slots[i].store(SlotPosted, std::memory_order_release);
    }
  }
}

void TriangleCollapser::SettleClaims(LookAhead& ahead) const
{
  // Before the loop reads the claims or writes the mesh: made here if the worker has not started
  // them, else awaited (the worker is making them).
  if (ahead.ClaimsSettled)
  {
    return;
  }
  unsigned char state = SlotPosted;
  if (ahead.Claims.compare_exchange_strong(state, SlotLoop, std::memory_order_acquire))
  {
    this->MakeClaims(ahead);
  }
  else
  {
    LookAhead::WaitWhileWorker(ahead.Claims);
  }
  ahead.Claims.store(SlotIdle, std::memory_order_relaxed);
  ahead.ClaimsSettled = true;
  ahead.Remaining = 0;
  for (const BatchEntry& entry : ahead.Batch.Entries)
  {
    ahead.Remaining += entry.Runs ? 1 : 0;
  }
  ahead.Evaluated += static_cast<long long>(ahead.Remaining);
}

void TriangleCollapser::ClaimInOrder(CollapseBatch& batch, size_t n) const
{
  if (++batch.Number == 0)
  {
    std::fill(batch.Owner.begin(), batch.Owner.end(), ~std::uint64_t(0));
    batch.Number = 1;
  }
  const std::uint64_t current = batch.Stamp(0) >> 32;
  for (size_t i = 0; i < n; ++i)
  {
    const Index* tri = this->Mesh.Triangle(batch.Entries[i].C.Triangle);
    for (int k = 0; k < 3; ++k)
    {
      this->Mesh.PrefetchBlock(tri[k]);
    }
  }
  for (size_t i = 0; i < n; ++i)
  {
    // Stamps grow with the entry within a look-ahead and older look-aheads' are larger: a vertex
    // already stamped by this look-ahead belongs to an earlier entry.
    // Only the entry's triangle is read: the loop may be picking the first entry's operation.
    BatchEntry& entry = batch.Entries[i];
    const std::uint64_t stamp = batch.Stamp(i);
    bool runs = true;
    const Index* tri = this->Mesh.Triangle(entry.C.Triangle);
    for (int k = 0; k < 3; ++k)
    {
      this->Mesh.ForEachTriangle(tri[k], [&](Index s) {
        const Index* around = this->Mesh.Triangle(s);
        for (int m = 0; m < 3; ++m)
        {
          std::uint64_t& owner = batch.Owner[around[m]];
          const bool earlier = (owner >> 32) == current && owner != stamp;
          runs = runs && !earlier;
          owner = earlier ? owner : stamp;
        }
      });
    }
    entry.Runs = runs;
  }
}

void TriangleCollapser::EvaluateSlot(LookAhead& ahead, size_t i) const
{
  // As EvaluateBatchFunctor for an entry of the look-ahead: picked here, the set's triangles kept.
  BatchEntry& entry = ahead.Batch.Entries[i];
  std::vector<Index>& gathered = ahead.Batch.Gathered[i];
  this->EvaluateEntry(entry, *ahead.Check, gathered, false);
  KeysAhead& keys = ahead.NewKeys[i];
  keys.Ready = false;
  if (entry.Result == BatchEntry::Outcome::Valid)
  {
    this->KeysBeforeCollapse(entry.C, gathered, keys, ahead.Batch.Spokes.Local());
  }
}

void TriangleCollapser::LookAheadWorker(LookAhead& ahead) const
{
  // Claims posted slots from the back (the loop takes them from the front, so the two rarely want
  // the same one). Idle, it spins briefly, then yields, then sleeps; it leaves when the loop has
  // finished, so it never outlives the loop's own bounded work.
  long long evaluated = 0, claimsMade = 0;
  for (int idle = 0; !ahead.Finished.load(std::memory_order_acquire);)
  {
    bool worked = false;
    unsigned char claims = SlotPosted;
    if (ahead.Claims.load(std::memory_order_relaxed) == SlotPosted &&
      ahead.Claims.compare_exchange_strong(claims, SlotWorker, std::memory_order_acquire))
    {
      this->MakeClaims(ahead);
      ahead.Claims.store(SlotDone, std::memory_order_release);
      worked = true;
      ++claimsMade;
    }
    for (int i = ahead.SlotCount.load(std::memory_order_relaxed) - 1; i >= 0 && !worked; --i)
    {
      unsigned char state = SlotPosted;
      if (ahead.Slots[i].load(std::memory_order_relaxed) == SlotPosted &&
        ahead.Slots[i].compare_exchange_strong(state, SlotWorker, std::memory_order_acquire))
      {
        this->EvaluateSlot(ahead, size_t(i));
        ahead.Slots[i].store(SlotDone, std::memory_order_release);
        worked = true;
        ++evaluated;
      }
    }
    // The loop posts the next look-ahead within microseconds of taking the last slot: spin through
    // such gaps (a yield on a loaded machine gives the core away for a time slice), then back off.
    idle = worked ? 0 : std::min(idle + 1, IdleSleepAfter);
    if (idle == IdleSleepAfter)
    {
      std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
    else if (idle > IdleYieldAfter)
    {
      std::this_thread::yield();
    }
    else
    {
      CpuRelax();
    }
  }
  ahead.WorkerEvaluations += evaluated;
  ahead.WorkerClaims += claimsMade;
}

bool TriangleCollapser::TakeFromLookAhead(CollapseBatch& lone) const
{
  // Any two entries that hold their rings have disjoint rings (each vertex is held by its earliest
  // claimant), so an entry's evaluation stays valid while only such entries are performed,
  // whatever their order.
  LookAhead& ahead = *lone.Ahead;
  if (ahead.Exhausted())
  {
    return false;
  }
  const Index t = lone.Entries[0].C.Triangle;
  const auto& entries = ahead.Batch.Entries;
  if (!ahead.ClaimsSettled)
  {
    // The first entry is the loop's: evaluated while the worker makes the claims.
    const bool first = !entries.empty() && entries[0].C.Triangle == t && ahead.Batch.Keys[0] == lone.Keys[0];
    if (first)
    {
      this->EvaluateSlot(ahead, 0);
    }
    this->SettleClaims(ahead);
    if (first)
    {
      return this->TakeSlot(lone, 0);
    }
  }
  size_t i = 0;
  while (i < entries.size() && (entries[i].C.Triangle != t || ahead.Taken[i]))
  {
    ++i;
  }
  if (i == entries.size() || !entries[i].Runs || ahead.Batch.Keys[i] != lone.Keys[0])
  {
    return false; // evaluated now; ForeignPop decides whether the look-ahead stays valid
  }
  // The slot: evaluated here if the worker has not claimed it (the first entry's is the loop's),
  // else its evaluation is awaited.
  unsigned char state = SlotPosted;
  if (ahead.Slots[i].compare_exchange_strong(state, SlotLoop, std::memory_order_acquire) || state == SlotLoop)
  {
    this->EvaluateSlot(ahead, i);
  }
  else
  {
    LookAhead::WaitWhileWorker(ahead.Slots[i]);
  }
  return this->TakeSlot(lone, i);
}

bool TriangleCollapser::TakeSlot(CollapseBatch& lone, size_t i) const
{
  LookAhead& ahead = *lone.Ahead;
  const auto& entries = ahead.Batch.Entries;
  ahead.Slots[i].store(SlotIdle, std::memory_order_relaxed);
  ahead.Taken[i] = 1;
  --ahead.Remaining;
  ++ahead.TakenCount;
  lone.Entries[0] = entries[i];
  lone.LoneGathered = &ahead.Batch.Gathered[i];
  lone.LoneKeys = &ahead.NewKeys[i];
  return true;
}

void TriangleCollapser::ForeignPop(const CollapseBatch& lone) const
{
  // A pop the look-ahead did not evaluate is evaluated (its triangle's edge caches written) and
  // may be performed: before either, the look-ahead ends unless the pop's three fans (which hold
  // any of its operations' rings) are disjoint from the rings of the entries still to take (a
  // vertex of such a ring is owned by that entry, its earliest claimant).
  LookAhead& ahead = *lone.Ahead;
  this->SettleClaims(ahead);
  if (ahead.Exhausted())
  {
    return;
  }
  const std::uint64_t claimed = ahead.Batch.Stamp(0) >> 32;
  bool overlaps = false;
  this->ForEachRingVertex(lone.Entries[0], [&](Index w) {
    const std::uint64_t owner = ahead.Batch.Owner[w];
    const size_t entry = size_t(owner & 0xffffffffu);
    overlaps = overlaps ||
      ((owner >> 32) == claimed && ahead.Batch.Entries[entry].Runs && !ahead.Taken[entry]);
  });
  if (overlaps)
  {
    ahead.End();
  }
}

void TriangleCollapser::CheckLookAhead(LookAhead& ahead) const
{
  // A compaction reorders the reference blocks (and so the order of a gathering) and raises the
  // room left; a retried triangle may lie in a ring evaluated ahead.
  const size_t room = this->Mesh.ReferencesBeforeCompaction();
  if (room > ahead.ReferenceRoom || this->Updates != ahead.Updates)
  {
    ahead.End();
  }
  ahead.ReferenceRoom = room;
  ahead.Updates = this->Updates;
}

TriangleCollapser::Validity TriangleCollapser::Settle(BatchEntry& entry, CollapseLoop& loop, TriangleCollapseResult& result)
{
  // The sequential decisions, in selection order: exclusions, the error bound, and whether an
  // alternative placement is still the cheapest operation left.
  Candidate& c = entry.C;
  switch (entry.Result)
  {
    case BatchEntry::Outcome::NoOperation:
      this->State[c.Triangle].Rejected = 1;
      return Validity::Deferred;
    case BatchEntry::Outcome::OverError:
      this->State[c.Triangle].Rejected = 2; // retried only when one of its vertices changes
      result.StoppedByError = true;
      return Validity::Deferred;
    default:
      break;
  }
  ++loop.StatusCounts[static_cast<int>(entry.Status)];
  if (entry.Result == BatchEntry::Outcome::Alternative)
  {
    // Keep the greedy order: do it now only if it is still the cheapest operation left.
    const double bias = c.Count == 2 ? this->Options.EdgeCollapseBias : 1.0;
    const float key = static_cast<float>(entry.AlternativeCost * bias * this->CostScale);
    if (!this->Heap.WouldBeFirst(key))
    {
      this->Heap.Set(c.Triangle, key);
      return Validity::Deferred;
    }
    c.Position = entry.Alternative;
    c.Error = entry.AlternativeError;
    c.Local = c.Position - this->Origin;
    ++loop.Replaced;
    return Validity::Valid;
  }
  return entry.Result == BatchEntry::Outcome::Valid ? Validity::Valid : Validity::Invalid;
}

bool TriangleCollapser::ApplyBatch(CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result)
{
  // A lone entry was checked on this thread and its scratch still lists the set's triangles (the
  // last check, optimum or alternative placement, was of the same set); in a larger batch the
  // scratch of each thread was reused by later entries.
  const std::vector<Index>* gathered = batch.Entries.size() != 1 ? nullptr
    : batch.LoneGathered                                          ? batch.LoneGathered
                                                                  : &batch.SerialScratch;
  for (BatchEntry& entry : batch.Entries)
  {
    if (!entry.Runs)
    {
      continue;
    }
    if (!loop.Settling && this->Mesh.NumberOfLiveTriangles() <= loop.Target)
    {
      return false;
    }
    const Validity validity = this->Settle(entry, loop, result);
    if (validity == Validity::Invalid)
    {
      this->Reject(entry.C, result);
    }
    if (validity != Validity::Valid)
    {
      continue;
    }
    if (batch.Ahead && (!gathered || this->Mesh.ReferencesBeforeCompaction() < gathered->size()))
    {
      batch.Ahead->End(); // the collapse may compact the references (moves every vertex's block)
    }
    const Index kept = this->Perform(entry.C, gathered, loop, result, batch.LoneKeys);
    this->RetryPendingAround(kept, loop);
    if (this->Options.RecordHistory)
    {
      this->AppendHistory(loop.Record, loop, result);
    }
    if (!this->ReportProgress(loop, result))
    {
      return false;
    }
  }
  return true;
}

template <typename PerformEntry>
void TriangleCollapser::SettleInOrder(
  CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result, bool& more, PerformEntry&& perform)
{
  // The sequential decisions, in selection order: the rings are disjoint, so an entry's outcome
  // does not depend on the collapses before it; the count target is met by the removals that
  // perform(i, kept) gives. The point data merge here, where the set's vertices are in place.
  batch.Order.clear();
  Index live = this->Mesh.NumberOfLiveTriangles();
  more = true;
  for (size_t i = 0; i < batch.Entries.size(); ++i)
  {
    BatchEntry& entry = batch.Entries[i];
    if (!entry.Runs)
    {
      continue;
    }
    if (!loop.Settling && live <= loop.Target)
    {
      more = false;
      break;
    }
    const Validity validity = this->Settle(entry, loop, result);
    if (validity == Validity::Invalid)
    {
      this->Reject(entry.C, result);
    }
    if (validity != Validity::Valid)
    {
      continue;
    }
    const Index kept = *std::min_element(entry.C.Set, entry.C.Set + entry.C.Count);
    if (this->Attributes)
    {
      this->MergeAttributes(entry.C, kept);
    }
    live -= perform(i, kept);
    batch.Order.push_back(i);
  }
}

size_t TriangleCollapser::SettleForParallel(
  CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result, bool& more)
{
  // Before any collapse of the batch: the removals are those the checks counted.
  this->SettleInOrder(batch, loop, result, more, [&](size_t i, Index) { return batch.Entries[i].Removes; });
  return batch.PlaceBlocks();
}

size_t CollapseBatch::PlaceBlocks()
{
  if (this->Performed.size() < this->Order.size())
  {
    this->Performed.resize(this->Order.size());
  }
  Index room = 0;
  for (size_t k = 0; k < this->Order.size(); ++k)
  {
    this->Performed[k].Block = room;
    room += this->Entries[this->Order[k]].Survives;
  }
  return static_cast<size_t>(room);
}

// The concurrent part of ParallelApply: each collapse edits only its set's vertices and the
// triangles around them, and re-evaluates the triangles around its new vertex (reading its closed
// one-ring only), all disjoint from the other entries'.
struct TriangleCollapser::PerformBatchFunctor
{
  TriangleCollapser& Self;
  CollapseBatch& Batch;
  Index Base;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    SpokeScratch& spokes = this->Batch.Spokes.Local();
    for (vtkIdType k = begin; k < end; ++k)
    {
      const size_t i = this->Batch.Order[size_t(k)];
      const Candidate& c = this->Batch.Entries[i].C;
      PerformedCollapse& done = this->Batch.Performed[size_t(k)];
      done.Kept = *std::min_element(c.Set, c.Set + c.Count);
      this->Self.Mesh.CollapseIntoBlock(
        c.Set, c.Count, done.Kept, c.Position, this->Batch.Gathered[i], this->Base + done.Block, done.Record);
      this->Self.MergeVertexState(c, done.Kept);
      if (this->Batch.PassesState)
      {
        this->Self.MarkChanged(done.Kept, done.Record, *this->Batch.PassesState);
      }
      else
      {
        this->Self.AroundKeys(done.Kept, done.Around, done.Keys, spokes);
      }
    }
  }
};

void TriangleCollapser::QueuePerformed(
  const BatchEntry& entry, PerformedCollapse& done, CollapseLoop& loop, TriangleCollapseResult& result)
{
  result.MaximumError = std::max(result.MaximumError, entry.C.Error);
  ++result.Collapses;
  result.EdgeCollapses += entry.C.Count == 2 ? 1 : 0;
  for (Index r : done.Record.RemovedTriangles)
  {
    this->Heap.Remove(r);
  }
  this->RequeueAround(done.Around, done.Keys);
  this->RetryPendingAround(done.Kept, loop);
  if (this->Options.RecordHistory)
  {
    this->AppendHistory(done.Record, loop, result);
  }
}

// The collapses of a batch performed in a step that several threads share when there are several
// (TriangleCollapseResult::SharedStepCollapses): the batch's steps split (more entries than one
// grain) and more collapses than one perform grain. Counted from sizes only: the same for any
// thread count (on one thread the same steps run in order on the caller).
void CountSharedCollapses(const CollapseBatch& batch, CollapseLoop& loop)
{
  const vtkIdType n = static_cast<vtkIdType>(batch.Order.size());
  if (!OnCaller(false, 0, static_cast<vtkIdType>(batch.Entries.size())) && !OnCaller(false, 0, n, PerformGrain))
  {
    loop.SharedCollapses += n;
  }
}

bool TriangleCollapser::ParallelApply(
  CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result, PhaseClock& clock)
{
  bool more = true;
  if (batch.InOrder)
  {
    this->CollapseInOrder(batch, loop, result, more);
    CountSharedCollapses(batch, loop);
    clock.Next();
    return this->QueueInOrder(batch, loop, result) && more;
  }
  const size_t room = this->SettleForParallel(batch, loop, result, more);
  CountSharedCollapses(batch, loop);
  clock.Next();
  const vtkIdType n = static_cast<vtkIdType>(batch.Order.size());
  PerformBatchFunctor perform{ *this, batch, this->Mesh.ReserveRefs(static_cast<Index>(room)) };
  ForEntries(batch.OneThread, 0, n, perform, PerformGrain);
  Index removedTriangles = 0, removedVertices = 0;
  for (vtkIdType k = 0; k < n; ++k)
  {
    removedTriangles += static_cast<Index>(batch.Performed[size_t(k)].Record.RemovedTriangles.size());
    removedVertices += batch.Entries[batch.Order[size_t(k)]].C.Count - 1;
  }
  this->Mesh.FinishCollapses(removedTriangles, removedVertices);
  clock.Next();
  return this->QueueInOrder(batch, loop, result) && more;
}

bool TriangleCollapser::QueueInOrder(CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result)
{
  // The queue is shared: its updates, the retries and the records follow in selection order.
  for (size_t k = 0; k < batch.Order.size(); ++k)
  {
    this->QueuePerformed(batch.Entries[batch.Order[k]], batch.Performed[k], loop, result);
  }
  return this->ReportProgress(loop, result);
}

void TriangleCollapser::CollapseInOrder(
  CollapseBatch& batch, CollapseLoop& loop, TriangleCollapseResult& result, bool& more)
{
  // SettleForParallel and PerformBatchFunctor one entry after the other: each collapse right after
  // its settling, the queue untouched until QueueInOrder. The rings are disjoint, so an entry's
  // settling does not see the collapses before it (they write only their rings; its own triangle's
  // state and the queue are not theirs), and the blocks appended one after the other lie where
  // the reserved room would have put them (the survivors in order). The live count is then known
  // from each collapse, without counting the removals ahead (EditableMesh::RemovedBy).
  Index removedTriangles = 0, removedVertices = 0;
  this->SettleInOrder(batch, loop, result, more, [&](size_t i, Index kept) {
    const Candidate& c = batch.Entries[i].C;
    if (batch.Performed.size() <= batch.Order.size())
    {
      batch.Performed.resize(batch.Order.size() + 1);
    }
    PerformedCollapse& done = batch.Performed[batch.Order.size()];
    done.Kept = kept;
    const Index removed = this->Mesh.CollapseAppending(c.Set, c.Count, kept, c.Position, batch.Gathered[i], done.Record);
    removedTriangles += removed;
    removedVertices += c.Count - 1;
    this->MergeVertexState(c, kept);
    this->AroundKeys(kept, done.Around, done.Keys, this->Spokes);
    return removed;
  });
  this->Mesh.FinishCollapses(removedTriangles, removedVertices);
}

void TriangleCollapser::AskForTarget(CollapseLoop& loop, bool nothingLeft)
{
  const double cheapest =
    nothingLeft ? std::numeric_limits<double>::infinity() : double(this->Heap.TopKey()) / this->CostScale;
  const Index target = this->Options.SettleTarget(cheapest, this->Mesh.NumberOfLiveTriangles());
  if (target >= 0)
  {
    loop.Target = target;
    loop.Settling = false;
  }
}

void TriangleCollapser::CollapseToTarget(CollapseLoop& loop, TriangleCollapseResult& result)
{
  CollapseBatch batch;
  batch.MaximumSize = this->Options.BatchCollapses ? MaximumBatchSize : 1;
  batch.Size = batch.MaximumSize;
  batch.CostTolerance = this->Options.BatchCollapses ? std::max(0.0, this->Options.BatchCostTolerance) : 0.0;
  batch.MinimumSize = static_cast<size_t>(std::max(1, this->Options.BatchMinimumSize));
  batch.Owner.assign(batch.MaximumSize > 1 ? size_t(this->Mesh.NumberOfPoints()) : 0, ~std::uint64_t(0));
  // The exact-union mode merges sorted plane lists through one shared buffer: performed in order.
  batch.Parallel = batch.MaximumSize > 1 && !this->Options.ExactUnion;
  batch.OneThread = vtkSMPTools::GetEstimatedNumberOfThreads() <= 1;
  // The look-ahead evaluates beside the loop: with the checks' own link tables, not the mesh's
  // marks, and not with the exact union's shared buffer.
  if (!(batch.MaximumSize == 1 && this->Options.LookAheadEvaluations > 1 && this->LinkTables &&
        !this->Options.ExactUnion && vtkSMPTools::GetEstimatedNumberOfThreads() > 1))
  {
    this->CollapseSteps(loop, batch, nullptr, result);
    return;
  }
  LookAhead ahead(std::min(this->Options.LookAheadEvaluations, 512));
  ahead.Width = ahead.MaximumWidth;
  ahead.Batch.Owner.assign(size_t(this->Mesh.NumberOfPoints()), ~std::uint64_t(0));
  batch.Ahead = &ahead;
  this->CollapseWithWorker(loop, batch, ahead, result);
  result.LookAheadEvaluated = ahead.Evaluated;
  result.LookAheadTaken = ahead.TakenCount;
  result.LookAheadKeysTaken = this->KeysAheadTaken;
  result.LookAheadRegions += 1;
  result.LookAheadWorkerEvaluations += ahead.WorkerEvaluations;
  vtkLogF(TRACE, "triangle collapse: the look-ahead's worker made the claims of %lld look-aheads", ahead.WorkerClaims);
}

void TriangleCollapser::CollapseWithWorker(
  CollapseLoop& loop, CollapseBatch& batch, LookAhead& ahead, TriangleCollapseResult& result)
{
  // One worker thread for the whole loop (vtkSMPTools runs the rest: its thread-local scratch
  // serves any thread). Not a vtkSMPTools::For of two chunks: the STDThread backend keeps the
  // caller out of its chunks and TBB may run both on the caller, so the loop (progress events,
  // abort) could not be kept on the calling thread. Without a thread the loop evaluates every slot.
  struct Joined
  {
    LookAhead& Ahead;
    LookAhead*& Beside; // TriangleCollapser::WorkerAhead
    std::thread Worker;
    ~Joined()
    {
      this->Ahead.End();
      this->Ahead.Finished.store(true, std::memory_order_release);
      if (this->Worker.joinable())
      {
        this->Worker.join();
      }
      this->Beside = nullptr;
    }
  } joined{ ahead, this->WorkerAhead, {} };
  try
  {
    joined.Worker = std::thread([this, &ahead] { this->LookAheadWorker(ahead); });
  }
  catch (const std::system_error&)
  {
    vtkLogF(WARNING, "triangle collapse: no thread for the look-ahead; it runs on the loop's thread");
  }
  this->WorkerAhead = &ahead;
  this->CollapseSteps(loop, batch, &ahead, result);
}

void TriangleCollapser::CollapseSteps(
  CollapseLoop& loop, CollapseBatch& batch, LookAhead* ahead, TriangleCollapseResult& result)
{
  loop.Settling = static_cast<bool>(this->Options.SettleTarget);
  for (;;)
  {
    if (loop.Settling)
    {
      this->AskForTarget(loop, this->Heap.Empty() || loop.Pops >= loop.MaximumPops);
    }
    if (this->Heap.Empty())
    {
      if (ahead)
      {
        ahead->End(); // the limits change
      }
      if (!this->RelaxNormalLimit(loop, result))
      {
        break;
      }
      continue;
    }
    if (!loop.Settling && this->Mesh.NumberOfLiveTriangles() <= loop.Target)
    {
      break;
    }
    if (loop.Pops >= loop.MaximumPops)
    {
      result.WorkBoundReached = true;
      break;
    }
    if (ahead && ahead->Exhausted())
    {
      this->EvaluateAhead(loop, *ahead);
    }
    PhaseClock clock(loop.PhaseTotals());
    this->SelectBatch(loop, batch);
    ++loop.Batches;
    loop.Selected += static_cast<long long>(batch.Entries.size());
    clock.Next();
    this->EvaluateBatch(loop, batch);
    clock.Next();
    const bool more =
      batch.PerformsTogether() ? this->ParallelApply(batch, loop, result, clock) : this->ApplyBatch(batch, loop, result);
    clock.Next();
    if (ahead)
    {
      this->CheckLookAhead(*ahead);
    }
    if (!more)
    {
      break;
    }
  }
}

bool TriangleCollapser::UsesPasses() const
{
  // The records are replayed in the queue's terms, the exact union and the attribute metric cost
  // sets that are not sums of vertex quadrics (no edge cache), and a distributed target is settled
  // against the queue's cheapest cost: those keep the queue.
  return this->Options.Schedule == CollapseSchedule::Passes && !this->Options.RecordHistory &&
    !this->Options.ExactUnion && this->AttributeComponents == 0 && !this->Options.SettleTarget;
}

void TriangleCollapser::InitializePasses()
{
  // The keys are computed by the first pass (CostPass); the edge cache serves the picks.
  AssignOnHugePages(this->State, size_t(this->Mesh.NumberOfTriangles()), TriangleState());
  this->CacheEdges = this->Options.EdgeCollapses;
  this->EdgeCachesCurrent = false; // the keys and caches change by passes, not around each collapse
}

void TriangleCollapser::MarkChanged(Index kept, const CollapseRecord& record, PassState& passes) const
{
  // Concurrent collapses have disjoint closed rings: no two threads write the same vertex (the
  // triangles' bits may share a word: atomic).
  std::vector<unsigned char>& change = passes.Change;
  change[kept] = VertexMoved;
  for (Index r : record.RemovedTriangles)
  {
    passes.ListConcurrently(r);
  }
  this->Mesh.ForEachTriangle(kept, [&](Index t) {
    passes.ListConcurrently(t);
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      change[tri[k]] = std::max(change[tri[k]], VertexInRing);
    }
  });
}

// A triangle's key changes only when one of its vertices moved (the kept vertex of a collapse of
// the last pass; only the edges at a moved vertex are costed again, as AroundKeys does for the
// queue), and its excluded operations may be valid again when it has a vertex in the closed ring
// of such a collapse. An edge's cost depends only on its two vertices: it is placed once, by the
// triangle where it runs from the smaller to the larger vertex id (one of the two triangles of an
// edge of a consistently oriented surface), and copied by the other in a second step
// (EdgeCopyFunctor); mc1m's edges were placed twice before. Each triangle writes only its own key
// and state: the same keys for any thread count.
struct TriangleCollapser::CostPassFunctor
{
  const TriangleCollapser& Self;
  PassState& Passes;
  const Index* Listed; // the triangles to visit (null: every triangle, by index)
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    const float none = std::numeric_limits<float>::infinity();
    const std::vector<unsigned char>& change = this->Passes.Change;
    for (vtkIdType i = begin; i < end; ++i)
    {
      const Index t = this->Listed ? this->Listed[i] : static_cast<Index>(i);
      this->Passes.Recost[t] = 0;
      if (!this->Self.Mesh.IsTriangleAlive(t))
      {
        this->Passes.Key[t] = none;
        continue;
      }
      const Index* tri = this->Self.Mesh.Triangle(t);
      const bool moved = change[tri[0]] == VertexMoved || change[tri[1]] == VertexMoved || change[tri[2]] == VertexMoved;
      const bool excluded = this->Self.State[t].Excluded != 0 && (change[tri[0]] || change[tri[1]] || change[tri[2]]);
      if (!this->Self.CacheEdges)
      {
        this->Self.State[t].Excluded = 0;
        Vec3 p;
        double error;
        int operation;
        const double cost = this->Self.Cost(t, p, error, operation);
        this->Passes.Key[t] = operation >= 0 ? static_cast<float>(cost * this->Self.CostScale) : none;
      }
      else if (this->Passes.AllStale || excluded)
      {
        this->Self.State[t].Excluded = 0;
        this->Passes.Recost[t] = this->Self.CostOwnedEdges(t, change, true, this->Passes.Key[t]);
      }
      else if (moved && this->Self.State[t].Excluded == 0)
      {
        this->Passes.Recost[t] = this->Self.CostOwnedEdges(t, change, false, this->Passes.Key[t]);
      }
    }
  }
};

unsigned char TriangleCollapser::CostOwnedEdges(
  Index t, const std::vector<unsigned char>& change, bool all, float& key) const
{
  const Index* tri = this->Mesh.Triangle(t);
  Vec3 p;
  // With TriangleCostBound the triangle is placed after its edges (EdgeCopyFunctor), if at all.
  const double triangle =
    this->Options.TriangleCostBound ? std::numeric_limits<double>::infinity() : this->TriangleOperationCost(tri, p);
  key = std::isfinite(triangle) ? static_cast<float>(triangle * this->CostScale) : std::numeric_limits<float>::infinity();
  float* cache = this->State[t].EdgeCost;
  const double bias = this->Options.EdgeCollapseBias;
  unsigned char flags = 1;
  for (int k = 0; k < 3; ++k)
  {
    const Index edge[2] = { tri[k], tri[(k + 1) % 3] };
    if (!all && change[edge[0]] != VertexMoved && change[edge[1]] != VertexMoved)
    {
      continue; // cached, both vertices unchanged
    }
    if (edge[0] < edge[1])
    {
      const Quadric qe = this->Vertex[edge[0]].Q + this->Vertex[edge[1]].Q;
      cache[k] = static_cast<float>(this->Place(edge, 2, qe, p) * bias * this->CostScale);
    }
    else
    {
      flags = static_cast<unsigned char>(flags | (2u << k));
    }
  }
  return flags;
}

float TriangleCollapser::EdgeOwnerCost(Index t, Index a, Index b) const
{
  // The owner holds the edge as (b, a) with b < a; it is costed again whenever a or b moves, as
  // this triangle is, so its cache is current. Without one (a border edge, an inconsistently
  // oriented one) the edge is placed here. Place is symmetric in the two vertices (the sum of
  // their quadrics, the midpoint and both vertices as fallbacks): the same cost either way.
  float cost = 0.0f;
  bool found = false;
  this->Mesh.ForEachTriangle(a, [&](Index s) {
    const Index* other = this->Mesh.Triangle(s);
    for (int j = 0; j < 3 && !found && s != t; ++j)
    {
      if (other[j] == b && other[(j + 1) % 3] == a)
      {
        cost = this->State[s].EdgeCost[j];
        found = true;
      }
    }
  });
  if (!found)
  {
    const Index edge[2] = { a, b };
    Vec3 p;
    const Quadric qe = this->Vertex[a].Q + this->Vertex[b].Q;
    cost = static_cast<float>(this->Place(edge, 2, qe, p) * this->Options.EdgeCollapseBias * this->CostScale);
  }
  return cost;
}

// CostPass's (and InitializeQueue's) second step: the edges each triangle left to its twin, then
// its key, the cheapest of its four operations (none is excluded: a triangle with exclusions was
// costed afresh). Each triangle writes only its own copies and reads only owned ones.
struct TriangleCollapser::EdgeCopyFunctor
{
  const TriangleCollapser& Self;
  const std::vector<unsigned char>& Recost;
  std::vector<float>& Key;
  const Index* Listed; // as CostPassFunctor's
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    for (vtkIdType i = begin; i < end; ++i)
    {
      const Index t = this->Listed ? this->Listed[i] : static_cast<Index>(i);
      const unsigned char flags = this->Recost[t];
      if (flags == 0)
      {
        continue;
      }
      const Index* tri = this->Self.Mesh.Triangle(t);
      float* cache = this->Self.State[t].EdgeCost;
      float key = this->Key[t];
      for (int k = 0; k < 3; ++k)
      {
        if (flags & (2u << k))
        {
          cache[k] = this->Self.EdgeOwnerCost(t, tri[k], tri[(k + 1) % 3]);
        }
        key = std::min(key, cache[k]);
      }
      if (this->Self.Options.TriangleCostBound && !this->Self.TriangleCannotWin(cache, 0))
      {
        Vec3 p;
        const double triangle = this->Self.TriangleOperationCost(tri, p);
        key = std::isfinite(triangle) ? std::min(key, static_cast<float>(triangle * this->Self.CostScale)) : key;
      }
      this->Key[t] = key;
    }
  }
};

void TriangleCollapser::InitialKeys(std::vector<float>& keys)
{
  // Each edge placed once, by the triangle that holds it from the smaller to the larger vertex id,
  // the twin copying its cost (as CostPass): the keys and caches of Cost bit for bit.
  const Index nt = this->Mesh.NumberOfTriangles();
  std::vector<unsigned char> recost(static_cast<size_t>(nt));
  const std::vector<unsigned char> unused;
  vtkSMPTools::For(0, nt, 4096, [&](vtkIdType begin, vtkIdType end) {
    for (Index t = static_cast<Index>(begin); t < static_cast<Index>(end); ++t)
    {
      recost[t] = this->CostOwnedEdges(t, unused, true, keys[t]);
    }
  });
  EdgeCopyFunctor copies{ *this, recost, keys, nullptr };
  vtkSMPTools::For(0, nt, 4096, copies);
}

void TriangleCollapser::CostPass(PassState& passes)
{
  const Index nt = this->Mesh.NumberOfTriangles();
  passes.Key.resize(size_t(nt), std::numeric_limits<float>::infinity());
  passes.Recost.resize(size_t(nt), 0);
  passes.Change.resize(size_t(this->Mesh.NumberOfPoints()), 0);
  // Without the edge cache every live triangle is costed afresh each pass.
  const bool everything = passes.AllStale || !this->CacheEdges || this->Options.PassCostSweepsEveryTriangle;
  passes.Listed.resize((size_t(nt) + 63) / 64, 0);
  std::vector<Index>& listed = passes.Visit;
  listed.clear();
  for (size_t w = 0; w < passes.Listed.size() && !everything; ++w)
  {
    // Only the triangles a visit of every triangle would change (the rest keep key and state):
    // the same keys and states.
    for (std::uint64_t bits = passes.Listed[w]; bits != 0; bits &= bits - 1)
    {
      listed.push_back(static_cast<Index>(64 * w + size_t(__builtin_ctzll(bits))));
    }
  }
  std::fill(passes.Listed.begin(), passes.Listed.end(), 0);
  const vtkIdType n = everything ? vtkIdType(nt) : static_cast<vtkIdType>(listed.size());
  const Index* list = everything ? nullptr : listed.data();
  passes.Visits += static_cast<long long>(n);
  CostPassFunctor costs{ *this, passes, list };
  vtkSMPTools::For(0, n, 4096, costs);
  EdgeCopyFunctor copies{ *this, passes.Recost, passes.Key, list };
  vtkSMPTools::For(0, n, 4096, copies);
  // The exclusions left (on triangles none of whose vertices changed) stay listed.
  for (vtkIdType i = 0; i < n && !everything; ++i)
  {
    if (this->Mesh.IsTriangleAlive(list[i]) && this->State[list[i]].Excluded != 0)
    {
      passes.List(list[i]);
    }
  }
  std::fill(passes.Change.begin(), passes.Change.end(), 0);
  passes.AllStale = false;
}

void TriangleCollapser::RankPass(const CollapseLoop& loop, PassState& passes) const
{
  const Index toRemove = std::max<Index>(1, this->Mesh.NumberOfLiveTriangles() - loop.Target);
  // After a pass that performed nothing, the goal rank doubles (not every candidate at once: a
  // pass taking them all performed its whole independent set up to the target in one go, far
  // beyond the greedy order; femur at 10 %: a collapse 1.6x the queue's largest error).
  const double goal = std::ldexp(std::ceil(this->Options.PassGoalShare * toRemove), std::min(passes.Widen, 62));
  const Index rank = goal >= double(this->Mesh.NumberOfTriangles()) ? -1 : static_cast<Index>(goal);
  RankPassCandidates(passes.Key, nullptr, rank, this->Options.PassErrorFactor, passes.Floor, passes.Ranking);
}

bool TriangleCollapser::SettlePassRound(
  CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result)
{
  // In rank order, the entries that hold their rings: which collapse (the count target met by the
  // removals their checks counted), which wait at a new cost, which lose an operation.
  batch.Order.clear();
  Index live = this->Mesh.NumberOfLiveTriangles();
  for (size_t i = 0; i < batch.Entries.size(); ++i)
  {
    BatchEntry& entry = batch.Entries[i];
    Candidate& c = entry.C;
    if (!entry.Runs)
    {
      continue;
    }
    if (live <= loop.Target)
    {
      return false;
    }
    ++loop.StatusCounts[static_cast<int>(entry.Status)];
    if (entry.Result == BatchEntry::Outcome::Alternative)
    {
      // The optimum folds a triangle: the alternative placement now if its cost is within the
      // pass's limit, else it waits for a later pass at that cost.
      const double bias = c.Count == 2 ? this->Options.EdgeCollapseBias : 1.0;
      const float key = static_cast<float>(entry.AlternativeCost * bias * this->CostScale);
      if (key > std::max(passes.Ranking.Limit, passes.Floor))
      {
        passes.Key[c.Triangle] = key;
        continue;
      }
      c.Position = entry.Alternative;
      c.Error = entry.AlternativeError;
      c.Local = c.Position - this->Origin;
      ++loop.Replaced;
    }
    else if (entry.Result != BatchEntry::Outcome::Valid)
    {
      // Its next best operation in a later pass; none left: it waits until its vertices change.
      ++result.RejectedCollapses;
      passes.List(c.Triangle);
      this->State[c.Triangle].Excluded |= static_cast<unsigned char>(1u << c.Operation);
      Vec3 p;
      double error;
      int operation;
      const double cost = this->Cost(c.Triangle, p, error, operation);
      passes.Key[c.Triangle] =
        operation >= 0 ? static_cast<float>(cost * this->CostScale) : std::numeric_limits<float>::infinity();
      continue;
    }
    if (this->Attributes)
    {
      this->MergeAttributes(c, *std::min_element(c.Set, c.Set + c.Count));
    }
    live -= entry.Removes;
    batch.Order.push_back(i);
  }
  return true;
}

size_t TriangleCollapser::FillWindow(
  size_t next, CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result)
{
  // The next ranked entries are tested in parallel (WaitsFunctor): those blocked by the collapses
  // so far wait for the next pass; the others join the window in rank order until it is full, and
  // pick their operations (once: an entry that waits keeps its set untouched); those without one
  // (every operation excluded, or over MaximumError) are settled at once and leave room for more.
  // The entries consumed and the window are those of a walk in rank order; a fill tests about as
  // many entries as that walk would need at the rate of waiting entries so far (the tests past the
  // full window are only reads). Each fill consumes ranked entries: bounded by the ranking's size.
  const std::vector<std::uint64_t>& order = passes.Ranking.Order;
  while (batch.Entries.size() < PassWindowSize && next < order.size())
  {
    const size_t first = batch.Entries.size();
    const double perAdmitted = double(batch.FillTested + 1) / double(batch.FillAdmitted + 1);
    const size_t room = PassWindowSize - first;
    const size_t take = std::min(order.size() - next,
      std::min(8 * PassWindowSize, static_cast<size_t>(1.25 * perAdmitted * double(room)) + 1));
    batch.Ranked.resize(take);
    batch.Waits.resize(take);
    for (size_t k = 0; k < take; ++k)
    {
      batch.Ranked[k] = RankedElement(order[next + k]);
    }
    WaitsFunctor waits{ {}, *this, passes, batch };
    vtkSMPTools::For(0, static_cast<vtkIdType>(take), 16, waits);
    size_t k = 0;
    for (; k < take && batch.Entries.size() < PassWindowSize; ++k)
    {
      if (batch.Waits[k])
      {
        ++result.WaitingEntries;
        continue;
      }
      batch.Entries.emplace_back();
      batch.Entries.back().C.Triangle = batch.Ranked[k];
    }
    next += k;
    batch.FillTested += static_cast<long long>(k);
    batch.FillAdmitted += static_cast<long long>(batch.Entries.size() - first);
    loop.Pops += static_cast<long long>(batch.Entries.size() - first);
    PickFunctor pick{ {}, *this, batch };
    vtkSMPTools::For(static_cast<vtkIdType>(first), static_cast<vtkIdType>(batch.Entries.size()), 16, pick);
    size_t kept = first;
    for (size_t i = first; i < batch.Entries.size(); ++i)
    {
      const BatchEntry& entry = batch.Entries[i];
      if (entry.Picked)
      {
        batch.Entries[kept++] = entry;
        continue;
      }
      passes.Key[entry.C.Triangle] = std::numeric_limits<float>::infinity();
      result.StoppedByError = result.StoppedByError || entry.Result == BatchEntry::Outcome::OverError;
    }
    batch.Entries.resize(kept);
  }
  return next;
}

bool TriangleCollapser::PassRound(
  CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result)
{
  ++passes.Rounds;
  const vtkIdType n = static_cast<vtkIdType>(batch.Entries.size());
  // Claims (the earliest entry in rank order holds a vertex), then the holders' checks, in
  // parallel: a holder's ring meets no undecided entry before it.
  if (++batch.Number == 0)
  {
    std::fill(batch.Owner.begin(), batch.Owner.end(), ~std::uint64_t(0));
    batch.Number = 1;
  }
  if (!this->LinkTables)
  {
    this->Mesh.ReserveEpochs(static_cast<std::uint32_t>(8 * n));
  }
  if (batch.Gathered.size() < batch.Entries.size())
  {
    batch.Gathered.resize(batch.Entries.size());
  }
  batch.InOrder = false;
  ClaimRingsFunctor claim{ {}, *this, batch };
  vtkSMPTools::For(0, n, 16, claim);
  EvaluateBatchFunctor evaluate{ *this, batch, loop.Check, batch.Scratch };
  vtkSMPTools::For(0, n, 16, evaluate);
  const bool more = this->SettlePassRound(loop, batch, passes, result);
  // The collapses in parallel, each marking what it changed.
  PerformBatchFunctor perform{ *this, batch, this->Mesh.ReserveRefs(static_cast<Index>(batch.PlaceBlocks())) };
  const vtkIdType performed = static_cast<vtkIdType>(batch.Order.size());
  if (performed > 0)
  {
    vtkSMPTools::For(0, performed, 16, perform);
  }
  Index removedTriangles = 0, removedVertices = 0;
  for (vtkIdType k = 0; k < performed; ++k)
  {
    const Candidate& c = batch.Entries[batch.Order[size_t(k)]].C;
    removedTriangles += static_cast<Index>(batch.Performed[size_t(k)].Record.RemovedTriangles.size());
    removedVertices += c.Count - 1;
    result.MaximumError = std::max(result.MaximumError, c.Error);
    ++result.Collapses;
    result.EdgeCollapses += c.Count == 2 ? 1 : 0;
    passes.Floor = std::max(passes.Floor, passes.Key[c.Triangle]);
  }
  this->Mesh.FinishCollapses(removedTriangles, removedVertices);
  passes.Performed += static_cast<Index>(performed);
  // The entries that lost a claim try again in the next round unless a collapse moved a vertex
  // of their triangle (three flags each: not worth a parallel loop).
  size_t kept = 0;
  for (size_t i = 0; i < batch.Entries.size(); ++i)
  {
    if (!batch.Entries[i].Runs && !this->Blocked(batch.Entries[i].C.Triangle, passes))
    {
      batch.Entries[kept++] = batch.Entries[i];
    }
  }
  batch.Entries.resize(kept);
  loop.Pops += static_cast<long long>(kept);
  if (loop.Pops >= loop.MaximumPops)
  {
    result.WorkBoundReached = true;
    return false;
  }
  return this->ReportProgress(loop, result) && more;
}

bool TriangleCollapser::RunPass(
  CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result)
{
  passes.Performed = 0;
  batch.Entries.clear();
  // PassRemovalShare: the pass stops after a round once it removed that share of what is left to
  // remove (at least one collapse's worth), so that the next pass re-ranks around its collapses.
  const Index live = this->Mesh.NumberOfLiveTriangles();
  const double share = std::min(1.0, std::max(0.0, this->Options.PassRemovalShare));
  const Index removals = std::max<Index>(2, static_cast<Index>(share * double(live - loop.Target)));
  // Rounds over the window in rank order: its first entry always holds its ring, so every round
  // decides at least one entry; the work is bounded by the pops (PassRound).
  for (size_t next = this->FillWindow(0, loop, batch, passes, result); !batch.Entries.empty();
       next = this->FillWindow(next, loop, batch, passes, result))
  {
    const size_t before = batch.Entries.size();
    if (!this->PassRound(loop, batch, passes, result))
    {
      return false;
    }
    if (share < 1.0 && live - this->Mesh.NumberOfLiveTriangles() >= removals)
    {
      return true;
    }
    // Entries crowding on a few vertices (a high-valence apex is in every ring) decide one per
    // round while every round walks all of them: decide the window one by one (the same result).
    const size_t decided = before - batch.Entries.size();
    if (batch.Entries.size() > 1 && decided * SlowRoundRatio < before &&
      !this->DecideOneByOne(loop, batch, passes, result))
    {
      return false;
    }
  }
  return true;
}

bool TriangleCollapser::DecideOneByOne(
  CollapseLoop& loop, CollapseBatch& batch, PassState& passes, TriangleCollapseResult& result)
{
  std::vector<BatchEntry> rest;
  rest.swap(batch.Entries);
  for (const BatchEntry& entry : rest)
  {
    if (this->Blocked(entry.C.Triangle, passes))
    {
      continue;
    }
    batch.Entries.assign(1, entry);
    ++loop.Pops;
    if (!this->PassRound(loop, batch, passes, result))
    {
      return false;
    }
  }
  batch.Entries.clear();
  return true;
}

void TriangleCollapser::CollapseInPasses(CollapseLoop& loop, TriangleCollapseResult& result)
{
  PassState passes;
  CollapseBatch batch;
  batch.Passes = true;
  batch.Parallel = true;
  batch.PassesState = &passes;
  batch.Owner.assign(size_t(this->Mesh.NumberOfPoints()), ~std::uint64_t(0));
  // Each iteration collapses, or doubles the next goal rank (at most 63 times in a row, then the
  // ranking holds every candidate), or relaxes the limits (a few times): bounded, and by the work
  // bound on the ranked entries (loop.Pops).
  while (this->Mesh.NumberOfLiveTriangles() > loop.Target)
  {
    PhaseClock clock(loop.PhaseTotals());
    this->CostPass(passes);
    clock.Next();
    this->RankPass(loop, passes);
    clock.Next();
    ++result.Passes;
    const Index before = this->Mesh.NumberOfLiveTriangles();
    const bool more = this->RunPass(loop, batch, passes, result);
    clock.Next();
    vtkLogF(TRACE, "triangle collapse: pass %d, %lld -> %lld triangles, %lld of %lld candidates ranked (limit %g, floor %g, widened %d), %lld collapses",
      int(result.Passes), (long long)before, (long long)this->Mesh.NumberOfLiveTriangles(),
      (long long)passes.Ranking.Order.size(), (long long)passes.Ranking.Candidates, double(passes.Ranking.Limit),
      double(passes.Floor), passes.Widen, (long long)passes.Performed);
    if (!more)
    {
      break;
    }
    if (passes.Performed > 0 || !passes.Ranking.Everything)
    {
      passes.Widen = passes.Performed == 0 ? passes.Widen + 1 : 0;
      continue;
    }
    if (!this->LoosenLimits(loop, result))
    {
      break;
    }
    passes.AllStale = true;
  }
  for (auto it = batch.Scratch.begin(); it != batch.Scratch.end(); ++it)
  {
    ++result.PassThreads;
  }
  result.CostPassVisits = passes.Visits;
  for (long long tests : batch.WindowTests)
  {
    result.WindowTests += tests;
    result.WindowTestThreads += tests > 0 ? 1 : 0;
  }
  vtkLogF(TRACE, "triangle collapse: %d passes, %lld rounds; costs %.3f s, ranking %.3f s, rounds %.3f s; "
    "window fills tested %lld entries (%lld waited) on %d threads",
    int(result.Passes), passes.Rounds, loop.PhaseSeconds[0], loop.PhaseSeconds[1], loop.PhaseSeconds[2],
    result.WindowTests, result.WaitingEntries, result.WindowTestThreads);
}

void TriangleCollapser::TraceStatistics(const CollapseLoop& loop, const TriangleCollapseResult& result) const
{
  vtkLogF(TRACE, "triangle collapse: %d collapses, %d rejected, %lld placements replaced, %.2f pops per input triangle",
    int(result.Collapses), int(result.RejectedCollapses), loop.Replaced,
    double(loop.Pops) / std::max<Index>(1, loop.StartTriangles));
  const double collapses = std::max<Index>(1, result.Collapses);
  vtkLogF(TRACE, "triangle collapse: per collapse %.2f key updates (%lld), %.2f placements for them (%lld), "
    "%.4f validity tests (%lld)", double(result.KeyUpdates) / collapses, result.KeyUpdates,
    double(result.FanPlacements) / collapses, result.FanPlacements, double(result.ValidityTests) / collapses,
    result.ValidityTests);
  vtkLogF(TRACE, "triangle collapse: %lld of the validity tests answered by an earlier test of the same set since the last collapse (%.4f per collapse); %lld one-ring gathers (%.4f per collapse)",
    result.TopologyTestsReused, double(result.TopologyTestsReused) / collapses, result.OneRingGathers,
    double(result.OneRingGathers) / collapses);
  const double* phase = loop.PhaseSeconds;
  vtkLogF(TRACE, "triangle collapse: %lld batches, %.1f operations per batch (%.1f ran, %.1f placements not made, %.2f ring walks per operation); select %.3f s, evaluate %.3f s, apply %.3f s",
    loop.Batches, double(loop.Selected) / double(std::max<long long>(1, loop.Batches)),
    double(loop.Ran) / double(std::max<long long>(1, loop.Batches)),
    double(loop.PlacementsDeferred) / double(std::max<long long>(1, loop.Batches)),
    double(loop.RingWalks) / double(std::max<long long>(1, loop.Selected)), phase[0], phase[1], phase[2] + phase[3] + phase[4]);
  vtkLogF(TRACE, "triangle collapse: %lld batches popped alone (fewer than %d entries within the tolerance)",
    loop.LoneBatches, this->Options.BatchMinimumSize);
  vtkLogF(TRACE, "triangle collapse: %lld batches, %lld of %lld entries and %lld of %d collapses in steps shared by "
    "the threads (the rest on the calling thread whatever the thread count)", loop.SharedBatches, loop.SharedEntries,
    loop.Selected, loop.SharedCollapses, int(result.Collapses));
  vtkLogF(TRACE, "triangle collapse: %lld of %lld vertices searched for border edges (the caller's border flags %s)",
    result.BorderSearches, static_cast<long long>(this->Mesh.NumberOfPoints()), this->BorderFlagsGiven ? "given" : "not given");
  if (phase[3] > 0 || phase[4] > 0)
  {
    vtkLogF(TRACE, "triangle collapse: apply = sequential settle %.3f s + parallel collapses %.3f s + sequential queue updates %.3f s",
      phase[2], phase[3], phase[4]);
  }
  if (this->Options.LookAheadEvaluations > 1)
  {
    vtkLogF(TRACE,
      "triangle collapse: look-ahead evaluated %lld, taken by %lld pops, new keys taken by %lld collapses; "
      "%lld evaluated by the worker",
      result.LookAheadEvaluated, result.LookAheadTaken, result.LookAheadKeysTaken, result.LookAheadWorkerEvaluations);
  }
  for (int k = 1; k <= static_cast<int>(CollapseStatus::Locked); ++k)
  {
    vtkLogF(TRACE, "triangle collapse: rejected %s %lld", ToString(static_cast<CollapseStatus>(k)), loop.StatusCounts[k]);
  }
}

void TriangleCollapser::MoveTowardOriginal(const OriginalSurface& original, TriangleCollapseResult& result)
{
  Ancestry ancestry;
  this->BuildAncestry(original, ancestry);
  this->Stages.Lap("ancestry");
  result.PassesWorkingBytes = std::max(result.PassesWorkingBytes,
    this->WorkingBytes() +
      sizeof(Index) *
        (ancestry.AncestorStart.capacity() + ancestry.Ancestors.capacity() + ancestry.OriginalStart.capacity() +
          ancestry.OriginalTriangles.capacity()));
  if (this->Options.FitToOriginal)
  {
    result.FittedVertices = this->FitToOriginal(original, ancestry);
    result.FitThreads = this->FitThreads;
    result.FitBudgetReached = this->FitBudgetReached;
    result.FitVisits = this->FitVisits;
    this->Stages.Lap("fit to original");
  }
  if (this->Options.RefineDeviation)
  {
    result.RefinedVertices = this->RefineDeviation(original, ancestry);
    result.RefinementVisits = this->RefinementVisits;
    this->Stages.Lap("deviation refinement");
  }
  if (this->Options.RecordHistory && result.FittedVertices + result.RefinedVertices > 0)
  {
    this->StoreMovedPositions(result);
  }
}

void TriangleCollapser::Run(TriangleMesh& input, TriangleCollapseResult& result)
{
  result = TriangleCollapseResult();
  result.History.StoreSurrounding = true;
  this->Stages.Restart();
  const bool refine = (this->Options.RefineDeviation || this->Options.FitToOriginal) && !this->Options.ExactUnion;
  this->Prepare(input, refine);
  this->InitializeQuadrics();
  result.BorderSearches = this->BorderSearches;
  result.TrianglePlanes = this->TrianglePlanes;
  this->Stages.Lap("quadrics");
  this->PackInputIds();
  this->Stages.Lap("input ids packed");
  const bool passes = this->UsesPasses();
  if (passes)
  {
    this->InitializePasses();
  }
  else
  {
    this->InitializeQueue();
  }
  this->Stages.Lap("queue");
  // The working set peaks here or at the end (the queue is largest here; the references and the
  // history may grow in the loop).
  const size_t startBytes = this->WorkingBytes();
  this->TraceWorkingParts("at the loop's start");
  CollapseLoop loop;
  this->StartLoop(loop);
  if (passes)
  {
    this->CollapseInPasses(loop, result);
  }
  else
  {
    this->CollapseToTarget(loop, result);
  }
  result.PeakWorkingBytes = std::max(startBytes, this->WorkingBytes() + result.History.MemoryBytes());
  this->TraceWorkingParts("at the loop's end");
  const double perVertex = 1.0 / std::max<double>(1.0, double(this->Mesh.NumberOfPoints()));
  vtkLogF(TRACE,
    "triangle collapse: working bytes per input vertex %.1f (editable mesh %.1f, input kept %.1f, quadrics %.1f, "
    "queue %.1f, triangle state %.1f)",
    perVertex * double(result.PeakWorkingBytes), perVertex * double(this->Mesh.MemoryBytes()),
    perVertex * double(this->Original.MemoryBytes()),
    perVertex * double(this->Vertex.capacity() * sizeof(WeightedQuadric)), perVertex * double(this->Heap.MemoryBytes()),
    perVertex * double(this->State.capacity() * sizeof(TriangleState)));
  this->Stages.Lap("collapses");
  // The queue and the per-triangle state are done: free them so that the output reuses their
  // memory instead of raising the peak.
  this->Heap = decltype(this->Heap)(); // (before State, which holds its bucket numbers)
  std::vector<TriangleState>().swap(this->State);
  this->CompactQuadrics();
  if (refine && !result.Aborted && this->RestoreOriginal())
  {
    this->Stages.Lap("original unpacked");
    this->MoveTowardOriginal(this->Original, result);
  }
  this->Original.Release();
  this->UnpackInputIds();
  result.PassesWorkingBytes = std::max(result.PassesWorkingBytes, this->WorkingBytes());
  this->ExtractResult(result);
  this->Stages.Lap("extraction");
  result.KeyUpdates = this->KeyUpdates;
  result.FanPlacements = this->FanPlacements;
  result.SelectedEntries = loop.Selected;
  result.RanEntries = loop.Ran;
  result.PlacementsNotMade = loop.PlacementsDeferred;
  result.RingWalks = loop.RingWalks;
  result.OneRingGathers = loop.Gathers;
  result.BatchesPoppedAlone = loop.LoneBatches;
  result.SharedStepBatches = loop.SharedBatches;
  result.SharedStepEntries = loop.SharedEntries;
  result.SharedStepCollapses = loop.SharedCollapses;
  result.TopologyTestsReused = this->FailedSets.Reused;
  for (long long tests : loop.StatusCounts)
  {
    result.ValidityTests += tests;
  }
  this->TraceStatistics(loop, result);
}

bool TriangleCollapser::RestoreOriginal()
{
  if (!this->Options.ReloadInput)
  {
    this->Original.Unpack();
    return true;
  }
  this->UnpackInputIds(); // Reorder's maps (packed through the collapses)
  TriangleMesh input;
  this->Options.ReloadInput(input);
  const size_t nv = this->VertexInput.size(), nt = this->TriangleInput.size();
  if (size_t(input.NumberOfPoints()) != nv || size_t(input.NumberOfTriangles()) != nt)
  {
    vtkLogF(ERROR, "triangle collapse: the reloaded input has %lld points and %lld triangles, not %lld and %lld: "
      "the passes after the collapses are skipped", static_cast<long long>(input.NumberOfPoints()),
      static_cast<long long>(input.NumberOfTriangles()), static_cast<long long>(nv), static_cast<long long>(nt));
    return false;
  }
  // Prepare's reordered copy, from Reorder's maps: vertex i is input vertex VertexInput[i],
  // triangle t input triangle TriangleInput[t] with its corners renumbered in their order.
  // (On huge pages, as Reorder's arrays: the gathers below are random reads.)
  TriangleMesh reordered;
  AssignOnHugePages(reordered.Points, 3 * nv, 0.0);
  std::vector<Index> newId;
  AssignOnHugePages(newId, nv, Index(0));
  for (size_t i = 0; i < nv; ++i)
  {
    const Index v = this->VertexInput[i];
    newId[size_t(v)] = static_cast<Index>(i);
    std::copy(&input.Points[3 * size_t(v)], &input.Points[3 * size_t(v)] + 3, &reordered.Points[3 * i]);
  }
  std::vector<double>().swap(input.Points);
  AssignOnHugePages(reordered.Triangles, 3 * nt, Index(0));
  for (size_t t = 0; t < nt; ++t)
  {
    const Index* tri = input.Triangle(this->TriangleInput[t]);
    for (int k = 0; k < 3; ++k)
    {
      reordered.Triangles[3 * t + size_t(k)] = newId[size_t(tri[k])];
    }
  }
  std::vector<Index>().swap(input.Triangles);
  this->Original.Take(reordered);
  return true;
}

void TriangleCollapser::CompactQuadrics()
{
  // The passes after the collapses and the extraction read the quadrics of the surviving vertices
  // only (about a tenth at 90 %) and the parents of the others: hold those instead of a quadric
  // per input vertex, which was the largest array after the loop (88 bytes per input vertex).
  // The values are moved, not recomputed: the outputs do not change.
  const size_t nv = this->Vertex.size();
  if (this->Options.ExactUnion || nv != size_t(this->Mesh.NumberOfPoints()))
  {
    return; // (the exact union reads its plane sets, not these sums)
  }
  this->Link.resize(nv);
  size_t slot = 0;
  for (size_t v = 0; v < nv; ++v)
  {
    const double w = this->Vertex[v].W;
    if (w < 0)
    {
      this->Link[v] = static_cast<Index>(-1.0 - w);
    }
    else
    {
      this->Link[v] = -1 - static_cast<Index>(slot);
      this->Vertex[slot++] = this->Vertex[v]; // (slot <= v)
    }
  }
  this->Vertex.resize(slot);
  this->Vertex.shrink_to_fit();
}

void TriangleCollapser::BuildAncestry(const OriginalSurface& original, Ancestry& ancestry)
{
  const Index nv = original.NumberOfPoints(), nt = original.NumberOfTriangles();
  // Each original vertex's surviving vertex (path-compressed), then CSR lists.
  for (Index v = 0; v < nv; ++v)
  {
    Index r = v;
    while (this->ParentOf(r) != r)
    {
      r = this->ParentOf(r);
    }
    for (Index w = v; this->ParentOf(w) != r && w != r;)
    {
      const Index next = this->ParentOf(w);
      this->SetParent(w, r);
      w = next;
    }
  }
  // CSR lists (GroupByKey, in parallel with ParallelStages): each vertex's ancestors in id order,
  // each original vertex's triangles in id order.
  const bool parallel = this->Options.ParallelStages;
  std::vector<Index> count(static_cast<size_t>(nv), 0);
  ancestry.AncestorStart.resize(size_t(nv) + 1);
  ancestry.AncestorStart[nv] = GroupByKey(
    nv, nv, [this](Index v) { return this->ParentOf(v); }, [](Index v) { return v; }, ancestry.AncestorStart.data(),
    count.data(), ancestry.Ancestors, parallel);
  std::fill(count.begin(), count.end(), 0);
  ancestry.OriginalStart.resize(size_t(nv) + 1);
  ancestry.OriginalStart[nv] = GroupByKey(
    3 * nt, nv, [&original](Index i) { return original.Triangles[i]; }, [](Index i) { return i / 3; },
    ancestry.OriginalStart.data(), count.data(), ancestry.OriginalTriangles, parallel);
}

// The live triangles of an editable mesh as a TriangleMesh (all points kept, so vertex ids stay
// the editable mesh's), and the editable triangle id of each: what a BVH is built on.
void LiveTriangles(const EditableMesh& mesh, TriangleMesh& out, std::vector<Index>& toMesh)
{
  out.Points.resize(3 * size_t(mesh.NumberOfPoints()));
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    const Vec3 p = mesh.Point(v);
    std::copy(p.begin(), p.end(), &out.Points[3 * size_t(v)]);
  }
  out.Triangles.clear();
  toMesh.clear();
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    if (mesh.IsTriangleAlive(t))
    {
      const Index* tri = mesh.Triangle(t);
      out.Triangles.insert(out.Triangles.end(), tri, tri + 3);
      toMesh.push_back(t);
    }
  }
}

// The neighbourhood of one output vertex v in which the passes after the collapses work: v's
// fan, the triangles of its neighbours, the original vertices (and optionally the original
// triangle centroids) that descend into v and its neighbours, and those original triangles.
// Moving v changes only its fan, so each original sample's distance to the rest of the
// neighbourhood is computed once (Freeze) and a candidate position costs tests against the fan
// only; the original triangles carry bounding spheres that prune most point-triangle tests.
// A lower bound of the squared distance of q to triangle (a, b, c): to its bounding box, each gap
// shortened by far more than the rounding of a computed closest point, so that a triangle is never
// skipped where the exact test would find it at most as far as a bound.
inline double BoxGap2(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c)
{
  double gap2 = 0;
  for (int k = 0; k < 3; ++k)
  {
    const double ab = a[k] < b[k] ? a[k] : b[k], lo = ab < c[k] ? ab : c[k];
    const double ba = a[k] < b[k] ? b[k] : a[k], hi = ba < c[k] ? c[k] : ba;
    const double d = q[k] < lo ? lo - q[k] : (q[k] > hi ? q[k] - hi : 0.0);
    const double slack = 1e-12 * (std::abs(q[k]) + std::abs(lo) + std::abs(hi));
    gap2 += d > slack ? (d - slack) * (d - slack) : 0.0;
  }
  return gap2;
}

class Neighbourhood
{
public:
  Neighbourhood(const EditableMesh& mesh, const OriginalSurface& original, const Ancestry& ancestry)
    : Mesh(mesh)
    , Original(original)
    , Lineage(ancestry)
  {
  }

  Vec3 OriginalPoint(Index v) const { return this->Original.Point(v); }

  // v and its fan only (what the fit's step needs).
  void GatherFan(Index v)
  {
    this->Center = v;
    this->Fan.clear();
    this->Mesh.ForEachTriangle(v, [&](Index t) { this->Fan.push_back(t); });
  }

  // The whole neighbourhood of v.
  void Gather(Index v, bool withCentroids)
  {
    this->GatherFan(v);
    this->GatherRest(withCentroids);
  }

  // v's distinct neighbours in the order EditableMesh::Neighbors lists them, without its shared
  // marks (a fan is small), so that neighbourhoods can be gathered concurrently.
  void GatherRing()
  {
    this->Ring.clear();
    for (Index t : this->Fan)
    {
      const Index* tri = this->Mesh.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        if (tri[k] != this->Center && std::find(this->Ring.begin(), this->Ring.end(), tri[k]) == this->Ring.end())
        {
          this->Ring.push_back(tri[k]);
        }
      }
    }
  }

  // The rest of the neighbourhood of the vertex of GatherFan.
  void GatherRest(bool withCentroids)
  {
    const Index v = this->Center;
    this->GatherRing();
    this->Ring.push_back(v);
    this->Near.clear();
    this->OriginalNear.clear();
    this->Samples.clear();
    this->SampleIsCentroid.clear();
    for (Index w : this->Ring)
    {
      if (w == v)
      {
        this->OwnSamplesBegin = this->Samples.size();
      }
      if (w != v)
      {
        this->Mesh.ForEachTriangle(w, [&](Index t) {
          const Index* tri = this->Mesh.Triangle(t);
          if (tri[0] != v && tri[1] != v && tri[2] != v)
          {
            this->Near.push_back(t);
          }
        });
      }
      for (Index i = this->Lineage.AncestorStart[w]; i < this->Lineage.AncestorStart[w + 1]; ++i)
      {
        const Index a = this->Lineage.Ancestors[i];
        this->Samples.push_back(this->OriginalPoint(a));
        this->SampleIsCentroid.push_back(0);
        this->OriginalNear.insert(this->OriginalNear.end(), this->Lineage.OriginalTriangles.begin() + this->Lineage.OriginalStart[a],
          this->Lineage.OriginalTriangles.begin() + this->Lineage.OriginalStart[a + 1]);
      }
    }
    this->OwnSamplesEnd = this->Samples.size();
    std::sort(this->Near.begin(), this->Near.end());
    this->Near.erase(std::unique(this->Near.begin(), this->Near.end()), this->Near.end());
    std::sort(this->OriginalNear.begin(), this->OriginalNear.end());
    this->OriginalNear.erase(std::unique(this->OriginalNear.begin(), this->OriginalNear.end()), this->OriginalNear.end());
    this->SphereCenter.clear();
    this->SphereRadius.clear();
    for (Index o : this->OriginalNear)
    {
      const Index* ot = &this->Original.Triangles[3 * size_t(o)];
      const Vec3 x = this->OriginalPoint(ot[0]), y = this->OriginalPoint(ot[1]), z = this->OriginalPoint(ot[2]);
      const Vec3 c = (1.0 / 3) * (x + y + z);
      this->SphereCenter.push_back(c);
      this->SphereRadius.push_back(std::sqrt(std::max({ Dot(x - c, x - c), Dot(y - c, y - c), Dot(z - c, z - c) })));
      if (withCentroids)
      {
        this->Samples.push_back(c);
        this->SampleIsCentroid.push_back(1);
      }
    }
  }

  // Each sample's distance to the triangles that do not touch v (they stay where they are).
  void Freeze()
  {
    this->RestDistance2.resize(this->Samples.size());
    this->RestClosest.resize(this->Samples.size());
    for (size_t i = 0; i < this->Samples.size(); ++i)
    {
      Index ignored;
      this->RestDistance2[i] = this->ToMesh(this->Samples[i], this->Near, this->RestClosest[i], ignored);
    }
  }

  // Squared distance of sample i to the neighbourhood with v where it is now; `which` is the
  // closest fan triangle, or InvalidIndex when the closest point is off the fan.
  double SampleDistance2(size_t i, Vec3& closest, Index& which) const
  {
    // Only a fan triangle at most as far as the rest can be the answer (ties go to the fan).
    const double d2 = this->ToMesh(this->Samples[i], this->Fan, closest, which, this->RestDistance2[i]);
    if (which == InvalidIndex || this->RestDistance2[i] < d2)
    {
      closest = this->RestClosest[i];
      which = InvalidIndex;
      return this->RestDistance2[i];
    }
    return d2;
  }

  // Squared distance of q to the closest of tris (and which one, InvalidIndex when none is closer
  // than `bound`). A triangle whose bounding box lies farther than the best so far cannot win and
  // is not measured: the same answer as measuring all, at a fraction of the cost. The budgets
  // count every triangle of the list, so they stop the passes where they always did.
  double ToMesh(const Vec3& q, const std::vector<Index>& tris, Vec3& closest, Index& which,
    double bound = std::numeric_limits<double>::max()) const
  {
    this->Work += tris.size();
    double best = bound;
    which = InvalidIndex;
    for (Index t : tris)
    {
      const Index* tri = this->Mesh.Triangle(t);
      const Vec3 a = this->Mesh.Point(tri[0]), b = this->Mesh.Point(tri[1]), e = this->Mesh.Point(tri[2]);
      if (BoxGap2(q, a, b, e) > best)
      {
        continue;
      }
      const Vec3 c = ClosestPointOnTriangle(q, a, b, e);
      const Vec3 d = q - c;
      const double d2 = Dot(d, d);
      // The first at most as far as the bound, then only strictly closer ones.
      if (which == InvalidIndex ? d2 <= best : d2 < best)
      {
        best = d2;
        closest = c;
        which = t;
      }
    }
    return best;
  }

  // Squared distance of q to the original triangles of the neighbourhood (and which one).
  double ToOriginal(const Vec3& q, Vec3& closest) const
  {
    Index ignored;
    return this->ToOriginal(q, closest, ignored);
  }
  double ToOriginal(const Vec3& q, Vec3& closest, Index& which) const
  {
    which = InvalidIndex;
    double best = std::numeric_limits<double>::max(), reach = std::numeric_limits<double>::max();
    for (size_t i = 0; i < this->OriginalNear.size(); ++i)
    {
      // Skip triangles whose bounding sphere lies farther than the best so far: |q - c| >= r +
      // sqrt(best), tested on squares (no root per triangle).
      const Vec3 d = q - this->SphereCenter[i];
      const double gap = this->SphereRadius[i] + reach;
      if (Dot(d, d) >= gap * gap)
      {
        continue;
      }
      ++this->Work;
      const Index* ot = &this->Original.Triangles[3 * size_t(this->OriginalNear[i])];
      const Vec3 c = ClosestPointOnTriangle(q, this->OriginalPoint(ot[0]), this->OriginalPoint(ot[1]), this->OriginalPoint(ot[2]));
      const Vec3 e = q - c;
      const double d2 = Dot(e, e);
      if (d2 < best)
      {
        best = d2;
        reach = std::sqrt(d2);
        closest = c;
        which = this->OriginalNear[i];
      }
    }
    return best;
  }

  // Per fan triangle, whether it faces the same way as the original triangle closest to its
  // centroid (a move must not turn a triangle against the surface it stands for).
  void Facing(std::vector<unsigned char>& out) const
  {
    out.clear();
    for (Index t : this->Fan)
    {
      const Index* tri = this->Mesh.Triangle(t);
      const Vec3 x = this->Mesh.Point(tri[0]), y = this->Mesh.Point(tri[1]), z = this->Mesh.Point(tri[2]);
      Vec3 closest;
      Index o;
      this->ToOriginal((1.0 / 3) * (x + y + z), closest, o);
      unsigned char facing = 1;
      if (o != InvalidIndex)
      {
        const Index* ot = &this->Original.Triangles[3 * size_t(o)];
        const Vec3 a = this->OriginalPoint(ot[0]);
        facing = Dot(Cross(y - x, z - x), Cross(this->OriginalPoint(ot[1]) - a, this->OriginalPoint(ot[2]) - a)) > 0;
      }
      out.push_back(facing);
    }
  }

  // v's barycentric weight at point c of its fan triangle t (0 when t is not v's).
  double WeightOfCenter(Index t, const Vec3& c) const
  {
    if (t == InvalidIndex)
    {
      return 0.0;
    }
    const Index* tri = this->Mesh.Triangle(t);
    const int k = tri[0] == this->Center ? 0 : (tri[1] == this->Center ? 1 : (tri[2] == this->Center ? 2 : -1));
    if (k < 0)
    {
      return 0.0;
    }
    const Vec3 p = this->Mesh.Point(this->Center);
    const Vec3 x = this->Mesh.Point(tri[(k + 1) % 3]), y = this->Mesh.Point(tri[(k + 2) % 3]);
    const Vec3 n = Cross(x - p, y - p);
    const double nn = Dot(n, n);
    return nn > 0 ? Dot(Cross(x - c, y - c), n) / nn : 0.0;
  }

  // Whether no fan triangle turned by more than the limit since `Normals` were taken.
  void TakeNormals()
  {
    this->StartNormal.clear();
    for (Index t : this->Fan)
    {
      this->StartNormal.push_back(this->Mesh.TriangleNormal(t));
    }
  }
  bool FanTurnsWithin(double minimumDot) const
  {
    for (size_t i = 0; i < this->Fan.size(); ++i)
    {
      const Index* tri = this->Mesh.Triangle(this->Fan[i]);
      const Vec3 n = Cross(this->Mesh.Point(tri[1]) - this->Mesh.Point(tri[0]), this->Mesh.Point(tri[2]) - this->Mesh.Point(tri[0]));
      const double length = Norm(n);
      if (!(length > 0) || Dot(n, this->StartNormal[i]) < minimumDot * length)
      {
        return false;
      }
    }
    return true;
  }

  // The fan's own samples (v, then per triangle points at thirds), and v's weight at each.
  template <typename Functor>
  void ForEachFanSample(Functor&& f) const
  {
    const Vec3 p = this->Mesh.Point(this->Center);
    f(p, 1.0);
    const double third = 1.0 / 3;
    for (Index t : this->Fan)
    {
      const Index* tri = this->Mesh.Triangle(t);
      const int k = tri[0] == this->Center ? 0 : (tri[1] == this->Center ? 1 : 2);
      const Vec3 x = this->Mesh.Point(tri[(k + 1) % 3]), y = this->Mesh.Point(tri[(k + 2) % 3]);
      f((2 * third) * p + third * x, 2 * third);
      f(third * p + (2 * third) * x, third);
      f(third * (p + x + y), third);
    }
  }

  const EditableMesh& Mesh;
  const OriginalSurface& Original;
  const Ancestry& Lineage;
  Index Center = InvalidIndex;
  size_t OwnSamplesBegin = 0, OwnSamplesEnd = 0; // v's own original vertices among the samples
  std::vector<Index> Fan, Ring, Near, OriginalNear;
  std::vector<Vec3> Samples, RestClosest, SphereCenter, StartNormal;
  std::vector<unsigned char> SampleIsCentroid;
  std::vector<double> RestDistance2, SphereRadius;
  mutable size_t Work = 0;
};
// Which original vertices a move of an output vertex can take farther away: per output triangle,
// the original vertices whose closest output point lies on it (CSR), when computed exactly.
struct ClosestAssignment
{
  bool Exact = false;
  std::vector<Index> Start, Members;
};

// What a move of one vertex must not make worse (see TriangleCollapser::WatchMove).
struct MoveGuard
{
  std::vector<Vec3> Watched;         // original points whose distance the move may raise
  std::vector<double> WatchedBefore; // and their squared distances before it
  std::vector<double> FanBefore;     // squared distances of the fan's samples to the original
  double Before = 0.0;               // the reliable local maximum (squared)
  double FanMaximum = 0.0;           // the largest of FanBefore
  std::vector<unsigned char> FacingBefore, FacingAfter;
};

std::vector<std::pair<double, Index>> TriangleCollapser::FitOrder(const Ancestry& ancestry) const
{
  // Merged interior vertices, the largest quadric error first.
  std::vector<std::pair<double, Index>> order;
  const Index nv = static_cast<Index>(ancestry.AncestorStart.size()) - 1;
  for (Index v = 0; v < nv; ++v)
  {
    if (ancestry.AncestorStart[v + 1] - ancestry.AncestorStart[v] >= 2 && !this->Boundary[v] && !this->IsPinned(v) &&
      this->Mesh.IsVertexAlive(v))
    {
      const WeightedQuadric& q = this->QuadricOf(v);
      order.emplace_back(q.W > 0 ? q.Q.Evaluate(this->Local(v)) / q.W : 0.0, v);
    }
  }
  std::sort(order.begin(), order.end(), WorseFirst);
  return order;
}

void TriangleCollapser::AssignClosest(const OriginalSurface& original, ClosestAssignment& assignment) const
{
  const Index nv = original.NumberOfPoints();
  TriangleMesh live;
  std::vector<Index> liveToMesh;
  LiveTriangles(this->Mesh, live, liveToMesh);
  const TriangleBVH tree(live);
  std::vector<Index> closestTriangle(static_cast<size_t>(nv));
  // One independent query per original vertex (the tree is read-only): in parallel, the same
  // assignment for any thread count. Each query starts from the squared distance to the vertex it
  // merged into (ParentOf, compressed by BuildAncestry), a point of the mesh: the search then skips
  // every box farther than that and finds the same triangle as an unbounded one (the boxes of the
  // closest triangles are never skipped, and the others keep their order). The margin covers
  // rounding; a query that finds nothing within the bound (the vertex is not on a live
  // triangle) is asked again without one.
  const double margin = 1e-18 * this->Diagonal * this->Diagonal;
  vtkSMPTools::For(0, nv, 1024, [&](vtkIdType begin, vtkIdType end) {
    for (Index a = static_cast<Index>(begin); a < static_cast<Index>(end); ++a)
    {
      const Vec3 q = original.Point(a);
      const Vec3 d = q - this->Mesh.Point(this->ParentOf(a));
      ClosestPointResult closest = tree.ClosestPoint(q, 1.0001 * Dot(d, d) + margin);
      if (closest.Triangle == InvalidIndex)
      {
        closest = tree.ClosestPoint(q);
      }
      closestTriangle[a] = liveToMesh[closest.Triangle];
    }
  });
  auto& start = assignment.Start;
  start.assign(size_t(this->Mesh.NumberOfTriangles()) + 1, 0);
  for (Index a = 0; a < nv; ++a)
  {
    ++start[closestTriangle[a] + 1];
  }
  for (size_t t = 0; t + 1 < start.size(); ++t)
  {
    start[t + 1] += start[t];
  }
  assignment.Members.resize(static_cast<size_t>(nv));
  std::vector<Index> fill(start.begin(), start.end() - 1);
  for (Index a = 0; a < nv; ++a)
  {
    assignment.Members[fill[closestTriangle[a]]++] = a;
  }
}

bool TriangleCollapser::FitStep(
  const Neighbourhood& region, const OriginalSurface& original, const Ancestry& ancestry, Index v, Vec3& step) const
{
  // Least squares of the distances, along the output normals, of the original surface that v
  // stands for (its original vertices weighted by a third of their triangles' area, and the
  // centroids of the original triangles whose first corner merged into v, so that each
  // original triangle counts once) as a function of v's displacement d with the closest points
  // held: a sample at barycentric weight b of v moves by b * d.
  Quadric fit;
  double trace = 0, residual2 = 0, weightSum = 0;
  auto addSample = [&](const Vec3& q, double weight) {
    Vec3 closest;
    Index which;
    region.ToMesh(q, region.Fan, closest, which);
    const double b = region.WeightOfCenter(which, closest);
    if (b > 0.05)
    {
      const Vec3 u = this->Mesh.TriangleNormal(which);
      fit += Quadric::FromPlane(b * u, -Dot(u, q - closest), weight);
      trace += weight * b * b;
      residual2 += weight * Dot(u, q - closest) * Dot(u, q - closest);
      weightSum += weight;
    }
  };
  for (Index i = ancestry.AncestorStart[v]; i < ancestry.AncestorStart[v + 1]; ++i)
  {
    const Index a = ancestry.Ancestors[i];
    double around = 0;
    for (Index j = ancestry.OriginalStart[a]; j < ancestry.OriginalStart[a + 1]; ++j)
    {
      const Index* ot = &original.Triangles[3 * size_t(ancestry.OriginalTriangles[j])];
      const Vec3 x = region.OriginalPoint(ot[0]), y = region.OriginalPoint(ot[1]), z = region.OriginalPoint(ot[2]);
      const double area = 0.5 * Norm(Cross(y - x, z - x));
      around += area;
      if (ot[0] == a)
      {
        addSample((1.0 / 3) * (x + y + z), area);
      }
    }
    addSample(region.OriginalPoint(a), around / 3);
  }
  // The tangential directions are free when the samples' normals agree: a small ridge term
  // keeps v where it is along them.
  const double ridge = FitRidge * trace;
  fit.Axx += ridge;
  fit.Ayy += ridge;
  fit.Azz += ridge;
  // Steps below 1 % of the RMS residual are not worth their check.
  return trace > 0 && fit.Minimize(step, 1e-12) && !(Dot(step, step) * weightSum < 1e-4 * residual2);
}

void TriangleCollapser::WatchMove(Neighbourhood& region, const ClosestAssignment& assignment, MoveGuard& guard) const
{
  // What the move can make worse, both ways: the original vertices whose closest point is on
  // v's fan (any other keeps or lowers its distance), and the fan's own samples against the
  // original triangles of the neighbourhood. Values measured over a neighbourhood only can
  // overestimate (the true closest part lies farther away): each may grow only up to a
  // reliable local maximum, never up to another inflated value.
  region.GatherRest(false);
  guard.Watched.clear();
  guard.WatchedBefore.clear();
  guard.Before = 0;
  auto watch = [&](const Vec3& q, double d2) {
    guard.Watched.push_back(q);
    guard.WatchedBefore.push_back(d2);
  };
  if (assignment.Exact)
  {
    for (Index t : region.Fan)
    {
      for (Index k = assignment.Start[t]; k < assignment.Start[t + 1]; ++k)
      {
        const Vec3 q = region.OriginalPoint(assignment.Members[k]);
        Vec3 closest;
        Index which;
        const double d2 = region.ToMesh(q, region.Fan, closest, which);
        watch(q, d2);
        guard.Before = std::max(guard.Before, d2);
      }
    }
  }
  else
  {
    // The reliable maximum: v's own original vertices (their closest parts are around v).
    region.Freeze();
    for (size_t i = 0; i < region.Samples.size(); ++i)
    {
      Vec3 closest;
      Index which;
      const double d2 = region.SampleDistance2(i, closest, which);
      if (which != InvalidIndex)
      {
        watch(region.Samples[i], d2);
      }
      if (i >= region.OwnSamplesBegin && i < region.OwnSamplesEnd)
      {
        guard.Before = std::max(guard.Before, d2);
      }
    }
  }
  guard.FanBefore.clear();
  region.ForEachFanSample([&](const Vec3& q, double) {
    Vec3 closest;
    guard.FanBefore.push_back(region.ToOriginal(q, closest));
  });
  // The fan's own points may not rise above the fan's largest distance either: the output
  // side is measured at samples only, and the original side's maximum says nothing of it.
  guard.FanMaximum = *std::max_element(guard.FanBefore.begin(), guard.FanBefore.end());
  region.TakeNormals();
  region.Facing(guard.FacingBefore);
}

bool TriangleCollapser::MoveKeepsBounds(
  const Neighbourhood& region, Index v, double reach, double minimumDot, MoveGuard& guard) const
{
  bool lower = region.FanTurnsWithin(minimumDot) && this->WithinMaximumError(v);
  if (lower)
  {
    region.Facing(guard.FacingAfter);
    for (size_t i = 0; i < guard.FacingAfter.size() && lower; ++i)
    {
      lower = guard.FacingAfter[i] >= guard.FacingBefore[i];
    }
  }
  // A point of the fan at weight w of v moves by w * |d|, so no distance changes by more:
  // only the values that could cross their limit are measured again.
  auto mayCross = [&](double before2, double limit2, double weight) {
    const double bound = std::sqrt(before2) + weight * reach;
    return bound * bound > limit2;
  };
  for (size_t k = 0; k < guard.Watched.size() && lower; ++k)
  {
    const double limit = std::max(guard.Before, guard.WatchedBefore[k]);
    if (mayCross(guard.WatchedBefore[k], limit, 1.0))
    {
      Vec3 closest;
      Index which;
      region.ToMesh(guard.Watched[k], region.Fan, closest, which, limit);
      lower = which != InvalidIndex; // a fan triangle within the limit
    }
  }
  size_t sample = 0;
  region.ForEachFanSample([&](const Vec3& q, double weight) {
    const double limit = std::max(guard.FanBefore[sample], std::min(guard.Before, guard.FanMaximum));
    if (lower && mayCross(guard.FanBefore[sample], limit, weight))
    {
      Vec3 closest;
      lower = region.ToOriginal(q, closest) <= limit;
    }
    ++sample;
  });
  return lower;
}

// A sweep of the passes after the collapses over vertices in a given order, each vertex visited
// with a neighbourhood that it alone moves (see SweepChunk): the sequential walk's neighbourhood,
// whose Work is the pass's test count, and one per thread for the concurrent visits.
struct TriangleCollapser::ChunkedSweep
{
  struct Worker
  {
    Worker(const EditableMesh& mesh, const OriginalSurface& original, const Ancestry& ancestry)
      : Region(mesh, original, ancestry)
    {
    }
    Neighbourhood Region;
    MoveGuard Guard;
  };
  // Per member of the current chunk: visited concurrently, where it started, whether it moved,
  // the tests it took and its ring.
  struct Outcome
  {
    bool Concurrent = false, Moved = false;
    Vec3 Start{};
    size_t Work = 0;
    std::vector<Index> Ring;
  };
  ChunkedSweep(const EditableMesh& mesh, const OriginalSurface& original, const Ancestry& ancestry, size_t workBudget)
    : Original(original)
    , Lineage(ancestry)
    , Main(mesh, original, ancestry)
    , WorkBudget(workBudget)
    , ChunkMark(size_t(original.NumberOfPoints()), 0)
  {
  }
  size_t Work() const { return this->Main.Region.Work; }
  bool WithinBudget() const { return this->Main.Region.Work <= this->WorkBudget; }
  const OriginalSurface& Original;
  const Ancestry& Lineage;
  Worker Main;
  size_t WorkBudget;
  vtkSMPThreadLocal<std::shared_ptr<Worker>> Workers;
  std::vector<std::uint32_t> ChunkMark; // per vertex: its mark in the chunk it was last a member of
  std::uint32_t MarkBase = 0;           // marks up to this are of earlier chunks
  std::vector<int> Level;               // per member of the current chunk: its step (SweepLevel)
  std::vector<Outcome> Outcomes;
  SweepCounts Counts; // diagnostics
};

bool TriangleCollapser::FitVertex(
  Neighbourhood& region, MoveGuard& guard, const ClosestAssignment& assignment, Index v, double minimumDot)
{
  // The step of v's least-squares fit, then the move (full, then half) if it keeps the bounds.
  region.GatherFan(v);
  const Vec3 p = this->Mesh.Point(v);
  Vec3 step;
  if (!this->FitStep(region, region.Original, region.Lineage, v, step))
  {
    return false;
  }
  this->WatchMove(region, assignment, guard);
  for (double s : { 1.0, 0.5 })
  {
    this->Mesh.SetPoint(v, p + s * step);
    if (this->MoveKeepsBounds(region, v, s * Norm(step), minimumDot, guard))
    {
      return true;
    }
    this->Mesh.SetPoint(v, p);
  }
  return false;
}

int TriangleCollapser::SweepLevel(Index v, const ChunkedSweep& sweep, std::uint32_t base, std::uint32_t own) const
{
  // One more than the largest level of the chunk's members before v (marks base + 1 .. own - 1)
  // within two edges of v, 0 without any: v reads what they move, so it is visited after them.
  int level = 0;
  this->Mesh.ForEachTriangle(v, [&](Index t) {
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      this->Mesh.ForEachTriangle(tri[k], [&](Index s) {
        const Index* around = this->Mesh.Triangle(s);
        for (int j = 0; j < 3; ++j)
        {
          const std::uint32_t mark = sweep.ChunkMark[around[j]];
          if (around[j] != v && mark > base && mark < own)
          {
            level = std::max(level, sweep.Level[mark - base - 1] + 1);
          }
        }
      });
    }
  });
  return level;
}

// Visits the chunk's vertices as one sequential sweep in their order would: visit(worker, v)
// reads positions within two edges of v only, moves only v and returns whether it did; it may
// stop early when its worker's Work passes the budget. Speculation that cannot be wrong: the
// members are visited concurrently level by level (SweepLevel), each with its worker's Work set
// to the sweep's count at the start of the chunk. Two members of one level are more than two
// edges apart, and each sees the earlier members near it moved (lower levels) and the later ones
// at their start (higher levels), as the sequential sweep would. The walk in order then takes a
// result when the budget held all along (the sweep's count at its turn plus its own tests), since
// its budget checks passed either way; the first result it cannot take, and everything after it,
// is visited again in order from the start positions. onMoved(v, ring) in order. The same moves,
// test counts and stop for any thread count. (Before session 20 only the members with no other
// member within two edges were concurrent: mc1m's refinement 28 of 151 visits, now all.)
template <typename Visit, typename OnMoved>
void TriangleCollapser::SweepChunk(ChunkedSweep& sweep, const std::vector<Index>& chunk, Visit&& visit, OnMoved&& onMoved)
{
  // Member i is marked base + 1 + i: its rank in the chunk, and marks of earlier chunks are <= base.
  const std::uint32_t size = static_cast<std::uint32_t>(chunk.size());
  if (sweep.MarkBase > std::numeric_limits<std::uint32_t>::max() - 2 * size - 2)
  {
    std::fill(sweep.ChunkMark.begin(), sweep.ChunkMark.end(), 0u);
    sweep.MarkBase = 0;
  }
  const std::uint32_t base = sweep.MarkBase;
  sweep.MarkBase += size + 1;
  sweep.Outcomes.resize(chunk.size());
  sweep.Level.assign(chunk.size(), 0);
  int levels = 0;
  for (std::uint32_t i = 0; i < size && size > 1; ++i)
  {
    sweep.ChunkMark[chunk[i]] = base + 1 + i;
    sweep.Level[i] = this->SweepLevel(chunk[i], sweep, base, base + 1 + i);
    levels = std::max(levels, sweep.Level[i] + 1);
  }
  for (std::uint32_t i = 0; i < size; ++i)
  {
    sweep.Outcomes[i].Start = this->Mesh.Point(chunk[i]);
    sweep.Outcomes[i].Concurrent = size > 1;
  }
  const size_t startWork = sweep.Work();
  for (int level = 0; level < levels; ++level)
  {
    vtkSMPTools::For(0, static_cast<vtkIdType>(size), 1, [&](vtkIdType begin, vtkIdType end) {
      std::shared_ptr<ChunkedSweep::Worker>& worker = sweep.Workers.Local();
      if (!worker)
      {
        worker = std::make_shared<ChunkedSweep::Worker>(this->Mesh, sweep.Original, sweep.Lineage);
      }
      for (vtkIdType i = begin; i < end; ++i)
      {
        if (sweep.Level[size_t(i)] == level)
        {
          ChunkedSweep::Outcome& outcome = sweep.Outcomes[size_t(i)];
          worker->Region.Work = startWork;
          outcome.Moved = visit(*worker, chunk[size_t(i)]);
          outcome.Work = worker->Region.Work - startWork;
          outcome.Ring = worker->Region.Ring;
        }
      }
    });
  }
  bool inOrder = false; // a result was not taken: the rest of the chunk is visited in order
  for (size_t i = 0; i < chunk.size(); ++i)
  {
    ChunkedSweep::Outcome& outcome = sweep.Outcomes[i];
    const Index v = chunk[i];
    if (!sweep.WithinBudget())
    {
      // The sweep stops here: the concurrent moves past this point are undone.
      for (size_t j = i; j < chunk.size(); ++j)
      {
        this->Mesh.SetPoint(chunk[j], sweep.Outcomes[j].Start);
      }
      return;
    }
    ++sweep.Counts.Visits;
    sweep.Counts.AfterEarlier += sweep.Level[i] > 0 ? 1 : 0;
    if (!inOrder && outcome.Concurrent && sweep.Work() + outcome.Work <= sweep.WorkBudget)
    {
      sweep.Main.Region.Work += outcome.Work;
    }
    else
    {
      ++sweep.Counts.InOrder;
      for (size_t j = i; j < chunk.size() && !inOrder; ++j)
      {
        this->Mesh.SetPoint(chunk[j], sweep.Outcomes[j].Start);
      }
      inOrder = true;
      outcome.Moved = visit(sweep.Main, v);
      outcome.Ring = sweep.Main.Region.Ring;
    }
    if (outcome.Moved)
    {
      onMoved(v, outcome.Ring);
    }
  }
}

Index TriangleCollapser::FitToOriginal(const OriginalSurface& original, const Ancestry& ancestry)
{
  const Index nv = original.NumberOfPoints(), nt = original.NumberOfTriangles();
  if (nv == 0 || this->Mesh.NumberOfLiveTriangles() == 0)
  {
    return 0;
  }
  const double minimumDot = NormalLimitDot(this->Options.MaximumNormalDeviation);
  // Point-triangle tests: the pass stops at its budget, the worst vertices first.
  ChunkedSweep sweep(this->Mesh, original, ancestry, FitBudget.For(nt));
  const std::vector<std::pair<double, Index>> order = this->FitOrder(ancestry);
  // Which original vertices a move of v can take farther away: those whose closest output
  // point is on v's fan. Exactly, from a closest-triangle assignment of every original vertex
  // (a BVH query each) when the input is small enough for that to be cheap; otherwise among the
  // original vertices of v's neighbourhood (an ancestor can be closest to a triangle farther
  // away, mostly after topology changes, so this misses a few).
  ClosestAssignment assignment;
  assignment.Exact = nv <= this->Options.FitExactAssignmentLimit;
  if (assignment.Exact)
  {
    this->AssignClosest(original, assignment);
  }
  std::vector<unsigned char> moved(size_t(nv), 0);
  std::vector<unsigned char> dirty, nowDirty(size_t(nv), 0);
  std::vector<Index> chunk;
  auto fit = [&](ChunkedSweep::Worker& worker, Index v) {
    return this->FitVertex(worker.Region, worker.Guard, assignment, v, minimumDot);
  };
  auto mark = [&](Index v, const std::vector<Index>& ring) {
    moved[v] = 1;
    nowDirty[v] = 1;
    for (Index w : ring)
    {
      nowDirty[w] = 1;
    }
  };
  for (int iteration = 0; iteration < FitIterations && sweep.WithinBudget(); ++iteration)
  {
    dirty.swap(nowDirty);
    nowDirty.assign(size_t(nv), 0);
    for (size_t next = 0; next < order.size() && sweep.WithinBudget();)
    {
      // The next vertices in order (after the first sweep only where something moved nearby:
      // the rest would not move).
      chunk.clear();
      for (; next < order.size() && chunk.size() < SweepChunkSize; ++next)
      {
        const Index v = order[next].second;
        if (iteration == 0 || dirty[v])
        {
          chunk.push_back(v);
        }
      }
      this->SweepChunk(sweep, chunk, fit, mark);
    }
  }
  this->FitThreads = 0;
  for (auto it = sweep.Workers.begin(); it != sweep.Workers.end(); ++it)
  {
    this->FitThreads += *it ? 1 : 0;
  }
  this->FitBudgetReached = !sweep.WithinBudget();
  vtkLogF(TRACE, "triangle collapse: fit to original: %zu point-triangle tests (%.1f per input triangle), %zu of %zu vertex fits concurrent",
    sweep.Work(), double(sweep.Work()) / std::max<Index>(nt, 1), size_t(sweep.Counts.Visits - sweep.Counts.InOrder),
    size_t(sweep.Counts.Visits));
  this->FitVisits = sweep.Counts;
  return static_cast<Index>(std::count(moved.begin(), moved.end(), 1));
}

std::vector<std::pair<double, Index>> TriangleCollapser::RefinementPool(const Ancestry& ancestry) const
{
  // Candidates: the merged interior vertices with the largest quadric error (RMS distance to
  // their original planes), a small fraction of the output; only they are screened.
  const Index nv = static_cast<Index>(ancestry.AncestorStart.size()) - 1;
  const Index live = this->Mesh.NumberOfLiveVertices();
  std::vector<std::pair<double, Index>> pool;
  for (Index v = 0; v < nv; ++v)
  {
    if (ancestry.AncestorStart[v + 1] - ancestry.AncestorStart[v] >= 2 && this->Mesh.IsVertexAlive(v) && !this->Boundary[v] &&
      !this->IsPinned(v))
    {
      const WeightedQuadric& q = this->QuadricOf(v);
      pool.emplace_back(q.W > 0 ? q.Q.Evaluate(this->Local(v)) / q.W : 0.0, v);
    }
  }
  const size_t poolSize = std::min(pool.size(), std::min<size_t>(RefinementPoolLimit, 64 + live / 10));
  std::partial_sort(pool.begin(), pool.begin() + poolSize, pool.end(), WorseFirst);
  pool.resize(poolSize);
  return pool;
}

double TriangleCollapser::ScreenDeviation(Neighbourhood& region, const std::vector<std::pair<double, Index>>& pool,
  size_t workBudget, std::vector<std::pair<double, Index>>& screen) const
{
  // Each candidate is screened on its own (read-only, its own neighbourhood and test count), so
  // chunks of the pool run in parallel with a neighbourhood per thread; the budget is then
  // applied in pool order exactly as one sweep would apply it (the same screen for any thread
  // count), and a chunk past the budget is the only work wasted.
  screen.clear();
  double worst = 0;
  std::vector<double> deviation;
  std::vector<size_t> work;
  vtkSMPThreadLocal<std::shared_ptr<Neighbourhood>> regions;
  for (size_t first = 0; first < pool.size() && region.Work <= workBudget; first += ScreenChunk)
  {
    const size_t n = std::min(ScreenChunk, pool.size() - first);
    deviation.assign(n, 0.0);
    work.assign(n, 0);
    vtkSMPTools::For(0, static_cast<vtkIdType>(n), 4, [&](vtkIdType begin, vtkIdType end) {
      std::shared_ptr<Neighbourhood>& local = regions.Local();
      if (!local)
      {
        local = std::make_shared<Neighbourhood>(this->Mesh, region.Original, region.Lineage);
      }
      for (vtkIdType i = begin; i < end; ++i)
      {
        const size_t before = local->Work;
        deviation[size_t(i)] = this->ScreenVertex(*local, pool[first + size_t(i)].second);
        work[size_t(i)] = local->Work - before;
      }
    });
    for (size_t i = 0; i < n && region.Work <= workBudget; ++i)
    {
      region.Work += work[i];
      screen.emplace_back(deviation[i], pool[first + i].second);
      worst = std::max(worst, deviation[i]);
    }
  }
  return worst;
}

double TriangleCollapser::ScreenVertex(Neighbourhood& region, Index v) const
{
  // The local deviation both ways, v's own original vertices against the neighbourhood and v's
  // fan against the neighbourhood's original triangles (v's own fan and ancestry alone
  // overestimate, by 10x on smooth surfaces at 1 %: an original vertex can lie beyond v's fan,
  // and a fan point's closest original part can be a neighbour's).
  region.Gather(v, false);
  double e = 0;
  Vec3 closest;
  Index which;
  for (size_t i = region.OwnSamplesBegin; i < region.OwnSamplesEnd; ++i)
  {
    const double toFan = region.ToMesh(region.Samples[i], region.Fan, closest, which);
    e = std::max(e, region.ToMesh(region.Samples[i], region.Near, closest, which, toFan));
  }
  region.ForEachFanSample([&](const Vec3& q, double) { e = std::max(e, region.ToOriginal(q, closest)); });
  return e;
}

double TriangleCollapser::LocalDeviation(const Neighbourhood& region, Index v, const Vec3& p, Vec3& step, double& sum)
{
  // The local maximum distance with v at p, and a direction that lowers the worst term (the
  // correction of v that would bring the worst point onto the other surface).
  this->Mesh.SetPoint(v, p);
  double best = -1;
  sum = 0;
  for (size_t i = 0; i < region.Samples.size(); ++i)
  {
    Vec3 closest;
    Index which;
    const double d2 = region.SampleDistance2(i, closest, which);
    sum += std::sqrt(d2);
    if (d2 > best)
    {
      best = d2;
      // v's weight at the closest point (rough for centroids and off-fan points: the line
      // search tries shorter steps too).
      const double weight = region.SampleIsCentroid[i] ? 3.0 : (which == InvalidIndex ? 0.3 : std::max(0.2, region.WeightOfCenter(which, closest)));
      step = (1.0 / weight) * (region.Samples[i] - closest);
    }
  }
  region.ForEachFanSample([&](const Vec3& q, double weight) {
    Vec3 closest;
    const double d2 = region.ToOriginal(q, closest);
    sum += std::sqrt(d2);
    if (d2 > best)
    {
      best = d2;
      step = (1.0 / weight) * (closest - q);
    }
  });
  return best;
}

bool TriangleCollapser::RefineVertex(Neighbourhood& region, Index v, double minimumDot, size_t workBudget)
{
  // The region whose distances v changes (see Neighbourhood), with the original triangle
  // centroids as samples of the original surface's interior.
  region.Gather(v, true);
  region.Freeze();
  region.TakeNormals();
  const Vec3 start = this->Mesh.Point(v);
  Vec3 current = start, step;
  double startSum = 0, sum = 0;
  double value = this->LocalDeviation(region, v, current, step, startSum);
  // A line search along the direction of the worst term, a few steps.
  for (int iteration = 0; iteration < 6 && region.Work <= workBudget; ++iteration)
  {
    const Vec3 direction = step;
    Vec3 bestPoint = current, ignored;
    double bestValue = value;
    for (double s : { 1.0, 0.75, 0.5, 0.25, 0.125 })
    {
      const Vec3 p = current + s * direction;
      this->Mesh.SetPoint(v, p);
      if (!region.FanTurnsWithin(minimumDot) || !this->WithinMaximumError(v))
      {
        continue;
      }
      const double candidate = this->LocalDeviation(region, v, p, ignored, sum);
      // The mean distance must not pay for the maximum: the local sum may grow only a little.
      if (candidate < bestValue && sum <= RefinementSumSlack * startSum)
      {
        bestValue = candidate;
        bestPoint = p;
      }
    }
    if (!(bestValue < value * (1.0 - 1e-3)))
    {
      break;
    }
    current = bestPoint;
    value = this->LocalDeviation(region, v, current, step, sum);
  }
  this->Mesh.SetPoint(v, current);
  return !(current == start);
}

void TriangleCollapser::PoolAroundMoved(
  const std::vector<Index>& movedVertices, const Ancestry& ancestry, std::vector<std::pair<double, Index>>& pool) const
{
  // The next round screens only where this one moved something (the rest is unchanged).
  std::vector<Index> next, ring;
  for (Index v : movedVertices)
  {
    next.push_back(v);
    this->Mesh.Neighbors(v, ring);
    next.insert(next.end(), ring.begin(), ring.end());
  }
  std::sort(next.begin(), next.end());
  next.erase(std::unique(next.begin(), next.end()), next.end());
  pool.clear();
  for (Index v : next)
  {
    if (ancestry.AncestorStart[v + 1] - ancestry.AncestorStart[v] >= 2 && !this->Boundary[v] && !this->IsPinned(v))
    {
      pool.emplace_back(0.0, v);
    }
  }
}

Index TriangleCollapser::RefineDeviation(const OriginalSurface& original, const Ancestry& ancestry)
{
  const Index nv = original.NumberOfPoints(), nt = original.NumberOfTriangles();
  if (nv == 0 || this->Mesh.NumberOfLiveTriangles() == 0)
  {
    return 0;
  }
  // Point-triangle tests: the pass stops at a budget proportional to the input, because a
  // region's cost grows with the reduction (ancestors x triangles).
  const size_t workBudget = RefinementBudget.For(nt);
  const double minimumDot = NormalLimitDot(this->Options.MaximumNormalDeviation);
  // Only a few of the worst regions: the pass must stay cheap next to the collapses.
  const size_t budget = static_cast<size_t>(16 + this->Mesh.NumberOfLiveVertices() / 2000);
  ChunkedSweep sweep(this->Mesh, original, ancestry, workBudget);
  Neighbourhood& region = sweep.Main.Region; // its Work counts the screening and the moves
  auto refine = [&](ChunkedSweep::Worker& worker, Index v) {
    return this->RefineVertex(worker.Region, v, minimumDot, workBudget);
  };
  std::vector<Index> movedVertices, chunk;
  auto keep = [&](Index v, const std::vector<Index>&) { movedVertices.push_back(v); };
  std::vector<std::pair<double, Index>> screen;
  std::vector<std::pair<double, Index>> pool = this->RefinementPool(ancestry);
  Index moved = 0;
  for (int round = 0; round < RefinementRounds; ++round)
  {
    const double worst = this->ScreenDeviation(region, pool, workBudget, screen);
    if (screen.empty() || worst <= 0)
    {
      break;
    }
    const size_t count = std::min(budget, screen.size());
    std::partial_sort(screen.begin(), screen.begin() + count, screen.end(), WorseFirst);
    for (size_t c = 0; c < count && screen[c].first >= 0.5 * worst && sweep.WithinBudget();)
    {
      chunk.clear();
      for (; c < count && screen[c].first >= 0.5 * worst && chunk.size() < SweepChunkSize; ++c)
      {
        chunk.push_back(screen[c].second);
      }
      this->SweepChunk(sweep, chunk, refine, keep);
    }
    if (movedVertices.empty())
    {
      break;
    }
    moved += static_cast<Index>(movedVertices.size());
    this->PoolAroundMoved(movedVertices, ancestry, pool);
    movedVertices.clear();
  }
  vtkLogF(TRACE, "triangle collapse: deviation refinement: %d vertex moves, %zu point-triangle tests (%.1f per input triangle), %zu of %zu vertex refinements concurrent",
    int(moved), region.Work, double(region.Work) / std::max<Index>(nt, 1), size_t(sweep.Counts.Visits - sweep.Counts.InOrder),
    size_t(sweep.Counts.Visits));
  this->RefinementVisits = sweep.Counts;
  return moved;
}

void TriangleCollapser::StoreMovedPositions(TriangleCollapseResult& result)
{
  // Records store input ids; re-collapsing to this level must give this mesh. Only merged
  // vertices move, so each has a last collapse that placed it.
  const Index nv = this->Mesh.NumberOfPoints();
  auto& h = result.History;
  std::vector<Index> inputToMesh(size_t(nv), InvalidIndex);
  for (Index v = 0; v < nv; ++v)
  {
    inputToMesh[this->VertexInput[v]] = v;
  }
  std::vector<unsigned char> seen(size_t(nv), 0);
  for (Index k = h.NumberOfCollapses() - 1; k >= 0; --k)
  {
    const Index v = inputToMesh[h.Vertices[3 * size_t(k)]];
    if (seen[v])
    {
      continue;
    }
    seen[v] = 1;
    if (this->Mesh.IsVertexAlive(v))
    {
      const Vec3 p = this->Mesh.Point(v);
      std::copy(p.begin(), p.end(), &h.NewPositions[3 * size_t(k)]);
    }
  }
}

void TriangleCollapser::ExtractResult(TriangleCollapseResult& result)
{
  const Index nv = this->Mesh.NumberOfPoints();
  const Index nt = this->Mesh.NumberOfTriangles();
  std::vector<Index> oldToNew(size_t(nv), InvalidIndex);
  TriangleMesh& out = result.Mesh;
  out.Points.clear();
  out.Triangles.clear();
  out.Triangles.reserve(3 * size_t(this->Mesh.NumberOfLiveTriangles()));
  result.OutputToInput.clear();
  result.OutputTriangleIds.clear();
  for (Index t = 0; t < nt; ++t)
  {
    if (!this->Mesh.IsTriangleAlive(t))
    {
      continue;
    }
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index v = tri[k];
      if (oldToNew[v] == InvalidIndex)
      {
        oldToNew[v] = out.AddPoint(this->Mesh.Point(v));
        result.OutputToInput.push_back(this->VertexInput[v]);
      }
      out.Triangles.push_back(oldToNew[v]);
    }
    result.OutputTriangleIds.push_back(this->TriangleInput[t]);
  }
  result.VertexError.resize(result.OutputToInput.size());
  std::vector<Index> newToOld(result.OutputToInput.size());
  for (Index v = 0; v < nv; ++v)
  {
    if (oldToNew[v] != InvalidIndex)
    {
      newToOld[oldToNew[v]] = v;
    }
  }
  for (size_t i = 0; i < result.OutputToInput.size(); ++i)
  {
    const Index v = newToOld[i];
    const Vec3 p = this->Local(v);
    double q = 0, w = 0;
    if (this->Options.ExactUnion)
    {
      for (Index id : this->LogicalSet[v])
      {
        q += this->PlaneQuadric[id].Evaluate(p);
        w += this->PlaneWeight[id];
      }
    }
    else
    {
      q = this->QuadricOf(v).Q.Evaluate(p);
      w = this->QuadricOf(v).W;
    }
    result.VertexError[i] = w > 0 ? std::sqrt(q / w) : 0.0;
    // The fit and the refinement move vertices after their collapse: the final error is the
    // largest of the output's.
    result.MaximumError = std::max(result.MaximumError, result.VertexError[i]);
  }
  this->StoreAttributeValues(newToOld, result);
}
} // namespace

void SimplifyByTriangleCollapse(TriangleMesh& mesh, const TriangleCollapseOptions& options,
  TriangleCollapseResult& result, PointAttributes* attributes)
{
  TriangleCollapser collapser(options, attributes);
  collapser.Run(mesh, result);
}
} // namespace slod
