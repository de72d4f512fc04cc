// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkLODInterpolation
 * @brief   in-between mesh of a detailed and a coarse level of detail (Pan, Zhou, Shi 2000, §4)
 *
 * Input 0 is the detailed mesh, input 1 a coarse mesh of the same object (any simplification,
 * the vertices need not be a subset). The output lives on the detailed mesh's connectivity:
 *  1. every coarse vertex is matched with its nearest detailed vertex;
 *  2. every detailed vertex left without a match gets its nearest coarse vertex (a detailed
 *     vertex matched by several coarse vertices keeps the nearest of them);
 *  3. each detailed vertex P_h moves to P = t * P_l + (1 - t) * P_h, P_l its coarse match;
 *  4. adjacent vertices closer than Epsilon (relative to the detailed mesh's bounding-box
 *     diagonal) are merged and the triangles that degenerate are removed (not when both already
 *     sit on their coarse matches: an edge that does not move is kept, so small triangles the
 *     coarse mesh shares do not vanish as soon as t leaves 0).
 * Nearest vertices are found with vtkStaticPointLocator (both directions). As in the paper, t = 0
 * is the detailed mesh and t = 1 the coarse one; at the two ends the output is exactly the
 * corresponding input (the merged detailed mesh at t = 1 has the coarse vertices but may differ
 * from the coarse triangulation, so the end point is taken as is).
 * Point data of the detailed mesh is carried to the vertices that remain.
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

  ///@{
  /// Interpolation parameter t in [0, 1]: 0 = detailed, 1 = coarse (default 0.5).
  vtkSetClampMacro(T, double, 0.0, 1.0);
  vtkGetMacro(T, double);
  ///@}

  ///@{
  /// Merge distance for adjacent vertices, relative to the bounding-box diagonal (default 1e-3).
  vtkSetClampMacro(Epsilon, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Epsilon, double);
  ///@}

  ///@{
  /// Results of the last update: merged vertices and removed degenerate triangles.
  vtkGetMacro(MergedVertices, vtkIdType);
  vtkGetMacro(RemovedTriangles, vtkIdType);
  ///@}

protected:
  vtkLODInterpolation();
  ~vtkLODInterpolation() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double T = 0.5;
  double Epsilon = 1e-3;
  vtkIdType MergedVertices = 0;
  vtkIdType RemovedTriangles = 0;

private:
  vtkLODInterpolation(const vtkLODInterpolation&) = delete;
  void operator=(const vtkLODInterpolation&) = delete;
};

#endif
