# SPDX-License-Identifier: BSD-3-Clause
"""Renders the pictures of Documentation/QuadricTriangleCollapse.md with the project's filter.

    xvfb-run -a python3 render_images.py <mesh dir> <output dir>
(PYTHONPATH=<build>/lib/python3/dist-packages). bunny00 original and at 88 %, 97 %, 99 % reduction.
"""
import os
import sys

import vtk
import surfacelod

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from slod_figures import figure_window, save_png  # noqa: E402 (Examples/slod_figures.py)

mesh_dir, out_dir = sys.argv[1], sys.argv[2]
os.makedirs(out_dir, exist_ok=True)
reader = surfacelod.vtkOFFMeshReader()
reader.SetFileName(mesh_dir + "/bunny00.off")
reader.Update()
bunny = reader.GetOutput()


def render(mesh, path, label):
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(mesh)
    mapper.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    prop = actor.GetProperty()
    prop.SetColor(0.85, 0.78, 0.62)
    prop.EdgeVisibilityOn()
    prop.SetEdgeColor(0.15, 0.15, 0.15)
    prop.SetInterpolationToFlat()
    text = vtk.vtkTextActor()
    text.SetInput(label)
    text.GetTextProperty().SetFontSize(18)
    text.GetTextProperty().SetColor(0, 0, 0)
    text.SetPosition(10, 10)
    renderer = vtk.vtkRenderer()
    renderer.AddActor(actor)
    renderer.AddActor2D(text)
    renderer.SetBackground(1, 1, 1)
    window = figure_window(renderer, (500, 480))
    camera = renderer.GetActiveCamera()
    camera.SetPosition(0, 0, 1)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 1, 0)
    renderer.ResetCamera()
    camera.Zoom(1.3)
    save_png(window, path)


render(bunny, out_dir + "/qtc_bunny00_original.png", "bunny00: %d triangles" % bunny.GetNumberOfPolys())
for reduction in (0.88, 0.97, 0.99):
    simplify = surfacelod.vtkQuadricTriangleCollapse()
    simplify.SetInputData(bunny)
    simplify.SetTargetReduction(reduction)
    simplify.Update()
    out = simplify.GetOutput()
    render(out, out_dir + "/qtc_bunny00_%d.png" % round(100 * reduction),
           "%d%% reduction: %d triangles" % (round(100 * reduction), out.GetNumberOfPolys()))
