// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: a non-manifold triangle mesh made manifold by splitting, never by opening.
//
// Around a non-manifold edge (three or more triangles) the triangles are paired in angular order
// so that each pair encloses the solid between them (the triangles' normals point away from the
// wedge between them): the sheets that touch along the edge are separated, as two solids that
// touch are. Then every vertex whose triangles form several fans (through manifold edges and the
// pairs) gets one copy per further fan. No border edge appears: each paired edge keeps exactly two
// triangles, and the positions of the copies equal their originals'. An edge whose triangles
// cannot be paired so (an odd count, or orientations that do not alternate around it) is left
// non-manifold, and so are its vertices.
#ifndef slodManifoldSplit_h
#define slodManifoldSplit_h

#include "slodMeshTopology.h"
#include "slodTriangleMesh.h"

#include <vector>

namespace slod
{
struct ManifoldSplitResult
{
  TriangleMesh Mesh;                 // the input's triangles, in the same order, on split vertices
  std::vector<Index> VertexSource;   // per output vertex: the input vertex it copies
  Index EdgesSplit = 0;              // non-manifold edges resolved into pairs
  Index EdgesLeft = 0;               // non-manifold edges left as they are
  Index VerticesSplit = 0;           // input vertices that got at least one copy
};

// Splits `mesh` (with its topology `topology`, built from it). Linear in the mesh's size, plus a
// sort of the triangles around each non-manifold edge.
SURFACELODFILTERS_EXPORT ManifoldSplitResult SplitNonManifold(
  const TriangleMesh& mesh, const MeshTopology& topology);
} // namespace slod

#endif
