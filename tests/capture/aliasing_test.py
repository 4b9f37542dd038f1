#!/usr/bin/env python3
"""The default frame (gallery at 960x540) reports its transient memory peak with and without
aliasing in timings.json, and aliasing lowers it by at least a quarter. Memory placement is
deterministic (unlike time), so this is asserted."""
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
if not (0 < aliased <= 0.75 * unaliased):
    sys.exit("aliasing must lower the default frame's transient peak by at least 25%")
if not graph.get("passes"):
    sys.exit("graph.json lists no passes")
