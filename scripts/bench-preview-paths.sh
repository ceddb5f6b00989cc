#!/usr/bin/env bash
# The preview's speed per path (docs/hybrid.md, "In the preview"): frames per second and samples
# per pixel per second of `lensray preview --path P --spp 4096 --frames N` (the exit line's
# median frame time and its samples-per-pixel rate, first 5 frames excluded), built-in default
# scene, under a private Xvfb server (FIFO is not throttled there), at 1280x720 and 640x360.
# Each configuration runs REPEAT times (default 3) in turn; the table gives the medians.
# Extra arguments go to every `lensray preview` (e.g. --shading unlit).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/preview-bench-env.sh
repeat=${REPEAT:-3}
paths=${PATHS:-rayquery software hybrid}

for size in 1280x720 640x360; do
  w=${size%x*}; h=${size#*x}
  frames=$(( w > 640 ? 60 : 150 ))
  for r in $(seq "$repeat"); do
    for p in $paths; do
      line=$("$bin" preview --width "$w" --height "$h" --path "$p" --spp 4096 --frames "$frames" "$@" \
        2>"$work/err" | tail -1)
      ms=$(sed -E 's/.*median frame time ([0-9.]+) ms.*/\1/' <<<"$line")
      rate=$(sed -E 's/.* ([0-9.]+) samples per pixel per second.*/\1/' <<<"$line")
      echo "$size $p $ms $rate" >>"$work/runs"
      echo "run $r $size $p: $line" >&2
    done
  done
done

echo "| image | path | median frame time | fps | samples per pixel per second |"
echo "|---|---|---|---|---|"
for size in 1280x720 640x360; do
  for p in $paths; do
    awk -v s="$size" -v p="$p" '$1 == s && $2 == p { print $3, $4 }' "$work/runs" | python3 -c '
import statistics, sys
rows = [tuple(map(float, l.split())) for l in sys.stdin if l.strip()]
ms = statistics.median(r[0] for r in rows)
rate = statistics.median(r[1] for r in rows)
print(f"| {sys.argv[1]} | {sys.argv[2]} | {ms:.1f} ms | {1000 / ms:.1f} | {rate:.3f} |")
' "$size" "$p"
  done
done
