// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: disjoint sets over 0..n-1 with path halving; the root of a set is its
// smallest member, so results do not depend on the order of the unions.
#ifndef slodUnionFind_h
#define slodUnionFind_h

#include "slodTriangleMesh.h"

#include <numeric>
#include <utility>
#include <vector>

namespace slod
{
class UnionFind
{
public:
  explicit UnionFind(Index n = 0)
    : Parent(static_cast<size_t>(n))
  {
    std::iota(this->Parent.begin(), this->Parent.end(), Index(0));
  }
  Index Find(Index x)
  {
    while (this->Parent[x] != x)
    {
      this->Parent[x] = this->Parent[this->Parent[x]];
      x = this->Parent[x];
    }
    return x;
  }
  // Joins the sets of a and b; returns false when they were one set already.
  bool Union(Index a, Index b)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a == b)
    {
      return false;
    }
    if (b < a)
    {
      std::swap(a, b);
    }
    this->Parent[b] = a;
    return true;
  }

private:
  std::vector<Index> Parent;
};
} // namespace slod

#endif
