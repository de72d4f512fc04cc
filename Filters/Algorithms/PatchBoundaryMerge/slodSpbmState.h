// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD patch boundary merge (internal, not installed): the working state
// of one SPBM level and the constants and small helpers that its stages share
// (slodPatchBoundaryMerge.cxx: chain hierarchy, triangulation and target
// search; slodSpbmMerging.cxx: the merging run).
#ifndef slodSpbmState_h
#define slodSpbmState_h

#include "slodIndexedHeap.h"
#include "slodPatchBoundaryMerge.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace slod
{
namespace spbm
{
using StageClock = std::chrono::steady_clock;
inline double Since(StageClock::time_point start)
{
  return std::chrono::duration<double>(StageClock::now() - start).count();
}
// Runs task(0), ..., task(n - 1) as independent vtkSMPTools work items, so that they can run on
// different threads (one after the other with the Sequential backend). The tasks must not wait
// for each other.
template<typename Task>
void RunTasks(int n, Task&& task)
{
  vtkSMPTools::For(0, vtkIdType(n), 1, [&](vtkIdType first, vtkIdType last) {
    for (vtkIdType i = first; i < last; ++i)
    {
      task(int(i));
    }
  });
}
// Support directions of the flatness measure: the 3 axes, 6 face and 4 body
// diagonals, both signs (a 26-DOP). A patch keeps its extreme vertex in each;
// the thickness of a union along any normal is then estimated from those 26 +
// 26 points.
inline constexpr int SupportDirections = 13;
inline constexpr int SupportSize = 2 * SupportDirections;
inline const double SupportAxes[SupportDirections][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 0 },
  { 1, -1, 0 }, { 1, 0, 1 }, { 1, 0, -1 }, { 0, 1, 1 }, { 0, 1, -1 }, { 1, 1, 1 }, { 1, 1, -1 }, { 1, -1, 1 },
  { -1, 1, 1 } };
inline constexpr float InfiniteKey = std::numeric_limits<float>::infinity();
// Fallback levels of a patch that could not be triangulated: 1 unmerged, 2..5
// its chains with epsilon / 4^(level-1), 6 full resolution, 7 its original
// triangles.
inline constexpr int FullResolutionLevel = 6;
inline constexpr int OriginalLevel = 7;
// Chain tolerance at a fallback level below FullResolutionLevel: levels 2.. divide epsilon by 4 each.
inline float FallbackTolerance(float epsilon, int level)
{
  return level >= 2 ? epsilon * std::pow(0.25f, float(level - 1)) : epsilon;
}
// Longer patch boundaries are not checked for simplicity while merging (left to
// the fallback).
inline constexpr Index MaximumCheckedBoundary = 1 << 16;
// Patches with at most this many boundary vertices redo the walks over all their chains after
// every change of the patch (collapse tries, merge candidates); larger ones only once their
// boundary has grown by half since the last walk. Without the bound, a patch that absorbs n small
// ones walks its n chains after each merge and retries every collapse (each a check of its whole
// boundary): cubic in the patch size, which rough surfaces reach (real scan isosurfaces).
inline constexpr Index FullRetryBoundary = 64;

inline double PointSegmentDistance2(const Vec3& p, const Vec3& a, const Vec3& b)
{
  const Vec3 ab = b - a;
  const Vec3 ap = p - a;
  const double len2 = Dot(ab, ab);
  double t = len2 > 0 ? Dot(ap, ab) / len2 : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  const Vec3 d = ap - t * ab;
  return Dot(d, d);
}

// Squared deviation of p from segment ab as the surface sees it: the offset's
// components along the two adjacent patch normals (an offset within both patch
// planes moves the surface little), but at least lambda times the full offset.
inline double SurfaceWeightedDistance2(
  const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& n1, const Vec3& n2, double lambda2)
{
  const Vec3 ab = b - a;
  const double len2 = Dot(ab, ab);
  const double t = len2 > 0 ? std::max(0.0, std::min(1.0, Dot(p - a, ab) / len2)) : 0.0;
  const Vec3 d = p - (a + t * ab);
  const double x = Dot(d, n1), y = Dot(d, n2);
  return std::max(std::max(x * x, y * y), lambda2 * Dot(d, d));
}

// Scratch of ProjectsToSimplePolygon, kept in the working state (it runs for
// every merge and collapse candidate).
struct PolygonScratch
{
  std::vector<std::array<double, 2>> Projected;
  std::vector<size_t> Order;
};

// True when the closed polygon, projected on the plane orthogonal to `normal`,
// is simple and counter-clockwise (the condition for a valid ear-clipping
// triangulation without flips). With `changed` set, the polygon is known to
// have been simple before vertex `changed` moved or its neighbour was removed:
// only the segments at `changed` are tested against the others (O(n)).
bool ProjectsToSimplePolygon(
  const std::vector<Vec3>& polygon, const Vec3& normal, PolygonScratch& scratch, size_t changed = size_t(-1));

// Open-addressing map from undirected edges to a small value (the chain that
// owns the edge, or a negative tag). One flat array, no per-element allocation.
// Optionally (TrackVertices) a 64-bit filter per vertex: bit h(b) of a's word is set when an
// edge a-b is inserted (never cleared by Erase, so it is a superset), and a lookup whose bits
// are not both set is answered without probing the table. The level's triangulation asks for
// every pair of a patch's polygon corners (EdgeContext, the minimum-deviation diagonals, the
// refinement), almost all of them absent; on large rough surfaces the table is hundreds of MB
// and each probe a cache miss, while a polygon's filter words stay in cache.
class EdgeMap
{
public:
  void Reset(size_t expected)
  {
    size_t capacity = 64;
    while (capacity < 2 * expected + 64)
    {
      capacity <<= 1;
    }
    this->Keys.assign(capacity, Empty);
    this->Values.resize(capacity);
    this->Count = 0;
    std::fill(this->VertexBits.begin(), this->VertexBits.end(), 0);
  }
  // Enables the per-vertex filter for vertex ids below `vertices` (larger ids always probe).
  // Call before Reset or on an empty map: edges inserted before are not in the filter.
  void TrackVertices(size_t vertices)
  {
    if (this->VertexBits.size() != vertices)
    {
      this->VertexBits.assign(vertices, 0);
    }
  }
  // False only when no edge a-b was inserted since the last Reset (TrackVertices on).
  bool MayContain(Index a, Index b) const
  {
    const size_t n = this->VertexBits.size();
    if (size_t(a) >= n || size_t(b) >= n)
    {
      return true;
    }
    return ((this->VertexBits[size_t(a)] >> VertexBit(b)) & (this->VertexBits[size_t(b)] >> VertexBit(a)) & 1u) != 0;
  }
  // Inserts (a,b) -> value; when present returns false and leaves `existing`
  // with its value.
  bool Insert(Index a, Index b, Index value, Index& existing)
  {
    if (2 * (this->Count + 1) > this->Keys.size())
    {
      this->Grow();
    }
    const uint64_t key = Key(a, b);
    size_t slot = this->Slot(key);
    while (this->Keys[slot] != Empty)
    {
      if (this->Keys[slot] == key)
      {
        existing = this->Values[slot];
        return false;
      }
      slot = (slot + 1) & (this->Keys.size() - 1);
    }
    this->Keys[slot] = key;
    this->Values[slot] = value;
    ++this->Count;
    this->NoteVertices(a, b);
    return true;
  }
  bool Contains(Index a, Index b) const
  {
    Index ignored;
    return this->Find(a, b, ignored);
  }
  // Starts loading the first slot an Insert of a-b will probe, so that a caller with other work
  // before the Insert (a diagonal's distance query) does not wait for the table's cache miss.
  void PrefetchSlot(Index a, Index b) const
  {
#if defined(__GNUC__)
    if (!this->Keys.empty())
    {
      __builtin_prefetch(this->Keys.data() + this->Slot(Key(a, b)), 1);
    }
#else
    (void)a;
    (void)b;
#endif
  }
  // Value of (a,b) in `value` when present.
  bool Find(Index a, Index b, Index& value) const
  {
    if (this->Keys.empty() || !this->MayContain(a, b))
    {
      return false;
    }
    const uint64_t key = Key(a, b);
    size_t slot = this->Slot(key);
    while (this->Keys[slot] != Empty)
    {
      if (this->Keys[slot] == key)
      {
        value = this->Values[slot];
        return true;
      }
      slot = (slot + 1) & (this->Keys.size() - 1);
    }
    return false;
  }
  // Removes (a,b); false when absent. Backward-shift deletion: the entries after it in its probe
  // run move up, so lookups never need tombstones.
  bool Erase(Index a, Index b)
  {
    if (this->Keys.empty())
    {
      return false;
    }
    const size_t mask = this->Keys.size() - 1;
    const uint64_t key = Key(a, b);
    size_t hole = this->Slot(key);
    while (this->Keys[hole] != key)
    {
      if (this->Keys[hole] == Empty)
      {
        return false;
      }
      hole = (hole + 1) & mask;
    }
    for (size_t next = (hole + 1) & mask; this->Keys[next] != Empty; next = (next + 1) & mask)
    {
      // The entry at `next` may fill the hole when the hole lies between its home slot and it.
      if (((next - this->Slot(this->Keys[next])) & mask) >= ((next - hole) & mask))
      {
        this->Keys[hole] = this->Keys[next];
        this->Values[hole] = this->Values[next];
        hole = next;
      }
    }
    this->Keys[hole] = Empty;
    --this->Count;
    return true;
  }
  size_t MemoryUsage() const
  {
    return this->Keys.capacity() * 8 + this->Values.capacity() * sizeof(Index) + this->VertexBits.capacity() * 8;
  }

private:
  static constexpr uint64_t Empty = ~uint64_t(0);
  static unsigned VertexBit(Index v) { return (uint32_t(v) * 0x9E3779B1u) >> 26; }
  void NoteVertices(Index a, Index b)
  {
    const size_t n = this->VertexBits.size();
    if (size_t(a) < n && size_t(b) < n)
    {
      this->VertexBits[size_t(a)] |= uint64_t(1) << VertexBit(b);
      this->VertexBits[size_t(b)] |= uint64_t(1) << VertexBit(a);
    }
  }
  static uint64_t Key(Index a, Index b)
  {
    if (a > b)
    {
      std::swap(a, b);
    }
    return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
  }
  size_t Slot(uint64_t key) const { return size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & (this->Keys.size() - 1); }
  void Grow()
  {
    std::vector<uint64_t> keys;
    std::vector<Index> values;
    keys.swap(this->Keys);
    values.swap(this->Values);
    // The filter words already hold every key moved below: kept aside, not cleared and set again.
    std::vector<uint64_t> bits;
    bits.swap(this->VertexBits);
    this->Reset(keys.size());
    Index ignored;
    for (size_t i = 0; i < keys.size(); ++i)
    {
      if (keys[i] != Empty)
      {
        this->Insert(Index(keys[i] >> 32), Index(keys[i] & 0xffffffffu), values[i], ignored);
      }
    }
    bits.swap(this->VertexBits);
  }
  std::vector<uint64_t> Keys;
  std::vector<Index> Values;
  std::vector<uint64_t> VertexBits; // TrackVertices: per vertex, bits of its neighbours' hashes
  size_t Count = 0;
};
// Outcomes of a yes/no test remembered by a 64-bit key (RefineNonSimplePatches: whether the boundary
// of a given signature projects to a simple polygon). One flat open-addressing array, no per-entry
// allocation; the outcome sits in the key's lowest bit, so keys are compared on their upper
// bits (62 of the key's). Past `limit` entries it starts empty again (its memory stays bounded; what it forgot is
// tested again).
class KeyedOutcomes
{
public:
  void Clear()
  {
    this->Slots.clear();
    this->Count = 0;
  }
  // 1 or 0: the outcome stored for `key`; -1: none.
  int Find(uint64_t key) const
  {
    if (this->Slots.empty())
    {
      return -1;
    }
    const uint64_t k = Stored(key);
    for (size_t slot = this->Home(k);; slot = (slot + 1) & (this->Slots.size() - 1))
    {
      if (this->Slots[slot] == 0)
      {
        return -1;
      }
      if ((this->Slots[slot] | 1) == k)
      {
        return int(this->Slots[slot] & 1);
      }
    }
  }
  // Stores (or overwrites) the outcome of `key`.
  void Insert(uint64_t key, bool outcome, size_t limit)
  {
    if (this->Count >= limit)
    {
      this->Clear();
    }
    if (2 * (this->Count + 1) > this->Slots.size())
    {
      this->Grow();
    }
    const uint64_t k = Stored(key);
    size_t slot = this->Home(k);
    while (this->Slots[slot] != 0 && (this->Slots[slot] | 1) != k)
    {
      slot = (slot + 1) & (this->Slots.size() - 1);
    }
    this->Count += this->Slots[slot] == 0;
    this->Slots[slot] = outcome ? k : k - 1;
  }
  size_t MemoryUsage() const { return this->Slots.capacity() * sizeof(uint64_t); }

private:
  // The key with its two lowest bits set: the outcome clears the lowest or not, and the slot is
  // never 0 (the empty slot) either way.
  static uint64_t Stored(uint64_t key) { return key | 3; }
  size_t Home(uint64_t k) const { return size_t((k * 0x9E3779B97F4A7C15ull) >> 17) & (this->Slots.size() - 1); }
  void Grow()
  {
    std::vector<uint64_t> old;
    old.swap(this->Slots);
    this->Slots.assign(std::max<size_t>(1024, 2 * old.size()), 0);
    for (const uint64_t stored : old)
    {
      if (stored != 0)
      {
        size_t slot = this->Home(stored | 3);
        while (this->Slots[slot] != 0)
        {
          slot = (slot + 1) & (this->Slots.size() - 1);
        }
        this->Slots[slot] = stored;
      }
    }
  }
  std::vector<uint64_t> Slots;
  size_t Count = 0;
};
// One field of an array of records, indexed as an array of its own (see State). Holds a reference
// to the records: the state that owns both is never copied or moved.
template<typename Record, typename T, T Record::*Member>
class FieldView
{
public:
  explicit FieldView(std::vector<Record>& records)
    : Records(records)
  {
  }
  FieldView(const FieldView&) = delete;
  FieldView& operator=(const FieldView&) = delete;
  T& operator[](size_t i) { return this->Records[i].*Member; }
  const T& operator[](size_t i) const { return this->Records[i].*Member; }

private:
  std::vector<Record>& Records;
};
} // namespace spbm

// Working state of one level: the chain graph after simplification, merging and
// collapses. Chains keep their Patchification ids; patch and endpoint
// memberships are intrusive linked lists of "slots" (2c = left side / start
// end, 2c+1 = right side / end end) so merges and collapses splice in O(1) plus
// one walk.
struct SpbmLevelGenerator::State
{
  StageTimes Times;
  // The fields that the merging run's steps read together are stored together (one record per
  // chain, per original chain as a part, per patch), and seen through views with the indexing of
  // separate arrays (s.A[c] is Chains[c].A). On the real scan isosurfaces the merging run makes
  // about a million small edits whose steps read scattered memory; separate arrays cost one cache
  // miss per field and step.
  struct alignas(32) ChainRecord
  {
    Index A, B, L, R; // endpoints, left and right patch (R: InvalidIndex on the border)
    Index Interior;   // kept interior vertices
    Index PartFirst, PartLast; // joined chains: list of original chains
    unsigned char Alive, Locked;
  };
  struct alignas(16) PartRecord // per original chain as a part of a (joined) chain
  {
    Index KeptOffsets, KeptEnd, PartNext;
    unsigned char PartReversed;
  };
  struct alignas(64) PatchRecord
  {
    Index Parent, PatchHead, Size, Version;
    Vec3 Normal;
    Vec3 UnitNormal; // Normalized(Normal) of every root patch (merge measures, costs)
  };
  static_assert(sizeof(ChainRecord) == 32 && sizeof(PartRecord) == 16 && sizeof(PatchRecord) == 64,
    "one record per cache line or less, never across two");
  std::vector<ChainRecord> Chains;
  std::vector<PartRecord> Parts;
  std::vector<PatchRecord> Patches;
  // The chains' locking, copied out of the records (kept with the edits or the refined tolerances).
  void LockedInto(std::vector<unsigned char>& locked) const
  {
    locked.resize(this->Chains.size());
    for (size_t c = 0; c < this->Chains.size(); ++c)
    {
      locked[c] = this->Chains[c].Locked;
    }
  }
  void LockedFrom(const std::vector<unsigned char>& locked)
  {
    for (size_t c = 0; c < this->Chains.size(); ++c)
    {
      this->Chains[c].Locked = locked[c];
    }
  }
  spbm::FieldView<ChainRecord, Index, &ChainRecord::A> A{ Chains };
  spbm::FieldView<ChainRecord, Index, &ChainRecord::B> B{ Chains };
  spbm::FieldView<ChainRecord, Index, &ChainRecord::L> L{ Chains };
  spbm::FieldView<ChainRecord, Index, &ChainRecord::R> R{ Chains };
  spbm::FieldView<ChainRecord, Index, &ChainRecord::Interior> Interior{ Chains };
  std::vector<float> Tolerance; // per chain: epsilon, finer next to refined (frozen) patches
  // Per chain: its kept interior positions, ascending, at KeptPositions[KeptOffsets[c],
  // KeptEnd[c]); from KeptOffsets[c] there is room for all its interior vertices, so a chain is
  // rebuilt alone. KeptTolerance / KeptLocked: the
  // tolerance and locking its positions were made for (KeptFor: sized to the chain count when
  // they are valid, cleared when the chain hierarchy changes). Merging runs, refinement rounds
  // and fallback passes rebuild only the chains whose tolerance or locking changed.
  spbm::FieldView<PartRecord, Index, &PartRecord::KeptOffsets> KeptOffsets{ Parts };
  spbm::FieldView<PartRecord, Index, &PartRecord::KeptEnd> KeptEnd{ Parts };
  std::vector<Index> KeptPositions;
  std::vector<float> KeptTolerance;
  std::vector<unsigned char> KeptLocked;
  // Chain tolerances after refining non-simple patches, for the last epsilon
  // (no fallbacks).
  bool RefinedValid = false;
  float RefinedEpsilon = 0;
  std::vector<float> RefinedTolerance;
  std::vector<unsigned char> RefinedLocked;
  spbm::FieldView<ChainRecord, unsigned char, &ChainRecord::Alive> Alive{ Chains };
  spbm::FieldView<ChainRecord, unsigned char, &ChainRecord::Locked> Locked{ Chains };
  spbm::FieldView<ChainRecord, Index, &ChainRecord::PartFirst> PartFirst{ Chains };
  spbm::FieldView<ChainRecord, Index, &ChainRecord::PartLast> PartLast{ Chains };
  spbm::FieldView<PartRecord, Index, &PartRecord::PartNext> PartNext{ Parts };
  std::vector<Index> JointBefore; // endpoint between a part and the previous one
  spbm::FieldView<PartRecord, unsigned char, &PartRecord::PartReversed> PartReversed{ Parts };
  // Endpoints.
  std::vector<Index> EndHead, EndSlotNext, Degree;
  // Patches (union-find over original patches).
  spbm::FieldView<PatchRecord, Index, &PatchRecord::Parent> Parent{ Patches };
  spbm::FieldView<PatchRecord, Index, &PatchRecord::PatchHead> PatchHead{ Patches };
  spbm::FieldView<PatchRecord, Index, &PatchRecord::Size> Size{ Patches };
  spbm::FieldView<PatchRecord, Index, &PatchRecord::Version> Version{ Patches };
  std::vector<Index> PatchSlotNext;
  // Per chain: the patch versions of its last failed collapse (TriedP, TriedQ) and merge
  // (MergeTriedP, MergeTriedQ), read together.
  struct alignas(16) TriedRecord
  {
    Index TriedP, TriedQ, MergeTriedP, MergeTriedQ;
  };
  std::vector<TriedRecord> Tries;
  spbm::FieldView<TriedRecord, Index, &TriedRecord::TriedP> TriedP{ Tries };
  spbm::FieldView<TriedRecord, Index, &TriedRecord::TriedQ> TriedQ{ Tries };
  spbm::FieldView<TriedRecord, Index, &TriedRecord::MergeTriedP> MergeTriedP{ Tries };
  spbm::FieldView<TriedRecord, Index, &TriedRecord::MergeTriedQ> MergeTriedQ{ Tries };
  // Per root patch: its boundary size when all its chains last tried to collapse / were requeued
  // as merge candidates (a large patch redoes either only once it has grown by half).
  std::vector<Index> CollapsesWalkedSize, CandidatesPushedSize;
  spbm::FieldView<PatchRecord, Vec3, &PatchRecord::Normal> Normal{ Patches };
  spbm::FieldView<PatchRecord, Vec3, &PatchRecord::UnitNormal> UnitNormal{ Patches };
  std::vector<Index> Support; // FlatnessMerge: per root patch, its extreme
                              // vertices (SupportSize)
  // The patches each patch absorbed, in the order of the unions (first, next, last), and the last
  // of them folded into its Support. A replayed pass applies its clean unions without uniting the
  // supports (most of them are never read again); a support is brought up to date when read, by
  // folding in the patches absorbed since, in the same order (MergingRun::FoldSupport): the same
  // extreme vertices as uniting them at each union.
  std::vector<Index> AbsorbedFirst, AbsorbedNext, AbsorbedLast, SupportFolded;
  // The patches whose Support entry a union or fold wrote since it was last reset to the
  // patchification's (flagged per patch, listed once), and which build of the generator's
  // PatchSupport it holds: a run or replay resets those entries only, not the whole array (26
  // entries per input patch: on a 4M-triangle scan about 100 MB per replay, for the few thousand
  // patches a late replay unites).
  std::vector<Index> SupportWritten;
  std::vector<unsigned char> SupportWrittenFlag;
  long long SupportBuild = -1;
  std::vector<unsigned char> Frozen;
  long long Total = 0;
  // Scratch.
  std::vector<Index> PatchStamp, EndStamp, EndLocal, VertexStamp;
  Index Stamp = 0;
  IndexedHeap<double> MergeQueue; // merge candidates (chains) by minus their merge measure
  spbm::PolygonScratch SimplePolygonScratch;
  std::vector<unsigned char> NoFreeze;
  // Generation buffers.
  std::vector<Index> SeqOffsets, SeqVertices;
  std::vector<unsigned char> SeqKeep;
  spbm::EdgeMap Edges;
  // Minimum-deviation triangulation: distance of each diagonal (vertex pair)
  // from the input, as float bits. It depends on the two original vertices
  // only, so it is kept across the levels and candidates of one chain hierarchy
  // (most patches recur between them).
  spbm::EdgeMap DiagonalCosts;
  std::vector<uint64_t> SimpleSignature; // per patch: boundary signature last
                                         // found simple (0: none)
  // Every boundary RefineNonSimplePatches tested, simple or not, by its signature and patch: a
  // replay resets the chain graph and refines from scratch, and without it each replay with patches
  // at finer fallback levels tested again every boundary that is not simple and those of their
  // neighbours (a patch's boundary alternates between the signatures of its rounds, and
  // SimpleSignature holds one). Cleared with SimpleSignature.
  spbm::KeyedOutcomes BoundaryOutcomes;
  long long BoundariesTested = -1; // by the last RefineNonSimplePatches (work counter; -1: reused)
  std::vector<PredictionMemo> Memo;      // predicted counts of the levels asked for (searches repeat them)
  // The edits of the run that made the chain graph above, in order (unions, collapses, joins;
  // the removal stage's from EditsRemovalBegin on), and the chain tolerances it started from: a
  // fallback pass that unmerges a few patches replays them instead of a new merging run
  // (SpbmLevelGenerator::ReplayMerging).
  struct Edit
  {
    unsigned char Kind;
    Index V[7];
  };
  std::vector<Edit> Edits;
  // A replay reads the old record while it writes the new one: the two buffers trade places
  // (Replay), so that no replay grows a record from empty again. Above glibc's mmap threshold
  // (32 MB: a 4M-triangle scan's record) each growth was a fresh mapping faulted in page by page.
  std::vector<Edit> EditsSpare;
  // The merging runs' removal queue (one per operation: 2 per chain and 1 per endpoint), kept
  // with the state for the same reason: each run and replay reset it within its capacity.
  IndexedHeap<double> RemovalQueue;
  // Merging runs and replays of this state whose edit record outgrew its buffer, and resets of the
  // removal queue that needed more room: a few for the largest run, not one per run and replay
  // (tests assert it).
  long long WorkspaceAllocations = 0;
  size_t EditsRemovalBegin = 0;
  bool EditsReachedTarget = true; // the recorded run's removal reached its target
  bool EditsValid = false;
  PredictionMemo EditsOf{};
  std::vector<float> EditsTolerance;
  std::vector<unsigned char> EditsLocked, EditsFrozen;
  // Replay: root patches and endpoints whose state may differ from the recorded run's.
  std::vector<unsigned char> DirtyPatch, DirtyEnd;
  // Replay: endpoints of a chain of a dirty or frozen root patch (EditIsClean's test around them).
  std::vector<unsigned char> DirtyNear;
  long long AppliedAsRecorded = 0; // the last replay's clean edits
  long long TestedAgain = 0;       // the last replay's edits tested again
  long long DirtyAtStart = 0;      // the last replay's dirty root patches before its first edit
  // The chain graph above is the merging run of these parameters without frozen patches (a
  // prediction's run): the first generation pass of the same level need not run it again.
  bool HoldsPrediction = false;
  PredictionMemo Holds{};
  // Set by another thread to stop this state's merging run (a side-by-side probe no longer
  // needed); the run then leaves no prediction, and Cancelled says so.
  const std::atomic<bool>* Cancel = nullptr;
  bool Cancelled = false;
  bool CancelRequested() const { return this->Cancel && this->Cancel->load(std::memory_order_relaxed); }

  Index Find(Index p)
  {
    PatchRecord* patches = this->Patches.data(); // one load of the records, not one per step
    while (patches[p].Parent != p)
    {
      patches[p].Parent = patches[patches[p].Parent].Parent;
      p = patches[p].Parent;
    }
    return p;
  }
  // Calls f(c) for every live chain that ends at endpoint e, unlinking the slots of dead chains
  // on the way: unions leave their chain's slots behind and collapses splice whole lists, so
  // without it the lists of much-collapsed endpoints drag every chain that ever ended there
  // through each walk (a tenth of the MRI's level time was these walks). A dead chain never
  // comes back within a run, and the live slots keep their order. `f` must not relink lists.
  template<typename Functor>
  void ForEndChains(Index e, Functor&& f)
  {
    Index previous = InvalidIndex;
    for (Index slot = this->EndHead[e]; slot != InvalidIndex;)
    {
      const Index c = slot / 2;
      const Index next = this->EndSlotNext[slot];
      if (!this->Alive[c])
      {
        (previous == InvalidIndex ? this->EndHead[e] : this->EndSlotNext[previous]) = next;
        slot = next;
        continue;
      }
      if ((slot % 2 == 0 ? this->A[c] : this->B[c]) == e)
      {
        f(c);
      }
      previous = slot;
      slot = next;
    }
  }
  // The two chains ending at u, when exactly two do.
  bool TwoChainsAt(Index u, Index (&pair)[2])
  {
    pair[0] = pair[1] = InvalidIndex;
    int found = 0;
    this->ForEndChains(u, [&](Index c) {
      if (found < 2)
      {
        pair[found] = c;
      }
      ++found;
    });
    return found == 2;
  }
  Index NextStamp()
  {
    if (++this->Stamp == std::numeric_limits<Index>::max())
    {
      std::fill(this->PatchStamp.begin(), this->PatchStamp.end(), 0);
      std::fill(this->EndStamp.begin(), this->EndStamp.end(), 0);
      std::fill(this->VertexStamp.begin(), this->VertexStamp.end(), 0);
      this->Stamp = 1;
    }
    return this->Stamp;
  }
};
} // namespace slod

#endif
