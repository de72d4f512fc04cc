// SPDX-License-Identifier: BSD-3-Clause
#include "vtkLODInterpolation.h"

#include "slodAttributeTransfer.h"
#include "slodCollapseRecordTable.h"
#include "slodInputPreparation.h"
#include "slodPointAttributes.h"
#include "slodUnionFind.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStaticPointLocator.h"
#include "vtkTable.h"

#include <algorithm>
#include <array>
#include <limits>

vtkStandardNewMacro(vtkLODInterpolation);

vtkLODInterpolation::vtkLODInterpolation()
{
  this->SetNumberOfInputPorts(3);
}

namespace
{
using slod::operator-; // Vec3 differences

vtkSmartPointer<vtkPolyData> PointsOnly(const slod::TriangleMesh& mesh)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(mesh.NumberOfPoints());
  for (slod::Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    points->SetPoint(v, &mesh.Points[3 * size_t(v)]);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  return pd;
}

// Steps 1-2 of the morph: per detailed vertex its coarse vertex. A coarse vertex claims its
// closest detailed vertex (the closest claimant wins); every other detailed vertex takes its
// closest coarse vertex (point locators both ways).
std::vector<slod::Index> MatchToCoarse(const slod::TriangleMesh& detailed, const slod::TriangleMesh& coarse)
{
  const slod::Index nh = detailed.NumberOfPoints(), nl = coarse.NumberOfPoints();
  vtkSmartPointer<vtkPolyData> detailedPoints = PointsOnly(detailed), coarsePoints = PointsOnly(coarse);
  vtkNew<vtkStaticPointLocator> detailedLocator, coarseLocator;
  detailedLocator->SetDataSet(detailedPoints);
  detailedLocator->BuildLocator();
  coarseLocator->SetDataSet(coarsePoints);
  coarseLocator->BuildLocator();
  std::vector<slod::Index> match(size_t(nh), slod::InvalidIndex);
  std::vector<double> matchDistance(size_t(nh), std::numeric_limits<double>::infinity());
  for (slod::Index l = 0; l < nl; ++l)
  {
    const slod::Vec3 p = coarse.Point(l);
    const auto h = static_cast<slod::Index>(detailedLocator->FindClosestPoint(p.data()));
    const slod::Vec3 d = p - detailed.Point(h);
    const double d2 = slod::Dot(d, d);
    if (d2 < matchDistance[h])
    {
      matchDistance[h] = d2;
      match[h] = l;
    }
  }
  for (slod::Index h = 0; h < nh; ++h)
  {
    if (match[h] == slod::InvalidIndex)
    {
      const slod::Vec3 p = detailed.Point(h);
      match[h] = static_cast<slod::Index>(coarseLocator->FindClosestPoint(p.data()));
    }
  }
  return match;
}

// The record id (vtkQuadricTriangleCollapse's prepared input numbering) of every prepared vertex:
// the OriginalVertexId point array, or, for the collapse filter's input itself (no such array,
// as many vertices as the records' input), the vertex's own index. False when neither applies.
bool RecordIds(vtkPolyData* input, const std::vector<slod::Index>& toInput, slod::Index prepared,
  vtkIdType recordPoints, bool identityAllowed, std::vector<slod::Index>& ids)
{
  ids.resize(size_t(prepared));
  vtkDataArray* array = input->GetPointData()->GetArray("OriginalVertexId");
  for (slod::Index v = 0; v < prepared; ++v)
  {
    const vtkIdType id = array ? static_cast<vtkIdType>(array->GetComponent(toInput[v], 0)) : v;
    if ((!array && !(identityAllowed && prepared == recordPoints)) || id < 0 || id >= recordPoints)
    {
      return false;
    }
    ids[v] = static_cast<slod::Index>(id);
  }
  return true;
}

// Steps 1-2 with records: the coarse vertex each detailed vertex collapses into. Walking the
// records backwards, a vertex removed by a record takes the representative of the record's kept
// vertex, which a later record (or the coarse level itself) has already settled; vertices alive in
// the coarse level are their own representative. Returns an error message, or nullptr.
const char* MatchThroughRecords(vtkTable* records, vtkPolyData* detailedInput, const std::vector<slod::Index>& detailedToInput,
  slod::Index nh, vtkPolyData* coarseInput, const std::vector<slod::Index>& coarseToInput, slod::Index nl,
  std::vector<slod::Index>& match)
{
  slod::CollapseRecords history;
  slod::Index recordPoints = 0, recordTriangles = 0;
  if (!slod::TableToCollapseRecords(records, history, recordPoints, recordTriangles))
  {
    return "The records are not vtkQuadricTriangleCollapse's collapse records (malformed table).";
  }
  std::vector<slod::Index> detailedIds, coarseIds;
  if (!RecordIds(coarseInput, coarseToInput, nl, recordPoints, false, coarseIds) ||
    !RecordIds(detailedInput, detailedToInput, nh, recordPoints, true, detailedIds))
  {
    return "The meshes are not levels of the records (OriginalVertexId missing or out of range).";
  }
  std::vector<slod::Index> representative(size_t(recordPoints), slod::InvalidIndex);
  for (slod::Index l = 0; l < nl; ++l)
  {
    representative[coarseIds[l]] = l;
  }
  // (TableToCollapseRecords has checked every vertex id against recordPoints.)
  for (slod::Index k = history.NumberOfCollapses() - 1; k >= 0; --k)
  {
    const slod::Index kept = history.Kept(k);
    for (int i = 1; i < history.VertexCount(k); ++i)
    {
      const slod::Index removed = history.Vertices[3 * size_t(k) + i];
      if (representative[removed] == slod::InvalidIndex)
      {
        representative[removed] = representative[kept];
      }
    }
  }
  match.resize(size_t(nh));
  for (slod::Index h = 0; h < nh; ++h)
  {
    match[h] = representative[detailedIds[h]];
    if (match[h] == slod::InvalidIndex)
    {
      return "A detailed vertex does not collapse into a coarse vertex: the coarse mesh is not a later level of the records.";
    }
  }
  return nullptr;
}

// A triangle's corners rotated so that the smallest comes first (orientation kept).
std::array<slod::Index, 3> Rotated(slod::Index a, slod::Index b, slod::Index c)
{
  if (b < a && b < c)
  {
    return { b, c, a };
  }
  return c < a && c < b ? std::array<slod::Index, 3>{ c, a, b } : std::array<slod::Index, 3>{ a, b, c };
}

// True when the detailed triangles mapped through `match`, less those that degenerate, are the
// coarse triangles, orientation included: the records relate the two meshes.
bool ImageIsCoarse(const slod::TriangleMesh& detailed, const slod::TriangleMesh& coarse, const std::vector<slod::Index>& match)
{
  std::vector<std::array<slod::Index, 3>> image, target;
  for (slod::Index f = 0; f < detailed.NumberOfTriangles(); ++f)
  {
    const slod::Index* tri = detailed.Triangle(f);
    const slod::Index a = match[tri[0]], b = match[tri[1]], c = match[tri[2]];
    if (a != b && b != c && c != a)
    {
      image.push_back(Rotated(a, b, c));
    }
  }
  for (slod::Index f = 0; f < coarse.NumberOfTriangles(); ++f)
  {
    const slod::Index* tri = coarse.Triangle(f);
    target.push_back(Rotated(tri[0], tri[1], tri[2]));
  }
  std::sort(image.begin(), image.end());
  std::sort(target.begin(), target.end());
  return image == target;
}

// Step 4 with records: the vertices of one coarse vertex become one when their interpolated
// positions all coincide (never only some of them: a partial merge need not be manifold).
// groups[h] is the vertex that h becomes.
std::vector<slod::Index> MergeCoincidentAncestries(const slod::TriangleMesh& mesh, const std::vector<slod::Index>& match, slod::Index nl)
{
  const slod::Index nh = mesh.NumberOfPoints();
  std::vector<slod::Index> first(size_t(nl), slod::InvalidIndex);
  std::vector<unsigned char> together(size_t(nl), 1);
  for (slod::Index h = 0; h < nh; ++h)
  {
    slod::Index& f = first[match[h]];
    if (f == slod::InvalidIndex)
    {
      f = h;
    }
    else if (!(mesh.Point(h) == mesh.Point(f)))
    {
      together[match[h]] = 0;
    }
  }
  std::vector<slod::Index> groups(static_cast<size_t>(nh));
  for (slod::Index h = 0; h < nh; ++h)
  {
    groups[h] = together[match[h]] ? first[match[h]] : h;
  }
  return groups;
}

// Step 4 without records (the paper's): merges the ends of the detailed edges that have shrunk to
// below eps, or to nothing, in the morphed mesh (the smaller id represents a group). An edge that
// has not shrunk is left alone: at t = 0 nothing merges, and detail the coarse mesh shares (both
// ends already on their matches) stays.
std::vector<slod::Index> MergeShrunkEdges(const slod::TriangleMesh& detailed, const slod::TriangleMesh& mesh, double eps)
{
  slod::UnionFind groups(detailed.NumberOfPoints());
  for (slod::Index f = 0; f < detailed.NumberOfTriangles(); ++f)
  {
    const slod::Index* tri = detailed.Triangle(f);
    for (int k = 0; k < 3; ++k)
    {
      const slod::Index u = tri[k], v = tri[(k + 1) % 3];
      const slod::Vec3 now = mesh.Point(u) - mesh.Point(v), before = detailed.Point(u) - detailed.Point(v);
      const double length2 = slod::Dot(now, now);
      if (length2 < slod::Dot(before, before) && (length2 < eps * eps || length2 == 0.0))
      {
        groups.Union(u, v);
      }
    }
  }
  std::vector<slod::Index> representative(size_t(detailed.NumberOfPoints()));
  for (slod::Index h = 0; h < detailed.NumberOfPoints(); ++h)
  {
    representative[h] = groups.Find(h);
  }
  return representative;
}

// The output connectivity: the detailed triangles over the merged vertices, less those that
// degenerate. kept[i] is the detailed triangle that mesh triangle i is; returns the removed count.
vtkIdType AddMergedTriangles(const slod::TriangleMesh& detailed, const std::vector<slod::Index>& groups,
  slod::TriangleMesh& mesh, std::vector<slod::Index>& kept)
{
  vtkIdType removed = 0;
  for (slod::Index f = 0; f < detailed.NumberOfTriangles(); ++f)
  {
    const slod::Index* tri = detailed.Triangle(f);
    const slod::Index a = groups[tri[0]], b = groups[tri[1]], c = groups[tri[2]];
    if (a == b || b == c || c == a)
    {
      ++removed;
      continue;
    }
    mesh.AddTriangle(a, b, c);
    kept.push_back(f);
  }
  return removed;
}
} // namespace

int vtkLODInterpolation::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 2)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
  }
  return this->Superclass::FillInputPortInformation(port, info);
}

int vtkLODInterpolation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  using namespace slod; // Vec3 operators
  vtkPolyData* detailedInput = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* coarseInput = vtkPolyData::GetData(inputVector[1], 0);
  vtkTable* records = vtkTable::GetData(inputVector[2], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->MergedVertices = 0;
  this->RemovedTriangles = 0;
  this->UsedCollapseRecords = records != nullptr;
  if (!detailedInput || !coarseInput || !output)
  {
    vtkErrorMacro(<< "Needs the detailed mesh (port 0) and the coarse mesh (port 1).");
    return 1;
  }

  slod::TriangleMesh detailed, coarse;
  std::vector<slod::Index> detailedToInput, coarseToInput, detailedTriangleToCell;
  if (!slod::PrepareFilterInput(this, detailedInput, slod::PreparationOptions(), detailed, detailedToInput, nullptr,
        slod::CellMapIfNeeded(detailedInput, detailedTriangleToCell)) ||
    !slod::PrepareFilterInput(this, coarseInput, slod::PreparationOptions(), coarse, coarseToInput))
  {
    return 1;
  }
  const slod::Index nh = detailed.NumberOfPoints(), nl = coarse.NumberOfPoints();
  if (detailed.NumberOfTriangles() == 0 || nl == 0)
  {
    return 1;
  }

  std::vector<slod::Index> match;
  if (records)
  {
    const char* error = MatchThroughRecords(records, detailedInput, detailedToInput, nh, coarseInput, coarseToInput, nl, match);
    if (!error && !ImageIsCoarse(detailed, coarse, match))
    {
      error = "The records do not turn the detailed mesh into the coarse mesh.";
    }
    if (error)
    {
      vtkErrorMacro(<< error);
      return 1;
    }
  }
  else
  {
    match = MatchToCoarse(detailed, coarse);
  }

  // Step 3: linear interpolation ((1 - t) * P_h + t * P_l is P_h at t = 0 and P_l at t = 1 exactly).
  const double t = this->T;
  slod::TriangleMesh mesh;
  mesh.Points.resize(3 * size_t(nh));
  for (slod::Index h = 0; h < nh; ++h)
  {
    mesh.SetPoint(h, (1.0 - t) * detailed.Point(h) + t * coarse.Point(match[h]));
  }
  const std::vector<slod::Index> groups = records
    ? MergeCoincidentAncestries(mesh, match, nl)
    : MergeShrunkEdges(detailed, mesh, this->Epsilon * detailed.BoundingBoxDiagonal());
  for (slod::Index h = 0; h < nh; ++h)
  {
    this->MergedVertices += groups[h] != h ? 1 : 0;
  }
  std::vector<slod::Index> keptTriangles;
  this->RemovedTriangles = AddMergedTriangles(detailed, groups, mesh, keptTriangles);
  std::vector<slod::Index> newToOld;
  mesh.RemoveUnusedPoints(&newToOld);

  const int pointType = detailedInput->GetPoints() && detailedInput->GetPoints()->GetDataType() == VTK_DOUBLE ? VTK_DOUBLE : VTK_FLOAT;
  slod::MeshToPolyData(mesh, output, pointType);
  slod::PointAttributes attributes;
  attributes.Load(detailedInput->GetPointData(), detailedToInput);
  attributes.Store(output->GetPointData(), newToOld);
  // Each triangle is a detailed triangle that did not degenerate: it keeps its own cell data.
  slod::StoreCellData(detailedInput, detailedTriangleToCell, keptTriangles, output);
  return 1;
}

void vtkLODInterpolation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "T: " << this->T << "\n";
  os << indent << "Epsilon: " << this->Epsilon << "\n";
  os << indent << "MergedVertices: " << this->MergedVertices << "\n";
  os << indent << "RemovedTriangles: " << this->RemovedTriangles << "\n";
  os << indent << "UsedCollapseRecords: " << this->UsedCollapseRecords << "\n";
}
