// SPDX-License-Identifier: BSD-3-Clause
// Benchmark of vtkHoleBumpRemoval (Ho 1999, chapter 5) against vtkQuadricDecimation and
// vtkDecimatePro in its topology-changing mode (PreserveTopologyOff, the dissertation's Fig. 31),
// measured in the same run at the triangle count our filter reaches (not part of ctest).
//
// usage: BenchHoleBumpRemoval [--repeat N] [--samples N]
// Models: vtkBlockModelSource plates with square / round holes, the mixed block, and the CGAL
// demo CAD models anchor, couplingdown, joint, turbine (SURFACELOD_MESH_DIR). For each: features
// removed, genus before / after, triangles, time (min of N runs), and the symmetric Hausdorff
// distance (vtkSurfaceDeviation, % of the bbox diagonal) to the input and, for the block models,
// to the same model without its features (what the simplification aims at).
#include "vtkBlockModelSource.h"
#include "vtkHoleBumpRemoval.h"
#include "vtkOFFMeshReader.h"
#include "vtkSurfaceDeviation.h"

#include "vtkDecimatePro.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkQuadricDecimation.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>

namespace
{
double Seconds(const std::function<void()>& f, int repeat)
{
  double best = 1e30;
  for (int i = 0; i < repeat; ++i)
  {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

double Hausdorff(vtkPolyData* a, vtkPolyData* b, vtkIdType samples)
{
  if (!a || !b || b->GetNumberOfPolys() == 0)
  {
    return -1;
  }
  vtkNew<vtkSurfaceDeviation> d;
  d->SetReferenceData(a);
  d->SetComparedData(b);
  d->SetNumberOfSamples(samples);
  d->Update();
  return 100.0 * d->GetHausdorffRelative();
}

struct Model
{
  std::string Name;
  vtkSmartPointer<vtkPolyData> Mesh;
  vtkSmartPointer<vtkPolyData> Target; // the model without its features, when known
  double Alpha;                       // relative
};

vtkSmartPointer<vtkPolyData> Block(int model, int fx, int fy, int subdivisions)
{
  vtkNew<vtkBlockModelSource> s;
  s->SetModel(model);
  s->SetFeaturesX(fx);
  s->SetFeaturesY(fy);
  s->SetSubdivisions(subdivisions);
  s->Update();
  return s->GetOutput();
}
} // namespace

int main(int argc, char* argv[])
{
  int repeat = 3;
  vtkIdType samples = 100000;
  for (int i = 1; i + 1 < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--repeat"))
    {
      repeat = std::max(1, std::atoi(argv[++i]));
    }
    else if (!std::strcmp(argv[i], "--samples"))
    {
      samples = std::atol(argv[++i]);
    }
  }
  std::vector<Model> models;
  models.push_back({ "fixture 10x10 holes", Block(vtkBlockModelSource::PLATE_WITH_HOLES, 10, 10, 3), nullptr, 0.1 });
  models.push_back({ "round holes 8x6", Block(vtkBlockModelSource::PLATE_WITH_ROUND_HOLES, 8, 6, 1), nullptr, 0.1 });
  models.push_back({ "battery 3x3 bumps", Block(vtkBlockModelSource::BUMPS, 3, 3, 4), nullptr, 0.2 });
  models.push_back({ "mixed block", Block(vtkBlockModelSource::MIXED, 3, 3, 4), nullptr, 0.2 });
  for (const char* name : { "anchor", "couplingdown", "joint", "turbine" })
  {
    vtkNew<vtkOFFMeshReader> reader;
    reader->SetFileName((std::string(SURFACELOD_MESH_DIR) + "/" + name + ".off").c_str());
    reader->Update();
    models.push_back({ name, reader->GetOutput(), nullptr, 0.2 });
  }
  std::printf("%-20s %7s %5s | %-10s %5s %6s %8s %8s | %-22s | %-30s\n", "model", "tris", "genus", "h/b/c rem",
    "genus", "tris", "time s", "H% in", "vtkQuadric: tris s H%", "vtkDecimatePro(topo off): tris s H% genus");
  for (const Model& m : models)
  {
    vtkNew<vtkHoleBumpRemoval> ours;
    ours->SetInputData(m.Mesh);
    ours->SetFeatureSize(m.Alpha);
    const double oursTime = Seconds([&] { ours->Modified(); ours->Update(); }, repeat);
    vtkPolyData* a = ours->GetOutput();
    const vtkIdType count = a->GetNumberOfPolys();
    const double reduction = 1.0 - double(count) / double(m.Mesh->GetNumberOfPolys());
    vtkNew<vtkQuadricDecimation> quadric;
    quadric->SetInputData(m.Mesh);
    quadric->SetTargetReduction(reduction);
    const double quadricTime = Seconds([&] { quadric->Modified(); quadric->Update(); }, repeat);
    vtkNew<vtkDecimatePro> pro;
    pro->SetInputData(m.Mesh);
    pro->SetTargetReduction(reduction);
    pro->PreserveTopologyOff();
    pro->SplittingOn();
    pro->BoundaryVertexDeletionOn();
    const double proTime = Seconds([&] { pro->Modified(); pro->Update(); }, repeat);
    // Genus of vtkDecimatePro's output through our filter's bookkeeping (detection only).
    vtkNew<vtkHoleBumpRemoval> probe;
    probe->SetInputData(pro->GetOutput());
    probe->SetFeatureSize(0);
    probe->SetCompletionToKeepTriangles();
    probe->FillCracksOff();
    probe->GlobalWarningDisplayOff();
    probe->Update();
    char feats[32];
    std::snprintf(feats, sizeof(feats), "%d/%d/%d", ours->GetNumberOfHolesRemoved(), ours->GetNumberOfBumpsRemoved(),
      ours->GetNumberOfCavitiesRemoved());
    std::printf("%-20s %7lld %5d | %-10s %5d %6lld %8.4f %8.3f | %6lld %7.4f %7.3f | %6lld %7.4f %7.3f %5d\n",
      m.Name.c_str(), static_cast<long long>(m.Mesh->GetNumberOfPolys()), ours->GetInputGenus(), feats,
      ours->GetOutputGenus(), static_cast<long long>(count), oursTime, Hausdorff(m.Mesh, a, samples),
      static_cast<long long>(quadric->GetOutput()->GetNumberOfPolys()), quadricTime,
      Hausdorff(m.Mesh, quadric->GetOutput(), samples), static_cast<long long>(pro->GetOutput()->GetNumberOfPolys()),
      proTime, Hausdorff(m.Mesh, pro->GetOutput(), samples), probe->GetInputGenus());
  }
  return 0;
}
