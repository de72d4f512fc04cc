// SPDX-License-Identifier: BSD-3-Clause
#ifndef slodGroupByKey_h
#define slodGroupByKey_h

#include "slodHugePages.h"
#include "slodTriangleMesh.h" // Index

#include "vtkSMPTools.h"

#include <algorithm>
#include <vector>

namespace slod
{
// A counting sort of the items 0..n-1 by key, the adjacency lists (CSR) of the preparation
// stages: keyOf(i) gives item i's group in [0, groups) or a negative value (left out), valueOf(i)
// what the group stores for it. On return `first[g]` is where group g starts in `grouped` and
// `count[g]` its size (`count` must hold zeros on entry, `first` and `count` hold `groups`
// entries each); the total is returned.
//
// Within a group the values are in item order, as the serial loop leaves them, provided valueOf
// does not decrease with i within a group (a triangle id of item 3t + k, for example). With more
// than one thread (vtkSMPTools) and `parallel` set the items are counted and placed concurrently
// (relaxed atomic counts, so a group fills in any order) and each group is then sorted: the same
// result for any thread count. `parallel` off is the serial loop. Measured (session 28, mc1m, two
// threads at load 20): the parallel form costs about 1.7x the serial CPU time (the atomic counts
// and the sort of each group) and did not shorten the calling thread's part.
template <class KeyOf, class ValueOf>
Index GroupByKey(Index n, Index groups, KeyOf&& keyOf, ValueOf&& valueOf, Index* first, Index* count,
  std::vector<Index>& grouped, bool parallel)
{
  const bool concurrent = parallel && vtkSMPTools::GetEstimatedNumberOfThreads() > 1;
  constexpr vtkIdType grain = 16384;
  if (concurrent)
  {
    vtkSMPTools::For(0, n, grain, [&](vtkIdType begin, vtkIdType end) {
      for (Index i = static_cast<Index>(begin); i < static_cast<Index>(end); ++i)
      {
        const Index g = keyOf(i);
        if (g >= 0)
        {
          __atomic_fetch_add(&count[g], 1, __ATOMIC_RELAXED);
        }
      }
    });
  }
  else
  {
    for (Index i = 0; i < n; ++i)
    {
      const Index g = keyOf(i);
      if (g >= 0)
      {
        ++count[g];
      }
    }
  }
  Index total = 0;
  for (Index g = 0; g < groups; ++g)
  {
    first[g] = total;
    total += count[g];
    count[g] = 0; // the cursor of the placement below, the size again at its end
  }
  ReserveOnHugePages(grouped, static_cast<size_t>(total));
  grouped.resize(static_cast<size_t>(total));
  if (!concurrent)
  {
    for (Index i = 0; i < n; ++i)
    {
      const Index g = keyOf(i);
      if (g >= 0)
      {
        grouped[static_cast<size_t>(first[g] + count[g]++)] = valueOf(i);
      }
    }
    return total;
  }
  vtkSMPTools::For(0, n, grain, [&](vtkIdType begin, vtkIdType end) {
    for (Index i = static_cast<Index>(begin); i < static_cast<Index>(end); ++i)
    {
      const Index g = keyOf(i);
      if (g >= 0)
      {
        grouped[static_cast<size_t>(first[g] + __atomic_fetch_add(&count[g], 1, __ATOMIC_RELAXED))] = valueOf(i);
      }
    }
  });
  vtkSMPTools::For(0, groups, grain, [&](vtkIdType begin, vtkIdType end) {
    for (Index g = static_cast<Index>(begin); g < static_cast<Index>(end); ++g)
    {
      Index* values = grouped.data() + first[g];
      if (count[g] > 32)
      {
        std::sort(values, values + count[g]); // a vertex of high valence
        continue;
      }
      // Most groups are short (a vertex's triangles): an insertion sort.
      for (Index a = 1; a < count[g]; ++a)
      {
        const Index value = values[a];
        Index b = a;
        for (; b > 0 && values[b - 1] > value; --b)
        {
          values[b] = values[b - 1];
        }
        values[b] = value;
      }
    }
  });
  return total;
}
} // namespace slod

#endif
