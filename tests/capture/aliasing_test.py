#!/usr/bin/env python3
"""The default frame (gallery at 960x540) reports its transient memory peak with and without
aliasing in timings.json, and aliasing lowers it by at least a fifth. Memory placement is
deterministic (unlike time), so this is asserted.

The bound was a quarter while the 16 MiB shadow map was a transient the G-buffer took the memory
of (48.4 MiB aliased against 77.4 without, 37% lower). Since issue 23 the shadow map is kept
across frames (engine/render/shadow.cpp: drawn once, not every frame), so it left the transient
set: the aliased peak is the same 48.4 MiB, the unaliased one 61.4 MiB (21% lower). The bound
follows what aliasing can still share, not a lower bar for the same frame."""
import json, os, subprocess, sys, tempfile

capture, root = sys.argv[1], sys.argv[2]
with tempfile.TemporaryDirectory() as out:
    subprocess.run([capture, "--scene", os.path.join(root, "assets/scenes/gallery.gltf"), "--camera", "main",
                    "--size", "960x540", "--warmup", "0", "--frames", "1", "--out", out],
                   check=True, stdout=subprocess.DEVNULL)
    memory = json.load(open(os.path.join(out, "timings.json")))["memory"]
    graph = json.load(open(os.path.join(out, "graph.json")))
aliased = memory["transient_peak_bytes_aliased"]
unaliased = memory["transient_peak_bytes_unaliased"]
print(f"transient peak: {aliased} bytes aliased, {unaliased} without ({100 * (1 - aliased / unaliased):.0f}% lower)")
if not (0 < aliased <= 0.8 * unaliased):
    sys.exit("aliasing must lower the default frame's transient peak by at least 20%")
if not graph.get("passes"):
    sys.exit("graph.json lists no passes")
