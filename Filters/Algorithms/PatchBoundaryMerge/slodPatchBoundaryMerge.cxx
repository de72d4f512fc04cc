#include "slodPatchBoundaryMerge.h"

#include "slodPolygonTriangulation.h"
#include "slodTriangleBVH.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <thread>

namespace slod
{
namespace
{
// SLOD_VERBOSE=1 in the environment prints the level's stage times (profiling aid).
struct StageTimes
{
  double Merging = 0, Generate = 0, Tree = 0, Triangulation = 0, Estimate = 0, Refinement = 0;
  int MergingRuns = 0, Estimates = 0;
};
thread_local StageTimes Times; // of the calling thread
using StageClock = std::chrono::steady_clock;
double Since(StageClock::time_point start)
{
  return std::chrono::duration<double>(StageClock::now() - start).count();
}
// Support directions of the flatness measure: the 3 axes, 6 face and 4 body diagonals, both
// signs (a 26-DOP). A patch keeps its extreme vertex in each; the thickness of a union along any
// normal is then estimated from those 26 + 26 points.
constexpr int SupportDirections = 13;
constexpr int SupportSize = 2 * SupportDirections;
const double SupportAxes[SupportDirections][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 0 }, { 1, -1, 0 },
  { 1, 0, 1 }, { 1, 0, -1 }, { 0, 1, 1 }, { 0, 1, -1 }, { 1, 1, 1 }, { 1, 1, -1 }, { 1, -1, 1 }, { -1, 1, 1 } };
constexpr float InfiniteKey = std::numeric_limits<float>::infinity();
constexpr double DegreesToRadians = 3.14159265358979323846 / 180.0;
// Fallback levels of a patch that could not be triangulated: 1 unmerged, 2..5 its chains with
// epsilon / 4^(level-1), 6 full resolution, 7 its original triangles.
constexpr int FullResolutionLevel = 6;
constexpr int OriginalLevel = 7;
// Longer patch boundaries are not checked for simplicity while merging (left to the fallback).
constexpr Index MaximumCheckedBoundary = 1 << 16;

double PointSegmentDistance2(const Vec3& p, const Vec3& a, const Vec3& b)
{
  const Vec3 ab = b - a;
  const Vec3 ap = p - a;
  const double len2 = Dot(ab, ab);
  double t = len2 > 0 ? Dot(ap, ab) / len2 : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  const Vec3 d = ap - t * ab;
  return Dot(d, d);
}

// Squared deviation of p from segment ab as the surface sees it: the offset's components along
// the two adjacent patch normals (an offset within both patch planes moves the surface little),
// but at least lambda times the full offset.
double SurfaceWeightedDistance2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& n1, const Vec3& n2, double lambda2)
{
  const Vec3 ab = b - a;
  const double len2 = Dot(ab, ab);
  const double t = len2 > 0 ? std::max(0.0, std::min(1.0, Dot(p - a, ab) / len2)) : 0.0;
  const Vec3 d = p - (a + t * ab);
  const double x = Dot(d, n1), y = Dot(d, n2);
  return std::max(std::max(x * x, y * y), lambda2 * Dot(d, d));
}

// True when the closed polygon, projected on the plane orthogonal to `normal`, is simple and
// counter-clockwise (the condition for a valid ear-clipping triangulation without flips). O(n^2):
// used on merged patch boundaries, which are short at the levels where merging happens.
// With `changed` set, the polygon is known to have been simple before vertex `changed` moved or
// its neighbour was removed: only the segments at `changed` are tested against the others (O(n)).
bool ProjectsToSimplePolygon(const std::vector<Vec3>& polygon, const Vec3& normal, size_t changed = size_t(-1))
{
  const size_t n = polygon.size();
  if (n < 3)
  {
    return false;
  }
  const Vec3 w = Normalized(normal);
  const Vec3 helper = std::fabs(w[0]) < 0.9 ? Vec3{ 1, 0, 0 } : Vec3{ 0, 1, 0 };
  const Vec3 u = Normalized(Cross(helper, w));
  const Vec3 v = Cross(w, u);
  // Scratch reused across calls (this runs for every merge and collapse candidate).
  thread_local std::vector<std::array<double, 2>> p;
  thread_local std::vector<size_t> order;
  p.resize(n);
  double area = 0;
  double cx = 0, cy = 0;
  for (size_t i = 0; i < n; ++i)
  {
    p[i] = { Dot(polygon[i], u), Dot(polygon[i], v) };
    cx += p[i][0];
    cy += p[i][1];
  }
  for (size_t i = 0; i < n; ++i)
  {
    const auto& a = p[i];
    const auto& b = p[(i + 1) % n];
    area += a[0] * b[1] - a[1] * b[0];
  }
  if (area <= 0)
  {
    return false;
  }
  auto orient = [](const std::array<double, 2>& o, const std::array<double, 2>& a, const std::array<double, 2>& b) {
    const double d = (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    return (d > 0) - (d < 0);
  };
  {
    // Fast accept in O(n): every edge turns strictly counter-clockwise around the vertex centroid
    // and winds around it once, so the polygon is star-shaped from it, hence simple (most patch
    // boundaries are; the general tests below run only for the others).
    const std::array<double, 2> c = { cx / double(n), cy / double(n) };
    bool star = true;
    int winding = 0;
    for (size_t i = 0; i < n && star; ++i)
    {
      const auto& a = p[i];
      const auto& b = p[(i + 1) % n];
      star = orient(c, a, b) > 0;
      // With every edge CCW around c, an upward crossing of the line y = c.y passes angle 0.
      winding += (a[1] < c[1] && b[1] >= c[1]) ? 1 : 0;
    }
    if (star && winding == 1)
    {
      return true;
    }
  }
  auto onSegment = [](const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& q) {
    return std::min(a[0], b[0]) <= q[0] && q[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= q[1] &&
      q[1] <= std::max(a[1], b[1]);
  };
  auto crossing = [&](size_t i, size_t j) {
    if (i > j)
    {
      std::swap(i, j);
    }
    if (j == i + 1 || (i == 0 && j == n - 1) || i == j)
    {
      return false; // adjacent segments share a vertex
    }
    const auto& a = p[i];
    const auto& b = p[(i + 1) % n];
    const auto& c = p[j];
    const auto& d = p[(j + 1) % n];
    const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    if (o1 != o2 && o3 != o4)
    {
      return true;
    }
    return (o1 == 0 && onSegment(a, b, c)) || (o2 == 0 && onSegment(a, b, d)) || (o3 == 0 && onSegment(c, d, a)) ||
      (o4 == 0 && onSegment(c, d, b));
  };
  if (changed < n)
  {
    // Only the two segments at the changed vertex are new.
    const size_t mine[2] = { (changed + n - 1) % n, changed };
    for (const size_t i : mine)
    {
      for (size_t j = 0; j < n; ++j)
      {
        if (crossing(i, j))
        {
          return false;
        }
      }
    }
    return true;
  }
  // Sweep along x: only segments whose x-ranges overlap are compared.
  order.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    order[i] = i;
  }
  auto minX = [&](size_t i) { return std::min(p[i][0], p[(i + 1) % n][0]); };
  auto maxX = [&](size_t i) { return std::max(p[i][0], p[(i + 1) % n][0]); };
  std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return minX(x) < minX(y); });
  for (size_t a = 0; a < n; ++a)
  {
    const size_t i = order[a];
    const double reach = maxX(i);
    const double lowY = std::min(p[i][1], p[(i + 1) % n][1]), highY = std::max(p[i][1], p[(i + 1) % n][1]);
    for (size_t b = a + 1; b < n && minX(order[b]) <= reach; ++b)
    {
      const size_t j = order[b];
      if (std::max(p[j][1], p[(j + 1) % n][1]) < lowY || std::min(p[j][1], p[(j + 1) % n][1]) > highY)
      {
        continue;
      }
      if (crossing(i, j))
      {
        return false;
      }
    }
  }
  return true;
}
// Open-addressing map from undirected edges to a small value (the chain that owns the edge, or a
// negative tag). One flat array, no per-element allocation.
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
  }
  // Inserts (a,b) -> value; when present returns false and leaves `existing` with its value.
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
    return true;
  }
  bool Contains(Index a, Index b) const
  {
    Index ignored;
    return this->Find(a, b, ignored);
  }
  // Value of (a,b) in `value` when present.
  bool Find(Index a, Index b, Index& value) const
  {
    if (this->Keys.empty())
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
  size_t MemoryUsage() const { return this->Keys.capacity() * 8 + this->Values.capacity() * sizeof(Index); }

private:
  static constexpr uint64_t Empty = ~uint64_t(0);
  static uint64_t Key(Index a, Index b)
  {
    if (a > b)
    {
      std::swap(a, b);
    }
    return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
  }
  size_t Slot(uint64_t key) const
  {
    return size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & (this->Keys.size() - 1);
  }
  void Grow()
  {
    std::vector<uint64_t> keys;
    std::vector<Index> values;
    keys.swap(this->Keys);
    values.swap(this->Values);
    this->Reset(keys.size());
    Index ignored;
    for (size_t i = 0; i < keys.size(); ++i)
    {
      if (keys[i] != Empty)
      {
        this->Insert(Index(keys[i] >> 32), Index(keys[i] & 0xffffffffu), values[i], ignored);
      }
    }
  }
  std::vector<uint64_t> Keys;
  std::vector<Index> Values;
  size_t Count = 0;
};
} // namespace

// Working state of one level: the chain graph after simplification, merging and collapses.
// Chains keep their Patchification ids; patch and endpoint memberships are intrusive linked
// lists of "slots" (2c = left side / start end, 2c+1 = right side / end end) so merges and
// collapses splice in O(1) plus one walk.
struct SpbmLevelGenerator::State
{
  // Chains.
  std::vector<Index> A, B, L, R, Interior;
  std::vector<float> Tolerance; // per chain: epsilon, finer next to refined (frozen) patches
  std::vector<Index> KeptOffsets, KeptPositions; // per chain: kept interior positions, ascending
  // Chain tolerances after refining non-simple patches, for the last epsilon (no fallbacks).
  bool RefinedValid = false;
  float RefinedEpsilon = 0;
  std::vector<float> RefinedTolerance;
  std::vector<unsigned char> RefinedLocked;
  std::vector<unsigned char> Alive, Locked;
  std::vector<Index> PartFirst, PartLast, PartNext; // joined chains: list of original chains
  std::vector<Index> JointBefore; // endpoint between a part and the previous one
  std::vector<unsigned char> PartReversed;
  // Endpoints.
  std::vector<Index> EndHead, EndSlotNext, Degree;
  // Patches (union-find over original patches).
  std::vector<Index> Parent, PatchHead, PatchSlotNext, Size, Version;
  std::vector<Index> TriedP, TriedQ; // per chain: patch versions of its last failed collapse
  std::vector<Index> MergeTriedP, MergeTriedQ; // per chain: patch versions of its last failed merge
  std::vector<Vec3> Normal;
  std::vector<Index> Support; // FlatnessMerge: per root patch, its extreme vertices (SupportSize)
  std::vector<unsigned char> Frozen;
  long long Total = 0;
  // Scratch.
  std::vector<Index> PatchStamp, EndStamp, EndLocal, VertexStamp;
  Index Stamp = 0;
  std::vector<std::pair<double, Index>> Heap;
  std::vector<double> HeapTop; // per chain: the highest value it has in the heap (or -infinity)
  std::vector<unsigned char> NoFreeze;
  // Generation buffers.
  std::vector<Index> SeqOffsets, SeqVertices;
  std::vector<unsigned char> SeqKeep;
  EdgeMap Edges;
  // Minimum-deviation triangulation: distance of each diagonal (vertex pair) from the input,
  // as float bits. It depends on the two original vertices only, so it is kept across the
  // levels and candidates of one chain hierarchy (most patches recur between them).
  EdgeMap DiagonalCosts;
  std::vector<uint64_t> SimpleSignature; // per patch: boundary signature last found simple (0: none)
  std::vector<PredictionMemo> Memo; // predicted counts of the levels asked for (searches repeat them)

  Index Find(Index p)
  {
    while (this->Parent[p] != p)
    {
      this->Parent[p] = this->Parent[this->Parent[p]];
      p = this->Parent[p];
    }
    return p;
  }
  // Calls f(c) for every live chain that ends at endpoint e.
  template <typename Functor>
  void ForEndChains(Index e, Functor&& f) const
  {
    for (Index slot = this->EndHead[e]; slot != InvalidIndex; slot = this->EndSlotNext[slot])
    {
      const Index c = slot / 2;
      if (this->Alive[c] && (slot % 2 == 0 ? this->A[c] : this->B[c]) == e)
      {
        f(c);
      }
    }
  }
  // The two chains ending at u, when exactly two do.
  bool TwoChainsAt(Index u, Index (&pair)[2]) const
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

SpbmLevelGenerator::SpbmLevelGenerator()
  : Work(new State)
  , Helper(new State)
{
}

SpbmLevelGenerator::~SpbmLevelGenerator() = default;

void SpbmLevelGenerator::Initialize(const TriangleMesh& mesh, const Patchification& patches)
{
  this->Initialize(mesh, patches, 1.0);
}

void SpbmLevelGenerator::Initialize(const TriangleMesh& mesh, const Patchification& patches, double inPlaneWeight)
{
  this->Mesh = &mesh;
  this->Patches = &patches;
  this->Work->Memo.clear();
  this->Helper->Memo.clear();
  this->Helper->RefinedValid = false;
  this->Helper->DiagonalCosts.Reset(0);
  if (!(this->PendingTree.valid() && this->TreeMesh == &mesh))
  {
    // Only a tree being built by StartInputTree for this mesh is kept (the mesh may have
    // changed in place since an older tree was built).
    if (this->PendingTree.valid())
    {
      this->PendingTree.get();
    }
    this->InputTree.reset();
    this->TreeMesh = &mesh;
  }
  this->Diagonal = mesh.BoundingBoxDiagonal();
  this->InPlaneWeight = std::max(0.0, std::min(1.0, inPlaneWeight));
  this->Work->RefinedValid = false;
  this->Work->SimpleSignature.clear();
  this->Helper->SimpleSignature.clear();
  this->Work->DiagonalCosts.Reset(0);
  this->PatchSupport.clear(); // built on first use (FlatnessMerge)
  const Patchification& P = patches;
  const Index nc = P.NumberOfChains();
  const Index ne = P.NumberOfEndpoints();
  const size_t totalVertices = nc > 0 ? size_t(P.ChainVerticesBegin(nc - 1) + P.ChainSize(nc - 1) - P.ChainVerticesBegin(0)) : 0;
  this->Keys.assign(totalVertices, InfiniteKey);
  this->SortedKeys.clear();

  // Divide-and-conquer refinement tree of every chain, stored as one key per vertex.
  struct Node
  {
    Index I, J;
    float ParentKey;
  };
  std::vector<Node> stack;
  // With inPlaneWeight < 1 a chain's deviation counts mostly along the normals of its two
  // patches (SurfaceWeightedDistance2): an offset within both patch planes moves the surface
  // little, so smooth boundaries get coarser and creases finer for the same vertex budget.
  const double lambda2 = std::max(0.0, std::min(1.0, inPlaneWeight)) * std::max(0.0, std::min(1.0, inPlaneWeight));
  for (Index c = 0; c < nc; ++c)
  {
    if (P.ChainIsNonManifold(c))
    {
      continue; // kept as it is
    }
    const Index* v = P.ChainVerticesBegin(c);
    const size_t offset = size_t(v - P.ChainVerticesBegin(0));
    const Index n = P.ChainSize(c);
    const bool surfaceWeighted = lambda2 < 1.0 && P.ChainRightPatch(c) != InvalidIndex;
    const Vec3 n1 = P.PatchNormal(P.ChainLeftPatch(c));
    const Vec3 n2 = surfaceWeighted ? P.PatchNormal(P.ChainRightPatch(c)) : n1;
    stack.clear();
    stack.push_back({ 0, n - 1, InfiniteKey });
    while (!stack.empty())
    {
      const Node node = stack.back();
      stack.pop_back();
      if (node.J - node.I < 2)
      {
        continue;
      }
      const Vec3 a = mesh.Point(v[node.I]);
      const Vec3 b = mesh.Point(v[node.J]);
      // Split at the farthest vertex (Douglas-Peucker) rather than at the middle index: the same
      // number of kept vertices then bounds a much smaller deviation (about half the Hausdorff
      // distance of the Fandisk levels, whose largest errors sit on long curved chains).
      double worst = 0;
      Index m = (node.I + node.J) / 2;
      for (Index k = node.I + 1; k < node.J; ++k)
      {
        const double d2 = surfaceWeighted ? SurfaceWeightedDistance2(mesh.Point(v[k]), a, b, n1, n2, lambda2) : PointSegmentDistance2(mesh.Point(v[k]), a, b);
        if (d2 > worst)
        {
          worst = d2;
          m = k;
        }
      }
      // Kept when epsilon < key: refined only if this sub-chain and all its ancestors are off.
      const float key = std::min(static_cast<float>(std::sqrt(worst)), node.ParentKey);
      this->Keys[offset + size_t(m)] = key;
      this->SortedKeys.push_back(key);
      stack.push_back({ node.I, m, key });
      stack.push_back({ m, node.J, key });
    }
  }
  std::sort(this->SortedKeys.begin(), this->SortedKeys.end(), std::greater<float>());
  // Per chain, its interior positions by decreasing key: the vertices kept for any epsilon are a
  // prefix (found by binary search).
  this->KeyOrder.assign(totalVertices, 0);
  this->OrderedKeys.assign(totalVertices, InfiniteKey);
  for (Index c = 0; c < nc; ++c)
  {
    const size_t offset = size_t(P.ChainVerticesBegin(c) - P.ChainVerticesBegin(0));
    const Index n = P.ChainSize(c);
    Index* order = this->KeyOrder.data() + offset;
    for (Index i = 1; i + 1 < n; ++i)
    {
      order[i - 1] = i;
    }
    const float* keys = this->Keys.data() + offset;
    std::stable_sort(order, order + std::max<Index>(0, n - 2), [&](Index x, Index y) { return keys[x] > keys[y]; });
    for (Index i = 0; i + 2 < n; ++i)
    {
      this->OrderedKeys[offset + i] = keys[order[i]];
    }
  }

  // Parallel chains (same two endpoints) bound a lens; all but one keep an interior vertex so
  // that no patch degenerates to two vertices and no two chains become the same edge.
  this->MinimumInterior.assign(size_t(nc), 0);
  {
    std::vector<Index> order(static_cast<size_t>(nc));
    for (Index c = 0; c < nc; ++c)
    {
      order[c] = c;
    }
    auto pairOf = [&](Index c) {
      const Index a = P.ChainStart(c), b = P.ChainEnd(c);
      return std::make_pair(std::min(a, b), std::max(a, b));
    };
    std::sort(order.begin(), order.end(), [&](Index x, Index y) {
      const auto px = pairOf(x), py = pairOf(y);
      return px < py || (px == py && (P.ChainSize(x) < P.ChainSize(y) || (P.ChainSize(x) == P.ChainSize(y) && x < y)));
    });
    for (size_t i = 0; i < order.size();)
    {
      size_t j = i + 1;
      while (j < order.size() && pairOf(order[j]) == pairOf(order[i]))
      {
        ++j;
      }
      for (size_t k = i + 1; k < j; ++k) // the shortest of the group may stay one segment
      {
        if (P.ChainSize(order[k]) > 2)
        {
          this->MinimumInterior[order[k]] = 1;
        }
      }
      i = j;
    }
  }

  // Normal variation around each endpoint: the largest angle between the patches meeting there.
  this->EndpointVariation.assign(size_t(ne), 0.0);
  for (Index c = 0; c < nc; ++c)
  {
    if (P.ChainRightPatch(c) == InvalidIndex)
    {
      continue;
    }
    const double variation = 1.0 - Dot(P.PatchNormal(P.ChainLeftPatch(c)), P.PatchNormal(P.ChainRightPatch(c)));
    for (const Index e : { P.ChainStart(c), P.ChainEnd(c) })
    {
      this->EndpointVariation[e] = std::max(this->EndpointVariation[e], variation);
    }
  }
}

double SpbmLevelGenerator::ChainVertexKey(Index c, Index i) const
{
  const size_t offset = size_t(this->Patches->ChainVerticesBegin(c) - this->Patches->ChainVerticesBegin(0));
  return this->Keys[offset + size_t(i)];
}

size_t SpbmLevelGenerator::MemoryUsage() const
{
  size_t bytes = this->Keys.capacity() * 4 + this->SortedKeys.capacity() * 4 + this->KeyOrder.capacity() * 4 + this->OrderedKeys.capacity() * 4 + this->MinimumInterior.capacity() +
    this->EndpointVariation.capacity() * 8;
  auto b = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  bytes += b(this->PatchSupport);
  for (const State* state : { this->Work.get(), this->Helper.get() }) // one working state per candidate thread
  {
    const State& s = *state;
    bytes += b(s.A) + b(s.B) + b(s.L) + b(s.R) + b(s.Interior) + b(s.Tolerance) + b(s.KeptOffsets) +
      b(s.KeptPositions) + b(s.RefinedTolerance) + b(s.RefinedLocked) + b(s.Alive) + b(s.Locked) + b(s.PartFirst) +
      b(s.PartLast) + b(s.PartNext) + b(s.JointBefore) + b(s.PartReversed) + b(s.EndHead) + b(s.EndSlotNext) +
      b(s.Degree) + b(s.Parent) + b(s.PatchHead) + b(s.PatchSlotNext) + b(s.Size) + b(s.Version) + b(s.TriedP) +
      b(s.TriedQ) + b(s.MergeTriedP) + b(s.MergeTriedQ) + b(s.Normal) + b(s.Support) + b(s.Frozen) +
      b(s.PatchStamp) + b(s.EndStamp) + b(s.EndLocal) + b(s.VertexStamp) + b(s.Heap) + b(s.HeapTop) + b(s.NoFreeze) +
      b(s.SeqOffsets) + b(s.SeqVertices) + b(s.SeqKeep) + s.Edges.MemoryUsage() + s.DiagonalCosts.MemoryUsage() +
      b(s.SimpleSignature) + b(s.Memo);
  }
  if (this->InputTree)
  {
    // Nodes, leaf order and the 9 leaf-ordered corner coordinates per triangle.
    const TriangleBVH& tree = *this->InputTree;
    bytes += b(tree.GetNodes()) + b(tree.GetOrder()) + tree.GetOrder().size() * 9 * sizeof(double);
  }
  return bytes;
}

void SpbmLevelGenerator::StartInputTree(const TriangleMesh& mesh)
{
  std::lock_guard<std::mutex> lock(this->LazyMutex);
  if (this->PendingTree.valid())
  {
    this->PendingTree.get();
  }
  this->InputTree.reset();
  this->TreeMesh = &mesh;
  this->PendingTree = std::async(std::launch::async, [&mesh]() { return std::make_unique<TriangleBVH>(mesh); });
}

const TriangleBVH& SpbmLevelGenerator::GetInputTree()
{
  // Built on first use (a non-planar patch), by whichever candidate thread needs it first.
  std::lock_guard<std::mutex> lock(this->LazyMutex);
  if (!this->InputTree && this->PendingTree.valid())
  {
    const auto started = StageClock::now();
    this->InputTree = this->PendingTree.get();
    Times.Tree += Since(started);
  }
  if (!this->InputTree)
  {
    const auto started = StageClock::now();
    this->InputTree.reset(new TriangleBVH(*this->Mesh));
    Times.Tree += Since(started);
  }
  return *this->InputTree;
}

void SpbmLevelGenerator::RunMerging(
  const SpbmLevelParameters& parameters, const std::vector<unsigned char>& frozen, State& s)
{
  const Patchification& P = *this->Patches;
  const TriangleMesh& mesh = *this->Mesh;
  const Index np = P.NumberOfPatches();
  const Index nc = P.NumberOfChains();
  const Index ne = P.NumberOfEndpoints();
  const float eps = static_cast<float>(parameters.Epsilon);
  const Index* base = nc > 0 ? P.ChainVerticesBegin(0) : nullptr;

  s.Parent.resize(size_t(np));
  s.PatchHead.assign(size_t(np), InvalidIndex);
  s.Size.assign(size_t(np), 0);
  s.Version.assign(size_t(np), 0);
  s.Normal.resize(size_t(np));
  s.Frozen = frozen;
  s.PatchStamp.resize(size_t(np), 0);
  for (Index p = 0; p < np; ++p)
  {
    s.Parent[p] = p;
    s.Normal[p] = P.PatchNormalSum(p);
  }
  if (parameters.FlatnessMerge)
  {
    std::lock_guard<std::mutex> lock(this->LazyMutex);
    if (this->PatchSupport.size() != size_t(np) * SupportSize)
    {
      // Extreme vertices of every patch in the support directions (first use only).
      this->PatchSupport.assign(size_t(np) * SupportSize, InvalidIndex);
      std::vector<double> extreme(size_t(np) * SupportSize, -std::numeric_limits<double>::infinity());
      const std::vector<Index>& patchOf = P.TrianglePatches();
      for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
      {
        const size_t base = size_t(patchOf[t]) * SupportSize;
        for (int k = 0; k < 3; ++k)
        {
          const Index v = mesh.Triangle(t)[k];
          const Vec3 x = mesh.Point(v);
          for (int d = 0; d < SupportDirections; ++d)
          {
            const double h = x[0] * SupportAxes[d][0] + x[1] * SupportAxes[d][1] + x[2] * SupportAxes[d][2];
            if (h > extreme[base + 2 * d])
            {
              extreme[base + 2 * d] = h;
              this->PatchSupport[base + 2 * d] = v;
            }
            if (-h > extreme[base + 2 * d + 1])
            {
              extreme[base + 2 * d + 1] = -h;
              this->PatchSupport[base + 2 * d + 1] = v;
            }
          }
        }
      }
    }
    s.Support = this->PatchSupport;
  }
  s.EndHead.assign(size_t(ne), InvalidIndex);
  s.Degree.assign(size_t(ne), 0);
  s.EndStamp.resize(size_t(ne), 0);
  s.EndLocal.resize(size_t(ne), 0);
  s.A.resize(size_t(nc));
  s.B.resize(size_t(nc));
  s.L.resize(size_t(nc));
  s.R.resize(size_t(nc));
  s.Interior.resize(size_t(nc));
  s.Tolerance.resize(size_t(nc));
  s.Alive.assign(size_t(nc), 1);
  s.TriedP.assign(size_t(nc), -1);
  s.TriedQ.assign(size_t(nc), -1);
  s.MergeTriedP.assign(size_t(nc), -1);
  s.MergeTriedQ.assign(size_t(nc), -1);
  s.Locked.resize(size_t(nc));
  s.PartFirst.resize(size_t(nc));
  s.PartLast.resize(size_t(nc));
  s.PartNext.assign(size_t(nc), InvalidIndex);
  s.JointBefore.assign(size_t(nc), InvalidIndex);
  s.PartReversed.assign(size_t(nc), 0);
  s.EndSlotNext.resize(2 * size_t(nc));
  s.PatchSlotNext.resize(2 * size_t(nc));
  s.KeptOffsets.resize(size_t(nc) + 1);
  s.KeptPositions.clear();

  for (Index c = 0; c < nc; ++c)
  {
    const Index a = P.ChainStart(c), b = P.ChainEnd(c), l = P.ChainLeftPatch(c), r = P.ChainRightPatch(c);
    const Index n = P.ChainSize(c);
    s.A[c] = a;
    s.B[c] = b;
    s.L[c] = l;
    s.R[c] = r;
    s.PartFirst[c] = s.PartLast[c] = c;
    const int level = std::max<int>(frozen[l], r != InvalidIndex ? frozen[r] : 0);
    const bool locked = P.ChainIsNonManifold(c) || level >= FullResolutionLevel;
    s.Locked[c] = locked;
    // Refinement levels 2.. divide epsilon by 4 each.
    s.Tolerance[c] = level >= 2 ? eps * std::pow(0.25f, float(level - 1)) : eps;
    s.EndSlotNext[2 * size_t(c)] = s.EndHead[a];
    s.EndHead[a] = 2 * c;
    s.EndSlotNext[2 * size_t(c) + 1] = s.EndHead[b];
    s.EndHead[b] = 2 * c + 1;
    ++s.Degree[a];
    ++s.Degree[b];
    s.PatchSlotNext[2 * size_t(c)] = s.PatchHead[l];
    s.PatchHead[l] = 2 * c;
    if (r != InvalidIndex)
    {
      s.PatchSlotNext[2 * size_t(c) + 1] = s.PatchHead[r];
      s.PatchHead[r] = 2 * c + 1;
    }
  }
  // Kept vertices of every chain for its tolerance (a prefix of its key order), patch sizes.
  auto rebuildKept = [&]() {
    s.KeptPositions.clear();
    std::fill(s.Size.begin(), s.Size.end(), 0);
    for (Index c = 0; c < nc; ++c)
    {
      const Index n = P.ChainSize(c);
      const size_t offset = size_t(P.ChainVerticesBegin(c) - base);
      const Index m = std::max<Index>(0, n - 2);
      Index interior = m;
      if (!s.Locked[c])
      {
        const float tolerance = s.Tolerance[c];
        const float* ordered = this->OrderedKeys.data() + offset;
        interior = static_cast<Index>(
          std::partition_point(ordered, ordered + m, [&](float k) { return k > tolerance; }) - ordered);
        if (interior == 0 && m > 0 && this->MinimumInterior[c])
        {
          interior = 1;
        }
      }
      s.KeptOffsets[c] = static_cast<Index>(s.KeptPositions.size());
      if (s.Locked[c])
      {
        for (Index i = 1; i + 1 < n; ++i)
        {
          s.KeptPositions.push_back(i);
        }
      }
      else
      {
        const Index* order = this->KeyOrder.data() + offset;
        s.KeptPositions.insert(s.KeptPositions.end(), order, order + interior);
        std::sort(s.KeptPositions.end() - interior, s.KeptPositions.end());
      }
      s.Interior[c] = interior;
      s.Size[s.L[c]] += interior + 1;
      if (s.R[c] != InvalidIndex)
      {
        s.Size[s.R[c]] += interior + 1;
      }
    }
    s.KeptOffsets[nc] = static_cast<Index>(s.KeptPositions.size());
  };
  rebuildKept();

  const double cosMerge = std::cos(parameters.MergeAngle * DegreesToRadians);
  auto sideDot = [&](Index p, Index q) { return Dot(Normalized(s.Normal[p]), Normalized(s.Normal[q])); };
  // Merge measure (larger = merge sooner) and its threshold. Plain: the cosine of the normals'
  // angle against cos(alpha1). Size-weighted: flattening the smaller patch of the pair onto the
  // union's plane moves it by about its extent times sin(angle), so the angle is weighted by the
  // smaller patch's extent relative to an average patch: small patches merge at wider angles,
  // large ones at narrower angles, for the same alpha1.
  double meanSize = 0;
  if (parameters.SizeWeightedMerge)
  {
    for (Index p = 0; p < np; ++p)
    {
      meanSize += Norm(s.Normal[p]);
    }
    meanSize = std::max(meanSize / std::max<Index>(1, np), std::numeric_limits<double>::min());
  }
  const bool flatness = parameters.FlatnessMerge;
  const double mergeThreshold = flatness
    ? (parameters.MergeAngle >= 90.0 ? -std::numeric_limits<double>::max() / 4
                                     : -parameters.FlatnessScale * std::tan(std::max(0.0, parameters.MergeAngle) * DegreesToRadians))
    : parameters.SizeWeightedMerge ? -std::sin(std::min(90.0, parameters.MergeAngle) * DegreesToRadians)
                                   : cosMerge;
  // Thickness of the union of root patches p and q along its normal, relative to the diagonal.
  const double inverseDiagonal = this->Diagonal > 0 ? 1.0 / this->Diagonal : 1.0;
  auto thickness = [&](Index p, Index q) {
    const Vec3 n = Normalized(s.Normal[p] + s.Normal[q]);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Index root : { p, q })
    {
      const Index* support = s.Support.data() + size_t(root) * SupportSize;
      for (int k = 0; k < SupportSize; ++k)
      {
        const double h = Dot(n, mesh.Point(support[k]));
        lo = std::min(lo, h);
        hi = std::max(hi, h);
      }
    }
    return (hi - lo) * inverseDiagonal;
  };
  auto mergeMeasure = [&](Index p, Index q) {
    const double d = sideDot(p, q);
    if (flatness)
    {
      return d <= 0 ? -std::numeric_limits<double>::max() : -thickness(p, q);
    }
    if (!parameters.SizeWeightedMerge)
    {
      return d;
    }
    if (d <= 0)
    {
      return -std::numeric_limits<double>::max();
    }
    const double weight = std::sqrt(std::min(Norm(s.Normal[p]), Norm(s.Normal[q])) / meanSize);
    return -std::sqrt(std::max(0.0, 1.0 - d * d)) * weight;
  };
  auto otherEnd = [&](Index c, Index e) { return s.A[c] == e ? s.B[c] : s.A[c]; };
  auto endpointPoint = [&](Index e) { return mesh.Point(P.EndpointVertex(e)); };
  auto movable = [&](Index c) {
    return s.Alive[c] && !s.Locked[c] && s.Interior[c] == 0 && s.R[c] != InvalidIndex;
  };
  auto pushCandidate = [&](Index c) {
    if (!movable(c))
    {
      return;
    }
    const Index p = s.Find(s.L[c]), q = s.Find(s.R[c]);
    if (p == q || s.Frozen[p] || s.Frozen[q])
    {
      return;
    }
    const double d = mergeMeasure(p, q);
    // An entry at least as high is already queued: it pops first and is re-evaluated then (merged
    // patches re-push all their chains; this keeps the heap from filling with duplicates).
    if (d >= mergeThreshold && d > s.HeapTop[c])
    {
      s.Heap.emplace_back(d, c);
      std::push_heap(s.Heap.begin(), s.Heap.end());
      s.HeapTop[c] = d;
    }
  };
  // Walk the alive chains of root patch p, unlinking dead ones on the way (merged patches would
  // otherwise drag every chain they ever absorbed through each walk: quadratic on large merges).
  // The order of the alive chains is kept. `f` must not relink patch lists.
  auto forPatchChains = [&](Index p, auto&& f) {
    Index previous = InvalidIndex;
    for (Index slot = s.PatchHead[p]; slot != InvalidIndex;)
    {
      const Index c = slot / 2;
      const Index next = s.PatchSlotNext[slot];
      if (s.Alive[c])
      {
        f(c);
        previous = slot;
      }
      else if (previous == InvalidIndex)
      {
        s.PatchHead[p] = next;
      }
      else
      {
        s.PatchSlotNext[previous] = next;
      }
      slot = next;
    }
  };
  auto forEndChains = [&](Index e, auto&& f) { s.ForEndChains(e, f); };
  auto spliceEndList = [&](Index from, Index to) {
    if (s.EndHead[from] == InvalidIndex)
    {
      return;
    }
    Index tail = s.EndHead[from];
    while (s.EndSlotNext[tail] != InvalidIndex)
    {
      tail = s.EndSlotNext[tail];
    }
    s.EndSlotNext[tail] = s.EndHead[to];
    s.EndHead[to] = s.EndHead[from];
    s.EndHead[from] = InvalidIndex;
  };
  auto reverseParts = [&](Index c) {
    // p1..pm with joints J2..Jm (J_i before p_i) becomes pm..p1 with J_{i+1} before p_i.
    Index previous = InvalidIndex;
    Index part = s.PartFirst[c];
    while (part != InvalidIndex)
    {
      const Index following = s.PartNext[part];
      const Index joint = s.JointBefore[part];
      s.PartNext[part] = previous;
      s.PartReversed[part] ^= 1;
      if (previous != InvalidIndex)
      {
        s.JointBefore[previous] = joint;
      }
      previous = part;
      part = following;
    }
    std::swap(s.PartFirst[c], s.PartLast[c]);
    s.JointBefore[s.PartFirst[c]] = InvalidIndex;
  };

  // Boundary points of root patch `x` (plus `y` when merging along chain `skip`), in order,
  // with the chain vertices the current tolerances keep. False when they do not close.
  std::vector<Index> oriented;
  std::vector<Vec3> forward;
  auto boundaryPoints = [&](Index x, Index y, Index skip, std::vector<Vec3>& points) {
    points.clear();
    oriented.clear();
    const Index stamp = s.NextStamp();
    for (const Index root : { x, y })
    {
      if (root == InvalidIndex)
      {
        continue;
      }
      for (Index slot = s.PatchHead[root]; slot != InvalidIndex; slot = s.PatchSlotNext[slot])
      {
        const Index c = slot / 2;
        if (!s.Alive[c] || c == skip)
        {
          continue;
        }
        const bool reversed = s.Find(s.L[c]) != root;
        const Index start = reversed ? s.B[c] : s.A[c];
        if (s.EndStamp[start] == stamp)
        {
          return false;
        }
        s.EndStamp[start] = stamp;
        s.EndLocal[start] = static_cast<Index>(oriented.size());
        oriented.push_back(reversed ? -1 - c : c);
      }
    }
    if (oriented.empty())
    {
      return false;
    }
    Index current = 0;
    for (size_t step = 0; step < oriented.size(); ++step)
    {
      const Index o = oriented[current];
      const Index c = o >= 0 ? o : -1 - o;
      forward.clear();
      forward.push_back(endpointPoint(s.A[c]));
      for (Index part = s.PartFirst[c]; part != InvalidIndex; part = s.PartNext[part])
      {
        const Index* v = P.ChainVerticesBegin(part);
        const Index first = s.KeptOffsets[part], last = s.KeptOffsets[part + 1];
        if (s.PartReversed[part])
        {
          for (Index i = last; i > first; --i)
          {
            forward.push_back(mesh.Point(v[s.KeptPositions[i - 1]]));
          }
        }
        else
        {
          for (Index i = first; i < last; ++i)
          {
            forward.push_back(mesh.Point(v[s.KeptPositions[i]]));
          }
        }
      }
      if (o >= 0)
      {
        points.insert(points.end(), forward.begin(), forward.end());
      }
      else
      {
        points.push_back(endpointPoint(s.B[c]));
        points.insert(points.end(), forward.rbegin(), forward.rend() - 1);
      }
      const Index end = o >= 0 ? s.B[c] : s.A[c];
      if (s.EndStamp[end] != stamp)
      {
        return false;
      }
      current = s.EndLocal[end];
    }
    return current == 0;
  };
  // Would patch x still project to a simple polygon once endpoint `gone` is dropped (replace ==
  // InvalidIndex) or replaced by `replace`?
  std::vector<Vec3> checkPoints;
  auto simpleAfter = [&](Index x, Index gone, Index replace) {
    if (s.Size[x] > MaximumCheckedBoundary)
    {
      return true; // left to the triangulation fallback
    }
    if (!boundaryPoints(x, InvalidIndex, InvalidIndex, checkPoints))
    {
      return false;
    }
    const Vec3 g = endpointPoint(gone);
    const auto at = std::find(checkPoints.begin(), checkPoints.end(), g);
    if (at == checkPoints.end())
    {
      return true;
    }
    size_t changed = size_t(at - checkPoints.begin());
    if (replace == InvalidIndex)
    {
      checkPoints.erase(at);
      changed = changed == 0 ? checkPoints.size() - 1 : changed - 1; // the new segment starts here
    }
    else
    {
      *at = endpointPoint(replace);
    }
    return ProjectsToSimplePolygon(checkPoints, s.Normal[x], changed);
  };
  // Method (3) of section 4.2.8 for the patches themselves: a patch whose simplified boundary
  // does not project to a simple polygon gets finer chains (epsilon / 4 per round, then full
  // resolution) before anything else, so that predictions include it and triangulation succeeds.
  // The refinement depends on epsilon only (not on alpha1): searches over alpha1 reuse it.
  bool anyFrozen = false;
  for (Index p = 0; p < np && !anyFrozen; ++p)
  {
    anyFrozen = frozen[p] != 0;
  }
  const auto refinementStart = StageClock::now();
  const bool reuse = !anyFrozen && s.RefinedValid && s.RefinedEpsilon == eps;
  if (reuse)
  {
    s.Tolerance = s.RefinedTolerance;
    s.Locked = s.RefinedLocked;
    rebuildKept();
  }
  if (s.SimpleSignature.size() != size_t(np))
  {
    s.SimpleSignature.assign(size_t(np), 0);
  }
  for (int round = 0; round < 8 && !reuse; ++round)
  {
    bool refined = false;
    for (Index p = 0; p < np; ++p)
    {
      if (s.Size[p] > MaximumCheckedBoundary || s.Frozen[p] >= FullResolutionLevel)
      {
        continue;
      }
      // The boundary is determined by how many vertices each of its chains keeps (a prefix of the
      // chain's key order, or all): remember the signatures of boundaries found simple, so that
      // the searches' many runs at nearby epsilons test only the patches whose boundary changed.
      uint64_t signature = 0;
      forPatchChains(p, [&](Index c) {
        uint64_t x = (uint64_t(uint32_t(c)) << 32) ^ (uint64_t(uint32_t(s.Interior[c])) << 1) ^ uint64_t(s.Locked[c]);
        x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull; // splitmix64 finalizer
        x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
        signature += x ^ (x >> 31);
      });
      if (s.SimpleSignature[p] == signature)
      {
        continue;
      }
      if (boundaryPoints(p, InvalidIndex, InvalidIndex, checkPoints) && ProjectsToSimplePolygon(checkPoints, s.Normal[p]))
      {
        s.SimpleSignature[p] = signature;
        continue;
      }
      forPatchChains(p, [&](Index c) {
        if (!s.Locked[c])
        {
          refined = true;
          if (round >= 5 || s.Tolerance[c] <= 0)
          {
            s.Locked[c] = 1; // full resolution
          }
          else
          {
            s.Tolerance[c] *= 0.25f;
          }
        }
      });
    }
    if (!refined)
    {
      break;
    }
    rebuildKept();
  }
  if (!anyFrozen && !reuse)
  {
    s.RefinedValid = true;
    s.RefinedEpsilon = eps;
    s.RefinedTolerance = s.Tolerance;
    s.RefinedLocked = s.Locked;
  }
  Times.Refinement += Since(refinementStart);
  s.Total = 0;
  for (Index p = 0; p < np; ++p)
  {
    s.Total += s.Size[p] - 2;
  }
  if (!parameters.MergePatches && !parameters.CollapseChains)
  {
    return;
  }

  // Chain collapse (4.2.6 (a)-(c), 4.2.7): one-edge chain e of patch x shrinks to one endpoint.
  // Cost-ordered removal (RemovalTarget): collapses without the length and epsilon bounds,
  // toward a chosen end, and joins without the epsilon bound.
  bool relaxed = false;
  Index forcedKeep = InvalidIndex;
  auto tryCollapse = [&](Index e, double longest) {
    if (!movable(e))
    {
      return false;
    }
    const Index p = s.Find(s.L[e]), q = s.Find(s.R[e]);
    if (p == q || s.Frozen[p] || s.Frozen[q] || (!relaxed && sideDot(p, q) < cosMerge)) // (b)
    {
      return false;
    }
    if (s.TriedP[e] == s.Version[p] && s.TriedQ[e] == s.Version[q])
    {
      return false; // failed before and neither patch changed since
    }
    s.TriedP[e] = s.Version[p];
    s.TriedQ[e] = s.Version[q];
    const Index a = s.A[e], b = s.B[e];
    const Vec3 pa = endpointPoint(a), pb = endpointPoint(b);
    if (!relaxed && Norm(pb - pa) >= parameters.CollapseLengthFactor * longest) // (c)
    {
      return false;
    }
    if (!relaxed && parameters.CollapseWithinEpsilon && Norm(pb - pa) > std::min(s.Tolerance[e], float(parameters.Epsilon)))
    {
      return false; // moving an endpoint farther than epsilon would break the chain bound
    }
    const bool borderA = P.EndpointOnBorder(a), borderB = P.EndpointOnBorder(b);
    if (borderA && borderB)
    {
      return false;
    }
    // Toward the border vertex, else toward the larger normal variation.
    Index keep = borderA ? a : (borderB ? b : (this->EndpointVariation[a] >= this->EndpointVariation[b] ? a : b));
    if (forcedKeep != InvalidIndex)
    {
      if ((forcedKeep == a && borderB) || (forcedKeep == b && borderA))
      {
        return false;
      }
      keep = forcedKeep;
    }
    const Index gone = keep == a ? b : a;
    if (s.Size[p] < 4 || s.Size[q] < 4)
    {
      return false;
    }
    const Index stamp = s.NextStamp();
    forEndChains(keep, [&](Index c) {
      s.PatchStamp[s.Find(s.L[c])] = stamp;
      if (s.R[c] != InvalidIndex)
      {
        s.PatchStamp[s.Find(s.R[c])] = stamp;
      }
      s.EndStamp[otherEnd(c, keep)] = stamp;
    });
    bool ok = true;
    forEndChains(gone, [&](Index c) {
      if (c == e || !ok)
      {
        return;
      }
      const Index sides[2] = { s.Find(s.L[c]), s.R[c] == InvalidIndex ? InvalidIndex : s.Find(s.R[c]) };
      for (const Index side : sides)
      {
        if (side == InvalidIndex)
        {
          continue;
        }
        if (s.Frozen[side] || (side != p && side != q && s.PatchStamp[side] == stamp)) // (a)
        {
          ok = false;
        }
      }
      const Index o = otherEnd(c, gone);
      if (s.Locked[c] || o == keep || s.EndStamp[o] == stamp) // would make parallel edges
      {
        ok = false;
      }
    });
    if (!ok)
    {
      return false;
    }
    // The patches around `gone` must stay simple in projection.
    if (!simpleAfter(p, gone, InvalidIndex) || !simpleAfter(q, gone, InvalidIndex))
    {
      return false;
    }
    const Index around = s.NextStamp();
    s.PatchStamp[p] = s.PatchStamp[q] = around;
    forEndChains(gone, [&](Index c) {
      for (const Index side : { s.L[c], s.R[c] })
      {
        if (ok && side != InvalidIndex && s.PatchStamp[s.Find(side)] != around)
        {
          s.PatchStamp[s.Find(side)] = around;
          ok = simpleAfter(s.Find(side), gone, keep);
        }
      }
    });
    if (!ok)
    {
      return false;
    }
    s.Alive[e] = 0;
    forEndChains(gone, [&](Index c) {
      if (s.A[c] == gone)
      {
        s.A[c] = keep;
      }
      if (s.B[c] == gone)
      {
        s.B[c] = keep;
      }
    });
    forEndChains(gone, [&](Index c) {
      ++s.Version[s.Find(s.L[c])];
      if (s.R[c] != InvalidIndex)
      {
        ++s.Version[s.Find(s.R[c])];
      }
    });
    spliceEndList(gone, keep);
    s.Degree[keep] += s.Degree[gone] - 2;
    s.Degree[gone] = 0;
    --s.Size[p];
    --s.Size[q];
    s.Total -= 2;
    return true;
  };
  auto tryCollapses = [&](Index x, Index exclude) {
    double longest = 0;
    forPatchChains(x, [&](Index c) { longest = std::max(longest, Norm(endpointPoint(s.B[c]) - endpointPoint(s.A[c]))); });
    forPatchChains(x, [&](Index c) {
      if (c != exclude)
      {
        tryCollapse(c, longest);
      }
    });
  };
  // An endpoint left between exactly two one-edge chains of the same two patches disappears.
  // All vertices of chain c from endpoint `from` to the other one, with kept flags.
  std::vector<Vec3> chainPoints;
  std::vector<unsigned char> chainKept;
  auto appendChain = [&](Index c, Index from, bool skipFirst) {
    const size_t start = chainPoints.size();
    chainPoints.push_back(endpointPoint(s.A[c]));
    chainKept.push_back(1);
    for (Index part = s.PartFirst[c]; part != InvalidIndex; part = s.PartNext[part])
    {
      if (part != s.PartFirst[c])
      {
        chainPoints.push_back(endpointPoint(s.JointBefore[part]));
        chainKept.push_back(0);
      }
      const Index* v = P.ChainVerticesBegin(part);
      const Index n = P.ChainSize(part);
      const bool reversed = s.PartReversed[part];
      const size_t partStart = chainPoints.size();
      for (Index i = 1; i + 1 < n; ++i)
      {
        chainPoints.push_back(mesh.Point(v[reversed ? n - 1 - i : i]));
        chainKept.push_back(0);
      }
      for (Index j = s.KeptOffsets[part]; j < s.KeptOffsets[part + 1]; ++j)
      {
        const Index k = s.KeptPositions[j];
        chainKept[partStart + size_t(reversed ? n - 1 - k : k) - 1] = 1;
      }
    }
    chainPoints.push_back(endpointPoint(s.B[c]));
    chainKept.push_back(1);
    if (s.A[c] != from)
    {
      std::reverse(chainPoints.begin() + std::ptrdiff_t(start), chainPoints.end());
      std::reverse(chainKept.begin() + std::ptrdiff_t(start), chainKept.end());
    }
    if (skipFirst)
    {
      chainPoints.erase(chainPoints.begin() + std::ptrdiff_t(start));
      chainKept.erase(chainKept.begin() + std::ptrdiff_t(start));
    }
  };
  // The chains x and y joined at their common endpoint u (dropped), and the kept vertices a < b
  // that become the ends of the segment replacing u.
  auto joinAround = [&](Index x, Index y, Index u, size_t& a, size_t& b) {
    chainPoints.clear();
    chainKept.clear();
    appendChain(x, otherEnd(x, u), false);
    const size_t joint = chainPoints.size() - 1;
    appendChain(y, u, true);
    chainKept[joint] = 0;
    a = joint;
    b = joint;
    while (!chainKept[a])
    {
      --a;
    }
    while (!chainKept[b])
    {
      ++b;
    }
  };
  // Dropping endpoint u between chains x and y keeps the chain within its tolerance: every
  // vertex between the kept neighbours of u stays within epsilon of the new segment.
  auto joinWithinTolerance = [&](Index x, Index y, Index u) {
    size_t a, b;
    joinAround(x, y, u, a, b);
    const double tolerance = std::min(s.Tolerance[x], s.Tolerance[y]);
    for (size_t i = a + 1; i < b; ++i)
    {
      if (PointSegmentDistance2(chainPoints[i], chainPoints[a], chainPoints[b]) > tolerance * tolerance ||
        tolerance < 0)
      {
        return false;
      }
    }
    return true;
  };
  auto tryJoin = [&](Index u) {
    if (s.Degree[u] != 2 || P.EndpointOnBorder(u))
    {
      return;
    }
    Index pair[2];
    const bool two = s.TwoChainsAt(u, pair);
    auto joinable = [&](Index c) {
      return s.Alive[c] && !s.Locked[c] && s.R[c] != InvalidIndex && !s.Frozen[s.Find(s.L[c])] &&
        !s.Frozen[s.Find(s.R[c])];
    };
    if (!two || !joinable(pair[0]) || !joinable(pair[1]))
    {
      return;
    }
    const Index x = pair[0], y = pair[1];
    const Index xl = s.Find(s.L[x]), xr = s.Find(s.R[x]), yl = s.Find(s.L[y]), yr = s.Find(s.R[y]);
    if (!((xl == yl && xr == yr) || (xl == yr && xr == yl)) || xl == xr)
    {
      return;
    }
    const Index ox = otherEnd(x, u), oy = otherEnd(y, u);
    if (ox == oy || s.Size[xl] < 4 || s.Size[xr] < 4)
    {
      return;
    }
    bool parallel = false;
    forEndChains(ox, [&](Index c) { parallel = parallel || otherEnd(c, ox) == oy; });
    if (parallel || (parameters.JoinWithinEpsilon && !relaxed && !joinWithinTolerance(x, y, u)) ||
      !simpleAfter(xl, u, InvalidIndex) || !simpleAfter(xr, u, InvalidIndex))
    {
      return;
    }
    if (s.B[x] == u)
    {
      // x runs ox -> u; append y oriented u -> oy.
      const bool forward = s.A[y] == u;
      if (forward != (yl == xl))
      {
        return; // inconsistent sides (cannot happen for oriented input)
      }
      if (!forward)
      {
        reverseParts(y);
      }
      s.JointBefore[s.PartFirst[y]] = u;
      s.PartNext[s.PartLast[x]] = s.PartFirst[y];
      s.PartLast[x] = s.PartLast[y];
      s.B[x] = oy;
      s.EndSlotNext[2 * size_t(x) + 1] = s.EndHead[oy];
      s.EndHead[oy] = 2 * x + 1;
    }
    else
    {
      // x runs u -> ox; prepend y oriented oy -> u.
      const bool forward = s.B[y] == u;
      if (forward != (yl == xl))
      {
        return;
      }
      if (!forward)
      {
        reverseParts(y);
      }
      s.JointBefore[s.PartFirst[x]] = u;
      s.PartNext[s.PartLast[y]] = s.PartFirst[x];
      s.PartFirst[x] = s.PartFirst[y];
      s.A[x] = oy;
      s.EndSlotNext[2 * size_t(x)] = s.EndHead[oy];
      s.EndHead[oy] = 2 * x;
    }
    s.Interior[x] += s.Interior[y];
    ++s.Version[xl];
    ++s.Version[xr];
    s.Alive[y] = 0;
    s.Degree[u] = 0;
    --s.Size[xl];
    --s.Size[xr];
    s.Total -= 2;
  };
  std::vector<Vec3> mergedPoints;
  auto tryMerge = [&](Index c, Index p, Index q) {
    // The paper also asks every chain of both patches to be one segment; only the common one
    // has to be (the union of two disks glued along one segment is a disk either way), which
    // lets small patches merge into large curved ones.
    if (s.Size[p] + s.Size[q] - 2 < 3)
    {
      return false;
    }
    // Common boundary = this one chain, and no other common vertex (the union stays a disk).
    const Index stamp = s.NextStamp();
    bool ok = true;
    forPatchChains(q, [&](Index x) {
      if (x != c)
      {
        const Index other = s.Find(s.L[x]) == q ? (s.R[x] == InvalidIndex ? InvalidIndex : s.Find(s.R[x])) : s.Find(s.L[x]);
        ok = ok && other != p;
        s.EndStamp[s.A[x]] = stamp;
        s.EndStamp[s.B[x]] = stamp;
      }
    });
    if (!ok)
    {
      return false;
    }
    forPatchChains(p, [&](Index x) {
      if (x != c)
      {
        for (const Index e : { s.A[x], s.B[x] })
        {
          if (e != s.A[c] && e != s.B[c] && s.EndStamp[e] == stamp)
          {
            ok = false;
          }
        }
      }
    });
    if (!ok)
    {
      return false;
    }
    // Method (3) of section 4.2.8: no merge whose boundary would not project to a simple polygon
    // on the merged normal (it could not be triangulated without flips). Long boundaries are
    // left to the triangulation fallback.
    if (s.Size[p] + s.Size[q] <= MaximumCheckedBoundary &&
      (!boundaryPoints(p, q, c, mergedPoints) || !ProjectsToSimplePolygon(mergedPoints, s.Normal[p] + s.Normal[q])))
    {
      return false;
    }
    if (flatness)
    {
      // The union's extreme vertices: the more extreme of the two in each direction.
      Index* sp = s.Support.data() + size_t(p) * SupportSize;
      const Index* sq = s.Support.data() + size_t(q) * SupportSize;
      for (int d = 0; d < SupportDirections; ++d)
      {
        const Vec3 axis{ SupportAxes[d][0], SupportAxes[d][1], SupportAxes[d][2] };
        if (Dot(axis, mesh.Point(sq[2 * d])) > Dot(axis, mesh.Point(sp[2 * d])))
        {
          sp[2 * d] = sq[2 * d];
        }
        if (Dot(axis, mesh.Point(sq[2 * d + 1])) < Dot(axis, mesh.Point(sp[2 * d + 1])))
        {
          sp[2 * d + 1] = sq[2 * d + 1];
        }
      }
    }
    s.Parent[q] = p;
    s.Version[p] += s.Version[q] + 1;
    s.Normal[p] = s.Normal[p] + s.Normal[q];
    s.Size[p] += s.Size[q] - 2;
    // Splice q's chain list into p's.
    forPatchChains(q, [](Index) {}); // drop q's dead chains before splicing
    if (s.PatchHead[q] != InvalidIndex)
    {
      Index tail = s.PatchHead[q];
      while (s.PatchSlotNext[tail] != InvalidIndex)
      {
        tail = s.PatchSlotNext[tail];
      }
      s.PatchSlotNext[tail] = s.PatchHead[p];
      s.PatchHead[p] = s.PatchHead[q];
      s.PatchHead[q] = InvalidIndex;
    }
    s.Alive[c] = 0;
    --s.Degree[s.A[c]];
    --s.Degree[s.B[c]];
    tryJoin(s.A[c]);
    tryJoin(s.B[c]);
    return true;
  };

  s.Heap.clear();
  s.HeapTop.assign(size_t(nc), -std::numeric_limits<double>::infinity());
  for (Index c = 0; c < nc; ++c)
  {
    pushCandidate(c);
  }
  while (!s.Heap.empty())
  {
    std::pop_heap(s.Heap.begin(), s.Heap.end());
    const auto entry = s.Heap.back();
    s.Heap.pop_back();
    const Index c = entry.second;
    if (entry.first >= s.HeapTop[c])
    {
      s.HeapTop[c] = -std::numeric_limits<double>::infinity();
    }
    if (!movable(c))
    {
      continue;
    }
    Index p = s.Find(s.L[c]), q = s.Find(s.R[c]);
    if (p == q || s.Frozen[p] || s.Frozen[q])
    {
      continue;
    }
    const double d = mergeMeasure(p, q);
    if (d < entry.first - 1e-12)
    {
      pushCandidate(c); // normals changed since: requeue with the current value
      continue;
    }
    if (s.MergeTriedP[c] == s.Version[p] && s.MergeTriedQ[c] == s.Version[q])
    {
      continue; // a duplicate entry: tried before (collapses and merge) and neither patch changed since
    }
    if (parameters.CollapseChains)
    {
      tryCollapses(p, c);
      tryCollapses(q, c);
      if (!movable(c))
      {
        continue;
      }
    }
    s.MergeTriedP[c] = s.Version[p];
    s.MergeTriedQ[c] = s.Version[q];
    if (parameters.MergePatches && tryMerge(c, p, q))
    {
      forPatchChains(p, [&](Index x) { pushCandidate(x); });
    }
  }
  if (parameters.RemovalTarget > 0 && s.Total > parameters.RemovalTarget && parameters.CollapseChains)
  {
    this->RemoveCheapest(parameters, s, [&](Index e, Index keep) {
      relaxed = true;
      forcedKeep = keep;
      s.TriedP[e] = s.TriedQ[e] = -1;
      const bool done = tryCollapse(e, std::numeric_limits<double>::infinity());
      forcedKeep = InvalidIndex;
      relaxed = false;
      return done;
    }, [&](Index u) {
      relaxed = true;
      tryJoin(u);
      relaxed = false;
      return s.Degree[u] == 0;
    }, [&](Index x, Index y, Index u) {
      // Largest surface-weighted distance of the chain vertices between u's kept neighbours
      // from the segment that replaces them.
      size_t a, b;
      joinAround(x, y, u, a, b);
      const Vec3 n1 = Normalized(s.Normal[s.Find(s.L[x])]), n2 = Normalized(s.Normal[s.Find(s.R[x])]);
      const double w2 = this->InPlaneWeight * this->InPlaneWeight;
      double worst = 0;
      for (size_t i = a + 1; i < b; ++i)
      {
        worst = std::max(worst, SurfaceWeightedDistance2(chainPoints[i], chainPoints[a], chainPoints[b], n1, n2, w2));
      }
      return std::sqrt(worst);
    });
  }
}

void SpbmLevelGenerator::RemoveCheapest(const SpbmLevelParameters& parameters, State& s,
  const std::function<bool(Index, Index)>& collapse, const std::function<bool(Index)>& join,
  const std::function<double(Index, Index, Index)>& joinDeviation)
{
  const Patchification& P = *this->Patches;
  const TriangleMesh& mesh = *this->Mesh;
  const Index nc = P.NumberOfChains();
  const Index ne = P.NumberOfEndpoints();
  const double infinite = std::numeric_limits<double>::infinity();
  auto point = [&](Index e) { return mesh.Point(P.EndpointVertex(e)); };
  auto forEndChains = [&](Index e, auto&& f) { s.ForEndChains(e, f); };
  auto movable = [&](Index c) {
    return s.Alive[c] && !s.Locked[c] && s.Interior[c] == 0 && s.R[c] != InvalidIndex &&
      s.Find(s.L[c]) != s.Find(s.R[c]) && !s.Frozen[s.Find(s.L[c])] && !s.Frozen[s.Find(s.R[c])];
  };
  // Moving endpoint `gone` onto `keep` moves the patches around `gone` by the displacement's
  // component along their normals (and, weighted, along the surface).
  auto collapseCost = [&](Index c, Index keep) {
    if (!movable(c))
    {
      return infinite;
    }
    const Index gone = s.A[c] == keep ? s.B[c] : s.A[c];
    if (P.EndpointOnBorder(gone))
    {
      return infinite;
    }
    const Vec3 d = point(gone) - point(keep);
    double cost = this->InPlaneWeight * Norm(d);
    forEndChains(gone, [&](Index x) {
      for (const Index side : { s.L[x], s.R[x] })
      {
        if (side != InvalidIndex)
        {
          cost = std::max(cost, std::fabs(Dot(Normalized(s.Normal[s.Find(side)]), d)));
        }
      }
    });
    return cost;
  };
  auto joinCost = [&](Index u) {
    Index pair[2];
    if (s.Degree[u] != 2 || P.EndpointOnBorder(u) || !s.TwoChainsAt(u, pair) || s.Locked[pair[0]] || s.Locked[pair[1]] || s.R[pair[0]] == InvalidIndex ||
      s.R[pair[1]] == InvalidIndex)
    {
      return infinite;
    }
    const Index xl = s.Find(s.L[pair[0]]), xr = s.Find(s.R[pair[0]]);
    const Index yl = s.Find(s.L[pair[1]]), yr = s.Find(s.R[pair[1]]);
    if (!((xl == yl && xr == yr) || (xl == yr && xr == yl)) || xl == xr)
    {
      return infinite;
    }
    return joinDeviation(pair[0], pair[1], u);
  };
  // Operations: 2c (collapse chain c into its start), 2c + 1 (into its end), 2 nc + u (join at u).
  using Entry = std::pair<double, Index>;
  std::vector<Entry> heap;
  const Index joinBase = 2 * nc;
  auto costOf = [&](Index op) {
    if (op >= joinBase)
    {
      return joinCost(op - joinBase);
    }
    const Index c = op / 2;
    return collapseCost(c, op % 2 == 0 ? s.A[c] : s.B[c]);
  };
  auto push = [&](Index op) {
    const double cost = costOf(op);
    if (cost < infinite)
    {
      heap.emplace_back(-cost, op);
      std::push_heap(heap.begin(), heap.end());
    }
  };
  for (Index c = 0; c < nc; ++c)
  {
    if (movable(c))
    {
      push(2 * c);
      push(2 * c + 1);
    }
  }
  for (Index u = 0; u < ne; ++u)
  {
    push(joinBase + u);
  }
  const long long target = parameters.RemovalTarget;
  while (s.Total > target && !heap.empty())
  {
    std::pop_heap(heap.begin(), heap.end());
    const Entry entry = heap.back();
    heap.pop_back();
    const Index op = entry.second;
    const double cost = costOf(op);
    if (cost == infinite)
    {
      continue;
    }
    if (cost > -entry.first * (1 + 1e-9) + 1e-300)
    {
      heap.emplace_back(-cost, op); // the neighbourhood changed: requeue at its current cost
      std::push_heap(heap.begin(), heap.end());
      continue;
    }
    Index touched[2] = { InvalidIndex, InvalidIndex };
    if (op >= joinBase)
    {
      const Index u = op - joinBase;
      Index ends[2] = { InvalidIndex, InvalidIndex };
      int k = 0;
      forEndChains(u, [&](Index c) {
        if (k < 2)
        {
          ends[k++] = s.A[c] == u ? s.B[c] : s.A[c];
        }
      });
      if (!join(u))
      {
        continue;
      }
      touched[0] = ends[0];
      touched[1] = ends[1];
    }
    else
    {
      const Index c = op / 2;
      const Index keep = op % 2 == 0 ? s.A[c] : s.B[c];
      if (!collapse(c, keep))
      {
        continue;
      }
      touched[0] = keep;
    }
    // Requeue what the change can make possible or cheaper: the chains and joins around it.
    for (const Index e : touched)
    {
      if (e == InvalidIndex)
      {
        continue;
      }
      push(joinBase + e);
      forEndChains(e, [&](Index c) {
        if (movable(c))
        {
          push(2 * c);
          push(2 * c + 1);
        }
        push(joinBase + (s.A[c] == e ? s.B[c] : s.A[c]));
      });
    }
  }
}

Index SpbmLevelGenerator::PredictTriangleCount(const SpbmLevelParameters& parameters)
{
  return this->PredictTriangleCountIn(parameters, *this->Work);
}

Index SpbmLevelGenerator::PredictTriangleCountIn(const SpbmLevelParameters& parameters, State& s)
{
  // Searches (and re-aimed searches) ask for the same levels again: remember the answers.
  const float eps = static_cast<float>(parameters.Epsilon);
  for (const PredictionMemo& m : s.Memo)
  {
    if (m.Epsilon == eps && m.MergeAngle == parameters.MergeAngle && m.MergePatches == parameters.MergePatches &&
      m.CollapseChains == parameters.CollapseChains && m.CollapseLengthFactor == parameters.CollapseLengthFactor &&
      m.JoinWithinEpsilon == parameters.JoinWithinEpsilon && m.CollapseWithinEpsilon == parameters.CollapseWithinEpsilon &&
      m.SizeWeightedMerge == parameters.SizeWeightedMerge && m.FlatnessMerge == parameters.FlatnessMerge &&
      m.FlatnessScale == parameters.FlatnessScale &&
      m.RemovalTarget == parameters.RemovalTarget)
    {
      return m.Count;
    }
  }
  s.NoFreeze.assign(size_t(this->Patches->NumberOfPatches()), 0);
  const auto started = StageClock::now();
  this->RunMerging(parameters, s.NoFreeze, s);
  Times.Merging += Since(started);
  ++Times.MergingRuns;
  if (s.Memo.size() > 256)
  {
    s.Memo.clear();
  }
  s.Memo.push_back({ eps, parameters.MergeAngle, parameters.MergePatches, parameters.CollapseChains,
    parameters.CollapseLengthFactor, parameters.JoinWithinEpsilon, parameters.CollapseWithinEpsilon,
    parameters.SizeWeightedMerge, parameters.FlatnessMerge, parameters.FlatnessScale, parameters.RemovalTarget,
    static_cast<Index>(s.Total) });
  return static_cast<Index>(s.Total);
}

SpbmLevelParameters SpbmLevelGenerator::FindParameters(
  Index target, const SpbmLevelParameters& base, Index* predicted)
{
  return this->FindParametersIn(target, base, predicted, *this->Work);
}

SpbmLevelParameters SpbmLevelGenerator::FindParametersIn(
  Index target, const SpbmLevelParameters& base, Index* predicted, State& s)
{
  SpbmLevelParameters params = base;
  const Index nk = static_cast<Index>(this->SortedKeys.size());
  auto epsilonFor = [&](Index k) { return k < nk ? double(this->SortedKeys[k]) : -1.0; };
  auto countFor = [&](Index k, double angle) {
    SpbmLevelParameters p = params;
    p.Epsilon = epsilonFor(k);
    p.MergeAngle = angle;
    return this->PredictTriangleCountIn(p, s);
  };
  // 1. alpha1: the given one, or (when even single-segment chains give too many triangles) the
  // smallest wider one, up to 90 degrees, that reaches the target.
  // Counts this close below the target are good enough: each evaluation is a whole merging run,
  // and the epsilon search below fills the rest.
  const Index countTolerance = std::max<Index>(2, target / 50);
  double angle = base.MergeAngle;
  if (countFor(0, angle) > target && (base.MergePatches || base.CollapseChains))
  {
    double lo = angle, hi = std::max(90.0, angle);
    Index countLo = countFor(0, lo), countHi = 0;
    // Bracket by doubling alpha1 (the count falls steeply at small angles and flattens toward
    // 90 degrees), stopping at RemovalMergeAngle on the way: the widest (and slowest) merging
    // run, at 90, is evaluated only when nothing narrower reaches the target.
    for (double probe = lo;;)
    {
      double next = probe <= 0 ? hi : std::min(hi, 2 * probe);
      if (base.CostOrderedRemoval && base.CollapseChains && probe < base.RemovalMergeAngle)
      {
        // With the removal, whether it is needed depends on RemovalMergeAngle's count only:
        // probe it first (the regula falsi below narrows the bracket when it is not needed).
        next = std::min(hi, base.RemovalMergeAngle);
      }
      probe = probe < base.RemovalMergeAngle && next > base.RemovalMergeAngle ? base.RemovalMergeAngle : next;
      const Index c = countFor(0, probe);
      const bool removal = base.CostOrderedRemoval && base.CollapseChains && probe == base.RemovalMergeAngle;
      if (c <= target || probe >= hi || removal)
      {
        // (With the cost-ordered removal, alpha1 is not widened beyond RemovalMergeAngle: the
        // removal below reaches the count with less flattening than wider merging.)
        hi = probe;
        countHi = c;
        break;
      }
      lo = probe;
      countLo = c;
    }
    // Even alpha1 = 90 leaves too many triangles (the Fandisk at 150): drop the epsilon bound on
    // collapses (the paper's rule), collapse longer chains (condition (c) up to the patch's
    // longest chain), and last drop the epsilon bound on joins, until the target is reached.
    // The target count wins over the profile curves' epsilon bound here, at a cost in fidelity.
    if (countHi > target && base.CollapseChains && base.CostOrderedRemoval)
    {
      // Remove endpoints cheapest first down to the target (the epsilon bounds stay on the rest).
      // The removal sets the count: alpha1 only bounds which unions become flat patches, and
      // merging up to RemovalMergeAngle (not 90) keeps creases sharper than that as chains.
      params.RemovalTarget = target;
      const double removalAngle = std::min(hi, std::max(angle, base.RemovalMergeAngle));
      const Index c = countFor(0, removalAngle);
      if (c <= target)
      {
        lo = hi = removalAngle;
        countLo = countHi = c;
      }
      else
      {
        hi = std::max(90.0, angle); // the removal alone does not reach it: widest merging too
        countHi = countFor(0, hi);
        countLo = countFor(0, lo);
      }
    }

    if (countHi > target && base.CollapseChains)
    {
      params.RemovalTarget = 0;
      struct Relaxation
      {
        bool Join, Collapse;
        double Factor;
      };
      const Relaxation relaxations[] = { { true, false, base.CollapseLengthFactor }, { true, false, 0.35 },
        { true, false, 0.5 }, { true, false, 0.75 }, { true, false, 1.0 }, { false, false, 1.0 } };
      for (const Relaxation& relaxation : relaxations)
      {
        params.JoinWithinEpsilon = base.JoinWithinEpsilon && relaxation.Join;
        params.CollapseWithinEpsilon = base.CollapseWithinEpsilon && relaxation.Collapse;
        params.CollapseLengthFactor = std::max(base.CollapseLengthFactor, relaxation.Factor);
        countHi = countFor(0, hi);
        if (countHi <= target)
        {
          countLo = countFor(0, lo);
          break;
        }
      }
    }
    if (countHi > target)
    {
      angle = hi;
    }
    else
    {
      // The count falls steeply at small angles and flattens toward 90 degrees: narrow the
      // bracket by doubling alpha1 first, then regula falsi (Illinois) on the count.
      while (lo > 1.0 && 2 * lo < hi && countHi < target - countTolerance)
      {
        const Index c = countFor(0, 2 * lo);
        if (c > target)
        {
          lo = 2 * lo;
          countLo = c;
        }
        else
        {
          hi = 2 * lo;
          countHi = c;
          break;
        }
      }
      int side = 0;
      Index realHi = countHi; // countHi is scaled by the Illinois steps
      for (int iteration = 0; iteration < 6 && hi - lo > 0.05 && realHi < target - countTolerance; ++iteration)
      {
        // Interpolated in log(alpha1): the count is about linear in it (fewer evaluations).
        const double logLo = std::log(std::max(lo, 1e-3)), logHi = std::log(std::max(hi, 1e-3));
        double mid = std::exp(logHi - (logHi - logLo) * double(target - countHi) / std::max(1.0, double(countLo - countHi)));
        mid = std::min(hi - 0.01 * (hi - lo), std::max(lo + 0.01 * (hi - lo), mid));
        const Index c = countFor(0, mid);
        if (c > target)
        {
          lo = mid;
          countLo = c;
          if (side == -1)
          {
            countHi = target + (countHi - target) / 2;
          }
          side = -1;
        }
        else
        {
          hi = mid;
          countHi = c;
          realHi = c;
          if (side == 1)
          {
            countLo = target + (countLo - target) / 2;
          }
          side = 1;
          if (c == target)
          {
            break;
          }
        }
      }
      angle = hi;
    }
  }
  params.MergeAngle = angle;
  // 2. epsilon: the number of kept chain vertices (top keys) whose count comes closest to the
  // target from below.
  Index bestK = 0, bestCount = countFor(0, angle);
  if (bestCount < target - countTolerance)
  {
    Index lo = 0, hi = nk;
    Index countLo = bestCount, countHi = 0;
    // Bracket from below: each kept chain vertex adds about two triangles (one on each side), so
    // step by the missing count over the measured slope (2 at first); the full-resolution count
    // is only needed when the target is beyond every step.
    bool bracketed = false;
    double slope = 2.0;
    for (int step = 0; step < 8 && !bracketed && lo < nk && countLo < target - countTolerance; ++step)
    {
      const Index next = std::min<Index>(nk, lo + std::max<Index>(1, static_cast<Index>(double(target - countLo) / slope)));
      const Index c = countFor(next, angle);
      if (c > target)
      {
        hi = next;
        countHi = c;
        bracketed = true;
      }
      else
      {
        if (c > countLo)
        {
          slope = std::max(0.5, double(c - countLo) / double(next - lo));
        }
        lo = next;
        countLo = c;
      }
    }
    if (!bracketed && lo < nk && countLo < target - countTolerance)
    {
      countHi = countFor(nk, angle);
      bracketed = countHi > target;
      if (!bracketed)
      {
        lo = nk;
        countLo = countHi;
      }
    }
    if (bracketed)
    {
      // Regula falsi (Illinois) over the number of kept vertices: the count grows about
      // linearly with it, so a few evaluations replace a binary search.
      int side = 0;
      Index realLo = countLo; // countLo is scaled by the Illinois steps
      for (int iteration = 0; iteration < 40 && hi - lo > 1 && realLo < target - countTolerance; ++iteration)
      {
        const double spread = std::max(1.0, double(countHi - countLo));
        Index mid = lo + static_cast<Index>(double(hi - lo) * double(target - countLo) / spread);
        mid = std::min(hi - 1, std::max(lo + 1, mid));
        const Index c = countFor(mid, angle);
        if (c > target)
        {
          hi = mid;
          countHi = c;
          if (side == 1)
          {
            countLo = target - (target - countLo) / 2;
          }
          side = 1;
        }
        else
        {
          lo = mid;
          countLo = c;
          realLo = c;
          if (side == -1)
          {
            countHi = target + (countHi - target) / 2;
          }
          side = -1;
          if (c == target)
          {
            break;
          }
        }
      }
    }
    // The count is not strictly monotone (merges, refinements): look around, unless the count
    // found is within the tolerance below the target.
    const Index found = countFor(lo, angle);
    const Index around = found <= target && found >= target - countTolerance ? 0 : 2;
    for (Index k = std::max<Index>(0, lo - around); k <= std::min<Index>(nk, lo + around); ++k)
    {
      const Index c = countFor(k, angle);
      if (c <= target && (bestCount > target || c > bestCount))
      {
        bestK = k;
        bestCount = c;
      }
    }
  }
  params.Epsilon = epsilonFor(bestK);
  if (predicted)
  {
    *predicted = bestCount;
  }
  return params;
}

bool SpbmLevelGenerator::Generate(
  const SpbmLevelParameters& parameters, SpbmLevel& level, const std::function<bool()>& abort)
{
  return this->GenerateIn(parameters, level, abort, *this->Work);
}

bool SpbmLevelGenerator::GenerateIn(
  const SpbmLevelParameters& parameters, SpbmLevel& level, const std::function<bool()>& abort, State& s)
{
  const Patchification& P = *this->Patches;
  const TriangleMesh& mesh = *this->Mesh;
  const Index np = P.NumberOfPatches();
  const Index nc = P.NumberOfChains();
  const Index nv = mesh.NumberOfPoints();
  const Index* base = nc > 0 ? P.ChainVerticesBegin(0) : nullptr;
  s.VertexStamp.resize(size_t(nv), 0);

  std::vector<unsigned char> frozen(size_t(np), 0);
  std::vector<unsigned char> failed;
  std::vector<Index> polygon, other, ring;
  std::vector<Vec3> points;
  std::vector<Index> localStart; // per endpoint, scratch via EndStamp
  std::vector<Index> order;
  level = SpbmLevel();
  const int maxPasses = 2 * 64 + 2;
  for (int pass = 1;; ++pass)
  {
    if (abort && abort())
    {
      return false;
    }
    level.Passes = pass;
    if (pass > maxPasses)
    {
      std::fill(frozen.begin(), frozen.end(), OriginalLevel); // last resort: the input itself
    }
    this->RunMerging(parameters, frozen, s);
    if (pass == 1)
    {
      level.PredictedTriangles = static_cast<Index>(s.Total);
    }
    failed.assign(size_t(np), 0);

    // 1. Vertex sequences of the alive chains (all vertices, with keep flags).
    s.SeqOffsets.assign(size_t(nc) + 1, 0);
    s.SeqVertices.clear();
    s.SeqKeep.clear();
    for (Index c = 0; c < nc; ++c)
    {
      s.SeqOffsets[c] = static_cast<Index>(s.SeqVertices.size());
      if (!s.Alive[c])
      {
        continue;
      }
      const bool single = s.PartFirst[c] == s.PartLast[c];
      s.SeqVertices.push_back(P.EndpointVertex(s.A[c]));
      s.SeqKeep.push_back(1);
      for (Index part = s.PartFirst[c]; part != InvalidIndex; part = s.PartNext[part])
      {
        if (part != s.PartFirst[c])
        {
          // Joint between parts: the endpoint dropped when they were joined.
          s.SeqVertices.push_back(P.EndpointVertex(s.JointBefore[part]));
          s.SeqKeep.push_back(0);
        }
        const Index* v = P.ChainVerticesBegin(part);
        const Index n = P.ChainSize(part);
        const bool reversed = s.PartReversed[part];
        const size_t partStart = s.SeqVertices.size();
        for (Index i = 1; i + 1 < n; ++i)
        {
          s.SeqVertices.push_back(v[reversed ? n - 1 - i : i]);
          s.SeqKeep.push_back(0);
        }
        for (Index j = s.KeptOffsets[part]; j < s.KeptOffsets[part + 1]; ++j)
        {
          const Index k = s.KeptPositions[j];
          s.SeqKeep[partStart + size_t(reversed ? n - 1 - k : k) - 1] = 1;
        }
      }
      s.SeqVertices.push_back(P.EndpointVertex(s.B[c]));
      s.SeqKeep.push_back(1);
      // Forced vertex (lens rule): the top of the hierarchy, or the middle of a joined chain.
      const Index first = s.SeqOffsets[c], count = static_cast<Index>(s.SeqVertices.size()) - first;
      Index kept = 0;
      for (Index i = 1; i + 1 < count; ++i)
      {
        kept += s.SeqKeep[first + i];
      }
      if (kept < s.Interior[c] && count > 2)
      {
        Index best = count / 2;
        if (single)
        {
          const float* keys = this->Keys.data() + (P.ChainVerticesBegin(c) - base);
          for (Index i = 1; i + 1 < count; ++i)
          {
            if (keys[i] > keys[best])
            {
              best = i;
            }
          }
        }
        s.SeqKeep[first + best] = 1;
      }
    }
    s.SeqOffsets[nc] = static_cast<Index>(s.SeqVertices.size());

    // 2. Segments must be unique: refine a chain whose shortcut duplicates another edge.
    for (int round = 0; round < 64; ++round)
    {
      bool changed = false;
      s.Edges.Reset(s.SeqVertices.size());
      for (Index c = 0; c < nc && !changed; ++c)
      {
        Index previous = s.SeqOffsets[c];
        for (Index i = s.SeqOffsets[c] + 1; i < s.SeqOffsets[c + 1]; ++i)
        {
          if (!s.SeqKeep[i])
          {
            continue;
          }
          Index existing;
          // A non-manifold input edge lies on the (full-resolution) chain of every patch around
          // it: the same segment on several non-manifold chains is that one edge, kept as is.
          if (!s.Edges.Insert(s.SeqVertices[previous], s.SeqVertices[i], c, existing) &&
            !(existing >= 0 && P.ChainIsNonManifold(c) && P.ChainIsNonManifold(existing)))
          {
            if (i - previous >= 2)
            {
              s.SeqKeep[(previous + i) / 2] = 1;
              changed = true;
            }
            else
            {
              // Refine the other one (find its segment), else give up on both patches.
              bool refined = false;
              Index prevOther = s.SeqOffsets[existing];
              for (Index j = s.SeqOffsets[existing] + 1; j < s.SeqOffsets[existing + 1] && !refined; ++j)
              {
                if (!s.SeqKeep[j])
                {
                  continue;
                }
                const Index x = s.SeqVertices[prevOther], y = s.SeqVertices[j];
                if (((x == s.SeqVertices[previous] && y == s.SeqVertices[i]) ||
                      (y == s.SeqVertices[previous] && x == s.SeqVertices[i])) &&
                  j - prevOther >= 2)
                {
                  s.SeqKeep[(prevOther + j) / 2] = 1;
                  refined = true;
                }
                prevOther = j;
              }
              if (refined)
              {
                changed = true;
              }
              else
              {
                for (const Index x : { c, existing })
                {
                  failed[s.Find(s.L[x])] = 1;
                  if (s.R[x] != InvalidIndex)
                  {
                    failed[s.Find(s.R[x])] = 1;
                  }
                }
              }
            }
          }
          previous = i;
        }
      }
      if (!changed)
      {
        break;
      }
    }

    // 3. Edges of patches kept as original triangles.
    level.Triangles.clear();
    level.TrianglePatch.clear();
    bool anyOriginal = false;
    for (Index p = 0; p < np; ++p)
    {
      anyOriginal = anyOriginal || frozen[p] == OriginalLevel;
    }
    if (anyOriginal)
    {
      const std::vector<Index>& patchOf = P.TrianglePatches();
      for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
      {
        const Index p = patchOf[t];
        if (frozen[p] != OriginalLevel)
        {
          continue;
        }
        const Index* tri = mesh.Triangle(t);
        for (int k = 0; k < 3; ++k)
        {
          Index existing;
          if (!s.Edges.Insert(tri[k], tri[(k + 1) % 3], -1 - p, existing) && existing >= 0)
          {
            const Index x = existing;
            if (s.Find(s.L[x]) != p && (s.R[x] == InvalidIndex || s.Find(s.R[x]) != p))
            {
              failed[s.Find(s.L[x])] = 1;
              if (s.R[x] != InvalidIndex)
              {
                failed[s.Find(s.R[x])] = 1;
              }
            }
          }
        }
        level.Triangles.insert(level.Triangles.end(), tri, tri + 3);
        level.TrianglePatch.push_back(p);
      }
    }

    // 4. Triangulate every other patch from its simplified boundary, smallest boundaries first:
    // they have the fewest alternative diagonals, large ones can avoid the edges already taken.
    order.clear();
    for (Index p = 0; p < np; ++p)
    {
      if (s.Parent[p] == p && frozen[p] != OriginalLevel && !failed[p])
      {
        order.push_back(p);
      }
    }
    std::stable_sort(order.begin(), order.end(), [&](Index x, Index y) { return s.Size[x] < s.Size[y]; });
    for (size_t orderIndex = 0; orderIndex < order.size(); ++orderIndex)
    {
      const Index p = order[orderIndex];
      if ((orderIndex & 255) == 0 && abort && abort())
      {
        return false;
      }
      // Oriented chains of p, linked end to start.
      ring.clear();
      const Index stamp = s.NextStamp();
      for (Index slot = s.PatchHead[p]; slot != InvalidIndex; slot = s.PatchSlotNext[slot])
      {
        const Index c = slot / 2;
        if (!s.Alive[c])
        {
          continue;
        }
        const bool reversed = s.Find(s.L[c]) != p;
        const Index startEnd = reversed ? s.B[c] : s.A[c];
        if (s.EndStamp[startEnd] == stamp)
        {
          ring.clear();
          break; // two chains leave the same vertex: not a simple loop
        }
        s.EndStamp[startEnd] = stamp;
        ring.push_back(reversed ? -1 - c : c);
      }
      polygon.clear();
      other.clear();
      bool ok = !ring.empty();
      if (ok)
      {
        // Order: follow end -> start through a small search (patch degrees are small).
        std::vector<Index>& order = localStart;
        order.assign(ring.begin(), ring.end());
        auto startOf = [&](Index o) { return o >= 0 ? s.A[o] : s.B[-1 - o]; };
        auto endOf = [&](Index o) { return o >= 0 ? s.B[o] : s.A[-1 - o]; };
        for (size_t i = 0; i + 1 < order.size() && ok; ++i)
        {
          size_t j = i + 1;
          while (j < order.size() && startOf(order[j]) != endOf(order[i]))
          {
            ++j;
          }
          if (j == order.size())
          {
            ok = false;
          }
          else
          {
            std::swap(order[i + 1], order[j]);
          }
        }
        ok = ok && endOf(order.back()) == startOf(order.front());
        for (size_t i = 0; i < order.size() && ok; ++i)
        {
          const Index c = order[i] >= 0 ? order[i] : -1 - order[i];
          const bool reversed = order[i] < 0;
          const Index otherSide = s.R[c] == InvalidIndex
            ? InvalidIndex
            : (reversed ? s.Find(s.L[c]) : s.Find(s.R[c]));
          const Index first = s.SeqOffsets[c], last = s.SeqOffsets[c + 1] - 1;
          for (Index k = 0; k < last - first; ++k) // all but the final vertex
          {
            const Index pos = reversed ? last - k : first + k;
            if (!s.SeqKeep[pos])
            {
              continue;
            }
            polygon.push_back(s.SeqVertices[pos]);
            other.push_back(k == 0 ? InvalidIndex : otherSide);
          }
        }
      }
      // Distinct vertices.
      const Index vstamp = s.NextStamp();
      for (const Index v : polygon)
      {
        ok = ok && s.VertexStamp[v] != vstamp;
        s.VertexStamp[v] = vstamp;
      }
      ok = ok && polygon.size() >= 3;
      if (ok)
      {
        points.resize(polygon.size());
        for (size_t i = 0; i < polygon.size(); ++i)
        {
          points[i] = mesh.Point(polygon[i]);
        }
        const Vec3 normal = Normalized(s.Normal[p]);
        const Index n = static_cast<Index>(polygon.size());
        PolygonTriangulationOptions options;
        options.AllowFallback = false;
        bool doubleEarRule = true;
        options.AcceptEar = [&](Index ia, Index k, Index ic) {
          if (s.Edges.Contains(polygon[ia], polygon[ic]))
          {
            return false; // the diagonal is already an edge: would be non-manifold
          }
          if (doubleEarRule && other[k] != InvalidIndex && ia == (k + n - 1) % n && ic == (k + 1) % n)
          {
            // Double ear: the mirrored triangle would also be an ear of the patch across; keep
            // the one whose normal is closer to its patch normal.
            const Vec3 nt = Cross(points[k] - points[ia], points[ic] - points[ia]);
            if (Dot(nt, normal + Normalized(s.Normal[other[k]])) < 0)
            {
              return false;
            }
          }
          return true;
        };
        PolygonTriangulationResult result;
        result.Failed = true;
        if (parameters.MinimumDeviationTriangulation && n > 3 && n <= parameters.MinimumDeviationMaxVertices)
        {
          // Non-planar boundary: the choice of diagonals decides how far the flat triangulation
          // lies from the original patch; choose the diagonals closest to the original surface.
          Vec3 centroid{ 0, 0, 0 };
          for (const Vec3& x : points)
          {
            centroid = centroid + x;
          }
          centroid = (1.0 / n) * centroid;
          double height = 0;
          for (const Vec3& x : points)
          {
            height = std::max(height, std::fabs(Dot(x - centroid, normal)));
          }
          if (height > parameters.NonPlanarTolerance * this->Diagonal)
          {
            const TriangleBVH& tree = this->GetInputTree();
            MinimumCostTriangulationOptions dp;
            dp.AcceptDiagonal = [&](Index i, Index j) { return !s.Edges.Contains(polygon[i], polygon[j]); };
            auto diagonalCost = [&](Index i, Index j) {
              // Distance of the diagonal's midpoint from the input. (Adding the quarter points
              // tripled the queries, about half of the level's triangulation time, for the same
              // Fandisk levels and 7% on bunny00 at 1500 triangles.)
              return std::sqrt(tree.ClosestPoint(0.5 * (points[i] + points[j])).Distance2);
            };
            dp.DiagonalCost = [&](Index i, Index j) {
              Index bits = 0;
              float cached = 0;
              if (s.DiagonalCosts.Find(polygon[i], polygon[j], bits))
              {
                std::memcpy(&cached, &bits, sizeof(float));
                return double(cached);
              }
              const double cost = diagonalCost(i, j);
              cached = static_cast<float>(cost);
              std::memcpy(&bits, &cached, sizeof(float));
              Index ignored;
              s.DiagonalCosts.Insert(polygon[i], polygon[j], bits, ignored);
              return cost;
            };
            // Thin triangles cost about as much as a diagonal 1e-3 of the diagonal off the surface.
            dp.AngleWeight = 1e-3 * this->Diagonal;
            const auto started = StageClock::now();
            result = TriangulatePolygonMinimumCost(points, normal, dp);
            Times.Triangulation += Since(started);
          }
        }
        if (result.Failed)
        {
          result = TriangulatePolygon(points, normal, options);
        }
        if (result.Failed)
        {
          doubleEarRule = false; // the rule only chooses between sides; never fail because of it
          result = TriangulatePolygon(points, normal, options);
        }
        ok = !result.Failed && result.Triangles.size() + 2 == polygon.size();
        if (ok)
        {
          for (const auto& t : result.Triangles)
          {
            Index ignored;
            for (int k = 0; k < 3; ++k)
            {
              s.Edges.Insert(polygon[t[k]], polygon[t[(k + 1) % 3]], -1, ignored);
            }
            level.Triangles.push_back(polygon[t[0]]);
            level.Triangles.push_back(polygon[t[1]]);
            level.Triangles.push_back(polygon[t[2]]);
            level.TrianglePatch.push_back(p);
          }
        }
      }
      if (!ok)
      {
        failed[p] = 1;
      }
    }

    // 5. Fallback: freeze the failed patches one level further and regenerate.
    bool anyFailed = false;
    for (Index q = 0; q < np; ++q)
    {
      if (failed[s.Find(q)] && frozen[q] < OriginalLevel)
      {
        ++frozen[q];
        anyFailed = true;
      }
    }
    if (!anyFailed)
    {
      break;
    }
  }

  // Compact patch ids and the profile curves.
  std::vector<Index> compact(size_t(np), InvalidIndex);
  Index next = 0;
  for (Index& p : level.TrianglePatch)
  {
    if (compact[p] == InvalidIndex)
    {
      compact[p] = next++;
    }
    p = compact[p];
  }
  level.NumberOfPatches = next;
  level.MergedPatchOf.assign(size_t(np), InvalidIndex);
  for (Index p = 0; p < np; ++p)
  {
    const Index root = s.Find(p);
    level.MergedPatchOf[p] = compact[root] != InvalidIndex ? compact[root] : compact[p];
  }
  for (Index p = 0; p < np; ++p)
  {
    level.UnmergedPatches += frozen[p] == 1;
    level.RefinedPatches += frozen[p] >= 2 && frozen[p] < OriginalLevel;
    level.OriginalPatches += frozen[p] == OriginalLevel;
  }
  level.CurveOffsets.assign(1, 0);
  level.CurveVertices.clear();
  for (Index c = 0; c < nc; ++c)
  {
    if (!s.Alive[c])
    {
      continue;
    }
    for (Index i = s.SeqOffsets[c]; i < s.SeqOffsets[c + 1]; ++i)
    {
      if (s.SeqKeep[i])
      {
        level.CurveVertices.push_back(s.SeqVertices[i]);
      }
    }
    level.CurveOffsets.push_back(static_cast<Index>(level.CurveVertices.size()));
  }
  return true;
}

double SpbmLevelGenerator::EstimateDeviation(const SpbmLevel& level, Index samples) const
{
  const TriangleMesh& mesh = *this->Mesh;
  const Index nt = mesh.NumberOfTriangles();
  if (nt == 0 || level.Triangles.empty())
  {
    return 0;
  }
  const auto started = StageClock::now();
  struct Count
  {
    StageClock::time_point Start;
    ~Count()
    {
      Times.Estimate += Since(Start);
      ++Times.Estimates;
    }
  } count{ started };
  // The level over its own vertices only (it is small), in a BVH.
  TriangleMesh simplified;
  std::vector<Index> local(size_t(mesh.NumberOfPoints()), InvalidIndex);
  simplified.Triangles.reserve(level.Triangles.size());
  for (const Index v : level.Triangles)
  {
    if (local[v] == InvalidIndex)
    {
      local[v] = simplified.NumberOfPoints();
      const Vec3 p = mesh.Point(v);
      simplified.Points.insert(simplified.Points.end(), p.begin(), p.end());
    }
    simplified.Triangles.push_back(local[v]);
  }
  const TriangleBVH bvh(simplified);
  // Samples: the first vertex and the centroid of every stride-th original triangle (every
  // vertex is the first of some triangle, so all are covered at full sampling).
  const Index stride = std::max<Index>(1, nt / std::max<Index>(1, samples / 2));
  double worst2 = 0;
  for (Index t = 0; t < nt; t += stride)
  {
    const Index* v = mesh.Triangle(t);
    const Vec3 a = mesh.Point(v[0]), b = mesh.Point(v[1]), c = mesh.Point(v[2]);
    const Vec3 queries[2] = { a, (1.0 / 3.0) * (a + b + c) };
    for (const Vec3& q : queries)
    {
      // Only samples farther than the current worst matter: a query bounded by it prunes most
      // of the tree and finds nothing exactly when the sample is farther (then measure it).
      if (worst2 > 0 && bvh.ClosestPoint(q, worst2).Triangle != InvalidIndex)
      {
        continue;
      }
      worst2 = std::max(worst2, bvh.ClosestPoint(q).Distance2);
    }
  }
  // The other side, when the input's BVH exists (the minimum-deviation triangulation builds it):
  // the level's largest triangles sampled on the barycentric grid of step 1/3 (the edge thirds
  // and the centroid; the corners are input vertices) against the input. A flat triangle across a
  // concave region can lie far from the input while every input sample is close to some other
  // part of the level (the Fandisk at 150: 0.032 one-sided, 0.041 both ways).
  const TriangleBVH* input = nullptr;
  {
    std::lock_guard<std::mutex> lock(this->LazyMutex);
    input = this->InputTree.get();
  }
  if (input)
  {
    // Budget: the 160 largest triangles (a flat triangle strays the farther the larger it is).
    const size_t count = level.Triangles.size() / 3;
    std::vector<std::pair<double, Index>> bySize(count);
    for (size_t t = 0; t < count; ++t)
    {
      const Vec3 a = mesh.Point(level.Triangles[3 * t]), b = mesh.Point(level.Triangles[3 * t + 1]),
                 c = mesh.Point(level.Triangles[3 * t + 2]);
      bySize[t] = { -Norm(Cross(b - a, c - a)), static_cast<Index>(t) };
    }
    const size_t budget = std::min<size_t>(count, 160);
    std::nth_element(bySize.begin(), bySize.begin() + std::ptrdiff_t(budget) - (budget > 0 ? 1 : 0), bySize.end());
    for (size_t k = 0; k < budget; ++k)
    {
      const size_t t = 3 * size_t(bySize[k].second);
      const Vec3 a = mesh.Point(level.Triangles[t]), b = mesh.Point(level.Triangles[t + 1]),
                 c = mesh.Point(level.Triangles[t + 2]);
      const Vec3 queries[7] = { (1.0 / 3.0) * (a + b + c), (2.0 / 3.0) * a + (1.0 / 3.0) * b,
        (1.0 / 3.0) * a + (2.0 / 3.0) * b, (2.0 / 3.0) * b + (1.0 / 3.0) * c, (1.0 / 3.0) * b + (2.0 / 3.0) * c,
        (2.0 / 3.0) * c + (1.0 / 3.0) * a, (1.0 / 3.0) * c + (2.0 / 3.0) * a };
      for (const Vec3& q : queries)
      {
        if (worst2 > 0 && input->ClosestPoint(q, worst2).Triangle != InvalidIndex)
        {
          continue;
        }
        worst2 = std::max(worst2, input->ClosestPoint(q).Distance2);
      }
    }
  }
  return std::sqrt(worst2);
}

bool SpbmLevelGenerator::GenerateForTarget(Index target, const SpbmLevelParameters& base, SpbmLevel& level,
  SpbmLevelParameters* used, const std::function<bool()>& abort)
{
  Times = StageTimes();
  struct Report
  {
    StageClock::time_point Start = StageClock::now();
    ~Report()
    {
      if (std::getenv("SLOD_VERBOSE"))
      {
        std::fprintf(stderr,
          "[spbm] level %.4f s; main thread: %d merging runs %.4f s (refinement %.4f s), generate %.4f s (input BVH "
          "%.4f s, minimum-deviation triangulation %.4f s), %d estimates %.4f s\n",
          Since(Start), Times.MergingRuns, Times.Merging, Times.Refinement, Times.Generate, Times.Tree,
          Times.Triangulation, Times.Estimates, Times.Estimate);
      }
    }
  } report;
  const bool verbose = std::getenv("SLOD_VERBOSE") != nullptr;
  auto describe = [&](const char* what, const SpbmLevelParameters& p, Index produced, double deviation) {
    if (verbose)
    {
      std::fprintf(stderr,
        "[spbm] %s: weighted %d flat %d alpha1 %.1f eps %.4g factor %.2f join %d collapse %d removal %d: %d tris, "
        "estimate %.4g\n",
        what, int(p.SizeWeightedMerge), int(p.FlatnessMerge), p.MergeAngle, p.Epsilon / this->Diagonal,
        p.CollapseLengthFactor, int(p.JoinWithinEpsilon), int(p.CollapseWithinEpsilon), int(p.RemovalTarget),
        int(produced), deviation / this->Diagonal);
    }
  };
  const bool compare = base.MergePatches && base.MergeAngle > 0 && base.CompareCandidates;
  // Candidates spend the same budget differently; the smallest sampled deviation from the input
  // (EstimateDeviation) wins. The first two (the given merge measure and the other one of
  // plain / size-weighted) run on two threads, each with its own working state.
  SpbmLevelParameters first, second;
  SpbmLevel secondLevel;
  bool secondDone = true;
  double secondDeviation = std::numeric_limits<double>::infinity();
  std::thread helper;
  if (compare)
  {
    SpbmLevelParameters other = base;
    other.SizeWeightedMerge = !base.SizeWeightedMerge;
    other.FlatnessMerge = false;
    helper = std::thread([&, other]() {
      const auto helperStart = StageClock::now();
      Times = StageTimes();
      secondDone = this->GenerateForTargetAndAngle(target, other, secondLevel, &second, abort, *this->Helper);
      if (secondDone)
      {
        secondDeviation = this->EstimateDeviation(secondLevel);
      }
      if (secondDone && second.RemovalTarget > 0)
      {
        // The count comes from the cost-ordered removal, so any merge measure reaches it at the
        // same parameters: also try the flatness measure (no search), keep the closer level.
        SpbmLevelParameters flat = second;
        flat.SizeWeightedMerge = false;
        flat.FlatnessMerge = true;
        SpbmLevel flatLevel;
        secondDone = this->GenerateIn(flat, flatLevel, abort, *this->Helper);
        const Index produced = static_cast<Index>(flatLevel.TrianglePatch.size());
        if (secondDone && produced <= std::max<Index>(target, static_cast<Index>(secondLevel.TrianglePatch.size())))
        {
          const double deviation = this->EstimateDeviation(flatLevel);
          describe("flatness measure (helper)", flat, produced, deviation);
          if (deviation < secondDeviation)
          {
            secondDeviation = deviation;
            std::swap(secondLevel, flatLevel);
            second = flat;
          }
        }
      }
      if (verbose)
      {
        std::fprintf(stderr,
          "[spbm] helper thread %.4f s: %d merging runs %.4f s (refinement %.4f s), generate %.4f s (input BVH %.4f s, "
          "minimum-deviation triangulation %.4f s), %d estimates %.4f s\n",
          Since(helperStart), Times.MergingRuns, Times.Merging, Times.Refinement, Times.Generate, Times.Tree,
          Times.Triangulation, Times.Estimates, Times.Estimate);
      }
    });
  }
  // Without CompareCandidates: when the count will come from the cost-ordered removal, every
  // merge measure reaches it at the same parameters without a search, so the two other measures
  // are generated there too (on the helper thread while this one generates the first level;
  // whichever thread is free takes the next) and the level closest to the input is kept. Cheap
  // next to a search; it matters at the coarsest levels, where the measure decides which large
  // patches become flat. (The plan's search is memoized: the first level's search repeats it for free.)
  SpbmLevelParameters tries[2];
  SpbmLevel triedLevels[2];
  double triedDeviations[2] = { std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity() };
  bool triedFinished[2] = { false, false };
  std::atomic<int> nextTry{ 2 }; // none
  bool triesPlanned = false;
  auto runTries = [&](State& state) {
    for (int j = nextTry++; j < 2; j = nextTry++)
    {
      triedFinished[j] = this->GenerateIn(tries[j], triedLevels[j], abort, state);
      if (triedFinished[j])
      {
        triedDeviations[j] = this->EstimateDeviation(triedLevels[j]);
      }
    }
  };
  if (!compare && base.MergePatches && base.CostOrderedRemoval)
  {
    Index predicted = 0;
    const SpbmLevelParameters planned = this->FindParametersIn(target, base, &predicted, *this->Work);
    if (planned.RemovalTarget > 0)
    {
      tries[0] = tries[1] = planned;
      tries[0].SizeWeightedMerge = !planned.SizeWeightedMerge || planned.FlatnessMerge;
      tries[0].FlatnessMerge = false;
      tries[1].SizeWeightedMerge = false;
      tries[1].FlatnessMerge = !planned.FlatnessMerge;
      if (!planned.FlatnessMerge && !planned.SizeWeightedMerge)
      {
        tries[1].FlatnessMerge = true; // plain first: weighted and flatness
      }
      nextTry = 0;
      triesPlanned = true;
      helper = std::thread([&]() { runTries(*this->Helper); });
    }
  }
  bool done = this->GenerateForTargetAndAngle(target, base, level, &first, abort, *this->Work);
  const Index count = static_cast<Index>(level.TrianglePatch.size());
  double bestDeviation = done && compare ? this->EstimateDeviation(level) : 0.0;
  describe("first", first, count, bestDeviation);
  SpbmLevelParameters best = first;
  // Same budget: not above the target (or the first level's count), not far below it.
  auto sameBudget = [&](Index produced) {
    return !((produced > target && produced > count) || produced < std::min(count, target) * 19 / 20);
  };
  // A narrower alpha1 for the plain measure (fewer merges, finer chains), when alpha1 did not
  // have to be widened (a narrower one would widen to the same level) and no removal was needed.
  SpbmLevel candidate;
  if (done && compare && !base.SizeWeightedMerge && !base.FlatnessMerge && first.MergeAngle <= base.MergeAngle &&
    first.RemovalTarget == 0)
  {
    SpbmLevelParameters narrower = base;
    narrower.MergeAngle = 0.5 * base.MergeAngle;
    SpbmLevelParameters parameters;
    done = this->GenerateForTargetAndAngle(target, narrower, candidate, &parameters, abort, *this->Work);
    if (done)
    {
      const Index produced = static_cast<Index>(candidate.TrianglePatch.size());
      const double deviation = sameBudget(produced) ? this->EstimateDeviation(candidate) : bestDeviation;
      describe("narrower alpha1", parameters, produced, deviation);
      if (deviation < bestDeviation)
      {
        bestDeviation = deviation;
        std::swap(level, candidate);
        best = parameters;
      }
    }
  }
  if (triesPlanned && done)
  {
    runTries(*this->Work); // take what the helper has not started
  }
  if (helper.joinable())
  {
    helper.join();
  }
  if (!done || !secondDone)
  {
    return false;
  }
  if (compare)
  {
    const Index produced = static_cast<Index>(secondLevel.TrianglePatch.size());
    describe("other measure", second, produced, secondDeviation);
    if (sameBudget(produced) && secondDeviation < bestDeviation)
    {
      bestDeviation = secondDeviation;
      std::swap(level, secondLevel);
      best = second;
    }
  }
  else if (base.MergePatches && 20 * count > 21 * target)
  {
    // The target is beyond what this measure reaches (unreachable counts: the femur, armadillo
    // at 1%): the other measure may merge further; keep the level closer to the target.
    SpbmLevelParameters other = base;
    other.SizeWeightedMerge = !base.SizeWeightedMerge;
    other.FlatnessMerge = false;
    SpbmLevelParameters parameters;
    if (!this->GenerateForTargetAndAngle(target, other, candidate, &parameters, abort, *this->Work))
    {
      return false;
    }
    describe("other measure (target not reached)", parameters, static_cast<Index>(candidate.TrianglePatch.size()), 0.0);
    if (candidate.TrianglePatch.size() < level.TrianglePatch.size())
    {
      std::swap(level, candidate);
      best = parameters;
    }
  }
  if (triesPlanned)
  {
    for (int i = 0; i < 2; ++i)
    {
      if (!triedFinished[i])
      {
        return false; // aborted
      }
    }
    if (!compare && bestDeviation == 0.0)
    {
      bestDeviation = this->EstimateDeviation(level);
      describe("first", first, count, bestDeviation);
    }
    for (int i = 0; i < 2; ++i)
    {
      const Index produced = static_cast<Index>(triedLevels[i].TrianglePatch.size());
      describe("removal, other measure", tries[i], produced, triedDeviations[i]);
      if (sameBudget(produced) && triedDeviations[i] < bestDeviation)
      {
        bestDeviation = triedDeviations[i];
        std::swap(level, triedLevels[i]);
        best = tries[i];
      }
    }
  }
  if (used)
  {
    *used = best;
  }
  return true;
}

bool SpbmLevelGenerator::GenerateForTargetAndAngle(Index target, const SpbmLevelParameters& base,
  SpbmLevel& level, SpbmLevelParameters* used, const std::function<bool()>& abort, State& s)
{
  // Fallbacks add triangles the prediction does not know about: aim lower by the overshoot and
  // keep the best level (closest count not above the target, else the smallest).
  Index aim = target;
  bool haveBest = false;
  SpbmLevel candidate;
  for (int attempt = 0; attempt < 6; ++attempt)
  {
    Index predicted = 0;
    const SpbmLevelParameters parameters = this->FindParametersIn(aim, base, &predicted, s);
    const auto started = StageClock::now();
    const bool generated = this->GenerateIn(parameters, candidate, abort, s);
    Times.Generate += Since(started);
    if (!generated)
    {
      return false;
    }
    const Index produced = static_cast<Index>(candidate.TrianglePatch.size());
    const Index best = haveBest ? static_cast<Index>(level.TrianglePatch.size()) : 0;
    // Closest on a log scale, ties to the one not above the target: a re-aimed level far below
    // the target (when fallbacks cannot be avoided) must not win over a moderate overshoot.
    auto distance = [&](Index count) { return std::fabs(std::log(double(std::max<Index>(count, 1)) / double(target))); };
    const bool better = !haveBest || distance(produced) < distance(best) - 1e-12 ||
      (std::fabs(distance(produced) - distance(best)) <= 1e-12 && produced <= target && best > target);
    if (better)
    {
      std::swap(level, candidate);
      if (used)
      {
        *used = parameters;
      }
      haveBest = true;
    }
    if (produced <= target || predicted > aim)
    {
      break; // reached, or even the coarsest level of the search is above the aim: re-aiming cannot help
    }
    const Index next = std::max<Index>(4, aim - (produced - target));
    if (next == aim)
    {
      break;
    }
    aim = next;
  }
  return true;
}
} // namespace slod
