#!/usr/bin/env python3
"""CMO tests against the reference renderer (label accuracy; thresholds.json "cmo"):

    cmo_test.py TOOLS... --check nested|highlight|curved --out DIR --cache DIR

nested     mirror_hall.facing, screen space off: with cmo_bounces=2 (thresholds.json "with") the
           nested reflections between the two facing mirrors are closer to a reference rendered
           with enough bounces than with cmo_bounces=0, by at least min_gain_db on the mirrors.
highlight  mirror_hall.highlight_a and _b: the ball behind the camera, seen only in the mirror
           (only CMOs see it), carries the lamp's highlight; its brightest spot lies within
           max_offset_px of the reference's at both camera positions, and moves by at least
           min_motion_px between them, as in the reference (shading at the hit for the viewer).
curved     cornell_mirrors close views of the curved reflectors: with CMOs (the default chain)
           at least psnr_min on pixels below max_roughness, and at least min_gain_db over the
           chain without CMOs.
never_hurts  closed_room's views with one CMO added at each of never_hurts.positions: the
           mirror band against the converged reference loses at most max_loss_db to the room
           without it (issue 24: a CMO never makes a view worse).
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "bench"))
sys.path.insert(0, str(HERE.parent / "capture"))
import speculum_bench as bench  # noqa: E402
from accuracy_args import tool_parser  # noqa: E402
from stripes_test import load, without_planar_probes  # noqa: E402


def hall_without_planar(out):
    """mirror_hall without the planar probe on its right mirror (tools/scenes/halls.py): these
    checks are about what the CMO traces there (its self-reflections, the moving highlight), and
    the planar probe's mirrored image would take those pixels. Returns the scene file."""
    scene = bench.SOURCE / "assets" / "scenes" / "mirror_hall.gltf"
    return without_planar_probes(str(scene), str(out / "scene"))


def band_scores(tools, test, ref_dir, exposure, rough, max_roughness):
    cmd = [tools.metrics, "compare", "--test", str(test), "--ref", str(ref_dir / "reflection.0000.exr"),
           "--ref-mask", str(ref_dir / "reflective.0000.exr"), "--test-mask", str(test), "--scale", str(exposure),
           "--band-image", str(rough), "--bands", f"0,{max_roughness:g}"]
    cmd += bench.store.ref_error_args(ref_dir)  # a converged reference: its unconverged pixels are not scored
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        bench.fail(f"speculum-metrics failed: {r.stderr.strip()}", 1)
    return json.loads(r.stdout)["bands"][0]


def roughness(tools, view, size, out):
    d = out / f"{bench.view_name(view)}.roughness"
    d.mkdir(parents=True, exist_ok=True)
    cmd = [tools.capture, "--scene", str(bench.scene_file(view)), *bench.camera_args(view), "--size", size,
           "--warmup", "0", "--aov", "roughness", "--out", str(d)]
    if bench.run(cmd, d / "log.txt") != 0:
        bench.fail(f"roughness capture failed; see {d / 'log.txt'}", 1)
    return bench.last_frame(d, "roughness")


def reference(tools, view, size, settings, cache):
    ref_dir, _ = bench.render_reference(tools, view, size, settings, cache)
    return ref_dir, json.loads((ref_dir / "reference.json").read_text())["exposure"]


def run(tools, view, size, sets, out, name):
    suite = {"warmup": 3, "frames": 1}
    image, ms, _, _ = bench.capture(tools, view, size, sets, "reflection", suite, out / name)
    return image, ms


def nested(tools, rule, out, cache):
    view = {"scene": "mirror_hall", "camera": "facing", "file": hall_without_planar(out)}
    ref_dir, exposure = reference(tools, view, rule["size"], rule["reference"], cache)
    rough = roughness(tools, view, rule["size"], out)
    got = {}
    for label, sets in (("bounces", rule["with"]), ("no_bounces", rule["without"])):
        image, _ = run(tools, view, rule["size"], sets, out, f"nested.{label}")
        got[label] = band_scores(tools, image, ref_dir, exposure, rough, rule["max_roughness"])
    gain = got["bounces"]["psnr_db"] - got["no_bounces"]["psnr_db"]
    print(f"nested: mirrors {got['bounces']['psnr_db']:.2f} dB with CMO bounces, {got['no_bounces']['psnr_db']:.2f} "
          f"without ({got['bounces']['pixels']} pixels), gain {gain:+.2f} dB; must be >= {rule['min_gain_db']}")
    return gain >= rule["min_gain_db"]


def luminance(path, tmp):
    w, h, c = load(str(path), tmp)
    lum = [[0.2126 * c["R"][y][x] + 0.7152 * c["G"][y][x] + 0.0722 * c["B"][y][x] for x in range(w)] for y in range(h)]
    return w, h, c, lum


def ball_box(path, tmp):
    """The bounding box of the red ball's reflection in the reference (red over twice green)."""
    w, h, c, _ = luminance(path, tmp)
    pts = [(x, y) for y in range(h) for x in range(w) if c["R"][y][x] > 0.02 and c["R"][y][x] > 2.5 * c["G"][y][x]]
    if not pts:
        bench.fail(f"{path}: no red ball in the reference's reflection", 1)
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    return min(xs), min(ys), max(xs), max(ys)


def brightest(path, tmp, box):
    """(x, y) of the brightest 3x3 mean luminance inside box (the ball): its highlight."""
    w, h, _, lum = luminance(path, tmp)
    best, at = -1.0, (0, 0)
    for y in range(max(1, box[1]), min(h - 1, box[3] + 1)):
        for x in range(max(1, box[0]), min(w - 1, box[2] + 1)):
            v = sum(lum[y + j][x + i] for j in (-1, 0, 1) for i in (-1, 0, 1))
            if v > best:
                best, at = v, (x, y)
    return at


def highlight(tools, rule, out, cache):
    ok = True
    spots = {}
    hall = hall_without_planar(out)
    with tempfile.TemporaryDirectory() as tmp:
        for cam in ("highlight_a", "highlight_b"):
            view = {"scene": "mirror_hall", "camera": cam, "file": hall}
            ref_dir, _ = reference(tools, view, rule["size"], rule["reference"], cache)
            image, _ = run(tools, view, rule["size"], rule["with"], out, f"highlight.{cam}")
            box = ball_box(ref_dir / "reflection.0000.exr", tmp)
            ours, theirs = brightest(image, tmp, box), brightest(ref_dir / "reflection.0000.exr", tmp, box)
            off = ((ours[0] - theirs[0]) ** 2 + (ours[1] - theirs[1]) ** 2) ** 0.5
            print(f"highlight {cam}: ours at {ours}, the reference's at {theirs}: {off:.1f} px apart "
                  f"(at most {rule['max_offset_px']})")
            ok &= off <= rule["max_offset_px"]
            spots[cam] = (ours, theirs)
    a, b = spots["highlight_a"], spots["highlight_b"]
    move = [((a[i][0] - b[i][0]) ** 2 + (a[i][1] - b[i][1]) ** 2) ** 0.5 for i in (0, 1)]
    print(f"highlight: moves {move[0]:.1f} px in ours, {move[1]:.1f} px in the reference (at least "
          f"{rule['min_motion_px']})")
    return ok and move[0] >= rule["min_motion_px"] and move[1] >= rule["min_motion_px"]


def curved(tools, rule, out, cache):
    ok = True
    for cam in rule["views"]:
        view = {"scene": "cornell_mirrors", "camera": cam}
        ref_dir, exposure = reference(tools, view, rule["size"], rule["reference"], cache)
        rough = roughness(tools, view, rule["size"], out)
        s = {}
        for label, sets in (("cmos", rule["with"]), ("no_cmos", rule["without"])):
            image, _ = run(tools, view, rule["size"], sets, out, f"curved.{cam}.{label}")
            s[label] = band_scores(tools, image, ref_dir, exposure, rough, rule["max_roughness"])["psnr_db"]
        floor = rule["psnr_min"][cam]
        print(f"curved {cam}: {s['cmos']:.2f} dB with CMOs, {s['no_cmos']:.2f} without (roughness < "
              f"{rule['max_roughness']}); must be >= {floor} and gain >= {rule['min_gain_db']} dB")
        ok &= s["cmos"] >= floor and s["cmos"] - s["no_cmos"] >= rule["min_gain_db"]
    return ok


def with_cmos(scene, positions, out):
    """The scene without the CMOs it has, with one CMO node at each position (the placement
    tool's own glTF edit)."""
    sys.path.insert(0, str(bench.SOURCE / "modules" / "probes" / "tools"))
    from placement.edit import dump, edited_document, write_atomic
    src = bench.SOURCE / "assets" / "scenes" / f"{scene}.gltf"
    doc = json.loads(src.read_text())
    cmo = lambda i: doc["nodes"][i].get("extensions", {}).get("SPECULUM_reflection_probe", {}).get("kind") == "cmo"
    for sc in doc.get("scenes", []):
        sc["nodes"] = [i for i in sc.get("nodes", []) if not cmo(i)]
    cmos = [{"pos": p, "res": 128, "order": i, "radius": 1.0} for i, p in enumerate(positions)]
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"{scene}.cmo.gltf"
    write_atomic(path, dump(edited_document(doc, cmos, src.parent, out)))
    return path


def never_hurts(tools, rule, out, cache):
    """A CMO added anywhere in the closed room (above the chrome sphere standing on the glossy
    floor, at head height in the middle, low in a corner) never lowers a view's mirror-band PSNR
    against the converged reference by more than max_loss_db. The CMO node changes nothing the
    reference sees, so the room's own reference is the truth for every edited scene."""
    ok = True
    # The closed room, then each room of "more" (its own scene, views, positions and reference).
    for room in [rule] + [dict(rule, **r) for r in rule.get("more", [])]:
        ok &= never_hurts_room(tools, room, out, cache)
    return ok


def never_hurts_room(tools, rule, out, cache):
    ok = True
    scene = rule["scene"]
    bare = str(with_cmos(scene, [], out / "none"))  # the scene without its own CMOs
    edited = {label: str(with_cmos(scene, [pos], out / label)) for label, pos in rule["positions"].items()}
    for cam in rule["views"]:
        ref_dir, exposure = reference(tools, {"scene": scene, "camera": cam}, rule["size"], rule["reference"], cache)
        view = {"scene": scene, "camera": cam, "file": bare}
        image, _ = run(tools, view, rule["size"], [], out, f"never_hurts.{scene}.{cam}.none")
        base = bench.score(tools, image, ref_dir, "reflection", exposure, out / f"never_hurts.{scene}.{cam}.none.png")
        for label, pos in rule["positions"].items():
            one = {"scene": scene, "camera": cam, "file": edited[label]}
            image, _ = run(tools, one, rule["size"], [], out, f"never_hurts.{scene}.{cam}.{label}")
            got = bench.score(tools, image, ref_dir, "reflection", exposure, out / f"never_hurts.{scene}.{cam}.{label}.png")
            loss = base["mirror_psnr_db"] - got["mirror_psnr_db"]
            good = loss <= rule["max_loss_db"]
            print(f"never_hurts {scene}.{cam} CMO {label} at {pos}: mirror band {got['mirror_psnr_db']:.2f} dB, without "
                  f"{base['mirror_psnr_db']:.2f} dB ({-loss:+.2f} dB; at most {rule['max_loss_db']} dB lost)"
                  f"{'' if good else '  FAIL'}")
            ok &= good
    return ok


def main():
    p = tool_parser()
    p.add_argument("--check", choices=("nested", "highlight", "curved", "never_hurts"), required=True)
    p.add_argument("--cache", required=True)
    p.add_argument("--out", required=True)
    a = p.parse_args()
    rules = json.loads(Path(a.thresholds).read_text())["cmo"]
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rule = dict(rules[a.check])
    for k in ("size", "reference"):
        rule.setdefault(k, rules[k])
    ok = {"nested": nested, "highlight": highlight, "curved": curved, "never_hurts": never_hurts}[a.check](
        a, rule, out, Path(a.cache))
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
