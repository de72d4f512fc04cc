#include "Render.h"

#include "CliSupport.h"
#include "MeshIO.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCoordinate.h"
#include "vtkErrorCode.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkWindowToImageFilter.h"

#include <cstdlib>

namespace slodcli
{
bool CanRender(std::string& reason)
{
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
  {
    reason = "no X display (DISPLAY is not set)";
    return false;
  }
  return true;
}

void RenderPanels(const std::vector<Panel>& panels, const std::string& pngPath, int panelSize)
{
  if (panels.empty())
  {
    return;
  }
  MessageCapture capture;
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  const int count = static_cast<int>(panels.size());
  window->SetSize(panelSize * count, panelSize);

  vtkNew<vtkCamera> camera; // shared: every mesh is seen from the same point
  for (int i = 0; i < count; ++i)
  {
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(double(i) / count, 0.0, double(i + 1) / count, 1.0);
    renderer->SetBackground(1.0, 1.0, 1.0);
    renderer->SetActiveCamera(camera);

    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(panels[i].Mesh);
    mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetInterpolationToFlat(); // facets show the triangle sizes
    actor->GetProperty()->SetColor(0.75, 0.80, 0.90);
    actor->GetProperty()->SetSpecular(0.2);
    renderer->AddActor(actor);

    vtkNew<vtkTextActor> title;
    title->SetInput(panels[i].Title.c_str());
    title->GetTextProperty()->SetFontSize(16);
    title->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
    title->GetTextProperty()->SetVerticalJustificationToTop();
    title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    title->GetPositionCoordinate()->SetValue(0.03, 0.97);
    renderer->AddActor2D(title);
    window->AddRenderer(renderer);
    if (i == 0)
    {
      renderer->ResetCamera(panels[0].Mesh->GetBounds());
      camera->Elevation(-45.0);
      camera->Azimuth(20.0);
      camera->OrthogonalizeViewUp();
      renderer->ResetCamera(panels[0].Mesh->GetBounds());
      camera->Zoom(1.3);
    }
  }
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  vtkNew<vtkPNGWriter> png;
  png->SetFileName(pngPath.c_str());
  png->SetInputConnection(grab->GetOutputPort());
  png->Write();
  if (!capture.FirstError().empty() || png->GetErrorCode() != vtkErrorCode::NoError)
  {
    throw CliError(ExitData, pngPath + ": cannot render or write the image: " +
        (capture.FirstError().empty() ? std::string("PNG writer failed") : capture.FirstError()));
  }
}
} // namespace slodcli
