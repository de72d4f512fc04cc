# SPDX-License-Identifier: BSD-3-Clause
"""Pictures of Documentation/TopologicalNoiseRemoval.md (run under xvfb-run -a):

    PYTHONPATH=<build>/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 render_figures.py <mesh_dir> <out_dir> [mri.vtp]

CGAL's cheese (genus 133) before and after vtkTopologicalNoiseRemoval at two feature sizes, with
the cut loops as red tubes; with the MRI surface, a close-up of the loops cut at 3 mm, and the
handles kept (blue, sized by the survey) beside those cut (red).
"""
import os
import sys

from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkTubeFilter
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer

import surfacelod
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from slod_figures import figure_window, save_png  # noqa: E402 (Examples/slod_figures.py)


def snapshot(actors, path, view, focus=None, zoom=1.0, size=(560, 420)):
    renderer = vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    window = figure_window(renderer, size)
    for actor in actors:
        renderer.AddActor(actor)
    renderer.ResetCamera()
    camera = renderer.GetActiveCamera()
    if focus is not None:
        camera.SetFocalPoint(*focus)
    centre = camera.GetFocalPoint()
    camera.SetPosition(*[c + d for c, d in zip(centre, view)])
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCameraClippingRange()
    camera.Zoom(zoom)
    save_png(window, path)
    print("wrote", path)


def mesh_actor(mesh, opacity=1.0):
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(mesh)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.85, 0.8, 0.65)
    actor.GetProperty().SetOpacity(opacity)
    return actor


def loops_with(loops, removed):
    """The loops whose cell data Removed is `removed` (1 cut, 0 kept)."""
    flags = loops.GetCellData().GetArray("Removed")
    ids = vtkIdList()
    for c in range(loops.GetNumberOfCells()):
        if int(flags.GetTuple1(c)) == removed:
            ids.InsertNextId(c)
    subset = vtkPolyData()
    subset.SetPoints(loops.GetPoints())
    subset.Allocate(ids.GetNumberOfIds())
    for i in range(ids.GetNumberOfIds()):
        subset.InsertNextCell(loops.GetCellType(ids.GetId(i)), loops.GetCell(ids.GetId(i)).GetPointIds())
    return subset


def loops_actor(loops, radius, colour=(0.85, 0.1, 0.1)):
    tubes = vtkTubeFilter()
    tubes.SetInputData(loops)
    tubes.SetRadius(radius)
    tubes.SetNumberOfSides(8)
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(tubes.GetOutputPort())
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*colour)
    return actor


def clean(mesh, size, relative, survey_factor=2.0):
    removal = surfacelod.vtkTopologicalNoiseRemoval()
    removal.SetInputData(mesh)
    removal.SetKeptHandleSurveyFactor(survey_factor)
    removal.SetFeatureSize(size)
    removal.SetFeatureSizeIsRelative(relative)
    removal.Update()
    print("size", size, "handles removed", removal.GetNumberOfHandlesRemoved(), "genus",
          removal.GetInputGenus(), "->", removal.GetOutputGenus())
    return removal.GetOutput(0), removal.GetOutput(1)


def main(mesh_dir, out_dir, mri=None):
    os.makedirs(out_dir, exist_ok=True)
    reader = surfacelod.vtkOFFMeshReader()
    reader.SetFileName(os.path.join(mesh_dir, "cheese.off"))
    reader.Update()
    cheese = reader.GetOutput()
    view = (0.25, -0.3, 0.2)
    snapshot([mesh_actor(cheese)], os.path.join(out_dir, "tnr_cheese_input.png"), view, zoom=1.5)
    for size in (0.04, 0.06):
        cleaned, loops = clean(cheese, size, True)
        name = "tnr_cheese_%s" % str(size).replace(".", "")
        snapshot([mesh_actor(cheese), loops_actor(loops, 0.0006)], os.path.join(out_dir, name + "_loops.png"), view,
                 zoom=1.5)
        snapshot([mesh_actor(cleaned)], os.path.join(out_dir, name + "_after.png"), view, zoom=1.5)
    if mri:
        mri_reader = vtkXMLPolyDataReader()
        mri_reader.SetFileName(mri)
        mri_reader.Update()
        cleaned, loops = clean(mri_reader.GetOutput(), 3.0, False, 64.0)
        sizes = cleaned.GetFieldData().GetArray("KeptHandleSizes")
        print("kept handle sizes (mm):", ", ".join("%.2f" % sizes.GetTuple1(i) for i in range(sizes.GetNumberOfTuples())))
        focus = loops.GetPoint(0) if loops.GetNumberOfPoints() else None
        cut_loops, kept_loops = loops_with(loops, 1), loops_with(loops, 0)
        snapshot([mesh_actor(mri_reader.GetOutput()), loops_actor(cut_loops, 0.25)],
                 os.path.join(out_dir, "tnr_mri_loops.png"), (0, -300, 80))
        # The surface see-through: most loops lie in the sulci.
        snapshot([mesh_actor(cleaned, 0.12), loops_actor(cut_loops, 0.4), loops_actor(kept_loops, 0.7, (0.1, 0.3, 0.9))],
                 os.path.join(out_dir, "tnr_mri_kept_handles.png"), (0, -300, 80))
        snapshot([mesh_actor(mri_reader.GetOutput()), loops_actor(cut_loops, 0.15)],
                 os.path.join(out_dir, "tnr_mri_loops_closeup.png"), (0, -60, 20), focus, 1.0)


if __name__ == "__main__":
    main(*sys.argv[1:])
