// SPDX-License-Identifier: BSD-3-Clause
#include "RenderTestSupport.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTesting.h"

#include <fstream>
#include <iostream>

namespace slodtest
{
bool RenderAndCompare(vtkPolyData* mesh, const std::string& baselineName, double threshold, const double viewDirection[3])
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(mesh);
  if (vtkDataArray* scalars = mesh->GetCellData()->GetScalars())
  {
    mapper->SetScalarModeToUseCellData();
    mapper->SetScalarRange(scalars->GetRange());
  }
  else
  {
    mapper->ScalarVisibilityOff();
  }
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetInterpolationToFlat();
  actor->GetProperty()->EdgeVisibilityOn();
  actor->GetProperty()->SetEdgeColor(0.1, 0.1, 0.15);
  actor->GetProperty()->SetColor(0.85, 0.8, 0.65);

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->SetBackground(1, 1, 1);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(400, 400);
  window->AddRenderer(renderer);
  vtkCamera* camera = renderer->GetActiveCamera();
  const double defaultDirection[3] = { 1.0, 0.6, 0.8 };
  const double* d = viewDirection ? viewDirection : defaultDirection;
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(d[0], d[1], d[2]);
  camera->SetViewUp(0, 0, 1);
  renderer->ResetCamera();
  window->Render();

  const std::string baseline = std::string(SURFACELOD_BASELINE_DIR) + "/" + baselineName + ".png";
  vtkNew<vtkTesting> testing;
  testing->SetRenderWindow(window);
  testing->AddArgument("-T");
  testing->AddArgument(SURFACELOD_TEST_OUTPUT_DIR);
  testing->AddArgument("-V");
  testing->AddArgument(baseline.c_str());
  if (!std::ifstream(baseline))
  {
    std::cerr << "baseline missing: " << baseline << " (a candidate image is written to " << SURFACELOD_TEST_OUTPUT_DIR
              << ")\n";
  }
  return testing->RegressionTest(threshold) == vtkTesting::PASSED;
}
} // namespace slodtest
