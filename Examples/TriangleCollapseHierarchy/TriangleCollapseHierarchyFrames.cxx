// SPDX-License-Identifier: BSD-3-Clause
// Renders a smooth sweep through a triangle-collapse hierarchy (Gieng et al. 1997) as PNG frames:
// frame f shows M_i(t) for the continuous level at which the triangle count is
// N0 (Nn / N0)^(f / (frames - 1)), from the input M0 to the coarsest mesh Mn. The hierarchy is built once; each frame only changes SetContinuousLevel, which
// is what an interactive slider would do.
//
// Usage: TriangleCollapseHierarchyFrames input.(off|ply|vtp) output-directory [frames=60] [flat]
//   Default style, like the paper's figures: the triangles collapsing in the current batch in a
//   strong random colour per collapse, their stencils in a lighter shade of it, the rest grey,
//   with edges. "flat": flat-shaded grey surface without edges.
#include "vtkTriangleCollapseHierarchy.h"
#include "vtkOFFMeshReader.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPLYReader.h"
#include "vtkPNGWriter.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"
#include "vtkXMLPolyDataReader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace
{
vtkSmartPointer<vtkPolyData> Read(const std::string& path)
{
  const std::string ext = path.size() > 4 ? path.substr(path.size() - 4) : "";
  vtkSmartPointer<vtkPolyData> out;
  if (ext == ".ply")
  {
    vtkNew<vtkPLYReader> r;
    r->SetFileName(path.c_str());
    r->Update();
    out = r->GetOutput();
  }
  else if (ext == ".vtp")
  {
    vtkNew<vtkXMLPolyDataReader> r;
    r->SetFileName(path.c_str());
    r->Update();
    out = r->GetOutput();
  }
  else
  {
    vtkNew<vtkOFFMeshReader> r;
    r->SetFileName(path.c_str());
    r->Update();
    out = r->GetOutput();
  }
  return out;
}

// Per-cell RGB colours from the hierarchy's CollapseRole / CollapseBatch arrays.
void ColourByBatch(vtkPolyData* mesh)
{
  vtkDataArray* role = mesh->GetCellData()->GetArray("CollapseRole");
  vtkDataArray* batch = mesh->GetCellData()->GetArray("CollapseBatch");
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetName("Colours");
  colours->SetNumberOfComponents(3);
  colours->SetNumberOfTuples(mesh->GetNumberOfCells());
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    unsigned char rgb[3] = { 200, 200, 200 };
    const int r = role ? static_cast<int>(role->GetTuple1(c)) : 0;
    if (r > 0 && batch)
    {
      // A fixed pseudo-random hue per collapse.
      unsigned int h = static_cast<unsigned int>(batch->GetTuple1(c)) * 2654435761u;
      for (int k = 0; k < 3; ++k)
      {
        const int v = 60 + static_cast<int>((h >> (8 * k)) & 0xff) * 195 / 255;
        rgb[k] = static_cast<unsigned char>(r == 2 ? v : (v + 2 * 235) / 3);
      }
    }
    colours->SetTypedTuple(c, rgb);
  }
  mesh->GetCellData()->SetScalars(colours);
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc < 3)
  {
    std::fprintf(stderr, "usage: %s input.(off|ply|vtp) output-directory [frames=60] [flat]\n", argv[0]);
    return 2;
  }
  const std::string outputDir = argv[2];
  const int frames = argc > 3 ? std::max(2, std::atoi(argv[3])) : 60;
  const bool flat = argc > 4 && std::string(argv[4]) == "flat";
  vtkSmartPointer<vtkPolyData> input = Read(argv[1]);
  if (!input || input->GetNumberOfPolys() == 0)
  {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 1;
  }

  vtkNew<vtkTriangleCollapseHierarchy> hierarchy;
  hierarchy->SetInputData(input);
  hierarchy->GenerateAllLevelsOff();
  hierarchy->SetLevel(0);
  hierarchy->Update();
  const int levels = hierarchy->GetNumberOfLevels();
  std::printf("%lld triangles, %d levels (coarsest %lld triangles), built in %.2f s\n",
    static_cast<long long>(input->GetNumberOfPolys()), levels,
    static_cast<long long>(hierarchy->GetLevelNumberOfTriangles(levels - 1)), hierarchy->GetHierarchyBuildTime());

  vtkNew<vtkPolyData> shown;
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(shown);
  mapper->SetScalarModeToUseCellData();
  mapper->SetColorModeToDirectScalars();
  mapper->SetScalarVisibility(!flat);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetInterpolationToFlat();
  actor->GetProperty()->SetColor(0.85, 0.82, 0.75);
  actor->GetProperty()->SetEdgeVisibility(!flat);
  actor->GetProperty()->SetEdgeColor(0.25, 0.25, 0.3);
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->SetBackground(1, 1, 1);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(640, 640);
  window->AddRenderer(renderer);

  // The sweep is geometric in the triangle count (each frame removes the same fraction), which
  // spreads the frames evenly over what the eye sees; the continuous level follows from the
  // triangle counts of the levels.
  const double n0 = static_cast<double>(hierarchy->GetLevelNumberOfTriangles(0));
  const double nn = static_cast<double>(hierarchy->GetLevelNumberOfTriangles(levels - 1));
  auto levelFor = [&](double count) {
    for (int i = 0; i + 1 < levels; ++i)
    {
      const double a = static_cast<double>(hierarchy->GetLevelNumberOfTriangles(i));
      const double b = static_cast<double>(hierarchy->GetLevelNumberOfTriangles(i + 1));
      if (count >= b)
      {
        return i + (a > b ? std::min(1.0, std::max(0.0, (a - count) / (a - b))) : 0.0);
      }
    }
    return double(levels - 1);
  };
  for (int f = 0; f < frames; ++f)
  {
    const double level = levelFor(n0 * std::pow(nn / n0, double(f) / (frames - 1)));
    hierarchy->SetContinuousLevel(level);
    hierarchy->Update();
    shown->ShallowCopy(hierarchy->GetOutput());
    if (!flat)
    {
      ColourByBatch(shown);
    }
    if (f == 0)
    {
      renderer->ResetCamera();
      renderer->GetActiveCamera()->Zoom(1.3);
    }
    window->Render();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    grab->ReadFrontBufferOff();
    vtkNew<vtkPNGWriter> writer;
    char name[64];
    std::snprintf(name, sizeof(name), "/frame_%04d.png", f);
    writer->SetFileName((outputDir + name).c_str());
    writer->SetInputConnection(grab->GetOutputPort());
    writer->Write();
    std::printf("frame %d: level %.2f, %lld triangles\n", f, level,
      static_cast<long long>(hierarchy->GetOutput()->GetNumberOfPolys()));
  }
  return 0;
}
