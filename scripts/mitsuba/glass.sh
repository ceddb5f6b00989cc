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
who=glass.sh
source scripts/mitsuba/setup.sh

lensray="${LENSRAY:-}"
if [ -z "$lensray" ]; then
  source scripts/setup.sh
  echo "glass.sh: building lensray (cargo build --release)"
  cargo build --release --quiet
  lensray="$target/release/lensray"
fi
exec "$venv/bin/python" scripts/mitsuba/glass.py --lensray "$lensray" --out "$target/mitsuba-glass" "$@"
