#!/usr/bin/env bash
# Sets everything up, then runs the main job: the sample game in a window when a display is
# there, in its own level (the hall of mirrors, whose gems only the mirrors show: a first run has
# a goal); otherwise a headless render of the default scene (gallery) to out/ with its timings.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
BUILD=${SPECULUM_BUILD_DIR:-build}
export MESA_SHADER_CACHE_DIR="$PWD/$BUILD/mesa-cache"
if [[ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]]; then
  exec "$BUILD/sample_game/speculum-game" "$@"
fi
echo "run: no display, rendering the gallery headless to out/ (960x540, 10 timed frames)"
"$BUILD/tools/capture/speculum-capture" --scene assets/scenes/gallery.gltf --camera main --size 960x540 \
  --warmup 3 --frames 10 --aov color,linear,depth,normal,roughness,motion --out out "$@"
echo "run: wrote out/color.0009.png, the other AOVs, timings.json and graph.dot/graph.json"
