#!/usr/bin/env python3
"""lensray's CPU path against Mitsuba 3 (`llvm_ad_rgb`) on the same scenes and camera.

Run through scripts/mitsuba/compare.sh, which sets up what this needs. Steps:
  1. `lensray generate default|dense` writes the scenes (OBJ); render.py exports them as PLY.
  2. Images: both renderers render each scene small (160x120) and well converged; the mean
     absolute differences against noise and against a shifted, mirrored or differently blurred
     lensray image show that camera, framing and blur agree (docs/mitsuba.md).
  3. Times, per scene, shading and thread count: `lensray bench --device cpu` (its trace time,
     median of --runs after a warm-up) and render.py's Mitsuba runs (the same: the median of
     --runs renders after an untimed first one), twice, first with an empty kernel cache.
Everything measured goes to target/mitsuba/out/results.json; the tables go to stdout.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
RENDER_PY = os.path.join(HERE, "render.py")


class Setup:
    """Where things are: the lensray binary and the work folders under the target folder."""

    def __init__(self, args):
        target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
        self.lensray = args.lensray or os.path.join(target, "release", "lensray")
        self.work = os.path.join(target, "mitsuba")
        self.scenes = os.path.join(self.work, "scenes")
        self.out = os.path.join(self.work, "out")
        os.makedirs(self.out, exist_ok=True)


def run(cmd, env=None):
    """Runs `cmd` with `env` added to the environment: its stdout, or an exit with its stdout
    and stderr when it fails."""
    full_env = dict(os.environ, **(env or {}))
    p = subprocess.run(cmd, env=full_env, text=True, capture_output=True)
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout or ''}{p.stderr}")
    return p.stdout


def scene_files(setup, name):
    """The scene's OBJ (regenerated when older than the lensray binary) and its PLY folder."""
    obj = os.path.join(setup.scenes, f"{name}.obj")
    toml = os.path.join(setup.scenes, f"{name}.toml")
    stale = not (os.path.exists(toml) and os.path.exists(obj)) or \
        os.path.getmtime(obj) < os.path.getmtime(setup.lensray)
    if stale:
        print(run([setup.lensray, "generate", name, "--out", setup.scenes]).strip())
    ply = os.path.join(setup.work, "ply", name)
    print(run([sys.executable, RENDER_PY, "export", obj, ply]).strip())
    return toml, ply


def lensray_bench(setup, toml, threads, shading, width, height, spp, runs, json_path):
    """`lensray bench --device cpu` on the scene file at one thread count; its JSON."""
    run([setup.lensray, "bench", "--device", "cpu", "--scene-file", toml,
         "--width", str(width), "--height", str(height), "--spp", str(spp),
         "--shading", shading, "--repeat", str(runs), "--reference-spp", "2", "--no-cache",
         "--json", json_path], env={"RAYON_NUM_THREADS": str(threads)})
    with open(json_path) as f:
        return json.load(f)


def lensray_startup(setup, toml, threads, shading):
    """Whole-process seconds of `lensray render --path cpu` at 1 spp (scene load, BVH build,
    one sample per pixel, PNG written), best of two."""
    out = os.path.join(setup.out, "startup.png")
    times = []
    for _ in range(2):
        start = time.perf_counter()
        run([setup.lensray, "render", "--scene", toml, "--path", "cpu", "--spp", "1",
             "--shading", shading, "--out", out, "--progress", "none"],
            env={"RAYON_NUM_THREADS": str(threads)})
        times.append(time.perf_counter() - start)
    return min(times)


def mitsuba(ply, camera_json, threads, integrator, spp, runs, home, size=None, exr=None,
            png=None):
    """render.py's timing of one configuration, in its own process; `home` holds Dr.Jit's
    kernel cache (~/.drjit)."""
    cmd = [sys.executable, RENDER_PY, "time", "--scene", ply, "--camera", camera_json,
           "--threads", str(threads), "--integrator", integrator, "--spp", str(spp),
           "--runs", str(runs)]
    for flag, value in (("--size", size), ("--exr", exr), ("--png", png)):
        if value:
            cmd += [flag, value]
    return json.loads(run(cmd, env={"HOME": home}).strip().splitlines()[-1])


def diff(a, b):
    return json.loads(run([sys.executable, RENDER_PY, "diff", a, b]).strip())


def check_images(setup, name, toml, ply, shading, spp):
    """Both renderers at 160x120 and `spp` samples; the differences that show whether camera,
    framing and blur agree. PNGs and EXRs go to target/mitsuba/out/."""
    w, h = 160, 120
    camera_json = os.path.join(setup.out, f"camera-{name}-{w}x{h}.json")
    camera = lensray_bench(setup, toml, 2, "unlit", w, h, 1, 1, camera_json)["camera"]
    radius = camera["aperture_radius"]
    # Lit: Mitsuba's direct integrator leaves misses black, so lensray's background is too.
    extra = ["--background", "0,0,0"] if shading == "lit" else []
    stem = os.path.join(setup.out, f"check-{name}-{shading}")

    def lensray(suffix, *flags):
        path = f"{stem}-lensray{suffix}.exr"
        run([setup.lensray, "render", "--scene", toml, "--path", "cpu", "--shading", shading,
             "--width", str(w), "--height", str(h), "--spp", str(spp), "--progress", "none",
             "--out", path, *extra, *flags])
        return path

    reference = lensray("")
    run([setup.lensray, "render", "--scene", toml, "--path", "cpu", "--shading", shading,
         "--width", str(w), "--height", str(h), "--spp", str(spp), "--progress", "none",
         "--out", f"{stem}-lensray.png", *extra])
    noise = lensray("-independent", "--sampler", "independent", "--seed", "1")
    smaller = lensray("-radius-0.9", "--aperture-radius", repr(radius * 0.9))
    larger = lensray("-radius-1.1", "--aperture-radius", repr(radius * 1.1))
    with tempfile.TemporaryDirectory() as home:
        mitsuba(ply, camera_json, 2, shading, spp // 4, 4, home, exr=f"{stem}-mitsuba.exr",
                png=f"{stem}-mitsuba.png")
    theirs = f"{stem}-mitsuba.exr"
    d = diff(reference, theirs)
    shifts = [v for k, v in d.items() if k.startswith("mean_abs_diff_b_shifted")]
    return {
        "scene": name, "shading": shading, "width": w, "height": h, "spp": spp,
        "lensray_vs_mitsuba": d["mean_abs_diff"],
        "noise_floor_lensray_vs_lensray_independent": diff(reference, noise)["mean_abs_diff"],
        "mitsuba_shifted_1px_min": min(shifts),
        "mitsuba_mirrored": d["mean_abs_diff_b_mirrored"],
        "lensray_radius_0.9_vs_mitsuba": diff(smaller, theirs)["mean_abs_diff"],
        "lensray_radius_1.1_vs_mitsuba": diff(larger, theirs)["mean_abs_diff"],
        "mean_lensray": d["mean_a"], "mean_mitsuba": d["mean_b"],
    }


def measure(setup, name, toml, ply, shading, threads, args):
    """One row: lensray's bench and start-up, Mitsuba's with an empty kernel cache, then again
    with the kernels cached (its throughput is taken from this second process)."""
    tag = f"{name}-{shading}-t{threads}"
    bench_json = os.path.join(setup.out, f"lensray-{tag}.json")
    # Mitsuba's albedo AOV is measured against lensray's unlit.
    ours = "lit" if shading == "lit" else "unlit"
    bench = lensray_bench(setup, toml, threads, ours, args.width, args.height, args.spp,
                          args.runs, bench_json)
    result = bench["points"][0]["results"][0]
    camera_rays = args.width * args.height * args.spp
    lensray = {
        "threads": threads, "median_trace_seconds": result["trace_seconds"]["median"],
        "rays": result["rays"], "camera_rays": camera_rays,
        "mrays_per_second": camera_rays / result["trace_seconds"]["median"] / 1e6,
        "scene_load_seconds": (bench["scene"].get("load") or {}).get("seconds"),
        "bvh_build_seconds": result["build_seconds"],
        "whole_process_1spp_seconds": lensray_startup(setup, toml, threads, ours),
        "triangles": bench["scene"]["triangles"],
    }
    with tempfile.TemporaryDirectory() as home:
        cold = mitsuba(ply, bench_json, threads, shading, args.spp, args.runs, home)
        warm = mitsuba(ply, bench_json, threads, shading, args.spp, args.runs, home)
    if cold["triangles"] != lensray["triangles"]:
        sys.exit(f"{name}: Mitsuba loaded {cold['triangles']} triangles, lensray "
                 f"{lensray['triangles']}")
    return {"scene": name, "shading": shading, "threads": threads, "lensray": lensray,
            "mitsuba_empty_kernel_cache": cold, "mitsuba": warm}


def cpu_model():
    try:
        out = subprocess.run(["lscpu"], text=True, capture_output=True).stdout
        return next(line.split(":", 1)[1].strip() for line in out.splitlines()
                    if line.startswith("Model name"))
    except (OSError, StopIteration):
        return "unknown"


def fmt(x, digits=2):
    return "-" if x is None else f"{x:.{digits}f}"


def print_tables(results, args):
    if results["checks"]:
        first = results["checks"][0]
        print(f"\nImages ({first['width']}x{first['height']}, {args.check_spp} spp each; mean "
              "absolute difference, linear RGB):")
        print("| scene | shading | lensray vs Mitsuba | noise floor | Mitsuba 1 px off | "
              "mirrored | radius x0.9 | radius x1.1 |")
        print("|---|---|---|---|---|---|---|---|")
    for c in results["checks"]:
        print(f"| {c['scene']} | {c['shading']} | {c['lensray_vs_mitsuba']:.4f} | "
              f"{c['noise_floor_lensray_vs_lensray_independent']:.4f} | "
              f"{c['mitsuba_shifted_1px_min']:.4f} | {c['mitsuba_mirrored']:.4f} | "
              f"{c['lensray_radius_0.9_vs_mitsuba']:.4f} | "
              f"{c['lensray_radius_1.1_vs_mitsuba']:.4f} |")
    print(f"\nThroughput ({args.width}x{args.height}, {args.spp} spp, camera rays per second, "
          f"median of {args.runs} after a warm-up):")
    print("| scene | shading | threads | lensray Mrays/s | Mitsuba Mrays/s | lensray / Mitsuba |")
    print("|---|---|---|---|---|---|")
    for r in results["rows"]:
        a, b = r["lensray"]["mrays_per_second"], r["mitsuba"]["mrays_per_second"]
        print(f"| {r['scene']} | {r['shading']} | {r['threads']} | {a:.1f} | {b:.1f} | "
              f"{a / b:.2f}x |")
    print("\nStart-up, seconds (lensray: OBJ parse, BVH build, whole `render` at 1 spp; "
          "Mitsuba: import, PLY load incl. Embree build, first render with an empty / a warm "
          "kernel cache, then a timed render):")
    print("| scene | shading | threads | lensray load | BVH | whole, 1 spp | Mitsuba import | "
          "load (Embree) | first render, cold (compile) | first, warm | timed render |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in results["rows"]:
        lr, mc, mw = r["lensray"], r["mitsuba_empty_kernel_cache"], r["mitsuba"]
        print(f"| {r['scene']} | {r['shading']} | {r['threads']} | "
              f"{fmt(lr['scene_load_seconds'])} | {fmt(lr['bvh_build_seconds'], 3)} | "
              f"{fmt(lr['whole_process_1spp_seconds'])} | {fmt(mc['import_seconds'])} | "
              f"{fmt(mc['load_seconds'])} ({fmt(mc['embree_seconds'])}) | "
              f"{fmt(mc['first_render_seconds'])} ({fmt(mc['first_render_compile_seconds'])}) | "
              f"{fmt(mw['first_render_seconds'])} | {fmt(mw['median_render_seconds'])} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", default="default,dense")
    parser.add_argument("--shadings", default="unlit,lit", help="unlit, lit, aov (Mitsuba's "
                        "albedo AOV against lensray's unlit with a black background)")
    parser.add_argument("--threads", default="1,2")
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--check-spp", type=int, default=1024,
                        help="samples per pixel of the image check (0: skip it)")
    parser.add_argument("--lensray", help="the lensray binary (default: target/release)")
    args = parser.parse_args()
    setup = Setup(args)
    results = {"cpu": cpu_model(), "cores": os.cpu_count(), "load_average_before":
               os.getloadavg(), "args": vars(args), "checks": [], "rows": []}
    for name in args.scenes.split(","):
        toml, ply = scene_files(setup, name)
        shadings = args.shadings.split(",")
        if args.check_spp:
            for shading in (s for s in shadings if s in ("unlit", "lit")):
                print(f"image check: {name}, {shading}", file=sys.stderr)
                results["checks"].append(check_images(setup, name, toml, ply, shading,
                                                      args.check_spp))
        for shading in shadings:
            for threads in (int(t) for t in args.threads.split(",")):
                print(f"timing: {name}, {shading}, {threads} thread(s)", file=sys.stderr)
                results["rows"].append(measure(setup, name, toml, ply, shading, threads, args))
    results["load_average_after"] = os.getloadavg()
    path = os.path.join(setup.out, "results.json")
    with open(path, "w") as f:
        json.dump(results, f, indent=1)
    print(f"{results['cpu']}, {results['cores']} cores; load average (1, 5, 15 min) before "
          f"{results['load_average_before']}, after {results['load_average_after']}")
    print_tables(results, args)
    print(f"\nall figures: {path}")


if __name__ == "__main__":
    main()
