// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkScanVolumeSource
 * @brief   deterministic scan-like test volumes: a noisy intensity volume or a label map
 *
 * Test and benchmark volumes that need no data file, on a cubic grid of Resolution^3 samples
 * over [-1, 1]^3 (spacing h = 2 / (Resolution - 1)).
 *
 * NoisyIntensity (default), 16-bit integers like a CT or MRI volume:
 *
 *   I(p) = round(IntensityPerVoxel * (s(p) / h + NoiseAmplitude * (2 u(i,j,k) - 1)))
 *
 * where s is a smooth signed distance-like field (positive inside)
 *   s(p) = 0.85 + 0.06 sin(9x + 1) sin(9y + 2) sin(9z + 3) - |p - (0.3, 0, 0)|,
 * a folded ball that leaves the volume through its x = 1 face (so its isosurface meets the edge
 * of the volume), and u is uniform in [0, 1) from a counter-based hash of (i, j, k, Seed) (not
 * rand(): the same on every platform, run and thread count). s / h is in voxels, so the noise
 * has the same size relative to the grid at every resolution, like a scanner's: the isosurface
 * I = 0 (GetNoisyIsoValue) is equally rough at every resolution, with handles, small tunnels
 * and, where a sample equals the contour value exactly (integer data, integer contour value, as
 * in a real scan), coincident contour points.
 *
 * LabelMap, 8-bit labels like a segmentation: 0 background, 1 an ellipsoidal organ, 2 a stalk
 * (cylinder) from the organ to the x = -1 face, 3 a ring handle on top of the organ, 4 a box
 * cut into the organ's side (see LabelAt). Labels 1..3 thresholded and contoured give a
 * staircase surface with exactly planar regions, a handle and a border on the volume's edge.
 */
#ifndef vtkScanVolumeSource_h
#define vtkScanVolumeSource_h

#include "SurfaceLODFiltersModule.h"
#include "vtkImageAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkScanVolumeSource : public vtkImageAlgorithm
{
public:
  static vtkScanVolumeSource* New();
  vtkTypeMacro(vtkScanVolumeSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Kinds
  {
    NoisyIntensity = 0,
    LabelMap = 1
  };
  ///@{
  /// What the volume holds (default NoisyIntensity).
  vtkSetClampMacro(Kind, int, NoisyIntensity, LabelMap);
  vtkGetMacro(Kind, int);
  void SetKindToNoisyIntensity() { this->SetKind(NoisyIntensity); }
  void SetKindToLabelMap() { this->SetKind(LabelMap); }
  ///@}

  ///@{
  /// Samples along each axis (default 200); clamped to [8, 2000].
  vtkSetClampMacro(Resolution, int, 8, 2000);
  vtkGetMacro(Resolution, int);
  ///@}

  ///@{
  /// Seed of the noise (default 1). NoisyIntensity only.
  vtkSetMacro(Seed, unsigned int);
  vtkGetMacro(Seed, unsigned int);
  ///@}

  ///@{
  /// Half-width of the uniform noise in voxels (default 1.75); 0 gives the smooth field alone.
  /// NoisyIntensity only.
  vtkSetClampMacro(NoiseAmplitude, double, 0.0, 100.0);
  vtkGetMacro(NoiseAmplitude, double);
  ///@}

  /// Intensity units per voxel of the smooth field (8).
  static int GetIntensityPerVoxel() { return 8; }
  /// The contour value of the noisy intensity (0, an integer like the data).
  static double GetNoisyIsoValue() { return 0.0; }
  /// The smooth field s(p) in world units (positive inside), before scaling and noise.
  static double SmoothField(double x, double y, double z);
  /// The label at (x, y, z) of the LabelMap volume.
  static int LabelAt(double x, double y, double z);
  /// Grid spacing of a resolution.
  static double SpacingOf(int resolution) { return 2.0 / (resolution - 1); }

protected:
  vtkScanVolumeSource();
  ~vtkScanVolumeSource() override = default;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Kind = NoisyIntensity;
  int Resolution = 200;
  unsigned int Seed = 1;
  double NoiseAmplitude = 1.75;

private:
  vtkScanVolumeSource(const vtkScanVolumeSource&) = delete;
  void operator=(const vtkScanVolumeSource&) = delete;
};

#endif
