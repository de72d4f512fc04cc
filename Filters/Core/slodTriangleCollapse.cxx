#include "slodTriangleCollapse.h"

#include "slodBucketQueue.h"
#include "slodPointAttributes.h"
#include "slodQuadric.h"

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <limits>

namespace slod
{
void CollapseHistory::Clear()
{
  *this = CollapseHistory();
}

void CollapseHistory::Append(const CollapseRecord& record, const EditableMesh& mesh)
{
  if (this->RemovedOffsets.empty())
  {
    this->RemovedOffsets.push_back(0);
    this->ChangedOffsets.push_back(0);
    this->SurroundingOffsets.push_back(0);
  }
  // Kept vertex first.
  Index order[3] = { 0, 1, 2 };
  for (int i = 0; i < record.VertexCount; ++i)
  {
    if (record.Vertices[i] == record.Kept)
    {
      std::swap(order[0], order[i]);
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    this->Vertices.push_back(record.Vertices[order[i]]);
    const Vec3& p = record.OldPositions[order[i]];
    this->OldPositions.insert(this->OldPositions.end(), p.begin(), p.end());
  }
  this->NewPositions.insert(this->NewPositions.end(), record.NewPosition.begin(), record.NewPosition.end());
  for (Index t : record.RemovedTriangles)
  {
    const Index* tri = mesh.Triangle(t);
    this->RemovedTriangles.insert(this->RemovedTriangles.end(), { t, tri[0], tri[1], tri[2] });
  }
  this->RemovedOffsets.push_back(static_cast<Index>(this->RemovedTriangles.size() / 4));
  for (size_t i = 0; i < record.ChangedTriangles.size(); ++i)
  {
    this->Changed.insert(this->Changed.end(),
      { record.ChangedTriangles[i], Index(record.ChangedCorner[i]), record.ChangedFrom[i] });
  }
  this->ChangedOffsets.push_back(static_cast<Index>(this->Changed.size() / 3));
}

void CollapseHistory::Get(Index k, CollapseRecord& record) const
{
  record.Clear();
  record.VertexCount = 3;
  record.Kept = this->Vertices[3 * size_t(k)];
  for (int i = 0; i < 3; ++i)
  {
    record.Vertices[i] = this->Vertices[3 * size_t(k) + i];
    const double* p = &this->OldPositions[9 * size_t(k) + 3 * i];
    record.OldPositions[i] = { p[0], p[1], p[2] };
  }
  const double* q = &this->NewPositions[3 * size_t(k)];
  record.NewPosition = { q[0], q[1], q[2] };
  for (Index r = this->RemovedOffsets[k]; r < this->RemovedOffsets[k + 1]; ++r)
  {
    record.RemovedTriangles.push_back(this->RemovedTriangles[4 * size_t(r)]);
  }
  for (Index c = this->ChangedOffsets[k]; c < this->ChangedOffsets[k + 1]; ++c)
  {
    record.ChangedTriangles.push_back(this->Changed[3 * size_t(c)]);
    record.ChangedCorner.push_back(static_cast<unsigned char>(this->Changed[3 * size_t(c) + 1]));
    record.ChangedFrom.push_back(this->Changed[3 * size_t(c) + 2]);
  }
}

size_t CollapseHistory::MemoryBytes() const
{
  return (this->Vertices.capacity() + this->RemovedOffsets.capacity() + this->RemovedTriangles.capacity() +
           this->ChangedOffsets.capacity() + this->Changed.capacity() + this->SurroundingOffsets.capacity() +
           this->Surrounding.capacity()) *
    sizeof(Index) +
    (this->OldPositions.capacity() + this->NewPositions.capacity()) * sizeof(double);
}

namespace
{
// The working state of one simplification. Coordinates of quadrics are relative to Origin (the
// bounding-box centre) so that plane offsets stay small and the 4x4 sums do not cancel.
class TriangleCollapser
{
public:
  TriangleCollapser(const TriangleCollapseOptions& options, PointAttributes* attributes)
    : Options(options)
    , Attributes(attributes && !attributes->Empty() ? attributes : nullptr)
  {
  }

  void Run(TriangleMesh& mesh, TriangleCollapseResult& result);

private:
  Vec3 Local(Index v) const { return this->Mesh.Point(v) - this->Origin; }
  void InitializeQuadrics();
  Quadric TriangleQuadric(const Index* tri, double& weight) const;
  // Best placement (local coordinates) and its cost for the triangle's quadric.
  double Place(const Index* tri, const Quadric& q, Vec3& local) const;
  double Cost(Index t, Vec3& local, double& error) const;
  void Update(Index t);
  void ExtractResult(TriangleCollapseResult& result);

  const TriangleCollapseOptions& Options;
  PointAttributes* Attributes;
  EditableMesh Mesh;
  Vec3 Origin{ 0, 0, 0 };
  double CostScale = 1.0; // makes float heap keys well scaled
  std::vector<Quadric> VertexQuadric; // accumulated mode: sum of the logical set's planes
  std::vector<double> VertexWeight;   // sum of their weights
  std::vector<unsigned char> Rejected; // 1: failed validity, retried when the 2-ring changes
  std::vector<unsigned char> Boundary; // per vertex: on a border (maintained, see CollapseOptions)
  std::vector<unsigned char> Pending;  // per vertex: a triangle of it was rejected for validity
  BucketQueue Heap;
  // Exact mode: original planes and, per vertex, the sorted ids of its logical set.
  std::vector<Quadric> PlaneQuadric;
  std::vector<double> PlaneWeight;
  std::vector<std::vector<Index>> LogicalSet;
  mutable std::vector<Index> UnionScratch;
};

void TriangleCollapser::InitializeQuadrics()
{
  const Index nv = this->Mesh.NumberOfPoints();
  const Index nt = this->Mesh.NumberOfTriangles();
  const bool exact = this->Options.ExactUnion;
  if (exact)
  {
    this->LogicalSet.assign(size_t(nv), {});
  }
  else
  {
    this->VertexQuadric.assign(size_t(nv), Quadric());
    this->VertexWeight.assign(size_t(nv), 0.0);
  }
  auto addPlane = [&](const Quadric& q, double w, const Index* vertices, int count) {
    if (exact)
    {
      const Index id = static_cast<Index>(this->PlaneQuadric.size());
      this->PlaneQuadric.push_back(q);
      this->PlaneWeight.push_back(w);
      for (int i = 0; i < count; ++i)
      {
        this->LogicalSet[vertices[i]].push_back(id);
      }
      return;
    }
    for (int i = 0; i < count; ++i)
    {
      this->VertexQuadric[vertices[i]] += q;
      this->VertexWeight[vertices[i]] += w;
    }
  };
  // Area-weighted planes: the quadric approximates the integral of the squared distance over the
  // surface, so large triangles count for the area they cover (Garland-Heckbert weighting).
  for (Index t = 0; t < nt; ++t)
  {
    const Index* tri = this->Mesh.Triangle(t);
    const Vec3 a = this->Local(tri[0]), b = this->Local(tri[1]), c = this->Local(tri[2]);
    const Vec3 n2 = Cross(b - a, c - a);
    const double len = Norm(n2);
    const double area = 0.5 * len;
    const Vec3 n = len > 0 ? (1.0 / len) * n2 : Vec3{ 0, 0, 0 };
    addPlane(Quadric::FromPointNormal(a, n, area), area, tri, 3);
  }
  // Boundary planes (§2.3): through the boundary edge, perpendicular to its triangle, weighted
  // by the squared edge length (same units as the areas) times the user weight.
  this->Boundary.assign(size_t(nv), 0);
  {
    for (Index t = 0; t < nt; ++t)
    {
      const Index* tri = this->Mesh.Triangle(t);
      for (int k = 0; k < 3; ++k)
      {
        const Index u = tri[k], v = tri[(k + 1) % 3];
        if (this->Mesh.EdgeTriangleCount(u, v) != 1)
        {
          continue;
        }
        this->Boundary[u] = this->Boundary[v] = 1;
        const Vec3 pu = this->Local(u), pv = this->Local(v);
        const Vec3 e = pv - pu;
        const Vec3 tn = Normalized(Cross(this->Local(tri[1]) - this->Local(tri[0]), this->Local(tri[2]) - this->Local(tri[0])));
        const Vec3 n = Normalized(Cross(e, tn));
        const double w = this->Options.BoundaryWeight * Dot(e, e);
        if (!(w > 0))
        {
          continue;
        }
        const Index ends[2] = { u, v };
        addPlane(Quadric::FromPointNormal(pu, n, w), 0.0, ends, 2);
      }
    }
  }
  if (exact)
  {
    for (auto& set : this->LogicalSet)
    {
      std::sort(set.begin(), set.end());
    }
  }
}

Quadric TriangleCollapser::TriangleQuadric(const Index* tri, double& weight) const
{
  if (!this->Options.ExactUnion)
  {
    Quadric q = this->VertexQuadric[tri[0]];
    q += this->VertexQuadric[tri[1]];
    q += this->VertexQuadric[tri[2]];
    weight = this->VertexWeight[tri[0]] + this->VertexWeight[tri[1]] + this->VertexWeight[tri[2]];
    return q;
  }
  // Union of the three sorted logical sets, each plane once.
  auto& u = this->UnionScratch;
  u.clear();
  for (int i = 0; i < 3; ++i)
  {
    const auto& s = this->LogicalSet[tri[i]];
    u.insert(u.end(), s.begin(), s.end());
  }
  std::sort(u.begin(), u.end());
  u.erase(std::unique(u.begin(), u.end()), u.end());
  Quadric q;
  weight = 0;
  for (Index id : u)
  {
    q += this->PlaneQuadric[id];
    weight += this->PlaneWeight[id];
  }
  return q;
}

double TriangleCollapser::Place(const Index* tri, const Quadric& q, Vec3& local) const
{
  const Vec3 a = this->Local(tri[0]), b = this->Local(tri[1]), c = this->Local(tri[2]);
  if (q.Minimize(local, 1e-10))
  {
    // A well-conditioned optimum far outside the neighbourhood still means a near-singular
    // system in practice (long thin features); keep it only within reach of the triangle.
    const Vec3 centroid = (1.0 / 3.0) * (a + b + c);
    const double reach = Dot(a - b, a - b) + Dot(b - c, b - c) + Dot(c - a, c - a);
    const Vec3 d = local - centroid;
    if (Dot(d, d) <= 4.0 * reach)
    {
      return q.Evaluate(local);
    }
  }
  // Fallback (§2.2): the best of the centroid, the vertices and the edge midpoints.
  const Vec3 candidates[7] = { (1.0 / 3.0) * (a + b + c), a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a) };
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3& p : candidates)
  {
    const double e = q.Evaluate(p);
    if (e < best)
    {
      best = e;
      local = p;
    }
  }
  return best;
}

double TriangleCollapser::Cost(Index t, Vec3& local, double& error) const
{
  const Index* tri = this->Mesh.Triangle(t);
  double weight = 0;
  const Quadric q = this->TriangleQuadric(tri, weight);
  const double cost = this->Place(tri, q, local);
  error = weight > 0 ? std::sqrt(cost / weight) : 0.0;
  return cost;
}

void TriangleCollapser::Update(Index t)
{
  Vec3 p;
  double error;
  const double cost = this->Cost(t, p, error);
  this->Heap.Set(t, static_cast<float>(cost * this->CostScale));
  this->Rejected[t] = 0;
}

void TriangleCollapser::Run(TriangleMesh& input, TriangleCollapseResult& result)
{
  result = TriangleCollapseResult();
  const bool verbose = std::getenv("SLOD_VERBOSE") != nullptr;
  auto clock = std::clock();
  auto lap = [&](const char* what) {
    if (verbose)
    {
      const auto now = std::clock();
      std::fprintf(stderr, "[triangle collapse] %s: %.3f s CPU\n", what, double(now - clock) / CLOCKS_PER_SEC);
      clock = now;
    }
  };
  const Index nt = input.NumberOfTriangles();
  {
    const auto bounds = input.Bounds();
    this->Origin = { 0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5]) };
    const double diagonal = input.BoundingBoxDiagonal();
    // Costs are area * distance^2 ~ length^4: normalise by the diagonal so float keys keep range.
    this->CostScale = diagonal > 0 ? 1.0 / (diagonal * diagonal * diagonal * diagonal) : 1.0;
  }
  this->Mesh.Reset(input);
  // The editable mesh holds its own copy: release the input's arrays (peak memory).
  std::vector<double>().swap(input.Points);
  std::vector<Index>().swap(input.Triangles);

  this->InitializeQuadrics();
  this->Rejected.assign(size_t(nt), 0);
  this->Pending.assign(size_t(this->Mesh.NumberOfPoints()), 0);
  {
    this->Heap.Reset(nt);
    for (Index t = 0; t < nt; ++t)
    {
      Vec3 p;
      double error;
      this->Heap.Set(t, static_cast<float>(this->Cost(t, p, error) * this->CostScale));
    }
  }

  lap("initialisation");
  const Index target = std::max<Index>(this->Options.TargetTriangles, 0);
  const double maxError = this->Options.MaximumError;
  CollapseOptions check;
  check.AllowTopologyChange = this->Options.AllowTopologyChange;
  check.BoundaryVertices = this->Options.AllowTopologyChange ? nullptr : this->Boundary.data();
  check.MinimumNormalDot = std::cos(std::min(180.0, std::max(0.0, this->Options.MaximumNormalDeviation)) * 3.14159265358979323846 / 180.0);
  CollapseRecord record;
  std::vector<Index> neighbors;
  long long resets = 0, updates = 0;
  const Index toRemove = std::max<Index>(1, this->Mesh.NumberOfLiveTriangles() - target);
  const Index progressStep = std::max<Index>(1, toRemove / 100);
  Index nextProgress = progressStep;
  const Index startTriangles = this->Mesh.NumberOfLiveTriangles();

  while (!this->Heap.Empty() && this->Mesh.NumberOfLiveTriangles() > target)
  {
    const Index t = this->Heap.Pop();
    Index tri[3];
    std::copy(this->Mesh.Triangle(t), this->Mesh.Triangle(t) + 3, tri);
    Vec3 local;
    double error;
    this->Cost(t, local, error);
    if (maxError >= 0 && error > maxError)
    {
      this->Rejected[t] = 2; // retried only when one of its vertices changes
      continue;
    }
    const Vec3 p = local + this->Origin;
    if (this->Mesh.CheckCollapse(tri, 3, p, check) != CollapseStatus::Ok)
    {
      this->Rejected[t] = 1;
      this->Pending[tri[0]] = this->Pending[tri[1]] = this->Pending[tri[2]] = 1;
      ++result.RejectedCollapses;
      continue;
    }
    const Index kept = std::min(tri[0], std::min(tri[1], tri[2]));
    // Point data: barycentric weights of the new vertex projected onto the triangle.
    if (this->Attributes)
    {
      const Vec3 a = this->Local(tri[0]), b = this->Local(tri[1]), c = this->Local(tri[2]);
      const Vec3 n = Cross(b - a, c - a);
      const double nn = Dot(n, n);
      double w[3] = { 1.0 / 3, 1.0 / 3, 1.0 / 3 };
      if (nn > 0)
      {
        w[0] = std::max(0.0, Dot(Cross(c - b, local - b), n) / nn);
        w[1] = std::max(0.0, Dot(Cross(a - c, local - c), n) / nn);
        w[2] = std::max(0.0, Dot(Cross(b - a, local - a), n) / nn);
      }
      this->Attributes->Merge(kept, tri, w, 3);
    }
    this->Mesh.Collapse(tri, 3, kept, p, &record);
    this->Boundary[kept] = this->Boundary[tri[0]] | this->Boundary[tri[1]] | this->Boundary[tri[2]];
    if (this->Options.ExactUnion)
    {
      auto& s = this->LogicalSet[kept];
      for (Index v : tri)
      {
        if (v != kept)
        {
          s.insert(s.end(), this->LogicalSet[v].begin(), this->LogicalSet[v].end());
          std::vector<Index>().swap(this->LogicalSet[v]);
        }
      }
      std::sort(s.begin(), s.end());
      s.erase(std::unique(s.begin(), s.end()), s.end());
    }
    else
    {
      Quadric q = this->VertexQuadric[tri[0]];
      q += this->VertexQuadric[tri[1]];
      q += this->VertexQuadric[tri[2]];
      this->VertexQuadric[kept] = q;
      this->VertexWeight[kept] = this->VertexWeight[tri[0]] + this->VertexWeight[tri[1]] + this->VertexWeight[tri[2]];
    }
    result.MaximumError = std::max(result.MaximumError, error);
    ++result.Collapses;
    for (Index r : record.RemovedTriangles)
    {
      this->Heap.Remove(r);
    }
    // Error propagation: the triangles around v0 get the quadric of their new logical sets.
    this->Mesh.ForEachTriangle(kept, [&](Index s) {
      this->Update(s);
      ++updates;
    });
    // Collapses rejected for validity may have become valid: retry those in the 2-ring.
    this->Mesh.Neighbors(kept, neighbors);
    for (Index w : neighbors)
    {
      if (this->Pending[w])
      {
        this->Pending[w] = 0;
        this->Mesh.ForEachTriangle(w, [&](Index s) {
          if (this->Rejected[s] == 1)
          {
            this->Update(s);
          }
        });
      }
    }
    if (this->Options.RecordHistory)
    {
      result.History.Append(record, this->Mesh);
      result.History.Surrounding.insert(result.History.Surrounding.end(), neighbors.begin(), neighbors.end());
      result.History.SurroundingOffsets.push_back(static_cast<Index>(result.History.Surrounding.size()));
    }
    const Index removed = startTriangles - this->Mesh.NumberOfLiveTriangles();
    if (removed >= nextProgress)
    {
      nextProgress = removed + progressStep;
      if (this->Options.Progress && !this->Options.Progress(double(removed) / double(toRemove)))
      {
        result.Aborted = true;
        break;
      }
    }
  }

  result.PeakWorkingBytes = this->Heap.MemoryBytes() + this->VertexQuadric.capacity() * sizeof(Quadric) +
    this->VertexWeight.capacity() * sizeof(double) + this->Rejected.capacity() + result.History.MemoryBytes();
  lap("collapses");
  this->ExtractResult(result);
  lap("extraction");
  if (verbose)
  {
    std::fprintf(stderr, "[triangle collapse] %d collapses, %d rejected, %lld heap re-keys, %lld updates\n",
      int(result.Collapses), int(result.RejectedCollapses), resets, updates);
  }
}

void TriangleCollapser::ExtractResult(TriangleCollapseResult& result)
{
  const Index nv = this->Mesh.NumberOfPoints();
  const Index nt = this->Mesh.NumberOfTriangles();
  std::vector<Index> oldToNew(size_t(nv), InvalidIndex);
  TriangleMesh& out = result.Mesh;
  out.Points.clear();
  out.Triangles.clear();
  out.Triangles.reserve(3 * size_t(this->Mesh.NumberOfLiveTriangles()));
  result.OutputToInput.clear();
  result.OutputTriangleIds.clear();
  for (Index t = 0; t < nt; ++t)
  {
    if (!this->Mesh.IsTriangleAlive(t))
    {
      continue;
    }
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index v = tri[k];
      if (oldToNew[v] == InvalidIndex)
      {
        oldToNew[v] = out.AddPoint(this->Mesh.Point(v));
        result.OutputToInput.push_back(v);
      }
      out.Triangles.push_back(oldToNew[v]);
    }
    result.OutputTriangleIds.push_back(t);
  }
  result.VertexError.resize(result.OutputToInput.size());
  for (size_t i = 0; i < result.OutputToInput.size(); ++i)
  {
    const Index v = result.OutputToInput[i];
    const Vec3 p = this->Local(v);
    double q = 0, w = 0;
    if (this->Options.ExactUnion)
    {
      for (Index id : this->LogicalSet[v])
      {
        q += this->PlaneQuadric[id].Evaluate(p);
        w += this->PlaneWeight[id];
      }
    }
    else
    {
      q = this->VertexQuadric[v].Evaluate(p);
      w = this->VertexWeight[v];
    }
    result.VertexError[i] = w > 0 ? std::sqrt(q / w) : 0.0;
  }
}
} // namespace

void SimplifyByTriangleCollapse(TriangleMesh& mesh, const TriangleCollapseOptions& options,
  TriangleCollapseResult& result, PointAttributes* attributes)
{
  TriangleCollapser collapser(options, attributes);
  collapser.Run(mesh, result);
}
} // namespace slod
