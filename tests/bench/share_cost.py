#!/usr/bin/env python3
"""Cost against the reflective share (issue 23, "work follows need"): the same view twice, once
with every material reflective and once with only a few materials reflective, chosen so that
about `--share` of the pixels reflect (every other material gets SPECULUM_reflections mode
"off"), timed back to back, alternating, with reflections.tiles on and off.

    share_cost.py [--build build] [--scene assets/scenes/gallery.gltf] [--camera main]
                  [--size 960x540] [--share 0.10] [--rounds 3] [--frames 5]

Prints the chosen materials, each variant's measured share (pixels whose method weights are not
zero, from the method AOV), a markdown table of the module's ms (the sum of the reflections.*
passes' GPU medians; median over rounds) and the frame's, and each reflections.* pass's ms per
variant (pyramid levels summed), so that what does not follow the share shows. Timing only,
never an assertion."""
import argparse, copy, json, os, statistics, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(ROOT, "tests", "capture"))
sys.path.insert(0, os.path.join(ROOT, "modules", "probes", "tools"))
from stripes_test import load  # uncompressed-EXR reader
from placement.edit import edited_document


def variant(doc, scene_dir, out_dir, name, keep):
    """The scene with only the materials in `keep` reflective (None: every material)."""
    d = copy.deepcopy(doc)
    for i, m in enumerate(d.get("materials", [])):
        ext = m.setdefault("extensions", {}).setdefault("SPECULUM_reflections", {})
        if keep is None:
            ext.setdefault("mode", "screen_space")
            if ext["mode"] == "off":
                ext["mode"] = "screen_space"
        elif i not in keep:
            ext.clear()
            ext["mode"] = "off"
    d = edited_document(d, [], scene_dir, os.path.abspath(out_dir))
    path = os.path.join(out_dir, name + ".gltf")
    json.dump(d, open(path, "w"), indent=1)
    return path


def capture(a, scene, size, frames, out, sets=(), aov="color"):
    cmd = [os.path.join(a.build, "tools", "capture", "speculum-capture"), "--scene", scene, "--camera", a.camera,
           "--size", size, "--warmup", "2", "--frames", str(frames), "--aov", aov, "--out", out]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return json.load(open(os.path.join(out, "timings.json")))


def share(a, scene, out):
    capture(a, scene, "320x180", 1, out, aov="method")
    w, h, ch = load(os.path.join(out, "method.0000.exr"), out)
    lit = sum(1 for y in range(h) for x in range(w) if ch["R"][y][x] + ch["G"][y][x] + ch["B"][y][x] + ch["A"][y][x] > 0)
    return lit / (w * h)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--scene", default="assets/scenes/gallery.gltf")
    ap.add_argument("--camera", default="main")
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--share", type=float, default=0.10)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--frames", type=int, default=5)
    a = ap.parse_args()
    doc = json.load(open(a.scene))
    scene_dir = os.path.dirname(os.path.abspath(a.scene))
    with tempfile.TemporaryDirectory() as tmp:
        full = variant(doc, scene_dir, tmp, "all", None)
        # Each material's own share, then the set closest to the target, smallest first.
        shares = []
        for i, m in enumerate(doc.get("materials", [])):
            s = share(a, variant(doc, scene_dir, tmp, "m%d" % i, {i}), os.path.join(tmp, "s%d" % i))
            print("[share] material %d %s: %.1f%%" % (i, m.get("name", ""), 100 * s), file=sys.stderr, flush=True)
            if s > 0:
                shares.append((s, i))
        keep, total = set(), 0.0
        for s, i in sorted(shares):
            if abs(total + s - a.share) < abs(total - a.share):
                keep.add(i)
                total += s
        part = variant(doc, scene_dir, tmp, "part", keep)
        measured = {"all": share(a, full, os.path.join(tmp, "sa")), "part": share(a, part, os.path.join(tmp, "sp"))}
        names = [doc["materials"][i].get("name", str(i)) for i in sorted(keep)]
        print("reflective materials of the partial variant: %s" % ", ".join(names))
        runs, passes = {}, {}
        for r in range(a.rounds):
            for tiles in ("true", "false"):
                for name, path in (("all", full), ("part", part)):
                    print("[share] round %d/%d tiles=%s %s" % (r + 1, a.rounds, tiles, name), file=sys.stderr, flush=True)
                    t = capture(a, path, a.size, a.frames, os.path.join(tmp, "t"), ["reflections.tiles=" + tiles])
                    module = sum(p["median_ms"] for p in t["passes"] if p["name"].startswith("reflections."))
                    runs.setdefault((tiles, name), []).append((module, t["frame"]["median_ms"]))
                    for p in t["passes"]:
                        stem, _, last = p["name"].rpartition(".")
                        key = stem if last.isdigit() else p["name"]  # pyramid levels summed
                        if key.startswith("reflections."):
                            got = passes.setdefault((tiles, name), {}).setdefault(key, {})
                            got[r] = got.get(r, 0.0) + p["median_ms"]
        print("\n%s/%s %s, %d rounds alternating, load average %.2f\n" % (os.path.basename(a.scene), a.camera, a.size,
                                                                     a.rounds, os.getloadavg()[0]))
        print("| reflections.tiles | variant | reflective share | module ms | frame ms | module / all's |")
        print("|---|---|---|---|---|---|")
        for tiles in ("true", "false"):
            base = statistics.median(m for m, _ in runs[(tiles, "all")])
            for name in ("all", "part"):
                m = statistics.median(x for x, _ in runs[(tiles, name)])
                f = statistics.median(x for _, x in runs[(tiles, name)])
                print("| %s | %s | %.1f%% | %.1f | %.1f | %.2f |" % (tiles, name, 100 * measured[name], m, f, m / base))
        columns = [(t, n) for t in ("true", "false") for n in ("all", "part")]
        print("\n| pass (median ms) | " + " | ".join("tiles=%s %s" % c for c in columns) + " |")
        print("|---" * (len(columns) + 1) + "|")
        names = sorted({k for c in columns for k in passes.get(c, {})})
        for key in names:
            cells = []
            for c in columns:
                v = passes.get(c, {}).get(key)
                cells.append("%.1f" % statistics.median(v.values()) if v else "-")
            print("| %s | %s |" % (key, " | ".join(cells)))


if __name__ == "__main__":
    main()
