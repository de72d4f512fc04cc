// SPDX-License-Identifier: BSD-3-Clause
#include "slodInputPreparation.h"

#include "slodAttributeTransfer.h"
#include "slodGroupByKey.h"
#include "slodHugePages.h"
#include "slodMeshTopology.h"
#include "slodPointGrid.h"
#include "slodPolygonTriangulation.h"
#include "slodStageClock.h"
#include "slodUnionFind.h"
#include "slodZeroLengthEdges.h"

#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkObject.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <sstream>

namespace slod
{
std::vector<std::string> PreparationReport::Warnings() const
{
  std::vector<std::string> out;
  auto say = [&](long long count, const char* what) {
    if (count > 0)
    {
      std::ostringstream s;
      s << count << ' ' << what;
      out.push_back(s.str());
    }
  };
  say(this->IgnoredVertexCells, "vertex cell(s) ignored: only surfaces are simplified");
  say(this->IgnoredLineCells, "line cell(s) ignored: only surfaces are simplified");
  say(this->TriangulatedPolygons, "polygon(s) with more than three points triangulated");
  say(this->TriangulatedStrips, "triangle strip(s) converted to triangles");
  say(this->MergedPoints, "coincident point(s) merged where they seal an open border");
  say(this->CoincidentPointsKeptApart,
    "coincident point(s) kept apart: merging them would create a non-manifold vertex or edge, or join components");
  say(this->AttributeSeamPoints, "coincident point(s) with other point data kept apart (attribute seams are never welded)");
  say(this->RemovedDegenerateTriangles, "degenerate triangle(s) (repeated vertex) removed");
  say(this->CollapsedZeroLengthEdges,
    "edge(s) of length zero collapsed: their coincident ends merged (the surface's shape and topology are unchanged)");
  say(this->RemovedDuplicateTriangles, "repeated triangle(s) (same vertices and winding) removed");
  say(this->FlippedTriangles, "triangle(s) flipped to make the orientation consistent");
  say(this->NonOrientableComponents, "non-orientable component(s): orientation left as given");
  say(this->NonManifoldEdges, "non-manifold edge(s) (more than two triangles)");
  say(this->NonManifoldVertices, "non-manifold vertex/vertices (several fans)");
  return out;
}

namespace
{
// cells (when given) gets the input cell id of each triangle: vtkPolyData numbers its cells vertices
// first, then lines, polygons and strips.
void CollectTriangles(vtkPolyData* input, const std::vector<double>& points, PreparationReport& report,
  std::vector<Index>& triangles, std::vector<Index>* cells)
{
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  vtkIdType cell = report.IgnoredVertexCells + report.IgnoredLineCells;
  auto recordCell = [&]() {
    if (cells)
    {
      cells->resize(triangles.size() / 3, static_cast<Index>(cell));
    }
  };
  if (vtkCellArray* polys = input->GetPolys())
  {
    auto it = vtk::TakeSmartPointer(polys->NewIterator());
    std::vector<Vec3> polygon;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), recordCell(), ++cell)
    {
      it->GetCurrentCell(n, ids);
      if (n == 3)
      {
        triangles.insert(triangles.end(), { Index(ids[0]), Index(ids[1]), Index(ids[2]) });
      }
      else if (n < 3)
      {
        ++report.RemovedDegenerateTriangles;
      }
      else
      {
        ++report.TriangulatedPolygons;
        polygon.resize(size_t(n));
        for (vtkIdType i = 0; i < n; ++i)
        {
          const double* p = &points[3 * size_t(ids[i])];
          polygon[size_t(i)] = { p[0], p[1], p[2] };
        }
        for (const auto& tri : TriangulatePolygon(polygon, PolygonNormal(polygon)).Triangles)
        {
          triangles.insert(triangles.end(), { Index(ids[tri[0]]), Index(ids[tri[1]]), Index(ids[tri[2]]) });
        }
      }
    }
  }
  if (vtkCellArray* strips = input->GetStrips())
  {
    auto it = vtk::TakeSmartPointer(strips->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), recordCell(), ++cell)
    {
      it->GetCurrentCell(n, ids);
      ++report.TriangulatedStrips;
      for (vtkIdType i = 0; i + 2 < n; ++i)
      {
        // Every other triangle of a strip is wound the other way.
        if (i % 2 == 0)
        {
          triangles.insert(triangles.end(), { Index(ids[i]), Index(ids[i + 1]), Index(ids[i + 2]) });
        }
        else
        {
          triangles.insert(triangles.end(), { Index(ids[i + 1]), Index(ids[i]), Index(ids[i + 2]) });
        }
      }
    }
  }
}

// Lean adjacency for the preparation only: vertex -> triangles as one CSR array (int32), 16 bytes
// per vertex for a closed mesh. Edge neighbours are found by scanning the (short) triangle list
// of an edge's first vertex, which is cheaper than building an edge table.
class VertexStar
{
public:
  VertexStar(const TriangleMesh& mesh)
    : Mesh(mesh)
  {
    // Each vertex's triangles in id order (GroupByKey's serial form: its parallel one cost more).
    const Index nv = mesh.NumberOfPoints();
    this->Offsets.resize(size_t(nv) + 1);
    std::vector<Index> count(size_t(nv), 0);
    this->Offsets[nv] = GroupByKey(
      static_cast<Index>(mesh.Triangles.size()), nv, [&mesh](Index i) { return mesh.Triangles[size_t(i)]; },
      [](Index i) { return i / 3; }, this->Offsets.data(), count.data(), this->Refs, false);
  }
  const Index* Begin(Index v) const { return this->Refs.data() + this->Offsets[v]; }
  const Index* End(Index v) const { return this->Refs.data() + this->Offsets[v + 1]; }
  Index Degree(Index v) const { return this->Offsets[v + 1] - this->Offsets[v]; }
  // The other triangle on edge k of t when the edge has exactly two triangles (as
  // MeshTopology::EdgeNeighbor), else InvalidIndex.
  Index EdgeNeighbor(Index t, int k) const
  {
    const Index* tri = this->Mesh.Triangle(t);
    const Index a = tri[k], b = tri[(k + 1) % 3];
    Index other = InvalidIndex;
    int count = 0;
    for (const Index* s = this->Begin(a); s != this->End(a); ++s)
    {
      const Index* u = this->Mesh.Triangle(*s);
      if (u[0] == b || u[1] == b || u[2] == b)
      {
        ++count;
        other = *s == t ? other : *s;
      }
    }
    return count == 2 ? other : InvalidIndex;
  }

private:
  const TriangleMesh& Mesh;
  std::vector<Index> Offsets, Refs;
};

// Makes neighbouring triangles traverse shared manifold edges in opposite directions.
void OrientConsistently(TriangleMesh& mesh, const VertexStar& star, PreparationReport& report)
{
  const Index nt = mesh.NumberOfTriangles();
  std::vector<signed char> flip(nt, -1); // -1 unvisited, 0 keep, 1 flip
  std::vector<Index> queue;
  auto directionOf = [&](Index t, Index a, Index b) {
    // +1 when t runs a->b, -1 when b->a.
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] == a && tri[(k + 1) % 3] == b)
      {
        return 1;
      }
    }
    return -1;
  };
  for (Index seed = 0; seed < nt; ++seed)
  {
    if (flip[seed] != -1)
    {
      continue;
    }
    bool orientable = true;
    queue.assign(1, seed);
    flip[seed] = 0;
    for (size_t head = 0; head < queue.size(); ++head)
    {
      const Index t = queue[head];
      for (int k = 0; k < 3; ++k)
      {
        const Index u = star.EdgeNeighbor(t, k);
        if (u == InvalidIndex)
        {
          continue;
        }
        const Index a = mesh.Triangle(t)[k], b = mesh.Triangle(t)[(k + 1) % 3];
        // t's effective direction on a->b, and u's raw direction.
        const int dt = (flip[t] ? -1 : 1) * directionOf(t, a, b);
        const int du = directionOf(u, a, b);
        const signed char wanted = (du == dt) ? 1 : 0;
        if (flip[u] == -1)
        {
          flip[u] = wanted;
          queue.push_back(u);
        }
        else if (flip[u] != wanted)
        {
          orientable = false;
        }
      }
    }
    // The queue holds the whole component.
    if (!orientable)
    {
      ++report.NonOrientableComponents;
      for (Index t : queue)
      {
        flip[t] = 0;
      }
      continue;
    }
    const size_t flipped = std::count_if(queue.begin(), queue.end(), [&](Index t) { return flip[t] == 1; });
    if (2 * flipped > queue.size())
    {
      for (Index t : queue)
      {
        flip[t] = static_cast<signed char>(1 - flip[t]);
      }
    }
  }
  for (Index t = 0; t < nt; ++t)
  {
    if (flip[t] == 1)
    {
      std::swap(mesh.Triangles[3 * size_t(t) + 1], mesh.Triangles[3 * size_t(t) + 2]);
      ++report.FlippedTriangles;
    }
  }
}

enum : unsigned char
{
  BoundaryFlag = 1,
  NonManifoldFlag = 2
};

// Whether some edge (a, b) with two triangles is traversed the same way by both (inconsistent
// orientation): the half-edge a -> b appears twice in a's star.
bool SameHalfEdgeTwice(const TriangleMesh& mesh, const VertexStar& star, Index a, std::vector<Index>& outgoing)
{
  outgoing.clear();
  for (const Index* s = star.Begin(a); s != star.End(a); ++s)
  {
    const Index* tri = mesh.Triangle(*s);
    const int c = tri[0] == a ? 0 : (tri[1] == a ? 1 : 2);
    outgoing.push_back(tri[(c + 1) % 3]);
  }
  std::sort(outgoing.begin(), outgoing.end());
  for (size_t i = 1; i < outgoing.size(); ++i)
  {
    if (outgoing[i] == outgoing[i - 1])
    {
      const Index b = outgoing[i];
      int count = 0;
      for (const Index* s = star.Begin(a); s != star.End(a); ++s)
      {
        const Index* tri = mesh.Triangle(*s);
        count += (tri[0] == b || tri[1] == b || tri[2] == b) ? 1 : 0;
      }
      if (count == 2)
      {
        return true;
      }
    }
  }
  return false;
}

// The edges (a, b) with b > a, counted from a's star: flags both ends (border: one triangle;
// non-manifold: more than two) and returns the number of non-manifold ones. The flags of other
// vertices are set by an atomic OR (the vertices run concurrently; OR does not depend on order).
long long FlagEdgesOf(const TriangleMesh& mesh, const VertexStar& star, Index a, std::vector<Index>& others,
  std::vector<unsigned char>& flags)
{
  // Each triangle around a holding b > a contributes one to the edge (a, b).
  others.clear();
  for (const Index* s = star.Begin(a); s != star.End(a); ++s)
  {
    const Index* tri = mesh.Triangle(*s);
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] > a)
      {
        others.push_back(tri[k]);
      }
    }
  }
  std::sort(others.begin(), others.end());
  long long nonManifold = 0;
  for (size_t i = 0; i < others.size();)
  {
    size_t j = i;
    while (j < others.size() && others[j] == others[i])
    {
      ++j;
    }
    const size_t count = j - i;
    const unsigned char flag = count == 1 ? BoundaryFlag : (count > 2 ? NonManifoldFlag : 0);
    if (flag)
    {
      nonManifold += flag == NonManifoldFlag ? 1 : 0;
      __atomic_fetch_or(&flags[a], flag, __ATOMIC_RELAXED);
      __atomic_fetch_or(&flags[others[i]], flag, __ATOMIC_RELAXED);
    }
    i = j;
  }
  return nonManifold;
}

// Per vertex: on a border edge, on a non-manifold edge (more than two triangles, counted in the
// report as MeshTopology does). Returns true when some edge with two triangles is traversed the
// same way by both (inconsistent orientation): without one, orientation needs no repair. In
// parallel over the vertices (vtkSMPTools): the flags are ORs, the count a sum and the answer an
// OR, so the result does not depend on the thread count.
bool ClassifyEdges(const TriangleMesh& mesh, const VertexStar& star, PreparationReport& report,
  std::vector<unsigned char>& flags)
{
  const Index nv = mesh.NumberOfPoints();
  flags.assign(size_t(nv), 0);
  bool inconsistent = false;
  vtkSMPThreadLocal<long long> nonManifold(0);
  vtkSMPThreadLocal<std::vector<Index>> scratch;
  vtkSMPTools::For(0, nv, 4096, [&](vtkIdType begin, vtkIdType end) {
    std::vector<Index>& local = scratch.Local();
    long long& count = nonManifold.Local();
    for (Index a = static_cast<Index>(begin); a < static_cast<Index>(end); ++a)
    {
      // One inconsistent edge is enough: the others are not searched for.
      if (!__atomic_load_n(&inconsistent, __ATOMIC_RELAXED) && SameHalfEdgeTwice(mesh, star, a, local))
      {
        __atomic_store_n(&inconsistent, true, __ATOMIC_RELAXED);
      }
      count += FlagEdgesOf(mesh, star, a, local, flags);
    }
  });
  for (long long count : nonManifold)
  {
    report.NonManifoldEdges += count;
  }
  return inconsistent;
}

// For a vertex without border or non-manifold edges: 1 when the fan walk of
// MarkNonManifoldVertices from its first triangle reaches every triangle, else 0; -1 when the star
// is too large or holds a triangle with a repeated vertex (the caller walks it then). The same
// walk, but each step searches v's own star (read once into local arrays) for the other triangle
// on the edge instead of the star of the edge's far end: the same triangles hold both ends.
int InteriorFanCount(const TriangleMesh& mesh, const VertexStar& star, Index v)
{
  constexpr Index smallStar = 32;
  const Index degree = star.Degree(v);
  if (degree > smallStar)
  {
    return -1;
  }
  Index next[smallStar], previous[smallStar];
  for (Index i = 0; i < degree; ++i)
  {
    const Index* tri = mesh.Triangle(star.Begin(v)[i]);
    const int c = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    next[i] = tri[(c + 1) % 3];
    previous[i] = tri[(c + 2) % 3];
    if (next[i] == v || previous[i] == v || next[i] == previous[i])
    {
      return -1;
    }
  }
  Index walked = 0;
  for (Index i = 0; walked < degree; )
  {
    ++walked;
    // The other triangle on the edge (v, previous[i]) when the edge has exactly two.
    const Index a = previous[i];
    Index count = 0, other = -1;
    for (Index j = 0; j < degree; ++j)
    {
      if (next[j] == a || previous[j] == a)
      {
        ++count;
        other = j == i ? other : j;
      }
    }
    if (count != 2 || other == 0)
    {
      break;
    }
    i = other;
  }
  return walked == degree ? 1 : 0;
}

// Whether vertex v (not on a non-manifold edge) has its triangles in several fans: walking the fan
// from its start (as MeshTopology::OrderedOneRing does) does not reach every triangle of v.
bool SeveralFans(const TriangleMesh& mesh, const VertexStar& star, Index v, bool border)
{
  const Index degree = star.Degree(v);
  if (!border)
  {
    const int fans = InteriorFanCount(mesh, star, v);
    if (fans >= 0)
    {
      return fans != 1;
    }
  }
  auto corner = [&](Index t) {
    const Index* tri = mesh.Triangle(t);
    return tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
  };
  Index start = *star.Begin(v);
  if (border)
  {
    start = FanStart(start, degree, [&](Index t) { return star.EdgeNeighbor(t, corner(t)); });
  }
  Index fan = 0;
  Index t = start;
  for (Index steps = 0; steps < degree; ++steps)
  {
    ++fan;
    const Index next = star.EdgeNeighbor(t, (corner(t) + 2) % 3);
    if (next == InvalidIndex || next == start)
    {
      break;
    }
    t = next;
  }
  return fan != degree;
}

// Non-manifold vertices: on a non-manifold edge (flagged by ClassifyEdges), or whose triangles
// form several fans (same definition as MeshTopology). Flags them all with NonManifoldFlag and
// returns their number. In parallel over the vertices: each reads the shared star and writes only
// its own flag, and the count is a sum (the same for any thread count).
long long MarkNonManifoldVertices(const TriangleMesh& mesh, const VertexStar& star, std::vector<unsigned char>& flags)
{
  vtkSMPThreadLocal<long long> counts(0);
  vtkSMPTools::For(0, mesh.NumberOfPoints(), 4096, [&](vtkIdType begin, vtkIdType end) {
    long long& count = counts.Local();
    for (Index v = static_cast<Index>(begin); v < static_cast<Index>(end); ++v)
    {
      if (star.Degree(v) > 0 && !(flags[v] & NonManifoldFlag) && SeveralFans(mesh, star, v, flags[v] & BoundaryFlag))
      {
        flags[v] |= NonManifoldFlag;
      }
      count += (flags[v] & NonManifoldFlag) ? 1 : 0;
    }
  });
  long long count = 0;
  for (long long c : counts)
  {
    count += c;
  }
  return count;
}

// Every point id of a polygon or strip must name an existing point: anything else would read
// outside the point array. Vertex and line cells are ignored by the filters, so not checked.
bool ValidateCellIds(vtkPolyData* input, PreparationReport& report)
{
  const vtkIdType np = input->GetNumberOfPoints();
  vtkIdType cellIndex = 0;
  for (vtkCellArray* cells : { input->GetPolys(), input->GetStrips() })
  {
    if (!cells)
    {
      continue;
    }
    auto it = vtk::TakeSmartPointer(cells->NewIterator());
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellIndex)
    {
      it->GetCurrentCell(n, ids);
      for (vtkIdType i = 0; i < n; ++i)
      {
        if (ids[i] < 0 || ids[i] >= np)
        {
          std::ostringstream s;
          s << "cell " << cellIndex << " refers to point id " << ids[i] << ", outside 0.." << np - 1;
          report.Valid = false;
          report.Error = s.str();
          return false;
        }
      }
    }
  }
  return true;
}

// Point coordinates as doubles, read straight from float or double arrays.
void ReadPoints(vtkPolyData* input, std::vector<double>& points)
{
  const vtkIdType np = input->GetNumberOfPoints();
  ReserveOnHugePages(points, 3 * size_t(np));
  points.resize(3 * size_t(np));
  vtkDataArray* data = input->GetPoints()->GetData();
  if (auto* f = vtkFloatArray::SafeDownCast(data))
  {
    std::copy(f->GetPointer(0), f->GetPointer(0) + 3 * np, points.begin());
  }
  else if (auto* d = vtkDoubleArray::SafeDownCast(data))
  {
    std::copy(d->GetPointer(0), d->GetPointer(0) + 3 * np, points.begin());
  }
  else
  {
    for (vtkIdType i = 0; i < np; ++i)
    {
      input->GetPoint(i, &points[3 * size_t(i)]);
    }
  }
}

// Hash of a point's exact coordinates (-0 and +0 hash alike: they compare equal).
std::uint64_t PointHash(const double* p)
{
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (int k = 0; k < 3; ++k)
  {
    const double x = p[k] + 0.0;
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    h ^= bits + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    h *= 0xff51afd7ed558ccdULL;
  }
  return h ^ (h >> 33);
}

// Whether two points carry the same values in every data array of the input's point data (points
// that coincide but differ there are an attribute seam, e.g. a texture seam: never welded).
bool SamePointData(vtkPointData* pointData, Index a, Index b)
{
  for (int i = 0; pointData && i < pointData->GetNumberOfArrays(); ++i)
  {
    vtkDataArray* array = pointData->GetArray(i);
    if (!array || array->GetNumberOfTuples() <= std::max(a, b))
    {
      continue;
    }
    for (int c = 0; c < array->GetNumberOfComponents(); ++c)
    {
      const double x = array->GetComponent(a, c), y = array->GetComponent(b, c);
      if (!(x == y || (std::isnan(x) && std::isnan(y))))
      {
        return false;
      }
    }
  }
  return true;
}

// Classes of exactly coincident used points with the same point data: coincident[v] is the smallest
// id of v's class. Coincident points whose point data differ are counted as attribute seams.
std::vector<Index> CoincidentClasses(const std::vector<double>& points, const std::vector<Index>& triangles, Index np,
  vtkPointData* pointData, PreparationReport& report)
{
  std::vector<Index> coincident(static_cast<size_t>(np));
  std::iota(coincident.begin(), coincident.end(), 0);
  std::vector<std::pair<std::uint64_t, Index>> keys;
  {
    std::vector<unsigned char> used(size_t(np), 0);
    for (Index v : triangles)
    {
      used[v] = 1;
    }
    keys.reserve(static_cast<size_t>(std::count(used.begin(), used.end(), 1)));
    for (Index v = 0; v < np; ++v)
    {
      if (used[v])
      {
        keys.emplace_back(PointHash(&points[3 * size_t(v)]), v);
      }
    }
  }
  // The pairs are distinct (one per vertex): the parallel sort gives the one sorted order.
  vtkSMPTools::Sort(keys.begin(), keys.end());
  for (size_t i = 0; i < keys.size();)
  {
    size_t j = i + 1;
    while (j < keys.size() && keys[j].first == keys[i].first)
    {
      ++j;
    }
    // Within a run of equal hashes (ids ascending) compare exactly (collisions are possible).
    for (size_t m = i + 1; m < j; ++m)
    {
      const double* q = &points[3 * size_t(keys[m].second)];
      bool seam = false;
      for (size_t l = i; l < m; ++l)
      {
        const Index r = keys[l].second;
        const double* p = &points[3 * size_t(r)];
        if (coincident[r] == r && p[0] == q[0] && p[1] == q[1] && p[2] == q[2])
        {
          if (SamePointData(pointData, r, keys[m].second))
          {
            coincident[keys[m].second] = r;
            seam = false;
            break;
          }
          seam = true;
        }
      }
      report.AttributeSeamPoints += seam ? 1 : 0;
    }
    i = j;
  }
  return coincident;
}

// The border edges (one triangle) among the edges whose two ends both have coincident partners:
// the only edges a sealing merge can join. Each as (class pair key, a, b).
std::vector<std::array<std::uint64_t, 3>> SealableBorderEdges(
  const std::vector<Index>& triangles, const std::vector<Index>& coincident, const std::vector<unsigned char>& partner)
{
  std::vector<std::uint64_t> edges;
  for (size_t t = 0; 3 * t < triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Index a = triangles[3 * t + k], b = triangles[3 * t + (k + 1) % 3];
      if (a != b && partner[a] && partner[b] && coincident[a] != coincident[b])
      {
        edges.push_back(EdgeKey(a, b));
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::array<std::uint64_t, 3>> border;
  for (size_t i = 0; i < edges.size();)
  {
    size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i])
    {
      ++j;
    }
    if (j == i + 1)
    {
      const Index a = static_cast<Index>(edges[i] >> 32), b = static_cast<Index>(edges[i] & 0xffffffffu);
      border.push_back({ EdgeKey(coincident[a], coincident[b]), std::uint64_t(a), std::uint64_t(b) });
    }
    i = j;
  }
  std::sort(border.begin(), border.end());
  return border;
}

// Which coincident points are merged: only those that seal an open border, i.e. the ends of two
// border edges whose ends are pairwise coincident, with no third border edge at that place (an
// edge cut open, as in STL files and split seams). Elsewhere coincident points stay apart: merging
// a pinch, two touching components or a sheet touching itself would create a non-manifold vertex
// or edge, join components or close a handle. Returns each point's representative.
std::vector<Index> SealingRepresentatives(const std::vector<double>& points, const std::vector<Index>& triangles,
  Index np, vtkPointData* pointData, PreparationReport& report)
{
  const std::vector<Index> coincident = CoincidentClasses(points, triangles, np, pointData, report);
  std::vector<Index> classSize(static_cast<size_t>(np), 0);
  for (Index v = 0; v < np; ++v)
  {
    ++classSize[coincident[v]];
  }
  std::vector<unsigned char> partner(static_cast<size_t>(np), 0);
  bool any = false;
  for (Index v = 0; v < np; ++v)
  {
    partner[v] = classSize[coincident[v]] > 1 ? 1 : 0;
    any = any || partner[v];
  }
  std::vector<Index> representative(static_cast<size_t>(np));
  std::iota(representative.begin(), representative.end(), 0);
  if (!any)
  {
    return representative;
  }
  const auto border = SealableBorderEdges(triangles, coincident, partner);
  UnionFind merged(np);
  for (size_t i = 0; i < border.size();)
  {
    size_t j = i + 1;
    while (j < border.size() && border[j][0] == border[i][0])
    {
      ++j;
    }
    if (j == i + 2)
    {
      const Index a1 = Index(border[i][1]), b1 = Index(border[i][2]);
      const Index a2 = Index(border[i + 1][1]), b2 = Index(border[i + 1][2]);
      const bool straight = coincident[a1] == coincident[a2];
      merged.Union(a1, straight ? a2 : b2);
      merged.Union(b1, straight ? b2 : a2);
    }
    i = j;
  }
  std::vector<unsigned char> used(static_cast<size_t>(np), 0);
  for (Index v : triangles)
  {
    used[v] = 1;
  }
  for (Index v = 0; v < np; ++v)
  {
    representative[v] = merged.Find(v);
    report.MergedPoints += representative[v] != v ? 1 : 0;
    report.CoincidentPointsKeptApart += used[v] && partner[v] && representative[v] == v && coincident[v] != v ? 1 : 0;
  }
  return representative;
}

// Drops triangles with a repeated vertex (in place; kept when options say so, then returns true).
bool RemoveRepeatedVertexTriangles(
  std::vector<Index>& triangles, std::vector<Index>* cells, bool remove, PreparationReport& report)
{
  size_t nt = 0;
  bool kept = false;
  for (size_t t = 0; 3 * t < triangles.size(); ++t)
  {
    const Index a = triangles[3 * t], b = triangles[3 * t + 1], c = triangles[3 * t + 2];
    if (a == b || b == c || a == c)
    {
      if (remove)
      {
        ++report.RemovedDegenerateTriangles;
        continue;
      }
      kept = true;
    }
    triangles[3 * nt] = a;
    triangles[3 * nt + 1] = b;
    triangles[3 * nt + 2] = c;
    if (cells)
    {
      (*cells)[nt] = (*cells)[t];
    }
    ++nt;
  }
  triangles.resize(3 * nt);
  if (cells)
  {
    cells->resize(nt);
  }
  return kept;
}

// Exact repeats (same three vertices, same winding) are removed: the first is kept. A triangle and
// its mirror (same vertices, opposite winding) are both kept: they are the two sides of a sheet
// that touches itself (as marching cubes makes them), and removing one would open the surface.
// Repeats share their smallest vertex, so only triangles grouped by it are compared.
void MarkRepeatedTriangles(const std::vector<Index>& triangles, Index np, std::vector<unsigned char>& keep,
  PreparationReport& report)
{
  const Index nt = static_cast<Index>(triangles.size() / 3);
  // Rotated so that the smallest vertex comes first: same winding <=> same rotated triple.
  auto rotated = [&](Index t) {
    const Index* tri = &triangles[3 * size_t(t)];
    const int k = tri[0] < tri[1] ? (tri[0] < tri[2] ? 0 : 2) : (tri[1] < tri[2] ? 1 : 2);
    return std::array<Index, 3>{ tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3] };
  };
  std::vector<Index> start(size_t(np) + 1, 0);
  for (Index t = 0; t < nt; ++t)
  {
    ++start[size_t(rotated(t)[0]) + 1];
  }
  for (Index v = 0; v < np; ++v)
  {
    start[v + 1] += start[v];
  }
  std::vector<Index> byVertex(static_cast<size_t>(nt));
  for (Index t = 0; t < nt; ++t)
  {
    byVertex[start[rotated(t)[0]]++] = t; // ascending t within each group
  }
  // start[v] is now the end of group v.
  std::vector<std::pair<std::array<Index, 3>, Index>> group;
  for (Index v = 0, begin = 0; v < np; begin = start[v], ++v)
  {
    if (start[v] - begin < 2)
    {
      continue;
    }
    group.clear();
    for (Index i = begin; i < start[v]; ++i)
    {
      group.push_back({ rotated(byVertex[i]), byVertex[i] });
    }
    std::sort(group.begin(), group.end());
    for (size_t i = 1; i < group.size(); ++i)
    {
      if (group[i].first == group[i - 1].first)
      {
        keep[group[i].second] = 0;
        ++report.RemovedDuplicateTriangles;
      }
    }
  }
}

// Compaction: the used points in input order (in place: a point only moves to a smaller slot) and
// the kept triangles in input order, renumbered.
void CompactInto(std::vector<double>& points, std::vector<Index>& triangles, const std::vector<unsigned char>& keep,
  Index np, TriangleMesh& mesh, std::vector<Index>& vertexToInputPoint, std::vector<Index>* cells)
{
  const Index nt = static_cast<Index>(triangles.size() / 3);
  std::vector<Index> inputToMesh(static_cast<size_t>(np), InvalidIndex);
  for (Index t = 0; t < nt; ++t)
  {
    for (int k = 0; k < 3 && keep[t]; ++k)
    {
      inputToMesh[triangles[3 * size_t(t) + k]] = 0;
    }
  }
  const Index used = static_cast<Index>(np - std::count(inputToMesh.begin(), inputToMesh.end(), InvalidIndex));
  vertexToInputPoint.reserve(size_t(used));
  for (Index v = 0; v < np; ++v)
  {
    if (inputToMesh[v] != InvalidIndex)
    {
      const Index i = static_cast<Index>(vertexToInputPoint.size());
      inputToMesh[v] = i;
      vertexToInputPoint.push_back(v);
      std::copy(&points[3 * size_t(v)], &points[3 * size_t(v)] + 3, &points[3 * size_t(i)]);
    }
  }
  points.resize(3 * size_t(used));
  if (used < np - np / 8)
  {
    points.shrink_to_fit(); // many unused points: worth a copy
  }
  mesh.Points.swap(points);
  Index kept = 0;
  for (Index t = 0; t < nt; ++t)
  {
    if (keep[t])
    {
      for (int k = 0; k < 3; ++k)
      {
        triangles[3 * size_t(kept) + k] = inputToMesh[triangles[3 * size_t(t) + k]];
      }
      if (cells)
      {
        (*cells)[kept] = (*cells)[t];
      }
      ++kept;
    }
  }
  triangles.resize(3 * size_t(kept));
  mesh.Triangles.swap(triangles);
  if (cells)
  {
    cells->resize(size_t(kept));
  }
}

// Reads the input's polygons and strips as triangles over its points; false (report says why)
// when the input cannot be used.
bool ReadSurface(vtkPolyData* input, PreparationReport& report, std::vector<double>& points, std::vector<Index>& triangles,
  std::vector<Index>* cells)
{
  const vtkIdType surfaceCells = (input->GetPolys() ? input->GetPolys()->GetNumberOfCells() : 0) +
    (input->GetStrips() ? input->GetStrips()->GetNumberOfCells() : 0);
  if (input->GetNumberOfPoints() == 0 || !input->GetPoints())
  {
    report.Valid = surfaceCells == 0;
    report.Error = report.Valid ? "" : "polygons or strips but no points";
    return false;
  }
  if (input->GetNumberOfPoints() >= std::numeric_limits<Index>::max() / 2)
  {
    report.Valid = false;
    report.Error = "too many points for 32-bit indices";
    return false;
  }
  if (!ValidateCellIds(input, report))
  {
    return false;
  }
  report.IgnoredVertexCells = input->GetVerts() ? input->GetVerts()->GetNumberOfCells() : 0;
  report.IgnoredLineCells = input->GetLines() ? input->GetLines()->GetNumberOfCells() : 0;
  ReadPoints(input, points);
  vtkIdType reserve = 0;
  reserve += input->GetPolys() ? input->GetPolys()->GetNumberOfConnectivityIds() : 0;
  reserve += input->GetStrips() ? input->GetStrips()->GetNumberOfConnectivityIds() : 0;
  ReserveOnHugePages(triangles, size_t(reserve));
  CollectTriangles(input, points, report, triangles, cells);
  // Non-finite coordinates on a used point make the input unusable.
  for (Index v : triangles)
  {
    const double* p = &points[3 * size_t(v)];
    report.NonFinitePoints += std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]) ? 0 : 1;
  }
  if (report.NonFinitePoints > 0)
  {
    report.Valid = false;
    report.Error = "input has points with NaN or infinite coordinates";
    return false;
  }
  return true;
}
} // namespace

namespace
{
// PreparationOptions::CollapseZeroLengthEdges: ends with equal point data only (as the sealing
// merge); the merged ends are no longer counted as kept apart.
void MergeZeroLengthEdges(vtkPointData* pointData, TriangleMesh& mesh, std::vector<Index>& vertexToInputPoint,
  std::vector<Index>* triangleToInputCell, PreparationReport& report)
{
  ZeroLengthEdgeMaps maps;
  maps.VertexToInputPoint = &vertexToInputPoint;
  maps.NonManifoldFlags = &report.NonManifoldVertexFlags;
  maps.BorderFlags = &report.BoundaryVertexFlags;
  maps.TriangleToInputCell = triangleToInputCell;
  maps.MayMerge = [pointData](Index a, Index b) { return SamePointData(pointData, a, b); };
  report.CollapsedZeroLengthEdges = CollapseZeroLengthEdges(mesh, maps);
  report.CoincidentPointsKeptApart = std::max(0LL, report.CoincidentPointsKeptApart - report.CollapsedZeroLengthEdges);
}
} // namespace

// Memory: the working arrays are int32 and released as soon as a stage is done; the points are
// read once and compacted in place into the output; coincident points are found by sorting
// 64-bit hashes of their exact coordinates (16 bytes per point, transient), repeated triangles
// by grouping the triangles by their smallest vertex (4 bytes per triangle), and the adjacency of
// the orientation / manifoldness checks is a single vertex->triangle CSR array.
PreparationReport PrepareTriangleMesh(vtkPolyData* input, const PreparationOptions& options, TriangleMesh& mesh,
  std::vector<Index>& vertexToInputPoint, std::vector<Index>* triangleToInputCell)
{
  PreparationReport report;
  mesh.Points.clear();
  mesh.Triangles.clear();
  vertexToInputPoint.clear();
  if (triangleToInputCell)
  {
    triangleToInputCell->clear();
  }
  StageClock stages("input preparation");
  std::vector<double> points;
  std::vector<Index> triangles;
  if (!input || !ReadSurface(input, report, points, triangles, triangleToInputCell))
  {
    return report;
  }
  stages.Lap("read");
  const Index np = static_cast<Index>(input->GetNumberOfPoints());
  if (options.MergeDuplicatePoints)
  {
    const std::vector<Index> representative = SealingRepresentatives(points, triangles, np, input->GetPointData(), report);
    for (Index& v : triangles)
    {
      v = representative[v];
    }
    stages.Lap("coincident points");
  }
  const bool repeatedVertices = RemoveRepeatedVertexTriangles(triangles, triangleToInputCell, options.RemoveDegenerateTriangles, report);
  std::vector<unsigned char> keep(triangles.size() / 3, 1);
  if (options.RemoveDuplicateTriangles)
  {
    MarkRepeatedTriangles(triangles, np, keep, report);
  }
  CompactInto(points, triangles, keep, np, mesh, vertexToInputPoint, triangleToInputCell);
  stages.Lap("repeated triangles, compaction");

  // One adjacency serves both the orientation repair and the non-manifold counts (flipping
  // triangles changes neither edges nor fans).
  const VertexStar star(mesh);
  stages.Lap("vertex star");
  std::vector<unsigned char> flags;
  const bool inconsistent = ClassifyEdges(mesh, star, report, flags);
  stages.Lap("edge classes");
  if (options.MakeOrientationConsistent && (inconsistent || repeatedVertices))
  {
    OrientConsistently(mesh, star, report);
    stages.Lap("orientation");
  }
  report.NonManifoldVertices = MarkNonManifoldVertices(mesh, star, flags);
  stages.Lap("non-manifold vertices");
  report.BoundaryVertexFlags.resize(flags.size());
  for (size_t v = 0; v < flags.size(); ++v)
  {
    report.BoundaryVertexFlags[v] = (flags[v] & BoundaryFlag) ? 1 : 0;
    flags[v] = (flags[v] & NonManifoldFlag) ? 1 : 0;
  }
  report.NonManifoldVertexFlags = std::move(flags);
  if (options.CollapseZeroLengthEdges)
  {
    MergeZeroLengthEdges(input->GetPointData(), mesh, vertexToInputPoint, triangleToInputCell, report);
    stages.Lap("zero-length edges");
  }
  return report;
}

std::vector<unsigned char> NonManifoldVertexFlags(const TriangleMesh& mesh)
{
  const VertexStar star(mesh);
  PreparationReport unused;
  std::vector<unsigned char> flags;
  ClassifyEdges(mesh, star, unused, flags);
  MarkNonManifoldVertices(mesh, star, flags);
  for (unsigned char& f : flags)
  {
    f = (f & NonManifoldFlag) ? 1 : 0;
  }
  return flags;
}

bool PrepareFilterInput(vtkObject* filter, vtkPolyData* input, const PreparationOptions& options,
  TriangleMesh& mesh, std::vector<Index>& vertexToInputPoint, PreparationReport* reportOut,
  std::vector<Index>* triangleToInputCell)
{
  const PreparationReport report = PrepareTriangleMesh(input, options, mesh, vertexToInputPoint, triangleToInputCell);
  if (reportOut)
  {
    *reportOut = report;
  }
  if (!report.Valid)
  {
    vtkErrorWithObjectMacro(filter, << "Invalid input: " << report.Error << "; the output is empty.");
    mesh.Points.clear();
    mesh.Triangles.clear();
    vertexToInputPoint.clear();
    if (triangleToInputCell)
    {
      triangleToInputCell->clear();
    }
    return false;
  }
  for (const std::string& warning : report.Warnings())
  {
    vtkWarningWithObjectMacro(filter, << "Input: " << warning << ".");
  }
  return true;
}

bool PrepareFilterTriangles(vtkObject* filter, vtkPolyData* input, const PreparationOptions& options,
  TriangleMesh& mesh, std::vector<Index>& vertexToInputPoint, PreparationReport* report,
  std::vector<Index>* triangleToInputCell, const NoTrianglesMessage& noTriangles)
{
  if (!PrepareFilterInput(filter, input, options, mesh, vertexToInputPoint, report, triangleToInputCell))
  {
    return false;
  }
  if (mesh.NumberOfTriangles() > 0)
  {
    return true;
  }
  if (noTriangles.IsError)
  {
    vtkErrorWithObjectMacro(filter, << noTriangles.Text);
  }
  else
  {
    vtkWarningWithObjectMacro(filter, << noTriangles.Text);
  }
  return false;
}

bool PrepareFilterTriangles(
  vtkObject* filter, vtkPolyData* input, PreparedTriangles& prepared, const NoTrianglesMessage& noTriangles)
{
  return PrepareFilterTriangles(filter, input, PreparationOptions(), prepared.Mesh, prepared.VertexToInput,
    &prepared.Report, CellMapIfNeeded(input, prepared.TriangleToCell), noTriangles);
}

ProgressFunction FilterProgress(vtkAlgorithm* filter, double from, double to)
{
  return [filter, from, to](double fraction) {
    filter->UpdateProgress(from + std::min(1.0, std::max(0.0, fraction)) * (to - from));
    return !filter->GetAbortExecute(); // VTK 9.1 has no CheckAbort()
  };
}

void ReportAbort(vtkAlgorithm* filter, vtkPolyData* output)
{
  output->Initialize();
  vtkWarningWithObjectMacro(filter, << "Aborted: the output is empty.");
}

void ReportTarget(vtkObject* filter, vtkPolyData* output, long long targetTriangles, bool reached, const char* reason)
{
  vtkFieldData* fieldData = output->GetFieldData();
  for (const auto& entry : { std::make_pair("TargetNumberOfTriangles", targetTriangles),
         std::make_pair("TargetReached", reached ? 1LL : 0LL) })
  {
    vtkNew<vtkIdTypeArray> array;
    array->SetName(entry.first);
    array->InsertNextValue(static_cast<vtkIdType>(entry.second));
    fieldData->AddArray(array);
  }
  if (!reached)
  {
    vtkWarningWithObjectMacro(filter, << "Target of " << targetTriangles << " triangles not reached: "
                                      << output->GetNumberOfPolys() << " remain (" << reason << ").");
  }
}

void MeshToPolyData(const TriangleMesh& mesh, vtkPolyData* output, int pointDataType)
{
  vtkNew<vtkPoints> points;
  points->SetDataType(pointDataType);
  points->SetNumberOfPoints(mesh.NumberOfPoints());
  for (Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    points->SetPoint(v, &mesh.Points[3 * size_t(v)]);
  }
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(mesh.NumberOfTriangles(), 3 * mesh.NumberOfTriangles());
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    const vtkIdType ids[3] = { tri[0], tri[1], tri[2] };
    polys->InsertNextCell(3, ids);
  }
  output->SetPoints(points);
  output->SetPolys(polys);
}

int OutputPointType(vtkPolyData* input, int outputPointsPrecision)
{
  if (outputPointsPrecision == vtkAlgorithm::SINGLE_PRECISION)
  {
    return VTK_FLOAT;
  }
  if (outputPointsPrecision == vtkAlgorithm::DOUBLE_PRECISION)
  {
    return VTK_DOUBLE;
  }
  return input->GetPoints() && input->GetPoints()->GetDataType() == VTK_DOUBLE ? VTK_DOUBLE : VTK_FLOAT;
}

void StoreUsedPoints(vtkPolyData* input, const TriangleMesh& mesh, const std::vector<Index>& used,
  const std::vector<Index>& vertexToInputPoint, int outputPointsPrecision, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataType(OutputPointType(input, outputPointsPrecision));
  points->SetNumberOfPoints(static_cast<vtkIdType>(used.size()));
  std::vector<Index> outputToInputPoint(used.size());
  for (size_t i = 0; i < used.size(); ++i)
  {
    points->SetPoint(static_cast<vtkIdType>(i), &mesh.Points[3 * size_t(used[i])]);
    outputToInputPoint[i] = vertexToInputPoint[used[i]];
  }
  CopyAttributeTuples(input->GetPointData(), input->GetNumberOfPoints(), outputToInputPoint, output->GetPointData());
  output->SetPoints(points);
}

std::vector<unsigned char> AttributeSeamVertexFlags(const TriangleMesh& mesh,
  const std::vector<unsigned char>& borderVertices, vtkPointData* pointData,
  const std::vector<Index>& vertexToInputPoint, double tolerance)
{
  const Index nv = mesh.NumberOfPoints();
  std::vector<unsigned char> seam(size_t(nv), 0);
  if (!pointData || pointData->GetNumberOfArrays() == 0 || vertexToInputPoint.size() != size_t(nv) ||
    borderVertices.size() != size_t(nv) || !(tolerance >= 0))
  {
    return seam;
  }
  // The sides of a seam are borders of the prepared mesh (their points were kept apart): only
  // border vertices are compared, each with the border vertices of the grid cells around it.
  std::vector<Index> borderIds;
  std::vector<double> borderXyz;
  for (Index v = 0; v < nv; ++v)
  {
    if (borderVertices[v])
    {
      borderIds.push_back(v);
      borderXyz.insert(borderXyz.end(), &mesh.Points[3 * size_t(v)], &mesh.Points[3 * size_t(v)] + 3);
    }
  }
  PointGrid grid;
  grid.Build(borderXyz, tolerance > 0 ? tolerance : 1.0);
  auto near = [&](Index a, Index b) {
    const Vec3 d = mesh.Point(a) - mesh.Point(b);
    return Dot(d, d) <= tolerance * tolerance;
  };
  for (size_t i = 0; i < borderIds.size(); ++i)
  {
    const Index a = borderIds[i];
    grid.ForEachNear(&borderXyz[3 * i], tolerance, [&](Index j) {
      const Index b = borderIds[size_t(j)];
      if (a < b && near(a, b) && !SamePointData(pointData, vertexToInputPoint[a], vertexToInputPoint[b]))
      {
        seam[a] = seam[b] = 1;
      }
    });
  }
  // A vertex with an edge shorter than the tolerance is the corner of a collapsed fan (a pole made of copies, one
  // per texture column): no line to keep, and pinning its copies would keep the zero-area triangles.
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      const Index a = tri[k], b = tri[(k + 1) % 3];
      if ((seam[a] || seam[b]) && near(a, b))
      {
        seam[a] = seam[b] = 2;
      }
    }
  }
  for (unsigned char& flag : seam)
  {
    flag = flag == 1 ? 1 : 0;
  }
  return seam;
}

std::vector<unsigned char> RegionBorderVertexFlags(
  const TriangleMesh& mesh, vtkDataArray* regions, const std::vector<Index>* triangleToInputCell)
{
  const Index nv = mesh.NumberOfPoints(), nt = mesh.NumberOfTriangles();
  std::vector<unsigned char> border(size_t(nv), 0);
  if (!regions || (triangleToInputCell && triangleToInputCell->size() != size_t(nt)))
  {
    return border;
  }
  // The first region seen at each vertex; a vertex whose triangles differ from it is on a border.
  std::vector<double> first(size_t(nv), std::numeric_limits<double>::quiet_NaN());
  for (Index t = 0; t < nt; ++t)
  {
    const Index cell = triangleToInputCell ? (*triangleToInputCell)[t] : t;
    if (cell < 0 || cell >= regions->GetNumberOfTuples())
    {
      continue;
    }
    const double r = regions->GetComponent(cell, 0);
    const Index* tri = mesh.Triangle(t);
    for (int k = 0; k < 3; ++k)
    {
      double& f = first[size_t(tri[k])];
      if (std::isnan(f))
      {
        f = r;
      }
      else if (f != r)
      {
        border[size_t(tri[k])] = 1;
      }
    }
  }
  return border;
}
namespace
{
template <typename ArrayType>
vtkSmartPointer<ArrayType> NewNamedArray(const char* name, int components, vtkIdType tuples)
{
  auto a = vtkSmartPointer<ArrayType>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}
} // namespace

vtkSmartPointer<vtkIdTypeArray> NewIdArray(const char* name, int components, vtkIdType tuples)
{
  return NewNamedArray<vtkIdTypeArray>(name, components, tuples);
}

vtkSmartPointer<vtkDoubleArray> NewDoubleArray(const char* name, int components, vtkIdType tuples)
{
  return NewNamedArray<vtkDoubleArray>(name, components, tuples);
}
} // namespace slod
