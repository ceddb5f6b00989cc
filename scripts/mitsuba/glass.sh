#!/usr/bin/env bash
# lensray's glass against Mitsuba 3.9.1: a smooth and a rough ball of index 1.5 before a
# checkered backdrop under a white sky (method and figures: docs/mitsuba-glass.md). Sets up what
# it needs first, saying what it installs, and is safe to run again:
#   - libllvm19 (apt-get; Dr.Jit's LLVM back end aborts with Debian 12's default LLVM 15);
#   - a Python venv with mitsuba==3.9.1 and numpy, in $target/mitsuba-venv;
#   - lensray's release build, unless LENSRAY names a lensray binary to compare instead.
# Arguments go to scripts/mitsuba/glass.py (--help: size, samples, roughness).
# Work files and results: $target/mitsuba-glass/ (results.json, glass.png, the EXR renders).
set -euo pipefail
cd "$(dirname "$0")/../.."
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
  echo "glass.sh: installing libllvm19 (apt-get install -y libllvm19): Mitsuba's llvm_ad_rgb needs LLVM >= 16 at run time"
  if ! apt-cache policy libllvm19 | grep -q 'Candidate: [0-9]'; then as_root apt-get update; fi
  as_root apt-get install -y libllvm19 || as_root apt-get install -y -t bookworm-backports libllvm19
fi
export DRJIT_LIBLLVM_PATH="${DRJIT_LIBLLVM_PATH:-$(llvm19)}"

if ! "$venv/bin/python" -c 'import mitsuba, numpy; assert mitsuba.__version__ == "3.9.1"' 2>/dev/null; then
  if [ ! -x "$venv/bin/python" ]; then
    echo "glass.sh: creating a Python venv in $venv (python3 -m venv)"
    python3 -m venv "$venv" || { as_root apt-get install -y python3-venv && python3 -m venv "$venv"; }
  fi
  echo "glass.sh: installing mitsuba==3.9.1 and numpy into $venv (pip)"
  "$venv/bin/pip" install --quiet mitsuba==3.9.1 numpy
fi

lensray="${LENSRAY:-}"
if [ -z "$lensray" ]; then
  source scripts/setup.sh
  echo "glass.sh: building lensray (cargo build --release)"
  cargo build --release --quiet
  lensray="$target/release/lensray"
fi
exec "$venv/bin/python" scripts/mitsuba/glass.py --lensray "$lensray" --out "$target/mitsuba-glass" "$@"
