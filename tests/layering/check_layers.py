#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks the include graph of the library against its layer order.

A layer includes only layers below it (src/CMakeLists.txt lists the order). Every
`#include "translucent/<layer>/..."` in src/translucent/<layer>/ is read; an include of the same
layer is fine, of a lower layer fine, of a layer at the same rank or above is an arrow the wrong
way. Also checks that every such include names a file that exists (the installed path is the
include path), and that no file includes a library header by any other path than
"translucent/...".

Usage: check_layers.py SRC_DIR          (exit 1 and a list of arrows when any is found)
       check_layers.py --self-test      (checks that a planted arrow is found)
"""
import os
import re
import sys
import tempfile

# Lowest first; layers of one rank do not include each other either.
RANKS = [
    ["optics", "geometry", "io"],
    ["bssrdf", "lights"],
    ["material", "gpu"],
    ["reference"],
    ["scene"],
    ["techniques", "analysis"],
    ["compare"],
]
RANK = {layer: i for i, layers in enumerate(RANKS) for layer in layers}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def arrows(src):
    root = os.path.join(src, "translucent")
    found, unknown, missing, stray = [], [], [], []
    for d, _, files in os.walk(root):
        for f in files:
            if not f.endswith((".h", ".cpp", ".inl", ".inc", ".in")):
                continue
            path = os.path.join(d, f)
            rel = os.path.relpath(path, root)
            layer = rel.split(os.sep)[0]
            if layer not in RANK:
                unknown.append(rel)
                continue
            with open(path, encoding="utf-8", errors="replace") as fh:
                text = fh.read()
            for inc in INCLUDE.findall(text):
                parts = inc.split("/")
                if parts[0] != "translucent":
                    if parts[0] in RANK:
                        stray.append(f"{rel}: #include \"{inc}\" (expected \"translucent/{inc}\")")
                    continue
                target = parts[1] if len(parts) > 2 else ""
                if target not in RANK:
                    unknown.append(f"{rel}: #include \"{inc}\"")
                    continue
                if not os.path.isfile(os.path.join(src, inc)):
                    missing.append(f"{rel}: #include \"{inc}\" (no such file)")
                if target != layer and RANK[target] >= RANK[layer]:
                    found.append(f"{layer}/{rel.split(os.sep, 1)[1]} -> {inc} "
                                 f"({layer} is rank {RANK[layer]}, {target} rank {RANK[target]})")
    return found, unknown, missing, stray


def check(src):
    found, unknown, missing, stray = arrows(src)
    for title, items in (("arrows from a lower layer to a higher one", found),
                         ("folders or includes outside the layer list", unknown),
                         ("includes of files that do not exist", missing),
                         ("library headers included by another path", stray)):
        if items:
            print(f"{len(items)} {title}:")
            for i in sorted(items):
                print("  " + i)
    print(f"layering: {len(found)} arrows from a lower layer to a higher one")
    return 1 if (found or unknown or missing or stray) else 0


def self_test():
    with tempfile.TemporaryDirectory() as tmp:
        for layer, text in (("optics", '#include "translucent/scene/scene.h"\n'),
                            ("scene", '#include "translucent/optics/medium.h"\n')):
            os.makedirs(os.path.join(tmp, "translucent", layer))
        with open(os.path.join(tmp, "translucent/optics/medium.h"), "w") as f:
            f.write('#include "translucent/scene/scene.h"\n')
        with open(os.path.join(tmp, "translucent/scene/scene.h"), "w") as f:
            f.write('#include "translucent/optics/medium.h"\n')
        found, unknown, missing, stray = arrows(tmp)
        if len(found) != 1 or "optics/medium.h -> translucent/scene/scene.h" not in found[0]:
            print("self-test failed: the planted arrow optics -> scene was not found:", found)
            return 1
        if unknown or missing or stray:
            print("self-test failed: unexpected findings", unknown, missing, stray)
            return 1
    print("self-test: the planted arrow was found, the downward include was not reported")
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 2 and sys.argv[1] == "--self-test":
        sys.exit(self_test())
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(check(sys.argv[1]))
