// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkRetile
 * @brief   re-tiles a triangle surface with a given number of evenly spread vertices (Turk 1992)
 *
 * Greg Turk, "Re-Tiling Polygonal Surfaces", SIGGRAPH 1992. New vertices are placed at random
 * on the surface (area weighted, seeded: the output is deterministic), spread by point repulsion
 * restricted to the surface (RepulsionIterations steps: each point is pushed by its neighbours
 * within a radius 2 sqrt(area / n), moves in its tangent plane and is projected back to the
 * closest point of the original surface, so it can cross triangles), then inserted into the
 * original triangles (the mutual tessellation). Every original vertex is then removed by
 * collapsing it onto a neighbouring new vertex, only when the local re-triangulation keeps the
 * topology (link condition: no edge shared by three triangles, no duplicate triangle, boundary
 * loops kept) and every new triangle faces the way the original surface faces at its vertices;
 * among the allowed neighbours the one giving the best smallest angle is chosen. Edge flips toward
 * max-min angle (nearly planar quads only) improve the shape afterwards.
 *
 * With CurvatureWeight > 0 the density of new vertices grows with Turk's curvature estimate
 * (minimum radius of curvature per vertex, smoothed): density 1 + CurvatureWeight * k / median(k),
 * k capped at 8 times the median, used both in the random placement and in the repulsion radii.
 *
 * Vertex count: NumberOfPoints when > 0; else derived from the triangle target
 * (the filter contract's TargetNumberOfTriangles and TargetReduction, each unused at 0: the larger
 * count when both are set, a reduction of 0.9 when neither is) as triangles / 2 + Euler characteristic, exact for closed surfaces (open
 * surfaces get one triangle fewer per output border edge: F = 2V - 2 chi - B). The output has exactly the
 * requested vertex count plus the original vertices no check allowed to remove
 * (NumberOfRetainedVertices, normally 0; such vertices are kept, as in the paper).
 *
 * Output vertices lie on the input surface (inside its triangles). All numeric point arrays are
 * interpolated (barycentric on the original triangle). The input must be a manifold triangle
 * surface (polygons and strips are triangulated, coincident points merged); non-manifold edges
 * or vertices are an error (empty output).
 *
 * Creases and borders (PreserveCreases, on by default): edges whose dihedral angle exceeds
 * FeatureAngle degrees (vtkDecimatePro's meaning) and border edges form feature lines. Their
 * corners (line ends, junctions, turns sharper than FeatureAngle) and samples evenly spaced along
 * each line (the spacing of the other vertices) are kept as input vertices and counted in the
 * vertex count; the other vertices of a line are removed only along it, so the output's edges
 * follow the lines. Lines shorter than the spacing that end freely are noise and ignored; lines
 * that would take half the vertices or more are all ignored, with a warning. Not applied to the
 * nested levels.
 *
 * Nested levels (sections 6.1-6.2), with GenerateNestedLevels on: output port 1 is a
 * vtkMultiBlockDataSet of NumberOfNestedLevels re-tilings, coarsest first, with
 * n, n * NestedLevelRatio, ... vertices up to the requested count (the last block is output 0).
 * The vertices of each level are the first vertices of every finer level (same positions): coarse
 * points stay fixed while the added points are placed and relaxed around them. The finest level
 * is tiled from the input; each coarser level is made from the next finer one by removing the
 * other vertices (the re-tiling's own collapses, then its shape flips), and carries those
 * operations as field data RetileRemovals (with RetileRemovalsFinerPoints), which
 * vtkRetileLevelInterpolation replays to track the fragments exactly. Vertices a removal cannot
 * take stay (and add triangles): the counts shrink (as for a single re-tiling) while the finest
 * level has more triangles than allowed; a warning says when it still has.
 */
#ifndef vtkRetile_h
#define vtkRetile_h

#include "SurfaceLODFiltersModule.h"
#include "vtkSimplificationAlgorithm.h"

class vtkMultiBlockDataSet;

class SURFACELODFILTERS_EXPORT vtkRetile : public vtkSimplificationAlgorithm
{
public:
  static vtkRetile* New();
  vtkTypeMacro(vtkRetile, vtkSimplificationAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  // Number of new vertices (0 = derive it from the triangle target).
  vtkSetClampMacro(NumberOfPoints, vtkIdType, 0, VTK_INT_MAX);
  vtkGetMacro(NumberOfPoints, vtkIdType);

  vtkSetClampMacro(RepulsionIterations, int, 0, VTK_INT_MAX);
  vtkGetMacro(RepulsionIterations, int);

  vtkSetClampMacro(CurvatureWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(CurvatureWeight, double);

  // With CurvatureWeight > 0: the density follows fillets (rounded creases) rather than the kept
  // crease lines (slod::RetilingOptions::FilletDensity). Off by default.
  vtkSetMacro(FilletDensity, bool);
  vtkGetMacro(FilletDensity, bool);
  vtkBooleanMacro(FilletDensity, bool);

  vtkSetMacro(RandomSeed, int);
  vtkGetMacro(RandomSeed, int);

  // Edge-flip passes for triangle shape after the old vertices are gone (0 = none).
  vtkSetClampMacro(ShapeImprovementPasses, int, 0, 100);
  vtkGetMacro(ShapeImprovementPasses, int);

  // Keep creases, corners and borders (see above). The nested levels do not keep them: set
  // explicitly with GenerateNestedLevels, it is ignored with a warning.
  virtual void SetPreserveCreases(bool preserve);
  vtkGetMacro(PreserveCreases, bool);
  vtkBooleanMacro(PreserveCreases, bool);
  // Refuse collapses whose new triangles face against the input (within a bounded budget of
  // waits, as PreserveCreases does); off by default (slod::RetilingOptions::EnforceFacing).
  vtkSetMacro(EnforceFacing, bool);
  vtkGetMacro(EnforceFacing, bool);
  vtkBooleanMacro(EnforceFacing, bool);
  // Re-triangulate an old vertex's whole ring where its fan faces against the input (Turk's
  // removal); off by default (slod::RetilingOptions::RetriangulateRings).
  vtkSetMacro(RetriangulateRings, bool);
  vtkGetMacro(RetriangulateRings, bool);
  vtkBooleanMacro(RetriangulateRings, bool);
  // Where the ring search takes a triangulation not facing the input's normals at its corners,
  // prefer one whose tiles face the input under their centroids; off by default
  // (slod::RetilingOptions::RingSearchFacesInput).
  vtkSetMacro(RingSearchFacesInput, bool);
  vtkGetMacro(RingSearchFacesInput, bool);
  vtkBooleanMacro(RingSearchFacesInput, bool);
  // After the repair, a final stage on the tiles still facing against the input under their
  // centroids (flips, moves of their vertices on the input); the vertex count does not change
  // (slod::RetilingOptions::RepairFlippedTiles).
  vtkSetMacro(RepairFlippedTiles, bool);
  vtkGetMacro(RepairFlippedTiles, bool);
  vtkBooleanMacro(RepairFlippedTiles, bool);
  // After that stage, a stage on the needles left (flips, moves of their vertices on the input)
  // kept only where the needles become fewer and the flipped tiles no more; with
  // RepairFlippedTiles; the vertex count does not change (slod::RetilingOptions::RepairNeedleTiles).
  vtkSetMacro(RepairNeedleTiles, bool);
  vtkGetMacro(RepairNeedleTiles, bool);
  vtkBooleanMacro(RepairNeedleTiles, bool);
  // With PreserveCreases: the kept lines push the free points off the stretches between their
  // samples that are longer than 1.5 spacings, in the repulsion (no vertex is added; the vertex
  // count does not change; slod::RetilingOptions::RepelFromLineGaps). On by default.
  vtkSetMacro(RepelFromLineGaps, bool);
  vtkGetMacro(RepelFromLineGaps, bool);
  vtkBooleanMacro(RepelFromLineGaps, bool);
  // Candidates standing on a crease of a feature line that is not kept move only along it in the
  // repair (slod::RetilingOptions::SlideAlongCreases; with PreserveCreases). Off by default.
  vtkSetMacro(SlideAlongCreases, bool);
  vtkGetMacro(SlideAlongCreases, bool);
  vtkBooleanMacro(SlideAlongCreases, bool);
  // The final stage on the flipped tiles may move retained original vertices too, on the input
  // within their star (slod::RetilingOptions::MoveRetainedVertices).
  vtkSetMacro(MoveRetainedVertices, bool);
  vtkGetMacro(MoveRetainedVertices, bool);
  vtkBooleanMacro(MoveRetainedVertices, bool);
  vtkSetClampMacro(FeatureAngle, double, 0.0, 180.0);
  vtkGetMacro(FeatureAngle, double);

  vtkSetMacro(GenerateNestedLevels, bool);
  vtkGetMacro(GenerateNestedLevels, bool);
  vtkBooleanMacro(GenerateNestedLevels, bool);
  vtkSetClampMacro(NumberOfNestedLevels, int, 1, 32);
  vtkGetMacro(NumberOfNestedLevels, int);
  vtkSetClampMacro(NestedLevelRatio, double, 1.01, VTK_DOUBLE_MAX);
  vtkGetMacro(NestedLevelRatio, double);
  // Output port 1 (empty unless GenerateNestedLevels).
  vtkMultiBlockDataSet* GetNestedLevels();

  // Results of the last run.
  vtkGetMacro(NumberOfRetainedVertices, vtkIdType);
  vtkGetMacro(NumberOfFlips, vtkIdType);
  // PreserveCreases: the vertices kept on feature lines (corners included) and the corners.
  vtkGetMacro(NumberOfFeatureVertices, vtkIdType);
  vtkGetMacro(NumberOfCorners, vtkIdType);
  // Nearest-neighbour spacing of the new vertices (min / mean) before and after repulsion.
  vtkGetMacro(MinimumSpacingBefore, double);
  vtkGetMacro(MeanSpacingBefore, double);
  vtkGetMacro(MinimumSpacingAfter, double);
  vtkGetMacro(MeanSpacingAfter, double);

protected:
  vtkRetile();
  ~vtkRetile() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkIdType NumberOfPoints = 0;
  int RepulsionIterations = 20;
  double CurvatureWeight = 0.0;
  int RandomSeed = 1;
  int ShapeImprovementPasses = 2;
  bool PreserveCreases = true;
  bool PreserveCreasesSetByUser = false; // only an explicit request is warned about when ignored
  bool EnforceFacing = false;
  bool FilletDensity = false;
  bool RetriangulateRings = false;
  bool RingSearchFacesInput = false;
  bool RepairFlippedTiles = true;
  bool RepairNeedleTiles = true;
  bool RepelFromLineGaps = true;
  bool SlideAlongCreases = false;
  bool MoveRetainedVertices = false;
  double FeatureAngle = 45.0;
  bool GenerateNestedLevels = false;
  int NumberOfNestedLevels = 3;
  double NestedLevelRatio = 4.0;

  vtkIdType NumberOfRetainedVertices = 0;
  vtkIdType NumberOfFlips = 0;
  vtkIdType NumberOfFeatureVertices = 0;
  vtkIdType NumberOfCorners = 0;
  double MinimumSpacingBefore = 0, MeanSpacingBefore = 0, MinimumSpacingAfter = 0, MeanSpacingAfter = 0;

private:
  vtkRetile(const vtkRetile&) = delete;
  void operator=(const vtkRetile&) = delete;
};

#endif
