#!/usr/bin/env python3
"""speculum-bench: speed against accuracy for every reflection method (docs/design.md section 7, measurement).

    speculum-bench --suite tests/bench/suite.json --out DIR

For each view (scene, camera) and size of the suite it renders the ground truth once with
speculum-reference (cached under --cache by a hash of everything that changes the image), then
for each method runs speculum-capture with warm-up frames, reads the per-pass GPU timestamp
medians from timings.json (reflection ms = the sum of the reflections.* passes) and scores the
method's reflection AOV against the reference with speculum-metrics (PSNR, MAE and gross-error
share on reflective pixels). Writes results.csv, results.json, chart.png and chart.svg (x =
reflection ms, y = PSNR, one colour per method, Pareto front), heatmaps/*.png and summary.md
(with what the probes add: each METHOD+probes against METHOD). `--replot --out DIR` rewrites
the chart and summary from DIR/results.json without rendering.

Until the capture has the reflections module (`--aov reflection` is exit 2), it benches the one
method the engine has, "env_only" (the split-sum sky on reflective surfaces), on the linear AOV.
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(SOURCE / "tests" / "reference"))
import store  # noqa: E402  (the converged references in assets/references)
from store import file_hash  # noqa: E402


def fail(message, code=2):
    print(f"speculum-bench: {message}", file=sys.stderr)
    sys.exit(code)


def load_suite(path):
    if not Path(path).is_file():  # a folder, a device such as /dev/zero (read forever), nothing
        fail(f"{path}: not a regular file (the suite must be a JSON file)", 3)
    try:
        suite = json.loads(Path(path).read_text())
    except (OSError, ValueError, RecursionError) as e:  # RecursionError: JSON nested ~1,000 deep
        fail(f"{path}: cannot read the suite: {type(e).__name__}: {str(e)[:200]}", 3)
    if not isinstance(suite, dict):
        fail(f"{path}: the suite must be a JSON object", 3)
    for key, kind in (("methods", dict), ("sizes", list), ("views", list), ("reference", dict)):
        if not isinstance(suite.get(key), kind):
            fail(f"{path}: '{key}' must be a JSON {kind.__name__}", 3)
    for v in suite["views"]:
        if not isinstance(v, dict) or "scene" not in v or "camera" not in v:
            fail(f"{path}: every view needs 'scene' and 'camera', got {v}", 3)
    suite.setdefault("warmup", 3)
    suite.setdefault("frames", 5)
    suite.setdefault("aov", "reflection")
    return suite


def scene_file(view):
    return SOURCE / view.get("file", f"assets/scenes/{view['scene']}.gltf")


def camera_args(view):
    """A named camera, or a camera path (every path frame is written)."""
    if "path" in view:
        return ["--path", str(SOURCE / view["path"])]
    return ["--camera", view["camera"]]


def view_name(view):
    return f"{view['scene']}.{view['camera'] if 'camera' in view else Path(view['path']).stem + '_path'}"


def reference_key(view, size, settings, reference_binary):
    """Everything that changes a reference image: the scene's files, camera, size, spp,
    bounces, seed and the renderer itself."""
    h = store.scene_digest(scene_file(view))
    camera = view.get("camera") or file_hash(SOURCE / view["path"])
    h.update(json.dumps([camera, size, settings], sort_keys=True).encode())
    h.update(file_hash(reference_binary).encode())
    return h.hexdigest()[:24]


def run(cmd, log):
    with open(log, "w") as out:
        return subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT).returncode


# The band edge of the scores (reference::kRoughBand): mirror pixels below it, rough above.
ROUGH_BAND = 0.3


def render_reference(tools, view, size, settings, cache):
    """The reference folder for a view and whether it was there already. settings {"converged":
    true, "bounces": N}: the fresh entry of the converged store (assets/references), or the
    bench stops with the command that regenerates it; with a "fallback" (fixed-rate settings)
    a view the store lacks is rendered with those instead and its rows say so. "path_bounces"
    (default: bounces) is the depth of a camera path's entries; either may be a list, the depths
    to take in turn where the store has no entry at the first."""
    if settings.get("converged"):
        # The store's entry at this size or at a whole fraction of it (960x540 is scored at the
        # 320x180 entry's pixel centres; camera paths have 160x90 entries for 480x270 runs).
        depths = settings.get("path_bounces", settings["bounces"]) if "path" in view else settings["bounces"]
        depths = depths if isinstance(depths, list) else [depths]
        # A list: the deepest first, the next only where the store has no entry at all (a stale
        # one stops the bench: it never falls back past a reference that should be rendered again).
        for bounces in depths:
            folder, why = store.lookup(view["scene"], view.get("camera"), size, bounces, path=view.get("path"))
            if folder is not None:
                return folder, True
            if not why.startswith(store.MISSING):
                break
        if settings.get("render_missing") and "camera" in view:
            return render_converged(tools, view, size, depths[0], cache)
        if "fallback" not in settings:
            fail(f"{view_name(view)} {size}: {why}", 1)
        settings = settings["fallback"]
    cmd = [tools.reference, "--scene", str(scene_file(view)), *camera_args(view), "--size", size,
           "--spp", str(settings["spp"]), "--bounces", str(settings["bounces"]),
           "--seed", str(settings.get("seed", 1)), "--aov", "linear,reflection,reflective"]

    def render(tmp):
        tmp.mkdir(parents=True, exist_ok=True)
        if run(cmd + ["--out", str(tmp)], tmp / "log.txt") != 0:
            fail(f"speculum-reference failed for {view_name(view)} {size}; see {tmp / 'log.txt'}", 1)
    return cached(cache, reference_key(view, size, settings, tools.reference), render)


def render_converged(tools, view, size, bounces, cache):
    """A view the store does not hold (the placement tool's edited scenes), rendered with the
    store's converged settings into the cache: minutes a view, with the reference's progress."""
    settings = store.manifest()["settings"]

    def render(tmp):
        print(f"speculum-bench: converged reference of {view_name(view)} at {size} (minutes)", flush=True)
        store.render(tools.reference, {"camera": view["camera"], "size": size, "bounces": bounces}, settings, tmp,
                     scene=scene_file(view))
    return cached(cache, reference_key(view, size, {"converged": settings, "bounces": bounces}, tools.reference),
                  render)


def cached(cache, key, render):
    """cache/key and whether it was there already; else render(folder) fills a private folder that
    is renamed into place when complete (parallel tests may render the same key)."""
    out = cache / key
    if (out / "reference.json").exists():
        return out, True
    tmp = cache / f"{key}.tmp{os.getpid()}"
    shutil.rmtree(tmp, ignore_errors=True)
    render(tmp)
    try:
        tmp.rename(out)
    except OSError:  # another process finished the same key first: its images are identical
        shutil.rmtree(tmp, ignore_errors=True)
    return out, False


def capture_has_reflections(tools, view, scratch):
    cmd = [tools.capture, "--scene", str(scene_file(view)), "--camera", view["camera"], "--size", "32x18",
           "--warmup", "0", "--aov", "reflection", "--out", str(scratch)]
    return run(cmd, scratch.parent / "probe.txt") != 2


def last_frame(folder, aov):
    files = sorted(folder.glob(f"{aov}.*.exr"))
    if not files:
        fail(f"{folder}: speculum-capture wrote no {aov} image", 1)
    return files[-1]


def capture(tools, view, size, method_sets, aov, suite, out):
    cmd = [tools.capture, "--scene", str(scene_file(view)), *camera_args(view), "--size", size,
           "--warmup", str(suite["warmup"]), "--aov", aov, "--out", str(out)]
    if "path" not in view:
        cmd += ["--frames", str(suite["frames"])]
    for s in method_sets:
        # "@FILE": a settings file (a preset such as assets/settings/medium.json), relative to
        # the source tree; anything else is one KEY=VALUE.
        cmd += ["--settings", str(SOURCE / s[1:])] if s.startswith("@") else ["--set", s]
    out.mkdir(parents=True, exist_ok=True)
    if run(cmd, out / "log.txt") != 0:
        fail(f"speculum-capture failed ({' '.join(map(str, cmd))}); see {out / 'log.txt'}", 1)
    timings = json.loads((out / "timings.json").read_text())
    passes = {p["name"]: p["median_ms"] for p in timings["passes"]}
    reflection_ms = sum(ms for name, ms in passes.items() if name.startswith("reflections."))
    return last_frame(out, aov), reflection_ms, timings["frame"]["median_ms"], timings.get("device", "")


def reference_factor(ref_dir, size):
    """k when the reference is 1/k of the run's size on both axes (1: the same size)."""
    return int(size.lower().split("x")[0]) // json.loads((ref_dir / "reference.json").read_text())["width"]


def score(tools, test, ref_dir, aov, exposure, heatmap, size=None):
    """PSNR, MAE and gross share on the reflective pixels; against a converged reference also per
    band (mirror_psnr_db, rough_psnr_db), without the pixels it left unconverged, and with the
    reference's own seed agreement beside (reference_agreement_db: mirror band). A reference
    smaller than the run's size (WxH; None: the same) by a whole k is scored at its own pixel centres."""
    cmd = [tools.metrics, "compare", "--test", str(test), "--ref", str(ref_dir / f"{aov}.0000.exr"),
           "--ref-mask", str(ref_dir / "reflective.0000.exr"), "--scale", str(exposure), "--heatmap", str(heatmap)]
    if size and reference_factor(ref_dir, size) > 1:
        cmd += ["--at-reference-pixels"]
    if aov == "reflection":
        cmd += ["--test-mask", str(test)]
    converged = (ref_dir / "stderror.0000.exr").is_file()
    if converged:
        cmd += [*store.ref_error_args(ref_dir),
                "--band-image", str(ref_dir / "roughness.0000.exr"), "--bands", f"0,{ROUGH_BAND},1000"]
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"speculum-metrics failed: {result.stderr.strip()}", 1)
    scores = json.loads(result.stdout)
    scores["converged_reference"] = converged
    if converged:
        mirror, rough = scores.pop("bands")
        scores.update({"mirror_psnr_db": mirror["psnr_db"], "mirror_pixels": mirror["pixels"],
                       "rough_psnr_db": rough["psnr_db"], "rough_pixels": rough["pixels"]})
        agree = json.loads((ref_dir / "reference.json").read_text())["frames"][0].get("seed_agreement", {})
        scores["reference_agreement_db"] = (agree.get("mirror") or {}).get("psnr_db")
        scores["reference_agreement_rough_db"] = (agree.get("rough") or {}).get("psnr_db")
    return scores


def flicker(tools, run_dir, ref_dir, aov, frames, exposure, size):
    """Excess flicker along the path; against a converged reference path also the floor its own
    noise puts under the score (reference_floor) and the pixel-frames it left out."""
    cmd = [tools.metrics, "flicker", "--test", str(run_dir), "--ref", str(ref_dir), "--aov", aov,
           "--frames", str(frames), "--ref-mask-aov", "reflective", "--scale", str(exposure)]
    if aov == "reflection":
        cmd += ["--test-mask-aov", "reflection"]
    cmd += store.ref_error_args(ref_dir, aov=True)
    if reference_factor(ref_dir, size) > 1:
        cmd += ["--at-reference-pixels"]
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"speculum-metrics flicker failed: {result.stderr.strip()}", 1)
    return json.loads(result.stdout)


def stability(tools, suite, methods, aov, out, cache, progress_step):
    """Excess flicker of every method along the suite's camera paths."""
    rows = []
    for entry in suite.get("paths", []):
        view = {"scene": entry["scene"], "path": entry["path"], "file": entry.get("file")}
        if view["file"] is None:
            del view["file"]
        size = entry.get("size", "320x180")
        for ref_dir, _, info, method, sets, run_dir in each_method(
                tools, view, size, suite, cache, methods, progress_step, f"{view_name(view)} {size}",
                out / "runs" / f"{view_name(view)}.{size}"):
            _, refl_ms, frame_ms, _ = capture(tools, view, size, sets, aov, suite, run_dir)
            f = flicker(tools, run_dir, ref_dir, aov, len(info["frames"]), info["exposure"], size)
            rows.append({"scene": view["scene"], "path": view["path"], "size": size, "method": method,
                         "frames": len(info["frames"]), "reflection_ms": refl_ms,
                         "excess_flicker": f["excess_flicker"], "reference_floor": f.get("reference_floor"),
                         "unconverged_pixel_frames": f.get("unconverged_pixel_frames"),
                         "reference": reference_label(ref_dir, info, size)})
    return rows


def reference_label(ref_dir, info, size):
    """What a row was scored against: 'converged' (at WxH when smaller than the run) or the fixed rate."""
    if not (ref_dir / "stderror.0000.exr").is_file():
        return f"{info['spp']} spp"
    k = reference_factor(ref_dir, size)
    return "converged" if k == 1 else f"converged at {info['width']}x{info['height']}"


def each_method(tools, view, size, suite, cache, methods, progress_step, label, runs):
    """The view's reference (rendered or cached) and then, for each method, where its run goes:
    the bench and the flicker rows walk views the same way and report progress alike."""
    progress_step(f"reference {label}")
    ref_dir, cached = render_reference(tools, view, size, suite["reference"], cache)
    info = json.loads((ref_dir / "reference.json").read_text())
    for method, sets in methods.items():
        progress_step(f"capture {label} {method}")
        yield ref_dir, cached, info, method, sets, Path(f"{runs}.{method}")


def rescore_parser():
    """The arguments of the scripts that re-score a finished bench run (edge_pixels.py,
    roughness_bands.py): the run, its suite and this build's tools."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--bench-out", required=True); ap.add_argument("--suite", required=True)
    ap.add_argument("--capture", required=True); ap.add_argument("--reference", required=True)
    ap.add_argument("--metrics", required=True); ap.add_argument("--cache")
    return ap


def finished_run(a):
    """(out, suite, tools) and each (view, size, name, reference folder, exposure) of the finished
    run that rescore_parser's arguments name; the references come from the run's cache."""
    out = Path(a.bench_out)
    suite = load_suite(a.suite)
    cache = Path(a.cache) if a.cache else out / "reference-cache"
    tools = argparse.Namespace(capture=a.capture, reference=a.reference, metrics=a.metrics)

    def views():
        for view in suite["views"]:
            for size in suite["sizes"]:
                ref_dir, _ = render_reference(tools, view, size, suite["reference"], cache)
                exposure = json.loads((ref_dir / "reference.json").read_text())["exposure"]
                yield view, size, f"{view_name(view)}.{size}", ref_dir, exposure
    return out, suite, tools, views()


def progress(i, n, label, start):
    elapsed = time.monotonic() - start
    eta = elapsed / i * (n - i) if i else 0.0
    print(f"[{i}/{n}] {label}  ({elapsed:.0f} s elapsed, ~{eta:.0f} s left)", flush=True)


def bench(args, tools):
    suite = load_suite(args.suite)
    out = Path(args.out)
    cache = Path(args.cache) if args.cache else out / "reference-cache"
    for d in (out / "heatmaps", out / "runs", cache):
        d.mkdir(parents=True, exist_ok=True)
    methods, aov = suite["methods"], suite["aov"]
    if aov == "reflection" and not capture_has_reflections(tools, suite["views"][0], out / "runs" / "probe"):
        print("speculum-bench: this speculum-capture has no reflections module (--aov reflection is exit 2); "
              "benching 'env_only' on the linear AOV instead", flush=True)
        methods, aov = {"env_only": []}, "linear"
    jobs = [(v, s) for v in suite["views"] for s in suite["sizes"]]
    total = len(jobs) * (1 + len(methods)) + len(suite.get("paths", [])) * (1 + len(methods))
    step, start, rows = 0, time.monotonic(), []

    def progress_step(label):
        nonlocal step
        step += 1
        progress(step, total, label, start)

    for view, size in jobs:
        name = f"{view_name(view)}.{size}"
        for ref_dir, cached, ref_info, method, sets, run_dir in each_method(
                tools, view, size, suite, cache, methods, progress_step, name, out / "runs" / name):
            image, refl_ms, frame_ms, device = capture(tools, view, size, sets, aov, suite, run_dir)
            m = score(tools, image, ref_dir, aov, ref_info["exposure"], out / "heatmaps" / f"{name}.{method}.png", size)
            rows.append({"scene": view["scene"], "camera": view["camera"], "size": size, "method": method,
                         "aov": aov, "reflection_ms": refl_ms, "frame_ms": frame_ms, "psnr_db": m["psnr_db"],
                         "mae": m["mae"], "gross_share": m["gross_share"], "pixels": m["pixels"],
                         "mirror_psnr_db": m.get("mirror_psnr_db"), "rough_psnr_db": m.get("rough_psnr_db"),
                         "reference": reference_label(ref_dir, ref_info, size),
                         "reference_agreement_db": m.get("reference_agreement_db"),
                         "reference_seconds": ref_info["frames"][0]["seconds"], "reference_cached": cached,
                         "device": device})
    paths = stability(tools, suite, methods, aov, out, cache, progress_step)
    write_results(out, suite, rows, paths, time.monotonic() - start)


def configurations(rows):
    """Mean over views per (method, size): the points of the chart."""
    groups = {}
    for r in rows:
        groups.setdefault((r["method"], r["size"]), []).append(r)
    configs = []
    for (method, size), rs in groups.items():
        scored = [r["psnr_db"] for r in rs if r["psnr_db"] is not None]
        # Only rows scored against a converged reference have bands (older results.json: none).
        mirror = [r["mirror_psnr_db"] for r in rs if r.get("mirror_psnr_db") is not None]
        rough = [r["rough_psnr_db"] for r in rs if r.get("rough_psnr_db") is not None]
        configs.append({"method": method, "size": size, "views": len(rs),
                        "mirror_psnr_db": sum(mirror) / len(mirror) if len(mirror) == len(rs) else None,
                        "rough_psnr_db": sum(rough) / len(rough) if len(rough) == len(rs) else None,
                        "reflection_ms": sum(r["reflection_ms"] for r in rs) / len(rs),
                        "frame_ms": sum(r["frame_ms"] for r in rs) / len(rs),
                        "psnr_db": sum(scored) / len(scored) if scored else None,
                        "mae": sum(r["mae"] for r in rs) / len(rs),
                        "gross_share": sum(r["gross_share"] for r in rs) / len(rs)})
    key = accuracy_key(configs)
    for c in configs:
        # On the front when no other configuration is at least as fast and as accurate, and
        # strictly better in one of the two.
        c["pareto"] = c[key] is not None and not any(
            o is not c and o[key] is not None and o["reflection_ms"] <= c["reflection_ms"]
            and o[key] >= c[key]
            and (o["reflection_ms"] < c["reflection_ms"] or o[key] > c[key]) for o in configs)
    return sorted(configs, key=lambda c: (c["size"], c["method"]))


def accuracy_key(configs):
    """What the chart and the Pareto front rank by: the mirror band when every configuration was
    scored against converged references (issue 24: rough walls no longer drown the mirrors, and
    the reference's noise is far below the error), else the PSNR on all reflective pixels."""
    if configs and all(c.get("mirror_psnr_db") is not None for c in configs):
        return "mirror_psnr_db"
    return "psnr_db"


AXIS_LABELS = {"mirror_psnr_db": "mirror band PSNR (dB, roughness < 0.3, against converged references)",
               "psnr_db": "PSNR on reflective pixels (dB, clamped linear)"}


def write_results(out, suite, rows, paths, seconds):
    fields = list(rows[0].keys()) if rows else []
    with open(out / "results.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    configs = configurations(rows)
    (out / "results.json").write_text(json.dumps({"suite": suite, "seconds": seconds, "rows": rows,
                                                   "configurations": configs, "stability": paths}, indent=2))
    chart(out, rows, configs)
    summary(out, rows, configs, paths, seconds)
    print(f"speculum-bench: {len(rows)} runs in {seconds:.0f} s; results in {out}")


# One colour per method that stays the same from run to run (and from chart to chart): the known
# methods keep theirs; any other takes the next free tab10 colour in name order.
KNOWN_COLOURS = {"linear": 1, "hiz": 0, "probes": 2, "hiz+probes": 3}


def method_colours(methods, cmap):
    import matplotlib.pyplot as plt
    free = [cmap(i) for i in range(10) if i not in KNOWN_COLOURS.values()]
    # Past the six free tab10 colours, tab20's light shades: two methods never share a colour
    # (issue 23's presets suite has seven new methods).
    free += [plt.get_cmap("tab20")(i) for i in range(1, 20, 2)]
    colours, extra = {}, 0
    for m in methods:
        if m in KNOWN_COLOURS:
            colours[m] = cmap(KNOWN_COLOURS[m])
        else:
            colours[m] = free[extra % len(free)]
            extra += 1
    return colours


def chart(out, rows, configs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 5.5))
    colours = method_colours(sorted({r["method"] for r in rows}), plt.get_cmap("tab10"))
    markers = {s: "osD^v<>"[i % 7] for i, s in enumerate(sorted({r["size"] for r in rows}))}
    key = accuracy_key(configs)
    for r in rows:
        if r.get(key) is not None:
            ax.scatter(r["reflection_ms"], r[key], color=colours[r["method"]], marker=markers[r["size"]],
                       alpha=0.25, s=18)
    for c in configs:
        if c[key] is None:
            continue
        ax.scatter(c["reflection_ms"], c[key], color=colours[c["method"]], marker=markers[c["size"]], s=90,
                   edgecolors="black", label=f"{c['method']} {c['size']}")
        ax.annotate(c["size"], (c["reflection_ms"], c[key]), textcoords="offset points", xytext=(6, 4),
                    fontsize=8)
    front = sorted((c for c in configs if c["pareto"]), key=lambda c: c["reflection_ms"])
    if front:
        ax.step([c["reflection_ms"] for c in front], [c[key] for c in front], where="post", color="black",
                linestyle="--", linewidth=1, marker="o", markersize=14, markerfacecolor="none",
                label="Pareto front")  # rings: a one-point front has no line to draw
    ax.set_xlabel("reflection ms (GPU timestamp medians of the reflections.* passes)")
    ax.set_ylabel(AXIS_LABELS[key])
    ax.set_title("Speed against accuracy (large markers: mean over views; small: one view)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(out / "chart.png", dpi=120)
    fig.savefig(out / "chart.svg")
    plt.close(fig)


def fmt(v, digits=2):
    return "n/a" if v is None else f"{v:.{digits}f}"


def summary(out, rows, configs, paths, seconds):
    device = rows[0]["device"] if rows else ""
    lines = [f"# speculum-bench summary", "",
             f"{len(rows)} runs in {seconds:.0f} s on {device}; chart: `chart.png` / `chart.svg`, "
             f"heatmaps in `heatmaps/`. Accuracy is on reflective pixels, clamped linear after the scene's "
             f"exposure (tests/reference/README.md).", "",
             "## Configurations (mean over views)", "",
             f"Pareto front and chart by {AXIS_LABELS[accuracy_key(configs)]}. Bands: mirror (roughness < 0.3) and "
             f"rough, each only where every view of the row was scored against a converged reference.", "",
             "| method | size | reflection ms | frame ms | PSNR dB | mirror band dB | rough band dB | MAE | gross share | Pareto |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for c in configs:
        lines.append(f"| {c['method']} | {c['size']} | {fmt(c['reflection_ms'])} | {fmt(c['frame_ms'])} | "
                     f"{fmt(c['psnr_db'])} | {fmt(c.get('mirror_psnr_db'))} | {fmt(c.get('rough_psnr_db'))} | "
                     f"{fmt(c['mae'], 4)} | {fmt(c['gross_share'], 4)} | {'yes' if c['pareto'] else ''} |")
    pairs = [(m, m + "+probes") for m in sorted({c["method"] for c in configs})
             if any(c["method"] == m + "+probes" for c in configs)]
    if pairs:
        lines += ["", "## What the probes add (mean over views)", "",
                  "| size | without | with | PSNR gain dB | gross share without | with | ratio | reflection ms added |",
                  "|---|---|---|---|---|---|---|---|"]
        by = {(c["method"], c["size"]): c for c in configs}
        for base, withp in pairs:
            for size in sorted({c["size"] for c in configs}):
                a, b = by.get((base, size)), by.get((withp, size))
                if not a or not b or a["psnr_db"] is None or b["psnr_db"] is None:
                    continue
                ratio = b["gross_share"] / a["gross_share"] if a["gross_share"] > 0 else None
                lines.append(f"| {size} | {base} | {withp} | {b['psnr_db'] - a['psnr_db']:+.2f} | "
                             f"{fmt(a['gross_share'], 4)} | {fmt(b['gross_share'], 4)} | {fmt(ratio)} | "
                             f"{b['reflection_ms'] - a['reflection_ms']:+.2f} |")
    lines += ["", "## Where each method stands", ""]
    for method in sorted({c["method"] for c in configs}):
        mine = [c for c in configs if c["method"] == method]
        on_front = [c["size"] for c in mine if c["pareto"]]
        key = accuracy_key(configs)
        best = max((c for c in mine if c[key] is not None), key=lambda c: c[key], default=None)
        lines.append(f"- **{method}**: on the Pareto front at {', '.join(on_front) if on_front else 'no size'}; "
                     f"best {'mirror band' if key == 'mirror_psnr_db' else 'PSNR'} {fmt(best[key] if best else None)} dB "
                     f"at {best['size'] if best else 'n/a'} "
                     f"for {fmt(best['reflection_ms'] if best else None)} ms of reflections.")
    if paths:
        lines += ["", "## Stability along camera paths", "",
                  "Excess flicker: mean over frames of |(R_t - R_t-1) - (Ref_t - Ref_t-1)| on reflective pixels. "
                  "Against a converged reference path, on its converged pixels only, with the floor its own noise "
                  "puts under every score beside (reference floor; issue 24).", "",
                  "| scene | path | size | method | frames | excess flicker | reference floor | reference | "
                  "pixel-frames left out | reflection ms |", "|---|---|---|---|---|---|---|---|---|---|"]
        for p in paths:
            lines.append(f"| {p['scene']} | {p['path']} | {p['size']} | {p['method']} | {p['frames']} | "
                         f"{p['excess_flicker']:.5f} | {fmt(p.get('reference_floor'), 5)} | {p.get('reference', '')} | "
                         f"{p.get('unconverged_pixel_frames') if p.get('unconverged_pixel_frames') is not None else 'n/a'} | "
                         f"{fmt(p['reflection_ms'])} |")
    lines += ["", "## Every run", "",
              "Mirror band: reflection roughness below 0.3; rough band: above. reference: `converged` (assets/references; "
              "its two seeds' agreement in the mirror band beside) or the fixed rate it was rendered at.", "",
              "| scene | camera | size | method | reflection ms | PSNR dB | mirror band dB | rough band dB | MAE | "
              "gross share | reference | reference seeds agree dB |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['camera']} | {r['size']} | {r['method']} | {fmt(r['reflection_ms'])} | "
                     f"{fmt(r['psnr_db'])} | {fmt(r.get('mirror_psnr_db'))} | {fmt(r.get('rough_psnr_db'))} | "
                     f"{fmt(r['mae'], 4)} | {fmt(r['gross_share'], 4)} | {r.get('reference', '')} | "
                     f"{fmt(r.get('reference_agreement_db'))} |")
    (out / "summary.md").write_text("\n".join(lines) + "\n")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--suite", help="suite JSON (tests/bench/suite.json)")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--cache", help="reference image cache (default OUT/reference-cache)")
    p.add_argument("--replot", action="store_true",
                   help="rewrite chart and summary.md from OUT/results.json (no rendering)")
    p.add_argument("--capture", help=argparse.SUPPRESS)
    p.add_argument("--reference", help=argparse.SUPPRESS)
    p.add_argument("--metrics", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.replot:
        out = Path(args.out)
        doc = json.loads((out / "results.json").read_text())
        write_results(out, doc["suite"], doc["rows"], doc.get("stability", []), doc["seconds"])
        return
    if not args.suite:
        fail("--suite FILE.json is required", 2)
    for tool in (args.capture, args.reference, args.metrics):
        if not tool or not os.access(tool, os.X_OK):
            fail(f"{tool}: not built (cmake --build the build folder first)", 2)
    bench(args, args)


if __name__ == "__main__":
    main()
