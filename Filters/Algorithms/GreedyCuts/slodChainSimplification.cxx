// SPDX-License-Identifier: BSD-3-Clause
#include "slodChainSimplification.h"

#include <algorithm>
#include <utility>

namespace slod
{
double PointSegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b)
{
  const Vec3 ab = b - a;
  const double l2 = Dot(ab, ab);
  double t = l2 > 0 ? Dot(p - a, ab) / l2 : 0.0;
  t = std::min(1.0, std::max(0.0, t));
  return Norm(p - (a + t * ab));
}

Index FarthestChainVertex(const TriangleMesh& mesh, const Index* vertices, Index first, Index last, double* distance)
{
  Index best = InvalidIndex;
  double far = -1;
  const Vec3 a = mesh.Point(vertices[first]);
  const Vec3 b = mesh.Point(vertices[last]);
  for (Index i = first + 1; i < last; ++i)
  {
    const double d = PointSegmentDistance(mesh.Point(vertices[i]), a, b);
    if (d > far)
    {
      far = d;
      best = i;
    }
  }
  if (distance)
  {
    *distance = far;
  }
  return best;
}

void SimplifyChain(
  const TriangleMesh& mesh, const Index* vertices, Index n, double epsilon, std::vector<unsigned char>& keep)
{
  keep.assign(size_t(std::max<Index>(n, 0)), epsilon < 0 ? 1 : 0);
  if (n <= 0)
  {
    return;
  }
  keep[0] = keep[size_t(n) - 1] = 1;
  // Explicit stack: chains can be long, recursion depth would be O(n) on spirals.
  std::vector<std::pair<Index, Index>> stack;
  if (epsilon >= 0 && n > 2)
  {
    stack.emplace_back(0, n - 1);
  }
  while (!stack.empty())
  {
    const auto [first, last] = stack.back();
    stack.pop_back();
    double d = 0;
    const Index split = FarthestChainVertex(mesh, vertices, first, last, &d);
    if (split == InvalidIndex || d <= epsilon)
    {
      continue;
    }
    keep[split] = 1;
    stack.emplace_back(first, split);
    stack.emplace_back(split, last);
  }
}
} // namespace slod
