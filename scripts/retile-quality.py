#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Triangle quality of vtkRetile's outputs against the input, with vtkQuadricDecimation in the same run.

  /usr/bin/python3 scripts/retile-quality.py --build build [--points 500,2000] [--levels] [--set Name=value] INPUT...

INPUT: an .off/.vtp/.ply file, a test mesh name (build/TestData/meshes) or noisy:N / synthetic:N.
Per input and vertex count: vtkRetile (NumberOfPoints) and vtkQuadricDecimation at the retiling's
triangle count, alternating; per output:
  flipped   triangles whose normal points against the input's triangle at the closest point of
            their centroid (dot < 0),
  folded    output edges whose two triangles turn by more than 150 degrees (a fold back),
  needles   triangles with a smallest angle under 1 degree or an edge under 1e-6 of the diagonal,
  min angle the smallest angle of any triangle (degrees),
  Hausdorff relative to the input's diagonal (vtkSurfaceDeviation, 100,000 samples), both ways.
--levels: also every nested level (three levels, ratio 4, the finest at the count).
--set Name=value: a vtkRetile setting (e.g. EnforceFacing=1).
--reduction R: TargetReduction R instead of the vertex counts (the tests' setting is 0.9).
Also printed: small5, the share of triangles with a smallest angle under 5 degrees, and each
flipped triangle's kind (a triangle counts once, in the first that applies):
  retained  it has a retained original vertex,
  vertex    it faces against the input's normal at one of its own vertices (the normal interpolated
            at the vertex's closest point: where the vertex lies),
  crease    the input faces more than 45 degrees apart at two of its vertices,
  thin      it faces the way the input does at its vertices, but its centroid's closest input
            triangle faces the other way (it spans a part thinner than the spacing).
"""
import argparse
import importlib.util
import math
import os
import time


def bench_module():
    # The levels bench's loading and distance (its file name is not a module name).
    spec = importlib.util.spec_from_file_location(
        "retile_levels_bench", os.path.join(os.path.dirname(os.path.abspath(__file__)), "retile-levels-bench.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


BENCH = bench_module()
import_surfacelod = BENCH.import_surfacelod
hausdorff = BENCH.hausdorff


def load(slod, build, name):
    import vtk
    triangles = vtk.vtkTriangleFilter()
    triangles.SetInputData(BENCH.load(slod, build, name))
    triangles.Update()
    return triangles.GetOutput()


def sub(u, v):
    return (u[0] - v[0], u[1] - v[1], u[2] - v[2])


def dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def norm(u):
    return math.sqrt(dot(u, u))


def corner_angle(p, q, r):
    u, v = sub(q, p), sub(r, p)
    length = norm(u) * norm(v)
    return math.degrees(math.acos(max(-1.0, min(1.0, dot(u, v) / length)))) if length > 0 else 0.0


def input_normal_at(source, normals, locator, point):
    """The input's point normals interpolated at the closest point of `point` on the input."""
    import vtk
    closest, cell, sub_id, dist2 = [0.0, 0.0, 0.0], vtk.reference(0), vtk.reference(0), vtk.reference(0.0)
    locator.FindClosestPoint(point, closest, cell, sub_id, dist2)
    triangle = source.GetCell(int(cell))
    weights, pcoords, d2 = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], vtk.reference(0.0)
    triangle.EvaluatePosition(closest, [0.0, 0.0, 0.0], vtk.reference(0), pcoords, d2, weights)
    n = [0.0, 0.0, 0.0]
    for k in range(3):
        m = normals.GetTuple3(triangle.GetPointId(k))
        n = [n[i] + weights[k] * m[i] for i in range(3)]
    length = norm(n)
    return tuple(x / length for x in n) if length > 0 else (0.0, 0.0, 0.0)


def point_normals(source):
    import vtk
    normals = vtk.vtkPolyDataNormals()
    normals.SetInputData(source)
    normals.SplittingOff()
    normals.ConsistencyOff()
    normals.ComputePointNormalsOn()
    normals.Update()
    return normals.GetOutput().GetPointData().GetNormals()


def classify_flip(tri, unit, retained_from, vertex_normals):
    if any(v >= retained_from for v in tri):
        return "retained"
    at = [vertex_normals[v] for v in tri]
    if any(dot(unit, n) < 0 for n in at):
        return "vertex"
    if min(dot(at[0], at[1]), dot(at[1], at[2]), dot(at[2], at[0])) < math.cos(math.radians(45)):
        return "crease"
    return "thin"


def quality(source, output, retained=0):
    import vtk
    diagonal = source.GetLength()
    points = [output.GetPoint(i) for i in range(output.GetNumberOfPoints())]
    ids = vtk.vtkIdList()
    tris = []
    polys = output.GetPolys()
    polys.InitTraversal()
    while polys.GetNextCell(ids):
        tris.append(tuple(ids.GetId(k) for k in range(ids.GetNumberOfIds())))
    locator = vtk.vtkStaticCellLocator()
    locator.SetDataSet(source)
    locator.BuildLocator()
    closest, cell, sub_id, dist2 = [0.0, 0.0, 0.0], vtk.reference(0), vtk.reference(0), vtk.reference(0.0)
    source_normal = vtk.vtkTriangle.ComputeNormal
    result = dict(flipped=0, folded=0, needles=0, min_angle=180.0, min_edge=float("inf"), small5=0.0,
                  kinds=dict(retained=0, vertex=0, crease=0, thin=0))
    normals = point_normals(source)
    vertex_normals = {}
    retained_from = len(points) - retained
    units = []
    half = {}
    normal_out = [0.0, 0.0, 0.0]
    for t, tri in enumerate(tris):
        a, b, c = points[tri[0]], points[tri[1]], points[tri[2]]
        n = cross(sub(b, a), sub(c, a))
        length = norm(n)
        unit = tuple(x / length for x in n) if length > 0 else (0.0, 0.0, 0.0)
        units.append(unit)
        centroid = tuple((a[k] + b[k] + c[k]) / 3.0 for k in range(3))
        locator.FindClosestPoint(centroid, closest, cell, sub_id, dist2)
        cell_points = source.GetCell(int(cell)).GetPoints()
        source_normal(cell_points.GetPoint(0), cell_points.GetPoint(1), cell_points.GetPoint(2), normal_out)
        if dot(unit, normal_out) < 0:
            result["flipped"] += 1
            for v in tri:
                if v not in vertex_normals:
                    vertex_normals[v] = input_normal_at(source, normals, locator, points[v])
            result["kinds"][classify_flip(tri, unit, retained_from, vertex_normals)] += 1
        smallest = min(corner_angle(a, b, c), corner_angle(b, c, a), corner_angle(c, a, b)) if length > 0 else 0.0
        result["small5"] += 1.0 / len(tris) if smallest < 5.0 else 0.0
        edge = min(norm(sub(b, a)), norm(sub(c, b)), norm(sub(a, c))) / diagonal
        result["min_angle"] = min(result["min_angle"], smallest)
        result["min_edge"] = min(result["min_edge"], edge)
        if smallest < 1.0 or edge < 1e-6:
            result["needles"] += 1
        for k in range(3):
            key = (min(tri[k], tri[(k + 1) % 3]), max(tri[k], tri[(k + 1) % 3]))
            other = half.pop(key, None)
            if other is None:
                half[key] = t
            elif dot(unit, units[other]) < math.cos(math.radians(150)):
                result["folded"] += 1
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", required=True)
    parser.add_argument("--points", default="500,2000")
    parser.add_argument("--levels", action="store_true")
    parser.add_argument("--set", action="append", default=[])
    parser.add_argument("--reduction", type=float, default=0.0)
    parser.add_argument("inputs", nargs="+")
    args = parser.parse_args()
    slod = import_surfacelod(args.build)
    import vtk
    for name in args.inputs:
        source = load(slod, args.build, name)
        counts = [0] if args.reduction > 0 else [int(x) for x in args.points.split(",")]
        for count in counts:
            retile = slod.vtkRetile()
            retile.SetInputData(source)
            if args.reduction > 0:
                retile.SetTargetReduction(args.reduction)
            else:
                retile.SetNumberOfPoints(count)
            for setting in args.set:
                key, value = setting.split("=")
                getattr(retile, "Set" + key)(float(value) if "." in value else int(value))
            if args.levels:
                retile.GenerateNestedLevelsOn()
                retile.SetNumberOfNestedLevels(3)
            start = time.process_time()
            retile.Update()
            seconds = time.process_time() - start
            output = retile.GetOutput()
            quadric = vtk.vtkQuadricDecimation()
            quadric.SetInputData(source)
            quadric.SetTargetReduction(1.0 - output.GetNumberOfPolys() / source.GetNumberOfPolys())
            start = time.process_time()
            quadric.Update()
            quadric_seconds = time.process_time() - start
            q = quality(source, output, retile.GetNumberOfRetainedVertices())
            h, hq = hausdorff(slod, source, output), hausdorff(slod, source, quadric.GetOutput())
            print("%-14s %6d pts %6d tris (QD %6d) flipped %3d folded %3d needles %3d min angle %6.2f min edge %.1e "
                  "retained %3d | Hausdorff %.3e QD %.3e ratio %5.2f | CPU %.2f s QD %.2f s" % (
                      name, output.GetNumberOfPoints(), output.GetNumberOfPolys(),
                      quadric.GetOutput().GetNumberOfPolys(), q["flipped"], q["folded"], q["needles"],
                      q["min_angle"], q["min_edge"], retile.GetNumberOfRetainedVertices(), h, hq, h / hq,
                      seconds, quadric_seconds), flush=True)
            print("  small5 %.2f%% flipped kinds %s" % (100.0 * q["small5"], " ".join(
                "%s %d" % item for item in q["kinds"].items())), flush=True)
            if args.levels:
                blocks = retile.GetNestedLevels()
                for k in range(blocks.GetNumberOfBlocks() - 1):
                    level = blocks.GetBlock(k)
                    q = quality(source, level)
                    print("  level %d: %6d pts %6d tris flipped %3d folded %3d needles %3d min angle %6.2f "
                          "min edge %.1e | Hausdorff %.3e" % (
                              k, level.GetNumberOfPoints(), level.GetNumberOfPolys(), q["flipped"], q["folded"],
                              q["needles"], q["min_angle"], q["min_edge"], hausdorff(slod, source, level)),
                          flush=True)


if __name__ == "__main__":
    main()
