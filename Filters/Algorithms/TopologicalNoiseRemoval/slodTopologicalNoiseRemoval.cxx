// SPDX-License-Identifier: BSD-3-Clause
#include "slodTopologicalNoiseRemoval.h"

#include "slodHandleDetection.h"
#include "slodManifoldSplit.h"
#include "slodMeshTopology.h"

#include "vtkLogger.h"

#include <algorithm>
#include <array>
#include <limits>
#include <tuple>

namespace slod
{
namespace
{

using Box = std::array<double, 6>;

Box EmptyBox()
{
  const double inf = std::numeric_limits<double>::infinity();
  return { inf, -inf, inf, -inf, inf, -inf };
}

void AddToBox(Box& box, const Vec3& p)
{
  for (int k = 0; k < 3; ++k)
  {
    box[2 * k] = std::min(box[2 * k], p[k]);
    box[2 * k + 1] = std::max(box[2 * k + 1], p[k]);
  }
}

double Diagonal(const Box& box)
{
  return Norm({ box[1] - box[0], box[3] - box[2], box[5] - box[4] });
}

bool Inside(const Box& inner, const Box& outer)
{
  return inner[0] >= outer[0] && inner[1] <= outer[1] && inner[2] >= outer[2] && inner[3] <= outer[3] &&
    inner[4] >= outer[4] && inner[5] <= outer[5];
}

// Per component: its box, triangle count and whether it is closed.
struct ComponentSummary
{
  Box Bounds = EmptyBox();
  Index Triangles = 0;
  bool Closed = true;
};

std::vector<ComponentSummary> SummarizeComponents(const TriangleMesh& mesh, const MeshTopology& topology)
{
  std::vector<ComponentSummary> components(size_t(topology.NumberOfComponents()));
  const std::vector<Index>& label = topology.TriangleComponents();
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    ComponentSummary& c = components[label[t]];
    ++c.Triangles;
    for (int k = 0; k < 3; ++k)
    {
      AddToBox(c.Bounds, mesh.Point(mesh.Triangle(t)[k]));
      c.Closed = c.Closed && !topology.IsBoundaryEdge(topology.TriangleEdge(t, k));
    }
  }
  return components;
}

// Stage 1: the mesh without its components smaller than alpha (never the largest); keptTriangles
// maps the new triangles to the input's.
TriangleMesh RemoveSmallComponents(const TriangleMesh& mesh, const MeshTopology& topology, double alpha,
  bool remove, std::vector<Index>& keptTriangles, TopologicalNoiseResult& result)
{
  const std::vector<ComponentSummary> components = SummarizeComponents(mesh, topology);
  size_t largest = 0;
  for (size_t c = 1; c < components.size(); ++c)
  {
    largest = components[c].Triangles > components[largest].Triangles ? c : largest;
  }
  std::vector<unsigned char> dropped(components.size(), 0);
  for (size_t c = 0; remove && c < components.size(); ++c)
  {
    if (c != largest && Diagonal(components[c].Bounds) < alpha)
    {
      dropped[c] = 1;
      const bool cavity = components[c].Closed && Inside(components[c].Bounds, components[largest].Bounds);
      ++(cavity ? result.CavitiesRemoved : result.ComponentsRemoved);
    }
  }
  TriangleMesh kept;
  kept.Points = mesh.Points;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    if (!dropped[topology.TriangleComponents()[t]])
    {
      const Index* tri = mesh.Triangle(t);
      kept.AddTriangle(tri[0], tri[1], tri[2]);
      keptTriangles.push_back(t);
    }
  }
  return kept;
}

// One candidate of a pass, ordered shortest first (then by seed, for determinism).
struct RankedLoop
{
  double Length;
  size_t Seed, Index;
  bool operator<(const RankedLoop& o) const
  {
    return std::tie(this->Length, this->Seed, this->Index) < std::tie(o.Length, o.Seed, o.Index);
  }
};

std::vector<RankedLoop> RankLoops(const std::vector<std::vector<CandidateLoop>>& loops)
{
  std::vector<RankedLoop> ranked;
  for (size_t s = 0; s < loops.size(); ++s)
  {
    for (size_t i = 0; i < loops[s].size(); ++i)
    {
      ranked.push_back({ loops[s][i].Length, s, i });
    }
  }
  std::sort(ranked.begin(), ranked.end());
  return ranked;
}

NoiseLoop RecordLoop(const CuttableMesh& mesh, const CandidateLoop& loop, bool removed)
{
  NoiseLoop record;
  record.Vertices = loop.Vertices;
  for (Index v : loop.Vertices)
  {
    record.Points.push_back(mesh.Point(v));
  }
  record.Length = loop.Length;
  record.Removed = removed;
  return record;
}

// Marks of one pass: vertices a cut changed (a later candidate through them is outdated) and
// vertices of loops already reported as kept (their near-copies from other seeds are not).
struct PassMarks
{
  std::vector<unsigned char> Changed, Reported;
  bool Any(const std::vector<unsigned char>& marks, const std::vector<Index>& vertices) const
  {
    for (Index v : vertices)
    {
      if (size_t(v) < marks.size() && marks[v])
      {
        return true;
      }
    }
    return false;
  }
  static void Set(std::vector<unsigned char>& marks, const std::vector<Index>& vertices)
  {
    for (Index v : vertices)
    {
      marks.resize(std::max(marks.size(), size_t(v) + 1), 0);
      marks[v] = 1;
    }
  }
};

// Stage 3b: cuts the pass's candidates that are still valid and do not separate the mesh,
// shortest first. Returns the vertices changed (for the next pass's seeds).
std::vector<Index> CutHandles(CuttableMesh& mesh, const std::vector<std::vector<CandidateLoop>>& loops,
  Index budget, TopologicalNoiseResult& result)
{
  PassMarks marks;
  std::vector<Index> changedAll, changed;
  for (const RankedLoop& ranked : RankLoops(loops))
  {
    const CandidateLoop& loop = loops[ranked.Seed][ranked.Index];
    if (marks.Any(marks.Changed, loop.Vertices) || marks.Any(marks.Reported, loop.Vertices))
    {
      ++result.Outdated;
      continue; // outdated by a cut (its seed grows again next pass) or a copy of a kept loop
    }
    const LoopSeparation separation = mesh.TestSeparation(loop.Vertices, budget);
    ++result.Tests[int(separation)];
    if (separation == LoopSeparation::NonSeparating && !mesh.CutAndFill(loop.Vertices, changed))
    {
      ++result.CutsRefused;
    }
    else if (separation == LoopSeparation::NonSeparating)
    {
      ++result.HandlesRemoved;
      result.Loops.push_back(RecordLoop(mesh, loop, true));
      PassMarks::Set(marks.Changed, changed);
      changedAll.insert(changedAll.end(), changed.begin(), changed.end());
    }
    else if (separation == LoopSeparation::Undetermined)
    {
      ++result.LoopsKept;
      result.Loops.push_back(RecordLoop(mesh, loop, false));
      result.Loops.back().Undetermined = true;
      PassMarks::Set(marks.Reported, loop.Vertices);
    }
  }
  return changedAll;
}

Index SearchBudget(const TopologicalNoiseParameters& parameters)
{
  return parameters.SeparationSearchBudget > 0 ? parameters.SeparationSearchBudget : std::numeric_limits<Index>::max();
}

// Stage 0 (SplitNonManifold): the mesh with its non-manifold edges and vertices split into
// sheets, and the topology rebuilt for it; nothing when the input is manifold.
void SplitIntoSheets(const TriangleMesh& input, MeshTopology& topology, const TopologicalNoiseParameters& parameters,
  ManifoldSplitResult& split, TopologicalNoiseResult& result)
{
  const MeshStatistics& stats = result.InputStatistics;
  if (!parameters.SplitNonManifold || (stats.NonManifoldEdges == 0 && stats.NonManifoldVertices == 0))
  {
    return;
  }
  split = SplitNonManifold(input, topology);
  result.NonManifoldEdgesSplit = split.EdgesSplit;
  result.NonManifoldEdgesLeft = split.EdgesLeft;
  result.NonManifoldVerticesSplit = split.VerticesSplit;
  topology = MeshTopology(split.Mesh);
}

// Stage 3: passes of region growth and cuts with feature size alpha, from every seed first and
// then from the seeds near the last pass's cuts. False when aborted.
bool CutPasses(CuttableMesh& mesh, double alpha, const TopologicalNoiseParameters& parameters,
  TopologicalNoiseResult& result, const ProgressFunction& progress, double progressStart, double progressSpan)
{
  // A loop of length L lies within L / 2 of each of its vertices, so a region of radius
  // spacing + L / 2 around a seed within `spacing` of the loop holds it whole. The work is
  // seeds x region area ~ (spacing + L / 2)^2 / spacing^2, smallest for large spacings: a
  // spacing of L / 2 costs a quarter of the work of L / 6.
  RegionGrowthLimits limits;
  limits.MaximumLoopLength = Pi * alpha;
  const double spacing = 0.5 * limits.MaximumLoopLength;
  limits.Radius = 0.5 * limits.MaximumLoopLength + spacing;
  const Index budget = SearchBudget(parameters);
  const std::vector<Index> seeds = CoveringSeeds(mesh, spacing);
  std::vector<Index> active = seeds;
  while (!active.empty() && result.Passes < parameters.MaximumPasses)
  {
    const std::vector<std::vector<CandidateLoop>> loops = FindCandidateLoops(mesh, active, limits);
    for (const auto& l : loops)
    {
      result.CandidateLoops += static_cast<Index>(l.size());
    }
    const Index cutsBefore = result.HandlesRemoved;
    const std::vector<Index> changed = CutHandles(mesh, loops, budget, result);
    ++result.Passes;
    vtkLogF(TRACE, "pass %d (alpha %g): %zu seeds, %d candidates so far, %d cuts", result.Passes, alpha,
      active.size(), int(result.CandidateLoops), int(result.HandlesRemoved - cutsBefore));
    if (progress && !progress(progressStart + progressSpan * result.Passes / parameters.MaximumPasses))
    {
      return false;
    }
    active = changed.empty() ? std::vector<Index>() : SeedsNear(mesh, seeds, changed, limits.Radius);
  }
  result.PassLimitReached = !active.empty();
  return true;
}

// A loop found on a copy of `mesh` cut on `mesh` itself, when its vertices are there and it is
// still a handle's loop.
bool CutOnMesh(CuttableMesh& mesh, const NoiseLoop& loop, Index budget)
{
  for (Index v : loop.Vertices)
  {
    if (v >= mesh.NumberOfPoints())
    {
      return false; // a vertex a cut of the copy made
    }
  }
  std::vector<Index> changed;
  return mesh.TestSeparation(loop.Vertices, budget) == LoopSeparation::NonSeparating &&
    mesh.CutAndFill(loop.Vertices, changed);
}

// The genus of a manifold mesh, -1 when it is not defined (non-manifold parts left).
long long GenusOf(const TriangleMesh& mesh)
{
  return MeshTopology(mesh).Statistics(mesh).Genus;
}

// One survey round: passes at `size` on the survey copy. Its loops that the copy lost are handles
// kept by the result, or, within pi alpha, handles the passes had over-measured: those are cut on
// the result too. Returns the handles the copy lost; false when aborted.
bool SurveyRound(CuttableMesh& copy, CuttableMesh& mesh, double alpha, double size,
  const TopologicalNoiseParameters& parameters, TopologicalNoiseResult& result, const ProgressFunction& progress,
  double progressStart, double progressSpan, Index& handlesFound)
{
  TopologicalNoiseResult survey;
  if (!CutPasses(copy, size, parameters, survey, progress, progressStart, progressSpan))
  {
    return false;
  }
  result.SurveyPassLimitReached = result.SurveyPassLimitReached || survey.PassLimitReached;
  handlesFound = survey.HandlesRemoved;
  const Index budget = SearchBudget(parameters);
  for (NoiseLoop& loop : survey.Loops)
  {
    if (!loop.Removed)
    {
      continue;
    }
    loop.Removed = loop.Length <= Pi * alpha && CutOnMesh(mesh, loop, budget);
    if (loop.Removed)
    {
      ++result.HandlesRemoved;
      ++result.HandlesRemovedBySurvey;
    }
    else
    {
      result.KeptHandleSizes.push_back(loop.Length / Pi);
    }
    result.Loops.push_back(std::move(loop));
  }
  return true;
}

// Stage 4 (KeptHandleSurveyFactor): the handles the cuts kept, sized by cutting a copy of the
// result in rounds of doubling size (2 alpha, 4 alpha, ...) up to the factor times alpha or the
// mesh's diagonal (no handle's shortest loop is much longer than pi times the diagonal), and
// stopping as soon as the copy has no handle left. Each round costs about as much as the passes
// (regions grow with the size, seeds thin out with its square), so the rounds are few: log2 of the
// factor at most.
bool SurveyKeptHandles(CuttableMesh& mesh, double alpha, const TopologicalNoiseParameters& parameters,
  TopologicalNoiseResult& result, const ProgressFunction& progress)
{
  if (parameters.KeptHandleSurveyFactor <= 1.0 || !parameters.RemoveHandles || alpha <= 0)
  {
    return true;
  }
  const double largest = std::min(alpha * parameters.KeptHandleSurveyFactor,
    std::max(2.0 * alpha, mesh.Result().BoundingBoxDiagonal()));
  // Each cut of a non-separating loop lowers a manifold's genus by one: the copy's handles left
  // are counted without rebuilding its topology after every round.
  long long handlesLeft = GenusOf(mesh.Result());
  CuttableMesh copy = mesh;
  double span = 0.2;
  double start = 0.55;
  for (double size = 2.0 * alpha; handlesLeft != 0; size = std::min(2.0 * size, largest))
  {
    Index found = 0;
    if (!SurveyRound(copy, mesh, alpha, size, parameters, result, progress, start, span, found))
    {
      return false;
    }
    ++result.SurveyRounds;
    result.SurveySize = size;
    handlesLeft = handlesLeft < 0 ? handlesLeft : std::max(0LL, handlesLeft - static_cast<long long>(found));
    start += span;
    span *= 0.5;
    if (size >= largest)
    {
      break;
    }
  }
  result.HandlesNotSized = handlesLeft;
  std::sort(result.KeptHandleSizes.begin(), result.KeptHandleSizes.end());
  return true;
}

// Stage 5: the edited mesh without unused vertices, with sources mapped to the input.
void StoreResult(const CuttableMesh& mesh, const std::vector<Index>& keptTriangles,
  const std::vector<Index>& splitSource, TopologicalNoiseResult& result)
{
  result.Mesh = mesh.Result();
  std::vector<Index> newToOld;
  result.Mesh.RemoveUnusedPoints(&newToOld);
  result.VertexSource.resize(newToOld.size());
  for (size_t i = 0; i < newToOld.size(); ++i)
  {
    const Index source = mesh.VertexSources()[newToOld[i]];
    result.VertexSource[i] = splitSource.empty() ? source : splitSource[source];
  }
  result.TriangleSource.resize(mesh.TriangleSources().size());
  for (size_t t = 0; t < result.TriangleSource.size(); ++t)
  {
    result.TriangleSource[t] = keptTriangles[mesh.TriangleSources()[t]];
  }
  result.LockedVertices = mesh.NumberOfLockedVertices();
  result.CentreFans = mesh.NumberOfCentreFans();
}
} // namespace

bool RemoveTopologicalNoise(const TriangleMesh& input, const TopologicalNoiseParameters& parameters,
  TopologicalNoiseResult& result, const ProgressFunction& progress)
{
  result = TopologicalNoiseResult();
  const double alpha = std::max(0.0, parameters.FeatureSize);
  std::vector<Index> keptTriangles;
  // One topology of the input serves its statistics, the split, the component stage and, when
  // that removed nothing (the kept mesh is then the input), the cuttable mesh: each build scans
  // the whole mesh.
  MeshTopology topology(input);
  result.InputStatistics = topology.Statistics(input);
  ManifoldSplitResult split;
  SplitIntoSheets(input, topology, parameters, split, result);
  const TriangleMesh& sheets = split.VertexSource.empty() ? input : split.Mesh;
  TriangleMesh kept = RemoveSmallComponents(sheets, topology, alpha, parameters.RemoveComponents, keptTriangles, result);
  const bool keptAll = kept.NumberOfTriangles() == sheets.NumberOfTriangles();
  CuttableMesh mesh = keptAll ? CuttableMesh(std::move(kept), std::move(topology)) : CuttableMesh(std::move(kept));
  topology = MeshTopology(); // (when not moved: the input's adjacency is not needed any more)
  split.Mesh = TriangleMesh();
  if (progress && !progress(0.1))
  {
    return false;
  }
  const bool surveyed = parameters.KeptHandleSurveyFactor > 1.0;
  if (parameters.RemoveHandles && alpha > 0 && mesh.NumberOfTriangles() > 0 &&
    !(CutPasses(mesh, alpha, parameters, result, progress, 0.1, surveyed ? 0.45 : 0.85) &&
      SurveyKeptHandles(mesh, alpha, parameters, result, progress)))
  {
    return false;
  }
  StoreResult(mesh, keptTriangles, split.VertexSource, result);
  return true;
}
} // namespace slod
