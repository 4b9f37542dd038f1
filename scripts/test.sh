#!/usr/bin/env bash
# Sets everything up and runs every test (unit, gpu on lavapipe with validation, capture).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD=${SPECULUM_BUILD_DIR:-build}
export MESA_SHADER_CACHE_DIR="$PWD/$BUILD/mesa-cache"
cd "$BUILD"
ctest --output-on-failure -j "$(nproc)" "$@"
