// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm CollapseHierarchy: least-squares quadratic height fields and their curvature.
//
// A surface patch near a point is written as a graph z = f(u, v) over a local orthonormal frame
// (origin, U, V, N), with f = c00 + c10 u + c01 v + c20 u^2 + c11 uv + c02 v^2. The fit is solved
// on the design matrix itself with a column-pivoting Householder QR (no normal equations, no
// inversion) after scaling u, v, z to the unit disc, so it stays well conditioned for tiny or
// huge patches. Curvatures follow standard differential geometry of a graph (do Carmo):
//   E = 1 + fu^2, F = fu fv, G = 1 + fv^2, W = 1 + fu^2 + fv^2,
//   K = (fuu fvv - fuv^2) / W^2,
//   H = ((1 + fv^2) fuu - 2 fu fv fuv + (1 + fu^2) fvv) / (2 W^(3/2)),
//   k1,2 = H +- sqrt(H^2 - K),
// with fuu = 2 c20, fvv = 2 c02, fuv = c11 (the printed formulas of Gieng et al. 1997 have typos).
#ifndef slodQuadraticFit_h
#define slodQuadraticFit_h

#include "slodTriangleMesh.h"

#include <vector>

namespace slod
{
// Right-handed orthonormal frame; Normal is the height direction.
struct SURFACELODFILTERS_EXPORT LocalFrame
{
  Vec3 Origin{ 0, 0, 0 };
  Vec3 U{ 1, 0, 0 }, V{ 0, 1, 0 }, Normal{ 0, 0, 1 };

  // Frame at origin with the given normal; U follows `direction` projected on the plane (any
  // perpendicular direction when that is degenerate). Returns false for a zero normal.
  bool Set(const Vec3& origin, const Vec3& normal, const Vec3& direction);
  // Origin and unit normal only, U and V left as they are (for a caller that needs no plane
  // coordinates: two square roots fewer). Returns false for a zero normal, as Set does.
  bool SetNormal(const Vec3& origin, const Vec3& normal);
  // Local coordinates (u, v, height) of a point.
  Vec3 ToLocal(const Vec3& p) const
  {
    const Vec3 d = p - this->Origin;
    return { Dot(d, this->U), Dot(d, this->V), Dot(d, this->Normal) };
  }
  Vec3 ToWorld(double u, double v, double h) const
  {
    return this->Origin + u * this->U + v * this->V + h * this->Normal;
  }
};

struct SURFACELODFILTERS_EXPORT QuadraticPatch
{
  // f = C[0] + C[1] u + C[2] v + C[3] u^2 + C[4] uv + C[5] v^2 (c00, c10, c01, c20, c11, c02).
  double C[6] = { 0, 0, 0, 0, 0, 0 };
  // 6: full quadratic; 3: only a plane could be fitted; 0: nothing (f = 0).
  int Degree = 0;

  double Evaluate(double u, double v) const
  {
    return this->C[0] + this->C[1] * u + this->C[2] * v + this->C[3] * u * u + this->C[4] * u * v +
      this->C[5] * v * v;
  }
};

struct SURFACELODFILTERS_EXPORT PatchCurvature
{
  double Gaussian = 0, Mean = 0;
  double K1 = 0, K2 = 0; // principal curvatures, K1 >= K2 (sign follows the frame normal)
  double Absolute() const { return std::abs(this->K1) + std::abs(this->K2); }
};

// Least-squares fit to points given in local coordinates (u, v, height), 3 doubles each. Needs
// at least 6 points in general position for a quadratic; falls back to a plane (Degree 3) when
// the quadratic system is rank deficient, and to f = 0 when even that fails.
class SURFACELODFILTERS_EXPORT QuadraticFitter
{
public:
  QuadraticPatch Fit(const double* uvh, int count);
  QuadraticPatch Fit(const std::vector<double>& uvh) { return this->Fit(uvh.data(), int(uvh.size() / 3)); }

private:
  std::vector<double> Design, Rhs, Scratch; // reused between calls
};

SURFACELODFILTERS_EXPORT PatchCurvature EvaluateCurvature(const QuadraticPatch& patch, double u, double v);
} // namespace slod

#endif
