#!/usr/bin/env python3
"""Writes the malformed-input corpus beyond meshes (issue #15 §8): scenes/, bssrdf/, images/ and
caches/, each with manifest.txt ("FILE EXPECTED MESSAGE TEXT"), replayed by tests/inputs.

The cache, EXR and VDB seeds (caches/valid_*, images/valid.exr, scenes/assets/*.vdb, ...) come
from a built tool:
    build/release/tests/inputs/translucent_check_input write-seeds /tmp/seeds
    python3 tests/data/malformed/generate_inputs.py /tmp/seeds
Each file is written once, here, from a description of what is wrong with it; the expected text
is what the error must say about that (the file, the key or line, the value, what was expected).
"""
import json
import os
import shutil
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SEEDS = sys.argv[1] if len(sys.argv) > 1 else None


def write(path, data):
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def manifest(folder, header, entries):
    lines = [f"# {l}" if l else "#" for l in header] + [""]
    for name, expected in entries:
        assert os.path.exists(os.path.join(HERE, folder, name)), name
        lines.append(f"{name} {expected}")
    write(os.path.join(HERE, folder, "manifest.txt"), "\n".join(lines) + "\n")


# ---- Scenes ------------------------------------------------------------------------------------
BASE = {"mesh": {"file": "assets/tetra.obj"}, "material": {"preset": "Marble"},
        "lights": [{"type": "directional", "direction": [0, 0, 1]}],
        "camera": {"position": [0, 0, 5]}}


def scene(**changes):
    s = json.loads(json.dumps(BASE))
    for path, value in changes.items():
        keys = path.split("__")
        obj = s
        for k in keys[:-1]:
            obj = obj[int(k)] if isinstance(obj, list) else obj[k]
        last = keys[-1]
        if value is DELETE:
            del obj[last]
        elif isinstance(obj, list):
            obj[int(last)] = value
        else:
            obj[last] = value
    return json.dumps(s)


DELETE = object()
scenes = []


def sc(name, text, expected):
    write(os.path.join(HERE, "scenes", name), text)
    scenes.append((name, expected))


RANGE = "expected a whole number in [1, 16384]"
MAG = "expected a finite number of magnitude at most 1e+15"
# Integers that do not fit: 4294967360 was read as 64 (j.get<int>() truncates).
sc("width_2pow32_plus_64.json", scene(camera__width=4294967360), f"camera.width: is 4294967360: {RANGE}")
sc("width_uint64_max.json", scene(camera__width=18446744073709551615), f"camera.width: is 18446744073709551615: {RANGE}")
sc("width_negative.json", scene(camera__width=-64), f"camera.width: is -64: {RANGE}")
sc("height_zero.json", scene(camera__height=0), f"camera.height: is 0: {RANGE}")
sc("height_too_large.json", scene(camera__height=16385), f"camera.height: is 16385: {RANGE}")
sc("width_fraction.json", scene(camera__width=64.5), f"camera.width: number 64.5: {RANGE}")
sc("width_string.json", scene(camera__width="64"), f'camera.width: string "64": {RANGE}')
# Finite numbers that overflow the float pipeline (1e308 irradiance gave inf, then NaN pixels).
sc("irradiance_1e308.json", scene(lights__0__irradiance=1e308), f"lights[0].irradiance: is 1e+308: {MAG}")
sc("second_light_irradiance_1e300.json",
   scene(lights=[BASE["lights"][0], {"type": "directional", "direction": [0, 1, 0], "irradiance": 1e300}]),
   f"lights[1].irradiance: is 1e+300: {MAG}")
sc("point_position_huge.json", scene(lights=[{"type": "point", "position": [1e300, 0, 0]}]),
   f"lights[0].position[0]: is 1e+300: {MAG}")
sc("intensity_1e20.json", scene(lights=[{"type": "point", "position": [0, 0, 3], "intensity": 1e20}]),
   f"lights[0].intensity: is 1e+20: {MAG}")
sc("camera_position_huge.json", scene(camera__position=[0, 0, 1e200]), f"camera.position[2]: is 1e+200: {MAG}")
sc("mesh_rotate_huge.json", scene(mesh__rotate=[1e16, 0, 0]), f"mesh.rotate[0]: is 1e+16: {MAG}")
sc("exposure_huge.json", scene(display={"exposure": 1e300}), f"display.exposure: is 1e+300: {MAG}")
sc("irradiance_overflow_1e999.json", scene().replace('"direction": [0, 0, 1]', '"direction": [0, 0, 1], "irradiance": 1e999'),
   "not valid JSON: the number 1e999 at line 1, column 147 (lights[0].irradiance) is beyond the range of a double")
sc("nan_literal.json", scene().replace("[0, 0, 1]", "[0, 0, NaN]"), "not valid JSON")
# Out of range.
sc("irradiance_negative.json", scene(lights__0__irradiance=-1), "lights[0].irradiance: is -1: expected a finite value > 0")
sc("irradiance_zero.json", scene(lights__0__irradiance=0), "lights[0].irradiance: is 0: expected a finite value > 0")
sc("beam_radius_negative.json", scene(lights=[{"type": "beam", "origin": [0, 0, 3], "direction": [0, 0, -1], "radius": -0.5}]),
   "lights[0].radius: is -0.5: expected >= 0")
sc("color_negative.json", scene(lights__0__color=[1, -1, 1]), "lights[0].color: green is -1: expected a value >= 0")
sc("direction_zero.json", scene(lights__0__direction=[0, 0, 0]), "lights[0].direction: is [0, 0, 0]: expected a non-zero finite direction")
sc("mesh_scale_negative.json", scene(mesh__scale=-2), "mesh.scale: is -2: expected a finite value > 0")
sc("gamma_zero.json", scene(display={"gamma": 0}), "display.gamma: is 0: expected a finite value > 0")
sc("cone_angle_zero.json", scene(cone_angle=0), "cone_angle: is 0: expected degrees in (0, 90]")
sc("cone_angle_180.json", scene(cone_angle=180), "cone_angle: is 180: expected degrees in (0, 90]")
sc("fov_180.json", scene(camera__fov=180), "camera: fov is 180: expected degrees in [0.001, 179]")
sc("near_after_far.json", scene(camera__near=5, camera__far=1), "camera: near 5 and far 1: expected 0 (automatic) or 0 < near < far")
sc("camera_at_look_at.json", scene(camera__position=[0, 0, 0]), "camera: look_at equals position")
# Inside the object (the tetrahedron, normalised: its centroid is at [-0.25, -0.25, -0.25]): a
# camera or a light there renders black (issue 15 §1), refused by scene::requireOutsideMesh.
sc("camera_inside_mesh.json", scene(camera__position=[-0.25, -0.25, -0.25]),
   "camera.position [-0.25, -0.25, -0.25] is inside the mesh")
sc("point_light_inside_mesh.json",
   scene(lights=[{"type": "point", "position": [-0.3, -0.2, -0.25], "intensity": 1}]),
   "lights[0].position [-0.3, -0.2, -0.25] is inside the mesh")
sc("beam_origin_inside_mesh.json",
   scene(lights=[{"type": "beam", "origin": [-0.25, -0.25, -0.2], "direction": [0, 0, 1]}]),
   "lights[0].origin [-0.25, -0.25, -0.2] is inside the mesh")
sc("up_parallel.json", scene(camera__up=[0, 0, 1]), "camera: up is zero or parallel to the viewing direction")
sc("environment_intensity_negative.json",
   scene(lights=[{"type": "environment", "file": "assets/sky.exr", "intensity": -1}]),
   "lights[0].intensity: is -1: expected a finite value > 0")
# Wrong types.
sc("irradiance_string.json", scene(lights__0__irradiance="bright"), 'lights[0].irradiance: string "bright": expected a number')
sc("direction_two_numbers.json", scene(lights__0__direction=[0, 1]), "lights[0].direction: array [0,1]: expected an array of three numbers [x, y, z]")
sc("direction_object.json", scene(lights__0__direction={"x": 1}), "lights[0].direction: object {\"x\":1}: expected an array of three numbers")
sc("fill_holes_number.json", scene(mesh__fill_holes=1), "mesh.fill_holes: number 1: expected true or false")
sc("mesh_file_number.json", scene(mesh__file=3), "mesh.file: number 3: expected a string")
sc("light_not_object.json", scene(lights=[5]), "lights[0]: number 5: expected an object")
sc("lights_object.json", scene(lights={"type": "point"}), 'lights: object {"type":"point"}: expected a non-empty array')
sc("lights_empty.json", scene(lights=[]), "lights: array []: expected a non-empty array")
sc("top_level_array.json", "[1, 2, 3]", "top level: array [1,2,3]: expected an object")
sc("top_level_string.json", '"scene"', 'top level: string "scene": expected an object')
sc("technique_setting_array.json", scene(technique={"name": "pointcloud", "points": [1, 2]}),
   "technique.points: expected a number, true/false or a string")
sc("technique_string.json", scene(technique="pointcloud"), "technique: expected an object")
sc("color_two_values.json", scene(lights__0__color=[1, 1]), "lights[0].color: array [1,1]: expected a number or an array [r, g, b]")
# Unknown keys and missing ones.
sc("unknown_top_key.json", scene(lihgts=[]), "lihgts: unknown key; valid keys here are mesh, material")
sc("unknown_light_key.json", scene(lights__0__irradience=2), "lights[0].irradience: unknown key; valid keys here are type, direction, irradiance, color")
sc("unknown_camera_key.json", scene(camera__fov_y=30), "camera.fov_y: unknown key")
sc("unknown_light_type.json", scene(lights__0__type="spot"), "lights[0].type: 'spot': expected directional, point, beam, filtered_directional or environment")
sc("missing_lights.json", scene(lights=DELETE), "lights: required (an array of lights)")
sc("missing_mesh.json", scene(mesh=DELETE), "mesh: required")
sc("missing_camera_position.json", scene(camera={"fov": 30}), "camera.position: required")
sc("preset_and_sigma.json", scene(material={"preset": "Marble", "sigma_a": 1}), "material: give either \"preset\" or \"sigma_a\" and \"sigma_s\", not both")
sc("unknown_preset.json", scene(material={"preset": "Jelly"}), "material.preset: unknown preset 'Jelly'")
sc("sigma_a_negative.json", scene(material={"sigma_a": [-1, 0.1, 0.1], "sigma_s": 1}), "material: sigma_a (red channel) is -1: expected a non-negative coefficient")
# Files: missing, a directory, empty, binary.
sc("mesh_file_missing.json", scene(mesh__file="nowhere.obj"), "mesh.file: file 'nowhere.obj' not found; looked in")
sc("mesh_file_directory.json", scene(mesh__file="assets"), "assets' is a directory: expected a file")
sc("environment_file_missing.json", scene(lights=[{"type": "environment", "file": "nosky.exr"}]), "lights[0].file: file 'nosky.exr' not found")
sc("environment_file_corrupt.json", scene(lights=[{"type": "environment", "file": "assets/corrupt.exr"}]), "assets/corrupt.exr' cannot be read")
sc("texture_file_missing.json", scene(lights=[{"type": "filtered_directional", "direction": [0, 0, 1], "texture": "glass.png"}]),
   "lights[0].texture: file 'glass.png' not found")
sc("model_bssrdf_missing.json", scene(material={"preset": "Marble", "model": "assets/none.bssrdf"}), "none.bssrdf: error: cannot open the file for reading")
sc("model_bssrdf_broken.json", scene(material={"preset": "Marble", "model": "assets/broken.bssrdf"}), "broken.bssrdf:1: error: missing attribute 'analytic'")
sc("model_empty.json", scene(material={"preset": "Marble", "model": ""}), "material.model: expected a model name or a .bssrdf file")
# Nesting deeper than the reader's limit: refused with the place instead of overflowing the stack.
sc("deeply_nested.json", '{"mesh": ' + "[" * 20000 + "]" * 20000 + "}",
   "not valid JSON: arrays and objects nest deeper than 512 levels (at line 1, column")
# Lights that light nothing: black, or so faint that every pixel is 0 in a 32-bit image.
sc("black_light.json", scene(lights__0__color=[0, 0, 0]), "lights[0].color: is [0, 0, 0]: the light emits nothing")
sc("faint_light.json", scene(lights__0__irradiance=1e-40), "irradiance 1e-40 times red 1 is 1e-40: expected at least")
# Display settings that map every pixel to black or white.
sc("gamma_tiny.json", scene(display={"gamma": 1e-300}), "display.gamma: is 1e-300: expected a display gamma in [0.01, 100]")
sc("exposure_1000.json", scene(display={"exposure": 1000}), "display.exposure: is 1000: expected stops in [-64, 64]")
sc("empty.json", "", "is empty: expected a JSON object")
sc("whitespace_only.json", " \n\t\n", "is empty: expected a JSON object")
sc("binary_garbage.json", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", "byte 8 is NUL: expected a JSON text file")
sc("truncated.json", scene()[:40], "not valid JSON")
sc("trailing_comma.json", scene().replace("}}", "},}", 1), "not valid JSON")
os.makedirs(os.path.join(HERE, "scenes", "directory.json"), exist_ok=True)
write(os.path.join(HERE, "scenes", "directory.json", "README"), "A folder named like a scene file (the corpus entry is the folder).\n")
scenes.append(("directory.json", "is a folder: expected a file"))
write(os.path.join(HERE, "scenes", "assets", "broken.bssrdf"), "radial\n::begin shader\n::end shader\n")
write(os.path.join(HERE, "scenes", "assets", "corrupt.exr"), b"v/1\x01\x02\x00\x00\x00garbage after the EXR magic")
# Voxel grids that neither absorb nor scatter outside the voxels set (written by write-seeds with
# OpenVDB): `pathtrace mesh` never finished on such a medium.
if SEEDS:
    shutil.copy(os.path.join(SEEDS, "zero_background.vdb"), os.path.join(HERE, "scenes", "assets", "zero_background.vdb"))
if os.path.exists(os.path.join(HERE, "scenes", "assets", "zero_background.vdb")):
    sc("voxels_zero_background.json",
       scene(material={"type": "voxels", "file": "assets/zero_background.vdb", "sigma_a": "sigma_a", "sigma_s": "sigma_s"}),
       "zero_background.vdb', grids 'sigma_a' and 'sigma_s'): sigma_a is 0 and sigma_s' is 0 in channel red at the background")
manifest("scenes", ["The malformed-scene corpus: FILE, then the text its error must contain (literally); the",
                    "message must also name the file (tests/inputs/check_malformed_input.cmake). Files it",
                    "names are under assets/. Regenerate with ../generate_inputs.py."], scenes)

# ---- .bssrdf files ---------------------------------------------------------------------------
SHADER = "::begin shader\nvec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) { return vec3(1.0); }\n::end shader\n"
GOOD = "analytic radial no_wi no_wo\n" + SHADER
bssrdfs = []


def bs(name, text, expected):
    write(os.path.join(HERE, "bssrdf", name), text)
    bssrdfs.append((name, expected))


def params(*lines):
    return "analytic radial\n::begin parameters\n" + "".join(l + "\n" for l in lines) + "::end parameters\n" + SHADER


bs("empty.bssrdf", "", "error: empty file: expected the attribute list")
bs("blank_first_line.bssrdf", "\n" + SHADER, ":1: error: expected the attribute list (e.g. 'analytic radial no_wi no_wo') on line 1, found an empty line")
bs("no_analytic.bssrdf", "radial no_wi\n" + SHADER, ":1: error: missing attribute 'analytic'")
bs("unknown_attribute.bssrdf", "analytic spherical\n" + SHADER, ":1: error: unknown attribute 'spherical'")
bs("section_first.bssrdf", SHADER, ":1: error: expected the attribute list")
bs("no_shader.bssrdf", "analytic\n::begin initializer\nvoid init() {}\n::end initializer\n", "error: missing section 'shader'")
bs("missing_end.bssrdf", "analytic\n::begin shader\nvec3 Bssrdf(vec3 a, vec3 b, vec3 c, vec3 d) { return a; }\n",
   ":2: error: unterminated section 'shader': expected '::end shader' before the end of the file")
bs("missing_end_before_begin.bssrdf", "analytic\n::begin initializer\nvoid init() {}\n" + SHADER,
   ":2: error: unterminated section 'initializer': expected '::end initializer' before '::begin shader' at line 4")
bs("end_wrong_name.bssrdf", "analytic\n::begin shader\nvec3 Bssrdf() {}\n::end shadr\n", ":4: error: '::end shadr' does not close the open section")
bs("end_without_begin.bssrdf", "analytic\n::end shader\n" + SHADER, ":2: error: '::end shader' without a matching '::begin'")
bs("unknown_directive.bssrdf", "analytic\n::include common.glsl\n" + SHADER, ":2: error: malformed section marker '::include common.glsl'")
bs("begin_without_name.bssrdf", "analytic\n::begin\n" + SHADER, ":2: error: section without a name: expected '::begin NAME'")
bs("begin_two_names.bssrdf", "analytic\n::begin shader extra\n::end\n", ":2: error: malformed section marker '::begin shader extra'")
bs("duplicate_section.bssrdf", GOOD + SHADER.replace("::begin", "\n::begin"), "error: duplicate section 'shader' (first begun at line 2)")
bs("text_outside.bssrdf", "analytic\nvec3 x;\n" + SHADER, ":2: error: text outside a section")
bs("param_unknown_type.bssrdf", params("int Count 0 10 5"), ":3: error: malformed parameter line 'int Count 0 10 5': unknown type 'int'")
bs("param_too_few.bssrdf", params("float Scale 0 1"), ":3: error: malformed parameter line 'float Scale 0 1': expected 'float NAME MIN MAX DEFAULT' (5 fields, found 4)")
bs("param_nan.bssrdf", params("float Scale 0 nan 1"), ":3: error: malformed parameter line 'float Scale 0 nan 1': maximum 'nan' is not a finite number")
bs("param_inf.bssrdf", params("float Scale -inf 1 0"), "minimum '-inf' is not a finite number")
bs("param_huge.bssrdf", params("float Scale 0 1e39 1"), ":3: error: malformed parameter line 'float Scale 0 1e39 1': maximum '1e39' is not a finite number that fits a float")
bs("param_overflow.bssrdf", params("float Scale 0 1e400 1"), "maximum '1e400' is not a finite number that fits a float")
bs("param_color_huge.bssrdf", params("color Tint 1 1e300 1"), "green '1e300' is not a finite number that fits a float")
bs("param_not_number.bssrdf", params("float Scale 0 ten 1"), "maximum 'ten' is not a finite number")
bs("param_min_gt_max.bssrdf", params("float Scale 2 1 1"), ":3: error: parameter 'Scale': minimum 2 is larger than maximum 1")
bs("param_default_outside.bssrdf", params("float Scale 0 1 5"), ":3: error: parameter 'Scale': default 5 is outside [0, 1]")
bs("param_bool_bad.bssrdf", params("bool Clamp yes"), "default 'yes' is not a boolean (expected true, false, 1 or 0)")
bs("param_bad_name.bssrdf", params("float 2x 0 1 0"), "parameter name '2x' is not a valid GLSL identifier")
bs("param_gl_name.bssrdf", params("float gl_Scale 0 1 0"), "parameter name 'gl_Scale' is not a valid GLSL identifier")
bs("param_reserved.bssrdf", params("float SigmaA 0 1 0"), ":3: error: parameter name 'SigmaA' is reserved")
bs("param_duplicate.bssrdf", params("float S 0 1 0", "bool S true"), ":4: error: duplicate parameter 'S' (first declared at line 3)")
bs("binary_garbage.bssrdf", b"\x7fELF\x02\x01\x01\x00\x00\x00\x00", ":1: error: byte 4 is 0x02, a control character: expected a text file (binary data?)")
bs("nul_in_shader.bssrdf", GOOD.replace("return", "re\x00turn"), ":3: error: byte 95 is 0x00, a control character")
bs("truncated_in_section.bssrdf", GOOD[:60], ":2: error: unterminated section 'shader'")
os.makedirs(os.path.join(HERE, "bssrdf", "directory.bssrdf"), exist_ok=True)
write(os.path.join(HERE, "bssrdf", "directory.bssrdf", "README"), "A folder named like a .bssrdf file (the corpus entry is the folder).\n")
bssrdfs.append(("directory.bssrdf", "error: is a folder: expected a .bssrdf text file"))
manifest("bssrdf", ["The malformed-.bssrdf corpus: FILE, then the text its BssrdfFileError must contain",
                    "(literally), 'PATH:LINE: error: ...'. Regenerate with ../generate_inputs.py."], bssrdfs)

# ---- Images (environment maps) ------------------------------------------------------------------
images = []


def im(name, data, expected):
    write(os.path.join(HERE, "images", name), data)
    images.append((name, expected))


def hdr(width, height, pixels, header_size=None):
    size = header_size or f"-Y {height} +X {width}"
    return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + size.encode() + b"\n" + pixels


def png(width, height, raw, color_type=2, crc_ok=True):
    def chunk(kind, body):
        crc = zlib.crc32(kind + body) & 0xffffffff
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", crc if crc_ok else crc ^ 1)
    ihdr = struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


rgbe = bytes([128, 128, 128, 129]) * 16
im("empty.hdr", b"", "the file is empty: expected an image")
im("empty.exr", b"", "the file is empty: expected an image")
im("text_as_exr.exr", "this is not an image\n", "is not an OpenEXR file")
im("hdr_header_only.hdr", hdr(4, 4, b""), "Read error reading pixels on scanline 0")
im("hdr_truncated_pixels.hdr", hdr(4, 4, rgbe[:20]), "Read error reading pixels on scanline 1")
im("hdr_zero_width.hdr", hdr(0, 4, b""), "image size 0x4: expected at least 1x1 and at most 268435456 pixels")
im("hdr_huge_size.hdr", hdr(2000000000, 2000000000, rgbe), "image size 2000000000x2000000000: expected at least 1x1")
im("hdr_negative_size.hdr", hdr(4, 4, rgbe, "-Y -4 +X 4"), "image size 4x-4: expected at least 1x1")
im("hdr_one_column.hdr", hdr(1, 16, rgbe), "is 1x16: expected a latitude-longitude image of at least 2x1 pixels")
im("png_bad_crc.png", png(4, 2, b"\x00" + b"\x80" * 12 + b"\x00" + b"\x80" * 12, crc_ok=False), "PNG read error: IHDR: CRC error")
im("png_truncated.png", png(4, 2, b"\x00" + b"\x80" * 12 + b"\x00" + b"\x80" * 12)[:40], "Read error: hit end of file")
im("png_gray.png", png(4, 2, b"\x00" + b"\x80" * 4 + b"\x00" + b"\x80" * 4, color_type=0), "1 channel(s): expected at least R, G, B")
im("png_zero_size.png", png(0, 0, b""), "PNG read error: Invalid IHDR data")
im("png_short_idat.png", png(4, 2, b"\x00\x80\x80"), "PNG read error: Not enough image data")
im("garbage.png", bytes(range(256)) * 4, "Not a PNG file")
# An attribute whose declared size runs past the end of the file (fuzz_image found that OpenEXR
# allocates the declared size first: 1.9 GB for a 402-byte file); refused before OpenEXR reads it.
im("exr_attribute_past_eof.exr",
   b"\x76\x2f\x31\x01\x02\x00\x00\x00" + b"capDate\x00string\x00" + struct.pack("<i", 0x74000000) + b"x" * 16,
   "OpenEXR header attribute 'capDate' (string) declares 1946157056 bytes, more than the 16 left in the file")
os.makedirs(os.path.join(HERE, "images", "directory.exr"), exist_ok=True)
write(os.path.join(HERE, "images", "directory.exr", "README"), "A folder named like an image (the corpus entry is the folder).\n")
images.append(("directory.exr", "it is a directory: expected an image file"))
if SEEDS:
    valid = open(os.path.join(SEEDS, "valid.exr"), "rb").read()
    im("exr_truncated_half.exr", valid[:len(valid) // 2], "OpenEXR exception: Cannot read image file")
    im("exr_truncated_header.exr", valid[:60], "OpenEXR exception: Cannot read image file")
    im("exr_bad_magic.exr", b"\x00\x00\x00\x00" + valid[4:], "is not an OpenEXR file")
    # Bytes flipped in the middle of the pixel data: zip-compressed chunks fail to inflate.
    flipped = bytearray(valid)
    for i in range(len(valid) - 40, len(valid) - 20):
        flipped[i] ^= 0xff
    im("exr_corrupt_pixels.exr", bytes(flipped), "OpenEXR exception: Cannot read image file")
    shutil.copy(os.path.join(SEEDS, "nan.exr"), os.path.join(HERE, "images", "nan_texel.exr"))
    images.append(("nan_texel.exr", "pixel 1 holds nan: expected finite radiance"))
    shutil.copy(os.path.join(SEEDS, "inf.exr"), os.path.join(HERE, "images", "inf_texel.exr"))
    images.append(("inf_texel.exr", "pixel 13 holds inf: expected finite radiance"))
    shutil.copy(os.path.join(SEEDS, "negative.exr"), os.path.join(HERE, "images", "negative_texel.exr"))
    images.append(("negative_texel.exr", "warning: environment map '"))
    shutil.copy(os.path.join(SEEDS, "one_pixel.exr"), os.path.join(HERE, "images", "one_pixel.exr"))
    images.append(("one_pixel.exr", "is 1x1: expected a latitude-longitude image of at least 2x1 pixels"))
    shutil.copy(os.path.join(SEEDS, "valid.exr"), os.path.join(HERE, "scenes", "assets", "sky.exr"))
manifest("images", ["The malformed-image corpus (environment maps, EnvironmentMap::load): FILE, then the",
                    "text its error (or warning) must contain. Regenerate with ../generate_inputs.py SEEDS."], images)

# ---- Cache files --------------------------------------------------------------------------------
if SEEDS:
    caches = []

    def ca(name, data, expected):
        write(os.path.join(HERE, "caches", name), data)
        caches.append((name, expected))

    ply = open(os.path.join(SEEDS, "valid_pointcloud.ply"), "rb").read()
    body = ply.index(b"end_header\n") + len(b"end_header\n")
    HASH = "(its header): the file was changed or truncated); resampled"
    ca("pc_truncated.ply", ply[:-100], HASH)
    ca("pc_truncated_header.ply", ply[:body - 20], "has no PLY header")
    ca("pc_empty.ply", b"", "has no PLY header")
    ca("pc_appended.ply", ply + b"\x00" * 28, HASH)
    t = bytearray(ply); t[body + 5] ^= 0x01
    ca("pc_one_bit_flipped.ply", bytes(t), HASH)
    t = bytearray(ply); t[body:body + 4] = struct.pack("<f", 1e30)
    ca("pc_position_edited.ply", bytes(t), HASH)
    t = bytearray(ply); t[body + 24:body + 28] = struct.pack("<f", float("nan"))
    ca("pc_area_nan.ply", bytes(t), HASH)
    i = ply.index(b"comment content_hash ")
    ca("pc_no_hash.ply", ply[:i] + ply[ply.index(b"\n", i) + 1:], "has no 'content_hash' header comment")
    ca("pc_hash_malformed.ply", ply.replace(ply[i:ply.index(b"\n", i)], b"comment content_hash xyz"), "expected 'content_hash <16 hex digits>'")
    hexhash = ply[i + len(b"comment content_hash "):ply.index(b"\n", i)]
    ca("pc_hash_edited.ply", ply.replace(hexhash, b"0" * 16), HASH)
    ca("pc_count_lies.ply", ply.replace(b"element vertex 64", b"element vertex 6400"), HASH)
    ca("pc_header_edited.ply", ply.replace(b"property float nx\nproperty float ny", b"property float ny\nproperty float nx"), HASH)
    ca("pc_garbage.ply", bytes(range(256)) * 8, "has no PLY header")
    atlas = open(os.path.join(SEEDS, "valid_atlas.bin"), "rb").read()
    AH = "(stored at its end): the file was changed or truncated); rebuilt"
    ca("atlas_truncated.bin", atlas[:-50], AH)
    ca("atlas_truncated_to_magic.bin", atlas[:10], "is truncated: 10 bytes")
    ca("atlas_empty.bin", b"", "is not an atlas cache file")
    t = bytearray(atlas); t[len(atlas) // 2] ^= 0x10
    ca("atlas_uv_edited.bin", bytes(t), AH)
    t = bytearray(atlas); t[8:12] = struct.pack("<I", 1)
    ca("atlas_old_version.bin", bytes(t), "has version 1, expected 2")
    t = bytearray(atlas); t[-1] ^= 0xff
    ca("atlas_hash_edited.bin", bytes(t), AH)
    ca("atlas_appended.bin", atlas + b"\x00" * 8, AH)
    ca("atlas_garbage.bin", bytes(range(256)) * 8, "is not an atlas cache file")
    manifest("caches", ["The malformed-cache corpus: FILE as the cache entry of a fixed mesh and sampling",
                        "(translucent_check_input); each must be regenerated with a note containing the text,",
                        "never used. *.ply: point-cloud cache, *.bin: atlas cache. Regenerate with",
                        "../generate_inputs.py SEEDS."], caches)
print(f"scenes {len(scenes)}, bssrdf {len(bssrdfs)}, images {len(images)}")
