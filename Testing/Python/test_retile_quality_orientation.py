# SPDX-License-Identifier: BSD-3-Clause
"""scripts/retile-quality.py's flipped count (run with Debian's /usr/bin/python3): it must not depend
on how the input's triangles are oriented. vtkRetile makes the input's orientation consistent (each
component's majority), so a triangle is flipped only against the input oriented the same way; an
input with a share of its triangles reversed must give the count of the consistent input."""
import importlib.util
import os
import unittest

import vtk

import surfacelod  # noqa: F401 (the script's vtkRetile)

MESH_DIR = os.environ.get("SURFACELOD_MESH_DIR", "")
SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "retile-quality.py")


def quality_script():
    spec = importlib.util.spec_from_file_location("retile_quality", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def triangles(mesh):
    result, ids, polys = [], vtk.vtkIdList(), mesh.GetPolys()
    polys.InitTraversal()
    while polys.GetNextCell(ids):
        result.append([ids.GetId(k) for k in range(ids.GetNumberOfIds())])
    return result


def with_reversed(mesh, every):
    """A copy of `mesh` with every `every`-th triangle's corners in the other order."""
    cells = vtk.vtkCellArray()
    for t, tri in enumerate(triangles(mesh)):
        cells.InsertNextCell(len(tri), tri[::-1] if t % every == 0 else tri)
    copy = vtk.vtkPolyData()
    copy.SetPoints(mesh.GetPoints())
    copy.SetPolys(cells)
    return copy


def same_orientation(a, b):
    # Same corners in the same cyclic order.
    return any(a == b[k:] + b[:k] for k in range(len(b)))


class RetileQualityOrientationTest(unittest.TestCase):
    def test_flipped_count_ignores_the_inputs_reversed_triangles(self):
        path = os.path.join(MESH_DIR, "bones.off")
        self.assertTrue(os.path.exists(path), "missing test mesh %s" % path)
        rq = quality_script()
        reader = surfacelod.vtkOFFMeshReader()
        reader.SetFileName(path)
        clean = vtk.vtkCleanPolyData()
        clean.SetInputConnection(reader.GetOutputPort())
        clean.SetTolerance(0.0)
        clean.Update()
        source = clean.GetOutput()
        self.assertEqual(rq.misoriented_edges(source), 0)
        reference, reversed_count = rq.flip_reference(source)
        self.assertIs(reference, source)
        self.assertEqual(reversed_count, 0)

        scrambled = with_reversed(source, 3)
        self.assertGreater(rq.misoriented_edges(scrambled), 0)
        oriented, reversed_count = rq.flip_reference(scrambled)
        self.assertEqual(rq.misoriented_edges(oriented), 0)
        # The minority (every third triangle) is the one turned back: the input's own orientation.
        self.assertEqual(reversed_count, (source.GetNumberOfPolys() + 2) // 3)
        # (The reference has its points merged, so it is compared by the corners' positions.)
        for a, b in zip(triangles(oriented), triangles(source)):
            self.assertTrue(same_orientation([oriented.GetPoint(v) for v in a], [source.GetPoint(v) for v in b]))

        retile = surfacelod.vtkRetile()
        retile.SetInputData(scrambled)
        retile.SetTargetReduction(0.8)
        retile.Update()
        output = retile.GetOutput()
        flipped = rq.quality(source, output)["flipped"]
        self.assertEqual(rq.quality(oriented, output)["flipped"], flipped)
        # Against the scrambled input as it is, a third of the tiles would count as flipped.
        self.assertGreater(rq.quality(scrambled, output)["flipped"], flipped + output.GetNumberOfPolys() // 5)


if __name__ == "__main__":
    unittest.main()
