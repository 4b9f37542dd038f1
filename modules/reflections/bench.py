#!/usr/bin/env python3
"""Trace cost and accuracy of the reflections module's tracers, for each scene and size:

- mean iterations per traced ray, over all rays and over rays longer than 64 pixels (length
  from the pixel to the hit of the exhaustive march below);
- accuracy on those long rays: the share whose result agrees with the exhaustive march (both
  miss, or both hit within 1 pixel);
- the trace pass's GPU median, the module's and the frame's, and the module's share.

The exhaustive march is the linear tracer at one-pixel steps over the whole screen with deep
refinement: no hierarchy, no stride, so it sees every pixel a ray crosses. `linear` is the
baseline at its defaults (2-pixel stride); `linear1` the same march at 1-pixel stride.

usage: python3 modules/reflections/bench.py [BUILD_DIR] [FRAMES] [--scenes a,b] [--sizes WxH,..]
(prints a markdown table)"""
import argparse, json, math, os, subprocess, sys, tempfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tests", "capture"))
from stripes_test import EXHAUSTIVE, load  # the exhaustive march; uncompressed-EXR reader

LONG_RAY_PX = 64
TRACERS = {
    "hiz": ["reflections.trace=hiz"],
    "linear": ["reflections.trace=linear"],
    "linear1": ["reflections.trace=linear", "reflections.linear_stride=1"],
}


def capture(exe, scene, size, settings, frames, out):
    args = [exe, "--scene", f"assets/scenes/{scene}.gltf", "--camera", "main", "--size", size, "--frames",
            str(frames), "--warmup", "2", "--aov", "hit", "--out", out]
    for s in settings:
        args += ["--set", s]
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    t = json.load(open(os.path.join(out, "timings.json")))
    passes = {p["name"]: p["median_ms"] for p in t["passes"]}
    module = sum(v for k, v in passes.items() if k.startswith("reflections."))
    w, h, ch = load(os.path.join(out, f"hit.{frames - 1:04d}.exr"), out)
    return {"trace": passes["reflections.trace"], "module": module, "frame": t["frame"]["median_ms"],
            "hit": (w, h, ch["R"], ch["G"], ch["B"], ch["A"])}


def agree(a, b, x, y):
    (_, _, ax, ay, az, _), (_, _, bx, by, bz, _) = a, b
    if az[y][x] <= 0.0 or bz[y][x] <= 0.0:
        return (az[y][x] > 0.0) == (bz[y][x] > 0.0)
    return math.hypot(ax[y][x] - bx[y][x], ay[y][x] - by[y][x]) <= 1.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build", nargs="?", default="build")
    ap.add_argument("frames", nargs="?", type=int, default=5)
    ap.add_argument("--scenes", default="gallery,failure_cases")
    ap.add_argument("--sizes", default="640x360,960x540")
    a = ap.parse_args()
    exe = os.path.join(a.build, "tools", "capture", "speculum-capture")
    print(f"| scene | size | tracer | iterations / ray | iterations / ray > {LONG_RAY_PX} px | agrees on rays > "
          f"{LONG_RAY_PX} px | trace ms | module ms | frame ms | module share |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as tmp:
        for scene in a.scenes.split(","):
            for size in a.sizes.split(","):
                print(f"[bench] {scene} {size}: exhaustive march", file=sys.stderr, flush=True)
                ref = capture(exe, scene, size, EXHAUSTIVE, 1, os.path.join(tmp, f"{scene}.{size}.ref"))["hit"]
                w, h, rx, ry, rz, _ = ref
                traced = [(x, y) for y in range(h) for x in range(w) if ref[5][y][x] > 0]
                long_rays = [(x, y) for x, y in traced
                             if rz[y][x] > 0 and math.hypot(rx[y][x] - x - 0.5, ry[y][x] - y - 0.5) > LONG_RAY_PX]
                for name, settings in TRACERS.items():
                    print(f"[bench] {scene} {size}: {name}", file=sys.stderr, flush=True)
                    r = capture(exe, scene, size, settings, a.frames, os.path.join(tmp, f"{scene}.{size}.{name}"))
                    it = r["hit"][5]
                    mean_all = sum(it[y][x] for x, y in traced) / max(len(traced), 1)
                    mean_long = sum(it[y][x] for x, y in long_rays) / max(len(long_rays), 1)
                    ok = sum(agree(r["hit"], ref, x, y) for x, y in long_rays) / max(len(long_rays), 1)
                    print(f"| {scene} | {size} | {name} | {mean_all:.1f} | {mean_long:.1f} ({len(long_rays)} rays) | "
                          f"{100 * ok:.1f}% | {r['trace']:.1f} | {r['module']:.1f} | {r['frame']:.1f} | "
                          f"{100 * r['module'] / r['frame']:.0f}% |", flush=True)


if __name__ == "__main__":
    main()
