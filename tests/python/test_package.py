# SPDX-License-Identifier: GPL-3.0-or-later
"""The package: type stubs for every public name, typed results, the share folder, and argument
errors that name the Python arguments (hostile inputs raise, never abort or return NaN)."""
import ast
import math
import os
import pathlib
import pickle
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import translucent

PACKAGE = pathlib.Path(translucent.__file__).parent
NAN, INF = float("nan"), float("inf")


def stub_names(body):
    """The public names a stub's module or class body defines."""
    names = set()
    for node in body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets if isinstance(t, ast.Name))
        elif isinstance(node, ast.ImportFrom):  # `from x import A as A` re-exports A
            names.update(a.asname for a in node.names if a.asname == a.name)
    return {n for n in names if not n.startswith("_") or n == "__version__"}


@pytest.fixture(scope="module")
def stubs():
    tree = ast.parse((PACKAGE / "__init__.pyi").read_text())
    classes = {n.name: stub_names(n.body) for n in tree.body if isinstance(n, ast.ClassDef)}
    return stub_names(tree.body), classes


def test_package_layout():
    assert PACKAGE.name == "translucent"
    assert (PACKAGE / "py.typed").is_file() and (PACKAGE / "__init__.pyi").is_file()
    assert translucent._translucent.__name__ == "translucent._translucent"
    assert translucent.__version__ and translucent.__version__[0].isdigit()


def test_stubs_cover_every_public_name(stubs):
    names, _ = stubs
    public = {n for n in dir(translucent) if not n.startswith("_")} | {"__version__"}
    assert public - names == set(), "in the module, not in __init__.pyi"
    assert names - public == set(), "in __init__.pyi, not in the module"
    assert set(translucent.__all__) == public
    # Everything the extension defines is re-exported by the package.
    ext = {n for n in dir(translucent._translucent) if not n.startswith("_")}
    assert ext <= public


def test_stubs_cover_every_member_of_the_classes(stubs):
    _, classes = stubs
    for name in ["Medium", "Preset", "Model", "Profiles", "BssrdfModel", "Scene", "Renderer"]:
        cls = getattr(translucent, name)
        members = {m for m in vars(cls) if not m.startswith("_")}
        assert members - classes[name] == set(), f"{name}: members missing from the stubs"
        assert classes[name] - members == set(), f"{name}: stubbed members that do not exist"


def test_results_are_typed_and_still_mappings():
    c = translucent.preset("Marble").medium().channel(1)
    assert isinstance(c, translucent.ChannelProperties) and isinstance(c, translucent.Result)
    assert c.sigma_tr == c["sigma_tr"] and "albedo" in c and "nope" not in c
    assert list(c.keys())[:4] == ["sigma_a", "sigma_s", "g", "eta"]
    assert dict(c) == c.to_dict() and c == c.to_dict()
    assert repr(c).startswith("ChannelProperties(sigma_a=")
    with pytest.raises(AttributeError, match="nope"):
        c.nope
    with pytest.raises(KeyError):
        c["nope"]
    assert pickle.loads(pickle.dumps(c)) == c

    s = translucent.pathtrace_slab(material="Marble", channel="r", photons=2000, radial_bins=4,
                                   radial_max=1.0)
    assert type(s) is translucent.SlabResult
    assert s.diffuse_reflectance == s["diffuse_reflectance"] > 0
    assert s.radial["rd"].shape == (4,)
    text = repr(s)
    assert text.startswith("SlabResult(") and "diffuse_reflectance=" in text
    assert "<array float64 (4,)>" not in text.split("radial=")[0]  # nested dicts abbreviated


def test_share_directory_holds_the_shaders_and_data():
    share = translucent.share_directory()
    assert isinstance(share, pathlib.Path)
    assert (share / "shaders").is_dir() and (share / "data" / "presets").is_dir()


def test_module_is_importable_from_any_folder(tmp_path):
    p = subprocess.run([sys.executable, "-c", "import translucent, sys; "
                        "print(translucent.model('dipole').name)"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "dipole"


@pytest.fixture(scope="module")
def cube():
    return str(pathlib.Path(os.environ.get("TRANSLUCENT_SOURCE_DIR", PACKAGE.parents[2]))
               / "data" / "scenes" / "cube.json")


@pytest.fixture(scope="module")
def bssrdf_file():
    return str(translucent.share_directory() / "data" / "bssrdf" / "better-dipole.bssrdf")


MARBLE = translucent.preset("Marble").medium()

# (call, exception type, text the message contains): every message names the Python argument.
BAD_CALLS = [
    (lambda: translucent.pathtrace_slab(material="Skin1"), ValueError, "channel=None"),
    (lambda: translucent.pathtrace_slab(material="Skin1", channel="x"), ValueError, "channel='x'"),
    (lambda: translucent.pathtrace_slab(), ValueError, "give the medium: sigma_a="),
    (lambda: translucent.pathtrace_slab(material="Skin1", channel="r", photons=0.5), ValueError,
     "photons="),
    (lambda: translucent.pathtrace_slab(material="Skin1", channel="r", thickness=NAN), ValueError,
     "thickness is nan"),
    (lambda: translucent.pathtrace_slab(material="Skin1", channel="r", phi=INF), ValueError,
     "phi is inf"),
    (lambda: translucent.pathtrace_slab(material="Skin1", channel="r", radial_bins=4,
                                        radial_max=NAN), ValueError, "radial_max is nan"),
    (lambda: translucent.pathtrace_slab(material="Skin1", channel="r", eta_above=-1), ValueError,
     "eta_above is -1"),
    (lambda: translucent.pathtrace_slab(material="Skin1", channel="r", threads=-1), ValueError,
     "threads is -1"),
    (lambda: translucent.pathtrace_slab(layers=42, eta=1.4), TypeError, "layers=42"),
    (lambda: translucent.pathtrace_slab(sigma_a=1, sigma_s=1, eta=1.3, kernel="x"), ValueError,
     "kernel='x'"),
    (lambda: translucent.pathtrace_sphere(passes=0), ValueError, "passes is 0"),
    (lambda: translucent.pathtrace_sphere(time_limit=0), ValueError, "time_limit is 0"),
    (lambda: translucent.pathtrace_sphere(light_dir="abc"), TypeError, "light_dir='abc'"),
    (lambda: translucent.pathtrace_sphere(light_dir=(0, 0, 0)), ValueError, "light_dir"),
    (lambda: translucent.pathtrace_sphere(view_dir=(1, NAN, 0)), ValueError, "view_dir"),
    (lambda: translucent.pathtrace_sphere(sigma_a=1), ValueError, "sigma_a requires sigma_s"),
    (lambda: translucent.pathtrace_sphere(material="Skin1", sigma_a=1, sigma_s=1), ValueError,
     "material excludes sigma_a and sigma_s"),
    (lambda: translucent.integrate_sphere(samples=0), ValueError, "samples="),
    (lambda: translucent.integrate_sphere(sampling="x"), ValueError, "sampling='x'"),
    (lambda: translucent.integrate_sphere(defensive=NAN), ValueError, "defensive is nan"),
    (lambda: translucent.profile("dipole", None), TypeError, "r=None"),
    (lambda: translucent.profile("dipole", "abc"), TypeError, "r='abc'"),
    (lambda: translucent.profile("dipole", {"a": 1}), TypeError, "r={'a': 1}"),
    (lambda: translucent.profile("dipole", [1.0, NAN]), ValueError, "r.flat[1] is nan"),
    (lambda: translucent.profile("dipole", [[1.0], [-2.0]]), ValueError, "r.flat[1] is -2"),
    (lambda: translucent.profile("dipole", INF), ValueError, "r is inf"),
    (lambda: translucent.profile("dipole", [1.0], sigma_a="abc", sigma_s=1), TypeError,
     "sigma_a='abc'"),
    (lambda: translucent.profile("dipole", [1.0], sigma_a=None, sigma_s=1), ValueError,
     "sigma_s requires sigma_a"),
    (lambda: translucent.profile("dipole", [1.0], sigma_a=(1, 2), sigma_s=1), ValueError,
     "sigma_a (1, 2)"),
    (lambda: translucent.profile("dipole", [1.0], material="Skin1", eta=NAN), ValueError,
     "eta is nan"),
    (lambda: translucent.profile("dipole", [1.0], material="Skin1", scale=-1), ValueError,
     "scale is -1"),
    (lambda: translucent.Medium(sigma_a=None, sigma_s="x"), TypeError, "sigma_s='x'"),
    (lambda: translucent.Medium(sigma_a=NAN), ValueError, "sigma_a (red channel) is nan"),
    (lambda: translucent.Medium.from_reduced(1, -1), ValueError, "sigma_s"),
    (lambda: translucent.preset("Marble").medium(scale=NAN), ValueError, "scale is nan"),
    (lambda: translucent.fdr(NAN), ValueError, "eta is nan"),
    (lambda: translucent.model("dipole").total_reflectance(2, 1.3), ValueError,
     "alpha_prime is 2"),
    (lambda: translucent.model("dipole").total_reflectance(0.5, INF), ValueError, "eta is inf"),
    (lambda: translucent.model("dipole").profiles(MARBLE).R(None), TypeError, "r=None"),
    (lambda: translucent.model("dipole").profiles(MARBLE).pdf([-1]), ValueError,
     "r.flat[0] is -1"),
    (lambda: translucent.model("dipole").profiles(MARBLE).sample([0.5, 1.5]), ValueError,
     "u.flat[1] is 1.5"),
    (lambda: translucent.model("dipole").profiles(MARBLE).radius(NAN), ValueError,
     "fraction is nan"),
    (lambda: translucent.invert("dipole", NAN, 1), ValueError, "rd (red channel) is nan"),
    (lambda: translucent.invert("dipole", 0.5, None), TypeError, "ld=None"),
    (lambda: translucent.invert("dipole", 0.5, 1, eta=0), ValueError, "eta is 0"),
    (lambda: translucent.BssrdfModel("/nonexistent/x.bssrdf"), ValueError,
     "path='/nonexistent/x.bssrdf': no such .bssrdf file"),
    (lambda: translucent.BssrdfModel(42), TypeError, "path=42"),
    (lambda: translucent.pathtrace_mesh(42), TypeError, "scene=42"),
    (lambda: translucent.render(42), TypeError, "scene=42"),
    (lambda: translucent.compare(subpixels=0), ValueError, "subpixels 0"),
    (lambda: translucent.compare(references=[]), ValueError, "references=[]"),
    (lambda: translucent.compare(techniques=[]), ValueError, "techniques=[]"),
    (lambda: translucent.compare(references=["x"]), ValueError, "references"),
    (lambda: translucent.compare(cache=True), TypeError, "cache=True"),
    (lambda: translucent.compare(reference_from=42), TypeError, "reference_from=42"),
    (lambda: translucent.compare(reference_device="tpu"), ValueError, "reference_device='tpu'"),
    (lambda: translucent.compare(photons=NAN), ValueError, "photons="),
    (lambda: translucent.compare(physical_method="x"), ValueError, "physical_method='x'"),
]


@pytest.mark.parametrize("call,error,text", BAD_CALLS,
                         ids=[f"{i}-{t}" for i, (_, _, t) in enumerate(BAD_CALLS)])
def test_errors_name_the_python_arguments(call, error, text):
    with pytest.raises(error) as e:
        call()
    message = str(e.value)
    assert text in message, message
    assert "--" not in message, f"a command-line option in {message!r}"


def test_render_and_bssrdf_errors(cube, bssrdf_file):
    with pytest.raises(TypeError, match=r"points=\[1\]"):
        translucent.render(cube, "pointcloud", points=[1])
    with pytest.raises(ValueError) as e:
        translucent.render(cube, "pointcloud", points=-3)
    assert str(e.value).startswith("points: ") and "--" not in str(e.value)
    with pytest.raises(ValueError, match=r"^time nan: expected a finite time"):
        translucent.render(cube, "empirical", time=NAN)
    with pytest.raises(TypeError, match="Multiplier='x': expected a number"):
        translucent.BssrdfModel(bssrdf_file, Multiplier="x")
    with pytest.raises(ValueError, match="Multiplier is nan"):
        translucent.BssrdfModel(bssrdf_file, Multiplier=NAN)
    b = translucent.BssrdfModel(bssrdf_file)
    before = b.parameters
    with pytest.raises(ValueError, match="declares no parameter 'Nope'"):
        b.set(Multiplier=3.0, Nope=1.0)
    assert b.parameters == before, "a refused set() changes nothing"
    with pytest.raises(TypeError, match="r=None"):
        b.profile(MARBLE, None)


def test_bad_bssrdf_parameter_raises_instead_of_aborting(bssrdf_file):
    # An unknown parameter used to abort the process in the GL loader (the evaluator was
    # destroyed without a current context): in a child process, so that an abort fails the test.
    script = textwrap.dedent(f"""
        import translucent
        try:
            translucent.BssrdfModel({bssrdf_file!r}, nope=float('nan'))
        except ValueError as e:
            print("ValueError", e)
        b = translucent.BssrdfModel({bssrdf_file!r})
        m = translucent.preset("Marble").medium()
        print("R", float(b.profile(m, [1.0])[0, 0]) > 0)
    """)
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0].startswith("ValueError nope=nan: ") and "no parameter 'nope'" in lines[0]
    assert lines[1] == "R True"


def test_profile_edge_radii_are_finite():
    # r = 0 and huge radii are valid radii: finite values (R tends to 0 far away).
    R = translucent.profile("dipole", [0.0, 1e-300, 1e6], material="Marble")
    assert np.all(np.isfinite(R)) and np.all(R[2] == pytest.approx(0.0, abs=1e-300))
    assert translucent.profile("dipole", []).shape == (0, 3)
    assert math.isfinite(translucent.model("dipole").total_reflectance(1.0, 1.3))
