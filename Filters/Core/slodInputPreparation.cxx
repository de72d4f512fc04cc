#include "slodInputPreparation.h"

#include "slodMeshTopology.h"
#include "slodPolygonTriangulation.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkObject.h"
#include "vtkPoints.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <array>
#include <cmath>
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
  say(this->MergedPoints, "coincident point(s) merged");
  say(this->RemovedDegenerateTriangles, "degenerate triangle(s) (repeated vertex) removed");
  say(this->RemovedDuplicateTriangles, "duplicate triangle(s) removed");
  say(this->FlippedTriangles, "triangle(s) flipped to make the orientation consistent");
  say(this->NonOrientableComponents, "non-orientable component(s): orientation left as given");
  say(this->NonManifoldEdges, "non-manifold edge(s) (more than two triangles)");
  say(this->NonManifoldVertices, "non-manifold vertex/vertices (several fans)");
  return out;
}

namespace
{
void CollectTriangles(vtkPolyData* input, const std::vector<double>& points, PreparationReport& report,
  std::vector<Index>& triangles)
{
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  if (vtkCellArray* polys = input->GetPolys())
  {
    auto it = vtk::TakeSmartPointer(polys->NewIterator());
    std::vector<Vec3> polygon;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
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
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
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

// Makes neighbouring triangles traverse shared manifold edges in opposite directions.
void OrientConsistently(TriangleMesh& mesh, const MeshTopology& topology, PreparationReport& report)
{
  const Index nt = mesh.NumberOfTriangles();
  std::vector<signed char> flip(nt, -1); // -1 unvisited, 0 keep, 1 flip
  std::vector<Index> queue, component;
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
    component.clear();
    queue.assign(1, seed);
    flip[seed] = 0;
    for (size_t head = 0; head < queue.size(); ++head)
    {
      const Index t = queue[head];
      component.push_back(t);
      for (int k = 0; k < 3; ++k)
      {
        const Index u = topology.EdgeNeighbor(t, k);
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
    if (!orientable)
    {
      ++report.NonOrientableComponents;
      for (Index t : component)
      {
        flip[t] = 0;
      }
      continue;
    }
    const size_t flipped = std::count_if(component.begin(), component.end(), [&](Index t) { return flip[t] == 1; });
    if (2 * flipped > component.size())
    {
      for (Index t : component)
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
} // namespace

PreparationReport PrepareTriangleMesh(vtkPolyData* input, const PreparationOptions& options, TriangleMesh& mesh,
  std::vector<Index>& vertexToInputPoint)
{
  PreparationReport report;
  mesh.Points.clear();
  mesh.Triangles.clear();
  vertexToInputPoint.clear();
  if (!input || input->GetNumberOfPoints() == 0)
  {
    return report;
  }
  if (input->GetNumberOfPoints() >= std::numeric_limits<Index>::max() / 2)
  {
    report.Valid = false;
    report.Error = "too many points for 32-bit indices";
    return report;
  }
  report.IgnoredVertexCells = input->GetVerts() ? input->GetVerts()->GetNumberOfCells() : 0;
  report.IgnoredLineCells = input->GetLines() ? input->GetLines()->GetNumberOfCells() : 0;

  const vtkIdType np = input->GetNumberOfPoints();
  std::vector<double> points(3 * size_t(np));
  for (vtkIdType i = 0; i < np; ++i)
  {
    input->GetPoint(i, &points[3 * size_t(i)]);
  }
  std::vector<Index> triangles;
  CollectTriangles(input, points, report, triangles);

  // Non-finite coordinates on a used point make the input unusable.
  for (Index v : triangles)
  {
    const double* p = &points[3 * size_t(v)];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      ++report.NonFinitePoints;
    }
  }
  if (report.NonFinitePoints > 0)
  {
    report.Valid = false;
    report.Error = "input has points with NaN or infinite coordinates";
    return report;
  }

  // Representative of each point: the first of the exactly coincident ones (by sorting).
  std::vector<Index> representative(np);
  std::iota(representative.begin(), representative.end(), 0);
  if (options.MergeDuplicatePoints)
  {
    std::vector<char> used(np, 0);
    for (Index v : triangles)
    {
      used[v] = 1;
    }
    std::vector<Index> order;
    order.reserve(np);
    for (Index v = 0; v < np; ++v)
    {
      if (used[v])
      {
        order.push_back(v);
      }
    }
    auto less = [&](Index a, Index b) {
      const double* p = &points[3 * size_t(a)];
      const double* q = &points[3 * size_t(b)];
      if (p[0] != q[0]) return p[0] < q[0];
      if (p[1] != q[1]) return p[1] < q[1];
      if (p[2] != q[2]) return p[2] < q[2];
      return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    for (size_t i = 1; i < order.size(); ++i)
    {
      const double* p = &points[3 * size_t(order[i - 1])];
      const double* q = &points[3 * size_t(order[i])];
      if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2])
      {
        representative[order[i]] = representative[order[i - 1]];
        ++report.MergedPoints;
      }
    }
  }
  for (Index& v : triangles)
  {
    v = representative[v];
  }

  // Drop triangles with a repeated vertex, then exact duplicates (same vertex set).
  std::vector<std::array<Index, 4>> keys; // sorted triple + triangle index
  std::vector<Index> kept;
  kept.reserve(triangles.size());
  for (size_t t = 0; 3 * t < triangles.size(); ++t)
  {
    const Index a = triangles[3 * t], b = triangles[3 * t + 1], c = triangles[3 * t + 2];
    if (options.RemoveDegenerateTriangles && (a == b || b == c || a == c))
    {
      ++report.RemovedDegenerateTriangles;
      continue;
    }
    std::array<Index, 3> s{ a, b, c };
    std::sort(s.begin(), s.end());
    keys.push_back({ s[0], s[1], s[2], static_cast<Index>(t) });
  }
  std::vector<char> keep(triangles.size() / 3, 0);
  std::sort(keys.begin(), keys.end());
  for (size_t i = 0; i < keys.size(); ++i)
  {
    const bool duplicate = options.RemoveDuplicateTriangles && i > 0 && keys[i][0] == keys[i - 1][0] &&
      keys[i][1] == keys[i - 1][1] && keys[i][2] == keys[i - 1][2];
    if (duplicate)
    {
      ++report.RemovedDuplicateTriangles;
    }
    else
    {
      keep[keys[i][3]] = 1;
    }
  }

  // Compact: used points in input order, triangles in input order.
  std::vector<Index> inputToMesh(np, InvalidIndex);
  for (size_t t = 0; t < keep.size(); ++t)
  {
    if (!keep[t])
    {
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      const Index v = triangles[3 * t + k];
      if (inputToMesh[v] == InvalidIndex)
      {
        inputToMesh[v] = 0;
      }
    }
  }
  for (Index v = 0; v < np; ++v)
  {
    if (inputToMesh[v] != InvalidIndex)
    {
      inputToMesh[v] = static_cast<Index>(vertexToInputPoint.size());
      vertexToInputPoint.push_back(v);
      const double* p = &points[3 * size_t(v)];
      mesh.Points.insert(mesh.Points.end(), p, p + 3);
    }
  }
  for (size_t t = 0; t < keep.size(); ++t)
  {
    if (keep[t])
    {
      mesh.AddTriangle(inputToMesh[triangles[3 * t]], inputToMesh[triangles[3 * t + 1]],
        inputToMesh[triangles[3 * t + 2]]);
    }
  }

  // One adjacency build serves both the orientation repair and the non-manifold counts (flipping
  // triangles changes neither edges nor fans).
  const MeshTopology topology(mesh);
  if (options.MakeOrientationConsistent)
  {
    OrientConsistently(mesh, topology, report);
  }
  for (Index e = 0; e < topology.NumberOfEdges(); ++e)
  {
    report.NonManifoldEdges += topology.IsNonManifoldEdge(e) ? 1 : 0;
  }
  for (Index v = 0; v < topology.NumberOfPoints(); ++v)
  {
    report.NonManifoldVertices += topology.IsNonManifoldVertex(v) ? 1 : 0;
  }
  return report;
}

bool PrepareFilterInput(vtkObject* filter, vtkPolyData* input, const PreparationOptions& options,
  TriangleMesh& mesh, std::vector<Index>& vertexToInputPoint, PreparationReport* reportOut)
{
  const PreparationReport report = PrepareTriangleMesh(input, options, mesh, vertexToInputPoint);
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
    return false;
  }
  for (const std::string& warning : report.Warnings())
  {
    vtkWarningWithObjectMacro(filter, << "Input: " << warning << ".");
  }
  return true;
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
} // namespace slod
