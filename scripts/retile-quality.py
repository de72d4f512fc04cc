#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Triangle quality of vtkRetile's outputs against the input, with vtkQuadricDecimation in the same run.

  /usr/bin/python3 scripts/retile-quality.py --build build [--points 500,2000] [--levels] [--set Name=value] INPUT...

INPUT: an .off/.vtp/.ply file, a test mesh name (build/TestData/meshes) or noisy:N / synthetic:N.
Per input and vertex count: vtkRetile (NumberOfPoints) and vtkQuadricDecimation at the retiling's
triangle count, alternating; per output:
  flipped   triangles whose normal points against the input's triangle at the closest point of
            their centroid (dot < 0); an input whose triangles are not consistently oriented is
            first oriented as vtkRetile orients it (flip_reference: each component's majority),
            else a re-tiling of a shuffled input counts as flipped wherever the input's triangle
            happens to be reversed (the count against the input as it is is printed too),
  folded    output edges whose two triangles turn by more than 150 degrees (a fold back),
  needles   triangles with a smallest angle under 1 degree or an edge under 1e-6 of the diagonal,
  min angle the smallest angle of any triangle (degrees),
  Hausdorff relative to the input's diagonal (vtkSurfaceDeviation, 100,000 samples), both ways.
--levels: also every nested level (three levels, ratio 4, the finest at the count).
--set Name=value: a vtkRetile setting (e.g. EnforceFacing=1).
--reduction R: TargetReduction R instead of the vertex counts (the tests' setting is 0.9).
Also printed: vtkQuadricDecimation's flipped, folded, needles and min angle at the same count
(what a decimation leaves there), small5, the share of triangles with a smallest angle under 5 degrees, and each
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


def misoriented_edges(mesh):
    """Manifold edges that both their triangles use in the same direction."""
    import vtk
    seen, count, ids = set(), 0, vtk.vtkIdList()
    polys = mesh.GetPolys()
    polys.InitTraversal()
    while polys.GetNextCell(ids):
        n = ids.GetNumberOfIds()
        for k in range(n):
            edge = (ids.GetId(k), ids.GetId((k + 1) % n))
            count += edge in seen
            seen.add(edge)
    return count


def flip_reference(source):
    """The input the flipped count is measured against. An input whose triangles are not
    consistently oriented (boeing: 978 misoriented edges) has no one side to face: the re-tiling
    orients it (the preparation keeps each component's majority), so its triangles are compared
    with the input's points merged and its orientation made consistent the same way (a walk over
    the manifold edges per component, the majority kept). Other inputs are used as they are."""
    import vtk
    clean = vtk.vtkCleanPolyData()
    clean.SetInputData(source)
    clean.SetTolerance(0.0)
    clean.Update()
    mesh = clean.GetOutput()
    if misoriented_edges(mesh) == 0:
        return source, 0
    tris, ids, polys = [], vtk.vtkIdList(), mesh.GetPolys()
    polys.InitTraversal()
    while polys.GetNextCell(ids):
        tris.append([ids.GetId(k) for k in range(ids.GetNumberOfIds())])
    users = {}
    for t, tri in enumerate(tris):
        for k in range(len(tri)):
            users.setdefault(frozenset((tri[k], tri[(k + 1) % len(tri)])), []).append((t, tri[k]))
    flip = [None] * len(tris)
    reversed_count = 0
    for seed in range(len(tris)):
        if flip[seed] is not None:
            continue
        flip[seed], component, stack = False, [seed], [seed]
        while stack:
            t = stack.pop()
            tri = tris[t]
            for k in range(len(tri)):
                pair = users[frozenset((tri[k], tri[(k + 1) % len(tri)]))]
                if len(pair) != 2:
                    continue
                (u, first_u), (w, first_w) = pair
                other, same = (w, first_w == first_u) if u == t else (u, first_w == first_u)
                if flip[other] is None:
                    flip[other] = flip[t] != same
                    component.append(other)
                    stack.append(other)
        flipped = sum(flip[t] for t in component)
        if 2 * flipped > len(component):
            for t in component:
                flip[t] = not flip[t]
            flipped = len(component) - flipped
        reversed_count += flipped
    cells = vtk.vtkCellArray()
    for t, tri in enumerate(tris):
        cells.InsertNextCell(len(tri), tri[::-1] if flip[t] else tri)
    oriented = vtk.vtkPolyData()
    oriented.SetPoints(mesh.GetPoints())
    oriented.SetPolys(cells)
    return oriented, reversed_count


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
            reference, reversed_count = flip_reference(source)
            q = quality(reference, output, retile.GetNumberOfRetainedVertices())
            if reversed_count:
                print("  input orientation made consistent for the flipped count: %d triangles reversed "
                      "(flipped against the input as it is: %d)" % (
                          reversed_count, quality(source, output)["flipped"]), flush=True)
            h, hq = hausdorff(slod, source, output), hausdorff(slod, source, quadric.GetOutput())
            print("%-14s %6d pts %6d tris (QD %6d) flipped %3d folded %3d needles %3d min angle %6.2f min edge %.1e "
                  "retained %3d | Hausdorff %.3e QD %.3e ratio %5.2f | CPU %.2f s QD %.2f s" % (
                      name, output.GetNumberOfPoints(), output.GetNumberOfPolys(),
                      quadric.GetOutput().GetNumberOfPolys(), q["flipped"], q["folded"], q["needles"],
                      q["min_angle"], q["min_edge"], retile.GetNumberOfRetainedVertices(), h, hq, h / hq,
                      seconds, quadric_seconds), flush=True)
            print("  small5 %.2f%% flipped kinds %s" % (100.0 * q["small5"], " ".join(
                "%s %d" % item for item in q["kinds"].items())), flush=True)
            # The same measures on vtkQuadricDecimation's output: what a decimation at the count leaves.
            qq = quality(reference, quadric.GetOutput())
            print("  QD flipped %d folded %d needles %d min angle %.2f" % (
                qq["flipped"], qq["folded"], qq["needles"], qq["min_angle"]), flush=True)
            if args.levels:
                blocks = retile.GetNestedLevels()
                for k in range(blocks.GetNumberOfBlocks() - 1):
                    level = blocks.GetBlock(k)
                    q = quality(reference, level)
                    print("  level %d: %6d pts %6d tris flipped %3d folded %3d needles %3d min angle %6.2f "
                          "min edge %.1e | Hausdorff %.3e" % (
                              k, level.GetNumberOfPoints(), level.GetNumberOfPolys(), q["flipped"], q["folded"],
                              q["needles"], q["min_angle"], q["min_edge"], hausdorff(slod, source, level)),
                          flush=True)


if __name__ == "__main__":
    main()
