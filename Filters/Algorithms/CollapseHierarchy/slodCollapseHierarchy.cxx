// SPDX-License-Identifier: BSD-3-Clause
#include "slodCollapseHierarchy.h"

#include "slodFreedMemory.h"
#include "slodInputPreparation.h"
#include "slodQuadricPoint.h"

#include "vtkLogger.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <numeric>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h> // madvise: CompactRows gives the pages of the freed rows back
#include <unistd.h>
#endif

namespace slod
{

namespace
{
constexpr Index Never = std::numeric_limits<Index>::max();
constexpr Index MaximumFitPoints = 64;
// Far above the valences collapses leave on ordinary meshes (about 3 to 20); a fan's centre or a
// cone's apex has thousands.
constexpr Index HubValence = 64;
// Triangles evaluated together (their working evaluations, 117 bytes each with the chunk's ids,
// are scratch): 4,096 of them (16,384 before session 36: 3.8 bytes per input vertex of mc1m's
// peak, 1.9 MB, where 4,096 take 0.5 MB; a chunk is still many times the threads' grain).
constexpr Index EvaluationChunk = Index(1) << 12;
// The priority order's bounds are taken from the triangles of every 16th slot.
constexpr Index SampleStride = 16;

// Gives the pages of values' room beyond its size back to the system without moving it.
// shrink_to_fit copies: the copy and the old array at once were the peak of the build, and the
// old one, when on the heap below newer blocks, stayed resident after it was freed (glibc only
// returns the heap's top). The contents beyond the size are not needed (a later growth writes
// them); on Linux the pages read as zero if touched again.
template <typename T>
void ReleaseRoomBeyondSize(std::vector<T>& values)
{
#if defined(__linux__)
  const std::uintptr_t page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(values.data() + values.size()) + page - 1) & ~(page - 1);
  const std::uintptr_t end = reinterpret_cast<std::uintptr_t>(values.data() + values.capacity()) & ~(page - 1);
  if (end > begin)
  {
    madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED);
  }
#else
  values.shrink_to_fit();
#endif
}

// Gives the arrays' memory back (empty, no room).
template <typename... Arrays>
void ReleaseArrays(Arrays&... arrays)
{
  (Arrays().swap(arrays), ...);
}

// Keeps the rows of values whose bit is set in kept (LiveRowIndex::Renumber), in order, as rows
// 0, 1, ... (perRow elements each) and gives the rest back: in place, since a row only moves down.
template <typename T>
void KeepRows(std::vector<T>& values, const std::vector<std::uint64_t>& kept, size_t perRow)
{
  if (values.empty())
  {
    return; // (not allocated: a rule set or the edge costs were not used)
  }
  // Runs of kept rows at once (a move per run instead of per row: the compactions of the first
  // levels keep most rows, and row by row the byte arrays cost more than the compaction's walk).
  size_t r = 0;
  for (size_t w = 0; w < kept.size(); ++w)
  {
    for (std::uint64_t bits = kept[w]; bits != 0;)
    {
      const unsigned first = unsigned(__builtin_ctzll(bits));
      const std::uint64_t rest = ~(bits >> first); // (bit 0 clear: the run's end is its first set bit)
      const unsigned length = rest == 0 ? 64 : unsigned(__builtin_ctzll(rest));
      const size_t oldRow = 64 * w + first;
      if (oldRow != r)
      {
        // (Moves down: the destination starts before the source, as std::copy allows.)
        std::copy(values.begin() + perRow * oldRow, values.begin() + perRow * (oldRow + length), values.begin() + perRow * r);
      }
      r += length;
      bits = first + length >= 64 ? 0 : bits & ~(((std::uint64_t(1) << length) - 1) << first);
    }
  }
  values.resize(perRow * r);
  ReleaseRoomBeyondSize(values);
}

// Whether compacting rows rows down to live pays: at any dead row while the rows are more than
// half of all (the peak of the build is there: the working data whole and the hierarchy growing;
// 7/8 left it 16 bytes per input vertex higher on mc1m, and since session 40 a level's batch is
// compacted in two steps there, CollapseBatch), at 7/8 while more than a quarter, at half below
// (each compaction scans every slot: on refined_elephant's whole build 7/8 throughout cost 3% of
// the instructions).
bool WorthCompacting(size_t live, size_t rows, size_t all)
{
  if (4 * rows > all)
  {
    return live < rows;
  }
  return 2 * live < rows;
}

// A triangle at its weight in a level's priority order, ordered as the pair (weight, triangle)
// but packed in 12 bytes instead of 16 (the order holds every live triangle).
#pragma pack(push, 4)
struct RankedTriangle
{
  double Weight;
  Index Triangle;
  bool operator<(const RankedTriangle& o) const
  {
    return this->Weight < o.Weight || (!(o.Weight < this->Weight) && this->Triangle < o.Triangle);
  }
};
#pragma pack(pop)
static_assert(sizeof(RankedTriangle) == sizeof(double) + sizeof(Index), "packed");

// Gieng et al.'s alpha = 2 (cos A + cos B + cos C - 1) = 2 r / R: 1 equilateral, 0 degenerate.
double Roundness(const Vec3& a, const Vec3& b, const Vec3& c)
{
  double cosSum = 0;
  // Edge k runs from corner k to corner k + 1; corner k's two edges are edge k and edge k + 2
  // reversed (a reversed difference and its dot product are the same numbers negated, exactly),
  // so each length is computed once.
  const Vec3 edges[3] = { b - a, c - b, a - c };
  const double lengths[3] = { Norm(edges[0]), Norm(edges[1]), Norm(edges[2]) };
  for (int k = 0; k < 3; ++k)
  {
    const double nu = lengths[k], nw = lengths[(k + 2) % 3];
    cosSum += (nu > 0 && nw > 0) ? -Dot(edges[k], edges[(k + 2) % 3]) / (nu * nw) : 1.0;
  }
  return std::min(1.0, std::max(0.0, 2.0 * (cosSum - 1.0)));
}


// The link edges of triangle tri: for each triangle around one of T's vertices that holds no
// other of them, its edge (a, b) opposite that vertex, in its orientation. The triangles of
// EditableMesh::ForEachSurvivingTriangle(tri, 3), in its order, with fewer comparisons (the
// evaluations walk every new vertex's neighbourhood this way).
template <typename Functor>
void ForEachLinkEdge(const EditableMesh& m, const Index* tri, Functor&& f)
{
  for (int k = 0; k < 3; ++k)
  {
    const Index v = tri[k], next = tri[(k + 1) % 3], previous = tri[(k + 2) % 3];
    m.ForEachTriangle(v, [&](Index x) {
      const Index* o = m.Triangle(x);
      const int corner = o[0] == v ? 0 : (o[1] == v ? 1 : 2);
      const Index a = o[(corner + 1) % 3], b = o[(corner + 2) % 3];
      if (a != next && a != previous && b != next && b != previous)
      {
        f(a, b);
      }
    });
  }
}

// The link edge (a, b) turns counter-clockwise around point seen along normal.
bool LinkEdgeTurns(const Vec3& a, const Vec3& b, const Vec3& point, const Vec3& normal)
{
  const Vec3 u = a - point, w = b - point;
  return Dot(Cross(u, w), normal) > 1e-12 * (Dot(u, u) + Dot(w, w));
}

// The quadric's point nearest the midpoint of edge (pu, pv), accepted when finite and within an
// edge length of the midpoint (farther is a poorly constrained extrapolation).
bool EdgeOptimum(const Quadric& q, const Vec3& pu, const Vec3& pv, Vec3& best)
{
  const Vec3 mid = 0.5 * (pu + pv);
  best = QuadricPointNear(q, mid);
  return std::isfinite(best[0]) && std::isfinite(best[1]) && std::isfinite(best[2]) && Norm(best - mid) <= Norm(pv - pu);
}

// A collapse check that failed on the vertex set alone (its topology: the link condition, the
// borders, dead, locked or isolated vertices), not on the point: every point of that set fails.
bool FailsForEveryPoint(CollapseStatus status)
{
  switch (status)
  {
    case CollapseStatus::DeadVertex:
    case CollapseStatus::NonManifold:
    case CollapseStatus::BoundaryChange:
    case CollapseStatus::TooSmall:
    case CollapseStatus::IsolatedVertex:
    case CollapseStatus::Locked:
      return true;
    default:
      return false;
  }
}
} // namespace

void HierarchyMesh::Clear()
{
  this->Points.clear();
  this->Triangles.clear();
  this->PointGlobal.clear();
  this->PointTarget.clear();
  this->TriangleCollapseLevel.clear();
  this->TriangleBatch.clear();
  this->TriangleRole.clear();
  this->TriangleOrigin.clear();
  this->BlendT = 0;
}

// ---------------------------------------------------------------------------------------------
// Adds the wall and process CPU time of its scope to a stage (when the build is timed: TRACE).
class CollapseHierarchy::StageTimer : public ScopedStageTime
{
public:
  StageTimer(const CollapseHierarchy& hierarchy, Stage stage)
    : ScopedStageTime(
        hierarchy.TimingStages ? &const_cast<CollapseHierarchy&>(hierarchy).StageTimes[stage] : nullptr)
  {
  }
};

void CollapseHierarchy::LogStageTimes() const
{
  static const char* const names[NumberOfStages] = { "M0", "order", "select", "collapse", "gather", "price",
    "evaluate", "compact" };
  for (int s = 0; s < NumberOfStages; ++s)
  {
    vtkLogF(TRACE, "collapse hierarchy stage %-8s %8.3f s wall %8.3f s cpu %8.3f s this thread", names[s],
      this->StageTimes[s].Wall, this->StageTimes[s].Cpu, this->StageTimes[s].Thread);
  }
}

// A collapse of a non-manifold edge (or next to a pinched vertex) can pass the link condition
// and cut the sheets around it apart (new border loops, another Euler characteristic): such
// vertices are locked, the edge stays as it is in every level.
// (The input preparation's flags, when given for this M0, are those NonManifoldVertexFlags gives:
// the same classification of the same mesh; on mc250k its second run was 2.3% of the instructions.)
void CollapseHierarchy::LockNonManifoldVertices(std::vector<unsigned char>&& given)
{
  if (given.size() == size_t(this->Base.NumberOfPoints()) && !this->Parameters.RemoveCycles)
  {
    this->LockedVertices = std::move(given);
    ++this->BuildsWithGivenFlags;
  }
  else
  {
    this->LockedVertices = NonManifoldVertexFlags(this->Base);
  }
  const bool any = std::find(this->LockedVertices.begin(), this->LockedVertices.end(), 1) != this->LockedVertices.end();
  this->MeshOptions.LockedVertices = any ? this->LockedVertices.data() : nullptr;
}

// ---------------------------------------------------------------------------------------------
// Cycle removal (Fig. 3): a valence-3 interior vertex q makes its three triangles a cycle; swapping
// the edge of one of them opposite q raises q's valence to four.
void CollapseHierarchy::RemoveCyclesBySwapping(TriangleMesh& mesh) const
{
  EditableMesh em(mesh);
  std::vector<Index> around, neighbors;
  for (Index q = 0; q < em.NumberOfPoints(); ++q)
  {
    if (!em.IsVertexAlive(q) || em.VertexDegree(q) != 3 || em.IsBoundaryVertex(q))
    {
      continue;
    }
    em.TrianglesAround(&q, 1, around);
    for (Index n : around)
    {
      const Index* tri = em.Triangle(n);
      const int c = tri[0] == q ? 0 : (tri[1] == q ? 1 : 2);
      const Index x = tri[(c + 1) % 3], y = tri[(c + 2) % 3];
      // The triangle across (x, y): it runs y -> x.
      Index other = InvalidIndex, z = InvalidIndex;
      em.ForEachTriangle(x, [&](Index m) {
        const Index* o = em.Triangle(m);
        for (int k = 0; k < 3; ++k)
        {
          if (m != n && o[k] == y && o[(k + 1) % 3] == x)
          {
            other = m;
            z = o[(k + 2) % 3];
          }
        }
      });
      if (other == InvalidIndex || z == q || em.VertexDegree(x) < 5 || em.VertexDegree(y) < 5)
      {
        continue;
      }
      em.Neighbors(q, neighbors);
      if (std::find(neighbors.begin(), neighbors.end(), z) != neighbors.end())
      {
        continue;
      }
      const Vec3 px = em.Point(x), py = em.Point(y), pq = em.Point(q), pz = em.Point(z);
      const Vec3 reference = Cross(py - px, pq - px) + Cross(px - py, pz - py);
      const Vec3 n1 = Cross(pz - px, pq - px), n2 = Cross(py - pz, pq - pz);
      if (Dot(n1, reference) <= 0 || Dot(n2, reference) <= 0 || IsDegenerate(px, pz, pq) ||
        IsDegenerate(pz, py, pq))
      {
        continue;
      }
      em.RemoveTriangle(n);
      em.RemoveTriangle(other);
      em.AddTriangle(x, z, q);
      em.AddTriangle(z, y, q);
      break;
    }
  }
  // Same points (same ids), live triangles in id order.
  TriangleMesh result;
  result.Points = mesh.Points;
  for (Index t = 0; t < em.NumberOfTriangles(); ++t)
  {
    if (em.IsTriangleAlive(t))
    {
      const Index* tri = em.Triangle(t);
      result.AddTriangle(tri[0], tri[1], tri[2]);
    }
  }
  mesh = std::move(result);
}

// ---------------------------------------------------------------------------------------------
// The weight terms of triangle t (section 4): area, roundness, valence of the collapse point,
// curvature of the fitted quadratic and, beyond the paper, the quadric error of the collapse point.
void CollapseHierarchy::Evaluate(Index t, Evaluation& e)
{
  Alternatives alternatives;
  const EvaluationRest rest = this->EvaluateConcurrently(t, e, this->Link, alternatives);
  this->FinishEvaluation(t, e, rest, alternatives);
}

// The serial rest of an evaluation: the stencil fit (its scratch is shared) or the search for a
// point that does not fold (EditableMesh::CheckCollapse uses the mesh's scratch).
void CollapseHierarchy::FinishEvaluation(Index t, Evaluation& e, EvaluationRest rest, const Alternatives& alternatives)
{
  if (rest == EvaluationRest::Fit)
  {
    this->EvaluateWithFit(t, e);
  }
  else if (rest == EvaluationRest::Unfold)
  {
    const Index* tri = this->Mesh.Triangle(t);
    const Quadric q = this->TriangleQuadric(tri);
    this->TakeCheapestValidAlternative(tri, alternatives, e.Point);
    e.Source = PointSource::Kept;
    this->SetCollapseError(tri, q, e);
  }
}

// Everything of an evaluation that reads the mesh only (safe to run for many triangles at once,
// with one LinkEdges per thread); what remains is returned for FinishEvaluation.
CollapseHierarchy::EvaluationRest CollapseHierarchy::EvaluateConcurrently(
  Index t, Evaluation& e, LinkEdges& link, Alternatives& alternatives) const
{
  const EditableMesh& m = this->Mesh;
  const Index* tri = m.Triangle(t);
  LocalFrame frame;
  if (!this->EvaluateShape(t, e, frame, false))
  {
    return EvaluationRest::None;
  }
  // The fitted quadratic gives the paper's collapse point and curvature. With the weight all
  // quadric error and the quadric collapse point (the defaults) it is only the fallback point,
  // so it is computed only when needed: the fit is most of the cost of an evaluation.
  if (!(this->Parameters.ErrorWeight >= 1 && this->Parameters.QuadricCollapsePoint))
  {
    return EvaluationRest::Fit;
  }
  const Vec3 centroid = frame.Origin;
  e.Kappa = 0;
  // (No hub: EvaluateShape took those.)
  e.EdgeError = this->PreferringEdges() ? this->CheapestEdgeError(t, 0, e.CheapestEdge) : std::numeric_limits<double>::infinity();
  OwnQuadric own[3];
  const Quadric q = this->TriangleQuadric(tri, own);
  if (!this->QuadricPointNearCentroid(tri, q, centroid, e.Point))
  {
    return EvaluationRest::Fit;
  }
  e.Source = PointSource::Quadric;
  // The error of the point decides whether T is ordered by its edge collapse and is T's error
  // when the point stays (computed once for both).
  const double error = this->CollapseError(own, 3, q, e.Point);
  if (!(this->PreferringEdges() && e.EdgeError < this->Parameters.PreferEdgeFactor * error))
  {
    if (!this->StarShapedAround(tri, e.Point, frame.Normal))
    {
      this->GatherLinkEdges(tri, link);
      alternatives = this->RankAlternatives(tri, q, frame.Normal, link);
      return EvaluationRest::Unfold;
    }
  }
  e.Error = error;
  e.ErrorRecomputable = true;
  e.PreferEdge = this->PreferringEdges() && e.EdgeError < this->Parameters.PreferEdgeFactor * e.Error;
  return EvaluationRest::None;
}

// Area, valence, roundness and T's frame (centroid, normal, and the axes in its plane when the fit
// needs them); false when that is all there is (a hub triangle, ordered by its edge, or no plane
// at all).
bool CollapseHierarchy::EvaluateShape(Index t, Evaluation& e, LocalFrame& frame, bool planeAxes) const
{
  const EditableMesh& m = this->Mesh;
  const Index* tri = m.Triangle(t);
  const Vec3 a = m.Point(tri[0]), b = m.Point(tri[1]), c = m.Point(tri[2]);
  const Vec3 centroid = (1.0 / 3.0) * (a + b + c);
  Vec3 areaVector = Cross(b - a, c - a);
  e.CheapestEdge = EdgeChoice(); // known again only where this evaluation computes it
  const double twiceArea = Norm(areaVector);
  e.Area = 0.5 * twiceArea;
  e.OwnPlane = false;
  if (this->ShapeTermsRead)
  {
    e.Valence = this->CollapsePointValence(tri);
    e.Alpha = Roundness(a, b, c);
  }
  const int hubs = this->HubMask(t);
  if (hubs != 0)
  {
    this->EvaluateHubTriangle(t, hubs, areaVector, centroid, e);
    return false;
  }
  // A degenerate triangle has no plane of its own: use its stencil's.
  const bool degenerate = IsDegenerateWithArea(a, b, c, twiceArea);
  if (degenerate)
  {
    areaVector = this->StencilAreaVector(tri);
  }
  if (!(planeAxes ? frame.Set(centroid, areaVector, b - a) : frame.SetNormal(centroid, areaVector)))
  {
    // No plane at all: never collapsed as a triangle (the error terms keep their last values).
    e.Normal = { 0, 0, 0 };
    e.Point = centroid;
    e.Source = PointSource::Centroid;
    e.Kappa = 0;
    e.Alpha = 0;
    e.PreferEdge = false;
    e.NoPlane = true;
    return false;
  }
  e.Normal = frame.Normal;
  // (Normalized(Cross(b - a, c - a)) of T's points: what OwnNormal computes, so NormalSourceOf's
  // answer, Own, is known without computing it again.)
  e.OwnPlane = !degenerate;
  return true;
}

// The evaluation with the stencil fit: the paper's weights and point, or the fallback point of
// the quadric collapse point.
void CollapseHierarchy::EvaluateWithFit(Index t, Evaluation& e)
{
  const Index* tri = this->Mesh.Triangle(t);
  LocalFrame frame;
  if (!this->EvaluateShape(t, e, frame, true))
  {
    return;
  }
  e.Source = PointSource::Kept;
  const Vec3 fitPoint = this->FitStencil(tri, frame, e.Kappa);
  e.EdgeError = this->PreferringEdges() ? this->CheapestEdgeError(t, 0, e.CheapestEdge) : std::numeric_limits<double>::infinity();
  e.Point = fitPoint;
  if (this->Parameters.ErrorWeight > 0)
  {
    const Quadric q = this->TriangleQuadric(tri);
    if (this->Parameters.QuadricCollapsePoint)
    {
      if (!this->QuadricPointNearCentroid(tri, q, frame.Origin, e.Point))
      {
        e.Point = fitPoint;
      }
      // (Not needed when T will be ordered by its much cheaper edge collapse anyway.)
      if (!this->OrderedByEdge(tri, q, e))
      {
        this->GatherLinkEdges(tri, this->Link);
        if (!StarShaped(this->Link, e.Point, frame.Normal))
        {
          this->TakeCheapestValidAlternative(tri, this->RankAlternatives(tri, q, frame.Normal, this->Link), e.Point);
        }
      }
    }
    this->SetCollapseError(tri, q, e);
    return;
  }
  e.PreferEdge = this->PreferringEdges() && e.EdgeError < this->Parameters.PreferEdgeFactor * e.Error;
}

bool CollapseHierarchy::PreferringEdges() const
{
  return this->Parameters.PreferEdgeFactor > 0 &&
    this->Parameters.EdgeCollapses == CollapseHierarchyParameters::EdgeFallback::Everywhere;
}

Quadric CollapseHierarchy::TriangleQuadric(const Index* tri) const
{
  OwnQuadric own[3];
  return this->TriangleQuadric(tri, own);
}

// The same sum, keeping its terms for CollapseError.
Quadric CollapseHierarchy::TriangleQuadric(const Index* tri, OwnQuadric (&own)[3]) const
{
  for (int k = 0; k < 3; ++k)
  {
    own[k] = this->OwnQuadricOf(tri[k]);
  }
  Quadric q = *own[0].Planes;
  q += *own[1].Planes;
  q += *own[2].Planes;
  return q;
}

// T will be ordered by its much cheaper edge collapse (its point then needs no fold test).
bool CollapseHierarchy::OrderedByEdge(const Index* tri, const Quadric& q, const Evaluation& e) const
{
  return this->PreferringEdges() &&
    e.EdgeError < this->Parameters.PreferEdgeFactor * this->CollapseError(tri, 3, q, e.Point);
}

// The quadric error of T's collapse point, and whether T is ordered by its edge collapse.
void CollapseHierarchy::SetCollapseError(const Index* tri, const Quadric& q, Evaluation& e) const
{
  e.Error = this->CollapseError(tri, 3, q, e.Point);
  e.ErrorRecomputable = true;
  e.PreferEdge = this->PreferringEdges() && e.EdgeError < this->Parameters.PreferEdgeFactor * e.Error;
}

// Valence of the collapse point: the stencil boundary (interior case: sum of valences - 9).
int CollapseHierarchy::CollapsePointValence(const Index* tri) const
{
  Index degree = 0;
  for (int k = 0; k < 3; ++k)
  {
    degree += this->Degree(tri[k]);
  }
  return static_cast<int>(std::max<Index>(0, degree - 9));
}

// Only its edge away from the hubs can collapse: ordered by that edge (no fit, no stencil).
void CollapseHierarchy::EvaluateHubTriangle(Index t, int hubs, const Vec3& areaVector, const Vec3& centroid, Evaluation& e) const
{
  e.Normal = Norm(areaVector) > 0 ? Normalized(areaVector) : Vec3{ 0, 0, 0 };
  e.Point = centroid;
  e.Source = PointSource::Centroid;
  e.Kappa = 0;
  e.EdgeError = this->Quadrics.empty() ? std::numeric_limits<double>::infinity() : this->CheapestEdgeError(t, hubs, e.CheapestEdge);
  e.Error = e.EdgeError;
  e.PreferEdge = true;
}

// Sum of the (unnormalised) normals of the triangles around T's vertices.
Vec3 CollapseHierarchy::StencilAreaVector(const Index* tri) const
{
  const EditableMesh& m = this->Mesh;
  Vec3 sum{ 0, 0, 0 };
  for (int k = 0; k < 3; ++k)
  {
    m.ForEachTriangle(tri[k], [&](Index x) {
      const Index* q = m.Triangle(x);
      sum = sum + Cross(m.Point(q[1]) - m.Point(q[0]), m.Point(q[2]) - m.Point(q[0]));
    });
  }
  return sum;
}

void CollapseHierarchy::NextMarkEpoch()
{
  if (++this->MarkEpoch == 0)
  {
    std::fill(this->VertexMark.begin(), this->VertexMark.end(), std::uint16_t(0));
    this->MarkEpoch = 1;
  }
}

// T's vertices and the stencil boundary, into StencilVertices (marked with a new epoch).
void CollapseHierarchy::GatherStencilVertices(const Index* tri)
{
  this->NextMarkEpoch();
  this->StencilVertices.clear();
  for (int k = 0; k < 3; ++k)
  {
    this->Mesh.ForEachTriangle(tri[k], [&](Index x) { this->AddUnmarkedVertices(x); });
  }
}

void CollapseHierarchy::AddUnmarkedVertices(Index x)
{
  const Index* q = this->Mesh.Triangle(x);
  for (int j = 0; j < 3; ++j)
  {
    if (this->VertexMark[q[j]] != this->MarkEpoch)
    {
      this->VertexMark[q[j]] = this->MarkEpoch;
      this->StencilVertices.push_back(q[j]);
    }
  }
}

// f(input point) for the input points merged into global vertex g, depth first through the
// collapses' sources in order: a collapse's point stands for its kept vertex's ancestors followed
// by those of its other sources, the order in which they were merged. Each collapse has at least
// two sources, so the walk visits fewer collapses than ancestors.
template <typename Functor>
void CollapseHierarchy::ForEachAncestor(Index g, Functor&& f)
{
  const Index np = this->NumberOfBasePoints();
  std::vector<Index>& stack = this->AncestorStack;
  stack.assign(1, g);
  while (!stack.empty())
  {
    const Index x = stack.back();
    stack.pop_back();
    if (x < np)
    {
      f(x);
      continue;
    }
    const Index* sources = this->Collapses[size_t(x - np)].Sources;
    for (int i = this->CountOfCollapse(x - np) - 1; i >= 0; --i)
    {
      stack.push_back(sources[i]);
    }
  }
}

// The squared reach of stencil vertices [begin, end) in the frame's plane: the farthest one's
// distance from the origin.
double CollapseHierarchy::StencilReach2(const LocalFrame& frame, size_t begin, size_t end) const
{
  double reach2 = 0;
  for (size_t i = begin; i < end; ++i)
  {
    const Vec3 l = frame.ToLocal(this->Mesh.Point(this->StencilVertices[i]));
    reach2 = std::max(reach2, l[0] * l[0] + l[1] * l[1]);
  }
  return reach2;
}

// Every stride-th original point merged into v that lies within the reach (squared, in the plane),
// counted over the calls by counter, in the local frame, onto FitPoints.
void CollapseHierarchy::AddAncestorPoints(Index v, const LocalFrame& frame, double reach2, Index stride, Index& counter)
{
  this->ForEachAncestor(this->GlobalOf[v], [&](Index o) {
    const Vec3 l = frame.ToLocal(this->BasePoints.Point(o));
    if (l[0] * l[0] + l[1] * l[1] <= reach2 && counter++ % stride == 0)
    {
      this->FitPoints.insert(this->FitPoints.end(), { l[0], l[1], l[2] });
    }
  });
}

// The least-squares quadratic over T's plane (section 5): returns the paper's collapse point
// c + f(0,0) n and sets kappa to |k1| + |k2| at the centroid.
Vec3 CollapseHierarchy::FitStencil(const Index* tri, const LocalFrame& frame, double& kappa)
{
  this->GatherStencilVertices(tri);
  // Fit to the ancestral original points of the stencil vertices, so that the error of earlier
  // collapses does not accumulate (section 7). Extended stencil when the system is singular.
  // On coarse levels the ancestors number hundreds: a regular subsample of about
  // MaximumFitPoints keeps the fit's cost bounded without biasing it. Only the ancestors over the
  // stencil's own footprint count: on coarse levels a vertex's ancestors can trail far beyond it
  // (a cap of half a sphere), where no quadratic graph over T's plane follows the surface and the
  // fit misses it at T by several times the input's noise.
  Index total = 0;
  for (Index v : this->StencilVertices)
  {
    total += this->AncestorCountOf(this->GlobalOf[v]);
  }
  const Index stride = std::max<Index>(1, (total + MaximumFitPoints - 1) / MaximumFitPoints);
  Index counter = 0;
  this->FitPoints.clear();
  const double reach2 = this->StencilReach2(frame, 0, this->StencilVertices.size());
  for (Index v : this->StencilVertices)
  {
    this->AddAncestorPoints(v, frame, reach2, stride, counter);
  }
  QuadraticPatch patch = this->Fitter.Fit(this->FitPoints);
  if (patch.Degree < 6)
  {
    // The next ring: vertices of the triangles around the stencil vertices, over its footprint.
    const size_t ring = this->StencilVertices.size();
    for (size_t i = 0; i < ring; ++i)
    {
      this->Mesh.ForEachTriangle(this->StencilVertices[i], [&](Index x) { this->AddUnmarkedVertices(x); });
    }
    const double extendedReach2 = std::max(reach2, this->StencilReach2(frame, ring, this->StencilVertices.size()));
    this->FitPoints.clear();
    counter = 0;
    for (Index v : this->StencilVertices)
    {
      this->AddAncestorPoints(v, frame, extendedReach2, stride, counter);
    }
    const QuadraticPatch extended = this->Fitter.Fit(this->FitPoints);
    if (extended.Degree >= patch.Degree)
    {
      patch = extended;
    }
  }
  kappa = EvaluateCurvature(patch, 0, 0).Absolute();
  return frame.ToWorld(0, 0, patch.Evaluate(0, 0));
}

// Least quadric error nearest to the centroid (crease line, corner, or along the normal), when it
// is finite and within reach of T.
bool CollapseHierarchy::QuadricPointNearCentroid(const Index* tri, const Quadric& q, const Vec3& centroid, Vec3& point) const
{
  const Vec3 best = QuadricPointNear(q, centroid);
  double reach = 0;
  for (int k = 0; k < 3; ++k)
  {
    reach += Norm(this->Mesh.Point(tri[k]) - centroid);
  }
  if (std::isfinite(best[0]) && std::isfinite(best[1]) && std::isfinite(best[2]) && Norm(best - centroid) <= reach)
  {
    point = best;
    return true;
  }
  return false;
}

// The link edges of T (the far edges of the triangles holding exactly one of T's vertices): the
// collapse joins them to the new point. They suffice for the star-shape test, without building the
// whole stencil, and one gathering serves every point tried.
void CollapseHierarchy::GatherLinkEdges(const Index* tri, LinkEdges& link) const
{
  const EditableMesh& m = this->Mesh;
  link.clear();
  ForEachLinkEdge(m, tri, [&](Index a, Index b) { link.push_back({ m.Point(a), m.Point(b) }); });
}

// The link edges turn around point in the plane of normal: the fan of the collapse cannot fold.
bool CollapseHierarchy::StarShaped(const LinkEdges& link, const Vec3& point, const Vec3& normal)
{
  for (const auto& edge : link)
  {
    if (!LinkEdgeTurns(edge.first, edge.second, point, normal))
    {
      return false;
    }
  }
  return true;
}

// StarShaped over T's link edges read from the mesh as they come: most quadric points pass, and
// gathering the link (for the alternatives) is then not needed.
bool CollapseHierarchy::StarShapedAround(const Index* tri, const Vec3& point, const Vec3& normal) const
{
  const EditableMesh& m = this->Mesh;
  bool star = true;
  ForEachLinkEdge(m, tri, [&](Index a, Index b) { star = star && LinkEdgeTurns(m.Point(a), m.Point(b), point, normal); });
  return star;
}

// When the optimum would fold the stencil, the alternatives are T's corners and edge midpoints (a
// triangle collapse can still go there).
void CollapseHierarchy::AlternativePoints(const Index* tri, Vec3 (&points)[6]) const
{
  const EditableMesh& m = this->Mesh;
  const Vec3 a = m.Point(tri[0]), b = m.Point(tri[1]), c = m.Point(tri[2]);
  points[0] = a;
  points[1] = b;
  points[2] = c;
  points[3] = 0.5 * (a + b);
  points[4] = 0.5 * (b + c);
  points[5] = 0.5 * (c + a);
}

// The alternatives by increasing error (ties in the order above, infinite errors left out) and
// which of them keep the fan star-shaped: everything but the mesh check, so it runs in parallel.
CollapseHierarchy::Alternatives CollapseHierarchy::RankAlternatives(
  const Index* tri, const Quadric& q, const Vec3& normal, const LinkEdges& link) const
{
  Vec3 points[6];
  this->AlternativePoints(tri, points);
  std::pair<double, int> byError[6];
  for (int i = 0; i < 6; ++i)
  {
    byError[i] = { this->CollapseError(tri, 3, q, points[i]), i };
  }
  std::sort(byError, byError + 6);
  Alternatives ranked;
  for (const auto& option : byError)
  {
    if (option.first < std::numeric_limits<double>::infinity())
    {
      ranked.Order[ranked.Count++] = static_cast<unsigned char>(option.second);
      ranked.StarShaped |= StarShaped(link, points[option.second], normal) ? 1 << option.second : 0;
    }
  }
  return ranked;
}

// The cheapest ranked alternative that keeps the fan star-shaped and passes the mesh check;
// point is unchanged when none does. Serial: EditableMesh::CheckCollapse uses the mesh's scratch.
void CollapseHierarchy::TakeCheapestValidAlternative(const Index* tri, const Alternatives& ranked, Vec3& point) const
{
  Vec3 points[6];
  this->AlternativePoints(tri, points);
  for (int i = 0; i < ranked.Count; ++i)
  {
    const int option = ranked.Order[i];
    if (((ranked.StarShaped >> option) & 1) &&
      this->Mesh.CheckCollapse(tri, 3, points[option], this->MeshOptions) == CollapseStatus::Ok)
    {
      point = points[option];
      return;
    }
  }
}

int CollapseHierarchy::FixedMask(const Index* tri) const
{
  int mask = 0;
  for (int k = 0; k < 3; ++k)
  {
    mask |= this->Degree(tri[k]) > HubValence ? 1 << k : 0;
  }
  return mask;
}

double CollapseHierarchy::CheapestEdgeError(Index t, int hubs, EdgeChoice& choice) const
{
  const Index* tri = this->Mesh.Triangle(t);
  const int fixed = hubs; // (FixedMask(tri): its callers have it, a fifth of this function's instructions)
  double cheapest = std::numeric_limits<double>::infinity();
  // The first minimum in FindEdgeCollapse's order (error, then edge, then best/u/v); unknown when
  // an error is not a number (that order is then not a minimum). Per edge, its cost holds its
  // first minimum over (best, u, v): the first over all edges is the first of those.
  choice = EdgeChoice();
  choice.Fixed = static_cast<unsigned char>(fixed);
  bool ordered = true;
  const size_t row = this->Row(t); // (once: the stores below could alias the rank words)
  for (int k = 0; k < 3; ++k)
  {
    if (((fixed >> k) & 1) || ((fixed >> ((k + 1) % 3)) & 1))
    {
      continue;
    }
    const size_t slot = 3 * row + size_t(k);
    EdgeCost cost;
    if (this->EdgeCostErrors.empty())
    {
      cost = this->EdgeCostOf(tri[k], tri[(k + 1) % 3]);
    }
    else if (!EdgeCostKnown(this->EdgeCostErrors[slot]))
    {
      cost = this->EdgeCostOf(tri[k], tri[(k + 1) % 3]);
      this->StoreEdgeCost(row, k, cost, false); // (only t's evaluation writes t's row)
    }
    else
    {
      const unsigned char kind = (this->EdgeCostKinds[row] >> (2 * k)) & 3;
      cost = { this->EdgeCostErrors[slot], static_cast<unsigned char>(kind == NotANumberKind ? 0 : kind),
        kind == NotANumberKind };
    }
    ordered = ordered && !cost.NotANumber;
    cost.Error *= this->ValenceDiscount(tri[k], tri[(k + 1) % 3]);
    if (cost.Kind < 3 && cost.Error < cheapest)
    {
      cheapest = cost.Error;
      choice.Edge = static_cast<signed char>(k);
      choice.Kind = cost.Kind;
    }
  }
  if (!ordered)
  {
    choice.Edge = -1;
  }
  return cheapest;
}

CollapseHierarchy::EdgeCost CollapseHierarchy::EdgeCostOf(Index u, Index v) const
{
  EdgePlacement placements[3];
  const int n = this->EdgePlacements(u, v, placements, true);
  if (this->Parameters.VerifyBoundedPricing)
  {
    this->VerifyPricing(u, v, placements, n);
  }
  return CheapestPlacement(placements, n);
}

// The costs of (u, v) and of (v, u) from one set of placements. Every error is the same both ways
// (the quadric sum, the midpoint and the vertex term do not depend on the order, bit for bit), so
// (v, u)'s placements are these with the two end points swapped in order and kind: the same
// first cheapest as EdgeCostOf(v, u), ties included.
void CollapseHierarchy::EdgeCostsBothWays(Index u, Index v, EdgeCost& uv, EdgeCost& vu) const
{
  EdgePlacement placements[3];
  const int n = this->EdgePlacements(u, v, placements, true);
  if (this->Parameters.VerifyBoundedPricing)
  {
    this->VerifyPricing(u, v, placements, n);
  }
  CostsBothWays(placements, n, uv, vu);
}

void CollapseHierarchy::CostsBothWays(const EdgePlacement* placements, int n, EdgeCost& uv, EdgeCost& vu)
{
  uv = CheapestPlacement(placements, n);
  // (v, u)'s list is [best, v, u]: the same least error and NaN flag; the same best point; an end
  // point taken alone becomes the other kind, and of two equal ends the first, kind 1, again.
  vu = uv;
  if ((uv.Kind == 1 || uv.Kind == 2) && !(placements[n - 2].Error == placements[n - 1].Error))
  {
    vu.Kind = static_cast<unsigned char>(3 - uv.Kind);
  }
}

// The bounded placements' costs against the exact ones, both ways, bit for bit (test support).
void CollapseHierarchy::VerifyPricing(Index u, Index v, const EdgePlacement* placements, int n) const
{
  EdgePlacement exact[3];
  const int m = this->EdgePlacements(u, v, exact, false);
  EdgeCost uv, vu, exactUV, exactVU;
  CostsBothWays(placements, n, uv, vu);
  CostsBothWays(exact, m, exactUV, exactVU);
  const auto same = [](const EdgeCost& a, const EdgeCost& b) {
    return std::memcmp(&a.Error, &b.Error, sizeof(double)) == 0 && a.Kind == b.Kind && a.NotANumber == b.NotANumber;
  };
  long long bounded = 0;
  for (int i = 0; i < std::min(n, m); ++i)
  {
    bounded += placements[i].Error != exact[i].Error ? 1 : 0;
  }
  const bool mismatch = m != n || !same(uv, exactUV) || !same(vu, exactVU);
  __atomic_fetch_add(&this->PricingMismatches, mismatch ? 1 : 0, __ATOMIC_RELAXED);
  __atomic_fetch_add(&this->BoundedEndPoints, bounded, __ATOMIC_RELAXED);
}

// The least float not below x (x itself when a float holds it; infinity and NaN stay): a kept
// edge cost bounds the double error the selection computes again for the same collapse.
static double FloatAbove(double x)
{
  if (!(x <= std::numeric_limits<float>::max()))
  {
    return x > 0 ? std::numeric_limits<double>::infinity() : x; // (NaN)
  }
  const float f = static_cast<float>(x);
  if (!(double(f) < x))
  {
    return double(f);
  }
  if (!(f >= 0))
  {
    return double(std::nextafter(f, std::numeric_limits<float>::infinity())); // (errors are not negative)
  }
  // The next float up of a non-negative one: its bits plus one (nextafter's library call was
  // a third of the pricing's instructions).
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  ++bits;
  float up;
  std::memcpy(&up, &bits, sizeof up);
  return double(up);
}

CollapseHierarchy::EdgeCost CollapseHierarchy::CheapestPlacement(const EdgePlacement* placements, int n)
{
  EdgeCost cost{ std::numeric_limits<double>::infinity(), 3, false };
  for (int i = 0; i < n; ++i)
  {
    cost.NotANumber = cost.NotANumber || std::isnan(placements[i].Error);
    if (placements[i].Error < cost.Error)
    {
      cost.Error = placements[i].Error;
      cost.Kind = static_cast<unsigned char>(placements[i].Kind);
    }
  }
  cost.Error = FloatAbove(cost.Error);
  return cost;
}

void CollapseHierarchy::StoreEdgeCost(size_t row, int edge, const EdgeCost& cost, bool concurrent) const
{
  const unsigned kind = cost.NotANumber ? NotANumberKind : (cost.Kind < 3 ? cost.Kind : 0u);
  const unsigned shift = 2 * unsigned(edge);
  unsigned char* kinds = &this->EdgeCostKinds[row];
  const auto with = [&](unsigned char old) { return static_cast<unsigned char>((old & ~(3u << shift)) | kind << shift); };
  if (concurrent)
  {
    unsigned char old = __atomic_load_n(kinds, __ATOMIC_RELAXED);
    while (!__atomic_compare_exchange_n(kinds, &old, with(old), true, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
    {
    }
  }
  else
  {
    *kinds = with(*kinds);
  }
  this->EdgeCostErrors[3 * row + size_t(edge)] = static_cast<float>(cost.Error); // (exact: CheapestPlacement rounded it)
}

// The spokes (v, w) of vertex v's fan, each priced once for the two triangles that share it: the
// one where w follows v holds it as (v, w), the one where w precedes v as (w, v). Only slots not
// known yet (all of them after a collapse forgot them), and not the spokes another thread prices:
// on M0 (allVertices) those to a lower vertex id, after a level those to another vertex of the
// list (marked: such a spoke's slots may belong to that vertex's fan). A hub's spokes are never
// priced (CheapestEdgeError skips them).
void CollapseHierarchy::PriceSpokesOf(Index v, bool allVertices) const
{
  const auto otherPrices = [&](Index w) { return allVertices ? w < v : this->VertexMark[w] == this->MarkEpoch; };
  struct Spoke
  {
    Index Other;
    size_t Row;
    int Edge;
  };
  Spoke leaving[HubValence], entering[HubValence];
  int nl = 0, ne = 0, fan = 0;
  bool fits = true;
  this->Mesh.ForEachTriangle(v, [&](Index x) {
    const Index* q = this->Mesh.Triangle(x);
    const int c = q[0] == v ? 0 : (q[1] == v ? 1 : 2);
    const Index next = q[(c + 1) % 3], previous = q[(c + 2) % 3];
    fits = fits && ++fan <= HubValence;
    if (!fits)
    {
      return;
    }
    const size_t row = this->Row(x);
    if (!EdgeCostKnown(this->EdgeCostErrors[3 * row + c]) && !otherPrices(next))
    {
      leaving[nl++] = { next, row, c };
    }
    if (!EdgeCostKnown(this->EdgeCostErrors[3 * row + (c + 2) % 3]) && !otherPrices(previous))
    {
      entering[ne++] = { previous, row, (c + 2) % 3 };
    }
  });
  for (int i = 0; fits && i < nl; ++i)
  {
    for (int j = 0; j < ne; ++j)
    {
      if (entering[j].Other == leaving[i].Other)
      {
        EdgeCost uv, vu;
        this->EdgeCostsBothWays(v, leaving[i].Other, uv, vu);
        this->StoreEdgeCost(leaving[i].Row, leaving[i].Edge, uv, true);
        this->StoreEdgeCost(entering[j].Row, entering[j].Edge, vu, true);
        entering[j] = entering[--ne];
        break;
      }
    }
  }
}

struct CollapseHierarchy::SpokePricing
{
  const CollapseHierarchy* Hierarchy;
  const std::vector<Index>* Vertices; // nullptr: every vertex
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    for (vtkIdType i = begin; i < end; ++i)
    {
      this->Hierarchy->PriceSpokesOf(this->Vertices ? (*this->Vertices)[i] : static_cast<Index>(i), !this->Vertices);
    }
  }
};

// Before the fans of a level's new vertices are evaluated: their spokes priced once per edge
// instead of once per triangle (each spoke is an edge of two fan triangles), in parallel over the
// vertices (their fans are disjoint: the batch's regions are). The same costs as the evaluation
// would compute, so the same hierarchy.
void CollapseHierarchy::PriceSpokes(const std::vector<Index>* vertices)
{
  if (this->EdgeCostErrors.empty() || !this->PreferringEdges())
  {
    return;
  }
  if (!vertices)
  {
    SpokePricing pricing{ this, nullptr };
    vtkSMPTools::For(0, static_cast<vtkIdType>(this->NumberOfBasePoints()), pricing);
    return;
  }
  this->NextMarkEpoch();
  this->Spokes.clear();
  for (Index v : *vertices)
  {
    if (this->VertexMark[v] != this->MarkEpoch && this->Mesh.IsVertexAlive(v))
    {
      this->Spokes.push_back(v); // once each (the swaps' vertices may repeat)
    }
    this->VertexMark[v] = this->MarkEpoch;
  }
  SpokePricing pricing{ this, &this->Spokes };
  vtkSMPTools::For(0, static_cast<vtkIdType>(this->Spokes.size()), pricing);
}

// v is the kept vertex of a collapse (new point and quadric): the costs of the edges at v go.
void CollapseHierarchy::ForgetEdgeCostsAround(Index v)
{
  this->Mesh.ForEachTriangle(v, [&](Index x) { this->ForgetEdgeCostsAt(v, this->Mesh.Triangle(x), this->Row(x)); });
}

// The costs of triangle q's (row's) edges at v.
void CollapseHierarchy::ForgetEdgeCostsAt(Index v, const Index* q, size_t row) const
{
  for (int k = 0; k < 3; ++k)
  {
    if (q[k] == v || q[(k + 1) % 3] == v)
    {
      this->ForgetEdgeCost(3 * row + size_t(k));
    }
  }
}

int CollapseHierarchy::EdgePlacements(
  Index u, Index v, EdgePlacement placements[3], bool cheapestOnly, const Vec3* optimum) const
{
  const OwnQuadric own[2] = { this->OwnQuadricOf(u), this->OwnQuadricOf(v) };
  Quadric q = *own[0].Planes;
  q += *own[1].Planes;
  const Vec3 pu = this->Mesh.Point(u), pv = this->Mesh.Point(v);
  int n = 0;
  Vec3 best;
  double cheapest = std::numeric_limits<double>::infinity(); // (of the exact errors so far)
  const auto place = [&](const Vec3& p, int kind) {
    double sum = -1;
    if (cheapestOnly && kind != 0 && this->EndPointAboveCheapest(q, p, cheapest, sum))
    {
      placements[n++] = { sum, p, kind };
      return;
    }
    placements[n++] = { sum >= 0 ? this->WithVertexTerm(own, 2, sum, p) : this->CollapseError(own, 2, q, p), p, kind };
    cheapest = std::min(cheapest, placements[n - 1].Error);
  };
  if (optimum ? (best = *optimum, true) : EdgeOptimum(q, pu, pv, best))
  {
    place(best, 0);
  }
  place(pu, 1);
  place(pv, 2);
  return n;
}

// The end point's error is the quadric sum q(p) plus the vertex term, a product of non-negative
// factors (each own error is clamped at 0, so never a NaN, and the weights are positive): when
// that term's factor is finite and positive, the error is never a NaN and, rounded, never below
// q(p). So when q(p) is strictly above the cheapest placement before it, so is the error: neither
// is CheapestPlacement's minimum (strict <), and neither equals it (EdgeCostsBothWays' tie test
// between the end points compares with the cheapest one). Two of the three vertex terms of most
// pricings (the quadric's best point is usually far cheaper than the end points) are not computed.
bool CollapseHierarchy::EndPointAboveCheapest(const Quadric& q, const Vec3& p, double cheapest, double& sum) const
{
  const double factor = this->Parameters.VertexErrorWeight * this->MeanArea;
  if (!(this->Parameters.VertexErrorWeight > 0) || !(factor > 0) || !std::isfinite(factor))
  {
    return false;
  }
  sum = q.Evaluate(p);
  return sum > cheapest;
}

Index CollapseHierarchy::CacheDegree(Index v) const
{
  const Index degree = this->Mesh.VertexDegree(v);
  if (!this->DegreesFrozen && degree < UnknownDegree)
  {
    this->VertexDegrees[v] = static_cast<std::uint16_t>(degree);
  }
  return degree;
}

int CollapseHierarchy::HubMask(Index t) const
{
  const Index* tri = this->Mesh.Triangle(t);
  int mask = 0;
  for (int k = 0; k < 3; ++k)
  {
    mask |= this->Degree(tri[k]) > HubValence ? 1 << k : 0;
  }
  return mask;
}

double CollapseHierarchy::CollapseError(const Index* vertices, int count, const Quadric& q, const Vec3& p) const
{
  OwnQuadric own[3];
  const int n = this->Parameters.VertexErrorWeight > 0 ? std::min(count, 3) : 0; // (2 or 3 vertices)
  for (int k = 0; k < n; ++k)
  {
    own[k] = this->OwnQuadricOf(vertices[k]);
  }
  return this->CollapseError(own, n, q, p);
}

double CollapseHierarchy::CollapseError(const OwnQuadric* own, int count, const Quadric& q, const Vec3& p) const
{
  // Sum over the ancestral planes (area-weighted squared distances), plus the worst merged
  // vertex's mean squared distance to its own ancestral planes times the mean triangle area:
  // a crease or corner vertex is pinned by its own planes however small the faces around it
  // are (narrow CAD strips are cheap for the sum alone, and flattening them was the largest
  // deviation on fandisk).
  return this->WithVertexTerm(own, count, q.Evaluate(p), p);
}

// CollapseError from the quadric sum q(p) already evaluated.
double CollapseHierarchy::WithVertexTerm(const OwnQuadric* own, int count, double sum, const Vec3& p) const
{
  double error = sum;
  if (this->Parameters.VertexErrorWeight > 0)
  {
    double worst = 0;
    for (int k = 0; k < count; ++k)
    {
      if (own[k].Weight > 0)
      {
        worst = std::max(worst, own[k].Planes->Evaluate(p) / own[k].Weight);
      }
    }
    error += this->Parameters.VertexErrorWeight * this->MeanArea * worst;
  }
  return error;
}

// The paper's part of W(T), normalised (needs the normalisers of M0's evaluation).
double CollapseHierarchy::PaperTerm(double kappa, double alpha, int valence, double area) const
{
  const CollapseHierarchyParameters& p = this->Parameters;
  const double term = p.CurvatureWeight * (kappa / this->KappaMax) + p.AngleWeight * alpha +
    p.ValenceWeight * (std::abs(valence - 6) / this->Mv);
  return area * term / (this->WeightSum * this->MeanArea);
}

// The weight of T's place in the order for a collapse of quadric error `collapseError`.
double CollapseHierarchy::WeightOf(Index t, double collapseError) const
{
  const CollapseHierarchyParameters& p = this->Parameters;
  const double error = collapseError / (this->MeanArea * this->MeanArea);
  const double paper = this->PaperTerms.empty() ? 0.0 : this->PaperTerms[this->Row(t)];
  return (1 - p.ErrorWeight) * paper + p.ErrorWeight * error;
}

// T's unit normal from its vertices (the normal of an evaluation's frame, when T has a plane).
Vec3 CollapseHierarchy::OwnNormal(Index t) const
{
  const EditableMesh& m = this->Mesh;
  const Index* tri = m.Triangle(t);
  const Vec3 a = m.Point(tri[0]), b = m.Point(tri[1]), c = m.Point(tri[2]);
  return Normalized(Cross(b - a, c - a));
}

// How normal, T's evaluated one, is kept: compared bit for bit with T's own and with zero, so
// that the one read back is the same.
CollapseHierarchy::NormalSource CollapseHierarchy::NormalSourceOf(Index t, const Vec3& normal) const
{
  const Vec3 own = this->OwnNormal(t), zero{ 0, 0, 0 };
  if (std::memcmp(&own, &normal, sizeof(Vec3)) == 0)
  {
    return NormalSource::Own;
  }
  return std::memcmp(&zero, &normal, sizeof(Vec3)) == 0 ? NormalSource::Zero : NormalSource::Stored;
}

// The normal of T's last evaluation.
Vec3 CollapseHierarchy::NormalOf(Index t) const
{
  switch (this->Evaluations[this->Row(t)].Normal)
  {
    case NormalSource::Own:
      return this->OwnNormal(t);
    case NormalSource::Zero:
      return { 0, 0, 0 };
    default:
      return this->OtherNormals.at(t);
  }
}

// The collapse point of T's last evaluation: recomputed as the evaluation computed it (T's
// vertices and their quadrics are those of the evaluation: a collapse that moves or merges one
// of them evaluates T again), or the kept one.
Vec3 CollapseHierarchy::PointOf(Index t) const
{
  const StoredEvaluation& s = this->Evaluations[this->Row(t)];
  if (s.Point == PointSource::Kept)
  {
    return this->KeptPoints.at(t);
  }
  const EditableMesh& m = this->Mesh;
  const Index* tri = m.Triangle(t);
  const Vec3 centroid = (1.0 / 3.0) * (m.Point(tri[0]) + m.Point(tri[1]) + m.Point(tri[2])); // (EvaluateShape's)
  return s.Point == PointSource::Centroid ? centroid : QuadricPointNear(this->TriangleQuadric(tri), centroid);
}

void CollapseHierarchy::StorePoint(Index t, StoredEvaluation& s, const Evaluation& e)
{
  if (e.Source == PointSource::Kept)
  {
    this->KeptPoints[t] = e.Point;
  }
  else if (s.Point == PointSource::Kept)
  {
    this->KeptPoints.erase(t);
  }
  s.Point = e.Source;
}

double CollapseHierarchy::ErrorOf(Index t) const
{
  return this->Evaluations[this->Row(t)].ErrorKept ? this->ErrorOf(t, Vec3{ 0, 0, 0 }) : this->ErrorOf(t, this->PointOf(t));
}

// (point: PointOf(t), read only when the error is not kept.)
double CollapseHierarchy::ErrorOf(Index t, const Vec3& point) const
{
  if (this->Evaluations[this->Row(t)].ErrorKept)
  {
    const auto kept = this->KeptErrors.find(t);
    return kept == this->KeptErrors.end() ? 0.0 : kept->second;
  }
  const Index* tri = this->Mesh.Triangle(t);
  return this->CollapseError(tri, 3, this->TriangleQuadric(tri), point); // (SetCollapseError's)
}

// Keeps `error`, evaluation e's error of t's triangle collapse, where ErrorOf cannot recompute it.
void CollapseHierarchy::StoreError(Index t, StoredEvaluation& s, const Evaluation& e, double error)
{
  const bool recomputable = e.ErrorRecomputable && this->Parameters.ErrorWeight > 0;
  if (recomputable || error == 0)
  {
    if (s.ErrorKept && !this->KeptErrors.empty())
    {
      this->KeptErrors.erase(t);
    }
  }
  else
  {
    this->KeptErrors[t] = error;
  }
  s.ErrorKept = !recomputable;
}

// M0's errors were computed with the mean area's guess (InitializeQuadrics): kept as they were
// when the final mean area differs (it is the same sum in the same order: not met so far).
void CollapseHierarchy::KeepGuessedErrors(double guess)
{
  if (this->Parameters.ErrorWeight <= 0)
  {
    return; // (every error kept already)
  }
  const double finalArea = this->MeanArea;
  this->MeanArea = guess;
  const Index nt = this->Base.NumberOfTriangles();
  for (Index t = 0; t < nt; ++t)
  {
    StoredEvaluation& s = this->Evaluations[this->Row(t)];
    if (!s.ErrorKept)
    {
      const double error = this->ErrorOf(t);
      if (error != 0)
      {
        this->KeptErrors[t] = error;
      }
      s.ErrorKept = true;
    }
  }
  this->MeanArea = finalArea;
}

// Keeps what the batch selection reads of evaluation e of triangle t (the normal as its source,
// compared bit for bit, so that the one read back is the same).
void CollapseHierarchy::StoreEvaluation(Index t, const Evaluation& e)
{
  StoredEvaluation& s = this->Evaluations[this->Row(t)];
  // A triangle without a plane carries its last error: read before its point is replaced (with
  // ErrorWeight 0 the evaluation carried it already, EvaluateChunk).
  const double error = e.NoPlane && this->Parameters.ErrorWeight > 0 ? this->ErrorOf(t) : e.Error;
  const bool wasStored = s.Normal == NormalSource::Stored;
  this->StorePoint(t, s, e);
  if (!this->PaperTerms.empty())
  {
    this->PaperTerms[this->Row(t)] = this->PaperTerm(e.Kappa, e.Alpha, e.Valence, e.Area);
  }
  this->StoreError(t, s, e, error);
  s.Weight = e.PreferEdge ? e.EdgeError : error; // (weighed by the caller)
  s.PreferEdge = e.PreferEdge;
  s.CheapestEdge = e.CheapestEdge;
  s.Normal = e.NormalKnown ? e.NormalKind : this->NormalSourceOf(t, e.Normal);
  if (s.Normal == NormalSource::Stored)
  {
    this->OtherNormals[t] = e.Normal;
    return;
  }
  if (wasStored)
  {
    this->OtherNormals.erase(t);
  }
}

// ---------------------------------------------------------------------------------------------
// The orientation test (see the header). M0's triangles and their points are cold (the mesh's are
// warm from the check): their loads are started for all the survivors' triangles, then for a
// chunk's points at once, and each test waits on one of them (one after the other, the misses
// were a sixteenth of the build on mc1m).
bool CollapseHierarchy::OrientationTest::Keeps(const Index* triangles, const Vec3* newAreaVectors, int n) const
{
  const CollapseHierarchy& h = *this->Hierarchy;
  for (int i = 0; i < n; ++i)
  {
    __builtin_prefetch(&h.Base.Triangles[3 * size_t(triangles[i])]);
  }
  constexpr int Chunk = 16;
  for (int first = 0; first < n; first += Chunk)
  {
    const int last = std::min(n, first + Chunk);
    for (int i = first; i < last; ++i)
    {
      const Index* b = &h.Base.Triangles[3 * size_t(triangles[i])];
      for (int j = 0; j < 3; ++j)
      {
        h.BasePoints.Prefetch(b[j]);
      }
    }
    for (int i = first; i < last; ++i)
    {
      if (!(Dot(newAreaVectors[i], h.BaseAreaVector(triangles[i])) > 0))
      {
        return false;
      }
    }
  }
  return true;
}

void CollapseHierarchy::ApplyCollapse(Index t, const Index* vertices, int count, const Vec3& p)
{
  EditableMesh& m = this->Mesh;
  const Index kept = vertices[0];
  const Index k = static_cast<Index>(this->Collapses.size());

  StoredCollapse collapse;
  for (int i = 0; i < 3; ++i)
  {
    collapse.Sources[i] = i < count ? this->GlobalOf[vertices[i]] : InvalidIndex;
  }
  this->EdgeCollapseCount += count == 2 ? 1 : 0;
  collapse.Triangle = t;
  collapse.Weight = this->Evaluations[this->Row(t)].Weight;
  this->CollapsePoints.insert(this->CollapsePoints.end(), p.begin(), p.end());

  m.Collapse(vertices, count, kept, p, &this->Record);
  for (int i = 1; i < count; ++i)
  {
    this->OnBorder[kept] |= this->OnBorder[vertices[i]];
  }
  if (!this->Quadrics.empty())
  {
    for (int i = 1; i < count; ++i)
    {
      this->QuadricOf(kept) += this->QuadricOf(vertices[i]);
    }
  }
  this->Collapses.push_back(collapse);
  Index ancestors = 0;
  for (int i = 0; i < count; ++i)
  {
    ancestors += this->AncestorCountOf(collapse.Sources[i]);
  }
  this->AncestorCounts.push_back(ancestors);
  this->VersionsBornBy.push_back(this->NumberOfEntries()); // (the versions below are born at k + 1)
  this->GlobalOf[kept] = this->PointOfCollapse(k);
  this->MarkChangedAround(kept);
  if (!this->EdgeCostErrors.empty())
  {
    this->ForgetEdgeCostsAround(kept);
  }

  // Triangle versions: removed ones end, the ones around the moved vertex start anew.
  // (Their deaths: DeriveDeaths.)
  m.ForEachTriangle(kept, [&](Index x) {
    const Index* q = m.Triangle(x);
    this->AppendEntry(x, q[0] == kept ? 0 : (q[1] == kept ? 1 : 2));
  });

  // The record for exact vertex splits (the old positions are those of the source global
  // vertices: not stored twice).
  this->Records.Append(this->Record, m);
}

// ---------------------------------------------------------------------------------------------
void CollapseHierarchy::MarkChangedAround(Index v)
{
  this->MarkChangedAround(v, ++this->ChangeCounter);
}

// v moved or got new triangles; the vertices around it lost or gained triangles. A vertex keeps
// the larger stamp: the later collapse's when collapses of a run that share it stamp it at once
// (relaxed atomics; one by one the stamps only grow).
void CollapseHierarchy::MarkChangedAround(Index v, Index stamp)
{
  this->RaiseStamp(v, stamp);
  this->Mesh.ForEachTriangle(v, [&](Index x) { this->RaiseStampsOf(this->Mesh.Triangle(x), stamp); });
}

// w's change stamp raised to stamp (the larger stays: concurrent collapses of a run meet at shared
// boundary vertices), and its valence unknown.
void CollapseHierarchy::RaiseStamp(Index w, Index stamp)
{
  Index* changed = &this->VertexStamps[w];
  Index old = __atomic_load_n(changed, __ATOMIC_RELAXED);
  while (old < stamp && !__atomic_compare_exchange_n(changed, &old, stamp, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
  {
  }
  __atomic_store_n(&this->VertexDegrees[w], UnknownDegree, __ATOMIC_RELAXED);
}

void CollapseHierarchy::RaiseStampsOf(const Index* q, Index stamp)
{
  for (int j = 0; j < 3; ++j)
  {
    this->RaiseStamp(q[j], stamp);
  }
}

bool CollapseHierarchy::StarsUnchangedSince(Index t, Index stamp, int skipMask) const
{
  if (stamp < 0)
  {
    return false;
  }
  const Index* tri = this->Mesh.Triangle(t);
  bool same = true;
  for (int k = 0; k < 3 && same; ++k)
  {
    if ((skipMask >> k) & 1)
    {
      continue;
    }
    this->Mesh.ForEachTriangle(tri[k], [&](Index x) {
      const Index* q = this->Mesh.Triangle(x);
      same = same && this->VertexStamps[q[0]] <= stamp && this->VertexStamps[q[1]] <= stamp && this->VertexStamps[q[2]] <= stamp;
    });
  }
  return same;
}

// ---------------------------------------------------------------------------------------------
void CollapseHierarchy::RecordFlip(const FlipRecord& flip)
{
  const Index k = this->NumberOfCollapses();
  const Index stamp = ++this->ChangeCounter;
  for (Index v : { flip.X, flip.Y, flip.Q, flip.Z })
  {
    this->StampVertex(v, stamp);
  }
  for (Index t : flip.Triangles)
  {
    this->AppendEntry(t, AllCorners); // (the version it replaces dies at this birth: DeriveDeaths)
    if (!this->EdgeCostErrors.empty())
    {
      std::fill_n(this->EdgeCostErrors.begin() + 3 * this->Row(t), 3, std::numeric_limits<float>::quiet_NaN()); // new corners
    }
  }
  this->Records.AppendFlip(flip);
}

// Every version's death, none written during the build: a slot's version ends when its next
// version is born (a collapse around it or a swap: the same count, ApplyCollapse, RecordFlip) or
// when a collapse removes the slot (a removed slot gets no version after its removal), else never.
// One walk of the records and one of the versions from the last to the first, with M0's entries
// (version s is slot s's first) holding each slot's next birth meanwhile: they end as M0's deaths.
void CollapseHierarchy::DeriveDeaths()
{
  const Index nt = this->Base.NumberOfTriangles();
  const Index entries = this->NumberOfEntries();
  this->Deaths.assign(size_t(entries), Never);
  const CollapseRecords& r = this->Records;
  for (Index k = 0; k < r.NumberOfCollapses(); ++k)
  {
    for (Index i = r.RemovedOffsets[size_t(k)]; i < r.RemovedOffsets[size_t(k) + 1]; ++i)
    {
      this->Deaths[size_t(r.RemovedTriangles[size_t(i)])] = k + 1;
    }
  }
  // versions [VersionsBornBy[K - 1], VersionsBornBy[K]) are born at K (K = 0: M0's)
  Index birth = static_cast<Index>(this->VersionsBornBy.size()) - 1;
  for (Index e = entries - 1; e >= nt; --e)
  {
    while (birth > 0 && this->VersionsBornBy[size_t(birth) - 1] > e)
    {
      --birth;
    }
    Index& next = this->Deaths[size_t(this->BuildCodeOf(e) >> 2)];
    this->Deaths[size_t(e)] = next;
    next = birth;
  }
}

void CollapseHierarchy::PackVersions()
{
  const Index nt = this->Base.NumberOfTriangles();
  const auto release = [](auto& v) { std::decay_t<decltype(v)>().swap(v); };
  const std::uint64_t lastDeath = std::uint64_t(this->NumberOfCollapses()) + 1;
  this->PackedDeaths.Assign(size_t(this->NumberOfEntries()), lastDeath, [this](size_t e) {
    const Index d = this->Deaths[e];
    return d == Never ? std::uint64_t(0) : std::uint64_t(d) + 1;
  });
  release(this->Deaths);
  this->PackedCodes.Assign(this->EntryCode.size(), 4 * std::uint64_t(nt) - 1,
    [this](size_t i) { return std::uint64_t(this->EntryCode[i]); });
  release(this->EntryCode);
  this->VersionsPacked = true;
}

// A new version of triangle x (as it is in the mesh now), born at the current collapse count:
// its corner `corner` is the last collapse's point, or (AllCorners) its three vertices are stored.
void CollapseHierarchy::AppendEntry(Index x, std::uint32_t corner)
{
  if (corner == AllCorners)
  {
    const Index* q = this->Mesh.Triangle(x);
    for (int j = 0; j < 3; ++j)
    {
      this->FullEntryVertices.push_back(this->GlobalOf[q[j]]);
    }
  }
  this->EntryCode.push_back(std::uint32_t(x) << 2 | corner);
  this->VersionsBornBy.back() = this->NumberOfEntries();
}

int CollapseHierarchy::SwapAround(Index q, double minimumDot, std::vector<Index>& touched)
{
  EditableMesh& m = this->Mesh;
  const Index degree = this->Degree(q);
  if (!m.IsVertexAlive(q) || degree < 3 || degree > 4 || this->OnBorder[q])
  {
    return 0;
  }
  // The best hinge among the edges opposite q: flattest, both ends keeping valence >= 5 (>= 4
  // for a valence-3 q: a cycle is worse than a valence-4 vertex).
  const Index keep = degree == 4 ? 6 : 5;
  double bestDot = minimumDot;
  Index bestX = InvalidIndex, bestY = InvalidIndex;
  m.ForEachTriangle(q, [&](Index t) {
    const Index* tri = m.Triangle(t);
    const int c = tri[0] == q ? 0 : (tri[1] == q ? 1 : 2);
    const Index x = tri[(c + 1) % 3], y = tri[(c + 2) % 3];
    if (this->Degree(x) < keep || this->Degree(y) < keep || this->OnBorder[x] || this->OnBorder[y])
    {
      return;
    }
    // The triangle across (x, y) runs y -> x -> z.
    Index z = InvalidIndex, across = InvalidIndex;
    m.ForEachTriangle(x, [&](Index o) {
      const Index* u = m.Triangle(o);
      for (int k = 0; k < 3; ++k)
      {
        if (u[k] == y && u[(k + 1) % 3] == x)
        {
          z = u[(k + 2) % 3];
          across = o;
        }
      }
    });
    if (z == InvalidIndex || z == q)
    {
      return;
    }
    const Vec3 px = m.Point(x), py = m.Point(y), pq = m.Point(q), pz = m.Point(z);
    const Vec3 n0 = Normalized(Cross(py - px, pq - px)), n1 = Normalized(Cross(px - py, pz - py));
    const double hinge = Dot(n0, n1);
    if (!(hinge > bestDot) || IsDegenerate(px, pz, pq) || IsDegenerate(pz, py, pq))
    {
      return;
    }
    // The new triangles must face like the old pair (the quad is convex enough), to the limit
    // reached so far (measured slightly better than the plain limit on fandisk).
    const Vec3 m0 = Normalized(Cross(pz - px, pq - px)), m1 = Normalized(Cross(py - pz, pq - pz));
    const Vec3 mean = Normalized(n0 + n1);
    if (Dot(m0, mean) < bestDot || Dot(m1, mean) < bestDot)
    {
      return;
    }
    // Like the collapses: no triangle may face away from the M0 triangle of its id (t keeps its
    // id as (x, z, q), the triangle across as (z, y, q)).
    if (Dot(m0, this->BaseAreaVector(t)) <= 0 || Dot(m1, this->BaseAreaVector(across)) <= 0)
    {
      return;
    }

    bestDot = hinge;
    bestX = x;
    bestY = y;
  });
  FlipRecord flip;
  if (bestX == InvalidIndex || !m.FlipEdge(bestX, bestY, &flip))
  {
    return 0;
  }
  this->RecordFlip(flip);
  touched.insert(touched.end(), { flip.X, flip.Y, flip.Q, flip.Z });
  return 1;
}

// ---------------------------------------------------------------------------------------------
// The evaluation's cheapest edge candidate, recomputed, when it is still the first in
// FindEdgeCollapse's order: T's vertices have not moved nor merged since (else T was evaluated
// again), the hub and border flags are those of the evaluation, and the evaluation used the
// current mean area (not the initial one's guess).
bool CollapseHierarchy::KnownCheapestEdge(Index t, int& edge, Vec3& point, double& error) const
{
  const StoredEvaluation& e = this->Evaluations[this->Row(t)];
  const Index* tri = this->Mesh.Triangle(t);
  if (e.CheapestEdge.Edge < 0 || e.CheapestEdge.Fixed != this->FixedMask(tri))
  {
    return false;
  }
  const int k = e.CheapestEdge.Edge;
  const Index uv[2] = { tri[k], tri[(k + 1) % 3] };
  const OwnQuadric own[2] = { this->OwnQuadricOf(uv[0]), this->OwnQuadricOf(uv[1]) };
  Quadric q = *own[0].Planes;
  q += *own[1].Planes;
  const Vec3 pu = this->Mesh.Point(uv[0]), pv = this->Mesh.Point(uv[1]);
  if (e.CheapestEdge.Kind == 0)
  {
    if (!EdgeOptimum(q, pu, pv, point))
    {
      return false;
    }
  }
  else
  {
    point = e.CheapestEdge.Kind == 1 ? pu : pv;
  }
  edge = k;
  error = this->CollapseError(own, 2, q, point) * this->ValenceDiscount(uv[0], uv[1]);
  return true;
}

// Under PreventNewValenceThree an interior vertex of valence four blocks the four edges opposite it
// (and, by rule (2), the triangle collapses around it); without the rule such vertices went on to
// valence three and were merged away, with it they piled up: on noisy137 at 10% a quarter of the
// output's interior vertices (4.9% without the rule), and the last levels found too few collapses
// (50 levels instead of 40, their selections scanning most triangles: +34% instructions). An edge
// that merges such a vertex into a neighbour (which keeps that neighbour's valence) is therefore
// ordered at ValenceFourDiscount times its error, in the evaluation's cheapest edge and in the
// selection's errors alike (else a triangle ordered by a discounted edge is put back as too dear).
// Measured on noisy137 (levels, instructions over the rule off) and the 56 CGAL meshes of 2,000
// triangles or more at 10% (Hausdorff geometric mean over the rule off): none 50, +34%, 1.031;
// 0.5: 47, +27%, 0.989; 0.25: 46, +20%; 0.1: 45, +15%, 1.199 (merging those vertices first
// whatever their error costs accuracy).
double CollapseHierarchy::ValenceDiscount(Index u, Index v) const
{
  constexpr double ValenceFourDiscount = 0.5;
  if (!this->KeepValences)
  {
    return 1.0; // (exactly: the rule off orders as before)
  }
  const bool four = (!this->OnBorder[u] && this->Degree(u) == 4) || (!this->OnBorder[v] && this->Degree(v) == 4);
  return four ? ValenceFourDiscount : 1.0;
}

bool CollapseHierarchy::FindEdgeCollapse(Index t, int& edge, Vec3& point, double& error, ChoiceScratch& scratch) const
{
  const EditableMesh& m = this->Mesh;
  const Index* tri = m.Triangle(t);
  // After the known cheapest, up to three points per edge are checked: each edge's triangles are
  // gathered (and their old normals computed) once, when its first of them is checked (on noisy
  // scans these checks were a third of the build's instructions, each gathering the same
  // triangles).
  int prepared = 0; // bit k: edge k's trial is prepared
  long long tested[3] = { 0, 0, 0 }; // per edge, its points tested so far (the counters)
  const auto checked = [&](const Index* vertices, const Vec3& p) {
    const int k = vertices[0] == tri[0] ? 0 : (vertices[0] == tri[1] ? 1 : 2);
    EditableMesh::SetTrial& trial = scratch.EdgeTrials[k];
    if (!((prepared >> k) & 1))
    {
      m.PrepareTrial(vertices, 2, this->ChoiceOptions, trial);
      prepared |= 1 << k;
      // The edge's topology before any of its points' geometry: on noisy scans seven in ten of the
      // edges tried here fail the link condition (noisy137: 215k of 299k), and with the geometry
      // first each of their points was tested in vain (350k of the 488k points refused as flips).
      const CollapseStatus topology = this->Parameters.TopologyBeforeTrialPoints
        ? m.CheckTrialTopology(this->ChoiceOptions, trial, scratch.OwnMarks())
        : CollapseStatus::Ok;
      if (topology != CollapseStatus::Ok)
      {
        return topology;
      }
    }
    const CollapseStatus status = m.CheckTrial(p, this->ChoiceOptions, trial, scratch.OwnMarks());
    ++tested[k];
    __atomic_fetch_add(&this->TrialPoints, 1, __ATOMIC_RELAXED);
    if (FailsForEveryPoint(status))
    {
      __atomic_fetch_add(&this->TrialPointsOnRefusedEdges, tested[k], __ATOMIC_RELAXED);
      tested[k] = 0;
    }
    return status;
  };
  // Most of the time the cheapest candidate, known from the evaluation, passes: the other eight
  // need not be computed (one eigen decomposition instead of three).
  const bool known = this->KnownCheapestEdge(t, edge, point, error);
  int failsEverywhere = 0; // bit k: edge k failed a check of its vertices alone (no point passes)
  // (PreventNewValenceThree refuses an edge for every point: it is not priced or checked.)
  const bool valences = this->KeepValences;
  const Index known0[2] = { tri[known ? edge : 0], tri[known ? (edge + 1) % 3 : 1] };
  if (known && valences && !this->EdgeKeepsValences(known0[0], known0[1]))
  {
    failsEverywhere |= 1 << edge;
  }
  else if (known)
  {
    // (A plain check: it mostly passes, and then no other point is tried; a trial's bookkeeping
    // cost 2% more instructions on bunny00.)
    const Index* vertices = known0;
    EditableMesh::CheckScratch* own = scratch.OwnMarks();
    const CollapseStatus status = own ? m.CheckCollapse(vertices, 2, point, this->ChoiceOptions, *own)
                                      : m.CheckCollapse(vertices, 2, point, this->ChoiceOptions);
    if (status == CollapseStatus::Ok)
    {
      return true;
    }
    failsEverywhere |= FailsForEveryPoint(status) ? 1 << edge : 0;
  }
  // Candidates: per edge, the quadric's best point near the midpoint and the two end points;
  // tried by increasing quadric error of the ancestral planes until one passes the checks.
  struct Candidate
  {
    double Error;
    int Edge;
    Vec3 Point;
  };
  Candidate candidates[9];
  int n = 0;
  // The known edge's candidates are not computed when its check failed for every point (they would
  // be skipped below): the sort, an insertion sort for 9 or fewer and so stable, then gives the
  // others in the same order, since none of them is a NaN (a known cheapest means none of the
  // triangle's edge errors was; checked all the same: with one, all are computed again). Else its
  // quadric point is the known one (the same EdgeOptimum of the same quadric and ends).
  const bool knownFailed = known && ((failsEverywhere >> edge) & 1);
  const Vec3 knownPoint = point;
  const bool knownOptimum = known && this->Evaluations[this->Row(t)].CheapestEdge.Kind == 0;
  bool excluded = false; // (the known edge's candidates left out)
  for (int pass = knownFailed ? 0 : 1; pass < 2; ++pass) // (pass 0: without the known edge)
  {
    n = 0;
    bool nan = false;
    for (int k = 0; k < 3; ++k)
    {
      const Index u = tri[k], v = tri[(k + 1) % 3];
      if ((pass == 0 && k == edge) || this->Degree(u) > HubValence || this->Degree(v) > HubValence)
      {
        continue; // (a hub's checks would cost its valence: see HubMask)
      }
      if (valences && !(known && k == edge) && !this->EdgeKeepsValences(u, v))
      {
        failsEverywhere |= 1 << k;
        continue;
      }
      EdgePlacement placements[3];
      const int count = this->EdgePlacements(u, v, placements, false, knownOptimum && k == edge ? &knownPoint : nullptr);
      const double discount = this->ValenceDiscount(u, v);
      for (int i = 0; i < count; ++i)
      {
        nan = nan || std::isnan(placements[i].Error);
        candidates[n++] = { placements[i].Error * discount, k, placements[i].Point };
      }
    }
    excluded = pass == 0;
    if (!(nan && excluded))
    {
      break;
    }
  }
  std::sort(candidates, candidates + n, [](const Candidate& a, const Candidate& b) {
    return a.Error < b.Error || (a.Error == b.Error && a.Edge < b.Edge);
  });
  // (The known cheapest, when in the list, is the first: it failed above.)
  for (int i = known && !excluded ? 1 : 0; i < n; ++i)
  {
    const int k = candidates[i].Edge;
    if ((failsEverywhere >> k) & 1)
    {
      continue; // (the same answer as checking it: on noisy scans most of the link failures)
    }
    const Index vertices[2] = { tri[k], tri[(k + 1) % 3] };
    const CollapseStatus status = checked(vertices, candidates[i].Point);
    if (status == CollapseStatus::Ok)
    {
      edge = k;
      point = candidates[i].Point;
      error = candidates[i].Error;
      return true;
    }
    failsEverywhere |= FailsForEveryPoint(status) ? 1 << k : 0;
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// The batch selection's data over one Build (reused from level to level).
// The batch's collapses in runs applied at once (ParallelCollapses). The batch's regions are
// disjoint, so a collapse changes only its region's triangles, its own vertices and their blocks:
// what made it depend on the collapses before it when applied one by one is where it writes (its
// index, reference block, versions and records: prefix sums over the run's counts) and the change
// stamps of the vertices its region shares with others (the larger, the later collapse's, stays).
// A run holds only collapses whose checks would not run again one by one (CollapseInOrder): edge
// collapses with no border vertex opposite their edge; triangle collapses and those go one by one.
// It also ends before the collapse after which the mesh's blocks would be compacted: a compaction
// reorders the fans, which the later collapses' versions follow.
struct CollapseHierarchy::BatchRun
{
  // Per batch position, surveyed once (RunSurvey; a collapse's counts depend only on its own
  // region, which no other collapse changes): one by one (1), and the triangles its collapse
  // keeps (references, versions), removes and redirects.
  std::vector<unsigned char> InOrder;
  std::vector<Index> Survivors, Removed, Changed;
  // Per batch position: an interior vertex opposite its collapsed edge(s) is also opposite
  // another collapse's (MarkSharedOpposites); the (vertex, position) pairs that found them.
  std::vector<unsigned char> SharedOpposite;
  std::vector<std::pair<Index, Index>> Opposites;
  size_t Surveyed = 0; // positions [0, Surveyed) are
  // ApplyRun's: per collapse of the run + 1, where its references and versions start.
  std::vector<Index> SurvivorStart;
  size_t Begin = 0;
  Index FirstCollapse = 0, FirstEntry = 0, FirstStamp = 0, ReferenceStart = 0;
  vtkSMPThreadLocal<CollapseRecord> Records;
  vtkSMPThreadLocal<std::vector<Index>> Sets;
  // (Not held through the next level's selection: a batch's 13 bytes per collapse.)
  void Release() { ReleaseArrays(this->InOrder, this->Survivors, this->Removed, this->Changed, this->SurvivorStart, this->SharedOpposite, this->Opposites);
  }
};

struct CollapseHierarchy::LevelState
{
  // Priority order of the level: (weight, triangle), collected range by range of that order as
  // the selection goes deeper (CollectRange), each range sorted: a level reads a few times its
  // batch size, so the order of every live triangle (12 bytes per input triangle at the first
  // levels, the peak of the build) is only made when a selection scans it all.
  std::vector<RankedTriangle> Candidates;
  // The ranks of the live triangles of every SampleStride-th slot at the level's start, sorted:
  // the range bounds.
  std::vector<RankedTriangle> Sample;
  // The upper bound of the ranges collected (valid when Ranges > 0); every candidate collected.
  RankedTriangle Bound{ 0, 0 };
  size_t Ranges = 0;
  bool Complete = false;
  // Collected triangles whose weight the selection raised: not collected again (sorted before a
  // range is collected).
  std::vector<Index> Raised;
  size_t FirstRange = 1024;
  // CollectRange's scratch: a bit per row (the members of the range) and a count per block of rows.
  std::vector<std::uint64_t> RangeBits;
  std::vector<size_t> RangeCounts;
  // The choices of the candidates from AheadStart on, decided concurrently (ChooseAhead), and the
  // threads' scratch for them.
  std::vector<CollapseHierarchy::Choice> Ahead;
  size_t AheadStart = 0;
  // Per window candidate: the earlier candidates of the window (their indices, -1: none) whose
  // triangle shares a vertex with its own (DeferNeighbours); and the vertices claimed so far
  // (open addressing by vertex id, -1 free) with the candidate claiming each.
  std::vector<std::array<Index, 3>> AheadClaimers;
  std::vector<Index> ClaimedVertices, ClaimedBy;
  vtkSMPThreadLocal<CollapseHierarchy::ChoiceScratch> AheadScratch;
  // The batch: triangle, -1 for its triangle collapse or the edge (tri[k], tri[k+1]) collapsed,
  // and the collapse point.
  std::vector<Index> Batch;
  std::vector<int> BatchEdge;
  std::vector<Vec3> BatchPoint;
  BatchRun Run;
  // Per triangle row, one mark for two uses that never overlap: the stamp of the level whose
  // batch region (stencil, or the triangles around a collapsed edge) holds it (RegionStamp;
  // regions of one batch are disjoint), or of the last gathering of the triangles to evaluate
  // again (AffectedStamp). A level's regions are marked only by a batch that is then collapsed;
  // its re-evaluation comes after, and a retried selection (relaxed rules, swaps) follows an
  // empty batch, which marked nothing. (Two arrays took 8 bytes per input vertex more; stamps
  // of 32 bits 6 more: NextStamp.)
  std::vector<std::uint8_t> Marks;
  std::uint8_t Stamp = 0, RegionStamp = 0, AffectedStamp = 0;
  // The next stamp. At the wrap of the byte, the rows of the current regions keep their mark as
  // stamp 1 and every other row is cleared: each comparison after it (with RegionStamp, or with
  // a new stamp, whose rows are all marked after it) answers as with stamps that never wrap.
  std::uint8_t NextStamp()
  {
    if (this->Stamp == std::numeric_limits<std::uint8_t>::max())
    {
      for (std::uint8_t& mark : this->Marks)
      {
        mark = mark == this->RegionStamp ? 1 : 0;
      }
      this->Stamp = this->RegionStamp = 1;
    }
    return ++this->Stamp;
  }
  // Triangles to evaluate again (marked AffectedStamp): how many, and the chunk of them being
  // evaluated (ReweighAround).
  size_t AffectedCount = 0;
  std::vector<Index> AffectedChunk;
  std::vector<Index> Touched, Ring;
  double MaximumWeight = std::numeric_limits<double>::infinity();
  // Per level: edge collapses allowed for blocked triangles, batch size in triangle collapses,
  // search depth in the priority order (in half triangle collapses: a candidate ordered by its
  // edge collapse counts one, any other two) and the batch below which the search goes on.
  bool Edges = false;
  Index Wanted = 1;
  size_t Depth = std::numeric_limits<size_t>::max();
  Index MinimumBatch = 1;

  // What only the selection reads (the order, its sample and bounds, the choices decided ahead),
  // given back once the batch is chosen: the batch's collapses grow the hierarchy next, and the
  // build's peak was there, after a first level's collapses, with these still held (8 bytes per
  // input vertex on mc1m). The next level collects its own.
  void ReleaseSelection()
  {
    ReleaseArrays(this->Candidates, this->Sample, this->Raised, this->RangeBits, this->RangeCounts, this->Ahead,
      this->AheadClaimers, this->ClaimedVertices, this->ClaimedBy);
  }
};


// ---------------------------------------------------------------------------------------------
// Build: M0 -> M1 -> ... by batches of collapses (section 6).
bool CollapseHierarchy::Build(
  const TriangleMesh& input, const CollapseHierarchyParameters& parameters, const ProgressFunction& progress)
{
  TriangleMesh copy = input;
  return this->Build(std::move(copy), parameters, progress);
}

bool CollapseHierarchy::Build(
  TriangleMesh&& input, const CollapseHierarchyParameters& parameters, const ProgressFunction& progress)
{
  return this->Build(std::move(input), std::vector<unsigned char>(), parameters, progress);
}

bool CollapseHierarchy::Build(TriangleMesh&& input, std::vector<unsigned char>&& nonManifoldVertices,
  const CollapseHierarchyParameters& parameters, const ProgressFunction& progress)
{
  this->SetParameters(parameters);
  this->PeakBytes = 0;
  this->PeakShares.clear();
  this->PeakLevelStateBytes = 0;
  this->PeakAtLevel = -1;
  this->PeakAtMoment = "";
  if (input.NumberOfTriangles() >= Index(1) << 30)
  {
    return false; // a version's code holds the triangle id in 30 bits
  }
  this->Reset(std::move(input), std::move(nonManifoldVertices));
  const Index nt = this->Base.NumberOfTriangles();
  if (nt == 0)
  {
    return true;
  }
  this->TimingStages = vtkLogger::GetCurrentVerbosityCutoff() >= vtkLogger::VERBOSITY_TRACE;
  this->StageTimes = {};
  {
    StageTimer timer(*this, StageM0);
    this->InitializeQuadrics();
    if (!this->EvaluateAllTriangles(progress))
    {
      this->FinishVersions(); // (an aborted hierarchy still reads as one)
      return false;
    }
  }
  // What the set-up freed (the input's double points, M0's evaluation's scratch) back to the
  // system before the levels, whose first ones are the build's peak.
  ReturnFreedMemory();
  this->NotePeak(nullptr, -1, "M0 evaluated");
  LevelState state;
  state.Marks.assign(nt, 0);
  if (this->Parameters.MaximumWeight > 0)
  {
    state.MaximumWeight = this->Parameters.MaximumWeight;
  }
  for (int level = 0; level + 1 < this->Parameters.MaximumNumberOfLevels; ++level)
  {
    const Index live = this->Mesh.NumberOfLiveTriangles();
    if (live <= this->Parameters.MinimumNumberOfTriangles ||
      (this->Parameters.StopAtTriangles > 0 && live <= this->Parameters.StopAtTriangles) ||
      !this->ReduceLevel(level, state))
    {
      break;
    }
    this->NotePeak(&state, level, "its end");
    {
      StageTimer timer(*this, StageCompact);
      this->CompactWorkingData(state);
    }
    if (progress)
    {
      const double done = double(nt - this->Mesh.NumberOfLiveTriangles()) / (0.95 * nt);
      if (!progress(0.1 + 0.9 * std::min(1.0, done)))
      {
        this->FinishVersions();
        return false;
      }
    }
  }
  this->ReleaseWorkingData();
  // The working data back to the system before the versions are finished: DeriveDeaths and
  // PackVersions allocate their arrays next (4 bytes per version, then the packed ones), which on
  // top of the freed but resident working data were the run's peak (mc1m: 4 MB above the levels').
  ReturnFreedMemory();
  this->DeriveDeaths();
  this->PackVersions();
  // The working data and the build's forms of the versions (the deaths derived at the end, the
  // 32-bit codes) back to the system: freed in the heap they stayed resident under the levels the
  // filter extracts next (2 MB more RSS on noisy273 than base-s41 before, whose deaths lived in a
  // block of their own, unmapped when freed).
  ReturnFreedMemory();
  if (this->TimingStages)
  {
    vtkLogF(TRACE,
      "collapse hierarchy: peak working bytes per input vertex %.1f, kept hierarchy %.1f (%lld triangle "
      "versions, codes in %u bits, deaths in %u)",
      double(this->PeakBytes) / double(std::max<Index>(1, this->NumberOfBasePoints())),
      double(this->StorageBytes()) / double(std::max<Index>(1, this->NumberOfBasePoints())),
      static_cast<long long>(this->NumberOfEntries()), this->PackedCodes.BitsPerValue(),
      this->PackedDeaths.BitsPerValue());
    this->LogPeakShares();
    this->LogStageTimes();
  }
  return true;
}

// f(t, row) for the live triangles in slot order. Before the first compaction every slot is its
// own row; after it, through the rows (the rank words' set bits give their slots), which skips
// the slots dead at the compactions: late in the build a small share of M0's slots is live, and
// the walks of every slot by each range of the priority order were 3% of the build's
// instructions on refined_elephant.
template <typename Functor>
void CollapseHierarchy::ForEachLiveTriangle(Functor&& f) const
{
  this->ForEachLiveTriangleIn(0, size_t(this->Rows), f);
}

// (Before the first compaction Rows is the number of slots: position, slot and row coincide.)
template <typename Functor>
void CollapseHierarchy::ForEachRowSlot(size_t begin, size_t end, Functor&& f) const
{
  if (this->Rows == this->Base.NumberOfTriangles())
  {
    for (size_t t = begin; t < end; ++t)
    {
      f(Index(t), t);
    }
    return;
  }
  this->RowOf.ForEachRow(begin, end, [&](size_t t, size_t r) { f(Index(t), r); });
}

template <typename Functor>
void CollapseHierarchy::ForEachLiveTriangleIn(size_t begin, size_t end, Functor&& f) const
{
  this->ForEachRowSlot(begin, end, [&](Index t, size_t r) {
    if (this->Mesh.IsTriangleAlive(t))
    {
      f(t, r);
    }
  });
}

// The stored normals of the triangles dead at this compaction (RowOf already renumbered).
void CollapseHierarchy::ForgetDeadNormals()
{
  for (auto i = this->OtherNormals.begin(); i != this->OtherNormals.end();)
  {
    i = !this->RowOf.HasRow(size_t(i->first)) ? this->OtherNormals.erase(i) : std::next(i);
  }
}

// The kept points of the triangles dead at this compaction (RowOf already renumbered).
void CollapseHierarchy::ForgetDeadPoints()
{
  for (auto i = this->KeptPoints.begin(); i != this->KeptPoints.end();)
  {
    i = !this->RowOf.HasRow(size_t(i->first)) ? this->KeptPoints.erase(i) : std::next(i);
  }
}

// The kept errors of the triangles dead at this compaction (RowOf already renumbered).
void CollapseHierarchy::ForgetDeadErrors()
{
  for (auto i = this->KeptErrors.begin(); i != this->KeptErrors.end();)
  {
    i = !this->RowOf.HasRow(size_t(i->first)) ? this->KeptErrors.erase(i) : std::next(i);
  }
}

// Called between levels. The rows of the live triangles keep their slot order, so each array is
// compacted in place (a row only moves down) and the pages of its freed rows are given back
// without a copy (ReleaseRoomBeyondSize).
// A compaction costs a pass over the slots and the rows (WorthCompacting: at most one per eighth of
// the rows removed while they are many; a quarter gave a first level 7% above the start on mc1m,
// the hierarchy growing while the working data were still whole).
void CollapseHierarchy::CompactRows(LevelState& state)
{
  const Index live = this->Mesh.NumberOfLiveTriangles();
  if (!WorthCompacting(size_t(live), size_t(this->Rows), this->RowOf.NumberOfElements()))
  {
    return;
  }
  const std::vector<std::uint64_t> keptRows = this->RowOf.Renumber([&](Index t) { return this->Mesh.IsTriangleAlive(t); });
  // Nine independent tasks (each array kept on its own; the dead rows' kept points and normals forgotten
  // before their evaluations move): concurrent with ParallelBookkeeping, the same arrays.
  constexpr vtkIdType Tasks = 9;
  const auto task = [&](vtkIdType i) {
    switch (i)
    {
      case 0:
        this->ForgetDeadNormals();
        this->ForgetDeadErrors();
        break;
      case 1:
        this->ForgetDeadPoints();
        KeepRows(this->Evaluations, keptRows, 1);
        break;
      case 2:
        KeepRows(state.Marks, keptRows, 1);
        break;
      case 3:
        KeepRows(this->BlockedStrict.Narrow, keptRows, 1);
        KeepRows(this->BlockedStrict.Wide, keptRows, 1);
        break;
      case 4:
        KeepRows(this->BlockedRelaxed.Narrow, keptRows, 1);
        KeepRows(this->BlockedRelaxed.Wide, keptRows, 1);
        break;
      case 5:
        KeepRows(this->BlockedEdge.Narrow, keptRows, 1);
        KeepRows(this->BlockedEdge.Wide, keptRows, 1);
        break;
      case 6:
        KeepRows(this->EdgeCostKinds, keptRows, 1);
        break;
      case 7:
        KeepRows(this->PaperTerms, keptRows, 1);
        break;
      default:
        KeepRows(this->EdgeCostErrors, keptRows, 3);
    }
  };
  if (this->Parameters.ParallelBookkeeping)
  {
    vtkSMPTools::For(0, Tasks, 1, [&](vtkIdType begin, vtkIdType end) {
      for (vtkIdType i = begin; i < end; ++i)
      {
        task(i);
      }
    });
  }
  else
  {
    for (vtkIdType i = 0; i < Tasks; ++i)
    {
      task(i);
    }
  }
  this->Rows = live;
}

// The rows of the live triangles and vertices (CompactRows, CompactQuadrics) where it pays.
void CollapseHierarchy::CompactWorkingData(LevelState& state)
{
  this->CompactRows(state);
  this->CompactQuadrics();
  // The freed blocks of the compaction and the level (the editable mesh's references given
  // back, the order's ranges) back to the system: the RSS stays flat over the first twenty
  // levels, as the working data shrink and the hierarchy grows, and freed blocks kept
  // resident made its later levels up to 23 bytes per input vertex higher than the arrays.
  ReturnFreedMemory();
}

// The quadrics of the live vertices, compacted as CompactRows does the triangles' working data
// (80 bytes per input vertex at full size).
void CollapseHierarchy::CompactQuadrics()
{
  const Index live = this->Mesh.NumberOfLiveVertices();
  if (!WorthCompacting(size_t(live), this->Quadrics.size(), this->QuadricRowOf.NumberOfElements()))
  {
    return;
  }
  KeepRows(this->Quadrics,
    this->QuadricRowOf.Renumber([&](Index v) { return this->Mesh.IsVertexAlive(v); }), 1);
}

// What only the build reads (evaluations, quadrics, costs, stamps, ancestors, scratch): the
// levels, blends, cuts and vertex splits read the versions, the collapses, the records, M0 and the
// coarsest mesh. Freed before the levels are handed out (a copy of each) and while a filter keeps
// the hierarchy for its slider (about 400 bytes per input vertex on mc1m).
void CollapseHierarchy::ReleaseWorkingData()
{
  const auto release = [](auto& v) { std::decay_t<decltype(v)>().swap(v); };
  release(this->Evaluations);
  release(this->KeptPoints);
  release(this->KeptErrors);
  release(this->OtherNormals);
  release(this->Quadrics);
  this->QuadricRowOf.Release();
  release(this->PaperTerms);
  release(this->AncestorCounts);
  release(this->AncestorStack);
  this->RowOf.Release();
  release(this->VertexMark);
  release(this->VertexStamps);
  release(this->VertexDegrees);
  for (BlockedColumn* column : { &this->BlockedStrict, &this->BlockedRelaxed, &this->BlockedEdge })
  {
    release(column->Narrow);
    release(column->Wide);
  }
  release(this->BlockEpochs);
  release(this->EdgeCostErrors);
  release(this->EdgeCostKinds);
  release(this->Spokes);
  release(this->Working);
  release(this->Rests);
  release(this->PendingAlternatives);
  release(this->StencilVertices);
  release(this->FitPoints);
  release(this->Link);
}

std::vector<CollapseHierarchy::StorageShare> CollapseHierarchy::Storage() const
{
  const auto bytes = [](const auto& v) { return v.size() * sizeof(v[0]); };
  const CollapseRecords& r = this->Records;
  const size_t records = bytes(r.Vertices) + bytes(r.RemovedOffsets) + bytes(r.RemovedTriangles) +
    bytes(r.ChangedOffsets) + bytes(r.ChangedTriangles) + bytes(r.ChangedCodes) +
    bytes(r.Flips) + bytes(r.FlipStamps);
  size_t stamps = bytes(this->VertexMark) + bytes(this->VertexStamps) + bytes(this->VertexDegrees) +
    bytes(this->BlockEpochs);
  for (const BlockedColumn* column : { &this->BlockedStrict, &this->BlockedRelaxed, &this->BlockedEdge })
  {
    stamps += bytes(column->Narrow) + bytes(column->Wide);
  }
  const size_t ancestors = bytes(this->AncestorCounts);
  return { { "M0 (points, triangles)", false, this->BasePoints.MemoryBytes() + bytes(this->Base.Triangles) },
    { "editable mesh (coarsest)", false, this->Mesh.MemoryBytes() },
    { "collapse points", false, bytes(this->CollapsePoints) },
    { "collapses", false, bytes(this->Collapses) },
    { "triangle versions", false,
      bytes(this->EntryCode) + bytes(this->Deaths) + bytes(this->FullEntryVertices) +
        bytes(this->VersionsBornBy) + this->PackedCodes.MemoryBytes() + this->PackedDeaths.MemoryBytes() },
    { "levels", false, bytes(this->LevelStarts) },
    { "collapse records", false, records },
    { "vertex ids, flags", false, bytes(this->GlobalOf) + bytes(this->OnBorder) + bytes(this->LockedVertices) },
    { "evaluations", true,
      bytes(this->Evaluations) +
        (this->KeptPoints.size() + this->OtherNormals.size()) * (sizeof(Index) + sizeof(Vec3)) +
        this->KeptErrors.size() * (sizeof(Index) + sizeof(double)) }, // (their entries)
    { "evaluation scratch", true, bytes(this->Working) + bytes(this->Rests) + bytes(this->PendingAlternatives) },
    { "paper's terms", true, bytes(this->PaperTerms) },
    { "quadrics", true, bytes(this->Quadrics) + this->QuadricRowOf.MemoryBytes() },
    { "edge costs", true, bytes(this->EdgeCostErrors) + bytes(this->EdgeCostKinds) },
    { "stamps, degrees, marks", true, stamps },
    { "ancestors", true, ancestors },
    { "rows", true, this->RowOf.MemoryBytes() } };
}

void LiveRowIndex::Reset(size_t n)
{
  this->Elements = n;
  this->Words.assign((n + 63) / 64, Word{ ~std::uint64_t(0), 0 });
  for (size_t w = 0; w < this->Words.size(); ++w)
  {
    this->Words[w].Base = static_cast<Index>(64 * w);
  }
  if (n % 64 != 0)
  {
    this->Words.back().Bits = (std::uint64_t(1) << (n % 64)) - 1;
  }
}

size_t CollapseHierarchy::StorageBytes() const
{
  size_t sum = 0;
  for (const StorageShare& share : this->Storage())
  {
    sum += share.Bytes;
  }
  return sum;
}

size_t CollapseHierarchy::LevelStateBytes(const LevelState& state)
{
  const auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  const BatchRun& run = state.Run;
  return bytes(state.Candidates) + bytes(state.Sample) + bytes(state.Raised) + bytes(state.RangeBits) +
    bytes(state.RangeCounts) + bytes(state.Ahead) + bytes(state.AheadClaimers) + bytes(state.ClaimedVertices) +
    bytes(state.ClaimedBy) + bytes(state.Batch) + bytes(state.BatchEdge) + bytes(state.BatchPoint) +
    bytes(state.Marks) + bytes(state.AffectedChunk) + bytes(state.Touched) + bytes(state.Ring) + bytes(run.InOrder) +
    bytes(run.Survivors) + bytes(run.Removed) + bytes(run.Changed) + bytes(run.SurvivorStart);
}

// (PeakWorkingBytes.)
void CollapseHierarchy::NotePeak(const LevelState* state, int level, const char* moment)
{
  const size_t levelBytes = state ? LevelStateBytes(*state) : 0;
  const size_t bytes = this->StorageBytes() + levelBytes;
  if (bytes > this->PeakBytes)
  {
    this->PeakBytes = bytes;
    this->PeakShares = this->Storage(); // (a few times per build: the peak rises at the first levels)
    this->PeakLevelStateBytes = levelBytes;
    this->PeakAtLevel = level;
    this->PeakAtMoment = moment;
  }
}

std::vector<CollapseHierarchy::StorageShare> CollapseHierarchy::PeakStorage() const
{
  std::vector<StorageShare> shares = this->PeakShares;
  shares.push_back({ "level state (selection)", true, this->PeakLevelStateBytes });
  return shares;
}

// The peak's structures in bytes per input vertex, largest first (at TRACE).
void CollapseHierarchy::LogPeakShares() const
{
  const double perVertex = 1.0 / double(std::max<Index>(1, this->NumberOfBasePoints()));
  std::vector<StorageShare> shares = this->PeakStorage();
  std::stable_sort(shares.begin(), shares.end(),
    [](const StorageShare& a, const StorageShare& b) { return a.Bytes > b.Bytes; });
  std::string line;
  for (const StorageShare& share : shares)
  {
    char item[96];
    std::snprintf(item, sizeof(item), "%s%s %.1f", line.empty() ? "" : ", ", share.Name, double(share.Bytes) * perVertex);
    line += item;
  }
  vtkLogF(TRACE, "collapse hierarchy: the peak (level %d, %s), bytes per input vertex: %s", this->PeakAtLevel,
    this->PeakAtMoment, line.c_str());
}

// The parameters with the weights made non-negative (normalised by their sum) and the fractions
// clamped.
void CollapseHierarchy::SetParameters(const CollapseHierarchyParameters& parameters)
{
  this->Parameters = parameters;
  CollapseHierarchyParameters& p = this->Parameters;
  p.CurvatureWeight = std::max(0.0, p.CurvatureWeight);
  p.AngleWeight = std::max(0.0, p.AngleWeight);
  p.ValenceWeight = std::max(0.0, p.ValenceWeight);
  this->WeightSum = p.CurvatureWeight + p.AngleWeight + p.ValenceWeight;
  if (!(this->WeightSum > 0))
  {
    p.CurvatureWeight = p.AngleWeight = p.ValenceWeight = 1.0 / 3.0;
    this->WeightSum = 1;
  }
  p.ErrorWeight = std::min(1.0, std::max(0.0, p.ErrorWeight));
  p.BatchFraction = std::min(1.0, std::max(1e-6, p.BatchFraction));
  this->MeshOptions = CollapseOptions();
  this->MeshOptions.MinimumNormalDot = p.MinimumNormalDot;
  // Folding candidates are rejected before the link walk. Every caller here only asks whether a
  // collapse is valid, never which test failed, so the order changes no result.
  this->MeshOptions.GeometryFirst = true;
  this->Rules = CollapsibleOptions();
  this->KeepValences = false;
}

// M0 and the empty hierarchy over it: every input point its own global vertex and ancestor,
// every triangle a version born at 0.
void CollapseHierarchy::Reset(TriangleMesh&& input, std::vector<unsigned char>&& nonManifoldVertices)
{
  this->Base = std::move(input);
  if (this->Parameters.RemoveCycles)
  {
    this->RemoveCyclesBySwapping(this->Base);
  }
  // The mesh only shrinks: its references compacted in place before they pass 1.25 times their
  // first size (the fans keep their order, so no output moves) instead of at twice it, where the
  // appended blocks took 48 bytes per input vertex at the peak of the build instead of 30.
  // Room of 1: the references are compacted in place whenever the appended blocks pass an eighth
  // of the live ones (EditableMesh's least room), 3 bytes per input vertex less than the 1.25 of
  // ShrinkingMeshRoomFactor at every level before the references' first rebuild (level 24 on
  // mc1m), for a compaction every level or two instead of every three or four (each a walk of the
  // vertices and references: a few milliseconds per million triangles).
  this->Mesh.SetReferenceRoomFactor(HierarchyReferenceRoomFactor);
  // No per-vertex link marks (12 bytes per input vertex for the whole build): the checks run in
  // serial (the concurrent ones, ChooseAhead's, bring their own tables) and take the mesh's table.
  this->Mesh.SetVertexLinkMarks(false);
  this->Mesh.Reset(this->Base);
  this->LockNonManifoldVertices(std::move(nonManifoldVertices));
  // M0's points for the life of the hierarchy (the editable mesh has its own copy to move).
  this->BasePoints.Take(this->Base.Points);
  const Index np = this->NumberOfBasePoints();
  const Index nt = this->Base.NumberOfTriangles();
  this->CollapsePoints.clear();
  this->GlobalOf.resize(np);
  std::iota(this->GlobalOf.begin(), this->GlobalOf.end(), 0);
  this->AncestorCounts.clear();
  this->VersionsBornBy.assign(1, nt);
  this->Deaths.clear(); // (DeriveDeaths)
  this->EntryCode.clear(); // (M0's versions are implicit: CodeOf)
  this->VersionsPacked = false;
  this->PackedCodes.Release();
  this->PackedDeaths.Release();
  this->FullEntryVertices.clear();
  this->RowOf.Reset(size_t(nt)); // every slot its own row until the first compaction
  this->Rows = nt;
  this->ResetRecords();
  this->ReserveRecords();
  this->VertexMark.assign(np, 0);
  this->MarkEpoch = 0;
  this->VertexStamps.assign(size_t(np), 0);
  this->VertexDegrees.assign(size_t(np), UnknownDegree);
  this->BlockedWide = false;
  this->BlockEpochs.clear();
  for (BlockedColumn* column : { &this->BlockedStrict, &this->BlockedRelaxed, &this->BlockedEdge })
  {
    *column = BlockedColumn(); // (an aborted build's, wide or not; relaxed and edge: allocated when first used)
  }
  this->AssignBlocked(this->BlockedStrict, nt);
  this->EdgeCollapseCount = 0;
  this->BatchRechecks = 0;
  this->ValenceRefusals = 0;
  this->PricingMismatches = 0;
  this->BoundedEndPoints = 0;
  this->TrialPoints = 0;
  this->TrialPointsOnRefusedEdges = 0;
  this->CollapsesInRuns = 0;
  this->ChoicesAhead = 0;
  this->ChoicesInOrder = 0;
  this->ChoicesDecidedAhead = 0;
  // Border flags, computed once (EditableMesh::IsBoundaryVertex was a fifth of the build when
  // asked at every check): collapses keep the topology, so a merged vertex is on the border
  // exactly when one of its vertices was, and swaps only turn interior edges.
  // (In one pass with the fans' counts on the stack: asked vertex by vertex through the mesh's
  // hashed table it was 1.5% of the run on mc250k.)
  this->Mesh.BoundaryVertexFlags(this->OnBorder);
  this->MeshOptions.BoundaryVertices = this->OnBorder.data();
  this->Orientation.Hierarchy = this;
  this->ChoiceOptions = this->MeshOptions;
  this->ChoiceOptions.Survivors = &this->Orientation;
  this->ChangeCounter = 0;
}

// Reserved at once instead of grown by doubling (each doubling copied the whole vector into
// freshly faulted pages and held both copies: on mri.vtp the versions outgrew a reserve of three
// per input triangle, a copy of 150 MB). A reserve is only address space until it is written,
// so the bounds are generous: a collapse removes at least two triangles (at most nt / 2
// collapses), adds a point and new versions of the seven or so triangles around it and
// redirects about four corners (measured: 4.0 versions and 1.6 redirected corners per input
// triangle when reduced to 10%).
void CollapseHierarchy::ReserveRecords()
{
  const size_t nt = size_t(this->Base.NumberOfTriangles());
  const size_t collapses = nt / 2 + 1, versions = 5 * nt;
  this->EntryCode.reserve(versions - nt);
  this->VersionsBornBy.reserve(collapses + 1);
  this->CollapsePoints.reserve(3 * collapses);
  this->Collapses.reserve(collapses);
  this->AncestorCounts.reserve(collapses);
  this->Records.Reserve(collapses, nt, 3 * nt);
}

void CollapseHierarchy::ResetRecords()
{
  this->Collapses.clear();
  this->LevelStarts.assign(1, 0);
  this->Records.StorePositions = false;
  this->Records.StoreRemovedTriangleVertices = false;
  this->Records.Clear();
}

// Per vertex: the area-weighted planes of its input triangles (only when the error or the edge
// collapses need them). Also a first mean area (the vertex error term of the evaluation uses it).
void CollapseHierarchy::InitializeQuadrics()
{
  const Index nt = this->Base.NumberOfTriangles();
  // The mean area as EvaluateAllTriangles computes it from M0's evaluations (the same sum in the
  // same order, so the same number): the edge costs priced during M0's evaluation stay valid.
  // (A sum of area / nt differed in the last bits, which threw all of M0's costs away.)
  double totalArea = 0;
  for (Index t = 0; t < nt; ++t)
  {
    totalArea += 0.5 * Norm(this->BaseAreaVector(t));
  }
  this->MeanArea = totalArea > 0 ? totalArea / nt : 1.0;
  this->Quadrics.clear();
  this->QuadricRowOf.Release();
  std::vector<float>().swap(this->EdgeCostErrors);
  std::vector<unsigned char>().swap(this->EdgeCostKinds);
  if (this->Parameters.ErrorWeight <= 0 && this->Parameters.EdgeCollapses == CollapseHierarchyParameters::EdgeFallback::Off)
  {
    return;
  }
  if (this->Parameters.ReuseEdgeCosts)
  {
    this->EdgeCostErrors.assign(3 * size_t(nt), std::numeric_limits<float>::quiet_NaN());
    this->EdgeCostKinds.assign(size_t(nt), 0);
  }
  this->Quadrics.assign(this->NumberOfBasePoints(), Quadric());
  this->QuadricRowOf.Reset(this->Quadrics.size());
  for (Index t = 0; t < nt; ++t)
  {
    const Index* tri = this->Base.Triangle(t);
    Quadric q;
    if (TrianglePlaneQuadric(this->BasePoints.Point(tri[0]), this->BasePoints.Point(tri[1]), this->BasePoints.Point(tri[2]), q) > 0)
    {
      for (int k = 0; k < 3; ++k)
      {
        this->QuadricOf(tri[k]) += q;
      }
    }
  }
  this->AddBorderPlanes();
}

// Border edges of M0 get a plane through the edge, perpendicular to its triangle, weighted by the
// squared edge length (area units), on both ends: an edge collapse along a border keeps the
// border's line, and an interior vertex merged into a border vertex stays on it.
void CollapseHierarchy::AddBorderPlanes()
{
  const EditableMesh& m = this->Mesh;
  for (Index t = 0; t < this->Base.NumberOfTriangles(); ++t)
  {
    const Index* tri = this->Base.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index u = tri[k], v = tri[(k + 1) % 3];
      if (!this->OnBorder[u] || !this->OnBorder[v] || this->LockedVertices[u] || this->LockedVertices[v])
      {
        continue;
      }
      int sharing = 0;
      m.ForEachTriangle(u, [&](Index x) {
        const Index* o = m.Triangle(x);
        sharing += (o[0] == v || o[1] == v || o[2] == v) ? 1 : 0;
      });
      Quadric q;
      // (A degenerate triangle's zero quadric adds nothing.)
      if (sharing == 1 && BorderEdgeQuadric(m.Point(u), m.Point(v), Normalized(this->BaseAreaVector(t)),
            this->Parameters.BoundaryWeight, q))
      {
        this->QuadricOf(u) += q;
        this->QuadricOf(v) += q;
      }
    }
  }
}

// The initial evaluation of every triangle; the curvature and valence normalisers come from M0.
bool CollapseHierarchy::EvaluateAllTriangles(const ProgressFunction& progress)
{
  const Index nt = this->Base.NumberOfTriangles();
  this->Evaluations.assign(nt, StoredEvaluation());
  this->KeptPoints.clear();
  this->KeptErrors.clear();
  this->OtherNormals.clear();
  M0Terms m0;
  if (this->Parameters.ErrorWeight < 1)
  {
    this->PaperTerms.assign(nt, 0.0);
    m0.Shapes.resize(static_cast<size_t>(nt));
  }
  else
  {
    std::vector<double>().swap(this->PaperTerms);
  }
  this->PriceSpokes(nullptr); // every edge once instead of once per triangle
  // (M0's order under the valence rule already: ValenceDiscount.)
  this->KeepValences = this->ValenceRuleHolds(nt);
  constexpr Index Slice = Index(1) << 16; // evaluated at once between progress reports
  for (Index first = 0; first < nt; first += Slice)
  {
    const Index count = std::min(Slice, nt - first);
    this->EvaluateTriangles(nullptr, first, count, &m0);
    if (progress && !progress(0.1 * (first + count) / nt))
    {
      return false;
    }
  }
  const double guess = this->MeanArea;
  this->MeanArea = m0.TotalArea > 0 ? m0.TotalArea / nt : 1.0;
  if (this->MeanArea != guess)
  {
    // The vertex error term of these evaluations used the guess: their edge choices may not be
    // FindEdgeCollapse's first with the final mean area.
    for (StoredEvaluation& e : this->Evaluations)
    {
      e.CheapestEdge.Edge = -1;
    }
    this->KeepGuessedErrors(guess);
    std::fill(this->EdgeCostErrors.begin(), this->EdgeCostErrors.end(), std::numeric_limits<float>::quiet_NaN());
  }
  this->KappaMax = m0.KappaMax > 0 ? m0.KappaMax : 1.0;
  this->Mv = this->Parameters.ValenceNormalizer > 0 ? this->Parameters.ValenceNormalizer : std::max(1, m0.ValenceMax);
  for (Index t = 0; t < nt; ++t)
  {
    if (!m0.Shapes.empty())
    {
      const ShapeTerms& shape = m0.Shapes[t];
      this->PaperTerms[this->Row(t)] = this->PaperTerm(shape.Kappa, shape.Alpha, shape.Valence, shape.Area);
    }
    StoredEvaluation& e = this->Evaluations[this->Row(t)];
    e.Weight = this->WeightOf(t, e.Weight);
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// One level M_level -> M_level+1: select a batch (relaxing, swapping or allowing edge collapses
// when blocked), collapse it, record the level, swap blocking edges and reweigh around the new
// vertices. False when no collapse was possible (the hierarchy is complete).
bool CollapseHierarchy::ReduceLevel(int level, LevelState& state)
{
  const CollapseHierarchyParameters& p = this->Parameters;
  {
    StageTimer timer(*this, StageOrder);
    this->PlanLevel(state);
    this->OrderCandidates(state);
  }
  {
    StageTimer timer(*this, StageSelect);
    this->SelectOrRelax(level, state);
    if (state.Batch.empty() && p.SwapBlockingEdges && p.SwapMinimumNormalDotWhenBlocked < p.SwapMinimumNormalDot)
    {
      this->SwapEverywhereAndRetry(level, state);
    }
    if (state.Batch.empty() && p.EdgeCollapses == CollapseHierarchyParameters::EdgeFallback::WhenBlocked)
    {
      // Still blocked everywhere: edge collapses for this level.
      state.Edges = true;
      this->SelectBatch(level, state);
    }
  }
  const size_t candidates = state.Candidates.size();
  this->NotePeak(&state, level, "its batch chosen");
  state.ReleaseSelection();
  ReturnFreedMemory();
  const Index levelStart = this->NumberOfCollapses();
  {
    StageTimer timer(*this, StageCollapse);
    this->CollapseBatch(state);
  }
  if (this->NumberOfCollapses() == levelStart)
  {
    return false;
  }
  this->LevelStarts.push_back(this->NumberOfCollapses());

  // Recompute the weights of the triangles around the new vertices (and swapped edges).
  state.Touched.clear();
  for (Index k = levelStart; k < this->NumberOfCollapses(); ++k)
  {
    state.Touched.push_back(this->Records.Kept(k));
  }
  if (p.SwapBlockingEdges)
  {
    this->SwapAroundNewVertices(state);
  }
  this->ReweighAround(state.Touched, state);
  vtkLogF(TRACE, "collapse hierarchy level %d: %lld collapses, %lld triangles left, %zu candidates, %zu re-evaluated",
    level, static_cast<long long>(this->NumberOfCollapses() - levelStart),
    static_cast<long long>(this->Mesh.NumberOfLiveTriangles()), candidates, state.AffectedCount);
  return true;
}

// The level's batch size, search depth and rules (the paper's, or with the stencil plane).
void CollapseHierarchy::PlanLevel(LevelState& state)
{
  const CollapseHierarchyParameters& p = this->Parameters;
  state.RegionStamp = state.NextStamp(); // (no row holds it yet)
  const Index live = this->Mesh.NumberOfLiveTriangles();
  state.Wanted = std::max<Index>(1, static_cast<Index>(std::floor(p.BatchFraction * live)));
  if (p.MinimumNumberOfTriangles > 0)
  {
    state.Wanted = std::min<Index>(state.Wanted, std::max<Index>(1, (live - p.MinimumNumberOfTriangles + 3) / 4));
  }
  this->Rules = CollapsibleOptions();
  this->Rules.StencilPlaneFallback = p.StarShapedInStencilPlane;
  this->KeepValences = this->ValenceRuleHolds(live);
  // Search depth in the priority order (BatchSearchDepth x batch size; unlimited when 0), in half
  // triangle collapses (SelectBatch).
  state.Depth = p.BatchSearchDepth > 0 ? 2 * static_cast<size_t>(std::ceil(p.BatchSearchDepth * state.Wanted))
                                       : std::numeric_limits<size_t>::max();
  // Below a quarter of the batch the search goes on: levels must keep making progress.
  state.MinimumBatch = std::max<Index>(1, state.Wanted / 4);
  // The first range of the priority order holds the depth searched (a candidate counts one half
  // collapse or more) with a margin for the sample's error; unlimited: the batch eight times.
  const size_t reach = p.BatchSearchDepth > 0 ? state.Depth : 8 * size_t(state.Wanted);
  state.FirstRange = std::min<size_t>(reach + reach / 4, size_t(live)) + 1024;
}

// Priority order of this level: its sample of the live triangles (the range bounds); the
// candidates themselves are collected by SelectBatch (CollectRange).
void CollapseHierarchy::OrderCandidates(LevelState& state) const
{
  state.Candidates.clear();
  state.Sample.clear();
  state.Raised.clear();
  state.Ranges = 0;
  state.Complete = false;
  const Index nt = this->Base.NumberOfTriangles();
  // Every 16th slot (a sixteenth of the memory a scan of the weights reads): the live ones
  // sample the live triangles evenly enough for bounds (a bound only sets a range's size). Late
  // in the build, when the rows are fewer than the sampled slots, through the rows (the same
  // triangles in the same order).
  const auto sample = [&](Index t, size_t row) {
    if (this->Evaluations[row].Weight <= state.MaximumWeight)
    {
      state.Sample.push_back({ this->Evaluations[row].Weight, t });
    }
  };
  if (size_t(this->Rows) * SampleStride < size_t(nt))
  {
    this->ForEachLiveTriangle([&](Index t, size_t row) {
      if (t % SampleStride == 0)
      {
        sample(t, row);
      }
    });
  }
  else
  {
    for (Index t = 0; t < nt; t += SampleStride)
    {
      if (this->Mesh.IsTriangleAlive(t))
      {
        sample(t, this->Row(t));
      }
    }
  }
  vtkSMPTools::Sort(state.Sample.begin(), state.Sample.end()); // (unique keys: one order)
}

// CollectRange in parallel, over blocks of BlockRows positions of ForEachLiveTriangle's walk (a
// whole number of bit words each): first each block marks its members in RangeBits and counts
// them, then (Fill) writes them at its offset in the candidates. The candidates are then those of
// one walk in slot order whatever the number of threads. (Collected in serial, with its sort,
// it was 8% of the build on mc1m.)
struct CollapseHierarchy::RangeCollection
{
  static constexpr size_t BlockRows = size_t(1) << 14;
  const CollapseHierarchy& Hierarchy;
  LevelState& State;
  RankedTriangle Bound;
  bool Bounded;
  size_t Have; // candidates of the earlier ranges
  bool Fill;

  // In the range: below the level's limit, after the ranges collected, up to the bound, and not
  // raised by the selection.
  bool Member(const RankedTriangle& r) const
  {
    const LevelState& s = this->State;
    return r.Weight <= s.MaximumWeight && (s.Ranges == 0 || s.Bound < r) && (!this->Bounded || !(this->Bound < r)) &&
      !std::binary_search(s.Raised.begin(), s.Raised.end(), r.Triangle);
  }

  void operator()(vtkIdType begin, vtkIdType end)
  {
    for (vtkIdType b = begin; b < end; ++b)
    {
      const size_t first = size_t(b) * BlockRows;
      const size_t last = std::min(first + BlockRows, size_t(this->Hierarchy.Rows));
      std::uint64_t* bits = this->State.RangeBits.data();
      if (!this->Fill)
      {
        size_t n = 0;
        this->Hierarchy.ForEachLiveTriangleIn(first, last, [&](Index t, size_t row) {
          if (this->Member({ this->Hierarchy.Evaluations[row].Weight, t }))
          {
            bits[row / 64] |= std::uint64_t(1) << (row % 64);
            ++n;
          }
        });
        this->State.RangeCounts[size_t(b)] = n;
        continue;
      }
      // (Only the members' rows are read again: through their bits; their slots, once rows are
      // compacted, along the rank words' bits.)
      const CollapseHierarchy& h = this->Hierarchy;
      RankedTriangle* out = this->State.Candidates.data() + this->Have + this->State.RangeCounts[size_t(b)];
      if (h.Rows == h.Base.NumberOfTriangles())
      {
        for (size_t w = first / 64; w < (last + 63) / 64; ++w)
        {
          for (std::uint64_t word = bits[w]; word != 0; word &= word - 1)
          {
            const size_t row = 64 * w + size_t(__builtin_ctzll(word));
            *out++ = { h.Evaluations[row].Weight, Index(row) };
          }
        }
        continue;
      }
      LiveRowIndex::Cursor slots(h.RowOf);
      for (size_t w = first / 64; w < (last + 63) / 64; ++w)
      {
        for (std::uint64_t word = bits[w]; word != 0; word &= word - 1)
        {
          const size_t row = 64 * w + size_t(__builtin_ctzll(word));
          *out++ = { h.Evaluations[row].Weight, Index(slots.ElementOf(row)) };
        }
      }
    }
  }
};

// Appends the next range of the priority order to the candidates, sorted: the live triangles
// ranked after the ranges already collected, up to the sample's rank of about twice as many
// (FirstRange the first time; the rest once the sample has no bound left). The ranks read are
// those of the level's start: a collected triangle whose weight the selection raised is left
// out (Raised), every other weight is unchanged until the level's collapses. False when every
// candidate has been collected.
bool CollapseHierarchy::CollectRange(LevelState& state) const
{
  if (state.Complete)
  {
    return false;
  }
  const size_t have = state.Candidates.size();
  // Ranks FirstRange, 2 FirstRange, 4 FirstRange, ... of the live triangles, in the sample's
  // proportion: at most 20 ranges, the last unbounded.
  const size_t live = std::max<size_t>(1, size_t(this->Mesh.NumberOfLiveTriangles()));
  const size_t at = state.Ranges < 20
    ? static_cast<size_t>(double(state.FirstRange << state.Ranges) * double(state.Sample.size()) / double(live))
    : state.Sample.size();
  const bool bounded = at < state.Sample.size();
  const RankedTriangle bound = bounded ? state.Sample[at] : RankedTriangle{ 0, 0 };
  std::sort(state.Raised.begin(), state.Raised.end());
  RangeCollection collection{ *this, state, bound, bounded, have, false };
  const vtkIdType blocks = static_cast<vtkIdType>((size_t(this->Rows) + RangeCollection::BlockRows - 1) / RangeCollection::BlockRows);
  state.RangeBits.assign((size_t(this->Rows) + 63) / 64, 0);
  state.RangeCounts.assign(size_t(blocks) + 1, 0);
  vtkSMPTools::For(0, blocks, 1, collection);
  // Each block's members go to the offset of the blocks before it: slot order, as one walk.
  size_t total = 0;
  for (size_t& count : state.RangeCounts)
  {
    const size_t n = count;
    count = total;
    total += n;
  }
  state.Candidates.resize(have + total);
  collection.Fill = true;
  vtkSMPTools::For(0, blocks, 1, collection);
  // (The keys are unique, a triangle is collected once: any sort gives this order.)
  vtkSMPTools::Sort(state.Candidates.begin() + have, state.Candidates.end());
  state.Bound = bound;
  state.Complete = !bounded;
  ++state.Ranges;
  return true;
}

// The paper's rules first; when nothing passes them, the relaxed rules (RelaxWhenBlocked).
void CollapseHierarchy::SelectOrRelax(int level, LevelState& state)
{
  state.Edges = this->Parameters.EdgeCollapses == CollapseHierarchyParameters::EdgeFallback::Everywhere;
  this->SelectBatch(level, state);
  if (state.Batch.empty() && this->Parameters.RelaxWhenBlocked)
  {
    // The whole list is sorted by now (the first pass scanned it all). The relaxed rules may make
    // valence-3 vertices: PreventNewValenceThree yields here, where nothing else can collapse
    // (the last levels of small or thin meshes), so that the targets are still reached.
    this->Rules.AllowNewCycles = true;
    this->Rules.StencilPlaneFallback = true;
    if (this->KeepValences)
    {
      this->KeepValences = false;
      // (Blocked under the valence rule says nothing without it; blocked without it, read by the
      // next levels, still holds with it. Cleared in place: the column keeps its size and room.)
      std::fill(this->BlockedEdge.Narrow.begin(), this->BlockedEdge.Narrow.end(), NoEpoch);
      std::fill(this->BlockedEdge.Wide.begin(), this->BlockedEdge.Wide.end(), Index(-1));
    }
    this->SelectBatch(level, state);
  }
}

// Blocked everywhere: swap the blocking edges of every vertex of valence 3 or 4 with a looser
// flatness limit, reweigh around them and try the level again.
void CollapseHierarchy::SwapEverywhereAndRetry(int level, LevelState& state)
{
  state.Touched.clear();
  for (Index q = 0; q < this->Mesh.NumberOfPoints(); ++q)
  {
    if (this->Mesh.IsVertexAlive(q))
    {
      this->SwapAround(q, this->Parameters.SwapMinimumNormalDotWhenBlocked, state.Touched);
    }
  }
  if (state.Touched.empty())
  {
    return;
  }
  this->ReweighAround(state.Touched, state);
  this->Rules = CollapsibleOptions();
  this->Rules.StencilPlaneFallback = this->Parameters.StarShapedInStencilPlane;
  this->KeepValences = this->ValenceRuleHolds(this->Mesh.NumberOfLiveTriangles());
  this->OrderCandidates(state);
  this->SelectOrRelax(level, state);
}

// ---------------------------------------------------------------------------------------------
// Independent batch (section 6): candidates in increasing weight, each taken when its collapse is
// allowed and its region is disjoint from the regions taken before, until the batch is full (in
// triangle collapses; an edge collapse removes two triangles instead of four and counts half).
// The priority order is sorted chunk by chunk: a batch usually needs a few times its size.
void CollapseHierarchy::SelectBatch(int level, LevelState& state)
{
  state.Batch.clear();
  state.BatchEdge.clear();
  state.BatchPoint.clear();
  state.Ahead.clear();
  state.AheadStart = 0;
  this->PrepareBlockedStamps(state);
  const bool ahead = this->Parameters.DecideAhead && vtkSMPTools::GetEstimatedNumberOfThreads() > 1;
  const Index full = 4 * state.Wanted;
  Index removed = 0;
  size_t examined = 0; // in half triangle collapses (see below)
  for (size_t i = 0; removed < full; ++i)
  {
    if (i == state.Candidates.size() && !this->CollectRange(state))
    {
      break;
    }
    if (i == state.Candidates.size())
    {
      --i; // an empty range: the next one
      continue;
    }
    // The depth counts in triangle collapses, as the batch: a candidate ordered by its edge
    // collapse removes half as much and counts half (else a level of edge collapses looked half
    // as deep and removed less: bunny00 needed 48 levels to get below 5% instead of 33).
    if (examined >= state.Depth && removed >= 4 * state.MinimumBatch)
    {
      break; // deeper candidates would force expensive collapses
    }
    if (!ahead)
    {
      this->PrefetchCandidates(state, i);
    }
    else if (i >= state.AheadStart + state.Ahead.size())
    {
      this->ChooseAhead(state, i, full - removed);
    }
    const RankedTriangle candidate = state.Candidates[i];
    const Index t = candidate.Triangle;
    const bool byEdge = state.Edges && (this->Evaluations[this->Row(t)].PreferEdge || this->HubMask(t) != 0);
    examined += byEdge ? 1 : 2;
    // The region of the collapse expected (for an edge, the triangles around its two ends, the
    // region MarkRegion marks), then of the one chosen.
    const int expected = byEdge ? this->Evaluations[this->Row(t)].CheapestEdge.Edge : -1;
    bool chosen = false;
    Choice choice;
    if (this->RegionIsFree(t, state, expected))
    {
      // (A region free now was free at the window's start: its choice is decided.)
      choice = ahead ? state.Ahead[i - state.AheadStart] : Choice();
      this->ChoicesAhead += choice.Decided ? 1 : 0;
      this->ChoicesInOrder += choice.Decided ? 0 : 1;
      choice = choice.Decided ? choice : this->ChooseCollapse(t, candidate.Weight, state.Edges, this->SerialChoice);
      this->Settle(t, choice);
      chosen = choice.Chosen && (choice.Edge == expected || this->RegionIsFree(t, state, choice.Edge));
    }
    if (this->Evaluations[this->Row(t)].Weight != candidate.Weight)
    {
      state.Raised.push_back(t);
    }
    if (!chosen)
    {
      continue;
    }
    this->MarkRegion(t, choice.Edge, state);
    state.Batch.push_back(t);
    state.BatchEdge.push_back(choice.Edge);
    state.BatchPoint.push_back(choice.Point);
    removed += choice.Edge < 0 ? 4 : 2;
  }
}

// The choices of the candidates i, i + 1, ... decided at once, in parallel: the selection does not
// change the mesh, and a choice reads only the mesh, its own row and the level's rules, so each
// is the one the selection would make on reaching it (Settle applies it then, in order). The
// candidates whose region is taken already are left undecided (the selection skips them); the
// window covers about as many candidates as the batch still needs collapses, since the regions
// taken meanwhile and the end of the batch make the choices beyond it wasted work.
struct CollapseHierarchy::ChoosingAhead
{
  const CollapseHierarchy& Hierarchy;
  LevelState& State;
  size_t First;
  bool Deferred; // the candidates with claimers (second pass), else those without

  void operator()(vtkIdType begin, vtkIdType end)
  {
    const CollapseHierarchy& h = this->Hierarchy;
    ChoiceScratch& scratch = this->State.AheadScratch.Local();
    scratch.Concurrent = true;
    for (vtkIdType j = begin; j < end; ++j)
    {
      bool claimed = false, taken = false;
      for (Index c : this->State.AheadClaimers[size_t(j)])
      {
        claimed = claimed || c >= 0;
        taken = taken || (c >= 0 && this->State.Ahead[size_t(c)].Chosen);
      }
      if (claimed != this->Deferred || taken)
      {
        continue;
      }
      const RankedTriangle candidate = this->State.Candidates[this->First + size_t(j)];
      const Index t = candidate.Triangle;
      const StoredEvaluation& e = h.Evaluations[h.Row(t)];
      const bool byEdge = this->State.Edges && (e.PreferEdge || h.HubMask(t) != 0);
      if (h.RegionIsFree(t, this->State, byEdge ? e.CheapestEdge.Edge : -1))
      {
        this->State.Ahead[size_t(j)] = h.ChooseCollapse(t, candidate.Weight, this->State.Edges, scratch);
      }
    }
  }
};

// Candidates next to each other in the order are often neighbours on the mesh (the two triangles
// of a cheap edge have the same edge collapse and weight): when the first is taken, the second's
// region is not free. A candidate whose triangle shares a vertex with earlier ones of the window
// (without claimers themselves) is decided in a second pass, and only when none of those was
// chosen (else the selection will skip it: on mc1m half of the choices decided ahead were wasted
// without this).
void CollapseHierarchy::DeferNeighbours(LevelState& state, size_t n) const
{
  size_t size = 64;
  while (size < 8 * n)
  {
    size *= 2;
  }
  state.ClaimedVertices.assign(size, -1);
  state.ClaimedBy.resize(size);
  state.AheadClaimers.assign(n, { { -1, -1, -1 } });
  const auto slot = [&](Index v) {
    size_t h = (size_t(std::uint32_t(v)) * 0x9E3779B1u) & (size - 1);
    while (state.ClaimedVertices[h] != v && state.ClaimedVertices[h] != -1) // (at most 3n of size >= 8n taken)
    {
      h = (h + 1) & (size - 1);
    }
    return h;
  };
  for (size_t j = 0; j < n; ++j)
  {
    const Index* tri = this->Mesh.Triangle(state.Candidates[state.AheadStart + j].Triangle);
    std::array<Index, 3>& claimers = state.AheadClaimers[j];
    bool claimed = false;
    for (int k = 0; k < 3; ++k)
    {
      const size_t h = slot(tri[k]);
      claimers[k] = state.ClaimedVertices[h] == tri[k] ? state.ClaimedBy[h] : -1;
      claimed = claimed || claimers[k] >= 0;
    }
    for (int k = 0; k < 3 && !claimed; ++k)
    {
      const size_t h = slot(tri[k]);
      state.ClaimedVertices[h] = tri[k];
      state.ClaimedBy[h] = Index(j);
    }
  }
}

void CollapseHierarchy::ChooseAhead(LevelState& state, size_t i, Index still)
{
  // still: what the batch still removes, in quarter triangle collapses. (On mc1m, an eighth of it
  // from 64 to 1,024 candidates: 4,059 windows, the choices decided ahead 2% more than those the
  // selection used.)
  const size_t window = std::min<size_t>(std::max<size_t>(size_t(still) / 8, 64), 1024);
  const size_t n = std::min(window, state.Candidates.size() - i);
  state.Ahead.assign(n, Choice());
  state.AheadStart = i;
  this->DeferNeighbours(state, n);
  ChoosingAhead choosing{ *this, state, i, false };
  this->DegreesFrozen = true;
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), 16, choosing);
  choosing.Deferred = true;
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), 16, choosing);
  for (const Choice& choice : state.Ahead)
  {
    this->ChoicesDecidedAhead += choice.Decided ? 1 : 0;
  }
  this->DegreesFrozen = false;
}

// The candidates are scattered over the mesh (weight order): what the selection reads of the
// coming ones is loaded ahead, in two steps (a triangle's row and vertices, then its row's data
// and its vertices' triangle blocks), so that the misses overlap instead of following each other.
void CollapseHierarchy::PrefetchCandidates(const LevelState& state, size_t i) const
{
  constexpr size_t Near = 4, Far = 8;
  const std::vector<RankedTriangle>& candidates = state.Candidates;
  if (i + Far < candidates.size())
  {
    const Index t = candidates[i + Far].Triangle;
    __builtin_prefetch(this->RowOf.Address(size_t(t)));
    __builtin_prefetch(this->Mesh.Triangle(t));
  }
  if (i + Near < candidates.size())
  {
    const Index t = candidates[i + Near].Triangle;
    __builtin_prefetch(&this->Evaluations[this->Row(t)]);
    __builtin_prefetch(&state.Marks[this->Row(t)]);
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      this->Mesh.PrefetchVertex(tri[k]);
    }
  }
}

// No triangle of t's region (edge -1: its stencil; else the triangles around that edge's two ends)
// is in the region of a collapse taken for this level. A hub triangle
// can only collapse its edge away from the hubs: its region is that edge's, and nothing it does
// reads the hubs' stars (without edge collapses it is no candidate).
bool CollapseHierarchy::RegionIsFree(Index t, const LevelState& state, int edge) const
{
  if (state.Marks[this->Row(t)] == state.RegionStamp)
  {
    return false;
  }
  const int hubs = this->HubMask(t);
  if (hubs != 0 && !state.Edges)
  {
    return false;
  }
  bool free = true;
  const Index* tri = this->Mesh.Triangle(t);
  for (int k = 0; k < 3 && free; ++k)
  {
    if (!((hubs >> k) & 1) && (edge < 0 || k == edge || k == (edge + 1) % 3))
    {
      this->Mesh.ForEachTriangle(tri[k], [&](Index x) { free = free && state.Marks[this->Row(x)] != state.RegionStamp; });
    }
  }
  return free;
}

// The region of the collapse (the stencil; for an edge, the triangles around its two vertices).
void CollapseHierarchy::MarkRegion(Index t, int edge, LevelState& state) const
{
  const Index* vertices = this->Mesh.Triangle(t);
  for (int k = 0; k < 3; ++k)
  {
    if (edge < 0 || k == edge || k == (edge + 1) % 3)
    {
      this->Mesh.ForEachTriangle(vertices[k], [&](Index x) { state.Marks[this->Row(x)] = state.RegionStamp; });
    }
  }
}

// The collapse triangle t takes at its place (weight) in the priority order: its triangle
// collapse, or (edges allowed) its cheapest valid edge collapse; a hub triangle only the latter,
// a triangle ordered by its edge collapse that first. Sets edge (-1: triangle) and point. Reads
// the mesh, t's row and the level's rules only, which no other candidate's choice changes.
CollapseHierarchy::Choice CollapseHierarchy::ChooseCollapse(
  Index t, double orderWeight, bool edges, ChoiceScratch& scratch) const
{
  Choice choice;
  choice.Decided = true;
  choice.Weight = this->Evaluations[this->Row(t)].Weight;
  const int hubs = this->HubMask(t);
  auto triangle = [&]() {
    if (!this->TriangleCollapseAllowed(t, orderWeight, choice, scratch))
    {
      return false;
    }
    choice.Edge = -1; // (TriangleCollapseAllowed set the point)
    return true;
  };
  auto edgeCollapse = [&]() { return edges && this->EdgeCollapseAllowed(t, orderWeight, hubs, choice, scratch); };
  if (hubs != 0)
  {
    choice.Chosen = edgeCollapse();
  }
  else
  {
    choice.Chosen = this->Evaluations[this->Row(t)].PreferEdge && edges ? (edgeCollapse() || triangle())
                                                                         : (triangle() || edgeCollapse());
  }
  return choice;
}

// What a choice changes of its triangle's row: its weight and blocked stamps.
void CollapseHierarchy::Settle(Index t, const Choice& choice)
{
  const size_t row = this->Row(t);
  this->Evaluations[row].Weight = choice.Weight;
  if (choice.BlockTriangle)
  {
    this->SetBlocked(this->Rules.AllowNewCycles ? this->BlockedRelaxed : this->BlockedStrict, row);
  }
  if (choice.BlockEdge)
  {
    this->SetBlocked(this->BlockedEdge, row);
  }
}

void CollapseHierarchy::SetBlocked(BlockedColumn& column, size_t row)
{
  if (!this->BlockedWide && (this->BlockEpochs.empty() || this->BlockEpochs.back() != this->ChangeCounter))
  {
    if (this->BlockEpochs.size() < size_t(std::clamp<int>(this->Parameters.NarrowBlockedEpochs, 0, NoEpoch)))
    {
      this->BlockEpochs.push_back(this->ChangeCounter);
    }
    else
    {
      this->WidenBlocked();
    }
  }
  if (this->BlockedWide)
  {
    column.Wide[row] = this->ChangeCounter;
  }
  else
  {
    column.Narrow[row] = static_cast<std::uint8_t>(this->BlockEpochs.size() - 1);
  }
}

void CollapseHierarchy::AssignBlocked(BlockedColumn& column, size_t rows) const
{
  if (this->BlockedWide)
  {
    column.Wide.assign(rows, -1);
  }
  else
  {
    column.Narrow.assign(rows, NoEpoch);
  }
}

// Every column holds its stamps from now on (the epochs ran out).
void CollapseHierarchy::WidenBlocked()
{
  for (BlockedColumn* column : { &this->BlockedStrict, &this->BlockedRelaxed, &this->BlockedEdge })
  {
    column->Wide.resize(column->Narrow.size());
    for (size_t r = 0; r < column->Narrow.size(); ++r)
    {
      column->Wide[r] = this->BlockedStamp(*column, r);
    }
    std::vector<std::uint8_t>().swap(column->Narrow);
  }
  this->BlockedWide = true;
}

// The blocked stamps of the level's rules (the relaxed ones and the edge collapses' at their
// first use), before any choice reads them.
void CollapseHierarchy::PrepareBlockedStamps(const LevelState& state)
{
  BlockedColumn& blocked = this->Rules.AllowNewCycles ? this->BlockedRelaxed : this->BlockedStrict;
  if (blocked.Empty())
  {
    this->AssignBlocked(blocked, size_t(this->Rows));
  }
  if (state.Edges && this->BlockedEdge.Empty())
  {
    this->AssignBlocked(this->BlockedEdge, size_t(this->Rows));
  }
}

// Rules (1)-(3), the mesh check and the orientation test for t's triangle collapse. Blocked
// before and nothing changed around it since: still blocked (the rules depend only on the stencil
// region, the collapse point only on T's vertices).
bool CollapseHierarchy::TriangleCollapseAllowed(Index t, double orderWeight, Choice& choice, ChoiceScratch& scratch) const
{
  const BlockedColumn& blocked = this->Rules.AllowNewCycles ? this->BlockedRelaxed : this->BlockedStrict;
  const StoredEvaluation& e = this->Evaluations[this->Row(t)];
  if (this->StarsUnchangedSince(t, this->BlockedStamp(blocked, this->Row(t))))
  {
    return false;
  }
  // (The point once: the error recomputed from it, and the checks below.)
  std::optional<Vec3> point;
  if (e.PreferEdge)
  {
    // Ordered by its edge collapse: the triangle collapse only at its own cost.
    if (!e.ErrorKept)
    {
      point = this->PointOf(t);
    }
    const double weight = this->WeightOf(t, this->ErrorOf(t, point ? *point : Vec3{ 0, 0, 0 }));
    if (weight > orderWeight * (1 + 1e-9) + 1e-300)
    {
      choice.Weight = std::max(choice.Weight, weight);
      return false;
    }
  }
  // (Rule (2) and the three edge neighbours first: they need the gathered stencil only, and on
  // isosurfaces they block many candidates before the classification would.)
  scratch.Stencils.Gather(this->Mesh, t, scratch.Stencil);
  if (StencilBuilder::FailsBeforeClassifying(this->Mesh, scratch.Stencil, this->Rules))
  {
    choice.BlockTriangle = true;
    return false;
  }
  scratch.Stencils.Classify(this->Mesh, scratch.Stencil);
  if (!point)
  {
    point = this->PointOf(t);
  }
  if (scratch.Stencils.CheckCollapsible(this->Mesh, scratch.Stencil, *point, this->NormalOf(t), &this->ChoiceOptions,
        this->Rules, scratch.OwnMarks()) == CollapsibleStatus::Ok &&
    !(this->KeepValences && scratch.Stencil.BoundaryPolygon.size() < 4))
  {
    // (A three-sided polygon: the collapse point would get valence three, a new cycle.)
    choice.Point = *point;
    return true;
  }
  choice.BlockTriangle = true;
  return false;
}

// t's cheapest valid edge collapse, taken at its own cost: when it is dearer than the triangle's
// place in the order, the triangle is put back with that cost (next level's order).
bool CollapseHierarchy::EdgeCollapseAllowed(
  Index t, double orderWeight, int hubs, Choice& choice, ChoiceScratch& scratch) const
{
  if (this->StarsUnchangedSince(t, this->BlockedStamp(this->BlockedEdge, this->Row(t)), hubs))
  {
    return false;
  }
  double error = 0;
  if (!this->FindEdgeCollapse(t, choice.Edge, choice.Point, error, scratch))
  {
    choice.BlockEdge = true;
    return false;
  }
  const double weight = this->WeightOf(t, error);
  if (weight <= orderWeight * (1 + 1e-9) + 1e-300)
  {
    return true;
  }
  choice.Weight = weight;
  return false;
}

// ---------------------------------------------------------------------------------------------
// The batch's collapses. Earlier collapses of the batch can only have changed valences on the
// shared stencil boundaries, so rule (2) is checked again.
//
// A collapse was selected after its checks passed on the mesh of the level's start. The regions
// are disjoint, so an earlier collapse of the batch changes nothing a later one's checks read
// (its triangles, their vertices' positions and flags, the triangles around those vertices)
// unless it changes the triangles around a vertex of that region: a vertex the two regions share
// on their boundaries, stamped by MarkChangedAround with the earlier collapse's new vertex (a
// merged vertex has all its triangles in its own region). Only such a region is checked again;
// the others would give the answer of their selection (a second CheckCollapse per collapse was
// 7% of the build's instructions on refined_elephant).
void CollapseHierarchy::CollapseBatch(LevelState& state)
{
  // (Runs shorter than this go one by one: a parallel region costs more than they gain.)
  constexpr size_t MinimumRun = 32;
  const Index batchStart = this->ChangeCounter;
  const size_t n = state.Batch.size();
  BatchRun& run = state.Run;
  run.Surveyed = 0;
  run.InOrder.resize(n);
  run.Survivors.resize(n);
  run.Removed.resize(n);
  run.Changed.resize(n);
  this->MarkSharedOpposites(state);
  // In the first levels (the rows over half the slots) the build's peak is the end of a batch: the
  // working data still hold the rows of the triangles and vertices the batch removed (about 12
  // bytes per input vertex on mc1m) while the hierarchy has grown by the batch (about 13). Those
  // of the first two thirds are given back before the last third is collapsed, where the two
  // moments are about equal. (Rows only move: the collapses read them by slot and vertex.)
  const size_t twoThirds = 2 * n / 3;
  const size_t compactAt = 4 * size_t(this->Rows) > size_t(this->Base.NumberOfTriangles()) && twoThirds > 0 ? twoThirds : n;
  for (size_t b = 0; b < n;)
  {
    if (b == compactAt)
    {
      this->NotePeak(&state, this->NumberOfLevels() - 1, "two thirds of its batch collapsed");
      this->CompactWorkingData(state);
    }
    const size_t stop = b < compactAt ? compactAt : n; // (a run does not cross the compaction)
    const size_t end = this->Parameters.ParallelCollapses ? this->RunEnd(state, b, stop) : b;
    if (end - b >= MinimumRun)
    {
      this->ApplyRun(state, b, end);
      b = end;
      continue;
    }
    for (const size_t last = std::max(end, b + 1); b < last; ++b)
    {
      this->CollapseInOrder(state, b, batchStart);
    }
  }
  run.Release(); // (the next batch sizes its own)
}

// Collapse b of the batch, checked again where an earlier collapse of the batch may have changed
// what its checks read (see CollapseBatch).
void CollapseHierarchy::CollapseInOrder(const LevelState& state, size_t b, Index batchStart)
{
  this->PrefetchBatch(state, b, state.Batch.size());
  const Index t = state.Batch[b];
  const Index* tri = this->Mesh.Triangle(t);
  const int edge = state.BatchEdge[b];
  if (edge >= 0)
  {
    const Index vertices[2] = { tri[edge], tri[(edge + 1) % 3] };
    const bool unchanged = !this->OppositeBorderVertexChangedSince(vertices[0], vertices[1], batchStart);
    this->BatchRechecks += unchanged ? 0 : 1;
    if (state.Run.SharedOpposite[b] && !this->EdgeKeepsValences(vertices[0], vertices[1]))
    {
      ++this->ValenceRefusals; // (an earlier collapse of the batch took an opposite vertex to four)
      return;
    }
    if (unchanged ||
      this->Mesh.CheckCollapse(vertices, 2, state.BatchPoint[b], this->MeshOptions) == CollapseStatus::Ok)
    {
      this->ApplyCollapse(t, vertices, 2, state.BatchPoint[b]);
    }
    return;
  }
  const bool unchanged = this->StarsUnchangedSince(t, batchStart);
  this->BatchRechecks += unchanged ? 0 : 1;
  if (unchanged || !this->CreatesCycle(t))
  {
    const Index vertices[3] = { tri[0], tri[1], tri[2] };
    this->ApplyCollapse(t, vertices, 3, state.BatchPoint[b]);
  }
}

// Surveys batch position b (reads the mesh only): whether it goes one by one, and its counts.
void CollapseHierarchy::SurveyCollapse(const LevelState& state, size_t b, std::vector<Index>& gathered) const
{
  BatchRun& run = const_cast<BatchRun&>(state.Run); // (each position written by one thread)
  const int edge = state.BatchEdge[b];
  run.InOrder[b] = 1;
  if (edge < 0)
  {
    return;
  }
  const Index* tri = this->Mesh.Triangle(state.Batch[b]);
  const Index u = tri[edge], v = tri[(edge + 1) % 3];
  const Index vertices[2] = { u, v };
  this->Mesh.GatherSet(vertices, 2, gathered);
  Index survivors = 0, removed = 0, changed = 0;
  bool borderOpposite = false;
  for (Index x : gathered)
  {
    const Index* q = this->Mesh.Triangle(x);
    int members = 0, other = 0;
    for (int j = 0; j < 3; ++j)
    {
      const bool member = q[j] == u || q[j] == v;
      members += member ? 1 : 0;
      other = member ? other : j;
    }
    if (members >= 2)
    {
      ++removed;
      borderOpposite = borderOpposite || (members == 2 && this->OnBorder[q[other]]);
      continue;
    }
    ++survivors;
    changed += (q[0] == v || q[1] == v || q[2] == v) ? 1 : 0; // (its corner becomes u)
  }
  run.InOrder[b] = borderOpposite || run.SharedOpposite[b] ? 1 : 0;
  run.Survivors[b] = survivors;
  run.Removed[b] = removed;
  run.Changed[b] = changed;
}

struct CollapseHierarchy::RunSurvey
{
  const CollapseHierarchy& Hierarchy;
  const LevelState& State;
  vtkSMPThreadLocal<std::vector<Index>>& Sets;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    std::vector<Index>& gathered = this->Sets.Local();
    for (vtkIdType b = begin; b < end; ++b)
    {
      this->Hierarchy.SurveyCollapse(this->State, size_t(b), gathered);
    }
  }
};

// The end of the run from b: the first collapse that goes one by one, or after which the blocks
// would be compacted. The positions are surveyed as the run reaches them, in parallel, in windows
// that grow with it.
size_t CollapseHierarchy::RunEnd(LevelState& state, size_t b, size_t stop) const
{
  BatchRun& run = state.Run;
  const size_t n = state.Batch.size();
  const size_t room = this->Mesh.ReferencesBeforeCompaction();
  size_t used = 0, r = b;
  for (; r < stop; ++r)
  {
    if (r == run.Surveyed)
    {
      const size_t window = std::min<size_t>(std::max<size_t>(64, r - b), size_t(1) << 14);
      const size_t last = std::min(n, r + window);
      RunSurvey survey{ *this, state, run.Sets };
      vtkSMPTools::For(static_cast<vtkIdType>(r), static_cast<vtkIdType>(last), survey);
      run.Surveyed = last;
    }
    if (run.InOrder[r] || used + size_t(run.Survivors[r]) > room)
    {
      break;
    }
    used += size_t(run.Survivors[r]);
  }
  return r;
}

struct CollapseHierarchy::RunApplication
{
  CollapseHierarchy& Hierarchy;
  const LevelState& State;
  BatchRun& Run;
  size_t Begin;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    CollapseRecord& record = this->Run.Records.Local();
    std::vector<Index>& gathered = this->Run.Sets.Local();
    for (vtkIdType i = begin; i < end; ++i)
    {
      this->Hierarchy.PrefetchBatch(this->State, this->Begin + size_t(i), this->Begin + size_t(end));
      this->Hierarchy.ApplyRunCollapse(this->State, this->Begin + size_t(i), record, gathered);
    }
  }
};

// The collapses [begin, end) of the batch at once: their slots first (prefix sums of their counts),
// then each collapse in parallel, then the counters.
void CollapseHierarchy::ApplyRun(LevelState& state, size_t begin, size_t end)
{
  BatchRun& run = state.Run;
  const size_t n = end - begin;
  run.Begin = begin;
  run.SurvivorStart.assign(1, 0);
  Index removed = 0;
  for (size_t b = begin; b < end; ++b)
  {
    run.SurvivorStart.push_back(run.SurvivorStart.back() + run.Survivors[b]);
    removed += run.Removed[b];
  }
  const Index survivors = run.SurvivorStart.back();
  run.FirstCollapse = this->NumberOfCollapses();
  run.FirstEntry = this->NumberOfEntries();
  run.FirstStamp = this->ChangeCounter;
  run.ReferenceStart = this->Mesh.ReserveRefs(survivors);
  const size_t collapses = size_t(run.FirstCollapse) + n;
  this->Collapses.resize(collapses);
  this->CollapsePoints.resize(3 * collapses);
  this->AncestorCounts.resize(collapses);
  this->VersionsBornBy.resize(collapses + 1);
  this->EntryCode.resize(this->EntryCode.size() + size_t(survivors));
  this->Records.AppendRoom(n, &run.Removed[begin], &run.Changed[begin]);
  RunApplication application{ *this, state, run, begin };
  vtkSMPTools::For(0, static_cast<vtkIdType>(n), application);
  this->Mesh.FinishCollapses(removed, static_cast<Index>(n)); // (no compaction: RunEnd)
  this->ChangeCounter += static_cast<Index>(n);
  this->EdgeCollapseCount += static_cast<Index>(n);
  this->CollapsesInRuns += static_cast<Index>(n);
}

// ApplyCollapse for edge collapse b of a run, in its slots (concurrently with the run's others).
void CollapseHierarchy::ApplyRunCollapse(
  const LevelState& state, size_t b, CollapseRecord& record, std::vector<Index>& gathered)
{
  const BatchRun& run = state.Run;
  const size_t i = b - run.Begin;
  const Index k = run.FirstCollapse + static_cast<Index>(i);
  const Index t = state.Batch[b];
  const Index* tri = this->Mesh.Triangle(t);
  const int edge = state.BatchEdge[b];
  const Index vertices[2] = { tri[edge], tri[(edge + 1) % 3] };
  const Index kept = vertices[0];
  const Vec3& p = state.BatchPoint[b];
  StoredCollapse& collapse = this->Collapses[size_t(k)];
  collapse.Sources[0] = this->GlobalOf[vertices[0]];
  collapse.Sources[1] = this->GlobalOf[vertices[1]];
  collapse.Sources[2] = InvalidIndex;
  collapse.Triangle = t;
  collapse.Weight = this->Evaluations[this->Row(t)].Weight;
  std::copy(p.begin(), p.end(), this->CollapsePoints.begin() + 3 * size_t(k));
  this->Mesh.GatherSet(vertices, 2, gathered);
  this->Mesh.CollapseIntoBlock(vertices, 2, kept, p, gathered, run.ReferenceStart + run.SurvivorStart[i], record);
  this->OnBorder[kept] |= this->OnBorder[vertices[1]];
  if (!this->Quadrics.empty())
  {
    this->QuadricOf(kept) += this->QuadricOf(vertices[1]);
  }
  this->AncestorCounts[size_t(k)] =
    this->AncestorCountOf(collapse.Sources[0]) + this->AncestorCountOf(collapse.Sources[1]);
  this->GlobalOf[kept] = this->PointOfCollapse(k);
  // One walk of kept's new fan for what ApplyCollapse does in three (MarkChangedAround,
  // ForgetEdgeCostsAround, the new versions): each triangle's row looked up once.
  const Index stamp = run.FirstStamp + static_cast<Index>(i) + 1;
  const bool costs = !this->EdgeCostErrors.empty();
  this->RaiseStamp(kept, stamp);
  Index e = run.FirstEntry + run.SurvivorStart[i]; // (the ended versions' deaths: DeriveDeaths)
  const Index nt = this->Base.NumberOfTriangles();
  this->Mesh.ForEachTriangle(kept, [&](Index x) {
    const Index* q = this->Mesh.Triangle(x);
    const size_t row = this->Row(x);
    this->RaiseStampsOf(q, stamp);
    if (costs)
    {
      this->ForgetEdgeCostsAt(kept, q, row);
    }
    this->EntryCode[size_t(e - nt)] = std::uint32_t(x) << 2 | (q[0] == kept ? 0 : (q[1] == kept ? 1 : 2));
    ++e;
  });
  this->VersionsBornBy[size_t(k) + 1] = e;
  this->Records.SetAt(k, record, this->Mesh);
}

// The batch's collapses are scattered over the mesh (weight order): what ApplyCollapse reads of
// the coming ones is loaded ahead in three steps (a triangle and its row; its vertices' blocks,
// points and quadric rows; their triangle blocks and quadrics), so that the misses overlap (the
// merged vertices' quadrics were a quarter of ApplyCollapse's samples on mc1m).
void CollapseHierarchy::PrefetchBatch(const LevelState& state, size_t b, size_t end) const
{
  constexpr size_t Near = 2, Middle = 4, Far = 8;
  const std::vector<Index>& batch = state.Batch;
  if (this->Quadrics.empty())
  {
    return; // (the paper's configuration: nothing cold to load but the mesh)
  }
  if (b + Far < end)
  {
    __builtin_prefetch(this->Mesh.Triangle(batch[b + Far]));
    __builtin_prefetch(this->RowOf.Address(size_t(batch[b + Far])));
  }
  if (b + Middle < end)
  {
    const Index* tri = this->Mesh.Triangle(batch[b + Middle]);
    for (int k = 0; k < 3; ++k)
    {
      this->Mesh.PrefetchVertex(tri[k]);
      __builtin_prefetch(this->QuadricRowOf.Address(size_t(tri[k])));
    }
  }
  if (b + Near < end)
  {
    const Index* tri = this->Mesh.Triangle(batch[b + Near]);
    for (int k = 0; k < 3; ++k)
    {
      this->Mesh.PrefetchBlock(tri[k]);
      const Quadric* q = &this->QuadricOf(tri[k]);
      __builtin_prefetch(q);
      __builtin_prefetch(reinterpret_cast<const char*>(q) + 64);
    }
  }
}

// What an edge collapse's check (EditableMesh::CheckCollapse) reads that an earlier collapse of
// the batch can change. Its two stars are in its region (the triangles, their corners and their
// vertices' positions: an earlier collapse moves only vertices all of whose triangles are in its
// own, disjoint, region), so the link, border-chain and geometry tests give the answer of the
// selection. What is read beyond them: the star of a border vertex opposite the edge (a vertex
// may not lose every triangle, IsolatesVertex), which an earlier collapse stamps when it changes
// it (MarkChangedAround). Only then is the collapse checked again (the whole-star test,
// StarsUnchangedSince, re-checked 60% of mc1m's collapses, none of which could fail: it has no
// border).
bool CollapseHierarchy::OppositeBorderVertexChangedSince(Index u, Index v, Index stamp) const
{
  bool changed = false;
  this->Mesh.ForEachTriangle(u, [&](Index x) {
    const Index* q = this->Mesh.Triangle(x);
    for (int j = 0; j < 3; ++j)
    {
      // (a triangle on the edge: its vertex other than u and v is opposite it)
      changed = changed || (q[j] != u && q[j] != v && this->OnBorder[q[j]] &&
                             this->VertexStamps[q[j]] > stamp && (q[0] == v || q[1] == v || q[2] == v));
    }
  });
  return changed;
}

// Rule (2) under the level's rules: an opposite vertex of T's edge neighbours has valence four.
bool CollapseHierarchy::CreatesCycle(Index t)
{
  if (this->Rules.AllowNewCycles)
  {
    return false;
  }
  this->Stencils.Gather(this->Mesh, t, this->Stencil); // (the opposite vertices need no classification)
  for (Index q : this->Stencil.OppositeVertices)
  {
    if (this->Degree(q) == 4)
    {
      return true;
    }
  }
  return false;
}

// PreventNewValenceThree holds on levels with more than ValenceRuleFraction of M0's triangles. On
// coarse levels the rule costs accuracy: it blocks the cheap collapses of thin parts (femur at 2%
// measured 2.2x vtkQuadricDecimation's Hausdorff distance and 5.8x its mean with the rule on every
// level, 1.0x without; cow's mean 1.8x), where at 10% and 50% it cost 1.03x and 1.00x (Hausdorff,
// geometric means over 56 CGAL meshes).
bool CollapseHierarchy::ValenceRuleHolds(Index live) const
{
  constexpr double ValenceRuleFraction = 0.05;
  return this->Parameters.PreventNewValenceThree &&
    double(live) > ValenceRuleFraction * double(this->Base.NumberOfTriangles());
}

// PreventNewValenceThree for the edge collapse of (u, v). The triangles on the edge go: an
// interior vertex opposite it loses a neighbour, and the merged vertex has val(u) + val(v) - 4
// (interior edge). Border vertices are left to the border rules (their valence counts differently).
bool CollapseHierarchy::EdgeKeepsValences(Index u, Index v) const
{
  bool keeps = true;
  this->ForEachOppositeVertex(u, v, InvalidIndex, [&](Index o) { keeps = keeps && (this->OnBorder[o] || this->Degree(o) > 4); });
  if (!keeps || this->OnBorder[u] || this->OnBorder[v])
  {
    return keeps;
  }
  const Index du = this->Degree(u), dv = this->Degree(v);
  return du <= 3 || dv <= 3 || du + dv >= 8; // (a valence-3 vertex merged away may leave one)
}

// Each collapse of the batch was checked on the level's mesh, alone; a vertex on the boundaries
// of two regions, opposite a collapsed edge in both, loses a neighbour to each. Where that could
// leave it below four, such edge collapses go one by one and check their opposite vertices again
// (CollapseInOrder); triangle collapses always do (CreatesCycle). Work: the fans of the collapsed edges' first vertices and
// a sort of at most six pairs per collapse.
void CollapseHierarchy::MarkSharedOpposites(LevelState& state)
{
  BatchRun& run = state.Run;
  const size_t n = state.Batch.size();
  run.SharedOpposite.assign(n, 0);
  if (!this->KeepValences)
  {
    return;
  }
  std::vector<std::pair<Index, Index>>& pairs = run.Opposites;
  pairs.clear();
  for (size_t b = 0; b < n; ++b)
  {
    const Index t = state.Batch[b];
    const Index* tri = this->Mesh.Triangle(t);
    const int edge = state.BatchEdge[b];
    for (int k = edge < 0 ? 0 : edge; k < (edge < 0 ? 3 : edge + 1); ++k)
    {
      // (a triangle collapse's own triangle holds no opposite vertex: its third vertex merges)
      this->ForEachOppositeVertex(tri[k], tri[(k + 1) % 3], edge < 0 ? t : InvalidIndex, [&](Index o) {
        if (!this->OnBorder[o])
        {
          pairs.emplace_back(o, static_cast<Index>(b));
        }
      });
    }
  }
  std::sort(pairs.begin(), pairs.end());
  for (size_t i = 0; i < pairs.size();)
  {
    size_t j = i + 1;
    while (j < pairs.size() && pairs[j].first == pairs[i].first)
    {
      ++j;
    }
    // (Only where the collapses together could take it below four: marking every shared vertex
    // sent most of mc250k's edge collapses one by one, out of the concurrent runs.)
    const bool low = j - i > 1 && this->Degree(pairs[i].first) < Index(4 + (j - i));
    for (size_t k = i; low && k < j; ++k)
    {
      run.SharedOpposite[size_t(pairs[k].second)] = 1;
    }
    i = j;
  }
}

// The valences changed on the batch's stencil boundaries: swap around the neighbours of the new
// vertices (state.Touched), adding the swapped edges' vertices to it.
void CollapseHierarchy::SwapAroundNewVertices(LevelState& state)
{
  const size_t kept = state.Touched.size();
  for (size_t i = 0; i < kept; ++i)
  {
    this->Mesh.Neighbors(state.Touched[i], state.Ring);
    for (Index q : state.Ring)
    {
      this->SwapAround(q, this->Parameters.SwapMinimumNormalDot, state.Touched);
    }
  }
}

// Each triangle around the given vertices is evaluated and weighed again, once.
void CollapseHierarchy::ReweighAround(const std::vector<Index>& vertices, LevelState& state)
{
  std::optional<StageTimer> timer;
  timer.emplace(*this, StageGather);
  state.AffectedStamp = state.NextStamp();
  state.AffectedCount = 0;
  for (Index v : vertices)
  {
    this->Mesh.ForEachTriangle(v, [&](Index x) {
      if (state.Marks[this->Row(x)] != state.AffectedStamp)
      {
        state.Marks[this->Row(x)] = state.AffectedStamp;
        ++state.AffectedCount;
      }
    });
  }
  timer.emplace(*this, StagePrice);
  this->PriceSpokes(&vertices);
  timer.emplace(*this, StageEvaluate);
  // The marked rows in row order, which is slot order (the input's, spatially coherent, rather
  // than the batch's, by weight: neighbouring evaluations then share cached triangles and points;
  // the results do not depend on the order), a chunk at a time: a list of all of them (4 bytes
  // per re-evaluated triangle, half the triangles at the first level) was 4 bytes per input
  // vertex of the build's peak.
  std::vector<Index>& chunk = state.AffectedChunk;
  chunk.clear();
  const auto evaluateChunk = [&]() {
    this->EvaluateTriangles(chunk.data(), 0, static_cast<Index>(chunk.size()));
    for (Index x : chunk)
    {
      StoredEvaluation& e = this->Evaluations[this->Row(x)];
      e.Weight = this->WeightOf(x, e.Weight);
    }
    chunk.clear();
  };
  // (A marked row's slot from the rank words, by a cursor: the rows not marked, most of them, are
  // a byte's test each.)
  const bool rowsAreSlots = this->Rows == this->Base.NumberOfTriangles();
  LiveRowIndex::Cursor slots(this->RowOf);
  for (size_t r = 0; r < size_t(this->Rows); ++r)
  {
    if (state.Marks[r] == state.AffectedStamp)
    {
      chunk.push_back(rowsAreSlots ? Index(r) : Index(slots.ElementOf(r)));
      if (chunk.size() == size_t(EvaluationChunk))
      {
        evaluateChunk();
      }
    }
  }
  evaluateChunk();
}

// ---------------------------------------------------------------------------------------------
// The evaluations of a list of triangles run in parallel: each reads the mesh only and writes its
// own Evaluation, so the result does not depend on the number of threads or the order.
struct CollapseHierarchy::ConcurrentEvaluation
{
  const CollapseHierarchy* Hierarchy;
  const Index* Triangles; // nullptr: the triangles First, First + 1, ...
  Index First;
  std::vector<Evaluation>& Working; // one per triangle of the list
  std::vector<EvaluationRest>& Rests;
  std::vector<Alternatives>& PendingAlternatives;
  vtkSMPThreadLocal<LinkEdges> Links;

  void operator()(vtkIdType begin, vtkIdType end)
  {
    LinkEdges& link = this->Links.Local();
    for (vtkIdType i = begin; i < end; ++i)
    {
      const Index t = this->Triangles ? this->Triangles[i] : this->First + static_cast<Index>(i);
      Evaluation& e = this->Working[i];
      this->Rests[i] = this->Hierarchy->EvaluateConcurrently(t, e, link, this->PendingAlternatives[i]);
      // (The stencil fit sets the normal again: decided in StoreEvaluation then.)
      if (this->Hierarchy->Parameters.ParallelBookkeeping && this->Rests[i] != EvaluationRest::Fit)
      {
        e.NormalKind = e.OwnPlane ? NormalSource::Own : this->Hierarchy->NormalSourceOf(t, e.Normal);
        e.NormalKnown = true;
      }
    }
  }
};

// Evaluates triangles[first, first + count) (or the ids first, ... when triangles is null), a
// chunk at a time (the working evaluations are scratch of bounded size), and keeps each result.
// m0 (M0's evaluation) receives the weight terms whose normalisers are not known yet.
void CollapseHierarchy::EvaluateTriangles(const Index* triangles, Index first, Index count, M0Terms* m0)
{
  this->ShapeTermsRead = m0 || !this->PaperTerms.empty();
  for (Index begin = 0; begin < count; begin += EvaluationChunk)
  {
    const Index n = std::min(EvaluationChunk, count - begin);
    this->EvaluateChunk(triangles, first + begin, n);
    for (Index i = 0; i < n; ++i)
    {
      const Index t = triangles ? triangles[first + begin + i] : first + begin + i;
      const Evaluation& e = this->Working[i];
      this->StoreEvaluation(t, e);
      if (m0)
      {
        m0->TotalArea += e.Area; // (in slot order, as InitializeQuadrics sums it)
        m0->KappaMax = std::max(m0->KappaMax, e.Kappa);
        m0->ValenceMax = std::max(m0->ValenceMax, std::abs(e.Valence - 6));
        if (!m0->Shapes.empty())
        {
          m0->Shapes[t] = { e.Kappa, e.Alpha, e.Area, e.Valence };
        }
      }
    }
  }
}

// Evaluates triangles[first, first + count) into Working: the read-only part in parallel
// (vtkSMPTools), then in list order what needs shared scratch. With the stencil fit in every
// evaluation (the paper's weights) all of it is serial. Each starts from the triangle's last
// evaluation (a triangle without a plane keeps its error terms).
void CollapseHierarchy::EvaluateChunk(const Index* triangles, Index first, Index count)
{
  auto triangleAt = [&](Index i) { return triangles ? triangles[first + i] : first + i; };
  this->Working.resize(static_cast<size_t>(count));
  for (Index i = 0; i < count; ++i)
  {
    const StoredEvaluation& last = this->Evaluations[this->Row(triangleAt(i))];
    Evaluation& e = this->Working[i];
    e = Evaluation(); // (every evaluation sets its point)
    // With ErrorWeight 0 an evaluation carries its error (no evaluation sets it but a hub's);
    // otherwise only one without a plane does, and StoreEvaluation reads it then.
    e.Error = this->Parameters.ErrorWeight > 0 ? 0.0 : this->ErrorOf(triangleAt(i), Vec3{ 0, 0, 0 });
    e.PreferEdge = last.PreferEdge;
    e.CheapestEdge = last.CheapestEdge;
  }
  if (!(this->Parameters.ErrorWeight >= 1 && this->Parameters.QuadricCollapsePoint))
  {
    for (Index i = 0; i < count; ++i)
    {
      this->Evaluate(triangleAt(i), this->Working[i]);
    }
    return;
  }
  // Degree() caches lazily; filled here, the evaluations then only read the cache. Filled in
  // parallel (serial, it was 4% of mc1m's build): a valence is the mesh's whichever thread stores
  // it, and threads meeting at a vertex store the same value (relaxed atomics: no data race).
  vtkSMPTools::For(0, static_cast<vtkIdType>(count), [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
    {
      const Index* tri = this->Mesh.Triangle(triangleAt(static_cast<Index>(i)));
      for (int k = 0; k < 3; ++k)
      {
        std::uint16_t* degree = &this->VertexDegrees[tri[k]];
        const Index valence =
          __atomic_load_n(degree, __ATOMIC_RELAXED) == UnknownDegree ? this->Mesh.VertexDegree(tri[k]) : UnknownDegree;
        if (valence < UnknownDegree)
        {
          __atomic_store_n(degree, static_cast<std::uint16_t>(valence), __ATOMIC_RELAXED);
        }
      }
    }
  });
  this->Rests.resize(static_cast<size_t>(count));
  this->PendingAlternatives.resize(static_cast<size_t>(count));
  ConcurrentEvaluation evaluation{ this, triangles ? triangles + first : nullptr, first, this->Working,
    this->Rests, this->PendingAlternatives, {} };
  vtkSMPTools::For(0, static_cast<vtkIdType>(count), evaluation);
  for (Index i = 0; i < count; ++i)
  {
    this->FinishEvaluation(triangleAt(i), this->Working[i], this->Rests[i], this->PendingAlternatives[i]);
  }
}

// ---------------------------------------------------------------------------------------------
Index CollapseHierarchy::CollapsesForTriangleCount(Index target) const
{
  // The triangle count decreases with the number of collapses (the removed ones increase): the
  // first cut at or below the target, as a reduction is asked of vtkQuadricDecimation (a
  // triangle collapse removes four, so the closest cut was often one to three above and the
  // target reported missed); the coarsest cut when none is that low.
  const std::vector<Index>& removed = this->Records.RemovedOffsets;
  if (removed.empty())
  {
    return 0;
  }
  const Index nt = this->Base.NumberOfTriangles();
  const auto it = std::lower_bound(
    removed.begin(), removed.end(), target, [nt](Index gone, Index value) { return nt - gone > value; });
  return static_cast<Index>(std::min<size_t>(size_t(it - removed.begin()), removed.size() - 1));
}

// The versions born after at most `collapses` collapses, in order, each with its three global
// vertices: every version's slot is replayed (its changed corner set), living or not.
template <typename Functor>
void CollapseHierarchy::ForEachVersion(Index collapses, Functor&& f) const
{
  const Index np = this->NumberOfBasePoints(), nt = this->Base.NumberOfTriangles();
  const Index entries = this->VersionsBornBy[collapses];
  this->ScratchCorners.resize(3 * size_t(nt));
  const Index* full = this->FullEntryVertices.data();
  Index birth = 0; // collapses made when version e was born
  for (Index e = 0; e < entries; ++e)
  {
    while (e >= this->VersionsBornBy[birth])
    {
      ++birth;
    }
    const std::uint32_t code = this->CodeOf(e), corner = code & 3;
    Index* c = &this->ScratchCorners[3 * size_t(code >> 2)];
    if (corner != AllCorners)
    {
      c[corner] = np + birth - 1; // the point of collapse birth - 1
    }
    else
    {
      const Index* from = e < nt ? &this->Base.Triangles[3 * size_t(code >> 2)] : full;
      std::copy(from, from + 3, c);
      full += e < nt ? 0 : 3;
    }
    f(e, static_cast<Index>(code >> 2), static_cast<const Index*>(c));
  }
}

void CollapseHierarchy::Extract(Index collapses, Index blendEnd, double t, HierarchyMesh& out) const
{
  out.Clear();
  const Index ng = this->NumberOfVertices();
  collapses = std::max<Index>(0, std::min(collapses, this->NumberOfCollapses()));
  blendEnd = std::max(collapses, std::min(blendEnd, this->NumberOfCollapses()));
  t = std::min(1.0, std::max(0.0, t));
  out.BlendT = t;
  this->ScratchMap.resize(ng, InvalidIndex);
  // The blend's targets and batches only when there is a blend: a cut (collapses = blendEnd, the
  // filter's output for a target or a level) reads none, and the two arrays (4 bytes per global
  // vertex each, about 8 per input vertex) made the extraction after the build the run's peak.
  const bool blending = blendEnd > collapses;
  if (blending)
  {
    this->ScratchTarget.resize(ng, InvalidIndex);
    this->ScratchBatch.resize(ng, InvalidIndex);
  }
  for (Index k = collapses; k < blendEnd; ++k)
  {
    for (int j = 0; j < this->CountOfCollapse(k); ++j)
    {
      const Index g = this->Collapses[k].Sources[j];
      this->ScratchTarget[g] = this->PointOfCollapse(k);
      this->ScratchBatch[g] = k - collapses;
    }
  }
  this->ForEachVersion(collapses, [&](Index e, Index origin, const Index* g) {
    const Index death = this->DeathOf(e);
    if (death <= collapses)
    {
      return;
    }
    Index batch = InvalidIndex;
    int moving = 0;
    for (int j = 0; j < 3; ++j)
    {
      Index& slot = this->ScratchMap[g[j]];
      if (slot == InvalidIndex)
      {
        slot = static_cast<Index>(out.PointGlobal.size());
        out.PointGlobal.push_back(g[j]);
      }
      out.Triangles.push_back(slot);
      if (blending && this->ScratchBatch[g[j]] != InvalidIndex)
      {
        batch = this->ScratchBatch[g[j]];
        ++moving;
      }
    }
    out.TriangleBatch.push_back(batch);
    // Collapsing: all merged vertices of its collapse are in it (T, or both edge triangles).
    const int count = batch != InvalidIndex ? this->CountOfCollapse(collapses + batch) : 3;
    out.TriangleRole.push_back(moving == count ? 2 : (moving > 0 ? 1 : 0));
    out.TriangleOrigin.push_back(origin);
    out.TriangleCollapseLevel.push_back(
      death == Never ? -1 : this->LevelOfCollapse(death - 1));
  });
  const size_t n = out.PointGlobal.size();
  out.Points.resize(3 * n);
  out.PointTarget.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    const Index g = out.PointGlobal[i];
    const Vec3 a = this->Vertex(g);
    const Index target = blending ? this->ScratchTarget[g] : InvalidIndex;
    out.PointTarget[i] = target;
    if (target != InvalidIndex && t > 0)
    {
      const Vec3 b = this->Vertex(target);
      for (int j = 0; j < 3; ++j)
      {
        out.Points[3 * i + j] = t == 1.0 ? b[j] : a[j] + t * (b[j] - a[j]);
      }
    }
    else
    {
      std::copy(a.begin(), a.end(), &out.Points[3 * i]);
    }
    this->ScratchMap[g] = InvalidIndex;
  }
  for (Index k = collapses; k < blendEnd; ++k)
  {
    for (int j = 0; j < this->CountOfCollapse(k); ++j)
    {
      const Index g = this->Collapses[k].Sources[j];
      this->ScratchTarget[g] = InvalidIndex;
      this->ScratchBatch[g] = InvalidIndex;
    }
  }
}

HierarchyCollapse CollapseHierarchy::GetCollapse(Index k) const
{
  const StoredCollapse& s = this->Collapses[k];
  HierarchyCollapse c;
  std::copy(s.Sources, s.Sources + 3, c.Sources);
  c.Count = this->CountOfCollapse(k);
  c.Point = this->PointOfCollapse(k);
  c.Level = this->LevelOfCollapse(k);
  c.Triangle = s.Triangle;
  c.Weight = s.Weight;
  return c;
}

void CollapseHierarchy::ExtractLevel(double level, HierarchyMesh& out) const
{
  const int n = this->NumberOfLevels() - 1;
  if (!(level > 0))
  {
    level = 0;
  }
  if (level >= n)
  {
    this->Extract(this->LevelStarts[n], this->LevelStarts[n], 0.0, out);
    return;
  }
  const int i = static_cast<int>(std::floor(level));
  this->Extract(this->LevelStarts[i], this->LevelStarts[i + 1], level - i, out);
}

void CollapseHierarchy::Refine(EditableMesh& mesh, Index k) const
{
  CollapseRecord record;
  this->Records.Get(k, record);
  for (int i = 0; i < record.VertexCount; ++i)
  {
    // An editable vertex is always at its global vertex's position (same doubles).
    record.OldPositions[i] = this->Vertex(this->Collapses[k].Sources[i]);
  }
  record.NewPosition = this->Vertex(this->PointOfCollapse(k));
  this->Records.UndoFlipsAfter(k, mesh);
  mesh.Undo(record);
}

void CollapseHierarchy::Expand(Index collapses, HierarchyMesh& out) const
{
  out.Clear();
  collapses = std::max<Index>(0, std::min(collapses, this->NumberOfCollapses()));
  EditableMesh mesh = this->Mesh;
  std::vector<Index> global = this->GlobalOf; // editable vertex -> global vertex, as it is split
  std::vector<int> changeLevel(static_cast<size_t>(mesh.NumberOfTriangles()), -1);
  for (Index k = this->NumberOfCollapses() - 1; k >= collapses; --k)
  {
    this->Refine(mesh, k);
    // Newest first: what remains is the earliest change at or after `collapses`.
    const HierarchyCollapse c = this->GetCollapse(k);
    const auto flips = this->Records.FlipsAfter(k);
    for (Index f = flips.first; f < flips.second; ++f)
    {
      for (Index x : this->Records.Flips[size_t(f)].Triangles)
      {
        changeLevel[x] = c.Level;
      }
    }
    for (int i = 0; i < c.Count; ++i)
    {
      const Index v = this->Records.Vertices[3 * size_t(k) + i];
      global[v] = c.Sources[i];
      mesh.ForEachTriangle(v, [&](Index x) { changeLevel[x] = c.Level; });
    }
  }
  // Output points numbered in order of first use, as Extract does.
  std::vector<Index> slot(static_cast<size_t>(mesh.NumberOfPoints()), InvalidIndex);
  for (Index x = 0; x < mesh.NumberOfTriangles(); ++x)
  {
    if (!mesh.IsTriangleAlive(x))
    {
      continue;
    }
    for (int j = 0; j < 3; ++j)
    {
      const Index v = mesh.Triangle(x)[j];
      if (slot[v] == InvalidIndex)
      {
        slot[v] = static_cast<Index>(out.PointGlobal.size());
        out.PointGlobal.push_back(global[v]);
        const Vec3 p = mesh.Point(v);
        out.Points.insert(out.Points.end(), p.begin(), p.end());
      }
      out.Triangles.push_back(slot[v]);
    }
    out.TriangleOrigin.push_back(x);
    out.TriangleCollapseLevel.push_back(changeLevel[x]);
  }
  out.PointTarget.assign(out.PointGlobal.size(), InvalidIndex);
  out.TriangleBatch.assign(out.TriangleOrigin.size(), InvalidIndex);
  out.TriangleRole.assign(out.TriangleOrigin.size(), 0);
}
} // namespace slod
