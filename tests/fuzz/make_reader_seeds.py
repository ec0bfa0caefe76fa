#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the seed corpora of fuzz_layers and fuzz_tabulated (tests/fuzz/corpus/<name>/).

Usage: make_reader_seeds.py layers|tabulated [FOLDER]   (default: the committed corpus folder)

The data/ folder holds neither a layers file nor a tabulated profile, so the valid seeds are the
documented examples (docs/guide/references.md, docs/guide/models.md) and small variants of them
that reach each branch of the readers (a semi-infinite last layer or none, "g" left out, the RGB
table and the `translucent profile` curves CSV, each unit, an "eta" line, CRLF line ends, a zero
sample at r = 0); the malformed seeds are the cases the unit tests
(tests/reference/test_layered_slab.cpp, tests/bssrdf/test_tabulated.cpp) expect to be refused, so
that the fuzzer starts from both sides of every check. Each file stays well under 4 KB.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def write(folder, name, text):
    data = text.encode() if isinstance(text, str) else text
    assert len(data) < 4096, name
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def layer(t, a, s, g=None):
    parts = [f'"thickness": {"null" if t is None else t}', f'"sigma_a": {a}', f'"sigma_s": {s}']
    if g is not None:
        parts.append(f'"g": {g}')
    return "{" + ", ".join(parts) + "}"


def layers(folder):
    valid = {
        # docs/guide/references.md
        "valid_docs.json": [(0.1, 0.5, 9.5, 0.8), (None, 0.3, 4.7, 0)],
        "valid_one_finite.json": [(1, 1, 10, 0.9)],
        "valid_one_semi_infinite.json": [(None, 0.1, 10, None)],
        "valid_three_finite.json": [(0.05, 2, 20, 0.8), (0.2, 0.1, 30, 0.9), (1.5, 0.5, 5, -0.3)],
        # epidermis, dermis, subcutis-like: absorbing top, scattering below
        "valid_skin_like.json": [(0.1, 3.3, 100, 0.8), (1.5, 0.26, 20, 0.9), (None, 0.05, 12, 0.8)],
        "valid_transparent_top.json": [(0.5, 0, 1e-3, 0), (None, 1, 10, 0.5)],
        "valid_absorber_only.json": [(2, 5, 0, 0), (None, 1, 1, 0)],
    }
    for name, ls in valid.items():
        write(folder, name, "[" + ",\n ".join(layer(*l) for l in ls) + "]\n")
    malformed = {
        "bad_not_array.json": '{"thickness": 1, "sigma_a": 1, "sigma_s": 1}',
        "bad_empty.json": "[]",
        "bad_not_json.json": "[{thickness: 1}",
        "bad_unknown_key.json": '[{"thickness": 1, "sigma_a": 1, "sigma_s": 1, "G": 0}]',
        "bad_missing_sigma_a.json":
            '[{"thickness": 1, "sigma_a": 1, "sigma_s": 1}, {"thickness": 1, "sigma_s": 1}]',
        "bad_null_not_last.json":
            '[{"thickness": null, "sigma_a": 1, "sigma_s": 1}, {"thickness": 1, "sigma_a": 1, "sigma_s": 1}]',
        "bad_negative_thickness.json": '[{"thickness": -1, "sigma_a": 1, "sigma_s": 1}]',
        "bad_string_number.json": '[{"thickness": 1, "sigma_a": 1, "sigma_s": "a"}]',
        "bad_g_one.json": '[{"thickness": 1, "sigma_a": 1, "sigma_s": 1, "g": 1}]',
        "bad_zero_medium.json": '[{"thickness": 1, "sigma_a": 0, "sigma_s": 0}]',
        "bad_semi_infinite_no_absorption.json": '[{"thickness": null, "sigma_a": 0, "sigma_s": 1}]',
        "bad_huge.json": '[{"thickness": 1e300, "sigma_a": 1e-300, "sigma_s": 1e300, "g": -0.999999}]',
        "bad_deep.json": "[" * 600 + "]" * 600,
        "bad_nul.json": b'[{"thickness": 1, "sigma_a": 1\x00, "sigma_s": 1}]',
    }
    for name, text in malformed.items():
        write(folder, name, text)


def dipole_like(r_mm, sigma_tr, scale):
    # A smooth, decaying radial profile of the shape of the dipole's far field (exp(-σtr r)/r²
    # near r^-1 at small r): realistic enough to exercise the interpolation and the tail fit.
    return scale * math.exp(-sigma_tr * r_mm) / (r_mm + 0.05) ** 1.5


def tabulated(folder):
    radii = [0.005 * 1.35 ** i for i in range(24)]
    rows = "".join(
        f"{r:.6g},{dipole_like(r, 1.2, 1):.6g},{dipole_like(r, 2.5, 0.8):.6g},"
        f"{dipole_like(r, 4.0, 0.6):.6g}\n" for r in radii)
    write(folder, "valid_rgb_mm.csv", "# units: mm\n# eta: 1.3\nr,R_r,R_g,R_b\n" + rows)
    write(folder, "valid_rgb_crlf_um.csv",
          ("# a comment\n# units: um\nr,R_r,R_g,R_b\n" +
           "".join(f"{r * 1000:.6g},{dipole_like(r, 1.2, 1e-6):.6g},{dipole_like(r, 2, 1e-6):.6g},"
                   f"{dipole_like(r, 3, 1e-6):.6g}\n" for r in radii[::3])).replace("\n", "\r\n"))
    write(folder, "valid_rgb_zero_at_origin.csv",
          "# units: cm\nr,R_r,R_g,R_b\n0,0,0.5,1\n0.01,1,1,1\n0.1,0.2,0.1,0.05\n1,0.001,0,0\n")
    write(folder, "valid_rgb_two_samples_m.csv", "# Units: M\nR,r_r,r_g,r_b\n0.001,5,6,7\n0.002,4,5,6\n")
    write(folder, "valid_rgb_flat_tail.csv",
          "# units: mm\nr,R_r,R_g,R_b\n0.1,1,1,1\n0.2,1,2,1\n0.3,1,3,0\n")
    curves = "# units: cm\nmodel,channel,r,value,stderr\n"
    for model, k in (("reference", 1.0), ("dipole", 1.1)):
        for ch, st in (("r", 1.2), ("g", 2.5), ("b", 4.0), ("luminance", 2.0)):
            for r in radii[::4]:
                curves += f"{model},{ch},{r / 10:.6g},{dipole_like(r, st, k) * 100:.6g},0.01\n"
    write(folder, "valid_curves_reference.csv", curves)
    write(folder, "valid_curves_one_model.csv",
          "model,channel,r,value\n" + "".join(
              f"pbd,{ch},{r:.6g},{dipole_like(r, 2, 1):.6g}\n"
              for ch in ("r", "g", "b") for r in radii[::6]))
    malformed = {
        "bad_no_units.csv": "r,R_r,R_g,R_b\n0.1,1,2,3\n1,1,1,1\n",
        "bad_unit.csv": "# units: furlong\nr,R_r,R_g,R_b\n",
        "bad_header.csv": "# units: mm\nradius,a,b,c\n",
        "bad_decreasing.csv": "# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n0.05,1,2,3\n",
        "bad_not_number.csv": "# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n0.2,1,x,3\n",
        "bad_negative.csv": "# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n0.2,1,-2,3\n",
        "bad_three_values.csv": "# units: mm\nr,R_r,R_g,R_b\n0.1,1,2\n",
        "bad_one_sample.csv": "# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n",
        "bad_zero_channel.csv": "# units: mm\nr,R_r,R_g,R_b\n0.1,0,2,3\n0.2,0,2,3\n",
        "bad_two_models.csv": "model,channel,r,value\na,r,0.1,1\nb,r,0.1,1\n",
        "bad_no_green.csv": "model,channel,r,value\nreference,r,0.1,1\nreference,r,0.2,1\n",
        "bad_overflow.csv": "# units: mm\nr,R_r,R_g,R_b\n0.1,1,1,1\n0.2,1e300,1,1\n",
        "bad_subnormal_peak.csv": "# units: mm\nr,R_r,R_g,R_b\n0.1,1,1e-320,1\n0.2,1,1e-321,1\n",
        "bad_far.csv": "# units: m\nr,R_r,R_g,R_b\n0.1,1,1,1\n2000,1,1,1\n",
        "bad_nul.csv": b"# units: mm\nr,R_r,R_g,R_b\n0.1,1,1,1\n0.2,1,x\x00y,1\n",
        "bad_eta.csv": "# eta: -1\n# units: mm\nr,R_r,R_g,R_b\n0.1,1,1,1\n0.2,1,1,1\n",
    }
    for name, text in malformed.items():
        write(folder, name, text)


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] not in ("layers", "tabulated"):
        sys.exit(__doc__)
    target = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "corpus", target)
    os.makedirs(out, exist_ok=True)
    (layers if target == "layers" else tabulated)(out)
    print(f"{target} seeds in {out}")
