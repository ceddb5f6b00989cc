#!/usr/bin/env bash
# Quick start, part 2: install what is missing and run the whole test suite (CPU reference and,
# on lavapipe or a real GPU, the Vulkan paths with validation layers on).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cargo test --all-targets "$@"
