#!/usr/bin/env bash
# The CPU path's figures (docs/performance.md, "CPU reference"): camera rays per second at one
# and two threads, unlit and lit, and the start-up of a whole `lensray render` at 1 spp (parse,
# acceleration structure, one sample, the file written), on the default scene, the generated
# 1M-triangle scene (as OBJ, and for start-up also as glTF) and the README's real model.
#   scripts/bench-cpu.sh [RUNS]        (LENSRAY=path/to/lensray to time another build)
# Heavy: run it on an otherwise idle machine (a few minutes), not in the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS=${1:-5}
LENSRAY=${LENSRAY:-./target/release/lensray}
[ -x "$LENSRAY" ] || cargo build --release --quiet
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; lensray: $LENSRAY"
"$LENSRAY" generate dense --out "$OUT" >/dev/null
"$LENSRAY" generate dense --gltf --out "$OUT/gltf" >/dev/null
SCENES=("default:" "dense-1M:--scene $OUT/dense.toml" "apples:--scene assets/food_apple_01/apples.gltf")
# Start-up also with the 1M scene's meshes as glTF: binary vertex data, no text to parse.
STARTUP_SCENES=("${SCENES[@]}" "dense-gltf:--scene $OUT/gltf/dense.toml")

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

# Camera rays per second: the bench's tracing time (the host clock around the traversal).
for entry in "${SCENES[@]}"; do
  name=${entry%%:*}; scene=${entry#*:}
  [ "$name" = default ] && file="" || file="--scene-file ${scene#--scene }"
  for shading in unlit lit; do
    for threads in 1 2; do
      RAYON_NUM_THREADS=$threads "$LENSRAY" bench --paths cpu $file --width 640 --height 480 \
        --spp 64 --shading $shading --repeat "$RUNS" --reference-spp 4 --no-cache \
        --json "$OUT/b.json" >/dev/null 2>&1
      python3 - "$OUT/b.json" "$name" "$shading" "$threads" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
r = next(r for r in d["points"][0]["results"] if r["path"] == "cpu")
name, shading, threads = sys.argv[2:5]
print(f"rays  {name:9} {shading:6} {threads} thread(s): {r['rays_per_second'] / 1e6:.2f} Mrays/s "
      f"(median of {len(r['runs'])}), build {r['build_seconds'] * 1e3:.1f} ms, "
      f"acceleration structure {r['accel_bytes'] / 2**20:.1f} MiB")
EOF
    done
  done
done

# Start-up: the whole process at 1 spp, the image written.
for entry in "${STARTUP_SCENES[@]}"; do
  name=${entry%%:*}; scene=${entry#*:}
  for _ in $(seq "$RUNS"); do
    start=$(date +%s.%N)
    # shellcheck disable=SC2086
    "$LENSRAY" render --path cpu $scene --spp 1 --shading unlit --out "$OUT/s.png" >/dev/null 2>&1
    echo "$(date +%s.%N) - $start" | bc
  done | median | awk -v n="$name" '{printf "start %-9s whole process at 1 spp: %.3f s (median)\n", n, $1}'
done
