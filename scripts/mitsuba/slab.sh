#!/usr/bin/env bash
# Mitsuba 3's figures for lensray's rough-slab white furnace test (scripts/mitsuba/slab.py says
# which). Sets up what it needs first (scripts/mitsuba/setup.sh: libllvm19, the venv with
# mitsuba==3.9.1 and numpy), saying what it installs; safe to run again. About 10 s of CPU.
set -euo pipefail
cd "$(dirname "$0")/../.."
who=slab.sh
source scripts/mitsuba/setup.sh
exec "$venv/bin/python" scripts/mitsuba/slab.py
