// SPDX-License-Identifier: BSD-3-Clause
#include "slodCollapsePasses.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace slod
{
namespace
{
std::uint64_t RankKey(float key, Index element)
{
  // Non-negative floats order as their bit patterns.
  std::uint32_t bits = 0;
  std::memcpy(&bits, &key, sizeof(bits));
  return (std::uint64_t(bits) << 32) | std::uint64_t(static_cast<std::uint32_t>(element));
}

float KeyOf(std::uint64_t entry)
{
  const std::uint32_t bits = static_cast<std::uint32_t>(entry >> 32);
  float key = 0.0f;
  std::memcpy(&key, &bits, sizeof(key));
  return key;
}
} // namespace

void RankPassCandidates(const std::vector<float>& keys, const unsigned char* alive, Index goalRank, double factor,
  float floor, PassRanking& ranking)
{
  std::vector<std::uint64_t>& order = ranking.Order;
  order.clear();
  for (size_t i = 0; i < keys.size(); ++i)
  {
    if ((!alive || alive[i]) && std::isfinite(keys[i]))
    {
      order.push_back(RankKey(std::max(0.0f, keys[i]), static_cast<Index>(i)));
    }
  }
  ranking.Candidates = static_cast<Index>(order.size());
  ranking.Limit = std::numeric_limits<float>::infinity();
  ranking.Everything = true;
  if (order.empty())
  {
    return;
  }
  if (goalRank >= 0 && size_t(goalRank) < order.size())
  {
    // The key of rank goalRank in linear time; only what lies under the limit is sorted.
    std::nth_element(order.begin(), order.begin() + goalRank, order.end());
    const double limit = std::max<double>(floor, factor * double(KeyOf(order[size_t(goalRank)])));
    ranking.Limit = static_cast<float>(std::min<double>(limit, std::numeric_limits<float>::max()));
    const auto cut = std::partition(order.begin(), order.end(), [&](std::uint64_t e) { return KeyOf(e) <= ranking.Limit; });
    ranking.Everything = cut == order.end();
    order.erase(cut, order.end());
  }
  // A total order (key, then index): the same result whatever sort and thread count.
  vtkSMPTools::Sort(order.begin(), order.end());
}
} // namespace slod
