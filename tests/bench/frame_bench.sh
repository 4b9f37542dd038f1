#!/usr/bin/env bash
# Times the default frame (gallery, camera main) and prints a markdown table of per-pass GPU
# medians plus transient memory with and without aliasing. Usage:
#   bash tests/bench/frame_bench.sh [WxH] [FRAMES] [speculum-capture flags...]
# (default 960x540, 20 frames; e.g. `--set reflections.enabled=false` for the engine alone)
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${SPECULUM_BUILD_DIR:-build}
size=${1:-960x540}; frames=${2:-20}; shift $(( $# < 2 ? $# : 2 ))
out=$(mktemp -d)
export MESA_SHADER_CACHE_DIR="$PWD/$BUILD/mesa-cache"
"$BUILD/tools/capture/speculum-capture" --scene assets/scenes/gallery.gltf --camera main --size "$size" \
  --warmup 5 --frames "$frames" --aov color --out "$out" "$@" >/dev/null
python3 - "$out/timings.json" "$size" "$frames" "$*" <<'PY'
import json, sys, os
t = json.load(open(sys.argv[1]))
flags = f" ({sys.argv[4]})" if sys.argv[4] else ""
print(f"gallery/main {sys.argv[2]}{flags}, {sys.argv[3]} timed frames after 5 warm-up, device: {t['device']}, "
      f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores\n")
# Passes run once per mip (name.N) are summed into one row: sums of medians and of minima.
rows = {}
for p in t["passes"]:
    stem, _, last = p["name"].rpartition(".")
    key = stem if last.isdigit() else p["name"]
    r = rows.setdefault(key, [0.0, 0.0, 0.0, 0])
    r[0] += p["median_ms"]; r[1] += p["min_ms"]; r[2] += p["max_ms"]; r[3] += 1
print("| pass | median ms | min ms | max ms |\n|---|---|---|---|")
for k, (md, mn, mx, n) in rows.items():
    name = f"{k} (x{n}, summed)" if n > 1 else k
    print(f"| {name} | {md:.2f} | {mn:.2f} | {mx:.2f} |")
med = {k: r[0] for k, r in rows.items()}
glt = sum(med.get(k, 0.0) for k in ("render.gbuffer", "render.lighting", "render.tonemap"))
module = sum(v for k, v in med.items() if k.startswith("reflections."))
f = t["frame"]
print(f"| **frame (all passes)** | **{f['median_ms']:.2f}** | {f['min_ms']:.2f} | {f['max_ms']:.2f} |\n")
print(f"G-buffer + lighting + tonemap (sum of medians): {glt:.1f} ms; reflections module: "
      f"{module:.1f} ms ({100 * module / f['median_ms']:.0f}% of the frame median)\n")
m = t["memory"]
a, u = m["transient_peak_bytes_aliased"], m["transient_peak_bytes_unaliased"]
print(f"transient memory: {a/2**20:.1f} MiB aliased vs {u/2**20:.1f} MiB without aliasing "
      f"({100*(1-a/u):.0f}% lower); persistent {m['persistent_bytes']/2**20:.1f} MiB")
PY
rm -rf "$out"
