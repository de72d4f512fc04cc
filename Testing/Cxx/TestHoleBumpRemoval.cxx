// Tests of the topology simplification of Ho 1999, chapter 5 (slodTopologySimplification and
// vtkHoleBumpRemoval): holes, bumps, cavities and cracks on programmatic block models (counted
// exactly), genus after removal, manifold and watertight output, triangle counts (a plate with
// holes becomes a 12-triangle box), the outer profile kept, features above alpha kept,
// determinism, bad input, and a comparison with vtkDecimatePro / vtkQuadricDecimation.
#include "TestSupport.h"

#include "slodBlockModel.h"
#include "slodMeshTopology.h"
#include "slodTopologySimplification.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkSurfaceDeviation.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDecimatePro.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkQuadricDecimation.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>

using namespace slod;

namespace
{
MeshStatistics Stats(const TriangleMesh& mesh)
{
  TriangleMesh copy = mesh;
  copy.RemoveUnusedPoints();
  return MeshTopology(copy).Statistics(copy);
}

TriangleMesh ResultMesh(const TriangleMesh& input, const TopologySimplificationResult& result)
{
  TriangleMesh out;
  out.Points = input.Points;
  out.Triangles = result.Triangles;
  out.RemoveUnusedPoints();
  return out;
}

void ExpectClosedManifold(const MeshStatistics& s)
{
  EXPECT_EQ(s.BoundaryEdges, 0);
  EXPECT_EQ(s.NonManifoldEdges, 0);
  EXPECT_EQ(s.NonManifoldVertices, 0);
  EXPECT_EQ(s.InconsistentlyOrientedEdges, 0);
  EXPECT_EQ(s.DegenerateTriangles, 0);
}

// Heights of a (2k+1) x (2k+1) plate: `value` at the odd cells.
std::vector<double> PlateHeights(int k, double plate, double value)
{
  const int n = 2 * k + 1;
  std::vector<double> h(size_t(n) * n, plate);
  for (int j = 1; j < n; j += 2)
  {
    for (int i = 1; i < n; i += 2)
    {
      h[size_t(i) + size_t(n) * j] = value;
    }
  }
  return h;
}
} // namespace

TEST(BlockModel, PlateWithHolesIsClosedWithGenusEqualToHoles)
{
  const TriangleMesh plate = PlateWithHoles(3, 2, 0.5, 2);
  const MeshStatistics s = Stats(plate);
  ExpectClosedManifold(s);
  EXPECT_EQ(s.Components, 1);
  EXPECT_EQ(s.Genus, 6);
}

TEST(TopologySimplification, PlateHolesRemovedDownToTwelveTriangles)
{
  const TriangleMesh plate = PlateWithHoles(3, 3, 0.5, 2);
  TopologySimplificationParameters p;
  p.MaximumFeatureSize = 2.0; // holes are 1 x 1 (diameter ~1.41), the plate 7 x 7
  TopologySimplificationResult r;
  ASSERT_TRUE(TopologySimplifier().Run(plate, p, r));
  EXPECT_EQ(r.Detected[int(TopologyFeatureKind::Hole)], 9);
  EXPECT_EQ(r.Removed[int(TopologyFeatureKind::Hole)], 9);
  EXPECT_EQ(r.Detected[int(TopologyFeatureKind::Bump)], 0);
  EXPECT_EQ(r.Detected[int(TopologyFeatureKind::Cavity)], 0);
  const MeshStatistics s = Stats(ResultMesh(plate, r));
  ExpectClosedManifold(s);
  EXPECT_EQ(s.Genus, 0);
  EXPECT_EQ(s.Triangles, 12);
  EXPECT_EQ(r.MergedPatches, 6);
}
