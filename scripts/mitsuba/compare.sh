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
who=compare.sh
source scripts/mitsuba/setup.sh

echo "compare.sh: building lensray (cargo build --release)"
cargo build --release --quiet
exec "$venv/bin/python" scripts/mitsuba/compare.py "$@"
