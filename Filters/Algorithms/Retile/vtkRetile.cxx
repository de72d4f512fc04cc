// SPDX-License-Identifier: BSD-3-Clause
#include "vtkRetile.h"

#include "slodAttributeTransfer.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodPointAttributes.h"
#include "slodRetiling.h"

#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkLogger.h"
#include "vtkInformationVector.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <sstream>
#include <cmath>
#include <limits>

vtkStandardNewMacro(vtkRetile);

namespace
{
using slod::operator-;

// Re-tilings with fewer points tried when one has more triangles than allowed.
constexpr int MaximumRetileAttempts = 4;
// Re-tilings tried to meet an explicit vertex count (each a whole re-tiling; the repair only for
// the one kept).
constexpr int MaximumExactCountAttempts = 8;

// The vertex count: numberOfPoints when > 0, else from the triangle target (the larger of
// TargetNumberOfTriangles and the reduction's count; the input's count when neither), which also
// lowers `limit` to that target.
slod::Index PointsForTarget(const slod::TriangleMesh& mesh, vtkIdType numberOfPoints, vtkIdType targetTriangles,
  double targetReduction, slod::Index& limit)
{
  if (numberOfPoints > 0)
  {
    return static_cast<slod::Index>(numberOfPoints);
  }
  // The filter contract's targets (slodFilterContract.h): whichever is reached first; none: 0.9.
  const vtkIdType target =
    std::max<vtkIdType>(1, slod::TargetTriangleCount(mesh.NumberOfTriangles(), targetTriangles, targetReduction, false));
  limit = static_cast<slod::Index>(std::min<vtkIdType>(limit, target));
  // V = F / 2 + chi on a closed surface.
  const slod::MeshStatistics stats = slod::ComputeMeshStatistics(mesh);
  return static_cast<slod::Index>(std::max<vtkIdType>(4, target / 2 + stats.EulerCharacteristic));
}

// The input itself as a re-tiling result (every vertex its own host, weight 1 at its corner).
slod::RetilingResult InputAsResult(const slod::TriangleMesh& mesh)
{
  slod::RetilingResult result;
  result.Mesh = mesh;
  result.HostTriangle.assign(size_t(mesh.NumberOfPoints()), 0);
  result.Barycentric.assign(3 * size_t(mesh.NumberOfPoints()), 0.0);
  for (slod::Index t = mesh.NumberOfTriangles() - 1; t >= 0; --t)
  {
    const slod::Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      result.HostTriangle[tri[k]] = t;
      std::fill_n(&result.Barycentric[3 * size_t(tri[k])], 3, 0.0);
      result.Barycentric[3 * size_t(tri[k]) + k] = 1.0;
    }
  }
  return result;
}

// The attempts at a triangle limit so far: the next point count from the last two. A closed
// surface has F = 2V - 2 chi triangles, so the first step removes half the excess in points; the
// old vertices retained (at the small handles and thin parts of noisy scans) grow as the points
// get fewer, so the later steps follow the slope measured between the last two attempts. Below
// MinimumAttemptSlope triangles per point removed, each point removed mostly comes back as a
// retained original vertex: fewer points would give a worse re-tiling for little gain, so the
// attempts stop there (the target is then reported missed). The slope is measured only over a
// step of at least MinimumSlopeStep of the points: over a small step the retained count's
// randomness (a few vertices more or less) decides it.
constexpr double MinimumAttemptSlope = 1.0;
constexpr double MinimumSlopeStep = 0.05;
// Which old vertices are retained changes from one attempt to the next (the MRI at 10%: 18, then
// 24 at nearly the same point count), and each one more costs two triangles, so a step aimed at
// the limit itself missed it by a few triangles about half the time and paid for a whole attempt
// more. The step aims below the limit by RetainedVariationMargin standard deviations of the
// difference of two retained counts, taken as counts of rare events (variance = mean, so
// sqrt(2 R) for R retained in the last attempt), at most MaximumMarginShare of the points: on a
// small mesh an attempt more costs little, and a margin of many points would leave the output
// far below the target (anchor at 10%: 86 triangles for 105).
constexpr double RetainedVariationMargin = 2.0;
constexpr double MaximumMarginShare = 0.05;
// The triangle and vertex counts of one attempt (negative triangles: aborted).
struct AttemptCounts
{
  slod::Index Triangles = 0, Vertices = 0;
};
struct LimitAttempts
{
  int Attempt = 0;
  slod::Index PreviousPoints = 0, PreviousTriangles = 0;

  // The point count of the attempt after one of `points` points gave `counts` over `limit`, or 0
  // when there is none (the last attempt, or no smaller count to try). The vertices beyond the
  // points are the retained old vertices (less any candidate dropped).
  slod::Index Next(slod::Index points, slod::Index limit, AttemptCounts counts) const
  {
    const slod::Index triangles = counts.Triangles;
    double slope = 2.0;
    if (double(this->PreviousPoints - points) >= MinimumSlopeStep * double(this->PreviousPoints))
    {
      slope = std::min(slope, double(this->PreviousTriangles - triangles) / double(this->PreviousPoints - points));
      if (slope < MinimumAttemptSlope)
      {
        return 0;
      }
    }
    const double retained = double(std::max<slod::Index>(0, counts.Vertices - points));
    const double margin = std::floor(
      std::min(RetainedVariationMargin * std::sqrt(2.0 * retained), MaximumMarginShare * double(points)));
    const auto fewer = static_cast<slod::Index>(std::floor(double(points) - double(triangles - limit) / slope - margin));
    return this->Attempt + 1 >= MaximumRetileAttempts || fewer >= points || fewer < 4 ? 0 : fewer;
  }
};

// Runs retile(points, attempts) (returns the attempt's counts, negative triangles when aborted)
// with `points`, then with fewer points while the result has more than `limit` triangles
// (retained old vertices and borders add triangles; LimitAttempts); leaves the point count of the
// last attempt in `points`.
template <typename RetileFunction>
void ShrinkWhileOverLimit(slod::Index& points, slod::Index limit, RetileFunction&& retile)
{
  for (LimitAttempts attempts; attempts.Attempt < MaximumRetileAttempts; ++attempts.Attempt)
  {
    const AttemptCounts counts = retile(points, attempts);
    vtkLogF(TRACE, "retile attempt %d: %lld points -> %lld triangles, %lld vertices (limit %lld)", attempts.Attempt,
      static_cast<long long>(points), static_cast<long long>(counts.Triangles),
      static_cast<long long>(counts.Vertices), static_cast<long long>(limit));
    if (counts.Triangles < 0 || counts.Triangles <= limit)
    {
      break;
    }
    const slod::Index fewer = attempts.Next(points, limit, counts);
    if (fewer == 0)
    {
      break;
    }
    attempts.PreviousPoints = points;
    attempts.PreviousTriangles = counts.Triangles;
    points = fewer;
  }
}

// Re-tiles within `limit` triangles if it can (ShrinkWhileOverLimit); returns the last attempt and
// leaves the point count used in options.
slod::RetilingResult RetileWithin(const slod::TriangleMesh& mesh, slod::RetilingOptions& options, slod::Index limit)
{
  slod::RetilingResult result;
  ShrinkWhileOverLimit(options.NumberOfPoints, limit, [&](slod::Index points, const LimitAttempts& attempts) {
    options.NumberOfPoints = points;
    // An attempt that another will follow is not repaired (the repair is most of the time on
    // noisy scans and changes no count).
    options.ContinueWithCounts = [&](slod::Index vertices, slod::Index triangles) {
      return triangles <= limit || attempts.Next(points, limit, AttemptCounts{ triangles, vertices }) == 0;
    };
    slod::Retile(mesh, options, result);
    return result.Aborted ? AttemptCounts{ -1, 0 }
                          : AttemptCounts{ result.Mesh.NumberOfTriangles(), result.Mesh.NumberOfPoints() };
  });
  options.ContinueWithCounts = nullptr;
  return result;
}

// The candidate-count attempts cannot settle an exact vertex count on their own: which old vertices
// are retained changes with the candidates (femur asked for 400 gave 401; 436 in an older build).
// A re-tiling with a few vertices too many loses its most crowded candidates instead
// (slod::RemoveCandidates), a few rounds while some go; one that stays (no collapse allowed) is
// not chosen again.
constexpr int MaximumTrimRounds = 5;
void TrimToCount(const slod::TriangleMesh& mesh, const slod::RetilingOptions& options, slod::Index wanted,
  slod::RetilingResult& result)
{
  if (result.Aborted || result.Stopped)
  {
    return;
  }
  slod::RetilingOptions trim = options;
  trim.ContinueWithCounts = nullptr;
  if (!slod::RemoveCandidates(mesh, trim, wanted, MaximumTrimRounds, result))
  {
    result = slod::RetilingResult();
    result.Aborted = true;
  }
}

// An explicit vertex count: the retained old vertices come on top of the candidates, so while the
// output has another count, re-tile with the candidates shifted by the difference (bounded
// attempts, never more than `limit` triangles), then trim a small surplus (TrimToCount). A result
// with at most `trimmable` vertices too many is as good as exact, and better than any other, so
// the attempts aim at the middle of that window; where the trim leaves a surplus (its candidates
// held: tiny meshes), the remaining attempts look for the exact count itself.
slod::RetilingResult RetileExactCount(const slod::TriangleMesh& mesh, slod::RetilingOptions& options,
  slod::Index wanted, slod::Index limit, slod::RetilingResult result)
{
  // Each attempt steps from the last attempt's own count (retained vertices vary with the
  // candidates, so the best result's count would step past the target again and again); a step
  // back onto a count already tried halves the gap to the nearest tried count instead.
  slod::Index trimmable = std::max<slod::Index>(2, wanted / 50);
  const auto settled = [&](slod::Index vertices) { return vertices >= wanted && vertices - wanted <= trimmable; };
  const auto miss = [&](slod::Index vertices) {
    return settled(vertices) ? vertices - wanted : std::abs(vertices - wanted) + trimmable;
  };
  std::vector<slod::Index> tried{ options.NumberOfPoints };
  slod::RetilingOptions attempt = options;
  slod::Index last = result.Mesh.NumberOfPoints();
  int k = 0;
  for (int phase = 0; phase < 2 && !result.Aborted; ++phase)
  {
    for (; k < MaximumExactCountAttempts && !result.Aborted && !settled(result.Mesh.NumberOfPoints()); ++k)
    {
      slod::Index points = attempt.NumberOfPoints + (wanted + trimmable / 2 - last);
      if (std::find(tried.begin(), tried.end(), points) != tried.end())
      {
        points = (points + attempt.NumberOfPoints) / 2;
      }
      if (points < 4 || std::find(tried.begin(), tried.end(), points) != tried.end())
      {
        break;
      }
      tried.push_back(points);
      attempt.NumberOfPoints = points;
      const slod::Index best = result.Mesh.NumberOfPoints();
      // Repaired only when kept (the repair changes no count).
      attempt.ContinueWithCounts = [&](slod::Index vertices, slod::Index triangles) {
        last = vertices;
        return triangles <= limit && miss(vertices) < miss(best);
      };
      slod::RetilingResult next;
      slod::Retile(mesh, attempt, next);
      if (next.Aborted)
      {
        return next;
      }
      if (!next.Stopped && next.Mesh.NumberOfTriangles() <= limit && miss(next.Mesh.NumberOfPoints()) < miss(best))
      {
        result = std::move(next);
        options.NumberOfPoints = attempt.NumberOfPoints;
      }
    }
    TrimToCount(mesh, options, wanted, result);
    trimmable = 0;
  }
  return result;
}

// The vertex counts of the nested levels, finest first: each NestedLevelRatio times smaller, at
// least 4.
std::vector<slod::Index> NestedLevelCounts(slod::Index finest, int numberOfLevels, double ratio)
{
  std::vector<slod::Index> counts;
  double count = finest;
  for (int k = 0; k < numberOfLevels && count >= 4; ++k)
  {
    counts.push_back(static_cast<slod::Index>(std::lround(count)));
    count /= ratio;
  }
  return counts;
}

// Nested levels whose finest level has at most `limit` triangles if it can: the vertices the
// coarser levels retain stay in the finer ones and add triangles there.
void RetileNestedWithin(const slod::TriangleMesh& mesh, const slod::RetilingOptions& options, int numberOfLevels,
  double ratio, slod::Index limit, std::vector<slod::RetilingResult>& levels)
{
  slod::Index finest = options.NumberOfPoints;
  ShrinkWhileOverLimit(finest, limit, [&](slod::Index points, const LimitAttempts&) {
    slod::RetileNested(mesh, NestedLevelCounts(points, numberOfLevels, ratio), options, levels);
    if (levels.empty() || levels.back().Aborted)
    {
      return AttemptCounts{ -1, 0 };
    }
    return AttemptCounts{ levels.back().Mesh.NumberOfTriangles(), levels.back().Mesh.NumberOfPoints() };
  });
}

// Turk's method assumes a manifold surface (every edge on one or two triangles, section 3.1): the
// input's non-manifold vertices are kept as they are (so non-manifold edges stay single edges and
// the surface is not cut open there). Its edges must be resolvable at the scale of the surface.
bool CheckRetilable(vtkAlgorithm* filter, const slod::TriangleMesh& mesh, const slod::PreparationReport& report)
{
  if (report.NonManifoldVertices > 0)
  {
    vtkWarningWithObjectMacro(filter, << "The input has " << report.NonManifoldEdges << " non-manifold edges and "
                                      << report.NonManifoldVertices
                                      << " non-manifold vertices: those vertices are kept in the output as they are.");
  }
  const double extent = slod::ExtentPerMedianEdge(mesh);
  if (!(extent <= slod::MaximumRetilingExtentPerEdge))
  {
    vtkErrorWithObjectMacro(filter, << "The input's extent is " << extent << " times its median edge length (more than "
                                    << slod::MaximumRetilingExtentPerEdge
                                    << "): re-tiling cannot resolve its edges at that scale "
                                    << "(a vertex far away from the others?).");
    return false;
  }
  return true;
}

// The default preparation, and the coincident ends of an edge merged: the removal cannot remove
// them (their triangles have no normal), and retained they would be output as tiles of zero area
// (marching cubes' vertices at a sample equal to the iso-value: mc1m.vtp).
slod::PreparationOptions RetilePreparation()
{
  slod::PreparationOptions options;
  options.CollapseZeroLengthEdges = true;
  return options;
}

// The input's attributes as a re-tiling carries them: point data interpolated at each vertex's host
// location, each triangle the cell data of the input triangle closest to its centroid.
struct InputAttributes
{
  vtkPolyData* Input;
  const std::vector<slod::Index>& TriangleToCell;
  slod::PointAttributes& Points;
};

// A re-tiling as poly data with the input's attributes.
void StoreRetiling(const slod::RetilingResult& retiling, const slod::TriangleMesh& mesh,
  const InputAttributes& inputAttributes, int pointType, vtkPolyData* polyData)
{
  slod::MeshToPolyData(retiling.Mesh, polyData, pointType);
  slod::StoreNearestCellData(inputAttributes.Input, inputAttributes.TriangleToCell, mesh, retiling.Mesh.Points,
    retiling.Mesh.Triangles, polyData);
  slod::PointAttributes& attributes = inputAttributes.Points;
  if (attributes.Empty())
  {
    return;
  }
  std::vector<slod::Index> rows(retiling.HostTriangle.size());
  for (size_t v = 0; v < rows.size(); ++v)
  {
    const slod::Index* tri = mesh.Triangle(retiling.HostTriangle[v]);
    rows[v] = attributes.AddInterpolated(tri, &retiling.Barycentric[3 * v], 3);
  }
  attributes.Store(polyData->GetPointData(), rows);
}
// Field data of coarser nested level k (levels: coarsest first): RetileRemovals, the collapses
// (removed, target) and flips ((-1 - x, y) for edge (x, y)) that turn each finer level into the
// next coarser one (section 6.2), chained from the finest level down to level k; each run is in
// the point ids of the level it starts from, which are those of every finer level (a level's
// vertices come first, in the same order), so the records from any finer level on replay to level
// k. RetileRemovalsFinerPoints: the point count of the level each run starts from (finest first),
// RetileRemovalsStart: its first record. vtkRetileLevelInterpolation replays the records from the
// high level it is given.
void StoreRemovals(const std::vector<slod::RetilingResult>& levels, size_t k, vtkPolyData* polyData)
{
  if (k + 1 >= levels.size())
  {
    return;
  }
  vtkNew<vtkIdTypeArray> removals, finerPoints, starts;
  removals->SetName("RetileRemovals");
  removals->SetNumberOfComponents(2);
  finerPoints->SetName("RetileRemovalsFinerPoints");
  starts->SetName("RetileRemovalsStart");
  for (size_t j = levels.size() - 1; j-- > k;)
  {
    finerPoints->InsertNextValue(levels[j + 1].Mesh.NumberOfPoints());
    starts->InsertNextValue(removals->GetNumberOfTuples());
    for (size_t i = 0; i + 1 < levels[j].Removals.size(); i += 2)
    {
      const vtkIdType pair[2] = { levels[j].Removals[i], levels[j].Removals[i + 1] };
      removals->InsertNextTypedTuple(pair);
    }
  }
  polyData->GetFieldData()->AddArray(removals);
  polyData->GetFieldData()->AddArray(finerPoints);
  polyData->GetFieldData()->AddArray(starts);
}

// Field data: RetainedVertices (original vertices kept for the topology) and, for an explicit
// vertex count, NumberOfPointsReached (1 when the output has exactly that many vertices).
void StoreCountReport(vtkPolyData* output, slod::Index wanted, slod::Index retained)
{
  vtkNew<vtkIdTypeArray> retainedArray;
  retainedArray->SetName("RetainedVertices");
  retainedArray->InsertNextValue(retained);
  output->GetFieldData()->AddArray(retainedArray);
  if (wanted > 0)
  {
    vtkNew<vtkIntArray> reached;
    reached->SetName("NumberOfPointsReached");
    reached->InsertNextValue(output->GetNumberOfPoints() == wanted ? 1 : 0);
    output->GetFieldData()->AddArray(reached);
  }
}

// A coarser nested level keeps the finer level's vertices no collapse (nor ring re-triangulation)
// can remove: each adds two triangles, so a level on a noisy scan can have several times the
// vertices asked for (scan-48's coarsest level, 169 asked, had 641). Said once for all levels.
void WarnAboutCoarserLevelsKeptVertices(vtkRetile* filter, const std::vector<slod::RetilingResult>& levels)
{
  std::ostringstream missed;
  for (size_t k = 0; k + 1 < levels.size(); ++k)
  {
    if (levels[k].RetainedOldVertices > 0)
    {
      missed << " level " << k << ": " << levels[k].Mesh.NumberOfPoints() << " vertices for " << levels[k].CandidatePoints
             << " asked (" << levels[k].RetainedOldVertices << " kept);";
    }
  }
  if (!missed.str().empty())
  {
    vtkWarningWithObjectMacro(filter, << "Coarser nested levels keep vertices of the finer level that could not be removed "
                                         "without changing the topology or folding the surface (field data RetainedVertices):"
                                      << missed.str());
  }
}
// The options vtkRetile passes on as they are.
void CopyPlainOptions(vtkRetile* self, slod::RetilingOptions& options)
{
  options.RepulsionIterations = self->GetRepulsionIterations();
  options.CurvatureWeight = self->GetCurvatureWeight();
  options.FilletDensity = self->GetFilletDensity();
  options.RandomSeed = static_cast<std::uint64_t>(static_cast<unsigned int>(self->GetRandomSeed()));
  options.ShapeImprovementPasses = self->GetShapeImprovementPasses();
  options.EnforceFacing = self->GetEnforceFacing();
  options.RetriangulateRings = self->GetRetriangulateRings();
  options.RingSearchFacesInput = self->GetRingSearchFacesInput();
  options.RepairFlippedTiles = self->GetRepairFlippedTiles();
  options.RepairNeedleTiles = self->GetRepairNeedleTiles();
  options.RepelFromLineGaps = self->GetRepelFromLineGaps();
  options.SlideAlongCreases = self->GetSlideAlongCreases();
  options.MoveRetainedVertices = self->GetMoveRetainedVertices();
  options.FeatureAngle = self->GetFeatureAngle();
}
} // namespace

vtkRetile::vtkRetile()
{
  this->AddSecondaryOutputPort("vtkMultiBlockDataSet");
}

void vtkRetile::SetPreserveCreases(bool preserve)
{
  this->PreserveCreasesSetByUser = true;
  if (this->PreserveCreases != preserve)
  {
    this->PreserveCreases = preserve;
    this->Modified();
  }
}

vtkMultiBlockDataSet* vtkRetile::GetNestedLevels()
{
  return vtkMultiBlockDataSet::SafeDownCast(this->GetOutputDataObject(1));
}

int vtkRetile::RequestData(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->NumberOfRetainedVertices = 0;
  this->NumberOfFlips = 0;
  this->NumberOfFeatureVertices = this->NumberOfCorners = 0;
  this->MinimumSpacingBefore = this->MeanSpacingBefore = this->MinimumSpacingAfter = this->MeanSpacingAfter = 0;
  if (!input || !output)
  {
    return 1;
  }
  slod::TriangleMesh mesh;
  std::vector<slod::Index> vertexToInput, triangleToCell;
  slod::PreparationReport report;
  if (!slod::PrepareFilterTriangles(this, input, RetilePreparation(), mesh, vertexToInput, &report,
        slod::CellMapIfNeeded(input, triangleToCell),
        { /*IsError=*/true, "The input has no triangles: nothing to re-tile." }) ||
    !CheckRetilable(this, mesh, report))
  {
    return 1;
  }
  // Never more triangles than asked for, nor than the input has.
  slod::Index limit = mesh.NumberOfTriangles();
  slod::RetilingOptions options;
  options.NumberOfPoints = PointsForTarget(mesh, this->NumberOfPoints, this->TargetNumberOfTriangles, this->TargetReduction, limit);
  if (options.NumberOfPoints < 4)
  {
    // The smallest closed surface (a tetrahedron) has 4 vertices.
    vtkWarningMacro(<< "NumberOfPoints " << options.NumberOfPoints << " is too small; using 4.");
    options.NumberOfPoints = 4;
  }
  CopyPlainOptions(this, options);
  // The nested levels do not keep feature lines (their coarser levels are made from the finer one
  // by recorded collapses): PreserveCreases applies to the plain re-tiling only.
  const bool nested = this->GenerateNestedLevels && this->NumberOfNestedLevels > 1;
  options.PreserveCreases = this->PreserveCreases && !nested;
  if (nested && this->PreserveCreases && this->PreserveCreasesSetByUser)
  {
    vtkWarningMacro(<< "PreserveCreases is ignored with nested levels (GenerateNestedLevels): their coarser levels "
                       "are made from the finer one by recorded collapses, which do not keep feature lines.");
  }
  options.Progress = slod::FilterProgress(this);
  options.NonManifoldVertices = &report.NonManifoldVertexFlags;
  slod::RetilingResult result = RetileWithin(mesh, options, limit);
  const slod::Index wanted = static_cast<slod::Index>(this->NumberOfPoints);
  if (wanted > 0 && !result.Aborted && result.Mesh.NumberOfTriangles() <= limit && !this->GenerateNestedLevels)
  {
    result = RetileExactCount(mesh, options, wanted, limit, std::move(result));
  }
  const bool retiled = result.Mesh.NumberOfTriangles() <= limit;
  const char* targetMissed = nullptr; // reported with the output (slod::ReportTarget)
  if (!result.Aborted && !retiled)
  {
    // `limit` is the target by now, which the input may exceed too: the smaller of the two is
    // returned, so the output never has more triangles than the input.
    const bool returnInput = mesh.NumberOfTriangles() <= result.Mesh.NumberOfTriangles();
    targetMissed = returnInput ? "re-tiling gives more triangles than the input: the input is returned"
                               : "re-tiling gives more triangles at least: the smallest re-tiling is returned";
    if (returnInput)
    {
      result = InputAsResult(mesh);
    }
  }
  std::vector<slod::RetilingResult> levels;
  if (!result.Aborted && retiled && this->GenerateNestedLevels && this->NumberOfNestedLevels > 1)
  {
    RetileNestedWithin(mesh, options, this->NumberOfNestedLevels, this->NestedLevelRatio, limit, levels);
    if (levels.empty() || levels.back().Aborted)
    {
      slod::ReportAbort(this, output);
      return 1;
    }
    if (levels.back().Mesh.NumberOfTriangles() > limit)
    {
      targetMissed = "the finest nested level has more: the vertices the coarser levels retain add triangles";
    }
    // The finest level is output 0 (its spacing figures come from a plain run's statistics).
    result = levels.back();
  }
  if (result.Aborted)
  {
    slod::ReportAbort(this, output);
    return 1;
  }

  const int pointType = slod::OutputPointType(input, this->OutputPointsPrecision);
  slod::PointAttributes attributes;
  attributes.Load(input->GetPointData(), vertexToInput);
  const InputAttributes inputAttributes{ input, triangleToCell, attributes };
  StoreRetiling(result, mesh, inputAttributes, pointType, output);
  slod::ReportTarget(this, output, limit, targetMissed == nullptr, targetMissed);
  vtkMultiBlockDataSet* levelsOutput = vtkMultiBlockDataSet::GetData(outputVector, 1);
  if (levelsOutput && levels.size() > 1)
  {
    levelsOutput->SetNumberOfBlocks(static_cast<unsigned int>(levels.size()));
    for (size_t k = 0; k < levels.size(); ++k)
    {
      vtkNew<vtkPolyData> level;
      StoreRetiling(levels[k], mesh, inputAttributes, pointType, level);
      StoreRemovals(levels, k, level);
      StoreCountReport(level, 0, levels[k].RetainedOldVertices);
      levelsOutput->SetBlock(static_cast<unsigned int>(k), level);
    }
    WarnAboutCoarserLevelsKeptVertices(this, levels);
  }
  this->NumberOfRetainedVertices = result.RetainedOldVertices;
  this->NumberOfFlips = result.Flips;
  this->NumberOfFeatureVertices = result.FeatureVertices;
  this->NumberOfCorners = result.Corners;
  this->MinimumSpacingBefore = result.MinSpacingBefore;
  this->MeanSpacingBefore = result.MeanSpacingBefore;
  this->MinimumSpacingAfter = result.MinSpacingAfter;
  this->MeanSpacingAfter = result.MeanSpacingAfter;
  if (result.FeaturesIgnored)
  {
    vtkWarningMacro(<< "PreserveCreases: the feature lines at FeatureAngle " << this->FeatureAngle
                    << " would take half the vertices or more; they are not kept.");
  }
  if (result.DroppedCandidates > 0)
  {
    vtkWarningMacro(<< result.DroppedCandidates
                    << " candidate points were dropped: the repulsion's projection onto the surface crowded them onto "
                       "others (at pinched vertices or sharp concave folds).");
  }
  if (result.RetainedOldVertices > 0)
  {
    vtkWarningMacro(<< result.RetainedOldVertices
                    << " original vertices could not be removed without changing the topology or folding the surface; they are kept.");
  }
  // Why the vertex count may differ from the one asked for: the retained original vertices.
  StoreCountReport(output, wanted, result.RetainedOldVertices);
  if (wanted > 0 && output->GetNumberOfPoints() != wanted && output->GetNumberOfPolys() > 0)
  {
    vtkWarningMacro(<< "NumberOfPoints " << wanted << " not reached: the output has " << output->GetNumberOfPoints()
                    << " vertices (" << result.RetainedOldVertices
                    << " original vertices retained for the topology; see the field data RetainedVertices).");
  }
  return 1;
}

void vtkRetile::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfPoints: " << this->NumberOfPoints << "\n";
  os << indent << "RepulsionIterations: " << this->RepulsionIterations << "\n";
  os << indent << "CurvatureWeight: " << this->CurvatureWeight << "\n";
  os << indent << "RandomSeed: " << this->RandomSeed << "\n";
  os << indent << "ShapeImprovementPasses: " << this->ShapeImprovementPasses << "\n";
  os << indent << "PreserveCreases: " << this->PreserveCreases << "\n";
  os << indent << "EnforceFacing: " << this->EnforceFacing << "\n";
  os << indent << "FilletDensity: " << this->FilletDensity << "\n";
  os << indent << "RetriangulateRings: " << this->RetriangulateRings << "\n";
  os << indent << "RingSearchFacesInput: " << this->RingSearchFacesInput << "\n";
  os << indent << "RepairFlippedTiles: " << this->RepairFlippedTiles << "\n";
  os << indent << "RepairNeedleTiles: " << this->RepairNeedleTiles << "\n";
  os << indent << "RepelFromLineGaps: " << this->RepelFromLineGaps << "\n";
  os << indent << "SlideAlongCreases: " << this->SlideAlongCreases << "\n";
  os << indent << "MoveRetainedVertices: " << this->MoveRetainedVertices << "\n";
  os << indent << "FeatureAngle: " << this->FeatureAngle << "\n";
  os << indent << "NumberOfFeatureVertices: " << this->NumberOfFeatureVertices << "\n";
  os << indent << "NumberOfCorners: " << this->NumberOfCorners << "\n";
  os << indent << "GenerateNestedLevels: " << this->GenerateNestedLevels << "\n";
  os << indent << "NumberOfNestedLevels: " << this->NumberOfNestedLevels << "\n";
  os << indent << "NestedLevelRatio: " << this->NestedLevelRatio << "\n";
  os << indent << "NumberOfRetainedVertices: " << this->NumberOfRetainedVertices << "\n";
  os << indent << "NumberOfFlips: " << this->NumberOfFlips << "\n";
  os << indent << "MinimumSpacingBefore: " << this->MinimumSpacingBefore << "\n";
  os << indent << "MeanSpacingBefore: " << this->MeanSpacingBefore << "\n";
  os << indent << "MinimumSpacingAfter: " << this->MinimumSpacingAfter << "\n";
  os << indent << "MeanSpacingAfter: " << this->MeanSpacingAfter << "\n";
}
