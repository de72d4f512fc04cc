// SPDX-License-Identifier: BSD-3-Clause
// Topological noise removal (Guskov & Wood 2001): the mesh that handles are cut from.
//
// A triangle mesh with its vertex -> triangles adjacency, edited by a few local cuts: the static
// adjacency of the input (slod::MeshTopology) plus an overlay for the vertices a cut touched. A
// cut along a closed loop of edges duplicates the loop's vertices (the triangles on the loop's
// right side move to the copies) and fills the two holes with disks over the loop's vertices, so
// no new point positions appear and every vertex keeps the data of the input vertex it copies.
// Reads (ForEachTriangle, Triangle, Point) are thread-safe between cuts.
#ifndef slodCuttableMesh_h
#define slodCuttableMesh_h

#include "slodMeshTopology.h"
#include "slodTriangleMesh.h"

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace slod
{
enum class LoopSeparation
{
  NonSeparating, // cutting keeps the mesh connected: a handle or tunnel
  Separating,    // cutting splits off a piece (a pocket, a neck): not a handle
  Undetermined,  // the search budget ran out before either answer
  Invalid        // the loop is not a simple loop of interior manifold edges
};

class SURFACELODFILTERS_EXPORT CuttableMesh
{
public:
  // Takes the mesh; vertices on a border or non-manifold are locked (never on a cut loop).
  explicit CuttableMesh(TriangleMesh mesh);
  // The same with the topology of an equal mesh already built (it is then not built again; only
  // its vertex adjacency and classification are read, never its BoundaryLoops).
  CuttableMesh(TriangleMesh mesh, MeshTopology topology);

  Index NumberOfPoints() const { return this->Mesh.NumberOfPoints(); }
  Index NumberOfTriangles() const { return this->Mesh.NumberOfTriangles(); }
  const Index* Triangle(Index t) const { return this->Mesh.Triangle(t); }
  Vec3 Point(Index v) const { return this->Mesh.Point(v); }
  bool IsLocked(Index v) const { return v < this->BaseVertices && this->Locked[v]; }
  Index NumberOfLockedVertices() const { return this->LockedCount; }

  template <typename Functor>
  void ForEachTriangle(Index v, Functor&& f) const
  {
    if (v < this->BaseVertices && !this->HasOverlay[v])
    {
      for (const Index* t = this->Base.VertexTrianglesBegin(v); t != this->Base.VertexTrianglesEnd(v); ++t)
      {
        f(*t);
      }
      return;
    }
    for (Index t : this->Overlay.at(v))
    {
      f(t);
    }
  }

  // The triangles other than `t` that hold both a and b (one across a manifold edge).
  template <typename Functor>
  void ForEachTriangleAcross(Index t, Index a, Index b, Functor&& f) const
  {
    this->ForEachTriangle(a, [&](Index u) {
      if (u != t && HasVertex(this->Triangle(u), b))
      {
        f(u);
      }
    });
  }
  bool HasEdge(Index a, Index b) const;

  // Is the closed loop (vertices in order, first not repeated) a handle's loop? Searches both
  // sides of the cut at once, triangle by triangle, at most `budget` triangles per side.
  LoopSeparation TestSeparation(const std::vector<Index>& loop, Index budget) const;

  // Cuts along the loop and fills both holes. Returns false (mesh unchanged) when the loop's
  // vertices do not split into two sides. `changed` gets the loop's vertices and their copies.
  bool CutAndFill(const std::vector<Index>& loop, std::vector<Index>& changed);

  // The edited mesh and, per vertex and triangle, the input vertex / triangle it comes from
  // (a fill triangle: the input triangle next to its loop).
  const TriangleMesh& Result() const { return this->Mesh; }
  const std::vector<Index>& VertexSources() const { return this->VertexSource; }
  const std::vector<Index>& TriangleSources() const { return this->TriangleSource; }
  // Fills made as a fan around a new centre vertex (ear clipping found no disk).
  Index NumberOfCentreFans() const { return this->CentreFans; }

private:
  static bool HasVertex(const Index* tri, Index v) { return tri[0] == v || tri[1] == v || tri[2] == v; }
  void LockAndIndex();
  struct LoopSides;
  bool FindLoopSides(const std::vector<Index>& loop, LoopSides& sides) const;
  bool RightFan(const std::vector<Index>& loop, size_t i, Index start, Index avoid, std::vector<Index>& fan) const;
  std::vector<Index>& EditableTriangles(Index v);
  bool PlanFill(const std::vector<Index>& polygon, std::vector<std::array<Index, 3>>& fill) const;
  std::vector<std::array<Index, 3>> CentreFan(std::vector<Index>& polygon);
  void AddFill(const std::vector<Index>& polygon, const std::vector<std::array<Index, 3>>& fill, Index source);

  TriangleMesh Mesh;
  MeshTopology Base;
  Index BaseVertices = 0;
  std::vector<unsigned char> Locked, HasOverlay;
  Index LockedCount = 0;
  std::unordered_map<Index, std::vector<Index>> Overlay;
  std::vector<Index> VertexSource, TriangleSource;
  Index CentreFans = 0;
  // Scratch of the separation search: the side (1 left, 2 right) of each triangle reached, valid
  // where VisitStamp equals the current search's stamp.
  mutable std::vector<std::uint32_t> VisitStamp;
  mutable std::vector<unsigned char> VisitSide;
  mutable std::uint32_t Stamp = 0;
};
} // namespace slod

#endif
