// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm GreedyCuts: simplification of a polyline (a boundary chain) to a tolerance.
//
// Douglas-Peucker refinement in 3D: a sub-chain is split at its vertex farthest from the segment
// joining its ends while that distance exceeds epsilon. Every dropped vertex, hence (distance to a
// segment is convex) every dropped original edge, lies within epsilon of the simplified segment
// that replaces it: the original chain is epsilon-close to its simplification one way; the other
// way (simplified segment -> surface) is the caller's test (e.g. the triangle feasibility test).
#ifndef slodChainSimplification_h
#define slodChainSimplification_h

#include "slodTriangleMesh.h"

#include <vector>

namespace slod
{
// Distance from p to the segment [a, b].
SURFACELODFILTERS_EXPORT double PointSegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b);

// keep[i] (size n) is set for the vertices of the chain `vertices` (n mesh vertex ids, open
// chain) kept at tolerance epsilon; the two ends are always kept. A negative epsilon keeps all.
SURFACELODFILTERS_EXPORT void SimplifyChain(
  const TriangleMesh& mesh, const Index* vertices, Index n, double epsilon, std::vector<unsigned char>& keep);

// Index in (first, last) of the vertex farthest from segment [vertices[first], vertices[last]]
// (InvalidIndex when last - first < 2).
SURFACELODFILTERS_EXPORT Index FarthestChainVertex(
  const TriangleMesh& mesh, const Index* vertices, Index first, Index last, double* distance = nullptr);
} // namespace slod

#endif
