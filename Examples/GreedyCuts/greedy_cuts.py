#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Greedy-cuts simplification with a guaranteed error bound, checked with vtkSurfaceDeviation.

usage: greedy_cuts.py MESH.off [RELATIVE_ERROR] [OUTPUT.vtp]
"""
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
from surfacelod import vtkGreedyCutsSimplification, vtkOFFMeshReader, vtkSurfaceDeviation

path = sys.argv[1]
error = float(sys.argv[2]) if len(sys.argv) > 2 else 0.01
reader = vtkOFFMeshReader()
reader.SetFileName(path)
reader.Update()

cuts = vtkGreedyCutsSimplification()
cuts.SetInputConnection(reader.GetOutputPort())
cuts.SetMaximumError(error)  # relative to the bounding box diagonal (MaximumErrorIsRelative is on)
cuts.Update()
out = cuts.GetOutput()

deviation = vtkSurfaceDeviation()
deviation.SetReferenceConnection(reader.GetOutputPort())
deviation.SetComparedConnection(cuts.GetOutputPort())
deviation.Update()

bound = out.GetFieldData().GetArray("MaximumErrorBound").GetValue(0)
print(f"{reader.GetOutput().GetNumberOfCells()} -> {out.GetNumberOfCells()} triangles")
print(f"guaranteed Hausdorff bound {bound:.6g}, measured {deviation.GetHausdorff():.6g}")
print(f"{cuts.GetNumberOfPatches()} patches, {cuts.GetNumberOfEars()} ears, {cuts.GetNumberOfBites()} bites, "
      f"{cuts.GetNumberOfRepairs()} repairs, {cuts.GetOriginalPatches()} patches kept original")
# The promise of the method, checked: the measured distance within the bound, fewer triangles.
kept = deviation.GetHausdorff() <= bound
fewer = out.GetNumberOfCells() < reader.GetOutput().GetNumberOfCells()
print(f"bound kept: {'yes' if kept else 'no'}; fewer triangles: {'yes' if fewer else 'no'}")
if len(sys.argv) > 3:
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(sys.argv[3])
    writer.SetInputData(out)
    writer.Write()
sys.exit(0 if kept and fewer else 1)
