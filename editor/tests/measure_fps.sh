#!/usr/bin/env bash
# measure_fps.sh [SCENE]: the editor's viewport frame rates under Xvfb at the default window size
# (1280x720), still and while the camera orbits, from camera `main` (editor/README.md). Prints
# the editor's measure lines: frames per second, the internal viewport size, GPU and UI ms, and
# the heaviest passes. Measured, never asserted: the machine is shared and noisy.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
scene=${1:-$root/assets/scenes/gallery.gltf}
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
MESA_SHADER_CACHE_DIR=$root/build/mesa-cache xvfb-run -a -s "-screen 0 1280x720x24" \
  "$root/build/editor/speculum-editor" --scene "$scene" --script "$root/editor/tests/data/measure.json" 2>&1 |
  grep "speculum-editor: " | grep -v "probe bake"
