// SPDX-License-Identifier: BSD-3-Clause
// slod::PointGrid: every point within the radius is visited (against brute force, for narrow and
// for wide queries), and the work of a query stays the same when a surface is sampled more densely
// with a radius that shrinks accordingly (the property that keeps Retile's repulsion linear).
#include "slodPointGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

using namespace slod;

namespace
{
// n points uniform on the unit sphere (a surface sample, as Retile's repulsion sees it).
std::vector<double> SpherePoints(std::size_t n, unsigned seed)
{
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> xyz(3 * n);
  for (std::size_t i = 0; i < n; ++i)
  {
    double p[3] = { normal(random), normal(random), normal(random) };
    const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; ++k)
    {
      xyz[3 * i + k] = p[k] / len;
    }
  }
  return xyz;
}

double Distance2(const std::vector<double>& xyz, std::size_t i, std::size_t j)
{
  double d2 = 0;
  for (int k = 0; k < 3; ++k)
  {
    d2 += (xyz[3 * i + k] - xyz[3 * j + k]) * (xyz[3 * i + k] - xyz[3 * j + k]);
  }
  return d2;
}

// Turk's repulsion radius for n points on the unit sphere: 2 sqrt(area / n).
double RepulsionRadius(std::size_t n)
{
  return 2.0 * std::sqrt(4.0 * M_PI / double(n));
}
}

TEST(PointGrid, VisitsEveryPointWithinTheRadius)
{
  const std::size_t n = 20000;
  const std::vector<double> xyz = SpherePoints(n, 3);
  const double radius = RepulsionRadius(n);
  PointGrid grid;
  grid.Build(xyz, radius);
  for (double queryRadius : { radius, 0.3 * radius, 5.0 })
  {
    for (std::size_t q = 0; q < n; q += 97)
    {
      std::set<Index> found, expected;
      grid.ForEachNear(&xyz[3 * q], queryRadius, [&](Index j) {
        if (Distance2(xyz, q, std::size_t(j)) <= queryRadius * queryRadius)
        {
          found.insert(j);
        }
      });
      for (std::size_t j = 0; j < n; ++j)
      {
        if (Distance2(xyz, q, j) <= queryRadius * queryRadius)
        {
          expected.insert(Index(j));
        }
      }
      ASSERT_EQ(found, expected) << "query " << q << " radius " << queryRadius;
    }
  }
}

TEST(PointGrid, QueryWorkDoesNotGrowWithTheSampleDensity)
{
  // 256 times the points, each radius 16 times smaller: a query should look at the same number
  // of candidates. (The capped dense grid it replaces looked at about twice as many.)
  double visitedPerQuery[2] = { 0, 0 };
  const std::size_t sizes[2] = { 1000, 256000 };
  for (int s = 0; s < 2; ++s)
  {
    const std::vector<double> xyz = SpherePoints(sizes[s], 11);
    const double radius = RepulsionRadius(sizes[s]);
    PointGrid grid;
    grid.Build(xyz, radius);
    std::size_t visited = 0, queries = 0;
    for (std::size_t q = 0; q < sizes[s]; q += sizes[s] / 1000)
    {
      grid.ForEachNear(&xyz[3 * q], radius, [&](Index) { ++visited; });
      ++queries;
    }
    visitedPerQuery[s] = double(visited) / double(queries);
  }
  EXPECT_GT(visitedPerQuery[0], 10.0); // the radius reaches the neighbours
  EXPECT_LT(visitedPerQuery[1], 1.25 * visitedPerQuery[0])
    << visitedPerQuery[0] << " candidates per query at 1,000 points, " << visitedPerQuery[1] << " at 256,000";
}

TEST(PointGrid, DegenerateInputs)
{
  PointGrid grid;
  grid.Build({}, 1.0);
  int calls = 0;
  const double origin[3] = { 0, 0, 0 };
  grid.ForEachNear(origin, 1.0, [&](Index) { ++calls; });
  EXPECT_EQ(calls, 0);
  // Coincident points and a zero cell size: one cell, every point found.
  const std::vector<double> same(3 * 50, 2.5);
  grid.Build(same, 0.0);
  grid.ForEachNear(&same[0], 0.0, [&](Index) { ++calls; });
  EXPECT_EQ(calls, 50);
  // Points far apart over a tiny cell: the cell grows to fit the key, the far point is still found.
  const std::vector<double> far = { 0, 0, 0, 1e12, 0, 0 };
  grid.Build(far, 1e-9);
  calls = 0;
  grid.ForEachNear(&far[0], 2e12, [&](Index) { ++calls; });
  EXPECT_EQ(calls, 2);
  // A radius of many cells over a zero cell size (the cell count overflows a long long unless it
  // is clamped before the conversion; the sanitizer build reports it), a query point far outside,
  // and a NaN query: all points, none, none.
  grid.Build(same, 0.0);
  calls = 0;
  grid.ForEachNear(&same[0], 1.0, [&](Index) { ++calls; });
  EXPECT_EQ(calls, 50);
  calls = 0;
  const double outside[3] = { 1e300, -1e300, 2.5 };
  grid.ForEachNear(outside, 1.0, [&](Index) { ++calls; });
  EXPECT_EQ(calls, 0);
  const double undefined[3] = { std::nan(""), 2.5, 2.5 };
  grid.ForEachNear(undefined, 1.0, [&](Index) { ++calls; });
  EXPECT_EQ(calls, 0);
}
