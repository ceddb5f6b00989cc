#!/usr/bin/env bash
# Quick start, part 1: install what is missing, build, and render the built-in default scene
# headless to lensray.png (or pass any `lensray render` options, e.g. --out shot.exr).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cargo build --release --quiet
exec ./target/release/lensray render "$@"
