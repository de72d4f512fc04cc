# SPDX-License-Identifier: BSD-3-Clause
"""Renders the pictures of Documentation/HoleBumpRemoval.md (run under xvfb-run -a):

    PYTHONPATH=<build>/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 render_figures.py <mesh_dir> <out_dir>

Block models (vtkBlockModelSource) and CGAL demo CAD models (anchor, couplingdown) before and after
vtkHoleBumpRemoval, the detected sharp loops coloured by kind, and vtkDecimatePro's topology-changing
mode (PreserveTopologyOff) at the same triangle count (the dissertation's Fig. 31).
"""
import os
import sys

from vtkmodules.vtkCommonCore import vtkLookupTable
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkDecimatePro, vtkTubeFilter
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer

import surfacelod

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from slod_figures import figure_window, save_png  # noqa: E402 (Examples/slod_figures.py)


def copy(data):
    result = vtkPolyData()
    result.DeepCopy(data)
    return result


def render(actors, path, direction=(1.0, -0.9, 1.1), size=(560, 420), zoom=1.25):
    renderer = vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    window = figure_window(renderer, size)
    for actor in actors:
        renderer.AddActor(actor)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*direction)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()
    camera.Zoom(zoom)
    save_png(window, path)
    print("wrote", path)


def surface_actor(mesh, scalars=None, colors=None):
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(mesh)
    if scalars:
        mesh.GetCellData().SetActiveScalars(scalars)
        mapper.SetScalarModeToUseCellData()
        table = vtkLookupTable()
        table.SetNumberOfTableValues(len(colors))
        for i, c in enumerate(colors):
            table.SetTableValue(i, c[0], c[1], c[2], 1.0)
        table.SetTableRange(0, len(colors) - 1)
        table.Build()
        mapper.SetLookupTable(table)
        mapper.SetScalarRange(0, len(colors) - 1)
    else:
        mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    prop = actor.GetProperty()
    prop.SetColor(0.85, 0.8, 0.65)
    prop.SetInterpolationToFlat()
    prop.EdgeVisibilityOn()
    prop.SetEdgeColor(0.2, 0.2, 0.2)
    return actor


KIND_COLORS = [(0.85, 0.1, 0.1), (0.1, 0.6, 0.1), (0.1, 0.3, 0.9), (0.8, 0.5, 0.0), (0.4, 0.4, 0.4)]


def loop_actor(loops, radius):
    # FeatureKind -1 (no feature) shows grey: shift the kinds by one in a copy.
    data = copy(loops)
    kinds = data.GetCellData().GetArray("FeatureKind")
    for i in range(kinds.GetNumberOfTuples()):
        k = kinds.GetTuple1(i)
        kinds.SetTuple1(i, 4 if k < 0 else k)
    data.GetCellData().SetActiveScalars("FeatureKind")
    tubes = vtkTubeFilter()
    tubes.SetInputData(data)
    tubes.SetRadius(radius)
    tubes.SetNumberOfSides(8)
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(tubes.GetOutputPort())
    mapper.SetScalarModeToUseCellData()
    table = vtkLookupTable()
    table.SetNumberOfTableValues(5)
    for i, c in enumerate(KIND_COLORS):
        table.SetTableValue(i, c[0], c[1], c[2], 1.0)
    table.SetTableRange(0, 4)
    table.Build()
    mapper.SetLookupTable(table)
    mapper.SetScalarRange(0, 4)
    actor = vtkActor()
    actor.SetMapper(mapper)
    return actor


FILL_COLORS = [(0.85, 0.8, 0.65), (0.25, 0.55, 0.95), (0.95, 0.6, 0.1)]


def figure_set(name, source, alpha, out, loop_radius, direction=(1.0, -0.9, 1.1)):
    source.Update()
    original = copy(source.GetOutput())
    removal = surfacelod.vtkHoleBumpRemoval()
    removal.SetInputData(original)
    removal.SetFeatureSize(alpha)
    removal.Update()
    after = copy(removal.GetOutput())
    loops = copy(removal.GetOutput(1))
    print(name, original.GetNumberOfPolys(), "->", after.GetNumberOfPolys(), "triangles; genus",
          removal.GetInputGenus(), "->", removal.GetOutputGenus(), "; holes/bumps/cavities removed",
          removal.GetNumberOfHolesRemoved(), removal.GetNumberOfBumpsRemoved(), removal.GetNumberOfCavitiesRemoved())
    radius = loop_radius * original.GetLength()  # relative to the bounding-box diagonal
    render([surface_actor(original), loop_actor(loops, radius)], os.path.join(out, "hbr_%s_loops.png" % name),
           direction)
    render([surface_actor(after)], os.path.join(out, "hbr_%s_after.png" % name), direction)
    removal.SetCompletionToKeepTriangles()
    removal.Update()
    render([surface_actor(copy(removal.GetOutput()), "FilledPatch", FILL_COLORS)],
           os.path.join(out, "hbr_%s_kept.png" % name), direction)
    return original, after


def main():
    mesh_dir, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    plate = surfacelod.vtkBlockModelSource()
    plate.SetModelToPlateWithRoundHoles()
    plate.SetFeaturesX(4)
    plate.SetFeaturesY(3)
    original, after = figure_set("plate", plate, 0.2, out, 0.004)
    # vtkDecimatePro's topology-changing mode at our count.
    pro = vtkDecimatePro()
    pro.SetInputData(original)
    pro.SetTargetReduction(1.0 - after.GetNumberOfPolys() / original.GetNumberOfPolys())
    pro.PreserveTopologyOff()
    pro.SplittingOn()
    pro.BoundaryVertexDeletionOn()
    pro.Update()
    print("vtkDecimatePro:", pro.GetOutput().GetNumberOfPolys(), "triangles")
    render([surface_actor(copy(pro.GetOutput()))], os.path.join(out, "hbr_plate_decimatepro.png"))
    mixed = surfacelod.vtkBlockModelSource()
    mixed.SetModelToMixed()
    figure_set("mixed", mixed, 0.2, out, 0.003)
    for name, alpha, radius in (("anchor", 0.2, 0.003), ("couplingdown", 0.2, 0.003)):
        reader = surfacelod.vtkOFFMeshReader()
        reader.SetFileName(os.path.join(mesh_dir, name + ".off"))
        figure_set(name, reader, alpha, out, radius, (1.0, 0.8, 1.2))


if __name__ == "__main__":
    main()
