// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSurfaceDeviation
 * @brief   two-sided point-to-surface distance between two triangle meshes
 *
 * Input 0 is the reference surface A, input 1 the surface B to compare with it (for example a
 * simplified version of A). Samples are taken on each surface (all of its vertices plus
 * NumberOfSamples deterministic, area-weighted random points on its triangles) and their
 * distance to the closest point of the other surface is measured with a bounding-volume
 * hierarchy. The output is a shallow copy of input 1 with a point array "Distance" (distance of
 * each of B's points to A) and field data with the results (absolute and relative to the
 * bounding-box diagonal of A):
 *   "Hausdorff", "HausdorffAB", "HausdorffBA", "Mean", "RMS", "MeanAB", "MeanBA", "RMSAB",
 *   "RMSBA", "BoundingBoxDiagonal", and the same divided by the diagonal with the suffix
 *   "Relative" (e.g. "HausdorffRelative").
 * AB means samples on A measured to B. Mean and RMS are computed over the random samples only
 * (unbiased surface averages); the maxima include the vertices. The symmetric Mean / RMS are
 * the averages of the two sides.
 * The results are also available through getters after Update().
 *
 * A side without a usable triangle (empty, or every triangle degenerate: a repeated vertex after
 * the input preparation), an invalid input (NaN/Inf on a used point) or an abort is an error (vtkErrorMacro,
 * except abort): the results are NaN and the output is empty. A 0 therefore always means a
 * measured 0.
 */
#ifndef vtkSurfaceDeviation_h
#define vtkSurfaceDeviation_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <cmath>

class SURFACELODFILTERS_EXPORT vtkSurfaceDeviation : public vtkPolyDataAlgorithm
{
public:
  static vtkSurfaceDeviation* New();
  vtkTypeMacro(vtkSurfaceDeviation, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Convenience: set the reference surface A (input port 0) and the compared surface B (port 1).
  void SetReferenceConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(0, output); }
  void SetComparedConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetReferenceData(vtkDataObject* input) { this->SetInputData(0, input); }
  void SetComparedData(vtkDataObject* input) { this->SetInputData(1, input); }

  ///@{
  /// Random area-weighted samples per surface, in addition to all vertices (default 300000).
  vtkSetClampMacro(NumberOfSamples, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(NumberOfSamples, vtkIdType);
  ///@}

  ///@{
  /// Seed of the deterministic sampler (default 12345).
  vtkSetMacro(Seed, unsigned int);
  vtkGetMacro(Seed, unsigned int);
  ///@}

  ///@{
  /// Include every vertex as a sample (default on).
  vtkSetMacro(SampleVertices, bool);
  vtkGetMacro(SampleVertices, bool);
  vtkBooleanMacro(SampleVertices, bool);
  ///@}

  ///@{
  /// Results of the last update, absolute (in A's units).
  vtkGetMacro(Hausdorff, double);
  vtkGetMacro(HausdorffAB, double);
  vtkGetMacro(HausdorffBA, double);
  vtkGetMacro(Mean, double);
  vtkGetMacro(RMS, double);
  vtkGetMacro(MeanAB, double);
  vtkGetMacro(MeanBA, double);
  vtkGetMacro(RMSAB, double);
  vtkGetMacro(RMSBA, double);
  vtkGetMacro(BoundingBoxDiagonal, double);
  ///@}

  /// The same divided by A's bounding-box diagonal (0 when the diagonal is 0; NaN stays NaN).
  double GetHausdorffRelative() const { return this->Relative(this->Hausdorff); }
  double GetHausdorffABRelative() const { return this->Relative(this->HausdorffAB); }
  double GetHausdorffBARelative() const { return this->Relative(this->HausdorffBA); }
  double GetMeanRelative() const { return this->Relative(this->Mean); }
  double GetRMSRelative() const { return this->Relative(this->RMS); }

protected:
  vtkSurfaceDeviation();
  ~vtkSurfaceDeviation() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void ClearResults();
  // The deviations as field data of the output (values and their "...Relative" twins).
  void StoreResults(vtkPolyData* inputB, vtkPolyData* output);
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Relative(double value) const
  {
    return this->BoundingBoxDiagonal > 0 || std::isnan(value) ? value / this->BoundingBoxDiagonal : 0.0;
  }

  vtkIdType NumberOfSamples = 300000;
  unsigned int Seed = 12345;
  bool SampleVertices = true;

  // NaN until a comparison succeeds (set in the constructor and at the start of every update).
  double Hausdorff, HausdorffAB, HausdorffBA;
  double Mean, RMS, MeanAB, MeanBA, RMSAB, RMSBA;
  double BoundingBoxDiagonal = 0;

private:
  vtkSurfaceDeviation(const vtkSurfaceDeviation&) = delete;
  void operator=(const vtkSurfaceDeviation&) = delete;
};

#endif
