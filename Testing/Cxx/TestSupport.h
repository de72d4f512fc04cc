// SPDX-License-Identifier: BSD-3-Clause
// Shared helpers of the SurfaceLOD test suite: test meshes, synthetic shapes, property checks.
#ifndef SurfaceLODTestSupport_h
#define SurfaceLODTestSupport_h

#include "slodMeshTopology.h"
#include "slodTriangleMesh.h"

#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkPolyData.h"
#include "vtkPolyDataAlgorithm.h"
#include "vtkSmartPointer.h"

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace slodtest
{
// A mesh of Debian's libcgal-demo (e.g. "fandisk", "bunny00"): fails the test loudly when missing.
vtkSmartPointer<vtkPolyData> LoadTestMesh(const std::string& name);
std::string TestMeshPath(const std::string& name);
std::string OutputPath(const std::string& fileName);
// The point ids of every cell of a cell array, in order (polygons, lines, ... as written or read).
std::vector<std::vector<vtkIdType>> CellPointIds(vtkCellArray* cells);

// Prepared triangle mesh of a vtkPolyData (the filters' own input preparation).
slod::TriangleMesh ToTriangleMesh(vtkPolyData* polyData);
vtkSmartPointer<vtkPolyData> ToPolyData(const slod::TriangleMesh& mesh);

// The triangles of a vtkPolyData exactly as stored (no preparation: orientation, duplicates and
// unused points show). Non-triangle cells fail the calling test.
slod::TriangleMesh RawTriangleMesh(vtkPolyData* polyData);

// The demo's deterministic marching-cubes surface (vtkSyntheticIsosurfaceSource): closed, genus 1;
// about 50,000 triangles at resolution 112 and 1,000,000 at 500.
vtkSmartPointer<vtkPolyData> SyntheticIsosurface(int resolution);
// vtkFlyingEdges3D's sphere x^2 + y^2 + z^2 = isoValue over the integer grid [-n/2, n/2)^3: with an
// iso-value that samples take (a sum of three squares), several of its vertices sit on each such
// sample, joined by edges of length zero and triangles of zero area (as on mc1m.vtp).
vtkSmartPointer<vtkPolyData> SphereThroughSamples(int samples, double isoValue);
// vtkScanSurfaceSource's noisy isosurface (resolution^3 samples, about 13 resolution^2 triangles),
// like a scan: handles, pinched vertices, non-manifold edges, a border; deterministic per seed.
vtkSmartPointer<vtkPolyData> NoisyScanIsosurface(int resolution, unsigned seed);

// Known shapes.
slod::TriangleMesh Tetrahedron();
slod::TriangleMesh Torus(int majorSegments, int minorSegments, double majorRadius = 1.0, double minorRadius = 0.35);
// The largest number of triangles around one vertex.
slod::Index MaximumVertexDegree(const slod::MeshTopology& topology);
slod::TriangleMesh Sphere(int thetaResolution, int phiResolution); // vtkSphereSource, cleaned
slod::TriangleMesh Disk(int rings, int segments);                    // open, one boundary loop
slod::TriangleMesh Grid(int nx, int ny, double z = 0.0);             // unit square, one boundary loop
// Closed cone: apex (0,0,height) and base centre (0,0,0) each on `segments` triangles (valence).
slod::TriangleMesh Cone(int segments, double height);
slod::TriangleMesh Concatenate(const slod::TriangleMesh& a, const slod::TriangleMesh& b);

// gtest expectations: `output` is a clean manifold (no non-manifold edge or vertex, no degenerate
// or misoriented triangle) with the Euler characteristic, genus, components and boundary loops of `input`.
void ExpectSameTopology(const slod::TriangleMesh& input, const slod::TriangleMesh& output);
slod::TriangleMesh NonManifoldFan(int wings);                        // `wings` triangles on one edge

// A filter's output keeps the topology of its input as the filter sees it (after the input
// preparation): Euler characteristic, components and non-manifold edges (each one edge still,
// none cut open, none added). Returns the prepared input's statistics. (Border loops are not
// compared here: where several loops touch at a pinched vertex, their count depends on how the
// border edges there are paired; filters that keep the border check its edges instead.)
slod::MeshStatistics ExpectPreparedInputTopology(vtkPolyData* input, vtkPolyData* output);

// Runs `filter` (its target already set) on NoisyScanIsosurface(resolution, seed), checks that the
// surface has what such a test needs (non-manifold edges, a border, handles) and that the output
// keeps its topology (ExpectPreparedInputTopology). Returns the prepared input's statistics.
slod::MeshStatistics SimplifyNoisyScan(vtkPolyDataAlgorithm* filter, int resolution, unsigned seed);

// A copy of `mesh` with point normals (vtkPolyDataNormals, splitting off, no cell normals).
vtkSmartPointer<vtkPolyData> WithPointNormals(vtkPolyData* mesh);

// Two-sided deviation of `compared` from `reference` (vtkSurfaceDeviation, `samples` per side),
// relative to the diagonal: {Hausdorff, mean}.
std::pair<double, double> RelativeDeviation(vtkPolyData* reference, vtkPolyData* compared, vtkIdType samples = 100000);

// vtkTexturedSphereSource (radius 0.5) with normals (vtkPolyDataNormals, splitting off), without
// its zero-area triangles at the poles (scripts/attribute-error.py's mesh). Its u = 1 meridian lies
// 1e-16 off the u = 0 one (sin(2 pi) in float), so the two sides are separate borders.
vtkSmartPointer<vtkPolyData> TexturedSphere(int resolution);

// Runs `run(n)` with vtkSMPTools initialised for n = 1, 2 and 8 threads, then restores the backend
// and the thread count. The STDThread backend: TBB keeps the worker limit of its first use in the
// process (after one thread, a request for more workers is ignored with a warning), so tests run
// with TBB compared one thread with itself and passed with thread-dependent code. Asserted here:
// one thread runs a loop for n = 1, several for n > 1 (STDThread caps n at the hardware
// concurrency: 8 runs as 2 on a 2-core machine).
void ForOneTwoAndEightThreads(const std::function<void(int)>& run);

// Collects (and so silences) the warnings and errors of a filter it observes.
class MessageCounter : public vtkCommand
{
public:
  static MessageCounter* New() { return new MessageCounter; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    (event == vtkCommand::ErrorEvent ? this->Errors : this->Warnings)
      .push_back(data ? static_cast<const char*>(data) : "");
  }
  std::vector<std::string> Warnings, Errors;
};

// Sets AbortExecute at the first progress event of the filter it observes and counts the warnings
// that mention the abort (the contract's abort result: slod::ReportAbort).
class AbortAtFirstProgress : public vtkCommand
{
public:
  static AbortAtFirstProgress* New() { return new AbortAtFirstProgress; }
  void Execute(vtkObject* caller, unsigned long event, void* data) override
  {
    if (event == vtkCommand::ProgressEvent)
    {
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
    }
    else if (event == vtkCommand::WarningEvent && data &&
      std::string(static_cast<const char*>(data)).find("Aborted") != std::string::npos)
    {
      ++this->AbortWarnings;
    }
  }
  int AbortWarnings = 0;
};
} // namespace slodtest

#endif
