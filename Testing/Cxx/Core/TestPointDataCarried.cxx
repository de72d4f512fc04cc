// SPDX-License-Identifier: BSD-3-Clause
// Point data through every simplifier: a textured sphere (vtkTexturedSphereSource leaves its normals
// and texture coordinates unnamed) with a named scalar array. Every array comes out, named or not,
// with its attribute role; normals are unit length, texture coordinates stay in the input's range;
// the texture seam (coincident points with other coordinates) is never welded.
//
// Cell data through every filter (CellDataCarried below): a CAD mesh, as triangles and as
// triangle strips, with vtkIdFilter's cell ids, an integer region id and a float vector per cell,
// and integer point labels and ids. Every output triangle has every array (role, type and
// components kept), all of its values from one input cell, and lies next to the input triangles
// of its region; integer point arrays stay integers and ids are ids of the input.
#include "TestSupport.h"

#include "slodTriangleBVH.h"
#include "vtkLODInterpolation.h"
#include "vtkProgressiveMeshReconstruction.h"
#include "vtkRetileLevelInterpolation.h"

#include "vtkGreedyCutsSimplification.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkPatchBoundaryMerge.h"
#include "vtkQuadricTriangleCollapse.h"
#include "vtkRetile.h"
#include "vtkTriangleCollapseHierarchy.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkIdFilter.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStripper.h"
#include "vtkTable.h"
#include "vtkTexturedSphereSource.h"
#include "vtkTriangleFilter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <vector>

namespace
{
vtkSmartPointer<vtkPolyData> TexturedSphere()
{
  vtkNew<vtkTexturedSphereSource> source;
  source->SetThetaResolution(48);
  source->SetPhiResolution(48);
  source->Update();
  auto sphere = vtkSmartPointer<vtkPolyData>::New();
  sphere->DeepCopy(source->GetOutput());
  vtkNew<vtkDoubleArray> height;
  height->SetName("Height");
  height->SetNumberOfTuples(sphere->GetNumberOfPoints());
  for (vtkIdType i = 0; i < sphere->GetNumberOfPoints(); ++i)
  {
    height->SetValue(i, sphere->GetPoint(i)[2]);
  }
  sphere->GetPointData()->AddArray(height);
  return sphere;
}

void ExpectPointDataCarried(vtkPolyData* output)
{
  ASSERT_GT(output->GetNumberOfPolys(), 0);
  vtkPointData* pd = output->GetPointData();
  vtkDataArray* normals = pd->GetNormals();
  vtkDataArray* tcoords = pd->GetTCoords();
  ASSERT_NE(normals, nullptr) << "normals (unnamed in the input) lost";
  ASSERT_NE(tcoords, nullptr) << "texture coordinates (unnamed in the input) lost";
  ASSERT_NE(pd->GetArray("Height"), nullptr);
  EXPECT_EQ(normals->GetNumberOfComponents(), 3);
  EXPECT_EQ(tcoords->GetNumberOfComponents(), 2);
  EXPECT_EQ(normals->GetNumberOfTuples(), output->GetNumberOfPoints());
  EXPECT_EQ(tcoords->GetNumberOfTuples(), output->GetNumberOfPoints());
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i)
  {
    const double* n = normals->GetTuple3(i);
    EXPECT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0, 1e-5) << "normal " << i;
    for (int c = 0; c < 2; ++c)
    {
      EXPECT_GE(tcoords->GetComponent(i, c), -1e-6) << "point " << i;
      EXPECT_LE(tcoords->GetComponent(i, c), 1.0 + 1e-6) << "point " << i;
    }
  }
}

struct Simplifier
{
  const char* Name;
  std::function<vtkSmartPointer<vtkPolyDataAlgorithm>()> Make;
  // The seam is a border of the prepared input: filters that keep borders keep it open. The
  // triangle collapse also keeps the whole prepared topology and removes the zero-area triangles of
  // the poles (their corners are coincident copies with other texture coordinates).
  bool KeepsBorders;
  bool KeepsTopology;
};

template <class Filter>
vtkSmartPointer<vtkPolyDataAlgorithm> Reducing()
{
  auto filter = vtkSmartPointer<Filter>::New();
  filter->SetTargetReduction(0.75);
  return filter;
}
} // namespace

TEST(PointDataCarried, EveryArrayWithItsRoleAndTheSeamKept)
{
  const vtkSmartPointer<vtkPolyData> sphere = TexturedSphere();
  ASSERT_EQ(sphere->GetPointData()->GetNormals()->GetName(), nullptr) << "premise: unnamed normals";
  ASSERT_EQ(sphere->GetPointData()->GetTCoords()->GetName(), nullptr) << "premise: unnamed texture coordinates";
  const Simplifier simplifiers[] = {
    { "vtkQuadricTriangleCollapse", Reducing<vtkQuadricTriangleCollapse>, true, true },
    { "vtkTriangleCollapseHierarchy", Reducing<vtkTriangleCollapseHierarchy>, true, false },
    { "vtkPatchBoundaryMerge", Reducing<vtkPatchBoundaryMerge>, false, false },
    { "vtkGreedyCutsSimplification", Reducing<vtkGreedyCutsSimplification>, false, false },
    { "vtkHoleBumpRemoval", Reducing<vtkHoleBumpRemoval>, false, false },
    { "vtkRetile", Reducing<vtkRetile>, false, false },
  };
  for (const Simplifier& simplifier : simplifiers)
  {
    SCOPED_TRACE(simplifier.Name);
    vtkSmartPointer<vtkPolyDataAlgorithm> filter = simplifier.Make();
    vtkNew<slodtest::MessageCounter> messages;
    filter->AddObserver(vtkCommand::WarningEvent, messages);
    filter->AddObserver(vtkCommand::ErrorEvent, messages);
    filter->SetInputData(sphere);
    filter->Update();
    EXPECT_TRUE(messages->Errors.empty());
    ExpectPointDataCarried(filter->GetOutput());
    if (simplifier.KeepsTopology)
    {
      const slod::MeshStatistics in = slodtest::ExpectPreparedInputTopology(sphere, filter->GetOutput());
      EXPECT_GT(in.BoundaryEdges, 0) << "premise: the seam is a border of the prepared input";
    }
    if (simplifier.KeepsBorders)
    {
      // Welding the seam would close the surface.
      EXPECT_GT(slod::ComputeMeshStatistics(slodtest::ToTriangleMesh(filter->GetOutput())).BoundaryEdges, 0);
    }
  }
}

namespace
{
// Octant (0..7) of p around c: a region id whose regions are large, contiguous and meet along
// borders that cut through triangles at any angle.
int Octant(const double* p, const double* c)
{
  return (p[0] > c[0] ? 1 : 0) + (p[1] > c[1] ? 2 : 0) + (p[2] > c[2] ? 4 : 0);
}

void CellCentroid(vtkPolyData* mesh, vtkIdType cell, double centroid[3])
{
  vtkIdType n;
  const vtkIdType* ids;
  mesh->GetCellPoints(cell, n, ids);
  centroid[0] = centroid[1] = centroid[2] = 0;
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double* p = mesh->GetPoint(ids[k]);
    for (int c = 0; c < 3; ++c)
    {
      centroid[c] += p[c] / n;
    }
  }
}

// `surface` with vtkIdFilter's point and cell ids (vtkIdType scalars), per cell an int "Region"
// (octant of its centroid) and a float vector "Direction" (its centroid's unit direction from the
// centre, the cell vectors), per point an int "PointLabel" (octant) and int global ids.
vtkSmartPointer<vtkPolyData> WithCellAndPointData(vtkPolyData* surface)
{
  vtkNew<vtkIdFilter> ids;
  ids->SetInputData(surface);
  ids->PointIdsOn();
  ids->CellIdsOn();
  ids->Update();
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->DeepCopy(ids->GetOutput());
  const double* c = mesh->GetCenter();
  vtkNew<vtkIntArray> region;
  region->SetName("Region");
  vtkNew<vtkFloatArray> direction;
  direction->SetName("Direction");
  direction->SetNumberOfComponents(3);
  for (vtkIdType cell = 0; cell < mesh->GetNumberOfCells(); ++cell)
  {
    double centroid[3];
    CellCentroid(mesh, cell, centroid);
    region->InsertNextValue(Octant(centroid, c));
    double d[3] = { centroid[0] - c[0], centroid[1] - c[1], centroid[2] - c[2] };
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    direction->InsertNextTuple3(d[0] / length, d[1] / length, d[2] / length);
  }
  mesh->GetCellData()->AddArray(region);
  mesh->GetCellData()->SetVectors(direction);
  vtkNew<vtkIntArray> label;
  label->SetName("PointLabel");
  vtkNew<vtkIntArray> global;
  global->SetName("GlobalPointId");
  for (vtkIdType p = 0; p < mesh->GetNumberOfPoints(); ++p)
  {
    label->InsertNextValue(Octant(mesh->GetPoint(p), c));
    global->InsertNextValue(static_cast<int>(p));
  }
  mesh->GetPointData()->AddArray(label);
  mesh->GetPointData()->SetGlobalIds(global);
  return mesh;
}

vtkSmartPointer<vtkPolyData> AsStrips(vtkPolyData* triangles)
{
  vtkNew<vtkStripper> stripper;
  stripper->SetInputData(triangles);
  stripper->Update();
  auto strips = vtkSmartPointer<vtkPolyData>::New();
  strips->DeepCopy(stripper->GetOutput());
  return strips;
}

// The input's triangles with their cell data, as VTK triangulates polygons and strips (the
// reference the filters' triangles are compared to).
vtkSmartPointer<vtkPolyData> ReferenceTriangles(vtkPolyData* input)
{
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(input);
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  triangulate->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(triangulate->GetOutput());
  return out;
}

std::vector<double> Tuple(vtkDataArray* array, vtkIdType i)
{
  std::vector<double> t(size_t(array->GetNumberOfComponents()));
  array->GetTuple(i, t.data());
  return t;
}

// Every cell array of `input` on every output cell: name, type, components, role; each tuple one
// of the input's; all arrays of an output cell from the same input cell (its vtkIdFilter id).
void ExpectCellArraysFromOneInputCell(vtkPolyData* input, vtkPolyData* output)
{
  vtkCellData* in = input->GetCellData();
  vtkCellData* out = output->GetCellData();
  ASSERT_GT(output->GetNumberOfCells(), 0);
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* inArray = in->GetArray(a);
    SCOPED_TRACE(inArray->GetName());
    int index = -1;
    vtkDataArray* outArray = vtkDataArray::SafeDownCast(out->GetAbstractArray(inArray->GetName(), index));
    ASSERT_NE(outArray, nullptr) << "cell array lost";
    EXPECT_EQ(outArray->GetDataType(), inArray->GetDataType());
    EXPECT_EQ(outArray->GetNumberOfComponents(), inArray->GetNumberOfComponents());
    EXPECT_EQ(out->IsArrayAnAttribute(index), in->IsArrayAnAttribute(a)) << "attribute role lost";
    ASSERT_EQ(outArray->GetNumberOfTuples(), output->GetNumberOfCells());
  }
  vtkDataArray* outIds = out->GetArray("vtkIdFilter_Ids");
  ASSERT_NE(outIds, nullptr);
  for (vtkIdType cell = 0; cell < output->GetNumberOfCells(); ++cell)
  {
    const vtkIdType source = static_cast<vtkIdType>(outIds->GetComponent(cell, 0));
    ASSERT_GE(source, 0);
    ASSERT_LT(source, input->GetNumberOfCells());
    for (int a = 0; a < in->GetNumberOfArrays(); ++a)
    {
      vtkDataArray* outArray = out->GetArray(in->GetArrayName(a));
      ASSERT_EQ(Tuple(outArray, cell), Tuple(in->GetArray(a), source))
        << in->GetArrayName(a) << " of output cell " << cell << " is not input cell " << source << "'s";
    }
  }
}

// How close an output triangle of region r must lie to the input triangles of region r: the
// distance of its centroid to them exceeds its distance to the whole input by
enum class RegionRule
{
  Nearest,    // nothing: a re-triangulating filter takes the closest input triangle's cell
  Descendant, // at most twice its longest edge: a triangle that survived collapses spans the area
              // of its collapsed neighbours, so its centroid may sit that far from its original
  Fragment,   // at most twice the longest edge of the triangle it is a fragment of (that triangle
              // took the cell closest to its centroid; the fragment lies within it): the test's
              // cell array "ParentLongestEdge" gives it
  Morphed     // not measured (the morph moves it by design): its corners must be its cell's points
};

// Returns the largest excess relative to the input's bounding-box diagonal.
double ExpectRegionsNearTheirInputRegions(vtkPolyData* reference, vtkPolyData* output, RegionRule rule)
{
  using slod::operator-;
  vtkDataArray* inRegion = reference->GetCellData()->GetArray("Region");
  vtkDataArray* outRegion = output->GetCellData()->GetArray("Region");
  EXPECT_NE(outRegion, nullptr);
  if (!outRegion)
  {
    return 0;
  }
  std::map<int, slod::TriangleMesh> regionMeshes;
  const slod::TriangleMesh all = slodtest::RawTriangleMesh(reference);
  for (vtkIdType t = 0; t < reference->GetNumberOfCells(); ++t)
  {
    slod::TriangleMesh& m = regionMeshes[static_cast<int>(inRegion->GetComponent(t, 0))];
    const slod::Index* tri = all.Triangle(static_cast<slod::Index>(t));
    m.AddTriangle(m.AddPoint(all.Point(tri[0])), m.AddPoint(all.Point(tri[1])), m.AddPoint(all.Point(tri[2])));
  }
  std::map<int, std::unique_ptr<slod::TriangleBVH>> trees;
  for (auto& entry : regionMeshes)
  {
    trees[entry.first] = std::make_unique<slod::TriangleBVH>(entry.second);
  }
  const slod::TriangleBVH whole(all);
  std::set<int> inputRegions, outputRegions;
  for (const auto& entry : regionMeshes)
  {
    inputRegions.insert(entry.first);
  }
  double largest = 0;
  const slod::TriangleMesh out = slodtest::RawTriangleMesh(output);
  for (slod::Index t = 0; t < out.NumberOfTriangles(); ++t)
  {
    const int r = static_cast<int>(outRegion->GetComponent(t, 0));
    outputRegions.insert(r);
    if (!trees.count(r))
    {
      ADD_FAILURE() << "region " << r << " is not an input region";
      continue;
    }
    const slod::Index* tri = out.Triangle(t);
    const slod::Vec3 a = out.Point(tri[0]), b = out.Point(tri[1]), c = out.Point(tri[2]);
    const slod::Vec3 centroid{ (a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3 };
    const double longest = std::sqrt(std::max({ slod::Dot(a - b, a - b), slod::Dot(b - c, b - c), slod::Dot(c - a, c - a) }));
    const double excess = std::sqrt(trees[r]->ClosestPoint(centroid).Distance2) - std::sqrt(whole.ClosestPoint(centroid).Distance2);
    const double allowed = rule == RegionRule::Nearest ? 1e-12 * longest
      : rule == RegionRule::Fragment ? 2 * output->GetCellData()->GetArray("ParentLongestEdge")->GetComponent(t, 0)
                                     : 2 * longest;
    EXPECT_TRUE(rule == RegionRule::Morphed || excess <= allowed)
      << "output triangle " << t << " of region " << r << " is " << excess << " farther from that region than from the input" << " (allowed: " << allowed << ")";
    largest = std::max(largest, excess);
  }
  EXPECT_EQ(outputRegions, inputRegions) << "the set of region ids changed";
  return largest / all.BoundingBoxDiagonal();
}

// Per output point, its longest edge.
std::vector<double> LongestIncidentEdges(vtkPolyData* mesh)
{
  std::vector<double> longest(size_t(mesh->GetNumberOfPoints()), 0.0);
  for (vtkIdType t = 0; t < mesh->GetNumberOfCells(); ++t)
  {
    vtkIdType n;
    const vtkIdType* ids;
    mesh->GetCellPoints(t, n, ids);
    for (vtkIdType k = 0; k < n; ++k)
    {
      double p[3], q[3];
      mesh->GetPoint(ids[k], p);
      mesh->GetPoint(ids[(k + 1) % n], q);
      const double length = std::sqrt(vtkMath::Distance2BetweenPoints(p, q));
      longest[size_t(ids[k])] = std::max(longest[size_t(ids[k])], length);
      longest[size_t(ids[(k + 1) % n])] = std::max(longest[size_t(ids[(k + 1) % n])], length);
    }
  }
  return longest;
}

// Integer point arrays stay integer arrays; the ids (global ids, vtkIdFilter's) are ids of input
// points, both of the same point (a merged vertex takes its heaviest source's ids, never an
// average); filters that keep original vertices copy every point value of the vertex they keep.
// With idsNearby, that point lies within two of the vertex's longest edges (it is one of the
// vertices merged into it, or a corner of the input triangle it was placed on).
void ExpectIntegerPointArraysKept(vtkPolyData* input, vtkPolyData* output, bool originalVertices, bool idsNearby)
{
  vtkPointData* in = input->GetPointData();
  vtkPointData* out = output->GetPointData();
  vtkDataArray* label = out->GetArray("PointLabel");
  ASSERT_NE(label, nullptr);
  EXPECT_EQ(label->GetDataType(), VTK_INT);
  ASSERT_NE(out->GetGlobalIds(), nullptr) << "global ids lost (or their role)";
  EXPECT_EQ(out->GetGlobalIds()->GetDataType(), VTK_INT);
  vtkDataArray* pointIds = out->GetScalars();
  ASSERT_NE(pointIds, nullptr) << "vtkIdFilter's point ids lost (or their role)";
  const std::vector<double> incident = LongestIncidentEdges(output);
  EXPECT_EQ(pointIds->GetDataType(), VTK_ID_TYPE);
  for (vtkIdType p = 0; p < output->GetNumberOfPoints(); ++p)
  {
    const double g = out->GetGlobalIds()->GetComponent(p, 0), id = pointIds->GetComponent(p, 0);
    ASSERT_TRUE(g >= 0 && g < input->GetNumberOfPoints() && g == std::floor(g)) << "global id " << g;
    ASSERT_TRUE(id >= 0 && id < input->GetNumberOfPoints()) << "point id " << id;
    ASSERT_EQ(id, g) << "the two ids of output point " << p << " name different input points";
    const double l = label->GetComponent(p, 0);
    EXPECT_TRUE(l >= 0 && l <= 7) << "label " << l;
    if (idsNearby)
    {
      double q[3], r[3];
      input->GetPoint(static_cast<vtkIdType>(g), q);
      output->GetPoint(p, r);
      EXPECT_LE(std::sqrt(vtkMath::Distance2BetweenPoints(q, r)), 2 * incident[size_t(p)])
        << "output point " << p << " is far from input point " << g << " whose ids it has";
    }
    if (originalVertices)
    {
      const auto source = static_cast<vtkIdType>(g);
      EXPECT_EQ(l, in->GetArray("PointLabel")->GetComponent(source, 0));
      const double* q = input->GetPoint(source);
      const double* r = output->GetPoint(p);
      EXPECT_TRUE(q[0] == r[0] && q[1] == r[1] && q[2] == r[2]) << "point " << p << " is not input point " << source;
    }
  }
}

// Each output triangle's corners (by their global point ids) are points of the input cell whose
// data it carries: the triangle is that cell's, moved.
void ExpectCornersOfTheirCell(vtkPolyData* input, vtkPolyData* output)
{
  vtkDataArray* cellIds = output->GetCellData()->GetArray("vtkIdFilter_Ids");
  vtkDataArray* pointIds = output->GetPointData()->GetGlobalIds();
  ASSERT_TRUE(cellIds && pointIds);
  for (vtkIdType t = 0; t < output->GetNumberOfCells(); ++t)
  {
    vtkIdType n, m;
    const vtkIdType *corners, *cellPoints;
    output->GetCellPoints(t, n, corners);
    input->GetCellPoints(static_cast<vtkIdType>(cellIds->GetComponent(t, 0)), m, cellPoints);
    for (vtkIdType k = 0; k < n; ++k)
    {
      const auto corner = static_cast<vtkIdType>(pointIds->GetComponent(corners[k], 0));
      EXPECT_NE(std::find(cellPoints, cellPoints + m, corner), cellPoints + m)
        << "corner " << corner << " of output triangle " << t << " is not a point of its cell";
    }
  }
}

struct CellDataCase
{
  const char* Name;
  std::function<vtkSmartPointer<vtkPolyData>(vtkPolyData*)> Run;
  bool OriginalVertices;
  RegionRule Rule;
  bool PointData = true; // the filter carries the input's point data
};

template <class Filter>
vtkSmartPointer<vtkPolyData> RunReducing(vtkPolyData* input)
{
  auto filter = vtkSmartPointer<Filter>::New();
  filter->SetTargetReduction(0.75);
  filter->SetInputData(input);
  filter->Update();
  return filter->GetOutput();
}

vtkSmartPointer<vtkPolyData> RunLODInterpolation(vtkPolyData* input)
{
  vtkNew<vtkQuadricTriangleCollapse> coarse;
  coarse->SetTargetReduction(0.75);
  coarse->SetInputData(input);
  vtkNew<vtkLODInterpolation> morph;
  morph->SetInputData(0, input);
  morph->SetInputConnection(1, coarse->GetOutputPort());
  morph->SetT(0.5);
  morph->SetEpsilon(0); // no vertex merged: every triangle is one of the input's, moved
  morph->Update();
  return morph->GetOutput();
}

double LongestEdge(vtkPolyData* mesh, vtkIdType cell)
{
  vtkIdType n;
  const vtkIdType* ids;
  mesh->GetCellPoints(cell, n, ids);
  double longest = 0;
  for (vtkIdType k = 0; k < n; ++k)
  {
    double p[3], q[3];
    mesh->GetPoint(ids[k], p);
    mesh->GetPoint(ids[(k + 1) % n], q);
    longest = std::max(longest, std::sqrt(vtkMath::Distance2BetweenPoints(p, q)));
  }
  return longest;
}

// A coarse mesh of `input` (a quarter of its triangles) with its collapse records, and the filter
// that rebuilds the levels from them.
struct ProgressiveMesh
{
  vtkNew<vtkQuadricTriangleCollapse> Coarse;
  vtkNew<vtkProgressiveMeshReconstruction> Reconstruct;
  explicit ProgressiveMesh(vtkPolyData* input)
  {
    this->Coarse->SetTargetReduction(0.75);
    this->Coarse->GenerateProgressiveMeshOn();
    this->Coarse->SetInputData(input);
    this->Reconstruct->SetCoarseMeshConnection(this->Coarse->GetOutputPort(0));
    this->Reconstruct->SetRecordsConnection(this->Coarse->GetOutputPort(1));
  }
};

// Half way back from the coarse mesh to the input, with the original mesh on input 2.
vtkSmartPointer<vtkPolyData> RunProgressiveMeshReconstruction(vtkPolyData* input)
{
  ProgressiveMesh progressive(input);
  progressive.Reconstruct->SetInputData(2, input);
  progressive.Coarse->Update();
  progressive.Reconstruct->SetNumberOfVertexSplits(progressive.Coarse->GetCollapseRecords()->GetNumberOfRows() / 2);
  progressive.Reconstruct->Update();
  return progressive.Reconstruct->GetOutput();
}

// At T = 1 (the finer level's shape), with the test's "ParentLongestEdge" per fragment.
vtkSmartPointer<vtkPolyData> RunRetileLevelInterpolation(vtkPolyData* input)
{
  vtkNew<vtkRetile> retile;
  retile->SetTargetReduction(0.5);
  retile->GenerateNestedLevelsOn();
  retile->SetNumberOfNestedLevels(2);
  retile->SetInputData(input);
  retile->Update();
  vtkMultiBlockDataSet* levels = retile->GetNestedLevels();
  EXPECT_EQ(levels->GetNumberOfBlocks(), 2u);
  vtkNew<vtkRetileLevelInterpolation> blend;
  blend->SetInputData(0, vtkPolyData::SafeDownCast(levels->GetBlock(1)));
  blend->SetInputData(1, vtkPolyData::SafeDownCast(levels->GetBlock(0)));
  blend->SetT(1.0);
  blend->Update();
  vtkPolyData* high = vtkPolyData::SafeDownCast(levels->GetBlock(1));
  auto output = vtkSmartPointer<vtkPolyData>::New();
  output->ShallowCopy(blend->GetOutput());
  vtkDataArray* parents = output->GetCellData()->GetArray("HighTriangle");
  EXPECT_NE(parents, nullptr);
  vtkNew<vtkDoubleArray> parentEdge;
  parentEdge->SetName("ParentLongestEdge");
  for (vtkIdType t = 0; parents && t < output->GetNumberOfCells(); ++t)
  {
    parentEdge->InsertNextValue(LongestEdge(high, static_cast<vtkIdType>(parents->GetComponent(t, 0))));
  }
  output->GetCellData()->AddArray(parentEdge);
  return output;
}
} // namespace

TEST(CellDataCarried, EveryFilterEveryTriangleFromOneInputCellOfItsRegion)
{
  const vtkSmartPointer<vtkPolyData> fandisk = slodtest::LoadTestMesh("fandisk");
  const vtkSmartPointer<vtkPolyData> triangles = WithCellAndPointData(fandisk);
  const vtkSmartPointer<vtkPolyData> strips = WithCellAndPointData(AsStrips(fandisk));
  ASSERT_GT(strips->GetNumberOfStrips(), 0) << "premise: the second input is made of strips";
  ASSERT_EQ(strips->GetNumberOfPolys(), 0);
  const CellDataCase cases[] = {
    { "vtkQuadricTriangleCollapse", RunReducing<vtkQuadricTriangleCollapse>, false, RegionRule::Descendant },
    { "vtkTriangleCollapseHierarchy", RunReducing<vtkTriangleCollapseHierarchy>, false, RegionRule::Descendant },
    { "vtkPatchBoundaryMerge", RunReducing<vtkPatchBoundaryMerge>, true, RegionRule::Nearest },
    { "vtkGreedyCutsSimplification", RunReducing<vtkGreedyCutsSimplification>, true, RegionRule::Nearest },
    { "vtkHoleBumpRemoval", RunReducing<vtkHoleBumpRemoval>, true, RegionRule::Nearest },
    { "vtkRetile", RunReducing<vtkRetile>, false, RegionRule::Nearest },
    { "vtkLODInterpolation", RunLODInterpolation, false, RegionRule::Morphed },
    // Fragments of the finer level's triangles, which carry the input's nearest cells.
    { "vtkRetileLevelInterpolation", RunRetileLevelInterpolation, false, RegionRule::Fragment, false },
    { "vtkProgressiveMeshReconstruction", RunProgressiveMeshReconstruction, false, RegionRule::Descendant, false },
  };
  for (vtkPolyData* input : { triangles.Get(), strips.Get() })
  {
    SCOPED_TRACE(input == strips ? "strips" : "triangles");
    const vtkSmartPointer<vtkPolyData> reference = ReferenceTriangles(input);
    for (const CellDataCase& c : cases)
    {
      SCOPED_TRACE(c.Name);
      const vtkSmartPointer<vtkPolyData> output = c.Run(input);
      ExpectCellArraysFromOneInputCell(input, output);
      const double excess = ExpectRegionsNearTheirInputRegions(reference, output, c.Rule);
      if (c.Rule == RegionRule::Morphed)
      {
        ExpectCornersOfTheirCell(input, output);
      }
      std::cout << c.Name << (input == strips ? " (strips)" : "") << ": " << output->GetNumberOfCells()
                << " triangles, largest region excess distance " << excess << " of the diagonal\n";
      if (c.PointData)
      {
        ExpectIntegerPointArraysKept(input, output, c.OriginalVertices, c.Rule != RegionRule::Morphed);
      }
    }
  }
}

// Without the original mesh only the coarse triangles would have cell data: none is carried, and
// the filter says so.
TEST(CellDataCarried, ProgressiveMeshWithoutTheOriginalMeshWarns)
{
  const vtkSmartPointer<vtkPolyData> input = WithCellAndPointData(slodtest::LoadTestMesh("fandisk"));
  ProgressiveMesh progressive(input);
  vtkNew<slodtest::MessageCounter> messages;
  progressive.Reconstruct->AddObserver(vtkCommand::WarningEvent, messages);
  progressive.Reconstruct->Update();
  vtkPolyData* output = progressive.Reconstruct->GetOutput();
  EXPECT_GT(output->GetNumberOfCells(), progressive.Coarse->GetOutput()->GetNumberOfCells());
  EXPECT_EQ(output->GetCellData()->GetArray("Region"), nullptr);
  ASSERT_EQ(messages->Warnings.size(), 1u);
  EXPECT_NE(messages->Warnings[0].find("input 2"), std::string::npos) << messages->Warnings[0];
}
