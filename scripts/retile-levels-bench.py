#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Nested re-tiling levels and their interpolation (Turk 1992 sections 6.1-6.3), measured in one run.

  /usr/bin/python3 scripts/retile-levels-bench.py --build build [--points 2000] [--repeat 3] INPUT...

INPUT: an .off/.vtp/.ply file or a test mesh name (bunny00, fandisk, ...: build/TestData/meshes),
or noisy:N / synthetic:N. Per input: vtkQuadricDecimation to the finest level's triangle count and
vtkRetile with two nested levels (NestedLevelRatio 4), alternating, best of --repeat (wall and CPU
seconds); the levels' Hausdorff to the input; then vtkRetileLevelInterpolation on the two levels
with the recorded removals (tracked) and without (closest point): fragments, inconsistent
fragments, T = 0 Hausdorff to the low level, T = 1 to the high level, wall seconds (best of
--repeat). Hausdorff distances are relative to the first argument's bounding-box diagonal
(vtkSurfaceDeviation, 100,000 samples). Run with Debian's /usr/bin/python3 (it has VTK).
"""
import argparse
import importlib.util
import os
import sys
import time


def import_surfacelod(build):
    # The same import as output-hashes.py's (its file name is not a module name).
    spec = importlib.util.spec_from_file_location(
        "output_hashes", os.path.join(os.path.dirname(os.path.abspath(__file__)), "output-hashes.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.import_surfacelod(build)


def load(slod, build, name):
    import vtk
    if name.startswith("noisy:") or name.startswith("synthetic:"):
        kind, resolution = name.split(":")
        source = slod.vtkScanSurfaceSource() if kind == "noisy" else slod.vtkSyntheticIsosurfaceSource()
        if kind == "noisy":
            source.SetKindToNoisyIsosurface()
        source.SetResolution(int(resolution))
        source.Update()
        return source.GetOutput()
    path = name if os.path.exists(name) else os.path.join(build, "TestData", "meshes", name + ".off")
    if not os.path.exists(path):
        sys.exit("no input %s" % name)
    if path.endswith(".off"):
        reader = slod.vtkOFFMeshReader()
    elif path.endswith(".ply"):
        reader = vtk.vtkPLYReader()
    else:
        reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def hausdorff(slod, a, b):
    deviation = slod.vtkSurfaceDeviation()
    deviation.SetReferenceData(a)
    deviation.SetComparedData(b)
    deviation.SetNumberOfSamples(100000)
    deviation.Update()
    return deviation.GetHausdorffRelative()


def timed(run):
    wall, cpu = time.perf_counter(), time.process_time()
    result = run()
    return result, time.perf_counter() - wall, time.process_time() - cpu


def best(runs):
    return min(r[1] for r in runs), min(r[2] for r in runs)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", required=True)
    parser.add_argument("--points", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("inputs", nargs="+")
    args = parser.parse_args()
    slod = import_surfacelod(args.build)
    import vtk
    vtk.vtkObject.GlobalWarningDisplayOff()
    print("load: %s" % open("/proc/loadavg").read().strip())
    for name in args.inputs:
        mesh = load(slod, args.build, name)

        def retile():
            f = slod.vtkRetile()
            f.SetInputData(mesh)
            f.SetNumberOfPoints(args.points)
            f.GenerateNestedLevelsOn()
            f.SetNumberOfNestedLevels(2)
            f.SetNestedLevelRatio(4.0)
            f.Update()
            return f

        retiles, decimations = [], []
        for _ in range(args.repeat):
            retiles.append(timed(retile))
            finest = retiles[-1][0].GetOutput().GetNumberOfPolys()

            def decimate():
                d = vtk.vtkQuadricDecimation()
                d.SetInputData(mesh)
                d.SetTargetReduction(1.0 - finest / float(mesh.GetNumberOfPolys()))
                d.Update()
                return d
            decimations.append(timed(decimate))
        levels = retiles[-1][0].GetNestedLevels()
        low, high = levels.GetBlock(0), levels.GetBlock(1)
        rw, rc = best(retiles)
        qw, qc = best(decimations)
        print("%s: %d triangles; levels %d / %d vertices, %d / %d triangles; retile nested %.3f s (CPU %.3f), "
              "vtkQuadricDecimation %.3f s (CPU %.3f): %.2fx its time (CPU %.2fx)"
              % (name, mesh.GetNumberOfPolys(), low.GetNumberOfPoints(), high.GetNumberOfPoints(),
                 low.GetNumberOfPolys(), high.GetNumberOfPolys(), rw, rc, qw, qc, rw / qw, rc / qc))
        print("  Hausdorff input->levels: low %.3g, high %.3g; high vs low %.3g"
              % (hausdorff(slod, mesh, low), hausdorff(slod, mesh, high), hausdorff(slod, high, low)))
        # A build without UseRemovalRecords (before section 6.2 tracking) has the closest-point path only.
        paths = (1, 0) if hasattr(slod.vtkRetileLevelInterpolation(), "SetUseRemovalRecords") else (0,)
        for tracked in paths:
            def blend(t):
                b = slod.vtkRetileLevelInterpolation()
                b.SetHighDetailData(high)
                b.SetLowDetailData(low)
                if hasattr(b, "SetUseRemovalRecords"):
                    b.SetUseRemovalRecords(tracked)
                b.SetT(t)
                b.Update()
                return b
            runs = [timed(lambda: blend(1.0)) for _ in range(args.repeat)]
            atOne = runs[-1][0]
            one = vtk.vtkPolyData()
            one.DeepCopy(atOne.GetOutput())
            zero = blend(0.0).GetOutput()
            print("  %-13s removals %5d, fragments %6d, inconsistent %3d, T=0 to low %.3g, T=1 to high %.3g, %.3f s"
                  % ("tracked" if tracked else "closest point",
                     atOne.GetNumberOfTrackedRemovals() if hasattr(atOne, "GetNumberOfTrackedRemovals") else 0,
                     atOne.GetNumberOfFragments(), atOne.GetNumberOfInconsistentFragments(),
                     hausdorff(slod, low, zero), hausdorff(slod, high, one), best(runs)[0]))
        sys.stdout.flush()
    print("load: %s" % open("/proc/loadavg").read().strip())


if __name__ == "__main__":
    main()
