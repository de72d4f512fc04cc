#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Renders the pictures of Documentation/GreedyCuts.md (run under xvfb-run -a).

usage: render_figures.py MESH_DIR OUTPUT_DIR
"""
import os
import sys

from vtkmodules.vtkCommonColor import vtkNamedColors  # noqa: F401
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer
from vtkmodules.vtkFiltersCore import vtkQuadricDecimation
from surfacelod import vtkGreedyCutsSimplification, vtkOFFMeshReader, vtkSurfaceDeviation

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from slod_figures import figure_window, save_png  # noqa: E402 (Examples/slod_figures.py)

mesh_dir, out_dir = sys.argv[1], sys.argv[2]
os.makedirs(out_dir, exist_ok=True)


def render(polydata, name, color_by_patch=False, camera=None):
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(polydata)
    if color_by_patch and polydata.GetCellData().GetArray("PatchId"):
        mapper.SetScalarModeToUseCellFieldData()
        mapper.SelectColorArray("PatchId")
        mapper.SetScalarRange(polydata.GetCellData().GetArray("PatchId").GetRange())
        mapper.ScalarVisibilityOn()
    else:
        mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().EdgeVisibilityOn()
    actor.GetProperty().SetEdgeColor(0.1, 0.1, 0.1)
    if not color_by_patch:
        actor.GetProperty().SetColor(0.85, 0.85, 0.8)
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetBackground(1, 1, 1)
    window = figure_window(renderer, (480, 400))
    renderer.ResetCamera()
    renderer.GetActiveCamera().Azimuth(30)
    renderer.GetActiveCamera().Elevation(20)
    renderer.ResetCameraClippingRange()
    save_png(window, os.path.join(out_dir, name))


reader = vtkOFFMeshReader()
reader.SetFileName(os.path.join(mesh_dir, "fandisk.off"))
reader.Update()
original = reader.GetOutput()
render(original, "gc_fandisk_input.png")
for error in (0.005, 0.01):
    cuts = vtkGreedyCutsSimplification()
    cuts.SetInputData(original)
    cuts.SetMaximumError(error)
    cuts.Update()
    out = cuts.GetOutput()
    render(out, f"gc_fandisk_{error}.png", color_by_patch=True)
    deviation = vtkSurfaceDeviation()
    deviation.SetReferenceData(original)
    deviation.SetComparedData(out)
    deviation.Update()
    print(f"fandisk eps {error}: {out.GetNumberOfCells()} triangles, bound {cuts.GetUsedMaximumError():.5g}, "
          f"measured {deviation.GetHausdorff():.5g}")
    if error == 0.01:
        quadric = vtkQuadricDecimation()
        quadric.SetInputData(original)
        quadric.SetTargetReduction(1.0 - out.GetNumberOfCells() / original.GetNumberOfCells())
        quadric.Update()
        render(quadric.GetOutput(), "gc_fandisk_quadric.png")
