// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD patch boundary merge (internal, not installed): triangulation of an SPBM level
// (Ho 1999, section 4.2.8) from the chain graph a merging run left in the working state.
// Stages of one pass:
//  1. BuildVertexSequences: every alive chain as its original vertices with keep flags;
//  2. MakeSegmentsUnique: a chain whose shortcut duplicates another edge keeps one more vertex;
//  3. AddOriginalPatches: patches frozen at the last fallback level as their input triangles;
//  4. TriangulatePatches: every other patch from its simplified boundary (ear clipping, or the
//     minimum-deviation triangulation for small non-planar boundaries);
//  4b. RefineFailedPatches: a patch that failed (not unmerged yet) keeps one more boundary vertex
//     and the patches on both sides of its chain are triangulated again (a few rounds), before
//     any patch goes to a fallback level;
//  5. FreezeFailedPatches: the patches that failed go one fallback level further for the next pass.
// Finish compacts the patch ids and writes the profile curves.
#ifndef slodSpbmTriangulation_h
#define slodSpbmTriangulation_h

#include "slodPolygonTriangulation.h"
#include "slodSpbmState.h"

#include <algorithm>
#include <functional>

namespace slod
{
class SpbmLevelGenerator::LevelTriangulation
{
public:
  LevelTriangulation(SpbmLevelGenerator& generator, const SpbmLevelParameters& parameters, State& s, SpbmLevel& level);
  // One pass over the current chain graph. False when aborted.
  bool RunPass(const std::vector<unsigned char>& frozen, const std::function<bool()>& abort);
  // Moves the failed patches one fallback level further; false when none failed. `unmerged`: some
  // patch went to the first level (unmerged), which only a new merging run can apply.
  bool FreezeFailedPatches(std::vector<unsigned char>& frozen, bool& unmerged);
  void Finish(const std::vector<unsigned char>& frozen);
  // What a pass leaves for the next one (LocalFallbackTriangulation): kept past the level's
  // generation, a further pass can go on from it (GenerateWithOriginalPatches, session 38).
  struct Memory
  {
    int PassesDone = 0;
    Index TouchStamp = 0;
    std::vector<unsigned char> Failed, RefinedVertex, PreviousFrozen, PreviousAlive;
    std::vector<Index> RefinedRoots, PreviousRoot, PreviousSize, PreviousKeptStart, PreviousKept, Touched, FirstCorner;
    std::vector<uint64_t> Context;
  };
  // Exchanges the pass memory with `memory`: keeps it after the last pass, or resumes from it
  // before the first (the level must then hold the kept pass's triangles, with root patch ids).
  void SwapMemory(Memory& memory);
  // Root patches that failed in the last pass.
  Index FailedPatches() const
  {
    return static_cast<Index>(failed.size() - size_t(std::count(failed.begin(), failed.end(), 0)));
  }

private:
  void BuildVertexSequences();
  // LocalFallbackTriangulation: which root patches keep their triangles of the pass before, and
  // those triangles with their diagonals back in the level; and what the next pass compares.
  void MarkChangedPatches(const std::vector<unsigned char>& frozen);
  void GroupPreviousTriangles();
  bool EdgeOutside(Index a, Index b, Index p);
  uint64_t EdgeContext(const Index* vertices, size_t n, Index p);
  bool ReusePreviousTriangles(Index p);
  // ReuseUntouchedPatches: the vertices around what may have changed since the pass before.
  void TouchPatch(Index x);
  void TouchChain(Index c);
  bool Untouched(Index p) const;
  void RememberPass(const std::vector<unsigned char>& frozen);
  void MakeSegmentsUnique();
  void AddOriginalPatches(const std::vector<unsigned char>& frozen);
  bool TriangulatePatches(const std::vector<unsigned char>& frozen, const std::function<bool()>& abort);
  bool BoundaryPolygon(Index p);
  bool TriangulateBoundary(Index p);
  bool RefineFailedPatches(const std::vector<unsigned char>& frozen);
  bool HiddenVertexFor(Index p, Index& c, Index& from, Index& at, Index& to);
  void RemoveTriangles(Index stamp);
  void PolygonPoints();
  bool MinimumDeviationApplies(const Vec3& normal) const;
  bool MinimumDeviationPolygon(Index p);
  void MeasureDiagonalsAhead(const std::vector<Index>& patches);
  void TriangulateAhead(const std::vector<Index>& patches);
  bool TakeTriangulationAhead(Index p, PolygonTriangulationResult& result);
  template<typename CostBitsOf>
  MinimumCostTriangulationOptions MinimumDeviationOptions(const Index* corner, CostBitsOf&& costBits) const;
  void TriangulateMinimumDeviation(const Vec3& normal, PolygonTriangulationResult& result);
  int NextEffectiveLevel(Index q, const std::vector<unsigned char>& frozen) const;
  Index CountChangeableFailures(const std::vector<unsigned char>& frozen);

  SpbmLevelGenerator& generator;
  const SpbmLevelParameters& parameters;
  State& s;
  SpbmLevel& level;
  const Patchification& P;
  const TriangleMesh& mesh;
  const Index np, nc;
  const Index* const base;           // first chain vertex: chain offsets into the generator's key arrays
  // Per patch of the pass: 0, or why it failed: its boundary or triangulation (RefineFailedPatches
  // may help), or a chain segment or original edge that another chain or patch already has (it
  // cannot: the patch waits for the fallback levels).
  enum : unsigned char
  {
    TriangulationFailure = 1,
    SegmentFailure = 2
  };
  std::vector<unsigned char> failed;
  std::vector<unsigned char> refinedVertex; // per mesh vertex: kept by RefineFailedPatches (all passes)
  std::vector<Index> affected;               // RefineFailedPatches: patches to triangulate again
  std::vector<unsigned char> changeable;     // CountChangeableFailures: per root, counted already
  // The pass before (LocalFallbackTriangulation): per patch of the patchification its root and
  // fallback level, per root whether it failed, per chain whether it was alive and its kept vertices
  // (previousKept[previousKeptStart[c], previousKeptStart[c + 1])), the triangles of each root
  // (previousTriangles, 3 per triangle, from previousFirst[p] to previousFirst[p + 1]); per root the
  // EdgeContext its triangles were made in (`context`, 0: none) and the first vertex of its polygon
  // then (`firstCorner`). `changed`: per root of this pass, 1 changed, 2 next to a changed one.
  int passesDone = 0; // RunPass calls that completed
  std::vector<Index> previousRoot, previousKeptStart, previousKept, previousFirst, previousTriangles;
  std::vector<unsigned char> previousFrozen, previousFailed, previousAlive, changed;
  std::vector<uint64_t> context;
  std::vector<Index> firstCorner;
  // ReuseUntouchedPatches: per mesh vertex the pass that touched it last (`touchStamp`); per root
  // whether its context must be compared (`checkContext`: it was triangulated by a refinement round
  // of the pass before, after the pass's other triangulations, or its place in the order moved);
  // per patch its boundary size in the pass before (the order); the roots the refinement rounds of
  // this pass and the pass before triangulated.
  std::vector<Index> touched, refinedRoots, previousRefinedRoots, previousSize;
  std::vector<unsigned char> checkContext;
  Index touchStamp = 0;
  // Larger polygons get no edge context (it is quadratic in their size): kept only untouched.
  static constexpr size_t MaximumReusedBoundary = 64;
  // TriangulateAhead (the first pass): per patch its job or InvalidIndex (`aheadJob`); per job its
  // patch (`aheadPatch`), polygon (aheadVertices[aheadStart[j], aheadStart[j + 1])), whether the triangulation failed,
  // and its n - 2 triangles (polygon indices) from aheadStart[j] - 2 j in `aheadTriangles`. The
  // diagonals the pass has inserted since (`passDiagonals`, their corners flagged in
  // `passDiagonalCorner`) decide whether a job still holds when its patch's turn comes.
  std::vector<Index> aheadJob, aheadStart, aheadVertices, aheadPatch;
  // Per job the pairs i < j of corners its triangulation asked about (bit i n + j of the words from
  // aheadAskedStart[j]).
  std::vector<size_t> aheadAskedStart;
  std::vector<uint64_t> aheadAsked;
  std::vector<std::array<Index, 3>> aheadTriangles;
  std::vector<unsigned char> aheadFailed, passDiagonalCorner;
  spbm::EdgeMap passDiagonals;
  // Scratch of one patch: its boundary polygon (original vertex ids), the patch across each
  // polygon corner's outgoing chain (or InvalidIndex), its oriented chains, the corner points.
  std::vector<Index> polygon, other, ring, order;
  std::vector<Vec3> points;
};

// The last pass of a level (SpbmLevelGenerator::KeepLastPass): its triangulation memory, fallback
// levels and triangles before Finish (root patch ids), for GenerateWithOriginalPatches.
struct SpbmLevelGenerator::KeptPass
{
  long long Generation = 0;
  SpbmLevelParameters Parameters;
  std::vector<unsigned char> Frozen;
  std::vector<Index> Triangles, TrianglePatch;
  LevelTriangulation::Memory Memory;
};
} // namespace slod

#endif
