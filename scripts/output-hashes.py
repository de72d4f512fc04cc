# SPDX-License-Identifier: BSD-3-Clause
"""Print a SHA-256 of every SurfaceLOD filter's output on a fixed set of meshes.

Used to prove that a refactoring changes no output: run it on the commit before and the commit
after and compare the two listings (`diff`). It hashes every output port's points, cells, point,
cell and field data, so any change of coordinates, connectivity, order or attributes shows.

  /usr/bin/python3 scripts/output-hashes.py --build build [--meshes DIR] > hashes.txt

DIR is the folder of the CGAL sample meshes (default BUILD/TestData/meshes, extracted by the
build). Run with Debian's /usr/bin/python3 (it has VTK).
"""
import argparse
import glob
import hashlib
import os
import sys

MESHES = ("fandisk.off", "cow.off", "elephant.off", "mushroom.off", "cube-ouvert.off")


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", required=True, help="the project's build folder")
    parser.add_argument("--meshes", help="folder of the CGAL sample meshes")
    return parser.parse_args()


def import_surfacelod(build):
    sites = glob.glob(os.path.join(build, "lib*", "python3*", "*-packages"))
    if not sites:
        sys.exit("no Python package under %s/lib*/python3*/*-packages: build with Python wrapping" % build)
    sys.path.insert(0, sites[0])
    import surfacelod  # noqa: E402 (the path is known only now)
    return surfacelod


def hash_array(digest, array):
    if array is None:
        return
    digest.update((array.GetName() or "").encode())
    digest.update(str((array.GetDataTypeAsString(), array.GetNumberOfTuples(),
                       array.GetNumberOfComponents())).encode())
    if array.IsA("vtkDataArray"):
        digest.update(bytes(memoryview(array)) if array.GetNumberOfTuples() else b"")
    else:
        for index in range(array.GetNumberOfValues()):
            digest.update(str(array.GetVariantValue(index).ToString()).encode())


def hash_attributes(digest, data):
    for index in range(data.GetNumberOfArrays()):
        hash_array(digest, data.GetAbstractArray(index))


def hash_output(data, digest=None):
    digest = digest or hashlib.sha256()
    digest.update(data.GetClassName().encode())
    if data.IsA("vtkPolyData"):
        if data.GetPoints() is not None:
            hash_array(digest, data.GetPoints().GetData())
        for cells in (data.GetVerts(), data.GetLines(), data.GetPolys(), data.GetStrips()):
            hash_array(digest, cells.GetOffsetsArray())
            hash_array(digest, cells.GetConnectivityArray())
        hash_attributes(digest, data.GetPointData())
        hash_attributes(digest, data.GetCellData())
    elif data.IsA("vtkTable"):
        hash_attributes(digest, data.GetRowData())
    elif data.IsA("vtkMultiBlockDataSet"):
        for block in blocks(data):
            hash_output(block, digest)
    hash_attributes(digest, data.GetFieldData())
    return digest.hexdigest()[:20]


def blocks(data):
    return [data.GetBlock(i) for i in range(data.GetNumberOfBlocks()) if data.GetBlock(i) is not None]


def triangle_count(data):
    if data.IsA("vtkPolyData"):
        return data.GetNumberOfPolys()
    if data.IsA("vtkMultiBlockDataSet"):
        return sum(triangle_count(block) for block in blocks(data))
    return data.GetNumberOfRows()


def report(name, mesh, algorithm):
    algorithm.Update()
    for port in range(algorithm.GetNumberOfOutputPorts()):
        output = algorithm.GetOutputDataObject(port)
        print("%-44s %-18s port %d  %s  %d" % (name, mesh, port, hash_output(output), triangle_count(output)))
    sys.stdout.flush()


def simplifiers(slod):
    """(name, factory) of every filter that simplifies one surface, in a fixed configuration."""
    def qtc(**settings):
        def make():
            f = slod.vtkQuadricTriangleCollapse()
            f.SetTargetReduction(0.9)
            for key, value in settings.items():
                getattr(f, "Set" + key)(value)
            return f
        return make

    def with_reduction(cls, reduction=0.9, **settings):
        def make():
            f = cls()
            f.SetTargetReduction(reduction)
            for key, value in settings.items():
                getattr(f, "Set" + key)(value)
            return f
        return make

    return [
        ("QuadricTriangleCollapse", qtc()),
        ("QuadricTriangleCollapse.ProgressiveMesh", qtc(GenerateProgressiveMesh=1)),
        ("QuadricTriangleCollapse.TopologyChange", qtc(AllowTopologyChange=1)),
        ("QuadricTriangleCollapse.MaximumError", qtc(MaximumError=0.01, TargetReduction=0.99)),
        ("TriangleCollapseHierarchy", with_reduction(slod.vtkTriangleCollapseHierarchy)),
        ("TriangleCollapseHierarchy.AllLevels",
         with_reduction(slod.vtkTriangleCollapseHierarchy, GenerateAllLevels=1, ContinuousLevel=1.5)),
        ("PatchBoundaryMerge", with_reduction(slod.vtkPatchBoundaryMerge)),
        ("PatchBoundaryMerge.Epsilon", with_reduction(slod.vtkPatchBoundaryMerge, 0.0, MaximumError=0.01, MaximumErrorIsRelative=1)),
        ("GreedyCutsSimplification", with_reduction(slod.vtkGreedyCutsSimplification, 0.8)),
        ("HoleBumpRemoval", with_reduction(slod.vtkHoleBumpRemoval, 0.0)),
        ("Retile", with_reduction(slod.vtkRetile, 0.8)),
        ("Retile.NestedLevels", with_reduction(slod.vtkRetile, 0.8, GenerateNestedLevels=1)),
    ]


def run_pairs(slod, mesh, source):
    """The filters of two inputs: interpolation between levels and progressive-mesh replay."""
    collapse = slod.vtkQuadricTriangleCollapse()
    collapse.SetInputConnection(source.GetOutputPort())
    collapse.SetTargetReduction(0.9)
    collapse.SetGenerateProgressiveMesh(1)
    replay = slod.vtkProgressiveMeshReconstruction()
    replay.SetCoarseMeshConnection(collapse.GetOutputPort(0))
    replay.SetRecordsConnection(collapse.GetOutputPort(1))
    replay.SetNumberOfVertexSplits(200)
    report("ProgressiveMeshReconstruction", mesh, replay)
    blend = slod.vtkLODInterpolation()
    blend.SetDetailedConnection(source.GetOutputPort())
    blend.SetCoarseConnection(collapse.GetOutputPort(0))
    blend.SetT(0.4)
    report("LODInterpolation", mesh, blend)
    deviation = slod.vtkSurfaceDeviation()
    deviation.SetInputConnection(0, source.GetOutputPort())
    deviation.SetInputConnection(1, collapse.GetOutputPort(0))
    deviation.SetNumberOfSamples(5000)
    report("SurfaceDeviation", mesh, deviation)
    retile = slod.vtkRetile()
    retile.SetInputConnection(source.GetOutputPort())
    retile.SetTargetReduction(0.8)
    retile.SetGenerateNestedLevels(1)
    retile.Update()
    levels = retile.GetOutputDataObject(1)  # coarsest first
    if levels.GetNumberOfBlocks() < 2:
        print("%-44s %-18s no nested levels" % ("RetileLevelInterpolation", mesh))
        return
    morph = slod.vtkRetileLevelInterpolation()
    morph.SetHighDetailData(levels.GetBlock(levels.GetNumberOfBlocks() - 1))
    morph.SetLowDetailData(levels.GetBlock(0))
    morph.SetT(0.3)
    report("RetileLevelInterpolation", mesh, morph)


def sources(slod, mesh_dir):
    for name in MESHES:
        path = os.path.join(mesh_dir, name)
        if not os.path.exists(path):
            sys.exit("mesh missing: " + path)
        reader = slod.vtkOFFMeshReader()
        reader.SetFileName(path)
        yield name, reader
    scan = slod.vtkScanSurfaceSource()
    scan.SetResolution(48)
    yield "scan-48", scan
    smooth = slod.vtkSyntheticIsosurfaceSource()
    smooth.SetResolution(40)
    yield "synthetic-40", smooth


def main():
    arguments = parse_arguments()
    slod = import_surfacelod(arguments.build)
    mesh_dir = arguments.meshes or os.path.join(arguments.build, "TestData", "meshes")
    for mesh, source in sources(slod, mesh_dir):
        source.Update()
        report("Source", mesh, source)
        for name, make in simplifiers(slod):
            algorithm = make()
            algorithm.SetInputConnection(source.GetOutputPort())
            report(name, mesh, algorithm)
        run_pairs(slod, mesh, source)


if __name__ == "__main__":
    main()
