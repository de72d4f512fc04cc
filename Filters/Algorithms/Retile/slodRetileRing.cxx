// SPDX-License-Identifier: BSD-3-Clause
#include "slodRetileRing.h"

#include "slodTriangleBVH.h"

#include <algorithm>
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
} // namespace slod
