# SPDX-License-Identifier: BSD-3-Clause
"""The wrapped SurfaceLOD filters in a real VTK Python pipeline (run with Debian's /usr/bin/python3)."""
import math
import os
import sys
import unittest

from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkFiltersCore import vtkQuadricDecimation

import surfacelod

MESH_DIR = os.environ.get("SURFACELOD_MESH_DIR", "")


class PythonPipelineTest(unittest.TestCase):
    def test_package_exports_filters(self):
        for name in ("vtkSurfaceDeviation", "vtkOFFMeshReader"):
            self.assertTrue(hasattr(surfacelod, name), name)

    def test_one_contract_from_the_base_classes(self):
        # Every simplifier takes its targets from vtkSimplificationAlgorithm; the error-bounded ones
        # MaximumError from vtkErrorBoundedSimplificationAlgorithm, with each filter's own default.
        bounded = ("vtkQuadricTriangleCollapse", "vtkPatchBoundaryMerge", "vtkGreedyCutsSimplification")
        others = ("vtkTriangleCollapseHierarchy", "vtkRetile", "vtkHoleBumpRemoval")
        sphere = vtkSphereSource()
        sphere.SetThetaResolution(40)
        sphere.SetPhiResolution(40)
        sphere.Update()
        triangles = sphere.GetOutput().GetNumberOfPolys()
        for name in bounded + others:
            f = getattr(surfacelod, name)()
            self.assertTrue(f.IsA("vtkSimplificationAlgorithm"), name)
            self.assertEqual(f.IsA("vtkErrorBoundedSimplificationAlgorithm") == 1, name in bounded, name)
            f.SetTargetNumberOfTriangles(300)
            self.assertEqual(f.ComputeTargetNumberOfTriangles(triangles), 300, name)
        self.assertEqual(surfacelod.vtkGreedyCutsSimplification().GetMaximumError(), 0.005)
        self.assertEqual(surfacelod.vtkQuadricTriangleCollapse().GetMaximumError(), 0.0)

    def test_deviation_in_pipeline(self):
        sphere = vtkSphereSource()
        sphere.SetThetaResolution(48)
        sphere.SetPhiResolution(48)
        decimate = vtkQuadricDecimation()
        decimate.SetInputConnection(sphere.GetOutputPort())
        decimate.SetTargetReduction(0.9)
        deviation = surfacelod.vtkSurfaceDeviation()
        deviation.SetInputConnection(0, sphere.GetOutputPort())
        deviation.SetInputConnection(1, decimate.GetOutputPort())
        deviation.SetNumberOfSamples(20000)
        deviation.Update()
        hausdorff = deviation.GetHausdorffRelative()
        self.assertGreater(hausdorff, 1e-4)
        self.assertLess(hausdorff, 0.05)
        out = deviation.GetOutput()
        self.assertEqual(out.GetNumberOfPolys(), decimate.GetOutput().GetNumberOfPolys())
        self.assertIsNotNone(out.GetPointData().GetArray("Distance"))
        # Identical surfaces are at distance zero.
        same = surfacelod.vtkSurfaceDeviation()
        same.SetInputConnection(0, sphere.GetOutputPort())
        same.SetInputConnection(1, sphere.GetOutputPort())
        same.SetNumberOfSamples(5000)
        same.Update()
        self.assertLess(same.GetHausdorffRelative(), 1e-9)

    def test_attribute_error_metric_from_python(self):
        """The metric's properties are wrapped with VTK's names, and a textured sphere keeps unit
        normals and finite texture coordinates through it."""
        from vtkmodules.vtkFiltersSources import vtkTexturedSphereSource
        from vtkmodules.vtkFiltersCore import vtkPolyDataNormals
        sphere = vtkTexturedSphereSource()
        sphere.SetThetaResolution(40)
        sphere.SetPhiResolution(20)
        normals = vtkPolyDataNormals()
        normals.SetInputConnection(sphere.GetOutputPort())
        normals.SplittingOff()
        collapse = surfacelod.vtkQuadricTriangleCollapse()
        collapse.SetInputConnection(normals.GetOutputPort())
        self.assertFalse(collapse.GetAttributeErrorMetric())
        collapse.AttributeErrorMetricOn()
        for name in ("Scalars", "Vectors", "Normals", "TCoords", "Tensors"):
            self.assertEqual(getattr(collapse, "Get%sWeight" % name)(), 0.1, name)
            getattr(collapse, "Set%sWeight" % name)(0.3)
            self.assertEqual(getattr(collapse, "Get%sWeight" % name)(), 0.3, name)
        collapse.SetTargetReduction(0.8)
        collapse.Update()
        out = collapse.GetOutput()
        self.assertGreater(out.GetNumberOfPolys(), 0)
        n, uv = out.GetPointData().GetNormals(), out.GetPointData().GetTCoords()
        for i in range(out.GetNumberOfPoints()):
            self.assertAlmostEqual(sum(c * c for c in n.GetTuple3(i)), 1.0, places=5)
            self.assertTrue(all(math.isfinite(c) for c in uv.GetTuple2(i)), uv.GetTuple2(i))

    def test_off_reader_reads_fandisk(self):
        path = os.path.join(MESH_DIR, "fandisk.off")
        self.assertTrue(os.path.exists(path), "test mesh missing: " + path)
        reader = surfacelod.vtkOFFMeshReader()
        reader.SetFileName(path)
        reader.Update()
        self.assertEqual(reader.GetOutput().GetNumberOfPolys(), 12946)
        self.assertEqual(reader.GetOutput().GetNumberOfPoints(), 6475)


if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    sys.exit(0 if result.wasSuccessful() and result.testsRun > 0 else 1)
