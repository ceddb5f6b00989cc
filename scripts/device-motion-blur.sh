#!/usr/bin/env bash
# Motion blur on a lent GPU, in one device run (docs/sequences.md, "Motion blur and rolling
# shutter"; docs/performance.md, "Motion blur"): the streak and the rolling shutter's frames of
# tests/cli/motion_blur.rs on cpu and each GPU path the device has (validation on), the raster
# path's refusal, and scripts/bench-motion-blur.sh at 1920x1080 (the dolly, and
# MOTION_SHOT=box on software and cpu). Everything lands in
# $OUT/results.tar; measure the streaks here with the test's method.
#   device: bash scripts/device-motion-blur.sh   (after ../shared/tools/device-bundle.sh, carry .device)
set -u
source .device/setup.sh
r=$OUT/r; mkdir -p "$r"; w=/tmp/mbw; mkdir -p "$w"
(nvidia-smi --query-gpu=name,driver_version --format=csv; lscpu | grep -E "Model name|^CPU\(s\)") > "$r/machine.txt" 2>&1
$LENSRAY info > "$r/info.txt" 2>&1
printf "v 4.9 -0.1 -10\nv 5.1 -0.1 -10\nv 5.1 0.1 -10\nv 4.9 0.1 -10\nf 1 2 3 4\n" > "$w/quad.obj"
cat > "$w/sliding.toml" <<'T'
mesh = "quad.obj"
[camera]
vfov_degrees = 40.0
[image]
width = 320
height = 240
fps = 24.0
[render]
shading = "unlit"
background = [0.0, 0.0, 0.0]
[[keyframe]]
frame = 0
eye = [0.0, 0.0, 0.0]
target = [0.0, 0.0, -10.0]
[[keyframe]]
frame = 10
eye = [10.0, 0.0, 0.0]
target = [10.0, 0.0, -10.0]
T
go() { # name, device/path args...
  local name=$1; shift
  ( cd "$w" && timeout 120 $LENSRAY render --spp 64 --scene sliding.toml --frames 5 --out "$r/$name.#.exr" "$@" ) > "$r/$name.log" 2>&1
  echo "$name rc=$?" >> "$r/rc.txt"
}
go cpu-off --device cpu
go cpu-on --device cpu --motion-blur on
go cpu-roll --device cpu --rolling-shutter 1/48
for p in software rtpipeline; do
  go $p-off --device gpu --path $p --validate
  go $p-on --device gpu --path $p --validate --motion-blur on
  go $p-roll --device gpu --path $p --validate --rolling-shutter 1/48
done
go raster-on --device gpu --path raster --motion-blur on
timeout 300 scripts/bench-motion-blur.sh "$LENSRAY" 1920x1080 64 5 software rtpipeline cpu > "$r/bench.md" 2> "$r/bench.err"
echo "bench rc=$?" >> "$r/rc.txt"
MOTION_SHOT=box timeout 200 scripts/bench-motion-blur.sh "$LENSRAY" 1920x1080 64 5 software cpu > "$r/bench-box.md" 2> "$r/bench-box.err"
echo "bench-box rc=$?" >> "$r/rc.txt"
tar -C "$OUT" -cf "$OUT/results.tar" r && rm -rf "$r"
