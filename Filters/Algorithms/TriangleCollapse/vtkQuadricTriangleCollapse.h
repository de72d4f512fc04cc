// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkQuadricTriangleCollapse
 * @brief   quadric-error simplification by triangle collapses (Pan, Zhou, Shi 2000)
 *
 * Each step merges the three vertices of the cheapest triangle into one new vertex, removing
 * the triangle and its edge neighbours (usually 4 triangles and 2 vertices per step). The cost
 * of a triangle is the sum of squared distances of the new vertex to the planes of the ORIGINAL
 * triangles its vertices descend from (the paper's logical interrelated set), area weighted;
 * the new vertex minimises it (3x3 solve), or is the best of the centroid, the vertices and
 * the edge midpoints when the system is ill-conditioned. Open borders are held by planes through
 * each boundary edge perpendicular to its triangle (BoundaryWeight).
 *
 * EdgeCollapses (default on) extends the paper: each triangle also offers its three edge
 * collapses (2 vertices -> 1, same quadrics and placement rules) and the cheapest of the four
 * operations is performed. A triangle collapse cannot remove a vertex whose triangles all hold
 * two feature vertices (a plane bordered by creases, a region between a crease and a border)
 * without moving the feature, so triangle collapses alone lose accuracy at a given triangle
 * count; with EdgeCollapses off the filter performs the paper's operation only.
 *
 * Union semantics: by default each vertex accumulates the quadric of its logical set and a
 * triangle's quadric is the sum of its three vertex quadrics, so planes shared by two or three of
 * the vertices count two or three times instead of once (all planes are still original planes:
 * no error accumulates). ExactUnion keeps per-vertex sets and counts each plane once, as in the
 * paper; it is slower and uses more memory, and measured quality is the same (see
 * Documentation/QuadricTriangleCollapse.md).
 *
 * Validity: a collapse is never performed when it would flip or degenerate a triangle (normal
 * turning more than MaximumNormalDeviation degrees; when no valid collapse is left before the
 * target the limit is relaxed step by step up to 90 degrees), create a non-manifold edge or
 * vertex, close, split, join or remove a boundary loop, leave a vertex without triangles, or change the
 * genus, unless AllowTopologyChange is on (then only the geometric tests apply). A rejected
 * operation is replaced by the triangle's next best one. Non-manifold input parts are kept as
 * they are; a mesh whose topology forbids further collapses (e.g. many small holes, each kept
 * with at least 3 border vertices) stops above the target.
 *
 * Stop criteria, the targets of every SurfaceLOD filter (slodFilterContract.h), whichever is
 * reached first: TargetNumberOfTriangles (0 = unused), TargetReduction (fraction of triangles to
 * remove, 0 = unused) and MaximumError (0 = unused; collapses whose error exceeds it are never
 * performed; absolute, or relative to the bounding-box diagonal when MaximumErrorIsRelative); with
 * none set, a reduction of 0.9. A triangle target is met within one collapse (the output has at
 * most the target count and at most 3 fewer). Abort gives an empty output with a warning.
 *
 * Output 0: the simplified mesh with all numeric point arrays interpolated onto the new vertices,
 * a point array "SimplificationError" (RMS distance of each vertex to its original planes) and
 * field data "MaximumSimplificationError" (largest performed collapse error) and
 * "MaximumSimplificationErrorRelative". With GenerateProgressiveMesh on, also point data
 * "OriginalVertexId" and cell data "OriginalTriangleId" (ids of the prepared input mesh).
 *
 * Output 1 (GenerateProgressiveMesh on): the collapse records as a vtkTable, one row per collapse
 * in collapse order, columns "Vertices" (3 ids: kept vertex v0 first, then the two removed),
 * "OldPositions" (9), "NewPosition" (3), "RemovedTriangles" (4 triangle ids, -1 padded),
 * "RemovedTriangleVertices" (12), "ChangedOffset" and "SurroundingOffset" (start of the row's
 * entries in the field-data arrays "Changed" (triangle id, corner, previous vertex per redirected
 * corner) and "Surrounding" (the paper's surrounding vertices)), with field data
 * "NumberOfInputPoints" and "NumberOfInputTriangles" (of the prepared input mesh).
 * vtkProgressiveMeshReconstruction rebuilds any level from output 0 + output 1.
 *
 * Distributed pieces: when the Controller (default: the global controller) runs more than one
 * process, each process simplifies its own piece of one surface. Cells marked as ghosts in
 * vtkGhostType are dropped first; the piece's vertices that another piece also holds (the seam,
 * found by exact coordinates with the controller's collectives, slodPieceSeams.h: any shared
 * point, on a border or not) are locked: never removed or moved, so the union of the outputs has
 * no crack. A triangle target (TargetNumberOfTriangles or TargetReduction) is set for the union:
 * the pieces agree while collapsing on how to divide it, cheapest collapses first wherever they
 * are (slod::UnionTargetAgreement), and a relative MaximumError is relative to the union's
 * diagonal. RequestData is then collective: every process must update the filter.
 */
#ifndef vtkQuadricTriangleCollapse_h
#define vtkQuadricTriangleCollapse_h

#include "SurfaceLODFiltersModule.h"
#include "vtkErrorBoundedSimplificationAlgorithm.h"

class vtkMultiProcessController;
class vtkTable;

class SURFACELODFILTERS_EXPORT vtkQuadricTriangleCollapse : public vtkErrorBoundedSimplificationAlgorithm
{
public:
  static vtkQuadricTriangleCollapse* New();
  vtkTypeMacro(vtkQuadricTriangleCollapse, vtkErrorBoundedSimplificationAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Weight of the boundary planes relative to the triangle planes (default 10; 0 = free borders).
  /// Both are in area units, so the weight does not depend on the mesh's scale; why 10 and not
  /// Garland and Heckbert's 1: slod::DefaultBorderPlaneWeight.
  vtkSetClampMacro(BoundaryWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(BoundaryWeight, double);
  ///@}

  ///@{
  /// Largest turn of a surviving triangle's normal in one collapse, in degrees (default 45;
  /// tighter keeps sharper features and fewer slivers).
  vtkSetClampMacro(MaximumNormalDeviation, double, 0.0, 90.0);
  vtkGetMacro(MaximumNormalDeviation, double);
  ///@}

  ///@{
  /// Allow genus, boundary-loop and manifoldness changes (default off).
  vtkSetMacro(AllowTopologyChange, bool);
  vtkGetMacro(AllowTopologyChange, bool);
  vtkBooleanMacro(AllowTopologyChange, bool);
  ///@}

  ///@{
  /// Also consider the three edge collapses of every triangle and perform the cheapest
  /// operation (default on). Off: triangle collapses only, exactly the paper's operation (faster,
  /// but the coarser operation costs accuracy at a given triangle count). An edge collapse's cost
  /// is multiplied by EdgeCollapseBias (default 2: it removes half as many triangles) before the
  /// comparison.
  vtkSetMacro(EdgeCollapses, bool);
  vtkGetMacro(EdgeCollapses, bool);
  vtkBooleanMacro(EdgeCollapses, bool);
  vtkSetClampMacro(EdgeCollapseBias, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(EdgeCollapseBias, double);
  ///@}

  ///@{
  /// Deviation refinement (default on; a departure from the paper): after the collapses, the
  /// merged vertices of the few regions with the largest deviation from the input are moved within
  /// their one-ring to lower the local maximum distance (both directions). Connectivity is
  /// unchanged and no triangle turns by more than MaximumNormalDeviation. Off: the paper's result.
  vtkSetMacro(DeviationRefinement, bool);
  vtkGetMacro(DeviationRefinement, bool);
  vtkBooleanMacro(DeviationRefinement, bool);
  ///@}

  ///@{
  /// Fit to the original surface (default on; a departure from the paper): after the collapses,
  /// every merged interior vertex moves to the least-squares fit of the input surface around it
  /// (distances of the input's vertices and triangle centroids to the output along its normals),
  /// two sweeps, before the deviation refinement. It lowers the mean distance; connectivity, the
  /// triangle count and the progressive records stay exact. Off with DeviationRefinement off:
  /// the paper's result.
  vtkSetMacro(FitToOriginal, bool);
  vtkGetMacro(FitToOriginal, bool);
  vtkBooleanMacro(FitToOriginal, bool);
  ///@}

  ///@{
  /// Exact union of the interrelated sets (each original plane once; slower reference mode). The
  /// fit and the deviation refinement do not run in this mode.
  vtkSetMacro(ExactUnion, bool);
  vtkGetMacro(ExactUnion, bool);
  vtkBooleanMacro(ExactUnion, bool);
  ///@}

  ///@{
  /// Collapse in batches (default off): the cheapest operations whose costs are within
  /// BatchCostTolerance (relative, default 0.01) of the cheapest and whose one-rings are pairwise
  /// disjoint are checked and performed in parallel (vtkSMPTools); the queue updates follow in
  /// cost order. The output is the same for any number of threads. Off: the strict greedy order,
  /// one collapse at a time (on the shared 2-core machine the batches were not faster yet).
  vtkSetMacro(BatchCollapses, bool);
  vtkGetMacro(BatchCollapses, bool);
  vtkBooleanMacro(BatchCollapses, bool);
  vtkSetClampMacro(BatchCostTolerance, double, 0.0, 1.0);
  vtkGetMacro(BatchCostTolerance, double);
  /// With BatchCollapses: a batch that will hold fewer entries than this (the queued costs within
  /// the tolerance, counted before it is formed; default 16, the entries one task runs) is
  /// performed as a lone pop of the strict order; 1: every batch as selected.
  vtkSetClampMacro(BatchMinimumSize, int, 1, 1024);
  vtkGetMacro(BatchMinimumSize, int);
  ///@}

  ///@{
  /// The order of the collapses: QUEUE (0, default) always performs the cheapest operation left
  /// (one priority queue); PASSES (1) costs every triangle's cheapest operation at once, ranks
  /// them and performs, pass by pass, the cheapest under a limit that do not touch each other's
  /// one-rings, checked and collapsed in parallel (as meshoptimizer's simplifier; the output is the
  /// same for any number of threads). With GenerateProgressiveMesh, ExactUnion or
  /// AttributeErrorMetric, and for a distributed surface, the queue runs whatever this says.
  /// PassGoalShare (default 0.2) and PassErrorFactor (default 1.5) set a pass's limit: the factor
  /// times the cost of rank share x (triangles still to remove); smaller: more, finer passes.
  ///@{
  /// TriangleCostBound (default off): a triangle's own (three-vertex) collapse is placed only when
  /// a bound from its edges' cached costs says it can be the triangle's cheapest operation (the
  /// triangle's quadric is at least half the sum of its edges' and at least each of them);
  /// otherwise the triangle is keyed by its cheapest edge. Fewer 3x3 solves per collapse; the
  /// outputs change where rounding or fallback placements break the bound (session 40).
  vtkSetMacro(TriangleCostBound, bool);
  vtkGetMacro(TriangleCostBound, bool);
  vtkBooleanMacro(TriangleCostBound, bool);
  ///@}

  ///@{
  /// FitExactAssignmentLimit (default 300,000): up to this many input vertices the fit to the
  /// original assigns every original vertex to its closest output triangle (one BVH query each) to
  /// know exactly which ones a move can take farther away; above, it watches the original vertices
  /// of the moved vertex's neighbourhood (cheaper, may miss a few). 0: never exact.
  vtkSetClampMacro(FitExactAssignmentLimit, int, 0, VTK_INT_MAX);
  vtkGetMacro(FitExactAssignmentLimit, int);
  ///@}

  ///@{
  /// LookAheadEvaluations (default 0: off): with more than one thread the queue's order also
  /// evaluates up to this many upcoming pops ahead in parallel (their checks and, for the valid
  /// ones, the new costs around their collapses), those whose one-rings no earlier one of them
  /// touches; a pop that is one of them takes that work. The output is the same for any value and
  /// any number of threads (sessions 33 and 36). Since session 37 the work ahead runs on one worker
  /// thread beside the loop for the whole run; the loop evaluates what the worker has not claimed.
  vtkSetClampMacro(LookAheadEvaluations, int, 0, 512);
  vtkGetMacro(LookAheadEvaluations, int);
  ///@}

  enum CollapseScheduleType
  {
    QUEUE = 0,
    PASSES = 1
  };
  vtkSetClampMacro(CollapseSchedule, int, QUEUE, PASSES);
  vtkGetMacro(CollapseSchedule, int);
  void SetCollapseScheduleToQueue() { this->SetCollapseSchedule(QUEUE); }
  void SetCollapseScheduleToPasses() { this->SetCollapseSchedule(PASSES); }
  vtkSetClampMacro(PassGoalShare, double, 0.001, 1.0);
  vtkGetMacro(PassGoalShare, double);
  vtkSetClampMacro(PassErrorFactor, double, 1.0, 100.0);
  vtkGetMacro(PassErrorFactor, double);
  /// PassRemovalShare (default 0.1; 1: off): a pass ends once it has removed this share of the
  /// triangles still to remove at its start, so that the next pass re-ranks around its collapses
  /// (closer to the queue's order, more passes; Documentation/QuadricTriangleCollapse.md, sessions
  /// 19 and 26).
  vtkSetClampMacro(PassRemovalShare, double, 0.001, 1.0);
  vtkGetMacro(PassRemovalShare, double);
  ///@}

  ///@{
  /// Attribute seams kept as features (default on; nothing changes where there are none): the
  /// vertices of a seam, border vertices with another border vertex within 1e-6 of the diagonal
  /// whose point data differ (texture seams, split normals; see slod::AttributeSeamVertexFlags),
  /// and, with RegionArrayName set, the vertices where cells of different values of that cell
  /// array meet, stay exactly where they are with their point data: other vertices may merge into
  /// them, two of them never merge. A seam then stays the same polyline on both of its sides and
  /// no triangle crosses a region border; their vertices are never removed (see
  /// Documentation/Attributes.md).
  vtkSetMacro(PreserveAttributeSeams, bool);
  vtkGetMacro(PreserveAttributeSeams, bool);
  vtkBooleanMacro(PreserveAttributeSeams, bool);
  ///@}

  ///@{
  /// The cell array (component 0) whose region borders are kept with PreserveAttributeSeams
  /// (default none). A name the input does not have is a warning.
  vtkSetStringMacro(RegionArrayName);
  vtkGetStringMacro(RegionArrayName);
  ///@}

  ///@{
  /// Point attributes in the cost and the placement (VTK's name; default off). Each active
  /// attribute of the input's point data with a weight above 0 (scalars, vectors, normals, texture
  /// coordinates, tensors: numeric arrays) enters the quadric of every triangle: the squared
  /// difference of each component from its linear interpolation over the triangle, area-weighted,
  /// a difference of the attribute's range (of its largest component range; 2 for normals)
  /// counting as Weight x the bounding-box diagonal of distance. The placement minimises position
  /// and attributes together, and a merged vertex gets the minimiser's attribute values (normals
  /// renormalised, integer arrays rounded and clamped). Other arrays are interpolated as before;
  /// SimplificationError and MaximumError stay geometric. Ignored with ExactUnion (a warning).
  /// Memory: per vertex 10 doubles and 4 per attribute component, only when on. See
  /// Documentation/Attributes.md.
  vtkSetMacro(AttributeErrorMetric, bool);
  vtkGetMacro(AttributeErrorMetric, bool);
  vtkBooleanMacro(AttributeErrorMetric, bool);
  vtkSetClampMacro(ScalarsWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(ScalarsWeight, double);
  vtkSetClampMacro(VectorsWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(VectorsWeight, double);
  vtkSetClampMacro(NormalsWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(NormalsWeight, double);
  vtkSetClampMacro(TCoordsWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(TCoordsWeight, double);
  vtkSetClampMacro(TensorsWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(TensorsWeight, double);
  ///@}

  ///@{
  /// Record every collapse (output 1) and add the id arrays to output 0 (default off).
  vtkSetMacro(GenerateProgressiveMesh, bool);
  vtkGetMacro(GenerateProgressiveMesh, bool);
  vtkBooleanMacro(GenerateProgressiveMesh, bool);
  ///@}

  /// The paper's configuration (Pan, Zhou, Shi 2000): triangle collapses only, the exact union of
  /// the interrelated sets, no pass after the collapses (EdgeCollapsesOff, ExactUnionOn,
  /// FitToOriginalOff, DeviationRefinementOff). The other settings are left as they are.
  void UsePaperConfiguration();

  ///@{
  /// Results of the last update. NumberOfEdgeCollapses of the NumberOfCollapses merged two
  /// vertices (the others are triangle collapses, three vertices); NumberOfFittedVertices were
  /// moved by the fit to the original, NumberOfRefinedVertices moves made by the refinement.
  vtkGetMacro(ActualReduction, double);
  vtkGetMacro(NumberOfCollapses, vtkIdType);
  vtkGetMacro(NumberOfEdgeCollapses, vtkIdType);
  vtkGetMacro(NumberOfFittedVertices, vtkIdType);
  vtkGetMacro(NumberOfRefinedVertices, vtkIdType);
  vtkGetMacro(MaximumSimplificationError, double);
  ///@}

  /// The collapse records (output port 1).
  vtkTable* GetCollapseRecords();

  ///@{
  /// The processes over which the input's pieces are spread (default: the global controller;
  /// nullptr or one process: the input is the whole surface).
  virtual void SetController(vtkMultiProcessController*);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

protected:
  vtkQuadricTriangleCollapse();
  ~vtkQuadricTriangleCollapse() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double BoundaryWeight = 10.0; // slod::DefaultBorderPlaneWeight (a test checks they agree)
  double MaximumNormalDeviation = 45.0;
  bool AllowTopologyChange = false;
  bool ExactUnion = false;
  bool DeviationRefinement = true;
  bool FitToOriginal = true;
  bool EdgeCollapses = true;
  double EdgeCollapseBias = 2.0;
  bool GenerateProgressiveMesh = false;
  bool BatchCollapses = false;
  double BatchCostTolerance = 0.01;
  int BatchMinimumSize = 16;
  int CollapseSchedule = QUEUE;
  int LookAheadEvaluations = 0;
  bool TriangleCostBound = false;
  int FitExactAssignmentLimit = 300000;
  double PassGoalShare = 0.2;
  double PassErrorFactor = 1.5;
  double PassRemovalShare = 0.1;
  bool PreserveAttributeSeams = true;
  char* RegionArrayName = nullptr;
  bool AttributeErrorMetric = false;
  double ScalarsWeight = 0.1;
  double VectorsWeight = 0.1;
  double NormalsWeight = 0.1;
  double TCoordsWeight = 0.1;
  double TensorsWeight = 0.1;
  vtkMultiProcessController* Controller = nullptr;

  double ActualReduction = 0.0;
  vtkIdType NumberOfCollapses = 0;
  vtkIdType NumberOfEdgeCollapses = 0;
  vtkIdType NumberOfFittedVertices = 0;
  vtkIdType NumberOfRefinedVertices = 0;
  double MaximumSimplificationError = 0.0;

private:
  vtkQuadricTriangleCollapse(const vtkQuadricTriangleCollapse&) = delete;
  void operator=(const vtkQuadricTriangleCollapse&) = delete;
};

#endif
