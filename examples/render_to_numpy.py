#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Renders a scene into a NumPy array and writes it as OpenEXR (linear) and PNG (tone mapped).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/render_to_numpy.py \
        --scene data/scenes/cube.json --technique pointcloud --out cube

translucent.render returns the linear radiance as an (height, width, 3) float32 array (rows from
the top) plus its layers (e.g. "exitance") and the GPU time of every pass. The PNG applies the
scene's display settings as `translucent render --out x.png` does: × 2^exposure, clamp to
[0, 1], ^(1/gamma). Images are written with OpenImageIO's Python bindings (python3-openimageio).
"""
import argparse

import numpy as np
import OpenImageIO as oiio

import translucent


def write(path, pixels):
    out = oiio.ImageOutput.create(path)
    if not out:
        raise SystemExit(oiio.geterror())
    h, w, c = pixels.shape
    fmt = oiio.HALF if path.endswith(".exr") else oiio.UINT8
    if not out.open(path, oiio.ImageSpec(w, h, c, fmt)) or not out.write_image(pixels):
        raise SystemExit(out.geterror())
    out.close()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=None, help="scene file (default: the built-in bunny)")
    ap.add_argument("--technique", default=None, help="default: the scene's")
    ap.add_argument("--width", type=int, default=None)
    ap.add_argument("--height", type=int, default=None)
    ap.add_argument("--out", default="render", help="writes OUT.exr and OUT.png")
    args = ap.parse_args()

    scene = translucent.Scene.load(args.scene) if args.scene else translucent.Scene.default()
    frame = translucent.render(scene, args.technique, width=args.width, height=args.height)
    image = frame["image"]
    print(f"{frame['technique']}: {image.shape[1]}x{image.shape[0]}, "
          f"{frame['total_ms']:.2f} ms on {translucent.gl_info()['renderer']}")
    for p in frame["passes"]:
        print(f"  {'  ' * p['depth']}{p['name']:<22} {p['ms']:9.3f} ms")
    write(args.out + ".exr", image)
    display = np.clip(image * 2.0 ** scene.exposure, 0.0, 1.0) ** (1.0 / scene.gamma)
    write(args.out + ".png", display)
    for name, layer in frame["layers"].items():
        print(f"  layer {name}: mean {layer.mean():.4g}")
    print(f"wrote {args.out}.exr and {args.out}.png")


if __name__ == "__main__":
    main()
