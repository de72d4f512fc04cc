// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: points held for a long time (a hierarchy's input points, for the life of
// the hierarchy) in floats when every coordinate is exactly a float, else in doubles. A float
// input read into doubles (mc1m, the MRI isosurface) gives the same values in half the bytes:
// Point returns the same doubles either way, so every sum over them is the same.
#ifndef slodPointStore_h
#define slodPointStore_h

#include "slodTriangleMesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace slod
{
class PointStore
{
public:
  // True when every coordinate converts to a float and back unchanged. (The range test comes
  // first: converting a double beyond the float range is undefined.)
  static bool AllFloats(const std::vector<double>& coordinates)
  {
    return std::all_of(coordinates.begin(), coordinates.end(), [](double x) {
      return std::fabs(x) <= double(std::numeric_limits<float>::max()) &&
        static_cast<double>(static_cast<float>(x)) == x;
    });
  }

  // Takes the coordinates (3 per point; the vector is left empty).
  void Take(std::vector<double>& coordinates)
  {
    std::vector<float>().swap(this->Floats);
    std::vector<double>().swap(this->Doubles);
    this->Count = static_cast<Index>(coordinates.size() / 3);
    if (AllFloats(coordinates))
    {
      this->Floats.assign(coordinates.begin(), coordinates.end());
      std::vector<double>().swap(coordinates);
    }
    else
    {
      this->Doubles.swap(coordinates);
      std::vector<double>().swap(coordinates);
    }
  }

  Index NumberOfPoints() const { return this->Count; }
  bool HoldsFloats() const { return !this->Floats.empty(); }
  Vec3 Point(Index v) const
  {
    const size_t i = 3 * static_cast<size_t>(v);
    if (!this->Floats.empty())
    {
      return { this->Floats[i], this->Floats[i + 1], this->Floats[i + 2] };
    }
    return { this->Doubles[i], this->Doubles[i + 1], this->Doubles[i + 2] };
  }
  void Prefetch(Index v) const
  {
    const size_t i = 3 * static_cast<size_t>(v);
    __builtin_prefetch(this->Floats.empty() ? static_cast<const void*>(this->Doubles.data() + i)
                                            : static_cast<const void*>(this->Floats.data() + i));
  }
  // Every coordinate as a double (a copy).
  std::vector<double> Coordinates() const
  {
    return this->Floats.empty() ? this->Doubles : std::vector<double>(this->Floats.begin(), this->Floats.end());
  }
  size_t MemoryBytes() const
  {
    return this->Floats.capacity() * sizeof(float) + this->Doubles.capacity() * sizeof(double);
  }

private:
  std::vector<float> Floats;
  std::vector<double> Doubles;
  Index Count = 0;
};
} // namespace slod

#endif
