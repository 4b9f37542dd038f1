#!/usr/bin/env bash
# Sets everything up and runs every test (unit, gpu on lavapipe with validation, capture, fuzz)
# except the long soak label; arguments go to ctest instead (-L soak runs the soak).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD=${SPECULUM_BUILD_DIR:-build}
export MESA_SHADER_CACHE_DIR="$PWD/$BUILD/mesa-cache"
cd "$BUILD"
# The soak label (thousands of frames, minutes) runs only when asked: scripts/test.sh -L soak.
if (($# == 0)); then set -- -LE soak; fi
ctest --output-on-failure -j "$(nproc)" "$@"
