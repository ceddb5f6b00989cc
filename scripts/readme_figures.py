#!/usr/bin/env python3
"""Every performance and error figure README.md and the docs quote, computed from the stored
measurements under docs/bench/ (standard library only).

    python3 scripts/readme_figures.py                  # one figure per line: "key: text"
    python3 scripts/readme_figures.py --check README.md docs/cli.md docs/performance.md ...

"text" is the figure exactly as the page that quotes it writes it, rounded the way it rounds.
--check passes a figure whose text is found verbatim (line breaks counting as spaces) in any of
the files given, and exits non-zero naming each figure found in none of them, so that a quoted
figure cannot drift from the stored runs: re-measure, store the JSON, rerun this and copy the
lines it reports into the page that quotes them. crates/lensray/tests/readme_figures.rs runs it
with the pages that quote figures.

Sources (docs/bench/):
  default.json, triangles.json, lit-default.json, hybrid-default.json, raster/*.json,
  hybrid-aperture-default/*.json, movements.json, movements/*.json: `lensray bench --json` runs
  (commands in docs/bench.md, docs/hybrid.md, docs/raster.md, docs/movements-bench.md);
  sampler-*.json, preview.json: tables copied from docs/sampler.md and docs/preview.md, with the
  command that printed them (`cargo bench --bench sampler -- --only ...`,
  `./scripts/bench-preview.sh`), which write no JSON of their own;
  gbuffer-ab.json: `./scripts/bench-gbuffer-ab.sh` runs (AB_JSON; docs/preview.md).
"""

import json
import math
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BENCH = ROOT / "docs" / "bench"

# The built-in camera's vertical field of view (lensray's DEFAULT_VFOV_DEGREES) and a 35 mm
# camera's film height (DEFAULT_SENSOR_HEIGHT_MM): they give the focal length that turns an
# aperture radius into an f-number (docs/hybrid.md, "f-number").
VFOV_DEGREES = 40.0
FILM_HEIGHT_MM = 24.0
# No photographic lens is faster than about f/1: apertures with N >= 1 are "real-camera" ones.
FASTEST_REAL_F_NUMBER = 1.0
FULL_STOPS = [math.sqrt(2) ** k for k in range(12)]  # f/1, 1.4, 2, 2.8, ... 45


def load(relative):
    with open(BENCH / relative, encoding="utf-8") as f:
        return json.load(f)


# ---- lensray bench JSON ("schema": "lensray-bench/1", docs/bench.md) ----

def point(run, spp=None, triangles=None):
    """The point of a bench run at `spp` (and `triangles`): {path: result}."""
    found = [
        p for p in run["points"]
        if (spp is None or p["spp"] == spp) and (triangles is None or p["triangles"] == triangles)
    ]
    if len(found) != 1:
        raise SystemExit(f"readme_figures: {len(found)} points at spp={spp} triangles={triangles}")
    return {r["path"]: r for r in found[0]["results"]}


def median(result):
    return result["trace_seconds"]["median"]


def time_to_error(run, path, error):
    """The time `path` needs for RMSE `error`: log-log interpolation between its sweep points,
    else extrapolated from the nearest with error ~ time^-1/2 (docs/bench/equal_error.py)."""
    pts = sorted(
        ((median(r), r["rmse"]) for p in run["points"] for r in p["results"] if r["path"] == path),
        key=lambda x: x[1],
    )
    for (t1, e1), (t0, e0) in zip(pts, pts[1:]):
        if e1 <= error <= e0:
            f = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    t, e = min(pts, key=lambda x: abs(math.log(x[1] / error)))
    return t * (e / error) ** 2


def equal_error(run, base, path, spp):
    """How many times sooner `path` reaches its RMSE at `spp` than `base` does."""
    r = point(run, spp)[path]
    return time_to_error(run, base, r["rmse"]) / median(r)


def equal_spp(run, base, path, spp=None, triangles=None):
    """`base`'s time over `path`'s at one point (same samples)."""
    p = point(run, spp, triangles)
    return median(p[base]) / median(p[path])


def f_number(aperture_radius_m):
    focal_mm = FILM_HEIGHT_MM / 2 / math.tan(math.radians(VFOV_DEGREES) / 2)
    return focal_mm / (2 * aperture_radius_m * 1000)


def full_stop(n):
    """The nearest full stop, written as on a lens barrel: 8, 5.6, 1.4."""
    stop = min(FULL_STOPS, key=lambda s: abs(math.log(s / n)))
    marked = {1.4142: "1.4", 2.8284: "2.8", 5.6569: "5.6", 11.3137: "11", 22.6274: "22"}
    return marked.get(round(stop, 4), f"{stop:.0f}")


# ---- formatting: as the README and the docs write figures ----

def x(v, digits):
    return f"{v:.{digits}f}x"


def x_range(lo, hi, digits, unit_each=True):
    """"4.4x-5.1x" (unit_each) or "1.5-3.6x"."""
    if unit_each:
        return f"{x(lo, digits)}-{x(hi, digits)}"
    return f"{lo:.{digits}f}-{x(hi, digits)}"


def mrays(rays_per_second):
    """Mrays/s to three significant digits, at most two decimals: 18.4, 3.81, 0.97."""
    v = rays_per_second / 1e6
    return f"{v:.1f}" if v >= 10 else f"{v:.2f}"


def percent(v):
    """Two significant digits: "1.8 %", "0.55 %"."""
    digits = max(0, 1 - math.floor(math.log10(abs(v))))
    return f"{v:.{digits}f} %"


def claim(holds, text):
    """A sentence of the README or the docs that states a comparison: itself while the data
    bear it out, else a line that --check cannot find."""
    return text if holds else f"NO LONGER TRUE: {text}"


# ---- the figures ----

def bench_runs():
    """Every `lensray bench` JSON under docs/bench, by path relative to it."""
    runs = {}
    for file in sorted(BENCH.rglob("*.json")):
        with open(file, encoding="utf-8") as f:
            data = json.load(f)
        if data.get("schema") == "lensray-bench/1":
            runs[file.relative_to(BENCH).as_posix()] = data
    return runs


def figures():
    out = []

    def fig(key, text):
        out.append((key, text))

    runs = bench_runs()

    # The machine: every stored bench run must come from one, or the docs cannot name it.
    machines = {json.dumps(r["machine"], sort_keys=True) for r in runs.values()}
    if len(machines) != 1:
        raise SystemExit(f"readme_figures: the stored bench runs come from {len(machines)} machines")
    machine = runs["default.json"]["machine"]
    fig("machine", f"{machine['cpu']}, {machine['threads']} threads, {machine['os']}")
    gpu = {p["device"] for r in runs.values() for p in r["paths"] if p["path"] != "cpu"}
    if len(gpu) != 1:
        raise SystemExit(f"readme_figures: the stored bench runs name {len(gpu)} Vulkan devices")
    fig("vulkan device", f"`{gpu.pop()}`")

    # Default scene, 640x480, 16 spp, unlit: every path taking turns (default.json).
    default = runs["default.json"]
    d16 = point(default, 16)
    fig(
        "default.json 16spp Mrays/s of cpu, software, rayquery",
        f"{mrays(d16['cpu']['rays_per_second'])}, {mrays(d16['software']['rays_per_second'])} "
        f"and {mrays(d16['rayquery']['rays_per_second'])} Mrays/s",
    )
    software_vs_rayquery = median(d16["rayquery"]) / median(d16["software"])
    fig("default.json 16spp software/rayquery", f"{x(software_vs_rayquery, 2)} faster")
    fig(
        "default.json 16spp speedup_vs_cpu of software, rayquery",
        f"{x(d16['software']['speedup_vs_cpu'], 2)} and {x(d16['rayquery']['speedup_vs_cpu'], 2)} "
        "its speed",
    )

    # The triangle sweep (triangles.json): its largest scene is the 1M-triangle one.
    triangles = runs["triangles.json"]
    most = max(p["triangles"] for p in triangles["points"])
    t1m = point(triangles, triangles=most)
    fig(
        f"triangles.json {most}tris Mrays/s of cpu, software, rayquery",
        f"{mrays(t1m['cpu']['rays_per_second'])}, {mrays(t1m['software']['rays_per_second'])} "
        f"and {mrays(t1m['rayquery']['rays_per_second'])}",
    )
    fig(
        f"triangles.json {most}tris software/rayquery",
        f"{x(equal_spp(triangles, 'rayquery', 'software', triangles=most), 2)} at {most / 1e6:.0f}M triangles",
    )
    # software against rayquery at 16 spp, over every stored scene (auto's first step).
    ratios = [software_vs_rayquery] + [
        equal_spp(triangles, "rayquery", "software", triangles=p["triangles"])
        for p in triangles["points"]
    ]
    fig("default.json+triangles.json 16spp software/rayquery range", x_range(min(ratios), max(ratios), 2))

    # Lit, every GPU path in one run (lit-default.json): equal error against rayquery at 16 spp.
    lit = runs["lit-default.json"]
    fig(
        "lit-default.json 16spp equal-error gain over rayquery of hybrid, raster, software",
        f"`hybrid` {x(equal_error(lit, 'rayquery', 'hybrid', 16), 2)}, "
        f"`raster` {x(equal_error(lit, 'rayquery', 'raster', 16), 2)}, "
        f"`software` {x(equal_error(lit, 'rayquery', 'software', 16), 2)}",
    )

    # The hybrid against rayquery at equal error, 16 spp, over apertures (docs/hybrid.md):
    # real-camera apertures (f-number >= 1 for the built-in 40-degree camera), and the built-in
    # camera's own aperture (the scene's, as the run without --aperture-radius records it).
    default_aperture = runs["hybrid-default.json"]["settings"]["aperture_radius"]
    for shading in ("unlit", "lit"):
        series = {
            r["settings"]["aperture_radius"]: equal_error(r, "rayquery", "hybrid", 16)
            for name, r in runs.items()
            if name.startswith("hybrid-aperture-default/") and r["settings"]["shading"] == shading
        }
        real = [a for a in series if f_number(a) >= FASTEST_REAL_F_NUMBER]
        gains = [series[a] for a in real]
        fig(f"hybrid-aperture-default/{shading}_* 16spp equal-error hybrid/rayquery, real apertures", x_range(min(gains), max(gains), 1))
        if shading == "unlit":
            fig(
                "hybrid-aperture-default real apertures as f-numbers",
                f"f/{full_stop(f_number(min(real)))}-f/{full_stop(f_number(max(real)))}",
            )
        fig(
            f"hybrid-aperture-default/{shading}_{default_aperture} 16spp equal-error hybrid/rayquery",
            f"{x(series[default_aperture], 1)} {shading}",
        )

    # The raster path against rayquery at equal spp, unlit, every point of the spp sweeps.
    for name, what, digits in (("raster/default.json", "default", 0), ("raster/dense.json", "dense", 1)):
        r = runs[name]
        gains = [equal_spp(r, "rayquery", "raster", spp=p["spp"]) for p in r["points"]]
        fig(f"{name} equal-spp raster/rayquery range", x_range(min(gains), max(gains), digits, False))

    # The sampler (cargo bench --bench sampler; tables copied into docs/bench/sampler-*.json).
    rmse = load("sampler-rmse.json")
    spp = rmse["spp"]
    for scene, s in rmse["scenes"].items():
        for sobol, independent, ratio in zip(s["sobol"], s["independent"], s["ratio"]):
            # The stored ratio is the bench's, from unrounded RMSEs: it must agree with the
            # rounded ones to within their rounding (a check on the copying).
            exact = sobol / independent
            slack = exact * (0.00005 / sobol + 0.00005 / independent) + 0.005
            if abs(ratio - exact) > slack:
                raise SystemExit(f"readme_figures: sampler-rmse.json {scene}: ratio {ratio} is not {exact:.3f}")
        at = [s["ratio"][spp.index(n)] for n in (16, 64, 256)]
        fig(f"sampler-rmse.json {scene} ratio at 16, 64, 256 spp", ", ".join(f"{v:.2f}x" for v in at))
    default_s = rmse["scenes"]["default"]
    fig("sampler-rmse.json default ratio at 16 spp", f"is {default_s['ratio'][spp.index(16)]:.2f}x that of independent")
    beats = {
        scene: s["sobol"][spp.index(16)] < s["independent"][spp.index(64)]
        for scene, s in rmse["scenes"].items()
    }
    fig("sampler-rmse.json default sobol@16 < independent@64",
        claim(beats["default"], "less than independent sampling leaves at 64 spp"))
    fig("sampler-rmse.json every scene sobol@16 < independent@64",
        claim(all(beats.values()), "16 spp look better than 64 independent ones"))

    edges = load("sampler-edges.json")
    floor = min(r["ratio"][edges["spp"].index(16)] for r in edges["rows"] if not r.get("control"))
    fig("sampler-edges.json lowest ratio at 16 spp", f"{floor:.2f}x at best")

    # Between powers of two: each count's sobol RMSE x spp^0.75 over that of the next power of
    # two, where the error meets the N^-0.75 trend again.
    between = {r["spp"]: r["sobol_rmse_x_spp_0_75"] for r in load("sampler-between.json")["rows"]}
    excess = []
    for n, v in between.items():
        if n & (n - 1):
            nxt = 1 << n.bit_length()
            excess.append(100 * (v / between[nxt] - 1))
    fig("sampler-between.json excess over the next power of two", f"{min(excess):.0f}-{max(excess):.0f} %")

    cost = {(r["device"], r["sampler"]): r for r in load("sampler-cost.json")["rows"]}
    share = {d: 100 * cost[d, "sobol"]["samples_ms"] / cost[d, "sobol"]["render_ms"] for d in ("cpu", "gpu")}
    fig("sampler-cost.json cpu share", f"{percent(share['cpu'])} of the CPU render time")
    fig("sampler-cost.json gpu share", f"{percent(share['gpu'])} of the GPU pass's")

    # The default render against the single paths (cargo bench --bench startup;
    # docs/bench/startup.json).
    startup = load("startup.json")
    warm = statistics.median(startup["default"]["warm_s"])
    single = {p: statistics.median(v["warm_s"]) for p, v in startup["single"].items()}
    fig("startup.json default warm", f"{warm:.2f} s warm")
    fig("startup.json fastest single path", f"{min(single.values()):.2f} s for `--path {min(single, key=single.get)}`")
    fig("startup.json default / fastest", f"{x(warm / min(single.values()), 2)} the fastest single path's time")
    fig("startup.json cold / warm", f"{startup['default']['cold_s']:.2f} s on the first run")
    fig("startup.json rayquery / cpu", f"{x(single['rayquery'] / single['cpu'], 1)} as long on `rayquery` as on the CPU reference")
    picked = startup["default"]["picked"]
    fig("startup.json stable", f"`{picked[0]}` in {picked.count(picked[0])} of {len(picked)} runs")
    fig("startup.json machine", f"{startup['machine']['cpu']}, {startup['machine']['threads']} threads")

    # The GPU frame (docs/gpu-frame.md): a lensray bench run per design, stored in docs/frame/
    # (this machine's, apart from the bench runs above).
    def frame(name):
        with open(BENCH.parent / "frame" / name, encoding="utf-8") as f:
            return json.load(f)["points"][0]["results"]
    after, before = frame("lit-default.json"), frame("lit-default-before.json")
    image = 640 * 480 * 16
    submits = {r["submits"] for r in after}
    fig("frame submits after", f"submits {max(submits)} command buffers" if len(submits) == 1
        else "NOT ONE FIGURE: submits differ between paths")
    fig("frame extra readback after", f"at most {max(r['readback_bytes'] for r in after) - image} bytes besides the image")
    fig("frame submits before", f"submitted {min(r['submits'] for r in before)}-{max(r['submits'] for r in before)}")

    # Real lenses against their thin models (docs/lens-bench.md): `lensray bench --sweep lens`
    # runs stored in docs/lens-bench/ (a later machine's, apart from the bench runs above).
    with open(BENCH.parent / "lens-bench" / "pair.json", encoding="utf-8") as f:
        pair = json.load(f)
    real = next(p for p in pair["points"] if p["lens"]["model"] == "real")
    cost = {r["path"]: r["cost_per_camera_ray_vs_thin"] for r in real["results"]}
    fig("lens-bench/pair.json cost per camera ray",
        claim(max(cost.values()) <= 2.0,
              f"{real['lens']['lens']} costs {x(cost['cpu'], 2)} the thin lens per camera ray on "
              f"the CPU reference, {x(cost['rayquery'], 2)} on `rayquery` and "
              f"{x(cost['software'], 2)} on `software`"))
    fig("lens-bench/pair.json pass share",
        f"{100 * real['lens']['centre_pass_share']:.1f} % of the camera samples at the image centre")
    fig("lens-bench/pair.json machine",
        f"{pair['machine']['cpu']}, {pair['machine']['threads']} threads")

    # Shift and tilt against the plain shot (docs/movements-bench.md): `lensray bench --sweep
    # movements` runs, every path in movements.json, the raster path alone in movements/.
    def vs_plain(run, shot):
        point = next(p for p in run["points"] if p["movements"]["point"] == shot)
        return {r["path"]: r["time_per_sample_vs_plain"] for r in point["results"]}
    moved = vs_plain(runs["movements.json"], "moved")
    traced = [moved[p] for p in ("rayquery", "software", "hybrid", "cpu")]
    raster_alone = vs_plain(runs["movements/raster.json"], "moved")["raster"]
    fig("movements.json moved/plain per sample, every path but raster",
        f"{x_range(min(traced), max(traced), 2)} of the plain shot's time per sample")
    fig("movements.json moved/plain per sample, raster",
        f"`raster` {x(moved['raster'], 3)} in the same run and {x(raster_alone, 3)} measured alone")

    # The preview window (./scripts/bench-preview.sh; docs/bench/preview.json).
    preview = load("preview.json")
    gbuffer = statistics.median(preview["gbuffer_view_frame_ms"]["runs"])
    fig("preview.json G-buffer view frame time", f"{gbuffer:.0f} ms per frame")
    fig("preview.json G-buffer view fps", f"{1000 / gbuffer:.0f} fps")
    fig("preview.json G-buffer view fps 640x360", f"{1000 / preview['gbuffer_view_frame_ms_640x360']:.0f} fps at 640x360")
    fig("preview.json accumulating frame", f"{preview['accumulating_frame_ms']:.0f} ms per frame")
    fig("preview.json spp after 5 s", f"{preview['spp_after_seconds']['5']} samples per pixel after 5 s")
    fig("preview.json input latency within a frame",
        claim(preview["input_to_frame_ms"] <= preview["accumulating_frame_ms_in_latency_run"],
              "the next frame shows an input"))
    fig("preview.json CPU while converged",
        claim(preview["cpu_ms_while_converged_3s"] == 0, "no CPU is used once converged"))

    # The G-buffer pass against a named commit (./scripts/bench-gbuffer-ab.sh, which writes
    # docs/bench/gbuffer-ab.json itself): medians of the runs of each binary, taken in turns.
    ab = load("gbuffer-ab.json")
    ab_med = {w: {k: statistics.median(ab[w][k]) for k in ("frame_ms", "gbuffer_ms")}
              for w in ("base", "build")}
    base, build = ab_med["base"], ab_med["build"]
    fig("gbuffer-ab.json G-buffer pass",
        f"G-buffer pass {build['gbuffer_ms']:.2f} ms per frame against {base['gbuffer_ms']:.2f} ms "
        f"at {ab['base']['commit']} ({x(build['gbuffer_ms'] / base['gbuffer_ms'], 2)})")
    fig("gbuffer-ab.json frame",
        f"frame {build['frame_ms']:.1f} ms against {base['frame_ms']:.1f} ms "
        f"({1000 / build['frame_ms']:.0f} fps)")
    fig("gbuffer-ab.json runs and machine",
        f"medians of {len(ab['build']['gbuffer_ms'])} runs each, {ab['machine']['cpu']}, "
        f"{ab['machine']['threads']} threads")
    return out


def main(argv):
    if len(argv) != 1 and (len(argv) < 3 or argv[1] != "--check"):
        print("usage: readme_figures.py [--check FILE.md...]", file=sys.stderr)
        return 2
    results = figures()
    if len(argv) == 1:
        for key, text in results:
            print(f"{key}: {text}")
        return 0
    files = argv[2:]
    # Line breaks inside a figure's sentence count as spaces.
    flat = [" ".join(Path(f).read_text(encoding="utf-8").split()) for f in files]
    missing = [(key, text) for key, text in results if not any(text in page for page in flat)]
    for key, text in missing:
        print(f"missing from every file given: {key}: {text}")
    if missing:
        print(f"{len(missing)} of {len(results)} figures are quoted in none of {' '.join(files)} "
              "(python3 scripts/readme_figures.py prints them all)")
        return 1
    print(f"{' '.join(files)}: all {len(results)} figures match docs/bench/")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
