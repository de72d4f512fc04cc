// SPDX-License-Identifier: BSD-3-Clause
// Baseline-image regression testing shared by every filter's image test.
#ifndef SurfaceLODRenderTestSupport_h
#define SurfaceLODRenderTestSupport_h

#include "vtkPolyData.h"

#include <string>

namespace slodtest
{
// Renders the mesh offscreen (fixed size, camera, flat shading with edges, colour by the active
// cell scalars when present) and compares with Testing/Data/Baseline/<baselineName>.png via
// vtkTesting. When the baseline is missing the image is written to the test output directory and
// the comparison fails (copy it into the baseline folder after checking it by eye).
// Returns true when the images match within `threshold`.
bool RenderAndCompare(vtkPolyData* mesh, const std::string& baselineName, double threshold = 0.05,
  const double viewDirection[3] = nullptr);
} // namespace slodtest

#endif
