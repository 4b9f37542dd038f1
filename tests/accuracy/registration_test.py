#!/usr/bin/env python3
"""Sub-pixel registration of reflected edges (issue 24 part 4; label accuracy; thresholds.json
"registration"):

    registration_test.py TOOLS... --out DIR --cache DIR

A reflected edge must land where the converged reference puts it within half a pixel. Along each
row of the reflection AOV, every strong step of the reference's luminance (a reflected edge:
more than `min_step` between neighbours, on reflective pixels) is placed at sub-pixel precision
(where the luminance crosses the middle of the step, linearly interpolated); the engine's
crossing of the same level nearest to it (within `search_px`) is its match. The median of the
absolute offsets must be at most `max_median_px`; the share matched is printed beside it.

Cases (rule "cases"): the flat mirror floor of mirror_floor (tests/accuracy/make_planar_scene.py)
through screen space (its planar probe removed: the hit refinement and the colour pyramid's
level-0 sampling), through its planar probe at the view's full height, and the curved chrome
sphere of cornell_mirrors.sphere_close through its CMOs (the CMO hit refinement).
"""
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "bench"))
sys.path.insert(0, str(HERE.parent / "capture"))
import speculum_bench as bench  # noqa: E402
from accuracy_args import tool_parser  # noqa: E402
from stripes_test import load  # noqa: E402


def luminance(img, w, h, exposure):
    r, g, b = img["R"], img["G"], img["B"]
    return [[min(max(exposure * (0.2126 * r[y][x] + 0.7152 * g[y][x] + 0.0722 * b[y][x]), 0.0), 1.0) ** (1 / 2.2)
             for x in range(w)] for y in range(h)]


def crossings(row, level, x0, x1):
    """Sub-pixel x positions (pixel centres at x + 0.5) where row crosses `level` in [x0, x1)."""
    out = []
    for x in range(max(x0, 0), min(x1, len(row) - 1)):
        a, b = row[x] - level, row[x + 1] - level
        if a == 0.0 or (a < 0.0) != (b < 0.0):
            out.append(x + 0.5 + (a / (a - b) if a != b else 0.0))
    return out


def offsets(test, ref, mask, rule):
    """(offsets of the matched edges, edges found in the reference)."""
    found, got = 0, []
    s = rule["search_px"]
    for y, (rt, rr, rm) in enumerate(zip(test, ref, mask)):
        for x in range(len(rr) - 1):
            if not (rm[x] and rm[x + 1]) or abs(rr[x + 1] - rr[x]) < rule["min_step"]:
                continue
            # A step, not a ramp: its neighbours on either side are flat beside it.
            if x >= 1 and x + 2 < len(rr) and (abs(rr[x] - rr[x - 1]) > 0.5 * abs(rr[x + 1] - rr[x]) or
                                               abs(rr[x + 2] - rr[x + 1]) > 0.5 * abs(rr[x + 1] - rr[x])):
                continue
            found += 1
            level = 0.5 * (rr[x] + rr[x + 1])
            want = crossings(rr, level, x, x + 1)[0]
            cand = crossings(rt, level, x - s, x + s + 1)
            if cand:
                got.append(min((c - want for c in cand), key=abs))
    return got, found


def case_images(tools, case, out, cache, size):
    view = {"scene": case["scene"], "camera": case["camera"]}
    if "edit" in case:
        subprocess.run([sys.executable, str(HERE / "make_planar_scene.py"), str(out / "scene")], check=True,
                       stdout=subprocess.DEVNULL)
        doc = json.loads((out / "scene" / f"{case['scene']}.gltf").read_text())
        for n in doc["nodes"]:
            ext = n.get("extensions", {}).get("SPECULUM_reflection_probe")
            if ext and ext.get("kind") == "planar":
                if case["edit"] == "no_planar":
                    del n["extensions"]
                else:
                    ext["resolution"] = int(size.split("x")[1])
        f = out / "scene" / f"{case['scene']}.{case['name']}.gltf"
        f.write_text(json.dumps(doc))
        view["file"] = str(f)
    ref_dir, _ = bench.render_reference(tools, {"scene": case["scene"], "camera": case["camera"]}, size,
                                        {"converged": True, "bounces": case["bounces"]}, cache)
    exposure = json.loads((ref_dir / "reference.json").read_text())["exposure"]
    image, _, _, _ = bench.capture(tools, view, size, [], "reflection", {"warmup": 3, "frames": 1}, out / case["name"])
    return image, ref_dir, exposure


def main():
    p = tool_parser()
    p.add_argument("--cache", required=True)
    p.add_argument("--out", required=True)
    a = p.parse_args()
    rule = json.loads(Path(a.thresholds).read_text())["registration"]
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    ok = True
    for case in rule["cases"]:
        image, ref_dir, exposure = case_images(a, case, out, Path(a.cache), rule["size"])
        w, h, t = load(str(image), str(out))
        _, _, r = load(str(ref_dir / "reflection.0000.exr"), str(out))
        _, _, m = load(str(ref_dir / "reflective.0000.exr"), str(out))
        _, _, rough = load(str(ref_dir / "roughness.0000.exr"), str(out))
        mc, rc = next(iter(m.values())), next(iter(rough.values()))
        mask = [[mc[y][x] > 0.5 and rc[y][x] < 0.3 for x in range(w)] for y in range(h)]
        got, found = offsets(luminance(t, w, h, exposure), luminance(r, w, h, exposure), mask, rule)
        med = sorted(abs(o) for o in got)[len(got) // 2] if got else float("inf")
        limit = case.get("max_median_px", rule["max_median_px"])
        good = med <= limit and len(got) >= rule["min_edges"]
        print(f"registration {case['name']}: {len(got)} of {found} reflected edges matched, median offset "
              f"{med:.2f} px (mean signed {sum(got) / max(len(got), 1):+.2f}); must be <= {limit} px"
              f"{'' if good else '  FAIL'}")
        ok &= good
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
