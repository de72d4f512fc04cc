// SPDX-License-Identifier: BSD-3-Clause
#include "slodRetileRing.h"

#include "slodTriangleBVH.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slod
{
bool RingRetriangulation::FacesWrong(const Index* tri) const
{
  const Vec3 p[3] = { this->Edit.Point(tri[0]), this->Edit.Point(tri[1]), this->Edit.Point(tri[2]) };
  const Vec3 normal = TriangleNormal(p[0], p[1], p[2]);
  if (Norm(normal) == 0 || IsDegenerate(p[0], p[1], p[2]))
  {
    return true;
  }
  for (int k = 0; k < 3; ++k)
  {
    if (Dot(normal, this->Reference[tri[k]]) <= this->MinimumFacing)
    {
      return true;
    }
  }
  return false;
}

// The ring tile across edge (x, y) from ring tile t (InvalidIndex: none, or not a ring tile).
Index RingRetriangulation::Across(Index t, Index x, Index y) const
{
  for (Index u : this->Ring)
  {
    const Index* tri = this->Edit.Triangle(u);
    if (u != t && this->Edit.IsTriangleAlive(u) &&
      ((tri[0] == y && tri[1] == x) || (tri[1] == y && tri[2] == x) || (tri[2] == y && tri[0] == x)))
    {
      return u;
    }
  }
  return InvalidIndex;
}

// Whether flipping edge (x, y) of tiles (x, y, q) and (y, x, z) leaves fewer of the two facing
// wrong (the flip gives (x, z, q) and (z, y, q)).
bool RingRetriangulation::FlipLeavesFewerWrong(Index t, Index x, Index y, Index q, Index z) const
{
  const Index u = this->Across(t, x, y);
  if (u == InvalidIndex)
  {
    return false;
  }
  const Index before[2][3] = { { x, y, q }, { y, x, z } };
  const Index after[2][3] = { { x, z, q }, { z, y, q } };
  const int wrongBefore = int(this->FacesWrong(before[0])) + int(this->FacesWrong(before[1]));
  const int wrongAfter = int(this->FacesWrong(after[0])) + int(this->FacesWrong(after[1]));
  return wrongAfter < wrongBefore;
}

// Flips one edge of a ring tile facing wrong when that leaves fewer wrong tiles; false when no
// such flip exists. The number of wrong tiles falls with every flip: at most one flip per tile.
bool RingRetriangulation::FlipOneWrongTile(std::vector<std::pair<Index, Index>>& flips, std::vector<FlipRecord>& undo)
{
  for (Index t : this->Ring)
  {
    if (!this->Edit.IsTriangleAlive(t) || !this->FacesWrong(this->Edit.Triangle(t)))
    {
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      const Index* tri = this->Edit.Triangle(t);
      const Index x = tri[k], y = tri[(k + 1) % 3], q = tri[(k + 2) % 3];
      const Index u = this->Across(t, x, y);
      if (u == InvalidIndex || (this->IsFixedEdge && this->IsFixedEdge(x, y)))
      {
        continue;
      }
      const Index* other = this->Edit.Triangle(u);
      const Index z = other[0] != x && other[0] != y ? other[0] : (other[1] != x && other[1] != y ? other[1] : other[2]);
      FlipRecord record;
      if (this->FlipLeavesFewerWrong(t, x, y, q, z) && this->Edit.FlipEdge(x, y, &record))
      {
        flips.emplace_back(x, y);
        undo.push_back(record);
        return true;
      }
    }
  }
  return false;
}

bool RingRetriangulation::Try(Index r, Index c, const Vec3& position, const Vec3& targetReference,
  std::vector<std::pair<Index, Index>>& flips, double& smallestAngle, double& distance)
{
  flips.clear();
  const Index pair[2] = { r, c };
  const Vec3 removed = this->Edit.Point(r);
  const Vec3 previousReference = this->Reference[c];
  CollapseRecord& collapse = this->Collapse;
  this->Edit.Collapse(pair, 2, c, position, &collapse);
  this->Reference[c] = targetReference;
  this->Ring.clear();
  for (Index t : collapse.ChangedTriangles)
  {
    if (this->Edit.IsTriangleAlive(t))
    {
      this->Ring.push_back(t);
    }
  }
  std::vector<FlipRecord>& undo = this->Undo;
  undo.clear();
  while (undo.size() < this->Ring.size() && this->FlipOneWrongTile(flips, undo))
  {
  }
  bool valid = true;
  smallestAngle = std::numeric_limits<double>::max();
  distance = std::numeric_limits<double>::max();
  for (Index t : this->Ring)
  {
    const Index* tri = this->Edit.Triangle(t);
    valid = valid && !this->FacesWrong(tri);
    const Vec3 a = this->Edit.Point(tri[0]), b = this->Edit.Point(tri[1]), d = this->Edit.Point(tri[2]);
    smallestAngle = std::min(smallestAngle, MinimumAngle(a, b, d));
    distance = std::min(distance, Norm(ClosestPointOnTriangle(removed, a, b, d) - removed));
  }
  for (auto it = undo.rbegin(); it != undo.rend(); ++it)
  {
    this->Edit.Undo(*it);
  }
  this->Reference[c] = previousReference;
  this->Edit.Undo(collapse);
  return valid;
}

// r's neighbours in the order of its tiles (r, a, b): a closed simple cycle, else false (a border
// or non-manifold vertex, or a ring longer than MaximumRing).
bool RingTriangulationSearch::OrderRing(Index r)
{
  std::vector<std::pair<Index, Index>> next; // (a, b): tile (r, a, b)
  bool manifold = true;
  this->Edit.ForEachTriangle(r, [&](Index t) {
    const Index* tri = this->Edit.Triangle(t);
    const int k = tri[0] == r ? 0 : (tri[1] == r ? 1 : 2);
    next.emplace_back(tri[(k + 1) % 3], tri[(k + 2) % 3]);
    manifold = manifold && next.size() <= size_t(MaximumRing);
  });
  this->Ring.clear();
  if (!manifold || next.size() < 3)
  {
    return false;
  }
  Index v = next.front().first;
  for (size_t step = 0; step < next.size(); ++step)
  {
    this->Ring.push_back(v);
    const auto it = std::find_if(next.begin(), next.end(), [v](const std::pair<Index, Index>& e) { return e.first == v; });
    if (it == next.end())
    {
      return false;
    }
    v = it->second;
  }
  std::vector<Index> sorted = this->Ring;
  std::sort(sorted.begin(), sorted.end());
  return v == this->Ring.front() && std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
}

// The tile (ring[i], ring[m], ring[j]) (ring order, so r's orientation) as the search ranks it:
// ValidTile plus its smallest angle when it faces the surface's way at its three vertices (and has
// no angle under MinimumAngle), else the worst cosine between its normal and their reference
// normals (in [-1, 1]), -2 when degenerate; `cosineOnly`: that cosine (or -2) for every tile, which
// InputTileScore ranks by the input under it. A larger worst value is a better triangulation.
double RingTriangulationSearch::TileScore(int i, int m, int j, bool cosineOnly) const
{
  const Index ids[3] = { this->Ring[i], this->Ring[m], this->Ring[j] };
  const Vec3 p[3] = { this->Edit.Point(ids[0]), this->Edit.Point(ids[1]), this->Edit.Point(ids[2]) };
  const Vec3 normal = TriangleNormal(p[0], p[1], p[2]);
  const double length = Norm(normal);
  if (length == 0 || IsDegenerate(p[0], p[1], p[2]))
  {
    return -2.0;
  }
  double facing = 1.0;
  bool faces = true;
  for (const Index v : ids)
  {
    const double dot = Dot(normal, this->Reference[v]);
    faces = faces && dot > this->MinimumFacing;
    const double referenceLength = Norm(this->Reference[v]);
    facing = std::min(facing, referenceLength > 0 ? dot / (length * referenceLength) : 0.0);
  }
  facing = std::min(facing, 1.0);
  if (cosineOnly)
  {
    return facing;
  }
  const double angle = slod::MinimumAngle(p[0], p[1], p[2]);
  return faces && angle >= this->MinimumAngle ? ValidTile + angle : facing;
}

// The dot of the tile's normal with the normal of the input triangle closest to its centroid (the
// sign is what counts). Every corner lies on the input, so the query is pruned at the nearest one.
double RingTriangulationSearch::InputFacing(const Vec3* p, const Vec3& normal) const
{
  const Vec3 centroid = (1.0 / 3.0) * (p[0] + p[1] + p[2]);
  double bound2 = std::numeric_limits<double>::max();
  for (int k = 0; k < 3; ++k)
  {
    bound2 = std::min(bound2, Dot(p[k] - centroid, p[k] - centroid));
  }
  ClosestPointResult closest = this->InputSurface->ClosestPoint(centroid, bound2 * (1.0 + 1e-6));
  if (closest.Triangle == InvalidIndex)
  {
    closest = this->InputSurface->ClosestPoint(centroid);
  }
  const TriangleMesh* input = this->InputSurface->GetMesh();
  return closest.Triangle == InvalidIndex || !input ? 0.0 : Dot(normal, input->TriangleAreaVector(closest.Triangle));
}

bool RingTriangulationSearch::Find(Index r, bool& valid, double& worst, double& smallestAngle)
{
  this->Tiles.clear();
  if (!this->OrderRing(r))
  {
    return false;
  }
  const int k = static_cast<int>(this->Ring.size());
  const auto at = [k](int i, int j) { return size_t(i) * size_t(k) + size_t(j); };
  // A side is a ring edge, or a diagonal the mesh does not have yet (else the new edge would be
  // shared by three triangles).
  this->Allowed.assign(size_t(k) * k, 0);
  for (int i = 0; i < k; ++i)
  {
    for (int j = i + 1; j < k; ++j)
    {
      const bool ringEdge = j == i + 1 || (i == 0 && j == k - 1);
      this->Allowed[at(i, j)] = ringEdge || this->Edit.EdgeTriangleCount(this->Ring[i], this->Ring[j]) == 0;
    }
  }
  double best = this->Solve(false);
  if (best == -std::numeric_limits<double>::max())
  {
    return false; // every triangulation needs an edge the mesh has
  }
  valid = best >= ValidTile;
  this->CollectTiles(0, k - 1);
  if (!valid && this->InputSurface)
  {
    best = this->SolveByInput(); // the fallback ranked by the input under the tiles (TileScore)
  }
  worst = valid ? best - ValidTile : best;
  smallestAngle = std::numeric_limits<double>::max();
  for (const auto& tile : this->Tiles)
  {
    smallestAngle = std::min(smallestAngle,
      slod::MinimumAngle(this->Edit.Point(this->Ring[tile[0]]), this->Edit.Point(this->Ring[tile[1]]),
        this->Edit.Point(this->Ring[tile[2]])));
  }
  return true;
}

// The fallback ranked by the input under the tiles, lazily: a tile not yet queried is taken to
// face the input (its score can only fall), the best triangulation under that assumption is found,
// and its unqueried tiles are queried; when one does not face the input, the search runs again.
// Each run but the last finds a tile that does not, so it ends; the result is the exact optimum
// (its tiles' assumed scores are their true ones, every other's can only be lower), at a few
// queries per ring instead of one per tile.
double RingTriangulationSearch::SolveByInput()
{
  const int k = static_cast<int>(this->Ring.size());
  this->Facing.assign(size_t(k) * k * k, 0);
  this->Cosine.assign(size_t(k) * k * k, std::numeric_limits<double>::quiet_NaN());
  const size_t bound = size_t(k) * size_t(k) * size_t(k);
  double best = -std::numeric_limits<double>::max();
  for (size_t run = 0; run < bound; ++run)
  {
    best = this->Solve(true);
    this->Tiles.clear();
    this->CollectTiles(0, k - 1);
    bool changed = false;
    for (const std::array<int, 3>& tile : this->Tiles)
    {
      signed char& known = this->Facing[this->TileKey(tile[0], tile[1], tile[2])];
      if (known == 0)
      {
        const Vec3 p[3] = { this->Edit.Point(this->Ring[tile[0]]), this->Edit.Point(this->Ring[tile[1]]),
          this->Edit.Point(this->Ring[tile[2]]) };
        known = this->InputFacing(p, TriangleNormal(p[0], p[1], p[2])) > 0 ? 1 : -1;
        changed = changed || known < 0;
      }
    }
    if (!changed)
    {
      break;
    }
  }
  return best;
}

// A tile's rank in the fallback (Solve's `byInput`): one that faces the input under its centroid
// (or is not known not to: SolveByInput) ranks above every tile that does not, as FacingInput plus
// its worst cosine. The cosine is computed once per tile for all the runs of SolveByInput.
double RingTriangulationSearch::InputTileScore(int i, int m, int j)
{
  const size_t key = this->TileKey(i, m, j);
  double& cosine = this->Cosine[key];
  if (std::isnan(cosine))
  {
    cosine = this->TileScore(i, m, j, true);
  }
  return cosine > -2.0 && this->Facing[key] >= 0 ? FacingInput + cosine : cosine;
}

// The dynamic programme over the ring's sub-polygons (Best, Split): the largest worst tile score
// of a triangulation of the whole ring (-max: none, every one needs an edge the mesh has).
double RingTriangulationSearch::Solve(bool byInput)
{
  const int k = static_cast<int>(this->Ring.size());
  const auto at = [k](int i, int j) { return size_t(i) * size_t(k) + size_t(j); };
  this->Best.assign(size_t(k) * k, -std::numeric_limits<double>::max());
  this->Split.assign(size_t(k) * k, -1);
  for (int i = 0; i + 1 < k; ++i)
  {
    this->Best[at(i, i + 1)] = std::numeric_limits<double>::max();
  }
  for (int length = 2; length < k; ++length)
  {
    for (int i = 0; i + length < k; ++i)
    {
      const int j = i + length;
      if (!this->Allowed[at(i, j)])
      {
        continue;
      }
      for (int m = i + 1; m < j; ++m)
      {
        const double sides = std::min(this->Best[at(i, m)], this->Best[at(m, j)]);
        if (sides <= this->Best[at(i, j)])
        {
          continue; // cannot beat the best split (and skips the tile's cost)
        }
        const double score = std::min(sides, byInput ? this->InputTileScore(i, m, j) : this->TileScore(i, m, j, false));
        if (score > this->Best[at(i, j)])
        {
          this->Best[at(i, j)] = score;
          this->Split[at(i, j)] = m;
        }
      }
    }
  }
  return this->Best[at(0, k - 1)];
}

void RingTriangulationSearch::CollectTiles(int i, int j)
{
  // Iterative (a ring of MaximumRing vertices has MaximumRing - 2 tiles).
  std::vector<std::pair<int, int>> stack{ { i, j } };
  const int k = static_cast<int>(this->Ring.size());
  while (!stack.empty())
  {
    const auto side = stack.back();
    stack.pop_back();
    if (side.second - side.first < 2)
    {
      continue;
    }
    const int m = this->Split[size_t(side.first) * size_t(k) + size_t(side.second)];
    this->Tiles.push_back({ side.first, m, side.second });
    stack.emplace_back(side.first, m);
    stack.emplace_back(m, side.second);
  }
}

void RingTriangulationSearch::Deviation(const Vec3& point, double& distance, double& longestEdge) const
{
  distance = std::numeric_limits<double>::max();
  longestEdge = 0;
  for (const std::array<int, 3>& tile : this->Tiles)
  {
    const Vec3 p[3] = { this->Edit.Point(this->Ring[tile[0]]), this->Edit.Point(this->Ring[tile[1]]),
      this->Edit.Point(this->Ring[tile[2]]) };
    distance = std::min(distance, Norm(ClosestPointOnTriangle(point, p[0], p[1], p[2]) - point));
    for (int k = 0; k < 3; ++k)
    {
      longestEdge = std::max(longestEdge, Norm(p[(k + 1) % 3] - p[k]));
    }
  }
}

int RingTriangulationSearch::TilesAt(Index c) const
{
  const auto it = std::find(this->Ring.begin(), this->Ring.end(), c);
  if (it == this->Ring.end())
  {
    return 0;
  }
  const int position = static_cast<int>(it - this->Ring.begin());
  int count = 0;
  for (const auto& tile : this->Tiles)
  {
    count += (tile[0] == position || tile[1] == position || tile[2] == position) ? 1 : 0;
  }
  return count;
}

// Walks from the triangulation found to c's fan (each flip turns a side opposite c into an edge
// at c: at most k - 3 flips), then gives the flips back in reverse order: from the fan, each flip
// of edge (c, d) restores the side it replaced.
bool RingTriangulationSearch::FlipsFromFan(Index c, std::vector<std::pair<Index, Index>>& flips) const
{
  flips.clear();
  const auto it = std::find(this->Ring.begin(), this->Ring.end(), c);
  if (it == this->Ring.end() || this->Tiles.empty())
  {
    return false;
  }
  const int k = static_cast<int>(this->Ring.size());
  const int pc = static_cast<int>(it - this->Ring.begin());
  const auto ringEdge = [k](int a, int b) { return (a - b + k) % k == 1 || (b - a + k) % k == 1; };
  const auto has = [](const std::array<int, 3>& tile, int v) { return tile[0] == v || tile[1] == v || tile[2] == v; };
  std::vector<std::array<int, 3>> tiles = this->Tiles;
  std::vector<int> made; // the far corner d of each edge (c, d) made
  for (int guard = 0; guard < k; ++guard)
  {
    bool flipped = false;
    for (size_t t = 0; t < tiles.size() && !flipped; ++t)
    {
      if (!has(tiles[t], pc))
      {
        continue;
      }
      int a = -1, b = -1;
      for (int v : tiles[t])
      {
        if (v != pc)
        {
          (a < 0 ? a : b) = v;
        }
      }
      if (ringEdge(a, b))
      {
        continue;
      }
      for (size_t u = 0; u < tiles.size(); ++u)
      {
        if (u == t || !has(tiles[u], a) || !has(tiles[u], b))
        {
          continue;
        }
        const int d = tiles[u][0] != a && tiles[u][0] != b ? tiles[u][0] : (tiles[u][1] != a && tiles[u][1] != b ? tiles[u][1] : tiles[u][2]);
        tiles[t] = { pc, a, d };
        tiles[u] = { pc, b, d };
        made.push_back(d);
        flipped = true;
        break;
      }
    }
    if (!flipped)
    {
      break;
    }
  }
  for (auto d = made.rbegin(); d != made.rend(); ++d)
  {
    flips.emplace_back(c, this->Ring[*d]);
  }
  return true;
}
// Ear cutting: while r has more than three neighbours, a neighbour a whose tile (prev, a, next)
// (its neighbours in r's current ring) is a tile of the triangulation other than `keep` is cut off
// by the flip of (r, a). A triangulation of a polygon with four or more vertices has two ears that
// do not overlap, so one of them is not `keep`: at most k - 3 flips, each found in O(k^2).
bool RingTriangulationSearch::SpokeFlipsInto(int keep, std::vector<Index>& spokes) const
{
  spokes.clear();
  std::vector<int> ring(this->Ring.size());
  for (size_t i = 0; i < ring.size(); ++i)
  {
    ring[i] = static_cast<int>(i);
  }
  const auto same = [](std::array<int, 3> a, std::array<int, 3> b) {
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    return a == b;
  };
  while (ring.size() > 3)
  {
    const size_t n = ring.size();
    size_t ear = n;
    for (size_t i = 0; i < n && ear == n; ++i)
    {
      const std::array<int, 3> corner{ ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n] };
      for (int t = 0; t < this->NumberOfTiles() && ear == n; ++t)
      {
        ear = t != keep && same(corner, this->Tiles[t]) ? i : n;
      }
    }
    if (ear == n)
    {
      return false;
    }
    spokes.push_back(this->Ring[ring[ear]]);
    ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(ear));
  }
  return true;
}
} // namespace slod
