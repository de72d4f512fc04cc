// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm CollapseHierarchy: stencils of triangles and the triangle-collapse rules of
// Gieng, Hamann, Joy, Schussman, Trotts, "Smooth hierarchical surface triangulations" (1997).
//
// The stencil S_T of a triangle T is the set of the other triangles sharing a vertex with T.
//  - connected: the stencil triangles are connected through shared edges;
//  - cyclic: three stencil triangles are pairwise edge neighbours (a vertex of valence three);
//  - complete: connected, acyclic, and the boundary polygon of S_T u {T} is one simple closed
//    polygon that contains no vertex of T (so T is interior and its neighbourhood is a disc).
// T is collapsible when (1) its stencil is complete, (2) no opposite vertex of its three edge
// neighbours has valence four (collapsing would leave a valence-three vertex, i.e. a new cycle),
// and (3) the boundary polygon projected onto T's plane is star-shaped with respect to the point
// the triangle collapses to (then the fan of new triangles cannot fold).
#ifndef slodTriangleStencil_h
#define slodTriangleStencil_h

#include "slodEditableMesh.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace slod
{
struct SURFACELODFILTERS_EXPORT TriangleStencil
{
  Index Triangle = InvalidIndex;
  Index Vertices[3] = { InvalidIndex, InvalidIndex, InvalidIndex };
  std::vector<Index> Triangles;        // stencil triangles (T excluded)
  std::vector<Index> Neighbors;        // the stencil triangles sharing an edge with T
  std::vector<Index> OppositeVertices; // vertex of each neighbour not in T
  std::vector<Index> BoundaryPolygon;  // ordered like T (counter-clockwise), when it is one loop
  bool Connected = false;
  bool Cyclic = false;
  bool Complete = false;
  void Clear();
};

enum class CollapsibleStatus
{
  Ok,
  DeadTriangle,
  IncompleteStencil, // disconnected, on the mesh boundary, or the polygon touches T
  CyclicStencil,
  CreatesCycle,      // an opposite vertex has valence four
  NotStarShaped,
  MeshCheckFailed    // EditableMesh::CheckCollapse refused (link condition, flip...)
};
SURFACELODFILTERS_EXPORT const char* ToString(CollapsibleStatus status);

// Relaxations of the paper's rules (both off = the paper).
struct SURFACELODFILTERS_EXPORT CollapsibleOptions
{
  // Skip rule (2): allow collapses that leave a valence-three vertex.
  bool AllowNewCycles = false;
  // Rule (3) also passes when the polygon is star-shaped in the plane of the stencil's mean
  // normal (T's own plane can be tilted against its neighbourhood on coarse meshes).
  bool StencilPlaneFallback = false;
};

// Builds the stencil of live triangle t and classifies it. Scratch vectors are reused.
class SURFACELODFILTERS_EXPORT StencilBuilder
{
public:
  void Build(const EditableMesh& mesh, Index t, TriangleStencil& stencil);
  // Build in two steps: Gather fills Triangles, Neighbors and OppositeVertices only (Connected,
  // Cyclic, Complete stay false); Classify (after Gather) the rest, as Build.
  void Gather(const EditableMesh& mesh, Index t, TriangleStencil& stencil) const;
  void Classify(const EditableMesh& mesh, TriangleStencil& stencil);
  // After Gather: true when CheckCollapsible cannot answer Ok whatever Classify finds and whatever
  // the point (not three edge neighbours, or rule (2) under these options), so that the
  // classification can be skipped.
  static bool FailsBeforeClassifying(
    const EditableMesh& mesh, const TriangleStencil& stencil, const CollapsibleOptions& options = CollapsibleOptions());

  // Rules (1)-(3) for the stencil (built by Build) and collapse point p; `normal` is T's plane
  // normal (unit). When meshOptions is given, EditableMesh::CheckCollapse is also consulted (with
  // the caller's scratch when given: then concurrent builders may check overlapping stencils).
  CollapsibleStatus CheckCollapsible(const EditableMesh& mesh, const TriangleStencil& stencil,
    const Vec3& p, const Vec3& normal, const CollapseOptions* meshOptions = nullptr,
    const CollapsibleOptions& options = CollapsibleOptions(), EditableMesh::CheckScratch* check = nullptr);

private:
  // Build's stages over the region S u {T}.
  void MatchRegionEdges(const EditableMesh& mesh, const TriangleStencil& stencil);
  void MatchEdgePair(size_t ei, size_t ej);
  void ClassifyAdjacency(TriangleStencil& stencil) const;
  bool TraceBoundaryPolygon(TriangleStencil& stencil, bool& touchesT);

  // A small hash table from 64-bit keys to int values, emptied in O(1) by a new stamp (a region has
  // at most 195 directed edges: sorting them was a third of the stencil's cost).
  class KeyTable
  {
  public:
    void Reset(size_t count); // room for count keys
    // The value slot of key; inserted tells whether the key was new (its value is then -1).
    std::int32_t& Find(std::uint64_t key, bool& inserted);

  private:
    struct Entry
    {
      std::uint64_t Key;
      std::int32_t Value;
      std::uint32_t Stamp; // the entry is used when it holds the table's stamp
    };
    std::vector<Entry> Entries;
    std::uint32_t Stamp = 0;
    unsigned Shift = 64;
  };

  std::vector<Index> EdgeFrom, EdgeTo;
  std::vector<unsigned char> EdgeBoundary;
  std::vector<unsigned long long> Adjacency;
  std::vector<std::int32_t> NextOnEdge; // the next directed edge of the region on the same undirected edge
  KeyTable Edges;    // undirected edge -> its last directed edge of the region
  KeyTable Outgoing; // boundary vertex -> its boundary edge leaving it
};
} // namespace slod

#endif
