// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm GreedyCuts, stage 1 of chapter 3 (Ho 1999, section 3.4.1, "Part 2"): the
// surface cut into few, large terrain-like patches, each with a height direction over which it is
// a height field, so greedy cuts can triangulate it in the plane orthogonal to that direction.
//
// Stages (named, over explicit data):
//  1. growth: patches grow breadth-first from a free triangle, keeping a disk (a triangle joins
//     through one edge when its third vertex is new to the patch, or through two edges). While the
//     patch's three "angle ranges" (the spread of the angle between its triangle normals and each
//     axis) stay within 90 degrees every triangle joins; when a triangle would widen one beyond
//     90 degrees, the patch's normal class is fixed: one of the 26 directions (i,j,k) in
//     {-1,0,1}^3 \ {0}, the closest to the patch's mean normal among those with which every
//     triangle so far agrees in sign (component by component, where the class is not 0). From
//     then on a triangle joins only when it agrees with the class too. Agreeing in sign on the
//     class's non-zero components means a positive dot product with the class direction: the
//     patch is a height field over the plane orthogonal to it (its height direction);
//  2. merging small patches: a patch with fewer than MinimumPatchTriangles triangles is merged
//     into a neighbour with which it shares exactly one boundary path (so the union is a disk),
//     when that path is not sharp (no dihedral angle across it above SharpAngle) and the union is
//     still a height field over one direction (its mean normal or the neighbour's direction);
//  3. labels: patches numbered in order of their first triangle, with their height directions.
#ifndef slodTerrainPatchification_h
#define slodTerrainPatchification_h

#include "slodFilterContract.h"
#include "slodMeshTopology.h"
#include "slodTriangleMesh.h"

#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT TerrainPatchificationParameters
{
  // Smallest dot product of a triangle's unit normal with its patch's height direction: keeps
  // triangles seen nearly edge-on out (their projection would be a sliver).
  double MinimumHeightCosine = 0.1;
  Index MinimumPatchTriangles = 32; // smaller patches are merged (stage 2) when possible
  double SharpAngle = 60.0;         // degrees: a boundary with a larger dihedral angle is kept
};

struct SURFACELODFILTERS_EXPORT TerrainPatches
{
  std::vector<Index> TrianglePatch; // patch of each triangle
  std::vector<Vec3> HeightDirection; // per patch (unit)
  Index NumberOfPatches = 0;
  Index GrownPatches = 0; // before merging
};

// Builds the terrain-like patches of a manifold mesh (topology built from it). Returns false when
// aborted through progress.
SURFACELODFILTERS_EXPORT bool BuildTerrainPatches(const TriangleMesh& mesh, const MeshTopology& topology,
  const TerrainPatchificationParameters& parameters, TerrainPatches& patches,
  const ProgressFunction& progress = nullptr);
} // namespace slod

#endif
