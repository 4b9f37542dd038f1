#!/usr/bin/env python3
"""Cost of half against full resolution (issue 13), in one run, alternating the configurations
so that machine noise falls on all of them: per configuration the median over runs of the sum of
trace + resolve (+ guide + upsample at half), of the whole module and of the frame, and the
median of every reflections.* pass (pyramid levels summed per pyramid).

    half_cost.py CAPTURE SCENE [--camera main] [--size 960x540] [--runs 3] [--frames 5]
                 [--config NAME=KEY=VALUE,KEY=VALUE ...] [--config NAME=@SETTINGS.json]

Prints markdown tables. Timing only: never an assertion (the machines are noisy)."""
import argparse, json, statistics, subprocess, sys, tempfile
from pathlib import Path

CORE = ("reflections.trace", "reflections.resolve", "reflections.guide", "reflections.upsample")


def run(capture, scene, camera, size, frames, sets, out):
    cmd = [capture, "--scene", scene, "--camera", camera, "--size", size, "--warmup", "3",
           "--frames", str(frames), "--out", str(out)]
    for s in sets:
        cmd += ["--settings", s[1:]] if s.startswith("@") else ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)
    t = json.loads((out / "timings.json").read_text())
    passes = {}
    for p in t["passes"]:
        # Pyramid levels (reflections.hiz.3) are summed under their pyramid's name.
        name = p["name"].rsplit(".", 1)[0] if p["name"].rsplit(".", 1)[-1].isdigit() else p["name"]
        passes[name] = passes.get(name, 0.0) + p["median_ms"]
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
    names = sorted({k for rs in results.values() for r in rs for k in r[3] if k.startswith("reflections.")})
    print("\n| pass (median ms) | " + " | ".join(results) + " |")
    print("|---|" + "---|" * len(results))
    for k in names:
        cells = []
        for n, rs in results.items():
            v = [r[3][k] for r in rs if k in r[3]]
            cells.append(f"{statistics.median(v):.1f}" if v else "-")
        print(f"| {k} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
