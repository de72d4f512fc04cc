// SPDX-License-Identifier: BSD-3-Clause
#include "slodFilterContract.h"

#include <algorithm>
#include <cmath>

namespace slod
{
Index TargetTriangleCount(Index inputTriangles, long long targetNumberOfTriangles, double targetReduction, bool hasErrorBound)
{
  const bool hasCount = targetNumberOfTriangles > 0;
  const bool hasReduction = targetReduction > 0;
  if (!hasCount && !hasReduction)
  {
    if (hasErrorBound)
    {
      return 0;
    }
    targetReduction = DefaultTargetReduction;
  }
  long long count = hasCount ? targetNumberOfTriangles : 0;
  if (targetReduction > 0)
  {
    const double kept = (1.0 - std::min(targetReduction, 1.0)) * static_cast<double>(inputTriangles);
    // At least the requested fraction is removed, as vtkQuadricDecimation does (the small margin
    // absorbs the rounding of 1 - reduction, e.g. 0.9 -> 0.09999999999999998).
    count = std::max(count, static_cast<long long>(std::floor(kept + 1e-6)));
  }
  return static_cast<Index>(std::min<long long>(count, inputTriangles));
}
} // namespace slod
