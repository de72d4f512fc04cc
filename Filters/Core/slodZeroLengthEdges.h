// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: merging the two ends of edges of length zero.
//
// Marching cubes puts two or three vertices at one grid point where the iso-value equals a
// sample; they are joined by edges of length zero and zero-area triangles. The input preparation
// keeps such coincident points apart (slodInputPreparation.h: merging coincident points in general
// can make non-manifold vertices or join components), but where the two points are the ends of an
// edge, merging them is an edge collapse that moves nothing: the surface keeps its shape, and with
// the link condition its topology. Filters that keep input vertices (vtkRetile's retained
// vertices) would otherwise output tiles of coincident vertices.
#ifndef slodZeroLengthEdges_h
#define slodZeroLengthEdges_h

#include "slodTriangleMesh.h"

#include <functional>
#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT ZeroLengthEdgeMaps
{
  // Per vertex of the mesh given (read, then replaced by the merged mesh's):
  std::vector<Index>* VertexToInputPoint = nullptr;    // required
  std::vector<unsigned char>* NonManifoldFlags = nullptr; // 1: kept apart (the link condition assumes one fan)
  std::vector<unsigned char>* BorderFlags = nullptr;    // a merged vertex is on a border when one end was
  // Per triangle of the mesh given (optional), replaced by the merged mesh's:
  std::vector<Index>* TriangleToInputCell = nullptr;
  // Optional: false keeps two input points apart (e.g. other point data: an attribute seam).
  std::function<bool(Index inputPointA, Index inputPointB)> MayMerge;
};

// Collapses every edge whose ends coincide exactly onto its smaller end, where the collapse keeps
// the mesh's topology (link condition, border loops; non-manifold vertices never merge). The
// triangles on the edge go; the vertices keep their order, as do the other triangles. Returns the
// number of vertices merged away (0: the mesh and maps are untouched).
SURFACELODFILTERS_EXPORT Index CollapseZeroLengthEdges(TriangleMesh& mesh, const ZeroLengthEdgeMaps& maps);
} // namespace slod

#endif
