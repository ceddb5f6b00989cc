#!/usr/bin/env python3
"""Each GPU image of a device run against the CPU's, by the suite's measure.

usage: scripts/device-compare.py DIR   (DIR: the r/ folder of scripts/device-materials.sh's tar)

For every NAME-cpu.png in DIR and each NAME-PATH.png beside it, prints the share of pixels whose
channels all lie within 1/255 of the CPU's (the suite's bound is 99.9 %, with a mean absolute
difference under 1e-3: tests/gpu_support), the share more than 8/255 off, the mean absolute
difference and the two images' means (a bias shows there, noise does not). ffmpeg decodes the
PNGs, so that nothing beyond the standard library is needed.
"""
import glob
import os
import subprocess
import sys


def pixels(path):
    """The image's RGB bytes, row by row."""
    return subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-f", "rawvideo", "-pix_fmt",
                           "rgb24", "-"], capture_output=True, check=True).stdout


def compare(gpu, cpu):
    within = over8 = 0
    total = 0
    for i in range(0, len(cpu), 3):
        d = max(abs(gpu[i] - cpu[i]), abs(gpu[i + 1] - cpu[i + 1]), abs(gpu[i + 2] - cpu[i + 2]))
        within += d <= 1
        over8 += d > 8
    total = sum(abs(a - b) for a, b in zip(gpu, cpu))
    n = len(cpu) // 3
    return within / n, over8 / n, total / len(cpu) / 255, sum(gpu) / len(gpu), sum(cpu) / len(cpu)


def main():
    folder = sys.argv[1]
    print(f"{'shot':24} {'path':11} {'within 1/255':>12} {'> 8/255':>8} {'mean |d|':>9} "
          f"{'mean gpu':>8} {'mean cpu':>8}")
    for cpu_png in sorted(glob.glob(os.path.join(folder, "*-cpu.png"))):
        name = os.path.basename(cpu_png)[:-len("-cpu.png")]
        cpu = pixels(cpu_png)
        for gpu_png in sorted(glob.glob(os.path.join(folder, f"{name}-*.png"))):
            path = os.path.basename(gpu_png)[len(name) + 1:-len(".png")]
            if path == "cpu" or "-" in path:
                continue
            within, over8, mean_abs, mg, mc = compare(pixels(gpu_png), cpu)
            print(f"{name:24} {path:11} {100 * within:11.2f}% {100 * over8:7.2f}% "
                  f"{mean_abs:9.5f} {mg:8.2f} {mc:8.2f}")


if __name__ == "__main__":
    main()
