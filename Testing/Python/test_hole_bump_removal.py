# SPDX-License-Identifier: BSD-3-Clause
"""vtkHoleBumpRemoval from Python (run with Debian's /usr/bin/python3): the wrapped class in a
pipeline with vtkBlockModelSource, counts in the getters and the field data, the sharp-loop
output, and a CGAL demo CAD model whose genus drops by the holes removed."""
import os
import unittest

import surfacelod

MESH_DIR = os.environ.get("SURFACELOD_MESH_DIR", "")


def field(polydata, name):
    return int(polydata.GetFieldData().GetArray(name).GetTuple1(0))


class HoleBumpRemovalTest(unittest.TestCase):
    def test_plate_with_holes_becomes_a_box(self):
        source = surfacelod.vtkBlockModelSource()
        source.SetModelToPlateWithHoles()
        source.SetFeaturesX(4)
        source.SetFeaturesY(3)
        removal = surfacelod.vtkHoleBumpRemoval()
        removal.SetInputConnection(source.GetOutputPort())
        removal.SetFeatureSize(0.2)
        removal.Update()
        out = removal.GetOutput()
        self.assertEqual(removal.GetInputGenus(), 12)
        self.assertEqual(removal.GetNumberOfHolesRemoved(), 12)
        self.assertEqual(removal.GetOutputGenus(), 0)
        self.assertEqual(out.GetNumberOfPolys(), 12)
        self.assertEqual(field(out, "HolesRemoved"), 12)
        self.assertIsNotNone(out.GetCellData().GetArray("PatchId"))
        loops = removal.GetOutput(1)
        self.assertEqual(loops.GetNumberOfLines(), 24)

    def test_former_feature_size_names_set_the_same_property(self):
        removal = surfacelod.vtkHoleBumpRemoval()
        removal.SetMaximumFeatureSize(0.125)
        removal.SetMaximumFeatureSizeIsRelative(False)
        self.assertEqual(removal.GetFeatureSize(), 0.125)
        self.assertFalse(removal.GetFeatureSizeIsRelative())
        self.assertEqual(removal.GetMaximumFeatureSize(), 0.125)

    def test_mixed_features_and_completions(self):
        source = surfacelod.vtkBlockModelSource()
        source.SetModelToMixed()
        removal = surfacelod.vtkHoleBumpRemoval()
        removal.SetInputConnection(source.GetOutputPort())
        removal.SetFeatureSize(0.2)
        removal.SetCompletionToKeepTriangles()
        removal.Update()
        self.assertEqual(removal.GetNumberOfHolesRemoved(), 1)
        self.assertEqual(removal.GetNumberOfBumpsRemoved(), 6)
        self.assertEqual(removal.GetNumberOfCavitiesRemoved(), 2)
        kept = removal.GetOutput().GetNumberOfPolys()
        removal.SetContinueWithSimplification(False)
        removal.Update()
        self.assertEqual(removal.GetOutput().GetNumberOfPolys(), 12)
        self.assertGreater(kept, 12)

    @unittest.skipUnless(os.path.exists(os.path.join(MESH_DIR, "anchor.off")), "CGAL demo meshes missing")
    def test_anchor(self):
        reader = surfacelod.vtkOFFMeshReader()
        reader.SetFileName(os.path.join(MESH_DIR, "anchor.off"))
        removal = surfacelod.vtkHoleBumpRemoval()
        removal.SetInputConnection(reader.GetOutputPort())
        removal.SetFeatureSize(0.2)
        removal.Update()
        self.assertEqual(removal.GetInputGenus(), 4)
        self.assertEqual(removal.GetNumberOfHolesRemoved(), 4)
        self.assertEqual(removal.GetOutputGenus(), 0)


if __name__ == "__main__":
    unittest.main()
