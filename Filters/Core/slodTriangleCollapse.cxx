#include "slodTriangleCollapse.h"

#include "slodBucketQueue.h"
#include "slodPointAttributes.h"
#include "slodQuadric.h"
#include "slodTriangleBVH.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <cstdint>
#include <limits>

namespace slod
{
void CollapseHistory::Clear()
{
  *this = CollapseHistory();
}

void CollapseHistory::Append(
  const CollapseRecord& record, const EditableMesh& mesh, const Index* vertexId, const Index* triangleId)
{
  if (this->RemovedOffsets.empty())
  {
    this->RemovedOffsets.push_back(0);
    this->ChangedOffsets.push_back(0);
    this->SurroundingOffsets.push_back(0);
  }
  // Kept vertex first; an edge collapse has no third vertex (-1, zero position).
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
    const bool has = order[i] < record.VertexCount;
    this->Vertices.push_back(has ? vertexId[record.Vertices[order[i]]] : InvalidIndex);
    const Vec3 p = has ? record.OldPositions[order[i]] : Vec3{ 0, 0, 0 };
    this->OldPositions.insert(this->OldPositions.end(), p.begin(), p.end());
  }
  this->NewPositions.insert(this->NewPositions.end(), record.NewPosition.begin(), record.NewPosition.end());
  for (Index t : record.RemovedTriangles)
  {
    const Index* tri = mesh.Triangle(t);
    this->RemovedTriangles.insert(
      this->RemovedTriangles.end(), { triangleId[t], vertexId[tri[0]], vertexId[tri[1]], vertexId[tri[2]] });
  }
  this->RemovedOffsets.push_back(static_cast<Index>(this->RemovedTriangles.size() / 4));
  for (size_t i = 0; i < record.ChangedTriangles.size(); ++i)
  {
    this->Changed.insert(this->Changed.end(),
      { triangleId[record.ChangedTriangles[i]], Index(record.ChangedCorner[i]), vertexId[record.ChangedFrom[i]] });
  }
  this->ChangedOffsets.push_back(static_cast<Index>(this->Changed.size() / 3));
}

void CollapseHistory::Get(Index k, CollapseRecord& record) const
{
  record.Clear();
  record.VertexCount = this->Vertices[3 * size_t(k) + 2] == InvalidIndex ? 2 : 3;
  record.Kept = this->Vertices[3 * size_t(k)];
  for (int i = 0; i < record.VertexCount; ++i)
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
// Budget of the deviation refinement in point-triangle distance tests per input triangle.
constexpr double RefinementWorkPerInputTriangle = 160;

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
  // Quadric of the interrelated set of 2 (edge) or 3 (triangle) vertices.
  Quadric SetQuadric(const Index* v, int count, double& weight) const;
  // Best placement (local coordinates) and its cost for the set's quadric.
  double Place(const Index* v, int count, const Quadric& q, Vec3& local) const;
  // Cheapest operation of triangle t: 0 = collapse the triangle, k = 1..3 = collapse its edge
  // (corner k-1, corner k % 3) when edge collapses are enabled.
  double Cost(Index t, Vec3& local, double& error, int& operation) const;
  void Update(Index t);
  void MarkPending(const Index* tri)
  {
    for (int k = 0; k < 3; ++k)
    {
      this->PendingCount += this->Pending[tri[k]] ? 0 : 1;
      this->Pending[tri[k]] = 1;
    }
  }
  // Update of every triangle around the new vertex v0: only the operations that involve v0 are
  // re-evaluated (each edge (v0, x) once); the edge opposite v0 keeps its cached cost.
  void UpdateAround(Index kept);
  // Cost at pop time: the triangle operation is evaluated, the edges come from the cache and
  // only the winning edge is placed again.
  double PopCost(Index t, Vec3& local, double& error, int& operation) const;
  // The cheapest valid one of the fallback placements of the set (world coordinates in p).
  bool AlternativePlacement(
    const Index* set, int count, const CollapseOptions& check, Vec3& p, double& error, double& cost) const;
  void ExtractResult(TriangleCollapseResult& result);
  // The RefineDeviation pass (see the header); original = the input mesh in this mesh's ids.
  void RefineDeviation(const TriangleMesh& original, TriangleCollapseResult& result);

  const TriangleCollapseOptions& Options;
  PointAttributes* Attributes;
  void Reorder(TriangleMesh& mesh);

  EditableMesh Mesh;
  // The mesh is renumbered in spatial (Morton) order for cache locality; these map back.
  std::vector<Index> VertexInput, TriangleInput;
  Vec3 Origin{ 0, 0, 0 };
  double CostScale = 1.0; // makes float heap keys well scaled
  // Accumulated mode: per vertex the sum of its logical set's planes and of their weights,
  // side by side (one cache line pair per vertex instead of two separate misses).
  struct WeightedQuadric
  {
    Quadric Q;
    double W = 0.0;
  };
  std::vector<WeightedQuadric> Vertex;
  // Per triangle, in one 16-byte record (one cache miss instead of three): the cached keys of its
  // edge collapses, the operations that failed validity (bit k), and whether it waits for a change
  // of its neighbourhood (1: failed validity, retried when the 2-ring changes; 2: over MaximumError).
  struct TriangleState
  {
    float EdgeCost[3] = { 0, 0, 0 };
    unsigned char Excluded = 0;
    unsigned char Rejected = 0;
  };
  mutable std::vector<TriangleState> State;
  bool CacheEdges = false;
  std::vector<Index> SpokeVertex;       // UpdateAround scratch: edges (kept, x) already costed
  std::vector<Index> AroundScratch;     // UpdateAround scratch: the triangles around the new vertex
  std::vector<float> SpokeCost;
  std::vector<Index> Parent;           // RefineDeviation: per vertex, the vertex it merged into
  std::vector<unsigned char> Boundary; // per vertex: on a border (maintained, see CollapseOptions)
  Index PendingCount = 0;              // vertices with Pending set
  std::vector<unsigned char> Pending;  // per vertex: a triangle of it was rejected for validity
  BucketQueue Heap;
  // Exact mode: original planes and, per vertex, the sorted ids of its logical set.
  std::vector<Quadric> PlaneQuadric;
  std::vector<double> PlaneWeight;
  std::vector<std::vector<Index>> LogicalSet;
  mutable std::vector<Index> UnionScratch;
};

namespace
{
std::uint64_t SpreadBits(std::uint64_t x)
{
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}
} // namespace

void TriangleCollapser::Reorder(TriangleMesh& mesh)
{
  // Vertices in Morton order of their position, triangles by their smallest new vertex id: the
  // neighbourhoods that every collapse reads then sit close together in memory.
  const Index nv = mesh.NumberOfPoints(), nt = mesh.NumberOfTriangles();
  const auto b = mesh.Bounds();
  const double extent = std::max({ b[1] - b[0], b[3] - b[2], b[5] - b[4], 1e-300 });
  const double scale = double((1 << 21) - 1) / extent;
  std::vector<std::pair<std::uint64_t, Index>> keys(static_cast<size_t>(nv));
  for (Index v = 0; v < nv; ++v)
  {
    const double* p = &mesh.Points[3 * size_t(v)];
    const auto q = [&](int k) { return static_cast<std::uint64_t>(std::max(0.0, (p[k] - b[2 * k]) * scale)); };
    keys[v] = { SpreadBits(q(0)) | SpreadBits(q(1)) << 1 | SpreadBits(q(2)) << 2, v };
  }
  std::sort(keys.begin(), keys.end());
  this->VertexInput.resize(static_cast<size_t>(nv));
  std::vector<Index> newId(static_cast<size_t>(nv));
  std::vector<double> points(mesh.Points.size());
  for (Index i = 0; i < nv; ++i)
  {
    const Index v = keys[i].second;
    this->VertexInput[i] = v;
    newId[v] = i;
    std::copy(&mesh.Points[3 * size_t(v)], &mesh.Points[3 * size_t(v)] + 3, &points[3 * size_t(i)]);
  }
  std::vector<std::pair<std::uint64_t, Index>>().swap(keys);
  mesh.Points.swap(points);
  std::vector<double>().swap(points);
  // Counting sort of the triangles by smallest vertex.
  std::vector<Index> start(static_cast<size_t>(nv) + 1, 0);
  for (Index t = 0; t < nt; ++t)
  {
    const Index* tri = mesh.Triangle(t);
    ++start[std::min({ newId[tri[0]], newId[tri[1]], newId[tri[2]] }) + 1];
  }
  for (Index v = 0; v < nv; ++v)
  {
    start[v + 1] += start[v];
  }
  this->TriangleInput.resize(static_cast<size_t>(nt));
  std::vector<Index> triangles(mesh.Triangles.size());
  for (Index t = 0; t < nt; ++t)
  {
    const Index* tri = mesh.Triangle(t);
    const Index a = newId[tri[0]], c = newId[tri[1]], d = newId[tri[2]];
    const Index slot = start[std::min({ a, c, d })]++;
    this->TriangleInput[slot] = t;
    triangles[3 * size_t(slot)] = a;
    triangles[3 * size_t(slot) + 1] = c;
    triangles[3 * size_t(slot) + 2] = d;
  }
  mesh.Triangles.swap(triangles);
}

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
    this->Vertex.assign(size_t(nv), WeightedQuadric());
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
      this->Vertex[vertices[i]].Q += q;
      this->Vertex[vertices[i]].W += w;
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

Quadric TriangleCollapser::SetQuadric(const Index* tri, int count, double& weight) const
{
  if (!this->Options.ExactUnion)
  {
    Quadric q = this->Vertex[tri[0]].Q;
    weight = this->Vertex[tri[0]].W;
    for (int i = 1; i < count; ++i)
    {
      q += this->Vertex[tri[i]].Q;
      weight += this->Vertex[tri[i]].W;
    }
    return q;
  }
  // Union of the sorted logical sets, each plane once.
  auto& u = this->UnionScratch;
  u.clear();
  for (int i = 0; i < count; ++i)
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

double TriangleCollapser::Place(const Index* tri, int count, const Quadric& q, Vec3& local) const
{
  const Vec3 a = this->Local(tri[0]), b = this->Local(tri[1]), c = count == 3 ? this->Local(tri[2]) : b;
  if (q.Minimize(local, 1e-10))
  {
    // A well-conditioned optimum far outside the neighbourhood still means a near-singular
    // system in practice (long thin features); keep it only within reach of the set.
    const Vec3 centroid = count == 3 ? (1.0 / 3.0) * (a + b + c) : 0.5 * (a + b);
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
  const int first = count == 3 ? 0 : 1, last = count == 3 ? 7 : 5; // edge: a, b, b, midpoint
  for (int i = first; i < last; ++i)
  {
    const Vec3& p = candidates[i];
    const double e = q.Evaluate(p);
    if (e < best)
    {
      best = e;
      local = p;
    }
  }
  return best;
}

double TriangleCollapser::Cost(Index t, Vec3& local, double& error, int& operation) const
{
  const Index* tri = this->Mesh.Triangle(t);
  const unsigned excluded = this->State[t].Excluded; // operations that failed the validity test
  operation = -1;
  double cost = std::numeric_limits<double>::infinity();
  error = 0.0;
  // An edge collapse removes half as many triangles: it wins only when its cost times the bias
  // is below the triangle collapse's.
  const double bias = this->Options.EdgeCollapseBias;
  const bool edges = this->Options.EdgeCollapses;
  double bestFactor = 1.0, bestWeight = 0.0;
  auto consider = [&](int op, const Index* set, int count, const Quadric& q, double weight, double factor, bool allowed) {
    Vec3 p;
    const double c = this->Place(set, count, q, p) * factor;
    if (allowed && c < cost)
    {
      cost = c;
      local = p;
      bestFactor = factor;
      bestWeight = weight;
      operation = op;
    }
    return c;
  };
  // The error (RMS distance to the set's planes) of the winner only.
  auto finish = [&]() {
    error = bestWeight > 0 && operation >= 0 ? std::sqrt(cost / bestFactor / bestWeight) : 0.0;
    return cost;
  };
  if (this->Options.ExactUnion)
  {
    double weight = 0;
    if (!(excluded & 1u))
    {
      const Quadric q = this->SetQuadric(tri, 3, weight);
      consider(0, tri, 3, q, weight, 1.0, true);
    }
    for (int k = 0; edges && k < 3; ++k)
    {
      if (!(excluded & (2u << k)))
      {
        const Index edge[2] = { tri[k], tri[(k + 1) % 3] };
        const Quadric qe = this->SetQuadric(edge, 2, weight);
        consider(k + 1, edge, 2, qe, weight, bias, true);
      }
    }
    return finish();
  }
  // Accumulated mode: the set quadrics are sums of the three vertex quadrics, shared below.
  const Quadric& qa = this->Vertex[tri[0]].Q;
  const Quadric& qb = this->Vertex[tri[1]].Q;
  const Quadric& qc = this->Vertex[tri[2]].Q;
  const double wa = this->Vertex[tri[0]].W, wb = this->Vertex[tri[1]].W, wc = this->Vertex[tri[2]].W;
  const Quadric qab = qa + qb;
  if (!(excluded & 1u))
  {
    consider(0, tri, 3, qab + qc, wa + wb + wc, 1.0, true);
  }
  if (edges)
  {
    // All three edge costs are computed and cached (UpdateAround reuses the edge that does not
    // touch the new vertex).
    const Index e0[2] = { tri[0], tri[1] }, e1[2] = { tri[1], tri[2] }, e2[2] = { tri[2], tri[0] };
    float* cache = this->State[t].EdgeCost;
    cache[0] = static_cast<float>(consider(1, e0, 2, qab, wa + wb, bias, !(excluded & 2u)) * this->CostScale);
    cache[1] = static_cast<float>(consider(2, e1, 2, qb + qc, wb + wc, bias, !(excluded & 4u)) * this->CostScale);
    cache[2] = static_cast<float>(consider(3, e2, 2, qc + qa, wc + wa, bias, !(excluded & 8u)) * this->CostScale);
  }
  return finish();
}

bool TriangleCollapser::AlternativePlacement(
  const Index* set, int count, const CollapseOptions& check, Vec3& p, double& error, double& cost) const
{
  double weight = 0;
  const Quadric q = this->SetQuadric(set, count, weight);
  const Vec3 a = this->Local(set[0]), b = this->Local(set[1]), c = count == 3 ? this->Local(set[2]) : b;
  std::pair<double, Vec3> candidates[7];
  int n = 0;
  const Vec3 all[7] = { a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a), (1.0 / 3.0) * (a + b + c) };
  const int used[2][7] = { { 0, 1, 3, -1, -1, -1, -1 }, { 0, 1, 2, 3, 4, 5, 6 } };
  for (int i : used[count == 3 ? 1 : 0])
  {
    if (i >= 0)
    {
      candidates[n++] = { q.Evaluate(all[i]), all[i] };
    }
  }
  std::sort(candidates, candidates + n, [](const auto& x, const auto& y) { return x.first < y.first; });
  for (int i = 0; i < n; ++i)
  {
    const Vec3 world = candidates[i].second + this->Origin;
    if (this->Mesh.CheckCollapse(set, count, world, check) == CollapseStatus::Ok)
    {
      p = world;
      cost = candidates[i].first;
      error = weight > 0 ? std::sqrt(cost / weight) : 0.0;
      return true;
    }
  }
  return false;
}

double TriangleCollapser::PopCost(Index t, Vec3& local, double& error, int& operation) const
{
  if (!this->CacheEdges)
  {
    return this->Cost(t, local, error, operation);
  }
  const Index* tri = this->Mesh.Triangle(t);
  const unsigned excluded = this->State[t].Excluded;
  const float* cache = this->State[t].EdgeCost;
  operation = -1;
  double best = std::numeric_limits<double>::infinity();
  if (!(excluded & 1u))
  {
    Quadric q = this->Vertex[tri[0]].Q;
    q += this->Vertex[tri[1]].Q;
    q += this->Vertex[tri[2]].Q;
    best = this->Place(tri, 3, q, local);
    operation = 0;
    const double w = this->Vertex[tri[0]].W + this->Vertex[tri[1]].W + this->Vertex[tri[2]].W;
    error = w > 0 ? std::sqrt(best / w) : 0.0;
  }
  int edge = -1;
  for (int k = 0; k < 3; ++k)
  {
    if (!(excluded & (2u << k)) && double(cache[k]) / this->CostScale < best)
    {
      best = double(cache[k]) / this->CostScale;
      edge = k;
    }
  }
  if (edge >= 0)
  {
    const Index e[2] = { tri[edge], tri[(edge + 1) % 3] };
    const double bias = this->Options.EdgeCollapseBias;
    best = this->Place(e, 2, this->Vertex[e[0]].Q + this->Vertex[e[1]].Q, local) * bias;
    const double w = this->Vertex[e[0]].W + this->Vertex[e[1]].W;
    error = w > 0 && bias > 0 ? std::sqrt(best / bias / w) : 0.0;
    operation = edge + 1;
  }
  return best;
}

void TriangleCollapser::UpdateAround(Index kept)
{
  if (!this->CacheEdges)
  {
    this->Mesh.ForEachTriangle(kept, [&](Index s) { this->Update(s); });
    return;
  }
  this->SpokeVertex.clear();
  this->SpokeCost.clear();
  const Quadric& qk = this->Vertex[kept].Q;
  const double bias = this->Options.EdgeCollapseBias;
  // Gather the triangles, then prefetch what their updates read (corners, vertex quadrics, cached
  // edge costs, queue slots): the loop is bound by memory latency, and independent prefetches
  // overlap where the loop's dependent loads would follow one another.
  auto& around = this->AroundScratch;
  around.clear();
  this->Mesh.ForEachTriangle(kept, [&](Index t) { around.push_back(t); });
  for (Index t : around)
  {
    __builtin_prefetch(this->Mesh.Triangle(t));
    __builtin_prefetch(this->State[t].EdgeCost);
    this->Heap.Prefetch(t);
  }
  for (Index t : around)
  {
    const Index* tri = this->Mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const char* q = reinterpret_cast<const char*>(&this->Vertex[tri[k]]);
      __builtin_prefetch(q);
      __builtin_prefetch(q + 64);
    }
  }
  for (Index t : around)
  {
    this->State[t].Excluded = 0;
    this->State[t].Rejected = 0;
    const Index* tri = this->Mesh.Triangle(t);
    Quadric q = this->Vertex[tri[0]].Q;
    q += this->Vertex[tri[1]].Q;
    q += this->Vertex[tri[2]].Q;
    Vec3 p;
    double best = this->Place(tri, 3, q, p);
    float* cache = this->State[t].EdgeCost;
    for (int k = 0; k < 3; ++k)
    {
      const Index u = tri[k], v = tri[(k + 1) % 3];
      if (u == kept || v == kept)
      {
        const Index x = u == kept ? v : u;
        const auto found = std::find(this->SpokeVertex.begin(), this->SpokeVertex.end(), x);
        if (found != this->SpokeVertex.end())
        {
          cache[k] = this->SpokeCost[found - this->SpokeVertex.begin()];
        }
        else
        {
          const Index edge[2] = { u, v };
          cache[k] = static_cast<float>(this->Place(edge, 2, qk + this->Vertex[x].Q, p) * bias * this->CostScale);
          this->SpokeVertex.push_back(x);
          this->SpokeCost.push_back(cache[k]);
        }
      }
      best = std::min(best, double(cache[k]) / this->CostScale);
    }
    this->Heap.Set(t, static_cast<float>(best * this->CostScale));
  }
}

void TriangleCollapser::Update(Index t)
{
  Vec3 p;
  double error;
  int operation;
  this->State[t].Excluded = 0; // its neighbourhood changed: every operation may be valid again
  const double cost = this->Cost(t, p, error, operation);
  this->Heap.Set(t, static_cast<float>(cost * this->CostScale));
  this->State[t].Rejected = 0;
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
      long rssKB = 0, peakKB = 0; // current and peak resident memory (Linux), per stage
      if (FILE* status = std::fopen("/proc/self/status", "r"))
      {
        char line[256];
        while (std::fgets(line, sizeof(line), status))
        {
          std::sscanf(line, "VmHWM: %ld", &peakKB);
          std::sscanf(line, "VmRSS: %ld", &rssKB);
        }
        std::fclose(status);
      }
      std::fprintf(stderr, "[triangle collapse] %s: %.3f s CPU, RSS %.1f MB, peak %.1f MB\n", what,
        double(now - clock) / CLOCKS_PER_SEC, rssKB / 1024.0, peakKB / 1024.0);
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
  lap("start");
  this->Reorder(input);
  lap("reorder");
  this->Mesh.Reset(input);
  const bool refine = this->Options.RefineDeviation && !this->Options.ExactUnion;
  if (refine)
  {
    // The refinement measures against the original surface: keep it, and who merged into whom.
    this->Parent.resize(size_t(this->Mesh.NumberOfPoints()));
    for (Index v = 0; v < this->Mesh.NumberOfPoints(); ++v)
    {
      this->Parent[v] = v;
    }
  }
  else
  {
    // The editable mesh holds its own copy: release the input's arrays (peak memory).
    std::vector<double>().swap(input.Points);
    std::vector<Index>().swap(input.Triangles);
  }

  lap("editable mesh");
  this->InitializeQuadrics();
  lap("quadrics");
  this->State.assign(size_t(nt), TriangleState());
  this->CacheEdges = this->Options.EdgeCollapses && !this->Options.ExactUnion;
  this->Pending.assign(size_t(this->Mesh.NumberOfPoints()), 0);
  {
    // Every triangle's cost depends only on its own vertices and writes only its own cache
    // entries: computed in parallel (vtkSMPTools), the same result for any thread count. The
    // exact-union mode shares a scratch buffer: sequential.
    std::vector<float> keys(static_cast<size_t>(nt));
    auto costs = [&](vtkIdType begin, vtkIdType end) {
      for (Index t = static_cast<Index>(begin); t < static_cast<Index>(end); ++t)
      {
        Vec3 p;
        double error;
        int operation;
        keys[t] = static_cast<float>(this->Cost(t, p, error, operation) * this->CostScale);
      }
    };
    if (this->Options.ExactUnion)
    {
      costs(0, nt);
    }
    else
    {
      vtkSMPTools::For(0, nt, 4096, costs);
    }
    this->Heap.Build(keys.data(), nt);
  }

  lap("initialisation");
  const Index target = std::max<Index>(this->Options.TargetTriangles, 0);
  const double maxError = this->Options.MaximumError;
  CollapseOptions check;
  check.AllowTopologyChange = this->Options.AllowTopologyChange;
  check.BoundaryVertices = this->Options.AllowTopologyChange ? nullptr : this->Boundary.data();
  check.MinimumNormalDot = std::cos(std::min(90.0, std::max(0.0, this->Options.MaximumNormalDeviation)) * 3.14159265358979323846 / 180.0);
  CollapseRecord record;
  std::vector<Index> neighbors;
  long long resets = 0, updates = 0, replaced = 0;
  long long statusCounts[static_cast<int>(CollapseStatus::IsolatedVertex) + 1] = {};
  const Index toRemove = std::max<Index>(1, this->Mesh.NumberOfLiveTriangles() - target);
  const Index progressStep = std::max<Index>(1, toRemove / 100);
  Index nextProgress = progressStep;
  const Index startTriangles = this->Mesh.NumberOfLiveTriangles();

  // When every remaining collapse fails the normal test, the limit is relaxed step by step (up
  // to 90 degrees, beyond which a triangle would turn over) so that the target is still reached;
  // the strict limit applies as long as it can.
  double deviation = std::min(90.0, std::max(0.0, this->Options.MaximumNormalDeviation));
  for (;;)
  {
    if (this->Heap.Empty())
    {
      if (this->Mesh.NumberOfLiveTriangles() <= target || deviation >= 90.0 || result.Aborted)
      {
        break;
      }
      deviation = std::min(90.0, deviation + 20.0);
      check.MinimumNormalDot = std::cos(deviation * 3.14159265358979323846 / 180.0);
      for (Index s = 0; s < nt; ++s)
      {
        if (this->State[s].Rejected == 1 && this->Mesh.IsTriangleAlive(s))
        {
          this->Update(s);
        }
      }
      continue;
    }
    if (this->Mesh.NumberOfLiveTriangles() <= target)
    {
      break;
    }
    const Index t = this->Heap.Pop();
    Vec3 local;
    double error;
    int operation;
    this->PopCost(t, local, error, operation);
    Index set[3];
    const Index* tri = this->Mesh.Triangle(t);
    if (operation < 0)
    {
      this->State[t].Rejected = 1;
      continue;
    }
    const int count = operation == 0 ? 3 : 2;
    if (operation == 0)
    {
      std::copy(tri, tri + 3, set);
    }
    else
    {
      set[0] = tri[operation - 1];
      set[1] = tri[operation % 3];
      set[2] = InvalidIndex;
    }
    if (maxError >= 0 && error > maxError)
    {
      this->State[t].Rejected = 2; // retried only when one of its vertices changes
      continue;
    }
    Vec3 p = local + this->Origin;
    CollapseStatus status = this->Mesh.CheckCollapse(set, count, p, check);
    ++statusCounts[static_cast<int>(status)];
    if (status == CollapseStatus::Flip || status == CollapseStatus::Degenerate || status == CollapseStatus::BadShape)
    {
      // The optimum folds a triangle: try the paper's other placements (vertices, midpoints,
      // centroid) of the same set, cheapest first.
      Vec3 alternative;
      double alternativeError = 0, alternativeCost = 0;
      if (this->AlternativePlacement(set, count, check, alternative, alternativeError, alternativeCost) &&
        !(maxError >= 0 && alternativeError > maxError))
      {
        // Keep the greedy order: do it now only if it is still the cheapest operation left.
        const float key = static_cast<float>(alternativeCost * (count == 2 ? this->Options.EdgeCollapseBias : 1.0) * this->CostScale);
        if (this->Heap.WouldBeFirst(key))
        {
          status = CollapseStatus::Ok;
          p = alternative;
          error = alternativeError;
          local = p - this->Origin;
          ++replaced;
        }
        else
        {
          this->Heap.Set(t, key);
          continue;
        }
      }
    }
    if (status != CollapseStatus::Ok)
    {
      ++result.RejectedCollapses;
      // Requeue the triangle with its next best operation; when none is left it waits for a
      // change of its neighbourhood.
      this->State[t].Excluded |= static_cast<unsigned char>(1u << operation);
      Vec3 next;
      double nextError;
      int nextOperation;
      const double nextCost = this->Cost(t, next, nextError, nextOperation);
      if (nextOperation >= 0)
      {
        this->Heap.Set(t, static_cast<float>(nextCost * this->CostScale));
      }
      else
      {
        this->State[t].Rejected = 1;
        this->MarkPending(tri);
      }
      continue;
    }
    const Index kept = *std::min_element(set, set + count);
    // Point data: barycentric weights of the new vertex projected onto the triangle (edge).
    if (this->Attributes)
    {
      double w[3] = { 1.0 / 3, 1.0 / 3, 1.0 / 3 };
      const Vec3 a = this->Local(set[0]), b = this->Local(set[1]);
      if (count == 3)
      {
        const Vec3 c = this->Local(set[2]);
        const Vec3 n = Cross(b - a, c - a);
        const double nn = Dot(n, n);
        if (nn > 0)
        {
          w[0] = std::max(0.0, Dot(Cross(c - b, local - b), n) / nn);
          w[1] = std::max(0.0, Dot(Cross(a - c, local - c), n) / nn);
          w[2] = std::max(0.0, Dot(Cross(b - a, local - a), n) / nn);
        }
      }
      else
      {
        const double ll = Dot(b - a, b - a);
        const double s01 = ll > 0 ? std::min(1.0, std::max(0.0, Dot(local - a, b - a) / ll)) : 0.5;
        w[0] = 1.0 - s01;
        w[1] = s01;
      }
      Index rows[3];
      for (int i = 0; i < count; ++i)
      {
        rows[i] = this->VertexInput[set[i]];
      }
      this->Attributes->Merge(this->VertexInput[kept], rows, w, count);
    }
    this->Mesh.Collapse(set, count, kept, p, &record);
    if (refine)
    {
      for (int i = 0; i < count; ++i)
      {
        this->Parent[set[i]] = kept;
      }
    }
    unsigned char boundary = 0;
    for (int i = 0; i < count; ++i)
    {
      boundary |= this->Boundary[set[i]];
    }
    this->Boundary[kept] = boundary;
    if (this->Options.ExactUnion)
    {
      auto& s = this->LogicalSet[kept];
      for (int i = 0; i < count; ++i)
      {
        const Index v = set[i];
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
      double weight = 0;
      this->Vertex[kept].Q = this->SetQuadric(set, count, weight);
      this->Vertex[kept].W = weight;
    }
    result.MaximumError = std::max(result.MaximumError, error);
    ++result.Collapses;
    for (Index r : record.RemovedTriangles)
    {
      this->Heap.Remove(r);
    }
    // Error propagation: the triangles around v0 get the quadric of their new logical sets.
    this->UpdateAround(kept);
    // Collapses rejected for validity may have become valid: retry those in the 2-ring.
    // (Skipped while no vertex is pending, the common case.)
    neighbors.clear();
    if (this->PendingCount > 0 || this->Options.RecordHistory)
    {
      this->Mesh.Neighbors(kept, neighbors);
    }
    for (Index w : neighbors)
    {
      if (this->Pending[w])
      {
        this->Pending[w] = 0;
        --this->PendingCount;
        this->Mesh.ForEachTriangle(w, [&](Index s) {
          if (this->State[s].Rejected == 1)
          {
            this->Update(s);
          }
        });
      }
    }
    if (this->Options.RecordHistory)
    {
      result.History.Append(record, this->Mesh, this->VertexInput.data(), this->TriangleInput.data());
      for (Index w : neighbors)
      {
        result.History.Surrounding.push_back(this->VertexInput[w]);
      }
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

  result.PeakWorkingBytes = this->Heap.MemoryBytes() + this->Vertex.capacity() * sizeof(WeightedQuadric) + this->State.capacity() * sizeof(TriangleState) + result.History.MemoryBytes();
  lap("collapses");
  // The queue and the per-triangle state are done: free them so that the output reuses their
  // memory instead of raising the peak.
  this->Heap = BucketQueue();
  std::vector<TriangleState>().swap(this->State);
  if (refine && !result.Aborted)
  {
    this->RefineDeviation(input, result);
    lap("deviation refinement");
  }
  std::vector<double>().swap(input.Points);
  std::vector<Index>().swap(input.Triangles);
  std::vector<Index>().swap(this->Parent);
  this->ExtractResult(result);
  lap("extraction");
  if (verbose)
  {
    std::fprintf(stderr, "[triangle collapse] %d collapses, %d rejected, %lld heap re-keys, %lld updates\n",
      int(result.Collapses), int(result.RejectedCollapses), resets, updates);
    for (int k = 1; k <= static_cast<int>(CollapseStatus::IsolatedVertex); ++k)
    {
      std::fprintf(stderr, "  rejected: %s %lld\n", ToString(static_cast<CollapseStatus>(k)), statusCounts[k]);
    }
    std::fprintf(stderr, "  placements replaced %lld\n", replaced);
  }
}

void TriangleCollapser::RefineDeviation(const TriangleMesh& original, TriangleCollapseResult& result)
{
  const Index nv = original.NumberOfPoints(), nt = original.NumberOfTriangles();
  if (nv == 0 || this->Mesh.NumberOfLiveTriangles() == 0)
  {
    return;
  }
  // Who descends from whom: each original vertex's surviving vertex (path-compressed), then the
  // ancestors of every surviving vertex and the original triangles of every original vertex (CSR).
  for (Index v = 0; v < nv; ++v)
  {
    Index r = v;
    while (this->Parent[r] != r)
    {
      r = this->Parent[r];
    }
    for (Index w = v; this->Parent[w] != r && w != r;)
    {
      const Index next = this->Parent[w];
      this->Parent[w] = r;
      w = next;
    }
  }
  std::vector<Index> ancestorStart(size_t(nv) + 1, 0), ancestors(static_cast<size_t>(nv));
  for (Index v = 0; v < nv; ++v)
  {
    ++ancestorStart[this->Parent[v] + 1];
  }
  for (Index v = 0; v < nv; ++v)
  {
    ancestorStart[v + 1] += ancestorStart[v];
  }
  {
    std::vector<Index> fill(ancestorStart.begin(), ancestorStart.end() - 1);
    for (Index v = 0; v < nv; ++v)
    {
      ancestors[fill[this->Parent[v]]++] = v;
    }
  }
  std::vector<Index> originalStart(size_t(nv) + 1, 0), originalTriangles(3 * size_t(nt));
  for (Index i = 0; i < 3 * nt; ++i)
  {
    ++originalStart[original.Triangles[i] + 1];
  }
  for (Index v = 0; v < nv; ++v)
  {
    originalStart[v + 1] += originalStart[v];
  }
  {
    std::vector<Index> fill(originalStart.begin(), originalStart.end() - 1);
    for (Index i = 0; i < 3 * nt; ++i)
    {
      originalTriangles[fill[original.Triangles[i]]++] = i / 3;
    }
  }
  auto originalPoint = [&](Index v) {
    const double* p = &original.Points[3 * size_t(v)];
    return Vec3{ p[0], p[1], p[2] };
  };
  // Point-triangle tests done so far: the pass stops when they exceed a budget proportional to the
  // input, because a region's cost grows with the square of the reduction (ancestors x triangles).
  size_t work = 0;
  const size_t workBudget = static_cast<size_t>(RefinementWorkPerInputTriangle) * static_cast<size_t>(nt);
  auto distanceToOriginal = [&](const Vec3& q, const Index* tris, size_t n, Vec3& closest) {
    work += n;
    double best = std::numeric_limits<double>::max();
    for (size_t i = 0; i < n; ++i)
    {
      const Index* t = &original.Triangles[3 * size_t(tris[i])];
      const Vec3 c = ClosestPointOnTriangle(q, originalPoint(t[0]), originalPoint(t[1]), originalPoint(t[2]));
      const Vec3 d = q - c;
      const double d2 = Dot(d, d);
      if (d2 < best)
      {
        best = d2;
        closest = c;
      }
    }
    return best;
  };
  auto distanceToMesh = [&](const Vec3& q, const Index* tris, size_t n, Vec3& closest, Index& which) {
    work += n;
    double best = std::numeric_limits<double>::max();
    for (size_t i = 0; i < n; ++i)
    {
      const Index* t = this->Mesh.Triangle(tris[i]);
      const Vec3 c = ClosestPointOnTriangle(q, this->Mesh.Point(t[0]), this->Mesh.Point(t[1]), this->Mesh.Point(t[2]));
      const Vec3 d = q - c;
      const double d2 = Dot(d, d);
      if (d2 < best)
      {
        best = d2;
        closest = c;
        which = tris[i];
      }
    }
    return best;
  };

  const double minimumDot = std::cos(std::min(90.0, std::max(0.0, this->Options.MaximumNormalDeviation)) * 3.14159265358979323846 / 180.0);
  const Index live = this->Mesh.NumberOfLiveVertices();
  // Only a few of the worst regions: the pass must stay cheap next to the collapses.
  const size_t budget = static_cast<size_t>(16 + live / 2000);
  std::vector<Index> fan, ring, ring2, near, nearOriginal, movedVertices;
  std::vector<Vec3> startNormal;
  std::vector<std::pair<double, Index>> screen;
  Vec3 closest;
  Index which;
  Index moved = 0;
  // Candidates: the merged interior vertices with the largest quadric error (RMS distance to
  // their original planes), a small fraction of the output; only they are screened below.
  std::vector<std::pair<double, Index>> pool;
  for (Index v = 0; v < nv; ++v)
  {
    if (ancestorStart[v + 1] - ancestorStart[v] >= 2 && this->Mesh.IsVertexAlive(v) && !this->Boundary[v])
    {
      const double w = this->Vertex[v].W;
      pool.emplace_back(w > 0 ? this->Vertex[v].Q.Evaluate(this->Local(v)) / w : 0.0, v);
    }
  }
  auto worseFirst = [](const std::pair<double, Index>& a, const std::pair<double, Index>& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  };
  const size_t poolSize = std::min(pool.size(), static_cast<size_t>(64 + live / 50));
  std::partial_sort(pool.begin(), pool.begin() + poolSize, pool.end(), worseFirst);
  pool.resize(poolSize);
  for (int round = 0; round < 2; ++round)
  {
    // Screening (an upper bound of the local deviation): the ancestors of the vertex against its
    // own triangles, and its triangles' centroid, edge midpoints and vertex against the original
    // triangles of the ancestors of their vertices.
    screen.clear();
    double worst = 0;
    for (const auto& candidate : pool)
    {
      if (work > workBudget)
      {
        break;
      }
      const Index v = candidate.second;
      const Index a0 = ancestorStart[v], a1 = ancestorStart[v + 1];
      fan.clear();
      this->Mesh.ForEachTriangle(v, [&](Index t) { fan.push_back(t); });
      double e = 0;
      for (Index i = a0; i < a1; ++i)
      {
        e = std::max(e, distanceToMesh(originalPoint(ancestors[i]), fan.data(), fan.size(), closest, which));
      }
      for (Index t : fan)
      {
        const Index* tri = this->Mesh.Triangle(t);
        nearOriginal.clear();
        for (int k = 0; k < 3; ++k)
        {
          for (Index i = ancestorStart[tri[k]]; i < ancestorStart[tri[k] + 1]; ++i)
          {
            nearOriginal.insert(nearOriginal.end(), originalTriangles.begin() + originalStart[ancestors[i]],
              originalTriangles.begin() + originalStart[ancestors[i] + 1]);
          }
        }
        std::sort(nearOriginal.begin(), nearOriginal.end());
        nearOriginal.erase(std::unique(nearOriginal.begin(), nearOriginal.end()), nearOriginal.end());
        const Vec3 x = this->Mesh.Point(tri[0]), y = this->Mesh.Point(tri[1]), z = this->Mesh.Point(tri[2]);
        const Vec3 samples[5] = { this->Mesh.Point(v), (1.0 / 3) * (x + y + z), 0.5 * (x + y), 0.5 * (y + z), 0.5 * (z + x) };
        for (const Vec3& q : samples)
        {
          e = std::max(e, distanceToOriginal(q, nearOriginal.data(), nearOriginal.size(), closest));
        }
      }
      screen.emplace_back(e, v);
      worst = std::max(worst, e);
    }
    if (screen.empty() || worst <= 0)
    {
      break;
    }
    const size_t count = std::min(budget, screen.size());
    std::partial_sort(screen.begin(), screen.begin() + count, screen.end(), worseFirst);
    Index movedThisRound = 0;
    for (size_t c = 0; c < count && screen[c].first >= 0.5 * worst && work <= workBudget; ++c)
    {
      const Index v = screen[c].second;
      // The region whose distances the vertex changes: its ring's triangles, the ancestors of the
      // vertex and of its neighbours, and their original triangles.
      this->Mesh.Neighbors(v, ring);
      fan.clear();
      this->Mesh.ForEachTriangle(v, [&](Index t) { fan.push_back(t); });
      near.assign(fan.begin(), fan.end());
      ring2.assign(1, v);
      for (Index w : ring)
      {
        this->Mesh.ForEachTriangle(w, [&](Index t) { near.push_back(t); });
        ring2.push_back(w);
      }
      std::sort(near.begin(), near.end());
      near.erase(std::unique(near.begin(), near.end()), near.end());
      nearOriginal.clear();
      for (Index w : ring2)
      {
        for (Index i = ancestorStart[w]; i < ancestorStart[w + 1]; ++i)
        {
          nearOriginal.insert(nearOriginal.end(), originalTriangles.begin() + originalStart[ancestors[i]],
            originalTriangles.begin() + originalStart[ancestors[i] + 1]);
        }
      }
      std::sort(nearOriginal.begin(), nearOriginal.end());
      nearOriginal.erase(std::unique(nearOriginal.begin(), nearOriginal.end()), nearOriginal.end());
      startNormal.clear();
      for (Index t : fan)
      {
        startNormal.push_back(this->Mesh.TriangleNormal(t));
      }
      // Local maximum distance with v at p, and a direction that lowers the worst term (the
      // correction of v that would bring the worst point onto the other surface).
      auto evaluate = [&](const Vec3& p, Vec3& step, double& sum) {
        this->Mesh.SetPoint(v, p);
        double best = -1;
        sum = 0;
        for (Index w : ring2)
        {
          for (Index i = ancestorStart[w]; i < ancestorStart[w + 1]; ++i)
          {
            const Vec3 a = originalPoint(ancestors[i]);
            const double d2 = distanceToMesh(a, near.data(), near.size(), closest, which);
            sum += std::sqrt(d2);
            if (d2 > best)
            {
              best = d2;
              // Weight of v at the closest point (barycentric), when on one of v's triangles.
              double weight = 0.3;
              const Index* t = this->Mesh.Triangle(which);
              for (int k = 0; k < 3; ++k)
              {
                if (t[k] == v)
                {
                  const Vec3 x = this->Mesh.Point(t[(k + 1) % 3]), y = this->Mesh.Point(t[(k + 2) % 3]);
                  const Vec3 n = Cross(x - p, y - p);
                  const double nn = Dot(n, n);
                  weight = nn > 0 ? std::max(0.2, Dot(Cross(x - closest, y - closest), n) / nn) : 0.3;
                }
              }
              step = (1.0 / weight) * (a - closest);
            }
          }
        }
        // Interior points of the original surface too (centroids of its triangles).
        for (Index o : nearOriginal)
        {
          const Index* ot = &original.Triangles[3 * size_t(o)];
          const Vec3 a = (1.0 / 3) * (originalPoint(ot[0]) + originalPoint(ot[1]) + originalPoint(ot[2]));
          const double d2 = distanceToMesh(a, near.data(), near.size(), closest, which);
          sum += std::sqrt(d2);
            if (d2 > best)
          {
            best = d2;
            step = (1.0 / 3) * (a - closest); // a rough weight: the full step is tried too
          }
        }
        for (Index t : fan)
        {
          const Index* tri = this->Mesh.Triangle(t);
          Vec3 others[2];
          int k = 0;
          for (int j = 0; j < 3; ++j)
          {
            if (tri[j] != v)
            {
              others[k++ & 1] = this->Mesh.Point(tri[j]);
            }
          }
          const double third = 1.0 / 3;
          const Vec3 samples[6] = { p, (2 * third) * p + third * others[0], (2 * third) * p + third * others[1],
            third * p + (2 * third) * others[0], third * p + (2 * third) * others[1],
            third * (p + others[0] + others[1]) };
          const double weights[6] = { 1.0, 2 * third, 2 * third, third, third, third };
          for (int s = 0; s < 6; ++s)
          {
            const double d2 = distanceToOriginal(samples[s], nearOriginal.data(), nearOriginal.size(), closest);
            sum += std::sqrt(d2);
            if (d2 > best)
            {
              best = d2;
              step = (1.0 / weights[s]) * (closest - samples[s]);
            }
          }
        }
        return best;
      };
      auto valid = [&](const Vec3& p) {
        this->Mesh.SetPoint(v, p);
        for (size_t i = 0; i < fan.size(); ++i)
        {
          const Index* tri = this->Mesh.Triangle(fan[i]);
          const Vec3 n = Cross(this->Mesh.Point(tri[1]) - this->Mesh.Point(tri[0]), this->Mesh.Point(tri[2]) - this->Mesh.Point(tri[0]));
          const double length = Norm(n);
          if (!(length > 0) || Dot(n, startNormal[i]) < minimumDot * length)
          {
            return false;
          }
        }
        return true;
      };
      const Vec3 start = this->Mesh.Point(v);
      Vec3 current = start, step;
      double startSum = 0, sum = 0;
      double value = evaluate(current, step, startSum);
      for (int iteration = 0; iteration < 6 && work <= workBudget; ++iteration)
      {
        const Vec3 direction = step;
        Vec3 bestPoint = current, ignored;
        double bestValue = value;
        for (double s : { 1.0, 0.75, 0.5, 0.25, 0.125 })
        {
          const Vec3 p = current + s * direction;
          if (!valid(p))
          {
            continue;
          }
          const double candidate = evaluate(p, ignored, sum);
          // The mean distance must not pay for the maximum: the local sum may not grow.
          if (candidate < bestValue && sum <= startSum)
          {
            bestValue = candidate;
            bestPoint = p;
          }
        }
        if (!(bestValue < value * (1.0 - 1e-3)))
        {
          break;
        }
        current = bestPoint;
        value = evaluate(current, step, sum);
      }
      this->Mesh.SetPoint(v, current);
      if (!(current == start))
      {
        ++movedThisRound;
        movedVertices.push_back(v);
      }
    }
    moved += movedThisRound;
    if (movedThisRound == 0)
    {
      break;
    }
    // The next round screens only where this one moved something (the rest is unchanged).
    std::vector<Index> next;
    for (Index v : movedVertices)
    {
      next.push_back(v);
      this->Mesh.Neighbors(v, ring);
      next.insert(next.end(), ring.begin(), ring.end());
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    pool.clear();
    for (Index v : next)
    {
      if (ancestorStart[v + 1] - ancestorStart[v] >= 2 && !this->Boundary[v])
      {
        pool.emplace_back(0.0, v);
      }
    }
    movedVertices.clear();
  }
  if (std::getenv("SLOD_VERBOSE"))
  {
    std::fprintf(stderr, "[triangle collapse] deviation refinement: %d vertex moves, %zu point-triangle tests (%.1f per input triangle)\n",
      int(moved), work, double(work) / std::max<Index>(nt, 1));
  }
  // Progressive records: the last collapse that produced a moved vertex now places it there
  // (records store input ids; re-collapsing to this level must give this mesh).
  if (this->Options.RecordHistory && moved > 0)
  {
    auto& h = result.History;
    std::vector<Index> inputToMesh(size_t(nv), InvalidIndex);
    for (Index v = 0; v < nv; ++v)
    {
      inputToMesh[this->VertexInput[v]] = v;
    }
    std::vector<unsigned char> seen(size_t(nv), 0);
    for (Index k = h.NumberOfCollapses() - 1; k >= 0; --k)
    {
      const Index v = inputToMesh[h.Vertices[3 * size_t(k)]];
      if (seen[v])
      {
        continue;
      }
      seen[v] = 1;
      if (this->Mesh.IsVertexAlive(v))
      {
        const Vec3 p = this->Mesh.Point(v);
        std::copy(p.begin(), p.end(), &h.NewPositions[3 * size_t(k)]);
      }
    }
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
        result.OutputToInput.push_back(this->VertexInput[v]);
      }
      out.Triangles.push_back(oldToNew[v]);
    }
    result.OutputTriangleIds.push_back(this->TriangleInput[t]);
  }
  result.VertexError.resize(result.OutputToInput.size());
  std::vector<Index> newToOld(result.OutputToInput.size());
  for (Index v = 0; v < nv; ++v)
  {
    if (oldToNew[v] != InvalidIndex)
    {
      newToOld[oldToNew[v]] = v;
    }
  }
  for (size_t i = 0; i < result.OutputToInput.size(); ++i)
  {
    const Index v = newToOld[i];
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
      q = this->Vertex[v].Q.Evaluate(p);
      w = this->Vertex[v].W;
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
