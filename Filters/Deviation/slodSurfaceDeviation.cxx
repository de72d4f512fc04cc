// SPDX-License-Identifier: BSD-3-Clause
#include "slodSurfaceDeviation.h"

#include "slodCounterHash.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slod
{
namespace
{
// Neumaier-compensated sum: the plane / offset tests expect ~1e-15 relative accuracy.
struct CompensatedSum
{
  double Sum = 0, Compensation = 0;
  void Add(double x)
  {
    const double t = this->Sum + x;
    this->Compensation += std::abs(this->Sum) >= std::abs(x) ? (this->Sum - t) + x : (x - t) + this->Sum;
    this->Sum = t;
  }
  double Value() const { return this->Sum + this->Compensation; }
};

constexpr std::int64_t ChunkSize = 256; // queries sharing one bound chain; fixed => thread-count independent
constexpr int ProgressSteps = 20;
} // namespace

void SampleSurface(const TriangleMesh& mesh, std::int64_t count, std::uint64_t seed, std::uint64_t stream,
  std::vector<double>& points)
{
  const Index nt = mesh.NumberOfTriangles();
  if (count <= 0 || nt == 0)
  {
    return;
  }
  std::vector<double> cumulative(size_t(nt) + 1, 0.0);
  for (Index t = 0; t < nt; ++t)
  {
    cumulative[size_t(t) + 1] = cumulative[size_t(t)] + mesh.TriangleArea(t);
  }
  const double total = cumulative.back();
  if (!(total > 0) || !std::isfinite(total))
  {
    return;
  }
  const std::uint64_t key = Finalise(seed * Golden + Finalise(stream + 0x632BE59BD9B4E019ull));
  const size_t offset = points.size();
  points.resize(offset + 3 * size_t(count));
  double* out = points.data() + offset;
  vtkSMPTools::For(0, count, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      const std::uint64_t c = 3 * std::uint64_t(i);
      // Triangle by area: first cumulative value above r (zero-area triangles have no interval).
      const double r = Uniform(key, c) * total;
      auto it = std::upper_bound(cumulative.begin() + 1, cumulative.end(), r);
      const Index t = std::min<Index>(nt - 1, static_cast<Index>(it - cumulative.begin()) - 1);
      // Uniform point in the triangle: sqrt warps the first coordinate to cancel the area growth.
      const double s = std::sqrt(Uniform(key, c + 1));
      const double u = Uniform(key, c + 2);
      const double wa = 1 - s, wb = s * (1 - u), wc = s * u;
      const Index* tri = mesh.Triangle(t);
      const double* a = &mesh.Points[3 * size_t(tri[0])];
      const double* b = &mesh.Points[3 * size_t(tri[1])];
      const double* d = &mesh.Points[3 * size_t(tri[2])];
      for (int k = 0; k < 3; ++k)
      {
        out[3 * i + k] = wa * a[k] + wb * b[k] + wc * d[k];
      }
    }
  });
}

bool ComputeDistances(const TriangleBVH& tree, const std::vector<double>& points, std::vector<double>& distances,
  const ProgressFunction& progress)
{
  const std::int64_t n = static_cast<std::int64_t>(points.size() / 3);
  distances.assign(size_t(n), std::numeric_limits<double>::quiet_NaN());
  if (n == 0 || tree.Empty())
  {
    return true;
  }

  // Queries in the core's Morton order (neighbouring queries share tree paths and bounds); points
  // with a non-finite coordinate are not measured (their distance stays NaN).
  const std::vector<MortonEntry> order = MortonOrder(points);
  std::vector<Index> keys;
  keys.reserve(order.size());
  double magnitude = 0;
  for (const MortonEntry& e : order)
  {
    const double* p = &points[3 * size_t(e.Id)];
    if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
    {
      keys.push_back(e.Id);
      magnitude = std::max({ magnitude, std::abs(p[0]), std::abs(p[1]), std::abs(p[2]) });
    }
  }
  if (keys.empty())
  {
    return true;
  }

  // Rounding slack for the bound taken from the previous answer (a point on the surface whose
  // recomputed distance may differ in the last bits).
  const double slack = (1e-13 * (magnitude + 1.0)) * (1e-13 * (magnitude + 1.0));
  const std::int64_t m = static_cast<std::int64_t>(keys.size());
  const std::int64_t chunks = (m + ChunkSize - 1) / ChunkSize;
  auto runChunks = [&](vtkIdType firstChunk, vtkIdType lastChunk) {
    for (vtkIdType c = firstChunk; c < lastChunk; ++c)
    {
      bool haveHint = false;
      Vec3 hint{ 0, 0, 0 };
      for (std::int64_t j = std::int64_t(c) * ChunkSize, e = std::min<std::int64_t>(m, (std::int64_t(c) + 1) * ChunkSize); j < e; ++j)
      {
        const size_t i = size_t(keys[size_t(j)]);
        const Vec3 q{ points[3 * i], points[3 * i + 1], points[3 * i + 2] };
        ClosestPointResult r;
        if (haveHint)
        {
          const Vec3 d = q - hint;
          r = tree.ClosestPoint(q, Dot(d, d) * (1 + 1e-9) + slack);
        }
        if (r.Triangle == InvalidIndex)
        {
          r = tree.ClosestPoint(q);
        }
        distances[i] = std::sqrt(r.Distance2);
        hint = r.Point;
        haveHint = true;
      }
    }
  };
  // A few sequential steps, each parallel, so progress is reported and abort checked on this thread.
  const std::int64_t steps = std::min<std::int64_t>(chunks, ProgressSteps);
  for (std::int64_t s = 0; s < steps; ++s)
  {
    const std::int64_t first = chunks * s / steps, last = chunks * (s + 1) / steps;
    vtkSMPTools::For(first, last, 1, runChunks);
    if (progress && !progress(double(s + 1) / double(steps)))
    {
      return false;
    }
  }
  return true;
}

bool MeasureDeviation(const TriangleMesh& from, const TriangleBVH& to, const DeviationOptions& options,
  OneSidedDeviation& result, std::vector<double>* vertexDistances, const ProgressFunction& progress)
{
  result = OneSidedDeviation{};
  if (to.Empty())
  {
    if (vertexDistances)
    {
      vertexDistances->assign(size_t(from.NumberOfPoints()), 0.0);
    }
    return true; // nothing to measure against: all zeros (the caller warns)
  }
  const Index nv = from.NumberOfPoints();
  std::vector<char> used(size_t(nv), 0);
  for (Index v : from.Triangles)
  {
    used[size_t(v)] = 1;
  }
  std::vector<double> samples(from.Points);
  SampleSurface(from, options.NumberOfSamples, options.Seed, options.Stream, samples);
  const std::int64_t randomCount = static_cast<std::int64_t>(samples.size() / 3) - nv;

  std::vector<double> distances;
  if (!ComputeDistances(to, samples, distances, progress))
  {
    return false;
  }

  // Without random samples the vertices carry every statistic.
  const bool countVertices = options.SampleVertices || randomCount == 0;
  CompensatedSum vertexSum, vertexSum2, randomSum, randomSum2;
  for (Index v = 0; v < nv; ++v)
  {
    if (!used[size_t(v)] || !countVertices)
    {
      continue;
    }
    const double d = distances[size_t(v)];
    result.MaxVertex = std::max(result.MaxVertex, d);
    vertexSum.Add(d);
    vertexSum2.Add(d * d);
    ++result.VertexSamples;
  }
  double maxRandom = 0;
  for (std::int64_t i = 0; i < randomCount; ++i)
  {
    const double d = distances[size_t(nv + i)];
    maxRandom = std::max(maxRandom, d);
    randomSum.Add(d);
    randomSum2.Add(d * d);
  }
  result.RandomSamples = randomCount;
  result.Max = std::max(result.MaxVertex, maxRandom);
  if (randomCount > 0)
  {
    result.Mean = randomSum.Value() / double(randomCount);
    result.RMS = std::sqrt(std::max(0.0, randomSum2.Value()) / double(randomCount));
  }
  else if (result.VertexSamples > 0)
  {
    result.Mean = vertexSum.Value() / double(result.VertexSamples);
    result.RMS = std::sqrt(std::max(0.0, vertexSum2.Value()) / double(result.VertexSamples));
  }
  if (vertexDistances)
  {
    vertexDistances->assign(distances.begin(), distances.begin() + nv);
  }
  return true;
}
} // namespace slod
