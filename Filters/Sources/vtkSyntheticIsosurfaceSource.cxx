// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSyntheticIsosurfaceSource.h"

#include "vtkCellArray.h"
#include "vtkFloatArray.h"
#include "vtkFlyingEdges3D.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include <array>
#include <cmath>

vtkStandardNewMacro(vtkSyntheticIsosurfaceSource);

namespace
{
constexpr int NumberOfBlobs = 8;
constexpr double RingRadius = 0.6;
constexpr double RippleAmplitude = 0.05;
constexpr double RippleFrequency = 11.0;
// Beyond 6 sigma a blob contributes < 1.6e-8: skipped (far below float precision of the field).
constexpr double CutoffSigmas = 6.0;
constexpr float SnapDistance = 1e-3f;
constexpr double DomainMin[3] = { -1.0, -1.0, -0.5 };
constexpr double DomainMax[3] = { 1.0, 1.0, 0.5 };

struct Blob
{
  double Center[3];
  double InverseTwoSigma2; // 1 / (2 s^2)
  double Cutoff2;          // (CutoffSigmas s)^2
};

std::array<Blob, NumberOfBlobs> MakeBlobs()
{
  std::array<Blob, NumberOfBlobs> blobs{};
  for (int k = 0; k < NumberOfBlobs; ++k)
  {
    const double theta = 2.0 * M_PI * k / NumberOfBlobs;
    const double sigma = 0.19 + 0.03 * std::cos(3.0 * theta);
    blobs[k].Center[0] = RingRadius * std::cos(theta);
    blobs[k].Center[1] = RingRadius * std::sin(theta);
    blobs[k].Center[2] = 0.12 * std::sin(2.0 * theta);
    blobs[k].InverseTwoSigma2 = 1.0 / (2.0 * sigma * sigma);
    blobs[k].Cutoff2 = CutoffSigmas * CutoffSigmas * sigma * sigma;
  }
  return blobs;
}

double Ripple(double x, double y, double z)
{
  return RippleAmplitude * std::sin(RippleFrequency * x) * std::sin(RippleFrequency * y + 1.0) *
    std::sin(RippleFrequency * z + 2.0);
}
} // namespace

vtkSyntheticIsosurfaceSource::vtkSyntheticIsosurfaceSource()
{
  this->SetNumberOfInputPorts(0);
}

double vtkSyntheticIsosurfaceSource::EvaluateField(double x, double y, double z)
{
  static const std::array<Blob, NumberOfBlobs> blobs = MakeBlobs();
  double value = Ripple(x, y, z);
  for (const Blob& b : blobs)
  {
    const double dx = x - b.Center[0], dy = y - b.Center[1], dz = z - b.Center[2];
    const double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < b.Cutoff2)
    {
      value += std::exp(-d2 * b.InverseTwoSigma2);
    }
  }
  return value;
}

void vtkSyntheticIsosurfaceSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Resolution: " << this->Resolution << "\n";
}

int vtkSyntheticIsosurfaceSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);

  // One spacing on all axes, so triangles are not stretched.
  const double spacing = (DomainMax[0] - DomainMin[0]) / (this->Resolution - 1);
  int dims[3];
  for (int a = 0; a < 3; ++a)
  {
    dims[a] = static_cast<int>(std::lround((DomainMax[a] - DomainMin[a]) / spacing)) + 1;
  }
  double origin[3];
  for (int a = 0; a < 3; ++a)
  {
    // Centre the grid on the domain (z may not divide evenly).
    origin[a] = 0.5 * (DomainMin[a] + DomainMax[a]) - 0.5 * spacing * (dims[a] - 1);
  }

  vtkNew<vtkImageData> image;
  image->SetDimensions(dims);
  image->SetOrigin(origin);
  image->SetSpacing(spacing, spacing, spacing);
  vtkNew<vtkFloatArray> scalars;
  scalars->SetName("f");
  scalars->SetNumberOfTuples(vtkIdType(dims[0]) * dims[1] * dims[2]);
  float* field = scalars->GetPointer(0);

  const float iso = static_cast<float>(GetIsoValue());
  // A sample at (or within float rounding of) the contour value puts the contour points of all
  // its edges on the sample itself: coincident points and zero-area triangles. Samples closer
  // than SnapDistance to the contour value are pushed to that distance, on their own side, so
  // every contour point is at least ~5% of an edge away from the grid points (the surface moves
  // by at most ~3e-4 of the bounding-box diagonal).
  const float below = iso - SnapDistance, above = iso + SnapDistance;
  const std::array<Blob, NumberOfBlobs> blobs = MakeBlobs();
  const vtkIdType rows = vtkIdType(dims[1]) * dims[2];
  vtkSMPTools::For(0, rows, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType row = begin; row < end; ++row)
    {
      const int j = static_cast<int>(row % dims[1]);
      const int k = static_cast<int>(row / dims[1]);
      const double y = origin[1] + j * spacing;
      const double z = origin[2] + k * spacing;
      // Blobs that can reach this row, with their y/z part of the squared distance.
      double rowD2[NumberOfBlobs];
      int active[NumberOfBlobs];
      int activeCount = 0;
      for (int b = 0; b < NumberOfBlobs; ++b)
      {
        const double dy = y - blobs[b].Center[1], dz = z - blobs[b].Center[2];
        const double d2 = dy * dy + dz * dz;
        if (d2 < blobs[b].Cutoff2)
        {
          rowD2[activeCount] = d2;
          active[activeCount++] = b;
        }
      }
      const double rippleYZ = RippleAmplitude * std::sin(RippleFrequency * y + 1.0) *
        std::sin(RippleFrequency * z + 2.0);
      float* out = field + row * dims[0];
      for (int i = 0; i < dims[0]; ++i)
      {
        const double x = origin[0] + i * spacing;
        double value = rippleYZ * std::sin(RippleFrequency * x);
        for (int a = 0; a < activeCount; ++a)
        {
          const Blob& blob = blobs[active[a]];
          const double dx = x - blob.Center[0];
          const double d2 = dx * dx + rowD2[a];
          if (d2 < blob.Cutoff2)
          {
            value += std::exp(-d2 * blob.InverseTwoSigma2);
          }
        }
        const float v = static_cast<float>(value);
        out[i] = (v >= below && v <= above) ? (v < iso ? below : above) : v;
      }
    }
  });
  image->GetPointData()->SetScalars(scalars);
  this->UpdateProgress(0.4);

  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(image);
  contour->SetValue(0, GetIsoValue());
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->InterpolateAttributesOff();
  contour->Update();

  vtkPolyData* surface = contour->GetOutput();
  output->Initialize();
  output->SetPoints(surface->GetPoints());
  output->SetPolys(surface->GetPolys());
  this->UpdateProgress(1.0);
  return 1;
}
