#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks docs/schema/scene.schema.json against the scenes the project ships and against scenes
the parser refuses.

Every shipped scene (data/scenes/*.json, the scenes under data/compare/ and any scene under
examples/) must validate; each malformed scene listed below, which the parser refuses for a reason
the schema can express (a wrong type, a value out of range, an unknown or missing key), must be
refused by the schema too. Usage: validate_scenes.py [SOURCE_DIR]
"""
import json
import pathlib
import sys

import jsonschema

# Malformed scenes of tests/data/malformed/scenes whose refusal is schema-level.
REFUSED = [
    "width_negative.json", "height_zero.json", "height_too_large.json", "width_fraction.json",
    "width_string.json", "irradiance_1e308.json", "point_position_huge.json",
    "irradiance_negative.json", "irradiance_zero.json", "beam_radius_negative.json",
    "color_negative.json", "direction_zero.json", "mesh_scale_negative.json", "gamma_zero.json",
    "cone_angle_zero.json", "cone_angle_180.json", "fov_180.json", "irradiance_string.json",
    "direction_two_numbers.json", "direction_object.json", "fill_holes_number.json",
    "mesh_file_number.json", "light_not_object.json", "lights_object.json", "lights_empty.json",
    "top_level_array.json", "top_level_string.json", "technique_setting_array.json",
    "technique_string.json", "color_two_values.json", "unknown_top_key.json",
    "unknown_light_key.json", "unknown_camera_key.json", "unknown_light_type.json",
    "missing_lights.json", "missing_mesh.json", "missing_camera_position.json",
    "preset_and_sigma.json", "model_empty.json", "gamma_tiny.json", "exposure_1000.json",
]


def is_scene(doc):
    return isinstance(doc, dict) and "mesh" in doc and "camera" in doc


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parents[2])
    schema = json.loads((root / "docs/schema/scene.schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    failures = []

    shipped = sorted(root.glob("data/scenes/*.json")) + sorted(root.glob("data/compare/**/*.json")) \
        + sorted(root.glob("examples/**/*.json"))
    count = 0
    for path in shipped:
        doc = json.loads(path.read_text())
        if not is_scene(doc):
            continue
        count += 1
        errors = sorted(validator.iter_errors(doc), key=lambda e: list(e.absolute_path))
        for e in errors[:3]:
            where = "/".join(str(p) for p in e.absolute_path) or "(top level)"
            failures.append(f"{path.relative_to(root)}: {where}: {e.message}")
    if count == 0:
        failures.append("no shipped scene found")

    malformed = root / "tests/data/malformed/scenes"
    for name in REFUSED:
        path = malformed / name
        try:
            doc = json.loads(path.read_text())
        except (OSError, ValueError) as e:
            failures.append(f"{path.relative_to(root)}: cannot read: {e}")
            continue
        if validator.is_valid(doc):
            failures.append(f"{path.relative_to(root)}: the parser refuses it, the schema accepts it")

    for f in failures:
        print("FAIL:", f)
    print(f"{count} shipped scenes validated, {len(REFUSED)} malformed scenes refused"
          if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
