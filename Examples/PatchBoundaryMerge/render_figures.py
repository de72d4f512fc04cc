# SPDX-License-Identifier: BSD-3-Clause
"""Renders the pictures of Documentation/PatchBoundaryMerge.md (run under xvfb-run -a):
the Fandisk coloured by patch, its profile curves, and the results at three levels.

    PYTHONPATH=<build>/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 render_figures.py fandisk.off out_dir
"""
import os
import sys

from vtkmodules.vtkCommonCore import vtkLookupTable
from vtkmodules.vtkFiltersCore import vtkTubeFilter
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer

import surfacelod

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from slod_figures import figure_window, save_png  # noqa: E402 (Examples/slod_figures.py)


def lookup_table(count):
    table = vtkLookupTable()
    table.SetNumberOfTableValues(max(count, 1))
    # Well-separated hues in a fixed pseudo-random order, so neighbouring patches differ.
    for i in range(max(count, 1)):
        h = (i * 0.618033988749895) % 1.0
        table.SetTableValue(i, *hsv(h, 0.55 + 0.4 * ((i * 7) % 5) / 4.0, 0.95), 1.0)
    table.SetTableRange(0, max(count - 1, 1))
    table.Build()
    return table


def hsv(h, s, v):
    i = int(h * 6) % 6
    f = h * 6 - int(h * 6)
    p, q, t = v * (1 - s), v * (1 - f * s), v * (1 - (1 - f) * s)
    return [(v, t, p), (q, v, p), (p, v, t), (p, q, v), (t, p, v), (v, p, q)][i]


def render(actors, path, size=(640, 480)):
    renderer = vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    for actor in actors:
        renderer.AddActor(actor)
    window = figure_window(renderer, size)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(1.0, 0.8, 1.6)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 1, 0)
    renderer.ResetCamera()
    camera.Zoom(1.3)
    save_png(window, path)


def surface_actor(mesh, by_patch=True, edges=True):
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(mesh)
    if by_patch:
        count = int(mesh.GetCellData().GetArray("PatchId").GetRange()[1]) + 1
        mesh.GetCellData().SetActiveScalars("PatchId")
        mapper.SetScalarModeToUseCellData()
        mapper.SetLookupTable(lookup_table(count))
        mapper.SetScalarRange(0, max(count - 1, 1))
    else:
        mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    prop = actor.GetProperty()
    prop.SetInterpolationToFlat()
    if edges:
        prop.EdgeVisibilityOn()
        prop.SetEdgeColor(0.15, 0.15, 0.15)
        prop.SetLineWidth(0.5)
    return actor


def curve_actor(curves, radius):
    tubes = vtkTubeFilter()
    tubes.SetInputData(curves)
    tubes.SetRadius(radius)
    tubes.SetNumberOfSides(6)
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(tubes.GetOutputPort())
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.1, 0.1, 0.1)
    return actor


def main():
    source, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    reader = surfacelod.vtkOFFMeshReader()
    reader.SetFileName(source)
    spbm = surfacelod.vtkPatchBoundaryMerge()
    spbm.SetInputConnection(reader.GetOutputPort())
    spbm.GeneratePatchColoredInputOn()
    levels = [460, 266, 150]
    for count in levels:
        spbm.SetTargetNumberOfTriangles(count)
        spbm.Update()
        result = spbm.GetOutput(0)
        print(count, result.GetNumberOfPolys(), "triangles,", spbm.GetNumberOfMergedPatches(), "patches")
        level_mesh = type(result)()
        level_mesh.DeepCopy(result)
        render([surface_actor(level_mesh)], os.path.join(out, "spbm_fandisk_%d.png" % count))
        if count == levels[0]:
            curves = type(result)()
            curves.DeepCopy(spbm.GetOutput(1))
            plain = type(result)()
            plain.DeepCopy(result)
            render([surface_actor(plain, by_patch=False, edges=False), curve_actor(curves, 0.003)],
                   os.path.join(out, "spbm_fandisk_profile_curves.png"))
    patches = type(spbm.GetOutput(2))()
    patches.DeepCopy(spbm.GetOutput(2))
    render([surface_actor(patches, edges=False)], os.path.join(out, "spbm_fandisk_patches.png"))
    print("patchification:", spbm.GetNumberOfPatches(), "patches")


if __name__ == "__main__":
    main()
