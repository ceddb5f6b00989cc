# Sourced by compare.sh and glass.sh (with `who` set to the script's name, for its messages):
# sets `target` and `venv`, installs libllvm19 and the venv with mitsuba==3.9.1 and numpy where
# they are missing, and exports DRJIT_LIBLLVM_PATH. Safe to run again.
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
  echo "$who: installing libllvm19 (apt-get install -y libllvm19): Mitsuba's llvm_ad_rgb needs LLVM >= 16 at run time"
  if ! apt-cache policy libllvm19 | grep -q 'Candidate: [0-9]'; then as_root apt-get update; fi
  as_root apt-get install -y libllvm19 || as_root apt-get install -y -t bookworm-backports libllvm19
fi
export DRJIT_LIBLLVM_PATH="${DRJIT_LIBLLVM_PATH:-$(llvm19)}"

if ! "$venv/bin/python" -c 'import mitsuba, numpy; assert mitsuba.__version__ == "3.9.1"' 2>/dev/null; then
  if [ ! -x "$venv/bin/python" ]; then
    echo "$who: creating a Python venv in $venv (python3 -m venv)"
    python3 -m venv "$venv" || { as_root apt-get install -y python3-venv && python3 -m venv "$venv"; }
  fi
  echo "$who: installing mitsuba==3.9.1 and numpy into $venv (pip)"
  "$venv/bin/pip" install --quiet mitsuba==3.9.1 numpy
fi

