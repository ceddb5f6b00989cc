#!/usr/bin/env python3
"""Which default tone map keeps base colours as the glTF viewers show them (docs/cli.md,
"Exposure and tone maps"): renders three Khronos samples with each tone map and measures them
against the samples' screenshots.

Run: python3 scripts/tonemap/choice.py LENSRAY MODELS OUT
  LENSRAY  the lensray binary (target/release/lensray)
  MODELS   a directory with VertexColorTest.glb, VertexColorTest-ref.png (its screenshot),
           EmissiveStrengthTest.glb and LightsPunctualLamp/LightsPunctualLamp.gltf, from
           KhronosGroup/glTF-Sample-Assets
  OUT      where the renders go
Needs numpy and pillow.
"""
import subprocess
import sys
from pathlib import Path

import numpy as np
from PIL import Image

TONEMAPS = ["none", "neutral", "agx"]
# EmissiveStrengthTest's strength-1 cube in its screenshot: its emission (0.1, 0.5, 0.9).
CUBE_REFERENCE = np.array([91, 186, 244])


def load(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(int)


def render(lensray, scene, out, *options):
    args = [lensray, "render", "--scene", str(scene), "--width", "320", "--height", "240"]
    subprocess.run(args + list(options) + ["--out", str(out)], check=True, capture_output=True)


def vertex_colour_classes(a):
    """The flat colours of VertexColorTest's board, told apart by their hue."""
    r, g, b = a[..., 0], a[..., 1], a[..., 2]
    return {
        "red check": (r > 150) & (g < 90) & (b < 90),
        "green check": (g > 150) & (r < 90) & (b < 90),
        "blue board": (b > 120) & (b <= 215) & (r < 90) & (g < 90),
        "blue check": (b > 215) & (r < 90) & (g < 90),
        "black square": (r < 50) & (g < 50) & (b < 50),
    }


def main(lensray, models, out):
    models, out = Path(models), Path(out)
    out.mkdir(parents=True, exist_ok=True)
    scenes = {
        "vertex": models / "VertexColorTest.glb",
        "emissive": models / "EmissiveStrengthTest.glb",
        "lamp": models / "LightsPunctualLamp" / "LightsPunctualLamp.gltf",
    }
    for name, scene in scenes.items():
        for t in TONEMAPS:
            render(lensray, scene, out / f"{name}-{t}.png", "--spp", "128", "--tonemap", t)
    # The lamp's pixels: where an unlit render does not show the magenta background.
    render(lensray, scenes["lamp"], out / "lamp-mask.png", "--spp", "16", "--shading", "unlit",
           "--background", "1,0,1", "--tonemap", "none")

    screenshot = load(models / "VertexColorTest-ref.png")
    reference = {k: np.median(screenshot[m], axis=0)
                 for k, m in vertex_colour_classes(screenshot).items()}
    # The classes and the cube are found in the render without a tone map, the same pixels
    # then measured in each.
    classes = vertex_colour_classes(load(out / "vertex-none.png"))
    plain = load(out / "emissive-none.png")
    cube = (plain[..., 2] > 230) & (plain[..., 1] > 150)
    left = np.where(cube.any(axis=0))[0].min()
    cube[:, left + 25:] = False
    mask = load(out / "lamp-mask.png")
    model = ~((mask[..., 0] > 250) & (mask[..., 1] < 5) & (mask[..., 2] > 250))
    for t in TONEMAPS:
        a = load(out / f"vertex-{t}.png")
        parts = []
        for k, m in classes.items():
            median = np.median(a[m], axis=0)
            worst = int(np.abs(median - reference[k]).max())
            parts.append(f"{k} {tuple(int(x) for x in median)} vs "
                         f"{tuple(int(x) for x in reference[k])} ({worst})")
        print(f"{t}: VertexColorTest: " + ", ".join(parts))
        median = np.median(load(out / f"emissive-{t}.png")[cube], axis=0)
        worst = int(np.abs(median - CUBE_REFERENCE).max())
        print(f"{t}: EmissiveStrengthTest's strength-1 cube {tuple(int(x) for x in median)} "
              f"vs {tuple(int(x) for x in CUBE_REFERENCE)} ({worst})")
        lamp = load(out / f"lamp-{t}.png")[model]
        clipped = 100 * (lamp >= 255).any(axis=1).mean()
        print(f"{t}: LightsPunctualLamp: {clipped:.1f} % of the model's pixels with a channel at 255")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
