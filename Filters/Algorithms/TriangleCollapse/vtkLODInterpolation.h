// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkLODInterpolation
 * @brief   in-between mesh of a detailed and a coarse level of detail (Pan, Zhou, Shi 2000, §4)
 *
 * Input 0 is the detailed mesh, input 1 a coarse mesh of the same object, input 2 (optional) the
 * collapse records of vtkQuadricTriangleCollapse (its output port 1). The output always lives on
 * the detailed mesh's connectivity; each detailed vertex P_h moves on a straight line,
 * P = (1 - t) * P_h + t * P_l, towards its coarse vertex P_l. Which coarse vertex that is depends on
 * the inputs:
 *
 * - With records (the geomorph): P_l is the coarse vertex the detailed vertex collapses into
 *   through the records (its ancestor). The detailed mesh is a level of those records (the
 *   collapse filter's input, or a vtkProgressiveMeshReconstruction level, carrying
 *   OriginalVertexId) and the coarse mesh a later level (the collapse filter's output with
 *   GenerateProgressiveMesh, or a coarser reconstruction level); anything else is an error. The
 *   vertices of one ancestor are merged exactly when their interpolated positions all coincide
 *   (in exact arithmetic only at t = 1), and the triangles that then degenerate are dropped: the
 *   output is the detailed mesh at t = 0, the coarse mesh at t = 1, manifold with the detailed
 *   mesh's connectivity in between, and every vertex moves by |P_l - P_h| * |dt| when t changes
 *   by dt (continuous at both ends). Epsilon is not used.
 * - Without records (the paper's Sec. 4, for any two meshes): every coarse vertex is matched
 *   with its nearest detailed vertex; every detailed vertex left without a match gets its nearest
 *   coarse vertex (a detailed vertex matched by several coarse vertices keeps the nearest);
 *   adjacent vertices are merged when their edge has shrunk below Epsilon (relative to the
 *   detailed mesh's bounding-box diagonal) or to zero length, and the triangles that degenerate
 *   are removed. At t = 0 this is the detailed mesh; at t = 1 it is the detailed connectivity on
 *   the coarse vertices, which need not be the coarse triangulation (it may have duplicate
 *   triangles and non-manifold edges), and merges make it jump by up to Epsilon.
 *
 * No value of t is treated specially. Nearest vertices are found with vtkStaticPointLocator (both
 * directions). Point data of the detailed mesh is carried to the vertices that remain, cell data
 * to the triangles that remain.
 */
#ifndef vtkLODInterpolation_h
#define vtkLODInterpolation_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkLODInterpolation : public vtkPolyDataAlgorithm
{
public:
  static vtkLODInterpolation* New();
  vtkTypeMacro(vtkLODInterpolation, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Convenience: the detailed mesh (port 0) and the coarse mesh (port 1).
  void SetDetailedConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(0, output); }
  void SetCoarseConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetDetailedData(vtkDataObject* input) { this->SetInputData(0, input); }
  void SetCoarseData(vtkDataObject* input) { this->SetInputData(1, input); }
  /// Optional: the collapse records (vtkQuadricTriangleCollapse port 1) relating the two levels.
  void SetRecordsConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(2, output); }
  void SetRecordsData(vtkDataObject* input) { this->SetInputData(2, input); }

  ///@{
  /// Interpolation parameter t in [0, 1]: 0 = detailed, 1 = coarse (default 0.5).
  vtkSetClampMacro(T, double, 0.0, 1.0);
  vtkGetMacro(T, double);
  ///@}

  ///@{
  /// Without records: merge distance for adjacent vertices whose edge shrank, relative to the
  /// bounding-box diagonal (default 1e-3; the paper's step 4). Not used with records.
  vtkSetClampMacro(Epsilon, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Epsilon, double);
  ///@}

  ///@{
  /// Results of the last update: merged vertices, removed degenerate triangles, and whether the
  /// correspondence came from collapse records (true) or nearest vertices (false).
  vtkGetMacro(MergedVertices, vtkIdType);
  vtkGetMacro(RemovedTriangles, vtkIdType);
  vtkGetMacro(UsedCollapseRecords, bool);
  ///@}

protected:
  vtkLODInterpolation();
  ~vtkLODInterpolation() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double T = 0.5;
  double Epsilon = 1e-3;
  vtkIdType MergedVertices = 0;
  vtkIdType RemovedTriangles = 0;
  bool UsedCollapseRecords = false;

private:
  vtkLODInterpolation(const vtkLODInterpolation&) = delete;
  void operator=(const vtkLODInterpolation&) = delete;
};

#endif
