#!/usr/bin/env bash
# The preview window's speed (docs/preview.md): 1280x720, built-in default scene, under a private
# Xvfb server (FIFO is not throttled there, so frame rates are the renderer's own).
#   1. frames per second and G-buffer pass time per frame of the G-buffer view alone (--view
#      albedo: no tracing, the view pass), three runs (the first launch after a build is often
#      slower: quote the median); scripts/bench-gbuffer-ab.sh compares the pass with a commit's
#   2. frames per second with depth of field accumulating (final view)
#   3. samples per pixel reached 1 s and 5 s after the window opened
#   4. time from an input (a key) to the submission of the frame that shows it
#   5. CPU time used while converged and idle (the event loop waits)
# Extra arguments go to every `lensray preview` (e.g. --scene assets/cornell/cornell.toml).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/preview-bench-env.sh
size=(--width 1280 --height 720)
run() { "$bin" preview "${size[@]}" "$@"; }

echo "== 1. G-buffer view alone: 3 runs of 300 frames (each exit line: median frame time, median G-buffer pass per frame)"
for _ in 1 2 3; do run --view albedo --frames 300 "$@" | tail -1; done
echo "== 2. depth of field accumulating (target 4096 spp): 150 frames"
run --spp 4096 --frames 150 "$@" | tail -1
echo "== 3. samples per pixel after 1 s and 5 s"
printf '1 screenshot %s/s1.png\n4 screenshot %s/s5.png\n0 quit\n' "$work" "$work" >"$work/spp.txt"
run --spp 4096 --script "$work/spp.txt" "$@" 2>&1 | grep -E "^screenshot"
echo "== 4. input to frame: 20 projection toggles (key O), 0.25 s apart, while accumulating"
{ for _ in $(seq 20); do echo "0.25 key O"; done; echo "0 quit"; } >"$work/keys.txt"
run --spp 4096 --script "$work/keys.txt" "$@" | tail -1
echo "== 5. CPU use once converged (16 spp), over 3 s of idling"
printf '0 wait converged\n0 key C\n6 quit\n' >"$work/idle.txt"
run --spp 16 --script "$work/idle.txt" "$@" >"$work/idle.out" 2>&1 &
pid=$!
for _ in $(seq 600); do grep -q '^\[camera\]' "$work/idle.out" 2>/dev/null && break; sleep 0.05; done
ticks() { awk '{print $14 + $15}' "/proc/$pid/stat"; }
t0=$(ticks); sleep 3; t1=$(ticks)
wait "$pid"
echo "CPU time while converged: $(( (t1 - t0) * 1000 / $(getconf CLK_TCK) )) ms in 3 s"
