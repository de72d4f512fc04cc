// SPDX-License-Identifier: BSD-3-Clause
#include "vtkLODInterpolation.h"

#include "slodAttributeTransfer.h"
#include "slodInputPreparation.h"
#include "slodPointAttributes.h"
#include "slodUnionFind.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStaticPointLocator.h"

#include <limits>

vtkStandardNewMacro(vtkLODInterpolation);

vtkLODInterpolation::vtkLODInterpolation()
{
  this->SetNumberOfInputPorts(2);
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

// Step 4: merges the ends of the detailed edges shorter than eps in the morphed mesh (the smaller
// id represents a group) and adds the triangles that do not degenerate. An edge whose two ends
// sit on their coarse matches already does not move: it is detail the coarse mesh shares, and
// merging it would drop triangles as soon as T leaves 0 (all of a mesh made of triangles smaller
// than epsilon, e.g. many small components). Returns the merges; removed counts the dropped
// triangles, kept[i] is the detailed triangle that mesh triangle i is.
vtkIdType MergeShortEdges(const slod::TriangleMesh& detailed, const slod::TriangleMesh& coarse,
  const std::vector<slod::Index>& match, double eps, slod::TriangleMesh& mesh, vtkIdType& removed,
  std::vector<slod::Index>& kept)
{
  auto staysInPlace = [&](slod::Index h) { return coarse.Point(match[h]) == detailed.Point(h); };
  slod::UnionFind groups(detailed.NumberOfPoints());
  vtkIdType merged = 0;
  for (slod::Index f = 0; f < detailed.NumberOfTriangles(); ++f)
  {
    const slod::Index* tri = detailed.Triangle(f);
    for (int k = 0; k < 3; ++k)
    {
      const slod::Index u = tri[k], v = tri[(k + 1) % 3];
      const slod::Vec3 d = mesh.Point(u) - mesh.Point(v);
      if (slod::Dot(d, d) < eps * eps && !(staysInPlace(u) && staysInPlace(v)) && groups.Union(u, v))
      {
        ++merged;
      }
    }
  }
  removed = 0;
  for (slod::Index f = 0; f < detailed.NumberOfTriangles(); ++f)
  {
    const slod::Index* tri = detailed.Triangle(f);
    const slod::Index a = groups.Find(tri[0]), b = groups.Find(tri[1]), c = groups.Find(tri[2]);
    if (a == b || b == c || c == a)
    {
      ++removed;
      continue;
    }
    mesh.AddTriangle(a, b, c);
    kept.push_back(f);
  }
  return merged;
}
} // namespace

int vtkLODInterpolation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  using namespace slod; // Vec3 operators
  vtkPolyData* detailedInput = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* coarseInput = vtkPolyData::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->MergedVertices = 0;
  this->RemovedTriangles = 0;
  if (!detailedInput || !coarseInput || !output)
  {
    vtkErrorMacro(<< "Needs the detailed mesh (port 0) and the coarse mesh (port 1).");
    return 1;
  }
  // The ends of the morph are the inputs themselves.
  if (this->T <= 0.0)
  {
    output->ShallowCopy(detailedInput);
    return 1;
  }
  if (this->T >= 1.0)
  {
    output->ShallowCopy(coarseInput);
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

  const std::vector<slod::Index> match = MatchToCoarse(detailed, coarse);

  // Step 3: linear interpolation.
  const double t = this->T;
  slod::TriangleMesh mesh;
  mesh.Points.resize(3 * size_t(nh));
  for (slod::Index h = 0; h < nh; ++h)
  {
    mesh.SetPoint(h, t * coarse.Point(match[h]) + (1.0 - t) * detailed.Point(h));
  }
  const double eps = this->Epsilon * detailed.BoundingBoxDiagonal();
  std::vector<slod::Index> keptTriangles;
  this->MergedVertices = MergeShortEdges(detailed, coarse, match, eps, mesh, this->RemovedTriangles, keptTriangles);
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
}
