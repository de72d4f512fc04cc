// SPDX-License-Identifier: BSD-3-Clause
// SurfaceLOD algorithm Retile: re-tiling of a triangle surface (Turk 1992, "Re-Tiling Polygonal Surfaces").
//
// Stages (each a named function, all deterministic for a given seed):
//  1. EstimateCurvatureRadius: Turk's per-vertex minimum radius of curvature (section 5.1),
//     r = min_i tan(theta_i) |P - Q_i| / 2, smoothed once over the one-ring.
//  2. DistributePoints: N points at random over the surface, area-weighted (section 3.2), the
//     stored areas scaled by a curvature density (section 5.2).
//  3. RelaxPoints: point repulsion (section 3.2). Linear fall-off force within a radius (per
//     point, smaller where the density is higher; a pair uses the mean radius), neighbours from a
//     uniform grid, each move in the tangent plane then projected back to the closest point of the
//     original surface (TriangleBVH), so points cross triangles. Jacobi updates: every move of an
//     iteration uses the previous positions, which makes the result independent of threading.
//     Kept feature lines push with their samples and, where the samples are far apart, with
//     points of the line between them that are no vertices (RepelFromLineGaps, session 44).
//  4. Mutual tessellation (section 4.2): each original triangle is split at the candidate points it
//     holds (incremental insertion, then Delaunay flips inside the triangle, original edges kept).
//  5. Old-vertex removal (sections 4.3/4.4/4.6): each old vertex is removed by collapsing it onto a
//     neighbouring candidate vertex. EditableMesh::CheckCollapse is the topological consistency
//     check (link condition = no edge shared by three triangles, no duplicated triangle, boundary
//     loops kept); every surviving triangle must also face the way the original surface faces at its
//     vertices. The neighbour giving the best smallest angle is chosen; where every fan leaves a
//     tile facing against the surface, the ring is re-triangulated as a whole (RingTriangulationSearch,
//     slodRetileRing.h: the best of all its triangulations). Old vertices that no check
//     lets go are retained (as in the paper); their number is reported. Non-manifold vertices of
//     the input (Turk assumes a manifold, section 3.1) are always retained, so a non-manifold edge
//     stays one edge and the surface is not cut open there.
//  6. Shape improvement (section 4.5): edge flips toward max-min angle where the two triangles are
//     nearly coplanar and the flip keeps the orientation relative to the original surface.
//  7. Repair (slodRetileRepair.h): tiles still facing against the original surface, folded onto a
//     neighbour or needles are repaired by flips and by moves of free candidates on the surface,
//     kept only when the tiles get better without moving away from the surface.
#ifndef slodRetiling_h
#define slodRetiling_h

#include "slodTriangleMesh.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace slod
{
class TriangleBVH;

struct SURFACELODFILTERS_EXPORT RetilingOptions
{
  Index NumberOfPoints = 1000;   // candidate vertices (the output vertex count)
  int RepulsionIterations = 20;  // relaxation steps
  double CurvatureWeight = 0.0;  // 0: uniform; > 0: density 1 + w * curvature / median curvature
  // With CurvatureWeight > 0: the density follows fillets (rounded creases, narrower than the
  // spacing) instead of the kept lines. The curvature is averaged as curvature (1/r) rather than
  // as a radius, the kept lines' vertices are left out of it (their normal averages the two faces
  // of a crease: the estimate is the crease's angle, and the line has its own samples), and two
  // points repel within the smaller of their radii (with the mean, the flat side's points push
  // the points of a band narrower than their radius off it). Off by default (Documentation/Retile.md).
  bool FilletDensity = false;
  std::uint64_t RandomSeed = 1;
  int ShapeImprovementPasses = 2; // edge-flip passes after vertex removal
  // Feature lines (slodRetileFeatures.h): edges whose dihedral angle exceeds FeatureAngle degrees
  // and border edges are kept as lines of the output (their corners and samples along them are
  // fixed vertices, counted in NumberOfPoints). Retile only; RetileNested ignores it.
  bool PreserveCreases = false;
  double FeatureAngle = 45.0;
  // Step 5 refuses a collapse onto a candidate whose new triangles face against the original
  // surface (PreserveCreases always does): such a vertex waits for a later phase, within a budget
  // of waits (one per old vertex in all; none for valence > 32), and the last phase takes the
  // refused target after all. Off by default: fewer flipped triangles, but not always a smaller
  // Hausdorff distance (Documentation/Retile.md).
  bool EnforceFacing = false;
  // Step 5 re-triangulates the whole ring of an old vertex (Turk's removal, slodRetileRing.h)
  // where the chosen fan faces against the original surface: a fan, then flips. Off by default:
  // about a quarter fewer flipped triangles, but a needle on rotor_small and a Hausdorff distance
  // up to 11% larger on some meshes (Documentation/Retile.md). The nested levels use it too.
  bool RetriangulateRings = false;
  // Where no triangulation of an old vertex's ring faces its tiles' corners and the ring search's
  // fallback is taken, rank the triangulations first by whether every tile faces the input
  // triangle under its centroid (Turk's local-plane test), then by the worst cosine
  // (RingTriangulationSearch::InputSurface). Off by default: fewer flipped tiles over the CGAL
  // meshes, but more needles at 10% of the vertices and a larger Hausdorff distance at 50%, and
  // twice the search's cost on cheese (Documentation/Retile.md, session 36). Retile only.
  bool RingSearchFacesInput = false;
  // After the repair, a final stage on the tiles still facing against the input triangle under
  // their centroids: flips, moves on the input and kernel moves of their vertices, each kept only
  // when the flipped tiles around it become fewer and needles and folds do not (session 37,
  // TileRepair::RunFlipped). The vertex count does not change. Retile's finest level only.
  bool RepairFlippedTiles = true;
  // After that final stage, a needle stage on the tiles with a smallest angle under 5 degrees (or
  // an edge under 1e-5 of the diagonal): the same flips and moves, each kept only when the needles
  // around it become fewer (or as many with a larger smallest angle) and the flipped tiles and
  // the folds the input lacks no more (session 43, TileRepair::RunNeedles). With an explicit
  // count it ends the trim too (flips only). The vertex count does not change. Retile's finest
  // level only; with RepairFlippedTiles only.
  bool RepairNeedleTiles = true;
  // With PreserveCreases: where two consecutive kept vertices of a line are 1.5 spacings or more
  // apart (input edges along the line longer than the spacing), points of the line between them
  // push the free points in the repulsion, as samples would, without being vertices
  // (FeatureLines::GapPoints, session 44). Without them a free point held on a convex crease in
  // such a gap became the obtuse corner of a cap over the line's edge.
  bool RepelFromLineGaps = true;
  // Candidates standing on an input crease move only along it in the repair and its final stage
  // (slodRetileCreases.h), instead of to the closest point of the surface. The creases are the
  // feature lines PreserveCreases detects but does not keep (they would take half the vertices
  // or more, or are mostly corners); a kept line has its own vertices, and a candidate held on it
  // left needles. Not in the repulsion: measured worse there (Documentation/Retile.md, session 38).
  bool SlideAlongCreases = false;
  // The final stage (RepairFlippedTiles) may also move the retained original vertices (those no
  // removal took out, not on a border, a kept line or a non-manifold spot), on the input within
  // their star like the candidates: a tile at a retained vertex otherwise keeps its corner where
  // the input had it (session 39). The vertex count does not change; a moved vertex's host
  // location is where it went (InputVertex no longer set).
  bool MoveRetainedVertices = false;
  // Optional: per input vertex, 1 when non-manifold (the input preparation's
  // PreparationReport::NonManifoldVertexFlags); computed when null. These vertices are kept as
  // they are (retained old vertices): the removal's link condition assumes one fan per vertex.
  const std::vector<unsigned char>* NonManifoldVertices = nullptr;
  // Progress in [0,1]; return false to abort (the result is then empty, Aborted set).
  std::function<bool(double)> Progress;
  // Optional: called with the output's vertex and triangle counts once the removal and the shape
  // flips have fixed them (the repair, step 7, changes neither); return false to stop there (the
  // result then has Stopped set and its Mesh is not repaired, nor its host locations recorded).
  // vtkRetile tries several point counts to meet a triangle target and repairs only the one it keeps.
  std::function<bool(Index vertices, Index triangles)> ContinueWithCounts;
};

// Where a point lies on the original surface.
struct SURFACELODFILTERS_EXPORT SurfacePoint
{
  Vec3 Position{ 0, 0, 0 };
  Index Triangle = InvalidIndex;
};

struct SURFACELODFILTERS_EXPORT RetilingResult
{
  TriangleMesh Mesh;
  // Per output vertex: the original triangle it lies on and its barycentric coordinates there
  // (to interpolate point data). Retained old vertices get a triangle of theirs with weight 1.
  std::vector<Index> HostTriangle;
  std::vector<double> Barycentric; // 3 per output vertex
  // Per output vertex: the input vertex it sits on (a retained old vertex, or a candidate moved
  // onto one as a last resort), else InvalidIndex.
  std::vector<Index> InputVertex;
  // Per output vertex: the candidate point it is (index into the candidates, in placement order),
  // else InvalidIndex (a retained old vertex).
  std::vector<Index> Candidate;
  // Nested levels (RetileNested), every level but the finest: how this level comes from the next
  // finer one (section 6.2), in order, as pairs in the finer level's vertex ids: (removed, target)
  // for the half-edge collapses that removed the finer level's other vertices, then (-1 - x, y)
  // for the shape flips of edge (x, y). Replaying them on the finer level gives this level's
  // triangles exactly (fragment tracking, slodFragmentTracking.h).
  std::vector<Index> Removals;
  Index CandidatePoints = 0;
  Index RetainedOldVertices = 0;   // old vertices no check allowed to remove (kept in the output)
  Index DroppedCandidates = 0;     // candidates repulsion crowded onto another (at pinches, folds)
  Index Flips = 0;
  // PreserveCreases: the fixed vertices on feature lines (corners included) and the corners;
  // FeaturesIgnored when they would have been half the vertices or more (lines finer than the
  // spacing: the re-tiling is then made without them).
  Index FeatureVertices = 0, Corners = 0;
  bool FeaturesIgnored = false;
  // Nearest-neighbour spacing of the candidate points (Euclidean), before and after repulsion.
  double MinSpacingBefore = 0, MeanSpacingBefore = 0, MinSpacingAfter = 0, MeanSpacingAfter = 0;
  bool Aborted = false;
  bool Stopped = false; // RetilingOptions::ContinueWithCounts returned false
};

// Turk's minimum radius of curvature per vertex (+inf-free: flat vertices get a large radius).
SURFACELODFILTERS_EXPORT void EstimateCurvatureRadius(const TriangleMesh& mesh, std::vector<double>& radius);

// Curvature 1/r per vertex from Turk's per-vertex minimum radius, averaged as curvature over the
// vertex and its neighbours, leaving out the vertices flagged in `skipped` (may be empty): they get
// the curvature of their other neighbours, or none. RetilingOptions::FilletDensity's estimate.
SURFACELODFILTERS_EXPORT void EstimateFilletCurvature(
  const TriangleMesh& mesh, const std::vector<unsigned char>& skipped, std::vector<double>& curvature);

// Density per vertex (1 + w * normalised curvature), the weights of the random placement (empty
// for w = 0). With `skipped` (FilletDensity: the kept lines' vertices) EstimateFilletCurvature's
// curvature, else Turk's (EstimateCurvatureRadius).
SURFACELODFILTERS_EXPORT void CurvatureDensity(const TriangleMesh& mesh, double curvatureWeight, std::vector<double>& vertexDensity,
  const std::vector<unsigned char>* skipped = nullptr);

// N random points, triangle chosen with probability area * density (density per vertex, may be empty),
// in the order of their triangles (points of one triangle in drawing order).
SURFACELODFILTERS_EXPORT void DistributePoints(const TriangleMesh& mesh, const std::vector<double>& vertexDensity,
  Index count, std::uint64_t seed, std::vector<SurfacePoint>& points);

// Point repulsion restricted to the surface. The first fixedCount points push but do not move.
// Two points repel within the mean of their radii (Turk), or the smaller one (smallerPairRadius,
// RetilingOptions::FilletDensity). The last `pushers` of the fixed points are not counted in the
// radius (2 sqrt(A / n)): they stand for a kept line between its samples (FeatureLines::GapPoints)
// and are no vertices. Returns false when progress asked to abort.
SURFACELODFILTERS_EXPORT bool RelaxPoints(const TriangleMesh& mesh, const TriangleBVH& bvh,
  const std::vector<double>& vertexDensity, int iterations, std::vector<SurfacePoint>& points,
  const std::function<bool(double)>& progress = nullptr, Index fixedCount = 0, bool smallerPairRadius = false,
  Index pushers = 0);

// Min and mean Euclidean nearest-neighbour distance of a point set (grid search).
SURFACELODFILTERS_EXPORT void NearestNeighborSpacing(const std::vector<double>& xyz, double& minimum, double& mean,
  std::vector<double>* perPoint = nullptr);

// The whole method.
SURFACELODFILTERS_EXPORT void Retile(const TriangleMesh& mesh, const RetilingOptions& options, RetilingResult& result);

// Nested re-tilings (sections 6.1-6.2), one per vertex count (sorted ascending; counts below 3 are
// dropped; options.NumberOfPoints is ignored). The points are placed coarse to fine (each level's
// points fixed while the next level's are added and relaxed); the finest level is tiled from the
// original surface, and each coarser level comes from the next finer one by removing the finer
// level's other vertices (collapses onto a neighbour, then shape flips; recorded in Removals). So
// the vertices of each level are the first vertices of every finer level, at the same positions
// and in the same order. A finer vertex no collapse can remove stays in the coarser level (after
// its own vertices; counted in RetainedOldVertices). Spacing figures are not computed per level.
SURFACELODFILTERS_EXPORT void RetileNested(const TriangleMesh& mesh, std::vector<Index> counts,
  const RetilingOptions& options, std::vector<RetilingResult>& levels);
// Brings a re-tiling with more than `wanted` vertices down towards `wanted` by removing free
// candidates (not on a kept line), the most crowded first and no two neighbours, as a coarser
// nested level is made (section 6.2: collapses, flips, the repair's flips), in at most
// `maximumRounds` rounds; a chosen candidate no collapse may remove stays and is not chosen
// again. The vertices keep their order. vtkRetile's explicit vertex count: the retained old
// vertices of one attempt come on top of the candidates. Returns false when aborted.
SURFACELODFILTERS_EXPORT bool RemoveCandidates(const TriangleMesh& mesh, const RetilingOptions& options, Index wanted,
  int maximumRounds, RetilingResult& result);
// Re-tiling and the level interpolation compute in the coordinates' own precision: a surface whose
// extent is more than this many times its median edge length (a vertex at 1e30 among unit edges,
// a copy 1e15 away) leaves its edges below the rounding of the positions, and tiles degenerate.
constexpr double MaximumRetilingExtentPerEdge = 1e12;

// Bounding-box diagonal divided by the median edge length (0 without edges, +inf when the median
// edge has zero length).
SURFACELODFILTERS_EXPORT double ExtentPerMedianEdge(const TriangleMesh& mesh);
} // namespace slod

#endif
