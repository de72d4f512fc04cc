// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkTriangleCollapseHierarchy
 * @brief   smooth hierarchical triangulations by triangle collapse (Gieng et al. 1997)
 *
 * Builds a hierarchy of meshes M0 (the input) .. Mn, where M(i+1) is obtained from M(i) by
 * collapsing a batch of triangles with pairwise disjoint stencils at once. Each triangle is
 * collapsed to the point of a least-squares quadratic fitted to the original points of its
 * neighbourhood (so errors do not accumulate); the paper orders collapses by the weight
 * W(T) = A(T) (CurvatureWeight kappa + AngleWeight alpha + ValenceWeight V).
 *
 * The defaults keep the paper's hierarchy, batches, stencil rules and blending but order by
 * geometric error, which is what makes the result competitive with vtkQuadricDecimation:
 * ErrorWeight 1 (quadric error of the collapse point), QuadricCollapsePoint on, RelaxWhenBlocked
 * on, BatchSearchDepth 4, MinimumNormalDot 0.5, StarShapedInStencilPlane on, SwapBlockingEdges off
 * (so that the blend is continuous: M_i(1) is M_i+1), EdgeCollapses EDGE_COLLAPSES_EVERYWHERE with
 * PreferEdgeFactor 0.5 (edge collapses, in the same batches, records and blends, where a triangle
 * collapse is blocked or dearer per removed triangle: it removes four, an edge collapse two; with
 * the quadric error that is nearly everywhere) and VertexErrorWeight 10 (crease and corner
 * vertices pinned to their own planes). The paper's configuration is ErrorWeight 0,
 * QuadricCollapsePoint off, RelaxWhenBlocked off, BatchSearchDepth 0, MinimumNormalDot 0.2,
 * StarShapedInStencilPlane off, SwapBlockingEdges off, EdgeCollapses EDGE_COLLAPSES_OFF.
 *
 * Output 0 is one mesh of the hierarchy, chosen by (first that applies):
 *  - ContinuousLevel >= 0: M_i(t) for ContinuousLevel = i + t, where the triangles that collapse
 *    between M_i and M_i+1 are partially collapsed (their vertices moved by t toward their
 *    collapse points). Changing only this (or Level, or the targets) does not rebuild the
 *    hierarchy: it is cached, keyed on the input and the hierarchy parameters, and a blend costs
 *    one pass over the stored triangles (a few ms for 100k triangles), so a slider can drive it;
 *  - Level >= 0: M_Level;
 *  - otherwise the targets of every SurfaceLOD filter (slodFilterContract.h): TargetNumberOfTriangles
 *    and TargetReduction (each unused at 0; of both, the larger count; neither: a reduction of 0.9);
 *    the mesh after the number of collapses that gives the closest triangle count (collapses of a
 *    batch are independent, so a batch may be cut).
 * When only the target is asked for (GenerateAllLevels off, no Level, no ContinuousLevel), the
 * hierarchy is built only down to the level that reaches the target (the same levels as the
 * whole hierarchy's, so the same mesh; the levels below are not built, and "CollapseLevel" is -1
 * for the triangles that only they would collapse). Asking for a lower target or a level
 * afterwards rebuilds it.
 * Cell arrays: "CollapseLevel" (level at which the triangle disappears or changes, -1 never),
 * "CollapseBatch" (for a blended level: index of the collapse whose stencil holds the triangle,
 * -1 otherwise; colour by it like the paper's figures) and "CollapseRole" (2 collapsing triangle,
 * 1 stencil, 0 other). Point data are interpolated (collapse points: mean of the three vertices;
 * blended points: linear in t). Field data "HierarchyLevel" holds the level shown.
 *
 * Output 1 (when GenerateAllLevels is on) is a vtkMultiBlockDataSet with every level M0..Mn as a
 * block named "Level i", for LOD switching.
 *
 * The input must be a manifold triangle mesh (polygons are triangulated); triangles on the mesh
 * boundary or next to non-manifold parts are never collapsed (their stencils are incomplete).
 */
#ifndef vtkTriangleCollapseHierarchy_h
#define vtkTriangleCollapseHierarchy_h

#include "SurfaceLODFiltersModule.h"
#include "vtkSimplificationAlgorithm.h"

#include <memory>

class vtkMultiBlockDataSet;

class SURFACELODFILTERS_EXPORT vtkTriangleCollapseHierarchy : public vtkSimplificationAlgorithm
{
public:
  static vtkTriangleCollapseHierarchy* New();
  vtkTypeMacro(vtkTriangleCollapseHierarchy, vtkSimplificationAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Selection of the output mesh (see the class description; -1 / 0 = unused).
  vtkSetMacro(ContinuousLevel, double);
  vtkGetMacro(ContinuousLevel, double);
  vtkSetMacro(Level, int);
  vtkGetMacro(Level, int);
  ///@}

  ///@{
  /// Weights of the curvature, angle and valence terms (normalised to sum 1; paper: 1/3 each).
  vtkSetClampMacro(CurvatureWeight, double, 0.0, 1.0);
  vtkGetMacro(CurvatureWeight, double);
  vtkSetClampMacro(AngleWeight, double, 0.0, 1.0);
  vtkGetMacro(AngleWeight, double);
  vtkSetClampMacro(ValenceWeight, double, 0.0, 1.0);
  vtkGetMacro(ValenceWeight, double);
  ///@}

  ///@{
  /// Blend of the paper's weight with a geometric error term E(T) (quadric error of the collapse
  /// point against the original triangles merged into T, not in the paper):
  /// W = (1 - ErrorWeight) W_paper + ErrorWeight E(T). 0 gives the paper's ordering exactly.
  vtkSetClampMacro(ErrorWeight, double, 0.0, 1.0);
  vtkGetMacro(ErrorWeight, double);
  ///@}

  ///@{
  /// Collapse point on the line through T's centroid along its normal: the paper's point on the
  /// fitted quadratic (off), or the point of least quadric error on that line (on; used only when
  /// ErrorWeight > 0).
  vtkSetMacro(QuadricCollapsePoint, bool);
  vtkGetMacro(QuadricCollapsePoint, bool);
  vtkBooleanMacro(QuadricCollapsePoint, bool);
  ///@}

  ///@{
  /// Fraction of the triangles collapsed together per level (default 0.025).
  vtkSetClampMacro(BatchFraction, double, 1e-6, 1.0);
  vtkGetMacro(BatchFraction, double);
  ///@}

  ///@{
  /// Adaptive batch threshold (not in the paper): when > 0, a level looks no deeper into the
  /// priority order than this factor times the batch size, so that cheap triangles blocked by the
  /// rules do not force expensive ones into the batch (levels may then hold fewer than
  /// BatchFraction of the triangles, but at least a quarter of it). 0: unlimited.
  vtkSetClampMacro(BatchSearchDepth, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(BatchSearchDepth, double);
  ///@}

  ///@{
  /// Only triangles with weight / (mean input triangle area) below this collapse (0: no limit).
  vtkSetClampMacro(MaximumWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumWeight, double);
  ///@}

  ///@{
  /// m_v, the normaliser of the valence term (0: automatic, the largest |val - 6| of the input).
  vtkSetClampMacro(ValenceNormalizer, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(ValenceNormalizer, double);
  ///@}

  ///@{
  /// Remove stencil cycles by edge swaps before reducing (M0 then differs from the input).
  vtkSetMacro(RemoveCycles, bool);
  vtkGetMacro(RemoveCycles, bool);
  vtkBooleanMacro(RemoveCycles, bool);
  ///@}

  ///@{
  /// When no triangle passes the paper's collapsibility rules, retry the level with the
  /// valence-four rule relaxed and star-shapedness also tried in the stencil's mean plane,
  /// instead of stopping (not in the paper).
  /// Collapsibility rule (3) also passes when the stencil polygon is star-shaped in the plane of
  /// the stencil's mean normal, not only in the triangle's own plane (tilted for long thin
  /// triangles). Default on; off is the paper's rule.
  vtkSetMacro(StarShapedInStencilPlane, bool);
  vtkGetMacro(StarShapedInStencilPlane, bool);
  vtkBooleanMacro(StarShapedInStencilPlane, bool);

  /// Swap edges between levels so that vertices of valence 3 or 4 next to the new collapse points
  /// reach valence 5 (the paper's Fig. 3 cycle removal, applied on every level): they block their
  /// neighbours' collapses by rule (2). Only hinges whose normals agree to SwapMinimumNormalDot
  /// are swapped (SwapMinimumNormalDot 0.9999: flat parts only). Default off, as in the paper: a
  /// swap changes the surface between M_i(1) and M_i+1, so the blend jumps there; with the edge
  /// collapses the swaps are no longer needed to reach the quality goal.
  vtkSetMacro(SwapBlockingEdges, bool);
  vtkGetMacro(SwapBlockingEdges, bool);
  vtkBooleanMacro(SwapBlockingEdges, bool);
  vtkSetClampMacro(SwapMinimumNormalDot, double, -1.0, 1.0);
  vtkGetMacro(SwapMinimumNormalDot, double);
  /// When a level finds nothing to collapse (even relaxed), swap over the whole mesh with this
  /// looser limit and retry the level (1 = never).
  vtkSetClampMacro(SwapMinimumNormalDotWhenBlocked, double, -1.0, 1.0);
  vtkGetMacro(SwapMinimumNormalDotWhenBlocked, double);

  vtkSetMacro(RelaxWhenBlocked, bool);
  vtkGetMacro(RelaxWhenBlocked, bool);
  vtkBooleanMacro(RelaxWhenBlocked, bool);
  ///@}

  ///@{
  /// Edge collapses where triangle collapses are blocked (not in the paper): a triangle that fails
  /// the collapse rules collapses its cheapest valid edge instead (point of least quadric error of
  /// the ancestral planes), in the same batches, records, blends and vertex splits.
  /// EDGE_COLLAPSES_OFF: the paper; EDGE_COLLAPSES_WHEN_BLOCKED: only in levels where no triangle
  /// collapse is possible (targets are reached on meshes with thin parts);
  /// EDGE_COLLAPSES_EVERYWHERE: any blocked triangle, at its place in the priority order.
  enum
  {
    EDGE_COLLAPSES_OFF = 0,
    EDGE_COLLAPSES_WHEN_BLOCKED = 1,
    EDGE_COLLAPSES_EVERYWHERE = 2
  };
  vtkSetClampMacro(EdgeCollapses, int, EDGE_COLLAPSES_OFF, EDGE_COLLAPSES_EVERYWHERE);
  vtkGetMacro(EdgeCollapses, int);
  /// With EDGE_COLLAPSES_EVERYWHERE: a triangle whose cheapest edge collapse costs less than this
  /// factor times its triangle collapse (quadric error) takes the edge collapse even when the
  /// triangle collapse is allowed (0: edge collapses only where triangles are blocked). Default
  /// 0.5: the cheaper per removed triangle (a triangle collapse removes four, an edge collapse
  /// two); 0.1 (the default before session 16) keeps most triangle collapses, at a worse
  /// Hausdorff distance (mc1m at 10%: 1.35x vtkQuadricDecimation's instead of 1.04x).
  vtkSetClampMacro(PreferEdgeFactor, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(PreferEdgeFactor, double);
  /// No collapse leaves an interior vertex of valence 3 where there was none (default off: on, the
  /// hierarchy takes 1.20-1.26x the CPU on noisy scans, session 44; not in the paper, whose rule (2) covers triangle collapses only): an edge collapse may not take an
  /// interior vertex opposite the edge from valence 4 to 3 nor make a merged vertex of valence 3,
  /// and a triangle collapse may not leave a three-sided stencil polygon. Lifted, as rule (2), in
  /// a level where nothing passes (RelaxWhenBlocked), so that targets are still reached (a closed
  /// genus-0 surface below 8 triangles must have valence-3 vertices), and on levels with 5% of the
  /// input's triangles or fewer (it cost accuracy there). Off: the behaviour before session 43.
  vtkSetMacro(PreventNewValenceThree, bool);
  vtkGetMacro(PreventNewValenceThree, bool);
  vtkBooleanMacro(PreventNewValenceThree, bool);
  /// Feature protection in the error (not in the paper; needs ErrorWeight > 0 or edge collapses):
  /// adds this factor times the mean triangle area times the largest mean squared distance of the
  /// collapse point to the original planes of one merged vertex, so crease and corner vertices
  /// stay on their planes however small the faces around them (default 10; 0: the plain quadric).
  vtkSetClampMacro(VertexErrorWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(VertexErrorWeight, double);
  ///@}

  ///@{
  /// Weight of the planes that hold open borders (through each border edge of the input,
  /// perpendicular to its triangle) relative to the triangle planes, as vtkQuadricTriangleCollapse's
  /// option of the same name (default 10; 0 = free borders). Borders move only by edge collapses,
  /// so this acts with EdgeCollapses on; why 10 and not Garland and Heckbert's 1:
  /// slod::DefaultBorderPlaneWeight.
  vtkSetClampMacro(BoundaryWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(BoundaryWeight, double);
  ///@}

  ///@{
  /// Upper bound on the number of meshes in the hierarchy (default 1000).
  vtkSetClampMacro(MaximumNumberOfLevels, int, 1, VTK_INT_MAX);
  vtkGetMacro(MaximumNumberOfLevels, int);
  ///@}

  ///@{
  /// Stop building once a level has at most this many triangles (0: as far as possible).
  vtkSetClampMacro(MinimumNumberOfTriangles, vtkIdType, 0, VTK_INT_MAX);
  vtkGetMacro(MinimumNumberOfTriangles, vtkIdType);
  ///@}

  ///@{
  /// Flip guard: a collapse may not turn a surviving triangle's normal so that the cosine of the
  /// turn drops below this (default 0.2).
  vtkSetClampMacro(MinimumNormalDot, double, -1.0, 1.0);
  vtkGetMacro(MinimumNormalDot, double);
  ///@}

  ///@{
  /// How the build uses threads; the hierarchy is the same, bit for bit, for every setting and
  /// number of threads (slod::CollapseHierarchyParameters). DecideAhead (default off): the batch
  /// selection decides the coming candidates' choices concurrently. ParallelCollapses (default
  /// on): the batch's collapses applied in runs, concurrently. ParallelBookkeeping (default on):
  /// the working data's compactions and the evaluations' normal tests concurrent. Off: the serial
  /// reference.
  vtkSetMacro(DecideAhead, bool);
  vtkGetMacro(DecideAhead, bool);
  vtkBooleanMacro(DecideAhead, bool);
  vtkSetMacro(ParallelCollapses, bool);
  vtkGetMacro(ParallelCollapses, bool);
  vtkBooleanMacro(ParallelCollapses, bool);
  vtkSetMacro(ParallelBookkeeping, bool);
  vtkGetMacro(ParallelBookkeeping, bool);
  vtkBooleanMacro(ParallelBookkeeping, bool);
  ///@}

  ///@{
  /// Make output 0 (a Level or a target) by vertex splits: the coarsest mesh of the hierarchy
  /// expanded through the collapse records, newest first (the reverse of the hierarchy, as for
  /// progressive transmission: the coarsest mesh plus the records give every level and every
  /// triangle count), instead of from the stored levels. The mesh is the same either way (its
  /// cells in input-cell order); changing this does not rebuild the hierarchy. A ContinuousLevel
  /// blend always comes from the stored levels. Default off.
  vtkSetMacro(ExpandFromCoarsestLevel, bool);
  vtkGetMacro(ExpandFromCoarsestLevel, bool);
  vtkBooleanMacro(ExpandFromCoarsestLevel, bool);
  ///@}
  ///@{
  /// Produce every level on output port 1 (default on). Off, with no Level and no
  /// ContinuousLevel, the hierarchy is built only down to the target.
  vtkSetMacro(GenerateAllLevels, bool);
  vtkGetMacro(GenerateAllLevels, bool);
  vtkBooleanMacro(GenerateAllLevels, bool);
  ///@}

  /// All levels (output port 1).
  vtkMultiBlockDataSet* GetLevelsOutput();

  ///@{
  /// The hierarchy of the last update.
  int GetNumberOfLevels() const;                 ///< n + 1 meshes M0..Mn
  vtkIdType GetLevelNumberOfTriangles(int level) const;
  vtkIdType GetNumberOfCollapses() const;
  vtkIdType GetNumberOfEdgeCollapses() const; ///< of which edge collapses (EdgeCollapses fallback)
  double GetShownLevel() const { return this->ShownLevel; } ///< level (i + t) of output 0
  int GetNumberOfHierarchyBuilds() const { return this->NumberOfHierarchyBuilds; }
  double GetHierarchyBuildTime() const { return this->HierarchyBuildTime; } ///< seconds
  ///@}

protected:
  vtkTriangleCollapseHierarchy();
  ~vtkTriangleCollapseHierarchy() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double ContinuousLevel = -1;
  int Level = -1;
  double CurvatureWeight = 1.0 / 3.0;
  double AngleWeight = 1.0 / 3.0;
  double ValenceWeight = 1.0 / 3.0;
  double ErrorWeight = 1.0;
  bool QuadricCollapsePoint = true;
  double BatchFraction = 0.025;
  double BatchSearchDepth = 4.0;
  double MaximumWeight = 0.0;
  double ValenceNormalizer = 0.0;
  bool RemoveCycles = false;
  bool RelaxWhenBlocked = true;
  int EdgeCollapses = EDGE_COLLAPSES_EVERYWHERE;
  double PreferEdgeFactor = 0.5;
  bool PreventNewValenceThree = false;
  double VertexErrorWeight = 10.0;
  double BoundaryWeight = 10.0; // slod::DefaultBorderPlaneWeight (a test checks they agree)
  bool StarShapedInStencilPlane = true;
  bool SwapBlockingEdges = false;
  double SwapMinimumNormalDot = 0.9999;
  double SwapMinimumNormalDotWhenBlocked = 0.5;
  int MaximumNumberOfLevels = 1000;
  vtkIdType MinimumNumberOfTriangles = 0;
  double MinimumNormalDot = 0.5;
  bool GenerateAllLevels = true;
  bool ExpandFromCoarsestLevel = false;
  bool DecideAhead = false;
  bool ParallelCollapses = true;
  bool ParallelBookkeeping = true;

  double ShownLevel = 0;
  int NumberOfHierarchyBuilds = 0;
  double HierarchyBuildTime = 0;

private:
  vtkTriangleCollapseHierarchy(const vtkTriangleCollapseHierarchy&) = delete;
  void operator=(const vtkTriangleCollapseHierarchy&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
