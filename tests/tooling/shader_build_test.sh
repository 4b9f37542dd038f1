#!/usr/bin/env bash
# Checks the shader build rule of cmake/Shaders.cmake on a scratch project:
#  1. a shader is written as <PREFIX>/<file>.spv, whatever folder it lives in;
#  2. an include in another module's folder resolves through INCLUDES ("mod/shaders/inc.glsl"
#     under the modules root), and editing it rebuilds the shader that includes it (depfile);
#  3. without that INCLUDES root the include does not resolve: no relative climbs, no default;
#  4. a GLSL error fails the build and names file:line.
set -euo pipefail
src_root=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
mkdir -p "$work/shaders/common" "$work/cmake" "$work/modules/mod/shaders" "$work/modules/user/shaders"
cp "$src_root/cmake/Shaders.cmake" "$work/cmake/"
write_project() {  # $1: the INCLUDES clause
  cat >"$work/CMakeLists.txt" <<CM
cmake_minimum_required(VERSION 3.25)
project(shadertest NONE)
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
include(cmake/Shaders.cmake)
speculum_add_shaders(shaders PREFIX user $1 SOURCES \${CMAKE_SOURCE_DIR}/modules/user/shaders/a.comp)
CM
}
write_project "INCLUDES \${CMAKE_SOURCE_DIR}/modules"
printf 'float helper() { return 1.0; }\n' >"$work/modules/mod/shaders/inc.glsl"
printf '#version 460\n#extension GL_GOOGLE_include_directive : require\n#include "mod/shaders/inc.glsl"\nlayout(local_size_x = 1) in;\nvoid main() { float x = helper(); }\n' \
  >"$work/modules/user/shaders/a.comp"
cmake -S "$work" -B "$work/build" -G Ninja >/dev/null
cmake --build "$work/build" >/dev/null
[[ -f "$work/build/shaders/user/a.comp.spv" ]] || { echo "no SPIR-V written at shaders/user/a.comp.spv"; exit 1; }
sleep 1; touch "$work/modules/mod/shaders/inc.glsl"
if ! ninja -C "$work/build" -n | grep -q "a.comp"; then echo "editing the include did not rebuild a.comp"; exit 1; fi
printf 'float helper() { return undefined_symbol; }\n' >"$work/modules/mod/shaders/inc.glsl"
if out=$(cmake --build "$work/build" 2>&1); then echo "a broken shader built"; exit 1; fi
if ! grep -qE "inc.glsl:1|ERROR: .*inc.glsl:1" <<<"$out"; then echo "error lacks file:line:"; echo "$out"; exit 1; fi
printf 'float helper() { return 1.0; }\n' >"$work/modules/mod/shaders/inc.glsl"
write_project ""
rm -rf "$work/build"
cmake -S "$work" -B "$work/build" -G Ninja >/dev/null
if out=$(cmake --build "$work/build" 2>&1); then echo "an include outside the declared paths resolved"; exit 1; fi
echo "ok: PREFIX names the SPIR-V, includes resolve only through INCLUDES, include edits rebuild, errors report file:line"
