#!/usr/bin/env python3
"""Planar probe tests against the converged reference (label accuracy; thresholds.json "planar"):

    planar_test.py TOOLS... --check floor|off_plane|cmo_floor|open_sky --out DIR --cache DIR

floor      mirror_floor (tests/accuracy/make_planar_scene.py: a chrome sphere standing on a sharp
           mirror floor in a sealed room) at every view of the rule: the floor's pixels (normal
           within 0.8 degrees of up) reach psnr_min against the converged reference with the
           scene's planar probe; the same without it is printed beside.
off_plane  the gallery (a chrome sphere, a torus, a concave mirror and four floor bands) with and
           without a planar probe on its sharp floor band, in the first frame (no reflection fed
           back yet): every reflective pixel off the floor's plane is the same, within max_abs_diff.
           Its ground is off on both sides (probes.planar_ground=0): rays that meet the floor from
           above read it by design, which `ground` tests against the reference.
cmo_floor  the scene without its planar probe, with and without a CMO above the sphere (issue 24
           part 3): the floor's pixels whose mirror ray meets the sphere (its reflected underside,
           computed from the scene's camera and sphere) are never worse with the CMO, by more than
           max_underside_loss_db, and the whole floor by more than max_loss_db.
open_sky   failure_cases (a sharp mirror floor under an open sky) with and without a planar probe
           on its floor: the floor reaches psnr_min with it and gains min_gain_db over without.
ground     closed_room's views with and without the planar probe's ground (probes.planar_ground):
           the mirror band gains min_gain_db[camera] with it.
"""
import json
import math
import struct
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "bench"))
sys.path.insert(0, str(HERE.parent / "capture"))
import speculum_bench as bench  # noqa: E402
from accuracy_args import tool_parser  # noqa: E402
from stripes_test import load, without_planar_probes  # noqa: E402

SCENE = "mirror_floor"
PLANAR_NODE = "reflection_probe.floor"
FLOOR_NY = 0.9999  # cos(0.8 degrees): the floor, not the sphere's top (under a pixel there)


def scenes(out):
    """The generated scene, and its variants: without the planar probe, and that with a CMO."""
    base = out / "scene"
    subprocess.run([sys.executable, str(HERE / "make_planar_scene.py"), str(base)], check=True)
    doc = json.loads((base / f"{SCENE}.gltf").read_text())
    for n in doc["nodes"]:
        if n.get("name") == PLANAR_NODE:
            del n["extensions"]
    (base / f"{SCENE}.no_planar.gltf").write_text(json.dumps(doc, indent=1))
    return {"planar": base / f"{SCENE}.gltf", "no_planar": base / f"{SCENE}.no_planar.gltf"}


def with_cmo(doc_path, pos, out):
    sys.path.insert(0, str(bench.SOURCE / "modules" / "probes" / "tools"))
    from placement.edit import dump, edited_document, write_atomic
    doc = json.loads(doc_path.read_text())
    cmos = [{"pos": pos, "res": 128, "order": 0, "radius": 1.0}]
    path = doc_path.parent / f"{SCENE}.cmo.gltf"
    write_atomic(path, dump(edited_document(doc, cmos, doc_path.parent, doc_path.parent)))
    return path


def floor_band(tools, view, size, out):
    """A one-channel image of the normal's y, which splits the scores into the floor and the rest."""
    d = out / f"{view['camera']}.normal"
    d.mkdir(parents=True, exist_ok=True)
    cmd = [tools.capture, "--scene", str(view["file"]), "--camera", view["camera"], "--size", size,
           "--warmup", "0", "--aov", "normal", "--out", str(d)]
    if bench.run(cmd, d / "log.txt") != 0:
        bench.fail(f"normal capture failed; see {d / 'log.txt'}", 1)
    band = d / "normal_y.exr"
    subprocess.run(["oiiotool", str(bench.last_frame(d, "normal")), "--ch", "G", "-o", str(band)], check=True)
    return band


def underside_band(scene, cam, size, floor, out):
    """The floor band (`floor`, the normal's y) kept only where the pixel's mirror ray, reflected in
    the floor's plane y = 0, meets the sphere: the camera and the sphere (its nodes' translation,
    the radius from its mesh's bounds) are read from the scene, pixel centres as the engine's."""
    doc = json.loads(Path(scene).read_text())
    node = next(n for n in doc["nodes"] if n.get("name") == cam and "camera" in n)
    yfov = doc["cameras"][node["camera"]]["perspective"]["yfov"]
    sphere = next(n for n in doc["nodes"] if n.get("name", "").startswith("sphere."))
    centre = sphere["translation"]
    radius = max(doc["accessors"][doc["meshes"][sphere["mesh"]]["primitives"][0]["attributes"]["POSITION"]]["max"])
    x, y, z, w = node["rotation"]
    rot = lambda v: [  # the unit quaternion (x, y, z, w) applied to v
        (1 - 2 * (y * y + z * z)) * v[0] + 2 * (x * y - z * w) * v[1] + 2 * (x * z + y * w) * v[2],
        2 * (x * y + z * w) * v[0] + (1 - 2 * (x * x + z * z)) * v[1] + 2 * (y * z - x * w) * v[2],
        2 * (x * z - y * w) * v[0] + 2 * (y * z + x * w) * v[1] + (1 - 2 * (x * x + y * y)) * v[2]]
    fwd, right, up = rot([0, 0, -1]), rot([1, 0, 0]), rot([0, 1, 0])
    eye = node["translation"]
    W, H = (int(v) for v in size.split("x"))
    th = math.tan(0.5 * yfov)
    rows = []
    for py in range(H):
        row = []
        for px in range(W):
            sx, sy = (2 * (px + 0.5) / W - 1) * th * W / H, (1 - 2 * (py + 0.5) / H) * th
            d = [f + sx * r + sy * u for f, r, u in zip(fwd, right, up)]
            hit = 0.0
            if d[1] < 0:
                t = -eye[1] / d[1]
                oc = [e + t * dv - c for e, dv, c in zip(eye, d, centre)]
                rd = [d[0], -d[1], d[2]]
                ln = math.sqrt(sum(v * v for v in rd))
                b = sum(o * v for o, v in zip(oc, rd)) / ln
                disc = b * b - (sum(o * o for o in oc) - radius * radius)
                hit = 1.0 if disc > 0 and -b - math.sqrt(disc) > 0 else 0.0
            row.append(hit)
        rows.append(row)
    pfm = out / f"{cam}.underside.pfm"
    with open(pfm, "wb") as f:  # a one-channel float map, bottom row first
        f.write(b"Pf\n%d %d\n-1.0\n" % (W, H))
        for row in reversed(rows):
            f.write(struct.pack(f"<{W}f", *row))
    band = out / f"{cam}.underside.exr"
    subprocess.run(["oiiotool", str(floor), str(pfm), "--mul", "-o", str(band)], check=True)
    return band


def floor_psnr(tools, image, ref_dir, exposure, band):
    cmd = [tools.metrics, "compare", "--test", str(image), "--ref", str(ref_dir / "reflection.0000.exr"),
           "--ref-mask", str(ref_dir / "reflective.0000.exr"), "--test-mask", str(image), "--scale", str(exposure),
           "--band-image", str(band), "--bands", f"{FLOOR_NY},2", *bench.store.ref_error_args(ref_dir)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        bench.fail(f"speculum-metrics failed: {r.stderr.strip()}", 1)
    return json.loads(r.stdout)["bands"][0]


def capture(tools, view, size, out, warmup=3, sets=()):
    image, _, _, _ = bench.capture(tools, view, size, list(sets), "reflection", {"warmup": warmup, "frames": 1}, out)
    return image


def reference(tools, cam, rule, cache):
    ref_dir, _ = bench.render_reference(tools, {"scene": SCENE, "camera": cam}, rule["size"], rule["reference"], cache)
    return ref_dir, json.loads((ref_dir / "reference.json").read_text())["exposure"]


def floor(tools, rule, out, cache):
    files = scenes(out)
    ok = True
    for cam in rule["views"]:
        ref_dir, exposure = reference(tools, cam, rule, cache)
        band = floor_band(tools, {"file": files["planar"], "camera": cam}, rule["size"], out)
        got = {}
        for label, f in files.items():
            image = capture(tools, {"scene": SCENE, "camera": cam, "file": str(f)}, rule["size"], out / f"{cam}.{label}")
            got[label] = floor_psnr(tools, image, ref_dir, exposure, band)
        good = got["planar"]["psnr_db"] >= rule["psnr_min"]
        print(f"floor {cam}: {got['planar']['psnr_db']:.2f} dB with the planar probe, {got['no_planar']['psnr_db']:.2f} "
              f"without ({got['planar']['pixels']} floor pixels); must be >= {rule['psnr_min']}"
              f"{'' if good else '  FAIL'}")
        ok &= good
    return ok


def gallery_with_planar(out, rule):
    """The gallery without its planar probe, and with one planar probe node on its sharp floor band."""
    d = out / "gallery"
    without = Path(without_planar_probes(str(bench.SOURCE / "assets" / "scenes" / "gallery.gltf"), str(d)))
    doc = json.loads(without.read_text())
    p = rule["gallery_planar"]
    doc["nodes"].append({"name": "planar.band_0", "translation": p["origin"],
                         "extensions": {"SPECULUM_reflection_probe": {"kind": "planar", "extents": p["extents"]}}})
    doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    (d / "gallery.planar.gltf").write_text(json.dumps(doc, indent=1))
    return {"planar": d / "gallery.planar.gltf", "no_planar": without}


def off_plane(tools, rule, out, cache):
    files = gallery_with_planar(out, rule)
    ok = True
    for cam in rule["gallery_views"]:
        tmp = out / f"{cam}.tmp"
        tmp.mkdir(parents=True, exist_ok=True)
        band = floor_band(tools, {"file": files["planar"], "camera": cam}, rule["size"], out)
        _, _, nb = load(str(band), str(tmp))
        ny = next(iter(nb.values()))
        imgs = {}
        for label, f in files.items():
            # The planar probe's ground off on both sides: it changes off-plane pixels by design
            # (a ray that meets the floor from above reads it; `ground` tests that it helps).
            image = capture(tools, {"scene": "gallery", "camera": cam, "file": str(f)}, rule["size"],
                            out / f"{cam}.{label}", warmup=0, sets=["probes.planar_ground=0"])
            w, h, imgs[label] = load(str(image), str(tmp))
        a, b = ([d[c] for c in ("R", "G", "B")] for d in (imgs["planar"], imgs["no_planar"]))
        worst, off, on, changed = 0.0, 0, 0, 0
        for y in range(h):
            for x in range(w):
                pa, pb = [ch[y][x] for ch in a], [ch[y][x] for ch in b]
                if ny[y][x] >= 0.99:  # on (or within 8 degrees of) the floor's plane
                    on += 1
                    changed += pa != pb
                    continue
                if any(pa) or any(pb):
                    off += 1
                    worst = max(worst, max(abs(u - v) for u, v in zip(pa, pb)))
        # It must also have done something on the plane, or the test could not fail.
        good = worst <= rule["max_abs_diff"] and off > 0 and changed > 0
        print(f"off_plane gallery.{cam}: {off} reflective pixels off the plane differ by at most {worst:.3g} "
              f"(limit {rule['max_abs_diff']}); {changed} of {on} on it changed{'' if good else '  FAIL'}")
        ok &= good
    return ok


def open_sky(tools, rule, out, cache):
    """failure_cases (a sharp mirror floor under an open sky) with and without a planar probe on
    its floor, against the scene's converged reference: the mirrored view's sky must be the
    reflected sky (the oblique projection once flipped it to the environment's ground)."""
    d = out / "failure_cases"
    d.mkdir(parents=True, exist_ok=True)
    # The scene ships with planar probes on its mirrors (tools/scenes/stages.py): without them is
    # the scene with those probes taken off, with them the floor's probe of this rule alone.
    shipped = bench.SOURCE / "assets" / "scenes" / "failure_cases.gltf"
    without = Path(without_planar_probes(str(shipped), str(d)))
    doc = json.loads(without.read_text())
    doc["nodes"].append({"name": "planar.floor", "translation": rule["origin"],
                         "extensions": {"SPECULUM_reflection_probe": {"kind": "planar", "extents": rule["extents"]}}})
    doc["scenes"][doc.get("scene", 0)]["nodes"].append(len(doc["nodes"]) - 1)
    # Already edited for its folder: the buffers', images' and environment's references hold.
    planar = d / "failure_cases.planar.gltf"
    planar.write_text(json.dumps(doc, indent=1))
    ok = True
    for cam in rule["views"]:
        ref_dir, _ = bench.render_reference(tools, {"scene": "failure_cases", "camera": cam}, rule["size"],
                                            rule["reference"], cache)
        exposure = json.loads((ref_dir / "reference.json").read_text())["exposure"]
        band = floor_band(tools, {"file": str(planar), "camera": cam}, rule["size"], out / cam)
        got = {}
        for label, f in (("planar", planar), ("no_planar", without)):
            image = capture(tools, {"scene": "failure_cases", "camera": cam, "file": str(f)}, rule["size"],
                            out / f"{cam}.{label}")
            got[label] = floor_psnr(tools, image, ref_dir, exposure, band)
        gain = got["planar"]["psnr_db"] - got["no_planar"]["psnr_db"]
        good = got["planar"]["psnr_db"] >= rule["psnr_min"] and gain >= rule["min_gain_db"]
        print(f"open_sky failure_cases.{cam}: floor {got['planar']['psnr_db']:.2f} dB with a planar probe, "
              f"{got['no_planar']['psnr_db']:.2f} without ({got['planar']['pixels']} floor pixels, {gain:+.2f} dB); "
              f"must be >= {rule['psnr_min']} and gain >= {rule['min_gain_db']} dB{'' if good else '  FAIL'}")
        ok &= good
    return ok


def cmo_floor(tools, rule, out, cache):
    files = scenes(out)
    edited = with_cmo(files["no_planar"], rule["cmo"], out)
    ok = True
    for cam in rule["views"]:
        ref_dir, exposure = reference(tools, cam, rule, cache)
        band = floor_band(tools, {"file": files["planar"], "camera": cam}, rule["size"], out)
        under = underside_band(files["planar"], cam, rule["size"], band, out)
        got, part = {}, {}
        for label, f in (("none", files["no_planar"]), ("cmo", edited)):
            image = capture(tools, {"scene": SCENE, "camera": cam, "file": str(f)}, rule["size"], out / f"{cam}.{label}")
            got[label] = floor_psnr(tools, image, ref_dir, exposure, band)["psnr_db"]
            part[label] = floor_psnr(tools, image, ref_dir, exposure, under)
        for what, scores, limit in (("floor", got, rule["max_loss_db"]),
                                    ("underside", {k: v["psnr_db"] for k, v in part.items()}, rule["max_underside_loss_db"])):
            loss = scores["none"] - scores["cmo"]
            # It must score pixels, or the test could not fail.
            good = loss <= limit and (what == "floor" or part["cmo"]["pixels"] > 0)
            pixels = f" on {part['cmo']['pixels']} px" if what == "underside" else ""
            print(f"cmo_floor {cam}: {what} {scores['cmo']:.2f} dB{pixels} with a CMO at {rule['cmo']}, {scores['none']:.2f} "
                  f"without ({-loss:+.2f} dB; at most {limit} dB lost){'' if good else '  FAIL'}")
            ok &= good
    return ok


def ground(tools, rule, out, cache):
    """closed_room (a chrome sphere, a torus and a copper sphere standing on a glossy floor with a
    planar probe) with and without the planar probe's ground, against the converged references:
    the rays that meet the floor under those objects read it there instead of the box probe's
    capture, which sees the objects in its place. The mirror band must gain min_gain_db[camera]."""
    ok = True
    for cam in rule["views"]:
        view = {"scene": "closed_room", "camera": cam}
        ref_dir, _ = bench.render_reference(tools, view, rule["size"], rule["reference"], cache)
        exposure = json.loads((ref_dir / "reference.json").read_text())["exposure"]
        got = {}
        for label, sets in (("ground", []), ("no_ground", ["probes.planar_ground=0"])):
            image = capture(tools, view, rule["size"], out / f"{cam}.{label}", sets=sets)
            got[label] = bench.score(tools, image, ref_dir, "reflection", exposure,
                                     out / f"{cam}.{label}.heatmap.png")["mirror_psnr_db"]
        gain = got["ground"] - got["no_ground"]
        limit = rule["min_gain_db"][cam]
        good = gain >= limit
        print(f"ground closed_room.{cam}: mirror band {got['ground']:.2f} dB with the ground, {got['no_ground']:.2f} "
              f"without ({gain:+.2f} dB; must gain >= {limit}){'' if good else '  FAIL'}")
        ok &= good
    return ok


def main():
    p = tool_parser()
    p.add_argument("--check", choices=("floor", "off_plane", "cmo_floor", "open_sky", "ground"), required=True)
    p.add_argument("--cache", required=True)
    p.add_argument("--out", required=True)
    a = p.parse_args()
    rules = json.loads(Path(a.thresholds).read_text())["planar"]
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rule = dict(rules[a.check])
    for k in ("size", "reference", "views"):
        rule.setdefault(k, rules[k])
    ok = {"floor": floor, "off_plane": off_plane, "cmo_floor": cmo_floor, "open_sky": open_sky, "ground": ground}[a.check](
        a, rule, out, Path(a.cache))
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
