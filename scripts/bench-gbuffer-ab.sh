#!/usr/bin/env bash
# The G-buffer pass of this working tree's build against a named commit's (docs/preview.md,
# "The G-buffer pass against a commit"). Builds COMMIT in a temporary git worktree with its own
# target dir, then runs the G-buffer view of the preview (`lensray preview --view albedo`:
# the view pass, no tracing; 1280x720, built-in default scene) with both binaries in turns under
# a private Xvfb, and prints every run, each binary's medians and the ratio this build / COMMIT.
# Turns, not blocks: the machine's load drifts over minutes, and each round runs first the binary
# the previous round ran second.
#
#   scripts/bench-gbuffer-ab.sh COMMIT [RUNS [PREVIEW ARGS...]]   # RUNS per binary, default 7
#
# Environment:
#   AB_TARGET_DIR  COMMIT's target dir (default: the build's target dir + /bench-ab; kept, so a
#                  later comparison builds incrementally)
#   AB_BASE_BIN    a release binary of COMMIT to run instead of building it
#   AB_FRAMES      frames per run (default 120; the median over a run's frames leaves out its
#                  first frames' pipeline compiles)
#   AB_JSON        also write the runs to this file (docs/bench/gbuffer-ab.json holds the stored
#                  baseline, read by scripts/readme_figures.py)
set -euo pipefail
commit=${1:?usage: scripts/bench-gbuffer-ab.sh COMMIT [RUNS [PREVIEW ARGS...]]}
runs=${2:-7}
shift $(($# < 2 ? $# : 2))
json_out=${AB_JSON:+$(realpath -m "$AB_JSON")}
cd "$(dirname "$0")/.."
base_rev=$(git rev-parse --verify --short "$commit^{commit}")
build_rev="$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- crates Cargo.toml Cargo.lock || echo +changes)"
root=$(pwd)
source scripts/preview-bench-env.sh
trap 'git -C "$root" worktree remove --force "$work/base" 2>/dev/null || true; cleanup' EXIT

cp "$bin" "$work/build.bin"
base_from="built in a temporary worktree"
if [ -n "${AB_BASE_BIN:-}" ]; then
  cp "$AB_BASE_BIN" "$work/base.bin"
  base_from="given (AB_BASE_BIN)"
else
  target=${AB_TARGET_DIR:-$(realpath "${CARGO_TARGET_DIR:-target}")/bench-ab}
  echo "building $base_rev in a temporary worktree (target dir $target)"
  git worktree add --quiet --detach "$work/base" "$base_rev"
  (cd "$work/base" && CARGO_TARGET_DIR="$target" cargo build --release --quiet --bin lensray)
  cp "$target/release/lensray" "$work/base.bin"
fi

frames=${AB_FRAMES:-120}
# One run: "frame_ms gbuffer_ms" from the exit line.
run() {
  local out
  out=$("$1" preview --width 1280 --height 720 --view albedo --frames "$2" "${@:3}" 2>&1) || {
    echo "$out" >&2
    return 1
  }
  device=$(sed -n 's/^preview: .*) on \(.*\)$/\1/p' <<<"$out" | tail -1)
  sed -n 's/^preview: .*median frame time \([0-9.]*\) ms, median G-buffer pass \([0-9.]*\) ms.*/\1 \2/p' \
    <<<"$out" | tail -1
}
# Each binary's first launch compiles its shaders into the pipeline cache: not a run.
run "$work/base.bin" 10 "$@" >/dev/null
run "$work/build.bin" 10 "$@" >/dev/null
: >"$work/runs"
load_before=$(cut -d' ' -f1 /proc/loadavg)
echo "run  binary            frame ms  G-buffer pass ms"
for i in $(seq "$runs"); do
  order=(base build)
  ((i % 2 == 0)) && order=(build base)
  for which in "${order[@]}"; do
    read -r frame gbuffer < <(run "$work/$which.bin" "$frames" "$@") || true
    [ -n "${gbuffer:-}" ] || { echo "run $i of $which printed no exit line" >&2; exit 1; }
    echo "$which $frame $gbuffer" >>"$work/runs"
    name=$base_rev
    [ "$which" = build ] && name=$build_rev
    printf '%-4s %-17s %8s  %16s\n' "$i" "$name" "$frame" "$gbuffer"
  done
done

load_after=$(cut -d' ' -f1 /proc/loadavg)
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
AB_LOAD="$load_before $load_after" AB_BASE_FROM=$base_from AB_BASE=$base_rev AB_BUILD=$build_rev \
  AB_CPU=$cpu AB_THREADS=$(nproc) AB_DEVICE=${device:-} AB_RUNS_FILE="$work/runs" \
  AB_COMMAND="scripts/bench-gbuffer-ab.sh $commit $runs $*" AB_FRAMES=$frames AB_JSON=$json_out \
  python3 - <<'EOF'
import json, os, statistics, datetime
e = os.environ
runs = {"base": {"frame_ms": [], "gbuffer_ms": []}, "build": {"frame_ms": [], "gbuffer_ms": []}}
for line in open(e["AB_RUNS_FILE"]):
    which, frame, gbuffer = line.split()
    runs[which]["frame_ms"].append(float(frame))
    runs[which]["gbuffer_ms"].append(float(gbuffer))
med = {w: {k: statistics.median(v) for k, v in r.items()} for w, r in runs.items()}
load = [float(v) for v in e["AB_LOAD"].split()]
print(f"machine: {e['AB_CPU']}, {e['AB_THREADS']} threads, {e['AB_DEVICE']}; load average "
      f"{load[0]:.2f} before the runs, {load[1]:.2f} after")
if max(load) > int(e["AB_THREADS"]) + 1:
    print("note: other work shared the cores (load above the threads + 1): expect slower, wider runs")
print(f"medians of {len(runs['base']['frame_ms'])} runs each, {e['AB_FRAMES']} frames per run:")
for w, rev in (("base", e["AB_BASE"]), ("build", e["AB_BUILD"])):
    g = runs[w]["gbuffer_ms"]
    print(f"  {rev:<17} frame {med[w]['frame_ms']:.1f} ms, G-buffer pass {med[w]['gbuffer_ms']:.2f} ms "
          f"(runs {min(g):.2f}-{max(g):.2f})")
# A round's two runs are seconds apart, the series' ends minutes: their ratio sees the least
# drift in the machine's load.
for k, what in (("gbuffer_ms", "G-buffer pass"), ("frame_ms", "frame")):
    paired = statistics.median(b / a for a, b in zip(runs["base"][k], runs["build"][k]))
    print(f"{what}: {e['AB_BUILD']} / {e['AB_BASE']} = {med['build'][k] / med['base'][k]:.3f} "
          f"(ratio of the medians), {paired:.3f} (median of each round's ratio)")
if e.get("AB_JSON"):
    stored = {
        "command": e["AB_COMMAND"].strip(),
        "measured": datetime.date.today().isoformat(),
        "machine": {"cpu": e["AB_CPU"], "threads": int(e["AB_THREADS"]), "device": e["AB_DEVICE"]},
        "load_average_before_after": load,
        "setup": "lensray preview --width 1280 --height 720 --view albedo (the view pass), "
                 f"built-in default scene, {e['AB_FRAMES']} frames per run, the two binaries in "
                 "turns under a private Xvfb; each run's median frame time and median G-buffer "
                 "pass (GPU timestamps)",
        "base": {"commit": e["AB_BASE"], "binary": e["AB_BASE_FROM"], **runs["base"]},
        "build": {"commit": e["AB_BUILD"], **runs["build"]},
    }
    with open(e["AB_JSON"], "w", encoding="utf-8") as f:
        json.dump(stored, f, indent=2)
        f.write("\n")
    print(f"wrote {e['AB_JSON']}")
EOF
