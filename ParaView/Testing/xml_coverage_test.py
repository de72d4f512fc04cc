# SPDX-License-Identifier: BSD-3-Clause
"""Every public class of the module has a ParaView proxy (its own or one of a ParaView/Extensions
subclass), and every proxy property calls a method the class declares (run by the system Python,
no ParaView needed).

  python3 xml_coverage_test.py <source dir>
"""
import pathlib
import re
import sys
import xml.etree.ElementTree as ElementTree


def public_classes(source):
    """The `classes` of Filters/CMakeLists.txt (paths without extension) -> their headers."""
    text = (source / "Filters" / "CMakeLists.txt").read_text()
    headers = {}
    for block in re.findall(r"list\(APPEND classes([^)]*)\)", text):
        for path in block.split():
            headers[pathlib.PurePath(path).name] = source / "Filters" / (path + ".h")
    return headers


def declared_methods(header, headers):
    """Methods a class's header declares (macros expanded by name), with its SurfaceLOD bases'."""
    text = header.read_text()
    methods = set(re.findall(r"\b((?:Set|Get)\w+)\s*\(", text))
    pattern = r"vtk(Set|Get|SetClamp|Boolean|SetStdStringFromChar|GetCharFromStdString|SetVector\d|GetVector\d)Macro\((\w+)"
    for kind, name in re.findall(pattern, text):
        methods.update({"Set" + name, "Get" + name} if kind != "Boolean" else {name + "On", name + "Off"})
    base = re.search(r"class \w+ (\w+) : public (\w+)", text)
    if base and base.group(2) in headers:
        methods |= declared_methods(headers[base.group(2)], headers)
    return methods


def main():
    source = pathlib.Path(sys.argv[1])
    headers = public_classes(source)
    extensions = {path.stem: path for path in (source / "ParaView" / "Extensions").glob("vtk*.h")}
    every_header = {**headers, **extensions}
    proxied = {}
    for xml in sorted((source / "ParaView" / "Plugin").glob("*.xml")):
        for proxy in ElementTree.parse(xml).getroot().iter():
            name = proxy.get("class")
            if name in every_header:
                proxied[name] = proxy
                base = re.search(r"class \w+ \w+ : public (\w+)", every_header[name].read_text())
                if name in extensions and base and base.group(1) in headers:
                    proxied.setdefault(base.group(1), proxy)
    failures = ["%s has no ParaView proxy" % name for name in sorted(set(headers) - set(proxied))]
    generic = {"SetInputConnection"}
    for name, proxy in sorted(proxied.items()):
        methods = declared_methods(every_header[proxy.get("class")], every_header) | generic
        for prop in proxy.iter():
            command = prop.get("command")
            if command and command not in methods:
                failures.append("%s: property %s calls %s, which the class does not declare" % (name, prop.get("name"), command))
    print("%d public classes, %d with a proxy" % (len(headers), len(set(headers) & set(proxied))))
    for failure in failures:
        print("FAIL  " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
