// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: the one model of collapse records, shared by every algorithm that keeps
// its collapses to split them again (progressive meshes of the triangle collapse, the vertex
// splits and levels of the collapse hierarchy).
//
// CollapseRecord and FlipRecord describe one edit of an EditableMesh, enough to revert it exactly
// (EditableMesh::Undo). CollapseRecords keeps a whole sequence of them in flat arrays (no heap
// block per collapse: millions of collapses on a marching-cubes surface) and replays it on an
// EditableMesh in either direction: Undo (a vertex split, newest first) and Redo (the collapse
// again, oldest first). Edge flips made between collapses are stamped with the number of
// collapses before them, so that undoing collapse k first undoes the flips made after it.
#ifndef slodCollapseRecords_h
#define slodCollapseRecords_h

#include "slodTriangleMesh.h"

#include <array>
#include <utility>
#include <vector>

namespace slod
{
class EditableMesh;

// What a collapse changed, enough to undo it exactly (a vertex split).
struct SURFACELODFILTERS_EXPORT CollapseRecord
{
  std::array<Index, 3> Vertices{ InvalidIndex, InvalidIndex, InvalidIndex }; // merged set
  int VertexCount = 0;
  Index Kept = InvalidIndex;               // the vertex that remains
  std::array<Vec3, 3> OldPositions;        // of Vertices
  Vec3 NewPosition{ 0, 0, 0 };
  std::vector<Index> RemovedTriangles;     // triangle ids (their vertices are unchanged in storage)
  std::vector<Index> ChangedTriangles;     // surviving triangles whose corner was redirected
  std::vector<unsigned char> ChangedCorner; // corner (0..2) of each changed triangle
  std::vector<Index> ChangedFrom;          // the vertex that corner had before
  void Clear();
};

// An edge flip (swap): triangles T0 = (X, Y, Q) and T1 = (Y, X, Z) around edge XY become
// T0 = (X, Z, Q) and T1 = (Z, Y, Q) in place (same triangle ids), replacing XY by QZ.
struct SURFACELODFILTERS_EXPORT FlipRecord
{
  Index Triangles[2] = { InvalidIndex, InvalidIndex };
  Index X = InvalidIndex, Y = InvalidIndex, Q = InvalidIndex, Z = InvalidIndex;
};

// A sequence of collapses (and flips), one entry per collapse in each per-collapse array.
// Vertex and triangle ids are those of the mesh the records are replayed on (Append maps them).
struct SURFACELODFILTERS_EXPORT CollapseRecords
{
  // What is stored besides the topology. Positions: without them the owner knows the positions
  // (the hierarchy's global vertices) and fills them into the record after Get. Removed triangle
  // vertices: needed to rebuild the removed triangles from the coarse mesh alone (a progressive
  // mesh read back from a table); an owner that keeps the whole mesh does not need them.
  bool StorePositions = true;
  bool StoreRemovedTriangleVertices = true;
  // Also the vertices around the kept vertex after each collapse (the surrounding vertices of Pan,
  // Zhou and Shi, the neighbours a vertex split reconnects): for reference, not needed to replay.
  bool StoreSurrounding = false;

  std::vector<Index> Vertices;               // 3 per collapse: the kept vertex first; -1 third for an edge collapse
  std::vector<double> OldPositions;          // 9 per collapse (StorePositions): of Vertices, zeros for -1
  std::vector<double> NewPositions;          // 3 per collapse (StorePositions): the kept vertex's new place
  std::vector<Index> RemovedOffsets{ 0 };    // collapses + 1 offsets into RemovedTriangles
  std::vector<Index> RemovedTriangles;       // ids of the triangles each collapse removed
  std::vector<Index> RemovedTriangleVertices; // 3 per removed triangle (StoreRemovedTriangleVertices)
  std::vector<Index> ChangedOffsets{ 0 };    // collapses + 1 offsets into the Changed arrays
  std::vector<Index> ChangedTriangles;       // surviving triangles whose corner was redirected
  // That corner (0..2, bits 0-1) and the vertex it had before, as its position in the collapse's
  // Vertices (bits 2-3): always one of the merged vertices, so one byte instead of the corner's
  // byte and a 4-byte id (ChangedCorner, ChangedFrom).
  std::vector<unsigned char> ChangedCodes;
  std::vector<Index> SurroundingOffsets{ 0 }; // collapses + 1 offsets into Surrounding (StoreSurrounding)
  std::vector<Index> Surrounding;
  std::vector<FlipRecord> Flips;             // in order
  std::vector<Index> FlipStamps;             // collapses made before each flip (non-decreasing)

  Index NumberOfCollapses() const { return static_cast<Index>(this->RemovedOffsets.size() - 1); }
  Index NumberOfFlips() const { return static_cast<Index>(this->Flips.size()); }
  Index Kept(Index k) const { return this->Vertices[3 * size_t(k)]; }
  int VertexCount(Index k) const { return this->Vertices[3 * size_t(k) + 2] == InvalidIndex ? 2 : 3; }
  Index RemovedCount(Index k) const { return this->RemovedOffsets[k + 1] - this->RemovedOffsets[k]; }
  // Changed entry c (of collapse k: ChangedOffsets[k] <= c < ChangedOffsets[k + 1]).
  int ChangedCorner(size_t c) const { return this->ChangedCodes[c] & 3; }
  Index ChangedFrom(Index k, size_t c) const { return this->Vertices[3 * size_t(k) + (this->ChangedCodes[c] >> 2)]; }
  // Appends a changed entry to the last collapse (whose vertices are stored); false when `from` is
  // not one of them (a reader of foreign records).
  bool AppendChanged(Index triangle, int corner, Index from);

  // Empties the records (keeping what they store).
  void Clear();
  // Room for `collapses` collapses removing `removed` triangles and redirecting `changed` corners.
  void Reserve(size_t collapses, size_t removed, size_t changed);
  // Appends the record of the collapse just made on `mesh` (which still holds the removed
  // triangles' vertices). vertexId / triangleId, when given, map the mesh's ids to the ids stored;
  // surrounding (mesh ids) is stored when StoreSurrounding.
  void Append(const CollapseRecord& record, const EditableMesh& mesh, const Index* vertexId = nullptr,
    const Index* triangleId = nullptr, const std::vector<Index>* surrounding = nullptr);
  // The same for collapses made concurrently: AppendRoom (sequential) adds n collapses removing
  // removed[i] and redirecting changed[i] triangles (their offsets), then SetAt(k, ...) writes
  // collapse k of them, concurrently for different k. Without id maps and StoreSurrounding.
  void AppendRoom(size_t n, const Index* removed, const Index* changed);
  void SetAt(Index k, const CollapseRecord& record, const EditableMesh& mesh);
  // Appends a flip made after the collapses recorded so far.
  void AppendFlip(const FlipRecord& flip);
  // The flips made after collapse k and before collapse k + 1: indices [first, second) of Flips.
  std::pair<Index, Index> FlipsAfter(Index k) const;
  // Record k as an EditableMesh record (positions left as they are unless StorePositions).
  void Get(Index k, CollapseRecord& record) const;

  // Replays on a mesh whose ids are the stored ones. Undo reverts collapse k, after undoing the
  // flips made after it, on a mesh where every later collapse is undone; Redo makes collapse k and
  // the flips after it again, on a mesh where every earlier one is made. `record` is scratch.
  // Both need StorePositions; an owner that fills the positions itself calls UndoFlipsAfter and
  // EditableMesh::Undo (or Collapse and RedoFlipsAfter) with the record from Get.
  void Undo(Index k, EditableMesh& mesh, CollapseRecord& record) const;
  void Redo(Index k, EditableMesh& mesh, CollapseRecord& record) const;
  void UndoFlipsAfter(Index k, EditableMesh& mesh) const;
  void RedoFlipsAfter(Index k, EditableMesh& mesh) const;

  size_t MemoryBytes() const;

private:
  // Collapse k's entries (its room made), ids mapped by vertex(v) and triangle(t).
  template <typename VertexId, typename TriangleId>
  void Write(Index k, const CollapseRecord& record, const EditableMesh& mesh, VertexId&& vertex, TriangleId&& triangle);
  static int PositionOf(Index v, const CollapseRecord& record, const int* order);
};
} // namespace slod

#endif
