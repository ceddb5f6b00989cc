#!/usr/bin/env bash
# lensray's CPU path against Mitsuba 3.9.1 (`llvm_ad_rgb`: Embree + Dr.Jit's LLVM JIT) on the same
# scenes and thin-lens camera: image check, camera rays per second at 1 and 2 threads, start-up.
# Method and caveats: docs/mitsuba.md. Sets up what it needs first, saying what it installs, and
# is safe to run again:
#   - what lensray needs (scripts/setup.sh) and its release build (cargo build --release);
#   - libllvm19 (apt-get; Dr.Jit's LLVM back end aborts with Debian 12's default LLVM 15);
#   - a Python venv with mitsuba==3.9.1 and numpy, in $target/mitsuba-venv.
# Arguments go to scripts/mitsuba/compare.py (--help: scenes, shadings, threads, spp, runs).
# Work files and results: $target/mitsuba/ (results.json, the image check's PNG and EXR files).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/setup.sh
target="${CARGO_TARGET_DIR:-$PWD/target}"
venv="$target/mitsuba-venv"

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

llvm19() {
  local dir
  dir="/usr/lib/$(uname -m)-linux-gnu"
  for lib in "$dir/libLLVM-19.so" "$dir/libLLVM.so.19.1" "$dir/libLLVM-19.so.1"; do
    [ -e "$lib" ] && { echo "$lib"; return 0; }
  done
  return 1
}

if ! llvm19 >/dev/null; then
  echo "compare.sh: installing libllvm19 (apt-get install -y libllvm19): Mitsuba's llvm_ad_rgb needs LLVM >= 16 at run time"
  if ! apt-cache policy libllvm19 | grep -q 'Candidate: [0-9]'; then as_root apt-get update; fi
  as_root apt-get install -y libllvm19 || as_root apt-get install -y -t bookworm-backports libllvm19
fi
export DRJIT_LIBLLVM_PATH="${DRJIT_LIBLLVM_PATH:-$(llvm19)}"

if ! "$venv/bin/python" -c 'import mitsuba, numpy; assert mitsuba.__version__ == "3.9.1"' 2>/dev/null; then
  if [ ! -x "$venv/bin/python" ]; then
    echo "compare.sh: creating a Python venv in $venv (python3 -m venv)"
    python3 -m venv "$venv" || { as_root apt-get install -y python3-venv && python3 -m venv "$venv"; }
  fi
  echo "compare.sh: installing mitsuba==3.9.1 and numpy into $venv (pip)"
  "$venv/bin/pip" install --quiet mitsuba==3.9.1 numpy
fi

echo "compare.sh: building lensray (cargo build --release)"
cargo build --release --quiet
exec "$venv/bin/python" scripts/mitsuba/compare.py "$@"
