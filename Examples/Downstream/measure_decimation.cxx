// SPDX-License-Identifier: BSD-3-Clause
// Downstream example: decimate a sphere with VTK and measure how far the result is from the
// original with SurfaceLOD's vtkSurfaceDeviation. Prints the relative Hausdorff distance.
#include "vtkSurfaceDeviation.h"

#include "vtkNew.h"
#include "vtkQuadricDecimation.h"
#include "vtkSphereSource.h"

#include <cstdio>

int main()
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(64);
  sphere->SetPhiResolution(64);

  vtkNew<vtkQuadricDecimation> decimate;
  decimate->SetInputConnection(sphere->GetOutputPort());
  decimate->SetTargetReduction(0.9);

  vtkNew<vtkSurfaceDeviation> deviation;
  deviation->SetReferenceConnection(sphere->GetOutputPort());
  deviation->SetComparedConnection(decimate->GetOutputPort());
  deviation->SetNumberOfSamples(20000);
  deviation->Update();

  std::printf("hausdorff_relative %.6g\n", deviation->GetHausdorffRelative());
  return deviation->GetHausdorffRelative() > 0 && deviation->GetHausdorffRelative() < 0.05 ? 0 : 1;
}
