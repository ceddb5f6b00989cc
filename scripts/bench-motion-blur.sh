#!/usr/bin/env bash
# Motion blur's cost per sample against a still (docs/performance.md, "Motion blur"): frame 13 of
# assets/spheres/dolly.toml (a tracking shot, lit, thin lens), still (--motion-blur off) and blurred
# (on), RUNS times each, alternating, on each path named; the median of `--timings`'s rendering phase
# of each, and their ratio. MOTION_SHOT=box times moving meshes instead: frame 7 of
# assets/BoxAnimated at 4 fps (1.75 s: its inner box turning, lit), where a 180-degree shutter sweeps 18
# degrees.
#
# usage: [MOTION_SHOT=dolly|box] scripts/bench-motion-blur.sh [LENSRAY] [WIDTHxHEIGHT] [SPP] [RUNS] [PATH...]
#   default: target/release/lensray 1280x720 64 5 cpu software rayquery
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
lensray=${1:-$root/target/release/lensray}
size=${2:-1280x720}
spp=${3:-64}
runs=${4:-5}
shift $(( $# < 4 ? $# : 4 ))
paths=("$@")
[[ ${#paths[@]} -gt 0 ]] || paths=(cpu software rayquery)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
case ${MOTION_SHOT:-dolly} in
  dolly)
    cp "$root"/assets/spheres/{dolly.toml,spheres.obj,spheres.mtl} "$work/"
    shot=(--scene "$work/dolly.toml" --frames 13) ;;
  box)
    cp "$root"/assets/BoxAnimated/* "$work/"
    shot=(--scene "$work/BoxAnimated.gltf" --frames 7 --fps 4 --eye 0,3,7 --target 0,1.5,0
      --up 0,1,0 --light-position 2,6,5 --light-intensity 60,60,60) ;;
  *) echo "MOTION_SHOT is dolly or box" >&2; exit 2 ;;
esac
seconds() { # path, blur: the rendering phase of one run, seconds
  local device=gpu; [[ $1 == cpu ]] && device=cpu
  "$lensray" render --device "$device" --path "$1" "${shot[@]}" \
    --out "$work/f.#.exr" --width "${size%x*}" --height "${size#*x}" --spp "$spp" \
    --motion-blur "$2" --timings --progress none 2>/dev/null | awk '/^timings: rendering/ {print $3}'
}
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
echo "| path | still, s | motion blur, s | ratio |"
echo "|---|---|---|---|"
for path in "${paths[@]}"; do
  seconds "$path" off >/dev/null # warm: pipelines and caches
  : > "$work/off"; : > "$work/on"
  for _ in $(seq "$runs"); do
    seconds "$path" off >> "$work/off"
    seconds "$path" on >> "$work/on"
  done
  off=$(median < "$work/off"); on=$(median < "$work/on")
  awk -v p="$path" -v a="$off" -v b="$on" 'BEGIN {printf "| %s | %.4f | %.4f | %.3f |\n", p, a, b, b / a}'
done
echo "($size, $spp spp, $runs runs each, medians of the rendering phase; $("$lensray" --version 2>/dev/null || echo lensray))"
