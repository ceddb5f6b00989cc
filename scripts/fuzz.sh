#!/usr/bin/env bash
# Fuzzes every loader (docs/testing.md, "Fuzzing"): builds the libFuzzer targets of fuzz/ on the
# stable toolchain and runs each for SECONDS over its checked-in corpus and regressions. A crash,
# a hang (10 s) or a blown memory limit fails the run; its input is saved under
# fuzz/artifacts/TARGET/ (add it to fuzz/regressions/TARGET/ once fixed).
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]   CI runs 10 s each (.ci/run)
#   scripts/fuzz.sh --merge [TARGET...]                 minimizes fuzz/corpus/ with the new finds
# Environment: FUZZ_TARGET_DIR (default fuzz/target); FUZZ_FLAGS, more libFuzzer flags (a long
# campaign: "-fork=1 -ignore_crashes=1" goes on past a crash, saving each).
set -euo pipefail
cd "$(dirname "$0")/.."

merge=0
if [ "${1:-}" = "--merge" ]; then merge=1; shift; fi
seconds=20
if [[ "${1:-}" =~ ^[0-9]+$ ]]; then seconds=$1; shift; fi
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(gltf obj scene lens environment image)
target_dir=${FUZZ_TARGET_DIR:-$PWD/fuzz/target}

# libfuzzer-sys's instrumentation without cargo-fuzz or nightly: SanitizerCoverage's counters
# and comparisons, with debug assertions and overflow checks, so arithmetic overflow is found.
# No sanitizer: the loaders are safe Rust.
export RUSTFLAGS="--cfg fuzzing -Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares -Cdebug-assertions -Coverflow-checks"
host=$(rustc -vV | sed -n 's/^host: //p')
start=$(date +%s)
echo "== fuzz: building ${targets[*]}"
bins=()
for t in "${targets[@]}"; do bins+=(--bin "$t"); done
cargo build --manifest-path fuzz/Cargo.toml --release --quiet --target "$host" \
  --target-dir "$target_dir" "${bins[@]}"
echo "fuzz: built in $(( $(date +%s) - start )) s"
bin_dir=$target_dir/$host/release
# Where the targets write each input's files; removed on exit.
LENSRAY_FUZZ_DIR=$(mktemp -d -p /dev/shm lensray-fuzz.XXXXXX 2>/dev/null || mktemp -d)
export LENSRAY_FUZZ_DIR
trap 'rm -rf "$LENSRAY_FUZZ_DIR"' EXIT

# What stops a run: an input that runs 10 s, or the process past 2 GiB. Inputs stay under
# 12 kB, so the checked-in corpus stays small.
limits=(-timeout=10 -rss_limit_mb=2048 -max_len=12000)
failed=()
for t in "${targets[@]}"; do
  corpus=fuzz/corpus/$t
  regressions=fuzz/regressions/$t
  mkdir -p "$corpus" "$regressions"
  dict=()
  [ -f "fuzz/dict/$t.dict" ] && dict=(-dict="fuzz/dict/$t.dict")
  if [ $merge -eq 1 ]; then
    # New finds (fuzz/new/TARGET) and the seeds (fuzz/seeds.py) with the corpus, minimized.
    merged=$(mktemp -d)
    extra=()
    for d in "fuzz/new/$t" "fuzz/seeds/$t"; do [ -d "$d" ] && extra+=("$d"); done
    # Edges only (no hit counts), so the checked-in corpus stays small.
    "$bin_dir/$t" -merge=1 -use_counters=0 "${limits[@]}" "$merged" "$corpus" "${extra[@]}" 2>&1 | grep -E '^MERGE-OUTER: [0-9]+ new files' || true
    rm -rf "$corpus" && mkdir -p "$corpus" && cp "$merged"/* "$corpus"/ && rm -rf "$merged"
    echo "fuzz: $t corpus: $(ls "$corpus" | wc -l) files, $(du -s --apparent-size -k "$corpus" | cut -f1) KiB"
    continue
  fi
  # New inputs go to fuzz/new/TARGET (ignored by git); the checked-in corpus is only read.
  new=fuzz/new/$t
  artifacts=fuzz/artifacts/$t
  mkdir -p "$new" "$artifacts"
  log=$(mktemp)
  echo "== fuzz: $t for $seconds s"
  status=0
  "$bin_dir/$t" "$new" "$corpus" "$regressions" "${dict[@]}" "${limits[@]}" -max_total_time="$seconds" \
    -artifact_prefix="$artifacts/" -print_final_stats=1 ${FUZZ_FLAGS:-} >"$log" 2>&1 || status=$?
  grep -E '^(stat::number_of_executed_units|stat::average_exec_per_sec|stat::peak_rss_mb)|^Done ' "$log" || true
  grep -E '^#[0-9]+: cov' "$log" | tail -1 || true
  if [ $status -ne 0 ]; then
    failed+=("$t")
    grep -E 'panicked|ERROR: libFuzzer|SUMMARY|Test unit written|deadly signal|timeout|out-of-memory' "$log" | head -20 || true
    echo "fuzz: $t failed (exit $status); full log: $log"
  else
    rm -f "$log"
  fi
done
echo "fuzz: ${#targets[@]} targets in $(( $(date +%s) - start )) s"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: FAILED: ${failed[*]} (inputs under fuzz/artifacts/)"
  exit 1
fi
