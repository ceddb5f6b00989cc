#!/usr/bin/env bash
# Issues 53 and 54 on a lent GPU, in one device run: the materials real assets carry (glass and
# volumes, clear coat and sheen on ToyCar, a second UV set), emitters as lights, normal maps, a
# metal's resampled map draw (the gold bottle), adaptive sampling and a real lens with
# dispersion, each rendered on cpu and on each GPU path the device has (validation on), the same
# shot, seed and samples. Everything lands in $OUT/results.tar;
# compare each GPU image with the CPU's here: scripts/device-compare.py (docs/materials.md,
# "On a real GPU").
#   here:    ../shared/tools/device-bundle.sh; scripts/device-materials.sh --stage DIR
#            (DIR: a git repository of the Khronos glTF-Sample-Assets; the scenes go to .device/scenes)
#   device:  bash scripts/device-materials.sh   (carry .device)
set -u
if [[ ${1:-} == --stage ]]; then
  set -e
  s=.device/scenes
  rm -rf "$s"; mkdir -p "$s/glass"
  for m in AttenuationTest/glTF-Binary ClearCoatTest/glTF-Binary EmissiveStrengthTest/glTF-Binary \
    MultiUVTest/glTF-Binary NormalTangentTest/glTF-Binary ToyCar/glTF \
    TransmissionRoughnessTest/glTF-Binary; do
    mkdir -p "$s/${m%/*}"
    git -C "$2" ls-tree --name-only HEAD "Models/$m/" | while read -r f; do
      git -C "$2" show "HEAD:$f" > "$s/${m%/*}/${f##*/}"
    done
  done
  # The normal-mapped gold bottle, its textures at 512 pixels (the device's tree is limited).
  b="$s/WaterBottle"; mkdir -p "$b"
  git -C "$2" ls-tree --name-only HEAD Models/WaterBottle/glTF/ | while read -r f; do
    git -C "$2" show "HEAD:$f" > "$b/${f##*/}"
    [[ $f == *.png ]] && ffmpeg -nostdin -v error -y -i "$b/${f##*/}" -vf scale=512:-1 "$b/small.png" \
      && mv "$b/small.png" "$b/${f##*/}"
  done
  g=${CARGO_TARGET_DIR:-target}/mitsuba-glass   # written by scripts/mitsuba/glass.sh
  cp "$g"/{smooth,rough}.gltf "$g"/{ball,backdrop}.ply "$g"/glass.bin "$g"/checker.png "$s/glass/"
  du -sh "$s"; exit 0
fi
# A dry run here: LENSRAY=target/release/lensray OUT=DIR PATHS=cpu W=64 H=48 bash $0
[[ -n ${LENSRAY:-} ]] || source .device/setup.sh
s=.device/scenes r=$OUT/r; mkdir -p "$r"
(nvidia-smi --query-gpu=name,driver_version --format=csv; lscpu | grep -E "Model name|^CPU\(s\)") > "$r/machine.txt" 2>&1
paths=${PATHS:-"cpu $($LENSRAY info 2>/dev/null | grep -q rtpipeline && echo rtpipeline) software"}
glass_camera="--eye 0.9,0.7,5 --target 0,0,0 --up 0,1,0 --vfov 35 --aperture-radius 0 --focus-distance 5 --environment 1,1,1 --bounces 16"
studio="--environment assets/environments/studio.hdr"
shot() { # name, args...: one shot on every path (64 spp unless the args say)
  local name=$1; shift
  for p in $paths; do
    local spp="--spp 64"; [[ " $* " == *" --spp "* ]] && spp=
    local dev="--device gpu --path $p --validate"; [[ $p == cpu ]] && dev="--path cpu"
    local t0=$(date +%s.%N)
    timeout 120 $LENSRAY render --width ${W:-320} --height ${H:-240} --seed 7 --progress none $spp $dev \
      --out "$r/$name-$p.png" "$@" > "$r/$name-$p.log" 2>&1
    echo "$name $p rc=$? s=$(awk "BEGIN { print $(date +%s.%N) - $t0 }")" >> "$r/rc.txt"
  done
}
shot glass-smooth --scene $s/glass/smooth.gltf $glass_camera --shading lit
shot glass-rough --scene $s/glass/rough.gltf $glass_camera --shading lit
shot transmission-roughness --scene $s/TransmissionRoughnessTest/TransmissionRoughnessTest.glb $studio --bounces 8
shot attenuation --scene $s/AttenuationTest/AttenuationTest.glb $studio --bounces 8
shot clearcoat --scene $s/ClearCoatTest/ClearCoatTest.glb $studio
shot toycar --scene $s/ToyCar/ToyCar.gltf $studio --bounces 8
shot multi-uv --scene $s/MultiUVTest/MultiUVTest.glb $studio
shot emissive --scene $s/EmissiveStrengthTest/EmissiveStrengthTest.glb --bounces 3
shot bottle --scene $s/WaterBottle/WaterBottle.gltf $studio
shot normal-tangent --scene $s/NormalTangentTest/NormalTangentTest.glb $studio
shot adaptive --noise-threshold 0.02 --spp 256
shot lens-dispersion --lens double-gauss-50 --f-number 2
grep -il 'validation' "$r"/*.log > "$r/validation.txt" 2>&1
tar -C "$OUT" -cf "$OUT/results.tar" r && rm -rf "$r"
