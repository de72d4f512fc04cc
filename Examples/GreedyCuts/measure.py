#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Greedy cuts against vtkQuadricDecimation at equal measured Hausdorff, and the sliver share.

usage: measure.py MESH.off EPS[,EPS...] [--patchification chapter3|chapter4] [--shaped DEGREES] [--no-qd]
                  [--no-final-collapses] [--single-run]

--single-run: MonotoneInEpsilon off (one run at epsilon itself, as before session 12).

Per epsilon (relative to the diagonal): triangles, measured Hausdorff (vtkSurfaceDeviation),
patches kept as original triangles, share of triangles whose smallest angle is under 5 degrees,
CPU seconds; then the fewest triangles at which vtkQuadricDecimation's measured Hausdorff is at
most ours (bisection on its target count, same run) and the ratio ours / vtkQD.
"""
import math
import sys
import time

from vtkmodules.vtkFiltersCore import vtkQuadricDecimation
from surfacelod import vtkGreedyCutsSimplification, vtkOFFMeshReader, vtkSurfaceDeviation


def hausdorff(a, b):
    d = vtkSurfaceDeviation()
    d.SetReferenceData(a)
    d.SetComparedData(b)
    d.SetNumberOfSamples(100000)
    d.Update()
    return d.GetHausdorff()


def sliver_share(poly, degrees=5.0):
    pts = poly.GetPoints()
    n = poly.GetNumberOfCells()
    thin = 0
    for c in range(n):
        ids = poly.GetCell(c).GetPointIds()
        p = [pts.GetPoint(ids.GetId(k)) for k in range(3)]
        angles = []
        for k in range(3):
            u = [p[(k + 1) % 3][i] - p[k][i] for i in range(3)]
            v = [p[(k + 2) % 3][i] - p[k][i] for i in range(3)]
            nu = math.sqrt(sum(x * x for x in u))
            nv = math.sqrt(sum(x * x for x in v))
            if nu == 0 or nv == 0:
                angles.append(0)
                continue
            cosine = max(-1.0, min(1.0, sum(u[i] * v[i] for i in range(3)) / (nu * nv)))
            angles.append(math.degrees(math.acos(cosine)))
        thin += min(angles) < degrees
    return thin / max(n, 1)


def quadric_at(inp, reduction):
    q = vtkQuadricDecimation()
    q.SetInputData(inp)
    q.SetTargetReduction(reduction)
    t = time.process_time()
    q.Update()
    return q.GetOutput(), time.process_time() - t


def quadric_equal_hausdorff(inp, h, steps=10):
    """Fewest vtkQD triangles whose measured Hausdorff is at most h (bisection on the reduction)."""
    n = inp.GetNumberOfCells()
    lo, hi = 0.0, 0.999  # reductions: lo meets h (the input does), hi may not
    best = (n, 0.0)
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        out, _ = quadric_at(inp, mid)
        if hausdorff(inp, out) <= h:
            lo = mid
            best = (out.GetNumberOfCells(), hausdorff(inp, out))
        else:
            hi = mid
    return best


def main():
    path = sys.argv[1]
    epsilons = [float(e) for e in sys.argv[2].split(',')]
    chapter3 = '--patchification' in sys.argv and sys.argv[sys.argv.index('--patchification') + 1] == 'chapter3'
    no_qd = '--no-qd' in sys.argv
    final_collapses = '--no-final-collapses' not in sys.argv
    single_run = '--single-run' in sys.argv
    shaped = float(sys.argv[sys.argv.index('--shaped') + 1]) if '--shaped' in sys.argv else 0.0
    r = vtkOFFMeshReader()
    r.SetFileName(path)
    r.Update()
    inp = r.GetOutput()
    name = path.split('/')[-1]
    for eps in epsilons:
        f = vtkGreedyCutsSimplification()
        f.SetInputData(inp)
        f.SetMaximumError(eps)
        if chapter3:
            f.SetPatchification(1)
        f.SetShapedTriangleAngle(shaped)
        f.SetFinalCollapses(final_collapses)
        if hasattr(f, 'SetMonotoneInEpsilon'):
            f.SetMonotoneInEpsilon(not single_run)
        t = time.process_time()
        f.Update()
        cpu = time.process_time() - t
        out = f.GetOutput()
        h = hausdorff(inp, out)
        fallbacks = f.GetOriginalPatches()
        line = (f"{name} eps {eps} (used {f.GetUsedMaximumError() / inp.GetLength():.4g}): "
                f"{inp.GetNumberOfCells()} -> {out.GetNumberOfCells()} tris, "
                f"H/eps {h / f.GetUsedMaximumError():.3f}, patches {f.GetNumberOfPatches()} "
                f"(original {fallbacks}), collapses {f.GetNumberOfFinalCollapses()}, <5deg {100 * sliver_share(out):.1f}%, cpu {cpu:.2f} s")
        if not no_qd:
            count, hq = quadric_equal_hausdorff(inp, h)
            qout, qcpu = quadric_at(inp, 1.0 - count / inp.GetNumberOfCells())
            line += (f"; vtkQD at H<= ours: {count} tris (H {hq:.4g}), ratio {out.GetNumberOfCells() / count:.2f}x, "
                     f"QD <5deg {100 * sliver_share(qout):.1f}%, QD cpu {qcpu:.2f} s")
        print(line, flush=True)


main()
