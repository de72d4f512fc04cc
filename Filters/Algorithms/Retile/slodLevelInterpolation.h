// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm Retile: interpolation between two nested levels of detail (Turk 1992, section 6).
//
// Input: a high-detail and a low-detail triangle mesh of the same surface where every low-detail
// vertex is also a high-detail vertex (same position), as vtkRetile's nested levels are.
// Output: the high-detail mesh cut into polygon fragments along the low-detail edges, each
// fragment vertex with two positions: its high-detail position and its "flattened" position on
// the low-detail surface. At t = 0 the fragments lie exactly on the low-detail triangles and
// together cover them; at t = 1 they are exactly the high-detail triangles.
//
// Stages of InterpolateLevels, the path for meshes without removal records (departure from the
// paper: Turk tracks fragments through the vertex removals, as slodFragmentTracking.h does with
// the records of RetileNested's levels; here the correspondence is computed afterwards from the
// two meshes alone):
//  1. FlattenVertices: a vertex shared with the low level maps to itself; a high-only vertex maps to
//     its closest point on the low-detail surface (TriangleBVH), snapped onto an edge or vertex when
//     it lies on one.
//  2. Edge paths: the image of each high-detail edge on the low-detail surface is the shortest
//     strip of low triangles between its ends' images (Dijkstra over triangle centroids), crossed on
//     each shared edge at the point closest to the straight segment between the ends; each low edge
//     crossed gives a crossing point (one vertex shared by the two high triangles of that edge),
//     placed on the high edge at the same fraction of the path length.
//  3. SplitTriangles: in each high triangle the low edges crossing it are chords joining two
//     crossings of the same low edge (or a crossing and the low vertex at a corner); since every low
//     vertex is a high vertex, no low vertex lies inside a high triangle and the chords cut the
//     triangle into convex fragments, each inside one low triangle. Fragments are fan-triangulated.
#ifndef slodLevelInterpolation_h
#define slodLevelInterpolation_h

#include "slodFilterContract.h"
#include "slodTriangleMesh.h"

#include <functional>
#include <string>
#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT LevelInterpolation
{
  bool Valid = false;
  bool Aborted = false; // the progress function asked to stop (Valid false, Error empty)
  std::string Error;

  // Output vertices: the high-detail vertices first (same order), then the low vertices inserted
  // into the high level (see InsertedVertices), then the edge crossings, then interior vertices.
  std::vector<double> LowPositions;  // 3 per vertex: flattened on the low-detail surface
  std::vector<double> HighPositions; // 3 per vertex: on the high-detail surface
  std::vector<Index> Triangles;      // 3 per output triangle, oriented as the high triangle
  std::vector<Index> HighTriangle;   // per output triangle: the high-detail triangle it is part of
  std::vector<Index> LowTriangle;    // per output triangle: the low-detail triangle it lies on at t = 0 (or InvalidIndex)
  std::vector<Index> Fragment;       // per output triangle: its polygon fragment

  Index SharedVertices = 0;        // high vertices that are low vertices
  Index InsertedVertices = 0;      // low vertices missing from the high level, inserted into it
  Index FlattenedVertices = 0;     // high-only vertices flattened onto the low surface
  Index Crossings = 0;             // new vertices where high edges cross low edges
  Index InteriorVertices = 0;      // low vertices that fall inside a high triangle's image (fold), added inside it
  Index Fragments = 0;             // polygon fragments
  Index UntracedEdges = 0;         // high edges whose path could not be walked (should be 0)
  Index InconsistentFragments = 0; // fragments not inside a single low triangle (should be 0)

  Index NumberOfPoints() const { return static_cast<Index>(this->LowPositions.size() / 3); }
  Index NumberOfTriangles() const { return static_cast<Index>(this->Triangles.size() / 3); }
  // The mesh at t in [0,1]: (1 - t) * low + t * high per vertex.
  void Evaluate(double t, TriangleMesh& mesh) const;
};

// Triangulates one fragment (a ring of result's vertices, convex on both shapes but with collinear
// vertices: crossings on its sides) into result by ear clipping: the best-shaped ear first
// (smallest angle on both shapes), never a flat or reflex one (normal: the high triangle's) nor one
// whose diagonal `allowed(previous, next)` (vertex ids) refuses, which would leave a T-junction.
SURFACELODFILTERS_EXPORT void ClipFragmentEars(std::vector<Index> ring, const Vec3& normal,
  const std::function<bool(Index, Index)>& allowed, Index highTriangle, Index lowTriangle, Index fragment,
  LevelInterpolation& result);

// Builds the fragments. Fails (Valid = false, Error set) when a mesh is empty or when more than half
// the low-detail vertices are not vertices of the high-detail mesh (the levels are not nested); the
// few missing ones are inserted into the high level at their closest point on it. Reports progress
// while it cuts the triangles; stops (Aborted, Valid false) when progress returns false.
SURFACELODFILTERS_EXPORT void InterpolateLevels(const TriangleMesh& high, const TriangleMesh& low, LevelInterpolation& result,
  const ProgressFunction& progress = nullptr);
} // namespace slod

#endif
