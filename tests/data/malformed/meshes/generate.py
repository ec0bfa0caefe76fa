#!/usr/bin/env python3
"""Writes the malformed-mesh corpus next to this script (committed; rerun after editing).

Each file breaks one rule a mesh loader must check before it trusts a count or an index; the
manifest (manifest.txt, next to this script) gives the error each one must produce. The binary
PLY files are why this is a script: a hex dump would hide which byte lies.
"""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

TETRA_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TETRA_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def write(name, data):
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def ply_header(fmt, nv, nf, extra=""):
    return (f"ply\nformat {fmt} 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\n"
            f"property float z\nelement face {nf}\nproperty list uchar int vertex_indices\n"
            f"{extra}end_header\n").encode()


def ply_binary(nv, nf, verts, faces, endian="<", fmt="binary_little_endian"):
    out = ply_header(fmt, nv, nf)
    for v in verts:
        out += struct.pack(endian + "3f", *v)
    for f in faces:
        out += struct.pack(endian + "B", len(f)) + struct.pack(endian + f"{len(f)}i", *f)
    return out


def ply_ascii(nv, nf, verts, faces, header_extra=""):
    out = ply_header("ascii", nv, nf, header_extra).decode()
    out += "".join(" ".join(str(c) for c in v) + "\n" for v in verts)
    out += "".join(" ".join(str(i) for i in (len(f), *f)) + "\n" for f in faces)
    return out


def off(nv, nf, verts, faces, head="OFF"):
    out = f"{head}\n{nv} {nf} 0\n"
    out += "".join(" ".join(str(c) for c in v) + "\n" for v in verts)
    out += "".join(" ".join(str(i) for i in (len(f), *f)) + "\n" for f in faces)
    return out


def obj(verts, faces, extra=""):
    return ("".join(f"v {x} {y} {z}\n" for x, y, z in verts) + extra +
            "".join("f " + " ".join(str(i) for i in f) + "\n" for f in faces))


nan, inf = math.nan, math.inf
# Binary PLY: the header is trusted by assimp, which reads past the data or allocates what it says.
write("ply_bin_short_vertices.ply", ply_binary(8, 4, TETRA_V, TETRA_F))
write("ply_bin_short_faces.ply", ply_binary(4, 9, TETRA_V, TETRA_F))
write("ply_bin_header_only.ply", ply_header("binary_little_endian", 4, 4))
write("ply_bin_negative_index.ply", ply_binary(4, 4, TETRA_V, [(0, 2, 1), (0, 1, -1)] + TETRA_F[2:]))
write("ply_bin_index_out_of_range.ply", ply_binary(4, 4, TETRA_V, TETRA_F[:3] + [(1, 2, 99)]))
write("ply_bin_huge_count.ply", ply_binary(4000000000, 4, TETRA_V, TETRA_F))
write("ply_bin_list_count_past_end.ply",
      ply_binary(4, 4, TETRA_V, TETRA_F)[:-13] + struct.pack("<B", 255) + struct.pack("<3i", 0, 1, 2))
# Found by fuzz_mesh: a face of no index failed an assertion in assimp's triangulation.
write("ply_bin_empty_face.ply", ply_binary(4, 4, TETRA_V, TETRA_F[:3] + [()]))
write("ply_bin_nan.ply", ply_binary(4, 4, [(nan, 0, 0)] + TETRA_V[1:], TETRA_F))
write("ply_bin_inf.ply", ply_binary(4, 4, TETRA_V[:3] + [(0, 0, inf)], TETRA_F))
write("ply_be_short_vertices.ply",
      ply_binary(6, 4, TETRA_V, TETRA_F, endian=">", fmt="binary_big_endian"))
# ASCII PLY: lying counts abort on an assimp assertion.
write("ply_ascii_lying_vertex_count.ply", ply_ascii(8, 4, TETRA_V, TETRA_F))
write("ply_ascii_lying_face_count.ply", ply_ascii(4, 7, TETRA_V, TETRA_F))
write("ply_ascii_index_out_of_range.ply", ply_ascii(4, 4, TETRA_V, TETRA_F[:3] + [(1, 2, 4)]))
write("ply_ascii_negative_index.ply", ply_ascii(4, 4, TETRA_V, [(0, -2, 1)] + TETRA_F[1:]))
write("ply_ascii_bad_number.ply", ply_ascii(4, 4, [(0, 0, 0), (1, "x", 0)] + TETRA_V[2:], TETRA_F))
write("ply_ascii_negative_count.ply", ply_ascii(-4, 4, TETRA_V, TETRA_F))
write("ply_ascii_huge_count.ply", ply_ascii(4000000000, 4, TETRA_V, TETRA_F))
write("ply_ascii_short_list.ply", ply_ascii(4, 4, TETRA_V, TETRA_F[:3]) + "3 1 2\n")
write("ply_ascii_two_index_face.ply", ply_ascii(4, 4, TETRA_V, TETRA_F[:3] + [(1, 2)]))
# Found by hand after the first fuzz run: assimp misreads a blank line inside the data and a line
# with more values than the header's properties (the latter fails an assertion).
write("ply_ascii_blank_line.ply", ply_ascii(4, 4, TETRA_V, TETRA_F).replace("\n1 0 0\n", "\n\n1 0 0\n"))
write("ply_ascii_extra_values.ply", ply_ascii(4, 4, TETRA_V, TETRA_F).replace("\n0 1 0\n", "\n0 1 0 7 7 7\n"))
# Loaded a different mesh, silently: assimp mixes repeated elements and properties.
write("ply_second_vertex_element.ply", ply_ascii(4, 4, TETRA_V, TETRA_F).replace(
    "end_header\n", "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
    "end_header\n") + "0 0 0\n0 0 0\n")
write("ply_repeated_property.ply", ply_ascii(4, 4, [(*v, 5) for v in TETRA_V], TETRA_F).replace(
    "property float z\n", "property float z\nproperty float x\n"))
write("ply_ascii_nan.ply", ply_ascii(4, 4, TETRA_V[:2] + [(0, "nan", 0)] + TETRA_V[3:], TETRA_F))
write("ply_no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n")
write("ply_unknown_format.ply", ply_ascii(4, 4, TETRA_V, TETRA_F).replace("format ascii", "format text"))
write("ply_unknown_type.ply", ply_ascii(4, 4, TETRA_V, TETRA_F).replace("property float y", "property flt y"))
write("ply_no_faces.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n")
write("ply_magic_only.ply", "ply\n")
write("ply_zero_area.ply", ply_ascii(4, 2, [(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)],
                                     [(0, 1, 2), (1, 2, 3)]))
# OFF: the same lies in a line format.
write("off_lying_vertex_count.off", off(9, 4, TETRA_V, TETRA_F))
write("off_lying_face_count.off", off(4, 8, TETRA_V, TETRA_F))
write("off_index_out_of_range.off", off(4, 4, TETRA_V, TETRA_F[:3] + [(1, 2, 7)]))
write("off_negative_index.off", off(4, 4, TETRA_V, [(0, 2, -1)] + TETRA_F[1:]))
write("off_huge_count.off", off(4000000000, 4, TETRA_V, TETRA_F))
write("off_negative_count.off", off(4, -4, TETRA_V, TETRA_F))
write("off_bad_counts.off", "OFF\n4 x 0\n0 0 0\n")
write("off_header_only.off", "OFF\n4 4 0\n")
write("off_nan.off", off(4, 4, [(0, 0, "nan")] + TETRA_V[1:], TETRA_F))
write("off_short_face.off", off(4, 4, TETRA_V, TETRA_F[:3] + [(1, 2)]).replace("\n2 1 2\n", "\n3 1 2\n"))
write("off_zero_area.off", off(3, 1, [(0, 0, 0), (1, 1, 1), (2, 2, 2)], [(0, 1, 2)]))
# OBJ: indices are 1-based, negative ones count back from the last vertex.
write("obj_index_out_of_range.obj", obj(TETRA_V, [(1, 3, 2), (1, 2, 4), (1, 4, 3), (2, 3, 5)]))
write("obj_index_zero.obj", obj(TETRA_V, [(1, 3, 2), (0, 2, 4), (1, 4, 3), (2, 3, 4)]))
write("obj_negative_beyond_range.obj", obj(TETRA_V, [(1, 3, 2), (1, 2, 4), (1, 4, 3), (-1, -2, -5)]))
write("obj_texcoord_out_of_range.obj", obj(TETRA_V, [], "vt 0 0\n") + "f 1/1 3/2 2/1\n")
write("obj_normal_out_of_range.obj", obj(TETRA_V, [], "vn 0 0 1\n") + "f 1//1 3//1 2//3\n")
write("obj_two_vertex_face.obj", obj(TETRA_V, [(1, 3, 2), (1, 2)]))
write("obj_texcoord_none.obj", obj(TETRA_V, []) + "f 1/1 3/1 2/1\n")
write("obj_nan.obj", obj([(0, 0, 0), (1, "nan", 0)] + TETRA_V[2:], TETRA_F_1 := [tuple(i + 1 for i in f) for f in TETRA_F]))
write("obj_inf.obj", obj(TETRA_V[:3] + [(0, 0, "inf")], TETRA_F_1))
write("obj_no_faces.obj", obj(TETRA_V, []))
write("obj_zero_area.obj", obj([(0, 0, 0), (1, 0, 0), (2, 0, 0)], [(1, 2, 3), (1, 1, 2)]))
write("obj_huge_index.obj", obj(TETRA_V, [(1, 2, 4000000000)]))
# No mesh at all.
write("empty.obj", b"")
write("empty.ply", b"")
os.makedirs(os.path.join(HERE, "directory.obj"), exist_ok=True)
write(os.path.join("directory.obj", "README"), "A directory named like a mesh file: not a mesh.\n")
