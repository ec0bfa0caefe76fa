#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the four synthetic 32x24 8-bit PNG pairs of tests/analysis/test_flip.cpp
(Flip.MatchesTheAuthorsImplementationOnSyntheticPairs), so that the expected mean FLIP values
can be recomputed with the authors' tool (https://github.com/NVlabs/flip, v1.6, commit 1eb247c):

    g++ -O2 -std=c++17 -fopenmp -I src/cpp src/cpp/tool/FLIP-tool.cpp -o flip   # in their repo
    scripts/flip_reference_pairs.py OUTDIR
    for k in uniform square edge texture; do flip -r OUTDIR/${k}_ref.png -t OUTDIR/${k}_test.png; done
    flip -r OUTDIR/square_ref.png -t OUTDIR/square_test.png -ppd 20

The pixel formulas must stay identical to the test's (kSquareRef, kEdgeRef, kTextureRef, ...).
Standard library only (PNG written with zlib).
"""
import os
import struct
import sys
import zlib

W, H = 32, 24


def write_png(path, pixel):
    raw = b"".join(b"\x00" + bytes(v for x in range(W) for v in pixel(x, y)) for y in range(H))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))

    header = struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)  # 8-bit RGB
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) +
                chunk(b"IEND", b""))


def clamp(v):
    return max(0, min(255, v))


def square_ref(x, y):
    return ((x * 8) % 256, (y * 10) % 256, 128)


def square_test(x, y):
    return (255, 40, 40) if 10 <= x < 16 and 8 <= y < 14 else square_ref(x, y)


def texture_ref(x, y):
    return (((x * 37 + y * 91) * 13) % 256, ((x * 53 + y * 29) * 7) % 256,
            ((x * 11 + y * 71) * 5) % 256)


def texture_test(x, y):
    r = texture_ref(x, y)
    return (clamp(r[0] + (x * y) % 7 - 3), clamp(r[1] + (x + 2 * y) % 9 - 4), r[2])


PAIRS = {
    "uniform": (lambda x, y: (0, 0, 0), lambda x, y: (255, 255, 255)),
    "square": (square_ref, square_test),
    "edge": (lambda x, y: (200,) * 3 if x < 16 else (50,) * 3,
             lambda x, y: (200,) * 3 if x < 17 else (50,) * 3),
    "texture": (texture_ref, texture_test),
}

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    os.makedirs(out, exist_ok=True)
    for name, (ref, test) in PAIRS.items():
        write_png(os.path.join(out, f"{name}_ref.png"), ref)
        write_png(os.path.join(out, f"{name}_test.png"), test)
