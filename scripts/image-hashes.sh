#!/usr/bin/env bash
# Renders a fixed set of small shots on every path and prints one SHA-256 per image (EXR, so the
# float values themselves are compared). A restructuring that must keep every image bit for bit
# runs it before and after and diffs the two lists:
#   scripts/image-hashes.sh target/release/lensray > before.txt   # at the old commit
#   scripts/image-hashes.sh target/release/lensray > after.txt    # at the new one
#   diff before.txt after.txt
# Hashes depend on the machine (the build uses every instruction the CPU has), so compare lists
# made on one machine. The hashes are of the files, so a change of the EXR encoding changes them
# all: then keep the images of both (IMAGE_HASHES_KEEP=DIR) and compare their decoded floats.
set -euo pipefail
bin=${1:?usage: scripts/image-hashes.sh PATH/TO/lensray}
cd "$(dirname "$0")/.."
out=${IMAGE_HASHES_KEEP:-$(mktemp -d)}
mkdir -p "$out"
[ -n "${IMAGE_HASHES_KEEP:-}" ] || trap 'rm -rf "$out"' EXIT
export LENSRAY_CACHE_DIR="$out/cache"

small=(--width 96 --height 72 --spp 8 --progress none)
shots=(
  "default-unlit|"
  "default-lit|--shading lit"
  "default-depth|--shading depth"
  "default-normal|--shading normal"
  "cornell-lit|--scene assets/cornell/cornell.toml --shading lit"
  "hexagon|--aperture-blades 6 --aperture-roundness 0.2"
  "double-gauss|--lens double-gauss-50 --f-number 2"
)
for path in cpu rayquery rtpipeline software hybrid raster; do
  for shot in "${shots[@]}"; do
    name=${shot%%|*}
    # shellcheck disable=SC2206
    extra=(${shot#*|})
    case "$path:$name" in
      hybrid:double-gauss) continue ;; # the hybrid refuses real lenses
    esac
    # The hybrid and raster paths trace with the traversal a timing race picks, and the
    # traversals' images differ in the last bits: pin the software traversal.
    case "$path" in hybrid | raster) extra+=(--hide-ray-query) ;; esac
    file="$out/$path-$name.exr"
    if "$bin" render --path "$path" "${small[@]}" "${extra[@]}" --out "$file" >/dev/null 2>"$out/err"; then
      echo "$path $name $(sha256sum "$file" | cut -c1-16)"
    else
      echo "$path $name FAILED: $(tail -1 "$out/err")"
    fi
  done
done
