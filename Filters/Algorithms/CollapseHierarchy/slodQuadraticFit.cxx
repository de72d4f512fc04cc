// SPDX-License-Identifier: BSD-3-Clause
#include "slodQuadraticFit.h"

#include <algorithm>
#include <cmath>

namespace slod
{
bool LocalFrame::SetNormal(const Vec3& origin, const Vec3& normal)
{
  this->Origin = origin;
  const Vec3 n = Normalized(normal);
  if (Dot(n, n) == 0)
  {
    return false;
  }
  this->Normal = n;
  return true;
}

bool LocalFrame::Set(const Vec3& origin, const Vec3& normal, const Vec3& direction)
{
  if (!this->SetNormal(origin, normal))
  {
    return false;
  }
  const Vec3 n = this->Normal;
  Vec3 u = direction - Dot(direction, n) * n;
  if (Norm(u) <= 1e-12 * Norm(direction) || Norm(direction) == 0)
  {
    // Any perpendicular: cross with the axis least aligned with n.
    const int axis = std::abs(n[0]) < std::abs(n[1]) ? (std::abs(n[0]) < std::abs(n[2]) ? 0 : 2)
                                                     : (std::abs(n[1]) < std::abs(n[2]) ? 1 : 2);
    Vec3 e{ 0, 0, 0 };
    e[axis] = 1;
    u = Cross(n, e);
  }
  this->U = Normalized(u);
  this->V = Cross(n, this->U);
  return true;
}

namespace
{
// Solves min |A x - b| for the first `columns` (<= 6) columns of the row-major n x 6 design
// matrix by column-pivoting Householder QR, in place on column-major scratch (no allocation per
// call: this runs for every triangle evaluation). Returns the rank: pivots |R_kk| at most 1e-9
// |R_00| count as zero (the monomials are scaled to the unit disc, so this relative threshold,
// well above round-off, separates genuinely degenerate point sets from thin ones).
int SolveLeastSquares(const double* design, const double* rhs, int rows, int columns, double* x,
  std::vector<double>& scratch)
{
  scratch.resize(size_t(rows) * (columns + 1));
  double* a = scratch.data(); // column j at a + j * rows; column `columns` is b
  for (int i = 0; i < rows; ++i)
  {
    for (int j = 0; j < columns; ++j)
    {
      a[size_t(j) * rows + i] = design[size_t(i) * 6 + j];
    }
    a[size_t(columns) * rows + i] = rhs[i];
  }
  double* b = a + size_t(columns) * rows;
  int permutation[6] = { 0, 1, 2, 3, 4, 5 };
  double diagonal[6] = { 0, 0, 0, 0, 0, 0 };
  int rank = 0;
  double first = 0;
  for (int k = 0; k < columns; ++k)
  {
    // Pivot: the remaining column of largest norm below row k (recomputed: six columns only).
    int best = k;
    double bestNorm2 = -1;
    for (int j = k; j < columns; ++j)
    {
      const double* c = a + size_t(j) * rows;
      double n2 = 0;
      for (int i = k; i < rows; ++i)
      {
        n2 += c[i] * c[i];
      }
      if (n2 > bestNorm2)
      {
        bestNorm2 = n2;
        best = j;
      }
    }
    if (best != k)
    {
      std::swap_ranges(a + size_t(k) * rows, a + size_t(k + 1) * rows, a + size_t(best) * rows);
      std::swap(permutation[k], permutation[best]);
    }
    double* c = a + size_t(k) * rows;
    const double norm = std::sqrt(bestNorm2);
    if (k == 0)
    {
      first = norm;
    }
    if (!(norm > 1e-9 * first) || k >= rows)
    {
      break;
    }
    ++rank;
    // Householder v = c[k..] + sign(c_k) |c| e_k, so that R_kk = -sign(c_k) |c|.
    const double alpha = c[k] >= 0 ? -norm : norm;
    c[k] -= alpha;
    double vv = 0;
    for (int i = k; i < rows; ++i)
    {
      vv += c[i] * c[i];
    }
    diagonal[k] = alpha;
    if (vv > 0)
    {
      for (int j = k + 1; j <= columns; ++j)
      {
        double* d = a + size_t(j) * rows;
        double dot = 0;
        for (int i = k; i < rows; ++i)
        {
          dot += c[i] * d[i];
        }
        const double f = 2 * dot / vv;
        for (int i = k; i < rows; ++i)
        {
          d[i] -= f * c[i];
        }
      }
    }
  }
  if (rank == columns)
  {
    // Back substitution R y = (Q^T b)[0..columns), then undo the column permutation.
    double y[6];
    for (int k = columns - 1; k >= 0; --k)
    {
      double sum = b[k];
      for (int j = k + 1; j < columns; ++j)
      {
        sum -= a[size_t(j) * rows + k] * y[j];
      }
      y[k] = sum / diagonal[k];
    }
    for (int k = 0; k < columns; ++k)
    {
      x[permutation[k]] = y[k];
    }
  }
  return rank;
}
} // namespace

QuadraticPatch QuadraticFitter::Fit(const double* uvh, int count)
{
  QuadraticPatch patch;
  if (count < 3)
  {
    return patch;
  }
  // Scale so that the points lie in the unit disc: the monomials are then O(1).
  double scale2 = 0;
  for (int i = 0; i < count; ++i)
  {
    scale2 = std::max(scale2, uvh[3 * i] * uvh[3 * i] + uvh[3 * i + 1] * uvh[3 * i + 1]);
  }
  const double scale = std::sqrt(scale2);
  if (!(scale > 0) || !std::isfinite(scale))
  {
    return patch;
  }
  const double inv = 1.0 / scale;
  this->Design.resize(size_t(count) * 6);
  this->Rhs.resize(count);
  for (int i = 0; i < count; ++i)
  {
    const double u = uvh[3 * i] * inv, v = uvh[3 * i + 1] * inv;
    double* row = &this->Design[size_t(i) * 6];
    // Column order: 1, u, v, u^2, uv, v^2 so that the first 3 columns are the plane.
    row[0] = 1;
    row[1] = u;
    row[2] = v;
    row[3] = u * u;
    row[4] = u * v;
    row[5] = v * v;
    this->Rhs[i] = uvh[3 * i + 2] * inv;
  }
  double x[6] = { 0, 0, 0, 0, 0, 0 };
  int degree = 0;
  if (count >= 6 && SolveLeastSquares(this->Design.data(), this->Rhs.data(), count, 6, x, this->Scratch) == 6)
  {
    degree = 6;
  }
  else if (SolveLeastSquares(this->Design.data(), this->Rhs.data(), count, 3, x, this->Scratch) == 3)
  {
    degree = 3;
    x[3] = x[4] = x[5] = 0;
  }
  else
  {
    return patch;
  }
  // Undo the scaling: f(u, v) = scale * g(u / scale, v / scale).
  patch.C[0] = x[0] * scale;
  patch.C[1] = x[1];
  patch.C[2] = x[2];
  patch.C[3] = x[3] * inv;
  patch.C[4] = x[4] * inv;
  patch.C[5] = x[5] * inv;
  patch.Degree = degree;
  return patch;
}

PatchCurvature EvaluateCurvature(const QuadraticPatch& p, double u, double v)
{
  const double fu = p.C[1] + 2 * p.C[3] * u + p.C[4] * v;
  const double fv = p.C[2] + p.C[4] * u + 2 * p.C[5] * v;
  const double fuu = 2 * p.C[3], fvv = 2 * p.C[5], fuv = p.C[4];
  const double w = 1 + fu * fu + fv * fv;
  PatchCurvature k;
  k.Gaussian = (fuu * fvv - fuv * fuv) / (w * w);
  k.Mean = ((1 + fv * fv) * fuu - 2 * fu * fv * fuv + (1 + fu * fu) * fvv) / (2 * w * std::sqrt(w));
  const double disc = std::sqrt(std::max(0.0, k.Mean * k.Mean - k.Gaussian));
  k.K1 = k.Mean + disc;
  k.K2 = k.Mean - disc;
  return k;
}
} // namespace slod
