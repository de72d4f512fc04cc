// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPatchBoundaryMerge.h"

#include "slodAttributeTransfer.h"
#include "slodInputPreparation.h"
#include "slodMeshTopology.h"
#include "slodPatchBoundaryMerge.h"
#include "slodPatchification.h"
#include "slodEditableMesh.h"
#include "slodSpbmFinalCollapses.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkLogger.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <numeric>
#include <cmath>
#include <memory>
#include <string>
#include <thread>

vtkStandardNewMacro(vtkPatchBoundaryMerge);

namespace
{
// Issue 15 (session 25), slod::PatchificationParameters::RulingAngle: a neighbour within 1 degree
// of the triangle it grows from joins alone. The rulings of the CAD meshes' cylinders and cones
// are within a small fraction of a degree; on a surface bent both ways (where the paper's fat
// patches are right) a neighbour that close is rare. Wider, the patches of coarse CAD targets get
// jagged (couplingdown and anchor at 10%: 1.7x and 1.9x vtkQuadricDecimation's Hausdorff distance
// at 1 degree, 3.7x with any feasible neighbour; couplingdown 2.5x at 8 degrees).
constexpr double RulingAngle = 1.0;
// Issue 15 (session 25): the curvature that sets the patches' thickness bound leaves out the
// creases, edges bent by more than this (degrees). A crease sharper than NeighborAngle is a patch
// boundary and costs chain vertices along its length, not flatness; counted as curvature it made
// the Fandisk's bound 5x what a simplification to 10% deviates (the estimate without creases is
// within 5% of vtkQuadricDecimation's Hausdorff distance there), so the patches merged across its
// cylinders into slabs 4e-3 of the diagonal thick. 60 rather than NeighborAngle: edges between 20
// and 60 degrees are still mostly curvature samples of coarse smooth meshes (bunny00, cow).
constexpr double CreaseAngle = 60.0;
// Issue 15 (session 27), slod::PatchificationParameters::SmallPatchTriangles: patches of up to
// four triangles join a vertex up to the span bound from their running plane. At mild targets the
// plane-distance cap is about the sag of one input triangle, and the vertex test at half the span
// left half the seeds alone. mc1m at 50%: 304,459 -> 192,945 patches, the search's merging runs
// about 1.6x cheaper, Hausdorff 3.85e-5 -> 3.68e-5, RMS equal; with every patch size the patches
// fill the span (172,655, RMS +11%), with single triangles only 233,694.
constexpr slod::Index SmallPatchTriangles = 4;
// Applied from this share of the input kept on (coarser targets keep the former growth: the
// Fandisk's and the scans' 10% levels are unchanged).
constexpr double MildTargetShare = 0.2;
// Issue 10 (session 28): the automatic PatchNoiseTolerance (-1) below MildTargetShare. Coarse
// targets merge the noisy patches of a scan isosurface anyway, and the merging runs, replays and
// fallback passes over hundreds of thousands of small patches were most of the level (the MRI at
// 10%); at mild targets the large flat patches over a staircase cost more than the budget saves.
constexpr double AggressiveTargetNoiseTolerance = 1.0;
// Issue 15 (session 29), LoosenThicknessForTarget: the level of a count target is tried again with
// the thickness bound doubled (at most LooserThicknessRounds times) when its sampled deviation is
// above LooseDeviationRatio times the bound and the search's epsilon above LooseEpsilonRatio times
// it: the budget went to the corners of too many small patches, not to their flatness.
constexpr int LooserThicknessRounds = 2;
constexpr double LooseDeviationRatio = 1.5;
constexpr double LooseEpsilonRatio = 1.5;
// Issue 15 (session 33), CollapseFinerLevelForTarget: the finer level's count (times the target)
// and the deviation (share of the thickness bound as given) above which it is tried. With the
// default PatchDeviationFactor 4 the share 0.5 is 2x the estimate kappa s^2 / 8 of what any
// simplification to the target deviates (the goal on CAD meshes; session 33's 0.75, 3x,
// the goal on smooth ones, left fandisk at 50% at 6.2x vtkQuadricDecimation). The strided samples
// are a cheap first check against FinerLevelStridedShare of that trigger (off scans). 1.5: at 2x
// the finer level is the input itself at 50%, and its collapses cost more.
constexpr double FinerLevelFactor = 1.5;
constexpr double FinerLevelDeviationShare = 0.5;
constexpr double FinerLevelStridedShare = 0.5;
// Issue 15 (session 36): levels of patches grown with a noise tolerance (every target below
// MildTargetShare) are tried only when their strided samples deviate more than this share of the
// trigger (not FinerLevelStridedShare): the every-vertex estimate costs about 7% of the MRI's
// level, whose strided samples read 0.65 of that trigger (every vertex: 0.78); the levels above the
// trigger read at least 0.71 of it strided (the CGAL meshes at 10%: fold).
constexpr double TolerantStridedShare = 0.7;
// Issue 10 (session 38): the trigger measures the level with as many of the input's samples as this
// share of its vertices, the farthest from it, left out (none below 10,000 vertices). On a noisy scan the distances of the
// vertices from the level follow the same distribution at every sampling density (noisy137 to
// noisy546: mean 0.15, 99.99th percentile 0.86-0.87 of the bound), but their largest grows with
// the number of vertices (0.99 / 0.96 / 1.12 / 1.20 at 0.25M / 1M / 2M / 4M triangles: a few
// extreme noise samples), so the finer level was made at 2M and 4M and not at 1M.
constexpr double DeviationTailShare = 1e-4;
// Issue 15 (session 37), RefineDeviatingRegions: the patches whose own vertices deviate from the
// level by more than RegionAllowanceShare of the thickness bound as given (the plane-distance cap
// without a noise tolerance: what session 35's finer level triggered at on smooth meshes) are kept
// as their original triangles in one more pass and the final collapses bring the count back, the
// worst patches first, up to RegionTriangleShare of the input's triangles: the cost follows the
// share of the surface that misses, not the surface.
constexpr double RegionAllowanceShare = 0.5;
constexpr double RegionTriangleShare = 0.03;
// Not where the noise tolerance admitted at least this share of the input's triangles that the
// angle tests refuse (Patchification::NoiseToleranceJoins; session 35 measured the MRI 0.38, the
// noisy scans 0.77, the smooth and CAD CGAL meshes under 0.1, mask and openscan under 0.25): there
// the vertices beyond the cap are noise that the patches were grown to absorb, and keeping their
// original triangles brings the noise back (the MRI at 10%: 7.4 -> 13.1 s CPU, same count).
constexpr double RegionNoiseJoinShare = 0.25;
// Session 45 (MildTargetRegionAllowance): at mild targets the refined level must deviate at least
// this much less than the level (the level side of the changed triangles included): a level whose
// count moved within the tolerance for a gain of a few digits (spool at 50%: 7.2929e-3 -> 7.2929e-3
// of the diagonal, 640 -> 646 triangles) is not a better level.
constexpr double MildRegionGain = 0.97;

// A candidate level replaces `result` when it deviates less (every input vertex) at a count no
// farther from the target (within the final collapses' tolerance).
bool CandidateWins(vtkIdType target, const slod::SpbmLevel& candidate, double candidateDeviation,
  const slod::SpbmLevel& result, double deviation)
{
  const vtkIdType tolerance =
    slod::SpbmFinalCollapseTolerance(static_cast<slod::Index>(std::min<vtkIdType>(target, VTK_INT_MAX)));
  auto miss = [&](const slod::SpbmLevel& l) {
    return std::max<vtkIdType>(tolerance, std::abs(vtkIdType(l.TrianglePatch.size()) - target));
  };
  return candidateDeviation < deviation && miss(candidate) <= miss(result);
}

// Manifold edges both of whose triangles run them the same way.
slod::Index InconsistentEdges(const slod::TriangleMesh& mesh, const slod::MeshTopology& topology)
{
  slod::Index count = 0;
  for (slod::Index e = 0; e < topology.NumberOfEdges(); ++e)
  {
    if (topology.EdgeTriangleCount(e) != 2)
    {
      continue;
    }
    const slod::Index a = topology.EdgeVertex(e, 0), b = topology.EdgeVertex(e, 1);
    int direction = 0;
    for (const slod::Index* t = topology.EdgeTrianglesBegin(e); t != topology.EdgeTrianglesEnd(e); ++t)
    {
      const slod::Index* tri = mesh.Triangle(*t);
      for (int k = 0; k < 3; ++k)
      {
        if (tri[k] == a && tri[(k + 1) % 3] == b)
        {
          ++direction;
        }
        else if (tri[k] == b && tri[(k + 1) % 3] == a)
        {
          --direction;
        }
      }
    }
    count += direction != 0;
  }
  return count;
}

// A count target is reached within 2% either way (at least 2 triangles): the search takes the
// closest count not above it down to 2% below (or, when a kept vertex jumps over that, a count in
// the band either side), fallback triangulations may add a little. With an
// error bound that stops first, more triangles are the contract's answer. A miss says why, and
// above the target with the final collapses on, what the topology alone would allow
// (slod::TopologicalTriangleFloor of the prepared input): the rest is the link condition around
// the handles and the normal bound.
void ReportTargetCount(vtkPatchBoundaryMerge* self, const slod::TriangleMesh& mesh, vtkPolyData* output,
  vtkIdType target, vtkIdType finestCount)
{
  const vtkIdType produced = output->GetNumberOfPolys();
  const vtkIdType tolerance = std::max<vtkIdType>(2, target / 50);
  const bool reached =
    std::abs(produced - target) <= tolerance || (self->GetMaximumError() > 0 && produced > target);
  std::string reason;
  if (produced < target && finestCount > target)
  {
    // The finest level is above the target: the search's steps jumped over the band.
    reason = "one more kept chain vertex takes the count above the target at every merge angle tried "
             "(a kept vertex blocks merges and collapses); ask for a slightly different target";
  }
  else if (produced < target)
  {
    reason = "SPBM keeps no vertex inside a patch: even every chain vertex gives fewer; lower PatchAngle, "
             "NeighborAngle and PatchPlaneDistance, or turn AdaptPatchesToTarget on";
  }
  else if (!self->GetFinalCollapses())
  {
    reason = "the patch corners, handles, borders and non-manifold chains SPBM must keep, and the fallback "
             "triangulations, leave more; turn FinalCollapses on";
  }
  else if (!reached)
  {
    const slod::MeshStatistics s = slod::ComputeMeshStatistics(mesh);
    reason = "every half-edge collapse left would change the topology (Euler characteristic " +
      std::to_string(s.EulerCharacteristic) + ", " + std::to_string(s.BoundaryLoops) +
      " border loop(s), non-manifold edges and pinch vertices stay) or turn a triangle by more than 90 degrees: this "
      "count is the floor of the final collapses; the topology alone needs at least about " +
      std::to_string(slod::TopologicalTriangleFloor(s)) + " triangles";
  }
  slod::ReportTarget(self, output, target, reached, reason.c_str());
}
} // namespace

// The patchification and its chain hierarchy, kept between updates.
struct vtkPatchBoundaryMerge::Cache
{
  const void* Input = nullptr;
  vtkMTimeType InputTime = 0;
  slod::PatchificationParameters Parameters;
  slod::TriangleMesh Mesh;
  std::vector<slod::Index> VertexToInput;
  std::vector<slod::Index> TriangleToCell; // input cell of each prepared triangle (empty: no cell data)
  slod::Patchification Patches;
  slod::SpbmLevelGenerator Generator;
  std::vector<std::string> Warnings;

  double RelativePlaneDistance = 0;
  double ChainInPlaneWeight = -1; // of the generator's chain hierarchy
  double ToleranceScale = 1;      // the patches were grown with the tolerances scaled by this
  double DeviationFactor = 0;     // PatchDeviationFactor of the cached patches
  double ThicknessScale = 1;      // the thickness bound of the cached patches is scaled by this
  double NoiseFraction = 0;       // PatchNoiseTolerance of the cached patches
  bool NoiseWithheld = false;     // the automatic noise tolerance was withheld (LoosenThickness)
  double MeanCurvature = 0;       // slod::MeanAbsoluteCurvature of the prepared input
  double Area = 0;                // the prepared input's area (ThicknessBound runs for every level)
  double PlaneDistanceCap = std::numeric_limits<double>::infinity(); // absolute, of the patch growth
  double LevelDeviation = -1;     // the level's deviation on every input vertex, when CollapseFinerLevel measured it
  std::vector<float> VertexBeyond; // with it: each input vertex's distance beyond the regions' allowance (else 0)
  // A count target that keeps at least MildTargetShare of the input (MildTargetRegionAllowance).
  bool MildTarget(vtkIdType target) const
  {
    return target > 0 && double(target) >= MildTargetShare * double(this->Mesh.NumberOfTriangles());
  }
  bool MildRegions(vtkPatchBoundaryMerge* self, vtkIdType target) const
  {
    return self->MildTargetRegionAllowance > 0 && this->MildTarget(target);
  }
  bool RegionsMayFollow(vtkPatchBoundaryMerge* self, vtkIdType target) const
  {
    return (self->RefineDeviatingRegions || this->MildRegions(self, target)) &&
      double(this->Patches.NoiseToleranceJoins()) < RegionNoiseJoinShare * double(this->Mesh.NumberOfTriangles());
  }
  // The regions' allowance: the share of the thickness bound as given (`bound`) beyond which a
  // patch's vertices mark it.
  double RegionAllowance(vtkPatchBoundaryMerge* self, vtkIdType target, double bound) const
  {
    return (this->MildRegions(self, target) ? self->MildTargetRegionAllowance : RegionAllowanceShare) * bound;
  }

  bool Matches(vtkPolyData* input, const slod::PatchificationParameters& p, double relativePlaneDistance) const
  {
    return this->Input == input && this->InputTime == input->GetMTime() &&
      this->Parameters.OneEdgePatchAngle == p.OneEdgePatchAngle &&
      this->Parameters.OneEdgeNeighborAngle == p.OneEdgeNeighborAngle &&
      this->Parameters.TwoEdgePatchAngle == p.TwoEdgePatchAngle &&
      this->Parameters.TwoEdgeNeighborAngle == p.TwoEdgeNeighborAngle &&
      this->Parameters.AreaWeighted == p.AreaWeighted && this->Parameters.BorderCornerAngle == p.BorderCornerAngle &&
      this->RelativePlaneDistance == relativePlaneDistance;
  }
  // Stages of RequestData (the cache is a nested struct: it reads the filter's settings).
  bool Build(vtkPatchBoundaryMerge* self, vtkPolyData* input, const slod::PatchificationParameters& patchParameters);
  bool GrowPatches(vtkPatchBoundaryMerge* self, const slod::MeshTopology& topology);
  bool FitPatchesToTarget(vtkPatchBoundaryMerge* self, vtkIdType target);
  double ThicknessBound(vtkPatchBoundaryMerge* self, vtkIdType target) const;
  bool FitPatchesToDeviation(vtkPatchBoundaryMerge* self, vtkIdType target);
  bool AutomaticNoiseTolerance(vtkPatchBoundaryMerge* self, vtkIdType target) const;
  double NoiseToleranceFraction(vtkPatchBoundaryMerge* self, vtkIdType target) const;
  bool GrowForPatchSetting(vtkPatchBoundaryMerge* self, vtkIdType target, double scale, bool noiseWithheld);
  bool LoosenThickness(
    vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result, slod::SpbmLevelParameters& level);
  bool CollapseFinerLevel(
    vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result, slod::SpbmLevelParameters& level);
  bool RefineRegions(
    vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result, const slod::SpbmLevelParameters& level);
  slod::Index MarkRegions(std::vector<unsigned char>& original, vtkIdType& triangles, bool passOverLarger) const;
  slod::SpbmLevelParameters LevelParameters(vtkPatchBoundaryMerge* self) const;
  bool GenerateLevel(
    vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result, slod::SpbmLevelParameters& level);
  void FinishWithCollapses(vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result);
  // The filter's count target (0: none, only an error bound).
  vtkIdType Target(vtkPatchBoundaryMerge* self) const
  {
    return self->ComputeTargetNumberOfTriangles(this->Mesh.NumberOfTriangles());
  }
  void WriteOutputs(vtkPatchBoundaryMerge* self, vtkPolyData* input, const slod::SpbmLevel& result,
    vtkPolyData* output, vtkPolyData* curves, vtkPolyData* colored);
  size_t MemoryUsage() const
  {
    return this->Mesh.Points.capacity() * sizeof(double) + this->Mesh.Triangles.capacity() * sizeof(slod::Index) +
      (this->VertexToInput.capacity() + this->TriangleToCell.capacity()) * sizeof(slod::Index) +
      this->Patches.MemoryUsage() +
      this->Generator.MemoryUsage();
  }
};

// Prepares the input (orientation repair only when needed), builds the patchification (and
// starts the input's BVH). False on invalid input or abort.
bool vtkPatchBoundaryMerge::Cache::Build(
  vtkPatchBoundaryMerge* self, vtkPolyData* input, const slod::PatchificationParameters& patchParameters)
{
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  this->Input = input;
  this->InputTime = input->GetMTime();
  this->Parameters = patchParameters;
  this->RelativePlaneDistance = self->PatchPlaneDistance;
  // Orientation repair is the costliest part of the preparation and most inputs do not need
  // it: prepare without it, and again with it only when an inconsistent edge shows up.
  slod::PreparationOptions options;
  options.MakeOrientationConsistent = false;
  slod::PreparationReport report = slod::PrepareTriangleMesh(
    input, options, this->Mesh, this->VertexToInput, slod::CellMapIfNeeded(input, this->TriangleToCell));
  const auto prepared = Clock::now();
  if (!report.Valid)
  {
    vtkErrorWithObjectMacro(self, "Cannot simplify this input: " << report.Error);
    return false;
  }
  self->UpdateProgress(0.05);
  Clock::time_point built;
  {
    auto topology = std::make_unique<slod::MeshTopology>(this->Mesh); // only needed while growing patches
    if (InconsistentEdges(this->Mesh, *topology) > 0)
    {
      report = slod::PrepareTriangleMesh(input, slod::PreparationOptions(), this->Mesh, this->VertexToInput,
        slod::CellMapIfNeeded(input, this->TriangleToCell));
      topology = std::make_unique<slod::MeshTopology>(this->Mesh);
    }
    this->Warnings = report.Warnings();
    if (report.NonManifoldEdges > 0)
    {
      this->Warnings.push_back("non-manifold edges are kept as patch borders at full resolution");
    }
    built = Clock::now(); // topology, orientation check
    this->MeanCurvature = slod::MeanAbsoluteCurvature(this->Mesh, *topology, slod::Radians(CreaseAngle));
    this->Area = this->Mesh.TotalArea();
    this->DeviationFactor = self->PatchDeviationFactor;
    this->NoiseFraction = self->PatchNoiseTolerance;
    this->PlaneDistanceCap = 0.5 * this->ThicknessBound(self, this->Target(self));
    if (!this->GrowPatches(self, *topology))
    {
      return false;
    }
  }
  vtkLogF(TRACE, "[spbm] preparation %.4f s, topology and orientation check %.4f s, patches %.4f s (%lld patches)",
    std::chrono::duration<double>(prepared - start).count(), std::chrono::duration<double>(built - prepared).count(),
    std::chrono::duration<double>(Clock::now() - built).count(), (long long)this->Patches.NumberOfPatches());
  return true;
}

// The automatic PatchNoiseTolerance (-1) applies: a count target below MildTargetShare.
bool vtkPatchBoundaryMerge::Cache::AutomaticNoiseTolerance(vtkPatchBoundaryMerge* self, vtkIdType target) const
{
  return this->NoiseFraction < 0 && self->PatchNoiseTolerance < 0 && target > 0 &&
    double(target) < MildTargetShare * double(this->Mesh.NumberOfTriangles());
}

// The PatchNoiseTolerance the patches are grown with: as set, or the automatic one (-1) unless
// LoosenThickness withheld it.
double vtkPatchBoundaryMerge::Cache::NoiseToleranceFraction(vtkPatchBoundaryMerge* self, vtkIdType target) const
{
  if (this->NoiseFraction >= 0)
  {
    return this->NoiseFraction;
  }
  return this->AutomaticNoiseTolerance(self, target) && !this->NoiseWithheld ? AggressiveTargetNoiseTolerance : 0.0;
}

// Grows the patches with the cached parameters scaled by ToleranceScale and builds the chain
// hierarchy (and, on the first growth, the input's BVH beside them). False when aborted.
bool vtkPatchBoundaryMerge::Cache::GrowPatches(vtkPatchBoundaryMerge* self, const slod::MeshTopology& topology)
{
  using Clock = std::chrono::steady_clock;
  slod::PatchificationParameters growth = this->Parameters;
  growth.OneEdgePatchAngle *= this->ToleranceScale;
  growth.OneEdgeNeighborAngle *= this->ToleranceScale;
  growth.MaximumPlaneDistance = this->ToleranceScale * self->PatchPlaneDistance * this->Mesh.BoundingBoxDiagonal();
  // A patch within d of its running plane is at most 2d thick (PatchDeviationFactor).
  growth.MaximumPlaneDistance = growth.MaximumPlaneDistance > 0
    ? std::min(growth.MaximumPlaneDistance, this->PlaneDistanceCap)
    : this->PlaneDistanceCap;
  // Mild targets only (at least MildTargetShare of the input kept): there the plane-distance cap is
  // within a few sags of one input triangle (cap / sag = 2 / share with PatchDeviationFactor 4).
  const vtkIdType target = this->Target(self);
  growth.SmallPatchTriangles =
    target > 0 && double(target) >= MildTargetShare * double(this->Mesh.NumberOfTriangles()) ? SmallPatchTriangles : 0;
  // The noise tolerance follows the plane distance (and so the target); none without a finite one.
  // Automatic (negative): on below the mild targets only.
  growth.NoiseTolerance = std::isfinite(growth.MaximumPlaneDistance)
    ? this->NoiseToleranceFraction(self, target) * growth.MaximumPlaneDistance
    : 0.0;
  const slod::ProgressFunction progress = slod::FilterProgress(self, 0.05, 0.65);
  auto initialize = [&]() {
    const auto initializing = Clock::now();
    this->Generator.Initialize(this->Mesh, this->Patches, self->ChainInPlaneWeight);
    this->ChainInPlaneWeight = self->ChainInPlaneWeight;
    vtkLogF(TRACE, "[spbm] chain hierarchy %.4f s", std::chrono::duration<double>(Clock::now() - initializing).count());
  };
  if (self->MinimumDeviationTriangulation && this->ToleranceScale == 1)
  {
    // The input's BVH (for the first level's triangulation) is built while the patches grow
    // (two vtkSMPTools tasks). (Built after the patch growth instead, the peak memory is about
    // 150 bytes per vertex lower, but the first level of a short search, e.g. bunny00 at 525
    // triangles, waits for it.) Progress events go out from the thread that runs the filter
    // only; the growth may run on another one, which then only checks for an abort.
    // The chain hierarchy is built in the same task: on smooth meshes the patches grow faster
    // than the BVH is built (mc1m), and the level's search needs the hierarchy, not the BVH.
    // (A regrowth for the target keeps that tree: Initialize with the same mesh keeps it.)
    const std::thread::id caller = std::this_thread::get_id();
    this->Generator.BuildInputTreeDuring(this->Mesh, [&]() {
      this->Patches.Build(this->Mesh, topology, growth, [&](double fraction) {
        return std::this_thread::get_id() == caller ? progress(fraction) : !self->GetAbortExecute();
      });
      if (!this->Patches.Aborted())
      {
        initialize();
      }
    });
  }
  else
  {
    this->Patches.Build(this->Mesh, topology, growth, progress);
    if (!this->Patches.Aborted())
    {
      initialize();
    }
  }
  return !this->Patches.Aborted();
}

// Issue 15: SPBM keeps no vertex inside a patch, so the finest level of a patchification (every
// chain vertex kept, at the given alpha1) can be below a mild target (mc1m at 10%: 60,038 of
// 100,165). Patches about k times smaller in angle have about 1/k times more boundary vertices,
// so the tolerances are scaled by (finest count / target) with a 10% margin, at most four times,
// until the finest level reaches the target within the count tolerance (2%). The last
// patchification is kept in the cache: later (coarser) targets reuse it. False when aborted.
bool vtkPatchBoundaryMerge::Cache::FitPatchesToTarget(vtkPatchBoundaryMerge* self, vtkIdType target)
{
  for (int round = 0; round < 4 && self->AdaptPatchesToTarget && target < this->Mesh.NumberOfTriangles(); ++round)
  {
    // The finest level's merging run (a whole run over every chain vertex: a third of the MRI's
    // merging time) is needed only when the cheap lower bound does not already reach the target.
    const vtkIdType bound = this->Generator.FinestLevelLowerBound();
    if (50 * bound >= 49 * target)
    {
      vtkLogF(TRACE, "[spbm] finest level at least %lld triangles (target %lld)", (long long)bound, (long long)target);
      break;
    }
    slod::SpbmLevelParameters finest = this->LevelParameters(self);
    finest.Epsilon = -1; // every chain vertex kept
    const vtkIdType count = this->Generator.FinestLevelCount(finest);
    vtkLogF(TRACE, "[spbm] finest level %lld triangles at tolerance scale %.4g (target %lld, lower bound %lld)",
      (long long)count, this->ToleranceScale, (long long)target, (long long)bound);
    if (50 * count >= 49 * target)
    {
      break;
    }
    this->ToleranceScale *= std::max(0.05, std::min(0.8, 0.9 * double(count) / double(target)));
    const slod::MeshTopology topology(this->Mesh);
    if (!this->GrowPatches(self, topology))
    {
      return false;
    }
  }
  return true;
}

// Issue 15: SPBM re-triangulates every patch flat from its boundary, so its distance from the
// input is about the patches' thickness. A budget of N triangles of the input's area A has
// triangles of edge s (s^2 = 4 A / (sqrt(3) N)), and a surface of curvature kappa bends by about
// kappa s^2 / 8 under such a triangle: the deviation any simplification to N triangles has
// (kappa without the creases, CreaseAngle: they are kept as chains, not flattened).
// The bound on a patch's thickness is PatchDeviationFactor times that (absolute; infinite
// without a count target or with the factor 0).
double vtkPatchBoundaryMerge::Cache::ThicknessBound(vtkPatchBoundaryMerge* self, vtkIdType target) const
{
  const double area = this->Area;
  if (self->PatchDeviationFactor <= 0 || target <= 0 || this->MeanCurvature <= 0 || area <= 0)
  {
    return std::numeric_limits<double>::infinity();
  }
  const double edgeSquared = 4.0 * area / (std::sqrt(3.0) * double(target));
  return this->ThicknessScale * self->PatchDeviationFactor * this->MeanCurvature * edgeSquared / 8.0;
}

// The patches are grown again (once) when the target's thickness bound is well below the one
// they were grown with (a finer target than the cached patches'); coarser targets reuse them, the
// merges are bounded by the target's own bound. False when aborted.
bool vtkPatchBoundaryMerge::Cache::FitPatchesToDeviation(vtkPatchBoundaryMerge* self, vtkIdType target)
{
  const double cap = 0.5 * this->ThicknessBound(self, target);
  if (!(cap < this->PlaneDistanceCap / 1.5))
  {
    return true;
  }
  vtkLogF(TRACE, "[spbm] patches grown again for the plane distance bound %.4g (was %.4g)", cap, this->PlaneDistanceCap);
  this->PlaneDistanceCap = cap;
  const slod::MeshTopology topology(this->Mesh);
  return this->GrowPatches(self, topology);
}

// The patches grown again for the target with the thickness bound scaled by `scale` and the
// automatic noise tolerance withheld or not (and fitted to the target's count again). False when
// aborted.
bool vtkPatchBoundaryMerge::Cache::GrowForPatchSetting(
  vtkPatchBoundaryMerge* self, vtkIdType target, double scale, bool noiseWithheld)
{
  this->ThicknessScale = scale;
  this->NoiseWithheld = noiseWithheld;
  this->PlaneDistanceCap = 0.5 * this->ThicknessBound(self, target);
  vtkLogF(TRACE, "[spbm] patches grown again with the thickness bound scaled by %g%s", scale,
    noiseWithheld ? ", without the automatic noise tolerance" : "");
  const slod::MeshTopology topology(this->Mesh);
  return this->GrowPatches(self, topology) && this->FitPatchesToTarget(self, target);
}

// LoosenThicknessForTarget (issue 15, sessions 29 and 30). The thickness bound follows the
// curvature and the target, but where the patches' corners alone nearly fill the budget (small
// patches on a surface bent both ways, flat regions between thin curved ones) the search keeps
// almost no chain vertex and the chains' epsilon, far above the bound, is the error
// (poly2x^2+y^2 at 50%: 33x). Such a level is made again from other patches and kept when its
// sampled deviation is smaller at a count no farther from the target:
// - first (session 30), when the automatic noise tolerance grew the patches (a coarse target),
//   without it: on a smooth or CAD surface, triangles that join a patch by their distance alone
//   make patches whose corners and flat re-triangulation cost more than a scan's noise would
//   (mannequin-devil at 10%: sampled deviation 5.2x the bound with it, 1.1x without);
// - then with the bound doubled (at most LooserThicknessRounds times): larger patches cost less
//   than their corners.
// The patches that made the kept level stay cached. False when aborted.
bool vtkPatchBoundaryMerge::Cache::LoosenThickness(
  vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result, slod::SpbmLevelParameters& level)
{
  if (!self->LoosenThicknessForTarget || self->GetMaximumError() > 0)
  {
    return true;
  }
  const vtkIdType tolerance = std::max<vtkIdType>(2, target / 50);
  auto miss = [&](const slod::SpbmLevel& l) {
    return std::max<vtkIdType>(tolerance, std::abs(vtkIdType(l.TrianglePatch.size()) - target));
  };
  double deviation = -1;
  bool regrown = false; // the cached patches are a rejected candidate's
  const bool noiseApplied = this->AutomaticNoiseTolerance(self, target) && !this->NoiseWithheld;
  for (int round = noiseApplied ? -1 : 0; round < LooserThicknessRounds; ++round)
  {
    const double thickness = this->ThicknessBound(self, target);
    if (!std::isfinite(thickness) || !(level.Epsilon > LooseEpsilonRatio * thickness))
    {
      break;
    }
    deviation = deviation < 0 ? this->Generator.EstimateDeviation(result, 3000, true) : deviation;
    vtkLogF(TRACE, "[spbm] thickness bound %.4g: epsilon %.3gx, sampled deviation %.3gx", thickness,
      level.Epsilon / thickness, deviation / thickness);
    if (!(deviation > LooseDeviationRatio * thickness))
    {
      break;
    }
    const double scale = this->ThicknessScale, toleranceScale = this->ToleranceScale;
    const bool withheld = this->NoiseWithheld;
    const vtkIdType collapses = self->FinalCollapseCount;
    slod::SpbmLevel candidate;
    slod::SpbmLevelParameters candidateLevel;
    const bool noiseTry = round < 0; // the same bound without the automatic noise tolerance
    if (!this->GrowForPatchSetting(self, target, noiseTry ? scale : 2 * scale, noiseTry || withheld) ||
      !this->GenerateLevel(self, target, candidate, candidateLevel))
    {
      return false;
    }
    const double candidateDeviation = this->Generator.EstimateDeviation(candidate, 3000, true);
    vtkLogF(TRACE, "[spbm] thickness scale %g%s: %zu triangles, sampled deviation %.4g (was %.4g)",
      this->ThicknessScale, this->NoiseWithheld ? " (noise tolerance withheld)" : "", candidate.TrianglePatch.size(),
      candidateDeviation, deviation);
    if (candidateDeviation < deviation && miss(candidate) <= miss(result))
    {
      std::swap(result, candidate);
      level = candidateLevel;
      deviation = candidateDeviation;
      regrown = false;
      continue;
    }
    // The former patches (grown again below when they are kept).
    self->FinalCollapseCount = collapses;
    this->ToleranceScale = toleranceScale;
    this->ThicknessScale = scale;
    this->NoiseWithheld = withheld;
    regrown = true;
    if (!noiseTry)
    {
      break;
    }
  }
  if (!regrown)
  {
    return true;
  }
  // The former patches made the better level: grown again, as they were.
  this->PlaneDistanceCap = 0.5 * this->ThicknessBound(self, target);
  const slod::MeshTopology topology(this->Mesh);
  return this->GrowPatches(self, topology);
}

// CollapseFinerLevelForTarget (issue 15, session 33). SPBM spends its budget on the patch corners
// and re-triangulates every patch flat, so where the patches of the target are too coarse for the
// surface (small smooth or curved CAD models: nefertiti, holes, horizons at 50-70%, 4x
// vtkQuadricDecimation's Hausdorff distance) the level is far from the input whatever the search
// chooses. A level of FinerLevelFactor times the target, made from patches grown for that count
// (thinner), is brought down to the target by the final collapses, which remove the vertices whose
// removal moves the surface least (quadric order); the level with the smaller deviation (every input
// vertex sampled) at a count no farther from the target is kept. Tried only when the level deviates
// by more than its patches were allowed to lie from their planes (below): first on the strided
// samples (cheap: the MRI's level stays below them), then on every vertex. False when aborted.
bool vtkPatchBoundaryMerge::Cache::CollapseFinerLevel(
  vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result, slod::SpbmLevelParameters& level)
{
  const vtkIdType finer = static_cast<vtkIdType>(FinerLevelFactor * double(target));
  if (!self->CollapseFinerLevelForTarget || !self->FinalCollapses || self->GetMaximumError() > 0 ||
    finer >= this->Mesh.NumberOfTriangles())
  {
    return true;
  }
  // The level misses what its patches were grown for when it deviates more than they were allowed
  // to lie from their planes: the plane-distance cap (FinerLevelDeviationShare of the bound) plus
  // the noise tolerance (that share again with the automatic one). Session 35 took patches the
  // tolerance had grown over less than a quarter of the input for a smooth mesh's (trigger at the
  // cap alone) and the others for a scan's (1.5x the bound): the kind of surface, not the level's
  // error, so it redid the segmentation mask's, the open scan's and mc1m's levels at 10% (0.77-0.94
  // of the bound, within the 3x of vtkQuadricDecimation's Hausdorff distance already) at
  // 2-5x their time. The scans' levels (MRI 0.78, noisy137 0.99) stay below the same trigger.
  const double noiseTolerance = this->NoiseToleranceFraction(self, target);
  const double share = FinerLevelDeviationShare * (1.0 + noiseTolerance);
  const double scale = this->ThicknessScale, toleranceScale = this->ToleranceScale;
  const double bound = this->ThicknessBound(self, target) / scale;
  const double trigger = share * bound;
  // The strided samples only rule out levels far below the trigger: they miss the few vertices
  // inside curved patches where a CAD level's error sits (fandisk at 50%: 0.67x the bound on every
  // vertex, the strided samples below the trigger).
  const double strided = (noiseTolerance > 0 ? TolerantStridedShare : FinerLevelStridedShare) * trigger;
  if (!std::isfinite(trigger) || !(trigger > 0))
  {
    return true;
  }
  const double stridedDeviation = this->Generator.EstimateDeviation(result, 3000, false);
  self->LevelDeviationShare = stridedDeviation / bound;
  if (!(stridedDeviation > strided))
  {
    return true;
  }
  // RefineRegions' per-vertex distances in the same pass (the same estimate).
  const bool regions = this->RegionsMayFollow(self, target);
  const auto leftOut = static_cast<slod::Index>(DeviationTailShare * double(this->Mesh.NumberOfPoints()));
  double tail = 0;
  const double deviation = this->Generator.EstimateDeviation(result, 3000, true,
    regions ? &this->VertexBeyond : nullptr, regions ? this->RegionAllowance(self, target, bound) : 0.0, leftOut, &tail);
  self->LevelDeviationShare = deviation / bound;
  self->LevelTailDeviationShare = tail / bound;
  this->LevelDeviation = deviation;
  vtkLogF(TRACE, "[spbm] level deviation %.3gx the thickness bound as given, %.3gx without the %d farthest samples "
    "(trigger %.3gx)", deviation / bound, tail / bound, int(leftOut), share);
  if (!(tail > trigger))
  {
    return true;
  }
  // The thickness bound scales as 1 / count: the finer count's bound is the target's scaled down.
  const vtkIdType collapses = self->FinalCollapseCount;
  slod::SpbmLevel candidate;
  slod::SpbmLevelParameters candidateLevel;
  self->FinerLevelTried = true;
  if (!this->GrowForPatchSetting(self, target, scale * double(target) / double(finer), this->NoiseWithheld) ||
    !this->FitPatchesToTarget(self, finer) || !this->GenerateLevel(self, finer, candidate, candidateLevel))
  {
    return false;
  }
  this->FinishWithCollapses(self, target, candidate);
  // At mild targets RefineRegions may follow on the kept level: the candidate's per-vertex distances
  // in the same pass (the same estimate).
  const bool mildRegions = regions && this->MildRegions(self, target);
  std::vector<float> candidateBeyond;
  const double candidateDeviation = this->Generator.EstimateDeviation(candidate, 3000, true,
    mildRegions ? &candidateBeyond : nullptr, mildRegions ? this->RegionAllowance(self, target, bound) : 0.0);
  vtkLogF(TRACE, "[spbm] finer level %lld collapsed to %zu triangles: deviation %.4g (was %.4g)", (long long)finer,
    candidate.TrianglePatch.size(), candidateDeviation, deviation);
  if (CandidateWins(target, candidate, candidateDeviation, result, deviation))
  {
    std::swap(result, candidate);
    level = candidateLevel;
    this->VertexBeyond.swap(candidateBeyond);
    this->LevelDeviation = mildRegions ? candidateDeviation : -1.0;
    return true;
  }
  // The former patches made the better level: grown again, as they were.
  self->FinalCollapseCount = collapses;
  this->ToleranceScale = toleranceScale;
  this->ThicknessScale = scale;
  this->PlaneDistanceCap = 0.5 * this->ThicknessBound(self, target);
  const slod::MeshTopology topology(this->Mesh);
  return this->GrowPatches(self, topology);
}

// Marks in `original` the patches whose vertices deviate from the level beyond the regions'
// allowance (VertexBeyond), the worst first, while their triangles (`triangles`) stay within
// RegionTriangleShare of the input's. Returns the number marked.
slod::Index vtkPatchBoundaryMerge::Cache::MarkRegions(
  std::vector<unsigned char>& original, vtkIdType& triangles, bool passOverLarger) const
{
  std::vector<double> patchDeviation;
  const slod::Index beyond = this->Generator.PatchDeviationsFromVertices(this->VertexBeyond, patchDeviation);
  original.assign(patchDeviation.size(), 0);
  std::vector<std::pair<double, slod::Index>> worst;
  worst.reserve(size_t(beyond));
  for (size_t p = 0; p < patchDeviation.size(); ++p)
  {
    if (patchDeviation[p] > 0)
    {
      worst.emplace_back(-patchDeviation[p], static_cast<slod::Index>(p));
    }
  }
  std::sort(worst.begin(), worst.end());
  const double budget = RegionTriangleShare * double(this->Mesh.NumberOfTriangles());
  triangles = 0;
  slod::Index marked = 0;
  for (const auto& patch : worst)
  {
    const vtkIdType more = this->Patches.PatchTriangleCount(patch.second);
    if (double(triangles + more) > budget)
    {
      if (passOverLarger)
      {
        continue;
      }
      break;
    }
    triangles += more;
    original[size_t(patch.second)] = 1;
    ++marked;
  }
  vtkLogF(TRACE, "[spbm] %d patches deviate beyond the allowance; %d of them refined (%lld triangles, at most %.0f)",
    int(beyond), int(marked), (long long)triangles, budget);
  return marked;
}

// RefineDeviatingRegions (issue 15, session 37). CollapseFinerLevel redoes the whole level, at 2-5x
// its time, when the whole level deviates beyond its patches' allowance; below that (most smooth and
// CAD levels at coarse targets: 0.5-0.9 of the bound) the level misses the quality of the finer level
// only in a few regions. Those regions' patches (MarkRegions) are kept as their original triangles in
// one more generation pass (the merging run replayed with them frozen, as a fallback pass) and the
// final collapses (quadric order) bring the level back to the target: the collapses take the
// region's cheapest vertices first, so it ends about as dense as its curvature needs. The level
// with the smaller deviation (every input vertex) at a count no farther from the target is kept.
// Session 38: the pass goes on from the level's own last pass (KeepLastPass: only the patches
// around the marked ones are triangulated again) and the refined level is measured only near the
// triangles that changed (EstimateDeviationNear): its cost follows the refined share. False when
// aborted.
bool vtkPatchBoundaryMerge::Cache::RefineRegions(
  vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result, const slod::SpbmLevelParameters& level)
{
  // After the finer level only at mild targets (MildTargetRegionAllowance): its every-vertex pass
  // measured the per-vertex distances of the level kept (CollapseFinerLevel).
  if (!(self->RefineDeviatingRegions || this->MildRegions(self, target)) || !self->FinalCollapses ||
    (self->FinerLevelTried && !this->MildRegions(self, target)) ||
    self->GetMaximumError() > 0 || target <= 0 || target >= this->Mesh.NumberOfTriangles())
  {
    return true;
  }
  if (!this->RegionsMayFollow(self, target))
  {
    vtkLogF(TRACE, "[spbm] regions not refined: the noise tolerance joined %lld triangles the angle tests refuse",
      (long long)this->Patches.NoiseToleranceJoins());
    return true;
  }
  const double bound = this->ThicknessBound(self, target) / this->ThicknessScale;
  const double allowance = this->RegionAllowance(self, target, bound);
  // The level's strided samples (measured by CollapseFinerLevel) far below the allowance: every
  // vertex is too, nearly always (the strided check of CollapseFinerLevel, same share).
  if (!std::isfinite(allowance) || !(allowance > 0) ||
    (self->LevelDeviationShare >= 0 && self->LevelDeviationShare * bound < FinerLevelStridedShare * allowance))
  {
    return true;
  }
  if (this->LevelDeviation < 0 || this->VertexBeyond.empty())
  {
    // CollapseFinerLevel's strided check ruled the level out: every vertex now, with the distances
    // beyond the allowance in the same pass.
    this->LevelDeviation = this->Generator.EstimateDeviation(result, 3000, true, &this->VertexBeyond, allowance);
  }
  std::vector<unsigned char> original;
  vtkIdType regionTriangles = 0;
  const slod::Index marked = this->MarkRegions(original, regionTriangles, this->MildRegions(self, target));
  if (marked == 0)
  {
    return true;
  }
  const vtkIdType collapses = self->FinalCollapseCount;
  slod::SpbmLevel candidate;
  auto abort = [self]() { return self->GetAbortExecute() != 0; };
  if (!this->Generator.GenerateWithOriginalPatches(level, original, candidate, abort, &result))
  {
    return false;
  }
  self->RegionInputTriangles = regionTriangles;
  self->RegionRetriangulatedTriangles = candidate.RetriangulatedTriangles;
  this->FinishWithCollapses(self, target, candidate);
  double deviation = this->LevelDeviation;
  slod::Index measured = 0;
  double candidateDeviation =
    this->Generator.EstimateDeviationNear(candidate, result, this->VertexBeyond, allowance, 3000, &measured);
  const bool mild = this->MildRegions(self, target);
  if (mild)
  {
    // Session 45: the final collapses spread the refined region's budget over the level, and their
    // triangles can stray from the input where no input vertex sees it (the Fandisk and cheese at
    // 50%: the input side 15-20% closer, the level side 20-25% farther). Both levels' own sides
    // where they differ count too.
    deviation = std::max(deviation, this->Generator.ChangedTriangleDeviation(result, candidate));
    candidateDeviation = std::max(candidateDeviation, this->Generator.ChangedTriangleDeviation(candidate, result));
  }
  vtkLogF(TRACE,
    "[spbm] %d regions' patches refined (%lld input triangles; %lld level triangles triangulated again): %zu "
    "triangles, deviation %.4g (was %.4g; %d vertices measured)",
    int(marked), (long long)regionTriangles, (long long)candidate.RetriangulatedTriangles,
    candidate.TrianglePatch.size(), candidateDeviation, deviation, int(measured));
  if (CandidateWins(target, candidate, candidateDeviation, result, deviation * (mild ? MildRegionGain : 1.0)))
  {
    std::swap(result, candidate);
    self->RegionRefinedPatches = marked;
    return true;
  }
  self->FinalCollapseCount = collapses;
  return true;
}

// The level parameters from the filter's settings (epsilon and targets aside).
slod::SpbmLevelParameters vtkPatchBoundaryMerge::Cache::LevelParameters(vtkPatchBoundaryMerge* self) const
{
  slod::SpbmLevelParameters level;
  level.MergeAngle = self->MergeAngle;
  level.MergePatches = self->MergePatches;
  level.CollapseChains = self->CollapseChains;
  level.CollapseLengthFactor = self->CollapseLengthFactor;
  level.CompareCandidates = self->CompareCandidates;
  level.CostOrderedRemoval = self->CostOrderedRemoval;
  level.SizeWeightedMerge = self->SizeWeightedMerge;
  level.MinimumDeviationTriangulation = self->MinimumDeviationTriangulation;
  level.FinalCollapsesFollow = self->FinalCollapses;
  level.LateFailureShare = self->LateFailureShare;
  const double thickness = this->ThicknessBound(self, this->Target(self));
  level.MaximumPatchThickness = std::isfinite(thickness) && this->Mesh.BoundingBoxDiagonal() > 0
    ? thickness / this->Mesh.BoundingBoxDiagonal()
    : 0.0;
  return level;
}

// The level for the filter's target, error bound or epsilon. False when aborted.
bool vtkPatchBoundaryMerge::Cache::GenerateLevel(
  vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result, slod::SpbmLevelParameters& level)
{
  const slod::TriangleMesh& mesh = this->Mesh;
  // The error bound is the chain tolerance epsilon (the paper's parameter); the target search
  // sets its own epsilon.
  const double bound = self->AbsoluteMaximumError(mesh.BoundingBoxDiagonal());
  level = this->LevelParameters(self);
  level.Epsilon = bound;
  // The filter contract's targets (slodFilterContract.h): an error bound alone is the level of that
  // epsilon (the paper's use); nothing set is the default reduction.
  auto abort = [self]() { return self->GetAbortExecute() != 0; };
  if (target >= mesh.NumberOfTriangles())
  {
    // No reduction asked for: the (prepared) input itself, with its patches and chains.
    result.Triangles = mesh.Triangles;
    result.TrianglePatch = this->Patches.TrianglePatches();
    result.NumberOfPatches = this->Patches.NumberOfPatches();
    result.CurveOffsets.assign(1, 0);
    for (slod::Index c = 0; c < this->Patches.NumberOfChains(); ++c)
    {
      const slod::Index* v = this->Patches.ChainVerticesBegin(c);
      result.CurveVertices.insert(result.CurveVertices.end(), v, v + this->Patches.ChainSize(c));
      result.CurveOffsets.push_back(static_cast<slod::Index>(result.CurveVertices.size()));
    }
    level.Epsilon = 0;
  }
  else if (target > 0)
  {
    const slod::SpbmLevelParameters base = level;
    if (!this->Generator.GenerateForTarget(
          static_cast<slod::Index>(std::min<vtkIdType>(target, VTK_INT_MAX)), base, result, &level, abort))
    {
      return false;
    }
    if (bound > 0 && level.Epsilon > bound)
    {
      // The error bound is reached before the target: stop there.
      level = base;
      if (!this->Generator.Generate(level, result, abort))
      {
        return false;
      }
    }
    else if (self->FinalCollapses)
    {
      this->FinishWithCollapses(self, target, result);
    }
  }
  else if (!this->Generator.Generate(level, result, abort))
  {
    return false;
  }
  return true;
}

// A count target beyond the patches: the level's own vertices are collapsed (FinalCollapses).
void vtkPatchBoundaryMerge::Cache::FinishWithCollapses(vtkPatchBoundaryMerge* self, vtkIdType target, slod::SpbmLevel& result)
{
  slod::SpbmFinalCollapseStatistics statistics;
  slod::SpbmFinalCollapses(
    this->Mesh, static_cast<slod::Index>(std::min<vtkIdType>(target, VTK_INT_MAX)), result, statistics);
  self->FinalCollapseCount = statistics.Collapses;
  vtkLogF(TRACE, "[spbm] final collapses: %d -> %zu triangles, %d collapses, %lld checks, %d stages%s",
    static_cast<int>(statistics.StartTriangles), result.TrianglePatch.size(), static_cast<int>(statistics.Collapses),
    statistics.Attempts, statistics.Stages, statistics.WorkBoundReached ? ", work bound" : "");
  for (int status = 1; status < 10; ++status)
  {
    if (statistics.Refused[status] > 0)
    {
      vtkLogF(TRACE, "[spbm] final collapses refused (%s): %lld",
        slod::ToString(static_cast<slod::CollapseStatus>(status)), statistics.Refused[status]);
    }
  }
}

// The simplified mesh with patch ids, the profile curves and (optionally) the input colored by patch.
void vtkPatchBoundaryMerge::Cache::WriteOutputs(vtkPatchBoundaryMerge* self, vtkPolyData* input,
  const slod::SpbmLevel& result, vtkPolyData* output, vtkPolyData* curves, vtkPolyData* colored)
{
  const slod::TriangleMesh& mesh = this->Mesh;
  slod::FirstUseNumbering numbering(mesh.NumberOfPoints());
  const std::vector<slod::Index>& used = numbering.Used;
  auto use = [&](slod::Index v) { return static_cast<vtkIdType>(numbering(v)); };
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(static_cast<vtkIdType>(result.TrianglePatch.size()), static_cast<vtkIdType>(result.Triangles.size()));
  for (size_t t = 0; t < result.TrianglePatch.size(); ++t)
  {
    const vtkIdType ids[3] = { use(result.Triangles[3 * t]), use(result.Triangles[3 * t + 1]),
      use(result.Triangles[3 * t + 2]) };
    polys->InsertNextCell(3, ids);
  }
  vtkNew<vtkCellArray> lines;
  for (size_t c = 0; c + 1 < result.CurveOffsets.size(); ++c)
  {
    lines->InsertNextCell(result.CurveOffsets[c + 1] - result.CurveOffsets[c]);
    for (slod::Index i = result.CurveOffsets[c]; i < result.CurveOffsets[c + 1]; ++i)
    {
      lines->InsertCellPoint(use(result.CurveVertices[i]));
    }
  }
  slod::StoreUsedPoints(input, mesh, used, this->VertexToInput, self->OutputPointsPrecision, output);
  vtkNew<vtkIntArray> patchIds;
  patchIds->SetName("PatchId");
  patchIds->SetNumberOfValues(static_cast<vtkIdType>(result.TrianglePatch.size()));
  for (size_t t = 0; t < result.TrianglePatch.size(); ++t)
  {
    patchIds->SetValue(static_cast<vtkIdType>(t), result.TrianglePatch[t]);
  }
  output->SetPolys(polys);
  slod::StoreNearestCellData(input, this->TriangleToCell, mesh, mesh.Points, result.Triangles, output);
  output->GetCellData()->AddArray(patchIds);
  curves->SetPoints(output->GetPoints());
  curves->GetPointData()->ShallowCopy(output->GetPointData());
  curves->SetLines(lines);

  if (self->GeneratePatchColoredInput)
  {
    slod::MeshToPolyData(mesh, colored, output->GetPoints()->GetDataType());
    std::vector<slod::Index> itself(size_t(mesh.NumberOfTriangles()));
    std::iota(itself.begin(), itself.end(), 0);
    slod::StoreCellData(input, this->TriangleToCell, itself, colored);
    vtkNew<vtkIntArray> inputPatch;
    inputPatch->SetName("PatchId");
    inputPatch->SetNumberOfValues(mesh.NumberOfTriangles());
    const std::vector<slod::Index>& patchOf = this->Patches.TrianglePatches();
    for (slod::Index t = 0; t < mesh.NumberOfTriangles(); ++t)
    {
      inputPatch->SetValue(t, patchOf[t]);
    }
    colored->GetCellData()->AddArray(inputPatch);
  }}

vtkPatchBoundaryMerge::vtkPatchBoundaryMerge()
{
  this->SetNumberOfOutputPorts(3);
}

vtkPatchBoundaryMerge::~vtkPatchBoundaryMerge() = default;

void vtkPatchBoundaryMerge::ReleaseCache()
{
  this->Cached.reset();
  this->CacheMemory = 0;
  this->Modified();
}

// RefineDeviatingRegions' field data, only when the refined level is kept (the other outputs stay as
// they were): the patches, and the work of the pass that refined them.
void vtkPatchBoundaryMerge::ReportRefinedRegions(vtkPolyData* output) const
{
  if (this->RegionRefinedPatches <= 0)
  {
    return;
  }
  const std::pair<const char*, vtkIdType> values[] = { { "RegionRefinedPatches", this->RegionRefinedPatches },
    { "RegionInputTriangles", this->RegionInputTriangles },
    { "RegionRetriangulatedTriangles", this->RegionRetriangulatedTriangles } };
  for (const auto& value : values)
  {
    vtkNew<vtkIdTypeArray> array;
    array->SetName(value.first);
    array->InsertNextValue(value.second);
    output->GetFieldData()->AddArray(array);
  }
}

namespace
{
// The late replays of a level: those after its first replay whose refinement of the non-simple
// patches was made again (not reused), with what had changed when each began (summed into the
// filter's results).
void CountLateReplays(const slod::SpbmLevel& result, int& replays, vtkIdType& changed, vtkIdType& tests)
{
  bool replayedBefore = false;
  for (size_t pass = 0; pass < result.PassDirtyPatches.size() && pass < result.PassBoundaryTests.size(); ++pass)
  {
    if (result.PassDirtyPatches[pass] < 0)
    {
      continue; // not a replay
    }
    if (replayedBefore && result.PassBoundaryTests[pass] >= 0)
    {
      ++replays;
      changed += vtkIdType(result.PassDirtyPatches[pass]);
      tests += vtkIdType(result.PassBoundaryTests[pass]);
    }
    replayedBefore = true;
  }
}
} // namespace

int vtkPatchBoundaryMerge::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  using Clock = std::chrono::steady_clock;
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* curves = vtkPolyData::GetData(outputVector, 1);
  vtkPolyData* colored = vtkPolyData::GetData(outputVector, 2);
  if (!input || !output || !curves || !colored)
  {
    return 0;
  }
  this->NumberOfMergedPatches = 0;
  this->UnmergedPatches = 0;
  this->RefinedPatches = 0;
  this->OriginalPatches = 0;
  this->GenerationPasses = 0;
  this->LateOriginalPatches = 0;
  this->LateReplays = 0;
  this->LateReplayChangedPatches = 0;
  this->LateReplayBoundaryTests = 0;
  this->FinalCollapseCount = 0;
  this->FinerLevelTried = false;
  this->LevelDeviationShare = -1.0;
  this->LevelTailDeviationShare = -1.0;
  this->RegionRefinedPatches = 0;
  this->RegionInputTriangles = -1;
  this->RegionRetriangulatedTriangles = -1;
  this->PatchificationTime = 0;
  this->LevelTime = 0;

  slod::PatchificationParameters patchParameters;
  patchParameters.OneEdgePatchAngle = this->PatchAngle;
  patchParameters.OneEdgeNeighborAngle = this->NeighborAngle;
  patchParameters.TwoEdgePatchAngle = this->TwoEdgePatchAngle;
  patchParameters.TwoEdgeNeighborAngle = this->TwoEdgeNeighborAngle;
  patchParameters.AreaWeighted = this->AreaWeightedNormals;
  patchParameters.RulingAngle = RulingAngle;
  patchParameters.BorderCornerAngle = this->BorderCornerAngle;
  // SPBM re-triangulates each patch flat: its thickness is the error (mc1m at 10%: Hausdorff 3.4x
  // vtkQuadricDecimation's without, 2.6x with).
  patchParameters.BoundPatchThickness = true;

  // 1. Patchification (cached).
  const auto start = Clock::now();
  this->PatchificationReused =
    this->Cached && this->Cached->Matches(input, patchParameters, this->PatchPlaneDistance) &&
    this->Cached->DeviationFactor == this->PatchDeviationFactor &&
    this->Cached->NoiseFraction == this->PatchNoiseTolerance;
  if (!this->PatchificationReused)
  {
    this->Cached.reset(new Cache);
    if (!this->Cached->Build(this, input, patchParameters))
    {
      const bool aborted = this->Cached->Patches.Aborted();
      this->Cached.reset();
      if (aborted)
      {
        slod::ReportAbort(this, output);
      }
      return 1;
    }
  }
  Cache& cache = *this->Cached;
  if (cache.ChainInPlaneWeight != this->ChainInPlaneWeight)
  {
    const auto initializing = Clock::now();
    cache.Generator.Initialize(cache.Mesh, cache.Patches, this->ChainInPlaneWeight);
    cache.ChainInPlaneWeight = this->ChainInPlaneWeight;
    vtkLogF(TRACE, "[spbm] chain hierarchy %.4f s", std::chrono::duration<double>(Clock::now() - initializing).count());
  }
  for (const std::string& warning : cache.Warnings)
  {
    vtkWarningMacro(<< warning);
  }
  const auto patched = Clock::now();
  if (!this->PatchificationReused)
  {
    this->PatchificationTime = std::chrono::duration<double>(patched - start).count();
  }
  this->UpdateProgress(0.7);
  const slod::TriangleMesh& mesh = cache.Mesh;
  if (mesh.NumberOfTriangles() == 0)
  {
    return 1;
  }

  // 2. The level.
  slod::SpbmLevelParameters level;
  slod::SpbmLevel result;
  const vtkIdType target = cache.Target(this);
  const double previousToleranceScale = cache.ToleranceScale;
  const bool previousNoiseWithheld = cache.NoiseWithheld;
  cache.ThicknessScale = 1; // every target starts from the bound as given (LoosenThickness)
  if (target > 0 && (!cache.FitPatchesToDeviation(this, target) || !cache.FitPatchesToTarget(this, target)))
  {
    this->Cached.reset();
    slod::ReportAbort(this, output);
    return 1;
  }
  const bool loosen = target > 0 && target < mesh.NumberOfTriangles();
  cache.LevelDeviation = -1;
  cache.VertexBeyond.clear();
  // RefineRegions goes on from the level's last pass.
  cache.Generator.KeepLastPass(loosen && this->FinalCollapses && cache.RegionsMayFollow(this, target));
  if (!cache.GenerateLevel(this, target, result, level) || (loosen && !cache.LoosenThickness(this, target, result, level)) ||
    (loosen && !cache.CollapseFinerLevel(this, target, result, level)) ||
    (loosen && !cache.RefineRegions(this, target, result, level)))
  {
    this->Cached.reset();
    slod::ReportAbort(this, output); // the level's generation fails only when aborted
    return 1;
  }
  cache.Generator.KeepLastPass(false); // its memory back
  this->PatchificationReused = this->PatchificationReused && cache.ToleranceScale == previousToleranceScale &&
    cache.ThicknessScale == 1 && cache.NoiseWithheld == previousNoiseWithheld;
  this->PatchToleranceScale = cache.ToleranceScale;
  this->PatchThicknessScale = cache.ThicknessScale;
  this->NoiseToleranceWithheld = cache.NoiseWithheld;
  {
    const slod::SpbmLevelParameters bounded = cache.LevelParameters(this);
    this->PatchThicknessBound = bounded.MaximumPatchThickness;
  }
  this->NumberOfPatches = cache.Patches.NumberOfPatches();
  this->NumberOfChains = cache.Patches.NumberOfChains();
  this->UsedEpsilon = level.Epsilon < 0 ? 0.0 : level.Epsilon;
  this->UsedMergeAngle = level.MergeAngle;
  this->NumberOfMergedPatches = result.NumberOfPatches;
  this->UnmergedPatches = result.UnmergedPatches;
  this->RefinedPatches = result.RefinedPatches;
  this->OriginalPatches = result.OriginalPatches;
  this->GenerationPasses = result.Passes;
  this->LateOriginalPatches = result.LateOriginalPatches;
  CountLateReplays(result, this->LateReplays, this->LateReplayChangedPatches, this->LateReplayBoundaryTests);
  this->UpdateProgress(0.9);

  // 3. Outputs over the original vertices that are used.
  cache.WriteOutputs(this, input, result, output, curves, colored);
  this->ReportRefinedRegions(output);
  if (target > 0 && target < mesh.NumberOfTriangles())
  {
    slod::SpbmLevelParameters finest = cache.LevelParameters(this);
    finest.Epsilon = -1; // every chain vertex kept; -1 when not known in closed form
    ReportTargetCount(this, mesh, output, target, cache.Generator.FinestLevelCountWithoutRun(finest));
  }
  this->CacheMemory = static_cast<vtkIdType>(cache.MemoryUsage());
  this->LevelTime = std::chrono::duration<double>(Clock::now() - patched).count();
  this->UpdateProgress(1.0);
  return 1;
}

void vtkPatchBoundaryMerge::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "AreaWeightedNormals: " << this->AreaWeightedNormals << "\n";
  os << indent << "PatchPlaneDistance: " << this->PatchPlaneDistance << "\n";
  os << indent << "PatchDeviationFactor: " << this->PatchDeviationFactor << "\n";
  os << indent << "PatchNoiseTolerance: " << this->PatchNoiseTolerance << "\n";
  os << indent << "BorderCornerAngle: " << this->BorderCornerAngle << "\n";
  os << indent << "MergeAngle: " << this->MergeAngle << "\n";
  os << indent << "MergePatches: " << this->MergePatches << "\n";
  os << indent << "CollapseChains: " << this->CollapseChains << "\n";
  os << indent << "CollapseLengthFactor: " << this->CollapseLengthFactor << "\n";
  os << indent << "SizeWeightedMerge: " << this->SizeWeightedMerge << "\n";
  os << indent << "CompareCandidates: " << this->CompareCandidates << "\n";
  os << indent << "CostOrderedRemoval: " << this->CostOrderedRemoval << "\n";
  os << indent << "ChainInPlaneWeight: " << this->ChainInPlaneWeight << "\n";
  os << indent << "MinimumDeviationTriangulation: " << this->MinimumDeviationTriangulation << "\n";
  os << indent << "MaximumError: " << this->MaximumError << (this->MaximumErrorIsRelative ? " (relative)" : " (absolute)")
     << "\n";
  os << indent << "GeneratePatchColoredInput: " << this->GeneratePatchColoredInput << "\n";
  os << indent << "FinalCollapses: " << this->FinalCollapses << "\n";
  os << indent << "LateFailureShare: " << this->LateFailureShare << "\n";
  os << indent << "CollapseFinerLevelForTarget: " << this->CollapseFinerLevelForTarget << "\n";
  os << indent << "RefineDeviatingRegions: " << this->RefineDeviatingRegions << "\n";
  os << indent << "MildTargetRegionAllowance: " << this->MildTargetRegionAllowance << "\n";
  os << indent << "NumberOfPatches: " << this->NumberOfPatches << "\n";
  os << indent << "NumberOfMergedPatches: " << this->NumberOfMergedPatches << "\n";
  os << indent << "UsedEpsilon: " << this->UsedEpsilon << "\n";
  os << indent << "UsedMergeAngle: " << this->UsedMergeAngle << "\n";
  os << indent << "PatchificationReused: " << this->PatchificationReused << "\n";
}
