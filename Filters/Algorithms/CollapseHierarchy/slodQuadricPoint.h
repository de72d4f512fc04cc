// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm CollapseHierarchy: the point of least quadric error nearest to a given point.
//
// A quadric's matrix A (symmetric, positive semi-definite) is often nearly singular: on a flat part
// only the normal direction is constrained, along a crease two. The point x = c - A+ (A c + b)
// uses the pseudo-inverse A+ that drops the eigen-directions whose eigenvalue is at most
// `relativeTolerance` times the largest: x moves from c along the constrained directions only.
// Solved without a general eigen decomposition: the largest eigenvalue by Newton's method on the
// characteristic cubic (from above, so it converges monotonically), the other two from the
// remaining quadratic, then one eigenvector by a cross product (the dominant one when one direction
// is kept, the dropped one when two are) and a 3x3 cofactor solve. No trigonometry, no iteration
// over the matrix; the same point as the eigen decomposition up to rounding.
#ifndef slodQuadricPoint_h
#define slodQuadricPoint_h

#include "slodQuadric.h"

namespace slod
{
// Eigenvalues of a symmetric 3x3 matrix with real non-negative spectrum (largest first); the
// smaller two lose relative accuracy when far below the largest (enough to rank them against it).
SURFACELODFILTERS_EXPORT void QuadricEigenvalues(const Quadric& q, double (&lambda)[3]);

// The least-error point nearest to center (see above). A zero or non-finite matrix gives center.
SURFACELODFILTERS_EXPORT Vec3 QuadricPointNear(const Quadric& q, const Vec3& center, double relativeTolerance = 1e-3);
} // namespace slod

#endif
