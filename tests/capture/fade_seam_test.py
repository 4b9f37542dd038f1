#!/usr/bin/env python3
"""The roughness cutoff's fade shows no seam (issue 23, "work follows need"): screen space serves
a pixel up to its screen-space roughness limit (reflections.max_roughness 0.6, the material's
maxScreenSpaceRoughness 0.6) and fades to the fallback over the last 0.1 of roughness; the tile
classification decides per tile which passes run there, so a seam could appear where a tile's
class changes. The scene: a metal floor of 24 strips whose roughness ramps from 0.36 to 0.82 in
steps of 0.02, below a wall of black and white horizontal bands that screen space sees and the sky
fallback does not (the change across the fade is large). Per strip the mean reflection luminance;
across the fade's window (roughness 0.46 to 0.66) no single strip-to-strip step may carry more
than 35% of the window's total change (a hard cut puts nearly all of it in one step; the 0.1 fade
spreads it over five: measured 21% with it and 49% with the fade cut to 0.001), and the window must show a change at all (else the scene tests nothing).
With reflections.tiles on and off.

    fade_seam_test.py CAPTURE OUTDIR
"""
import os, subprocess, sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
from stripes_test import load  # noqa: E402
from scenes.document import Gltf  # noqa: E402
from scenes.materials import mirror_ext  # noqa: E402
from scenes.mesh import MeshData  # noqa: E402

STRIPS, R0, DR = 24, 0.36, 0.02
WINDOW = (0.46, 0.66)
MAX_SHARE = 0.35


def make_scene(out):
    g = Gltf("roughness_ramp", folder=out)
    width = 0.2
    for k in range(STRIPS):
        g.material("floor.%d" % k, (0.9, 0.9, 0.9), 1.0, R0 + DR * k, reflections=mirror_ext())
    g.material("wall.white", (0.9, 0.9, 0.9), 0.0, 0.9)
    g.material("wall.black", (0.02, 0.02, 0.02), 0.0, 0.9)
    for k in range(STRIPS):
        m = MeshData()
        m.quad((-STRIPS * width / 2 + k * width, 0.0, 1.0), (width, 0, 0), (0, 0, -3.0), facing=(0, 1, 0))
        g.object("strip.%d" % k, m, "floor.%d" % k)
    # Horizontal bands: every strip sees the same pattern, so strips differ by roughness only.
    for k in range(10):
        m = MeshData()
        m.quad((-4.0, k * 0.25, -2.0), (8.0, 0, 0), (0, 0.25, 0), facing=(0, 0, 1))
        g.object("wall.%d" % k, m, "wall.white" if k % 2 == 0 else "wall.black")
    for mat in g.doc["materials"]:
        if mat["name"].startswith("wall."):
            mat.setdefault("extensions", {})["KHR_materials_unlit"] = {}
    g.used.add("KHR_materials_unlit")
    g.camera("main", (0.0, 1.0, 2.2), (0.0, 0.1, -1.2))
    g.write({"exposure": 1.0})
    return os.path.join(out, "roughness_ramp.gltf")


def main():
    exe, out = sys.argv[1:3]
    os.makedirs(out, exist_ok=True)
    scene = make_scene(out)
    failures = []
    for tiles in ("true", "false"):
        d = os.path.join(out, "tiles_" + tiles)
        subprocess.run([exe, "--scene", scene, "--camera", "main", "--size", "480x270", "--warmup", "3", "--aov",
                        "reflection,roughness", "--set", "reflections.tiles=" + tiles, "--out", d],
                       check=True, stdout=subprocess.DEVNULL)
        w, h, refl = load(os.path.join(d, "reflection.0000.exr"), d)
        _, _, rough = load(os.path.join(d, "roughness.0000.exr"), d)
        rch = next(iter(rough.values()))
        sums = [[0.0, 0] for _ in range(STRIPS)]
        for y in range(h):
            for x in range(w):
                k = round((rch[y][x] - R0) / DR)
                if 0 <= k < STRIPS and abs(rch[y][x] - (R0 + DR * k)) < 0.004:
                    lum = 0.2126 * refl["R"][y][x] + 0.7152 * refl["G"][y][x] + 0.0722 * refl["B"][y][x]
                    sums[k][0] += lum
                    sums[k][1] += 1
        if any(n < 50 for _, n in sums):
            sys.exit("a strip covers fewer than 50 pixels: the camera no longer sees the ramp")
        means = [s / n for s, n in sums]
        steps = [(R0 + DR * k, abs(means[k + 1] - means[k])) for k in range(STRIPS - 1)]
        window = [s for r, s in steps if WINDOW[0] <= r < WINDOW[1]]
        total = sum(window)
        print("tiles=%s: strip means %s" % (tiles, " ".join("%.3f" % m for m in means)))
        print("  steps in the fade window %s, total %.4f, largest share %.2f (bound %.2f)" %
              (" ".join("%.4f" % s for s in window), total, max(window) / max(total, 1e-9), MAX_SHARE))
        if total < 0.02:
            failures.append("tiles=%s: no change across the fade window (%.4f): the scene tests nothing" % (tiles, total))
        elif max(window) > MAX_SHARE * total:
            failures.append("tiles=%s: one step carries %.0f%% of the fade's change: a seam" %
                            (tiles, 100 * max(window) / total))
    if failures:
        sys.exit("; ".join(failures))
    print("no seam at the screen-space roughness cutoff")


if __name__ == "__main__":
    main()
