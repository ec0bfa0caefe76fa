# SPDX-License-Identifier: GPL-3.0-or-later
"""Media, presets and inversion against `translucent presets --json` and `translucent invert`."""
import json

import numpy as np
import pytest

import translucent


def test_presets_match_cli(cli):
    table = json.loads(cli("presets", "--json").stdout)["materials"]
    presets = translucent.presets()
    assert [p.name for p in presets] == [m["name"] for m in table]
    for p, m in zip(presets, table):
        # JSON doubles round-trip exactly: the same numbers, not close ones.
        assert p.sigma_s_prime.tolist() == m["sigma_s_prime"]
        assert p.sigma_a.tolist() == m["sigma_a"]
        assert (p.g, p.eta) == (m["g"], m["eta"])


def test_preset_medium_and_arrays():
    m = translucent.preset("skin1").medium(scale=10)  # case-insensitive, as the CLI
    assert isinstance(m, translucent.Medium)
    assert m.sigma_a.dtype == np.float64 and m.sigma_a.shape == (3,)
    assert m.scale == 10
    assert m.sigma_s_prime.tolist() == translucent.preset("Skin1").sigma_s_prime.tolist()
    # channel(): coefficients per scene unit (σ · scale).
    assert m.channel(0)["sigma_a"] == pytest.approx(0.032 * 10, rel=1e-15)


def test_medium_validation_message():
    with pytest.raises(ValueError, match="g"):
        translucent.Medium(g=1.5)
    with pytest.raises(ValueError, match="sigma_a"):
        translucent.Medium(sigma_a=(0.1, 0.2))


def test_unknown_preset_same_message_as_cli(cli_error, as_python):
    expected = cli_error("profile", "--preset", "Nope", "--out", "/tmp/never.csv")
    with pytest.raises(ValueError) as e:
        translucent.preset("Nope")
    assert str(e.value) == as_python(expected)


@pytest.mark.parametrize("model", ["dipole", "better-dipole", "photon-beam"])
def test_invert_matches_cli(cli, model):
    out = json.loads(cli("invert", "--model", model, "--rd", "0.8,0.6,0.4", "--ld", "5,2,1",
                         "--eta", "1.4", "--json").stdout)
    m = translucent.invert(model, [0.8, 0.6, 0.4], [5, 2, 1], eta=1.4)
    assert m.sigma_a.tolist() == out["sigma_a"]
    assert m.sigma_s_prime.tolist() == out["sigma_s_prime"]
    assert m.eta == 1.4


def test_invert_unreachable_same_message_as_cli(cli_error, as_python):
    expected = cli_error("invert", "--model", "dipole", "--rd", "1.5", "--ld", "1")
    with pytest.raises(ValueError) as e:
        translucent.invert("dipole", 1.5, 1)
    assert str(e.value) == as_python(expected)


def test_fdr_is_the_rational_fit():
    # Egan & Hilgeman's fit (1979), evaluated by the same expression in Python.
    for eta in (1.0, 1.3, 1.5, 2.0):
        expected = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
        assert translucent.fdr(eta) == pytest.approx(expected, rel=1e-15, abs=1e-15)


def test_medium_channel_derived_quantities():
    m = translucent.Medium(sigma_a=(0.1, 0.2, 0.3), sigma_s=(2.0, 3.0, 4.0), g=0.5, eta=1.4,
                           scale=2.0)
    c = m.channel(1)
    sa, ss = 0.2 * 2.0, 3.0 * 2.0
    sp = (1 - 0.5) * ss
    assert (c["sigma_a"], c["sigma_s"], c["g"], c["eta"]) == (sa, ss, 0.5, 1.4)
    assert c["reduced_albedo"] == pytest.approx(sp / (sa + sp), rel=1e-15)
    assert c["sigma_tr"] == pytest.approx((3 * sa * (sa + sp)) ** 0.5, rel=1e-15)
    assert c["diffuse_mean_free_path"] == pytest.approx(1 / c["sigma_tr"], rel=1e-15)
    with pytest.raises(ValueError, match="channel 3"):
        m.channel(3)
