// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm Retile: feature lines for re-tiling (creases, corners and borders).
//
// Turk's re-tiling spreads vertices evenly and has no notion of a sharp edge: a uniform vertex
// set cuts creases (fandisk: Hausdorff 116 times vtkQuadricDecimation's). Here the input's
// feature lines are found (edges whose dihedral angle exceeds a feature angle, and border edges),
// split into chains at corners (vertices with one or three or more feature edges, or where a
// line turns by more than the feature angle), and each chain is sampled at the spacing the
// repulsion gives the free points: evenly by arc length between its corners, which is where 1-D
// repulsion along the line settles. The samples are snapped to the chain's own vertices, so they
// lie exactly on the crease; they and the corners are kept as fixed vertices, and the other
// vertices of a line may only be removed by collapsing along it (the line's edges then join the
// kept vertices).
#ifndef slodRetileFeatures_h
#define slodRetileFeatures_h

#include "slodTriangleMesh.h"

#include <vector>

namespace slod
{
// A point on the feature edge from input vertex From to To: From + T (To - From), with the
// edge's triangles (two on a crease, the second InvalidIndex on a border), found with the
// topology the lines were detected with.
struct LinePoint
{
  Index From, To;
  double T;
  Index Faces[2] = { InvalidIndex, InvalidIndex };
};

struct SURFACELODFILTERS_EXPORT FeatureLines
{
  // Per input vertex: the vertices it is joined to by feature edges (empty: not on a line).
  std::vector<std::vector<Index>> LineNeighbors;
  // Input vertices kept as output vertices: corners first, then the samples along the chains.
  std::vector<Index> Kept;
  // Session 44: points along the chains where two consecutive kept vertices are 1.5 spacings or
  // more apart (the samples snap to the chain's vertices, so an input edge longer than the spacing
  // leaves a gap), at the spacing. Not output vertices: they push the free points off the line
  // in the repulsion, which otherwise holds free points on a convex crease between the samples,
  // where the removal joins the samples over them and leaves caps.
  std::vector<LinePoint> GapPoints;
  Index Corners = 0;
  Index FeatureEdges = 0;
  Index DroppedChains = 0; // dangling chains and loops shorter than the spacing (noise)
  Index PruningRounds = 0; // rounds that dropped chains (each drop can make other chains noise)
  Index WalkSteps = 0;     // feature edges walked in all (the detection's work)
};

class MeshTopology;

// Feature lines of `mesh` at `featureAngle` degrees, sampled at `spacing` (the free points'
// expected nearest-neighbour distance). Border edges are feature edges too. The mesh's topology is
// built here and held while the lines are found (it gives the gap points their faces).
SURFACELODFILTERS_EXPORT void DetectFeatureLines(
  const TriangleMesh& mesh, double featureAngle, double spacing, FeatureLines& features);
// The same with `topology` built on `mesh` by the caller, who uses it again (CreasePolylines).
SURFACELODFILTERS_EXPORT void DetectFeatureLines(const TriangleMesh& mesh, const MeshTopology& topology,
  double featureAngle, double spacing, FeatureLines& features);

// Expected nearest-neighbour distance of `count` evenly spread points on `area` (a hexagonal
// packing: each point owns sqrt(3)/2 d^2).
SURFACELODFILTERS_EXPORT double EvenSpacing(double area, Index count);
} // namespace slod

#endif
