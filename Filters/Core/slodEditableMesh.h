// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD shared core: a triangle mesh that collapse algorithms edit in place.
//
// Flat arrays only: each vertex owns a block [RefStart, RefStart+RefCount) of the global Refs
// array listing its triangles. A collapse appends one fresh block for the surviving vertex
// (the old blocks become garbage) and the array is compacted when garbage dominates, so no
// per-vertex heap allocation happens in the hot loop.
//
// Collapses merge two (edge collapse) or three (triangle collapse) vertices into one. CheckCollapse
// tells whether the result stays a manifold with the same topology (generalised link condition)
// and whether any triangle flips or degenerates; Collapse applies it and can fill a record that
// Undo (a vertex split) reverts exactly, which is what progressive meshes are made of.
#ifndef slodEditableMesh_h
#define slodEditableMesh_h

#include "slodCollapseRecords.h" // CollapseRecord, FlipRecord
#include "slodTriangleMesh.h"

#include <array>
#include <cstdint>
#include <vector>

namespace slod
{
// A caller's own test of the triangles that survive a collapse (CollapseOptions::Survivors), given
// their new area vectors (the set's corner moved to the point), which the geometric check computes
// anyway: a caller that tests them against data of its own (the collapse hierarchy's orientation
// against M0) need not walk the set's triangles and compute them again. Asked last, once every
// other test passed (the caller's data are often cold where the mesh's are warm), with the
// survivors in chunks; the checks may run concurrently (const, no state).
class SURFACELODFILTERS_EXPORT SurvivorTest
{
public:
  virtual ~SurvivorTest() = default;
  // Whether the n surviving triangles may take their new area vectors (unnormalised, as the flip
  // test computed them); false rejects the collapse with CollapseStatus::Flip.
  virtual bool Keeps(const Index* triangles, const Vec3* newAreaVectors, int n) const = 0;
};

struct SURFACELODFILTERS_EXPORT CollapseOptions
{
  // Reject when a surviving triangle's unit normal turns so that dot(old, new) < this.
  // 0 rejects turns beyond 90 degrees; -1 only degenerate triangles.
  double MinimumNormalDot = 0.0;
  // Reject when a surviving triangle gets a smaller minimum angle (radians) than this, unless
  // it already had a smaller one. 0 disables the check.
  double MinimumAngle = 0.0;
  // Allow changes of topology (genus, boundary loops, manifoldness). Off: never.
  bool AllowTopologyChange = false;
  // Optional per-vertex flags (1 = on a border) kept up to date by the caller, used instead of
  // IsBoundaryVertex (which is the most expensive part of the check). Without topology changes
  // a merged vertex is on the border exactly when one of its vertices was. The flags must be
  // exact: an interior flag also skips the isolated-vertex walk for that vertex.
  const unsigned char* BoundaryVertices = nullptr;
  // Optional per-vertex flags (1 = locked): a set holding a locked vertex is rejected. Filters lock
  // the input's non-manifold vertices (on an edge with more than two triangles, or joining several
  // fans): the link condition assumes one fan per vertex, and a collapse there could remove a
  // whole component or open the surface.
  const unsigned char* LockedVertices = nullptr;
  // Check the surviving triangles' geometry before the topology. The geometric test stops at the
  // first folding triangle while the link walk always visits the whole fan: far cheaper where most
  // candidates fold (a vertex of high valence moved away). A set failing both then reports the
  // geometric status, so callers that act on a geometric rejection (alternative placements) keep
  // it off.
  bool GeometryFirst = false;
  // Optional: the caller's test of the surviving triangles, after the others (see SurvivorTest).
  const SurvivorTest* Survivors = nullptr;
};

enum class CollapseStatus
{
  Ok,
  DeadVertex,      // a vertex of the set was already removed
  NonManifold,     // the result would have a non-manifold edge or vertex (link condition)
  BoundaryChange,  // a boundary loop would close, split or vanish
  TooSmall,        // the component would degenerate (fewer than 4 triangles around closed vertex)
  Flip,            // a triangle would turn over (normal deviation)
  Degenerate,      // a triangle would get zero area
  BadShape,        // a triangle would get a minimum angle below the limit
  IsolatedVertex,  // a vertex outside the set would lose all its triangles
  Locked           // a vertex of the set is locked (CollapseOptions::LockedVertices)
};
SURFACELODFILTERS_EXPORT const char* ToString(CollapseStatus status);

class SURFACELODFILTERS_EXPORT EditableMesh
{
public:
  EditableMesh() = default;
  explicit EditableMesh(const TriangleMesh& mesh) { this->Reset(mesh); }
  void Reset(const TriangleMesh& mesh);
  // Bytes held by the mesh's arrays (capacities, scratch included).
  size_t MemoryBytes() const;
  // Collapses append a new block of references per merged vertex and leave the old ones as
  // garbage, compacted when it reaches the live size. A factor f > 0 (before Reset) compacts
  // earlier, so that the reference array stays within f times its size at Reset (peak memory of a
  // shrinking mesh; a mesh that grows still gets an eighth of its size as room). 0: no limit.
  void SetReferenceRoomFactor(double factor) { this->RoomFactor = factor; }
  // The factor for a mesh that only shrinks (collapse loops): the peak of an unbounded array is
  // at the end of the collapses, about twice its start; this bound costs a few compactions more,
  // each a walk over the triangles, and moves no output (see CompactInOrder).
  static constexpr double ShrinkingMeshRoomFactor = 1.25;
  // On: the vertex -> triangle blocks are built in parallel (GroupByKey, the same blocks for any
  // thread count); off (default): serially, which cost less CPU and no more wall time at load
  // (session 28, TriangleCollapseOptions::ParallelStages).
  void SetParallelRebuild(bool parallel) { this->ParallelRebuild = parallel; }
  // On (default): the link tests of checks without a CheckScratch, IsBoundaryVertex and Neighbors
  // mark the vertices in a per-vertex array (12 bytes per vertex). Off (before Reset): they use one
  // small table of the mesh's instead, as the checks with a CheckScratch do (the same answers;
  // such checks must then not run concurrently).
  void SetVertexLinkMarks(bool on) { this->VertexLinkMarks = on; }

  Index NumberOfPoints() const { return static_cast<Index>(this->Points.size() / 3); }
  Index NumberOfTriangles() const { return static_cast<Index>(this->Triangles.size() / 3); }
  Index NumberOfLiveTriangles() const { return this->LiveTriangles; }
  Index NumberOfLiveVertices() const { return this->LiveVertices; }

  bool IsTriangleAlive(Index t) const { return this->TriangleAlive[t] != 0; }
  bool IsVertexAlive(Index v) const { return this->VertexAlive[v] != 0; }
  const Index* Triangle(Index t) const { return &this->Triangles[3 * size_t(t)]; }
  Vec3 Point(Index v) const
  {
    const double* p = &this->Points[3 * size_t(v)];
    return { p[0], p[1], p[2] };
  }
  void SetPoint(Index v, const Vec3& p);
  Vec3 TriangleNormal(Index t) const;
  double TriangleArea(Index t) const;

  // Live triangles around v. The span may include dead triangles, which are skipped by
  // ForEachTriangle; use it instead of reading the block directly.
  template <typename Functor>
  void ForEachTriangle(Index v, Functor&& f) const
  {
    const Index* refs = this->Refs.data() + this->RefStart[v];
    for (Index i = 0, n = this->RefCount[v]; i < n; ++i)
    {
      if (this->TriangleAlive[refs[i]])
      {
        f(refs[i]);
      }
    }
  }
  // Whether p holds for every live triangle around v, in ForEachTriangle's order; stops at the
  // first that fails.
  template <typename Predicate>
  bool AllTriangles(Index v, Predicate&& p) const
  {
    const Index* refs = this->Refs.data() + this->RefStart[v];
    for (Index i = 0, n = this->RefCount[v]; i < n; ++i)
    {
      if (this->TriangleAlive[refs[i]] && !p(refs[i]))
      {
        return false;
      }
    }
    return true;
  }
  // The triangles that survive merging the set (2 or 3 vertices): those around it that hold exactly
  // one of its vertices. f(t, corner) sees each once, with the corner (0..2) of that vertex.
  template <typename Functor>
  void ForEachSurvivingTriangle(const Index* vertices, int count, Functor&& f) const
  {
    for (int k = 0; k < count; ++k)
    {
      this->ForEachTriangle(vertices[k], [&](Index t) {
        const Index* tri = this->Triangle(t);
        int members = 0, corner = 0;
        for (int j = 0; j < 3; ++j)
        {
          for (int i = 0; i < count; ++i)
          {
            if (tri[j] == vertices[i])
            {
              ++members;
              corner = j;
            }
          }
        }
        if (members == 1)
        {
          f(t, corner);
        }
      });
    }
  }
  // Prefetch hints for callers that walk many scattered neighbourhoods at once (memory-latency
  // bound): a vertex's block bounds and point, then (once those arrived) its block of triangles.
  void PrefetchVertex(Index v) const
  {
    __builtin_prefetch(&this->RefStart[v]);
    __builtin_prefetch(&this->RefCount[v]);
    __builtin_prefetch(&this->Points[3 * size_t(v)]);
  }
  void PrefetchBlock(Index v) const { __builtin_prefetch(this->Refs.data() + this->RefStart[v]); }
  Index VertexDegree(Index v) const;
  // True when an edge at v has a single triangle.
  bool IsBoundaryVertex(Index v) const;
  // IsBoundaryVertex of every vertex (1 or 0), in one pass: each fan's link counts in a small array
  // on the stack rather than in the marks or the hashed table (a few fans of more than 32 triangles
  // take IsBoundaryVertex itself). Serial; the same answers.
  void BoundaryVertexFlags(std::vector<unsigned char>& flags) const;
  // Number of live triangles containing both u and v.
  int EdgeTriangleCount(Index u, Index v) const;
  // Distinct neighbours of v (appended to out after clearing it).
  void Neighbors(Index v, std::vector<Index>& out) const;

  // Would merging the vertices (2 or 3 of them, forming an edge or a triangle) into one vertex
  // at position p keep the mesh valid?
  CollapseStatus CheckCollapse(const Index* vertices, int count, const Vec3& p,
    const CollapseOptions& options = CollapseOptions()) const;
  // The same with the caller's scratch (which then holds the set's triangles, for Collapse): concurrent calls are safe for sets whose closed one-rings
  // (the vertices of the triangles around them) are pairwise disjoint, when no edit runs meanwhile
  // and ReserveEpochs(number of calls) was called before (sequentially).
  CollapseStatus CheckCollapse(const Index* vertices, int count, const Vec3& p, const CollapseOptions& options,
    std::vector<Index>& scratch) const;
  void ReserveEpochs(std::uint32_t checks) const;
  // A caller's whole scratch of a check: the set's triangles and the link test's marks, in a small
  // table of its own instead of the mesh's per-vertex marks. With it, concurrent checks are safe
  // whatever their neighbourhoods (speculative checks of overlapping candidates), as long as no
  // edit runs meanwhile and options.BoundaryVertices is given (IsBoundaryVertex uses the mesh's
  // marks); the answer is the other overloads'.
  class CheckScratch
  {
  public:
    std::vector<Index> Gathered;

  private:
    friend class EditableMesh;
    std::vector<Index> Keys; // open addressing by vertex id, InvalidIndex: free
    std::vector<std::array<Index, 2>> Links; // (In, Out) of Keys' vertex
  };
  CollapseStatus CheckCollapse(
    const Index* vertices, int count, const Vec3& p, const CollapseOptions& options, CheckScratch& scratch) const;
  // One set's collapse tried at several points (a caller ranking candidate points of one edge,
  // session 26): what CheckCollapse does that does not depend on the point (the dead and locked
  // vertices and the gathering of the set's triangles by PrepareTrial, their old normals as the
  // tests reach them, and the topology once a point passes the geometry) is done once per set.
  // CheckTrial(p) is then Ok
  // exactly when CheckCollapse(p) is (with no edit in between); a failing point may report
  // another geometric status than CheckCollapse, since the triangle that failed the last point is
  // tested first.
  class SetTrial
  {
  private:
    friend class EditableMesh;
    struct Surviving
    {
      Vec3 Corners[3];
      Vec3 OldNormal;
      Vec3 NewNormal; // at the point tested last (CollapseOptions::Survivors)
      double OldLength, OldMinimumAngle;
      Index Triangle;
      int Corner; // the set's vertex
    };
    std::vector<Index> Gathered;
    std::vector<Surviving> Survivors;
    Index Vertices[3] = { InvalidIndex, InvalidIndex, InvalidIndex };
    int Count = 0;
    CollapseStatus Fixed = CollapseStatus::Ok; // dead, locked, or the topology once known
    bool TopologyKnown = false;
    size_t FirstTested = 0;
    size_t NextGathered = 0; // the survivors are those of Gathered before it
  };
  void PrepareTrial(const Index* vertices, int count, const CollapseOptions& options, SetTrial& trial) const;
  // PrepareTrial for a set that CheckCollapse has just rejected with a geometric status (Flip,
  // Degenerate, BadShape) with options.GeometryFirst off and no edit since: that check gathered
  // its triangles (`gathered`, its scratch, swapped into the trial: swap them back with
  // ReturnGathered before the collapse) and passed its topology, so neither is done again
  // (session 44: the alternative placements of a folding optimum). The same answers as
  // PrepareTrial's.
  void PrepareTrialAfterGeometry(
    const Index* vertices, int count, const CollapseOptions& options, std::vector<Index>& gathered, SetTrial& trial) const;
  static void ReturnGathered(SetTrial& trial, std::vector<Index>& gathered) { trial.Gathered.swap(gathered); }
  // (link: as CheckCollapse's CheckScratch, or null for the mesh's marks)
  CollapseStatus CheckTrial(const Vec3& p, const CollapseOptions& options, SetTrial& trial, CheckScratch* link) const;
  // The set's topology (the link condition, borders, isolated vertices) tested now, before any
  // point, instead of after the first point that passes the geometry; returns the set's fixed
  // status (Ok, or a status no point can change). For a caller whose sets often fail it: their
  // points' geometric tests are then never run. CheckTrial answers Ok for the same points.
  CollapseStatus CheckTrialTopology(const CollapseOptions& options, SetTrial& trial, CheckScratch* link) const;

  // Merges the vertices into `kept` (one of them) placed at p. Triangles with two or more of the
  // vertices disappear. Call CheckCollapse first. The record, when given, allows Undo.
  void Collapse(const Index* vertices, int count, Index kept, const Vec3& p, CollapseRecord* record = nullptr);
  // The same with the set's triangles already gathered: the scratch of the CheckCollapse that
  // just accepted this set, with no edit since (collapse loops check then collapse at once; the
  // neighbourhood is not walked twice).
  void Collapse(const Index* vertices, int count, Index kept, const Vec3& p, const std::vector<Index>& gathered,
    CollapseRecord* record);

  // Batches of collapses whose sets have pairwise disjoint closed one-rings, performed
  // concurrently: ReserveRefs (sequential) makes room for the new blocks, CollapseIntoBlock
  // (concurrent; each writes only its set's vertices, the triangles around them and its own part
  // of the reserved room) merges one set whose gathered triangles include `surviving` survivors,
  // FinishCollapses (sequential) updates the counts and compacts. Returns the start of the room.
  Index ReserveRefs(Index count);
  // Returns the number of triangles removed; the record is filled (it is needed to requeue).
  Index CollapseIntoBlock(const Index* vertices, int count, Index kept, const Vec3& p,
    const std::vector<Index>& gathered, Index blockStart, CollapseRecord& record);
  void FinishCollapses(Index removedTriangles, Index removedVertices);
  // CollapseIntoBlock with its block appended at the end of the references (sequential): a batch
  // performed one collapse after the other gets the layout of ReserveRefs' room without knowing
  // its survivors beforehand. No compaction until FinishCollapses.
  Index CollapseAppending(const Index* vertices, int count, Index kept, const Vec3& p,
    const std::vector<Index>& gathered, CollapseRecord& record);
  // How many of the gathered triangles of the set (CheckCollapse's scratch) a collapse removes.
  Index RemovedBy(const Index* vertices, int count, const std::vector<Index>& gathered) const;
  // The live triangles touching the set, deduplicated, in the order Collapse gathers them (a
  // caller preparing CollapseIntoBlock; safe concurrently while no edit runs).
  void GatherSet(const Index* vertices, int count, std::vector<Index>& gathered) const
  {
    this->GatherTriangles(vertices, count, gathered);
  }
  // References that collapses can append before the next one compacts the blocks (a compaction
  // reorders them: a caller that wants the fans of Collapse one by one stops its concurrent batch
  // before that collapse).
  size_t ReferencesBeforeCompaction() const
  {
    return this->CompactThreshold > this->Refs.size() ? this->CompactThreshold - this->Refs.size() : 0;
  }

  // Reverts the most recent collapse whose record this is (records must be undone newest first).
  void Undo(const CollapseRecord& record);

  // Flips the interior manifold edge (x, y) when its two triangles have distinct opposite vertices
  // that are not yet joined by an edge; returns false (mesh unchanged) otherwise. Topological
  // checks only: the caller judges the geometry. Undo(FlipRecord) restores the triangles exactly.
  bool FlipEdge(Index x, Index y, FlipRecord* record = nullptr);
  void Undo(const FlipRecord& record);

  // Triangles removed (ids) and the live triangles around v, for algorithms that recompute costs.
  void TrianglesAround(const Index* vertices, int count, std::vector<Index>& out) const;

  // Adds a triangle over live vertices; returns its id.
  Index AddTriangle(Index a, Index b, Index c);
  // Removes a live triangle (vertices left without triangles stay alive but isolated).
  void RemoveTriangle(Index t);

  // The live part as a compact mesh; newToOld (optional) maps output vertices to this mesh's ids.
  void Extract(TriangleMesh& out, std::vector<Index>* newToOld = nullptr) const;

  // Debug aid: verifies the reference blocks against the triangles. Returns false on mismatch.
  bool CheckInvariants() const;

private:
  void AppendBlock(Index v, const std::vector<Index>& triangles);
  bool AddNextSurvivor(const CollapseOptions& options, SetTrial& trial) const;
  // The common part of the collapses: redirects the corners of the surviving triangles to kept
  // (each passed to keep(t)), marks the others and the merged vertices dead, moves kept to p;
  // returns the number of triangles removed. Touches no counter and no shared scratch.
  template <typename Keep>
  Index MergeSet(const Index* vertices, int count, Index kept, const Vec3& p, const std::vector<Index>& gathered,
    CollapseRecord* record, Keep&& keep);
  void CompactIfNeeded();
  // The two compactions: every block rebuilt from the live triangles (in triangle order), or, with
  // a room limit and between those rebuilds, in place in the blocks' own order (a limited mesh
  // compacts more often: its collapses then see their fans in the same order as without a limit).
  void RebuildBlocks();
  void CompactInOrder();
  void ReplaceInBlock(Index v, Index removed, Index added);
  // Collects the live triangles touching the set into gathered (deduplicated).
  void GatherTriangles(const Index* vertices, int count, std::vector<Index>& gathered) const;
  // The steps of CheckCollapse, over the gathered triangles.
  void PrefetchGathered(const std::vector<Index>& gathered) const;
  // The gathered triangles sorted by their role as the link test meets them (on the stack).
  struct SetScan;
  // (link: the link test's marks in a scratch of the caller's; null: the mesh's VertexLink)
  CollapseStatus CheckTopology(const Index* vertices, int count, const CollapseOptions& options,
    const std::vector<Index>& gathered, CheckScratch* link, SetScan& scan) const;
  struct MarkedLink; // CheckLink's marks in VertexLink
  struct TableLink;  // CheckLink's marks in a CheckScratch
  template <typename Link>
  CollapseStatus CheckLink(const Index* vertices, int count, bool anyBoundary, const std::vector<Index>& gathered,
    Link&& link, SetScan& scan) const;
  CollapseStatus CheckCollapseWith(const Index* vertices, int count, const Vec3& p, const CollapseOptions& options,
    std::vector<Index>& gathered, CheckScratch* link) const;
  bool BorderVerticesFormChain(const Index* vertices, int count, const bool* onBoundary) const;
  bool IsolatesVertex(const Index* vertices, int count, const CollapseOptions& options,
    const std::vector<Index>& gathered, const SetScan& scan) const;
  // Whether the vertex outside the set of triangle t (which holds two of the set) loses all its triangles.
  bool LosesAllTriangles(Index t, const Index* vertices, int count, const CollapseOptions& options) const;
  // The survivors' new area vectors kept by CheckGeometry for options.Survivors (on the stack).
  struct SurvivorNormals;
  CollapseStatus CheckGeometry(const Index* vertices, int count, const Vec3& p, const CollapseOptions& options,
    const std::vector<Index>& gathered, const SetScan* scan, SurvivorNormals& normals) const;
  CollapseStatus SurvivorGeometry(
    Index t, int corner, const Vec3& p, const CollapseOptions& options, SurvivorNormals& normals) const;
  CollapseStatus TestSurvivors(const Index* vertices, int count, const Vec3& p, const CollapseOptions& options,
    const std::vector<Index>& gathered, const SurvivorNormals& normals) const;
  CollapseStatus TestTrialSurvivors(const CollapseOptions& options, const SetTrial& trial) const;

  std::vector<double> Points;
  std::vector<Index> Triangles;
  std::vector<unsigned char> TriangleAlive, VertexAlive;
  std::vector<Index> RefStart, RefCount, Refs;
  Index LiveTriangles = 0, LiveVertices = 0;
  size_t CompactThreshold = 0;
  size_t RebuildThreshold = 0; // twice the references' size after the last RebuildBlocks
  size_t CompactedAway = 0;    // references CompactInOrder took out since then
  double RoomFactor = 0.0;     // SetReferenceRoomFactor
  size_t RoomLimit = 0;        // RoomFactor times the references' size at the first build
  bool ParallelRebuild = false; // SetParallelRebuild
  bool VertexLinkMarks = true;  // SetVertexLinkMarks

  // Scratch state reused across calls (mutable: checks are logically const).
  mutable std::vector<Index> Scratch, ScratchBlock;
  // Per vertex scratch of the link tests, side by side (one cache miss per vertex instead of three).
  struct LinkEntry
  {
    std::uint32_t Mark = 0;
    Index In = 0, Out = 0;
  };
  mutable std::vector<LinkEntry> VertexLink;
  mutable CheckScratch LinkTable; // instead of VertexLink when the marks are off
  // IsBoundaryVertex's and Neighbors' walks, with VertexLink's marks or the table's.
  template <typename Link>
  bool BorderThrough(Index v, Link&& link) const;
  template <typename Link>
  void NeighborsThrough(Index v, Link&& link, std::vector<Index>& out) const;
  mutable std::uint32_t Epoch = 0;
  std::uint32_t NextEpoch() const;
  void ClearMarks() const;
};
} // namespace slod

#endif
