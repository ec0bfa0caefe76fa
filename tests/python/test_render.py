# SPDX-License-Identifier: GPL-3.0-or-later
"""Techniques and compare against `translucent render --exr` and `translucent compare`'s
report.json (headless GL: Mesa llvmpipe without a GPU)."""
import json

import numpy as np
import pytest

import translucent
from test_reference import read_exr_layers


@pytest.fixture
def cube(source_dir):
    return source_dir / "data" / "scenes" / "cube.json"


def test_techniques_listed():
    names = translucent.techniques()
    assert "pointcloud" in names and "empirical" in names
    params = {p["name"]: p for p in translucent.technique_parameters("pointcloud")}
    assert params["points"]["type"] == "int" and params["points"]["min"] >= 1
    assert params["epsilon"]["sweep"], "epsilon is pointcloud's quality parameter"


@pytest.mark.parametrize("technique,settings,cli_args", [
    ("empirical", {}, []),
    ("pointcloud", {"points": 20000, "epsilon": 0.2}, ["--points", "20000", "--epsilon", "0.2"]),
])
def test_render_matches_cli_exr(cli, cube, tmp_path, technique, settings, cli_args):
    exr = tmp_path / "r.exr"
    cli("render", cube, "--technique", technique, "--width", 80, "--height", 60,
        *cli_args, "--exr", exr)
    out = translucent.render(str(cube), technique, width=80, height=60, **settings)
    img = out["image"]
    assert img.shape == (60, 80, 3) and img.dtype == np.float32 and img.flags["C_CONTIGUOUS"]
    layers = read_exr_layers(exr)
    # The same library calls on the same GL implementation: the same pixels.
    assert np.array_equal(img, layers[""])
    for name, layer in out["layers"].items():
        assert layer.shape == (60, 80, 3)
        assert np.array_equal(layer, layers[name]), name
    assert out["passes"] and all(p["ms"] >= 0 for p in out["passes"])
    assert out["total_ms"] == pytest.approx(sum(p["ms"] for p in out["passes"] if p["depth"] == 0))
    assert img.max() > 0, "the lit cube is not black"


def test_renderer_keeps_technique_and_changes_settings(cube):
    r = translucent.Renderer(translucent.Scene.load(cube), "pointcloud", width=64, height=48,
                             points=20000)
    a = r.render()["image"]
    r.set(epsilon=0.8)
    b = r.render()["image"]
    assert r.parameters["epsilon"] == 0.8 and r.parameters["points"] == 20000
    assert not np.array_equal(a, b), "a coarser epsilon changes the image"
    r.set(epsilon=translucent.Renderer(cube, "pointcloud").parameters["epsilon"])
    assert np.array_equal(r.render()["image"], a)


def test_render_errors_same_message_as_cli(cli_error, as_python, cube, tmp_path):
    expected = cli_error("render", cube, "--technique", "pointcloud", "--points", "-3",
                         "--exr", tmp_path / "x.exr")
    # A setting given as text is taken as the CLI takes it: the same message.
    with pytest.raises(ValueError) as e:
        translucent.render(str(cube), "pointcloud", points="-3")
    assert str(e.value) == as_python(expected)
    # As a number, the message names the number (not quoted as text).
    with pytest.raises(ValueError) as e:
        translucent.render(str(cube), "pointcloud", points=-3)
    assert str(e.value) == as_python(expected).replace("'-3'", "-3")
    expected = cli_error("render", cube, "--technique", "nope", "--exr",
                         tmp_path / "x.exr")
    with pytest.raises(ValueError) as e:
        translucent.render(str(cube), "nope")
    assert str(e.value) == as_python(expected)


def test_compare_matches_cli_report(cli, cube, tmp_path):
    out = tmp_path / "report"
    cli("compare", cube, "--techniques", "empirical", "--photons", "2e4", "--samples", "2000",
        "--frames", "1", "--warmup", "0", "--no-cache", "--width", "64", "--height", "48",
        "--out", out)
    with open(out / "report.json") as f:
        expected = json.load(f)
    got = translucent.compare(str(cube), techniques=["empirical"], photons=2e4, samples=2000,
                              frames=1, warmup=0, cache=False, width=64, height=48,
                              out=tmp_path / "py-report")
    assert (tmp_path / "py-report" / "index.html").is_file()
    # Metrics, masks, scene: the same numbers (same references, same frames).
    for key in ["metrics", "masks", "scene", "material"]:
        assert got[key] == expected[key], key
    timing = {"seconds"}
    strip = lambda refs: [{k: v for k, v in r.items() if k not in timing} for r in refs]
    assert strip(got["references"]) == strip(expected["references"])
    assert [t["name"] for t in got["techniques"]] == ["empirical"]
    assert got["techniques"][0]["frame_ms"] > 0


def test_compare_reference_on_the_gpu_matches_cli_report(cli, cube, tmp_path):
    # --reference-device gpu / reference_device="gpu": the physical reference traced by the GL
    # walk, the same images from both, said in the notes; not the CPU's images.
    out = tmp_path / "report"
    common = dict(techniques=["empirical"], references=["physical"], photons=2e4, frames=1,
                  warmup=0, cache=False, width=48, height=36)
    cli("compare", cube, "--techniques", "empirical", "--reference", "physical", "--photons",
        "2e4", "--reference-device", "gpu", "--frames", "1", "--warmup", "0", "--no-cache",
        "--width", "48", "--height", "36", "--out", out)
    with open(out / "report.json") as f:
        expected = json.load(f)
    got = translucent.compare(str(cube), **common, reference_device="gpu")
    assert got["metrics"] == expected["metrics"]
    assert any("computed on the GPU" in n for n in got["notes"]), got["notes"]
    assert got["settings"]["reference_device"] == "gpu"
    cpu = translucent.compare(str(cube), **common)
    assert cpu["metrics"] != got["metrics"]
    with pytest.raises(ValueError, match="reference_device='tpu': expected cpu or gpu"):
        translucent.compare(str(cube), **common, reference_device="tpu")


def test_compare_reference_from_a_pathtrace_run(cli, cube, tmp_path):
    # reference_from= (`compare --reference-from`): the physical reference read from a
    # `pathtrace mesh` run of the scene at the comparison's size is the one compare traces itself
    # with the same photons and seed; a run of another scene is refused naming what differs.
    s = translucent.Scene.load(cube)
    s.width, s.height = 48, 36
    small = tmp_path / "cube-48.json"
    s.save(small)
    js = tmp_path / "ref.json"
    cli("pathtrace", "mesh", "--scene", small, "--photons", "2e4", "--seed", "2", "--device", "cpu",
        "--exr", tmp_path / "ref.exr", "--json", js)
    common = dict(techniques=["empirical"], references=["physical"], photons=2e4, seed=2,
                  frames=1, warmup=0, cache=False)
    got = translucent.compare(str(small), **common, reference_from=str(js))
    traced = translucent.compare(str(small), **common)
    assert got["metrics"] == traced["metrics"]
    assert any(n.startswith("physical reference: read from " + str(js)) for n in got["notes"])
    # A list (pathlib paths too): the one traced for the scene is taken.
    listed = translucent.compare(str(small), **common, reference_from=[js, js])
    assert listed["metrics"] == traced["metrics"]
    with pytest.raises(ValueError, match="traced for another scene than this comparison's"):
        translucent.compare(str(cube), **common, width=64, height=48, reference_from=[js])


def test_compare_sweep_has_points(cube):
    got = translucent.compare(str(cube), techniques=["empirical"], references=["model"],
                              samples=2000, frames=1, warmup=0, cache=False, width=48,
                              height=36, sweep=True)
    sweep = got["sweep"]
    params = {p["name"]: p for p in translucent.technique_parameters("empirical")}
    swept = [p for p in params.values() if p["sweep"]]
    assert len(sweep) == sum(len(p["sweep"]) for p in swept)
    assert all(s["frame_ms"] > 0 and s["metrics"] for s in sweep)


def test_compare_errors():
    with pytest.raises(ValueError, match="unknown technique 'nope'"):
        translucent.compare(techniques=["nope"])
    with pytest.raises(ValueError, match="subpixels 0"):
        translucent.compare(subpixels=0)


def test_compare_ctrl_c_keeps_the_partial_report(source_dir, tmp_path):
    # SIGINT during the physical reference (1e10 photons: hours): KeyboardInterrupt within
    # seconds, its partial_result the report (written) marked partial.
    import os
    import signal
    import subprocess
    import sys
    import textwrap
    import time
    script = textwrap.dedent(f"""
        import sys, translucent
        print("ready", flush=True)
        try:
            translucent.compare({str(source_dir / "data" / "scenes" / "cube.json")!r},
                                techniques=["empirical"], references=["physical"],
                                photons=1e10, cache=False, width=32, height=24,
                                out={str(tmp_path / "report")!r})
        except KeyboardInterrupt as e:
            r = e.partial_result
            print("interrupted", r["partial"], r["references"][0]["partial"], flush=True)
            sys.exit(0)
        sys.exit(1)
    """)
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                         env=os.environ.copy())
    assert p.stdout.readline().strip() == "ready"
    time.sleep(2.0)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 0, out
    assert out.split() == ["interrupted", "True", "True"]
    assert (tmp_path / "report" / "report.json").is_file()


def test_render_from_any_thread(cube):
    # The one GL context is lent to the calling thread for each call (gl_lock.h): threads take
    # turns, and a Renderer made on one thread renders on another.
    import threading
    main = translucent.render(str(cube), "empirical", width=32, height=24)["image"]
    r = translucent.Renderer(str(cube), "empirical", width=32, height=24)
    results, errors = [], []

    def work():
        try:
            results.append(translucent.render(str(cube), "empirical", width=32, height=24)["image"])
            results.append(r.render()["image"])
        except Exception as e:  # reported below: an assertion in a thread would be lost
            errors.append(e)
    threads = [threading.Thread(target=work) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert len(results) == 6 and all(np.array_equal(x, main) for x in results)
