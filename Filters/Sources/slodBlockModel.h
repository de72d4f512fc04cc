// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD sources: closed "block" models for topology simplification (tests, examples,
// documentation pictures), in the spirit of Ho 1999's Disk, Box, Battery and Fixture models.
//
// A block model is a height field of columns over a grid of nx x ny cells: cell (i, j) is a
// column from z = 0 to z = heights[i + nx * j] (0: no column, e.g. a through-hole). Each cell is
// tessellated as `subdivisions` x `subdivisions` quads (two triangles each) on top and bottom;
// the vertical walls between columns of different heights are conforming (split at every height
// present at their corners). The surface is closed and consistently oriented (outward normals);
// it is a manifold as long as no two empty (or lower) cells touch only diagonally at a corner
// where the other two are full. Genus = number of enclosed empty regions (through-holes).
#ifndef slodBlockModel_h
#define slodBlockModel_h

#include "slodTriangleMesh.h"

#include <vector>

namespace slod
{
SURFACELODFILTERS_EXPORT TriangleMesh BlockModel(
  int nx, int ny, const std::vector<double>& heights, double cellSize = 1.0, int subdivisions = 1);

// A square plate of (2 * holesX + 1) x (2 * holesY + 1) cells with a one-cell square
// through-hole at every odd (i, j): genus holesX * holesY (like the dissertation's Fixture).
SURFACELODFILTERS_EXPORT TriangleMesh PlateWithHoles(
  int holesX, int holesY, double thickness = 0.5, int subdivisions = 2);

// A plate of tilesX x tilesY unit tiles, each with a round through-hole of the given radius
// (< 0.5) approximated by `segments` facets (a multiple of 4, >= 8): the top and bottom faces are
// rings between each tile's square border and its circle. Closed, genus tilesX * tilesY.
SURFACELODFILTERS_EXPORT TriangleMesh PlateWithRoundHoles(
  int tilesX, int tilesY, double radius = 0.25, int segments = 16, double thickness = 0.5);
} // namespace slod

#endif
