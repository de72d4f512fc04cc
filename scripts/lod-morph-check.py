#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Checks vtkLODInterpolation's morph between two levels of one vtkQuadricTriangleCollapse run.

For each input: the coarse level (--coarse share of the triangles, with collapse records), the
detailed level (--detailed share, a vtkProgressiveMeshReconstruction level; 1 = the input), then
the morph at several t, with the records (the geomorph) and without (the paper's nearest vertices):
non-manifold edges, duplicate triangles, Euler characteristic, border loops, the distance between
t and t + 1e-6 (symmetric Hausdorff relative to the detailed diagonal, vtkSurfaceDeviation) and,
at the ends, whether the output is the level (Hausdorff 0).

  /usr/bin/python3 scripts/lod-morph-check.py --build build INPUT... [--detailed 0.1] [--coarse 0.02]

INPUT: a mesh file (.off/.vtp/.ply/.stl), or noisy:<resolution> (vtkScanSurfaceSource).
"""
import argparse
import collections
import os
import sys
import time

T_VALUES = [0.0, 1e-6, 0.1, 0.25, 0.5, 0.75, 0.9, 0.999999, 1.0]
DELTA = 1e-6


def import_surfacelod(build):
    """The project's wrapped module, found as scripts/output-hashes.py finds it."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("output_hashes", os.path.join(os.path.dirname(__file__), "output-hashes.py"))
    hashes = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hashes)
    return hashes.import_surfacelod(build)


def read(slod, vtk, name):
    if name.startswith("noisy:"):
        source = slod.vtkScanSurfaceSource()
        source.SetResolution(int(name.split(":")[1]))
        source.Update()
        return source.GetOutput()
    ext = os.path.splitext(name)[1].lower()
    reader = {".vtp": vtk.vtkXMLPolyDataReader, ".ply": vtk.vtkPLYReader, ".stl": vtk.vtkSTLReader}.get(ext)
    reader = reader() if reader else slod.vtkOFFMeshReader()
    reader.SetFileName(name)
    reader.Update()
    return reader.GetOutput()


def topology(polydata):
    """Triangles, non-manifold edges, duplicate triangles, Euler characteristic, border loops."""
    polys = polydata.GetPolys()
    ids = polys.GetConnectivityArray()
    offsets = polys.GetOffsetsArray()
    triangles = [(ids.GetValue(offsets.GetValue(c)), ids.GetValue(offsets.GetValue(c) + 1), ids.GetValue(offsets.GetValue(c) + 2))
                 for c in range(polys.GetNumberOfCells())]
    uses = collections.Counter()
    for a, b, c in triangles:
        for e in ((a, b), (b, c), (c, a)):
            uses[(min(e), max(e))] += 1
    vertices = len({v for t in triangles for v in t})
    # Border loops: connected components of the border edges (breadth-first).
    border = collections.defaultdict(list)
    for (a, b), n in uses.items():
        if n == 1:
            border[a].append(b)
            border[b].append(a)
    loops, seen = 0, set()
    for start in border:
        if start not in seen:
            loops += 1
            seen.add(start)
            queue = collections.deque([start])
            while queue:
                for w in border[queue.popleft()]:
                    if w not in seen:
                        seen.add(w)
                        queue.append(w)
    return {
        "triangles": len(triangles),
        "nm_edges": sum(1 for n in uses.values() if n > 2),
        "duplicates": len(triangles) - len({tuple(sorted(t)) for t in triangles}),
        "euler": vertices - len(uses) + len(triangles),
        "loops": loops,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", required=True)
    parser.add_argument("--detailed", type=float, default=0.1)
    parser.add_argument("--coarse", type=float, default=0.02)
    parser.add_argument("--samples", type=int, default=20000)
    parser.add_argument("inputs", nargs="+")
    a = parser.parse_args()
    slod = import_surfacelod(a.build)
    # Only the modules needed: `import vtk` also loads VTK's MPI modules, and the collapse filter
    # then finds a global controller it should not use here.
    from vtkmodules import vtkCommonDataModel, vtkIOGeometry, vtkIOPLY, vtkIOXML
    vtk = argparse.Namespace(vtkPolyData=vtkCommonDataModel.vtkPolyData, vtkTable=vtkCommonDataModel.vtkTable,
                             vtkXMLPolyDataReader=vtkIOXML.vtkXMLPolyDataReader, vtkPLYReader=vtkIOPLY.vtkPLYReader,
                             vtkSTLReader=vtkIOGeometry.vtkSTLReader)

    for name in a.inputs:
        start = time.time()
        mesh = read(slod, vtk, name)
        n = mesh.GetNumberOfPolys()
        collapse = slod.vtkQuadricTriangleCollapse()
        collapse.SetInputData(mesh)
        collapse.SetTargetNumberOfTriangles(int(a.coarse * n))
        collapse.SetTargetReduction(0)
        collapse.GenerateProgressiveMeshOn()
        collapse.Update()
        coarse = vtk.vtkPolyData()
        coarse.DeepCopy(collapse.GetOutput(0))
        records = vtk.vtkTable()
        records.DeepCopy(collapse.GetOutputDataObject(1))
        detailed = mesh
        if a.detailed < 1:
            levels = slod.vtkProgressiveMeshReconstruction()
            levels.SetInputData(0, coarse)
            levels.SetInputData(1, records)
            levels.SetTargetNumberOfTriangles(int(a.detailed * n))
            levels.Update()
            detailed = vtk.vtkPolyData()
            detailed.DeepCopy(levels.GetOutput())
        d, c = topology(detailed), topology(coarse)
        print("%s: %d triangles; detailed %d (Euler %d, %d loops), coarse %d (Euler %d, %d loops); levels in %.1f s"
              % (name, n, d["triangles"], d["euler"], d["loops"], c["triangles"], c["euler"], c["loops"], time.time() - start))
        for mode in ("records", "nearest"):
            morph = slod.vtkLODInterpolation()
            morph.SetInputData(0, detailed)
            morph.SetInputData(1, coarse)
            if mode == "records":
                morph.SetInputData(2, records)

            def at(t):
                morph.SetT(t)
                morph.Update()
                out = vtk.vtkPolyData()
                out.DeepCopy(morph.GetOutput())
                return out, morph.GetMergedVertices()

            def distance(x, y):
                deviation = slod.vtkSurfaceDeviation()
                deviation.SetInputData(0, x)
                deviation.SetInputData(1, y)
                deviation.SetNumberOfSamples(a.samples)
                deviation.Update()
                return deviation.GetHausdorffRelative()

            worst = 0.0
            for t in T_VALUES:
                out, merged = at(t)
                s = topology(out)
                nxt = min(1.0, t + DELTA)
                jump = distance(at(nxt - DELTA)[0], at(nxt)[0])
                worst = max(worst, jump)
                end = ""
                if t in (0.0, 1.0):
                    end = " | Hausdorff to the %s level %.2e" % ("detailed" if t == 0 else "coarse", distance(detailed if t == 0 else coarse, out))
                print("  %-7s t=%-8g %7d triangles %5d merged  nm-edges %4d  duplicates %4d  Euler %5d  loops %4d  jump(t, t+1e-6) %.2e%s"
                      % (mode, t, s["triangles"], merged, s["nm_edges"], s["duplicates"], s["euler"], s["loops"], jump, end))
            print("  %s: largest jump over a step of 1e-6: %.2e of the diagonal" % (mode, worst))
        print("  (%.1f s)" % (time.time() - start))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
