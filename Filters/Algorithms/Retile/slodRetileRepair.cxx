// SPDX-License-Identifier: BSD-3-Clause
#include "slodRetileRepair.h"

#include "slodTriangleBVH.h"

#include "vtkLogger.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slod
{
bool TileRepair::IsBad(const Index* ids, const Vec3* p, Index t) const
{
  const Vec3 normal = TriangleNormal(p[0], p[1], p[2]);
  return this->IsBadLocally(ids, p, normal, MinimumAngle(p[0], p[1], p[2])) || this->FacesAgainstInput(p, normal, t);
}

bool TileRepair::IsNeedle(const Vec3* p, double angle) const
{
  if (angle < this->NeedleAngle || Norm(TriangleNormal(p[0], p[1], p[2])) == 0)
  {
    return true;
  }
  for (int k = 0; k < 3; ++k)
  {
    if (Norm(p[(k + 1) % 3] - p[k]) < this->ShortestEdge)
    {
      return true;
    }
  }
  return false;
}

bool TileRepair::Improves(const Score& after, const Score& before) const
{
  switch (this->Stage)
  {
    case Target::Flipped:
      return after.Bad < before.Bad && after.Guarded <= before.Guarded;
    case Target::Needles:
      return after.Flipped <= before.Flipped && after.Guarded <= before.Guarded && after.Better(before);
    default:
      return after.Better(before);
  }
}

bool TileRepair::IsBadLocally(const Index* ids, const Vec3* p, const Vec3& normal, double angle) const
{
  if (Norm(normal) == 0 || angle < this->NeedleAngle)
  {
    return true;
  }
  for (int k = 0; k < 3; ++k)
  {
    if (Norm(p[(k + 1) % 3] - p[k]) < this->ShortestEdge || Dot(normal, this->Reference[ids[k]]) <= 0)
    {
      return true;
    }
  }
  return false;
}

// The original surface under the tile: the closest point of its centroid. Every corner of a tile
// lies on the original surface, so the closest point is no further than the nearest corner: the
// query is pruned there (same triangle as an unbounded query: only farther boxes are skipped).
Index TileRepair::InputTriangleUnder(const Vec3* p, Index t) const
{
  FacingEntry* entry = nullptr;
  if (t != InvalidIndex)
  {
    entry = &this->FacingCache[t];
    if (entry->Known && entry->Corners[0] == p[0] && entry->Corners[1] == p[1] && entry->Corners[2] == p[2])
    {
      return entry->Under;
    }
  }
  const Vec3 centroid = (1.0 / 3.0) * (p[0] + p[1] + p[2]);
  double bound2 = std::numeric_limits<double>::max();
  for (int k = 0; k < 3; ++k)
  {
    bound2 = std::min(bound2, Dot(p[k] - centroid, p[k] - centroid));
  }
  ++this->DistanceQueries;
  // Slack for the rounding of the corners' positions on the input.
  ClosestPointResult closest = this->InputBVH.ClosestPoint(centroid, bound2 * (1.0 + 1e-6));
  if (closest.Triangle == InvalidIndex)
  {
    closest = this->InputBVH.ClosestPoint(centroid);
  }
  if (entry)
  {
    *entry = FacingEntry{ { p[0], p[1], p[2] }, closest.Triangle, true };
  }
  return closest.Triangle;
}

bool TileRepair::FacesAgainstInput(const Vec3* p, const Vec3& normal, Index t) const
{
  const Index under = this->InputTriangleUnder(p, t);
  return under != InvalidIndex && Dot(normal, this->Input.TriangleAreaVector(under)) <= 0;
}

bool TileRepair::InputFoldsBetween(Index t, Index u) const
{
  Index under[2];
  const Index tiles[2] = { t, u };
  for (int i = 0; i < 2; ++i)
  {
    const Index* tri = this->Edit.Triangle(tiles[i]);
    const Vec3 p[3] = { this->Edit.Point(tri[0]), this->Edit.Point(tri[1]), this->Edit.Point(tri[2]) };
    under[i] = this->InputTriangleUnder(p, tiles[i]);
  }
  return under[0] != InvalidIndex && under[1] != InvalidIndex &&
    Dot(this->Input.TriangleAreaVector(under[0]), this->Input.TriangleAreaVector(under[1])) <= 0;
}

// The triangle across edge (x, y) from triangle t (InvalidIndex on a border or a non-manifold edge).
Index TileRepair::Across(Index t, Index x, Index y) const
{
  Index other = InvalidIndex;
  int count = 0;
  this->Edit.ForEachTriangle(x, [&](Index u) {
    ++this->Work;
    const Index* tri = this->Edit.Triangle(u);
    if (u != t && (tri[0] == y || tri[1] == y || tri[2] == y))
    {
      other = u;
      ++count;
    }
  });
  return count == 1 ? other : InvalidIndex;
}

TileRepair::Score TileRepair::TriangleScore(Index t) const
{
  const Index* tri = this->Edit.Triangle(t);
  const Vec3 p[3] = { this->Edit.Point(tri[0]), this->Edit.Point(tri[1]), this->Edit.Point(tri[2]) };
  Score score;
  ++this->TilesScored;
  score.Angle = MinimumAngle(p[0], p[1], p[2]);
  const Vec3 normal = TriangleNormal(p[0], p[1], p[2]);
  if (this->Stage == Target::Needles)
  {
    score.Bad = this->IsNeedle(p, score.Angle) ? 1 : 0;
    return score;
  }
  const bool locally = this->Stage == Target::Any && this->IsBadLocally(tri, p, normal, score.Angle);
  score.Bad = locally || this->FacesAgainstInput(p, normal, t) ? 1 : 0;
  return score;
}

// The tiles' bad count (a fold with a neighbour, turning by more than FoldAngle, counts as bad
// too), smallest angle and longest edge; their edge midpoints and centroids appended to
// deviationSamples when given (their distance to the original surface is measured later, only
// for a change that gets that far). The local checks come first: the centroid queries (the cost)
// are made only for tiles not bad already, and not at all when the tiles cannot beat `bound`.
TileRepair::Score TileRepair::RegionScore(
  const std::vector<Index>& triangles, std::vector<Vec3>* deviationSamples, const Score* bound) const
{
  Score total;
  total.Angle = std::numeric_limits<double>::max();
  this->RegionTiles += static_cast<long long>(triangles.size());
  this->LocallyBad.assign(triangles.size(), 0);
  for (size_t i = 0; i < triangles.size(); ++i)
  {
    const Index t = triangles[i];
    const Index* tri = this->Edit.Triangle(t);
    const Vec3 p[3] = { this->Edit.Point(tri[0]), this->Edit.Point(tri[1]), this->Edit.Point(tri[2]) };
    ++this->TilesScored;
    const double angle = MinimumAngle(p[0], p[1], p[2]);
    const Vec3 normal = this->Edit.TriangleNormal(t);
    if (this->Stage == Target::Flipped)
    {
      // The flipped stage counts needles (and folds, below) apart and queries every tile.
      total.Guarded += this->IsNeedle(p, angle) ? 1 : 0;
    }
    else if (this->Stage == Target::Needles)
    {
      total.Bad += this->IsNeedle(p, angle) ? 1 : 0;
    }
    else
    {
      this->LocallyBad[i] = this->IsBadLocally(tri, p, TriangleNormal(p[0], p[1], p[2]), angle) ? 1 : 0;
      total.Bad += this->LocallyBad[i];
    }
    total.Angle = std::min(total.Angle, angle);
    Vec3 centroid{ 0, 0, 0 };
    for (int k = 0; k < 3; ++k)
    {
      const Vec3 a = this->Edit.Point(tri[k]), b = this->Edit.Point(tri[(k + 1) % 3]);
      centroid = centroid + (1.0 / 3.0) * a;
      if (deviationSamples)
      {
        deviationSamples->push_back(0.5 * (a + b));
      }
      total.Extent = std::max(total.Extent, Dot(b - a, b - a));
      const Index other = this->Across(t, tri[k], tri[(k + 1) % 3]);
      const bool fold = other != InvalidIndex && Dot(normal, this->Edit.TriangleNormal(other)) < FoldCosine;
      if (!this->FinalStage())
      {
        total.Bad += fold ? 1 : 0;
      }
      else if (fold && !this->InputFoldsBetween(t, other))
      {
        // The final stage refuses only folds the input does not have (session 42): where the
        // input under the two tiles turns by 90 degrees or more (a wall thinner than the spacing,
        // a sharp ridge) the tiles must fold too, and counting that fold refused the changes that
        // put them the input's way (on the 132 consistently oriented CGAL meshes at 10% of the
        // vertices, 353 flipped tiles were left with those refusals, 306 without).
        ++total.Guarded;
      }
    }
    if (deviationSamples)
    {
      deviationSamples->push_back(centroid);
    }
  }
  if (bound && !this->Improves(total, *bound))
  {
    return total; // the queries could only add bad (or guarded) tiles
  }
  // The needle stage guards the flipped tiles: the same query, counted apart.
  int& flipped = this->Stage == Target::Needles ? total.Flipped : total.Bad;
  for (size_t i = 0; i < triangles.size(); ++i)
  {
    if (!this->LocallyBad[i])
    {
      const Index* tri = this->Edit.Triangle(triangles[i]);
      const Vec3 p[3] = { this->Edit.Point(tri[0]), this->Edit.Point(tri[1]), this->Edit.Point(tri[2]) };
      flipped += this->FacesAgainstInput(p, TriangleNormal(p[0], p[1], p[2]), triangles[i]) ? 1 : 0;
    }
  }
  return total;
}

// Whether every sample lies within sqrt(bound2) of the original surface (queries pruned at the bound).
bool TileRepair::WithinDeviation(const std::vector<Vec3>& samples, double bound2) const
{
  for (const Vec3& q : samples)
  {
    ++this->DistanceQueries;
    if (this->InputBVH.ClosestPoint(q, bound2).Triangle == InvalidIndex)
    {
      return false;
    }
  }
  return true;
}

// The region before a change: its score, its surface samples and its deviation samples.
void TileRepair::Measure(const std::vector<Index>& triangles, Before& before)
{
  before.DeviationSamples.clear();
  before.Tiles = this->RegionScore(triangles, &before.DeviationSamples);
  before.Surface.clear();
  for (Index t : triangles)
  {
    const Index* tri = this->Edit.Triangle(t);
    const Vec3 p[3] = { this->Edit.Point(tri[0]), this->Edit.Point(tri[1]), this->Edit.Point(tri[2]) };
    before.Surface.insert(before.Surface.end(), { p[0], 0.5 * (p[0] + p[1]), 0.5 * (p[1] + p[2]),
                                                  0.5 * (p[2] + p[0]), (1.0 / 3.0) * (p[0] + p[1] + p[2]) });
  }
}

// Whether the tiles after a change are an improvement on `before` that moves the surface by at
// most MovedBound of their size and the tiles no further from the original surface than they were
// (or than DeviationShare of their size). Cheapest test first; the distances to the original
// surface last, pruned at the bound, and the tiles' distance before only when the bound needs it.
bool TileRepair::Accept(Before& before, const std::vector<Index>& triangles)
{
  this->AfterSamples.clear();
  const Score after = this->RegionScore(triangles, &this->AfterSamples, &before.Tiles);
  const double extent = std::max(before.Tiles.Extent, after.Extent);
  // The last resort moves the surface further than the other changes: it must not leave a needle
  // sharper than the region had (a needle still counts as one bad tile only).
  const bool worseNeedle =
    this->MovedBound > MovedShare && after.Angle < std::min(before.Tiles.Angle, this->NeedleAngle);
  if (!this->Improves(after, before.Tiles) || worseNeedle ||
    !this->WithinDistanceOf(before.Surface, triangles, this->MovedBound * this->MovedBound * extent))
  {
    return false;
  }
  const double tolerance2 = DeviationShare * DeviationShare * extent;
  if (this->WithinDeviation(this->AfterSamples, tolerance2))
  {
    return true;
  }
  double deviation = 0; // squared, before the change
  for (const Vec3& q : before.DeviationSamples)
  {
    ++this->DistanceQueries;
    deviation = std::max(deviation, this->InputBVH.ClosestPoint(q).Distance2);
  }
  return deviation > tolerance2 && this->WithinDeviation(this->AfterSamples, deviation);
}

// Whether every sample lies within sqrt(bound2) of the tiles (how far the change moved the
// surface). A sample is done at the first tile close enough, its own tile first (samples come five
// per tile, in the tiles' order, and a change keeps the tile ids); the test fails at the first sample
// farther than the bound from every tile.
bool TileRepair::WithinDistanceOf(const std::vector<Vec3>& samples, const std::vector<Index>& triangles, double bound2) const
{
  auto near = [&](const Vec3& q, Index t) {
    const Index* tri = this->Edit.Triangle(t);
    const Vec3 c = ClosestPointOnTriangle(q, this->Edit.Point(tri[0]), this->Edit.Point(tri[1]), this->Edit.Point(tri[2]));
    return Dot(c - q, c - q) <= bound2;
  };
  for (size_t i = 0; i < samples.size(); ++i)
  {
    const size_t own = i / 5 < triangles.size() ? i / 5 : 0;
    if (near(samples[i], triangles[own]))
    {
      continue;
    }
    bool found = false;
    for (size_t j = 0; j < triangles.size() && !found; ++j)
    {
      found = j != own && near(samples[i], triangles[j]);
    }
    if (!found)
    {
      return false;
    }
  }
  return true;
}

void TileRepair::Star(Index v, std::vector<Index>& star) const
{
  star.clear();
  this->Edit.ForEachTriangle(v, [&](Index t) { star.push_back(t); });
  this->Work += static_cast<long long>(star.size());
}

// Flips (x, y) when its two tiles are then better; undone otherwise.
bool TileRepair::TryFlip(Index x, Index y)
{
  if (this->IsFixedEdge && this->IsFixedEdge(x, y))
  {
    return false;
  }
  std::vector<Index>& pair = this->Region;
  pair.clear();
  this->Edit.ForEachTriangle(x, [&](Index t) {
    const Index* tri = this->Edit.Triangle(t);
    if (tri[0] == y || tri[1] == y || tri[2] == y)
    {
      pair.push_back(t);
    }
  });
  if (pair.size() != 2)
  {
    return false;
  }
  this->Measure(pair, this->Previous);
  FlipRecord undo;
  if (!this->Edit.FlipEdge(x, y, &undo))
  {
    return false;
  }
  // FlipEdge keeps the two triangle ids.
  if (!this->Accept(this->Previous, pair))
  {
    this->Edit.Undo(undo);
    return false;
  }
  for (Index t : pair)
  {
    this->Touched.insert(this->Touched.end(), this->Edit.Triangle(t), this->Edit.Triangle(t) + 3);
  }
  if (this->Record)
  {
    this->Record->push_back(-1 - x);
    this->Record->push_back(y);
  }
  ++this->Flips;
  return true;
}

// Whether v may move: a free vertex with at most MaximumRepairValence tiles (then in `star`).
bool TileRepair::MovableStar(Index v, std::vector<Index>& star)
{
  if (!this->Movable[v])
  {
    return false;
  }
  this->Star(v, star);
  return star.size() <= MaximumRepairValence;
}

// Moves v toward the centre of its neighbours (the whole way, then half of it), projected onto
// the original surface on a sheet facing its way, when its star is then better.
bool TileRepair::TryMove(Index v)
{
  std::vector<Index>& star = this->Region;
  if (!this->MovableStar(v, star))
  {
    return false;
  }
  this->Edit.Neighbors(v, this->Neighbors);
  if (this->Neighbors.size() < 3)
  {
    return false;
  }
  Vec3 centre{ 0, 0, 0 };
  for (Index w : this->Neighbors)
  {
    centre = centre + this->Edit.Point(w);
  }
  centre = (1.0 / double(this->Neighbors.size())) * centre;
  const Vec3 start = this->Edit.Point(v);
  const Vec3 targets[3] = { centre, start + 0.5 * (centre - start), start + 0.25 * (centre - start) };
  return this->MoveToFirstAccepted(v, star, targets, 3);
}

// Moves v to the first of `targets` (projected onto the original surface, on a sheet facing the
// way v's does) that makes its star better; v stays where it was when none does.
bool TileRepair::MoveToFirstAccepted(Index v, const std::vector<Index>& star, const Vec3* targets, int count)
{
  const Vec3 start = this->Edit.Point(v);
  const Vec3 startReference = this->Reference[v];
  this->Work += static_cast<long long>(star.size()); // the star is visited again by the scores
  this->Measure(star, this->Previous);
  for (int i = 0; i < count; ++i)
  {
    ClosestPointResult c;
    if (this->ProjectTarget(v, start, startReference, targets[i], c) && this->KeepMoveIfAccepted(v, c, star))
    {
      return true;
    }
  }
  this->Edit.SetPoint(v, start);
  this->Reference[v] = startReference;
  return false;
}

// `target`'s closest point on the original surface, on a sheet facing `reference`'s way (false
// when it faces the other way: the vertex would change sheets in a thin part). A vertex v on a
// crease (AlongCrease) goes along the crease instead.
bool TileRepair::ProjectTarget(
  Index v, const Vec3& start, const Vec3& reference, const Vec3& target, ClosestPointResult& c) const
{
  ++this->DistanceQueries;
  if (this->AlongCrease && this->AlongCrease(v, start, target, reference, c))
  {
    // A crease vertex moves along its crease only (a move across it has no part left).
    return c.Distance2 > 0 && Dot(this->Input.TriangleAreaVector(c.Triangle), reference) > 0;
  }
  // start lies on the original surface: the closest point is no further from the query (pruned).
  const Vec3 step = target - start;
  c = this->InputBVH.ClosestPoint(target, Dot(step, step) * (1.0 + 1e-6));
  if (c.Triangle == InvalidIndex)
  {
    c = this->InputBVH.ClosestPoint(target);
  }
  return c.Triangle != InvalidIndex && Dot(this->Input.TriangleAreaVector(c.Triangle), reference) > 0;
}

// Moves v onto c (its reference normal follows) and keeps it there when the region `star` is then
// better than this->Previous (the caller puts v back otherwise).
bool TileRepair::KeepMoveIfAccepted(Index v, const ClosestPointResult& c, const std::vector<Index>& star)
{
  this->Edit.SetPoint(v, c.Point);
  this->Reference[v] = this->NormalAt(c.Point, c.Triangle);
  if (!this->Accept(this->Previous, star))
  {
    return false;
  }
  this->Moved(v, c.Point, c.Triangle);
  this->Touched.push_back(v);
  ++this->Moves;
  return true;
}

// The star's tiles (v, a, b) face the way of `normal` in its plane exactly when v lies left of
// each outer edge a -> b: the kernel is the intersection of those half-planes. Its corners are
// intersections of two edge lines inside every half-plane; their mean lies inside it (convex).
bool TileRepair::StarKernelPoint(Index v, const std::vector<Index>& star, Vec3& point) const
{
  const Vec3 start = this->Edit.Point(v);
  Vec3 normal = this->Reference[v];
  for (Index t : star)
  {
    const Index* tri = this->Edit.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      normal = normal + this->Reference[tri[k]];
    }
  }
  if (Norm(normal) == 0)
  {
    return false;
  }
  normal = Normalized(normal);
  // (The opposite frame of the one this code first had: every coordinate negated, the same point.)
  const Vec3 e1 = AnyOrthogonal(normal), e2 = Cross(normal, e1);
  // Each half-plane as m . p >= c with |m| = 1, in the plane's coordinates around start.
  std::vector<HalfPlane>& planes = this->KernelPlanes;
  planes.clear();
  double scale = 0;
  for (Index t : star)
  {
    const Index* tri = this->Edit.Triangle(t);
    const int at = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    const Vec3 a3 = this->Edit.Point(tri[(at + 1) % 3]) - start, b3 = this->Edit.Point(tri[(at + 2) % 3]) - start;
    const double a[2] = { Dot(a3, e1), Dot(a3, e2) }, b[2] = { Dot(b3, e1), Dot(b3, e2) };
    const double d[2] = { b[0] - a[0], b[1] - a[1] }, length = std::hypot(d[0], d[1]);
    if (length == 0)
    {
      return false;
    }
    scale = std::max(scale, length);
    const HalfPlane h{ { -d[1] / length, d[0] / length }, (-d[1] * a[0] + d[0] * a[1]) / length };
    planes.push_back(h);
  }
  const double slack = 1e-9 * scale;
  double sum[2] = { 0, 0 };
  int corners = 0;
  for (size_t i = 0; i < planes.size(); ++i)
  {
    for (size_t j = i + 1; j < planes.size(); ++j)
    {
      const HalfPlane &p = planes[i], &q = planes[j];
      const double det = p.M[0] * q.M[1] - p.M[1] * q.M[0];
      if (std::abs(det) < 1e-12)
      {
        continue;
      }
      const double x = (p.C * q.M[1] - p.M[1] * q.C) / det, y = (p.M[0] * q.C - p.C * q.M[0]) / det;
      const bool inside = std::all_of(
        planes.begin(), planes.end(), [&](const HalfPlane& h) { return h.M[0] * x + h.M[1] * y >= h.C - slack; });
      if (inside)
      {
        sum[0] += x;
        sum[1] += y;
        ++corners;
      }
    }
  }
  if (corners < 3)
  {
    return false; // empty, or no room inside
  }
  point = start + (sum[0] / corners) * e1 + (sum[1] / corners) * e2;
  return true;
}

// The last resort for a bad tile no flip or move toward the centre repairs: its vertex v goes
// where its whole star faces the surface's way in the star's plane (the kernel's centre, or half
// way there), projected onto the original surface; the surface may move by LastResortMovedShare.
bool TileRepair::TryKernelMove(Index v)
{
  std::vector<Index>& star = this->Region;
  Vec3 kernel;
  if (!this->MovableStar(v, star) || !this->StarKernelPoint(v, star, kernel))
  {
    return false;
  }
  const Vec3 start = this->Edit.Point(v);
  const Vec3 targets[2] = { kernel, start + 0.5 * (kernel - start) };
  this->MovedBound = LastResortMovedShare;
  const bool moved = this->MoveToFirstAccepted(v, star, targets, 2);
  this->MovedBound = this->UsualMovedBound();
  return moved;
}

// The last resort's relocation of v (session 26): a star with no kernel is a folded ring, but the
// ring itself may have a triangulation whose tiles all face the surface's way (the ring search,
// as the removal's). v's edges are flipped into that triangulation but for one tile, and v moves
// inside that tile (its centroid, projected onto the original surface): the same vertices, the
// same tiles, v's star now a valid triangle split in three. Tried in the RelocationTiles tiles
// nearest to v; accepted by the test of the other last-resort changes on v's old star's tiles
// (the flips keep the tile ids).
bool TileRepair::TryRelocate(Index v)
{
  std::vector<Index>& star = this->Region;
  bool valid = false;
  double worst = 0, smallestAngle = 0;
  this->Rings.MinimumAngle = this->NeedleAngle;
  if (!this->MovableStar(v, star) || this->HasOpposedRingEdge(v, star) ||
    !this->Rings.Find(v, valid, worst, smallestAngle) || !valid)
  {
    return false;
  }
  const Vec3 start = this->Edit.Point(v);
  std::vector<std::pair<double, int>> nearest;
  for (int i = 0; i < this->Rings.NumberOfTiles(); ++i)
  {
    const std::array<Index, 3> tile = this->Rings.Tile(i);
    const Vec3 centroid =
      (1.0 / 3.0) * (this->Edit.Point(tile[0]) + this->Edit.Point(tile[1]) + this->Edit.Point(tile[2]));
    nearest.emplace_back(Dot(centroid - start, centroid - start), i);
  }
  std::sort(nearest.begin(), nearest.end());
  nearest.resize(std::min(nearest.size(), size_t(RelocationTiles)));
  this->Measure(star, this->Previous);
  this->MovedBound = LastResortMovedShare;
  bool relocated = false;
  for (size_t i = 0; i < nearest.size() && !relocated; ++i)
  {
    this->Work += static_cast<long long>(2 * star.size()); // the flips' and the score's visits
    relocated = this->RelocateInto(v, nearest[i].second, star);
  }
  this->MovedBound = this->UsualMovedBound();
  return relocated;
}

// Whether a ring edge of v's star joins corners whose reference normals are 90 degrees or more
// apart (a part thinner than the spacing, a crease sharper than a right angle): a tile on that
// edge faces both only with its normal in the narrow lune between them, so the ring search is
// skipped there (on cheese it took most of the relocation's cost and seldom found a valid ring).
bool TileRepair::HasOpposedRingEdge(Index v, const std::vector<Index>& star) const
{
  for (Index t : star)
  {
    const Index* tri = this->Edit.Triangle(t);
    const int at = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    if (Dot(this->Reference[tri[(at + 1) % 3]], this->Reference[tri[(at + 2) % 3]]) <= 0)
    {
      return true;
    }
  }
  return false;
}

// One try of TryRelocate: v's edges flipped so that v keeps only the three tiles inside the ring
// triangulation's tile `tile`, then v moved to that tile's centroid on the original surface; all
// undone unless accepted.
bool TileRepair::RelocateInto(Index v, int tile, const std::vector<Index>& star)
{
  if (!this->Rings.SpokeFlipsInto(tile, this->Spokes))
  {
    return false;
  }
  const Vec3 start = this->Edit.Point(v);
  const Vec3 startReference = this->Reference[v];
  this->SpokeUndo.clear();
  bool flipped = true;
  for (size_t i = 0; i < this->Spokes.size() && flipped; ++i)
  {
    FlipRecord undo;
    flipped = (!this->IsFixedEdge || !this->IsFixedEdge(v, this->Spokes[i])) &&
      this->Edit.FlipEdge(v, this->Spokes[i], &undo);
    if (flipped)
    {
      this->SpokeUndo.push_back(undo);
    }
  }
  const std::array<Index, 3> corners = this->Rings.Tile(tile);
  const Vec3 centroid =
    (1.0 / 3.0) * (this->Edit.Point(corners[0]) + this->Edit.Point(corners[1]) + this->Edit.Point(corners[2]));
  ClosestPointResult c;
  if (flipped && this->ProjectTarget(v, start, startReference, centroid, c) && this->KeepsPoint(start, v, c.Point, star) &&
    this->KeepMoveIfAccepted(v, c, star))
  {
    for (Index t : star)
    {
      this->Touched.insert(this->Touched.end(), this->Edit.Triangle(t), this->Edit.Triangle(t) + 3);
    }
    for (Index a : this->Spokes)
    {
      if (this->Record)
      {
        this->Record->insert(this->Record->end(), { -1 - v, a });
      }
    }
    this->Flips += static_cast<Index>(this->Spokes.size());
    ++this->Relocations;
    return true;
  }
  this->Edit.SetPoint(v, start);
  this->Reference[v] = startReference;
  for (auto undo = this->SpokeUndo.rbegin(); undo != this->SpokeUndo.rend(); ++undo)
  {
    this->Edit.Undo(*undo);
  }
  return false;
}

// Whether `point` (where v was, a point of the original surface) lies within MovedShare of the
// star's longest edge of its tiles once v is at `position`: the removal's bound on a re-triangulated
// ring (slodRetiling.cxx). Accept compares the tiles with the input, not the input with the tiles:
// without this a relocation could cut off the tip v stood on (mannequin-devil's Hausdorff x1.5).
bool TileRepair::KeepsPoint(const Vec3& point, Index v, const Vec3& position, const std::vector<Index>& star)
{
  this->Edit.SetPoint(v, position);
  double distance2 = std::numeric_limits<double>::max(), extent = 0;
  for (Index t : star)
  {
    const Index* tri = this->Edit.Triangle(t);
    const Vec3 p[3] = { this->Edit.Point(tri[0]), this->Edit.Point(tri[1]), this->Edit.Point(tri[2]) };
    const Vec3 c = ClosestPointOnTriangle(point, p[0], p[1], p[2]);
    distance2 = std::min(distance2, Dot(c - point, c - point));
    for (int k = 0; k < 3; ++k)
    {
      extent = std::max(extent, Dot(p[(k + 1) % 3] - p[k], p[(k + 1) % 3] - p[k]));
    }
  }
  return distance2 <= MovedShare * MovedShare * extent;
}

// Two flips made together (the last resort): the edge (x, y) of bad tile t, then one of the four
// outer edges of the quad t makes with the tile u across (x, y). A pleat whose single flips each
// leave as many bad tiles (or a needle) is undone only by both: the flips measured on the 32 CGAL
// meshes left 6% fewer flipped tiles and 21% fewer folded edges (Documentation/Retile.md, session
// 25). Accepted by the same test as a single flip, on the three triangles the two flips change.
bool TileRepair::TryFlipPair(Index t, Index x, Index y)
{
  const Index u = this->Across(t, x, y);
  if (u == InvalidIndex || (this->IsFixedEdge && this->IsFixedEdge(x, y)))
  {
    return false;
  }
  // The quad's outer edges and the triangle outside each: the flip of (x, y) changes neither.
  std::pair<Index, Index> outer[4];
  Index outside[4];
  int count = 0;
  for (Index w : { t, u })
  {
    const Index* tri = this->Edit.Triangle(w);
    for (int k = 0; k < 3 && count < 4; ++k)
    {
      const Index a = tri[k], b = tri[(k + 1) % 3];
      if ((a == x && b == y) || (a == y && b == x))
      {
        continue;
      }
      outer[count] = { a, b };
      outside[count++] = this->Across(w, a, b);
    }
  }
  std::vector<Index>& region = this->Region;
  for (int i = 0; i < count; ++i)
  {
    const Index a = outer[i].first, b = outer[i].second;
    if (outside[i] == InvalidIndex || outside[i] == t || outside[i] == u ||
      (this->IsFixedEdge && this->IsFixedEdge(a, b)))
    {
      continue;
    }
    region.assign({ t, u, outside[i] });
    this->Measure(region, this->Previous);
    FlipRecord first, second;
    if (!this->Edit.FlipEdge(x, y, &first))
    {
      return false;
    }
    if (!this->Edit.FlipEdge(a, b, &second))
    {
      this->Edit.Undo(first);
      continue;
    }
    if (!this->Accept(this->Previous, region))
    {
      this->Edit.Undo(second);
      this->Edit.Undo(first);
      continue;
    }
    for (Index w : region)
    {
      this->Touched.insert(this->Touched.end(), this->Edit.Triangle(w), this->Edit.Triangle(w) + 3);
    }
    if (this->Record)
    {
      this->Record->insert(this->Record->end(), { -1 - x, y, -1 - a, b });
    }
    this->Flips += 2;
    return true;
  }
  return false;
}

// A bad tile: a flip of one of its edges, else a move of one of its vertices toward the centre of
// its neighbours; else (the last resort, session 23) a move of one of its vertices into its star's
// kernel, else a flip that moves the surface by up to LastResortMovedShare, else two flips
// together (TryFlipPair, session 25), else a relocation of one of its vertices inside its ring's
// re-triangulation (TryRelocate, session 26). Most tiles a flip
// leaves facing against the surface are pleats: undoing one moves the surface by more than
// MovedShare (the old tiles' samples lie on the fold) although the new tiles lie on the input.
bool TileRepair::RepairTriangle(Index t)
{
  if (this->FinalStage())
  {
    return this->RepairFlippedTriangle(t);
  }
  const Index* tri = this->Edit.Triangle(t);
  const Index ids[3] = { tri[0], tri[1], tri[2] };
  for (int k = 0; k < 3; ++k)
  {
    if (this->TryFlip(ids[k], ids[(k + 1) % 3]))
    {
      return true;
    }
  }
  for (int k = 0; k < 3; ++k)
  {
    if (this->TryMove(ids[k]))
    {
      return true;
    }
  }
  for (int k = 0; k < 3 && this->LastResort; ++k)
  {
    if (this->TryKernelMove(ids[k]))
    {
      return true;
    }
  }
  if (!this->LastResort)
  {
    return false;
  }
  this->MovedBound = LastResortMovedShare;
  bool repaired = false;
  for (int k = 0; k < 3 && !repaired; ++k)
  {
    repaired = this->TryFlip(ids[k], ids[(k + 1) % 3]);
  }
  for (int k = 0; k < 3 && !repaired; ++k)
  {
    repaired = this->TryFlipPair(t, ids[k], ids[(k + 1) % 3]);
  }
  this->MovedBound = this->UsualMovedBound();
  for (int k = 0; k < 3 && !repaired; ++k)
  {
    repaired = this->TryRelocate(ids[k]);
  }
  return repaired;
}

// A flipped tile in the final stage (or a needle in the needle stage): the flips of its edges,
// then two flips together, then moves of its vertices toward their neighbours' centre on the
// input, into their star's kernel, and the relocation inside their ring's re-triangulation; every
// change bounded by LastResortMovedShare.
bool TileRepair::RepairFlippedTriangle(Index t)
{
  const Index* tri = this->Edit.Triangle(t);
  const Index ids[3] = { tri[0], tri[1], tri[2] };
  // The first of the tile's edges (x, y) for which `change` is kept; y unused by the moves of x.
  const auto onAnEdge = [&](const auto& change) {
    for (int k = 0; k < 3; ++k)
    {
      if (change(ids[k], ids[(k + 1) % 3]))
      {
        return true;
      }
    }
    return false;
  };
  return onAnEdge([&](Index x, Index y) { return this->TryFlip(x, y); }) ||
    onAnEdge([&](Index x, Index y) { return this->TryFlipPair(t, x, y); }) ||
    onAnEdge([&](Index x, Index) { return this->TryMove(x) || this->TryKernelMove(x) || this->TryRelocate(x); });
}

Index TileRepair::RunFlipped(int rounds)
{
  return this->RunFinal(Target::Flipped, rounds);
}

Index TileRepair::RunNeedles(int rounds)
{
  return this->RunFinal(Target::Needles, rounds);
}

Index TileRepair::RunFinal(Target stage, int rounds)
{
  this->Stage = stage;
  this->MovedBound = this->UsualMovedBound();
  this->Work = 0;
  std::vector<unsigned char> wasMovable;
  for (Index v : this->MovableInFinalStage)
  {
    wasMovable.push_back(this->Movable[v]);
    this->Movable[v] = 1;
  }
  const Index left = this->Run(rounds, FlippedWorkPerTriangle);
  for (size_t i = 0; i < wasMovable.size(); ++i)
  {
    this->Movable[this->MovableInFinalStage[i]] = wasMovable[i];
  }
  this->Stage = Target::Any;
  this->MovedBound = this->UsualMovedBound();
  return left;
}

Index TileRepair::Run(int passes)
{
  return this->Run(passes, RepairWorkPerTriangle);
}

Index TileRepair::Run(int passes, long long workPerTriangle)
{
  std::vector<Index> bad, near, ring;
  for (Index t = 0; t < this->Edit.NumberOfTriangles(); ++t)
  {
    if (this->Edit.IsTriangleAlive(t) && this->TriangleScore(t).Bad)
    {
      bad.push_back(t);
    }
  }
  // Work bound: triangle visits, a fixed number per triangle of the mesh (a valence-5000 apex
  // would otherwise cost 5000 visits per check of every tile around it, pass after pass).
  const long long budget = workPerTriangle * static_cast<long long>(this->Edit.NumberOfTriangles());
  for (int pass = 0; pass < passes && !bad.empty() && this->Work < budget; ++pass)
  {
    this->Touched.clear();
    vtkLogF(TRACE, "retile repair pass %d: %zu bad tiles, %lld scored, %lld queries so far, %lld flips, %lld moves", pass,
      bad.size(), this->TilesScored, this->DistanceQueries, static_cast<long long>(this->Flips),
      static_cast<long long>(this->Moves));
    for (Index t : bad)
    {
      if (this->Work < budget && this->Edit.IsTriangleAlive(t) && this->TriangleScore(t).Bad)
      {
        this->RepairTriangle(t);
      }
    }
    if (this->Touched.empty())
    {
      break;
    }
    // The next pass tries only the bad tiles near what changed (two rings around the changed
    // vertices): the others would be tried on the same tiles again, and fail again.
    near = this->Touched;
    for (Index v : this->Touched)
    {
      this->Edit.Neighbors(v, ring);
      near.insert(near.end(), ring.begin(), ring.end());
    }
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    bad.clear();
    for (Index v : near)
    {
      this->Edit.ForEachTriangle(v, [&](Index t) { bad.push_back(t); });
    }
    std::sort(bad.begin(), bad.end());
    bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
    bad.erase(std::remove_if(bad.begin(), bad.end(),
                [&](Index t) { return !this->Edit.IsTriangleAlive(t) || !this->TriangleScore(t).Bad; }),
      bad.end());
  }
  return static_cast<Index>(bad.size());
}
} // namespace slod
