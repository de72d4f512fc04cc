// SPDX-License-Identifier: BSD-3-Clause
#include "vtkScanSurfaceSource.h"

#include "slodCounterHash.h"
#include "slodTriangleMesh.h"
#include "vtkScanVolumeSource.h"

#include "vtkCellArray.h"
#include "vtkCleanPolyData.h"
#include "vtkFlyingEdges3D.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataConnectivityFilter.h"
#include "vtkUnsignedCharArray.h"

#include <cmath>
#include <cstdint>
#include <vector>

vtkStandardNewMacro(vtkScanSurfaceSource);

namespace
{
// Open scan: the outline is an ellipse with a wavy radius, and holes of fixed world size.
constexpr double OutlineRadiusX = 0.95, OutlineRadiusY = 0.85;
constexpr int NumberOfHoles = 12;
constexpr double DropOutProbability = 0.001; // per triangle: missing samples of the scanner
constexpr double HeightNoiseInCells = 0.15;  // height noise, in grid spacings

// Contour -> largest region -> clean: the pipeline of a scanned organ's surface (as the MRI
// surface of scripts/make-mri-isosurface.py is made). Coincident points are merged exactly and
// the triangles they make degenerate are removed (not turned into lines).
void LargestCleanIsosurface(vtkImageData* volume, double isoValue, vtkPolyData* output)
{
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(volume);
  contour->SetValue(0, isoValue);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->InterpolateAttributesOff();
  vtkNew<vtkPolyDataConnectivityFilter> largest;
  largest->SetInputConnection(contour->GetOutputPort());
  largest->SetExtractionModeToLargestRegion();
  vtkNew<vtkCleanPolyData> clean;
  clean->SetInputConnection(largest->GetOutputPort());
  clean->PointMergingOn();
  clean->SetTolerance(0.0);
  clean->ConvertPolysToLinesOff();
  clean->ConvertLinesToPointsOff();
  clean->ConvertStripsToPolysOff();
  clean->Update();
  output->Initialize();
  output->SetPoints(clean->GetOutput()->GetPoints());
  output->SetPolys(clean->GetOutput()->GetPolys());
}

// Labels first..last of a label map as a 0/1 mask on the same grid.
vtkSmartPointer<vtkImageData> ThresholdLabels(vtkImageData* labels, int first, int last)
{
  auto mask = vtkSmartPointer<vtkImageData>::New();
  mask->CopyStructure(labels);
  vtkNew<vtkUnsignedCharArray> inside;
  const vtkIdType n = labels->GetNumberOfPoints();
  inside->SetNumberOfTuples(n);
  const unsigned char* label = static_cast<const unsigned char*>(labels->GetScalarPointer());
  for (vtkIdType i = 0; i < n; ++i)
  {
    inside->SetValue(i, label[i] >= first && label[i] <= last ? 1 : 0);
  }
  mask->GetPointData()->SetScalars(inside);
  return mask;
}

struct Disc
{
  double X, Y, Radius;
};

// Holes of the open scan: centres in [-0.7, 0.7]^2, radii 0.02..0.08 (world units).
std::vector<Disc> MakeHoles(std::uint64_t key)
{
  std::vector<Disc> holes;
  for (int h = 0; h < NumberOfHoles; ++h)
  {
    holes.push_back({ -0.7 + 1.4 * slod::Uniform(key, 3 * h), -0.7 + 1.4 * slod::Uniform(key, 3 * h + 1),
      0.02 + 0.06 * slod::Uniform(key, 3 * h + 2) });
  }
  return holes;
}

// Whether the open scan covers the point (x, y): inside the wavy outline, outside every hole.
bool Scanned(double x, double y, double outlineJitter, const std::vector<Disc>& holes)
{
  const double ex = x / OutlineRadiusX, ey = y / OutlineRadiusY;
  const double wave = 1.0 + 0.05 * std::sin(5.0 * std::atan2(y, x)) + outlineJitter;
  if (ex * ex + ey * ey > wave * wave)
  {
    return false;
  }
  for (const Disc& d : holes)
  {
    if ((x - d.X) * (x - d.X) + (y - d.Y) * (y - d.Y) < d.Radius * d.Radius)
    {
      return false;
    }
  }
  return true;
}

// The height field's triangles that the scan covers (a triangle counts by its centroid).
std::vector<slod::Index> OpenScanTriangles(int resolution, std::uint64_t key)
{
  const double h = 2.0 / (resolution - 1);
  const std::vector<Disc> holes = MakeHoles(key);
  std::vector<slod::Index> triangles;
  for (int j = 0; j + 1 < resolution; ++j)
  {
    for (int i = 0; i + 1 < resolution; ++i)
    {
      const slod::Index v00 = j * resolution + i, v10 = v00 + 1, v01 = v00 + resolution, v11 = v01 + 1;
      const slod::Index corners[2][3] = { { v00, v10, v11 }, { v00, v11, v01 } };
      const double centroid[2][2] = { { i + 2.0 / 3.0, j + 1.0 / 3.0 }, { i + 1.0 / 3.0, j + 2.0 / 3.0 } };
      for (int t = 0; t < 2; ++t)
      {
        const std::uint64_t cell = 2 * (std::uint64_t(j) * resolution + i) + t;
        const double jitter = 0.5 * h * (2.0 * slod::Uniform(key ^ 0x0D71E5ull, cell) - 1.0);
        const double x = -1.0 + centroid[t][0] * h, y = -1.0 + centroid[t][1] * h;
        if (Scanned(x, y, jitter, holes) && slod::Uniform(key ^ 0xD50Full, cell) >= DropOutProbability)
        {
          triangles.insert(triangles.end(), corners[t], corners[t] + 3);
        }
      }
    }
  }
  return triangles;
}

void MakeOpenScan(int resolution, unsigned int seed, vtkPolyData* output)
{
  const std::uint64_t key = slod::Finalise(std::uint64_t(seed) * slod::Golden + 0x0BE45CA4ull);
  const std::vector<slod::Index> triangles = OpenScanTriangles(resolution, key);
  const double h = 2.0 / (resolution - 1);
  slod::FirstUseNumbering numbering(slod::Index(resolution) * resolution);
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(vtkIdType(triangles.size() / 3), vtkIdType(triangles.size()));
  for (size_t t = 0; t < triangles.size(); t += 3)
  {
    const vtkIdType ids[3] = { numbering(triangles[t]), numbering(triangles[t + 1]), numbering(triangles[t + 2]) };
    polys->InsertNextCell(3, ids);
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(vtkIdType(numbering.Used.size()));
  for (size_t p = 0; p < numbering.Used.size(); ++p)
  {
    const slod::Index v = numbering.Used[p];
    const double x = -1.0 + (v % resolution) * h, y = -1.0 + (v / resolution) * h;
    const double noise = HeightNoiseInCells * h * (2.0 * slod::Uniform(key ^ 0x4E015Eull, std::uint64_t(v)) - 1.0);
    points->SetPoint(vtkIdType(p), x, y, vtkScanSurfaceSource::OpenScanHeight(x, y) + noise);
  }
  output->Initialize();
  output->SetPoints(points);
  output->SetPolys(polys);
}
} // namespace

vtkScanSurfaceSource::vtkScanSurfaceSource()
{
  this->SetNumberOfInputPorts(0);
}

double vtkScanSurfaceSource::OpenScanHeight(double x, double y)
{
  const double dome = 0.35 * std::exp(-(x * x + y * y) / 0.5);
  const double ridge = 0.12 * std::exp(-(x / 0.08) * (x / 0.08) - ((y + 0.05) / 0.3) * ((y + 0.05) / 0.3));
  const double left = (x + 0.3) * (x + 0.3) + (y - 0.25) * (y - 0.25);
  const double right = (x - 0.3) * (x - 0.3) + (y - 0.25) * (y - 0.25);
  const double sockets = -0.05 * (std::exp(-left / 0.01) + std::exp(-right / 0.01));
  const double ripples = 0.01 * std::sin(13.0 * x) * std::cos(11.0 * y);
  return dome + ridge + sockets + ripples;
}

void vtkScanSurfaceSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* kinds[] = { "NoisyIsosurface", "SegmentationMask", "OpenScan" };
  os << indent << "Kind: " << kinds[this->Kind] << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "NoiseAmplitude: " << this->NoiseAmplitude << "\n";
}

int vtkScanSurfaceSource::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (this->Kind == OpenScan)
  {
    MakeOpenScan(this->Resolution, this->Seed, output);
    return 1;
  }
  vtkNew<vtkScanVolumeSource> volume;
  volume->SetResolution(this->Resolution);
  volume->SetSeed(this->Seed);
  volume->SetNoiseAmplitude(this->NoiseAmplitude);
  if (this->Kind == SegmentationMask)
  {
    volume->SetKindToLabelMap();
    volume->Update();
    this->UpdateProgress(0.3);
    vtkSmartPointer<vtkImageData> mask = ThresholdLabels(volume->GetOutput(), GetFirstMaskLabel(), GetLastMaskLabel());
    LargestCleanIsosurface(mask, 0.5, output);
  }
  else
  {
    volume->Update();
    this->UpdateProgress(0.3);
    LargestCleanIsosurface(volume->GetOutput(), vtkScanVolumeSource::GetNoisyIsoValue(), output);
  }
  this->UpdateProgress(1.0);
  return 1;
}
