#!/usr/bin/env python3
"""Pepper: the share of pixels far darker (and brighter) than a converged render, and the mean.

usage: scripts/pepper.py LOW.png CONVERGED.png DEPTH.png [LEVELS]

LOW and CONVERGED are the same shot at few and many samples (`--tonemap none`), DEPTH the same
shot's `--shading depth` image, whose non-black pixels are the model's. Prints, for the whole
image and for the model, the share of pixels whose mean of channels is more than LEVELS (default
25) of 255 darker, and brighter, than CONVERGED's, and the relative difference of the means
(docs/environment.md, "Metals under a map's lamps"; docs/shading-normals.md). ffmpeg decodes the
PNGs, so that nothing beyond the standard library is needed.
"""
import subprocess
import sys


def pixels(path):
    """Each pixel's RGB bytes, row by row."""
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-f", "rawvideo", "-pix_fmt",
                          "rgb24", "-"], capture_output=True, check=True).stdout
    return [raw[i:i + 3] for i in range(0, len(raw), 3)]


def main():
    low, high, depth = (pixels(p) for p in sys.argv[1:4])
    levels = float(sys.argv[4]) if len(sys.argv) > 4 else 25.0
    model = [max(d) > 0 for d in depth]
    for region, inside in (("image", [True] * len(model)), ("model", model)):
        dark = bright = 0
        sum_low = sum_high = 0.0
        count = 0
        for a, b, keep in zip(low, high, inside):
            if not keep:
                continue
            la, lb = sum(a) / 3, sum(b) / 3
            dark += la - lb < -levels
            bright += la - lb > levels
            sum_low += la
            sum_high += lb
            count += 1
        print(f"{region}: {count} px, {100 * dark / count:.2f} % more than {levels:g} levels "
              f"darker, {100 * bright / count:.2f} % brighter, mean {100 * (sum_low / sum_high - 1):+.2f} %")


if __name__ == "__main__":
    main()
