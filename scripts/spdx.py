# SPDX-License-Identifier: BSD-3-Clause
"""Every source file of the project starts with its SPDX license line (BSD-3-Clause, as LICENSE).

  python3 scripts/spdx.py [--fix] [ROOT]

Checks the tracked C++, CMake, Python and shell files under ROOT (default: the repository); lists
those without an `SPDX-License-Identifier: BSD-3-Clause` line in their first three lines and exits 1.
With --fix, adds the line (after a #! line or a VTK module descriptor's first line where needed).
"""
import os
import subprocess
import sys

LINE = "SPDX-License-Identifier: BSD-3-Clause"
COMMENT = {".h": "// ", ".cxx": "// ", ".cpp": "// ", ".py": "# ", ".sh": "# ", ".cmake": "# ",
           "CMakeLists.txt": "# "}


def comment_prefix(path):
    name = os.path.basename(path)
    return COMMENT.get(name) or COMMENT.get(os.path.splitext(name)[1])


def tracked_files(root):
    listing = subprocess.run(["git", "-C", root, "ls-files"], check=True, capture_output=True, text=True)
    return [os.path.join(root, f) for f in listing.stdout.splitlines() if comment_prefix(f)]


def main():
    fix = "--fix" in sys.argv[1:]
    roots = [a for a in sys.argv[1:] if a != "--fix"]
    root = roots[0] if roots else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    missing = []
    for path in tracked_files(root):
        with open(path, encoding="utf-8") as f:
            lines = f.readlines()
        if any(LINE in line for line in lines[:3]):
            continue
        missing.append(os.path.relpath(path, root))
        if fix:
            at = 1 if lines and lines[0].startswith("#!") else 0
            lines.insert(at, comment_prefix(path) + LINE + "\n")
            with open(path, "w", encoding="utf-8") as f:
                f.writelines(lines)
    for path in missing:
        print(("added to " if fix else "no SPDX line: ") + path)
    print("%d files without the SPDX line%s" % (len(missing), " (fixed)" if fix else ""))
    return 0 if fix or not missing else 1


if __name__ == "__main__":
    sys.exit(main())
