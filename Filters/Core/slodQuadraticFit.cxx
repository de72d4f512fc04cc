#include "slodQuadraticFit.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace slod
{
bool LocalFrame::Set(const Vec3& origin, const Vec3& normal, const Vec3& direction)
{
  this->Origin = origin;
  const Vec3 n = Normalized(normal);
  if (Dot(n, n) == 0)
  {
    return false;
  }
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
  this->Normal = n;
  this->U = Normalized(u);
  this->V = Cross(n, this->U);
  return true;
}

namespace
{
// Solves min |A x - b| for the first `columns` columns of the row-major n x 6 design matrix.
// Returns the rank found by the column-pivoting QR.
int SolveLeastSquares(const double* design, const double* rhs, int rows, int columns, double* x)
{
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::Map<const Matrix, 0, Eigen::OuterStride<>> full(design, rows, columns, Eigen::OuterStride<>(6));
  Eigen::Map<const Eigen::VectorXd> b(rhs, rows);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(full);
  // Monomials are scaled to the unit disc, so a relative threshold well above round-off
  // separates genuinely degenerate point sets (collinear, too few) from thin ones.
  qr.setThreshold(1e-9);
  const int rank = static_cast<int>(qr.rank());
  if (rank == columns)
  {
    Eigen::Map<Eigen::VectorXd>(x, columns) = qr.solve(b);
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
  if (count >= 6 && SolveLeastSquares(this->Design.data(), this->Rhs.data(), count, 6, x) == 6)
  {
    degree = 6;
  }
  else if (SolveLeastSquares(this->Design.data(), this->Rhs.data(), count, 3, x) == 3)
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
