# SPDX-License-Identifier: BSD-3-Clause
"""List the longest C++ functions of the library, and fail when one is over the limit.

  python3 scripts/function-lengths.py [--limit 150] [--top 20] [PATH ...]   (default PATH: Filters)

A function's length is the number of lines from its signature's line to its closing brace,
lambdas and local classes inside it included (a stage that hides in a lambda is still part of
the function that holds it). Functions are found by their braces after comments, strings and
preprocessor lines are removed: a brace opens a function body when the text before it, since the
previous statement, ends a parameter list and is not a control statement. Exit status 1 when a
function is longer than the limit.
"""
import argparse
import os
import re
import sys

CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|return)\b")
SCOPE = re.compile(r"\b(namespace|class|struct|union|enum)\b[^()]*$")
NAME = re.compile(r"([A-Za-z_][\w:~]*(?:operator\s*\S+)?)\s*\([^()]*(?:\([^()]*\)[^()]*)*\)[^()]*$", re.S)


def strip_code(text):
    """Comments, string and character literals and preprocessor lines blanked; newlines kept."""
    pattern = re.compile(r'//[^\n]*|/\*.*?\*/|R"\((?:.|\n)*?\)"|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'|^\s*#[^\n]*(?:\\\n[^\n]*)*',
                         re.S | re.M)
    return pattern.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def functions(path):
    """(name, first line, last line) of every function body in the file outside another body."""
    code = strip_code(open(path, encoding="utf-8", errors="replace").read())
    found, stack, statement_start = [], [], 0
    for index, char in enumerate(code):
        if char in ";}":
            if char == "}" and stack:
                kind, name, line = stack.pop()
                if kind == "function":
                    found.append((name, line, code.count("\n", 0, index) + 1))
            statement_start = index + 1
        elif char == "{":
            head = code[statement_start:index]
            inside_function = any(kind == "function" for kind, _, _ in stack)
            match = NAME.search(head.strip()) if not inside_function else None
            if match and not CONTROL.match(head) and not SCOPE.search(head):
                first = statement_start + len(head) - len(head.lstrip())
                stack.append(("function", match.group(1), code.count("\n", 0, first) + 1))
            else:
                stack.append(("block", "", 0))
            statement_start = index + 1
    return found


def source_files(paths):
    for root in paths:
        if os.path.isfile(root):
            yield root
            continue
        for folder, _, names in sorted(os.walk(root)):
            for name in sorted(names):
                if name.endswith((".cxx", ".cpp", ".h", ".hpp", ".txx")):
                    yield os.path.join(folder, name)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=int, default=150)
    parser.add_argument("--top", type=int, default=20)
    parser.add_argument("paths", nargs="*", default=["Filters"])
    arguments = parser.parse_args()
    rows = [(last - first + 1, path, first, name)
            for path in source_files(arguments.paths) for name, first, last in functions(path)]
    rows.sort(key=lambda row: (-row[0], row[1], row[2]))
    for length, path, first, name in rows[:arguments.top]:
        print("%5d  %s:%d  %s" % (length, path, first, name))
    over = [row for row in rows if row[0] > arguments.limit]
    print("%d functions, %d over %d lines, %d over 100" % (len(rows), len(over), arguments.limit,
                                                           sum(1 for row in rows if row[0] > 100)))
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
