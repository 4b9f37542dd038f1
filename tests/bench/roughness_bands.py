#!/usr/bin/env python3
"""Accuracy per roughness band of every method of a finished speculum-bench run (issue 13: is
cone tracing or stochastic glossy the more accurate for the time it takes, per roughness?).

    roughness_bands.py --bench-out DIR --suite SUITE.json --capture C --reference R --metrics M
                       [--cache DIR] [--bands 0,0.05,0.2,0.4,1.01]

For each view and size of the suite it captures the roughness AOV once (the G-buffer's
perceptual roughness: the same for every method), then scores each method's last reflection
frame of DIR/runs against the cached reference per band with `speculum-metrics compare
--band-image`. Prints a markdown table: PSNR (dB) per band and method, pooled over views by
squared error (pixels weigh equally), and the method's mean reflection ms from DIR/results.json."""
import json, math, subprocess, sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import speculum_bench as bench  # noqa: E402


def main():
    ap = bench.rescore_parser()
    ap.add_argument("--bands", default="0,0.05,0.2,0.4,1.01")
    a = ap.parse_args()
    out, suite, tools, views = bench.finished_run(a)
    edges = [float(x) for x in a.bands.split(",")]
    pooled = {}  # (method, band) -> [squared error sum, pixel count]
    for view, size, name, ref_dir, exposure in views:
        rough_dir = out / "runs" / f"{name}.roughness"
        if not list(rough_dir.glob("roughness.*.exr")):
            cmd = [a.capture, "--scene", str(bench.scene_file(view)), *bench.camera_args(view), "--size", size,
                   "--warmup", "0", "--aov", "roughness", "--out", str(rough_dir)]
            rough_dir.mkdir(parents=True, exist_ok=True)
            if bench.run(cmd, rough_dir / "log.txt") != 0:
                bench.fail(f"roughness capture failed for {name}; see {rough_dir / 'log.txt'}", 1)
        rough = bench.last_frame(rough_dir, "roughness")
        for method in suite["methods"]:
            run_dir = out / "runs" / f"{name}.{method}"
            test = bench.last_frame(run_dir, "reflection")
            cmd = [a.metrics, "compare", "--test", str(test), "--ref", str(ref_dir / "reflection.0000.exr"),
                   "--ref-mask", str(ref_dir / "reflective.0000.exr"), "--test-mask", str(test),
                   "--scale", str(exposure), "--band-image", str(rough), "--bands", a.bands]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                bench.fail(f"speculum-metrics failed: {r.stderr.strip()}", 1)
            for i, b in enumerate(json.loads(r.stdout)["bands"]):
                if b["pixels"] and b["psnr_db"] is not None:
                    mse = 10 ** (-b["psnr_db"] / 10)
                    acc = pooled.setdefault((method, i), [0.0, 0])
                    acc[0] += mse * b["pixels"]
                    acc[1] += b["pixels"]
        print(f"{name}: scored", file=sys.stderr, flush=True)
    rows = json.loads((out / "results.json").read_text())["rows"]
    ms = {m: sum(r["reflection_ms"] for r in rows if r["method"] == m) / max(1, sum(1 for r in rows if r["method"] == m))
          for m in suite["methods"]}
    bands = [f"[{edges[i]:g}, {edges[i + 1]:g})" for i in range(len(edges) - 1)]
    print("| method | reflection ms | " + " | ".join(f"PSNR roughness {b}" for b in bands) + " |")
    print("|---|---|" + "---|" * len(bands))
    for m in suite["methods"]:
        cells = []
        for i in range(len(bands)):
            se, n = pooled.get((m, i), [0.0, 0])
            cells.append(f"{10 * math.log10(n / se):.2f} ({n} px)" if n and se > 0 else "-")
        print(f"| {m} | {ms[m]:.1f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
