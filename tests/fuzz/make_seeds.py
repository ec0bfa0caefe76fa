#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes fuzz_mesh seed inputs into the folder given (default: /tmp/translucent_fuzz_seeds).

An input is one byte choosing the extension (0 .obj, 1 .ply, 2 .off; fuzz_mesh.cpp) and then the
file. Seeds: every file of the malformed-mesh corpus, and small valid meshes of each format and
variant (ASCII and both binary PLY byte orders, OBJ with texture coordinates, normals and
negative indices), so that the fuzzer starts from both sides of every check.
"""
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
MALFORMED = os.path.join(HERE, "..", "data", "malformed", "meshes")
EXT = {".obj": 0, ".ply": 1, ".off": 2}
out = sys.argv[1] if len(sys.argv) > 1 else "/tmp/translucent_fuzz_seeds"
os.makedirs(out, exist_ok=True)


def seed(name, ext, data):
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(out, name), "wb") as f:
        f.write(bytes([EXT[ext]]) + data)


for name in sorted(os.listdir(MALFORMED)):
    path = os.path.join(MALFORMED, name)
    ext = os.path.splitext(name)[1]
    if os.path.isfile(path) and ext in EXT:
        with open(path, "rb") as f:
            seed("malformed_" + name, ext, f.read())

V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
seed("valid_cube.obj", ".obj",
     "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
     "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n")
seed("valid_tetra_uv_normals.obj", ".obj",
     "# tetrahedron\no t\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in V) +
     "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n" +
     "f -4/1/1 -2/3/1 -3/2/1\nf 1/1/1 2/2/1 4/3/1\nf 1//1 4//1 3//1\nf 2/2 3/3 4/1\n")
header = ("ply\nformat {} 1.0\ncomment seed\nelement vertex 4\nproperty float x\n"
          "property float y\nproperty float z\nproperty float nx\nproperty float ny\n"
          "property float nz\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n")
seed("valid_tetra_ascii.ply", ".ply", header.format("ascii") +
     "".join(f"{x} {y} {z} 0 0 1\n" for x, y, z in V) +
     "".join("3 " + " ".join(map(str, f)) + "\n" for f in F))
for fmt, e in (("binary_little_endian", "<"), ("binary_big_endian", ">")):
    body = b"".join(struct.pack(e + "6f", *v, 0, 0, 1) for v in V)
    body += b"".join(struct.pack(e + "B3i", 3, *f) for f in F)
    seed(f"valid_tetra_{fmt}.ply", ".ply", header.format(fmt).encode() + body)
seed("valid_quad_double_uint.ply", ".ply",
     "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
     "property double z\nelement face 1\nproperty list uint uint vertex_index\nend_header\n"
     "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
seed("valid_tetra.off", ".off", "OFF\n4 4 0\n\n" + "".join(f"{x} {y} {z}\n" for x, y, z in V) +
     "".join("3 " + " ".join(map(str, f)) + "\n" for f in F))
seed("valid_tetra_counts_on_header.off", ".off", "COFF 4 4 6\n" +
     "".join(f"{x} {y} {z} 255 0 0 255\n" for x, y, z in V) +
     "".join("3 " + " ".join(map(str, f)) + "\n" for f in F))
print(f"seeds in {out}")
