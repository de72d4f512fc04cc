#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""An installed SurfaceLOD works after its prefix is moved (run by ctest as Install.RelocatedPrefix).

Installs the build into a staging prefix, moves that prefix elsewhere, then runs the *installed*
`surfacelod` (methods, info, simplify on a generated torus) and the installed Python package with
/usr/bin/python3, with no LD_LIBRARY_PATH and a PYTHONPATH pointing into the moved prefix only.
The SurfaceLOD libraries actually loaded must come from the moved prefix, and no installed file
may still name the staging prefix.

usage: install_relocated_test.py [--cmake CMAKE] --source DIR --build DIR --work DIR [--python-site REL]
"""
import argparse
import os
import shutil
import sys

from cli_test import FAILURES, check, json_line, run

# The generated test surface: a torus of RING x TUBE quads split into triangles (closed, genus 1).
RING, TUBE = 48, 24
TORUS_VERTICES = RING * TUBE
TORUS_TRIANGLES = 2 * RING * TUBE
TARGET_TRIANGLES = TORUS_TRIANGLES // 4


def clean_environment(python_path=None):
    """The caller's environment without any loader or Python search path, so nothing but the
    installed files' own RPATHs and the given PYTHONPATH can locate SurfaceLOD."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("LD_LIBRARY_PATH", "PYTHONPATH", "PYTHONHOME", "PYTHONSTARTUP")}
    if python_path:
        env["PYTHONPATH"] = python_path
    return env


def write_torus_off(path, major=2.0, minor=0.6):
    import math
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (TORUS_VERTICES, TORUS_TRIANGLES))
        for i in range(RING):
            u = 2 * math.pi * i / RING
            for j in range(TUBE):
                v = 2 * math.pi * j / TUBE
                r = major + minor * math.cos(v)
                f.write("%.9g %.9g %.9g\n" % (r * math.cos(u), r * math.sin(u), minor * math.sin(v)))
        for i in range(RING):
            for j in range(TUBE):
                a, b = i * TUBE + j, i * TUBE + (j + 1) % TUBE
                c, d = ((i + 1) % RING) * TUBE + j, ((i + 1) % RING) * TUBE + (j + 1) % TUBE
                f.write("3 %d %d %d\n3 %d %d %d\n" % (a, c, d, a, d, b))


def install_and_move(cmake, build, work):
    """Returns (staging prefix, moved prefix); the staging prefix no longer exists afterwards."""
    staged = os.path.join(work, "staged-prefix")
    moved = os.path.join(work, "elsewhere", "moved-prefix")
    run(cmake, "--install", build, "--prefix", staged, env=clean_environment())
    os.makedirs(os.path.dirname(moved))
    shutil.move(staged, moved)
    check(not os.path.exists(staged), "staging prefix still exists after the move")
    return staged, moved


def check_no_file_names(prefix, forbidden):
    """No installed file (text or binary: configs, RPATHs, scripts) mentions the staging prefix."""
    needle = forbidden.encode()
    for root, _, files in os.walk(prefix):
        for name in files:
            path = os.path.join(root, name)
            if os.path.islink(path):
                continue
            with open(path, "rb") as f:
                check(needle not in f.read(), "%s names the staging prefix %s" % (path, forbidden))


def check_license_installed(source, prefix):
    installed = os.path.join(prefix, "share", "licenses", "SurfaceLOD", "LICENSE")
    check(os.path.isfile(installed), "no license installed at %s" % installed)
    if os.path.isfile(installed):
        with open(installed, "rb") as a, open(os.path.join(source, "LICENSE"), "rb") as b:
            check(a.read() == b.read(), "the installed LICENSE differs from the source tree's")


def surfacelod_libraries_loaded_by(cli, env):
    """The SurfaceLOD shared libraries the dynamic loader resolves for the installed CLI."""
    listing = run("ldd", cli, env=env).stdout
    check("not found" not in listing, "unresolved libraries of %s:\n%s" % (cli, listing))
    return [line.split("=>")[1].split("(")[0].strip() for line in listing.splitlines()
            if "SurfaceLOD" in line and "=>" in line and "not found" not in line]


def check_installed_cli(build, prefix, work):
    cli = os.path.join(prefix, "bin", "surfacelod")
    env = clean_environment()
    libraries = surfacelod_libraries_loaded_by(cli, env)
    check(libraries, "the installed CLI resolves no SurfaceLOD library")
    for library in libraries:
        check(library.startswith(prefix + os.sep), "the installed CLI loads %s, outside %s" % (library, prefix))

    methods = run(cli, "methods", env=env).stdout
    names = [line.split()[0] for line in methods.splitlines() if line.strip()]
    check("quadric-triangle-collapse" in names, "installed `surfacelod methods` lists: %r" % names)
    built = run(os.path.join(build, "bin", "surfacelod"), "methods", env=env).stdout
    check(methods == built, "installed and built `surfacelod methods` differ")

    torus = os.path.join(work, "torus.off")
    write_torus_off(torus)
    info = json_line(run(cli, "info", torus, "--json", env=env))
    expected = {"vertices": TORUS_VERTICES, "triangles": TORUS_TRIANGLES, "boundary_edges": 0,
                "nonmanifold_edges": 0, "components": 1, "euler_characteristic": 0, "genus": 1}
    for key, value in expected.items():
        check(info.get(key) == value, "torus %s = %r, expected %r" % (key, info.get(key), value))

    simplified = os.path.join(work, "torus_simplified.ply")
    result = json_line(run(cli, "simplify", torus, simplified, "--method", "quadric-triangle-collapse",
                            "--target-triangles", TARGET_TRIANGLES, "--json", env=env))
    check(result.get("input_triangles") == TORUS_TRIANGLES, "simplify read %r triangles" % result.get("input_triangles"))
    check(abs(result.get("output_triangles", -1) - TARGET_TRIANGLES) <= TARGET_TRIANGLES // 100,
          "simplify gave %r triangles for a target of %d" % (result.get("output_triangles"), TARGET_TRIANGLES))
    info = json_line(run(cli, "info", simplified, "--json", env=env))
    check(info.get("triangles") == result.get("output_triangles"),
          "written file has %r triangles, simplify said %r" % (info.get("triangles"), result.get("output_triangles")))
    check(info.get("boundary_edges") == 0 and info.get("genus") == 1,
          "simplified torus: %r boundary edges, genus %r" % (info.get("boundary_edges"), info.get("genus")))


# Runs inside /usr/bin/python3 with PYTHONPATH = the moved prefix's site directory only: imports the
# package, simplifies the torus, prints one JSON line (where the package and libraries came from).
PYTHON_PROBE = r"""
import json, sys
import surfacelod
reader = surfacelod.vtkOFFMeshReader()
reader.SetFileName(sys.argv[1])
collapse = surfacelod.vtkQuadricTriangleCollapse()
collapse.SetInputConnection(reader.GetOutputPort())
collapse.SetTargetNumberOfTriangles(int(sys.argv[2]))
collapse.Update()
with open("/proc/self/maps") as maps:
    libraries = sorted({line.split()[-1] for line in maps if "SurfaceLOD" in line})
print(json.dumps({"package": surfacelod.__file__, "version": surfacelod.__version__,
                  "input": reader.GetOutput().GetNumberOfPolys(),
                  "output": collapse.GetOutput().GetNumberOfPolys(), "libraries": libraries}))
"""


def check_installed_python(prefix, site, work):
    env = clean_environment(python_path=os.path.join(prefix, site))
    torus = os.path.join(work, "torus.off")
    probe = json_line(run("/usr/bin/python3", "-c", PYTHON_PROBE, torus, TARGET_TRIANGLES, env=env))
    check(probe["package"].startswith(os.path.join(prefix, site) + os.sep), "surfacelod imported from %s" % probe["package"])
    check(probe["input"] == TORUS_TRIANGLES, "Python read %r triangles" % probe["input"])
    check(abs(probe["output"] - TARGET_TRIANGLES) <= TARGET_TRIANGLES // 100,
          "Python collapse gave %r triangles for a target of %d" % (probe["output"], TARGET_TRIANGLES))
    check(any("libSurfaceLODFilters.so" in lib for lib in probe["libraries"]),
          "the Python package did not load libSurfaceLODFilters: %r" % probe["libraries"])
    for library in probe["libraries"]:
        check(library.startswith(prefix + os.sep), "Python loaded %s, outside %s" % (library, prefix))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cmake", default="cmake")
    parser.add_argument("--source", required=True)
    parser.add_argument("--build", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--python-site", help="the Python package's directory relative to the prefix")
    a = parser.parse_args()
    build, work = os.path.realpath(a.build), os.path.realpath(a.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    staged, moved = install_and_move(a.cmake, build, work)
    check_no_file_names(moved, staged)
    check_license_installed(a.source, moved)
    check_installed_cli(build, moved, work)
    if a.python_site:
        check_installed_python(moved, a.python_site, work)
    if FAILURES:
        print("%d failure(s)" % len(FAILURES))
        return 1
    print("relocated install OK: %s" % moved)
    return 0


if __name__ == "__main__":
    sys.exit(main())
