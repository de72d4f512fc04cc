// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD deviation: one-sided surface deviation (samples on one mesh measured to another).
// The algorithm behind vtkSurfaceDeviation, usable by any filter or test without VTK data objects.
//
// Samples = the mesh's vertices and/or deterministic area-weighted random points. Distances are
// queried in Morton order (neighbouring queries share tree paths and start from the previous
// answer as a bound) in fixed-size chunks run with vtkSMPTools; the chunking does not depend on
// the thread count, so results are bit-identical for any number of threads.
#ifndef slodSurfaceDeviation_h
#define slodSurfaceDeviation_h

#include "slodFilterContract.h"
#include "slodTriangleBVH.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace slod
{
// Called on the calling thread with the fraction done (0..1); return false to abort.

// `count` area-weighted random points on the mesh (3 doubles each, appended to points).
// Deterministic: a counter-based generator seeded with (seed, stream); zero-area triangles are never
// chosen. Nothing is added when the mesh has no area.
SURFACELODFILTERS_EXPORT void SampleSurface(const TriangleMesh& mesh, std::int64_t count, std::uint64_t seed,
  std::uint64_t stream, std::vector<double>& points);

// Unsigned distance of each point (3 doubles each) to the surface of the tree (which must not be
// empty). Non-finite points get NaN. Returns false when aborted by the callback.
SURFACELODFILTERS_EXPORT bool ComputeDistances(const TriangleBVH& tree, const std::vector<double>& points,
  std::vector<double>& distances, const ProgressFunction& progress = {});

struct SURFACELODFILTERS_EXPORT DeviationOptions
{
  std::int64_t NumberOfSamples = 300000; // random samples, in addition to the vertices
  std::uint64_t Seed = 12345;
  std::uint64_t Stream = 0; // use a different stream per side so the two sides sample independently
  bool SampleVertices = true; // vertices count in the maximum
};

struct SURFACELODFILTERS_EXPORT OneSidedDeviation
{
  double Max = 0;       // over vertices (if sampled) and random samples
  double MaxVertex = 0; // over vertices (0 when not sampled)
  double Mean = 0;      // over the random samples; over the vertices when there are none
  double RMS = 0;
  std::int64_t VertexSamples = 0;
  std::int64_t RandomSamples = 0;
};

// Samples on `from` measured to the surface in `to` (not empty). vertexDistances (optional) gets
// the distance of every vertex of `from`, whether or not vertices count as samples.
// Returns false when aborted.
SURFACELODFILTERS_EXPORT bool MeasureDeviation(const TriangleMesh& from, const TriangleBVH& to,
  const DeviationOptions& options, OneSidedDeviation& result, std::vector<double>* vertexDistances = nullptr,
  const ProgressFunction& progress = {});
} // namespace slod

#endif
