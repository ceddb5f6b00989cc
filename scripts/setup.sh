#!/usr/bin/env bash
# Installs what lensray needs to build, render and test, and nothing that is already there.
# Idempotent: every step checks first and says what it installs.
# Debian 12 (bookworm): Mesa's lavapipe with ray queries comes from bookworm-backports (>= 24.1).
# Ubuntu >= 24.10 / Debian >= 13: the distribution's own Mesa is recent enough.
set -euo pipefail

say() { echo "setup: $*"; }

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    say "not root and no sudo: install the packages listed in README.md (Requirements) by hand"; exit 1
  fi
fi

if ! command -v apt-get >/dev/null 2>&1 || [ ! -r /etc/os-release ]; then
  say "this is not a Debian/Ubuntu system. Install by hand: Rust (cargo), the Vulkan loader and"
  say "validation layers, Mesa lavapipe >= 24.1 (ray queries), shaderc + glslang + SPIRV-Tools"
  say "libraries, cmake, python3, a C++ compiler, Xvfb for the window tests and ffmpeg (--video)."
  exit 1
fi

. /etc/os-release
# libembree-dev: Embree 3.13, the CPU path's ray queries (the `embree3` crate links libembree3).
# ffmpeg: `render --video` encodes with it; its tests check the video with ffprobe.
# time: GNU time, whose peak memory the tests of files declaring huge images read.
PACKAGES=(libvulkan1 libvulkan-dev vulkan-tools vulkan-validationlayers mesa-vulkan-drivers
          libshaderc-dev glslang-dev spirv-tools libembree-dev xvfb ffmpeg pkg-config cmake python3 g++
          time)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

# Mesa's version decides whether lavapipe has ray queries.
mesa_version() { dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true; }
mesa_ok() {
  local v; v=$(mesa_version); [ -n "$v" ] || return 1
  dpkg --compare-versions "$v" ge 24.1
}

updated=0
apt_update() { if [ $updated -eq 0 ]; then say "apt-get update"; $SUDO apt-get update -qq; updated=1; fi; }

need_backports=0
if [ "${ID:-}" = debian ] && [ "${VERSION_CODENAME:-}" = bookworm ] && ! mesa_ok; then
  need_backports=1
  if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    say "adding bookworm-backports to apt sources (for Mesa >= 24.1 with ray queries)"
    echo "deb http://deb.debian.org/debian bookworm-backports main" | $SUDO tee /etc/apt/sources.list.d/lensray-backports.list >/dev/null
    updated=0
  fi
fi

if [ ${#missing[@]} -gt 0 ]; then
  apt_update
  say "installing: ${missing[*]}"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi

if [ $need_backports -eq 1 ]; then
  apt_update
  say "installing mesa-vulkan-drivers from bookworm-backports (lavapipe with VK_KHR_ray_query)"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq -t bookworm-backports mesa-vulkan-drivers >/dev/null
fi

# The CPU path links Embree 3 (libembree3); a distribution whose libembree-dev is Embree 4 lacks it.
if [ -z "${EMBREE_DIR:-}" ] && ! compgen -G "/usr/lib/*/libembree3.so" >/dev/null \
   && [ ! -e /usr/lib/libembree3.so ]; then
  say "libembree3.so not found: install Embree 3.13 (https://github.com/embree/embree/releases/tag/v3.13.5)"
  say "and point EMBREE_DIR at it; the CPU path's ray queries link it."; exit 1
fi

if ! mesa_ok; then
  say "warning: mesa-vulkan-drivers $(mesa_version) is older than 24.1: lavapipe has no ray queries;"
  say "the GPU path needs another Vulkan device with VK_KHR_ray_query."
fi

# Rust: Debian's own rustc is too old for the dependencies (edition 2021, rust >= 1.85).
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
  export PATH="$HOME/.cargo/bin:$PATH"
fi
if ! command -v cargo >/dev/null 2>&1; then
  if command -v curl >/dev/null 2>&1 || { apt_update; $SUDO apt-get install -y -qq curl >/dev/null; }; then
    say "installing Rust (stable) with rustup into $HOME/.cargo"
    curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal -c rustfmt,clippy >/dev/null
    export PATH="$HOME/.cargo/bin:$PATH"
  fi
fi
if ! command -v cargo >/dev/null 2>&1; then
  say "cargo not found and rustup could not install it: install Rust >= 1.85 (https://rustup.rs)"; exit 1
fi
say "ok (mesa-vulkan-drivers $(mesa_version))"
