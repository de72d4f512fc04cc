# SPDX-License-Identifier: BSD-3-Clause
"""Distributed simplification in ParaView: `mpiexec -n N pvbatch paraview_mpi_test.py ...`.

A source that honours piece requests (ParaView's Sphere, half of it: each rank makes its own band
of meridians, bit-identical points on the seams between bands; a full sphere's last band would
close onto the first at 360 degrees, whose points differ in the last bit) feeds the plugin's Quadric
Triangle Collapse on every rank; the pieces are fetched to rank 0, their points joined where they
have exactly the same position (the seams) and the union is checked with the measures of
paraview_plugin_test.py: one disk again (Euler characteristic 1, one border loop: no crack, no
non-manifold edge), the triangle count within 1% of the target. A missing plugin is a failure,
never a skip.

  mpiexec -n 2 pvbatch paraview_mpi_test.py --plugin <.../SurfaceLOD.so>
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from paraview import servermanager  # noqa: E402
from paraview import simple  # noqa: E402
from vtkmodules.vtkCommonCore import vtkIdList, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData  # noqa: E402

import paraview_plugin_test as measures  # noqa: E402

REDUCTION = 0.9


def joined_at_equal_positions(polydata):
    """The fetched pieces (appended, each with its own copy of the seam points) with points at
    exactly the same position made one."""
    index_of = {}
    remap = []
    points = vtkPoints()
    for i in range(polydata.GetNumberOfPoints()):
        position = polydata.GetPoint(i)
        if position not in index_of:
            index_of[position] = points.InsertNextPoint(position)
        remap.append(index_of[position])
    cells = vtkCellArray()
    ids = vtkIdList()
    polys = polydata.GetPolys()
    polys.InitTraversal()
    while polys.GetNextCell(ids):
        cells.InsertNextCell(ids.GetNumberOfIds(), [remap[ids.GetId(k)] for k in range(ids.GetNumberOfIds())])
    joined = vtkPolyData()
    joined.SetPoints(points)
    joined.SetPolys(cells)
    return joined


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--plugin", required=True, help="the built SurfaceLOD.so")
    args = parser.parse_args()
    if not os.path.isfile(args.plugin):
        print("FAIL  the ParaView plugin was not built: %s is missing "
              "(run scripts/paraview-plugin.sh, or the README's set-up command)" % args.plugin)
        return 1
    simple.LoadPlugin(args.plugin, remote=False)
    processes = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    checks = measures.Checks("distributed sphere")
    checks.expect(processes >= 2, "runs on %d processes (expected mpiexec -n 2 or more)" % processes)

    sphere = simple.Sphere(ThetaResolution=160, PhiResolution=120, StartTheta=0.0, EndTheta=180.0)
    simplified = simple.QuadricTriangleCollapse(Input=sphere, TargetReduction=REDUCTION)
    whole = measures.topology(joined_at_equal_positions(measures.fetch(sphere)))
    union = measures.topology(joined_at_equal_positions(measures.fetch(simplified)))
    print("sphere on %d processes: %s -> %s" % (processes, whole, union))

    disk = {"euler": 1, "border_loops": 1, "non_manifold_edges": 0}
    measures.expect_topology(checks, "the pieces of the input", whole, disk)
    measures.expect_topology(checks, "union of the simplified pieces", union, disk)
    target = math.floor((1.0 - REDUCTION) * whole["triangles"] + 1e-6)
    checks.expect(abs(union["triangles"] - target) <= 0.01 * target,
                  "%d triangles, target %d (within 1%%)" % (union["triangles"], target))
    print("%d failure(s)" % len(checks.failures))
    return 1 if checks.failures else 0


if __name__ == "__main__":
    # Not sys.exit: under mpiexec it would leave pvbatch without finalising MPI (the other ranks are
    # killed and mpiexec fails even on success). An uncaught exception makes pvbatch exit non-zero.
    if main() != 0:
        raise AssertionError("the distributed checks failed (see above)")
