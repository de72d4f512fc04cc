# SPDX-License-Identifier: BSD-3-Clause
"""The ParaView plugin's property defaults are the filters' own: for every single-valued int or
double property of the plugin's XML whose class is in the wrapped module, a new filter's getter
returns the XML's default_values. A default changed in the C++ class but not in the XML (or the
other way round) gives ParaView users another filter than VTK and Python users get."""
import glob
import os
import unittest
import xml.etree.ElementTree as ElementTree

import surfacelod

PLUGIN_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "ParaView", "Plugin")


def xml_properties():
    """(file, proxy class, command, default text, kind) of every single-valued property."""
    for path in sorted(glob.glob(os.path.join(PLUGIN_DIR, "*.xml"))):
        for proxy in ElementTree.parse(path).getroot().iter("SourceProxy"):
            for prop in proxy:
                if prop.tag not in ("IntVectorProperty", "DoubleVectorProperty"):
                    continue
                command = prop.get("command")
                default = prop.get("default_values")
                if not command or default is None or prop.get("number_of_elements") != "1":
                    continue
                if prop.get("information_only") == "1":
                    continue
                yield os.path.basename(path), proxy.get("class"), command, default, prop.tag


class ParaViewDefaultsTest(unittest.TestCase):
    def test_xml_defaults_are_the_filters_defaults(self):
        checked = 0
        classes = set()
        without_getter = []
        paraview_side = set()
        for path, class_name, command, default, kind in xml_properties():
            cls = getattr(surfacelod, class_name, None)
            if cls is None:
                paraview_side.add(class_name)  # a class of the plugin only (vtkPV...): reported
                continue
            getter_name = "Get" + command[3:] if command.startswith("Set") else None
            getter = getattr(cls(), getter_name, None) if getter_name else None
            if getter is None:
                without_getter.append(class_name + "." + command)
                continue
            with self.subTest(file=path, cls=class_name, property=command):
                value = getter()
                if isinstance(value, bool):
                    value = int(value)
                if kind == "IntVectorProperty":
                    self.assertEqual(int(value), int(float(default)))
                else:
                    self.assertAlmostEqual(float(value), float(default), delta=1e-12 * max(1.0, abs(float(default))))
            checked += 1
            classes.add(class_name)
        # The check must have looked at the simplifiers (a broken parse or import checks nothing).
        for name in ("vtkQuadricTriangleCollapse", "vtkPatchBoundaryMerge", "vtkRetile", "vtkGreedyCutsSimplification"):
            self.assertIn(name, classes)
        self.assertGreater(checked, 50)
        print("checked %d defaults of %d classes; %d properties without a getter: %s; not in the "
              "wrapped module (plugin-side classes, not checked): %s"
              % (checked, len(classes), len(without_getter), ", ".join(without_getter),
                 ", ".join(sorted(paraview_side))))


if __name__ == "__main__":
    unittest.main()
