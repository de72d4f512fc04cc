// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: counter-based pseudo-random numbers (splitmix64 finaliser).
//
// Value i of a stream is Finalise(key + i * Golden): any value can be drawn on its own, in any
// order and on any thread, and is the same on every platform and standard library (std
// distributions and rand() are not).
#ifndef slodCounterHash_h
#define slodCounterHash_h

#include <cstdint>

namespace slod
{
constexpr std::uint64_t Golden = 0x9E3779B97F4A7C15ull;

inline std::uint64_t Finalise(std::uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Uniform in [0, 1): value `counter` of the stream `key`.
inline double Uniform(std::uint64_t key, std::uint64_t counter)
{
  return double(Finalise(key + (counter + 1) * Golden) >> 11) * 0x1.0p-53;
}

// Uniform in [0, 1) for the grid point (i, j, k) of the stream `key` (i, j, k below 2^21).
inline double GridUniform(std::uint64_t key, std::uint64_t i, std::uint64_t j, std::uint64_t k)
{
  return Uniform(key, (k << 42) | (j << 21) | i);
}
} // namespace slod

#endif
