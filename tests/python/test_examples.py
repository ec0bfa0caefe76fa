# SPDX-License-Identifier: GPL-3.0-or-later
"""The examples run end to end, as a user runs them, and write their plots and images."""
import os
import pathlib
import subprocess
import sys

import matplotlib.image
import numpy as np

import translucent


def run_example(source_dir, tmp_path, name, *args):
    # The package this test imported (by absolute path: the example runs in tmp_path).
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(translucent.__file__).parent.parent))
    p = subprocess.run([sys.executable, str(source_dir / "examples" / name), *map(str, args)],
                       capture_output=True, text=True, cwd=tmp_path, timeout=600, env=env)
    assert p.returncode == 0, p.stderr
    return p.stdout


def test_profiles_vs_reference_writes_its_plot(source_dir, tmp_path):
    out = tmp_path / "skin.png"
    stdout = run_example(source_dir, tmp_path, "profiles_vs_reference.py", "--preset", "Skin1",
                         "--photons", "2e4", "--out", out)
    assert f"wrote {out}" in stdout
    img = matplotlib.image.imread(out)
    assert img.shape[0] > 300 and img.shape[1] > 1000
    assert img[..., :3].std() > 0.05, "the plot is not blank"


def test_render_to_numpy_writes_exr_and_png(source_dir, tmp_path):
    import OpenImageIO as oiio
    run_example(source_dir, tmp_path, "render_to_numpy.py", "--scene",
                source_dir / "data" / "scenes" / "cube.json", "--technique", "empirical",
                "--width", 64, "--height", 48, "--out", tmp_path / "cube")
    for ext in ("exr", "png"):
        inp = oiio.ImageInput.open(str(tmp_path / f"cube.{ext}"))
        assert inp, oiio.geterror()
        assert (inp.spec().width, inp.spec().height, inp.spec().nchannels) == (64, 48, 3)
        pixels = inp.read_image(oiio.FLOAT)
        inp.close()
        assert np.isfinite(pixels).all() and pixels.max() > 0


def test_sweep_error_vs_time_writes_its_plot(source_dir, tmp_path):
    out = tmp_path / "sweep.png"
    stdout = run_example(source_dir, tmp_path, "sweep_error_vs_time.py", "--scene",
                         source_dir / "data" / "scenes" / "cube.json", "--technique",
                         "empirical", "--samples", 2000, "--width", 48, "--height", 36,
                         "--frames", 1, "--out", out)
    assert "relative RMSE" in stdout and f"wrote {out}" in stdout
    assert matplotlib.image.imread(out).shape[1] > 500
