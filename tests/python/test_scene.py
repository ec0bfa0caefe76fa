# SPDX-License-Identifier: GPL-3.0-or-later
"""Scenes (load, edit, save) and the mesh path tracer against `translucent pathtrace mesh`."""
import json

import numpy as np
import pytest

import translucent
from test_reference import read_exr_layers


@pytest.fixture
def cube(source_dir):
    return source_dir / "data" / "scenes" / "cube.json"


def test_round_trip_is_the_same_json(cube, tmp_path):
    s = translucent.Scene.load(cube)
    text = s.to_json()
    assert translucent.Scene.from_json(text).to_json() == text
    out = tmp_path / "saved.json"
    s.save(out)
    assert out.read_text().strip() == text.strip()
    assert translucent.Scene.load(out).to_json() == text
    assert json.loads(text) == s.to_dict()


def test_edit_through_dict_and_properties(cube):
    s = translucent.Scene.load(cube)
    d = s.to_dict()
    d["material"]["preset"] = "Skin1"
    d["camera"]["width"] = 64
    e = translucent.Scene.from_dict(d)
    assert e.width == 64
    assert e.medium.sigma_a.tolist() == translucent.preset("Skin1").medium(scale=10).sigma_a.tolist()
    e.technique = "tsm"
    e.settings = {"shadow_map_size": 512, "flag": True}  # an int is a number, not a bool
    e.height = 48
    again = translucent.Scene.from_json(e.to_json())
    assert again.technique == "tsm" and again.height == 48
    assert again.settings == {"shadow_map_size": 512.0, "flag": True}
    assert type(again.settings["shadow_map_size"]) is float


def test_bad_scene_same_message_as_cli(cli_error, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"mesh": {"file": "/usr/share/glmark2/models/bunny.obj"}, "materiel": {}}')
    expected = cli_error("pathtrace", "mesh", "--scene", bad, "--exr", tmp_path / "x.exr")
    with pytest.raises(ValueError) as e:
        translucent.Scene.load(bad)
    assert str(e.value) == expected
    assert "materiel" in str(e.value)


def test_deeply_nested_json_is_a_value_error():
    # 10^5 nested brackets: refused by the depth limit with a message, not a stack overflow.
    deep = "[" * 100_000 + "]" * 100_000
    with pytest.raises(ValueError, match="nest"):
        translucent.Scene.from_json(deep)
    with pytest.raises(ValueError, match="nest"):
        translucent.Scene.from_json('{"mesh": ' + deep + "}")


def test_pathtrace_mesh_matches_cli(cli, cube, tmp_path):
    exr, js = tmp_path / "m.exr", tmp_path / "m.json"
    cli("pathtrace", "mesh", "--scene", cube, "--photons", "2e4", "--seed", "3", "--device", "cpu",
        "--exr", exr, "--json", js)
    d = translucent.pathtrace_mesh(str(cube), photons=2e4, seed=3, device="cpu")
    layers = read_exr_layers(exr)
    for key in ["exitance", "exitance_stderr", "radiance", "cone_radiance_stderr"]:
        assert d[key].shape == (120, 160, 3) and d[key].dtype == np.float32
        assert np.array_equal(d[key], layers[key]), key
    with open(js) as f:
        expected = json.load(f)
    for key in ["triangles", "photons_per_channel", "scattering_events", "flux_per_channel",
                "median_relative_stderr", "reference_key", "partial", "device"]:
        assert d[key] == expected[key], key
    # A Scene object gives the same as its file.
    s = translucent.pathtrace_mesh(translucent.Scene.load(cube), photons=2e4, seed=3, device="cpu")
    assert np.array_equal(s["exitance"], d["exitance"])


def test_pathtrace_mesh_camera_method_matches_cli(cli, cube, tmp_path):
    # method="camera": `pathtrace mesh --method camera`, bit for bit (the cube is eta 1.3: its
    # refracted connections and light-traced complement), and its exitance agrees with the light
    # method's within the errors.
    exr, js = tmp_path / "c.exr", tmp_path / "c.json"
    cli("pathtrace", "mesh", "--scene", cube, "--method", "camera", "--samples", "4", "--seed", "5",
        "--exr", exr, "--json", js)
    d = translucent.pathtrace_mesh(str(cube), method="camera", samples=4, seed=5)
    layers = read_exr_layers(exr)
    for key in ["exitance", "cone_radiance", "cone_radiance_stderr", "radiance"]:
        assert np.array_equal(d[key], layers[key]), key
    with open(js) as f:
        expected = json.load(f)
    for key in ["samples_per_pixel", "paths", "shadow_rays", "complement_photons",
                "complement_cone_angle", "triangles", "median_relative_stderr"]:
        assert d[key] == expected[key], key
    assert d["method"] == "camera" and d["complement_photons"] > 0
    light = translucent.pathtrace_mesh(str(cube), photons=2e5, seed=6, device="cpu")
    a, b = d["exitance"].mean(), light["exitance"].mean()
    se = np.hypot(np.sqrt((d["exitance_stderr"] ** 2).sum()), np.sqrt((light["exitance_stderr"] ** 2).sum())) / d["exitance"].size
    assert abs(a - b) < 3.5 * se, (a, b, se)
    with pytest.raises(ValueError, match="photons: the camera method"):
        translucent.pathtrace_mesh(str(cube), method="camera", photons=1e4)
    with pytest.raises(ValueError, match="method='x'"):
        translucent.pathtrace_mesh(str(cube), method="x")


def test_pathtrace_mesh_camera_method_on_the_gpu_matches_cli(cli, cube, tmp_path):
    # method="camera", device="gpu": the GL camera walk (here through the cube's refractive
    # boundary, eta 1.3: its refracted connections on the device, the light-traced complement on
    # the CPU), bit for bit with `pathtrace mesh --method camera --device gpu`.
    d = json.loads(translucent.Scene.load(cube).to_json())
    d["mesh"]["file"] = str((cube.parent / d["mesh"]["file"]).resolve())
    d["camera"]["width"], d["camera"]["height"] = 32, 24
    small = tmp_path / "small.json"
    small.write_text(json.dumps(d))
    exr, js = tmp_path / "g.exr", tmp_path / "g.json"
    cli("pathtrace", "mesh", "--scene", small, "--method", "camera", "--samples", "2",
        "--seed", "3", "--device", "gpu", "--exr", exr, "--json", js)
    r = translucent.pathtrace_mesh(str(small), method="camera", samples=2, seed=3, device="gpu")
    layers = read_exr_layers(exr)
    for key in ["exitance", "cone_radiance", "cone_radiance_stderr", "radiance"]:
        assert np.array_equal(r[key], layers[key]), key
    with open(js) as f:
        expected = json.load(f)
    for key in ["device", "samples_per_pixel", "paths", "shadow_rays", "scattering_events",
                "complement_photons"]:
        assert r[key] == expected[key], key
    assert r["device"].startswith("gpu (") and r["exitance"].sum() > 0
    assert r["complement_photons"] > 0


def test_pathtrace_mesh_on_the_gpu_matches_cli(cli, cube, tmp_path):
    # device="gpu": the GL walk of `pathtrace mesh --device gpu` (its own Philox streams), bit for
    # bit, with the GPU's reference key (another estimate than the CPU's, cached apart).
    exr, js = tmp_path / "g.exr", tmp_path / "g.json"
    cli("pathtrace", "mesh", "--scene", cube, "--photons", "1e4", "--seed", "4", "--device", "gpu",
        "--exr", exr, "--json", js)
    d = translucent.pathtrace_mesh(str(cube), photons=1e4, seed=4, device="gpu")
    layers = read_exr_layers(exr)
    for key in ["exitance", "radiance_stderr", "cone_radiance"]:
        assert np.array_equal(d[key], layers[key]), key
    with open(js) as f:
        expected = json.load(f)
    for key in ["device", "reference_key", "flux_per_channel", "scattering_events"]:
        assert d[key] == expected[key], key
    assert d["device"].startswith("gpu (")
    cpu = translucent.pathtrace_mesh(str(cube), photons=1e4, seed=4, device="cpu")
    assert cpu["reference_key"] != d["reference_key"]
    with pytest.raises(ValueError, match="device 'tpu': expected cpu, gpu or auto"):
        translucent.pathtrace_mesh(str(cube), photons=1e4, device="tpu")
