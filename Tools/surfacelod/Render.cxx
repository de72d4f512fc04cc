// SPDX-License-Identifier: BSD-3-Clause
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
  // Top row: whole surfaces; bottom row: the same close-up of each, with triangle edges.
  window->SetSize(panelSize * count, 2 * panelSize);

  vtkPolyData* first = panels[0].Mesh;
  double bounds[6];
  first->GetBounds(bounds);
  vtkNew<vtkCamera> overview; // shared: every mesh is seen from the same point
  {
    vtkNew<vtkRenderer> probe;
    probe->SetActiveCamera(overview);
    probe->ResetCamera(bounds);
    overview->Elevation(-45.0);
    overview->Azimuth(20.0);
    overview->OrthogonalizeViewUp();
    probe->ResetCamera(bounds);
    overview->Zoom(1.3);
  }
  // Close-up on the vertex of the first mesh nearest to the viewer (surely visible).
  vtkNew<vtkCamera> closeUp;
  closeUp->DeepCopy(overview);
  {
    double position[3], focal[3], toViewer[3];
    overview->GetPosition(position);
    overview->GetFocalPoint(focal);
    for (int a = 0; a < 3; ++a)
    {
      toViewer[a] = position[a] - focal[a];
    }
    double best = -1e300, nearest[3] = { focal[0], focal[1], focal[2] };
    for (vtkIdType i = 0; i < first->GetNumberOfPoints(); ++i)
    {
      double p[3];
      first->GetPoint(i, p);
      const double d = (p[0] - focal[0]) * toViewer[0] + (p[1] - focal[1]) * toViewer[1] + (p[2] - focal[2]) * toViewer[2];
      if (d > best)
      {
        best = d;
        nearest[0] = p[0];
        nearest[1] = p[1];
        nearest[2] = p[2];
      }
    }
    closeUp->SetFocalPoint(nearest);
    closeUp->SetPosition(nearest[0] + toViewer[0], nearest[1] + toViewer[1], nearest[2] + toViewer[2]);
    closeUp->Zoom(8.0);
  }

  for (int row = 0; row < 2; ++row)
  {
    for (int i = 0; i < count; ++i)
    {
      vtkNew<vtkRenderer> renderer;
      // Row 0 is the top half of the window.
      renderer->SetViewport(double(i) / count, row == 0 ? 0.5 : 0.0, double(i + 1) / count, row == 0 ? 1.0 : 0.5);
      renderer->SetBackground(1.0, 1.0, 1.0);
      renderer->SetActiveCamera(row == 0 ? overview.GetPointer() : closeUp.GetPointer());

      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputData(panels[i].Mesh);
      mapper->ScalarVisibilityOff();
      vtkNew<vtkActor> actor;
      actor->SetMapper(mapper);
      actor->GetProperty()->SetInterpolationToFlat(); // facets show the triangle sizes
      actor->GetProperty()->SetColor(0.75, 0.80, 0.90);
      actor->GetProperty()->SetSpecular(0.2);
      if (row == 1)
      {
        actor->GetProperty()->EdgeVisibilityOn();
        actor->GetProperty()->SetEdgeColor(0.2, 0.25, 0.35);
      }
      renderer->AddActor(actor);

      vtkNew<vtkTextActor> title;
      title->SetInput(row == 0 ? panels[i].Title.c_str() : "close-up");
      title->GetTextProperty()->SetFontSize(16);
      title->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
      title->GetTextProperty()->SetVerticalJustificationToTop();
      title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
      title->GetPositionCoordinate()->SetValue(0.03, 0.97);
      renderer->AddActor2D(title);
      window->AddRenderer(renderer);
      renderer->ResetCameraClippingRange();
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
