// SPDX-License-Identifier: BSD-3-Clause
#include "vtkScanVolumeSource.h"

#include "slodCounterHash.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkType.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

vtkStandardNewMacro(vtkScanVolumeSource);

namespace
{
constexpr double DomainMin = -1.0;
// The ball's centre and radius: it leaves the domain through x = 1 (0.3 + 0.85 > 1).
constexpr double BallCenterX = 0.3;
constexpr double BallRadius = 0.85;
constexpr double FoldAmplitude = 0.06;
constexpr double FoldFrequency = 9.0;
constexpr double IntensityLimit = 32000.0; // inside the 16-bit range

bool InBox(double x, double y, double z, const double (&box)[6])
{
  return x >= box[0] && x <= box[1] && y >= box[2] && y <= box[3] && z >= box[4] && z <= box[5];
}

// Fills every sample with sample(x, y, z, i, j, k), slices of constant z in parallel.
template <typename T, typename Sample>
void FillVolume(vtkImageData* image, int resolution, Sample sample)
{
  T* values = static_cast<T*>(image->GetScalarPointer());
  const double h = vtkScanVolumeSource::SpacingOf(resolution);
  const vtkIdType n = resolution;
  vtkSMPTools::For(0, n, [&](vtkIdType kBegin, vtkIdType kEnd) {
    for (vtkIdType k = kBegin; k < kEnd; ++k)
    {
      const double z = DomainMin + k * h;
      for (vtkIdType j = 0; j < n; ++j)
      {
        const double y = DomainMin + j * h;
        T* row = values + (k * n + j) * n;
        for (vtkIdType i = 0; i < n; ++i)
        {
          row[i] = sample(DomainMin + i * h, y, z, i, j, k);
        }
      }
    }
  });
}
} // namespace

vtkScanVolumeSource::vtkScanVolumeSource()
{
  this->SetNumberOfInputPorts(0);
}

double vtkScanVolumeSource::SmoothField(double x, double y, double z)
{
  const double dx = x - BallCenterX;
  const double fold = FoldAmplitude * std::sin(FoldFrequency * x + 1.0) * std::sin(FoldFrequency * y + 2.0) *
    std::sin(FoldFrequency * z + 3.0);
  return BallRadius + fold - std::sqrt(dx * dx + y * y + z * z);
}

int vtkScanVolumeSource::LabelAt(double x, double y, double z)
{
  // Highest label first: the box is cut out of everything, the ring and the stalk are on top of
  // the organ.
  static constexpr double NotchBox[6] = { 0.45, 1.0, -0.2, 0.25, -0.15, 0.2 };
  if (InBox(x, y, z, NotchBox))
  {
    return 4;
  }
  // A ring in the x-z plane around (0.1, 0, 0.6), half inside the organ: one handle.
  const double ringRadial = std::hypot(x - 0.1, z - 0.6) - 0.3;
  if (ringRadial * ringRadial + y * y <= 0.08 * 0.08)
  {
    return 3;
  }
  // A stalk along -x from the organ to the domain's face x = -1.
  if (x <= 0.0 && y * y + (z + 0.1) * (z + 0.1) <= 0.15 * 0.15)
  {
    return 2;
  }
  const double ex = (x - 0.1) / 0.75, ey = y / 0.55, ez = z / 0.6;
  return ex * ex + ey * ey + ez * ez <= 1.0 ? 1 : 0;
}

void vtkScanVolumeSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Kind: " << (this->Kind == LabelMap ? "LabelMap" : "NoisyIntensity") << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "NoiseAmplitude: " << this->NoiseAmplitude << "\n";
}

int vtkScanVolumeSource::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int last = this->Resolution - 1;
  const int extent[6] = { 0, last, 0, last, 0, last };
  const double h = SpacingOf(this->Resolution);
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::ORIGIN(), DomainMin, DomainMin, DomainMin);
  outInfo->Set(vtkDataObject::SPACING(), h, h, h);
  vtkDataObject::SetPointDataActiveScalarInfo(
    outInfo, this->Kind == LabelMap ? VTK_UNSIGNED_CHAR : VTK_SHORT, 1);
  return 1;
}

int vtkScanVolumeSource::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  const int last = this->Resolution - 1;
  const double h = SpacingOf(this->Resolution);
  output->SetExtent(0, last, 0, last, 0, last);
  output->SetOrigin(DomainMin, DomainMin, DomainMin);
  output->SetSpacing(h, h, h);
  if (this->Kind == LabelMap)
  {
    output->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
    FillVolume<unsigned char>(output, this->Resolution,
      [](double x, double y, double z, vtkIdType, vtkIdType, vtkIdType) {
        return static_cast<unsigned char>(LabelAt(x, y, z));
      });
    output->GetPointData()->GetScalars()->SetName("label");
    return 1;
  }
  output->AllocateScalars(VTK_SHORT, 1);
  const std::uint64_t key = slod::Finalise(std::uint64_t(this->Seed) * slod::Golden + 0x5CA11ED5ull);
  const double amplitude = this->NoiseAmplitude;
  const double scale = GetIntensityPerVoxel();
  FillVolume<short>(output, this->Resolution,
    [=](double x, double y, double z, vtkIdType i, vtkIdType j, vtkIdType k) {
      const double noise = amplitude * (2.0 * slod::GridUniform(key, i, j, k) - 1.0);
      const double intensity = std::round(scale * (SmoothField(x, y, z) / h + noise));
      return static_cast<short>(std::clamp(intensity, -IntensityLimit, IntensityLimit));
    });
  output->GetPointData()->GetScalars()->SetName("intensity");
  return 1;
}
