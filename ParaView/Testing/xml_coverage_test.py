# SPDX-License-Identifier: BSD-3-Clause
"""Every public class of the module that can be instantiated has a ParaView proxy (its own or one of a ParaView/Extensions
subclass), every proxy property calls a method the class declares, and every default in the XML
is the class's own (its member initialiser), so the panels start where the filters do (run by the
system Python, no ParaView needed).

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
    pattern = r"vtk(Set|Get|SetClamp|Boolean|SetString|GetString|SetStdStringFromChar|GetCharFromStdString|SetVector\d|GetVector\d)Macro\((\w+)"
    for kind, name in re.findall(pattern, text):
        methods.update({"Set" + name, "Get" + name} if kind != "Boolean" else {name + "On", name + "Off"})
    base = re.search(r"class \w+ (\w+) : public (\w+)", text)
    if base and base.group(2) in headers:
        methods |= declared_methods(headers[base.group(2)], headers)
    return methods


def initial_values(header, headers):
    """Member initialisers `type Name = value;` of a class and its SurfaceLOD bases, then the
    class's constructor's `this->Name = value;` (a class's own default of a base's property),
    evaluated (numbers, true/false, arithmetic, the class's enumerators, vtkAlgorithm's precisions)."""
    text = header.read_text()
    names = {"true": 1, "false": 0, "vtkAlgorithm::SINGLE_PRECISION": 0,
             "vtkAlgorithm::DOUBLE_PRECISION": 1, "vtkAlgorithm::DEFAULT_PRECISION": 2}
    for body in re.findall(r"enum\s*\w*\s*\{([^}]*)\}", text):
        for name, value in re.findall(r"(\w+)\s*=\s*(-?\d+)", body):
            names[name] = int(value)
    values = {}
    base = re.search(r"class \w+ (\w+) : public (\w+)", text)
    if base and base.group(2) in headers:
        values.update(initial_values(headers[base.group(2)], headers))
    assignments = re.findall(r"^\s+[\w:]+ (\w+) = ([^;]+);", text, re.MULTILINE)
    source = header.with_suffix(".cxx")
    if base and source.exists():
        constructor = re.search(r"^%s::%s\(\)\s*\{(.*?)^\}" % (base.group(1), base.group(1)),
                                source.read_text(), re.MULTILINE | re.DOTALL)
        if constructor:
            assignments += re.findall(r"this->(\w+) = ([^;]+);", constructor.group(1))
    for name, expression in assignments:
        for symbol, value in names.items():
            expression = expression.replace(symbol, str(value))
        if re.fullmatch(r"[-+*/. 0-9e()]+", expression):
            values[name] = eval(expression)  # arithmetic on literals only (checked above)
    return values


def default_mismatches(name, proxy, header, headers, checked):
    initial = initial_values(header, headers)
    failures = []
    for prop in proxy:
        command = prop.get("command") or ""
        member = command[3:] if command.startswith("Set") else None
        if member not in initial or prop.get("default_values") is None:
            continue
        checked.append(member)
        xml_value = float(prop.get("default_values"))
        if abs(xml_value - initial[member]) > 1e-9 * max(1.0, abs(initial[member])):
            failures.append("%s: %s defaults to %s in the XML, %s in the class"
                            % (name, prop.get("name"), prop.get("default_values"), initial[member]))
    return failures


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
    # An abstract base (no New(): vtkMeshFileReader, vtkMeshFileWriter) cannot have a proxy of its own.
    concrete = {name for name, header in headers.items() if re.search(r"static %s\* New\(\)" % name, header.read_text())}
    failures = ["%s has no ParaView proxy" % name for name in sorted(concrete - set(proxied))]
    generic = {"SetInputConnection"}
    checked = []
    for name, proxy in sorted(proxied.items()):
        methods = declared_methods(every_header[proxy.get("class")], every_header) | generic
        for prop in proxy.iter():
            command = prop.get("command")
            if command and command not in methods:
                failures.append("%s: property %s calls %s, which the class does not declare" % (name, prop.get("name"), command))
        failures += default_mismatches(name, proxy, every_header[proxy.get("class")], every_header, checked)
    print("%d public classes, %d with a proxy; %d defaults compared with the classes' initialisers"
          % (len(headers), len(set(headers) & set(proxied)), len(checked)))
    for failure in failures:
        print("FAIL  " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
