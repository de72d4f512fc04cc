// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: the one contract of every simplification filter (stop targets, progress
// and abort). Documentation/Architecture.md states it for users; the VTK side (progress to
// vtkAlgorithm, the abort warning, the target report) is in slodInputPreparation.h.
//
// Stop targets: TargetNumberOfTriangles (a count), TargetReduction (the fraction of the input's
// triangles to remove) and MaximumError (how far the surface may move), each unused at 0.
// Simplification stops at whichever set target is reached first: of a count and a reduction, the
// larger triangle count; before either when the next step would exceed the error bound. A count
// alone gives that count; with no target at all a filter reduces by DefaultTargetReduction, as
// vtkQuadricDecimation does.
//
// Progress: long stages call a ProgressFunction with the fraction done, in [0, 1]; it returns
// false to abort. An aborted filter returns an empty output with a warning.
#ifndef slodFilterContract_h
#define slodFilterContract_h

#include "slodTriangleMesh.h"

#include <functional>

namespace slod
{
using ProgressFunction = std::function<bool(double)>;

constexpr double DefaultTargetReduction = 0.9;

// The triangle count at which simplifying `inputTriangles` stops, from the filter's settings
// (count <= 0 and reduction <= 0 are unused): the larger of the count target and the reduction's
// count (nearest whole number), never above the input; DefaultTargetReduction's count when neither
// is set and there is no error bound; 0 (no count target) when only an error bound is set.
SURFACELODFILTERS_EXPORT Index TargetTriangleCount(
  Index inputTriangles, long long targetNumberOfTriangles, double targetReduction, bool hasErrorBound);
} // namespace slod

#endif
