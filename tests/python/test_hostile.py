# SPDX-License-Identifier: GPL-3.0-or-later
"""Hostile arguments for the public functions of the `translucent` module.

Its first run (4000 calls) found 10 failures, all fixed: a .bssrdf name longer than the file
system takes raised RuntimeError (std::filesystem's throwing is_regular_file); fdr(η) returned
-inf or NaN for η near 0 (the fit is a reflectance only for η of about 1 to 4); Profiles.pdf of
the better dipole returned NaN at r = 1e308 (2π r overflowed against R = 0, and R itself
overflowed r²); a Scene's time took 2^64 although its JSON refuses magnitudes above 1e15.

A libFuzzer target cannot drive the module from inside Python, so this is its deterministic
stand-in: a fixed-seed stream of calls, each of a public function or method with one to three of
its arguments replaced by a hostile value (NaN, ±inf, None, huge and negative numbers, the wrong
type, text, a list nested deeper than any recursion limit, bytes and text with a NUL, ...) and the
others valid. Every call must either return a valid result, in which no number is NaN (and no
array of values, such as R(r), holds an infinity), or raise TypeError, ValueError or OSError with
a message (not pybind11's "incompatible function arguments" without the argument's name). A
crash of the interpreter fails the ctest; any other exception (RuntimeError, RecursionError,
SystemError, MemoryError, ...) or a NaN fails here, with the call that did it.

Arguments that decide how long a call runs (photons, image size, samples, the medium of a path
tracer) only get hostile values that the module must refuse, or small valid ones: a legal but
huge run is the user's choice (and the cost checks of the CLI have tests of their own), not a
finding. Functions that need the GL context (render, Renderer, compare, BssrdfModel's
evaluation) are left out: their argument checks are the same helpers (common.h) this exercises
through the CPU functions, and a GL context per call would make thousands of calls too slow.
"""
import math
import os
import pathlib
import random
import sys

import numpy as np
import pytest

import translucent

SEED = 20261206
CALLS = 4000

# Errors a bad argument may raise (the module's contract: ValueError naming the argument, or
# TypeError for a wrong type; OSError for a file that cannot be read or written).
ALLOWED = (TypeError, ValueError, OSError)


def deep_list(depth):
    """[[[...]]] nested `depth` levels, built without recursion."""
    x = []
    for _ in range(depth):
        x = [x]
    return x


def deep_dict(depth):
    x = {}
    for _ in range(depth):
        x = {"a": x}
    return x


class Weird:
    """An object whose conversions raise: float(), len(), iter() and repr() are all hostile."""

    def __float__(self):
        raise ZeroDivisionError("float of Weird")

    def __index__(self):
        raise ZeroDivisionError("index of Weird")

    def __len__(self):
        raise ZeroDivisionError("len of Weird")

    def __iter__(self):
        raise ZeroDivisionError("iter of Weird")

    def __repr__(self):
        raise ZeroDivisionError("repr of Weird")

    def __fspath__(self):
        raise ZeroDivisionError("fspath of Weird")


class NanFloat(float):
    """A float subclass whose value is NaN (passes isinstance(x, float))."""


def hostile_values():
    nan, inf = float("nan"), float("inf")
    return [
        nan, inf, -inf, -0.0, None, True, False, -1, 0, 1, -(2 ** 63), 2 ** 63, 2 ** 64,
        10 ** 400, 1e308, -1e308, 5e-324, 1e-300, 1e18, 1e19, 2 ** 31, 2 ** 31 - 1, -(2 ** 31),
        1 + 2j, "", "x", "nan", "1.5", "a\0b", "dipole\0", "../" * 50, "é" * 1000,
        b"", b"a\0b", bytearray(b"\0\xff"), [], [nan], [1, 2], [1, 2, 3, 4], [nan, nan, nan],
        [inf, 1, 1], ["a", "b", "c"], [None, None, None], [[1, 2, 3]], (1, 2, 3),
        deep_list(100000), deep_dict(20000), {}, {"a": nan}, {"thickness": nan}, set(),
        np.float64("nan"), np.float32("inf"), np.array([]), np.array([nan, 1, 2]),
        np.array([[1, 2, 3]] * 2), np.array(["a", "b", "c"]), np.array(1e400),
        np.array([1, 2, 3], dtype=object), np.int64(-1), np.uint64(2 ** 64 - 1),
        np.zeros((0, 3)), NanFloat("nan"), Weird(), object(), lambda: 0,
        pathlib.Path("/dev/null"), pathlib.Path("a\0b"), pathlib.Path("/"),
    ]


HOSTILE = hostile_values()


def refused_for_cost(v):
    """Whether `v` is one of the hostile values that an argument deciding a run's cost must refuse
    (anything but a plain large or small valid count)."""
    if isinstance(v, bool) or v is None:
        return True
    if isinstance(v, (int, float, np.integer, np.floating)):
        x = float(v) if not isinstance(v, int) or abs(v) < 10 ** 300 else math.inf
        return not math.isfinite(x) or x <= 0 or x > 1e18 or x != math.floor(x) or x >= 2 ** 31
    return True


# Valid files the calls may name.
@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("hostile")
    table = d / "table.csv"
    table.write_text("# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n1,0.1,0.2,0.3\n2,0.01,0.02,0.03\n")
    layers = d / "layers.json"
    layers.write_text('[{"thickness": 0.5, "sigma_a": 1, "sigma_s": 10, "g": 0.9},'
                      ' {"thickness": null, "sigma_a": 1, "sigma_s": 1}]')
    bad_layers = d / "bad_layers.json"
    bad_layers.write_text('[{"thickness": NaN, "sigma_a": 1, "sigma_s": 10}]')
    return {"table": str(table), "layers": str(layers), "bad_layers": str(bad_layers),
            "dir": str(d)}


# ---------------------------------------------------------------------------------------------
# The calls: each a function of keyword arguments with a valid value for each and, for the
# arguments that decide a run's cost, the flag that only refused values replace them.

def medium():
    return translucent.Medium(sigma_a=(0.01, 0.02, 0.03), sigma_s=(1, 2, 3), g=0.2)


def call_medium_setter(attr, value):
    m = medium()
    setattr(m, attr, value)
    return m


def call_scene_setter(attr, value):
    s = translucent.Scene.default()
    setattr(s, attr, value)
    return s


def specs(files):
    """name -> (callable(**kwargs), {arg: valid value}, {args whose hostile values must be
    refused})."""
    M = medium
    slab = dict(sigma_a=1.0, sigma_s=10.0, g=0.5, eta=1.3, material=None, channel=None,
                eta_above=1.0, eta_below=1.0, thickness=None, theta=0.0, phi=0.0, photons=200,
                seed=1, threads=1, radial_bins=4, radial_max=1.0, angle_bins=3,
                long_path_roulette=0, absorption="analog", kernel="scalar", device="cpu",
                layers=None, time_limit=None)
    sphere = dict(material=None, sigma_a=0.01, sigma_s=1.0, g=0.0, eta=1.3, scale=1.0, radius=1.0,
                  light_dir=(1, 1, 1), view_dir=(0, 0, 1), width=6, height=5, photons=100,
                  passes=1, seed=1, threads=1, device="cpu", time_limit=None,
                  split_orders=False, cone_angle=5.0)
    integ = dict(model="dipole", material=None, sigma_a=0.01, sigma_s=1.0, g=0.0, eta=1.3,
                 scale=1.0, radius=1.0, light_dir=(1, 1, 1), view_dir=(0, 0, 1), width=5,
                 height=4, samples=4, passes=1, sampling="importance", defensive=0.1, seed=1,
                 threads=1, time_limit=None)
    cost_slab = {"photons", "radial_bins", "angle_bins", "sigma_a", "sigma_s", "thickness",
                 "threads", "long_path_roulette", "eta", "g", "layers"}
    cost_sphere = {"photons", "passes", "width", "height", "sigma_a", "sigma_s", "scale", "radius",
                   "threads", "samples", "preset", "g", "eta"}
    return {
        "Medium": (lambda **k: translucent.Medium(**k),
                   dict(sigma_a=(0.1, 0.2, 0.3), sigma_s=1.0, g=0.1, eta=1.3, scale=1.0), set()),
        "Medium.from_reduced": (lambda **k: translucent.Medium.from_reduced(**k),
                                dict(sigma_a=0.1, sigma_s_prime=(1, 2, 3), g=0.5, eta=1.4,
                                     scale=2.0), set()),
        "Medium.setter": (lambda **k: call_medium_setter(**k),
                          dict(attr="g", value=0.3), set()),
        "Medium.channel": (lambda **k: M().channel(**k), dict(c=1), set()),
        "preset": (lambda **k: translucent.preset(**k), dict(name="Skin1"), set()),
        "Preset.medium": (lambda **k: translucent.preset("Marble").medium(**k),
                          dict(scale=3.0), set()),
        "fdr": (lambda **k: translucent.fdr(**k), dict(eta=1.3), set()),
        "invert": (lambda **k: translucent.invert(**k),
                   dict(model="dipole", rd=(0.8, 0.6, 0.4), ld=(5, 2, 1), eta=1.4), set()),
        "model": (lambda **k: translucent.model(**k), dict(name="better-dipole"), set()),
        "model.table": (lambda **k: translucent.model(**k), dict(name=files["table"]), set()),
        "Model.total_reflectance": (
            lambda **k: translucent.model("dipole").total_reflectance(**k),
            dict(alpha_prime=0.9, eta=1.3), set()),
        "Model.profiles": (lambda **k: translucent.model("photon-beam").profiles(**k),
                           dict(medium=M()), set()),
        "Profiles.R": (lambda **k: translucent.model("dipole").profiles(M()).R(**k),
                       dict(r=[0.0, 0.5, 2.0]), set()),
        "Profiles.pdf": (lambda **k: translucent.model("better-dipole").profiles(M()).pdf(**k),
                         dict(r=np.linspace(0, 3, 5)), set()),
        "Profiles.sample": (
            lambda **k: translucent.model("dipole").profiles(M()).sample(**k),
            dict(u=[0.0, 0.5, 0.99]), set()),
        "Profiles.radius": (lambda **k: translucent.model("dipole").profiles(M()).radius(**k),
                            dict(fraction=0.9), set()),
        "profile": (lambda **k: translucent.profile(**k),
                    dict(model="dipole", r=[0.1, 1.0], material="Skin1", sigma_a=None,
                         sigma_s=None, g=0.0, eta=1.3, scale=1.0), set()),
        "profile.table": (lambda **k: translucent.profile(**k),
                          dict(model=files["table"], r=[0.0, 1.5, 9.0], material=None,
                               sigma_a=0.1, sigma_s=1.0, g=0.0, eta=1.3, scale=2.0), set()),
        "pathtrace_slab": (lambda **k: translucent.pathtrace_slab(**k), slab, cost_slab),
        "pathtrace_slab.layers": (
            lambda **k: translucent.pathtrace_slab(**k),
            dict(slab, sigma_a=None, sigma_s=None, g=None, eta=1.4, layers=files["layers"]),
            cost_slab - {"layers"}),
        "integrate_sphere": (lambda **k: translucent.integrate_sphere(**k), integ, cost_sphere),
        "pathtrace_sphere": (lambda **k: translucent.pathtrace_sphere(**k), sphere, cost_sphere),
        "Scene.from_json": (lambda **k: translucent.Scene.from_json(**k),
                            dict(text=translucent.Scene.default().to_json(),
                                 base_dir=files["dir"]), set()),
        "Scene.from_dict": (lambda **k: translucent.Scene.from_dict(**k),
                            dict(d=translucent.Scene.default().to_dict(),
                                 base_dir=files["dir"]), set()),
        "Scene.load": (lambda **k: translucent.Scene.load(**k),
                       dict(path=files["bad_layers"]), set()),
        "Scene.setter": (lambda **k: call_scene_setter(**k),
                         dict(attr="exposure", value=0.5), set()),
        "Scene.save": (lambda **k: translucent.Scene.default().save(**k),
                       dict(path=os.path.join(files["dir"], "saved.json")), set()),
        "technique_parameters": (lambda **k: translucent.technique_parameters(**k),
                                 dict(name="tsm"), set()),
        "BssrdfModel": (lambda **k: translucent.BssrdfModel(**k),
                        dict(path=os.path.join(files["dir"], "missing.bssrdf")), {"path"}),
    }


# Values of the setters' `attr` argument: every writable attribute.
MEDIUM_ATTRS = ["sigma_a", "sigma_s", "g", "eta", "scale"]
SCENE_ATTRS = ["technique", "settings", "model", "time", "exposure", "gamma", "cone_angle",
               "width", "height"]


# ---------------------------------------------------------------------------------------------
# Checking a result.

# Quantities that are infinite by definition for a valid input (ℓd = 1/σtr with σa = 0).
MAY_BE_INFINITE = {"diffuse_mean_free_path"}


def bad_numbers(x, where="result", depth=0):
    """The places in `x` where a number is NaN (or infinite, outside MAY_BE_INFINITE)."""
    out = []
    if depth > 50:
        return out
    if isinstance(x, bool) or x is None or isinstance(x, (str, bytes)):
        return out
    if isinstance(x, (float, int, np.floating, np.integer)):
        v = float(x) if not isinstance(x, int) else 0.0
        if math.isnan(v) or (math.isinf(v) and where.split("[")[-1].strip("]'\"") not in
                             MAY_BE_INFINITE):
            out.append(f"{where} = {x!r}")
        return out
    if isinstance(x, np.ndarray):
        if x.dtype.kind in "fc" and not np.all(np.isfinite(x)):
            out.append(f"{where}: array {x.shape} with {np.count_nonzero(~np.isfinite(x))} "
                       f"non-finite values")
        return out
    if isinstance(x, translucent.Medium):
        for k in ("sigma_a", "sigma_s", "g", "eta", "scale"):
            out += bad_numbers(getattr(x, k), f"{where}.{k}", depth + 1)
        return out
    if isinstance(x, translucent.Scene):
        for k in ("time", "exposure", "gamma", "cone_angle", "width", "height"):
            out += bad_numbers(getattr(x, k), f"{where}.{k}", depth + 1)
        # What the scene would write must read back: the setters validate.
        try:
            translucent.Scene.from_json(x.to_json(), base_dir=".")
        except ALLOWED as e:
            out.append(f"{where}: to_json() does not read back: {e}")
        return out
    if isinstance(x, dict) or hasattr(x, "items"):
        for k, v in x.items():
            out += bad_numbers(v, f"{where}[{k!r}]", depth + 1)
        return out
    if isinstance(x, (list, tuple)):
        for i, v in enumerate(x):
            out += bad_numbers(v, f"{where}[{i}]", depth + 1)
        return out
    return out


def short(v):
    try:
        r = repr(v)
    except Exception:  # Weird's repr raises
        return f"<{type(v).__name__}>"
    return r if len(r) <= 80 else r[:77] + "..."


def test_hostile_arguments(files, tmp_path):
    table = specs(files)
    names = sorted(table)
    rng = random.Random(SEED)
    cwd = os.getcwd()
    os.chdir(tmp_path)  # Scene.save of a relative hostile name writes here
    failures, raised, returned = [], 0, 0
    try:
        for i in range(CALLS):
            name = names[rng.randrange(len(names))]
            fn, valid, cost = table[name]
            kwargs = dict(valid)
            if name == "Medium.setter":
                kwargs["attr"] = rng.choice(MEDIUM_ATTRS)
            elif name == "Scene.setter":
                kwargs["attr"] = rng.choice(SCENE_ATTRS)
            targets = [a for a in kwargs if a != "attr"]
            for arg in rng.sample(targets, min(len(targets), rng.choice([1, 1, 1, 2, 3]))):
                pool = [v for v in HOSTILE if refused_for_cost(v)] if arg in cost else HOSTILE
                kwargs[arg] = pool[rng.randrange(len(pool))]
            shown = ", ".join(f"{k}={short(v)}" for k, v in kwargs.items())
            try:
                out = fn(**kwargs)
            except ALLOWED as e:
                raised += 1
                if not str(e):
                    failures.append(f"call {i}: {name}({shown}): {type(e).__name__} without a "
                                    f"message")
                elif "incompatible function arguments" in str(e):
                    # pybind11's list of signatures: the argument at fault must be named instead
                    # (translucent/_arguments.py).
                    failures.append(f"call {i}: {name}({shown}): {type(e).__name__} does not "
                                    f"name the argument: {short(str(e))}")
                continue
            except BaseException as e:  # noqa: B902 - anything else is the finding
                failures.append(f"call {i}: {name}({shown}): {type(e).__name__}: "
                                f"{short(str(e))}")
                continue
            returned += 1
            for bad in bad_numbers(out):
                failures.append(f"call {i}: {name}({shown}): returned {bad}")
    finally:
        os.chdir(cwd)
    print(f"{CALLS} calls: {returned} returned, {raised} raised TypeError/ValueError/OSError, "
          f"{len(failures)} failures")
    assert not failures, "\n".join(failures[:40]) + (
        f"\n... and {len(failures) - 40} more" if len(failures) > 40 else "")
    assert returned > CALLS // 20 and raised > CALLS // 4  # both sides were reached


# Arguments that no signature of the compiled function accepts: the message names the argument
# and what it expected (translucent/_arguments.py), where pybind11 listed the signatures.
SLAB = dict(sigma_a=1.0, sigma_s=10.0, eta=1.3, photons=2000, threads=1, device="cpu")


@pytest.mark.parametrize("call, kind, text", [
    (lambda: translucent.pathtrace_slab(**{**SLAB, "threads": 2**40}), ValueError,
     "threads=1099511627776: expected an integer in [-2147483648, 2147483647]"),
    (lambda: translucent.pathtrace_slab(**SLAB, angle_bins=2**40), ValueError,
     "angle_bins=1099511627776: expected an integer in [-2147483648, 2147483647]"),
    (lambda: translucent.pathtrace_slab(**SLAB, long_path_roulette=-1), ValueError,
     "long_path_roulette=-1: expected an integer >= 0"),
    (lambda: translucent.pathtrace_slab(**SLAB, long_path_roulette=2**64), ValueError,
     "long_path_roulette=18446744073709551616: expected an integer of at most 64 bits"),
    (lambda: translucent.pathtrace_slab(**SLAB, seed="x"), TypeError,
     "seed='x': expected an integer"),
    (lambda: translucent.pathtrace_slab(**SLAB, theta=10**400), ValueError,
     "theta=10000000... (401 digits): beyond the range of a double"),
    (lambda: translucent.pathtrace_slab(**SLAB, phi=np.array([1.0, 2.0])), TypeError,
     "phi=array([1., 2.]): expected a number"),
    (lambda: translucent.Scene.load("a\0b.json"), ValueError,
     "path='a\\x00b.json': a file name cannot hold a NUL character"),
    (lambda: translucent.Scene.from_json("{}", base_dir="a\0b"), ValueError,
     "base_dir='a\\x00b': a file name cannot hold a NUL character"),
    (lambda: translucent.Scene.from_json('{"a": "\ud800"}'), ValueError,
     "not valid Unicode text (a lone surrogate at index 7)"),
    (lambda: setattr(translucent.Scene.default(), "width", "x"), TypeError,
     "width='x': expected an integer"),
    (lambda: translucent.model("dipole").profiles(3), TypeError,
     "medium=3: expected a translucent.Medium"),
])
def test_unconvertible_arguments_are_named(call, kind, text):
    with pytest.raises(kind) as e:
        call()
    assert text in str(e.value)
    assert "incompatible function arguments" not in str(e.value)


# JSON given as Python objects: a NaN or an infinity is named by its place in the object; a
# number beyond a double's range in JSON text by its line, column and key.
def test_json_values_are_named_by_their_place():
    d = translucent.Scene.default().to_dict()
    d["lights"][0]["irradiance"] = math.nan
    with pytest.raises(ValueError, match=r"^d\['lights'\]\[0\]\['irradiance'\] is nan: expected a "
                                         r"finite number"):
        translucent.Scene.from_dict(d)
    with pytest.raises(ValueError, match=r"^layers\[0\]\['thickness'\] is inf"):
        translucent.pathtrace_slab(eta=1.3, photons=2000, threads=1, device="cpu",
                                   layers=[{"thickness": math.inf, "sigma_a": 1, "sigma_s": 1}])
    text = translucent.Scene.default().to_json().replace('"width": 640', '"width": 1' + "0" * 400)
    with pytest.raises(ValueError, match=r"the number 100000000000… \(401 characters\) at line "
                                         r"\d+, column \d+ \(camera\.width\) is beyond the range"):
        translucent.Scene.from_json(text)


# R(∞) = 0: radii where the closed forms' r² overflows give 0, not NaN, for every model.
def test_far_radii_give_zero():
    for name in translucent.model_names():
        values = translucent.profile(name, [1e154, 5e300, 1e308], material="Skin1")
        assert np.all(values == 0.0), (name, values)
