# Sourced by the preview benchmarks (bench-preview.sh, bench-preview-paths.sh): the release build
# in `bin`, a scratch folder in `work`, and a private Xvfb server in DISPLAY (FIFO is not
# throttled there, so frame rates are the renderer's own), both removed on exit.
source scripts/setup.sh >/dev/null
cargo build --release --quiet
bin=$(realpath "${CARGO_TARGET_DIR:-target}")/release/lensray
work=$(mktemp -d)
xvfb=""
cleanup() { [ -n "$xvfb" ] && kill "$xvfb" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
Xvfb -displayfd 3 -screen 0 1920x1080x24 -nolisten tcp 3>"$work/display" 2>/dev/null &
xvfb=$!
for _ in $(seq 100); do [ -s "$work/display" ] && break; sleep 0.1; done
export DISPLAY=":$(head -1 "$work/display")"
