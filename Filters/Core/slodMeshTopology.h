// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: static adjacency of a triangle mesh, built in linear time.
//
// Vertex -> triangles and edge -> triangles in compressed (offset + list) arrays, unique edges,
// boundary and non-manifold classification, ordered one-rings, components, boundary loops,
// Euler characteristic and genus. Read-only: editing algorithms use slod::EditableMesh.
#ifndef slodMeshTopology_h
#define slodMeshTopology_h

#include "slodTriangleMesh.h"

#include <cstdint>
#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT MeshStatistics
{
  Index Vertices = 0;           // vertices used by at least one triangle
  Index Triangles = 0;
  Index Edges = 0;
  Index BoundaryEdges = 0;      // edges with one triangle
  Index NonManifoldEdges = 0;   // edges with three or more triangles
  Index NonManifoldVertices = 0; // vertices whose triangles do not form one fan
  Index BoundaryLoops = 0;      // connected sets of boundary edges (see BorderComponentCount)
  Index Components = 0;         // edge-connected triangle components
  Index DegenerateTriangles = 0;
  Index InconsistentlyOrientedEdges = 0; // manifold edges used in the same direction by both triangles
  long long EulerCharacteristic = 0;     // V - E + F
  // (2C - chi - loops) / 2 for a manifold, orientable mesh; -1 when not defined.
  long long Genus = -1;
};

// The first triangle of an open fan around a vertex: from `start`, steps across the edge before
// the vertex (acrossPrevious(t) gives the neighbour there, or InvalidIndex at a border) until the
// border, at most `degree` steps (a closed fan returns to `start`).
template <class AcrossPrevious>
Index FanStart(Index start, Index degree, AcrossPrevious acrossPrevious)
{
  Index t = start;
  for (Index steps = 0; steps <= degree; ++steps)
  {
    const Index previous = acrossPrevious(t);
    if (previous == InvalidIndex)
    {
      break;
    }
    t = previous;
    if (t == start)
    {
      break;
    }
  }
  return t;
}

// Work of one MeshTopology::Update (counters for tests and traces).
struct MeshTopologyUpdateWork
{
  std::int64_t RemovedTriangles = 0;
  std::int64_t AppendedTriangles = 0;
  std::int64_t TouchedVertices = 0; // vertices of the removed and appended triangles
  // Vertex-triangle incidences of the touched vertices examined (before and after the edit): the
  // only indexing work; it is bounded by a multiple of the changed triangles where the valences
  // are bounded.
  std::int64_t LocalIncidences = 0;
  // Entries of the arrays carried over with their triangle and edge ids shifted (one sequential
  // pass each, no lookup by vertex or edge): what Build would index again.
  std::int64_t CarriedEntries = 0;
};

class SURFACELODFILTERS_EXPORT MeshTopology
{
public:
  MeshTopology() = default;
  explicit MeshTopology(const TriangleMesh& mesh) { this->Build(mesh); }
  void Build(const TriangleMesh& mesh);
  // The topology of `mesh` when it is the indexed mesh edited: its triangles without those flagged
  // in `removed` (one flag per indexed triangle; empty: none), in their order, then new triangles
  // appended. `previousTriangles` holds the indexed triangles (read only where removed). Only the
  // edges, valences and flags around the vertices of removed and appended triangles are computed
  // again; the rest of the arrays are carried over with their ids shifted. The result equals
  // Build(mesh) entry for entry (the same edge numbering and component labels), so callers see
  // no difference. Falls back to Build when the sizes do not fit. The components are computed
  // when first asked for (TriangleComponents / NumberOfComponents / Statistics).
  void Update(const std::vector<Index>& previousTriangles, const std::vector<unsigned char>& removed,
    const TriangleMesh& mesh);
  const MeshTopologyUpdateWork& LastUpdateWork() const { return this->UpdateWork; }
  // The same triangles in another TriangleMesh object (a copy): BoundaryLoops reads that one.
  void Rebind(const TriangleMesh& mesh) { this->Mesh = &mesh; }
  // The spare arrays an Update keeps for the next one (its earlier arrays), released.
  void ReleaseUpdateBuffers();

  Index NumberOfPoints() const { return this->NumPoints; }
  Index NumberOfTriangles() const { return this->NumTriangles; }
  Index NumberOfEdges() const { return static_cast<Index>(this->EdgeVertices.size() / 2); }

  // Triangles around vertex v (unordered).
  const Index* VertexTrianglesBegin(Index v) const { return this->VertexTriangles.data() + this->VertexOffsets[v]; }
  const Index* VertexTrianglesEnd(Index v) const { return this->VertexTriangles.data() + this->VertexOffsets[v + 1]; }
  Index VertexDegree(Index v) const { return this->VertexOffsets[v + 1] - this->VertexOffsets[v]; }

  // Edge e joins EdgeVertex(e,0) < EdgeVertex(e,1).
  Index EdgeVertex(Index e, int i) const { return this->EdgeVertices[2 * size_t(e) + i]; }
  // Edge k of triangle t joins its corners k and (k+1)%3.
  Index TriangleEdge(Index t, int k) const { return this->TriangleEdges[3 * size_t(t) + k]; }
  const Index* EdgeTrianglesBegin(Index e) const { return this->EdgeTriangles.data() + this->EdgeOffsets[e]; }
  const Index* EdgeTrianglesEnd(Index e) const { return this->EdgeTriangles.data() + this->EdgeOffsets[e + 1]; }
  Index EdgeTriangleCount(Index e) const { return this->EdgeOffsets[e + 1] - this->EdgeOffsets[e]; }
  bool IsBoundaryEdge(Index e) const { return this->EdgeTriangleCount(e) == 1; }
  bool IsNonManifoldEdge(Index e) const { return this->EdgeTriangleCount(e) > 2; }
  // The edge between u and v, or InvalidIndex.
  Index FindEdge(Index u, Index v) const;
  // The triangle across edge k of t when the edge is manifold, else InvalidIndex.
  Index EdgeNeighbor(Index t, int k) const;

  bool IsBoundaryVertex(Index v) const { return this->VertexFlags[v] & BoundaryFlag; }
  bool IsNonManifoldVertex(Index v) const { return this->VertexFlags[v] & NonManifoldFlag; }
  // Number of distinct neighbour vertices.
  Index Valence(Index v) const { return this->ValenceOf[v]; }

  // Ordered one-ring of a manifold vertex: neighbour vertices in counter-clockwise order, and
  // the triangle between ring[i] and ring[i+1]. For a boundary vertex the ring starts and ends
  // on the border (ring.size() == triangles.size() + 1); for an interior one it is closed
  // (ring.size() == triangles.size()). Returns false for non-manifold vertices.
  bool OrderedOneRing(const TriangleMesh& mesh, Index v, std::vector<Index>& ring,
    std::vector<Index>& triangles) const;

  // Edge-connected components of triangles: a label per triangle, InvalidIndex-free.
  const std::vector<Index>& TriangleComponents() const
  {
    this->EnsureComponents();
    return this->TriangleComponent;
  }
  Index NumberOfComponents() const
  {
    this->EnsureComponents();
    return this->ComponentCount;
  }

  // Closed loops of boundary edges, each a list of vertices in order (first not repeated).
  std::vector<std::vector<Index>> BoundaryLoops() const;
  // Connected sets of boundary edges: the loops counted so that the count does not depend on the
  // numbering. Where a vertex has four or more boundary edges (a pinch), BoundaryLoops() chains
  // whichever edge comes first, so its number of loops changes with the order of the vertices.
  Index BorderComponentCount() const;

  MeshStatistics Statistics(const TriangleMesh& mesh) const;

private:
  enum : unsigned char
  {
    BoundaryFlag = 1,
    NonManifoldFlag = 2
  };
  Index NumPoints = 0;
  Index NumTriangles = 0;
  std::vector<Index> VertexOffsets, VertexTriangles;
  std::vector<Index> EdgeVertices, TriangleEdges, EdgeOffsets, EdgeTriangles;
  std::vector<unsigned char> VertexFlags;
  std::vector<Index> ValenceOf;
  // Computed by Build, or on first use after an Update (not thread-safe then: ask once before
  // sharing the topology across threads).
  mutable std::vector<Index> TriangleComponent;
  mutable Index ComponentCount = 0;
  mutable bool ComponentsStale = false;
  const TriangleMesh* Mesh = nullptr;
  MeshTopologyUpdateWork UpdateWork;
  // Update's arrays: the previous ones, reused within their capacity by the next Update.
  struct Spare
  {
    std::vector<Index> VertexOffsets, VertexTriangles, EdgeVertices, TriangleEdges, EdgeOffsets, EdgeTriangles;
    std::vector<Index> NewId, EdgeShift, Stamp, StampEdge;
    std::vector<unsigned char> Touched;
  } Buffers;

  void EnsureComponents() const
  {
    if (this->ComponentsStale)
    {
      this->BuildComponents();
    }
  }
  void BuildComponents() const;
  // Update's stages (see Update).
  void UpdateVertexTriangles(const std::vector<Index>& previousTriangles, const std::vector<unsigned char>& removed,
    const TriangleMesh& mesh, const std::vector<Index>& touched);
  void UpdateEdges(const TriangleMesh& mesh);
  void UpdateVertexFlags(const TriangleMesh& mesh, const std::vector<Index>& touched);
};

// Mean absolute curvature of a surface: the sum over interior manifold edges of |dihedral angle| x
// length, over twice the area (the discrete integral of |mean curvature|: 1/R on a sphere of
// radius R). Noise counts fully, and so do creases unless `creaseAngle` (radians) is below pi:
// edges bent by more than it are left out. 0 for an empty or flat mesh.
SURFACELODFILTERS_EXPORT double MeanAbsoluteCurvature(
  const TriangleMesh& mesh, const MeshTopology& topology, double creaseAngle = Pi);

// Share of the interior manifold edges that are "noisy bends": their two triangles' normals are
// more than `angle` (radians) apart, yet each triangle's third vertex lies within `planeDistance`
// of the other triangle's plane. A patch growth's angle tests stop at such an edge although the
// surface stays within its plane distance there: the noise and voxel steps of a scan isosurface,
// at a scale far below the plane distance. On smooth meshes the bends are small and on CAD or
// coarse meshes the bent triangles are large, so next to none qualify. `mesh` consistently
// oriented (a flipped neighbour is a 180-degree bend). 0 for a mesh without interior edges.
SURFACELODFILTERS_EXPORT double NoisyBendShare(
  const TriangleMesh& mesh, const MeshTopology& topology, double angle, double planeDistance);

// Convenience: statistics of a mesh in one call.
SURFACELODFILTERS_EXPORT MeshStatistics ComputeMeshStatistics(const TriangleMesh& mesh);

// The fewest triangles a manifold with the border loops b and Euler characteristic chi of `s` can
// have when every loop keeps at least three edges on its own vertices: V >= 3b (4 when closed),
// and closing each loop of k edges with k - 2 triangles gives F >= 2 V - 2 chi - (number of border
// edges) >= 3b - 2 chi (8 - 2 chi when closed). A floor for topology-keeping simplifiers' targets.
inline long long TopologicalTriangleFloor(const MeshStatistics& s)
{
  const long long b = s.BoundaryLoops, chi = s.EulerCharacteristic;
  return b > 0 ? 3 * b - 2 * chi : 8 - 2 * chi;
}
} // namespace slod

#endif
