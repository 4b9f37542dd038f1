#!/usr/bin/env bash
# Times the default frame (gallery, camera main) and prints a markdown table of per-pass GPU
# medians plus transient memory with and without aliasing. Usage:
#   bash tests/bench/frame_bench.sh [WxH] [FRAMES]      (default 960x540, 20 frames)
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${SPECULUM_BUILD_DIR:-build}
size=${1:-960x540}; frames=${2:-20}
out=$(mktemp -d)
export MESA_SHADER_CACHE_DIR="$PWD/$BUILD/mesa-cache"
"$BUILD/engine/speculum-capture" --scene assets/scenes/gallery.gltf --camera main --size "$size" \
  --warmup 5 --frames "$frames" --aov color --out "$out" >/dev/null
python3 - "$out/timings.json" "$size" "$frames" <<'PY'
import json, sys, os
t = json.load(open(sys.argv[1]))
print(f"gallery/main {sys.argv[2]}, {sys.argv[3]} timed frames after 5 warm-up, device: {t['device']}, "
      f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores\n")
print("| pass | median ms | min ms | max ms |\n|---|---|---|---|")
for p in t["passes"]:
    print(f"| {p['name']} | {p['median_ms']:.2f} | {p['min_ms']:.2f} | {p['max_ms']:.2f} |")
f = t["frame"]
print(f"| **frame (render.\\*)** | **{f['median_ms']:.2f}** | {f['min_ms']:.2f} | {f['max_ms']:.2f} |\n")
m = t["memory"]
a, u = m["transient_peak_bytes_aliased"], m["transient_peak_bytes_unaliased"]
print(f"transient memory: {a/2**20:.1f} MiB aliased vs {u/2**20:.1f} MiB without aliasing "
      f"({100*(1-a/u):.0f}% lower); persistent {m['persistent_bytes']/2**20:.1f} MiB")
PY
rm -rf "$out"
