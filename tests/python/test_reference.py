# SPDX-License-Identifier: GPL-3.0-or-later
"""The slab and sphere path tracers against `translucent pathtrace slab|sphere` output files."""
import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import translucent

# Keys that depend on the run's timing only.
TIMING = {"seconds", "photons_per_second"}


def comparable(d):
    """The dict with arrays as flat lists (the CLI's JSON stores Rd(r, θ), an (r, θ) array here,
    row-major) and the timing keys dropped."""
    out = {}
    for k, v in d.items():
        if k in TIMING:
            continue
        if isinstance(v, dict):
            v = comparable(v)
        elif isinstance(v, np.ndarray):
            v = v.ravel().tolist()
        out[k] = v
    return out


SLABS = [
    (["--material", "Skin1", "--channel", "r"], dict(material="Skin1", channel="r")),
    (["--sigma-a", "10", "--sigma-s", "90", "--g", "0.75", "--eta", "1.37", "--thickness", "0.02",
      "--theta", "30", "--absorption", "weighted", "--angle-bins", "6"],
     dict(sigma_a=10, sigma_s=90, g=0.75, eta=1.37, thickness=0.02, theta=30,
          absorption="weighted", angle_bins=6)),
]


@pytest.mark.parametrize("cli_args,kwargs", SLABS)
def test_slab_matches_cli_json(cli, tmp_path, cli_args, kwargs):
    out = tmp_path / "slab.json"
    cli("pathtrace", "slab", *cli_args, "--photons", "2e4", "--seed", "7", "--threads", "2",
        "--radial-bins", "20", "--radial-max", "0.5", "--json", out)
    with open(out) as f:
        expected = json.load(f)
    got = translucent.pathtrace_slab(**kwargs, photons=2e4, seed=7, threads=2, radial_bins=20,
                                     radial_max=0.5)
    assert isinstance(got["radial"]["rd"], np.ndarray)
    assert got["radial"]["rd"].dtype == np.float64 and got["radial"]["rd"].shape == (20,)
    if "angle_bins" in kwargs:
        assert got["angular"]["rd_r_theta"].shape == (20, kwargs["angle_bins"])
    # Every estimate, standard error and tally bit for bit (the same library call).
    assert comparable(got) == {k: v for k, v in expected.items() if k not in TIMING}


def test_slab_on_the_gpu_matches_cli_json(cli, tmp_path):
    # device="gpu": the same GL walk as `--device gpu` (Philox streams), bit for bit.
    out = tmp_path / "slab.json"
    cli("pathtrace", "slab", "--preset", "Marble", "--channel", "g", "--photons", "2e4", "--seed",
        "7", "--radial-bins", "10", "--radial-max", "2", "--device", "gpu", "--json", out)
    with open(out) as f:
        expected = json.load(f)
    got = translucent.pathtrace_slab(material="Marble", channel="g", photons=2e4, seed=7,
                                     radial_bins=10, radial_max=2, device="gpu")
    assert got["device"].startswith("gpu (")
    assert comparable(got) == {k: v for k, v in expected.items() if k not in TIMING}
    assert translucent.pathtrace_slab(material="Marble", channel="g", photons=2e4, seed=7,
                                      device="cpu")["device"] == "cpu"
    with pytest.raises(ValueError, match="device='tpu': expected cpu, gpu or auto"):
        translucent.pathtrace_slab(material="Marble", channel="g", device="tpu")


def test_slab_seed_determinism_and_threads():
    a = translucent.pathtrace_slab(material="Marble", channel="g", photons=3e4, seed=3, threads=1)
    b = translucent.pathtrace_slab(material="Marble", channel="g", photons=3e4, seed=3, threads=2)
    c = translucent.pathtrace_slab(material="Marble", channel="g", photons=3e4, seed=4, threads=2)
    assert comparable(a) | {"threads": 0} == comparable(b) | {"threads": 0}
    assert a["diffuse_reflectance"] != c["diffuse_reflectance"]
    # The standard error is what it claims: two seeds agree within 5 combined errors.
    se = np.hypot(a["diffuse_reflectance_stderr"], c["diffuse_reflectance_stderr"])
    assert abs(a["diffuse_reflectance"] - c["diffuse_reflectance"]) < 5 * se


def test_layered_slab_matches_cli(cli, tmp_path):
    layers = [{"thickness": 0.1, "sigma_a": 0.5, "sigma_s": 9.5, "g": 0.8},
              {"thickness": None, "sigma_a": 0.3, "sigma_s": 4.7, "g": 0.0}]
    path = tmp_path / "layers.json"
    path.write_text(json.dumps(layers))
    out = tmp_path / "layered.json"
    cli("pathtrace", "slab", "--layers", path, "--eta", "1.4", "--photons", "1e4",
        "--radial-bins", "10", "--radial-max", "2", "--json", out)
    with open(out) as f:
        expected = {k: v for k, v in json.load(f).items() if k not in TIMING}
    from_file = comparable(translucent.pathtrace_slab(layers=str(path), eta=1.4, photons=1e4,
                                                      radial_bins=10, radial_max=2))
    assert from_file == expected
    from_list = comparable(translucent.pathtrace_slab(layers=layers, eta=1.4, photons=1e4,
                                                      radial_bins=10, radial_max=2))
    assert from_list == expected | {"layers_file": ""}


@pytest.mark.parametrize("args,kwargs", [
    (["--preset", "Skin1", "--channel", "x"], dict(material="Skin1", channel="x")),
    (["--sigma-a", "1", "--sigma-s", "1"], dict(sigma_a=1, sigma_s=1)),
    (["--preset", "Skin1", "--channel", "r", "--photons", "0.5"],
     dict(material="Skin1", channel="r", photons=0.5)),
    (["--sigma-a", "1e-12", "--sigma-s", "1", "--eta", "1"], dict(sigma_a=1e-12, sigma_s=1, eta=1)),
    # Walks short enough one by one, but hours all together: refused unless time_limit= is given.
    (["--sigma-a", "1e-20", "--sigma-s", "1", "--eta", "1.3", "--photons", "1e5"],
     dict(sigma_a=1e-20, sigma_s=1, eta=1.3, photons=1e5)),
])
def test_slab_errors_same_message_as_cli(cli_error, as_python, tmp_path, args, kwargs):
    # The CLI's message in the Python arguments' names.
    expected = cli_error("pathtrace", "slab", *args, "--json", tmp_path / "x.json")
    with pytest.raises(ValueError) as e:
        translucent.pathtrace_slab(**kwargs)
    assert str(e.value) == as_python(expected)


def test_time_limit_returns_partial():
    start = time.monotonic()
    d = translucent.pathtrace_slab(material="Marble", channel="r", photons=1e10, time_limit=0.5)
    assert time.monotonic() - start < 10
    assert d["partial"] is True and 0 < d["photons"] < 1e10


def test_ctrl_c_raises_keyboard_interrupt_with_partial_result(tmp_path):
    # In a child process: SIGINT after 1 s must end a trace of 1e10 photons (hours) quickly,
    # as KeyboardInterrupt carrying what was traced.
    script = textwrap.dedent("""
        import sys, translucent
        print("ready", flush=True)
        try:
            translucent.pathtrace_slab(material="Marble", channel="r", photons=1e10,
                                       time_limit=120)
        except KeyboardInterrupt as e:
            r = e.partial_result
            print("interrupted", r["partial"], r["photons"], flush=True)
            sys.exit(0)
        print("not interrupted", flush=True)
        sys.exit(1)
    """)
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                         env=os.environ.copy())
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.0)
    start = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=30)
    assert time.monotonic() - start < 5, "the trace did not stop within 5 s of Ctrl-C"
    assert p.returncode == 0, out
    word, partial, photons = out.split()
    assert word == "interrupted" and partial == "True" and int(photons) > 0


def test_gil_released_while_tracing():
    # A Python thread keeps counting while the trace runs on the main thread.
    import threading
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.01)
    t = threading.Thread(target=count)
    t.start()
    start = time.monotonic()
    translucent.pathtrace_slab(material="Marble", channel="r", photons=1e10, time_limit=1.0)
    elapsed = time.monotonic() - start
    stop.set()
    t.join()
    assert len(ticks) > 0.5 * elapsed / 0.01, (len(ticks), elapsed)


def read_exr_layers(path):
    """{layer: (H, W, 3) float32} of an EXR written by the CLI ('' for R, G, B)."""
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(str(path))
    assert inp, oiio.geterror()
    spec = inp.spec()
    pixels = inp.read_image(oiio.FLOAT)
    inp.close()
    names = list(spec.channelnames)
    layers = {}
    for i, n in enumerate(names):
        layer, _, ch = n.rpartition(".")
        layers.setdefault(layer, {})[ch] = pixels[:, :, i]
    return {k: np.stack([v["R"], v["G"], v["B"]], axis=-1) for k, v in layers.items()}


def test_sphere_matches_cli_exr(cli, tmp_path):
    exr, js = tmp_path / "s.exr", tmp_path / "s.json"
    cli("pathtrace", "sphere", "--preset", "Skin1", "--scale", "5", "--light-dir", "1,0.5,1",
        "--width", "48", "--height", "40", "--photons", "2e4", "--passes", "2", "--seed", "5",
        "--exr", exr, "--json", js)
    d = translucent.pathtrace_sphere(material="Skin1", scale=5, light_dir=(1, 0.5, 1), width=48,
                                     height=40, photons=2e4, passes=2, seed=5)
    layers = read_exr_layers(exr)
    for name in ["exitance", "radiance", "cone_radiance"]:
        for key in [name, name + "_stderr"]:
            img = d[key]
            assert img.shape == (40, 48, 3) and img.dtype == np.float32
            assert img.flags["C_CONTIGUOUS"]
            assert np.array_equal(img, layers[key]), key
    with open(js) as f:
        expected = json.load(f)
    assert d["flux_per_channel"] == expected["flux_per_channel"]
    assert d["photons_per_channel"] == expected["photons_per_channel"]
    assert d["passes"] == expected["passes"] and d["partial"] is False
    # Fresnel reflection at entry: less flux enters than was emitted towards the sphere.
    for f in d["flux_per_channel"]:
        assert 0 < f["entered"] < f["emitted"]


def test_sphere_split_by_scattering_order_matches_cli_exr(cli, tmp_path):
    # --split-orders / split_orders=True (seed Eq. 2.13): every quantity per scattering order,
    # the CLI's EXR layers array for array; the orders add up to the total (float32 rounding);
    # without the option there are no such keys.
    exr, js = tmp_path / "s.exr", tmp_path / "s.json"
    cli("pathtrace", "sphere", "--sigma-a", "0.5", "--sigma-s", "2.5", "--g", "0.3", "--eta", "1.4",
        "--width", "24", "--height", "20", "--photons", "2e4", "--seed", "5", "--split-orders",
        "--exr", exr, "--json", js)
    d = translucent.pathtrace_sphere(sigma_a=0.5, sigma_s=2.5, g=0.3, eta=1.4, width=24, height=20,
                                     photons=2e4, seed=5, split_orders=True)
    layers = read_exr_layers(exr)
    orders = ["unscattered", "single", "multiple"]
    for name in ["exitance", "radiance", "cone_radiance"]:
        for order in orders:
            for key in [f"{name}_{order}", f"{name}_{order}_stderr"]:
                assert np.array_equal(d[key], layers[key]), key
        parts = sum(d[f"{name}_{order}"].astype(np.float64) for order in orders)
        assert np.allclose(parts, d[name], rtol=1e-6, atol=1e-7 * d[name].max()), name
    assert d["exitance_single"].sum() > 0 and d["exitance_multiple"].sum() > 0
    with open(js) as f:
        expected = json.load(f)
    assert expected["split_orders"] is True
    assert d["flux_per_channel"] == expected["flux_per_channel"]
    for f in d["flux_per_channel"]:
        by = f["exited_by_order"]
        assert abs(sum(by[o]["exited"] for o in orders) - f["exited"]) <= 1e-12 * f["exited"]
    plain = translucent.pathtrace_sphere(width=8, height=8, photons=4096)
    assert "exitance_single" not in plain


def test_sphere_on_the_gpu_matches_cli_exr(cli, tmp_path):
    exr, js = tmp_path / "s.exr", tmp_path / "s.json"
    cli("pathtrace", "sphere", "--preset", "Skin1", "--scale", "5", "--width", "24", "--height",
        "20", "--photons", "2e4", "--seed", "5", "--device", "gpu", "--exr", exr, "--json", js)
    d = translucent.pathtrace_sphere(material="Skin1", scale=5, width=24, height=20, photons=2e4,
                                     seed=5, device="gpu")
    layers = read_exr_layers(exr)
    for key in ["exitance", "exitance_stderr", "cone_radiance"]:
        assert np.array_equal(d[key], layers[key]), key
    with open(js) as f:
        expected = json.load(f)
    assert d["device"] == expected["device"] and d["device"].startswith("gpu (")
    assert d["flux_per_channel"] == expected["flux_per_channel"]


def test_sphere_same_images_on_any_thread_count():
    a = translucent.pathtrace_sphere(width=24, height=24, photons=8192, seed=9, threads=1)
    b = translucent.pathtrace_sphere(width=24, height=24, photons=8192, seed=9, threads=2)
    c = translucent.pathtrace_sphere(width=24, height=24, photons=8192, seed=10, threads=2)
    for key in ["exitance", "exitance_stderr", "cone_radiance"]:
        assert np.array_equal(a[key], b[key]), key
    assert not np.array_equal(a["exitance"], c["exitance"])


def test_sphere_errors_same_message_as_cli(cli_error, as_python, tmp_path):
    expected = cli_error("pathtrace", "sphere", "--passes", "0", "--exr", tmp_path / "x.exr")
    with pytest.raises(ValueError) as e:
        translucent.pathtrace_sphere(passes=0)
    assert str(e.value) == as_python(expected)


def test_run_of_days_is_refused_after_five_seconds():
    # The CLI's cost check (apps/cli/progress.h): without a time limit, a run projected past 24
    # hours is stopped after 5 s with the measured rate (1e13 photons: years on 2 cores).
    start = time.monotonic()
    with pytest.raises(ValueError, match=r"refused: 10000000000000 photons at the measured .* "
                                         r"would take about .* days \(more than 24 hours\)"):
        translucent.pathtrace_slab(material="Marble", channel="r", photons=1e13)
    assert 5 <= time.monotonic() - start < 15


@pytest.mark.parametrize("sampling", ["importance", "uniform"])
def test_integrate_sphere_matches_cli_exr(cli, tmp_path, sampling):
    exr = tmp_path / "i.exr"
    cli("integrate", "sphere", "--model", "better-dipole", "--preset", "Skin1", "--scale", "5",
        "--width", "32", "--height", "24", "--samples", "16", "--sampling", sampling,
        "--seed", "4", "--exr", exr)
    d = translucent.integrate_sphere("better-dipole", material="Skin1", scale=5, width=32,
                                     height=24, samples=16, sampling=sampling, seed=4)
    layers = read_exr_layers(exr)
    for key in ["exitance", "exitance_stderr", "radiance", "radiance_stderr"]:
        assert d[key].shape == (24, 32, 3) and d[key].dtype == np.float32
        assert np.array_equal(d[key], layers[key]), key
    assert d["samples_per_pixel"] == 16 and d["partial"] is False


BSSRDF_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data", "bssrdf")


@pytest.mark.parametrize("name", ["better-dipole", "directional-dipole"])
def test_integrate_sphere_of_bssrdf_files_matches_cli_exr(cli, tmp_path, name):
    # A radial file (tabulated on the GPU, integrated on the CPU) and a directional one (on the
    # GPU with the light's direction, uniform sampling): the same images as the CLI's.
    path = os.path.join(BSSRDF_DIR, name + ".bssrdf")
    exr = tmp_path / "b.exr"
    cli("integrate", "sphere", "--model", path, "--preset", "Skin1", "--light-dir", "1,0,1",
        "--width", "12", "--height", "10", "--samples", "32", "--seed", "5", "--exr", exr)
    d = translucent.integrate_sphere(path, material="Skin1", light_dir=[1, 0, 1], width=12,
                                     height=10, samples=32, seed=5)
    layers = read_exr_layers(exr)
    for key in ["exitance", "exitance_stderr", "radiance", "radiance_stderr"]:
        assert d[key].shape == (10, 12, 3) and d[key].dtype == np.float32
        assert np.array_equal(d[key], layers[key]), key
    assert d["sampling"] == ("uniform" if name == "directional-dipole" else "importance")
    assert d["exitance"].max() > 0
