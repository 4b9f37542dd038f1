#!/usr/bin/env bash
# measure_fps.sh [FRAMES]: speculum-game's frame rate per preset under Xvfb at the default window
# (1280x720), standing at the start of the hall of mirrors with dynamic resolution on
# (sample_game/README.md). Prints per preset the median of the game's fps lines after the first
# three (warm-up), the internal resolution it settled at and the GPU, present and events ms (the
# last: glfwPollEvents, which under Xvfb waits for the X server to finish reading the last
# present's image). Measured, never asserted: the machine is shared and noisy.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
frames=${1:-200}
build=$root/${SPECULUM_BUILD_DIR:-build}
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
for preset in low medium high; do
  # The whole output is kept: when the game prints no fps line (no device, no surface, a crash),
  # its own last lines say why, and the script stops there with the game's status.
  out=$(mktemp)
  rc=0
  MESA_SHADER_CACHE_DIR=$build/mesa-cache xvfb-run -a -s "-screen 0 1280x720x24" \
    "$build/sample_game/speculum-game" --preset "$preset" --frames "$frames" >"$out" 2>&1 || rc=$?
  readings=$(grep ' fps ' "$out" | tail -n +4 || true)
  last=$(tail -n 8 "$out")
  rm -f "$out"
  if [[ -z $readings ]]; then
    printf '%s: no fps readings after warm-up (the game exited with %s); its last lines:\n%s\n' "$preset" "$rc" "$last" >&2
    exit 1
  fi
  echo "$readings" | python3 -c "
import re, statistics, sys
rows = [re.match(r'([\d.]+) fps \(GPU ([\d.]+) ms, present ([\d.]+) ms, events ([\d.]+) ms\) at (\d+x\d+)', l).groups() for l in sys.stdin if 'fps' in l]
fps, gpu, present, events = (statistics.median(float(r[k]) for r in rows) for k in range(4))
print('$preset: %.1f fps (median of %d readings), GPU %.1f ms, present %.1f ms, events %.1f ms, internal %s at the end' % (fps, len(rows), gpu, present, events, rows[-1][4]))"
done
