// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm Retile: the input's crease polylines, along which a re-tiling vertex that
// stands on a crease moves (issue 15: "crease vertices move only along their crease"). The
// repulsion and the repair project a moved vertex onto the closest point of the input surface; a
// vertex on a crease then leaves it as soon as its move has a part across the crease, and the
// output's edges stop following the crease. Here such a vertex slides along the crease's polyline
// instead (the input's own edges between two faces turning by more than the feature angle), by the
// part of its move along the crease, and stops at a corner (a vertex with one crease edge or
// three or more: a line's end or a junction).
#ifndef slodRetileCreases_h
#define slodRetileCreases_h

#include "slodMeshTopology.h"
#include "slodTriangleBVH.h"
#include "slodTriangleMesh.h"

#include <array>
#include <vector>

namespace slod
{
class SURFACELODFILTERS_EXPORT CreasePolylines
{
public:
  // The crease edges of `mesh`: edges with exactly two triangles (by `topology`, built on `mesh`)
  // whose ends are joined in `lineNeighbors` (DetectFeatureLines' lines). Border edges are left
  // out (borders have their own rules) and so are non-manifold ones (no side to slide along), so a
  // line through a non-manifold edge ends at its vertices.
  CreasePolylines(const TriangleMesh& mesh, const MeshTopology& topology,
    const std::vector<std::vector<Index>>& lineNeighbors);
  // The same with the mesh's topology built here (held only while the polylines are made).
  CreasePolylines(const TriangleMesh& mesh, const std::vector<std::vector<Index>>& lineNeighbors)
    : CreasePolylines(mesh, MeshTopology(mesh), lineNeighbors)
  {
  }

  Index NumberOfSegments() const { return static_cast<Index>(this->Segments.size()); }
  // The crease segment a point of triangle t lies on: a crease side of t whose distance from the
  // point is at most `tolerance` times the opposite corner's distance from it (a barycentric
  // coordinate) and which lies between its ends, else InvalidIndex.
  Index SegmentAt(Index t, const Vec3& point, double tolerance) const;
  // The point `position` of segment s moved along the crease by the part of `displacement` along
  // s (an arc length), through the crease's vertices where it goes on as one line, stopping at
  // its corners. The result's triangle is the one of its segment whose normal is closest to
  // `facing`; Distance2 is the squared distance from `position`.
  ClosestPointResult Slide(Index s, const Vec3& position, const Vec3& displacement, const Vec3& facing) const;

private:
  struct Segment
  {
    Index Ends[2];
    Index Triangles[2];
  };
  // The segment continuing s beyond its vertex v, or InvalidIndex at a line's end or a junction.
  Index Continuation(Index s, Index v) const;
  const TriangleMesh& Mesh;
  std::vector<Segment> Segments;
  // Per triangle: its slot in TriangleSides, or InvalidIndex when no side is a crease (an index
  // array: SegmentAt is asked at every move of the repair).
  std::vector<Index> TriangleSideSlot;
  std::vector<std::array<Index, 3>> TriangleSides; // segment of side k (opposite corner k)
  // Per vertex its crease segments, compressed: those of v are [VertexOffsets[v], VertexOffsets[v + 1]).
  std::vector<Index> VertexOffsets, VertexSegments;
};
} // namespace slod

#endif
