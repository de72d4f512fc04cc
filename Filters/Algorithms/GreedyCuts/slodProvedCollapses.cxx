// SPDX-License-Identifier: BSD-3-Clause
#include "slodProvedCollapses.h"

#include "slodEditableMesh.h"
#include "slodGreedyCuts.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <limits>

namespace slod
{
namespace
{
// New triangles at more than about 75 degrees to the input at their centroid are rejected (as
// the greedy cuts' own candidates): thin standing triangles can be within epsilon yet fold.
constexpr double MinimumFacingCosine = 0.25;
// Input triangles examined per collapse: beyond, the collapse is not tried (bounded work).
constexpr size_t MaximumInputTriangles = 4096;
// ... or this many times the input triangles per output triangle, when more: a coarse output's
// stars cover much of the input, and a fixed cap refused its collapses more often the larger the
// tolerance (fandisk: most input -> output rejections at 0.02 of the diagonal), so a larger
// tolerance could end with more triangles. The gathering per pass stays linear in the input.
constexpr size_t InputTrianglesPerOutputTriangle = 256;
// Collapses and flips of an edge whose two vertices have more triangles than this together are
// not tried: checking one costs a walk over both fans (a fan of thousands of slivers around one
// centre would make every pass quadratic); larger fans are left out of the local proofs' meshes.
constexpr Index MaximumCollapseValence = 128;
// Triangles thinner than this are slivers for the last stage (issue 15's quality measure).
constexpr double SliverDegrees = 5.0;
// A border collapse may leave its target with at most this many triangles: twice the six of a
// regular interior vertex, four times the three of a regular border vertex (the cuts' own outputs
// hold at most 18 on the open CGAL meshes measured, 95 % at most 6). Border collapses gather along
// a loop onto the same few vertices, which grew fans of thin triangles without it.
constexpr Index MaximumBorderValence = 12;
// A flip must raise the smaller of the pair's smallest angles by this factor (no cycling).
constexpr double FlipGain = 1.05;
// The corners of the input triangles relying on a change are queried before their proofs only
// when the replaced triangles' sphere is more than this many tolerances wide: at larger tolerances
// (a coarse output, the target search's top level) those proofs end at their first piece, and the
// queries cost more than the refusals they save (fandisk's top level: +270,000 pieces for 120,000).
constexpr double CornerCheckStarRatio = 4.0;
// A change reads its relying input from the index (ProvedCollapseParameters::Witnesses) when the
// tolerance is more than this many times its star's radius: there the gathering within epsilon
// holds (epsilon / star)^2 stars' worth of input, and it grew with the input's size at a relative
// tolerance (the target search's top levels on scans). Nearer the star's size the gathering is
// local and kept: reading the index there too changed the greedy order on CAD meshes at 0.01 of
// the diagonal (more triangles: oblong 254 -> 542).
constexpr double IndexedStarRatio = 2.0;

class Collapser
{
public:
  Collapser(const TriangleMesh& input, const TriangleBVH& bvh, const ProvedCollapseParameters& parameters,
    const std::vector<Index>& triangles, long long* pieces)
    : In(input)
    , Bvh(bvh)
    , Prm(parameters)
    , Pieces(pieces)
  {
    TriangleMesh output;
    output.Points = input.Points;
    output.Triangles = triangles;
    this->Out.Reset(output);
    this->Border.assign(size_t(output.NumberOfPoints()), 0);
    this->Used.assign(size_t(output.NumberOfPoints()), 0);
    this->LocalId.assign(size_t(output.NumberOfPoints()), InvalidIndex);
    this->CornerSeen.assign(size_t(output.NumberOfPoints()), 0);
    this->Degree.assign(size_t(output.NumberOfPoints()), 0);
    for (Index v = 0; v < output.NumberOfPoints(); ++v)
    {
      this->Degree[size_t(v)] = this->Out.VertexDegree(v);
    }
    this->DegreeWalks = static_cast<long long>(output.NumberOfPoints());
    for (Index v : triangles)
    {
      this->Used[v] = 1;
    }
    for (Index v = 0; v < output.NumberOfPoints(); ++v)
    {
      this->Border[v] = this->Used[v] && this->Out.IsBoundaryVertex(v);
    }
    this->AliveTriangles = output.NumberOfTriangles();
    this->Options.BoundaryVertices = this->Border.data();
    this->Options.MinimumAngle = Radians(parameters.MinimumAngle);
    this->Options.LockedVertices = parameters.LockedVertices;
  }

  long long VerdictsHeld() const { return static_cast<long long>(this->NewTriangleVerdicts.Size()); }
  long long VerdictsDropped() const { return this->NewTriangleVerdicts.Dropped; }

  bool Locked(Index v) const { return this->Prm.LockedVertices && this->Prm.LockedVertices[v]; }

  // v's live triangles (EditableMesh::VertexDegree), read from Degree: a try asks it of u, its
  // targets and the vertices around its star, and each walk of v's references reads the
  // triangles' alive flags at random (their share of the CPU grew with the input).
  Index DegreeOf(Index v) const { return this->Degree[size_t(v)]; }

  // Degree again for the corners of `triangles` (ids taken before a change: a collapse or flip
  // alters the degree of no other vertex).
  void NoteCorners(const std::vector<Index>& triangles)
  {
    this->DegreeChanged.clear();
    for (Index t : triangles)
    {
      const Index* tri = this->Out.Triangle(t);
      this->DegreeChanged.insert(this->DegreeChanged.end(), tri, tri + 3);
    }
  }
  void RefreshDegrees()
  {
    for (Index x : this->DegreeChanged)
    {
      this->Degree[size_t(x)] = this->Out.VertexDegree(x);
    }
    this->DegreeWalks += static_cast<long long>(this->DegreeChanged.size());
  }

  // One pass over the removable vertices, shortest incident edge first. Returns the collapses.
  long long Pass(ProvedCollapseStatistics& statistics, const ProgressFunction& progress, bool& aborted)
  {
    this->TakeSnapshot();
    std::vector<std::pair<double, Index>>& order = this->Order;
    std::vector<Index>& neighbours = this->Neighbours;
    order.clear();
    for (Index u = 0; u < Index(this->Used.size()); ++u)
    {
      if (!this->Used[u] || (this->Border[u] && !this->Prm.BorderCollapses) || this->DegreeOf(u) == 0 ||
        this->Locked(u))
      {
        continue;
      }
      this->Out.Neighbors(u, neighbours);
      double shortest = HUGE_VAL;
      for (Index w : neighbours)
      {
        shortest = std::min(shortest, Norm(this->Out.Point(w) - this->Out.Point(u)));
      }
      order.emplace_back(this->PassKey(shortest, u), u);
    }
    std::sort(order.begin(), order.end());
    long long done = 0;
    for (size_t i = 0; i < order.size(); ++i)
    {
      if (i > 0)
      {
        statistics.PassStepLength += Norm(this->In.Point(order[i].second) - this->In.Point(order[i - 1].second));
        ++statistics.PassSteps;
      }
      if (progress && i % 256 == 0 && !progress(double(i) / double(order.size())))
      {
        aborted = true;
        return done;
      }
      done += this->RemoveVertex(order[i].second, statistics);
      if (this->TargetMet() || this->WorkSpent())
      {
        break;
      }
    }
    return done;
  }

  // A vertex's place in a collapse pass (PassOrderBands): its shortest edge's band, then its
  // position's Morton rank (unique, so the order is total), packed exactly in a double.
  double PassKey(double shortest, Index u)
  {
    if (this->Prm.PassOrderBands <= 0)
    {
      return shortest;
    }
    if (this->SpatialRank.empty())
    {
      const std::vector<MortonEntry> order = MortonOrder(this->In.NumberOfPoints(), [this](Index v, double* xyz) {
        const Vec3 p = this->In.Point(v);
        std::copy(p.begin(), p.end(), xyz);
      });
      this->SpatialRank.resize(order.size());
      for (size_t i = 0; i < order.size(); ++i)
      {
        this->SpatialRank[order[i].Id] = Index(i);
      }
    }
    // Bands relative to epsilon (the same bands for the mesh at any scale), bounded to +-2^20 so
    // that band * 2^32 + rank stays an exact integer.
    const double relative = shortest / this->Prm.Epsilon;
    const double band = relative > 0 ? std::floor(std::log2(relative) * this->Prm.PassOrderBands) : -1048576.0;
    return std::clamp(band, -1048576.0, 1048576.0) * 4294967296.0 + double(this->SpatialRank[u]);
  }

  size_t InputCap() const
  {
    const size_t output = size_t(std::max<Index>(1, this->AliveTriangles));
    return std::max(MaximumInputTriangles, InputTrianglesPerOutputTriangle * size_t(this->In.NumberOfTriangles()) / output);
  }

  bool TargetMet() const { return this->Prm.TargetTriangles > 0 && this->AliveTriangles <= this->Prm.TargetTriangles; }
  bool WorkSpent() const
  {
    return this->Prm.MaximumProofPieces > 0 && this->Pieces && *this->Pieces > this->Prm.MaximumProofPieces;
  }
  bool Finished() const { return this->TargetMet() || this->WorkSpent(); }

  // Visits the triangles in order until the work is spent, reporting progress; `change(t)` tries
  // one triangle and says whether it changed the mesh. Returns the changes.
  template <typename Change>
  long long TrianglePass(const ProgressFunction& progress, bool& aborted, Change&& change)
  {
    this->TakeSnapshot();
    long long done = 0;
    const Index n = this->Out.NumberOfTriangles();
    for (Index t = 0; t < n && !this->WorkSpent(); ++t)
    {
      if (progress && t % 1024 == 0 && !progress(double(t) / double(n)))
      {
        aborted = true;
        return done;
      }
      done += change(t) ? 1 : 0;
    }
    return done;
  }

  // One pass of edge flips that make the pair's thinner triangle fatter, each proved like a
  // collapse. Returns the flips.
  long long FlipPass(const ProgressFunction& progress, bool& aborted)
  {
    return this->TrianglePass(progress, aborted, [this](Index t) {
      for (int k = 0; k < 3 && this->Out.IsTriangleAlive(t); ++k)
      {
        const Index* tri = this->Out.Triangle(t);
        const Index x = tri[k], y = tri[(k + 1) % 3], q = tri[(k + 2) % 3];
        if (x < y && this->DegreeOf(x) + this->DegreeOf(y) <= MaximumCollapseValence &&
          this->Out.EdgeTriangleCount(x, y) == 2 && this->TryFlip(t, x, y, q))
        {
          return true;
        }
      }
      return false;
    });
  }

  // One pass over the triangles thinner than SliverAngle (after section 3.4.3's sharp-angle repair,
  // here on the output): the edges of each are flipped where that makes the pair fatter (as FlipPass),
  // else an end of its shortest edge (a needle) or its widest corner (a cap) is collapsed onto a
  // neighbour, only when the smallest angle around rises; every change is proved like
  // a collapse, so the bound holds. Returns the changes.
  long long SliverPass(ProvedCollapseStatistics& statistics, const ProgressFunction& progress, bool& aborted)
  {
    return this->TrianglePass(progress, aborted, [&](Index t) {
      if (!this->Out.IsTriangleAlive(t) || this->TriangleAngle(t) >= this->SliverAngle)
      {
        return false;
      }
      const bool flipped = this->FlipSliver(t);
      statistics.Flips += flipped;
      // At a count target, or when only flips are asked for, the count stays.
      const bool collapsed =
        !flipped && !this->TargetMet() && !this->Prm.FlipsOnly && this->CollapseSliver(t, statistics);
      return flipped || collapsed;
    });
  }

  // The output at the start of a pass, with a BVH: its triangles that are still alive and unchanged
  // are part of the current output (found near a change: the other side of a thin part).
  void TakeSnapshot()
  {
    this->Snapshot.Points.clear();
    this->Snapshot.Triangles.clear();
    this->SnapshotIds.clear();
    for (Index t = 0; t < this->Out.NumberOfTriangles(); ++t)
    {
      if (this->Out.IsTriangleAlive(t))
      {
        this->SnapshotIds.push_back(t);
      }
    }
    this->Snapshot.Points = this->In.Points; // output vertices are input vertices, never moved
    for (Index t : this->SnapshotIds)
    {
      this->Snapshot.Triangles.insert(this->Snapshot.Triangles.end(), this->Out.Triangle(t), this->Out.Triangle(t) + 3);
    }
    this->SnapshotBvh.Build(this->Snapshot);
    this->Changed.assign(size_t(this->Out.NumberOfTriangles()), 0);
    if (this->Prm.Witnesses && this->Witness.empty())
    {
      this->InitialWitnesses();
      this->InitialRegistrations();
    }
  }

  // Each input triangle's witness on entry: the output triangle closest to its centroid, when its
  // three corners lie within epsilon of it (one BVH query per input triangle, once per run).
  void InitialWitnesses()
  {
    this->Witness.assign(size_t(this->In.NumberOfTriangles()), InvalidIndex);
    this->StarMark.assign(size_t(this->Out.NumberOfTriangles()), 0);
    for (Index p = 0; p < this->In.NumberOfTriangles(); ++p)
    {
      const Index* tri = this->In.Triangle(p);
      const Vec3 g = (1.0 / 3.0) * (this->In.Point(tri[0]) + this->In.Point(tri[1]) + this->In.Point(tri[2]));
      const ClosestPointResult hit = this->SnapshotBvh.ClosestPoint(g);
      if (hit.Triangle != InvalidIndex && this->IsWitness(p, this->Out.Triangle(this->SnapshotIds[size_t(hit.Triangle)])))
      {
        this->Witness[size_t(p)] = this->SnapshotIds[size_t(hit.Triangle)];
      }
    }
  }

  // Whether the three corners of input triangle p lie within epsilon of triangle abc (3 output
  // vertex ids), hence all of p (convexity), with a relative margin for rounding.
  bool IsWitness(Index p, const Index* abc) const
  {
    const double limit = this->Prm.Epsilon * this->Prm.Epsilon * (1 - 1e-9);
    const Vec3 a = this->Out.Point(abc[0]), b = this->Out.Point(abc[1]), c = this->Out.Point(abc[2]);
    for (int k = 0; k < 3; ++k)
    {
      const Vec3 x = this->In.Point(this->In.Triangle(p)[k]);
      const Vec3 e = x - ClosestPointOnTriangle(x, a, b, c);
      if (Dot(e, e) > limit)
      {
        return false;
      }
    }
    return true;
  }

  // The triangles a change leaves around its new triangles' vertices (alive, not replaced: the
  // old star is marked), at most MaximumCollapseValence per vertex: where the new witnesses are
  // looked for besides the new triangles.
  void WitnessRing()
  {
    this->Ring.clear();
    for (Index x : this->NewTriangles)
    {
      if (this->DegreeOf(x) > MaximumCollapseValence)
      {
        continue;
      }
      this->Out.ForEachTriangle(x, [&](Index s) {
        if (this->StarMark[size_t(s)] != this->StarStamp)
        {
          this->Ring.push_back(s);
        }
      });
    }
    std::sort(this->Ring.begin(), this->Ring.end());
    this->Ring.erase(std::unique(this->Ring.begin(), this->Ring.end()), this->Ring.end());
  }

  // Whether every input triangle relying on the change has a new witness among the new triangles
  // (before the change: their corners) and the unchanged ring around them: then each lies within
  // epsilon of the output after the change, with no local output and no proof.
  bool RelyingHaveNewWitnesses()
  {
    this->WitnessRing();
    for (Index p : this->Relying)
    {
      bool found = false;
      for (size_t i = 0; i < this->NewTriangles.size() && !found; i += 3)
      {
        found = this->IsWitness(p, &this->NewTriangles[i]);
      }
      for (size_t i = 0; i < this->Ring.size() && !found; ++i)
      {
        found = this->IsWitness(p, this->Out.Triangle(this->Ring[i]));
      }
      if (!found)
      {
        return false;
      }
    }
    return true;
  }

  // After an accepted change: each input triangle that relied on it takes a witness among the
  // triangles around the new triangles' vertices (now in the mesh), or none.
  void AssignWitnesses()
  {
    if (this->Witness.empty())
    {
      return;
    }
    this->Ring.clear();
    for (Index x : this->NewTriangles)
    {
      if (this->DegreeOf(x) <= MaximumCollapseValence)
      {
        this->Out.ForEachTriangle(x, [&](Index s) { this->Ring.push_back(s); });
      }
    }
    std::sort(this->Ring.begin(), this->Ring.end());
    this->Ring.erase(std::unique(this->Ring.begin(), this->Ring.end()), this->Ring.end());
    if (this->Indexed)
    {
      for (Index t : this->OldStar)
      {
        this->Registered[size_t(t)].clear(); // every live entry there belongs to Relying
      }
    }
    for (Index p : this->Relying)
    {
      Index witness = InvalidIndex;
      for (size_t i = 0; i < this->Ring.size() && witness == InvalidIndex; ++i)
      {
        witness = this->IsWitness(p, this->Out.Triangle(this->Ring[i])) ? this->Ring[i] : InvalidIndex;
      }
      this->Witness[size_t(p)] = witness;
      if (this->Indexed)
      {
        this->RegisterAfterChange(p, witness);
      }
    }
  }

  // Input triangle p relied on the accepted change: registered on its new witness, else (proved
  // against the local output) on the ring around the new triangles and the kept local output near
  // it. Without either the index is turned off (the gathering path stays exact).
  void RegisterAfterChange(Index p, Index witness)
  {
    if (witness != InvalidIndex)
    {
      this->Register(p, &witness, 1);
      return;
    }
    if (!this->LocalProved)
    {
      this->Indexed = false;
      return;
    }
    this->Spread.assign(this->Ring.begin(), this->Ring.end());
    const Index* tri = this->In.Triangle(p);
    const Vec3 a = this->In.Point(tri[0]), b = this->In.Point(tri[1]), c = this->In.Point(tri[2]);
    const Vec3 g = (1.0 / 3.0) * (a + b + c);
    const double r = std::sqrt(std::max({ Dot(g - a, g - a), Dot(g - b, g - b), Dot(g - c, g - c) }));
    this->SnapshotNear.clear();
    this->LocalBvh.TrianglesNear(g, r + this->Prm.Epsilon, size_t(this->Local.NumberOfTriangles()), this->SnapshotNear);
    for (Index i : this->SnapshotNear)
    {
      if (size_t(i) < this->Kept.size()) // the local output's first triangles are Kept's
      {
        this->Spread.push_back(this->Kept[size_t(i)]);
      }
    }
    this->Register(p, this->Spread.data(), this->Spread.size());
  }

  void MarkChanged()
  {
    for (Index t : this->OldStar)
    {
      this->Changed[t] = 1;
    }
  }

  void Store(std::vector<Index>& triangles, std::vector<Index>& patches) const
  {
    std::vector<Index> kept, keptPatches;
    for (Index t = 0; t < this->Out.NumberOfTriangles(); ++t)
    {
      if (this->Out.IsTriangleAlive(t))
      {
        kept.insert(kept.end(), this->Out.Triangle(t), this->Out.Triangle(t) + 3);
        keptPatches.push_back(patches[t]);
      }
    }
    triangles.swap(kept);
    patches.swap(keptPatches);
  }

private:
  double TriangleAngle(Index t) const
  {
    const Index* tri = this->Out.Triangle(t);
    return MinimumAngle(this->Out.Point(tri[0]), this->Out.Point(tri[1]), this->Out.Point(tri[2]));
  }

  // Its three edges, longest first (a cap's long edge is the one whose flip removes it).
  bool FlipSliver(Index t)
  {
    const Index* tri = this->Out.Triangle(t);
    int order[3] = { 0, 1, 2 };
    auto length = [&](int k) { return Norm(this->Out.Point(tri[(k + 1) % 3]) - this->Out.Point(tri[k])); };
    std::sort(order, order + 3, [&](int a, int b) { return length(a) > length(b); });
    for (int k : order)
    {
      const Index x = tri[k], y = tri[(k + 1) % 3], q = tri[(k + 2) % 3];
      if (this->DegreeOf(x) + this->DegreeOf(y) <= MaximumCollapseValence &&
        this->Out.EdgeTriangleCount(x, y) == 2 && this->TryFlip(t, x, y, q))
      {
        return true;
      }
    }
    return false;
  }

  // A needle loses an end of its shortest edge, a cap its widest corner, onto any neighbour
  // (nearest first); only collapses that raise the smallest angle around are tried.
  bool CollapseSliver(Index t, ProvedCollapseStatistics& statistics)
  {
    const Index tri[3] = { this->Out.Triangle(t)[0], this->Out.Triangle(t)[1], this->Out.Triangle(t)[2] };
    int shortest = 0, widest = 0;
    double shortestLength = HUGE_VAL, widestCosine = 2;
    for (int k = 0; k < 3; ++k)
    {
      const Vec3 p = this->Out.Point(tri[k]), a = this->Out.Point(tri[(k + 1) % 3]), b = this->Out.Point(tri[(k + 2) % 3]);
      if (Norm(a - p) < shortestLength)
      {
        shortestLength = Norm(a - p);
        shortest = k;
      }
      const double cosine = Dot(Normalized(a - p), Normalized(b - p));
      if (cosine < widestCosine)
      {
        widestCosine = cosine;
        widest = k;
      }
    }
    // A cap (an angle over 90 degrees) has no short edge to lose: its widest corner goes.
    const bool cap = widestCosine < 0;
    const Index removed[2] = { cap ? tri[widest] : tri[shortest], cap ? InvalidIndex : tri[(shortest + 1) % 3] };
    for (Index u : removed)
    {
      if (u != InvalidIndex && !this->Border[u] && this->RemoveVertex(u, statistics, true))
      {
        return true;
      }
    }
    return false;
  }

  // The smallest angle of the triangles that collapsing u onto its neighbour w would leave around w.
  double SmallestAngleAfter(Index u, Index w) const
  {
    const Vec3 pw = this->Out.Point(w);
    double smallest = HUGE_VAL;
    this->Out.ForEachTriangle(u, [&](Index t) {
      const Index* tri = this->Out.Triangle(t);
      if (tri[0] != w && tri[1] != w && tri[2] != w)
      {
        const Vec3 p[3] = { tri[0] == u ? pw : this->Out.Point(tri[0]), tri[1] == u ? pw : this->Out.Point(tri[1]),
          tri[2] == u ? pw : this->Out.Point(tri[2]) };
        smallest = std::min(smallest, MinimumAngle(p[0], p[1], p[2]));
      }
    });
    return smallest;
  }

  // The smallest angle of the triangles a change replaces (OldStar) and of the new ones.
  std::pair<double, double> SmallestAnglesBeforeAndAfter() const
  {
    double before = HUGE_VAL, after = HUGE_VAL;
    for (Index t : this->OldStar)
    {
      before = std::min(before, this->TriangleAngle(t));
    }
    for (size_t i = 0; i < this->NewTriangles.size(); i += 3)
    {
      after = std::min(after, MinimumAngle(this->Out.Point(this->NewTriangles[i]), this->Out.Point(this->NewTriangles[i + 1]),
                                this->Out.Point(this->NewTriangles[i + 2])));
    }
    return { before, after };
  }

  // The smallest angle of the new triangles is larger than that of the triangles they replace.
  bool RaisesSmallestAngle() const
  {
    const auto [before, after] = this->SmallestAnglesBeforeAndAfter();
    return after > before;
  }

  // The guard of a border collapse u -> v (u on a border, v its neighbour along the loop): v keeps
  // at most MaximumBorderValence triangles, and no new triangle is a sliver (under SliverAngle)
  // unless the star already had one as thin (then none gets thinner). Interior collapses only
  // prefer such targets (the sliver step repairs them later), but that step never moves a border
  // vertex: a border sliver would stay.
  bool BorderStarGuarded(Index u, Index v) const
  {
    // u and v share one triangle (their border edge's), which goes.
    if (this->DegreeOf(u) + this->DegreeOf(v) - 2 > MaximumBorderValence)
    {
      return false;
    }
    const auto [before, after] = this->SmallestAnglesBeforeAndAfter();
    return after >= std::min(before, this->SliverAngle);
  }

  // A border vertex moves only along its border loop: its targets (Neighbours) become its two
  // neighbours on the loop, and none when the loop has three vertices (it would close), so the
  // loops and their number stay; the proofs bound the distance as for any collapse (the cuts keep
  // every border vertex their chains keep: on inputs with many small patches along the border,
  // b9_mesh, those were most of the output).
  // A border vertex next to a fan of more than MaximumCollapseValence triangles stays: its star
  // then spans the fan (a fan disk's centre), so each proof gathers much of the input, and a loop
  // of thousands of such vertices made the pass quadratic (valence-5000 fan disk: 26 s of CPU for
  // 20,000 refused collapses).
  bool BorderTargets(Index u)
  {
    Index along[2] = { InvalidIndex, InvalidIndex };
    int found = 0;
    for (Index w : this->Neighbours)
    {
      if (this->DegreeOf(w) > MaximumCollapseValence)
      {
        this->Neighbours.clear();
        ++this->BorderGuardRejections;
        return false;
      }
    }
    for (Index w : this->Neighbours)
    {
      if (this->Border[w] && this->Out.EdgeTriangleCount(u, w) == 1)
      {
        along[std::min(found, 1)] = w;
        ++found;
      }
    }
    this->Neighbours.clear();
    // Two border edges exactly (a vertex where loops touch stays); a border edge between the two
    // neighbours closes a loop of three.
    if (found == 2 && this->Out.EdgeTriangleCount(along[0], along[1]) != 1)
    {
      this->Neighbours.assign(along, along + 2);
    }
    return !this->Neighbours.empty();
  }

  // Tries u's neighbours as targets (those leaving no new sliver first, each group nearest first);
  // true when one collapse was made.
  bool RemoveVertex(Index u, ProvedCollapseStatistics& statistics, bool fatter = false)
  {
    this->Share = SharedStar(); // the mesh may have changed since u's last tries
    if (this->DegreeOf(u) == 0 || this->DegreeOf(u) > MaximumCollapseValence)
    {
      return false;
    }
    // Nearest first (ties by id): each distance computed once, in reused buffers (no allocation
    // per vertex once they have grown).
    this->Out.Neighbors(u, this->Neighbours);
    const Vec3 pu = this->Out.Point(u);
    std::vector<std::pair<double, Index>>& targets = this->Targets;
    targets.clear();
    if (this->Border[u] && !this->BorderTargets(u))
    {
      return false;
    }
    for (Index w : this->Neighbours)
    {
      targets.emplace_back(Norm(this->Out.Point(w) - pu), w);
    }
    std::sort(targets.begin(), targets.end());
    if (!fatter)
    {
      // Targets that leave no new sliver first (each group nearest first): among the collapses
      // the proofs accept, the nearest one is often a cap-maker while another target would do.
      std::stable_partition(targets.begin(), targets.end(),
        [&](const std::pair<double, Index>& target) { return this->SmallestAngleAfter(u, target.second) >= this->SliverAngle; });
    }
    targets.resize(std::min<size_t>(targets.size(), size_t(this->Prm.MaximumNeighbours)));
    const Index valence = this->DegreeOf(u);
    for (const auto& [distance, v] : targets)
    {
      if (valence + this->DegreeOf(v) > MaximumCollapseValence)
      {
        continue;
      }
      ++statistics.Attempts;
      if (this->TryCollapse(u, v, fatter))
      {
        ++statistics.Collapses;
        return true;
      }
    }
    return false;
  }

  bool TryCollapse(Index u, Index v, bool fatter = false)
  {
    const Index set[2] = { u, v };
    const Vec3 target = this->Out.Point(v);
    if (this->Out.CheckCollapse(set, 2, target, this->Options, this->Gathered) != CollapseStatus::Ok)
    {
      ++this->Rejected[0];
      return false;
    }
    // The new triangles: u's surviving triangles with u replaced by v.
    this->NewTriangles.clear();
    this->Out.ForEachSurvivingTriangle(set, 2, [&](Index t, int corner) {
      const Index* tri = this->Out.Triangle(t);
      if (tri[corner] == u)
      {
        for (int k = 0; k < 3; ++k)
        {
          this->NewTriangles.push_back(k == corner ? v : tri[k]);
        }
      }
    });
    this->OldStar.clear();
    this->Out.ForEachTriangle(u, [&](Index t) { this->OldStar.push_back(t); });
    if (!this->Prm.ReuseStarGathering || this->Share.Vertex != u)
    {
      this->Share = SharedStar();
      this->Share.Vertex = u;
    }
    if (fatter && !this->RaisesSmallestAngle())
    {
      return false;
    }
    if (this->Border[u] && !this->BorderStarGuarded(u, v))
    {
      ++this->BorderGuardRejections;
      return false;
    }
    // The removed vertex first: the cheapest refusal.
    if (!this->RemovedVertexNearChange(u))
    {
      ++this->Rejected[2];
      return false;
    }
    if (!this->NewTrianglesNearInput())
    {
      ++this->Rejected[1];
      return false;
    }
    if (!this->InputNearChange(true))
    {
      ++this->Rejected[2];
      return false;
    }
    this->MarkChanged();
    this->Share = SharedStar();
    this->NoteCorners(this->Gathered);
    this->Out.Collapse(set, 2, v, target, this->Gathered, nullptr);
    this->RefreshDegrees();
    this->AliveTriangles -= Index(this->OldStar.size() - this->NewTriangles.size() / 3);
    this->AssignWitnesses();
    return true;
  }

  // Triangle t = (x, y, q) and its neighbour (y, x, z) become (x, z, q) and (z, y, q).
  bool TryFlip(Index t, Index x, Index y, Index q)
  {
    Index other = InvalidIndex, z = InvalidIndex;
    this->Out.ForEachTriangle(x, [&](Index s) {
      const Index* tri = this->Out.Triangle(s);
      for (int k = 0; k < 3 && s != t; ++k)
      {
        if (tri[k] == y && tri[(k + 1) % 3] == x)
        {
          other = s;
          z = tri[(k + 2) % 3];
        }
      }
    });
    if (other == InvalidIndex || z == q || this->Out.EdgeTriangleCount(q, z) != 0)
    {
      return false;
    }
    const Vec3 px = this->Out.Point(x), py = this->Out.Point(y), pq = this->Out.Point(q), pz = this->Out.Point(z);
    const double before = std::min(MinimumAngle(px, py, pq), MinimumAngle(py, px, pz));
    const double after = std::min(MinimumAngle(px, pz, pq), MinimumAngle(pz, py, pq));
    const Vec3 n0 = Cross(py - px, pq - px), n1 = Cross(px - py, pz - py);
    const Vec3 m0 = Cross(pz - px, pq - px), m1 = Cross(py - pz, pq - pz);
    if (after <= FlipGain * before || Dot(m0, n0) <= 0 || Dot(m0, n1) <= 0 || Dot(m1, n0) <= 0 || Dot(m1, n1) <= 0)
    {
      return false;
    }
    this->NewTriangles = { x, z, q, z, y, q };
    this->OldStar = { t, other };
    this->Share = SharedStar(); // a flip's own star
    if (!this->NewTrianglesNearInput() || !this->InputNearChange())
    {
      return false;
    }
    this->MarkChanged();
    this->NoteCorners(this->OldStar);
    if (!this->Out.FlipEdge(x, y))
    {
      return false;
    }
    this->RefreshDegrees();
    this->AssignWitnesses();
    return true;
  }

  // Every new triangle faces the input at its centroid and lies within epsilon of it. The cheap
  // refusals come first for all of them (the facing test, then each triangle's first proof piece),
  // and only then the subdivisions of the undecided ones: a collapse whose third new triangle is
  // refused at once no longer pays the first two triangles' subdivisions.
  // Each triangle's answer (facing and proof) depends on its three corners only (the input and the
  // tolerance are fixed for the collapser), so it is remembered (NewTriangleVerdicts): the passes try
  // every refused vertex again with the same targets, and a changed neighbourhood leaves most of a
  // star's new triangles as they were. The set's answer is the same (the conjunction of its
  // triangles'); only the triangles not decided before are examined, in the same order.
  bool NewTrianglesNearInput()
  {
    const double tolerance = this->Prm.NewTriangleTolerance > 0 ? std::min(this->Prm.NewTriangleTolerance, this->Prm.Epsilon)
                                                                 : this->Prm.Epsilon;
    this->Undecided.clear();
    for (size_t i = 0; i < this->NewTriangles.size(); i += 3)
    {
      const signed char* verdict = this->NewTriangleVerdicts.Find(&this->NewTriangles[i]);
      if (verdict == nullptr)
      {
        const int carried = this->Prm.CarriedProofs ? this->Prm.CarriedProofs->Recall(&this->NewTriangles[i], tolerance) : 0;
        if (carried == 0)
        {
          this->Undecided.insert(this->Undecided.end(), &this->NewTriangles[i], &this->NewTriangles[i] + 3);
          continue;
        }
        ++this->NewTrianglesCarried;
        this->RememberVerdict(&this->NewTriangles[i], carried > 0);
        if (carried < 0)
        {
          return false;
        }
        continue;
      }
      ++this->NewTrianglesRecalled;
      if (*verdict == 0)
      {
        return false;
      }
    }
    this->NewTriangleProofs += static_cast<long long>(this->Undecided.size() / 3);
    for (size_t i = 0; i < this->Undecided.size(); i += 3)
    {
      const Vec3 a = this->Out.Point(this->Undecided[i]), b = this->Out.Point(this->Undecided[i + 1]),
                 c = this->Out.Point(this->Undecided[i + 2]);
      const Vec3 normal = Normalized(Cross(b - a, c - a));
      const ClosestPointResult hit = this->Bvh.ClosestPoint((1.0 / 3.0) * (a + b + c));
      if (hit.Triangle == InvalidIndex ||
        Dot(normal, Normalized(this->In.TriangleAreaVector(hit.Triangle))) < MinimumFacingCosine)
      {
        this->RememberVerdict(&this->Undecided[i], false);
        if (this->Prm.CarriedProofs)
        {
          this->Prm.CarriedProofs->DoesNotFace(&this->Undecided[i]);
        }
        return false;
      }
    }
    size_t refused = 0;
    const bool proved = this->ProveTriangles(this->Bvh, [this](Index x) { return this->Out.Point(x); },
      this->Undecided.data(), this->Undecided.size() / 3, tolerance, &refused);
    if (!proved)
    {
      this->RememberVerdict(&this->Undecided[3 * refused], false);
      return false;
    }
    for (size_t i = 0; i < this->Undecided.size(); i += 3)
    {
      this->RememberVerdict(&this->Undecided[i], true);
      if (this->Prm.CarriedProofs)
      {
        this->Prm.CarriedProofs->Proved(&this->Undecided[i], tolerance);
      }
    }
    return true;
  }

  void RememberVerdict(const Index* triangle, bool verdict)
  {
    const signed char value = verdict ? 1 : 0;
    this->NewTriangleVerdicts.Insert(triangle, value, [this](const Index* corners) {
      return this->Out.IsVertexAlive(corners[0]) && this->Out.IsVertexAlive(corners[1]) &&
        this->Out.IsVertexAlive(corners[2]);
    });
  }

  // The corners of the input triangles that rely on the old star (Relying) are within epsilon of
  // the local output: each is a point of a triangle whose proof must hold, so a corner farther
  // away refuses the change before any proof piece is spent. At small tolerances most refusals by
  // the input's side have such a corner (fandisk's target at 1/16 of the ladder's bottom: their
  // pieces 491,000 -> 134,000); the local output's own vertices are at distance 0, and each other
  // corner is queried once, charged as one piece.
  bool CornersNearLocalOutput()
  {
    ++this->CornerStamp;
    for (Index x : this->LocalVertices)
    {
      this->CornerSeen[x] = this->CornerStamp;
    }
    for (Index p : this->Relying)
    {
      for (int k = 0; k < 3; ++k)
      {
        const Index x = this->In.Triangle(p)[k];
        if (this->CornerSeen[x] == this->CornerStamp)
        {
          continue;
        }
        this->CornerSeen[x] = this->CornerStamp;
        if (this->Pieces)
        {
          ++*this->Pieces;
        }
        if (this->LocalBvh.ClosestPoint(this->In.Point(x), this->Prm.Epsilon * this->Prm.Epsilon).Triangle == InvalidIndex)
        {
          return false;
        }
      }
    }
    return true;
  }

  // Triangles (3 vertex ids each, `point(id)` their positions) within epsilon of `bvh`'s surface,
  // every first proof piece before any subdivision (TrianglesWithinDistance).
  template <typename PointOf>
  bool ProveTriangles(const TriangleBVH& bvh, const PointOf& point, const Index* ids, size_t count, double distance,
    size_t* refused = nullptr)
  {
    this->Corners.clear();
    for (size_t i = 0; i < 3 * count; ++i)
    {
      this->Corners.push_back(point(ids[i]));
    }
    return TrianglesWithinDistance(bvh, this->Corners, distance, this->Prm.SubdivisionDepth, this->Pieces, refused);
  }

  // The sphere around the replaced triangles (OldStar): the input triangles within epsilon of it
  // are those that may rely on them. Computed once per star when it is shared (SharedStar); the
  // current change's local output is gathered afresh either way.
  void StarSphere()
  {
    this->LocalGathered = false;
    if (this->Share.Sphere)
    {
      return;
    }
    this->Share.Sphere = true;
    Vec3 center{ 0, 0, 0 };
    for (Index t : this->OldStar)
    {
      const Index* tri = this->Out.Triangle(t);
      center = center + (1.0 / (3.0 * double(this->OldStar.size()))) * (this->Out.Point(tri[0]) + this->Out.Point(tri[1]) + this->Out.Point(tri[2]));
    }
    double radius = 0;
    for (Index t : this->OldStar)
    {
      for (int k = 0; k < 3; ++k)
      {
        radius = std::max(radius, Norm(this->Out.Point(this->Out.Triangle(t)[k]) - center));
      }
    }
    this->StarCenter = center;
    this->StarRadius = radius;
    this->StarBounds.clear();
    for (Index t : this->OldStar)
    {
      const Index* tri = this->Out.Triangle(t);
      const Vec3 p[3] = { this->Out.Point(tri[0]), this->Out.Point(tri[1]), this->Out.Point(tri[2]) };
      const Vec3 centre = (1.0 / 3.0) * (p[0] + p[1] + p[2]);
      this->StarBounds.emplace_back(centre, std::max({ Norm(p[0] - centre), Norm(p[1] - centre), Norm(p[2] - centre) }));
    }
  }

  // Whether x lies within epsilon of one of the triangles (3 output vertex ids each).
  bool WithinOfTriangles(const Vec3& x, const Index* ids, size_t count) const
  {
    for (size_t i = 0; i < 3 * count; i += 3)
    {
      const Vec3 e = x - ClosestPointOnTriangle(x, this->Out.Point(ids[i]), this->Out.Point(ids[i + 1]), this->Out.Point(ids[i + 2]));
      if (Dot(e, e) <= this->Prm.Epsilon * this->Prm.Epsilon)
      {
        return true;
      }
    }
    return false;
  }

  // The removed vertex of a collapse is an input vertex of triangles that rely on the old star (it
  // was in it), so InputNearChange fails whenever it is farther than epsilon from the new local
  // output: the same answer, cheaper, and asked before any triangle's proof. At small tolerances on
  // a curved input most collapses fail here (fandisk at 1/16 of the ladder's bottom: 22,000 of
  // 41,000); a border collapse fails here as a rule (the new border edge cuts the loop's arc), and
  // its star may reach far (a fan disk's centre: 15 million proof pieces for 96 refused collapses).
  // Within epsilon of a new triangle (the usual case, checked directly) it passes without the local
  // output, which can be large (a fan's centre in the star: thousands of snapshot triangles).
  // Else the unchanged part of the local output (KeptOutput) decides, one triangle after the other
  // (most collapses that get here fail; a BVH of it for each cost lion-head a sixth of its CPU);
  // that part and its answer are the same for every target of the vertex (SharedStar).
  bool RemovedVertexNearChange(Index removed)
  {
    this->StarSphere();
    const Vec3 x = this->Out.Point(removed);
    if (this->WithinOfTriangles(x, this->NewTriangles.data(), this->NewTriangles.size() / 3))
    {
      return true;
    }
    if (this->Share.RemovedNearKept < 0)
    {
      this->KeptOutput();
      bool near = false;
      for (size_t i = 0; i < this->Kept.size() && !near; ++i)
      {
        near = this->WithinOfTriangles(x, this->Out.Triangle(this->Kept[i]), 1);
      }
      this->Share.RemovedNearKept = near ? 1 : 0;
    }
    return this->Share.RemovedNearKept == 1;
  }

  // Every input triangle that may rely on the replaced triangles (OldStar) is within epsilon of
  // the new ones (NewTriangles) and the unchanged triangles around them. A collapse's sphere comes
  // from RemovedVertexNearChange; a flip's is made here.
  bool InputNearChange(bool sphereMade = false)
  {
    if (!sphereMade)
    {
      this->StarSphere();
    }
    if (!this->Share.Relying)
    {
      this->GatherRelying();
    }
    if (!this->Share.NearFits)
    {
      return false;
    }
    const std::vector<Index>& relying = this->Relying;
    if (relying.empty())
    {
      return true;
    }
    this->LocalProved = false;
    if (!this->Witness.empty() && this->RelyingHaveNewWitnesses())
    {
      ++this->AcceptedByWitnesses;
      return true;
    }
    if (!this->LocalGathered)
    {
      this->GatherLocalOutput();
    }
    this->LocalBvh.Build(this->Local);
    this->LocalProved = true;
    this->LocalOutputTriangles += this->Local.NumberOfTriangles();
    if (this->StarRadius > CornerCheckStarRatio * this->Prm.Epsilon && !this->CornersNearLocalOutput())
    {
      return false;
    }
    this->RelyingIds.clear();
    for (Index p : relying)
    {
      const Index* tri = this->In.Triangle(p);
      this->RelyingIds.insert(this->RelyingIds.end(), tri, tri + 3);
    }
    return this->ProveTriangles(this->LocalBvh, [this](Index x) { return this->In.Point(x); }, this->RelyingIds.data(),
      relying.size(), this->Prm.Epsilon);
  }

  // The input triangles registered on the old star's triangles (Indexed) that come within epsilon
  // of it (MayRelyOnOldStar): those whose proof may use it; NearFits as for a gathering.
  void RegisteredOnOldStar()
  {
    this->MarkOldStar();
    ++this->SeenStamp;
    for (Index t : this->OldStar)
    {
      for (const auto& [p, stamp] : this->Registered[size_t(t)])
      {
        if (stamp != this->RegistrationStamp[size_t(p)] || this->Seen[size_t(p)] == this->SeenStamp)
        {
          continue;
        }
        this->Seen[size_t(p)] = this->SeenStamp;
        ++this->InputTrianglesGathered;
        // Registered near the star but not within epsilon of it: covered by its other registrations.
        const Index* tri = this->In.Triangle(p);
        if (this->MayRelyOnOldStar(this->In.Point(tri[0]), this->In.Point(tri[1]), this->In.Point(tri[2])))
        {
          this->Relying.push_back(p);
        }
      }
    }
    this->Share.NearFits = this->Relying.size() <= this->InputCap();
  }

  void MarkOldStar()
  {
    this->StarMark.resize(size_t(this->Out.NumberOfTriangles()), 0);
    ++this->StarStamp;
    for (Index t : this->OldStar)
    {
      this->StarMark[size_t(t)] = this->StarStamp;
    }
  }

  // Input triangle p lies within epsilon of the union of `triangles` (output ids): registered on
  // each, so that only a change replacing one of them re-proves p. A single witness is also kept.
  void Register(Index p, const Index* triangles, size_t count)
  {
    const unsigned stamp = ++this->RegistrationStamp[size_t(p)];
    for (size_t i = 0; i < count; ++i)
    {
      this->Registered[size_t(triangles[i])].emplace_back(p, stamp);
    }
    this->Witness[size_t(p)] = count == 1 ? triangles[0] : InvalidIndex;
  }

  // Whether the output triangle with corners q has its bounding sphere within epsilon of input
  // triangle p's (those that may hold p's nearest points within epsilon pass).
  bool ComesNear(Index p, const Vec3* q) const
  {
    const Index* tri = this->In.Triangle(p);
    const Vec3 a = this->In.Point(tri[0]), b = this->In.Point(tri[1]), c = this->In.Point(tri[2]);
    const Vec3 g = (1.0 / 3.0) * (a + b + c), h = (1.0 / 3.0) * (q[0] + q[1] + q[2]);
    const double r = std::sqrt(std::max({ Dot(g - a, g - a), Dot(g - b, g - b), Dot(g - c, g - c) }));
    const double s = std::max({ Norm(h - q[0]), Norm(h - q[1]), Norm(h - q[2]) });
    const double apart = Norm(g - h) - r - s;
    return apart - this->Prm.Epsilon <= 1e-9 * (this->Prm.Epsilon + r + s + Norm(g - h));
  }

  // The input triangles' registrations on entry: on their witness when they have one, else on
  // every output triangle near them (the output is within epsilon on entry). An input triangle
  // with more than MaximumInputTriangles such triangles turns the index off (the gathering path).
  void InitialRegistrations()
  {
    this->Registered.assign(size_t(this->Out.NumberOfTriangles()), {});
    this->RegistrationStamp.assign(size_t(this->In.NumberOfTriangles()), 0);
    this->Seen.assign(size_t(this->In.NumberOfTriangles()), 0);
    this->Indexed = true;
    for (Index p = 0; p < this->In.NumberOfTriangles() && this->Indexed; ++p)
    {
      if (this->Witness[size_t(p)] != InvalidIndex)
      {
        this->Register(p, &this->Witness[size_t(p)], 1);
        continue;
      }
      const Index* tri = this->In.Triangle(p);
      const Vec3 a = this->In.Point(tri[0]), b = this->In.Point(tri[1]), c = this->In.Point(tri[2]);
      const Vec3 g = (1.0 / 3.0) * (a + b + c);
      const double r = std::sqrt(std::max({ Dot(g - a, g - a), Dot(g - b, g - b), Dot(g - c, g - c) }));
      this->SnapshotNear.clear();
      this->Indexed = this->SnapshotBvh.TrianglesNear(g, r + this->Prm.Epsilon, MaximumInputTriangles, this->SnapshotNear);
      this->Ring.clear();
      for (Index i : this->SnapshotNear)
      {
        const Index t = this->SnapshotIds[size_t(i)];
        const Index* o = this->Out.Triangle(t);
        const Vec3 q[3] = { this->Out.Point(o[0]), this->Out.Point(o[1]), this->Out.Point(o[2]) };
        if (this->ComesNear(p, q))
        {
          this->Ring.push_back(t);
        }
      }
      this->Register(p, this->Ring.data(), this->Ring.size());
    }
  }

  // The input triangles that may rely on the old star (Relying), from those whose boxes come within
  // epsilon of its sphere; NearFits says whether these were at most InputCap() (else the change
  // is not tried: bounded work).
  void GatherRelying()
  {
    this->Share.Relying = true;
    ++this->InputGatherings;
    this->Near.clear();
    this->Relying.clear();
    if (this->Indexed && this->Prm.Epsilon > IndexedStarRatio * this->StarRadius)
    {
      this->RegisteredOnOldStar();
      return;
    }
    this->Share.NearFits =
      this->Bvh.TrianglesNear(this->StarCenter, this->StarRadius + this->Prm.Epsilon, this->InputCap(), this->Near);
    this->InputTrianglesGathered += static_cast<long long>(this->Near.size());
    if (!this->Share.NearFits)
    {
      return;
    }
    const bool witnesses = !this->Witness.empty();
    if (witnesses)
    {
      this->MarkOldStar();
    }
    for (Index p : this->Near)
    {
      const Index w = witnesses ? this->Witness[size_t(p)] : InvalidIndex;
      if (w != InvalidIndex && this->StarMark[size_t(w)] != this->StarStamp && this->Out.IsTriangleAlive(w))
      {
        ++this->WitnessesKept; // within epsilon of a triangle the change keeps
        continue;
      }
      const Index* tri = this->In.Triangle(p);
      if (this->MayRelyOnOldStar(this->In.Point(tri[0]), this->In.Point(tri[1]), this->In.Point(tri[2])))
      {
        this->Relying.push_back(p);
      }
    }
  }

  // False only when no point of triangle abc comes within epsilon of the old star (its bounding
  // sphere stays farther than epsilon from every star triangle).
  // A star triangle whose bounding sphere (StarBounds) stays farther than epsilon from abc's (with a
  // margin for rounding) is skipped without its closest point: the same answer, for most of the
  // input triangles gathered around a star (they lie near one or two of its triangles).
  bool MayRelyOnOldStar(const Vec3& a, const Vec3& b, const Vec3& c) const
  {
    const Vec3 g = (1.0 / 3.0) * (a + b + c);
    const double r = std::sqrt(std::max({ Dot(g - a, g - a), Dot(g - b, g - b), Dot(g - c, g - c) }));
    for (size_t i = 0; i < this->OldStar.size(); ++i)
    {
      const auto& [centre, radius] = this->StarBounds[i];
      const double apart = Norm(g - centre) - radius - r;
      if (apart - this->Prm.Epsilon > 1e-9 * (this->Prm.Epsilon + radius + r + Norm(g - centre)))
      {
        continue;
      }
      const Index t = this->OldStar[i];
      const Index* tri = this->Out.Triangle(t);
      const Vec3 x = ClosestPointOnTriangle(g, this->Out.Point(tri[0]), this->Out.Point(tri[1]), this->Out.Point(tri[2]));
      if (Norm(g - x) - r <= this->Prm.Epsilon)
      {
        return true;
      }
    }
    return false;
  }

  // The unchanged output around the replaced triangles (Kept, sorted triangle ids): every triangle
  // around their vertices but them, and the snapshot's triangles near the star that are still alive
  // and unchanged (the other side of a thin part). Gathered once per star when it is shared.
  void KeptOutput()
  {
    if (this->Share.Kept)
    {
      return;
    }
    this->Share.Kept = true;
    ++this->OutputGatherings;
    std::vector<Index>& replaced = this->Replaced;
    std::vector<Index>& kept = this->Kept;
    replaced.assign(this->OldStar.begin(), this->OldStar.end());
    kept.clear();
    std::sort(replaced.begin(), replaced.end());
    for (Index t : this->OldStar)
    {
      for (int k = 0; k < 3; ++k)
      {
        const Index x = this->Out.Triangle(t)[k];
        if (this->DegreeOf(x) > MaximumCollapseValence)
        {
          continue; // a subset of the output still proves; the snapshot adds what lies near
        }
        this->Out.ForEachTriangle(x, [&](Index s) {
          if (!std::binary_search(replaced.begin(), replaced.end(), s))
          {
            kept.push_back(s);
          }
        });
      }
    }
    this->SnapshotNear.clear();
    this->SnapshotBvh.TrianglesNear(this->StarCenter, this->StarRadius + 3 * this->Prm.Epsilon, MaximumInputTriangles, this->SnapshotNear);
    for (Index i : this->SnapshotNear)
    {
      const Index t = this->SnapshotIds[i];
      if (this->Out.IsTriangleAlive(t) && !this->Changed[t] &&
        !std::binary_search(replaced.begin(), replaced.end(), t))
      {
        kept.push_back(t);
      }
    }
    std::sort(kept.begin(), kept.end());
    kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
  }

  // The new triangles and the unchanged output around them (KeptOutput), as a small mesh (a subset
  // of the output after the change: a proof against it holds for all).
  void GatherLocalOutput()
  {
    this->KeptOutput();
    this->LocalGathered = true;
    this->Local.Points.clear();
    this->Local.Triangles.clear();
    this->LocalVertices.clear();
    auto add = [&](Index x) {
      if (this->LocalId[x] == InvalidIndex)
      {
        this->LocalId[x] = this->Local.AddPoint(this->Out.Point(x));
        this->LocalVertices.push_back(x);
      }
      this->Local.Triangles.push_back(this->LocalId[x]);
    };
    for (Index t : this->Kept)
    {
      const Index* tri = this->Out.Triangle(t);
      add(tri[0]), add(tri[1]), add(tri[2]);
    }
    for (Index x : this->NewTriangles)
    {
      add(x);
    }
    for (Index x : this->LocalVertices)
    {
      this->LocalId[x] = InvalidIndex;
    }
  }

  const TriangleMesh& In;
  const TriangleBVH& Bvh;
  const ProvedCollapseParameters& Prm;
  long long* Pieces;
public:
  long long Rejected[3] = { 0, 0, 0 }; // collapses rejected by topology, output -> input, input -> output
  long long BorderGuardRejections = 0;
  long long NewTriangleProofs = 0, NewTrianglesRecalled = 0, NewTrianglesCarried = 0;
  long long InputGatherings = 0, OutputGatherings = 0;
  long long WitnessesKept = 0, AcceptedByWitnesses = 0, LocalOutputTriangles = 0, InputTrianglesGathered = 0;
  long long DegreeWalks = 0;

private:
  EditableMesh Out;
  Index AliveTriangles = 0;
  Vec3 StarCenter{ 0, 0, 0 };
  double StarRadius = 0;
  bool LocalGathered = false; // Local holds the local output of the current change
  // What the tries of one vertex share (ProvedCollapseParameters::ReuseStarGathering): every target
  // of u replaces the same triangles (u's star) of the same mesh (nothing changes between the tries
  // of one RemoveVertex), so the star's sphere, the unchanged output around it (Kept), whether u
  // lies within epsilon of that (RemovedNearKept) and the input triangles relying on the star
  // (Relying, NearFits) are the same for each target: gathered for the first target that needs
  // them, reused by the others. Each target's own part (its new triangles, the local output's BVH
  // and the proofs) is made for it as before, so every answer and every piece charged is the same.
  struct SharedStar
  {
    Index Vertex = InvalidIndex; // the removed vertex whose star this describes (none: nothing shared)
    bool Sphere = false;         // StarCenter, StarRadius, StarBounds
    bool Kept = false;
    int RemovedNearKept = -1; // -1: not asked yet
    bool Relying = false;
    bool NearFits = false;
  } Share;
  double SliverAngle = Radians(SliverDegrees);
  CollapseOptions Options;
  std::vector<unsigned char> Border, Used;
  std::vector<Index> Degree, DegreeChanged; // DegreeOf; the vertices whose degree a change alters
  std::vector<Index> LocalId, LocalVertices;
  std::vector<Index> Gathered, NewTriangles, OldStar, Near, Undecided;
  // Per new triangle (its corners in order) tried so far: faces the input and proved within the
  // new triangles' tolerance (true) or refused (false).
  TriangleKeyTable<signed char> NewTriangleVerdicts; // 1 proved, 0 refused
  // Scratch buffers reused by every candidate (their capacity grows once, no allocation per try).
  std::vector<Index> Neighbours, Replaced, Kept, SnapshotNear, Relying, RelyingIds;
  std::vector<Vec3> Corners;
  std::vector<std::pair<Vec3, double>> StarBounds; // per OldStar triangle: centroid, corners' farthest distance
  std::vector<unsigned> CornerSeen; // == CornerStamp: a local output vertex or a corner already queried
  unsigned CornerStamp = 0;
  std::vector<std::pair<double, Index>> Order, Targets;
  std::vector<Index> SpatialRank; // per input vertex: its Morton rank (PassOrderBands), made on first use
  TriangleMesh Local, Snapshot;
  TriangleBVH LocalBvh, SnapshotBvh;
  std::vector<Index> SnapshotIds;
  std::vector<unsigned char> Changed;
  // Per input triangle: an output triangle it lies within epsilon of on its own (Witnesses), or
  // none; empty when witnesses are off. StarMark == StarStamp: in the current change's old star.
  std::vector<Index> Witness, Ring;
  std::vector<unsigned> StarMark;
  unsigned StarStamp = 0;
  // The index (Witnesses): per output triangle, the input triangles registered on it with their
  // registration stamp (an entry is live while it equals the triangle's RegistrationStamp). A
  // change's relying input is read from its old star's lists: no gathering of the input within
  // epsilon, whose size grew with (epsilon / edge)^2.
  bool Indexed = false;
  bool LocalProved = false; // the current try built and proved against its local output
  std::vector<std::vector<std::pair<Index, unsigned>>> Registered;
  std::vector<unsigned> RegistrationStamp, Seen;
  unsigned SeenStamp = 0;
  std::vector<Index> Spread;
};
} // namespace

namespace
{
// The least float not below t (t >= 0): a stored tolerance is never smaller than the proved one.
float FloatNotBelow(double t)
{
  const float f = static_cast<float>(t);
  return double(f) < t ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}
} // namespace

int CarriedTriangleProofs::Recall(const Index* corners, double tolerance) const
{
  const float* known = this->Verdicts.Find(corners);
  if (known == nullptr)
  {
    return 0;
  }
  return *known < 0 ? -1 : (double(*known) <= tolerance ? 1 : 0);
}

void CarriedTriangleProofs::Proved(const Index* corners, double tolerance)
{
  const float stored = FloatNotBelow(tolerance);
  float* known = this->Verdicts.Find(corners);
  if (known == nullptr)
  {
    this->Verdicts.Insert(corners, stored);
  }
  else if (*known >= 0)
  {
    *known = std::min(*known, stored);
  }
}

void CarriedTriangleProofs::DoesNotFace(const Index* corners)
{
  float* known = this->Verdicts.Find(corners);
  if (known == nullptr)
  {
    this->Verdicts.Insert(corners, -1.0f);
  }
  else
  {
    *known = -1.0f;
  }
}

bool ProvedCollapses(const TriangleMesh& input, const TriangleBVH& inputBvh, const ProvedCollapseParameters& parameters,
  std::vector<Index>& triangles, std::vector<Index>& patches, ProvedCollapseStatistics& statistics,
  const ProgressFunction& progress, long long* proofPieces)
{
  statistics = ProvedCollapseStatistics();
  if (parameters.Epsilon <= 0 || triangles.empty() ||
    (parameters.TargetTriangles > 0 && Index(triangles.size() / 3) <= parameters.TargetTriangles))
  {
    statistics.TargetReached = parameters.TargetTriangles > 0 && Index(triangles.size() / 3) <= parameters.TargetTriangles;
    return true;
  }
  Collapser collapser(input, inputBvh, parameters, triangles, proofPieces);
  bool aborted = false;
  // Collapses, then flips (fatter triangles, which may allow more collapses), then collapses again,
  // then the slivers the collapses left are flipped or collapsed away. EarlySliverStep: a sliver
  // step first too, while the collapses have not used the bound up around the slivers.
  // FlipsOnly: the flips and the sliver step's flips alone.
  enum Kind { Collapses, Flips, Slivers };
  const Kind kinds[5] = { Slivers, Collapses, Flips, Collapses, Slivers };
  const Kind flipKinds[2] = { Flips, Slivers };
  const bool early = parameters.EarlySliverStep && !parameters.CollapsesOnly && !parameters.FlipsOnly;
  const Kind* order = parameters.FlipsOnly ? flipKinds : (early ? kinds : kinds + 1);
  const int steps = parameters.FlipsOnly ? 2 : (parameters.CollapsesOnly ? 1 : (early ? 5 : 4));
  const int stages = steps * parameters.MaximumRounds;
  int pass = 0;
  auto stage = [&](double f) { return progress ? progress((pass + f) / double(stages)) : true; };
  for (int index = 0; index < steps && !aborted; ++index)
  {
    const Kind step = order[index];
    if (collapser.TargetMet() && step != Slivers)
    {
      pass = (index + 1) * parameters.MaximumRounds;
      continue; // the slivers' flips still run
    }
    for (int round = 0; round < parameters.MaximumRounds && !aborted; ++round, ++pass)
    {
      ++statistics.Rounds;
      const long long changes = step == Flips ? collapser.FlipPass(stage, aborted)
        : step == Slivers                   ? collapser.SliverPass(statistics, stage, aborted)
                                            : collapser.Pass(statistics, stage, aborted);
      statistics.Flips += step == Flips ? changes : 0;
      if (changes == 0 || collapser.Finished())
      {
        break;
      }
    }
    pass = (index + 1) * parameters.MaximumRounds;
    if (collapser.WorkSpent())
    {
      break;
    }
  }
  statistics.TargetReached = collapser.TargetMet();
  statistics.WorkBoundReached = collapser.WorkSpent();
  collapser.Store(triangles, patches);
  std::copy(collapser.Rejected, collapser.Rejected + 3, statistics.Rejected);
  statistics.BorderGuardRejections = collapser.BorderGuardRejections;
  statistics.NewTriangleProofs = collapser.NewTriangleProofs;
  statistics.NewTrianglesRecalled = collapser.NewTrianglesRecalled;
  statistics.NewTrianglesCarried = collapser.NewTrianglesCarried;
  statistics.InputGatherings = collapser.InputGatherings;
  statistics.OutputGatherings = collapser.OutputGatherings;
  statistics.WitnessesKept = collapser.WitnessesKept;
  statistics.AcceptedByWitnesses = collapser.AcceptedByWitnesses;
  statistics.LocalOutputTriangles = collapser.LocalOutputTriangles;
  statistics.InputTrianglesGathered = collapser.InputTrianglesGathered;
  statistics.VerdictsHeld = collapser.VerdictsHeld();
  statistics.DegreeWalks = collapser.DegreeWalks;
  statistics.VerdictsDropped = collapser.VerdictsDropped();
  return !aborted;
}
} // namespace slod
