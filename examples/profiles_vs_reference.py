#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Radial profiles R(r) of every BSSRDF model against the path-traced reference, for a preset.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/profiles_vs_reference.py \
        --preset Skin1 --photons 1e6 --out skin1_profiles.png

One panel per RGB channel: each model's R(r) (translucent.profile) and the reference (a pencil
beam on a semi-infinite slab of the medium, translucent.pathtrace_slab) with ±1 standard error,
as `translucent profile --reference` plots them. The reference's Rd(r) is per incident photon;
the models' R(r) is per unit flux entering the medium, so the tally is divided by 1 - Rsp (the
exact entry transmittance).
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import numpy as np

import translucent


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--preset", default="Skin1")
    ap.add_argument("--photons", type=float, default=1e6, help="reference photons per channel")
    ap.add_argument("--bins", type=int, default=60, help="annuli of the reference")
    ap.add_argument("--out", default="profiles.png")
    args = ap.parse_args()

    medium = translucent.preset(args.preset).medium()
    # The plotted range: the largest 95% energy radius of the models, as the CLI's default.
    r_max = max(translucent.model(m).profiles(medium).radius(0.95).max()
                for m in translucent.model_names())
    r = np.linspace(r_max / 400, r_max, 400)

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5), sharey=True)
    for c, (ax, channel) in enumerate(zip(axes, "rgb")):
        for model in translucent.model_names():
            R = translucent.profile(model, r, preset=args.preset)
            ax.plot(r, R[:, c], label=model, lw=1.2)
        ref = translucent.pathtrace_slab(preset=args.preset, channel=channel,
                                         photons=args.photons, seed=1 + c,
                                         radial_bins=args.bins, radial_max=r_max)
        entered = 1.0 - ref["specular_reflectance"]
        rad = ref["radial"]
        ax.errorbar(rad["r"], rad["rd"] / entered, yerr=rad["rd_stderr"] / entered, fmt="k.",
                    ms=3, lw=0.8, label=f"path traced ({ref['photons']:.3g} photons)")
        ax.set_yscale("log")
        ax.set_xlabel("r [mm]")
        ax.set_title(f"{args.preset}, {['red', 'green', 'blue'][c]} channel")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("R(r) [1/mm²]")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
