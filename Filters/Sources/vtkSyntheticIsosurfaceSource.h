// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSyntheticIsosurfaceSource
 * @brief   deterministic closed test surface: isosurface of a smooth synthetic scalar field
 *
 * A benchmark and demo mesh that needs no data file. The scalar field is
 *
 *   f(p) = sum_{k=0..7} exp(-|p - c_k|^2 / (2 s_k^2)) + 0.05 sin(11 x) sin(11 y + 1) sin(11 z + 2)
 *
 * with eight Gaussian blobs on a wavy ring, theta_k = k pi / 4:
 *   c_k = (0.6 cos theta_k, 0.6 sin theta_k, 0.12 sin 2 theta_k),  s_k = 0.19 + 0.03 cos 3 theta_k,
 * sampled on a regular grid over x, y in [-1, 1], z in [-0.5, 0.5] (same spacing on every axis)
 * and contoured at f = 0.5 with vtkFlyingEdges3D (marching cubes); samples within 1e-3 of 0.5 are
 * pushed to 0.5 -/+ 1e-3 so that no two contour points coincide. Neighbouring blobs merge and
 * the centre of the ring stays empty, and f < 0.5 on the whole domain boundary, so the result
 * is one closed, manifold, consistently oriented surface of genus 1 (a lumpy, rippled torus with
 * Euler characteristic 0). The blobs have different radii and the ring is not planar, so the
 * surface has varying curvature; the ripple adds small-scale detail that simplification must
 * remove first.
 *
 * Resolution is the number of samples along x (and y); z gets the same spacing. The triangle
 * count grows as Resolution^2: about 1,000,000 triangles (1,004,688) at the default 500,
 * about 50,000 (49,692) at 112.
 * The output has float points and triangles only (no normals, no scalars); it is identical on
 * every run and every thread count.
 */
#ifndef vtkSyntheticIsosurfaceSource_h
#define vtkSyntheticIsosurfaceSource_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkSyntheticIsosurfaceSource : public vtkPolyDataAlgorithm
{
public:
  static vtkSyntheticIsosurfaceSource* New();
  vtkTypeMacro(vtkSyntheticIsosurfaceSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Samples along x and y (default 500, about 1M triangles); clamped to [16, 4000].
  vtkSetClampMacro(Resolution, int, 16, 4000);
  vtkGetMacro(Resolution, int);
  ///@}

  /// The scalar field f at (x, y, z) (for tests and documentation).
  static double EvaluateField(double x, double y, double z);

  /// The contour value (0.5).
  static double GetIsoValue() { return 0.5; }

protected:
  vtkSyntheticIsosurfaceSource();
  ~vtkSyntheticIsosurfaceSource() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Resolution = 500;

private:
  vtkSyntheticIsosurfaceSource(const vtkSyntheticIsosurfaceSource&) = delete;
  void operator=(const vtkSyntheticIsosurfaceSource&) = delete;
};

#endif
