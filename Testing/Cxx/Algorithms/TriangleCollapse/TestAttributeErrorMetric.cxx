// SPDX-License-Identifier: BSD-3-Clause
// vtkQuadricTriangleCollapse with AttributeErrorMetric (issue 13): at the same triangle count the
// texture coordinates and normals of the output are closer to the input's than without the metric
// (measured here, at the closest point of the input surface); a weight of 0 is the geometry of the
// metric off; linear attributes of a plane are reproduced exactly; the output does not depend on
// the thread count; the progressive records still rebuild the input exactly.
#include "TestSupport.h"

#include "vtkProgressiveMeshReconstruction.h"
#include "vtkQuadricTriangleCollapse.h"

#include "vtkCellLocator.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkGenericCell.h"
#include "vtkIdList.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace
{
struct Weights
{
  double TCoords = 0.1, Normals = 0.1, Scalars = 0.1;
};

vtkSmartPointer<vtkPolyData> Simplify(vtkPolyData* input, vtkIdType target, bool metric, Weights weights = Weights(),
  bool records = false, slodtest::MessageCounter* messages = nullptr)
{
  vtkNew<vtkQuadricTriangleCollapse> filter;
  filter->SetInputData(input);
  filter->SetTargetNumberOfTriangles(target);
  filter->SetAttributeErrorMetric(metric);
  filter->SetTCoordsWeight(weights.TCoords);
  filter->SetNormalsWeight(weights.Normals);
  filter->SetScalarsWeight(weights.Scalars);
  filter->SetGenerateProgressiveMesh(records);
  if (messages)
  {
    filter->AddObserver(vtkCommand::WarningEvent, messages);
  }
  vtkNew<vtkProgressiveMeshReconstruction> rebuild;
  if (records)
  {
    rebuild->SetCoarseMeshConnection(filter->GetOutputPort(0));
    rebuild->SetRecordsConnection(filter->GetOutputPort(1));
    rebuild->Update();
  }
  filter->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(records ? rebuild->GetOutput() : filter->GetOutput());
  return out;
}

double AngleDegrees(const double a[3], const double b[3])
{
  const double la = vtkMath::Norm(a), lb = vtkMath::Norm(b);
  if (!(la > 0) || !(lb > 0))
  {
    return 180.0;
  }
  return vtkMath::DegreesFromRadians(std::acos(std::max(-1.0, std::min(1.0, vtkMath::Dot(a, b) / (la * lb)))));
}

// Mean differences between the output's attributes and the input's at the closest point of the
// input surface, over the output's vertices and triangle centroids (attributes averaged there, as
// a renderer interpolates them): the (u, v) distance and the normals' angle in degrees. At a seam
// several input triangles are closest: the smallest difference counts.
struct AttributeError
{
  double TCoords = 0.0, NormalDegrees = 0.0;
};

class InputSurface
{
public:
  explicit InputSurface(vtkPolyData* input)
    : Input(input)
    , Tolerance(1e-9 * input->GetLength())
  {
    this->Locator->SetDataSet(input);
    this->Locator->BuildLocator();
  }

  // Differences at p of the output's (uv, n) (either may be null) from the input's.
  void Compare(const double p[3], const double* uv, const double* n, double& uvError, double& normalError)
  {
    double closest[3], dist2 = 0.0;
    vtkIdType cellId = -1;
    int subId = 0;
    this->Locator->FindClosestPoint(p, closest, cellId, subId, dist2);
    const double reach = std::sqrt(dist2) + this->Tolerance;
    double bounds[6] = { p[0] - reach, p[0] + reach, p[1] - reach, p[1] + reach, p[2] - reach, p[2] + reach };
    this->Locator->FindCellsWithinBounds(bounds, this->Ids);
    uvError = normalError = std::numeric_limits<double>::infinity();
    vtkDataArray* tcoords = this->Input->GetPointData()->GetTCoords();
    vtkDataArray* normals = this->Input->GetPointData()->GetNormals();
    for (vtkIdType k = 0; k < this->Ids->GetNumberOfIds(); ++k)
    {
      this->Input->GetCell(this->Ids->GetId(k), this->Cell);
      double pcoords[3], weights[3], d2 = 0.0;
      if (this->Cell->GetNumberOfPoints() != 3 ||
        this->Cell->EvaluatePosition(p, closest, subId, pcoords, d2, weights) < 0 || std::sqrt(d2) > reach)
      {
        continue;
      }
      double inUV[2] = { 0, 0 }, inN[3] = { 0, 0, 0 };
      for (int c = 0; c < 3; ++c)
      {
        const vtkIdType id = this->Cell->GetPointId(c);
        for (int j = 0; tcoords && j < 2; ++j)
        {
          inUV[j] += weights[c] * tcoords->GetComponent(id, j);
        }
        for (int j = 0; normals && j < 3; ++j)
        {
          inN[j] += weights[c] * normals->GetComponent(id, j);
        }
      }
      if (uv)
      {
        uvError = std::min(uvError, std::hypot(uv[0] - inUV[0], uv[1] - inUV[1]));
      }
      if (n)
      {
        normalError = std::min(normalError, AngleDegrees(n, inN));
      }
    }
  }

private:
  vtkPolyData* Input;
  double Tolerance;
  vtkNew<vtkCellLocator> Locator;
  vtkNew<vtkIdList> Ids;
  vtkNew<vtkGenericCell> Cell;
};

AttributeError MeanAttributeError(vtkPolyData* input, vtkPolyData* output)
{
  InputSurface surface(input);
  vtkDataArray* tcoords = output->GetPointData()->GetTCoords();
  vtkDataArray* normals = output->GetPointData()->GetNormals();
  AttributeError sum;
  size_t samples = 0;
  auto add = [&](const std::vector<vtkIdType>& ids) {
    double p[3] = { 0, 0, 0 }, uv[2] = { 0, 0 }, n[3] = { 0, 0, 0 };
    for (vtkIdType id : ids)
    {
      for (int j = 0; j < 3; ++j)
      {
        p[j] += output->GetPoint(id)[j] / double(ids.size());
        n[j] += normals ? normals->GetComponent(id, j) : 0.0;
      }
      for (int j = 0; tcoords && j < 2; ++j)
      {
        uv[j] += tcoords->GetComponent(id, j) / double(ids.size());
      }
    }
    double uvError = 0, normalError = 0;
    surface.Compare(p, tcoords ? uv : nullptr, normals ? n : nullptr, uvError, normalError);
    sum.TCoords += tcoords ? uvError : 0.0;
    sum.NormalDegrees += normals ? normalError : 0.0;
    ++samples;
  };
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i)
  {
    add({ i });
  }
  for (const auto& triangle : slodtest::CellPointIds(output->GetPolys()))
  {
    add(triangle);
  }
  EXPECT_GT(samples, 0u);
  sum.TCoords /= double(std::max<size_t>(samples, 1));
  sum.NormalDegrees /= double(std::max<size_t>(samples, 1));
  return sum;
}

double MeanDistance(vtkPolyData* input, vtkPolyData* output)
{
  return slodtest::RelativeDeviation(input, output).second;
}

std::vector<double> Values(vtkDataArray* array)
{
  std::vector<double> values;
  for (vtkIdType i = 0; array && i < array->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < array->GetNumberOfComponents(); ++c)
    {
      values.push_back(array->GetComponent(i, c));
    }
  }
  return values;
}

std::vector<double> PointsOf(vtkPolyData* mesh)
{
  return Values(mesh->GetPoints()->GetData());
}

} // namespace

// Fails without the metric: the collapse merges texture coordinates and normals by interpolation
// only, and chooses its collapses by geometry alone.
TEST(AttributeErrorMetric, TexturedSphereCloserAtEqualCount)
{
  for (int resolution : { 120, 160 })
  {
    SCOPED_TRACE(resolution);
    const vtkSmartPointer<vtkPolyData> sphere = slodtest::TexturedSphere(resolution);
    const vtkIdType target = sphere->GetNumberOfPolys() / 10;
    const vtkSmartPointer<vtkPolyData> off = Simplify(sphere, target, false);
    const vtkSmartPointer<vtkPolyData> on = Simplify(sphere, target, true);
    ASSERT_GT(on->GetNumberOfPolys(), target - 3);
    ASSERT_LE(on->GetNumberOfPolys(), target);
    ASSERT_GT(off->GetNumberOfPolys(), target - 3);
    const AttributeError eOff = MeanAttributeError(sphere, off), eOn = MeanAttributeError(sphere, on);
    EXPECT_LT(eOn.TCoords, 0.9 * eOff.TCoords) << "on " << eOn.TCoords << ", off " << eOff.TCoords;
    EXPECT_LT(eOn.NormalDegrees, 0.9 * eOff.NormalDegrees) << "on " << eOn.NormalDegrees << ", off " << eOff.NormalDegrees;
    // The normals are unit vectors again.
    vtkDataArray* normals = on->GetPointData()->GetNormals();
    ASSERT_NE(normals, nullptr);
    for (vtkIdType i = 0; i < normals->GetNumberOfTuples(); ++i)
    {
      double n[3];
      normals->GetTuple(i, n);
      ASSERT_NEAR(vtkMath::Norm(n), 1.0, 1e-6) << "normal " << i;
    }
  }
}

// A scanned mesh with normals only (no texture coordinates): the normals metric alone.
TEST(AttributeErrorMetric, ScanNormalsCloserAtEqualCount)
{
  const vtkSmartPointer<vtkPolyData> mesh = slodtest::WithPointNormals(slodtest::LoadTestMesh("elephant"));
  const vtkIdType target = mesh->GetNumberOfPolys() / 10;
  const vtkSmartPointer<vtkPolyData> off = Simplify(mesh, target, false);
  const vtkSmartPointer<vtkPolyData> on = Simplify(mesh, target, true);
  ASSERT_EQ(on->GetNumberOfPolys(), off->GetNumberOfPolys());
  const AttributeError eOff = MeanAttributeError(mesh, off), eOn = MeanAttributeError(mesh, on);
  EXPECT_LT(eOn.NormalDegrees, 0.9 * eOff.NormalDegrees) << "on " << eOn.NormalDegrees << ", off " << eOff.NormalDegrees;
}

// Weight 0 leaves the attribute out: the output is the metric off's, point for point. A larger
// texture-coordinate weight keeps the texture coordinates closer and costs geometric distance.
TEST(AttributeErrorMetric, WeightsOrderTheTradeOff)
{
  const vtkSmartPointer<vtkPolyData> sphere = slodtest::TexturedSphere(120);
  const vtkIdType target = sphere->GetNumberOfPolys() / 10;
  const vtkSmartPointer<vtkPolyData> off = Simplify(sphere, target, false);
  Weights zero;
  zero.TCoords = zero.Normals = zero.Scalars = 0.0;
  const vtkSmartPointer<vtkPolyData> none = Simplify(sphere, target, true, zero);
  EXPECT_EQ(PointsOf(none), PointsOf(off));
  EXPECT_EQ(Values(none->GetPointData()->GetTCoords()), Values(off->GetPointData()->GetTCoords()));

  double previousError = MeanAttributeError(sphere, off).TCoords, previousDistance = MeanDistance(sphere, off);
  for (double weight : { 0.1, 1.0 })
  {
    SCOPED_TRACE(weight);
    Weights tcoordsOnly;
    tcoordsOnly.TCoords = weight;
    tcoordsOnly.Normals = tcoordsOnly.Scalars = 0.0;
    const vtkSmartPointer<vtkPolyData> out = Simplify(sphere, target, true, tcoordsOnly);
    const double error = MeanAttributeError(sphere, out).TCoords, distance = MeanDistance(sphere, out);
    EXPECT_LT(error, previousError);
    EXPECT_GT(distance, previousDistance);
    previousError = error;
    previousDistance = distance;
  }
}

// The minimiser of a linear attribute's quadric is the attribute's own value: on a plane with
// texture coordinates (x, y) and scalars 2x - 3y + 1, every output vertex carries exactly those.
TEST(AttributeErrorMetric, LinearAttributesOfAPlaneAreExact)
{
  vtkSmartPointer<vtkPolyData> plane = slodtest::ToPolyData(slodtest::Grid(30, 30));
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetNumberOfComponents(2);
  vtkNew<vtkDoubleArray> scalars;
  for (vtkIdType i = 0; i < plane->GetNumberOfPoints(); ++i)
  {
    const double* p = plane->GetPoint(i);
    tcoords->InsertNextTuple2(p[0], p[1]);
    scalars->InsertNextValue(2 * p[0] - 3 * p[1] + 1);
  }
  plane->GetPointData()->SetTCoords(tcoords);
  plane->GetPointData()->SetScalars(scalars);
  const vtkSmartPointer<vtkPolyData> out = Simplify(plane, plane->GetNumberOfPolys() / 10, true);
  ASSERT_LT(out->GetNumberOfPoints(), plane->GetNumberOfPoints() / 5);
  vtkDataArray* uv = out->GetPointData()->GetTCoords();
  vtkDataArray* s = out->GetPointData()->GetScalars();
  ASSERT_NE(uv, nullptr);
  ASSERT_NE(s, nullptr);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const double* p = out->GetPoint(i);
    EXPECT_NEAR(uv->GetComponent(i, 0), p[0], 1e-6) << "point " << i;
    EXPECT_NEAR(uv->GetComponent(i, 1), p[1], 1e-6) << "point " << i;
    EXPECT_NEAR(s->GetComponent(i, 0), 2 * p[0] - 3 * p[1] + 1, 1e-9) << "point " << i;
  }
}

// The attribute terms are summed per vertex in parallel: the same output for 1 and 4 threads,
// and for two runs.
TEST(AttributeErrorMetric, DeterministicForAnyThreadCount)
{
  const vtkSmartPointer<vtkPolyData> sphere = slodtest::TexturedSphere(80);
  const vtkIdType target = sphere->GetNumberOfPolys() / 10;
  const int threads = vtkSMPTools::GetEstimatedNumberOfThreads();
  vtkSMPTools::Initialize(1);
  const vtkSmartPointer<vtkPolyData> one = Simplify(sphere, target, true);
  vtkSMPTools::Initialize(4);
  const vtkSmartPointer<vtkPolyData> four = Simplify(sphere, target, true);
  const vtkSmartPointer<vtkPolyData> again = Simplify(sphere, target, true);
  vtkSMPTools::Initialize(threads);
  EXPECT_EQ(PointsOf(one), PointsOf(four));
  EXPECT_EQ(PointsOf(four), PointsOf(again));
  EXPECT_EQ(Values(one->GetPointData()->GetTCoords()), Values(four->GetPointData()->GetTCoords()));
  EXPECT_EQ(Values(one->GetPointData()->GetNormals()), Values(four->GetPointData()->GetNormals()));
}

// The collapse records hold positions and connectivity only (no attribute values): with the
// metric on, the coarse mesh plus every record is still the input, point for point.
TEST(AttributeErrorMetric, ProgressiveRecordsStillRebuildTheInput)
{
  const vtkSmartPointer<vtkPolyData> sphere = slodtest::TexturedSphere(80);
  const slod::TriangleMesh prepared = slodtest::ToTriangleMesh(sphere);
  const vtkSmartPointer<vtkPolyData> rebuilt =
    Simplify(sphere, sphere->GetNumberOfPolys() / 10, true, Weights(), true);
  const slod::TriangleMesh mesh = slodtest::RawTriangleMesh(rebuilt);
  EXPECT_EQ(mesh.NumberOfTriangles(), prepared.NumberOfTriangles());
  std::vector<std::array<double, 3>> a, b;
  for (slod::Index v = 0; v < prepared.NumberOfPoints(); ++v)
  {
    a.push_back(prepared.Point(v));
  }
  for (slod::Index v = 0; v < mesh.NumberOfPoints(); ++v)
  {
    b.push_back(mesh.Point(v));
  }
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_TRUE(a == b) << "the rebuilt points differ from the input's";
}

// Colours (unsigned char RGB scalars) come out rounded and within 0-255, close to the input's
// colour field; texture coordinates with a NaN are left out of the metric with a warning.
TEST(AttributeErrorMetric, IntegerColoursAndNonFiniteValues)
{
  vtkSmartPointer<vtkPolyData> sphere = slodtest::TexturedSphere(80);
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetNumberOfComponents(3);
  auto colourOf = [](const double* p, int c) { return 255.0 * std::min(1.0, std::max(0.0, p[c] + 0.5)); };
  for (vtkIdType i = 0; i < sphere->GetNumberOfPoints(); ++i)
  {
    const double* p = sphere->GetPoint(i);
    colours->InsertNextTuple3(std::round(colourOf(p, 0)), std::round(colourOf(p, 1)), std::round(colourOf(p, 2)));
  }
  sphere->GetPointData()->SetScalars(colours);
  const vtkSmartPointer<vtkPolyData> out = Simplify(sphere, sphere->GetNumberOfPolys() / 10, true);
  vtkDataArray* c = out->GetPointData()->GetScalars();
  ASSERT_NE(c, nullptr);
  ASSERT_EQ(c->GetDataType(), VTK_UNSIGNED_CHAR);
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      // The colour field is linear in the position: within a few units of the position's colour.
      EXPECT_NEAR(c->GetComponent(i, k), colourOf(out->GetPoint(i), k), 12.0) << "point " << i;
    }
  }

  vtkDataArray* tcoords = sphere->GetPointData()->GetTCoords();
  tcoords->SetComponent(sphere->GetNumberOfPoints() / 2, 0, std::numeric_limits<double>::quiet_NaN());
  vtkNew<slodtest::MessageCounter> messages;
  const vtkSmartPointer<vtkPolyData> withNaN =
    Simplify(sphere, sphere->GetNumberOfPolys() / 10, true, Weights(), false, messages);
  EXPECT_GT(withNaN->GetNumberOfPolys(), 0);
  EXPECT_TRUE(std::any_of(messages->Warnings.begin(), messages->Warnings.end(),
    [](const std::string& w) { return w.find("not finite") != std::string::npos; }));
  vtkDataArray* n = withNaN->GetPointData()->GetNormals();
  ASSERT_NE(n, nullptr);
  for (double value : Values(n))
  {
    ASSERT_TRUE(std::isfinite(value));
  }
}
