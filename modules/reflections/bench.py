#!/usr/bin/env python3
"""Trace cost of the reflections module: for each scene, size and tracer, the mean iterations
per traced ray, the trace pass's GPU median and the module's share of the frame.

usage: python3 modules/reflections/bench.py [BUILD_DIR] [FRAMES]   (writes a markdown table)"""
import json, os, subprocess, sys, tempfile

build = sys.argv[1] if len(sys.argv) > 1 else "build"
frames = sys.argv[2] if len(sys.argv) > 2 else "5"
capture = os.path.join(build, "engine", "speculum-capture")
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tests", "capture"))
from stripes_test import load  # uncompressed-EXR reader via oiiotool

print("| scene | size | tracer | mean iterations / ray | trace ms | module ms | frame ms | module share |")
print("| --- | --- | --- | --- | --- | --- | --- | --- |")
with tempfile.TemporaryDirectory() as tmp:
    for scene in ("gallery", "failure_cases"):
        for size in ("640x360", "960x540"):
            for trace in ("hiz", "linear"):
                out = os.path.join(tmp, f"{scene}.{size}.{trace}")
                subprocess.run([capture, "--scene", f"assets/scenes/{scene}.gltf", "--camera", "main", "--size", size,
                                "--frames", frames, "--warmup", "2", "--set", f"reflections.trace={trace}",
                                "--aov", "iterations", "--out", out], check=True, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
                t = json.load(open(os.path.join(out, "timings.json")))
                passes = {p["name"]: p["median_ms"] for p in t["passes"]}
                module = sum(v for k, v in passes.items() if k.startswith("reflections."))
                frame = t["frame"]["median_ms"]
                _, _, it = load(os.path.join(out, f"iterations.{int(frames) - 1:04d}.exr"), tmp)
                vals = [v for row in it[list(it.keys())[0]] for v in row if v > 0]
                mean = sum(vals) / max(len(vals), 1)
                print(f"| {scene} | {size} | {trace} | {mean:.1f} | {passes['reflections.trace']:.1f} | "
                      f"{module:.1f} | {frame:.1f} | {100 * module / frame:.0f}% |", flush=True)
