// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm Retile: Turk's removal of an old vertex with its whole ring re-triangulated
// (Turk 1992, section 4.3), where every fan from a neighbour leaves a tile facing against the
// original surface. The ring is first fanned from a neighbour c (the half-edge collapse r -> c),
// then the fan's edges are flipped while a flip leaves fewer of the ring's tiles facing against
// the surface. Any triangulation of the ring can be reached from a fan by flips; this greedy walk
// finds one facing the surface's way in most rings where a fan does not (the rest keep the fan's
// collapse, as before). Only tried, then undone: the caller performs the collapse and replays the
// flips (so they can be recorded for the nested levels' tracking).
#ifndef slodRetileRing_h
#define slodRetileRing_h

#include "slodEditableMesh.h"

#include <array>
#include <functional>
#include <utility>
#include <vector>

namespace slod
{
class TriangleBVH;

struct SURFACELODFILTERS_EXPORT RingRetriangulation
{
  RingRetriangulation(EditableMesh& edit, std::vector<Vec3>& reference)
    : Edit(edit)
    , Reference(reference)
  {
  }

  EditableMesh& Edit;
  // Per vertex: what the original surface faces there. A tile faces the surface's way when its
  // normal's dot with the reference of each of its vertices is above MinimumFacing.
  std::vector<Vec3>& Reference;
  double MinimumFacing = 0.0;
  // Edges that are never flipped (feature lines); may be empty.
  std::function<bool(Index, Index)> IsFixedEdge;

  // Tries removing r by the collapse onto neighbour c (c placed at `position`, its reference
  // normal `targetReference` afterwards), then flips. True when every tile of the new ring faces
  // the surface's way and none is degenerate: `flips` (edges (x, y) to flip in order after the
  // collapse), `smallestAngle` (radians) and `distance` (from r's position to the new ring: how
  // far the surface moved there) are then set. The mesh is left as it was either way.
  bool Try(Index r, Index c, const Vec3& position, const Vec3& targetReference,
    std::vector<std::pair<Index, Index>>& flips, double& smallestAngle, double& distance);

private:
  bool FacesWrong(const Index* tri) const;
  bool FlipLeavesFewerWrong(Index t, Index x, Index y, Index q, Index z) const;
  Index Across(Index t, Index x, Index y) const;
  bool FlipOneWrongTile(std::vector<std::pair<Index, Index>>& flips, std::vector<FlipRecord>& undo);
  std::vector<Index> Ring; // the tiles the collapse changed (same ids through the flips)
  // Scratch reused by every Try (one removal tries several targets): no allocation per try.
  CollapseRecord Collapse;
  std::vector<FlipRecord> Undo;
};

// Turk's removal by a search over every triangulation of the ring (section 4.3: the hole left by
// an old vertex is re-triangulated so that each new tile faces the way the surface does), where
// every fan from a neighbour leaves a tile facing against the surface. Dynamic programming over
// the closed ring's sub-polygons (O(k^3) tiles for a ring of k vertices, k at most MaximumRing),
// among the triangulations that add no edge the mesh already has: when some have all their tiles
// facing the surface's way (the reference normals of their three vertices), not degenerate and
// with no angle under MinimumAngle, the one of those with the largest smallest angle; else the
// one whose worst tile turns least against the reference normals (the fans are among the
// triangulations searched, so it is never worse than the best fan by that measure). The caller
// performs it as the collapse of the old vertex onto a ring vertex c then the flips FlipsFromFan(c)
// gives (so the nested levels' tracking replays it as any other removal). Read-only on the mesh.
struct SURFACELODFILTERS_EXPORT RingTriangulationSearch
{
  RingTriangulationSearch(const EditableMesh& edit, const std::vector<Vec3>& reference)
    : Edit(edit)
    , Reference(reference)
  {
  }

  static constexpr int MaximumRing = 32;
  static constexpr double ValidTile = 4.0; // scores of valid tiles start here (above any cosine)
  // Scores of tiles that are not valid but face the input at their centroid (InputSurface set):
  // this plus their worst cosine to the reference normals, so in [FacingInput - 1, FacingInput + 1].
  static constexpr double FacingInput = 2.0;
  const EditableMesh& Edit;
  const std::vector<Vec3>& Reference;
  double MinimumFacing = 0.0;
  double MinimumAngle = 0.0; // radians
  // Optional: the input surface (the tree of the mesh being re-tiled). When set and no
  // triangulation is valid, they are ranked again, first by whether every tile faces the input
  // triangle closest to its centroid (Turk's local-plane test, section 4.4), then by the worst
  // cosine: where the reference normals of a tile's corners are far apart (a thin part, a crease
  // sharper than a right angle) no tile faces all three, and the worst cosine alone ranks only
  // that tile, so the others could be turned over against the surface under them.
  const TriangleBVH* InputSurface = nullptr;

  // True when r has a closed ring (interior manifold vertex, at most MaximumRing neighbours) and a
  // triangulation as above: `valid` says whether all its tiles face the surface's way, `worst` is
  // then its smallest angle (radians), else the smallest cosine between a tile's normal and the
  // reference normal of one of its vertices (plus FacingInput when InputSurface is set and every
  // tile faces the input under its centroid); `smallestAngle` is its smallest angle either way.
  bool Find(Index r, bool& valid, double& worst, double& smallestAngle);
  // The flips, in order, that turn the fan of ring vertex c (after the collapse of r onto c) into
  // the triangulation Find found; false when c is not on the ring.
  bool FlipsFromFan(Index c, std::vector<std::pair<Index, Index>>& flips) const;
  // How many tiles of the triangulation found have ring vertex c as a corner (the fewer flips the
  // more), 0 when c is not on the ring.
  int TilesAt(Index c) const;
  // How far the surface moves where the triangulation found replaces r's star: the distance from
  // `point` (r's position) to its nearest tile, and the longest edge of its tiles.
  void Deviation(const Vec3& point, double& distance, double& longestEdge) const;
  // The triangulation found: its number of tiles, and the ring vertices of tile i.
  int NumberOfTiles() const { return static_cast<int>(this->Tiles.size()); }
  std::array<Index, 3> Tile(int i) const
  {
    return { this->Ring[this->Tiles[i][0]], this->Ring[this->Tiles[i][1]], this->Ring[this->Tiles[i][2]] };
  }
  // The ring vertices a whose edges (r, a) to flip, in order, so that r's star becomes the
  // triangulation found with r inside its tile `keep` (each flip cuts an ear of the triangulation
  // off r's star: r keeps its three tiles inside `keep`); false when no ear is left to cut.
  bool SpokeFlipsInto(int keep, std::vector<Index>& spokes) const;

private:
  bool OrderRing(Index r);
  double Solve(bool byInput);
  double SolveByInput();
  double InputTileScore(int i, int m, int j);
  double TileScore(int i, int m, int j, bool cosineOnly) const;
  size_t TileKey(int i, int m, int j) const
  {
    const size_t k = this->Ring.size();
    return (size_t(i) * k + size_t(m)) * k + size_t(j);
  }
  double InputFacing(const Vec3* p, const Vec3& normal) const;
  void CollectTiles(int i, int j);
  std::vector<Index> Ring;                 // r's neighbours in the order of its tiles
  std::vector<unsigned char> Allowed;      // k x k: edge (i, j) may be a side of a tile
  std::vector<double> Best;                // k x k: best smallest angle of sub-polygon i..j (-1: none)
  std::vector<int> Split;                  // k x k: the apex of the tile on side (i, j)
  std::vector<std::array<int, 3>> Tiles;   // the triangulation found, in ring positions
  std::vector<signed char> Facing;         // k x k x k: tile (i, m, j) faces the input (1), not (-1), unknown (0)
  std::vector<double> Cosine;              // k x k x k: its worst cosine (-2 degenerate, NaN not yet computed)
};
} // namespace slod

#endif
