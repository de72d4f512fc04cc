#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Texture-coordinate and normal error of simplified meshes at equal triangle count (issue 13).

At every output vertex, edge midpoint and triangle centroid, the input attributes are interpolated
(barycentric weights of the cell) at the closest point of the input surface and compared with the
output's own there: the distance in the (u, v) plane for texture coordinates, the angle in degrees
for normals. At an attribute seam
(the textured sphere's u = 0 / u = 1 meridian) several input cells are closest; the smallest
difference among them counts, so a seam vertex is not charged for the side it does not belong to.
The reference is vtkQuadricDecimation with AttributeErrorMetricOn (TCoords and Normals weighted)
and Off (TargetReduction); each project method is asked for the same count (TargetNumberOfTriangles).

The geometric cost is measured too: the two-sided Hausdorff and mean distance to the input
(vtkSurfaceDeviation, relative to the diagonal). Times: with --repeat N the methods run N times in
turns (alternating, on a loaded machine) and the median wall and CPU seconds are given.

usage: /usr/bin/python3 scripts/attribute-error.py --build build [--reduction 0.9]
       [--sphere-resolution 400] [--mesh build/TestData/meshes/armadillo.off ...]
       [--mesh /work/data/mri-normals.vtp] [--methods "a;b;..."] [--repeat 3] [--max-samples 200000]
"""
import argparse
import math
import os
import sys
import time


def load_modules(build):
    sys.path.insert(0, os.path.join(build, "lib", "python3", "dist-packages"))
    import vtk  # noqa: F401  (Debian's VTK Python)
    import surfacelod  # noqa: F401
    return vtk, surfacelod


def textured_sphere(vtk, resolution):
    """vtkTexturedSphereSource without its zero-area triangles at the poles (two corners at the
    pole): vtkQuadricDecimation leaves the source's output untouched while they are there (3600 ->
    3600 triangles at reduction 0.9). The points, their texture coordinates and the seam stay."""
    sphere = vtk.vtkTexturedSphereSource()
    sphere.SetThetaResolution(resolution)
    sphere.SetPhiResolution(resolution // 2)
    triangles = vtk.vtkTriangleFilter()
    triangles.SetInputConnection(sphere.GetOutputPort())
    triangles.Update()
    source = triangles.GetOutput()
    kept = vtk.vtkCellArray()
    for c in range(source.GetNumberOfCells()):
        ids = [source.GetCell(c).GetPointId(k) for k in range(3)]
        corners = [source.GetPoint(i) for i in ids]
        if corners[0] != corners[1] and corners[1] != corners[2] and corners[0] != corners[2]:
            kept.InsertNextCell(3, ids)
    mesh = vtk.vtkPolyData()
    mesh.SetPoints(source.GetPoints())
    mesh.SetPolys(kept)
    mesh.GetPointData().ShallowCopy(source.GetPointData())
    producer = vtk.vtkTrivialProducer()
    producer.SetOutput(mesh)
    return with_normals(vtk, producer.GetOutputPort())


def updated_copy(vtk, algorithm):
    algorithm.Update()
    mesh = vtk.vtkPolyData()
    mesh.DeepCopy(algorithm.GetOutput())
    return mesh


def with_normals(vtk, port):
    triangles = vtk.vtkTriangleFilter()
    triangles.SetInputConnection(port)
    normals = vtk.vtkPolyDataNormals()
    normals.SetInputConnection(triangles.GetOutputPort())
    normals.SplittingOff()
    normals.ConsistencyOn()
    normals.ComputeCellNormalsOff()
    return updated_copy(vtk, normals)


def real_mesh(vtk, surfacelod, path):
    """A real mesh with normals (its own point normals if a .vtp has them, else computed) and a
    spherical-projection (u, v) parameterisation: u wraps around the centre without a seam
    (vtkTextureMapToSphere's PreventSeam mirrors it)."""
    if path.endswith(".vtp"):
        reader = vtk.vtkXMLPolyDataReader()
        reader.SetFileName(path)
        reader.Update()
        mesh = updated_copy(vtk, reader) if reader.GetOutput().GetPointData().GetNormals() else None
        mesh = mesh or with_normals(vtk, reader.GetOutputPort())
    else:
        reader = surfacelod.vtkOFFMeshReader()
        reader.SetFileName(path)
        mesh = with_normals(vtk, reader.GetOutputPort())
    mapper = vtk.vtkTextureMapToSphere()
    mapper.SetInputData(mesh)
    mapper.AutomaticSphereGenerationOn()
    mapper.PreventSeamOn()
    return updated_copy(vtk, mapper)


def quadric_decimation(vtk, mesh, reduction, attribute_metric):
    decimate = vtk.vtkQuadricDecimation()
    decimate.SetInputData(mesh)
    decimate.SetTargetReduction(reduction)
    decimate.SetAttributeErrorMetric(attribute_metric)
    if attribute_metric:
        decimate.TCoordsAttributeOn()
        decimate.NormalsAttributeOn()
        decimate.ScalarsAttributeOff()
        decimate.VectorsAttributeOff()
        decimate.TensorsAttributeOff()
    decimate.VolumePreservationOn()
    return decimate


def project_filter(surfacelod, name, mesh, triangles):
    if name == "quadric-triangle-collapse, AttributeErrorMetricOn":
        f = project_filter(surfacelod, "quadric-triangle-collapse", mesh, triangles)
        f.AttributeErrorMetricOn()  # the default weights (0.1) of the normals and texture coordinates
        return f
    if name == "quadric-triangle-collapse, PreserveAttributeSeams off":
        f = project_filter(surfacelod, "quadric-triangle-collapse", mesh, triangles)
        f.PreserveAttributeSeamsOff()
        return f
    make = {"quadric-triangle-collapse": surfacelod.vtkQuadricTriangleCollapse,
            "triangle-collapse-hierarchy": surfacelod.vtkTriangleCollapseHierarchy,
            "retile": surfacelod.vtkRetile}[name]
    f = make()
    f.SetInputData(mesh)
    f.SetTargetNumberOfTriangles(triangles)
    return f


def run(algorithm):
    start, cpu = time.perf_counter(), time.process_time()
    algorithm.Update()
    return algorithm.GetOutput(), time.perf_counter() - start, time.process_time() - cpu


class InputAttributes:
    """The input surface, its cell locator and its point attributes interpolated at any point."""

    def __init__(self, vtk, mesh):
        self.vtk = vtk
        self.mesh = mesh
        self.locator = vtk.vtkCellLocator()
        self.locator.SetDataSet(mesh)
        self.locator.BuildLocator()
        self.tcoords = mesh.GetPointData().GetTCoords()
        self.normals = mesh.GetPointData().GetNormals()
        diagonal = math.sqrt(mesh.GetLength() ** 2)
        self.tolerance = 1e-9 * diagonal

    def candidate_cells(self, point):
        """The cells at (nearly) the smallest distance from point: more than one at a seam."""
        vtk = self.vtk
        closest = [0.0, 0.0, 0.0]
        cell_id, sub_id, dist2 = vtk.reference(0), vtk.reference(0), vtk.reference(0.0)
        self.locator.FindClosestPoint(point, closest, cell_id, sub_id, dist2)
        radius = math.sqrt(float(dist2)) + self.tolerance
        ids = vtk.vtkIdList()
        bounds = [point[0] - radius, point[0] + radius, point[1] - radius, point[1] + radius,
                  point[2] - radius, point[2] + radius]
        self.locator.FindCellsWithinBounds(bounds, ids)
        return [ids.GetId(k) for k in range(ids.GetNumberOfIds())], float(dist2)

    def interpolated(self, cell_id, point, best_dist2):
        """(tcoords, normal) of the input at its closest point in cell_id, or None when the cell
        is not among the closest."""
        cell = self.mesh.GetCell(cell_id)
        closest = [0.0, 0.0, 0.0]
        sub_id, pcoords, dist2 = self.vtk.reference(0), [0.0, 0.0, 0.0], self.vtk.reference(0.0)
        weights = [0.0] * cell.GetNumberOfPoints()
        cell.EvaluatePosition(point, closest, sub_id, pcoords, dist2, weights)
        if math.sqrt(float(dist2)) > math.sqrt(best_dist2) + self.tolerance:
            return None
        ids = [cell.GetPointId(k) for k in range(cell.GetNumberOfPoints())]
        uv = [sum(w * self.tcoords.GetComponent(i, c) for w, i in zip(weights, ids)) for c in range(2)]
        n = [sum(w * self.normals.GetComponent(i, c) for w, i in zip(weights, ids)) for c in range(3)]
        return uv, n


def angle_degrees(a, b):
    la = math.sqrt(sum(x * x for x in a))
    lb = math.sqrt(sum(x * x for x in b))
    if la == 0 or lb == 0:
        return 180.0
    cosine = max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b)) / (la * lb)))
    return math.degrees(math.acos(cosine))


def output_samples(output, stride=1):
    """Points of the output surface with the output's own attributes there: every vertex used by a
    triangle, every edge midpoint and every triangle centroid (attributes interpolated linearly, as
    a renderer does), so the error between the vertices counts too."""
    tcoords = output.GetPointData().GetTCoords()
    normals = output.GetPointData().GetNormals()

    def sample(ids):
        w = 1.0 / len(ids)
        point = [w * sum(output.GetPoint(i)[c] for i in ids) for c in range(3)]
        uv = [w * sum(tcoords.GetComponent(i, c) for i in ids) for c in range(2)] if tcoords else None
        n = [w * sum(normals.GetComponent(i, c) for i in ids) for c in range(3)] if normals else None
        return point, uv, n

    seen = set()
    for c in range(0, output.GetNumberOfCells(), stride):
        cell = output.GetCell(c)
        ids = [cell.GetPointId(k) for k in range(cell.GetNumberOfPoints())]
        pieces = [(i,) for i in ids] + [tuple(sorted((ids[k], ids[(k + 1) % len(ids)]))) for k in range(len(ids))]
        for piece in pieces:
            if piece not in seen:
                seen.add(piece)
                yield sample(piece)
        yield sample(ids)


def attribute_errors(reference, output, max_samples=None):
    """(mean, max) texture-coordinate distance and (mean, max) normal angle over the output samples;
    None for an attribute the output does not carry."""
    tcoords = output.GetPointData().GetTCoords()
    normals = output.GetPointData().GetNormals()
    if tcoords is None and normals is None:
        return None, None
    uv_errors, normal_errors = [], []
    # About 3.5 samples per triangle: every stride-th triangle when that would exceed max_samples.
    stride = max(1, int(math.ceil(3.5 * output.GetNumberOfCells() / max_samples))) if max_samples else 1
    for point, uv, normal in output_samples(output, stride):
        cells, best = reference.candidate_cells(point)
        uv_best, normal_best = math.inf, math.inf
        for cell_id in cells:
            values = reference.interpolated(cell_id, point, best)
            if values is None:
                continue
            if uv is not None:
                uv_best = min(uv_best, math.hypot(uv[0] - values[0][0], uv[1] - values[0][1]))
            if normal is not None:
                normal_best = min(normal_best, angle_degrees(normal, values[1]))
        uv_errors.append(uv_best)
        normal_errors.append(normal_best)
    summary = lambda e: (sum(e) / len(e), max(e))  # noqa: E731
    return (summary(uv_errors) if tcoords is not None else None,
            summary(normal_errors) if normals is not None else None)


METHODS = ("vtkQuadricDecimation, AttributeErrorMetricOn", "vtkQuadricDecimation, AttributeErrorMetricOff",
           "quadric-triangle-collapse", "quadric-triangle-collapse, AttributeErrorMetricOn",
           "quadric-triangle-collapse, PreserveAttributeSeams off", "triangle-collapse-hierarchy", "retile")


def make_method(vtk, surfacelod, name, mesh, reduction, target):
    if name.startswith("vtkQuadricDecimation"):
        return quadric_decimation(vtk, mesh, reduction, name.endswith("On"))
    return project_filter(surfacelod, name, mesh, target)


def geometric_distance(surfacelod, mesh, output):
    """(Hausdorff, mean) two-sided distance relative to the input's diagonal."""
    deviation = surfacelod.vtkSurfaceDeviation()
    deviation.SetReferenceData(mesh)
    deviation.SetComparedData(output)
    deviation.SetNumberOfSamples(100000)
    deviation.Update()
    return deviation.GetHausdorffRelative(), deviation.GetMeanRelative()


def measure(vtk, surfacelod, label, mesh, options):
    reference = InputAttributes(vtk, mesh)
    target = int(round(mesh.GetNumberOfPolys() * (1.0 - options.reduction)))
    outputs, walls, cpus = {}, {name: [] for name in options.methods}, {name: [] for name in options.methods}
    for _ in range(options.repeat):  # in turns: each round runs every method once
        for name in options.methods:
            output, wall, cpu = run(make_method(vtk, surfacelod, name, mesh, options.reduction, target))
            outputs[name] = vtk.vtkPolyData()
            outputs[name].DeepCopy(output)
            walls[name].append(wall)
            cpus[name].append(cpu)
    print("\n%s: %d triangles, target %d (reduction %.2f), %d round(s), load %s" % (
        label, mesh.GetNumberOfPolys(), target, options.reduction, options.repeat, os.getloadavg()))
    print("| method | triangles | tcoord error mean | tcoord error max | normal error mean (deg) "
          "| normal error max (deg) | Hausdorff | mean distance | seconds (wall, median) | CPU seconds |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    median = lambda v: sorted(v)[len(v) // 2]  # noqa: E731
    for name in options.methods:
        output = outputs[name]
        uv, normal = attribute_errors(reference, output, options.max_samples)
        hausdorff, mean = geometric_distance(surfacelod, mesh, output)
        cell = lambda e, k, f: ("%" + f) % e[k] if e else "not carried"  # noqa: E731
        print("| %s | %d | %s | %s | %s | %s | %.3e | %.3e | %.2f | %.2f |" % (
            name, output.GetNumberOfPolys(), cell(uv, 0, ".5f"), cell(uv, 1, ".4f"), cell(normal, 0, ".3f"),
            cell(normal, 1, ".2f"), hausdorff, mean, median(walls[name]), median(cpus[name])))
        sys.stdout.flush()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--reduction", type=float, default=0.9)
    parser.add_argument("--sphere-resolution", type=int, default=400)
    parser.add_argument("--mesh", action="append", default=[],
                        help="a real OFF mesh (normals and a spherical (u, v) are computed); repeatable")
    parser.add_argument("--methods", default=";".join(METHODS), help="separated by semicolons, of: " + "; ".join(METHODS))
    parser.add_argument("--repeat", type=int, default=1, help="rounds of every method, in turns (times: median)")
    parser.add_argument("--max-samples", type=int, default=None,
                        help="at most about this many attribute samples per output (every k-th triangle)")
    parser.add_argument("--no-sphere", action="store_true", help="only the --mesh inputs")
    args = parser.parse_args()
    args.methods = [m.strip() for m in args.methods.split(";") if m.strip()]
    unknown = [m for m in args.methods if m not in METHODS]
    if unknown:
        parser.error("unknown method(s): %s" % ", ".join(unknown))
    vtk, surfacelod = load_modules(args.build)
    vtk.vtkObject.GlobalWarningDisplayOff()  # vtkQuadricDecimation's 'Unable to factor' lines
    if not args.no_sphere:
        measure(vtk, surfacelod, "vtkTexturedSphereSource %d x %d" % (args.sphere_resolution, args.sphere_resolution // 2),
                textured_sphere(vtk, args.sphere_resolution), args)
    for mesh in args.mesh:
        measure(vtk, surfacelod, os.path.basename(mesh), real_mesh(vtk, surfacelod, mesh), args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
