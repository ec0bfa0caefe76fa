#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""A technique's error against its GPU time over its quality parameter's sweep, through compare.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/sweep_error_vs_time.py \
        --scene data/scenes/cube.json --technique pointcloud --out sweep.png

translucent.compare(..., sweep=True) renders the technique at each value of its quality
parameter (translucent.technique_parameters(name): "sweep") and measures the noise-aware relative
RMSE of the radiance L against the references; this plots it against the median GPU frame time
(log-log), one curve per reference, and prints the table.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import translucent


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=None, help="scene file (default: the built-in bunny)")
    ap.add_argument("--technique", default="pointcloud")
    ap.add_argument("--references", default="model", help="physical, model or physical,model")
    ap.add_argument("--photons", type=float, default=1e6)
    ap.add_argument("--samples", type=float, default=200000)
    ap.add_argument("--width", type=int, default=None)
    ap.add_argument("--height", type=int, default=None)
    ap.add_argument("--frames", type=int, default=3)
    ap.add_argument("--out", default="sweep.png")
    args = ap.parse_args()

    report = translucent.compare(args.scene, techniques=[args.technique],
                                 references=args.references.split(","), photons=args.photons,
                                 samples=args.samples, width=args.width, height=args.height,
                                 frames=args.frames, warmup=1, sweep=True)
    curves = {}  # (parameter, reference) -> [(ms, rel_rmse %, value)]
    for point in report["sweep"]:
        for m in point["metrics"]:
            if m["quantity"] == "radiance":
                curves.setdefault((point["parameter"], m["reference"]), []).append(
                    (point["frame_ms"], 100 * m["metrics"]["rel_rmse"], point["value"]))
    if not curves:
        raise SystemExit(f"{args.technique} has no sweep points: {report['notes']}")
    fig, ax = plt.subplots(figsize=(8, 5))
    for (param, ref), pts in curves.items():
        ms, err, values = zip(*pts)
        ax.plot(ms, err, "o-", label=f"{args.technique} {param} vs {ref}")
        for x, y, v in pts:
            ax.annotate(f"{v:g}", (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
        print(f"{param} vs {ref}:")
        for x, y, v in pts:
            print(f"  {param} = {v:<8g} {x:9.3f} ms  relative RMSE {y:7.3f} %")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("GPU time per frame [ms] (median)")
    ax.set_ylabel("relative RMSE of L, noise-aware [%]")
    ax.set_title(f"{args.technique}: error against time ({report['gpu']})", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
