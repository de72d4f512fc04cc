# SPDX-License-Identifier: BSD-3-Clause
"""vtkTopologicalNoiseRemoval from Python (run with Debian's /usr/bin/python3): the wrapped class
on CGAL's cheese (genus 133), its getters against the field data and the cut-loop output."""
import os
import unittest

import surfacelod

MESH_DIR = os.environ.get("SURFACELOD_MESH_DIR", "")


def field(polydata, name):
    return polydata.GetFieldData().GetArray(name).GetTuple1(0)


class TopologicalNoiseRemovalTest(unittest.TestCase):
    def test_cheese_loses_its_thin_handles(self):
        path = os.path.join(MESH_DIR, "cheese.off")
        self.assertTrue(os.path.exists(path), "missing test mesh %s" % path)
        reader = surfacelod.vtkOFFMeshReader()
        reader.SetFileName(path)
        removal = surfacelod.vtkTopologicalNoiseRemoval()
        removal.SetInputConnection(reader.GetOutputPort())
        removal.SetFeatureSize(0.06)  # relative to the diagonal (the default)
        removal.Update()
        out = removal.GetOutput()
        removed = removal.GetNumberOfHandlesRemoved()
        self.assertEqual(removal.GetInputGenus(), 133)
        self.assertGreater(removed, 0)
        self.assertEqual(removal.GetOutputGenus(), 133 - removed)
        self.assertEqual(removal.GetOutputEulerCharacteristic(), removal.GetInputEulerCharacteristic() + 2 * removed)
        self.assertEqual(field(out, "HandlesRemoved"), removed)
        self.assertEqual(field(out, "HandlesKept"), removal.GetOutputGenus())
        self.assertAlmostEqual(field(out, "FeatureSize"), removal.GetUsedFeatureSize())
        loops = removal.GetOutput(1)
        removed_flags = loops.GetCellData().GetArray("Removed")
        lengths = loops.GetCellData().GetArray("Length")
        alpha = removal.GetUsedFeatureSize()
        cut = [i for i in range(loops.GetNumberOfLines()) if removed_flags.GetTuple1(i) == 1]
        self.assertEqual(len(cut), removed)
        for i in cut:
            self.assertLessEqual(lengths.GetTuple1(i), 3.14159266 * alpha)
        # The handles kept are surveyed in rounds of doubling size and reported with their sizes.
        sizes = out.GetFieldData().GetArray("KeptHandleSizes")
        kept = removal.GetNumberOfHandlesKeptAboveFeatureSize()
        self.assertGreater(kept, 0)
        self.assertLessEqual(kept, removal.GetOutputGenus())
        self.assertEqual(sizes.GetNumberOfTuples(), kept)
        self.assertEqual(loops.GetNumberOfLines() - len(cut), kept + removal.GetNumberOfLoopsKept())
        for i in range(kept):
            self.assertGreater(sizes.GetTuple1(i), alpha)
            self.assertLessEqual(sizes.GetTuple1(i), field(out, "KeptHandleSurveySize") * (1 + 1e-9))
        self.assertEqual(kept + field(out, "HandlesNotSized"), removal.GetOutputGenus())

if __name__ == "__main__":
    unittest.main()
