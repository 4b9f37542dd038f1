#!/usr/bin/env python3
"""Cost of half against full resolution (issue 13), in one run, alternating the configurations
so that machine noise falls on both: per configuration the median over runs of the sum of
trace + resolve (+ guide + upsample at half) and of the whole module and frame.

    half_cost.py CAPTURE SCENE [--camera main] [--size 960x540] [--runs 3] [--frames 5]
                 [--config NAME=KEY=VALUE,KEY=VALUE ...]

Prints a markdown table. Timing only: never an assertion (the machines are noisy)."""
import argparse, json, statistics, subprocess, sys, tempfile
from pathlib import Path

CORE = ("reflections.trace", "reflections.resolve", "reflections.guide", "reflections.upsample")


def run(capture, scene, camera, size, frames, sets, out):
    cmd = [capture, "--scene", scene, "--camera", camera, "--size", size, "--warmup", "3",
           "--frames", str(frames), "--out", str(out)]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)
    t = json.loads((out / "timings.json").read_text())
    passes = {p["name"]: p["median_ms"] for p in t["passes"]}
    core = sum(ms for n, ms in passes.items() if n in CORE)
    module = sum(ms for n, ms in passes.items() if n.startswith("reflections."))
    return core, module, t["frame"]["median_ms"], passes


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("capture"); ap.add_argument("scene")
    ap.add_argument("--camera", default="main"); ap.add_argument("--size", default="960x540")
    ap.add_argument("--runs", type=int, default=3); ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--config", action="append", default=[])
    a = ap.parse_args()
    configs = {"full": [], "half": ["reflections.resolution=half"]}
    for c in a.config:
        name, _, sets = c.partition("=")
        configs[name] = [s for s in sets.split(",") if s]
    results = {n: [] for n in configs}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(a.runs):
            for n, sets in configs.items():
                results[n].append(run(a.capture, a.scene, a.camera, a.size, a.frames, sets, Path(tmp) / f"{n}.{r}"))
                print(f"run {r + 1}/{a.runs} {n}: core {results[n][-1][0]:.1f} ms", file=sys.stderr, flush=True)
    print(f"| config | trace+resolve(+guide+upsample) ms | module ms | frame ms | module share |")
    print("|---|---|---|---|---|")
    for n, rs in results.items():
        core = statistics.median(r[0] for r in rs); mod = statistics.median(r[1] for r in rs)
        frame = statistics.median(r[2] for r in rs)
        print(f"| {n} | {core:.1f} | {mod:.1f} | {frame:.1f} | {mod / frame:.0%} |")
    if "full" in results and "half" in results:
        f = statistics.median(r[0] for r in results["full"]); h = statistics.median(r[0] for r in results["half"])
        print(f"\nhalf is {f / h:.2f}x cheaper than full on trace + resolve (+ guide + upsample)")
    last = {n: rs[-1][3] for n, rs in results.items()}
    print("\nper pass (last run, ms): " + json.dumps({n: {k: round(v, 2) for k, v in p.items() if k.startswith("reflections.")
                                                       and not k[-1].isdigit()} for n, p in last.items()}))


if __name__ == "__main__":
    main()
