#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes fuzz_cli seed inputs into the folder given (default: /tmp/translucent_fuzz_cli_seeds).

A seed is a real command line, one argument per line (fuzz_cli.cpp): every `translucent ...`
command of README.md (code blocks and inline code) and every command line of the CLI tests
(tests/cli/CMakeLists.txt `cli_test(... ARGS ...)`, tests/cli/outputs.cmake `run(...)`). Files they
name become the scratch folder's (fuzz_cli.cpp): scenes scene.json, meshes cube.obj, .bssrdf files
model.bssrdf, input tables table.csv, layer files layers.json; an output keeps its file name.
"""
import hashlib
import os
import re
import shlex
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
out = sys.argv[1] if len(sys.argv) > 1 else "/tmp/translucent_fuzz_cli_seeds"
os.makedirs(out, exist_ok=True)

# Options whose value is a file the command reads.
INPUT_OPTIONS = {"--scene": "scene.json", "--layers": "layers.json", "--bunny": "scene.json",
                 "--reference-from": "scene.json"}


def scratch_name(arg, previous):
    """The scratch folder's file for an argument that names a file, else the argument."""
    if previous == "--shard":
        return arg
    if previous in INPUT_OPTIONS and not arg.startswith("-"):
        return INPUT_OPTIONS[previous]
    if previous == "--model" or previous == "--models":
        return ",".join(scratch_name(m, "") for m in arg.split(","))
    base = arg.replace("${OUT}/", "").replace("${WORK}/", "")
    if base.endswith(".bssrdf"):
        return "model.bssrdf"
    if re.search(r"\.(obj|ply|off)$", base) and previous not in ("--out",):
        return "cube.obj"
    if base.endswith(".json") and ("scenes/" in base or "${" in base or base.startswith("/")) \
            and previous not in ("--json", "--out"):
        return "scene.json"
    if base.endswith(".csv") and ("bad_table" in base or "${" in base) and previous != "--out" \
            and previous != "--csv" and previous != "--save-profile":
        return "table.csv"
    if "/" in base and not base.startswith("-"):
        # An output or a folder: its name alone (fuzz_cli skips absolute paths and "..").
        return os.path.basename(base.rstrip("/")) or "out"
    return base


def normalise(args):
    out_args = []
    previous = ""
    for a in args:
        a = a.replace("${PROJECT_SOURCE_DIR}", "").replace("${CMAKE_CURRENT_BINARY_DIR}", "")
        a = a.replace("${CMAKE_CURRENT_SOURCE_DIR}", "").replace("${BSSRDF_DIR}", "")
        a = a.replace("${WRAP}", "")
        out_args.append(scratch_name(a, previous))
        previous = a
    return out_args


commands = []

# README: code lines starting with `translucent` (with continuation lines) and inline code.
readme = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read()
lines = readme.split("\n")
i = 0
while i < len(lines):
    line = lines[i].strip()
    if line.startswith("translucent ") or line.startswith("build/release/bin/translucent "):
        text = line
        while text.endswith("\\") and i + 1 < len(lines):
            i += 1
            text = text[:-1] + " " + lines[i].strip()
        commands.append(text.split("#")[0])
    i += 1
for m in re.finditer(r"`translucent ([a-z][^`]*)`", readme):
    commands.append("translucent " + m.group(1))

# The CLI tests.
cli = open(os.path.join(ROOT, "tests", "cli", "CMakeLists.txt"), encoding="utf-8").read()
for m in re.finditer(r"cli_test\(\s*\S+\s+(?:FAIL\s+)?ARGS\s+(.*?)(?:\s+(?:MATCH|FILE|STDOUT|PNG_SIZE)\s|\))",
                     cli, re.S):
    commands.append("translucent " + " ".join(m.group(1).split()))
outputs = open(os.path.join(ROOT, "tests", "cli", "outputs.cmake"), encoding="utf-8").read()
pt = "pathtrace mesh --scene scene.json --photons 1000 --threads 1"
for m in re.finditer(r"run\((?:OK|FAIL)\s+\"(?:[^\"\\]|\\.)*\"\s+(.*?)\)\n", outputs, re.S):
    commands.append("translucent " + " ".join(m.group(1).replace("${PT}", pt).split()))

# Options the documents above do not show on a command line of their own.
commands += [
    "translucent --version",
    "translucent pathtrace slab --preset Marble --channel g --photons 1e5 --shard 0/4 --partial p.tpart",
    "translucent pathtrace sphere --photons 1e4 --shard 1/2 --partial p.tpart --device cpu",
    "translucent pathtrace mesh --scene scene.json --time 0.5 --quantity cone-radiance --exr o.exr",
    "translucent integrate mesh --scene scene.json --subpixels 2 --jitter --convention normalized "
    "--near-field 3 --tail 0.01 --environment-rays 8 --exr o.exr --json o.json",
    "translucent integrate sphere --model table.csv --sampling uniform --defensive 0.2 --exr o.exr",
    "translucent render scene.json --frames 3 --fps 12 --time 1 --out f_%04d.png --exr f_%04d.exr",
    "translucent render scene.json --frames 2 --video v.mp4",
    "translucent render scene.json --technique tsis --width 64 --height 48 --exr old.png",
    "translucent render --out old.png --gamma 2.2 --exposure -1 --model table.csv",
    "translucent compare scene.json --techniques pointcloud,tsis:mode=hybrid --reference physical "
    "--reference-device gpu --frames 2 --warmup 0 --time 0.5 --no-cache --out sub",
    "translucent compare --suite sub --cache cache --force --out report",
    "translucent profile --model dipole,table.csv,model.bssrdf --rmax 5 --points 30 --times-r "
    "--title T --width 400 --height 300 --out p.svg",
    "translucent profile --study --model dipole --study-presets Skin1,Marble --seed 2 --json s.json",
    "translucent invert --model better-dipole --rd 0.5 --ld 2 --json",
    "translucent atlas cube.obj --method triangles --gutter 4 --range 2 --mesh-uvs --json",
    "translucent pointcloud cube.obj --sampling random --seed 3 --points 10 --out p.ply",
    "translucent merge p.tpart --json o.json --csv o.csv --exr o.exr --png o.png "
    "--quantity radiance --exposure 1 --gamma 2",
]

written = set()
for c in commands:
    c = c.replace("…", "").replace("...", "")
    try:
        words = shlex.split(c)
    except ValueError:
        continue
    if not words:
        continue
    if words[0].endswith("translucent"):
        words = words[1:]
    words = [w for w in words if w not in ("\\",)]
    if not words or "[" in " ".join(words) or "<" in " ".join(words):
        continue  # a synopsis with placeholders
    data = "\n".join(normalise(words)).encode()
    if data in written:
        continue
    written.add(data)
    name = hashlib.sha1(data).hexdigest()[:16]
    with open(os.path.join(out, f"seed-{name}"), "wb") as f:
        f.write(data)
print(f"{len(written)} seeds in {out}")
