// SPDX-License-Identifier: BSD-3-Clause
#include "slodSpbmTriangulation.h"

#include "slodPolygonTriangulation.h"
#include "slodSpbmFinalCollapses.h"
#include "slodStageClock.h"
#include "slodTriangleBVH.h"

#include "vtkLogger.h"
#include "vtkSMPTools.h"

#include <cstring>

namespace slod
{
using namespace spbm;

SpbmLevelGenerator::LevelTriangulation::LevelTriangulation(
  SpbmLevelGenerator& generator_, const SpbmLevelParameters& parameters_, State& state, SpbmLevel& level_)
  : generator(generator_)
  , parameters(parameters_)
  , s(state)
  , level(level_)
  , P(*generator_.Patches)
  , mesh(*generator_.Mesh)
  , np(P.NumberOfPatches())
  , nc(P.NumberOfChains())
  , base(nc > 0 ? P.ChainVerticesBegin(0) : nullptr)
{
}

bool SpbmLevelGenerator::LevelTriangulation::RunPass(
  const std::vector<unsigned char>& frozen, const std::function<bool()>& abort)
{
  const bool local = passesDone > 0 && parameters.LocalFallbackTriangulation;
  previousFailed.swap(failed);
  failed.assign(size_t(np), 0);
  previousRefinedRoots.swap(refinedRoots);
  refinedRoots.clear();
  // Where a pass's time goes, stage by stage (TRACE): on the large scans the late passes change a
  // few patches and their cost is these sweeps over the whole level.
  slod::StageClock clock("[spbm] triangulation pass");
  this->BuildVertexSequences();
  if (!refinedVertex.empty())
  {
    // Vertices kept by the rounds of the passes before: a replay leaves most patches as they were,
    // and the same patches would fail again.
    for (size_t i = 0; i < s.SeqVertices.size(); ++i)
    {
      s.SeqKeep[i] = s.SeqKeep[i] || refinedVertex[s.SeqVertices[i]];
    }
  }
  clock.Lap("vertex sequences");
  this->MakeSegmentsUnique();
  clock.Lap("unique segments");
  if (local)
  {
    this->GroupPreviousTriangles(); // before AddOriginalPatches clears the level
    this->MarkChangedPatches(frozen);
    clock.Lap("changed patches");
  }
  this->AddOriginalPatches(frozen);
  clock.Lap("original patches");
  const size_t originalTriangles = level.TrianglePatch.size();
  const long long retriangulatedBefore = level.RetriangulatedPatches, trianglesBefore = level.RetriangulatedTriangles;
  if (!this->TriangulatePatches(frozen, abort))
  {
    return false;
  }
  clock.Lap("patches");
  if (local)
  {
    // What a late pass changed against what it walked (TRACE, issue 10): the triangles kept from
    // the pass before were copied in the whole pass's order.
    const long long again = level.RetriangulatedTriangles - trianglesBefore;
    vtkLogF(TRACE, "[spbm] triangulation pass work: %lld triangles kept from the pass before, %lld patches (%lld triangles) triangulated again, %zu original triangles",
      static_cast<long long>(level.TrianglePatch.size() - originalTriangles) - again,
      static_cast<long long>(level.RetriangulatedPatches - retriangulatedBefore), again, originalTriangles);
  }
  for (int round = 0; round < parameters.FailedPatchRefinementRounds; ++round)
  {
    const Index before = level.RefinedInPass;
    const bool refined = this->RefineFailedPatches(frozen);
    vtkLogF(TRACE, "[spbm] refinement round %d: %d vertices kept, %d patches still failed", round,
      int(level.RefinedInPass - before), int(this->FailedPatches()));
    if (!refined)
    {
      break;
    }
  }
  clock.Lap("refinement rounds");
  this->RememberPass(frozen);
  clock.Lap("remember");
  ++passesDone;
  return true;
}

void SpbmLevelGenerator::LevelTriangulation::SwapMemory(Memory& memory)
{
  std::swap(passesDone, memory.PassesDone);
  std::swap(touchStamp, memory.TouchStamp);
  context.swap(memory.Context);
  for (const auto& flags : { std::make_pair(&failed, &memory.Failed), std::make_pair(&refinedVertex, &memory.RefinedVertex),
         std::make_pair(&previousFrozen, &memory.PreviousFrozen), std::make_pair(&previousAlive, &memory.PreviousAlive) })
  {
    flags.first->swap(*flags.second);
  }
  for (const auto& ids : { std::make_pair(&refinedRoots, &memory.RefinedRoots),
         std::make_pair(&previousRoot, &memory.PreviousRoot), std::make_pair(&previousSize, &memory.PreviousSize),
         std::make_pair(&previousKeptStart, &memory.PreviousKeptStart),
         std::make_pair(&previousKept, &memory.PreviousKept), std::make_pair(&touched, &memory.Touched),
         std::make_pair(&firstCorner, &memory.FirstCorner) })
  {
    ids.first->swap(*ids.second);
  }
}

// Root patches whose triangles of the pass before cannot be kept (`changed`): those whose set of
// original patches changed (a replay unmerged or merged them differently), that failed or are
// kept as original triangles, and both sides of every chain that died, came alive or keeps other
// vertices (a new tolerance, a refinement, a collapse or join that moved an end). Then the
// patches next to them: the double-ear rule reads the normal of the patch across, and their
// common diagonals were decided by the order of the patches.
void SpbmLevelGenerator::LevelTriangulation::MarkChangedPatches(const std::vector<unsigned char>& frozen)
{
  changed.assign(size_t(np), 0);
  touched.resize(size_t(mesh.NumberOfPoints()), 0);
  ++touchStamp;
  for (Index q = 0; q < np; ++q)
  {
    const Index root = s.Find(q), before = previousRoot[q];
    // An original patch that was one in the pass before too has the same triangles, edges and
    // normal (refused segments of others fail those others): it changes nothing around it.
    const bool keptOriginal = parameters.KeptOriginalPatchesUnchanged && root == before &&
      frozen[q] == OriginalLevel && previousFrozen[q] == OriginalLevel;
    if (root != before || frozen[q] != previousFrozen[q] ||
      (!keptOriginal && (frozen[q] == OriginalLevel || previousFailed[before])))
    {
      changed[root] = 1;
      changed[before] = 1; // when it is still a root, it lost q
    }
  }
  for (Index c = 0; c < nc; ++c)
  {
    bool same = bool(s.Alive[c]) == bool(previousAlive[c]);
    Index k = previousKeptStart[c];
    for (Index i = s.SeqOffsets[c]; same && i < s.SeqOffsets[c + 1]; ++i)
    {
      if (s.SeqKeep[i])
      {
        same = k < previousKeptStart[c + 1] && previousKept[k++] == s.SeqVertices[i];
      }
    }
    if (!same || k != previousKeptStart[c + 1])
    {
      this->TouchChain(c);
      changed[s.Find(s.L[c])] = 1;
      if (s.R[c] != InvalidIndex)
      {
        changed[s.Find(s.R[c])] = 1;
      }
    }
  }
  // The patches across their chains (2: changed only as a neighbour, not spread further): the
  // double-ear rule reads the normal of the patch across.
  for (Index c = 0; c < nc; ++c)
  {
    if (!s.Alive[c] || s.R[c] == InvalidIndex)
    {
      continue;
    }
    const Index l = s.Find(s.L[c]), r = s.Find(s.R[c]);
    if (changed[l] == 1 && !changed[r])
    {
      changed[r] = 2;
    }
    else if (changed[r] == 1 && !changed[l])
    {
      changed[l] = 2;
    }
  }
  checkContext.assign(size_t(np), 0);
  for (const Index q : previousRefinedRoots)
  {
    checkContext[q] = 1;
    this->TouchPatch(q);
  }
  for (Index q = 0; q < np; ++q)
  {
    if (s.Parent[q] == q && previousRoot[q] == q && s.Size[q] != previousSize[q])
    {
      // Another place in the passes' order (smallest boundary first): other patches' edges are
      // made before or after its triangulation than in the pass before.
      checkContext[q] = 1;
      this->TouchPatch(q);
    }
  }
  for (Index q = 0; q < np; ++q)
  {
    if (changed[q])
    {
      this->TouchPatch(q);
    }
  }
}

// Touches the vertices of x's triangles of the pass before and, for a root, the kept vertices of
// its chains now.
void SpbmLevelGenerator::LevelTriangulation::TouchPatch(Index x)
{
  if (size_t(x) + 1 < previousFirst.size())
  {
    for (Index i = 3 * previousFirst[x]; i < 3 * previousFirst[x + 1]; ++i)
    {
      touched[previousTriangles[i]] = touchStamp;
    }
  }
  if (s.Parent[x] != x)
  {
    return;
  }
  for (Index slot = s.PatchHead[x]; slot != InvalidIndex; slot = s.PatchSlotNext[slot])
  {
    if (s.Alive[slot / 2])
    {
      this->TouchChain(slot / 2);
    }
  }
}

// Touches the kept vertices of chain c now and in the pass before (its segments then and now).
void SpbmLevelGenerator::LevelTriangulation::TouchChain(Index c)
{
  for (Index i = s.SeqOffsets[c]; i < s.SeqOffsets[c + 1]; ++i)
  {
    if (s.SeqKeep[i])
    {
      touched[s.SeqVertices[i]] = touchStamp;
    }
  }
  for (Index k = previousKeptStart[c]; k < previousKeptStart[c + 1]; ++k)
  {
    touched[previousKept[k]] = touchStamp;
  }
}

// Whether no vertex of p's polygon (the scratch `polygon`) was touched in this pass.
bool SpbmLevelGenerator::LevelTriangulation::Untouched(Index p) const
{
  return parameters.ReuseUntouchedPatches && !checkContext[p] &&
    std::none_of(polygon.begin(), polygon.end(), [&](Index v) { return touched[v] == touchStamp; });
}

// The pass before's triangles grouped by patch (previousFirst[p] .. previousFirst[p + 1]).
void SpbmLevelGenerator::LevelTriangulation::GroupPreviousTriangles()
{
  previousFirst.assign(size_t(np) + 1, 0);
  for (const Index p : level.TrianglePatch)
  {
    ++previousFirst[size_t(p) + 1];
  }
  for (Index p = 0; p < np; ++p)
  {
    previousFirst[p + 1] += previousFirst[p];
  }
  previousTriangles.resize(level.Triangles.size());
  std::vector<Index> next(previousFirst.begin(), previousFirst.end() - 1);
  for (size_t t = 0; t < level.TrianglePatch.size(); ++t)
  {
    const Index at = next[level.TrianglePatch[t]]++;
    std::copy_n(level.Triangles.begin() + std::ptrdiff_t(3 * t), 3, previousTriangles.begin() + 3 * std::ptrdiff_t(at));
  }
}

// Whether a-b is an edge of the level other than a segment of p's own chains (a diagonal of
// another patch, -1, or a chain segment of another patch).
bool SpbmLevelGenerator::LevelTriangulation::EdgeOutside(Index a, Index b, Index p)
{
  Index x;
  return s.Edges.Find(a, b, x) &&
    !(x >= 0 && (s.Find(s.L[x]) == p || (s.R[x] != InvalidIndex && s.Find(s.R[x]) == p)));
}

// The edges already in the level between the vertices of patch p other than its own chains'
// segments: what the triangulation of p is told (a diagonal that is an edge is refused). An
// order-independent hash of them, 0 for a polygon too large to check (never reused).
uint64_t SpbmLevelGenerator::LevelTriangulation::EdgeContext(const Index* vertices, size_t n, Index p)
{
  if (n > MaximumReusedBoundary)
  {
    return 0;
  }
  uint64_t sum = 0x9E3779B97F4A7C15ull;
  for (size_t i = 0; i < n; ++i)
  {
    for (size_t j = i + 1; j < n; ++j)
    {
      if (this->EdgeOutside(vertices[i], vertices[j], p))
      {
        uint64_t key = (uint64_t(uint32_t(std::min(vertices[i], vertices[j]))) << 32) |
          uint32_t(std::max(vertices[i], vertices[j]));
        key = (key ^ (key >> 31)) * 0xBF58476D1CE4E5B9ull; // splitmix64's finaliser
        sum += (key ^ (key >> 29)) * 0x94D049BB133111EBull;
      }
    }
  }
  return sum | 1;
}

// Patch p (a root of this pass, in the whole pass's order) keeps its triangles of the pass before
// when it is unchanged (MarkChangedPatches) and the level has the same edges between its vertices
// as when they were made: the triangulation of p would then be the same (it depends on its
// polygon, its normal and those of the patches across, and which diagonals are edges already).
bool SpbmLevelGenerator::LevelTriangulation::ReusePreviousTriangles(Index p)
{
  if (changed[p] || p + 1 >= Index(previousFirst.size()) || previousFirst[p] == previousFirst[p + 1] ||
    p >= Index(context.size()))
  {
    return false;
  }
  const Index* first = previousTriangles.data() + 3 * size_t(previousFirst[p]);
  const Index* last = previousTriangles.data() + 3 * size_t(previousFirst[p + 1]);
  const Index stamp = s.NextStamp();
  polygon.clear();
  for (const Index* v = first; v != last; ++v)
  {
    if (s.VertexStamp[*v] != stamp)
    {
      s.VertexStamp[*v] = stamp;
      polygon.push_back(*v);
    }
  }
  // The polygon starts where BoundaryPolygon would start it (the ear order can depend on it): at
  // the start of p's first live chain, as p runs along it.
  Index slot = s.PatchHead[p];
  while (slot != InvalidIndex && !s.Alive[slot / 2])
  {
    slot = s.PatchSlotNext[slot];
  }
  if (slot == InvalidIndex)
  {
    return false;
  }
  const Index c = slot / 2;
  const Index start = P.EndpointVertex(s.Find(s.L[c]) != p ? s.B[c] : s.A[c]);
  if (start != firstCorner[p])
  {
    return false;
  }
  if (this->Untouched(p))
  {
    ++level.ReusedUntouched; // the same edges between its vertices, made in the same order
  }
  else
  {
    // A polygon too large for a context (0) is kept only untouched (session 38: most of a coarse
    // level's triangles are in such polygons, and a further pass kept none of them).
    if (context[p] == 0)
    {
      return false;
    }
    ++level.ContextsCompared;
    if (this->EdgeContext(polygon.data(), polygon.size(), p) != context[p])
    {
      return false;
    }
    // The context is a hash: a kept diagonal that is now an edge outside p (a collision) would be
    // a duplicate edge, so each triangle edge is checked before any is inserted.
    for (const Index* t = first; t != last; t += 3)
    {
      for (int k = 0; k < 3; ++k)
      {
        if (this->EdgeOutside(t[k], t[(k + 1) % 3], p))
        {
          return false;
        }
      }
    }
  }
  for (const Index* t = first; t != last; t += 3)
  {
    Index ignored;
    for (int k = 0; k < 3; ++k)
    {
      s.Edges.Insert(t[k], t[(k + 1) % 3], -1, ignored); // the diagonals (the segments are in)
    }
    level.Triangles.insert(level.Triangles.end(), t, t + 3);
    level.TrianglePatch.push_back(p);
  }
  return true;
}

// What the next pass compares (LocalFallbackTriangulation): the roots, fallback levels and kept
// chain vertices of this pass, after its refinement rounds.
void SpbmLevelGenerator::LevelTriangulation::RememberPass(const std::vector<unsigned char>& frozen)
{
  if (!parameters.LocalFallbackTriangulation)
  {
    return;
  }
  previousRoot.resize(size_t(np));
  previousSize.resize(size_t(np));
  for (Index q = 0; q < np; ++q)
  {
    previousRoot[q] = s.Find(q);
    previousSize[q] = s.Size[q];
  }
  previousFrozen = frozen;
  previousAlive.resize(size_t(nc));
  previousKeptStart.resize(size_t(nc) + 1);
  previousKept.clear();
  for (Index c = 0; c < nc; ++c)
  {
    previousAlive[c] = s.Alive[c];
    previousKeptStart[c] = static_cast<Index>(previousKept.size());
    for (Index i = s.SeqOffsets[c]; i < s.SeqOffsets[c + 1]; ++i)
    {
      if (s.SeqKeep[i])
      {
        previousKept.push_back(s.SeqVertices[i]);
      }
    }
  }
  previousKeptStart[nc] = static_cast<Index>(previousKept.size());
}

// Every failed patch (not unmerged yet) with a hidden vertex to keep keeps one; the patches on
// both sides of its chain lose their triangles and are triangulated again with it (every other
// patch and edge of the pass is unchanged). True when a vertex was kept.
bool SpbmLevelGenerator::LevelTriangulation::RefineFailedPatches(const std::vector<unsigned char>& frozen)
{
  const Index stamp = s.NextStamp();
  affected.clear();
  for (Index p = 0; p < np; ++p)
  {
    Index c = InvalidIndex, from = 0, at = 0, to = 0;
    if (failed[p] != TriangulationFailure || s.Parent[p] != p || frozen[p] != 0 ||
      !this->HiddenVertexFor(p, c, from, at, to))
    {
      continue;
    }
    const Index x = s.SeqVertices[from], m = s.SeqVertices[at], y = s.SeqVertices[to];
    Index owner = InvalidIndex;
    if (P.ChainIsNonManifold(c) || s.Edges.Contains(x, m) || s.Edges.Contains(m, y) || !s.Edges.Find(x, y, owner) ||
      owner != c)
    {
      continue; // the split would duplicate an edge (or the segment is shared): left to the fallback
    }
    s.Edges.Erase(x, y);
    Index ignored;
    s.Edges.Insert(x, m, c, ignored);
    s.Edges.Insert(m, y, c, ignored);
    s.SeqKeep[at] = 1;
    refinedVertex.resize(size_t(mesh.NumberOfPoints()), 0);
    refinedVertex[m] = 1;
    ++level.RefinedInPass;
    for (const Index side : { p, s.Find(s.L[c]), s.R[c] == InvalidIndex ? InvalidIndex : s.Find(s.R[c]) })
    {
      if (side != InvalidIndex && s.PatchStamp[side] != stamp && frozen[side] != OriginalLevel)
      {
        s.PatchStamp[side] = stamp;
        affected.push_back(side);
      }
    }
  }
  if (affected.empty())
  {
    return false;
  }
  this->RemoveTriangles(stamp);
  std::stable_sort(affected.begin(), affected.end(), [&](Index x, Index y) { return s.Size[x] < s.Size[y]; });
  refinedRoots.insert(refinedRoots.end(), affected.begin(), affected.end());
  for (const Index q : affected)
  {
    if (failed[q] != SegmentFailure) // a duplicate chain segment stays one whatever p keeps
    {
      failed[q] = !this->BoundaryPolygon(q) || !this->TriangulateBoundary(q) ? TriangulationFailure : 0;
    }
  }
  return true;
}

// Removes the triangles of the patches stamped `stamp` and their diagonals (a diagonal is an edge
// of its own patch only; chain segments and original triangles' edges carry other values).
void SpbmLevelGenerator::LevelTriangulation::RemoveTriangles(Index stamp)
{
  size_t kept = 0;
  for (size_t t = 0; t < level.TrianglePatch.size(); ++t)
  {
    const Index tri[3] = { level.Triangles[3 * t], level.Triangles[3 * t + 1], level.Triangles[3 * t + 2] };
    if (s.PatchStamp[level.TrianglePatch[t]] != stamp)
    {
      std::copy(tri, tri + 3, level.Triangles.begin() + std::ptrdiff_t(3 * kept));
      level.TrianglePatch[kept++] = level.TrianglePatch[t];
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      Index value;
      if (s.Edges.Find(tri[k], tri[(k + 1) % 3], value) && value == -1)
      {
        s.Edges.Erase(tri[k], tri[(k + 1) % 3]);
      }
    }
  }
  level.Triangles.resize(3 * kept);
  level.TrianglePatch.resize(kept);
}

// The vertex failed patch p keeps (sequence position `at` on chain c, between the kept positions
// `from` and `to`): the hidden vertex of its boundary chains farthest from the kept segment that
// skips it (the vertex the chain hierarchy would add next, near enough), else one of a chain
// segment elsewhere that joins two of its corners (the diagonal p could not use). False when
// neither hides a vertex.
bool SpbmLevelGenerator::LevelTriangulation::HiddenVertexFor(Index p, Index& c, Index& from, Index& at, Index& to)
{
  double bestDistance2 = -1;
  Index chain = InvalidIndex;
  auto farthestHidden = [&](Index previous, Index i) {
    const Vec3& a = mesh.Point(s.SeqVertices[previous]);
    const Vec3& b = mesh.Point(s.SeqVertices[i]);
    for (Index k = previous + 1; k < i; ++k)
    {
      const double d2 = PointSegmentDistance2(mesh.Point(s.SeqVertices[k]), a, b);
      if (d2 > bestDistance2)
      {
        bestDistance2 = d2;
        c = chain;
        from = previous;
        at = k;
        to = i;
      }
    }
  };
  auto forKeptSegments = [&](Index x, auto&& f) {
    chain = x;
    Index previous = s.SeqOffsets[x];
    for (Index i = previous + 1; i < s.SeqOffsets[x + 1]; ++i)
    {
      if (s.SeqKeep[i])
      {
        f(previous, i);
        previous = i;
      }
    }
  };
  for (Index slot = s.PatchHead[p]; slot != InvalidIndex; slot = s.PatchSlotNext[slot])
  {
    const Index x = slot / 2;
    if (s.Alive[x] && !(slot % 2 == 1 && s.Find(s.L[x]) == p)) // once per chain
    {
      forKeptSegments(x, farthestHidden);
    }
  }
  // Else a chain segment elsewhere between two corners of p's polygon (BoundaryPolygon again: the
  // polygon of the failure was overwritten by the patches triangulated after it).
  const size_t n = bestDistance2 < 0 && this->BoundaryPolygon(p) ? polygon.size() : 0;
  for (size_t i = 0; i < n; ++i)
  {
    for (size_t j = i + 2; j < n; ++j)
    {
      Index x;
      if ((i == 0 && j + 1 == n) || !s.Edges.Find(polygon[i], polygon[j], x) || x < 0)
      {
        continue;
      }
      forKeptSegments(x, [&](Index previous, Index k) {
        const Index u = s.SeqVertices[previous], v = s.SeqVertices[k];
        if ((u == polygon[i] && v == polygon[j]) || (u == polygon[j] && v == polygon[i]))
        {
          farthestHidden(previous, k);
        }
      });
    }
  }
  return bestDistance2 >= 0;
}

// Vertex sequences of the alive chains (all vertices, with keep flags).
void SpbmLevelGenerator::LevelTriangulation::BuildVertexSequences()
{
  s.SeqOffsets.assign(size_t(nc) + 1, 0);
  s.SeqVertices.clear();
  s.SeqKeep.clear();
  for (Index c = 0; c < nc; ++c)
  {
    s.SeqOffsets[c] = static_cast<Index>(s.SeqVertices.size());
    if (!s.Alive[c])
    {
      continue;
    }
    const bool single = s.PartFirst[c] == s.PartLast[c];
    s.SeqVertices.push_back(P.EndpointVertex(s.A[c]));
    s.SeqKeep.push_back(1);
    for (Index part = s.PartFirst[c]; part != InvalidIndex; part = s.PartNext[part])
    {
      if (part != s.PartFirst[c])
      {
        // Joint between parts: the endpoint dropped when they were joined.
        s.SeqVertices.push_back(P.EndpointVertex(s.JointBefore[part]));
        s.SeqKeep.push_back(0);
      }
      const Index* v = P.ChainVerticesBegin(part);
      const Index n = P.ChainSize(part);
      const bool reversed = s.PartReversed[part];
      const size_t partStart = s.SeqVertices.size();
      for (Index i = 1; i + 1 < n; ++i)
      {
        s.SeqVertices.push_back(v[reversed ? n - 1 - i : i]);
        s.SeqKeep.push_back(0);
      }
      for (Index j = s.KeptOffsets[part]; j < s.KeptEnd[part]; ++j)
      {
        const Index k = s.KeptPositions[j];
        s.SeqKeep[partStart + size_t(reversed ? n - 1 - k : k) - 1] = 1;
      }
    }
    s.SeqVertices.push_back(P.EndpointVertex(s.B[c]));
    s.SeqKeep.push_back(1);
    // Forced vertex (lens rule): the top of the hierarchy, or the middle of a joined chain.
    const Index first = s.SeqOffsets[c], count = static_cast<Index>(s.SeqVertices.size()) - first;
    Index kept = 0;
    for (Index i = 1; i + 1 < count; ++i)
    {
      kept += s.SeqKeep[first + i];
    }
    if (kept < s.Interior[c] && count > 2)
    {
      Index best = count / 2;
      if (single)
      {
        const float* keys = generator.Keys.data() + (P.ChainVerticesBegin(c) - base);
        for (Index i = 1; i + 1 < count; ++i)
        {
          if (keys[i] > keys[best])
          {
            best = i;
          }
        }
      }
      s.SeqKeep[first + best] = 1;
    }
  }
  s.SeqOffsets[nc] = static_cast<Index>(s.SeqVertices.size());
}

// Segments must be unique: refine a chain whose shortcut duplicates another edge. Each round
// refines every duplicate it finds (adding a kept vertex, or giving up on a pair of patches), so
// the rounds (at most 64, each linear) follow the depth of the refinement, not the number of
// duplicates: stopping at the first duplicate left all but 64 of them unrefined on large rough
// surfaces.
void SpbmLevelGenerator::LevelTriangulation::MakeSegmentsUnique()
{
  s.Edges.TrackVertices(size_t(mesh.NumberOfPoints())); // most pair lookups of the pass find nothing
  for (int round = 0; round < 64; ++round)
  {
    bool changed = false;
    s.Edges.Reset(s.SeqVertices.size());
    for (Index c = 0; c < nc; ++c)
    {
      Index previous = s.SeqOffsets[c];
      for (Index i = s.SeqOffsets[c] + 1; i < s.SeqOffsets[c + 1]; ++i)
      {
        if (!s.SeqKeep[i])
        {
          continue;
        }
        Index existing;
        // A non-manifold input edge lies on the (full-resolution) chain of every patch around
        // it: the same segment on several non-manifold chains is that one edge, kept as is.
        if (!s.Edges.Insert(s.SeqVertices[previous], s.SeqVertices[i], c, existing) &&
          !(existing >= 0 && P.ChainIsNonManifold(c) && P.ChainIsNonManifold(existing)))
        {
          if (i - previous >= 2)
          {
            s.SeqKeep[(previous + i) / 2] = 1;
            changed = true;
          }
          else
          {
            // Refine the other one (find its segment), else give up on both patches.
            bool refined = false;
            Index prevOther = s.SeqOffsets[existing];
            for (Index j = s.SeqOffsets[existing] + 1; j < s.SeqOffsets[existing + 1] && !refined; ++j)
            {
              if (!s.SeqKeep[j])
              {
                continue;
              }
              const Index x = s.SeqVertices[prevOther], y = s.SeqVertices[j];
              if (((x == s.SeqVertices[previous] && y == s.SeqVertices[i]) ||
                    (y == s.SeqVertices[previous] && x == s.SeqVertices[i])) &&
                j - prevOther >= 2)
              {
                s.SeqKeep[(prevOther + j) / 2] = 1;
                refined = true;
              }
              prevOther = j;
            }
            if (refined)
            {
              changed = true;
            }
            else
            {
              for (const Index x : { c, existing })
              {
                failed[s.Find(s.L[x])] = SegmentFailure;
                if (s.R[x] != InvalidIndex)
                {
                  failed[s.Find(s.R[x])] = SegmentFailure;
                }
              }
            }
          }
        }
        previous = i;
      }
    }
    if (!changed)
    {
      break;
    }
  }
}

// Edges and triangles of patches kept as original triangles.
void SpbmLevelGenerator::LevelTriangulation::AddOriginalPatches(const std::vector<unsigned char>& frozen)
{
  level.Triangles.clear();
  level.TrianglePatch.clear();
  bool anyOriginal = false;
  for (Index p = 0; p < np; ++p)
  {
    anyOriginal = anyOriginal || frozen[p] == OriginalLevel;
  }
  if (anyOriginal)
  {
    const std::vector<Index>& patchOf = P.TrianglePatches();
    for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      const Index p = patchOf[t];
      if (frozen[p] != OriginalLevel)
      {
        continue;
      }
      const Index* tri = mesh.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        Index existing;
        if (!s.Edges.Insert(tri[k], tri[(k + 1) % 3], -1 - p, existing) && existing >= 0)
        {
          const Index x = existing;
          if (s.Find(s.L[x]) != p && (s.R[x] == InvalidIndex || s.Find(s.R[x]) != p))
          {
            failed[s.Find(s.L[x])] = SegmentFailure;
            if (s.R[x] != InvalidIndex)
            {
              failed[s.Find(s.R[x])] = SegmentFailure;
            }
          }
        }
      }
      level.Triangles.insert(level.Triangles.end(), tri, tri + 3);
      level.TrianglePatch.push_back(p);
      if (!touched.empty())
      {
        for (int k = 0; k < 3; ++k)
        {
          touched[tri[k]] = touchStamp; // original edges (interior vertices too)
        }
      }
    }
  }
}

// Every other patch from its simplified boundary, smallest boundaries first: they have the
// fewest alternative diagonals, large ones can avoid the edges already taken.
bool SpbmLevelGenerator::LevelTriangulation::TriangulatePatches(
  const std::vector<unsigned char>& frozen, const std::function<bool()>& abort)
{
  std::vector<Index> patches;
  const bool local = passesDone > 0 && parameters.LocalFallbackTriangulation;
  for (Index p = 0; p < np; ++p)
  {
    if (s.Parent[p] == p && frozen[p] != OriginalLevel && !failed[p])
    {
      patches.push_back(p);
    }
    else if (local && s.Parent[p] == p && failed[p])
    {
      this->TouchPatch(p); // its triangles of the pass before are not in the level
    }
  }
  std::stable_sort(patches.begin(), patches.end(), [&](Index x, Index y) { return s.Size[x] < s.Size[y]; });
  if (!local && parameters.MinimumDeviationTriangulation && parameters.MeasureDiagonalsAhead)
  {
    this->MeasureDiagonalsAhead(patches);
  }
  if (!local && parameters.MinimumDeviationTriangulation && parameters.TriangulateAheadOverThreads)
  {
    this->TriangulateAhead(patches);
  }
  for (size_t index = 0; index < patches.size(); ++index)
  {
    const Index p = patches[index];
    if ((index & 255) == 0 && abort && abort())
    {
      return false;
    }
    if (local && this->ReusePreviousTriangles(p))
    {
      continue;
    }
    if (local)
    {
      this->TouchPatch(p); // triangulated again: its edges may differ from the pass before
    }
    level.RetriangulatedPatches += passesDone > 0;
    const size_t before = level.TrianglePatch.size();
    if (!this->BoundaryPolygon(p) || !this->TriangulateBoundary(p))
    {
      failed[p] = TriangulationFailure;
    }
    level.RetriangulatedTriangles += passesDone > 0 ? Index(level.TrianglePatch.size() - before) : 0;
  }
  // The refinement rounds also remove edges: the jobs hold for this walk only.
  aheadJob.clear();
  return true;
}

// The boundary polygon of root patch p (polygon, other): its oriented chains linked end to
// start, the kept vertices of each. False when they do not form one simple loop.
bool SpbmLevelGenerator::LevelTriangulation::BoundaryPolygon(Index p)
{
  // Oriented chains of p, linked end to start.
  ring.clear();
  const Index stamp = s.NextStamp();
  for (Index slot = s.PatchHead[p]; slot != InvalidIndex; slot = s.PatchSlotNext[slot])
  {
    const Index c = slot / 2;
    if (!s.Alive[c])
    {
      continue;
    }
    const bool reversed = s.Find(s.L[c]) != p;
    const Index startEnd = reversed ? s.B[c] : s.A[c];
    if (s.EndStamp[startEnd] == stamp)
    {
      ring.clear();
      break; // two chains leave the same vertex: not a simple loop
    }
    s.EndStamp[startEnd] = stamp;
    ring.push_back(reversed ? -1 - c : c);
  }
  polygon.clear();
  other.clear();
  bool ok = !ring.empty();
  if (ok)
  {
    // Order: follow end -> start through a small search (patch degrees are small).
    order.assign(ring.begin(), ring.end());
    auto startOf = [&](Index o) { return o >= 0 ? s.A[o] : s.B[-1 - o]; };
    auto endOf = [&](Index o) { return o >= 0 ? s.B[o] : s.A[-1 - o]; };
    for (size_t i = 0; i + 1 < order.size() && ok; ++i)
    {
      size_t j = i + 1;
      while (j < order.size() && startOf(order[j]) != endOf(order[i]))
      {
        ++j;
      }
      if (j == order.size())
      {
        ok = false;
      }
      else
      {
        std::swap(order[i + 1], order[j]);
      }
    }
    ok = ok && endOf(order.back()) == startOf(order.front());
    for (size_t i = 0; i < order.size() && ok; ++i)
    {
      const Index c = order[i] >= 0 ? order[i] : -1 - order[i];
      const bool reversed = order[i] < 0;
      const Index otherSide = s.R[c] == InvalidIndex ? InvalidIndex : (reversed ? s.Find(s.L[c]) : s.Find(s.R[c]));
      const Index first = s.SeqOffsets[c], last = s.SeqOffsets[c + 1] - 1;
      for (Index k = 0; k < last - first; ++k) // all but the final vertex
      {
        const Index pos = reversed ? last - k : first + k;
        if (!s.SeqKeep[pos])
        {
          continue;
        }
        polygon.push_back(s.SeqVertices[pos]);
        other.push_back(k == 0 ? InvalidIndex : otherSide);
      }
    }
  }
  // Distinct vertices.
  const Index vstamp = s.NextStamp();
  for (const Index v : polygon)
  {
    ok = ok && s.VertexStamp[v] != vstamp;
    s.VertexStamp[v] = vstamp;
  }
  ok = ok && polygon.size() >= 3;
  return ok;
}

// Triangulates the boundary polygon of patch p into the level: the minimum-deviation
// triangulation for small non-planar boundaries, else ear clipping (smallest angle first) with
// the double-ear normal rule, then without it. No diagonal may duplicate an existing edge.
bool SpbmLevelGenerator::LevelTriangulation::TriangulateBoundary(Index p)
{
  if (parameters.LocalFallbackTriangulation)
  {
    context.resize(size_t(np), 0);
    context[p] = this->EdgeContext(polygon.data(), polygon.size(), p); // before its own diagonals
    firstCorner.resize(size_t(np), InvalidIndex);
    firstCorner[p] = polygon[0];
  }
  this->PolygonPoints();
  const Vec3 normal = Normalized(s.Normal[p]);
  const Index n = static_cast<Index>(polygon.size());
  PolygonTriangulationOptions options;
  options.AllowFallback = false;
  bool doubleEarRule = true;
  options.AcceptEar = [&](Index ia, Index k, Index ic) {
    if (s.Edges.Contains(polygon[ia], polygon[ic]))
    {
      return false; // the diagonal is already an edge: would be non-manifold
    }
    if (doubleEarRule && other[k] != InvalidIndex && ia == (k + n - 1) % n && ic == (k + 1) % n)
    {
      // Double ear: the mirrored triangle would also be an ear of the patch across; keep
      // the one whose normal is closer to its patch normal.
      const Vec3 nt = Cross(points[k] - points[ia], points[ic] - points[ia]);
      if (Dot(nt, normal + Normalized(s.Normal[other[k]])) < 0)
      {
        return false;
      }
    }
    return true;
  };
  PolygonTriangulationResult result;
  result.Failed = true;
  if (parameters.MinimumDeviationTriangulation && this->MinimumDeviationApplies(normal) &&
    !this->TakeTriangulationAhead(p, result))
  {
    this->TriangulateMinimumDeviation(normal, result);
  }
  if (result.Failed)
  {
    result = TriangulatePolygon(points, normal, options);
  }
  if (result.Failed)
  {
    doubleEarRule = false; // the rule only chooses between sides; never fail because of it
    result = TriangulatePolygon(points, normal, options);
  }
  if (result.Failed || result.Triangles.size() + 2 != polygon.size())
  {
    return false;
  }
  for (const auto& t : result.Triangles)
  {
    Index ignored;
    for (int k = 0; k < 3; ++k)
    {
      const Index a = polygon[t[k]], b = polygon[t[(k + 1) % 3]];
      if (s.Edges.Insert(a, b, -1, ignored) && !aheadJob.empty())
      {
        passDiagonals.Insert(a, b, -1, ignored);
        passDiagonalCorner[size_t(a)] = passDiagonalCorner[size_t(b)] = 1;
      }
    }
    level.Triangles.push_back(polygon[t[0]]);
    level.Triangles.push_back(polygon[t[1]]);
    level.Triangles.push_back(polygon[t[2]]);
    level.TrianglePatch.push_back(p);
  }
  return true;
}

// The corner points of the current polygon.
void SpbmLevelGenerator::LevelTriangulation::PolygonPoints()
{
  points.resize(polygon.size());
  for (size_t i = 0; i < polygon.size(); ++i)
  {
    points[i] = mesh.Point(polygon[i]);
  }
}

// Whether the current polygon (with its points) gets the minimum-deviation triangulation: more
// than a triangle, at most MinimumDeviationMaxVertices corners, and not planar.
bool SpbmLevelGenerator::LevelTriangulation::MinimumDeviationApplies(const Vec3& normal) const
{
  const Index n = static_cast<Index>(polygon.size());
  if (n <= 3 || n > parameters.MinimumDeviationMaxVertices)
  {
    return false;
  }
  Vec3 centroid{ 0, 0, 0 };
  for (const Vec3& x : points)
  {
    centroid = centroid + x;
  }
  centroid = (1.0 / n) * centroid;
  double height = 0;
  for (const Vec3& x : points)
  {
    height = std::max(height, std::fabs(Dot(x - centroid, normal)));
  }
  return height > parameters.NonPlanarTolerance * generator.Diagonal;
}

namespace
{
// A diagonal's cost: the distance of its midpoint from the input, as float. (Adding the quarter
// points tripled the queries, about half of the level's triangulation time, for the same Fandisk
// levels and 7% on bunny00 at 1500 triangles.) Float also when just measured: the level then does
// not depend on which working state (candidate thread) or pass measured a diagonal first.
float DiagonalCost(const TriangleBVH& tree, const Vec3& a, const Vec3& b)
{
  return static_cast<float>(std::sqrt(tree.ClosestPoint(0.5 * (a + b)).Distance2));
}

Index CostBits(float cost)
{
  Index bits = 0;
  std::memcpy(&bits, &cost, sizeof(float));
  return bits;
}
} // namespace

// MeasureDiagonalsAhead: every diagonal that the minimum-deviation triangulations of `patches` may
// ask for (all vertex pairs of their polygons that are not measured yet nor edges of the level:
// a superset, the pass only adds edges) measured over threads into per-pair slots, then cached in
// patch order. A diagonal's cost depends on its two vertices only, so the pass reads the costs it
// would have measured itself; only the cache holds a few more. The queries were about a fifth of
// the MRI's instructions at 10%, all on the level's thread.
void SpbmLevelGenerator::LevelTriangulation::MeasureDiagonalsAhead(const std::vector<Index>& patches)
{
  std::vector<std::array<Index, 2>> pairs;
  for (const Index p : patches)
  {
    if (!this->MinimumDeviationPolygon(p))
    {
      continue;
    }
    const size_t n = polygon.size();
    for (size_t i = 0; i + 2 < n; ++i)
    {
      for (size_t j = i + 2; j < n - (i == 0 ? 1 : 0); ++j)
      {
        if (!s.DiagonalCosts.Contains(polygon[i], polygon[j]) && !s.Edges.Contains(polygon[i], polygon[j]))
        {
          pairs.push_back({ polygon[i], polygon[j] });
        }
      }
    }
  }
  if (pairs.empty())
  {
    return;
  }
  const TriangleBVH& tree = generator.GetInputTree(s.Times);
  const auto started = spbm::StageClock::now();
  std::vector<float> costs(pairs.size());
  vtkSMPTools::For(0, vtkIdType(pairs.size()), [&](vtkIdType first, vtkIdType last) {
    for (vtkIdType k = first; k < last; ++k)
    {
      costs[size_t(k)] = DiagonalCost(tree, mesh.Point(pairs[size_t(k)][0]), mesh.Point(pairs[size_t(k)][1]));
    }
  });
  for (size_t k = 0; k < pairs.size(); ++k)
  {
    Index ignored;
    s.DiagonalCosts.Insert(pairs[k][0], pairs[k][1], CostBits(costs[k]), ignored);
  }
  level.DiagonalsMeasured += static_cast<Index>(pairs.size());
  level.DiagonalsMeasuredAhead += static_cast<Index>(pairs.size());
  s.Times.Triangulation += Since(started);
}

// The boundary polygon of root patch p (polygon, points) when it gets the minimum-deviation
// triangulation.
bool SpbmLevelGenerator::LevelTriangulation::MinimumDeviationPolygon(Index p)
{
  if (!this->BoundaryPolygon(p))
  {
    return false;
  }
  this->PolygonPoints();
  return this->MinimumDeviationApplies(Normalized(s.Normal[p]));
}

// The minimum-deviation options for the polygon `corner` (indices into the mesh): a diagonal
// that is an edge of the level is refused; `costBits(i, k)` gives the float cost's bits.
template<typename CostBitsOf>
MinimumCostTriangulationOptions SpbmLevelGenerator::LevelTriangulation::MinimumDeviationOptions(
  const Index* corner, CostBitsOf&& costBits) const
{
  MinimumCostTriangulationOptions dp;
  dp.AcceptDiagonal = [this, corner](Index i, Index j) { return !s.Edges.Contains(corner[i], corner[j]); };
  dp.DiagonalCost = [costBits](Index i, Index j) {
    const Index bits = costBits(i, j);
    float cost = 0;
    std::memcpy(&cost, &bits, sizeof(float));
    return double(cost);
  };
  // Thin triangles cost about as much as a diagonal 1e-3 of the diagonal off the surface.
  dp.AngleWeight = 1e-3 * generator.Diagonal;
  // Issue 15 (session 34): three vertices of a curved crease chain (a gear tooth's rim) make a
  // triangle in the plane of the face beyond the crease, where both its diagonals are free (their
  // midpoints lie on that face); turned by more than 75 degrees from its patch's normal, its
  // height along that normal is its cost (pinion at 50%: 1.3e-3 of the diagonal, vtkQD 2.5e-4).
  // (60 degrees also changed triangles standing less steeply in coarse merged patches of smooth
  // models, about as often for the worse: mannequin-devil at 10% 1.5x -> 2.2x vtkQD.)
  dp.FoldedTriangleCosine = 0.2588; // cos 75 degrees
  return dp;
}

// TriangulateAhead: the minimum-deviation triangulation of each polygon of `patches` that gets
// one, over threads, against the level's edges now (read only), noting which pairs of corners it
// asked about (those inside the polygon); the costs measured are cached afterwards (the pass and
// later levels read them as when measured on demand).
void SpbmLevelGenerator::LevelTriangulation::TriangulateAhead(const std::vector<Index>& patches)
{
  aheadJob.assign(size_t(np), InvalidIndex);
  aheadStart.assign(1, 0);
  aheadVertices.clear();
  aheadPatch.clear();
  aheadAskedStart.assign(1, 0);
  for (const Index p : patches)
  {
    if (this->MinimumDeviationPolygon(p))
    {
      aheadJob[size_t(p)] = static_cast<Index>(aheadStart.size() - 1);
      aheadPatch.push_back(p);
      aheadVertices.insert(aheadVertices.end(), polygon.begin(), polygon.end());
      aheadStart.push_back(static_cast<Index>(aheadVertices.size()));
      aheadAskedStart.push_back(aheadAskedStart.back() + (polygon.size() * polygon.size() + 63) / 64);
    }
  }
  const Index jobs = static_cast<Index>(aheadStart.size() - 1);
  if (jobs == 0)
  {
    aheadJob.clear();
    return;
  }
  passDiagonals.Reset(aheadVertices.size());
  passDiagonalCorner.assign(size_t(mesh.NumberOfPoints()), 0);
  aheadFailed.assign(size_t(jobs), 0);
  aheadAsked.assign(aheadAskedStart.back(), 0);
  aheadTriangles.resize(aheadVertices.size() - 2 * size_t(jobs));
  const TriangleBVH& tree = generator.GetInputTree(s.Times);
  const auto started = spbm::StageClock::now();
  struct Measured
  {
    Index A, B;
    float Cost;
  };
  vtkSMPThreadLocal<std::vector<Measured>> measured;
  vtkSMPTools::For(0, vtkIdType(jobs), 16, [&](vtkIdType first, vtkIdType last) {
    std::vector<Measured>& local = measured.Local();
    std::vector<Vec3> corners;
    for (vtkIdType j = first; j < last; ++j)
    {
      const Index* corner = aheadVertices.data() + aheadStart[size_t(j)];
      const Index n = aheadStart[size_t(j) + 1] - aheadStart[size_t(j)];
      corners.resize(size_t(n));
      for (Index i = 0; i < n; ++i)
      {
        corners[size_t(i)] = mesh.Point(corner[i]);
      }
      MinimumCostTriangulationOptions dp = this->MinimumDeviationOptions(corner, [&](Index i, Index k) {
          Index bits = 0;
          if (s.DiagonalCosts.Find(corner[i], corner[k], bits))
          {
            return bits;
          }
          const float cost = DiagonalCost(tree, corners[size_t(i)], corners[size_t(k)]);
          local.push_back({ corner[i], corner[k], cost });
          return CostBits(cost);
        });
      uint64_t* asked = aheadAsked.data() + aheadAskedStart[size_t(j)];
      dp.AcceptDiagonal = [&, corner, asked, n](Index i, Index k) {
        const size_t bit = size_t(i) * size_t(n) + size_t(k);
        asked[bit / 64] |= uint64_t(1) << (bit % 64);
        return !s.Edges.Contains(corner[i], corner[k]);
      };
      const PolygonTriangulationResult result =
        TriangulatePolygonMinimumCost(corners, Normalized(s.Normal[aheadPatch[size_t(j)]]), dp);
      // A complete triangulation or none (Failed); anything else is left to the pass.
      aheadFailed[size_t(j)] = result.Failed ? 1 : (result.Triangles.size() + 2 == size_t(n) ? 0 : 2);
      if (aheadFailed[size_t(j)] == 0)
      {
        std::copy(result.Triangles.begin(), result.Triangles.end(),
          aheadTriangles.begin() + (aheadStart[size_t(j)] - 2 * Index(j)));
      }
    }
  });
  for (const std::vector<Measured>& local : measured)
  {
    for (const Measured& m : local)
    {
      Index ignored;
      level.DiagonalsMeasured += s.DiagonalCosts.Insert(m.A, m.B, CostBits(m.Cost), ignored);
    }
  }
  s.Times.Triangulation += Since(started);
}

// The triangulation TriangulateAhead made for root patch p (the current polygon), unless its
// polygon differs or a diagonal the pass inserted since joins two of its corners that it asked
// about: it would then get the same answers, so it is the one the pass would make.
bool SpbmLevelGenerator::LevelTriangulation::TakeTriangulationAhead(Index p, PolygonTriangulationResult& result)
{
  if (aheadJob.empty() || aheadJob[size_t(p)] == InvalidIndex)
  {
    return false;
  }
  const Index j = aheadJob[size_t(p)];
  const Index* corner = aheadVertices.data() + aheadStart[size_t(j)];
  const size_t n = size_t(aheadStart[size_t(j) + 1] - aheadStart[size_t(j)]);
  if (aheadFailed[size_t(j)] == 2 || n != polygon.size() || !std::equal(polygon.begin(), polygon.end(), corner))
  {
    return false;
  }
  order.clear(); // the corners with a diagonal of the pass (polygon indices)
  for (size_t i = 0; i < n; ++i)
  {
    if (passDiagonalCorner[size_t(polygon[i])])
    {
      order.push_back(static_cast<Index>(i));
    }
  }
  const uint64_t* asked = aheadAsked.data() + aheadAskedStart[size_t(j)];
  for (size_t a = 0; a < order.size(); ++a)
  {
    for (size_t b = a + 1; b < order.size(); ++b)
    {
      // Only a pair the triangulation asked about (a diagonal inside the polygon) can change it.
      const size_t bit = size_t(order[a]) * n + size_t(order[b]);
      if (((asked[bit / 64] >> (bit % 64)) & 1u) && passDiagonals.Contains(polygon[order[a]], polygon[order[b]]))
      {
        ++level.TriangulatedAgain;
        return false;
      }
    }
  }
  ++level.TriangulatedAhead;
  result.Failed = aheadFailed[size_t(j)] != 0;
  result.Triangles.clear();
  if (!result.Failed)
  {
    const auto begin = aheadTriangles.begin() + (aheadStart[size_t(j)] - 2 * j);
    result.Triangles.assign(begin, begin + (n - 2));
  }
  return true;
}

// Non-planar boundary: the choice of diagonals decides how far the flat triangulation lies from
// the original patch; choose the diagonals closest to the original surface.
void SpbmLevelGenerator::LevelTriangulation::TriangulateMinimumDeviation(
  const Vec3& normal, PolygonTriangulationResult& result)
{
  const TriangleBVH& tree = generator.GetInputTree(s.Times);
  const auto started = spbm::StageClock::now();
  result = TriangulatePolygonMinimumCost(points, normal, this->MinimumDeviationOptions(polygon.data(), [&](Index i, Index j) {
    Index bits = 0;
    if (!s.DiagonalCosts.Find(polygon[i], polygon[j], bits))
    {
      s.DiagonalCosts.PrefetchSlot(polygon[i], polygon[j]); // loads during the query below
      bits = CostBits(DiagonalCost(tree, points[i], points[j]));
      ++level.DiagonalsMeasured;
      Index ignored;
      s.DiagonalCosts.Insert(polygon[i], polygon[j], bits, ignored);
    }
    return bits;
  }));
  s.Times.Triangulation += Since(started);
}

bool SpbmLevelGenerator::LevelTriangulation::FreezeFailedPatches(std::vector<unsigned char>& frozen, bool& unmerged)
{
  unmerged = false;
  // With a negative epsilon every chain keeps all its vertices already, so the finer-chain levels
  // (2 .. FullResolutionLevel) would each repeat the level-1 pass for nothing: the level after an
  // unmerged patch that still fails is its original triangles (mc1m at 10%: 12 patches failed
  // through 6 such passes, 0.35 s of triangulation and a merging run each).
  const bool fullResolution = parameters.Epsilon < 0;
  // Final collapses will finish this level (FinalCollapsesFollow): the same jump for the patches
  // that are unmerged already.
  const bool collapsesFollow = parameters.FinalCollapsesFollow && parameters.RemovalTarget > 0 &&
    s.Total > parameters.RemovalTarget + SpbmFinalCollapseTolerance(parameters.RemovalTarget);
  const bool straightToOriginal = fullResolution || collapsesFollow;
  // A late pass (LateFailureShare): its few failures relative to the input go to their original
  // triangles at once. Through the unmerged level each would need a further whole-level pass or
  // two when it or a patch re-merged next to it fails again, and the passes' cost is the level's.
  const Index changeableFailures = this->CountChangeableFailures(frozen);
  level.ChangeableFailures.push_back(changeableFailures);
  const bool late = straightToOriginal && changeableFailures > 0 &&
    double(changeableFailures) <= parameters.LateFailureShare * double(np);
  vtkLogF(TRACE, "[spbm] pass %d: %d failed patches can change%s", int(level.ChangeableFailures.size()),
    int(changeableFailures), late ? " (late pass: to their original triangles)" : "");
  // Every failed patch goes one level further per pass; the passes in which none of them keeps a
  // vertex more (or is unmerged) would repeat this one, so they are skipped: the level is the same.
  int step = parameters.SkipIneffectiveFallbackLevels ? OriginalLevel : 1;
  bool anyFailed = false;
  for (Index q = 0; q < np && step > 1; ++q)
  {
    if (failed[s.Find(q)] && frozen[q] < OriginalLevel && !(straightToOriginal && frozen[q] >= 1))
    {
      step = std::min(step, frozen[q] == 0 ? 1 : this->NextEffectiveLevel(q, frozen) - frozen[q]);
    }
  }
  for (Index p = 0; p < np; ++p)
  {
    level.FailedPatches += failed[p] && s.Parent[p] == p;
  }
  for (Index q = 0; q < np; ++q)
  {
    if (failed[s.Find(q)] && frozen[q] < OriginalLevel)
    {
      unmerged = unmerged || frozen[q] == 0;
      level.LateOriginalPatches += late && frozen[q] == 0;
      frozen[q] = late || (straightToOriginal && frozen[q] >= 1) ? OriginalLevel : std::min(OriginalLevel, frozen[q] + step);
      anyFailed = true;
    }
  }
  return anyFailed;
}

// The failed root patches of the last pass that a further pass can change: those with an input
// patch below the original level (an original patch's triangles are the input's already).
Index SpbmLevelGenerator::LevelTriangulation::CountChangeableFailures(const std::vector<unsigned char>& frozen)
{
  changeable.assign(size_t(np), 0);
  Index count = 0;
  for (Index q = 0; q < np; ++q)
  {
    const Index root = s.Find(q);
    if (failed[root] && frozen[q] < OriginalLevel && !changeable[root])
    {
      changeable[root] = 1;
      ++count;
    }
  }
  return count;
}

// The next fallback level of unmerged patch q that makes one of its chains keep more vertices
// (else its original triangles). A level that keeps the same vertices gives the same boundaries:
// on the MRI at 10% one patch went through four such passes (each a triangulation of the whole
// level) before the level that changed it.
int SpbmLevelGenerator::LevelTriangulation::NextEffectiveLevel(Index q, const std::vector<unsigned char>& frozen) const
{
  const float epsilon = static_cast<float>(parameters.Epsilon);
  for (int next = frozen[q] + 1; next < OriginalLevel; ++next)
  {
    // The chains of an unmerged patch are the patchification's own (no merge, collapse or join).
    for (Index slot = s.PatchHead[q]; slot != InvalidIndex; slot = s.PatchSlotNext[slot])
    {
      const Index c = slot / 2;
      if (!s.Alive[c] || s.Locked[c])
      {
        continue;
      }
      const Index across = s.L[c] == q ? s.R[c] : s.L[c];
      const int level = std::max<int>(next, across == InvalidIndex ? 0 : frozen[across]);
      const Index kept = level >= FullResolutionLevel
        ? std::max<Index>(0, P.ChainSize(c) - 2)
        : generator.KeptInterior(c, std::min(s.Tolerance[c], FallbackTolerance(epsilon, level)));
      if (kept > s.Interior[c])
      {
        return next;
      }
    }
  }
  return OriginalLevel;
}

// Compact patch ids and the profile curves.
void SpbmLevelGenerator::LevelTriangulation::Finish(const std::vector<unsigned char>& frozen)
{
  std::vector<Index> compact(size_t(np), InvalidIndex);
  Index next = 0;
  for (Index& p : level.TrianglePatch)
  {
    if (compact[p] == InvalidIndex)
    {
      compact[p] = next++;
    }
    p = compact[p];
  }
  level.NumberOfPatches = next;
  level.MergedPatchOf.assign(size_t(np), InvalidIndex);
  for (Index p = 0; p < np; ++p)
  {
    const Index root = s.Find(p);
    level.MergedPatchOf[p] = compact[root] != InvalidIndex ? compact[root] : compact[p];
  }
  for (Index p = 0; p < np; ++p)
  {
    level.UnmergedPatches += frozen[p] == 1;
    level.RefinedPatches += frozen[p] >= 2 && frozen[p] < OriginalLevel;
    level.OriginalPatches += frozen[p] == OriginalLevel;
  }
  level.CurveOffsets.assign(1, 0);
  level.CurveVertices.clear();
  for (Index c = 0; c < nc; ++c)
  {
    if (!s.Alive[c])
    {
      continue;
    }
    for (Index i = s.SeqOffsets[c]; i < s.SeqOffsets[c + 1]; ++i)
    {
      if (s.SeqKeep[i])
      {
        level.CurveVertices.push_back(s.SeqVertices[i]);
      }
    }
    level.CurveOffsets.push_back(static_cast<Index>(level.CurveVertices.size()));
  }
}
} // namespace slod
