// SPDX-License-Identifier: BSD-3-Clause
// Side-by-side offscreen rendering of meshes into a PNG (for `surfacelod demo`).
#ifndef surfacelodRender_h
#define surfacelodRender_h

#include "vtkPolyData.h"

#include <string>
#include <vector>

namespace slodcli
{
struct Panel
{
  vtkPolyData* Mesh;
  std::string Title; // may contain newlines
};

// True when an X display is available for offscreen OpenGL rendering.
bool CanRender(std::string& reason);

// One viewport per panel, all seen from the same camera, flat shaded. Throws CliError on failure.
void RenderPanels(const std::vector<Panel>& panels, const std::string& pngPath, int panelSize = 480);
} // namespace slodcli

#endif
