# SPDX-License-Identifier: GPL-3.0-or-later
"""`pip install .` into a fresh virtual environment, offline, reusing the configured build tree
(ctest label `install`: slow). The installed package is imported from another folder, finds its
shaders and data inside site-packages, and computes what the build tree's module computes."""
import json
import os
import pathlib
import subprocess
import sys
import textwrap

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("TRANSLUCENT_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))
BUILD_DIR = os.environ.get("TRANSLUCENT_CMAKE_BUILD_DIR")

pytestmark = pytest.mark.skipif(
    not BUILD_DIR, reason="TRANSLUCENT_CMAKE_BUILD_DIR must name the configured build tree "
                          "(ctest sets it)")


def dipole_rd(alpha_prime, eta):
    """Total diffuse reflectance of the dipole, Jensen et al. 2001 (Eq. 5's integral):
    Rd = α'/2 (1 + exp(-4/3 A √(3(1 - α')))) exp(-√(3(1 - α'))), with A = (1 + Fdr)/(1 - Fdr)
    and Fdr the rational fit of Egan & Hilgeman 1979."""
    import math
    fdr = -1.440 / eta**2 + 0.710 / eta + 0.668 + 0.0636 * eta
    a = (1 + fdr) / (1 - fdr)
    s = math.sqrt(3 * (1 - alpha_prime))
    return alpha_prime / 2 * (1 + math.exp(-4 / 3 * a * s)) * math.exp(-s)


@pytest.fixture(scope="module")
def venv(tmp_path_factory):
    """A virtual environment (with the system's site packages: NumPy, setuptools, wheel) with
    the package installed by pip from the source tree, offline."""
    root = tmp_path_factory.mktemp("install")
    env_dir = root / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(env_dir)],
                   check=True, timeout=300)
    python = env_dir / "bin" / "python"
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "TRANSLUCENT_SHARE_DIR", "PIP_INDEX_URL")}
    env.update(TRANSLUCENT_CMAKE_BUILD_DIR=BUILD_DIR, PIP_NO_INDEX="1",
               PIP_DISABLE_PIP_VERSION_CHECK="1", PYTHONDONTWRITEBYTECODE="1")
    p = subprocess.run([str(python), "-m", "pip", "install", "--no-build-isolation", "--no-index",
                        str(SOURCE_DIR)],
                       cwd=root, env=env, capture_output=True, text=True, timeout=1800)
    assert p.returncode == 0, f"pip install failed:\n{p.stdout}\n{p.stderr}"
    return python, root, env


def run_in(venv, script):
    python, root, env = venv
    work = root / "elsewhere"
    work.mkdir(exist_ok=True)
    p = subprocess.run([str(python), "-c", textwrap.dedent(script)], cwd=work, env=env,
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.strip().splitlines()[-1])


def test_installed_package_works_from_another_folder(venv):
    got = run_in(venv, """
        import json, pathlib, site, translucent
        medium = translucent.preset("Marble").medium()
        rd = translucent.model("dipole").profiles(medium).Rd
        c = [medium.channel(i) for i in range(3)]
        print(json.dumps({
            "file": translucent.__file__,
            "site": site.getsitepackages(),
            "share": str(translucent.share_directory()),
            "files": sorted(p.name for p in pathlib.Path(translucent.__file__).parent.iterdir()),
            "rd": rd.tolist(),
            "alpha_prime": [x.reduced_albedo for x in c],
            "eta": medium.eta,
            "version": translucent.__version__,
        }))
    """)
    package = pathlib.Path(got["file"]).parent
    # Installed into the environment, not imported from the source or build tree.
    assert any(package.parent == pathlib.Path(s) for s in got["site"]), got
    assert not package.is_relative_to(SOURCE_DIR / "python")
    # The shaders and data inside the package, not the source tree's.
    assert pathlib.Path(got["share"]) == package / "share" / "translucent"
    assert (package / "share" / "translucent" / "shaders").is_dir()
    assert (package / "share" / "translucent" / "data" / "presets").is_dir()
    for f in ["__init__.py", "__init__.pyi", "_arguments.py", "_results.py", "py.typed"]:
        assert f in got["files"], got["files"]
    assert any(f.startswith("_translucent") and f.endswith(".so") for f in got["files"])
    # Marble's dipole Rd: the closed form, per channel.
    for rd, ap in zip(got["rd"], got["alpha_prime"]):
        assert rd == pytest.approx(dipole_rd(ap, got["eta"]), rel=1e-9)


def test_installed_package_reads_its_own_shaders(venv):
    # A .bssrdf model compiled on the GL context from the package's data and shaders agrees with
    # the C++ model of the same formula (float32 on the GPU).
    got = run_in(venv, """
        import json, translucent
        share = translucent.share_directory()
        path = share / "data" / "bssrdf" / "better-dipole.bssrdf"
        medium = translucent.preset("Skin1").medium()
        r = [0.5, 1.0, 2.0]
        gpu = translucent.BssrdfModel(path).profile(medium, r)
        cpu = translucent.profile("better-dipole", r, medium=medium)
        print(json.dumps({"gpu": gpu.tolist(), "cpu": cpu.tolist(), "path": str(path)}))
    """)
    assert "site-packages" in got["path"]
    for g, c in zip(got["gpu"], got["cpu"]):
        assert g == pytest.approx(c, rel=1e-5)
