#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks that every source file of the project carries its licence's SPDX identifier.

Every C++, GLSL, Python, shell and CMake file under the source folders must name
"SPDX-License-Identifier: GPL-3.0-or-later" in its first three lines (after a shebang or a GLSL
#version line). Test data (tests/data, fuzz corpora) and generated files are not sources.

Usage: check_spdx.py ROOT
"""
import os
import sys

FOLDERS = ["src", "apps", "python", "tests", "bench", "shaders", "scripts", "cmake", "examples"]
SKIP = [os.path.join("tests", "data"), os.path.join("tests", "fuzz", "corpus")]
EXTENSIONS = (".h", ".cpp", ".inl", ".inc", ".in", ".comp", ".glsl", ".frag", ".vert", ".py",
              ".sh", ".cmake", ".sbatch", ".pyi")
TAG = "SPDX-License-Identifier: GPL-3.0-or-later"


def is_source(rel, path):
    if rel.endswith(EXTENSIONS) or os.path.basename(rel) == "CMakeLists.txt":
        return True
    # Extension-less scripts: a shebang on the first line.
    if "." not in os.path.basename(rel):
        with open(path, "rb") as f:
            return f.read(2) == b"#!"
    return False


def main(root):
    missing, checked = [], 0
    tops = [os.path.join(root, f) for f in FOLDERS] + [root]
    for top in tops:
        if not os.path.isdir(top):
            continue
        walk = os.walk(top) if top != root else [(root, [], os.listdir(root))]
        for d, dirs, files in walk:
            rel_d = os.path.relpath(d, root)
            dirs[:] = [x for x in dirs if not any(os.path.join(rel_d, x).startswith(s) for s in SKIP)
                       and x not in ("__pycache__", "node_modules")]
            for f in files:
                path = os.path.join(d, f)
                rel = os.path.relpath(path, root)
                if not os.path.isfile(path) or not is_source(rel, path):
                    continue
                checked += 1
                with open(path, encoding="utf-8", errors="replace") as fh:
                    head = [fh.readline() for _ in range(3)]
                if not any(TAG in line for line in head):
                    missing.append(rel)
    for m in sorted(missing):
        print(f"no '{TAG}' in the first lines of {m}")
    print(f"spdx: {checked} source files, {len(missing)} without the identifier")
    return 1 if missing or checked == 0 else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
