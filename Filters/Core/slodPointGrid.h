// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: a uniform grid over a point set for fixed-radius neighbour queries.
//
// Only occupied cells are stored (sorted cell keys and an open-addressing hash of them). A dense
// grid over samples of a surface has far more empty cells than occupied ones; capping its size
// (as Retile's first grid did) made the cells, and so each query's work, grow with the point
// count: its repulsion step cost n^(4/3). Here a query of radius <= the cell size visits the 27
// cells around the point whatever n is. Points within a cell are visited in increasing id order
// and cells in (z, y, x) order, so sums over a query's points are deterministic.
#ifndef slodPointGrid_h
#define slodPointGrid_h

#include "slodTriangleMesh.h" // Index

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace slod
{
class SURFACELODFILTERS_EXPORT PointGrid
{
public:
  // xyz: 3 coordinates per point; cell: the edge of a cell (enlarged only when the extent over it
  // would not fit 2^21 cells per axis).
  void Build(const std::vector<double>& xyz, double cell);

  // f(j) for every point j in the cells that the box of half-width `radius` around p touches (a
  // superset of the points within `radius`; radius <= CellSize() gives the 27 cells).
  template <typename F>
  void ForEachNear(const double* p, double radius, F&& f) const
  {
    this->ForEachSlotNear(p, radius, [&](Index slot) { f(this->Ids[slot]); });
  }

  // The same visit by slot: the point of slot s is CellOrder()[s]. Data copied into cell order
  // (slot by slot) is read contiguously by nearby queries, which matters once it leaves the cache.
  template <typename F>
  void ForEachSlotNear(const double* p, double radius, F&& f) const;
  const std::vector<Index>& CellOrder() const { return this->Ids; }

  double CellSize() const { return this->Cell; }
  std::size_t NumberOfOccupiedCells() const { return this->CellKeys.size(); }

private:
  static constexpr long long MaxCellsPerAxis = 1LL << 21;
  static constexpr std::size_t NoCell = std::numeric_limits<std::size_t>::max();

  static std::uint64_t PackKey(long long x, long long y, long long z)
  {
    return std::uint64_t(x) | (std::uint64_t(y) << 21) | (std::uint64_t(z) << 42);
  }
  static bool KeyInBox(std::uint64_t key, const long long* c0, const long long* c1);
  std::uint64_t Key(const double* p) const;
  // The cell coordinate of x along axis k, clamped to [-1, Dims[k]] before the conversion: a
  // far, huge-radius or NaN query would overflow it (undefined); NaN gives -1 (no cell).
  long long CellCoordinate(double x, int k) const
  {
    const double c = std::floor((x - this->Origin[k]) / this->Cell);
    return c >= double(this->Dims[k]) ? this->Dims[k] : (c >= 0 ? static_cast<long long>(c) : -1);
  }
  void SortPointsByCell(const std::vector<double>& xyz, std::size_t n);
  void HashCells();
  std::size_t FindCell(std::uint64_t key) const;
  template <typename F>
  void ForEachInCell(std::size_t c, F& f) const
  {
    for (Index slot = this->Start[c]; slot < this->Start[c + 1]; ++slot)
    {
      f(slot);
    }
  }

  double Origin[3] = { 0, 0, 0 };
  double Cell = 1;
  long long Dims[3] = { 1, 1, 1 };
  std::vector<std::uint64_t> CellKeys; // occupied cells, increasing
  std::vector<Index> Start, Ids;       // Ids[Start[c] .. Start[c + 1]) are cell c's points
  std::vector<std::size_t> Table;      // hash slot -> cell, NoCell when empty
  int HashShift = 63;
};

template <typename F>
void PointGrid::ForEachSlotNear(const double* p, double radius, F&& f) const
{
  long long c0[3], c1[3];
  for (int k = 0; k < 3; ++k)
  {
    c0[k] = std::max<long long>(0, this->CellCoordinate(p[k] - radius, k));
    c1[k] = std::min<long long>(this->Dims[k] - 1, this->CellCoordinate(p[k] + radius, k));
  }
  const double boxCells = double(c1[0] - c0[0] + 1) * double(c1[1] - c0[1] + 1) * double(c1[2] - c0[2] + 1);
  if (boxCells > double(this->CellKeys.size()))
  {
    // A wide query: walk the occupied cells (in the same (z, y, x) order) instead of probing
    // mostly empty ones, so its work is bounded by the grid's size.
    for (std::size_t c = 0; c < this->CellKeys.size(); ++c)
    {
      if (KeyInBox(this->CellKeys[c], c0, c1))
      {
        this->ForEachInCell(c, f);
      }
    }
    return;
  }
  for (long long z = c0[2]; z <= c1[2]; ++z)
    for (long long y = c0[1]; y <= c1[1]; ++y)
      for (long long x = c0[0]; x <= c1[0]; ++x)
      {
        const std::size_t c = this->FindCell(PackKey(x, y, z));
        if (c != NoCell)
        {
          this->ForEachInCell(c, f);
        }
      }
}
} // namespace slod

#endif
