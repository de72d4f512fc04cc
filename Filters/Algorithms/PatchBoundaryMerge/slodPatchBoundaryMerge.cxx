// SPDX-License-Identifier: BSD-3-Clause
#include "slodPatchBoundaryMerge.h"

#include "slodPointGrid.h"
#include "slodPolygonTriangulation.h"
#include "slodSpbmState.h"
#include "slodSpbmTargetSearch.h"
#include "slodSpbmTriangulation.h"
#include "slodTriangleBVH.h"

#include "vtkLogger.h"
#include "vtkMath.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iterator>
#include <limits>

namespace slod
{
using namespace spbm;

// Stage times of one working state, logged at verbosity TRACE (profiling aid).
void SpbmLevelGenerator::LogStageTimes(const char* what, double seconds, const StageTimes& times)
{
  vtkLogF(TRACE,
    "[spbm] %s %.4f s: %d merging runs %.4f s (refinement %.4f s), generate %.4f s (input BVH %.4f s, "
    "minimum-deviation triangulation %.4f s)",
    what, seconds, times.MergingRuns, times.Merging, times.Refinement, times.Generate, times.Tree, times.Triangulation);
}

SpbmLevelGenerator::SpbmLevelGenerator()
  : Work(new State)
  , Helper(new State)
{
}

SpbmLevelGenerator::~SpbmLevelGenerator() = default;

void SpbmLevelGenerator::Initialize(const TriangleMesh& mesh, const Patchification& patches)
{
  this->Initialize(mesh, patches, 1.0);
}

void SpbmLevelGenerator::Initialize(const TriangleMesh& mesh, const Patchification& patches, double inPlaneWeight)
{
  this->Mesh = &mesh;
  this->Patches = &patches;
  this->Work->Memo.clear();
  this->Helper->Memo.clear();
  this->Work->HoldsPrediction = this->Helper->HoldsPrediction = false;
  this->Helper->RefinedValid = false;
  // Almost every diagonal a pass asks for is new: the filter answers those without a probe.
  this->Helper->DiagonalCosts.TrackVertices(size_t(mesh.NumberOfPoints()));
  this->Helper->DiagonalCosts.Reset(0);
  if (!(this->BuiltTree && this->TreeMesh == &mesh))
  {
    // Only a tree built by BuildInputTreeDuring for this mesh is kept (the mesh may have
    // changed in place since an older tree was built).
    this->BuiltTree.reset();
    this->InputTree.reset();
    this->TreeMesh = &mesh;
  }
  this->Diagonal = mesh.BoundingBoxDiagonal();
  this->InPlaneWeight = std::max(0.0, std::min(1.0, inPlaneWeight));
  this->Work->RefinedValid = false;
  this->Work->SimpleSignature.clear();
  this->Helper->SimpleSignature.clear();
  this->Work->BoundaryOutcomes.Clear();
  this->Helper->BoundaryOutcomes.Clear();
  this->Work->DiagonalCosts.TrackVertices(size_t(mesh.NumberOfPoints()));
  this->Work->DiagonalCosts.Reset(0);
  this->Work->KeptTolerance.clear(); // the chain keys change: every chain's kept positions too
  this->Helper->KeptTolerance.clear();
  this->PatchSupport.clear(); // built on first use (FlatnessMerge)
  this->LastPass.reset();     // of other patches
  const Patchification& P = patches;
  const Index nc = P.NumberOfChains();
  const size_t totalVertices = nc > 0 ? size_t(P.ChainVerticesBegin(nc - 1) + P.ChainSize(nc - 1) - P.ChainVerticesBegin(0)) : 0;
  this->BuildChainKeys(totalVertices);
  this->OrderChainKeys(totalVertices);
  this->MarkParallelChains();
  this->MeasureEndpointVariation();
}

// The divide-and-conquer refinement tree of every chain, stored as one key per chain vertex.
void SpbmLevelGenerator::BuildChainKeys(size_t totalVertices)
{
  const TriangleMesh& mesh = *this->Mesh;
  const Patchification& P = *this->Patches;
  const Index nc = P.NumberOfChains();
  this->Keys.assign(totalVertices, InfiniteKey);
  this->SortedKeys.clear();
  struct Node
  {
    Index I, J;
    float ParentKey;
  };
  std::vector<Node> stack;
  // With inPlaneWeight < 1 a chain's deviation counts mostly along the normals of its two
  // patches (SurfaceWeightedDistance2): an offset within both patch planes moves the surface
  // little, so smooth boundaries get coarser and creases finer for the same vertex budget.
  const double lambda2 = this->InPlaneWeight * this->InPlaneWeight;
  for (Index c = 0; c < nc; ++c)
  {
    if (P.ChainIsNonManifold(c))
    {
      continue; // kept as it is
    }
    const Index* v = P.ChainVerticesBegin(c);
    const size_t offset = size_t(v - P.ChainVerticesBegin(0));
    const Index n = P.ChainSize(c);
    const bool surfaceWeighted = lambda2 < 1.0 && P.ChainRightPatch(c) != InvalidIndex;
    const Vec3 n1 = P.PatchNormal(P.ChainLeftPatch(c));
    const Vec3 n2 = surfaceWeighted ? P.PatchNormal(P.ChainRightPatch(c)) : n1;
    stack.clear();
    stack.push_back({ 0, n - 1, InfiniteKey });
    while (!stack.empty())
    {
      const Node node = stack.back();
      stack.pop_back();
      if (node.J - node.I < 2)
      {
        continue;
      }
      const Vec3 a = mesh.Point(v[node.I]);
      const Vec3 b = mesh.Point(v[node.J]);
      // Split at the farthest vertex (Douglas-Peucker) rather than at the middle index: the same
      // number of kept vertices then bounds a much smaller deviation (about half the Hausdorff
      // distance of the Fandisk levels, whose largest errors sit on long curved chains).
      double worst = 0;
      Index m = (node.I + node.J) / 2;
      for (Index k = node.I + 1; k < node.J; ++k)
      {
        const double d2 = surfaceWeighted ? SurfaceWeightedDistance2(mesh.Point(v[k]), a, b, n1, n2, lambda2) : PointSegmentDistance2(mesh.Point(v[k]), a, b);
        if (d2 > worst)
        {
          worst = d2;
          m = k;
        }
      }
      // Kept when epsilon < key: refined only if this sub-chain and all its ancestors are off.
      const float key = std::min(static_cast<float>(std::sqrt(worst)), node.ParentKey);
      this->Keys[offset + size_t(m)] = key;
      this->SortedKeys.push_back(key);
      stack.push_back({ node.I, m, key });
      stack.push_back({ m, node.J, key });
    }
  }
  std::sort(this->SortedKeys.begin(), this->SortedKeys.end(), std::greater<float>());
}

void SpbmLevelGenerator::OrderChainKeys(size_t totalVertices)
{
  const Patchification& P = *this->Patches;
  const Index nc = P.NumberOfChains();
  // Per chain, its interior positions by decreasing key: the vertices kept for any epsilon are a
  // prefix (found by binary search).
  this->KeyOrder.assign(totalVertices, 0);
  this->OrderedKeys.assign(totalVertices, InfiniteKey);
  for (Index c = 0; c < nc; ++c)
  {
    const size_t offset = size_t(P.ChainVerticesBegin(c) - P.ChainVerticesBegin(0));
    const Index n = P.ChainSize(c);
    Index* order = this->KeyOrder.data() + offset;
    for (Index i = 1; i + 1 < n; ++i)
    {
      order[i - 1] = i;
    }
    const float* keys = this->Keys.data() + offset;
    std::stable_sort(order, order + std::max<Index>(0, n - 2), [&](Index x, Index y) { return keys[x] > keys[y]; });
    for (Index i = 0; i + 2 < n; ++i)
    {
      this->OrderedKeys[offset + i] = keys[order[i]];
    }
  }
}

void SpbmLevelGenerator::MarkParallelChains()
{
  const Patchification& P = *this->Patches;
  const Index nc = P.NumberOfChains();
  // Parallel chains (same two endpoints) bound a lens; all but one keep an interior vertex so
  // that no patch degenerates to two vertices and no two chains become the same edge.
  this->MinimumInterior.assign(size_t(nc), 0);
  {
    // Chains ordered by (endpoint pair, size, id), the sort keys gathered first: a comparison
    // that reads them through the patchification was 3% of the MRI crop's instructions.
    struct ChainOrder
    {
      uint64_t Pair; // smaller endpoint in the high half
      Index Size, Chain;
      bool operator<(const ChainOrder& o) const
      {
        return Pair != o.Pair ? Pair < o.Pair : (Size != o.Size ? Size < o.Size : Chain < o.Chain);
      }
    };
    std::vector<ChainOrder> order(static_cast<size_t>(nc));
    for (Index c = 0; c < nc; ++c)
    {
      const Index a = P.ChainStart(c), b = P.ChainEnd(c);
      order[c] = { (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b)), P.ChainSize(c), c };
    }
    std::sort(order.begin(), order.end());
    for (size_t i = 0; i < order.size();)
    {
      size_t j = i + 1;
      while (j < order.size() && order[j].Pair == order[i].Pair)
      {
        ++j;
      }
      for (size_t k = i + 1; k < j; ++k) // the shortest of the group may stay one segment
      {
        if (order[k].Size > 2)
        {
          this->MinimumInterior[order[k].Chain] = 1;
        }
      }
      i = j;
    }
  }
}

void SpbmLevelGenerator::MeasureEndpointVariation()
{
  const Patchification& P = *this->Patches;
  const Index nc = P.NumberOfChains();
  const Index ne = P.NumberOfEndpoints();
  // Endpoint coordinates in one array: the merging runs read them for every try, and the
  // double indirection through the mesh's vertex ids missed the cache (9% of a run on MRI/3).
  this->EndpointPoints.resize(size_t(ne));
  for (Index e = 0; e < ne; ++e)
  {
    this->EndpointPoints[e] = this->Mesh->Point(P.EndpointVertex(e));
  }
  // Normal variation around each endpoint: the largest angle between the patches meeting there.
  this->EndpointVariation.assign(size_t(ne), 0.0);
  for (Index c = 0; c < nc; ++c)
  {
    if (P.ChainRightPatch(c) == InvalidIndex)
    {
      continue;
    }
    const double variation = 1.0 - Dot(P.PatchNormal(P.ChainLeftPatch(c)), P.PatchNormal(P.ChainRightPatch(c)));
    for (const Index e : { P.ChainStart(c), P.ChainEnd(c) })
    {
      this->EndpointVariation[e] = std::max(this->EndpointVariation[e], variation);
    }
  }
}

Index SpbmLevelGenerator::KeptInterior(Index c, float tolerance) const
{
  const Index m = std::max<Index>(0, this->Patches->ChainSize(c) - 2);
  const float* ordered =
    this->OrderedKeys.data() + (this->Patches->ChainVerticesBegin(c) - this->Patches->ChainVerticesBegin(0));
  const Index interior = static_cast<Index>(
    std::partition_point(ordered, ordered + m, [&](float k) { return k > tolerance; }) - ordered);
  return interior == 0 && m > 0 && this->MinimumInterior[c] ? 1 : interior;
}

double SpbmLevelGenerator::ChainVertexKey(Index c, Index i) const
{
  const size_t offset = size_t(this->Patches->ChainVerticesBegin(c) - this->Patches->ChainVerticesBegin(0));
  return this->Keys[offset + size_t(i)];
}

size_t SpbmLevelGenerator::MemoryUsage() const
{
  size_t bytes = this->Keys.capacity() * 4 + this->SortedKeys.capacity() * 4 + this->KeyOrder.capacity() * 4 + this->OrderedKeys.capacity() * 4 + this->MinimumInterior.capacity() +
    this->EndpointVariation.capacity() * 8 + this->EndpointPoints.capacity() * sizeof(Vec3);
  auto b = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  bytes += b(this->PatchSupport);
  for (const State* state : { this->Work.get(), this->Helper.get() }) // one working state per candidate thread
  {
    const State& s = *state;
    bytes += b(s.Chains) + b(s.Parts) + b(s.Patches) + b(s.Tolerance) +
      b(s.KeptPositions) + b(s.KeptTolerance) + b(s.KeptLocked) + b(s.RefinedTolerance) + b(s.RefinedLocked) +
      b(s.JointBefore) + b(s.EndHead) + b(s.EndSlotNext) +
      b(s.Degree) + b(s.PatchSlotNext) + b(s.Tries) + b(s.CollapsesWalkedSize) + b(s.CandidatesPushedSize) + b(s.Support) + b(s.SupportWritten) + b(s.SupportWrittenFlag) + b(s.Frozen) +
      b(s.PatchStamp) + b(s.EndStamp) + b(s.EndLocal) + b(s.VertexStamp) + s.MergeQueue.MemoryBytes() + b(s.NoFreeze) +
      b(s.SeqOffsets) + b(s.SeqVertices) + b(s.SeqKeep) + s.Edges.MemoryUsage() + s.DiagonalCosts.MemoryUsage() +
      b(s.SimpleSignature) + s.BoundaryOutcomes.MemoryUsage() + b(s.Memo) + b(s.Edits) + b(s.EditsSpare) + s.RemovalQueue.MemoryBytes() + b(s.EditsTolerance) + b(s.EditsLocked) +
      b(s.EditsFrozen) + b(s.DirtyPatch) + b(s.DirtyEnd) + b(s.DirtyNear);
  }
  for (const TriangleBVH* tree : { this->InputTree.get(), this->BuiltTree.get() })
  {
    if (tree)
    {
      // Nodes, leaf order and the 9 leaf-ordered corner coordinates per triangle.
      bytes += b(tree->GetNodes()) + b(tree->GetOrder()) + tree->GetOrder().size() * 9 * sizeof(double);
    }
  }
  return bytes;
}

void SpbmLevelGenerator::BuildInputTreeDuring(const TriangleMesh& mesh, const std::function<void()>& work)
{
  {
    std::lock_guard<std::mutex> lock(this->LazyMutex);
    this->InputTree.reset();
    this->BuiltTree.reset();
    this->TreeMesh = &mesh;
  }
  std::unique_ptr<TriangleBVH> tree;
  RunTasks(2, [&](int task) {
    if (task == 0)
    {
      tree = std::make_unique<TriangleBVH>(mesh);
    }
    else
    {
      work();
    }
  });
  std::lock_guard<std::mutex> lock(this->LazyMutex);
  this->BuiltTree = std::move(tree);
}

const TriangleBVH& SpbmLevelGenerator::GetInputTree(StageTimes& times)
{
  // Built on first use (a non-planar patch), by whichever candidate thread needs it first.
  std::lock_guard<std::mutex> lock(this->LazyMutex);
  if (!this->InputTree && this->BuiltTree)
  {
    // Taken from BuildInputTreeDuring on first use: until then EstimateDeviation measures one
    // side only, as when the tree is built here.
    this->InputTree = std::move(this->BuiltTree);
  }
  if (!this->InputTree)
  {
    const auto started = StageClock::now();
    this->InputTree.reset(new TriangleBVH(*this->Mesh));
    times.Tree += Since(started);
  }
  return *this->InputTree;
}

Index SpbmLevelGenerator::PredictTriangleCount(const SpbmLevelParameters& parameters)
{
  return this->PredictTriangleCountIn(parameters, *this->Work);
}

SpbmLevelGenerator::PredictionMemo SpbmLevelGenerator::PredictionMemo::Of(const SpbmLevelParameters& parameters)
{
  return { static_cast<float>(parameters.Epsilon), parameters.MergeAngle, parameters.MergePatches,
    parameters.CollapseChains, parameters.CollapseLengthFactor, parameters.JoinWithinEpsilon,
    parameters.CollapseWithinEpsilon, parameters.SizeWeightedMerge, parameters.FlatnessMerge,
    parameters.FlatnessScale, parameters.MaximumPatchThickness, parameters.RemovalTarget, 0 };
}

bool SpbmLevelGenerator::PredictionMemo::SameLevel(const PredictionMemo& m) const
{
  return m.Epsilon == this->Epsilon && m.MergeAngle == this->MergeAngle && m.MergePatches == this->MergePatches &&
    m.CollapseChains == this->CollapseChains && m.CollapseLengthFactor == this->CollapseLengthFactor &&
    m.JoinWithinEpsilon == this->JoinWithinEpsilon && m.CollapseWithinEpsilon == this->CollapseWithinEpsilon &&
    m.SizeWeightedMerge == this->SizeWeightedMerge && m.FlatnessMerge == this->FlatnessMerge &&
    m.FlatnessScale == this->FlatnessScale && m.MaximumPatchThickness == this->MaximumPatchThickness &&
    m.RemovalTarget == this->RemovalTarget;
}

bool SpbmLevelGenerator::RememberedCount(const SpbmLevelParameters& parameters, const State& s, Index& count)
{
  const PredictionMemo key = PredictionMemo::Of(parameters);
  for (const PredictionMemo& m : s.Memo)
  {
    if (key.SameLevel(m))
    {
      count = m.Count;
      return true;
    }
  }
  return false;
}

Index SpbmLevelGenerator::PredictTriangleCountIn(const SpbmLevelParameters& parameters, State& s)
{
  // Searches (and re-aimed searches) ask for the same levels again: remember the answers.
  PredictionMemo key = PredictionMemo::Of(parameters);
  if (RememberedCount(parameters, s, key.Count))
  {
    return key.Count;
  }
  s.NoFreeze.assign(size_t(this->Patches->NumberOfPatches()), 0);
  const auto started = StageClock::now();
  PredictionMemo merged = key;
  merged.RemovalTarget = 0;
  if (parameters.RemovalTarget > 0 && s.HoldsPrediction && s.Holds.SameLevel(merged))
  {
    // The search asks for the removal right after the merging at the same parameters (the
    // count at RemovalMergeAngle decides whether it is needed): only the removal stage runs.
    this->ContinueWithRemoval(parameters, s);
  }
  else
  {
    this->RunMerging(parameters, s.NoFreeze, s);
    if (s.Cancelled)
    {
      s.Cancelled = false;
      s.Times.Merging += Since(started);
      return -1;
    }
  }
  s.Times.Merging += Since(started);
  ++s.Times.MergingRuns;
  if (s.Memo.size() > 256)
  {
    s.Memo.clear();
  }
  key.Count = static_cast<Index>(s.Total);
  s.Memo.push_back(key);
  s.Holds = key;
  s.HoldsPrediction = true;
  return key.Count;
}

Index SpbmLevelGenerator::FinestLevelLowerBound() const
{
  // A level has sum over root patches of (boundary size - 2) triangles. Two bounds: (1) a
  // boundary counts the kept interior vertices of its chains on each side (interior vertices are
  // never removed at full resolution: merges and collapses take one-segment chains, a join keeps
  // both chains' vertices) plus at least one endpoint (a root has at least one chain), and there
  // are at most as many roots as patches: at least (interior vertices - 1) per root; (2) merges
  // keep the count and every collapse or join removes one endpoint not on the border (two
  // triangles) from the unmerged patches' count.
  const Patchification& P = *this->Patches;
  long long interiorBound = -(long long)P.NumberOfPatches();
  long long endpointBound = -2 * (long long)P.NumberOfPatches();
  for (Index c = 0; c < P.NumberOfChains(); ++c)
  {
    const long long sides = P.ChainRightPatch(c) != InvalidIndex ? 2 : 1;
    interiorBound += sides * std::max<Index>(0, P.ChainSize(c) - 2);
    endpointBound += sides * std::max<Index>(1, P.ChainSize(c) - 1);
  }
  for (Index e = 0; e < P.NumberOfEndpoints(); ++e)
  {
    endpointBound -= P.EndpointOnBorder(e) ? 0 : 2;
  }
  const long long bound = std::max(interiorBound, endpointBound);
  return static_cast<Index>(std::max(0LL, std::min<long long>(bound, std::numeric_limits<Index>::max())));
}

Index SpbmLevelGenerator::FinestLevelCount(const SpbmLevelParameters& parameters)
{
  // The merging run of this level was a whole run over every chain vertex, super-linear on noisy
  // scans (its boundary tests and refinement rounds: 38 s of noisy:273's level under load) only
  // to learn a count that merges cannot change.
  const Index count = this->FinestLevelCountWithoutRun(parameters);
  return count >= 0 ? count : this->PredictTriangleCount(parameters);
}

Index SpbmLevelGenerator::FinestLevelCountWithoutRun(const SpbmLevelParameters& parameters) const
{
  if (!(parameters.Epsilon < 0) || !parameters.JoinWithinEpsilon || !parameters.CollapseWithinEpsilon ||
    parameters.RemovalTarget > 0)
  {
    return -1;
  }
  const Patchification& P = *this->Patches;
  long long count = -2LL * P.NumberOfPatches();
  for (Index c = 0; c < P.NumberOfChains(); ++c)
  {
    const long long sides = P.ChainRightPatch(c) != InvalidIndex ? 2 : 1;
    count += sides * (P.ChainSize(c) - 1);
  }
  return static_cast<Index>(std::max(0LL, std::min<long long>(count, std::numeric_limits<Index>::max())));
}

int SpbmLevelGenerator::MergingRunCount() const
{
  return this->Work->Times.MergingRuns;
}

void SpbmLevelGenerator::RenewHelper()
{
  const bool spare = this->SpareState == this->Helper.get();
  this->Helper.reset(new State);
  // As Initialize sets it up.
  this->Helper->DiagonalCosts.TrackVertices(size_t(this->Mesh->NumberOfPoints()));
  this->Helper->DiagonalCosts.Reset(0);
  if (spare)
  {
    this->SpareState = this->Helper.get();
  }
}

int SpbmLevelGenerator::SideBySideProbeCount() const
{
  return this->SideBySideProbes;
}

SpbmLevelParameters SpbmLevelGenerator::FindParameters(
  Index target, const SpbmLevelParameters& base, Index* predicted)
{
  return this->FindParametersIn(target, base, predicted, *this->Work);
}

SpbmLevelParameters SpbmLevelGenerator::FindParametersIn(
  Index target, const SpbmLevelParameters& base, Index* predicted, State& s)
{
  return TargetSearch(*this, target, base, s).Run(predicted);
}

bool SpbmLevelGenerator::Generate(
  const SpbmLevelParameters& parameters, SpbmLevel& level, const std::function<bool()>& abort)
{
  return this->GenerateIn(parameters, level, abort, *this->Work);
}

bool SpbmLevelGenerator::GenerateWithOriginalPatches(const SpbmLevelParameters& parameters,
  const std::vector<unsigned char>& original, SpbmLevel& level, const std::function<bool()>& abort,
  const SpbmLevel* from)
{
  std::unique_ptr<KeptPass> kept;
  if (from && this->LastPass && from->Generation == this->LastPass->Generation &&
    PredictionMemo::Of(this->LastPass->Parameters).SameLevel(PredictionMemo::Of(parameters)) &&
    this->LastPass->Frozen.size() == original.size())
  {
    kept = std::move(this->LastPass); // consumed: its memory goes on in the new level's passes
  }
  return this->GenerateIn(parameters, level, abort, *this->Work, 0, &original, kept.get());
}

void SpbmLevelGenerator::KeepLastPass(bool keep)
{
  this->KeepPasses = keep;
  if (!keep)
  {
    this->LastPass.reset();
  }
}

void SpbmLevelGenerator::DropKeptPass()
{
  this->LastPass.reset();
}

bool SpbmLevelGenerator::GenerateIn(const SpbmLevelParameters& parameters, SpbmLevel& level,
  const std::function<bool()>& abort, State& s, Index budget, const std::vector<unsigned char>* original,
  KeptPass* resume)
{
  const Index np = this->Patches->NumberOfPatches();
  s.VertexStamp.resize(size_t(this->Mesh->NumberOfPoints()), 0);
  std::vector<unsigned char> frozen(size_t(np), 0);
  if (resume)
  {
    frozen.swap(resume->Frozen); // the kept pass's fallback levels: its next pass goes on from them
  }
  bool anyOriginal = false; // the held chain graph (no frozen patch) is not this level's then
  for (Index p = 0; p < np; ++p)
  {
    if (original && p < Index(original->size()) && (*original)[size_t(p)])
    {
      frozen[size_t(p)] = OriginalLevel;
    }
    anyOriginal = anyOriginal || frozen[size_t(p)] != 0;
  }
  level = SpbmLevel();
  level.Generation = &s == this->Work.get() ? ++this->Generations : 0; // a state is one thread's
  LevelTriangulation triangulation(*this, parameters, s, level);
  if (resume)
  {
    triangulation.SwapMemory(resume->Memory);
    level.Triangles.swap(resume->Triangles);
    level.TrianglePatch.swap(resume->TrianglePatch);
  }
  const StageTimes before = s.Times;
  const long long allocationsBefore = s.WorkspaceAllocations;
  // Each pass freezes at least one patch one level further (7 levels), except when it is aborted;
  // past that bound every patch keeps its original triangles.
  const int maxPasses = 2 * 64 + 2;
  bool unmergedAny = true; // the last pass unmerged a patch: the next one needs a new merging run
  for (int pass = 1;; ++pass)
  {
    if (abort && abort())
    {
      return false;
    }
    level.Passes = pass;
    if (pass > maxPasses)
    {
      std::fill(frozen.begin(), frozen.end(), OriginalLevel); // last resort: the input itself
      unmergedAny = true;
    }
    // The search's last prediction is usually this level's first pass: its chain graph is
    // still in the state (the merging run depends on the parameters and frozen patches only).
    const auto passStart = StageClock::now();
    const bool held =
      pass == 1 && !anyOriginal && s.HoldsPrediction && s.Holds.SameLevel(PredictionMemo::Of(parameters));
    s.BoundariesTested = -1;
    level.PassDirtyPatches.push_back(-1);
    if (!held && unmergedAny && parameters.ReplayFallbackPasses && this->ReplayMerging(parameters, frozen, s))
    {
      ++level.ReplayedPasses;
      level.EditsAppliedAsRecorded += s.AppliedAsRecorded;
      level.EditsTestedAgain += s.TestedAgain;
      level.PassDirtyPatches.back() = s.DirtyAtStart;
    }
    else if (!held && unmergedAny)
    {
      this->RunMerging(parameters, frozen, s);
    }
    else if (!held)
    {
      this->RefineFrozenInPlace(parameters, frozen, s);
    }
    level.PassBoundaryTests.push_back(s.BoundariesTested);
    const double mergingSeconds = Since(passStart);
    if (pass == 1)
    {
      level.PredictedTriangles = static_cast<Index>(s.Total);
    }
    if (budget > 0 && s.Total > budget)
    {
      vtkLogF(TRACE, "[spbm] candidate abandoned in pass %d: %lld triangles over the budget of %d", pass, s.Total,
        int(budget));
      level.Triangles.clear();
      level.TrianglePatch.clear();
      return true;
    }
    const auto triangulationStart = StageClock::now();
    if (!triangulation.RunPass(frozen, abort))
    {
      return false;
    }
    const bool anyFailed = triangulation.FreezeFailedPatches(frozen, unmergedAny);
    vtkLogF(TRACE,
      "[spbm] pass %d: merging %.4f s (%lld triangles), triangulation %.4f s, %d patches failed, %lld diagonals "
      "measured (%lld ahead); %d patches triangulated ahead (%d again); so far %d patches triangulated again, %d "
      "contexts compared, %d kept untouched",
      pass, mergingSeconds, s.Total, Since(triangulationStart), int(triangulation.FailedPatches()),
      (long long)level.DiagonalsMeasured, (long long)level.DiagonalsMeasuredAhead, int(level.TriangulatedAhead),
      int(level.TriangulatedAgain), int(level.RetriangulatedPatches), int(level.ContextsCompared),
      int(level.ReusedUntouched));
    if (!anyFailed)
    {
      break;
    }
    if (budget > 0)
    {
      // A try without a search (budget) gets one pass: every fallback pass is a whole merging
      // run, and on rough surfaces (scan isosurfaces) tries needed 3-9 of them only to be
      // rejected. The first level of a target pays for its fallbacks; the alternatives do not.
      vtkLogF(TRACE, "[spbm] candidate abandoned after pass %d: patches failed to triangulate", pass);
      level.Triangles.clear();
      level.TrianglePatch.clear();
      return true;
    }
  }
  if (this->KeepPasses && budget == 0 && level.Generation > 0)
  {
    auto kept = std::make_unique<KeptPass>();
    kept->Generation = level.Generation;
    kept->Parameters = parameters;
    kept->Frozen = frozen;
    kept->Triangles = level.Triangles;
    kept->TrianglePatch = level.TrianglePatch;
    triangulation.SwapMemory(kept->Memory);
    this->LastPass = std::move(kept);
  }
  triangulation.Finish(frozen);
  level.ChainRebuilds = s.Times.ChainRebuilds - before.ChainRebuilds;
  level.WalkedChains = s.Times.WalkedChains - before.WalkedChains;
  level.WalkSideFinds = s.Times.WalkSideFinds - before.WalkSideFinds;
  level.SupportUnions = s.Times.SupportUnions - before.SupportUnions;
  level.SupportFolds = s.Times.SupportFolds - before.SupportFolds;
  level.WorkspaceAllocations = s.WorkspaceAllocations - allocationsBefore;
  vtkLogF(TRACE, "[spbm] generated %d triangles (predicted %d) in %d passes; fallback patches: %d unmerged, %d refined, %d original",
    int(level.TrianglePatch.size()), int(level.PredictedTriangles), level.Passes, int(level.UnmergedPatches),
    int(level.RefinedPatches), int(level.OriginalPatches));
  return true;
}

namespace
{
// The level over its own vertices only (it is small), to be put in a BVH.
void LevelOverItsVertices(const TriangleMesh& mesh, const SpbmLevel& level, TriangleMesh& simplified)
{
  std::vector<Index> local(size_t(mesh.NumberOfPoints()), InvalidIndex);
  simplified.Triangles.reserve(level.Triangles.size());
  for (const Index v : level.Triangles)
  {
    if (local[v] == InvalidIndex)
    {
      local[v] = simplified.NumberOfPoints();
      const Vec3 p = mesh.Point(v);
      simplified.Points.insert(simplified.Points.end(), p.begin(), p.end());
    }
    simplified.Triangles.push_back(local[v]);
  }
}
} // namespace

Index SpbmLevelGenerator::PatchDeviationsFromVertices(
  const std::vector<float>& beyond, std::vector<double>& patchDeviation) const
{
  const TriangleMesh& mesh = *this->Mesh;
  patchDeviation.assign(size_t(this->Patches->NumberOfPatches()), 0.0);
  const bool any = std::any_of(beyond.begin(), beyond.end(), [](float d) { return d > 0; });
  Index count = 0;
  const std::vector<Index>& patchOf = this->Patches->TrianglePatches();
  for (Index t = 0; any && t < mesh.NumberOfTriangles() && Index(beyond.size()) == mesh.NumberOfPoints(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    const double worst = std::max({ beyond[size_t(tri[0])], beyond[size_t(tri[1])], beyond[size_t(tri[2])] });
    double& patch = patchDeviation[size_t(patchOf[size_t(t)])];
    count += worst > 0 && patch == 0 ? 1 : 0;
    patch = std::max(patch, worst);
  }
  return count;
}

// EstimateDeviation's running tally: the largest squared distance of every sample and, when some
// of the farthest input samples are left out, the `Keep` largest distances of the input's samples
// (vertices and strided centroids; a min-heap) and the largest of the level's own samples. A query
// is bounded by what can still change a result.
class DeviationTally
{
public:
  explicit DeviationTally(size_t keep)
    : Keep(keep)
  {
    this->Largest.reserve(keep);
  }
  // Samples within this (squared) distance change nothing.
  double Bound2(bool inputSample) const
  {
    if (this->Keep == 0)
    {
      return this->Worst2;
    }
    const double kept = this->Largest.size() == this->Keep ? this->Largest.front() : 0.0;
    return inputSample ? kept : std::max(this->Other2, kept);
  }
  void Add(double d2, bool inputSample)
  {
    this->Worst2 = std::max(this->Worst2, d2);
    if (this->Keep == 0)
    {
      return;
    }
    if (!inputSample)
    {
      this->Other2 = std::max(this->Other2, d2);
      return;
    }
    const auto later = std::greater<double>();
    if (this->Largest.size() < this->Keep)
    {
      this->Largest.push_back(d2);
      std::push_heap(this->Largest.begin(), this->Largest.end(), later);
    }
    else if (d2 > this->Largest.front())
    {
      std::pop_heap(this->Largest.begin(), this->Largest.end(), later);
      this->Largest.back() = d2;
      std::push_heap(this->Largest.begin(), this->Largest.end(), later);
    }
  }
  double Worst2 = 0;
  // The largest squared distance with the Keep - 1 farthest vertices left out.
  double WithoutFarthest2() const { return this->Bound2(false); }

private:
  const size_t Keep; // 0: no vertex left out (one running maximum)
  double Other2 = 0; // the level's own samples (and, with none left out, the centroids)
  std::vector<double> Largest;
};

namespace
{
// Adds q's squared distance from `bvh` to the tally when it can change a result. Only samples
// farther than the tally's bound matter: a query bounded by it prunes most of the tree and finds
// nothing exactly when the sample is farther (then it is measured).
// `hint` (optional): the BVH leaf to test first (TriangleBVH::AnyWithin), for neighbouring points.
void RaiseToDistance(
  const TriangleBVH& bvh, const Vec3& q, DeviationTally& tally, bool inputSample = true, Index* hint = nullptr)
{
  const double bound2 = tally.Bound2(inputSample);
  Index none = InvalidIndex;
  if (bound2 > 0 && bvh.AnyWithin(q, bound2, hint ? *hint : none))
  {
    return;
  }
  tally.Add(bvh.ClosestPoint(q).Distance2, inputSample);
}

// The level triangle `v` (three input vertex ids) sampled on the barycentric grid of step
// 1/`steps` (without the corners, input vertices) against the input's `bvh`: the level's side of
// the deviation.
void RaiseToTriangleDistance(
  const TriangleBVH& bvh, const TriangleMesh& mesh, const Index* v, DeviationTally& tally, int steps = 3)
{
  const Vec3 a = mesh.Point(v[0]), b = mesh.Point(v[1]), c = mesh.Point(v[2]);
  const double step = 1.0 / double(steps);
  for (int i = 0; i <= steps; ++i)
  {
    for (int j = 0; i + j <= steps; ++j)
    {
      const int k = steps - i - j;
      if (i == steps || j == steps || k == steps)
      {
        continue; // a corner
      }
      RaiseToDistance(bvh, (step * i) * a + (step * j) * b + (step * k) * c, tally, false);
    }
  }
}

// The triangles of `a` that are not in `b` (as vertex sets), appended to `out`.
void TrianglesNotIn(const std::vector<Index>& a, const std::vector<Index>& b, std::vector<Index>& out)
{
  using Key = std::array<Index, 3>;
  auto keys = [](const std::vector<Index>& triangles) {
    std::vector<Key> sorted(triangles.size() / 3);
    for (size_t t = 0; t < sorted.size(); ++t)
    {
      sorted[t] = { triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2] };
      std::sort(sorted[t].begin(), sorted[t].end());
    }
    std::sort(sorted.begin(), sorted.end());
    return sorted;
  };
  const std::vector<Key> ka = keys(a), kb = keys(b);
  std::vector<Key> only;
  std::set_difference(ka.begin(), ka.end(), kb.begin(), kb.end(), std::back_inserter(only));
  for (const Key& k : only)
  {
    out.insert(out.end(), k.begin(), k.end());
  }
}
} // namespace

void SpbmLevelGenerator::StridedDeviation(
  const TriangleBVH& bvh, Index samples, bool centroidsOnly, DeviationTally& tally) const
{
  // The first vertex and the centroid of every stride-th original triangle (every vertex is the
  // first of some triangle, so all are covered at full sampling).
  const TriangleMesh& mesh = *this->Mesh;
  const Index nt = mesh.NumberOfTriangles();
  const Index stride = std::max<Index>(1, nt / std::max<Index>(1, samples / 2));
  for (Index t = 0; t < nt; t += stride)
  {
    const Index* v = mesh.Triangle(t);
    const Vec3 a = mesh.Point(v[0]), b = mesh.Point(v[1]), c = mesh.Point(v[2]);
    if (!centroidsOnly)
    {
      RaiseToDistance(bvh, a, tally);
    }
    // A centroid is a sample of the input like a vertex: next to the farthest vertices it is as far
    // (noisy388's level: 1.11x the bound at one centroid, 0.87x without the 99 farthest vertices).
    RaiseToDistance(bvh, (1.0 / 3.0) * (a + b + c), tally, centroidsOnly);
  }
}

double SpbmLevelGenerator::EstimateDeviation(const SpbmLevel& level, Index samples, bool everyVertex,
  std::vector<float>* beyond, double allowance, Index farthestLeftOut, double* withoutFarthest) const
{
  const TriangleMesh& mesh = *this->Mesh;
  if (mesh.NumberOfTriangles() == 0 || level.Triangles.empty())
  {
    return 0;
  }
  TriangleMesh simplified;
  LevelOverItsVertices(mesh, level, simplified);
  const TriangleBVH bvh(simplified);
  // With input samples left out (every vertex sampled), the strided vertices are left to that pass.
  const bool leaveOut = everyVertex && farthestLeftOut > 0;
  DeviationTally tally(leaveOut ? size_t(farthestLeftOut) + 1 : 0);
  this->StridedDeviation(bvh, samples, leaveOut, tally);
  if (beyond)
  {
    beyond->assign(everyVertex ? size_t(mesh.NumberOfPoints()) : 0, 0.0f);
  }
  const double allowance2 = allowance * allowance;
  // Consecutive input vertices are mostly neighbours: each query first tests the BVH leaf that
  // answered the previous one (the same answers, many without a walk from the root).
  Index hint = InvalidIndex;
  for (Index v = 0; everyVertex && v < mesh.NumberOfPoints(); ++v)
  {
    const Vec3 q = mesh.Point(v);
    if (!beyond || !(allowance > 0))
    {
      RaiseToDistance(bvh, q, tally, true, &hint);
    }
    else if (bvh.AnyWithin(q, allowance2, hint))
    {
      if (allowance2 > tally.Bound2(true)) // within the allowance, but it may still count
      {
        RaiseToDistance(bvh, q, tally, true, &hint);
      }
    }
    else
    {
      const double d2 = bvh.ClosestPoint(q).Distance2;
      (*beyond)[size_t(v)] = static_cast<float>(std::sqrt(d2));
      tally.Add(d2, true);
    }
  }
  this->LevelSideDeviation(level, tally);
  if (withoutFarthest)
  {
    *withoutFarthest = std::sqrt(leaveOut ? tally.WithoutFarthest2() : tally.Worst2);
  }
  return std::sqrt(tally.Worst2);
}

double SpbmLevelGenerator::EstimateDeviationNear(const SpbmLevel& level, const SpbmLevel& from,
  const std::vector<float>& fromBeyond, double allowance, Index samples, Index* measured) const
{
  const TriangleMesh& mesh = *this->Mesh;
  if (mesh.NumberOfTriangles() == 0 || level.Triangles.empty() || from.Triangles.empty() ||
    Index(fromBeyond.size()) != mesh.NumberOfPoints() || !(allowance > 0) || !std::isfinite(allowance))
  {
    return this->EstimateDeviation(level, samples, true);
  }
  TriangleMesh simplified;
  LevelOverItsVertices(mesh, level, simplified);
  const TriangleBVH bvh(simplified);
  DeviationTally tally(0);
  this->StridedDeviation(bvh, samples, false, tally);
  // The vertices beyond the allowance from `from` (few): measured.
  Index count = 0, hint = InvalidIndex;
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    if (fromBeyond[size_t(v)] > 0)
    {
      ++count;
      RaiseToDistance(bvh, mesh.Point(v), tally, true, &hint);
    }
  }
  // The others lie within the allowance of a triangle of `from`: they can only be beyond it now
  // when that triangle is gone, i.e. when a triangle of `from` missing from `level` is within the
  // allowance (the triangles `level` added only bring vertices closer). Those are found from the
  // removed triangles, over a grid of the input's vertices: the work follows the changed places.
  std::vector<Index> removed;
  TrianglesNotIn(from.Triangles, level.Triangles, removed);
  const double reach = allowance * (1.0 + 1e-6) + 1e-12 * this->Diagonal;
  // Each removed triangle's box grown by the reach (lo, hi), and its half extent (the grid's query).
  const size_t nr = removed.size() / 3;
  std::vector<Vec3> lo(nr), hi(nr);
  std::vector<double> half(nr);
  for (size_t t = 0; t < nr; ++t)
  {
    const Vec3 a = mesh.Point(removed[3 * t]), b = mesh.Point(removed[3 * t + 1]), c = mesh.Point(removed[3 * t + 2]);
    for (int k = 0; k < 3; ++k)
    {
      lo[t][k] = std::min({ a[k], b[k], c[k] }) - reach;
      hi[t][k] = std::max({ a[k], b[k], c[k] }) + reach;
      half[t] = std::max(half[t], 0.5 * (hi[t][k] - lo[t][k]));
    }
  }
  if (nr > 0)
  {
    std::vector<double> cells(half);
    std::nth_element(cells.begin(), cells.begin() + std::ptrdiff_t(nr / 2), cells.end());
    PointGrid grid;
    grid.Build(mesh.Points, 2 * cells[nr / 2]);
    std::vector<unsigned char> near(size_t(mesh.NumberOfPoints()), 0);
    for (size_t t = 0; t < nr; ++t)
    {
      const Vec3 a = mesh.Point(removed[3 * t]), b = mesh.Point(removed[3 * t + 1]), c = mesh.Point(removed[3 * t + 2]);
      const Vec3 centre = 0.5 * (lo[t] + hi[t]);
      grid.ForEachNear(centre.data(), half[t], [&](Index v) {
        const Vec3 q = mesh.Point(v);
        if (near[size_t(v)] || fromBeyond[size_t(v)] > 0 || q[0] < lo[t][0] || q[0] > hi[t][0] || q[1] < lo[t][1] ||
          q[1] > hi[t][1] || q[2] < lo[t][2] || q[2] > hi[t][2])
        {
          return;
        }
        const Vec3 d = ClosestPointOnTriangle(q, a, b, c) - q;
        if (Dot(d, d) <= reach * reach)
        {
          near[size_t(v)] = 1;
          ++count;
          RaiseToDistance(bvh, q, tally, true, &hint);
        }
      });
    }
  }
  if (measured)
  {
    *measured = count;
  }
  this->LevelSideDeviation(level, tally);
  return std::sqrt(tally.Worst2);
}

void SpbmLevelGenerator::LevelSideDeviation(const SpbmLevel& level, DeviationTally& tally) const
{
  // The other side, when the input's BVH exists (the minimum-deviation triangulation builds it):
  // the level's largest triangles sampled on the barycentric grid of step 1/3 (the edge thirds
  // and the centroid; the corners are input vertices) against the input. A flat triangle across a
  // concave region can lie far from the input while every input sample is close to some other
  // part of the level (the Fandisk at 150: 0.032 one-sided, 0.041 both ways).
  const TriangleMesh& mesh = *this->Mesh;
  const TriangleBVH* input = nullptr;
  {
    std::lock_guard<std::mutex> lock(this->LazyMutex);
    input = this->InputTree.get();
  }
  if (!input)
  {
    return;
  }
  // Budget: the 160 largest triangles (a flat triangle strays the farther the larger it is).
  const size_t count = level.Triangles.size() / 3;
  std::vector<std::pair<double, Index>> bySize(count);
  for (size_t t = 0; t < count; ++t)
  {
    const Vec3 a = mesh.Point(level.Triangles[3 * t]), b = mesh.Point(level.Triangles[3 * t + 1]),
               c = mesh.Point(level.Triangles[3 * t + 2]);
    bySize[t] = { -Norm(Cross(b - a, c - a)), static_cast<Index>(t) };
  }
  const size_t budget = std::min<size_t>(count, 160);
  std::nth_element(bySize.begin(), bySize.begin() + std::ptrdiff_t(budget) - (budget > 0 ? 1 : 0), bySize.end());
  for (size_t k = 0; k < budget; ++k)
  {
    RaiseToTriangleDistance(*input, mesh, level.Triangles.data() + 3 * size_t(bySize[k].second), tally);
  }
}

// The changed triangles are few: a finer grid than the largest triangles' (lion at 50%: the 1/3 grid
// missed the level side of its refined level, 1.21e-3 of the diagonal where it read under 9e-4).
constexpr int ChangedTriangleSteps = 6;

double SpbmLevelGenerator::ChangedTriangleDeviation(const SpbmLevel& level, const SpbmLevel& other) const
{
  const TriangleBVH* input = nullptr;
  {
    std::lock_guard<std::mutex> lock(this->LazyMutex);
    input = this->InputTree.get();
  }
  if (!input)
  {
    return 0;
  }
  std::vector<Index> changed;
  TrianglesNotIn(level.Triangles, other.Triangles, changed);
  DeviationTally tally(0);
  for (size_t t = 0; t < changed.size(); t += 3) // bounded by the level's triangles
  {
    RaiseToTriangleDistance(*input, *this->Mesh, changed.data() + t, tally, ChangedTriangleSteps);
  }
  return std::sqrt(tally.Worst2);
}

// The candidate levels of one GenerateForTarget call and the one kept so far. While the helper
// thread runs, it writes only the Second* fields (CompareCandidates) or the tries it takes from
// NextTry; the calling thread reads them after joining it.
struct SpbmLevelGenerator::TargetCandidates
{
  TargetCandidates(Index target, const std::function<bool()>& abort)
    : Target(target)
    , Abort(abort)
  {
  }
  const Index Target;
  const std::function<bool()>& Abort;
  bool Compare = false; // CompareCandidates applies

  // The other merge measure of plain / size-weighted (CompareCandidates), on the helper thread.
  SpbmLevelParameters Second;
  SpbmLevel SecondLevel;
  bool SecondDone = true;
  double SecondDeviation = std::numeric_limits<double>::infinity();

  // The two other merge measures at the planned removal parameters (without CompareCandidates):
  // whichever thread is free takes the next.
  SpbmLevelParameters Tries[2];
  SpbmLevel TriedLevels[2];
  double TriedDeviations[2] = { std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity() };
  bool TriedFinished[2] = { false, false };
  std::atomic<int> NextTry{ 2 }; // none
  bool TriesPlanned = false;

  // The first level's triangle count and the level kept so far.
  Index FirstCount = 0;
  SpbmLevelParameters Best;
  double BestDeviation = 0.0;

  // Same budget: not above the target (or the first level's count), not far below it.
  bool SameBudget(Index produced) const
  {
    return !((produced > this->Target && produced > this->FirstCount) ||
      produced < std::min(this->FirstCount, this->Target) * 19 / 20);
  }
};

void SpbmLevelGenerator::DescribeCandidate(
  const char* what, const SpbmLevelParameters& p, Index produced, double deviation) const
{
  vtkLogF(TRACE,
    "[spbm] %s: weighted %d flat %d alpha1 %.1f eps %.4g factor %.2f join %d collapse %d removal %d: %d tris, "
    "estimate %.4g",
    what, int(p.SizeWeightedMerge), int(p.FlatnessMerge), p.MergeAngle, p.Epsilon / this->Diagonal,
    p.CollapseLengthFactor, int(p.JoinWithinEpsilon), int(p.CollapseWithinEpsilon), int(p.RemovalTarget),
    int(produced), deviation / this->Diagonal);
}

// Helper thread, CompareCandidates: the other one of plain / size-weighted, and when its count
// comes from the removal also the flatness measure; keeps the closer of the two in Second*.
void SpbmLevelGenerator::GenerateOtherMeasure(const SpbmLevelParameters& base, TargetCandidates& run)
{
  const auto helperStart = StageClock::now();
  this->Helper->Times = StageTimes();
  SpbmLevelParameters other = base;
  other.SizeWeightedMerge = !base.SizeWeightedMerge;
  other.FlatnessMerge = false;
  run.SecondDone =
    this->GenerateForTargetAndAngle(run.Target, other, run.SecondLevel, &run.Second, run.Abort, *this->Helper);
  if (run.SecondDone)
  {
    run.SecondDeviation = this->EstimateDeviation(run.SecondLevel);
  }
  if (run.SecondDone && run.Second.RemovalTarget > 0 && run.SecondLevel.Passes == 1)
  {
    // The count comes from the cost-ordered removal, so any merge measure reaches it at the
    // same parameters: also try the flatness measure (no search), keep the closer level. Like
    // the planned removal tries (RunPlannedTriesAfter), only when the level needed no fallback
    // pass: the try gets one pass, and where the level needed some (rough scans) the try's
    // pass failed too (hole-bump removal on noisy273 at 10%: a whole merging run, 9% of the
    // filter's CPU, then abandoned).
    SpbmLevelParameters flat = run.Second;
    flat.SizeWeightedMerge = false;
    flat.FlatnessMerge = true;
    SpbmLevel flatLevel;
    run.SecondDone = this->GenerateIn(flat, flatLevel, run.Abort, *this->Helper,
      std::max<Index>(run.Target, static_cast<Index>(run.SecondLevel.TrianglePatch.size())));
    const Index produced = static_cast<Index>(flatLevel.TrianglePatch.size());
    if (run.SecondDone && produced > 0 &&
      produced <= std::max<Index>(run.Target, static_cast<Index>(run.SecondLevel.TrianglePatch.size())))
    {
      const double deviation = this->EstimateDeviation(flatLevel);
      this->DescribeCandidate("flatness measure (helper)", flat, produced, deviation);
      if (deviation < run.SecondDeviation)
      {
        run.SecondDeviation = deviation;
        std::swap(run.SecondLevel, flatLevel);
        run.Second = flat;
      }
    }
  }
  LogStageTimes("candidates, second working state", Since(helperStart), this->Helper->Times);
}

// Without CompareCandidates: when the count will come from the cost-ordered removal, every merge
// measure reaches it at the same parameters without a search, so the two other measures are
// planned there too (the plan's search is memoized: the first level's search repeats it for
// free). Cheap next to a search; it matters at the coarsest levels, where the measure decides
// which large patches become flat. Returns whether tries were planned.
bool SpbmLevelGenerator::PlanRemovalTries(const SpbmLevelParameters& base, TargetCandidates& run)
{
  if (!base.MergePatches || !base.CostOrderedRemoval)
  {
    return false;
  }
  Index predicted = 0;
  const SpbmLevelParameters planned = this->FindParametersIn(run.Target, base, &predicted, *this->Work);
  if (!(planned.RemovalTarget > 0))
  {
    return false;
  }
  SpbmLevelParameters* tries = run.Tries;
  tries[0] = tries[1] = planned;
  tries[0].SizeWeightedMerge = !planned.SizeWeightedMerge || planned.FlatnessMerge;
  tries[0].FlatnessMerge = false;
  tries[1].SizeWeightedMerge = false;
  tries[1].FlatnessMerge = !planned.FlatnessMerge;
  if (!planned.FlatnessMerge && !planned.SizeWeightedMerge)
  {
    tries[1].FlatnessMerge = true; // plain first: weighted and flatness
  }
  run.NextTry = 0;
  run.TriesPlanned = true;
  return true;
}

// Generates the planned tries not yet taken by the other thread, in working state s.
void SpbmLevelGenerator::RunPlannedTries(TargetCandidates& run, State& s)
{
  for (int j = run.NextTry++; j < 2; j = run.NextTry++)
  {
    // Above the target a try cannot be kept (SameBudget) unless the first level overshoots too;
    // that count is not known yet on this thread, so the target bounds it (deterministically).
    run.TriedFinished[j] = this->GenerateIn(run.Tries[j], run.TriedLevels[j], run.Abort, s, run.Target);
    if (run.TriedFinished[j] && !run.TriedLevels[j].TrianglePatch.empty())
    {
      run.TriedDeviations[j] = this->EstimateDeviation(run.TriedLevels[j]);
    }
  }
}

// A narrower alpha1 for the plain measure (fewer merges, finer chains). Returns false when aborted.
bool SpbmLevelGenerator::TryNarrowerAngle(const SpbmLevelParameters& base, SpbmLevel& level, TargetCandidates& run)
{
  SpbmLevelParameters narrower = base;
  narrower.MergeAngle = 0.5 * base.MergeAngle;
  SpbmLevelParameters parameters;
  SpbmLevel candidate;
  if (!this->GenerateForTargetAndAngle(run.Target, narrower, candidate, &parameters, run.Abort, *this->Work))
  {
    return false;
  }
  const Index produced = static_cast<Index>(candidate.TrianglePatch.size());
  const double deviation = run.SameBudget(produced) ? this->EstimateDeviation(candidate) : run.BestDeviation;
  this->DescribeCandidate("narrower alpha1", parameters, produced, deviation);
  if (deviation < run.BestDeviation)
  {
    run.BestDeviation = deviation;
    std::swap(level, candidate);
    run.Best = parameters;
  }
  return true;
}

// CompareCandidates: keeps the helper's level when it has the same budget and is closer.
void SpbmLevelGenerator::KeepOtherMeasure(SpbmLevel& level, TargetCandidates& run)
{
  const Index produced = static_cast<Index>(run.SecondLevel.TrianglePatch.size());
  this->DescribeCandidate("other measure", run.Second, produced, run.SecondDeviation);
  if (run.SameBudget(produced) && run.SecondDeviation < run.BestDeviation)
  {
    run.BestDeviation = run.SecondDeviation;
    std::swap(level, run.SecondLevel);
    run.Best = run.Second;
  }
}

// The target is beyond what this measure reaches (unreachable counts: the femur, armadillo at
// 1%): the other measure may merge further; keeps the level closer to the target. Returns false
// when aborted. Like the removal tries, only after a first level that needed one generation pass:
// the try gets one pass, and where the first level needed fallback passes (rough scans) the try's
// pass failed too (noisy:137 at 10%: 1,002 failed patches, two merging runs, 18% of the filter).
bool SpbmLevelGenerator::TryOtherMeasureForUnreachedTarget(
  const SpbmLevelParameters& base, SpbmLevel& level, TargetCandidates& run)
{
  SpbmLevelParameters other = base;
  other.SizeWeightedMerge = !base.SizeWeightedMerge;
  other.FlatnessMerge = false;
  SpbmLevelParameters parameters;
  SpbmLevel candidate;
  // Kept only when below the first level's count: a try that goes above it, or needs fallback
  // passes (each a whole merging run, and on rough scans the unmerged patches add more triangles
  // than the other measure saved: noisy:137 at 10%, predicted 39,870, 133,944 after 10 passes,
  // 75 of the filter's 129 s), is abandoned.
  if (!this->GenerateForTargetAndAngle(run.Target, other, candidate, &parameters, run.Abort, *this->Work,
        std::max<Index>(1, run.FirstCount - 1)))
  {
    return false;
  }
  this->DescribeCandidate(
    "other measure (target not reached)", parameters, static_cast<Index>(candidate.TrianglePatch.size()), 0.0);
  if (!candidate.TrianglePatch.empty() && candidate.TrianglePatch.size() < level.TrianglePatch.size())
  {
    std::swap(level, candidate);
    run.Best = parameters;
  }
  return true;
}

// The planned tries: keeps the closest level of the same budget. Returns false when aborted.
bool SpbmLevelGenerator::KeepClosestTry(const SpbmLevelParameters& first, SpbmLevel& level, TargetCandidates& run)
{
  for (int i = 0; i < 2; ++i)
  {
    if (!run.TriedFinished[i])
    {
      return false; // aborted
    }
  }
  if (!run.Compare && run.BestDeviation == 0.0)
  {
    run.BestDeviation = this->EstimateDeviation(level);
    this->DescribeCandidate("first", first, run.FirstCount, run.BestDeviation);
  }
  for (int i = 0; i < 2; ++i)
  {
    const Index produced = static_cast<Index>(run.TriedLevels[i].TrianglePatch.size());
    this->DescribeCandidate("removal, other measure", run.Tries[i], produced, run.TriedDeviations[i]);
    if (run.SameBudget(produced) && run.TriedDeviations[i] < run.BestDeviation)
    {
      run.BestDeviation = run.TriedDeviations[i];
      std::swap(level, run.TriedLevels[i]);
      run.Best = run.Tries[i];
    }
  }
  return true;
}

// Candidates spend the same budget differently; the smallest sampled deviation from the input
// (EstimateDeviation) wins. The first level (the given merge measure) runs in the working state
// Work; with CompareCandidates the other measures run meanwhile in Helper (two vtkSMPTools tasks).
// The planned removal tries run after the first level, one per working state, and only when it
// needed no fallback pass: a try gets one pass (GenerateIn's budget), and on the real scan
// isosurfaces, where the first level needs 5-9 passes, every try failed its pass and was thrown
// away (two merging runs and two triangulations of CPU time per level, MRI and inia19 at 10%).
bool SpbmLevelGenerator::GenerateForTarget(Index target, const SpbmLevelParameters& base, SpbmLevel& level,
  SpbmLevelParameters* used, const std::function<bool()>& abort)
{
  this->Work->Times = StageTimes();
  struct Report
  {
    const StageTimes& Times;
    StageClock::time_point Start = StageClock::now();
    ~Report() { LogStageTimes("level, first working state", Since(this->Start), this->Times); }
  } report{ this->Work->Times };
  TargetCandidates run(target, abort);
  run.Compare = base.MergePatches && base.MergeAngle > 0 && base.CompareCandidates;
  // Without the compared candidates the second working state is idle while Work searches: the
  // search may probe there (ProbeAnglesSideBySide). The planned tries run after the searches.
  struct SpareDuringSearches
  {
    State*& Spare;
    ~SpareDuringSearches() { this->Spare = nullptr; }
  } spare{ this->SpareState };
  spare.Spare = run.Compare ? nullptr : this->Helper.get();
  if (!run.Compare)
  {
    this->PlanRemovalTries(base, run);
  }
  SpbmLevelParameters first;
  bool done = true;
  RunTasks(run.Compare ? 2 : 1, [&](int task) {
    if (task == 1)
    {
      this->GenerateOtherMeasure(base, run);
      return;
    }
    done = this->GenerateForTargetAndAngle(target, base, level, &first, abort, *this->Work);
    run.FirstCount = static_cast<Index>(level.TrianglePatch.size());
    run.BestDeviation = done && run.Compare ? this->EstimateDeviation(level) : 0.0;
    this->DescribeCandidate("first", first, run.FirstCount, run.BestDeviation);
    run.Best = first;
    // A narrower alpha1 only when alpha1 did not have to be widened (a narrower one would widen
    // to the same level) and no removal was needed.
    if (done && run.Compare && !base.SizeWeightedMerge && !base.FlatnessMerge &&
      first.MergeAngle <= base.MergeAngle && first.RemovalTarget == 0)
    {
      done = this->TryNarrowerAngle(base, level, run);
    }
  });
  if (run.TriesPlanned && done)
  {
    this->RunPlannedTriesAfter(level, run);
  }
  if (!done || !run.SecondDone)
  {
    return false;
  }
  if (run.Compare)
  {
    this->KeepOtherMeasure(level, run);
  }
  else if (base.MergePatches && 20 * run.FirstCount > 21 * target && level.Passes == 1 &&
    !this->TryOtherMeasureForUnreachedTarget(base, level, run))
  {
    return false;
  }
  if (run.TriesPlanned && !this->KeepClosestTry(first, level, run))
  {
    return false;
  }
  if (used)
  {
    *used = run.Best;
  }
  return true;
}

// The planned tries, one per working state (two vtkSMPTools tasks), when the first level needed
// one generation pass; otherwise they are skipped (see GenerateForTarget) and count as finished
// without a level.
void SpbmLevelGenerator::RunPlannedTriesAfter(const SpbmLevel& firstLevel, TargetCandidates& run)
{
  if (firstLevel.Passes > 1)
  {
    vtkLogF(TRACE, "[spbm] removal tries skipped: the first level needed %d generation passes", firstLevel.Passes);
    run.NextTry = 2;
    run.TriedFinished[0] = run.TriedFinished[1] = true;
    return;
  }
  RunTasks(2, [&](int task) { this->RunPlannedTries(run, task == 0 ? *this->Work : *this->Helper); });
}

bool SpbmLevelGenerator::GenerateForTargetAndAngle(Index target, const SpbmLevelParameters& base,
  SpbmLevel& level, SpbmLevelParameters* used, const std::function<bool()>& abort, State& s, Index budget)
{
  // Fallbacks add triangles the prediction does not know about: aim lower by the overshoot and
  // keep the best level (closest count not above the target, else the smallest).
  Index aim = target;
  bool haveBest = false;
  SpbmLevel candidate;
  for (int attempt = 0; attempt < 6; ++attempt)
  {
    Index predicted = 0;
    const SpbmLevelParameters parameters = this->FindParametersIn(aim, base, &predicted, s);
    const auto started = StageClock::now();
    const bool generated = this->GenerateIn(parameters, candidate, abort, s, budget);
    s.Times.Generate += Since(started);
    if (!generated)
    {
      return false;
    }
    const Index produced = static_cast<Index>(candidate.TrianglePatch.size());
    // The vertices a failed patch kept in its pass (FailedPatchRefinementRounds) add about two
    // triangles each, a few hundredths of a percent: a new search and generation (a merging run
    // and its fallback passes again) would cost more than it gains.
    const Index refinedTriangles = 2 * candidate.RefinedInPass;
    const Index best = haveBest ? static_cast<Index>(level.TrianglePatch.size()) : 0;
    // Closest on a log scale, ties to the one not above the target: a re-aimed level far below
    // the target (when fallbacks cannot be avoided) must not win over a moderate overshoot.
    auto distance = [&](Index count) { return std::fabs(std::log(double(std::max<Index>(count, 1)) / double(target))); };
    const bool better = !haveBest || distance(produced) < distance(best) - 1e-12 ||
      (std::fabs(distance(produced) - distance(best)) <= 1e-12 && produced <= target && best > target);
    if (better)
    {
      std::swap(level, candidate);
      if (used)
      {
        *used = parameters;
      }
      haveBest = true;
    }
    if (produced <= target + refinedTriangles || predicted > aim)
    {
      break; // reached, or even the coarsest level of the search is above the aim: re-aiming cannot help
    }
    const Index next = std::max<Index>(4, aim - (produced - target));
    if (next == aim)
    {
      break;
    }
    aim = next;
  }
  return true;
}
} // namespace slod
