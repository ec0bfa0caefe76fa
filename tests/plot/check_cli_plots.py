#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line without Qt: `ldd` of the translucent binary names no Qt library, and
`translucent profile --model all` writes a valid PNG, SVG and PDF.

Usage: check_cli_plots.py TRANSLUCENT_BINARY OUTPUT_DIR
"""
import pathlib
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET


def fail(message):
    print(f"check_cli_plots: FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def main():
    cli, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)

    ldd = subprocess.run(["ldd", str(cli)], capture_output=True, text=True, check=True).stdout
    qt = [line.strip() for line in ldd.splitlines() if "qt" in line.lower()]
    if qt:
        fail(f"{cli} links Qt:\n  " + "\n  ".join(qt))
    print(f"ldd {cli.name}: {len(ldd.splitlines())} libraries, none of them Qt")

    for ext in ("png", "svg", "pdf"):
        path = out / f"all_models.{ext}"
        path.unlink(missing_ok=True)
        run = subprocess.run([str(cli), "profile", "--preset", "Marble", "--model", "all",
                              "--out", str(path)], capture_output=True, text=True)
        if run.returncode != 0:
            fail(f"profile --out {path.name} exited {run.returncode}:\n{run.stderr}")
        data = path.read_bytes()
        if ext == "png":
            # Signature, then the IHDR chunk: width and height (the default 1600 x 1000).
            if data[:8] != b"\x89PNG\r\n\x1a\n" or data[12:16] != b"IHDR":
                fail(f"{path} is not a PNG")
            width, height = struct.unpack(">II", data[16:24])
            if (width, height) != (1600, 1000):
                fail(f"{path} is {width} x {height}, expected 1600 x 1000")
        elif ext == "svg":
            root = ET.fromstring(data)  # raises on malformed XML
            if root.tag != "{http://www.w3.org/2000/svg}svg":
                fail(f"{path}: root element {root.tag}, expected svg")
            paths = root.findall(".//{http://www.w3.org/2000/svg}path")
            if len(paths) < 10:
                fail(f"{path}: {len(paths)} <path> elements, expected the curves among them")
        else:
            if not data.startswith(b"%PDF-") or b"%%EOF" not in data[-32:]:
                fail(f"{path} is not a complete PDF")
        print(f"{path.name}: {len(data)} bytes")


main()
