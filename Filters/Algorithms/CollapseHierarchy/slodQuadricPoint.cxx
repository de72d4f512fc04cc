// SPDX-License-Identifier: BSD-3-Clause
#include "slodQuadricPoint.h"

#include <algorithm>
#include <cmath>

namespace slod
{
namespace
{
// The symmetric matrix A - shift I (or any symmetric 3x3), by its six entries.
struct Symmetric3
{
  double XX, XY, XZ, YY, YZ, ZZ;
};

Symmetric3 MatrixOf(const Quadric& q, double shift = 0)
{
  return { q.Axx - shift, q.Axy, q.Axz, q.Ayy - shift, q.Ayz, q.Azz - shift };
}

// Unit vector along the longest cross product of two rows of m: the direction m maps to zero
// when m has rank two (m = A - lambda I for a simple eigenvalue lambda). False when m is
// (numerically) of rank below two.
bool NullDirection(const Symmetric3& m, Vec3& u)
{
  const Vec3 r0{ m.XX, m.XY, m.XZ }, r1{ m.XY, m.YY, m.YZ }, r2{ m.XZ, m.YZ, m.ZZ };
  const Vec3 candidates[3] = { Cross(r0, r1), Cross(r0, r2), Cross(r1, r2) };
  double longest = 0;
  int best = -1;
  for (int i = 0; i < 3; ++i)
  {
    const double length = Dot(candidates[i], candidates[i]);
    if (length > longest)
    {
      longest = length;
      best = i;
    }
  }
  if (best < 0 || !std::isfinite(longest))
  {
    return false;
  }
  u = (1.0 / std::sqrt(longest)) * candidates[best];
  return true;
}

// y = m^-1 g by cofactors; false when m is singular.
bool Solve(const Symmetric3& m, const Vec3& g, Vec3& y)
{
  const double c00 = m.YY * m.ZZ - m.YZ * m.YZ;
  const double c01 = m.XZ * m.YZ - m.XY * m.ZZ;
  const double c02 = m.XY * m.YZ - m.XZ * m.YY;
  const double det = m.XX * c00 + m.XY * c01 + m.XZ * c02;
  if (det == 0 || !std::isfinite(det))
  {
    return false;
  }
  const double c11 = m.XX * m.ZZ - m.XZ * m.XZ;
  const double c12 = m.XY * m.XZ - m.XX * m.YZ;
  const double c22 = m.XX * m.YY - m.XY * m.XY;
  const double inverse = 1.0 / det;
  y = { inverse * (c00 * g[0] + c01 * g[1] + c02 * g[2]), inverse * (c01 * g[0] + c11 * g[1] + c12 * g[2]),
    inverse * (c02 * g[0] + c12 * g[1] + c22 * g[2]) };
  return true;
}
} // namespace

void QuadricEigenvalues(const Quadric& q, double (&lambda)[3])
{
  // Shifted by the mean eigenvalue (B = A - mean I has trace 0), which keeps the coefficients'
  // rounding relative to the spread of the eigenvalues rather than to their size. Characteristic
  // polynomial of B: p(y) = y^3 + minors y - det.
  const double mean = (q.Axx + q.Ayy + q.Azz) / 3;
  const Symmetric3 b = MatrixOf(q, mean);
  const double minors =
    (b.XX * b.YY - b.XY * b.XY) + (b.XX * b.ZZ - b.XZ * b.XZ) + (b.YY * b.ZZ - b.YZ * b.YZ);
  const double det = b.XX * (b.YY * b.ZZ - b.YZ * b.YZ) + b.XY * (b.XZ * b.YZ - b.XY * b.ZZ) +
    b.XZ * (b.XY * b.YZ - b.XZ * b.YY);
  // B's eigenvalues sum to 0, so the largest is at most sqrt(2/3) times the Frobenius norm (equal
  // when the other two are equal: a matrix of rank one, the common case, starts on its root).
  // p is increasing and convex beyond B's largest root (which is at least 0, the inflection
  // point): Newton's steps from that bound decrease monotonically onto it. Quadratic convergence
  // for a simple root; a double root converges linearly, within the bound.
  double y = std::sqrt((2.0 / 3.0) *
    (b.XX * b.XX + b.YY * b.YY + b.ZZ * b.ZZ + 2 * (b.XY * b.XY + b.XZ * b.XZ + b.YZ * b.YZ)));
  for (int iteration = 0; iteration < 100; ++iteration)
  {
    const double p = (y * y + minors) * y - det;
    const double slope = 3 * y * y + minors;
    if (!(p > 0) || !(slope > 0))
    {
      break; // on the root within rounding
    }
    const double step = p / slope;
    y -= step;
    if (!(step > 1e-15 * y))
    {
      break;
    }
  }
  // The other two roots of B: sum -y, product det / y.
  const double product = y > 0 ? det / y : 0;
  const double root = std::sqrt(std::max(0.0, y * y - 4 * product));
  // The one of larger magnitude first (no cancellation), the other from the product.
  const double low = 0.5 * (-y - root);
  const double high = low != 0 ? product / low : 0;
  lambda[0] = mean + y;
  lambda[1] = mean + std::max(high, low);
  lambda[2] = mean + std::min(high, low);
}

Vec3 QuadricPointNear(const Quadric& q, const Vec3& center, double relativeTolerance)
{
  // Well conditioned (the determinant test implies every eigenvalue above the tolerance): the
  // plain minimum, by cofactors.
  Vec3 minimum;
  if (q.Minimize(minimum, relativeTolerance))
  {
    return minimum;
  }
  double lambda[3];
  QuadricEigenvalues(q, lambda);
  const double top = std::max(std::abs(lambda[0]), std::abs(lambda[2]));
  if (!(top > 0) || !std::isfinite(top))
  {
    return center;
  }
  const double limit = relativeTolerance * top;
  const Vec3 g{ q.Axx * center[0] + q.Axy * center[1] + q.Axz * center[2] + q.Bx,
    q.Axy * center[0] + q.Ayy * center[1] + q.Ayz * center[2] + q.By,
    q.Axz * center[0] + q.Ayz * center[1] + q.Azz * center[2] + q.Bz };
  Vec3 step;
  if (lambda[2] > limit && Solve(MatrixOf(q), g, step))
  {
    return center - step; // every direction kept
  }
  if (lambda[1] > limit)
  {
    // Two kept: shift the dropped eigenvalue up to the largest, solve, and take the dropped
    // direction's part out again.
    Vec3 dropped;
    if (!NullDirection(MatrixOf(q, lambda[2]), dropped))
    {
      return center;
    }
    const double raise = lambda[0] - lambda[2];
    const Symmetric3 shifted{ q.Axx + raise * dropped[0] * dropped[0], q.Axy + raise * dropped[0] * dropped[1],
      q.Axz + raise * dropped[0] * dropped[2], q.Ayy + raise * dropped[1] * dropped[1],
      q.Ayz + raise * dropped[1] * dropped[2], q.Azz + raise * dropped[2] * dropped[2] };
    if (!Solve(shifted, g, step))
    {
      return center;
    }
    return center - (step - (Dot(dropped, g) / lambda[0]) * dropped);
  }
  // One kept: move along the dominant direction only.
  Vec3 dominant;
  if (!(lambda[0] > limit) || !NullDirection(MatrixOf(q, lambda[0]), dominant))
  {
    return center;
  }
  return center - (Dot(dominant, g) / lambda[0]) * dominant;
}
} // namespace slod
