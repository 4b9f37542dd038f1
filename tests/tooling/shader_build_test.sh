#!/usr/bin/env bash
# Checks the shader build rule of cmake/Shaders.cmake on a scratch project:
#  1. editing an included file rebuilds the shader that includes it (depfile);
#  2. a GLSL error fails the build and names file:line.
set -euo pipefail
src_root=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
mkdir -p "$work/shaders/common" "$work/cmake"
cp "$src_root/cmake/Shaders.cmake" "$work/cmake/"
cat >"$work/CMakeLists.txt" <<'CM'
cmake_minimum_required(VERSION 3.25)
project(shadertest NONE)
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
include(cmake/Shaders.cmake)
speculum_add_shaders(shaders ${CMAKE_SOURCE_DIR}/shaders/a.comp)
CM
printf 'float helper() { return 1.0; }\n' >"$work/shaders/common/inc.glsl"
printf '#version 460\n#extension GL_GOOGLE_include_directive : require\n#include "inc.glsl"\nlayout(local_size_x = 1) in;\nvoid main() { float x = helper(); }\n' \
  >"$work/shaders/a.comp"
cmake -S "$work" -B "$work/build" -G Ninja >/dev/null
cmake --build "$work/build" >/dev/null
[[ -f "$work/build/shaders/a.comp.spv" ]] || { echo "no SPIR-V written"; exit 1; }
sleep 1; touch "$work/shaders/common/inc.glsl"
if ! ninja -C "$work/build" -n | grep -q "a.comp"; then echo "editing the include did not rebuild a.comp"; exit 1; fi
printf 'float helper() { return undefined_symbol; }\n' >"$work/shaders/common/inc.glsl"
if out=$(cmake --build "$work/build" 2>&1); then echo "a broken shader built"; exit 1; fi
if ! grep -qE "inc.glsl:1|ERROR: .*inc.glsl:1" <<<"$out"; then echo "error lacks file:line:"; echo "$out"; exit 1; fi
echo "ok: include edits rebuild, errors report file:line"
