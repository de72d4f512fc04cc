// SPDX-License-Identifier: BSD-3-Clause
// vtkQuadricTriangleCollapse on the pieces of a surface spread over MPI processes (run by
// `mpiexec -n N`, ctest label `mpi`). Each process takes its piece with VTK's own piece extraction
// (vtkExtractPolyDataPiece, one layer of ghost cells) or the tool's Morton split, simplifies it,
// and rank 0 gathers the pieces and checks the union against the input and against the
// single-process result: no crack (no open seam edge, no non-manifold edge), the same Euler
// characteristic and border loops, the triangle count within 1% of the target.
#include "Distributed.h"
#include "TestSupport.h"

#include "slodMeshTopology.h"
#include "slodPieceSeams.h"
#include "vtkQuadricTriangleCollapse.h"
#include "vtkSurfaceDeviation.h"

#include "vtkExtractPolyDataPiece.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>

using namespace slod;

namespace
{
constexpr double Reduction = 0.9;
using Position = std::array<double, 3>;
using PositionEdge = std::pair<Position, Position>;

PositionEdge EdgeOfPositions(const TriangleMesh& mesh, Index u, Index v)
{
  const Vec3 a = mesh.Point(u), b = mesh.Point(v);
  const Position pa{ a[0], a[1], a[2] }, pb{ b[0], b[1], b[2] };
  return pa < pb ? PositionEdge{ pa, pb } : PositionEdge{ pb, pa };
}

// The border edges of a mesh, by the positions of their ends.
std::set<PositionEdge> BorderEdges(const TriangleMesh& mesh)
{
  const MeshTopology topology(mesh);
  std::set<PositionEdge> border;
  for (Index e = 0; e < topology.NumberOfEdges(); ++e)
  {
    if (topology.IsBoundaryEdge(e))
    {
      border.insert(EdgeOfPositions(mesh, topology.EdgeVertex(e, 0), topology.EdgeVertex(e, 1)));
    }
  }
  return border;
}

// Positions held by two or more of the simplified pieces: the seam vertices.
std::set<Position> SeamPositions(const std::vector<vtkSmartPointer<vtkDataObject>>& pieces)
{
  std::map<Position, int> pieceCount;
  for (const auto& object : pieces)
  {
    const TriangleMesh piece = slodtest::RawTriangleMesh(vtkPolyData::SafeDownCast(object));
    std::set<Position> mine;
    for (Index v = 0; v < piece.NumberOfPoints(); ++v)
    {
      const Vec3 p = piece.Point(v);
      mine.insert({ p[0], p[1], p[2] });
    }
    for (const Position& p : mine)
    {
      ++pieceCount[p];
    }
  }
  std::set<Position> seam;
  for (const auto& entry : pieceCount)
  {
    if (entry.second > 1)
    {
      seam.insert(entry.first);
    }
  }
  return seam;
}

// Border edges of the union between two seam vertices that the input does not have on its border:
// the two sides of the seam did not meet there (a crack).
int OpenSeamEdges(const TriangleMesh& merged, const std::set<Position>& seam, const std::set<PositionEdge>& inputBorder)
{
  int open = 0;
  for (const PositionEdge& edge : BorderEdges(merged))
  {
    open += (seam.count(edge.first) && seam.count(edge.second) && !inputBorder.count(edge)) ? 1 : 0;
  }
  return open;
}

double Hausdorff(vtkPolyData* reference, vtkPolyData* compared)
{
  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceData(reference);
  deviation->SetComparedData(compared);
  deviation->Update();
  return deviation->GetHausdorffRelative();
}

vtkSmartPointer<vtkPolyData> SingleProcessResult(vtkPolyData* input)
{
  vtkNew<vtkQuadricTriangleCollapse> collapse;
  collapse->SetController(nullptr);
  collapse->SetInputData(input);
  collapse->SetTargetReduction(Reduction);
  collapse->Update();
  auto output = vtkSmartPointer<vtkPolyData>::New();
  output->ShallowCopy(collapse->GetOutput());
  return output;
}

// The simplified pieces of `input`, gathered on rank 0 (empty on the other ranks). VTK's piece
// extraction (with a layer of ghost cells) cuts by cell ids: coherent pieces for the isosurface, made
// slice by slice; a CGAL mesh's cells are not in a spatial order, so the tool's Morton split cuts it.
std::vector<vtkSmartPointer<vtkDataObject>> SimplifiedPieces(
  vtkMultiProcessController* controller, vtkPolyData* input, bool byVTKPieceExtraction)
{
  const int rank = controller->GetLocalProcessId(), processes = controller->GetNumberOfProcesses();
  vtkNew<vtkExtractPolyDataPiece> extraction;
  vtkNew<vtkQuadricTriangleCollapse> collapse;
  if (byVTKPieceExtraction)
  {
    extraction->SetInputData(input);
    collapse->SetInputConnection(extraction->GetOutputPort());
  }
  else
  {
    collapse->SetInputData(slodcli::SplitIntoPieces(input, processes)[rank]);
  }
  collapse->SetTargetReduction(Reduction);
  collapse->UpdatePiece(rank, processes, /*ghostLevels=*/1);
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  controller->Gather(collapse->GetOutput(), pieces, 0);
  return pieces;
}

struct UnionMeasures
{
  MeshStatistics Input, Union, OneProcess;
  size_t SeamVertices = 0;
  int OpenSeamEdges = 0;
  double Target = 0, Hausdorff = 0, OneProcessHausdorff = 0;
};

UnionMeasures MeasureUnion(const char* name, vtkPolyData* input, const std::vector<vtkSmartPointer<vtkDataObject>>& pieces)
{
  UnionMeasures m;
  const TriangleMesh prepared = slodtest::ToTriangleMesh(input);
  m.Input = ComputeMeshStatistics(prepared);
  vtkSmartPointer<vtkPolyData> merged = slodcli::MergePieces(pieces);
  const TriangleMesh unionMesh = slodtest::RawTriangleMesh(merged);
  m.Union = ComputeMeshStatistics(unionMesh);
  vtkSmartPointer<vtkPolyData> single = SingleProcessResult(input);
  m.OneProcess = ComputeMeshStatistics(slodtest::RawTriangleMesh(single));
  const std::set<Position> seam = SeamPositions(pieces);
  m.SeamVertices = seam.size();
  m.OpenSeamEdges = OpenSeamEdges(unionMesh, seam, BorderEdges(prepared));
  m.Target = std::floor((1.0 - Reduction) * double(m.Input.Triangles) + 1e-6);
  m.Hausdorff = Hausdorff(input, merged);
  m.OneProcessHausdorff = Hausdorff(input, single);
  std::printf("[distributed] %s on %d pieces: %d -> %d triangles (target %.0f, one process %d), seam %zu "
              "vertices, open seam edges %d, Euler %lld/%lld, loops %d/%d, Hausdorff %.4e (one process %.4e)\n",
    name, int(pieces.size()), int(m.Input.Triangles), int(m.Union.Triangles), m.Target, int(m.OneProcess.Triangles),
    m.SeamVertices, m.OpenSeamEdges, m.Union.EulerCharacteristic, m.Input.EulerCharacteristic,
    int(m.Union.BoundaryLoops), int(m.Input.BoundaryLoops), m.Hausdorff, m.OneProcessHausdorff);
  return m;
}

void ExpectCrackFreeOnTarget(const UnionMeasures& m)
{
  // EXPECT, not ASSERT: a union without any seam (pieces simplified apart) still reports its cracks.
  EXPECT_GT(m.SeamVertices, 10u) << "the pieces share no seam: nothing was tested";
  EXPECT_EQ(m.OpenSeamEdges, 0);
  EXPECT_EQ(m.Union.NonManifoldEdges, m.Input.NonManifoldEdges);
  EXPECT_EQ(m.Union.NonManifoldEdges, m.OneProcess.NonManifoldEdges);
  EXPECT_EQ(m.Union.NonManifoldVertices, m.Input.NonManifoldVertices);
  EXPECT_EQ(m.Union.EulerCharacteristic, m.Input.EulerCharacteristic);
  EXPECT_EQ(m.Union.EulerCharacteristic, m.OneProcess.EulerCharacteristic);
  EXPECT_EQ(m.Union.BoundaryLoops, m.Input.BoundaryLoops);
  EXPECT_EQ(m.Union.BoundaryLoops, m.OneProcess.BoundaryLoops);
  EXPECT_LE(std::fabs(double(m.Union.Triangles) - m.Target), 0.01 * m.Target);
}

vtkMultiProcessController* Controller()
{
  vtkMultiProcessController* controller = slodcli::DistributedController();
  EXPECT_NE(controller, nullptr) << "run under mpiexec with 2 or more processes";
  return controller;
}

class DistributedTriangleCollapse : public ::testing::TestWithParam<std::string>
{
};

// The distance is measured and printed, not asserted: the seams stay at full resolution, so the rest
// of each piece is coarser and the Hausdorff distance is larger than one process's (1.1-1.3x at 2
// pieces, up to 5x at 4 pieces of the 50,000-triangle isosurface whose seams hold a third of the
// output's vertices; Documentation/Distributed.md).
TEST_P(DistributedTriangleCollapse, UnionIsCrackFreeAndOnTarget)
{
  vtkMultiProcessController* controller = Controller();
  ASSERT_NE(controller, nullptr);
  const bool isosurface = GetParam() == "synthetic-isosurface";
  vtkSmartPointer<vtkPolyData> input = isosurface ? slodtest::SyntheticIsosurface(112) : slodtest::LoadTestMesh(GetParam());
  const auto pieces = SimplifiedPieces(controller, input, isosurface);
  if (controller->GetLocalProcessId() == 0)
  {
    const UnionMeasures m = MeasureUnion(GetParam().c_str(), input, pieces);
    EXPECT_EQ(m.Input.NonManifoldEdges, 0); // these inputs are manifold: so must the union be
    ExpectCrackFreeOnTarget(m);
  }
}

// Two closed, bumpy lenses, one inside the other, sharing their rim: every rim edge has four
// triangles (one per cap), two sheets. `lensOfTriangle` and `columnOfTriangle` say where each triangle
// lies (lens 0 or 1; column 0..rimVertices-1 around the axis). Euler characteristic 4 (two spheres
// glued along a circle); nothing is symmetric, so the caps' quadrics differ along the rim.
struct TwoLenses
{
  TriangleMesh Mesh;
  std::vector<int> LensOfTriangle, ColumnOfTriangle;
};

TwoLenses TwoLensesSharingTheirRim(int rimVertices, int rings)
{
  constexpr double Pi = 3.14159265358979323846;
  TwoLenses lenses;
  TriangleMesh& mesh = lenses.Mesh;
  const auto rimRadius = [](double phi) { return 1.0 + 0.15 * std::cos(3 * phi); };
  const auto rimHeight = [](double phi) { return 0.12 * std::sin(2 * phi); };
  for (int j = 0; j < rimVertices; ++j)
  {
    const double phi = 2 * Pi * j / rimVertices;
    mesh.AddPoint({ rimRadius(phi) * std::cos(phi), rimRadius(phi) * std::sin(phi), rimHeight(phi) });
  }
  const double capHeights[4] = { 0.35, -0.35, 0.7, -0.7 }; // lens 0: caps 0, 1; lens 1 around it: 2, 3
  for (int cap = 0; cap < 4; ++cap)
  {
    const double c = capHeights[cap];
    // Ring i (1..rings-1) at s = i/rings; ring 0 is the cap's centre, ring `rings` the shared rim.
    const Index centre = mesh.AddPoint({ 0.0, 0.0, c });
    const Index first = mesh.NumberOfPoints();
    for (int i = 1; i < rings; ++i)
    {
      const double s = double(i) / rings;
      for (int j = 0; j < rimVertices; ++j)
      {
        const double phi = 2 * Pi * j / rimVertices;
        const double z = rimHeight(phi) * s * s + c * (1 - s * s) * (1 + 0.15 * s * std::sin(4 * phi + cap));
        mesh.AddPoint({ s * rimRadius(phi) * std::cos(phi), s * rimRadius(phi) * std::sin(phi), z });
      }
    }
    const auto ringPoint = [&](int i, int j) -> Index {
      j %= rimVertices;
      return i == 0 ? centre : (i == rings ? Index(j) : first + Index(i - 1) * rimVertices + j);
    };
    const auto add = [&](Index a, Index b, Index d, int column) {
      // Outward: counter-clockwise seen from above on the upper caps, clockwise on the lower ones.
      if (c > 0)
        mesh.AddTriangle(a, b, d);
      else
        mesh.AddTriangle(a, d, b);
      lenses.LensOfTriangle.push_back(cap / 2);
      lenses.ColumnOfTriangle.push_back(column);
    };
    for (int j = 0; j < rimVertices; ++j)
    {
      add(centre, ringPoint(1, j), ringPoint(1, j + 1), j);
      for (int i = 1; i < rings; ++i)
      {
        add(ringPoint(i, j), ringPoint(i + 1, j), ringPoint(i + 1, j + 1), j);
        add(ringPoint(i, j), ringPoint(i + 1, j + 1), ringPoint(i, j + 1), j);
      }
    }
  }
  return lenses;
}

// The triangles of `mesh` that `pieceOf` gives to `rank` (over all of `mesh`'s points: the filter's
// input preparation drops the unused ones).
vtkSmartPointer<vtkPolyData> PieceOfMesh(const TriangleMesh& mesh, int rank, const std::function<int(Index)>& pieceOf)
{
  TriangleMesh piece;
  piece.Points = mesh.Points;
  for (Index t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    if (pieceOf(t) == rank)
    {
      const Index* v = mesh.Triangle(t);
      piece.AddTriangle(v[0], v[1], v[2]);
    }
  }
  return slodtest::ToPolyData(piece);
}

// Simplifies this process's piece (`pieceOf(rank, processes)`); the simplified pieces gathered on
// rank 0 (empty elsewhere).
std::vector<vtkSmartPointer<vtkDataObject>> SimplifiedPiecesOf(
  vtkMultiProcessController* controller, const std::function<vtkSmartPointer<vtkPolyData>(int, int)>& pieceOf)
{
  vtkNew<vtkQuadricTriangleCollapse> collapse;
  collapse->SetInputData(pieceOf(controller->GetLocalProcessId(), controller->GetNumberOfProcesses()));
  collapse->SetTargetReduction(Reduction);
  collapse->Update();
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  controller->Gather(collapse->GetOutput(), pieces, 0);
  return pieces;
}

// This process's piece of the lenses: the two lenses never share a piece, so the rim's two sheets
// are in different pieces everywhere. With 2 processes each piece is a closed lens (no border at
// all); with 4, each lens is also cut in two halves around the axis.
vtkSmartPointer<vtkPolyData> LensPiece(const TwoLenses& lenses, int rank, int processes)
{
  const int sectors = std::max(1, processes / 2);
  const int rimVertices = lenses.ColumnOfTriangle.empty() ? 1 : 1 + *std::max_element(
    lenses.ColumnOfTriangle.begin(), lenses.ColumnOfTriangle.end());
  return PieceOfMesh(lenses.Mesh, rank, [&](Index t) {
    return lenses.LensOfTriangle[t] * sectors + lenses.ColumnOfTriangle[t] * sectors / rimVertices;
  });
}

// The sheets of a non-manifold edge in different pieces: there the edge is interior (or, with 4
// pieces, partly on a border) on both sides, so only a seam found from every shared point, not only
// from the pieces' borders, keeps the rim whole. Without it each lens's rim is simplified on its own
// and the union loses non-manifold edges and opens cracks.
TEST(DistributedTriangleCollapse, NonManifoldRimSplitBetweenPiecesStaysWhole)
{
  vtkMultiProcessController* controller = Controller();
  ASSERT_NE(controller, nullptr);
  const TwoLenses lenses = TwoLensesSharingTheirRim(160, 40);
  const auto pieces =
    SimplifiedPiecesOf(controller, [&](int rank, int processes) { return LensPiece(lenses, rank, processes); });
  if (controller->GetLocalProcessId() == 0)
  {
    vtkSmartPointer<vtkPolyData> input = slodtest::ToPolyData(lenses.Mesh);
    const UnionMeasures m = MeasureUnion("two-lenses", input, pieces);
    ASSERT_EQ(m.Input.NonManifoldEdges, 160); // the construction: every rim edge has 4 triangles
    ASSERT_EQ(m.Input.EulerCharacteristic, 4);
    ASSERT_EQ(m.Input.BoundaryLoops, 0);
    EXPECT_EQ(m.Union.Components, m.Input.Components);
    ExpectCrackFreeOnTarget(m);
  }
}

// The seam finder against the truth every process can compute from all the pieces (the Morton split
// is deterministic): the vertices it marks are exactly those whose position another piece holds, and
// it exchanged only the band of positions along the cuts, not every vertex (the occupancy grid).
TEST(DistributedTriangleCollapse, SeamIsExactAndOnlyTheBandIsExchanged)
{
  vtkMultiProcessController* controller = Controller();
  ASSERT_NE(controller, nullptr);
  const int rank = controller->GetLocalProcessId(), processes = controller->GetNumberOfProcesses();
  const auto pieces = slodcli::SplitIntoPieces(slodtest::LoadTestMesh("bunny00"), processes);
  std::vector<vtkSmartPointer<vtkDataObject>> objects(pieces.begin(), pieces.end());
  std::set<Position> others; // positions of every other piece
  for (int r = 0; r < processes; ++r)
  {
    if (r != rank)
    {
      const TriangleMesh piece = slodtest::RawTriangleMesh(pieces[r]);
      for (Index v = 0; v < piece.NumberOfPoints(); ++v)
      {
        const Vec3 p = piece.Point(v);
        others.insert({ p[0], p[1], p[2] });
      }
    }
  }
  const TriangleMesh mine = slodtest::RawTriangleMesh(pieces[rank]);
  const PieceSeam seam = FindPieceSeam(mine, controller);
  Index expectedShared = 0, mismatches = 0;
  for (Index v = 0; v < mine.NumberOfPoints(); ++v)
  {
    const Vec3 p = mine.Point(v);
    const bool shared = others.count({ p[0], p[1], p[2] }) > 0;
    expectedShared += shared;
    mismatches += shared != (seam.SharedVertices[v] != 0);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(seam.SharedVertexCount, expectedShared);
  EXPECT_GT(expectedShared, 0);
  // The exchanged positions include the shared ones and stay a small part of the piece (a band about
  // one grid cell wide on each side of the cuts; every vertex was sent before the grid).
  EXPECT_GE(seam.ExchangedPositions, expectedShared);
  EXPECT_LT(seam.ExchangedPositions, mine.NumberOfPoints() / 3);
  std::printf("[distributed] seam of piece %d: %lld shared, %lld of %lld positions exchanged\n", rank,
    static_cast<long long>(expectedShared), static_cast<long long>(seam.ExchangedPositions),
    static_cast<long long>(mine.NumberOfPoints()));
}

// The demo's isosurface (closed, genus 1), a closed CGAL scan and a CGAL mesh with two border loops.
INSTANTIATE_TEST_SUITE_P(Meshes, DistributedTriangleCollapse, ::testing::Values("synthetic-isosurface", "bunny00", "blade"));

// A height field over [0, 2] x [0, 1]: flat where x < 1, bumpy where x > 1 (continuous at x = 1).
// One process spends nearly the whole budget on the bumps; pieces that each took a share
// proportional to their size would leave the bumpy half with about half of that.
TriangleMesh FlatAndBumpyHalves(int columns, int rows)
{
  constexpr double Pi = 3.14159265358979323846;
  TriangleMesh mesh;
  for (int j = 0; j <= rows; ++j)
  {
    for (int i = 0; i <= columns; ++i)
    {
      const double x = 2.0 * i / columns, y = double(j) / rows;
      const double z = x <= 1.0 ? 0.0 : 0.04 * std::sin(5 * Pi * x) * std::sin(6 * Pi * y) * (1 + 0.5 * y);
      mesh.AddPoint({ x, y, z });
    }
  }
  const auto id = [columns](int i, int j) { return Index(j) * (columns + 1) + i; };
  for (int j = 0; j < rows; ++j)
  {
    for (int i = 0; i < columns; ++i)
    {
      mesh.AddTriangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.AddTriangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return mesh;
}

// This process's piece of the halves: the flat and the bumpy half in different pieces (with 4
// processes, each half also cut in two across y).
vtkSmartPointer<vtkPolyData> HalfPiece(const TriangleMesh& mesh, int rank, int processes)
{
  const int sectors = std::max(1, processes / 2);
  return PieceOfMesh(mesh, rank, [&](Index t) {
    const Index* v = mesh.Triangle(t);
    const Vec3 centroid = (1.0 / 3.0) * (mesh.Point(v[0]) + mesh.Point(v[1]) + mesh.Point(v[2]));
    const int sector = std::min(sectors - 1, static_cast<int>(centroid[1] * sectors));
    return (centroid[0] < 1.0 ? 0 : 1) * sectors + sector;
  });
}

// Pieces of very different detail: the union's target must go where one process would spend it
// (the pieces agree on it while collapsing, slod::UnionTargetAgreement). With fixed shares
// proportional to the pieces' sizes the Hausdorff distance was 2.7x one process's at 2 pieces and
// 3.0x at 4; agreed, 1.1x and 1.3x (the rest is the seam, kept at full resolution). The bound
// 1.5x lies between the two: it fails when the pieces stop agreeing.
TEST(DistributedTriangleCollapse, TargetGoesWhereTheDetailIs)
{
  vtkMultiProcessController* controller = Controller();
  ASSERT_NE(controller, nullptr);
  const TriangleMesh mesh = FlatAndBumpyHalves(240, 120);
  const auto pieces =
    SimplifiedPiecesOf(controller, [&](int rank, int processes) { return HalfPiece(mesh, rank, processes); });
  if (controller->GetLocalProcessId() == 0)
  {
    const UnionMeasures m = MeasureUnion("flat-and-bumpy", slodtest::ToPolyData(mesh), pieces);
    ExpectCrackFreeOnTarget(m);
    EXPECT_LE(m.Hausdorff, 1.5 * m.OneProcessHausdorff);
  }
}

} // namespace

int main(int argc, char** argv)
{
  const slodcli::MpiSession mpi(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  if (slodcli::ProcessRank() != 0)
  {
    // One report, from rank 0; the other ranks still fail the run through their exit code.
    delete ::testing::UnitTest::GetInstance()->listeners().Release(
      ::testing::UnitTest::GetInstance()->listeners().default_result_printer());
  }
  return RUN_ALL_TESTS();
}
