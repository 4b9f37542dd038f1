#!/usr/bin/env python3
"""Accuracy tests: each reflection method against speculum-reference (label accuracy).

    accuracy_test.py TOOLS... --view SCENE.CAMERA --method NAME     one suite view and method
    accuracy_test.py TOOLS... --agreement                           the 40 dB mirror-floor case
    accuracy_test.py TOOLS... --measure                             print today's numbers as thresholds

Thresholds live in thresholds.json beside this file (and nowhere else). Rendering and scoring
are speculum-bench's own functions, so the tests and the bench measure the same way. Exit 77
(ctest's skip) when speculum-capture has no reflections module yet.
"""
import argparse
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "bench"))
import speculum_bench as bench  # noqa: E402

SKIP = 77


def load_thresholds(path):
    doc = json.loads(Path(path).read_text())
    for key in ("size", "reference", "methods", "views", "agreement"):
        if key not in doc:
            bench.fail(f"{path}: missing '{key}'", 3)
    return doc


def measure(tools, doc, view, method, out, cache):
    """Scores of one method on one view at the thresholds' size: the bench's path, one run."""
    suite = {"warmup": doc.get("warmup", 3), "frames": doc.get("frames", 1)}
    ref_dir, _ = bench.render_reference(tools, view, doc["size"], doc["reference"], cache)
    exposure = json.loads((ref_dir / "reference.json").read_text())["exposure"]
    name = f"{view['scene']}.{view['camera']}.{method}"
    image, refl_ms, _, _ = bench.capture(tools, view, doc["size"], doc["methods"][method], "reflection", suite,
                                         out / name)
    scores = bench.score(tools, image, ref_dir, "reflection", exposure, out / f"{name}.heatmap.png")
    scores["reflection_ms"] = refl_ms
    return scores


def check(scores, limits, label):
    problems = []
    if scores["pixels"] == 0:
        problems.append("no reflective pixels")
    if "psnr_min" in limits and (scores["psnr_db"] is None or scores["psnr_db"] < limits["psnr_min"]):
        problems.append(f"PSNR {scores['psnr_db']} dB < {limits['psnr_min']}")
    if "mae_max" in limits and scores["mae"] > limits["mae_max"]:
        problems.append(f"MAE {scores['mae']:.5f} > {limits['mae_max']}")
    if "gross_max" in limits and scores["gross_share"] > limits["gross_max"]:
        problems.append(f"gross share {scores['gross_share']:.5f} > {limits['gross_max']}")
    print(f"{label}: PSNR {scores['psnr_db']:.2f} dB, MAE {scores['mae']:.5f}, gross {scores['gross_share']:.5f}, "
          f"{scores['pixels']} reflective pixels; limits {limits}")
    for p in problems:
        print(f"FAIL {label}: {p}")
    return not problems


def view_of(key):
    scene, camera = key.split(".", 1)
    return {"scene": scene, "camera": camera}


def agreement(tools, doc, out, cache):
    scene_dir = out / "agreement_scene"
    subprocess.run([sys.executable, str(HERE / "make_agreement_scene.py"), str(scene_dir)], check=True)
    view = {"scene": "mirror_wall", "camera": "main", "file": str(scene_dir / "mirror_wall.gltf")}
    ok = True
    for method in doc["methods"]:
        ok &= check(measure(tools, doc, view, method, out, cache), doc["agreement"], f"agreement {method}")
    return ok


def main():
    p = argparse.ArgumentParser()
    for tool in ("capture", "reference", "metrics"):
        p.add_argument(f"--{tool}", required=True)
    p.add_argument("--thresholds", default=str(HERE / "thresholds.json"))
    p.add_argument("--cache", required=True, help="reference cache (keyed like the bench's)")
    p.add_argument("--out", required=True)
    p.add_argument("--view")
    p.add_argument("--method")
    p.add_argument("--agreement", action="store_true")
    p.add_argument("--measure", action="store_true")
    args = p.parse_args()
    doc = load_thresholds(args.thresholds)
    out, cache = Path(args.out), Path(args.cache)
    out.mkdir(parents=True, exist_ok=True)
    probe_view = view_of(next(iter(doc["views"])))
    if not bench.capture_has_reflections(args, probe_view, out / "probe"):
        print("SKIP: speculum-capture has no reflections module yet (--aov reflection is exit 2)")
        sys.exit(SKIP)
    if args.agreement:
        sys.exit(0 if agreement(args, doc, out, cache) else 1)
    if args.measure:
        margin = doc["margin"]
        table = {}
        for key in doc["views"]:
            table[key] = {}
            for method in doc["methods"]:
                s = measure(args, doc, view_of(key), method, out, cache)
                table[key][method] = {"psnr_min": round(s["psnr_db"] - margin["psnr_db"], 2),
                                      "mae_max": round(s["mae"] * margin["mae_factor"], 4),
                                      "gross_max": round(s["gross_share"] + margin["gross_share"], 4)}
                print(f"{key} {method}: PSNR {s['psnr_db']:.3f} MAE {s['mae']:.5f} gross {s['gross_share']:.5f} "
                      f"reflection {s['reflection_ms']:.2f} ms", file=sys.stderr)
        print(json.dumps(table, indent=2))
        return
    if args.view not in doc["views"] or args.method not in doc["views"][args.view]:
        bench.fail(f"{args.thresholds}: no thresholds for view '{args.view}' and method '{args.method}'", 2)
    scores = measure(args, doc, view_of(args.view), args.method, out, cache)
    sys.exit(0 if check(scores, doc["views"][args.view][args.method], f"{args.view} {args.method}") else 1)


if __name__ == "__main__":
    main()
