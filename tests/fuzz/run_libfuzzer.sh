#!/usr/bin/env bash
# run_libfuzzer.sh [SECONDS] [BUILD_DIR]: the optional sanitizer campaign of tests/fuzz/README.md.
# Builds the scene loader with clang, AddressSanitizer, UBSan and libFuzzer (-DSPECULUM_FUZZ=ON,
# its own build folder), seeds a working corpus from the scenes, the bad files and tests/fuzz/corpus,
# and fuzzes for SECONDS (default 600). Findings land in BUILD_DIR/fuzz-findings/ (crash-*,
# leak-*, timeout-*); turn each into a file in tests/fuzz/corpus/ and a fix.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-600}
build=${2:-build-fuzz}
command -v clang++ >/dev/null || { echo "needs clang (apt-get install clang libclang-rt-14-dev)"; exit 1; }
CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPECULUM_FUZZ=ON >/dev/null
cmake --build "$build" --target speculum-scene-fuzzer -j "$(nproc)"
work="$build/fuzz-corpus"
mkdir -p "$work" "$build/fuzz-findings"
cp -n assets/scenes/*.gltf tests/data/*.gltf tests/data/*.glb tests/data/bad/*.gltf tests/data/bad/*.glb "$work"/ 2>/dev/null || true
cp -n tests/fuzz/corpus/* "$work"/ 2>/dev/null || true
# The seeds' .bin files and environment maps resolve beside the fuzzer's input file.
export SPECULUM_FUZZ_ASSETS=$PWD/assets
export ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
"$build/tests/fuzz/speculum-scene-fuzzer" "$work" -dict=tests/fuzz/gltf.dict -max_len=65536 -rss_limit_mb=4096 \
  -timeout=20 -max_total_time="$seconds" -artifact_prefix="$build/fuzz-findings/" -print_final_stats=1
