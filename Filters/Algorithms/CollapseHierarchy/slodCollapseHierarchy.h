// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm CollapseHierarchy: smooth hierarchical surface triangulations by triangle collapse
// (Gieng, Hamann, Joy, Schussman, Trotts, IEEE Visualization 1997).
//
// Build() reduces a closed or open manifold triangle mesh M0 by batches of triangle collapses:
// every triangle T gets a least-squares quadratic height field fitted over T's plane to the
// ancestral original points of its stencil (slodQuadraticFit), which gives the collapse point
// c + f(0,0) n and the absolute curvature |k1| + |k2| at the centroid. Its weight is
//   W(T) = A(T) (wk kappa(T) / max kappa + wa alpha(T) + wv |val(cP) - 6| / mv),
// alpha(T) = 2 (sum cos(angles) - 1) (0 degenerate .. 1 equilateral). Each level takes triangles
// in increasing weight order (a priority order rebuilt per level by partial sorting), keeps up to
// BatchFraction of the live triangles that are collapsible (slodTriangleStencil) and have pairwise
// disjoint stencils, collapses them together and refits the triangles around the new vertices.
// This yields the levels M0 .. Mn. Beyond the paper (all optional, see the parameters): the
// quadric error of the ancestral planes as weight and collapse point, edge swaps, and edge
// collapses (two vertices to one point) where a triangle collapse is blocked or much dearer,
// stored like the triangle collapses (HierarchyCollapse::Count = 2).
//
// Representation (compact, reversible, fast to blend):
//  - global vertices: the input points followed by one collapse point per collapse;
//  - triangle lifetimes: every triangle version (its M0 slot and the corner it changed, replayed
//    into global vertex ids) with the collapse count at which it appears (Birth) and disappears
//    (Death); the mesh after K collapses is the set of versions with Birth <= K < Death, and
//    M_i = the mesh after LevelStart(i) collapses;
//  - per collapse the EditableMesh record (flat), so Refine() splits the vertex exactly (Undo).
// M_i(t) moves the vertices of level i's collapsing triangles linearly to their collapse points.
#ifndef slodCollapseHierarchy_h
#define slodCollapseHierarchy_h

#include "slodCollapseRecords.h"
#include "slodEditableMesh.h"
#include "slodPointStore.h"
#include "slodQuadric.h"
#include "slodQuadraticFit.h"
#include "slodStageClock.h"
#include "slodTriangleStencil.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT CollapseHierarchyParameters
{
  // W(T) = A(T) (CurvatureWeight kappa + AngleWeight alpha + ValenceWeight V); normalised to sum 1.
  double CurvatureWeight = 1.0 / 3.0;
  double AngleWeight = 1.0 / 3.0;
  double ValenceWeight = 1.0 / 3.0;
  // Blend with a geometric error term (not in the paper): W = (1 - e) W_paper + e E(T), where E(T)
  // is the area-weighted squared distance of the collapse point to the planes of the original
  // triangles merged into T's vertices (quadric error), divided by the squared mean triangle area.
  // 0 gives the paper's weights exactly.
  double ErrorWeight = 0.0;
  // Added to the quadric error E(T) (not in the paper): this factor times the mean triangle area
  // times the largest mean squared distance of the collapse point to the ancestral planes of one
  // merged vertex. Keeps crease and corner vertices on their planes even where the faces around
  // them are small (the plain area-weighted sum makes narrow strips cheap to flatten). 0: off.
  double VertexErrorWeight = 0.0;
  // Collapse point: the paper's c + f(0,0) n on the fitted quadratic (false), or the point of
  // least quadric error (true; needs ErrorWeight > 0): the quadric's minimum when it is well
  // conditioned and near T (creases, corners), else the minimum on the line c + s n.
  bool QuadricCollapsePoint = false;
  // Adaptive threshold of a batch: when > 0, a level looks no deeper into the priority order than
  // this factor times the batch size, so that cheap triangles blocked by the rules do not force
  // expensive ones into the batch (a level still takes at least a quarter of its batch size, so
  // that levels keep making progress). Counted like the batch, in triangle collapses: a candidate
  // ordered by its edge collapse counts half. 0: unlimited (paper).
  double BatchSearchDepth = 0.0;
  // Fraction of the live triangles collapsed per level (at most).
  double BatchFraction = 0.025;
  // Only triangles with W(T) / (mean input triangle area) below this are collapsed (0: no limit).
  double MaximumWeight = 0.0;
  // m_v of V(T) = |val(cP) - 6| / m_v; 0: the largest |val - 6| over the input's triangles.
  double ValenceNormalizer = 0.0;
  // Swap edges to remove stencil cycles (valence-3 vertices) from M0 before reducing (Fig. 3).
  bool RemoveCycles = false;
  // Rule (3) also passes when the stencil polygon is star-shaped in the plane of the stencil's mean
  // normal (not only in T's plane, which is tilted against its neighbourhood for long thin
  // triangles and on coarse levels). Off: the paper's rule.
  bool StarShapedInStencilPlane = false;
  // Between levels, swap edges so that vertices of valence three or four around the new collapse
  // points reach valence five (Fig. 3 applied on every level, not only to M0): such vertices block
  // the collapses of their neighbours by rule (2). Only hinges whose triangles' normals agree to
  // SwapMinimumNormalDot are swapped, so creases and curved parts keep their edges. M_(i+1) shows
  // the swapped edges; M_i(t) blends the collapses in the triangulation before the swaps.
  bool SwapBlockingEdges = false;
  double SwapMinimumNormalDot = 0.95;
  // When a level finds no collapsible triangle at all (even relaxed), swap with this looser limit
  // over the whole mesh and retry the level (no effect when >= SwapMinimumNormalDot).
  double SwapMinimumNormalDotWhenBlocked = 1.0;
  // When no triangle passes the paper's rules, retry the level with rule (2) relaxed (a valence-3
  // vertex may appear) and rule (3) also tried in the stencil's mean plane, instead of stopping.
  bool RelaxWhenBlocked = false;
  // Edge collapses where triangle collapses are blocked (not in the paper): a triangle that fails
  // the rules (incomplete or cyclic stencil, valence-four rule, star shape, mesh check) collapses
  // its cheapest edge instead (two vertices to the point of least quadric error on the edge or
  // an end point, chosen by the quadric error of the ancestral planes; checked like any collapse),
  // in the same batches, records and blends.
  //  Off: triangle collapses only (paper).
  //  WhenBlocked: only in levels where no triangle collapse is possible at all (the final levels of
  //    meshes with thin parts), so that the targets are still reached.
  //  Everywhere: any blocked triangle may take an edge collapse, in its place in the priority order.
  enum class EdgeFallback
  {
    Off,
    WhenBlocked,
    Everywhere
  };
  EdgeFallback EdgeCollapses = EdgeFallback::Off;
  // With EdgeCollapses Everywhere: a triangle whose cheapest edge collapse has less than this
  // factor times the quadric error of its triangle collapse takes the edge collapse (and is
  // ordered by its error) even when the triangle collapse is allowed. 0: edges only where blocked.
  double PreferEdgeFactor = 0.0;
  // No collapse may leave an interior vertex of valence three (or less) where there was none:
  // rule (2) extended to the edge collapses (an interior vertex opposite the edge may not have
  // valence four, the merged vertex may not get fewer than four neighbours unless one of the two
  // had), and a triangle collapse may not leave a three-sided stencil polygon. A valence-3 vertex
  // makes needle and cap triangles and blocks its neighbours' triangle collapses (a cyclic
  // stencil). Lifted with the relaxed rules (RelaxWhenBlocked: a level where nothing else can
  // collapse), so that targets are still reached, and on levels with 5% of M0's triangles or
  // fewer (ValenceRuleHolds). Under the rule the edges that merge an interior valence-4 vertex
  // are ordered at half their error (ValenceDiscount: else such vertices pile up and jam the
  // last levels). Off: edge collapses may make them anywhere, and the order is the error's.
  bool PreventNewValenceThree = false;
  int MaximumNumberOfLevels = 1000;
  // Stop once a level has at most this many triangles (0: reduce as far as possible).
  Index MinimumNumberOfTriangles = 0;
  // Stop once a level has at most this many triangles, with the batches unchanged (unlike
  // MinimumNumberOfTriangles, which shrinks the last batches to land on it): the levels built are
  // those of the whole hierarchy, so a cut at this count is the same. 0: no stop.
  Index StopAtTriangles = 0;
  // Flip guard of the collapse (EditableMesh::CheckCollapse MinimumNormalDot).
  double MinimumNormalDot = 0.2;
  // Weight of the planes through M0's border edges (perpendicular to their triangles) in the
  // quadrics, relative to the triangle planes (0: free borders); why 10: DefaultBorderPlaneWeight.
  double BoundaryWeight = DefaultBorderPlaneWeight;
  // Keep each triangle edge's edge collapse cost until one of its ends moves (15 bytes per input
  // triangle; fewer edge collapses priced again, the same hierarchy). Off: every evaluation prices
  // its three edges.
  bool ReuseEdgeCosts = true;
  // With more than one thread, the batch selection decides the coming candidates' choices in
  // parallel (ChooseAhead); the hierarchy is the same. Off by default: on the shared 2 cores (load
  // 20-25) it cost 13-15% more CPU time on mc1m for no wall time measurable there (session 25).
  bool DecideAhead = false;
  // The batch's collapses applied in runs, concurrently (vtkSMPTools), each collapse writing the
  // slots prefix sums give it (its index, reference block, versions, records): the same hierarchy,
  // bit for bit, for any number of threads. Off: one by one (the serial reference).
  bool ParallelCollapses = true;
  // Upkeep of the working data run concurrently (vtkSMPTools): the nine compactions of CompactRows
  // as tasks, and the test of an evaluation's normal against T's own (StoreEvaluation) made in
  // the concurrent evaluation. The same hierarchy, bit for bit, for any number of threads. Off:
  // in serial (the reference).
  bool ParallelBookkeeping = true;
  // Test support: every edge pricing also computes its placements' exact errors and compares the
  // costs (EdgeCostsBothWays, EdgeCostOf) with those of the bounded end points (session 41):
  // NumberOfPricingMismatches() must stay 0. The same hierarchy either way.
  bool VerifyBoundedPricing = false;
  // FindEdgeCollapse's edge trials test an edge's topology (the link condition, borders) before
  // any of its points' geometry, so that no point of an edge that fails it is tested (session 43).
  // Off (test support): the geometry first, as before. The same hierarchy either way.
  bool TopologyBeforeTrialPoints = true;
  // Selection passes whose blocked stamps are kept as 1-byte indices before the blocked columns
  // turn into full stamps (at most 255). Lower only to exercise the wide columns: the same
  // hierarchy, bit for bit, at any value.
  int NarrowBlockedEpochs = 255;
};

// One collapse as GetCollapse hands it out (the hierarchy keeps only its sources, triangle and
// weight: the point, count and level follow from its index, its sources and the level starts).
struct SURFACELODFILTERS_EXPORT HierarchyCollapse
{
  Index Sources[3];   // global ids of the collapsed triangle's vertices (edge: Sources[2] = -1)
  int Count = 3;      // 3 triangle collapse, 2 edge collapse (EdgeCollapses fallback)
  Index Point;        // global id of the collapse point
  int Level;          // M_Level -> M_Level+1
  Index Triangle;     // the triangle's id in M0 numbering
  double Weight;      // W(T) / mean input area when it was selected
};

// A mesh of the hierarchy, ready to hand to VTK.
struct SURFACELODFILTERS_EXPORT HierarchyMesh
{
  std::vector<double> Points;        // xyz
  std::vector<Index> Triangles;      // 3 per triangle, output point ids
  std::vector<Index> PointGlobal;    // global vertex of each output point
  std::vector<Index> PointTarget;    // global collapse point it moves to (blend), or -1
  std::vector<int> TriangleCollapseLevel; // level at which this triangle disappears, -1 never
  std::vector<Index> TriangleBatch;  // collapse (index within the blended batch) of the stencil, -1
  std::vector<unsigned char> TriangleRole; // 2 collapsing triangle, 1 its stencil, 0 other
  std::vector<Index> TriangleOrigin; // the M0 triangle this one descends from (same slot)
  double BlendT = 0;
  void Clear();
};

// The rows of the elements (triangle slots, vertices) live at the last compaction, in index
// order: the row of element i is the number of such elements before it, a rank over one bit per
// element (12 bytes per 64 elements instead of a 4-byte row per element: about 8 bytes per input
// vertex less for the triangles, 4 for the vertices, for the whole build; the 64-element words fit
// in the caches where the row array did not).
class SURFACELODFILTERS_EXPORT LiveRowIndex
{
public:
  // n elements, element i in row i.
  void Reset(size_t n);
  // Was element i live at the last compaction (does it have a row)?
  bool HasRow(size_t i) const { return (this->Words[i >> 6].Bits >> (i & 63)) & 1u; }
  // Its row (only for an element that has one).
  size_t Row(size_t i) const
  {
    const Word& w = this->Words[i >> 6];
    return size_t(w.Base) + PopCount(w.Bits & ((std::uint64_t(1) << (i & 63)) - 1));
  }
  const void* Address(size_t i) const { return &this->Words[i >> 6]; } // (prefetch)
  // f(i, row) for the elements with a row in [begin, end) of the rows, in order (the inverse of
  // Row: a binary search for the word of row `begin`, then the words' set bits).
  template <typename Functor>
  void ForEachRow(size_t begin, size_t end, Functor&& f) const;
  // The elements of increasing rows, one at a time (walks that read a few of their rows' slots:
  // each costs the set bits skipped since the one before, words skipped by their bases).
  class Cursor;
  size_t NumberOfElements() const { return this->Elements; }
  // Rows for the elements with a row that are alive(i), in index order; returns
  // which old rows are kept (a bit per old row), for the arrays compacted to the new rows.
  template <typename Alive>
  std::vector<std::uint64_t> Renumber(Alive&& alive);
  size_t MemoryBytes() const { return this->Words.capacity() * sizeof(Word); }
  void Release() { std::vector<Word>().swap(this->Words); this->Elements = 0; }

private:
  static size_t PopCount(std::uint64_t x)
  {
    // (Bit arithmetic: the build has no popcnt instruction by default.)
    x -= (x >> 1) & 0x5555555555555555u;
    x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fu;
    return size_t((x * 0x0101010101010101u) >> 56);
  }
#pragma pack(push, 4)
  struct Word
  {
    std::uint64_t Bits; // bit j: element 64 w + j has a row
    Index Base;         // rows of the elements before the word's
  };
#pragma pack(pop)
  static_assert(sizeof(Word) == 12, "a rank word per 64 elements");
  std::vector<Word> Words;
  size_t Elements = 0;
};

class LiveRowIndex::Cursor
{
public:
  explicit Cursor(const LiveRowIndex& index)
    : Words(index.Words)
  {
  }
  // (row at least the one asked before, and below the number of rows)
  size_t ElementOf(size_t row)
  {
    if (this->W == Unset)
    {
      const auto after = std::upper_bound(this->Words.begin(), this->Words.end(), row,
        [](size_t r, const Word& w) { return r < size_t(w.Base); });
      this->Enter(size_t(after - this->Words.begin()) - 1);
    }
    while (this->W + 1 < this->Words.size() && size_t(this->Words[this->W + 1].Base) <= row)
    {
      this->Enter(this->W + 1);
    }
    for (; this->At < row; ++this->At) // (at most 63 per word)
    {
      this->Bits &= this->Bits - 1;
    }
    return 64 * this->W + size_t(__builtin_ctzll(this->Bits));
  }

private:
  static constexpr size_t Unset = ~size_t(0);
  void Enter(size_t w)
  {
    this->W = w;
    this->Bits = this->Words[w].Bits;
    this->At = size_t(this->Words[w].Base);
  }
  const std::vector<Word>& Words;
  size_t W = Unset, At = 0;
  std::uint64_t Bits = 0;
};

template <typename Functor>
void LiveRowIndex::ForEachRow(size_t begin, size_t end, Functor&& f) const
{
  if (begin >= end)
  {
    return;
  }
  // The last word whose rows start at or before `begin` holds it (bases never decrease).
  const auto after = std::upper_bound(this->Words.begin(), this->Words.end(), begin,
    [](size_t row, const Word& w) { return row < size_t(w.Base); });
  size_t w = size_t(after - this->Words.begin()) - 1;
  std::uint64_t bits = this->Words[w].Bits;
  for (size_t skip = begin - size_t(this->Words[w].Base); skip > 0; --skip) // (at most 63)
  {
    bits &= bits - 1;
  }
  for (size_t row = begin;;)
  {
    if (row + PopCount(bits) < end)
    {
      for (; bits != 0; bits &= bits - 1) // (the whole word: no test of the end per element)
      {
        f(64 * w + size_t(__builtin_ctzll(bits)), row++);
      }
    }
    else
    {
      for (; row < end; bits &= bits - 1)
      {
        f(64 * w + size_t(__builtin_ctzll(bits)), row++);
      }
      return;
    }
    if (++w == this->Words.size())
    {
      return;
    }
    bits = this->Words[w].Bits;
  }
}

template <typename Alive>
std::vector<std::uint64_t> LiveRowIndex::Renumber(Alive&& alive)
{
  // A bit per old row, not the old row of each kept one (4 bytes per live row: 6 bytes per input
  // vertex on top of the working data at the first compactions, the build's peak).
  const size_t oldRows = this->Words.empty() ? 0
                                             : size_t(this->Words.back().Base) + PopCount(this->Words.back().Bits);
  std::vector<std::uint64_t> kept((oldRows + 63) / 64, 0);
  Index newRows = 0;
  size_t oldRow = 0;
  for (size_t w = 0; w < this->Words.size(); ++w)
  {
    Word& word = this->Words[w];
    word.Base = newRows;
    for (std::uint64_t bits = word.Bits; bits != 0; bits &= bits - 1)
    {
      const size_t j = size_t(__builtin_ctzll(bits));
      if (alive(static_cast<Index>(64 * w + j)))
      {
        kept[oldRow >> 6] |= std::uint64_t(1) << (oldRow & 63);
        ++newRows;
      }
      else
      {
        word.Bits &= ~(std::uint64_t(1) << j); // dead (nothing dead comes back: swaps reuse their slots)
      }
      ++oldRow;
    }
  }
  return kept;
}

// Non-negative integers in the fewest bits the largest of them needs, read at any index: the
// finished hierarchy's triangle versions (their codes and deaths, 4 bytes each in the build's
// arrays, which threads write concurrently) take 20 to 22 bits a field on a 1M-triangle input.
class SURFACELODFILTERS_EXPORT BitPackedArray
{
public:
  // n values, value i = valueAt(i), none above `largest` (which sets the width).
  template <typename ValueAt>
  void Assign(size_t n, std::uint64_t largest, ValueAt&& valueAt);
  std::uint64_t operator[](size_t i) const
  {
    const size_t bit = i * this->Width;
    const size_t w = bit >> 6;
    const unsigned shift = unsigned(bit & 63);
    std::uint64_t v = this->Words[w] >> shift;
    if (shift + this->Width > 64)
    {
      v |= this->Words[w + 1] << (64 - shift);
    }
    return v & this->Mask;
  }
  size_t size() const { return this->Count; }
  unsigned BitsPerValue() const { return this->Width; }
  size_t MemoryBytes() const { return this->Words.capacity() * sizeof(std::uint64_t); }
  void Release()
  {
    std::vector<std::uint64_t>().swap(this->Words);
    this->Count = 0;
  }

private:
  std::vector<std::uint64_t> Words;
  size_t Count = 0;
  unsigned Width = 1;
  std::uint64_t Mask = 1;
};

template <typename ValueAt>
void BitPackedArray::Assign(size_t n, std::uint64_t largest, ValueAt&& valueAt)
{
  this->Width = 1;
  while (this->Width < 64 && (largest >> this->Width) != 0)
  {
    ++this->Width;
  }
  this->Mask = this->Width == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << this->Width) - 1;
  this->Count = n;
  std::vector<std::uint64_t>((n * this->Width + 63) / 64, 0).swap(this->Words);
  for (size_t i = 0; i < n; ++i)
  {
    const std::uint64_t v = valueAt(i) & this->Mask;
    const size_t bit = i * this->Width;
    const unsigned shift = unsigned(bit & 63);
    this->Words[bit >> 6] |= v << shift;
    if (shift + this->Width > 64)
    {
      this->Words[(bit >> 6) + 1] |= v >> (64 - shift);
    }
  }
}

class SURFACELODFILTERS_EXPORT CollapseHierarchy
{
public:
  // Progress in [0,1]; return false to abort (Build then returns false).
  using ProgressFunction = std::function<bool(double)>;

  bool Build(const TriangleMesh& mesh, const CollapseHierarchyParameters& parameters,
    const ProgressFunction& progress = ProgressFunction());
  // The same, taking the mesh as M0 instead of copying it (the caller's copy is not held twice).
  bool Build(TriangleMesh&& mesh, const CollapseHierarchyParameters& parameters,
    const ProgressFunction& progress = ProgressFunction());
  // The same with the mesh's non-manifold vertex flags already known (the input preparation's
  // PreparationReport::NonManifoldVertexFlags, for exactly this mesh): M0's set-up does not
  // classify the mesh a second time. Computed as without them when their size is not the mesh's
  // vertex count or when RemoveCycles changes M0 first.
  bool Build(TriangleMesh&& mesh, std::vector<unsigned char>&& nonManifoldVertices,
    const CollapseHierarchyParameters& parameters, const ProgressFunction& progress = ProgressFunction());
  // How many builds took their non-manifold vertex flags as given (the others computed them).
  int NumberOfBuildsWithGivenFlags() const { return this->BuildsWithGivenFlags; }

  // Meshes M0..Mn: NumberOfLevels() = n + 1.
  int NumberOfLevels() const { return static_cast<int>(this->LevelStarts.size()); }
  Index NumberOfCollapses() const { return static_cast<Index>(this->Collapses.size()); }
  Index NumberOfEdgeCollapses() const { return this->EdgeCollapseCount; }
  // Collapses whose checks ran again when their batch was collapsed: those whose region shares a
  // vertex with the region of an earlier collapse of the batch (the others cannot have changed).
  Index NumberOfBatchRechecks() const { return this->BatchRechecks; }
  // Edge collapses of a batch dropped because an earlier one took an opposite vertex down to
  // valence four (PreventNewValenceThree; MarkSharedOpposites).
  Index NumberOfValenceRefusals() const { return this->ValenceRefusals; }
  // With VerifyBoundedPricing: edge pricings whose costs (either way) differ from those of the
  // exact errors, and end points whose error the pricing bounded instead of computing.
  long long NumberOfPricingMismatches() const { return this->PricingMismatches; }
  long long NumberOfBoundedEndPoints() const { return this->BoundedEndPoints; }
  // FindEdgeCollapse's edge trials (after a failed known cheapest): the points tested, and those of
  // of them on an edge that no point passes (its topology fails, or a vertex is locked): in vain.
  long long NumberOfTrialPoints() const { return this->TrialPoints; }
  long long NumberOfTrialPointsOnRefusedEdges() const { return this->TrialPointsOnRefusedEdges; }
  // Collapses applied in runs, concurrently (ParallelCollapses; the others one by one).
  Index NumberOfCollapsesInRuns() const { return this->CollapsesInRuns; }
  // The batch selection's choices (a candidate's collapse, decided when its region is free): those
  // decided ahead, concurrently, and used (DecideAhead, more than one thread), those the selection
  // decided itself in order, and every choice decided ahead (the used ones and the wasted ones).
  Index NumberOfChoicesAhead() const { return this->ChoicesAhead; }
  Index NumberOfChoicesInOrder() const { return this->ChoicesInOrder; }
  Index NumberOfChoicesDecidedAhead() const { return this->ChoicesDecidedAhead; }
  Index NumberOfSwaps() const { return this->Records.NumberOfFlips(); }
  // Triangle versions stored (M0's and every one a collapse or swap gave birth to).
  Index NumberOfTriangleVersions() const { return this->NumberOfEntries(); }
  // Edge swaps made after `collapses` collapses (between M_i(1) and M_i+1 when collapses =
  // LevelStart(i + 1)); each changes two triangles.
  Index SwapsAfter(Index collapses) const
  {
    const auto range = this->Records.FlipsAfter(collapses - 1);
    return range.second - range.first;
  }
  Index LevelStart(int level) const { return this->LevelStarts[level]; }
  // Only collapses remove triangles (swaps keep the count): M0's count less those the records list
  // as removed (no count kept per collapse).
  Index NumberOfTrianglesAfter(Index collapses) const
  {
    return this->Base.NumberOfTriangles() - this->Records.RemovedOffsets[size_t(collapses)];
  }
  Index LevelTriangleCount(int level) const { return this->NumberOfTrianglesAfter(this->LevelStarts[level]); }
  // The fewest collapses whose result has at most target triangles (all of them when even the
  // coarsest cut has more).
  Index CollapsesForTriangleCount(Index target) const;
  HierarchyCollapse GetCollapse(Index k) const;
  // Level whose batch contains collapse k (the last level starting at or before k; levels are
  // never empty).
  int LevelOfCollapse(Index k) const
  {
    return static_cast<int>(std::upper_bound(this->LevelStarts.begin(), this->LevelStarts.end(), k) -
             this->LevelStarts.begin()) - 1;
  }
  // Global id of collapse k's point: the collapse points follow the input points in order.
  Index PointOfCollapse(Index k) const { return this->NumberOfBasePoints() + k; }
  // 3 for a triangle collapse, 2 for an edge collapse.
  int CountOfCollapse(Index k) const { return this->Collapses[k].Sources[2] == InvalidIndex ? 2 : 3; }

  Index NumberOfVertices() const
  {
    return this->NumberOfBasePoints() + static_cast<Index>(this->CollapsePoints.size() / 3);
  }
  Vec3 Vertex(Index g) const
  {
    const Index np = this->NumberOfBasePoints();
    if (g < np)
    {
      return this->BasePoints.Point(g);
    }
    const double* p = &this->CollapsePoints[3 * size_t(g - np)];
    return { p[0], p[1], p[2] };
  }
  // M0 (the input, or the input after cycle-removing swaps), assembled: its points are held apart
  // (BasePoints).
  TriangleMesh BaseMesh() const { return { this->BasePoints.Coordinates(), this->Base.Triangles }; }
  // Largest curvature of M0 (1 when not computed: ErrorWeight 1 with QuadricCollapsePoint).
  double MaximumCurvature() const { return this->KappaMax; }
  double ValenceNormalizer() const { return this->Mv; }

  // The mesh after `collapses` collapses, with the collapses [collapses, blendEnd) partially
  // applied with parameter t in [0,1] (their triangles' vertices moved toward the collapse point).
  void Extract(Index collapses, Index blendEnd, double t, HierarchyMesh& out) const;
  // M_i(t) for level = i + t (clamped to [0, n]); M_n for level >= n.
  void ExtractLevel(double level, HierarchyMesh& out) const;

  // Vertex splits: the coarsest mesh as an EditableMesh (M0 numbering), and the undo of
  // collapse k (collapses must be refined newest first; the edge swaps made after collapse k are
  // undone first).
  const EditableMesh& CoarsestMesh() const { return this->Mesh; }
  // The collapses and swaps as Refine replays them (M0 numbering).
  const CollapseRecords& SplitRecords() const { return this->Records; }
  void Refine(EditableMesh& mesh, Index k) const;
  // The reverse of the hierarchy: the coarsest mesh expanded by vertex splits (Refine, newest
  // first) until `collapses` collapses are left (LevelStart(i) gives M_i; any count between gives
  // a cut inside a batch, as CollapsesForTriangleCount). `out` holds the live triangles in M0 slot
  // order with their global vertex ids, unblended (TriangleBatch -1, TriangleRole 0), and per
  // triangle the level of the next collapse or swap that changes it (-1 none).
  void Expand(Index collapses, HierarchyMesh& out) const;

  // Where the memory goes: bytes of each structure (elements in use; the editable mesh's
  // capacities). Build-only structures are released at the end of Build (ask from the progress
  // function to see them during the build).
  struct StorageShare
  {
    const char* Name;
    bool BuildOnly;
    size_t Bytes;
  };
  std::vector<StorageShare> Storage() const;
  // The largest sum of Storage() and the level's selection data (its order, sample, marks and
  // batch) met during the last Build: after M0's evaluation, at every level's batch chosen (its
  // order whole, released then) and at the end of every level, before its compaction (the working
  // data whole, the hierarchy grown by the level).
  size_t PeakWorkingBytes() const { return this->PeakBytes; }
  // What made up that peak: Storage() then, and the level state's bytes ("level state
  // (selection)", build only); their sum is PeakWorkingBytes(). PeakLevel(): the level during
  // which it was met, -1 before the levels (after M0's evaluation).
  std::vector<StorageShare> PeakStorage() const;
  int PeakLevel() const { return this->PeakAtLevel; }
  // When in that level: "its batch chosen" (the selection's order still held), "two thirds of its
  // batch collapsed" (before the compaction inside a batch of the first levels), "its end" (before
  // its compaction), or "M0 evaluated" (PeakLevel -1).
  const char* PeakMoment() const { return this->PeakAtMoment; }
  // The scratch Extract keeps between calls (a slider's extractions reuse it): the replay's
  // corners, the map to output points and, once a blend was extracted, its targets and batches.
  size_t ExtractionScratchBytes() const
  {
    return (this->ScratchCorners.capacity() + this->ScratchMap.capacity() + this->ScratchTarget.capacity() +
             this->ScratchBatch.capacity()) * sizeof(Index);
  }

private:
  // Which of T's edge collapse candidates was the cheapest (FindEdgeCollapse's first), with the
  // hub and border flags of T's vertices then (bit k: tri[k] fixed); Edge -1: not known.
  struct EdgeChoice
  {
    signed char Edge = -1;
    unsigned char Kind = 0; // 0 the quadric's point near the midpoint, 1 tri[Edge], 2 tri[Edge + 1]
    unsigned char Fixed = 0;
  };
  enum class PointSource : unsigned char
  {
    Quadric,  // QuadricPointNear(T's quadric, T's centroid)
    Centroid, // T's centroid
    Kept      // another point (the fit's, a fold-free alternative): in KeptPoints
  };
  // How an evaluation's normal is kept (StoreEvaluation).
  enum class NormalSource : unsigned char
  {
    Own,    // T's own unit normal, recomputed
    Zero,   // no plane
    Stored  // another (a degenerate T's stencil normal): in OtherNormals
  };
  // An evaluation while it is computed (scratch, a chunk of triangles at a time).
  struct Evaluation
  {
    double Kappa = 0, Alpha = 0, Area = 0, Error = 0;
    double EdgeError = 0; // cheapest edge collapse of T (quadric error), when computed
    bool PreferEdge = false;
    EdgeChoice CheapestEdge; // the candidate of EdgeError (fits in the padding)
    int Valence = 6;
    Vec3 Point{ 0, 0, 0 }, Normal{ 0, 0, 1 };
    // Where Point came from: the quadric's point near T's centroid or the centroid (both
    // recomputed from T's vertices when read back), else kept as it is (KeptPoints).
    PointSource Source = PointSource::Kept;
    // How Normal is kept, when the concurrent evaluation decided it (ParallelBookkeeping).
    bool NormalKnown = false;
    NormalSource NormalKind = NormalSource::Own;
    // Error is CollapseError of T's vertices, their quadrics and Point (ErrorOf gives it again
    // from the stored evaluation); else it is kept (KeptErrors): a hub's edge error, or the last
    // error a triangle without a plane carries (NoPlane: StoreEvaluation reads it then).
    bool ErrorRecomputable = false;
    bool NoPlane = false;
    // Normal is T's own area vector normalised (EvaluateShape): OwnNormal's numbers, bit for bit.
    bool OwnPlane = false;
  };
  // What the batch selection reads of a triangle's evaluation, kept per triangle (12 bytes instead
  // of the Evaluation's 104): the paper's weight terms folded into one (their normalisers are fixed
  // after M0's evaluation), and T's unit normal, collapse point and the error of its triangle
  // collapse recomputed from its vertices and their quadrics (they do not change until T is
  // evaluated again) unless they came from elsewhere (NormalOf, PointOf, ErrorOf).
  // (Packed to 4 bytes: 12 bytes instead of 16 per live triangle; the double on a 4-byte boundary
  // costs no measurable time. The error, 8 bytes per row before session 41, about 15 bytes per
  // input vertex at the first levels, the build's peak, is read only for a triangle ordered by its
  // edge collapse whose edge collapse was not taken: recomputed then.)
#pragma pack(push, 4)
  struct StoredEvaluation
  {
    // (A new row carries the error 0: kept, and 0 is what KeptErrors does not hold.)
    StoredEvaluation()
      : PreferEdge(false)
      , ErrorKept(true)
      , Normal(NormalSource::Own)
      , Point(PointSource::Quadric)
    {
    }
    // T's place in the priority order: WeightOf, raised when the collapse it was ordered by was
    // not taken and the other one was dearer. From StoreEvaluation until the caller weighs it
    // (WeightOf, once M0's normalisers are known): the error T is ordered by (its cheapest edge
    // collapse's when PreferEdge, else Error), so that the edge's need not be kept.
    double Weight = 0;
    EdgeChoice CheapestEdge;
    bool PreferEdge : 1;
    // The error of T's triangle collapse is kept: in KeptErrors, or 0 when not there (else ErrorOf
    // recomputes it).
    bool ErrorKept : 1;
    NormalSource Normal : 2;
    // The collapse point: recomputed (Quadric, Centroid) from T's vertices, else kept in
    // KeptPoints under T's slot (on the defaults 96-100% of the triangles of mc1m, the MRI and
    // noisy scans have a recomputable one: the 4-byte index into a point array every row had
    // cost more than the few kept points' entries).
    PointSource Point : 2;
  };
#pragma pack(pop)
  static_assert(sizeof(StoredEvaluation) == 12, "one evaluation record per live triangle");
  std::unordered_map<Index, Vec3> KeptPoints; // PointSource::Kept, by slot
  Vec3 PointOf(Index t) const;
  // The error of T's triangle collapse at its last evaluation (read when T is ordered by its edge
  // collapse, and carried by an evaluation without a plane): recomputed from T's vertices, their
  // quadrics and its collapse point (PointOf, or `point` when the caller has it), as the
  // evaluation computed it, else kept by slot (ErrorKept: hubs, triangles without a plane, and
  // with ErrorWeight 0 every error that is not 0, the value an evaluation then carries).
  std::unordered_map<Index, double> KeptErrors;
  double ErrorOf(Index t) const;
  double ErrorOf(Index t, const Vec3& point) const;
  void StoreError(Index t, StoredEvaluation& s, const Evaluation& e, double error);
  void KeepGuessedErrors(double guess);
  void ForgetDeadErrors();
  void StorePoint(Index t, StoredEvaluation& s, const Evaluation& e);
  // The weight terms of M0's evaluation, until their normalisers are known.
  struct ShapeTerms
  {
    double Kappa = 0, Alpha = 0, Area = 0;
    int Valence = 6;
  };
  // M0's evaluation: the normalisers' sums (in slot order) and, when the paper's term weighs
  // (ErrorWeight < 1), each triangle's terms (32 bytes per input triangle, else not allocated).
  struct M0Terms
  {
    double TotalArea = 0, KappaMax = 0;
    int ValenceMax = 0;
    std::vector<ShapeTerms> Shapes;
  };
  struct LevelState; // the batch selection's data over one Build (in the .cxx)

  // Build's stages: set up M0, weigh every triangle, then reduce level by level.
  void SetParameters(const CollapseHierarchyParameters& parameters);
  void Reset(TriangleMesh&& input, std::vector<unsigned char>&& nonManifoldVertices);
  void ResetRecords();
  void ReserveRecords();
  void InitializeQuadrics();
  void AddBorderPlanes();
  bool EvaluateAllTriangles(const ProgressFunction& progress);
  bool ReduceLevel(int level, LevelState& state);
  void PlanLevel(LevelState& state);
  void OrderCandidates(LevelState& state) const;
  bool CollectRange(LevelState& state) const;
  struct RangeCollection; // the vtkSMPTools functor of CollectRange (in the .cxx)
  void PrefetchCandidates(const LevelState& state, size_t i) const;
  void SelectOrRelax(int level, LevelState& state);
  void SwapEverywhereAndRetry(int level, LevelState& state);
  void SelectBatch(int level, LevelState& state);
  bool RegionIsFree(Index t, const LevelState& state, int edge = -1) const;
  void MarkRegion(Index t, int edge, LevelState& state) const;
  // A candidate's choice, decided on the level's mesh without writing anything shared (so that
  // the coming candidates can be decided concurrently, ChooseAhead); Settle then applies what it
  // changes of the candidate's own row, in the selection's order.
  struct Choice
  {
    bool Decided = false; // (ChooseAhead: false when the region was taken at the window's start)
    bool Chosen = false;
    bool BlockTriangle = false; // the triangle collapse is blocked under the level's rules
    bool BlockEdge = false;     // no valid edge collapse
    int Edge = -1;              // -1: the triangle collapse
    Vec3 Point{ { 0, 0, 0 } };
    double Weight = 0; // the row's weight after the choice (raised when the collapse is dearer)
  };
  // A choice's scratch (one per thread). The selection's own checks use the mesh's link marks
  // (cheaper: no table to clear), the threads' their own (Concurrent).
  struct ChoiceScratch
  {
    StencilBuilder Stencils;
    TriangleStencil Stencil;
    EditableMesh::CheckScratch Check;
    EditableMesh::SetTrial EdgeTrials[3]; // FindEdgeCollapse's, per edge of the triangle
    bool Concurrent = false;
    EditableMesh::CheckScratch* OwnMarks() { return this->Concurrent ? &this->Check : nullptr; }
  };
  struct ChoosingAhead; // the vtkSMPTools functor of ChooseAhead (in the .cxx)
  void ChooseAhead(LevelState& state, size_t i, Index still);
  void DeferNeighbours(LevelState& state, size_t n) const;
  Choice ChooseCollapse(Index t, double orderWeight, bool edges, ChoiceScratch& scratch) const;
  bool TriangleCollapseAllowed(Index t, double orderWeight, Choice& choice, ChoiceScratch& scratch) const;
  bool EdgeCollapseAllowed(Index t, double orderWeight, int hubs, Choice& choice, ChoiceScratch& scratch) const;
  void Settle(Index t, const Choice& choice);
  void PrepareBlockedStamps(const LevelState& state);
  void CollapseBatch(LevelState& state);
  void CollapseInOrder(const LevelState& state, size_t b, Index batchStart);
  void PrefetchBatch(const LevelState& state, size_t b, size_t end) const; // (within [b, end))
  // ParallelCollapses: the run of the batch's collapses from b on that may be applied at once (see
  // the .cxx), its collapses' sets gathered and counted; then applied.
  struct BatchRun;      // a run's data (in the .cxx)
  struct RunSurvey;     // the vtkSMPTools functors (in the .cxx)
  struct RunApplication;
  size_t RunEnd(LevelState& state, size_t b, size_t stop) const; // (a run ends at stop at the latest)
  void SurveyCollapse(const LevelState& state, size_t b, std::vector<Index>& gathered) const;
  void ApplyRun(LevelState& state, size_t begin, size_t end);
  void ApplyRunCollapse(const LevelState& state, size_t b, CollapseRecord& record, std::vector<Index>& gathered);
  bool OppositeBorderVertexChangedSince(Index u, Index v, Index stamp) const;
  // PreventNewValenceThree for the edge collapse of (u, v): no interior vertex opposite the edge
  // of valence four, and the merged vertex keeps at least four neighbours (or one of u, v had
  // fewer).
  bool EdgeKeepsValences(Index u, Index v) const;
  bool ValenceRuleHolds(Index live) const; // on a level of `live` triangles
  // The factor on the error of the edge collapse of (u, v) in the order: below one where it merges
  // an interior vertex of valence four (under the valence rule only).
  double ValenceDiscount(Index u, Index v) const;
  // f(o) for the vertex o opposite the edge (u, v) in each of its triangles but `skip`.
  template <typename F>
  void ForEachOppositeVertex(Index u, Index v, Index skip, F&& f) const
  {
    this->Mesh.ForEachTriangle(u, [&](Index x) {
      const Index* q = this->Mesh.Triangle(x);
      if (x != skip && (q[0] == v || q[1] == v || q[2] == v))
      {
        f(q[0] != u && q[0] != v ? q[0] : (q[1] != u && q[1] != v ? q[1] : q[2]));
      }
    });
  }
  // The batch's edge collapses that share an interior opposite vertex with another collapse of
  // the batch (each was checked alone on the level's mesh; together they may take that vertex
  // down to valence three): marked to go one by one and be checked again (CollapseInOrder).
  void MarkSharedOpposites(LevelState& state);
  bool CreatesCycle(Index t);
  void SwapAroundNewVertices(LevelState& state);
  void ReweighAround(const std::vector<Index>& vertices, LevelState& state);
  void CompactWorkingData(LevelState& state);
  void CompactRows(LevelState& state);
  void ForgetDeadNormals();
  void ForgetDeadPoints();
  void ReleaseWorkingData();
  size_t StorageBytes() const;
  static size_t LevelStateBytes(const LevelState& state);
  void NotePeak(const LevelState* state, int level, const char* moment);
  size_t PeakBytes = 0;
  // What made up the peak (PeakStorage; at TRACE LogPeakShares prints it).
  std::vector<StorageShare> PeakShares;
  size_t PeakLevelStateBytes = 0;
  int PeakAtLevel = -1;
  const char* PeakAtMoment = "";
  void LogPeakShares() const;

  // Evaluate's stages: the weight terms of one triangle and its collapse point. The part that only
  // reads the mesh (EvaluateConcurrently) runs for many triangles at once; FinishEvaluation does
  // what needs shared scratch (the stencil fit, EditableMesh::CheckCollapse), in serial.
  enum class EvaluationRest
  {
    None,
    Fit,   // the whole evaluation needs the stencil fit (EvaluateWithFit)
    Unfold // the quadric point folds the fan: TakeCheapestValidAlternative, then the error
  };
  // T's corners and edge midpoints ranked by error (positions 0..5 of AlternativePoints), and a
  // bit per point that keeps the fan star-shaped.
  struct Alternatives
  {
    unsigned char Order[6] = { 0, 0, 0, 0, 0, 0 };
    unsigned char Count = 0;
    unsigned char StarShaped = 0;
  };
  using LinkEdges = std::vector<std::pair<Vec3, Vec3>>;
  struct ConcurrentEvaluation; // the vtkSMPTools functor (in the .cxx)
  void EvaluateTriangles(const Index* triangles, Index first, Index count, M0Terms* m0 = nullptr);
  void EvaluateChunk(const Index* triangles, Index first, Index count);
  void StoreEvaluation(Index t, const Evaluation& e);
  Vec3 OwnNormal(Index t) const;
  NormalSource NormalSourceOf(Index t, const Vec3& normal) const;
  Vec3 NormalOf(Index t) const;
  double PaperTerm(double kappa, double alpha, int valence, double area) const;
  void Evaluate(Index t, Evaluation& e);
  EvaluationRest EvaluateConcurrently(Index t, Evaluation& e, LinkEdges& link, Alternatives& alternatives) const;
  void FinishEvaluation(Index t, Evaluation& e, EvaluationRest rest, const Alternatives& alternatives);
  bool EvaluateShape(Index t, Evaluation& e, LocalFrame& frame, bool planeAxes) const;
  // Whether the evaluations under way need the paper's shape terms (valence, roundness): M0's
  // (their normalisers) and those of a weight with the paper's term (ErrorWeight < 1). Else
  // nothing reads them (EvaluateTriangles sets it).
  bool ShapeTermsRead = true;
  void EvaluateWithFit(Index t, Evaluation& e);
  bool PreferringEdges() const;
  Quadric TriangleQuadric(const Index* tri) const;
  bool OrderedByEdge(const Index* tri, const Quadric& q, const Evaluation& e) const;
  void SetCollapseError(const Index* tri, const Quadric& q, Evaluation& e) const;
  void GatherLinkEdges(const Index* tri, LinkEdges& link) const;
  static bool StarShaped(const LinkEdges& link, const Vec3& point, const Vec3& normal);
  bool StarShapedAround(const Index* tri, const Vec3& point, const Vec3& normal) const;
  int CollapsePointValence(const Index* tri) const;
  void EvaluateHubTriangle(Index t, int hubs, const Vec3& areaVector, const Vec3& centroid, Evaluation& e) const;
  Vec3 StencilAreaVector(const Index* tri) const;
  void GatherStencilVertices(const Index* tri);
  void AddUnmarkedVertices(Index triangle);
  double StencilReach2(const LocalFrame& frame, size_t begin, size_t end) const;
  void AddAncestorPoints(Index v, const LocalFrame& frame, double reach2, Index stride, Index& counter);
  Vec3 FitStencil(const Index* tri, const LocalFrame& frame, double& kappa);
  bool QuadricPointNearCentroid(const Index* tri, const Quadric& q, const Vec3& centroid, Vec3& point) const;
  void AlternativePoints(const Index* tri, Vec3 (&points)[6]) const;
  Alternatives RankAlternatives(const Index* tri, const Quadric& q, const Vec3& normal, const LinkEdges& link) const;
  void TakeCheapestValidAlternative(const Index* tri, const Alternatives& ranked, Vec3& point) const;
  double WeightOf(Index t, double error) const;
  double CollapseError(const Index* vertices, int count, const Quadric& q, const Vec3& p) const;
  // A merged vertex's own quadric and the sum of its planes' weights, looked up once for all the
  // points a caller prices (each look-up is a rank-word count).
  struct OwnQuadric
  {
    const Quadric* Planes;
    double Weight;
  };
  OwnQuadric OwnQuadricOf(Index v) const
  {
    const Quadric& own = this->QuadricOf(v);
    return { &own, own.Axx + own.Ayy + own.Azz }; // (unit normals: the weights' sum)
  }
  double CollapseError(const OwnQuadric* own, int count, const Quadric& q, const Vec3& p) const;
  double WithVertexTerm(const OwnQuadric* own, int count, double sum, const Vec3& p) const;
  Quadric TriangleQuadric(const Index* tri, OwnQuadric (&own)[3]) const;
  void RemoveCyclesBySwapping(TriangleMesh& mesh) const;
  void ApplyCollapse(Index t, const Index* vertices, int count, const Vec3& p);
  // The cheapest valid edge collapse of triangle t (edge (tri[k], tri[k+1]) and its point).
  // (scratch: the trials of its edges, and the link marks, OwnMarks)
  bool FindEdgeCollapse(Index t, int& edge, Vec3& point, double& error, ChoiceScratch& scratch) const;
  // The per-collapse flip guard bounds each turn; this bounds the accumulated one: no surviving
  // triangle may end up facing away from the M0 triangle it descends from. Asked by the mesh's
  // check (ChoiceOptions) once its other tests passed, with the new area vectors its flip test
  // computed.
  struct OrientationTest final : SurvivorTest
  {
    const CollapseHierarchy* Hierarchy = nullptr;
    bool Keeps(const Index* triangles, const Vec3* newAreaVectors, int n) const override;
  };
  OrientationTest Orientation;
  // Swaps the edges blocking vertex q (valence 3 or 4); returns the number of swaps.
  int SwapAround(Index q, double minimumDot, std::vector<Index>& touched);
  void RecordFlip(const FlipRecord& flip);
  void LockNonManifoldVertices(std::vector<unsigned char>&& given);
  int BuildsWithGivenFlags = 0;

  CollapseHierarchyParameters Parameters;
  // M0: its triangles in Base (whose points are moved out at Reset) and its points in BasePoints,
  // in floats when every coordinate is one (12 bytes per input vertex less for the life of the
  // hierarchy on float inputs; the same values).
  TriangleMesh Base;
  PointStore BasePoints;
  Index NumberOfBasePoints() const { return this->BasePoints.NumberOfPoints(); }
  // The area vector of M0's triangle t, the orientation reference (computed when asked: not kept,
  // 24 bytes per input triangle), as TriangleMesh::TriangleAreaVector.
  Vec3 BaseAreaVector(Index t) const
  {
    const Index* tri = this->Base.Triangle(t);
    const Vec3 a = this->BasePoints.Point(tri[0]);
    return Cross(this->BasePoints.Point(tri[1]) - a, this->BasePoints.Point(tri[2]) - a);
  }
  EditableMesh Mesh;
  static constexpr double HierarchyReferenceRoomFactor = 1.0; // (Reset)
  // Global vertex g: input point g of M0, else the collapse point of collapse g - (input points)
  // (not a second copy of the input points; Vertex).
  std::vector<double> CollapsePoints;
  std::vector<Index> GlobalOf;                  // editable vertex -> current global id
  // The original points merged into a vertex (its ancestors, which the stencil fit reads): the
  // input points at the leaves of its global vertex's collapses, sources first to last (the
  // order the linked lists per vertex had, 16 bytes per input vertex: the walk reads the collapses
  // instead). AncestorCounts: per collapse, how many (build only).
  std::vector<Index> AncestorCounts;
  Index AncestorCountOf(Index g) const
  {
    const Index np = this->NumberOfBasePoints();
    return g < np ? 1 : this->AncestorCounts[size_t(g - np)];
  }
  template <typename Functor>
  void ForEachAncestor(Index g, Functor&& f);
  std::vector<Index> AncestorStack; // ForEachAncestor's scratch
  // Triangle versions, appended in the order they are born: births stored as counts
  // (VersionsBornBy[K] versions are born after at most K collapses), the collapse count at which
  // each disappears, and its M0 slot with the one corner it changed (EntryCode = slot << 2 |
  // corner). A collapse gives the triangles around its kept vertex a new version whose kept corner
  // is the collapse's point (global id = input points + the collapse's index), all else as the
  // slot's previous version; corner 3 (M0's versions, a swap's two) holds all three: Base's
  // triangle, or the next three of FullEntryVertices. 8 bytes per version instead of 20: Extract
  // replays the slots' corners in the same pass it already makes. M0's versions (the first nt,
  // Base's triangles in slot order) have no code stored: EntryCode holds version e >= nt at e - nt (CodeOf; 4 bytes per input triangle
  // less, at every stage of the build).
  static constexpr std::uint32_t AllCorners = 3;
  std::vector<std::uint32_t> EntryCode;
  std::uint32_t CodeOf(Index e) const
  {
    const Index nt = this->Base.NumberOfTriangles();
    if (e < nt)
    {
      return std::uint32_t(e) << 2 | AllCorners;
    }
    return this->VersionsPacked ? std::uint32_t(this->PackedCodes[size_t(e - nt)]) : this->EntryCode[size_t(e - nt)];
  }
  // (The build's form only: DeriveDeaths.)
  std::uint32_t BuildCodeOf(Index e) const
  {
    const Index nt = this->Base.NumberOfTriangles();
    return e < nt ? std::uint32_t(e) << 2 | AllCorners : this->EntryCode[size_t(e - nt)];
  }
  // No death is written during the build: a version ends where its slot's next version is born
  // (a collapse ends the versions around its kept vertex at the count its new ones are born at, a
  // swap likewise), or at its slot's removal (the records' removed triangles), else never. So
  // DeriveDeaths gives every version's death from the codes, the births and the records once the
  // build ends (Deaths, in version order). M0's versions' deaths were derived so since session 32
  // (8 bytes per input vertex), the later ones' since session 41: 4 bytes per version born, 27
  // bytes per input vertex on mc1m at level 25, where the grown hierarchy had become the peak.
  std::vector<Index> Deaths, VersionsBornBy, FullEntryVertices;
  // Once built (PackVersions), the codes of the versions after M0's and every version's death
  // (Never as 0, collapse count d as d + 1) in the fewest bits their largest needs; the build's
  // arrays above are then released.
  bool VersionsPacked = false;
  BitPackedArray PackedCodes, PackedDeaths;
  void PackVersions();
  void FinishVersions()
  {
    this->DeriveDeaths();
    this->PackVersions();
  }
  Index NumberOfEntries() const
  {
    return this->VersionsPacked ? static_cast<Index>(this->PackedDeaths.size())
                                : this->Base.NumberOfTriangles() + static_cast<Index>(this->EntryCode.size());
  }
  Index DeathOf(Index e) const
  {
    if (this->VersionsPacked)
    {
      const std::uint64_t d = this->PackedDeaths[size_t(e)];
      return d == 0 ? std::numeric_limits<Index>::max() : static_cast<Index>(d - 1);
    }
    return this->Deaths[size_t(e)]; // (between DeriveDeaths and PackVersions)
  }
  void DeriveDeaths();
  void AppendEntry(Index x, std::uint32_t corner);
  mutable std::vector<Index> ScratchCorners; // Extract's replay: 3 per slot
  template <typename Functor>
  void ForEachVersion(Index collapses, Functor&& f) const;
  // What is kept per collapse: 24 bytes instead of HierarchyCollapse's 40 (one per collapse, about
  // one per input vertex at the coarsest level; PointOfCollapse, CountOfCollapse, LevelOfCollapse
  // give the rest).
  struct StoredCollapse
  {
    Index Sources[3]; // as HierarchyCollapse::Sources
    Index Triangle;
    double Weight;
  };
  static_assert(sizeof(StoredCollapse) == 24, "one record per collapse");
  std::vector<StoredCollapse> Collapses;
  std::vector<Index> LevelStarts;
  // The collapses and edge swaps in M0 numbering, for exact vertex splits (topology only: the
  // positions are those of the global vertices, Sources and Point of each HierarchyCollapse).
  CollapseRecords Records;

  // The per-triangle working data (evaluations, paper's terms, edge costs, blocked stamps, the
  // level state's marks) are indexed by row, not by M0 slot: when the live triangles
  // fall below 15/16 of the rows while the rows are over half of the slots, 7/8 while over a
  // quarter, 1/2 after that (WorthCompacting), CompactRows renumbers the live ones in slot order
  // and gives the dead ones' rows back. The working data then shrink with the mesh while the
  // hierarchy grows (both at full size made the end of the build its peak).
  LiveRowIndex RowOf; // M0 slot -> row (for the slots live at the last compaction)
  Index Rows = 0;
  size_t Row(Index t) const { return this->RowOf.Row(size_t(t)); }
  // f(t, r) for the rows [begin, end) in order, t the M0 slot of row r (live or not): the rows'
  // slots are the rank words' set bits in order, so no row stores its slot. (Until session 45
  // each row held its current version, 4 bytes per row, 8 per input vertex at the build's peak,
  // to read the slot from the version's code; the walks that needed it all go in row order.)
  template <typename Functor>
  void ForEachRowSlot(size_t begin, size_t end, Functor&& f) const;
  template <typename Functor>
  void ForEachLiveTriangle(Functor&& f) const; // f(t, row), in slot order
  // The same for the positions [begin, end) of that walk (0 <= begin <= end <= Rows).
  template <typename Functor>
  void ForEachLiveTriangleIn(size_t begin, size_t end, Functor&& f) const;
  std::vector<StoredEvaluation> Evaluations;
  std::unordered_map<Index, Vec3> OtherNormals; // NormalSource::Stored (degenerate triangles)
  // Per editable vertex: planes of its original triangles, in rows compacted as the triangles'
  // (CompactQuadrics; QuadricRowOf: the vertices live at the last compaction have rows).
  std::vector<Quadric> Quadrics;
  LiveRowIndex QuadricRowOf;
  Quadric& QuadricOf(Index v) { return this->Quadrics[this->QuadricRowOf.Row(size_t(v))]; }
  const Quadric& QuadricOf(Index v) const { return this->Quadrics[this->QuadricRowOf.Row(size_t(v))]; }
  void CompactQuadrics();
  // Per row: the paper's term of W(T), A(T) (wk kappa / max kappa + wa alpha + wv V) / mean area;
  // not allocated when ErrorWeight is 1 (it weighs 0; 16 bytes per input vertex).
  std::vector<double> PaperTerms;
  double KappaMax = 1, Mv = 1, MeanArea = 1, WeightSum = 1;

  // Scratch.
  QuadraticFitter Fitter;
  StencilBuilder Stencils;
  TriangleStencil Stencil;
  CollapseRecord Record;
  CollapseOptions MeshOptions;
  // MeshOptions with the orientation test (Orientation): the selection's checks (set by Reset).
  CollapseOptions ChoiceOptions;
  // Vertices of non-manifold edges and pinched vertices of M0: never collapsed, so that such an
  // edge stays one edge with all its sheets (MeshOptions.LockedVertices points here).
  std::vector<unsigned char> LockedVertices;
  CollapsibleOptions Rules;
  ChoiceScratch SerialChoice; // the selection's own (ChooseAhead's threads have theirs)
  std::vector<double> FitPoints;
  LinkEdges Link;
  std::vector<Evaluation> Working;    // of the triangles evaluated together
  std::vector<EvaluationRest> Rests; // of the triangles evaluated together
  std::vector<Alternatives> PendingAlternatives; // of those whose rest is Unfold
  std::vector<Index> StencilVertices;
  // Per editable vertex: the epoch that last marked it (stencil gathering, the spokes' owners).
  // Two bytes (four before: 2 bytes per input vertex less for the whole build); cleared at the
  // wrap, every 65,535 epochs (NextMarkEpoch).
  std::vector<std::uint16_t> VertexMark;
  void NextMarkEpoch();
  // Rule results that cannot change until the neighbourhood does: a triangle found not collapsible
  // (by the stencil rules, the mesh check or the orientation test) is skipped until a vertex of
  // its stencil region changes (position or triangles around it). One stamp per rule set (strict,
  // relaxed); -1: not known to be blocked.
  // A selection never changes the mesh, so every stamp it writes is the same ChangeCounter value:
  // a row keeps the index of that value in BlockEpochs, 1 byte instead of 4 (2 in sessions 30-35;
  // at the first levels, the build's peak, 2 bytes per input vertex less per rule set in use
  // than 2 bytes). Few passes block anything new (mc1m's whole build: 9 epochs); more values
  // than a byte holds (255) turn every column into the stamps themselves (Wide), so the answers
  // never change.
  struct BlockedColumn
  {
    std::vector<std::uint8_t> Narrow; // index into BlockEpochs, NoEpoch: not known to be blocked
    std::vector<Index> Wide;           // (BlockedWide) the stamp, -1: not known
    bool Empty() const { return this->Narrow.empty() && this->Wide.empty(); }
  };
  static constexpr std::uint8_t NoEpoch = 0xff;
  BlockedColumn BlockedStrict, BlockedRelaxed, BlockedEdge;
  std::vector<Index> BlockEpochs;
  bool BlockedWide = false;
  Index BlockedStamp(const BlockedColumn& column, size_t row) const
  {
    if (this->BlockedWide)
    {
      return column.Wide[row];
    }
    const std::uint8_t epoch = column.Narrow[row];
    return epoch == NoEpoch ? -1 : this->BlockEpochs[epoch];
  }
  void SetBlocked(BlockedColumn& column, size_t row); // stamped ChangeCounter
  void AssignBlocked(BlockedColumn& column, size_t rows) const;
  void WidenBlocked();
  // Per editable vertex: the stamp of its last change (position or triangles around it) and its
  // valence, cached since then (UnknownDegree: not known; the cache is dropped where the change is
  // stamped, so that Degree reads no stamp). The valence in 2 bytes (4 before session 34, in one
  // record with the stamp: 2 bytes per input vertex less for the whole build); a valence of
  // UnknownDegree or more is computed at each call, not cached.
  static constexpr std::uint16_t UnknownDegree = 0xffff;
  mutable std::vector<Index> VertexStamps;
  mutable std::vector<std::uint16_t> VertexDegrees;
  // Set while threads read the mesh concurrently (ChooseAhead): Degree then computes an unknown
  // valence without caching it (no thread writes VertexDegrees).
  bool DegreesFrozen = false;
  void StampVertex(Index v, Index stamp) const
  {
    this->VertexStamps[v] = stamp;
    this->VertexDegrees[v] = UnknownDegree;
  }
  Index EdgeCollapseCount = 0;
  Index BatchRechecks = 0;
  Index ValenceRefusals = 0;
  // PreventNewValenceThree under the level's rules (lifted with the relaxed rules: SelectOrRelax).
  bool KeepValences = false;
  mutable long long PricingMismatches = 0, BoundedEndPoints = 0; // (atomic adds: concurrent pricing)
  mutable long long TrialPoints = 0, TrialPointsOnRefusedEdges = 0; // (atomic adds: ChooseAhead)
  Index CollapsesInRuns = 0;
  Index ChoicesAhead = 0, ChoicesInOrder = 0, ChoicesDecidedAhead = 0;
  // Per editable vertex: on a border of the mesh (MeshOptions.BoundaryVertices points here).
  std::vector<unsigned char> OnBorder;
  Index ChangeCounter = 0;
  void MarkChangedAround(Index v);
  void MarkChangedAround(Index v, Index stamp);
  void RaiseStamp(Index w, Index stamp);
  void RaiseStampsOf(const Index* q, Index stamp); // (each corner of a triangle)
  // The stars of the vertices of t not in skipMask (bit k: tri[k]) are unchanged since stamp
  // (false for a negative stamp: not known).
  bool StarsUnchangedSince(Index t, Index stamp, int skipMask = 0) const;
  // Hubs: vertices on more than HubValence triangles. Every check of a collapse merging a hub costs
  // its valence, and a hub touches that many candidates: such collapses are no candidates (the
  // hub triangles' other edge still collapses, which lowers the hub's valence). Valences are
  // cached until the vertex's neighbourhood changes (VertexDegrees).
  Index Degree(Index v) const
  {
    const std::uint16_t cached = this->VertexDegrees[v];
    return cached != UnknownDegree ? Index(cached) : this->CacheDegree(v);
  }
  Index CacheDegree(Index v) const; // (the walk, out of the callers' loops)
  int HubMask(Index t) const; // bit k: tri[k] is a hub
  // Over edges with no hub or border end; choice: which candidate it was. Reads and fills t's
  // EdgeCosts. hubs: t's HubMask, which every caller has just computed (EvaluateShape).
  double CheapestEdgeError(Index t, int hubs, EdgeChoice& choice) const;
  // The cheapest placement of one edge collapse as CheapestEdgeError needs it, kept per triangle
  // edge (tri[k], tri[k + 1]): the error, the kind of the first cheapest placement and whether an
  // error was not a number. An edge's cost depends only on its two vertices' points and quadrics,
  // which change only when the vertex is the kept one of a collapse; the collapse then forgets the
  // costs of the edges around it (ForgetEdgeCostsAround), a swap those of its two triangles. A
  // re-evaluated triangle of a new vertex's fan thus reuses its outer edge, whose ends did not
  // move (a third of the edge work; the same numbers, so the same outputs).
  struct EdgeCost
  {
    double Error;
    unsigned char Kind; // 0..2 as EdgeChoice::Kind; 3: no finite placement
    bool NotANumber;
  };
  EdgeCost EdgeCostOf(Index u, Index v) const;
  void EdgeCostsBothWays(Index u, Index v, EdgeCost& uv, EdgeCost& vu) const;
  // (concurrent: other threads may write the row's other edges meanwhile)
  void StoreEdgeCost(size_t row, int edge, const EdgeCost& cost, bool concurrent) const;
  // The spokes of the new vertices' fans priced before their evaluation, once per edge (the
  // evaluation would price each in both of its triangles).
  void PriceSpokes(const std::vector<Index>* vertices); // nullptr: every edge of M0
  void PriceSpokesOf(Index v, bool allVertices) const; // writes slots of v's fan only
  struct SpokePricing;               // the vtkSMPTools functor (in the .cxx)
  std::vector<Index> Spokes;         // the vertices whose spokes are priced
  void ForgetEdgeCostsAround(Index v);
  void ForgetEdgeCostsAt(Index v, const Index* q, size_t row) const;
  // 3 per triangle row. Floats (session 26: 12 bytes per input triangle less): every edge cost is
  // rounded up to a float where it is made (CheapestPlacement), kept or not, so a kept cost is the
  // one a fresh pricing gives, and the selection's own errors (doubles) are never dearer than it.
  // A cost not known is a NaN error (a made one never is: CheapestPlacement keeps the least of
  // its errors, starting from infinity).
  mutable std::vector<float> EdgeCostErrors;
  // 1 per triangle row (3 before session 34: 4 bytes per input vertex less at the build's peak):
  // 2 bits per edge k at bits 2k, its cost's Kind (0..2), or NotANumberKind when an error was not
  // a number (the kind is then never read: such a choice is not kept, CheapestEdgeError). Kind 3
  // (no finite placement) is kept as 0: its error is infinity, never the cheapest. Threads pricing
  // spokes write other edges of one row at once (StoreEdgeCost: a compare-and-swap of the byte).
  mutable std::vector<unsigned char> EdgeCostKinds;
  static constexpr unsigned char NotANumberKind = 3;
  static bool EdgeCostKnown(float error) { return error == error; } // (not a NaN)
  void ForgetEdgeCost(size_t slot) const
  {
    this->EdgeCostErrors[slot] = std::numeric_limits<float>::quiet_NaN();
  }
  // A placement of edge (u, v)'s collapse: the quadric's best point (Kind 0), u (1) or v (2).
  struct EdgePlacement
  {
    double Error;
    Vec3 Point;
    int Kind;
  };
  // cheapestOnly (the pricing's use): an end point whose quadric sum alone is above the cheapest
  // placement before it keeps that sum as its Error, a bound (EndPointAboveCheapest): the same
  // CheapestPlacement and the same ties, without its vertex term. Else every Error is exact (the
  // selection sorts them).
  // (optimum: the edge's quadric point when the caller has it, EdgeOptimum's of the same edge)
  int EdgePlacements(
    Index u, Index v, EdgePlacement placements[3], bool cheapestOnly = false, const Vec3* optimum = nullptr) const;
  bool EndPointAboveCheapest(const Quadric& q, const Vec3& p, double cheapest, double& sum) const;
  static EdgeCost CheapestPlacement(const EdgePlacement* placements, int n);
  void VerifyPricing(Index u, Index v, const EdgePlacement* placements, int n) const;
  static void CostsBothWays(const EdgePlacement* placements, int n, EdgeCost& uv, EdgeCost& vu);
  int FixedMask(const Index* tri) const; // bit k: tri[k] is a hub
  // The candidate of the evaluation's EdgeError, when still FindEdgeCollapse's first.
  bool KnownCheapestEdge(Index t, int& edge, Vec3& point, double& error) const;
  std::uint16_t MarkEpoch = 0;
  mutable std::vector<Index> ScratchMap, ScratchTarget, ScratchBatch;

  // Build's stages timed at TRACE verbosity (wall and process CPU seconds; StageTimer in the
  // .cxx): a stage whose CPU time stays its wall time with two threads runs in serial.
  enum Stage
  {
    StageM0,        // quadrics and M0's evaluation
    StageOrder,     // the level's plan and sample
    StageSelect,    // the batch selection (ranges, choices, regions)
    StageCollapse,  // the batch's collapses
    StageGather,    // the triangles to evaluate again
    StagePrice,     // the new spokes' edge costs
    StageEvaluate,  // their evaluation
    StageCompact,   // rows and quadrics compacted
    NumberOfStages
  };
  std::array<StageTotal, NumberOfStages> StageTimes;
  bool TimingStages = false;
  class StageTimer; // adds a scope's times to its stage (in the .cxx)
  void LogStageTimes() const;
};
} // namespace slod

#endif
