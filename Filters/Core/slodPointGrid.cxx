// SPDX-License-Identifier: BSD-3-Clause
#include "slodPointGrid.h"

#include <utility>

namespace slod
{
void PointGrid::Build(const std::vector<double>& xyz, double cell)
{
  const std::size_t n = xyz.size() / 3;
  double lo[3] = { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::max() };
  double hi[3] = { -lo[0], -lo[1], -lo[2] };
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], xyz[3 * i + k]);
      hi[k] = std::max(hi[k], xyz[3 * i + k]);
    }
  }
  if (n == 0)
  {
    lo[0] = lo[1] = lo[2] = hi[0] = hi[1] = hi[2] = 0;
  }
  // Cell coordinates must fit the key's 21 bits per axis (the extent over a tiny cell would not).
  cell = std::max(cell, 1e-300);
  for (int k = 0; k < 3; ++k)
  {
    cell = std::max(cell, (hi[k] - lo[k]) / double(MaxCellsPerAxis - 1));
  }
  this->Cell = cell;
  std::copy(lo, lo + 3, this->Origin);
  for (int k = 0; k < 3; ++k)
  {
    this->Dims[k] =
      std::min<long long>(MaxCellsPerAxis, static_cast<long long>(std::floor((hi[k] - lo[k]) / cell)) + 1);
  }
  this->SortPointsByCell(xyz, n);
  this->HashCells();
}

bool PointGrid::KeyInBox(std::uint64_t key, const long long* c0, const long long* c1)
{
  for (int k = 0; k < 3; ++k)
  {
    const long long c = static_cast<long long>((key >> (21 * k)) & std::uint64_t(MaxCellsPerAxis - 1));
    if (c < c0[k] || c > c1[k])
    {
      return false;
    }
  }
  return true;
}

std::uint64_t PointGrid::Key(const double* p) const
{
  long long c[3];
  for (int k = 0; k < 3; ++k)
  {
    c[k] = std::min<long long>(this->Dims[k] - 1,
      std::max<long long>(0, static_cast<long long>(std::floor((p[k] - this->Origin[k]) / this->Cell))));
  }
  return PackKey(c[0], c[1], c[2]);
}

// Ids in (cell key, point id) order; CellKeys and Start describe the runs of equal keys.
void PointGrid::SortPointsByCell(const std::vector<double>& xyz, std::size_t n)
{
  std::vector<std::pair<std::uint64_t, Index>> keyed(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    keyed[i] = { this->Key(&xyz[3 * i]), static_cast<Index>(i) };
  }
  std::sort(keyed.begin(), keyed.end());
  this->Ids.resize(n);
  this->CellKeys.clear();
  this->Start.clear();
  for (std::size_t i = 0; i < n; ++i)
  {
    this->Ids[i] = keyed[i].second;
    if (i == 0 || keyed[i].first != keyed[i - 1].first)
    {
      this->CellKeys.push_back(keyed[i].first);
      this->Start.push_back(static_cast<Index>(i));
    }
  }
  this->Start.push_back(static_cast<Index>(n));
}

namespace
{
std::size_t HashSlot(std::uint64_t key, int shift)
{
  return std::size_t((key * 0x9E3779B97F4A7C15ull) >> shift);
}
}

// Open addressing with linear probing, at most half full: a lookup takes a few probes, and every
// probe sequence reaches an empty slot.
void PointGrid::HashCells()
{
  int bits = 1;
  while ((std::size_t(1) << bits) < 2 * this->CellKeys.size() + 2)
  {
    ++bits;
  }
  this->HashShift = 64 - bits;
  this->Table.assign(std::size_t(1) << bits, NoCell);
  const std::size_t mask = this->Table.size() - 1;
  for (std::size_t c = 0; c < this->CellKeys.size(); ++c)
  {
    std::size_t h = HashSlot(this->CellKeys[c], this->HashShift);
    while (this->Table[h] != NoCell)
    {
      h = (h + 1) & mask;
    }
    this->Table[h] = c;
  }
}

std::size_t PointGrid::FindCell(std::uint64_t key) const
{
  const std::size_t mask = this->Table.size() - 1;
  for (std::size_t h = HashSlot(key, this->HashShift), probes = 0; probes < this->Table.size();
       h = (h + 1) & mask, ++probes)
  {
    const std::size_t c = this->Table[h];
    if (c == NoCell || this->CellKeys[c] == key)
    {
      return c;
    }
  }
  return NoCell;
}
} // namespace slod
