// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkProgressiveMeshReconstruction
 * @brief   any level of a progressive mesh from a coarse mesh and its collapse records
 *
 * Input 0 is the coarse mesh made by vtkQuadricTriangleCollapse with GenerateProgressiveMesh on
 * (it carries the point array "OriginalVertexId" and the cell array "OriginalTriangleId"),
 * input 1 its collapse records (vtkQuadricTriangleCollapse output port 1, a vtkTable). The
 * records are undone newest first by vertex splits (paper §3): each split turns the vertex v0
 * back into the three vertices v1, v2, v3 of the collapsed triangle at their old positions,
 * gives the surrounding triangles their previous corners and restores the removed triangles.
 * Undoing all records rebuilds the (prepared) input mesh exactly.
 *
 * The level is NumberOfVertexSplits (-1, the default, = all) or, when TargetNumberOfTriangles is
 * positive, the fewest splits that reach at least that many triangles. The filter keeps the
 * current level between updates: going from level j to level k costs |k - j| splits or
 * re-collapses, so browsing the levels interactively is cheap; only a change of the inputs
 * rebuilds the state (linear in the input size).
 *
 * The output carries the point array "OriginalVertexId" (prepared input vertex ids).
 *
 * Cell data: with the original mesh (the collapse filter's input) on the optional input 2, each
 * output triangle carries the cell data of its own input cell (slodAttributeTransfer.h). Without
 * it only the coarse triangles would have theirs, so none is carried (with a warning when the
 * coarse mesh has cell data).
 */
#ifndef vtkProgressiveMeshReconstruction_h
#define vtkProgressiveMeshReconstruction_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <memory>

class SURFACELODFILTERS_EXPORT vtkProgressiveMeshReconstruction : public vtkPolyDataAlgorithm
{
public:
  static vtkProgressiveMeshReconstruction* New();
  vtkTypeMacro(vtkProgressiveMeshReconstruction, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Convenience: the coarse mesh (port 0) and the collapse records (port 1).
  void SetCoarseMeshConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(0, output); }
  void SetRecordsConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  /// Optional: the original mesh (the collapse filter's input, port 2), whose cell data is carried.
  void SetOriginalMeshConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(2, output); }

  ///@{
  /// Number of vertex splits applied to the coarse mesh (-1 = all, default).
  vtkSetClampMacro(NumberOfVertexSplits, vtkIdType, -1, VTK_ID_MAX);
  vtkGetMacro(NumberOfVertexSplits, vtkIdType);
  ///@}

  ///@{
  /// When positive, overrides NumberOfVertexSplits: split until at least this many triangles.
  vtkSetClampMacro(TargetNumberOfTriangles, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(TargetNumberOfTriangles, vtkIdType);
  ///@}

  ///@{
  /// Results of the last update: splits applied in total, and how many operations (splits or
  /// re-collapses) the update itself needed.
  vtkGetMacro(AppliedVertexSplits, vtkIdType);
  vtkGetMacro(OperationsLastUpdate, vtkIdType);
  ///@}

protected:
  vtkProgressiveMeshReconstruction();
  ~vtkProgressiveMeshReconstruction() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkIdType NumberOfVertexSplits = -1;
  vtkIdType TargetNumberOfTriangles = 0;
  vtkIdType AppliedVertexSplits = 0;
  vtkIdType OperationsLastUpdate = 0;

private:
  vtkProgressiveMeshReconstruction(const vtkProgressiveMeshReconstruction&) = delete;
  void operator=(const vtkProgressiveMeshReconstruction&) = delete;
  struct State;
  std::unique_ptr<State> Cache;
};

#endif
