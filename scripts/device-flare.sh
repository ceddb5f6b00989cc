#!/usr/bin/env bash
# The lens's own light on a lent GPU, in one device run (docs/flare.md): assets/night (a lamp
# through double-gauss-50 at f/8, 7 blades) rendered with and without --flare on cpu and on
# each GPU path the device has (validation on), and `lensray bench --flare on --starburst on`
# at 1920x1080. Everything lands in $OUT/results.tar; compare the ghost light (flare on less
# off) of each GPU path with the CPU's here.
#   device: bash scripts/device-flare.sh   (after ../shared/tools/device-bundle.sh, carry .device)
set -u
source .device/setup.sh
r=$OUT/r; mkdir -p "$r"
(nvidia-smi --query-gpu=name,driver_version --format=csv; lscpu | grep -E "Model name|^CPU\(s\)") > "$r/machine.txt" 2>&1
go() { # name, args...
  local name=$1; shift
  timeout 120 $LENSRAY render --scene assets/night/night.toml --width 480 --height 270 --spp 64 \
    --timings --out "$r/$name.exr" "$@" > "$r/$name.log" 2>&1
  echo "$name rc=$?" >> "$r/rc.txt"
}
for flare in off on; do
  go cpu-$flare --device cpu --flare $flare
  for p in software rtpipeline; do go $p-$flare --device gpu --path $p --validate --flare $flare; done
done
timeout 240 $LENSRAY bench --scene-file assets/night/night.toml --shading lit --flare on --starburst on \
  --width 1920 --height 1080 --spp 16 --reference-spp 64 --repeat 3 --paths cpu,software,rtpipeline --no-cache \
  --json "$r/bench.json" > "$r/bench.txt" 2> "$r/bench.err"
echo "bench rc=$?" >> "$r/rc.txt"
tar -C "$OUT" -cf "$OUT/results.tar" r && rm -rf "$r"
