# SPDX-License-Identifier: GPL-3.0-or-later
"""Models and profiles against `translucent profile --out x.csv` (9 significant digits)."""
import csv
import json

import numpy as np
import pytest

import translucent


def read_curves(path):
    """{(model, channel): (r strings, value strings)} of a profile CSV."""
    curves = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            r, v = curves.setdefault((row["model"], row["channel"]), ([], []))
            r.append(row["r"])
            v.append(row["value"])
    return curves


MEDIA = [
    # (CLI options, profile() keywords)
    (["--material", "Skin1"], dict(material="Skin1")),
    (["--material", "Marble", "--g", "0.5", "--eta", "1.4", "--scale", "10"],
     dict(material="Marble", g=0.5, eta=1.4, scale=10)),
    (["--sigma-a", "0.01,0.02,0.05", "--sigma-s", "1.0,1.5,2", "--g", "0.8", "--eta", "1.33"],
     dict(sigma_a=[0.01, 0.02, 0.05], sigma_s=[1.0, 1.5, 2.0], g=0.8, eta=1.33)),
]


@pytest.mark.parametrize("cli_args,kwargs", MEDIA)
def test_profile_matches_cli_csv(cli, tmp_path, cli_args, kwargs):
    out = tmp_path / "p.csv"
    points, r_max = 50, 7.0
    cli("profile", "--model", "all", "--channel", "all", "--points", points, "--rmax", r_max,
        *cli_args, "--out", out)
    curves = read_curves(out)
    assert {m for m, _ in curves} == set(translucent.model_names())
    # The CLI's grid, computed as analysis::radiusGrid does: r_i = r_max (i + 1) / points (the
    # radii of the CSV are printed to 9 digits only, not enough to call R at the same r).
    r = np.array([r_max * (i + 1) / points for i in range(points)])
    for model in translucent.model_names():
        R = translucent.profile(model, r, **kwargs)
        assert R.shape == (points, 3)
        for c, ch in enumerate("rgb"):
            assert curves[(model, ch)][0] == [f"{x:.9g}" for x in r]
            # The CSV prints {:.9g}; Python's '.9g' of the same double is the same text.
            assert [f"{v:.9g}" for v in R[:, c]] == curves[(model, ch)][1], (model, ch)


def test_profile_signature_is_the_documented_one():
    # translucent.profile(model, r, preset=None, sigma_a=None, sigma_s=None, g=0, eta=1.3, scale=1,
    #                     *, medium=None, material=None)
    first = translucent.profile.__doc__.splitlines()[0]
    for arg in ["model", "r", "preset", "sigma_a", "sigma_s", "g", "eta", "scale"]:
        assert f"{arg}:" in first, (arg, first)
    assert "preset: Optional[str] = None" in first and "g: Optional[float] = 0.0" in first, first
    assert "eta: Optional[float] = 1.3" in first and "scale: float = 1.0" in first, first
    r = np.linspace(0.1, 4, 7)
    assert "material: Optional[str] = None" in first, first  # keyword only, the CLI's --material
    # The defaults are every preset's own g and eta: giving them changes nothing. (The third
    # positional argument is the preset's deprecated spelling.)
    with pytest.warns(DeprecationWarning):
        positional = translucent.profile("dipole", r, "Skin1", None, None, 0, 1.3, 1)
    assert np.array_equal(translucent.profile("dipole", r, material="Skin1"), positional)
    # Another g with a preset: sigma_s = sigma_s' / (1 - g), as `profile --preset --g`.
    p = translucent.preset("Skin1")
    m = translucent.Medium.from_reduced(p.sigma_a, p.sigma_s_prime, 0.5, 1.3)
    assert np.array_equal(translucent.profile("dipole", r, material="Skin1", g=0.5),
                          translucent.profile("dipole", r, medium=m))
    assert not np.array_equal(translucent.profile("dipole", r, material="Skin1", eta=1.5),
                              translucent.profile("dipole", r, material="Skin1"))


@pytest.mark.parametrize("name", ["dipole", "better-dipole", "normalized-diffusion",
                                  "normalized-diffusion-fit", "quantized-diffusion", "photon-beam"])
def test_every_model_rd_and_radius_agree_with_quadrature_of_its_profile(name):
    # Profiles.Rd (each model's own total, analytic or tabulated in C++) against 2π ∫ R(r) r dr
    # by quadrature of Profiles.R here (an independent computation, to 1%: the tail beyond
    # 200 mean free paths and the grid's error are below that), and radius() in order.
    assert name in translucent.model_names()
    medium = translucent.preset("Skin1").medium()
    p = translucent.model(name).profiles(medium)
    rd = p.Rd
    x = np.geomspace(1e-7, 400.0, 400001)
    R = p.R(x)
    for c in range(3):
        y = 2 * np.pi * x * R[:, c]
        assert np.trapz(y, x) == pytest.approx(rd[c], rel=1e-2), (name, c)
    r50 = p.radius(0.5)
    assert np.all(r50 > 0) and np.all(r50 < p.radius(0.95))


def test_profile_array_layout():
    r = np.linspace(0.1, 3.0, 12).reshape(3, 4)
    R = translucent.profile("dipole", r)
    assert R.shape == (3, 4, 3) and R.dtype == np.float64 and R.flags["C_CONTIGUOUS"]
    assert R.flags["OWNDATA"] is False  # the C++ buffer itself, handed over without a copy
    flat = translucent.profile("dipole", r.ravel())
    assert np.array_equal(R.reshape(-1, 3), flat)
    # Lists and integer arrays are accepted (converted to float64).
    assert np.array_equal(translucent.profile("dipole", [1, 2]),
                          translucent.profile("dipole", np.array([1.0, 2.0])))


def test_profiles_object_matches_profile():
    medium = translucent.preset("Ketchup").medium()
    p = translucent.model("better-dipole").profiles(medium)
    r = np.geomspace(0.01, 20, 64)
    assert np.array_equal(p.R(r), translucent.profile("better-dipole", r, material="Ketchup"))
    rd = p.Rd
    assert rd.shape == (3,) and np.all((rd > 0) & (rd < 1))
    # radius(f): the cumulative 2π∫0^r R r' dr' reaches f·Rd there (checked by quadrature of
    # R(r) on a fine grid, to 0.5%).
    r95 = p.radius(0.95)
    for c in range(3):
        x = np.linspace(1e-6, r95[c], 200001)
        y = 2 * np.pi * x * p.R(x)[:, c]
        assert np.trapz(y, x) / rd[c] == pytest.approx(0.95, rel=5e-3)
    # sample(): r increases with u and its pdf is pdf(r).
    u = np.array([0.1, 0.5, 0.9])
    rs, pdf = p.sample(u)
    assert rs.shape == (3, 3) and pdf.shape == (3, 3)
    assert np.all(np.diff(rs, axis=0) > 0)
    for c in range(3):
        assert p.pdf(rs[:, c])[:, c] == pytest.approx(pdf[:, c], rel=1e-9)


def test_unknown_model_same_message_as_cli(cli_error, as_python):
    expected = cli_error("profile", "--model", "nope", "--out", "/tmp/never.csv")
    with pytest.raises(ValueError) as e:
        translucent.profile("nope", [1.0])
    assert str(e.value) == as_python(expected)


def test_bad_medium_same_message_as_cli(cli_error, as_python):
    expected = cli_error("profile", "--model", "dipole", "--sigma-a", "-1", "--sigma-s", "1",
                         "--out", "/tmp/never.csv")
    with pytest.raises(ValueError) as e:
        translucent.profile("dipole", [1.0], sigma_a=-1, sigma_s=1)
    assert str(e.value) == as_python(expected)


def test_bssrdf_file_profile_matches_cli_csv(cli, source_dir, tmp_path):
    # A .bssrdf plug-in model, evaluated on the GPU (llvmpipe without one), as the CLI does.
    model = source_dir / "data" / "bssrdf" / "better-dipole.bssrdf"
    out = tmp_path / "p.csv"
    points, r_max = 40, 6.0
    cli("profile", "--model", model, "--channel", "all", "--points", points, "--rmax", r_max,
        "--preset", "Skin1", "--out", out)
    curves = read_curves(out)
    r = np.array([r_max * (i + 1) / points for i in range(points)])
    R = translucent.profile(str(model), r, material="Skin1")
    assert R.shape == (points, 3) and R.dtype == np.float64
    for c, ch in enumerate("rgb"):
        assert [f"{v:.9g}" for v in R[:, c]] == curves[("better-dipole", ch)][1], ch
    # The GPU's float32 evaluation of the same formula as the C++ model: within 1e-5.
    cpu = translucent.profile("better-dipole", r, material="Skin1")
    assert np.allclose(R, cpu, rtol=1e-5, atol=0)


def test_bssrdf_model_parameters_and_invert(cli, source_dir):
    path = str(source_dir / "data" / "bssrdf" / "better-dipole.bssrdf")
    b = translucent.BssrdfModel(path)
    assert b.name == "better-dipole" and "Multiplier" in b.parameters
    expected = json.loads(cli("invert", "--model", path, "--rd", "0.8,0.6,0.4", "--ld", "5,2,1",
                              "--json").stdout)
    m = b.invert([0.8, 0.6, 0.4], [5, 2, 1])
    assert m.sigma_a.tolist() == expected["sigma_a"]
    assert m.sigma_s_prime.tolist() == expected["sigma_s_prime"]
    medium = translucent.preset("Skin1").medium()
    r = np.array([0.5, 1.0, 2.0])
    base = b.profile(medium, r)
    b.set(Multiplier=2.0)
    assert b.parameters["Multiplier"] == 2.0
    assert np.allclose(b.profile(medium, r), 2 * base, rtol=1e-6)
    e = b.energy(medium)
    assert e["Rd"].shape == (3,) and np.all(e["radius"] > 0)
    with pytest.raises(ValueError, match="declares no parameter 'Nope'"):
        b.set(Nope=1.0)


def read_table(path):
    """(header comments, r, R[n, 3]) of a tabulated-profile CSV (r,R_r,R_g,R_b)."""
    comments, rows = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                comments.append(line[1:].strip())
            elif not line.startswith("r,"):
                rows.append([float(x) for x in line.split(",")])
    rows = np.array(rows)
    return comments, rows[:, 0], rows[:, 1:]


def test_tabulated_profile_from_the_path_tracer(cli, tmp_path):
    # `profile --reference --save-profile` turns the path-traced R(r) into a model (tabulated
    # files wherever a model is named).
    saved = tmp_path / "skin1.csv"
    cli("profile", "--preset", "Skin1", "--reference", "--photons", 200000, "--device", "cpu",
        "--save-profile", saved)
    comments, r, R = read_table(saved)
    assert "units: mm" in comments and len(r) > 100
    # At its samples the model is the table; at scale 10 (scene units of 1 cm) r and R convert.
    assert np.allclose(translucent.profile(str(saved), r, material="Skin1"), R, rtol=1e-12, atol=0)
    # (r / 10 · 10 is not always r: next to an empty annulus R is then ~1e-19, not 0)
    assert np.allclose(translucent.profile(str(saved), r / 10, material="Skin1", scale=10), R * 100,
                       rtol=1e-9, atol=1e-12 * R.max())
    # Its Rd (quadrature of the interpolated table and its fitted tail) is the tracer's own total
    # diffuse reflectance, which the file records: the merged annuli keep each annulus's energy,
    # so what is lost is the interpolation near the source and the tail beyond 3x the 95% radius.
    traced = next(c for c in comments if c.startswith("traced Rd"))
    traced = np.array([float(x) for x in traced.split(":")[1].split(",")])
    medium = translucent.preset("Skin1").medium()
    rd = translucent.model(str(saved)).profiles(medium).Rd
    assert rd == pytest.approx(traced, rel=0.01)
    # The CLI plots it under its file's stem, with the values profile() gives.
    out = tmp_path / "p.csv"
    points, r_max = 40, 6.0
    cli("profile", "--model", f"dipole,{saved}", "--channel", "all", "--points", points, "--rmax",
        r_max, "--preset", "Skin1", "--out", out)
    curves = read_curves(out)
    grid = np.array([r_max * (i + 1) / points for i in range(points)])
    ours = translucent.profile(str(saved), grid, material="Skin1")
    for c, ch in enumerate("rgb"):
        assert [f"{v:.9g}" for v in ours[:, c]] == curves[("skin1", ch)][1], ch


def test_tabulated_profile_errors_name_the_file(cli_error, as_python, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n0.05,1,2,3\n")
    expected = cli_error("profile", "--model", bad, "--out", tmp_path / "x.csv")
    assert f"{bad}:4: r 0.05 after 0.1" in expected
    with pytest.raises(ValueError) as e:
        translucent.profile(str(bad), [1.0])
    assert str(e.value) == as_python(expected)
    # A table has no Rd(α') and no profile of a scalar medium.
    good = tmp_path / "good.csv"
    good.write_text("# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n1,0.1,0.2,0.3\n")
    with pytest.raises(ValueError, match="tabulated profile"):
        translucent.model(str(good)).total_reflectance(0.9, 1.3)


def test_material_is_the_preset_and_preset_is_deprecated():
    """material= is the CLI's --material in every function; preset= still works, with a
    DeprecationWarning, and both together are refused."""
    r = np.linspace(0.1, 2.0, 7)
    new = translucent.profile("dipole", r, material="Skin1")
    with pytest.warns(DeprecationWarning, match=r"translucent\.profile: preset= is deprecated: use material=Skin1"):
        old = translucent.profile("dipole", r, preset="Skin1")
    assert np.array_equal(new, old)
    assert not np.array_equal(new, translucent.profile("dipole", r, material="Marble"))
    with pytest.raises(ValueError, match="material= and preset="):
        translucent.profile("dipole", r, material="Skin1", preset="Skin1")
    with pytest.raises(ValueError, match="valid presets"):
        translucent.profile("dipole", r, material="Jelly")
    small = dict(width=8, height=8, time_limit=30)
    for f, kw in [(translucent.pathtrace_sphere, dict(photons=2000, **small)),
                  (translucent.integrate_sphere, dict(samples=2, **small)),
                  (translucent.pathtrace_slab, dict(channel="r", photons=2000))]:
        a = f(material="Skin1", seed=3, threads=1, **kw)
        with pytest.warns(DeprecationWarning, match=f"translucent.{f.__name__}: preset="):
            b = f(preset="Skin1", seed=3, threads=1, **kw)
        assert a.medium == b.medium, f.__name__
        with pytest.raises(ValueError, match="material= and preset="):
            f(material="Skin1", preset="Marble", **kw)
