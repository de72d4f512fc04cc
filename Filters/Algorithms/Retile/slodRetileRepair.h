// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm Retile: the last check of a re-tiling (Turk 1992, section 4.4's "no tile
// faces the wrong way", extended to needles). The removal of the old vertices picks, for each, the
// best fan it may; where none is valid it still takes one, and the tiles it leaves can face against
// the original surface or be needles (an edge of nearly no length, an angle of nearly zero). This
// stage finds those tiles and repairs them with two local operations, each accepted only when it
// leaves fewer bad tiles around it (or as many, with a larger smallest angle):
//  - an edge flip of one of the tile's edges (never a feature-line edge), recorded like step 6's;
//  - a move of one of its movable vertices (a free candidate: not a coarser level's, a border's, a
//    retained original vertex) toward the centre of its neighbours, projected onto the original
//    surface (so the vertex stays on it; its host location follows);
//  - the last resort (session 23), for a tile neither repairs: a move of one of its movable
//    vertices into the kernel of its star (where every tile of the star faces the surface's way,
//    in the star's plane), then a flip, then (session 25) two flips together (one of its edges
//    and an outer edge of the quad that flip leaves), each allowed to move the surface by
//    LastResortMovedShare;
//  - (session 26) where those leave the tile as it is, a relocation of one of its movable vertices:
//    its ring is re-triangulated by the ring search (every tile facing the surface's way) and the
//    vertex goes back inside one of the new tiles (flips of its edges, then a move): the vertex
//    count stays, and a star with no kernel gets one.
// A final stage (session 37, RunFlipped) then works on the flipped tiles alone (normal against the
// input triangle under the centroid): the same changes, each kept only when the flipped tiles
// around it become fewer and the needles and folds no more (session 42: only folds the input does
// not have under the two tiles count); there the vertices of
// MovableInFinalStage may move too (session 39: retained original vertices, by option). A needle
// stage (session 43, RunNeedles) follows it: the same changes on the needles, kept only when they
// become fewer and the flipped tiles and folds the input lacks no more.
// Bounded: a fixed number of passes over the bad tiles, and a budget of triangle visits.
#ifndef slodRetileRepair_h
#define slodRetileRepair_h

#include "slodEditableMesh.h"
#include "slodRetileRing.h"

#include <functional>
#include <unordered_map>
#include <utility>
#include <vector>

namespace slod
{
class TriangleBVH;
struct ClosestPointResult;

// Two neighbouring tiles fold when their normals turn by more than 150 degrees.
constexpr double FoldCosine = -0.8660254037844386;
// A repair may move tiles away from the original surface by this share of their longest edge (or
// up to how far they were from it already), and the surface away from where it was by MovedShare.
constexpr double DeviationShare = 0.02;
constexpr double MovedShare = 0.03;
// The repair's last resort (a move into a vertex's star kernel, a flip) may move the surface by
// this share: undoing a pleat moves it by the fold's height, which MovedShare refuses.
constexpr double LastResortMovedShare = 0.25;
// Vertices with more neighbours are not moved; the repair stops after this many triangle visits
// per triangle of the mesh.
constexpr size_t MaximumRepairValence = 32;
constexpr long long RepairWorkPerTriangle = 400;
constexpr long long FlippedWorkPerTriangle = 100;
// A relocation tries the vertex in at most this many tiles of its ring's triangulation (the
// nearest to where it is first).
constexpr int RelocationTiles = 4;

struct SURFACELODFILTERS_EXPORT TileRepair
{
  TileRepair(EditableMesh& edit, std::vector<Vec3>& reference, const TriangleMesh& input, const TriangleBVH& inputBVH,
    std::vector<unsigned char> movable)
    : Edit(edit)
    , Reference(reference)
    , Input(input)
    , InputBVH(inputBVH)
    , Movable(std::move(movable))
    , Rings(edit, reference)
  {
  }

  EditableMesh& Edit;
  // Per vertex of Edit: what the original surface faces there (updated when a vertex moves).
  std::vector<Vec3>& Reference;
  const TriangleMesh& Input;
  const TriangleBVH& InputBVH;
  // Per vertex of Edit: 1 when the repair may move it.
  std::vector<unsigned char> Movable;
  // Vertices only the final stage (RunFlipped) may move, besides Movable's (session 39: retained
  // original vertices, whose tiles the earlier passes leave as they are).
  std::vector<Index> MovableInFinalStage;
  // Edges that are never flipped (feature lines); may be empty.
  std::function<bool(Index, Index)> IsFixedEdge;
  // What the original surface faces at `position` on its triangle `triangle` (a moved vertex's
  // new reference normal).
  std::function<Vec3(const Vec3& position, Index triangle)> NormalAt;
  // Optional (issue 15): when v stands on an input crease, sets c to where its move from `start`
  // toward `target` ends when it slides along the crease (CreasePolylines::Slide; c.Triangle a
  // triangle of that crease facing `reference` most) and returns true; v then never leaves it.
  std::function<bool(Index v, const Vec3& start, const Vec3& target, const Vec3& reference, ClosestPointResult& c)>
    AlongCrease;
  // Called after vertex v moved to `position` on input triangle `triangle`.
  std::function<void(Index v, const Vec3& position, Index triangle)> Moved;
  // Optional: each flip of edge (x, y) as the pair (-1 - x, y), as step 6 records them.
  std::vector<Index>* Record = nullptr;
  // Whether RepairTriangle has its last resort. The coarser nested levels go without: each of
  // their flips is recorded and cuts the level interpolation's fragments again (with it,
  // scan-48's morph had 107,886 triangles instead of 89,228).
  bool LastResort = true;
  // A tile is a needle below this smallest angle (radians) or this shortest edge (length).
  double NeedleAngle = 0;
  double ShortestEdge = 0;

  // Returns the number of bad tiles near the last pass's changes (the others were tried and left
  // as they are). Flips and moves done are counted in the members below.
  Index Run(int passes);
  // The final stage: `rounds` passes over the tiles facing against the input under their
  // centroids, with a budget of its own (FlippedWorkPerTriangle); returns those left near the
  // last round's changes.
  Index RunFlipped(int rounds);
  // The needle stage (session 43), after the final stage: `rounds` passes over the needles (a
  // smallest angle under NeedleAngle or an edge under ShortestEdge) with the final stage's changes
  // and bounds, each kept only when the needles around it become fewer (or as many with a larger
  // smallest angle) and the flipped tiles and the folds the input lacks no more. The repair
  // proper counts a tile against a corner's reference normal as bad and moves by MovedShare
  // only, so it leaves free candidates standing next to a kept line's samples as caps; returns
  // the needles left near the last round's changes.
  Index RunNeedles(int rounds);
  Index Flips = 0, Moves = 0, Relocations = 0;
  mutable long long Work = 0; // triangle visits so far (bounded in Run)
  // Tiles scored (is it bad?), of those the tiles of a region scored before or after a try, and
  // the closest-point queries to the input made.
  mutable long long TilesScored = 0, RegionTiles = 0, DistanceQueries = 0;

  // Whether a tile with these corners faces against the original surface (at one of its vertices'
  // reference normals or at the closest point of its centroid) or is a needle. `t`: the tile's id
  // in Edit when known (its centroid query is then cached), else InvalidIndex.
  bool IsBad(const Index* ids, const Vec3* p, Index t = InvalidIndex) const;

private:
  // The centroid query of a tile, cached per tile id with the corners it was made for: most tiles
  // of a region are scored again by the next try around the same bad tile, unchanged.
  struct FacingEntry
  {
    Vec3 Corners[3];
    Index Under = InvalidIndex; // the input triangle closest to the centroid
    bool Known = false;
  };
  // The input triangle closest to the tile's centroid (InvalidIndex when none).
  Index InputTriangleUnder(const Vec3* p, Index t) const;
  bool FacesAgainstInput(const Vec3* p, const Vec3& normal, Index t) const;
  // Whether the input under tile t and under tile u (their centroids' closest triangles) turns by
  // 90 degrees or more: a fold of t and u there follows the input (session 42).
  bool InputFoldsBetween(Index t, Index u) const;
  // IsBad without the centroid query, given the tile's normal and smallest angle.
  bool IsBadLocally(const Index* ids, const Vec3* p, const Vec3& normal, double angle) const;
  // Sparse: only the tiles queried. A dense array over the editable mesh's triangle slots (80 bytes
  // each) raised retile's working memory on mc1m from 553 to 729 bytes per input vertex.
  mutable std::unordered_map<Index, FacingEntry> FacingCache;
  struct Score
  {
    int Bad = 0;
    // What a change of the final stages may not increase, counted apart from Bad: needles and
    // folds the input lacks in the flipped stage, those folds in the needle stage; and there,
    // apart from them, the flipped tiles (a change trading a fold for a flipped tile was taken).
    int Guarded = 0;
    int Flipped = 0;
    double Angle = 0;
    double Extent = 0; // squared longest edge
    bool Better(const Score& other) const
    {
      return this->Bad < other.Bad || (this->Bad == other.Bad && this->Angle > other.Angle + 1e-4);
    }
  };
  // Whether `after` is an improvement on `before`: Score::Better; in the flipped stage fewer
  // flipped tiles, in the needle stage Score::Better on the needles with no more Flipped, with no
  // more Guarded.
  bool Improves(const Score& after, const Score& before) const;
  // Which tiles are bad: every kind (Run), only the flipped ones (RunFlipped), only the needles
  // (RunNeedles).
  enum class Target
  {
    Any,
    Flipped,
    Needles
  };
  Target Stage = Target::Any;
  bool FinalStage() const { return this->Stage != Target::Any; }
  // The moves' bound outside the last resort: MovedShare, LastResortMovedShare in the final stages.
  double UsualMovedBound() const { return this->FinalStage() ? LastResortMovedShare : MovedShare; }
  // Runs `rounds` passes of a final stage on the `stage` tiles (the vertices of MovableInFinalStage
  // movable meanwhile).
  Index RunFinal(Target stage, int rounds);
  bool RepairFlippedTriangle(Index t);
  bool IsNeedle(const Vec3* p, double angle) const;
  Index Run(int passes, long long workPerTriangle);
  // A region's tiles before a change: their score, where the surface was (vertices, edge
  // midpoints, centroids) and the points whose distance to the input is compared (edge midpoints
  // and centroids), measured only when the change gets that far.
  struct Before
  {
    Score Tiles;
    std::vector<Vec3> Surface;
    std::vector<Vec3> DeviationSamples;
  };
  Score TriangleScore(Index t) const;
  // `bound` (optional): the score to beat; the centroid queries are skipped (and the returned
  // score is not better than it) when the local checks already show the tiles cannot beat it.
  Score RegionScore(const std::vector<Index>& triangles, std::vector<Vec3>* deviationSamples = nullptr,
    const Score* bound = nullptr) const;
  bool Accept(Before& before, const std::vector<Index>& triangles);
  bool WithinDeviation(const std::vector<Vec3>& samples, double bound2) const;
  void Measure(const std::vector<Index>& triangles, Before& before);
  Index Across(Index t, Index x, Index y) const;
  void Star(Index v, std::vector<Index>& star) const;
  bool WithinDistanceOf(const std::vector<Vec3>& samples, const std::vector<Index>& triangles, double bound2) const;
  bool TryFlip(Index x, Index y);
  bool TryFlipPair(Index t, Index x, Index y);
  bool MovableStar(Index v, std::vector<Index>& star);
  bool TryMove(Index v);
  // Where v makes every tile of its star face the surface's way, seen in the plane its star's
  // reference normals face: the kernel of the star's outline there (false when it has none).
  bool StarKernelPoint(Index v, const std::vector<Index>& star, Vec3& point) const;
  bool TryKernelMove(Index v);
  bool TryRelocate(Index v);
  bool HasOpposedRingEdge(Index v, const std::vector<Index>& star) const;
  bool KeepsPoint(const Vec3& point, Index v, const Vec3& position, const std::vector<Index>& star);
  bool RelocateInto(Index v, int tile, const std::vector<Index>& star);
  bool ProjectTarget(Index v, const Vec3& start, const Vec3& reference, const Vec3& target, ClosestPointResult& c) const;
  bool KeepMoveIfAccepted(Index v, const ClosestPointResult& c, const std::vector<Index>& star);
  bool MoveToFirstAccepted(Index v, const std::vector<Index>& star, const Vec3* targets, int count);
  bool RepairTriangle(Index t);
  std::vector<Index> Touched; // vertices of the tiles a repair changed in this pass
  // Scratch buffers reused by every try (no allocation per tile).
  std::vector<Index> Region, Neighbors;
  mutable std::vector<unsigned char> LocallyBad; // per tile of a region: bad without the query
  std::vector<Vec3> AfterSamples;
  Before Previous;
  // How far a change may move the surface (share of its tiles' longest edge): MovedShare, or
  // LastResortMovedShare during the last resort.
  double MovedBound = MovedShare;
  // A half-plane m . p >= c of the star's plane (|m| = 1), scratch of StarKernelPoint.
  struct HalfPlane
  {
    double M[2], C;
  };
  mutable std::vector<HalfPlane> KernelPlanes;
  // The ring search of TryRelocate (with its scratch), and the vertex's edges it flips.
  RingTriangulationSearch Rings;
  std::vector<Index> Spokes;
  std::vector<FlipRecord> SpokeUndo;
};
} // namespace slod

#endif
