#!/usr/bin/env python3
"""Accuracy tests: each reflection method against speculum-reference (label accuracy).

    accuracy_test.py TOOLS... --view SCENE.CAMERA --method NAME     one suite view and method
    accuracy_test.py TOOLS... --agreement                           the 40 dB mirror-floor case
    accuracy_test.py TOOLS... --probe-gain SCENE.CAMERA [--scores DIR]  with probes against without
    accuracy_test.py TOOLS... --measure                             print today's numbers as thresholds

Thresholds live in thresholds.json beside this file (and nowhere else). Rendering and scoring
are speculum-bench's own functions, so the tests and the bench measure the same way. Exit 77
(ctest's skip) when speculum-capture has no reflections module yet.

--probe-gain compares two methods of thresholds.json's "probe_gain" on one view (hiz+probes
against hiz): the PSNR with probes must be at least the PSNR without less a small tolerance,
and at least "min_gain_db" above it on the views listed there. With --scores it reads the two
methods' scores that the view's own tests wrote (ctest runs those first: a fixture), and
measures only what is missing.
"""
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "bench"))
import speculum_bench as bench  # noqa: E402
from accuracy_args import tool_parser  # noqa: E402

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
    (out / f"{name}.scores.json").unlink(missing_ok=True)  # never leave a previous run's scores
    image, refl_ms, _, _ = bench.capture(tools, view, doc["size"], doc["methods"][method], "reflection", suite,
                                         out / name)
    scores = bench.score(tools, image, ref_dir, "reflection", exposure, out / f"{name}.heatmap.png")
    scores["reflection_ms"] = refl_ms
    # Read by --probe-gain (the view's gain test) so that it need not render the view again.
    (out / f"{name}.scores.json").write_text(json.dumps(scores, indent=2))
    return scores


def view_methods(doc, key):
    """The methods a view is tested with: those its entry lists (all of them when it lists none)."""
    return list(doc["views"][key]) or list(doc["methods"])


def saved_scores(scores_dir, name):
    """Where the test of view and method NAME (VIEW.METHOD) left its scores."""
    return Path(scores_dir) / name / f"{name}.scores.json"


def probe_gain(tools, doc, key, scores_dir, out, cache):
    rule = doc["probe_gain"]
    got = {}
    for method in (rule["without"], rule["with"]):
        name = f"{key}.{method}"
        saved = saved_scores(scores_dir, name) if scores_dir else None
        if saved and saved.exists():
            got[method] = json.loads(saved.read_text())
            print(f"{name}: scores from {saved}")
        else:
            got[method] = measure(tools, doc, view_of(key), method, out, cache)
    a, b = got[rule["without"]], got[rule["with"]]
    if a["psnr_db"] is None or b["psnr_db"] is None:
        print(f"FAIL {key}: no PSNR ({rule['without']} {a['psnr_db']}, {rule['with']} {b['psnr_db']})")
        return False
    gain = b["psnr_db"] - a["psnr_db"]
    floor = -rule["psnr_tolerance_db"]
    wanted = rule.get("min_gain_db", {}).get(key)
    print(f"{key}: {rule['with']} {b['psnr_db']:.2f} dB, {rule['without']} {a['psnr_db']:.2f} dB, gain {gain:+.2f} dB "
          f"(gross {a['gross_share']:.4f} -> {b['gross_share']:.4f}); must be >= {floor:+.2f} dB"
          + (f" and >= {wanted:+.2f} dB" if wanted is not None else ""))
    ok = True
    if gain < floor:
        print(f"FAIL {key}: {rule['with']} is {-gain:.2f} dB worse than {rule['without']} "
              f"(tolerance {rule['psnr_tolerance_db']} dB)")
        ok = False
    if wanted is not None and gain < wanted:
        print(f"FAIL {key}: {rule['with']} gains {gain:.2f} dB over {rule['without']}, less than {wanted} dB")
        ok = False
    return ok


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
    if "mirror_psnr_min" in limits and (scores.get("mirror_psnr_db") is None
                                        or scores["mirror_psnr_db"] < limits["mirror_psnr_min"]):
        problems.append(f"mirror-band PSNR {scores.get('mirror_psnr_db')} dB < {limits['mirror_psnr_min']}")
    print(f"{label}: PSNR {scores['psnr_db']:.2f} dB, MAE {scores['mae']:.5f}, gross {scores['gross_share']:.5f}, "
          f"{scores['pixels']} reflective pixels; limits {limits}")
    if scores.get("converged_reference"):
        print(f"{label}: mirror band {band(scores, 'mirror')}, rough band {band(scores, 'rough')}; "
              f"{scores.get('unconverged_pixels', 0)} pixels left out (reference unconverged); the reference's two "
              f"seeds agree at {fmt_db(scores.get('reference_agreement_db'))} (mirror band), "
              f"{fmt_db(scores.get('reference_agreement_rough_db'))} (rough band)")
    for p in problems:
        print(f"FAIL {label}: {p}")
    return not problems


def fmt_db(v):
    return "-" if v is None else f"{v:.2f} dB"


def band(scores, name):
    return f"{fmt_db(scores.get(name + '_psnr_db'))} on {scores.get(name + '_pixels', 0)} px"


def view_of(key):
    scene, camera = key.split(".", 1)
    return {"scene": scene, "camera": camera}


def agreement(tools, doc, out, cache):
    scene_dir = out / "agreement_scene"
    subprocess.run([sys.executable, str(HERE / "make_agreement_scene.py"), str(scene_dir)], check=True)
    view = {"scene": "mirror_wall", "camera": "main", "file": str(scene_dir / "mirror_wall.gltf")}
    ok = True
    for method in doc["agreement"].get("methods", doc["methods"]):
        ok &= check(measure(tools, doc, view, method, out, cache), doc["agreement"], f"agreement {method}")
    return ok


def main():
    p = tool_parser()
    p.add_argument("--cache", required=True, help="reference cache (keyed like the bench's)")
    p.add_argument("--out", required=True)
    p.add_argument("--view")
    p.add_argument("--method")
    p.add_argument("--agreement", action="store_true")
    p.add_argument("--measure", action="store_true")
    p.add_argument("--probe-gain", metavar="SCENE.CAMERA", help="with probes against without on one view")
    p.add_argument("--scores", help="folder of the per-view tests' outputs (--probe-gain reads their scores)")
    args = p.parse_args()
    doc = load_thresholds(args.thresholds)
    out, cache = Path(args.out), Path(args.cache)
    out.mkdir(parents=True, exist_ok=True)
    if args.probe_gain and args.scores and all(
            saved_scores(args.scores, f"{args.probe_gain}.{m}").exists()
            for m in (doc["probe_gain"]["without"], doc["probe_gain"]["with"])):
        # Both scores are there, so the capture has the module: no probe capture, no rendering.
        sys.exit(0 if probe_gain(args, doc, args.probe_gain, args.scores, out, cache) else 1)
    probe_view = view_of(next(iter(doc["views"])))
    if not bench.capture_has_reflections(args, probe_view, out / "probe"):
        print("SKIP: speculum-capture has no reflections module yet (--aov reflection is exit 2)")
        sys.exit(SKIP)
    if args.agreement:
        sys.exit(0 if agreement(args, doc, out, cache) else 1)
    if args.probe_gain:
        if args.probe_gain not in doc["views"]:
            bench.fail(f"{args.thresholds}: no view '{args.probe_gain}'", 2)
        sys.exit(0 if probe_gain(args, doc, args.probe_gain, args.scores, out, cache) else 1)
    if args.measure:
        margin = doc["margin"]
        table, gains = {}, {}
        rule = doc.get("probe_gain")
        # --view: one view alone (its reference was rendered again; the rest stay as measured)
        for key in [args.view] if args.view else doc["views"]:
            if key not in doc["views"]:
                bench.fail(f"{args.thresholds}: no view '{key}'", 2)
            table[key] = {}
            for method in view_methods(doc, key):
                s = measure(args, doc, view_of(key), method, out, cache)
                table[key][method] = {"psnr_min": round(s["psnr_db"] - margin["psnr_db"], 2),
                                      "mae_max": round(s["mae"] * margin["mae_factor"], 4),
                                      "gross_max": round(s["gross_share"] + margin["gross_share"], 4)}
                if s.get("mirror_psnr_db") is not None:
                    table[key][method]["mirror_psnr_min"] = round(s["mirror_psnr_db"] - margin["psnr_db"], 2)
                print(f"{key} {method}: PSNR {s['psnr_db']:.3f} MAE {s['mae']:.5f} gross {s['gross_share']:.5f} "
                      f"reflection {s['reflection_ms']:.2f} ms", file=sys.stderr)
                table[key][method]["_measured"] = {"psnr_db": round(s["psnr_db"], 3), "mae": round(s["mae"], 5),
                                                   "gross_share": round(s["gross_share"], 5)}
                for k in ("mirror_psnr_db", "rough_psnr_db", "reference_agreement_db", "reference_agreement_rough_db"):
                    if s.get(k) is not None:
                        table[key][method]["_measured"][k] = round(s[k], 2)
            if rule and rule["with"] in table[key] and rule["without"] in table[key]:
                gains[key] = round(table[key][rule["with"]]["_measured"]["psnr_db"]
                                   - table[key][rule["without"]]["_measured"]["psnr_db"], 3)
        print(json.dumps({"views": table, "probe_gain_db": gains}, indent=2))
        return
    if args.view not in doc["views"] or args.method not in view_methods(doc, args.view):
        bench.fail(f"{args.thresholds}: no thresholds for view '{args.view}' and method '{args.method}'", 2)
    scores = measure(args, doc, view_of(args.view), args.method, out, cache)
    sys.exit(0 if check(scores, doc["views"][args.view].get(args.method, {}), f"{args.view} {args.method}") else 1)


if __name__ == "__main__":
    main()
