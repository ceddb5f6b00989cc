#!/usr/bin/env bash
# The cluster test (docs/cluster.md): the three ways of deploy/ run for real on this machine.
#  1. Slurm: scripts/slurm-cluster.sh starts a single-node cluster; deploy/slurm's job array
#     renders 12 frames as 3 tasks; task 1 is cancelled once its first frame is written; the
#     array is submitted again with --resume. The set must then equal a single-process render of
#     the same range byte for byte, and the re-submission must have left the complete frames
#     alone.
#  2. OpenJD: deploy/openjd's template passes `openjd check`, and `openjd run` renders 2 frames
#     equal to the single-process ones.
#  3. Kubernetes: deploy/kubernetes's manifest validates strictly against the Job schema of
#     kubernetes-validate's bundled OpenAPI schemas (offline), and its index count agrees with
#     its --chunk.
# LENSRAY names the binary (default: the debug build that scripts/test.sh's cargo test makes);
# TEST_CLUSTER_KEEP=1 keeps the frames and the tasks' logs.
# openjd-cli and kubernetes-validate go into a virtual environment in the target folder, once.
# Exit status: 0 passed, 1 failed, 3 skipped (this lensray has no --frames yet).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

say() { echo "test-cluster: $*"; }
fail() { echo "test-cluster: FAIL: $*" >&2; exit 1; }

target=${CARGO_TARGET_DIR:-$root/target}
lensray=$(realpath -m "${LENSRAY:-$target/debug/lensray}")
[ -x "$lensray" ] || fail "no lensray binary at $lensray: build it first (cargo build -p lensray)"
if ! "$lensray" render --help | grep -q -- '--frames'; then
  say "SKIPPED: $lensray render has no --frames option"
  exit 3
fi

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"

# The Python tools, pinned, in a venv made once.
venv=$target/cluster-venv
if ! "$venv/bin/openjd" --version >/dev/null 2>&1 || [ ! -x "$venv/bin/kubernetes-validate" ]; then
  if ! python3 -c 'import ensurepip, venv' 2>/dev/null; then
    say "installing python3-venv"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq python3-venv >/dev/null
  fi
  say "installing openjd-cli and kubernetes-validate into $venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q openjd-cli==0.8.0 kubernetes-validate==1.37.0
fi

work=$(mktemp -d)
export SLURM_CONF=
cleanup() {
  scripts/slurm-cluster.sh stop || true
  if [ -n "${TEST_CLUSTER_KEEP:-}" ]; then say "frames and logs kept in $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT

# A small shot: 12 frames of 160x90 at 2 spp.
scene=$root/assets/spheres/spheres.toml
look=(--path cpu --width 160 --height 90 --spp 2 --progress lines)
frames=1-12
mkdir -p "$work/single" "$work/farm" "$work/log" "$work/openjd"

say "a single-process render of frames $frames"
"$lensray" render --scene "$scene" "${look[@]}" --frames "$frames" --out "$work/single/shot.####.exr" \
  >"$work/log/single.log" 2>&1 || { cat "$work/log/single.log"; fail "the single-process render failed"; }

frame_file() { printf '%s/shot.%04d.exr' "$1" "$2"; }

# Waits until Slurm no longer lists job $1 (its tasks ended one way or another).
wait_job() {
  local i
  for i in $(seq 1200); do
    [ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && return 0
    sleep 0.1
  done
  squeue; fail "job $1 still runs after 120 s"
}

submit() {
  sbatch --parsable --array=0-2 --output="$work/log/%A_%a.log" --export="ALL,LENSRAY=$lensray" \
    deploy/slurm/lensray-frames.sbatch --scene "$scene" "${look[@]}" --frames "$frames" \
    --out "$work/farm/shot.####.exr" "$@"
}

started=$(scripts/slurm-cluster.sh start)
echo "$started"
eval "$(grep '^export SLURM_CONF=' <<<"$started")"
[ -n "$SLURM_CONF" ] || fail "scripts/slurm-cluster.sh start printed no SLURM_CONF"

say "Slurm: the array as 3 tasks over frames $frames; cancelling task 1 after its first frame"
SECONDS=0
job=$(submit)
# Task 1's process runs in slices of 20 ms, stopped in between, until its first frame (5) is
# written; it is cancelled while stopped, so however fast frames render, it dies part-way.
pid=""
for _ in $(seq 6000); do
  pid=$(pgrep -f -- "--chunk 1/3\$" | head -n 1 || true)
  [ -n "$pid" ] && break
  sleep 0.01
done
[ -n "$pid" ] || { cat "$work/log/"*; fail "task 1 did not start in 60 s"; }
kill -STOP "$pid"
first=$(frame_file "$work/farm" 5)
for _ in $(seq 3000); do
  [ -e "$first" ] && break
  kill -CONT "$pid"; sleep 0.02; kill -STOP "$pid" 2>/dev/null || break
done
[ -e "$first" ] || { cat "$work/log/"*; fail "task 1 wrote no frame in 60 s of running"; }
scancel "${job}_1"
kill -CONT "$pid" 2>/dev/null || true
wait_job "$job"
grep -q CANCELLED "$work/log/${job}_1.log" \
  || fail "task 1's log does not say it was cancelled: $(tail -n 3 "$work/log/${job}_1.log")"
done_in_chunk=0
for f in 5 6 7 8; do [ -e "$(frame_file "$work/farm" "$f")" ] && done_in_chunk=$((done_in_chunk + 1)); done
if [ "$done_in_chunk" -eq 4 ]; then
  fail "task 1 finished all 4 frames before it was cancelled: the test's frames render too fast to cancel one part-way"
fi
say "task 1 was cancelled with $done_in_chunk of its 4 frames written"

# The frames of tasks 0 and 2, as they are before the re-submission: --resume must not touch them.
kept=()
for f in 1 2 3 4 9 10 11 12; do
  file=$(frame_file "$work/farm" "$f")
  [ -e "$file" ] || { cat "$work/log/${job}_0.log" "$work/log/${job}_2.log"; fail "frame $f is missing after tasks 0 and 2"; }
  kept+=("$f $(stat -c %Y.%y "$file")")
done

say "Slurm: the array again, with --resume"
job2=$(submit --resume)
wait_job "$job2"
for entry in "${kept[@]}"; do
  f=${entry%% *}
  [ "$(stat -c %Y.%y "$(frame_file "$work/farm" "$f")")" = "${entry#* }" ] \
    || fail "frame $f was written again by the --resume submission; it was complete"
done
different=()
for f in $(seq 1 12); do
  cmp -s "$(frame_file "$work/single" "$f")" "$(frame_file "$work/farm" "$f")" || different+=("$f")
done
if [ ${#different[@]} -gt 0 ]; then
  ls -l "$work/single" "$work/farm"; cat "$work/log/${job2}_"*.log
  fail "frames ${different[*]} of the array differ from the single-process render (of 12)"
fi
say "Slurm: 12 of 12 frames equal the single-process render byte for byte; 8 complete frames left alone by --resume (${SECONDS} s)"

say "OpenJD: openjd check, then openjd run over frames 1-2"
"$venv/bin/openjd" check deploy/openjd/lensray-frames.yaml
"$venv/bin/openjd" run deploy/openjd/lensray-frames.yaml -p "Scene=$scene" -p Frames=1-2 \
  -p FramesPerTask=1 -p "Output=$work/openjd/shot.####.exr" -p "Lensray=$lensray" \
  -p "RenderArgs=${look[*]}" >"$work/log/openjd.log" 2>&1 \
  || { tail -n 30 "$work/log/openjd.log"; fail "openjd run failed"; }
for f in 1 2; do
  cmp "$(frame_file "$work/single" "$f")" "$(frame_file "$work/openjd" "$f")" \
    || fail "OpenJD's frame $f differs from the single-process render"
done
say "OpenJD: frames 1 and 2 equal the single-process render byte for byte"

say "Kubernetes: the manifest against the Job schema (strict), and its chunk count"
"$venv/bin/kubernetes-validate" --strict deploy/kubernetes/lensray-frames.yaml
"$venv/bin/python" - deploy/kubernetes/lensray-frames.yaml <<'EOF'
import re, sys, yaml
job = yaml.safe_load(open(sys.argv[1]))
spec = job["spec"]
command = " ".join(spec["template"]["spec"]["containers"][0]["args"])
chunk = re.search(r'--chunk "\$JOB_COMPLETION_INDEX/(\d+)"', command)
problems = []
if spec.get("completionMode") != "Indexed":
    problems.append(f"completionMode is {spec.get('completionMode')!r}, not 'Indexed'")
if not chunk:
    problems.append("the command has no --chunk \"$JOB_COMPLETION_INDEX/N\"")
elif not int(chunk.group(1)) == spec["completions"] == spec["parallelism"]:
    problems.append(f"--chunk's N {chunk.group(1)}, completions {spec['completions']} and "
                    f"parallelism {spec['parallelism']} differ")
for option in ("--frames", "--resume", "--out"):
    if option not in command:
        problems.append(f"the command has no {option}")
if problems:
    sys.exit("test-cluster: FAIL: " + "; ".join(problems))
print(f"test-cluster: Kubernetes: {spec['completions']} indexes, --chunk I/{chunk.group(1)}")
EOF
say "passed"
