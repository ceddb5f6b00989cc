#!/usr/bin/env python3
"""What Khronos PBR Neutral can show at all (docs/cli.md, "Exposure and tone maps"): the least
worst channel error, in 8-bit sRGB levels, between a screenshot's flat colour and Neutral's
output for that surface under any light (or exposure) and any Fresnel reflection on top, found
by a sweep. No renderer is involved: the formula is the specification's (KhronosGroup/
ToneMapping, PBR_Neutral), written here again, independently of lensray's.

Run: python3 scripts/tonemap/neutral_reach.py
Needs numpy.
"""
import numpy as np

START_COMPRESSION = 0.8 - 0.04
DESATURATION = 0.15


def neutral(colour):
    """Khronos PBR Neutral of a linear colour."""
    c = np.array(colour, dtype=float)
    x = c.min()
    offset = x - 6.25 * x * x if x < 0.08 else 0.04
    c = c - offset
    peak = c.max()
    if peak < START_COMPRESSION:
        return c
    d = 1.0 - START_COMPRESSION
    new_peak = 1.0 - d * d / (peak + d - START_COMPRESSION)
    c = c * (new_peak / peak)
    g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0)
    return c * (1.0 - g) + new_peak * g


def srgb_bytes(linear):
    x = np.clip(linear, 0.0, 1.0)
    encoded = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
    return np.round(encoded * 255.0)


def linear(levels):
    x = np.asarray(levels, dtype=float) / 255.0
    return np.where(x <= 0.04045, x / 12.92, ((x + 0.055) / 1.055) ** 2.4)


def best(surface, reference, scales, fresnels):
    """The least worst channel error over every scale (light or exposure) and reflection."""
    found = None
    for k in scales:
        for f in fresnels:
            shown = srgb_bytes(neutral(k * surface + f))
            error = np.abs(shown - reference).max()
            if found is None or error < found[0]:
                found = (error, k, f, shown)
    return found


def main():
    fresnels = np.linspace(0.0, 0.06, 61)
    # VertexColorTest's red check, a pure red base colour lit by a white light of any
    # strength k (k = 1: a face-on white is 1), with any share of white reflection on top.
    red = best(np.array([1.0, 0.0, 0.0]), np.array([255, 1, 2]),
               np.linspace(0.3, 4.0, 1481), fresnels)
    # EmissiveStrengthTest's strength-1 cube: the screenshot's colour as emission, at any
    # exposure, with any reflection on top.
    cube_ref = np.array([91, 186, 244])
    cube = best(linear(cube_ref), cube_ref, np.linspace(0.3, 4.0, 1481), fresnels)
    # The same cube at exposure 1 (the default), any reflection.
    cube1 = best(linear(cube_ref), cube_ref, [1.0], fresnels)
    for name, (error, k, f, shown) in [("VertexColorTest red check, against (255, 1, 2)", red),
                                       ("EmissiveStrengthTest cube, against (91, 186, 244)", cube),
                                       ("the cube at exposure 1", cube1)]:
        print(f"{name}: at best {error:.0f} levels off, shown {tuple(int(v) for v in shown)} "
              f"at light/exposure {k:.3f} with reflection {f:.3f}")


if __name__ == "__main__":
    main()
