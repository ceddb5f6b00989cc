#!/usr/bin/env bash
# Quick start, part 2: install what is missing and run the whole test suite (CPU reference and,
# on lavapipe or a real GPU, the Vulkan paths with validation layers on).
# GPU tests never skip silently: with LENSRAY_SKIP_GPU_TESTS=1 on a machine without a usable
# device, each skipped test is recorded and the last lines below say how many and why.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh

skip_log=$(mktemp)
# What lensray caches per machine (auto's calibration, the pipeline cache) goes to a fresh
# folder: the tests neither read nor change the user's.
cache_dir=$(mktemp -d)
trap 'rm -rf "$skip_log" "$cache_dir"' EXIT
status=0
cluster_skipped=0
export LENSRAY_SKIP_LOG="$skip_log" LENSRAY_CACHE_DIR="$cache_dir"
# cargo-nextest runs the tests where it is installed: one process a test, as many at once as the
# CPU has cores, across the test binaries. cargo test runs one binary at a time, and a binary
# whose few tests each compile lavapipe's trace shaders one after another keeps a core idle for
# minutes (docs/testing.md, "Where CI's time goes"). The benches (harness = false, so nextest
# cannot list them) run their small checks under cargo test. LENSRAY_TEST_RUNNER=cargo, or no
# cargo-nextest, runs everything under cargo test.
if [ "${LENSRAY_TEST_RUNNER:-}" != cargo ] && cargo nextest --version >/dev/null 2>&1; then
  if [ $# -eq 0 ]; then
    cargo nextest run --workspace --lib --bins --tests --no-fail-fast || status=$?
    cargo test --workspace --benches || status=$?
  else
    cargo nextest run "$@" || status=$?
  fi
else
  cargo test --all-targets "$@" || status=$?
fi
echo "== the tests took $SECONDS s"

# Embree picks its kernels by the CPU (SSE4.2, AVX2, AVX-512), and their floats differ. The run
# above used the widest this CPU has; the CPU reference's tests run again on each other one
# (LENSRAY_EMBREE_CONFIG=isa=...), and tests/cli/isa.rs compares the default render across all.
# Only for the whole suite (no arguments).
if [ $# -eq 0 ]; then
  lensray="${CARGO_TARGET_DIR:-target}/debug/lensray"
  isas=$("$lensray" info 2>/dev/null | sed -n 's/^ *this CPU runs *//p' | tr -d ',' || true)
  widest=${isas##* }
  for isa in sse4.2 avx2 avx512; do
    if [[ " $isas " == *" $isa "* && $isa != "$widest" ]]; then
      echo "== the CPU reference's tests on Embree's $isa kernels"
      LENSRAY_EMBREE_CONFIG="isa=$isa" cargo test -q -p lensray-core --lib --test reference \
        || status=$?
    fi
  done
  # deploy/ on a single-node Slurm cluster, with openjd and the Kubernetes schema: about 16 s.
  echo "== the cluster test (scripts/test-cluster.sh)"
  cluster=0
  LENSRAY="$lensray" ./scripts/test-cluster.sh || cluster=$?
  if [ $cluster -eq 3 ]; then cluster_skipped=1; elif [ $cluster -ne 0 ]; then status=$cluster; fi
fi

skipped=$(wc -l <"$skip_log")
if [ "$skipped" -gt 0 ]; then
  echo
  echo "SKIPPED: $skipped GPU test(s) did not run (LENSRAY_SKIP_GPU_TESTS=1); this is not a full pass:"
  cut -f2 "$skip_log" | sort | uniq -c | sed 's/^/  /'
  cut -f1 "$skip_log" | tr '\n' ' ' | fold -s -w 100 | sed 's/^/  skipped: /'
  echo
fi
if [ $cluster_skipped -eq 1 ]; then
  echo "SKIPPED: the cluster test did not run: this lensray has no 'render --frames'; this is not a full pass"
fi
exit $status
