#!/usr/bin/env python3
"""Where a view's mirror-band error comes from (issue 24): the share of its squared error by the
method that answered each pixel, and for screen-space pixels by what the hit landed on.

    error_sources.py --capture BIN --view SCENE.CAMERA [--size WxH] [--bounces N] [--scene FILE] [--set KEY=VALUE]... [--out DIR] [--blocks N]

It captures the view at its converged reference's size (assets/references, tests/reference/README.md;
`--size` picks one where the view has several, by default the smallest; `--bounces` its depth, by
default the bounce-converged 4 where the view has it, else 2)
with the reflection, method and hit AOVs after 8 warm-up frames, and scores the mirror band as
the bench does (reflective in the reference, the reference's reflection roughness below 0.3,
converged pixels only, as speculum-metrics cuts them: the reference's standard error, already in
display units, at most the entry's max_reference_error; clamped after the scene's exposure). Classes: the method whose weight is above one
half (`ssr`, `cmo`, `probe` for local and planar probes, `env` for the sky, else `mix`), and for
`ssr` the surface at the hit pixel: `hit-mirror` (reflective, roughness below 0.3: a mirror seen in
a mirror), `hit-glossy` (reflective, rougher), `hit-diffuse`, each with its level (as below). A second table splits the method by
reflection roughness in tenths, with the level of our reflection against the reference's (sum of
ours over sum of theirs: a bias shows as a level far from 1). The N 32x30 blocks with the most
error close the tables. The first line also gives the rough band's PSNR (a change made for the
mirror band must not cost it). This is how the mirror hits' 72% of cornell_mirrors.main's error was found
(modules/reflections/MEASUREMENTS.md)."""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parents[1]
sys.path.insert(0, str(HERE.parent / "capture"))
from stripes_test import load  # noqa: E402
sys.path.insert(0, str(HERE.parent / "reference"))
import store  # noqa: E402

MIRROR = 0.3


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--capture", required=True)
    ap.add_argument("--view", required=True, help="SCENE.CAMERA with a converged reference")
    ap.add_argument("--scene", help="the scene file to capture (default assets/scenes/SCENE.gltf): a variant of the "
                    "view's scene, say with other probes, scored against the same reference")
    ap.add_argument("--size", help="WxH: the converged reference's size, where the view has several")
    ap.add_argument("--bounces", type=int, help="the reference's bounces (default 4 where the view has it, else 2)")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--out")
    ap.add_argument("--blocks", type=int, default=6)
    a = ap.parse_args()
    scene, camera = a.view.split(".", 1)
    def entries(bounces):
        return sorted((SOURCE / "assets" / "references").glob(f"{scene}.{camera}.{a.size or '*'}.b{bounces}"),
                      key=lambda d: int(d.name.split(".")[-2].split("x")[0]))
    refs = entries(a.bounces) if a.bounces else (entries(4) or entries(2))
    if not refs:
        sys.exit(f"error_sources.py: no converged reference for {a.view}{' at ' + a.size if a.size else ''}"
                 f"{f' with {a.bounces} bounces' if a.bounces else ''} in assets/references")
    ref_dir = refs[0]
    info = json.loads((ref_dir / "reference.json").read_text())
    w, h, scale = info["width"], info["height"], info["exposure"]
    cut = store.max_reference_error(ref_dir) or 0.01  # speculum-metrics' default, kMaxReferenceError
    out = Path(a.out or tempfile.mkdtemp(prefix="error-sources-"))
    cmd = [a.capture, "--scene", a.scene or str(SOURCE / "assets" / "scenes" / f"{scene}.gltf"), "--camera", camera,
           "--size", f"{w}x{h}", "--warmup", "8", "--aov", "reflection,method,hit", "--out", str(out)]
    for kv in a.set:
        cmd += ["--set", kv]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"error_sources.py: capture failed ({r.returncode}): {r.stderr.strip()[-400:]}")
    with tempfile.TemporaryDirectory() as tmp:
        T, M, H = (load(str(out / f"{n}.0000.exr"), tmp)[2] for n in ("reflection", "method", "hit"))
        R, K, E, G = (load(str(ref_dir / f"{n}.0000.exr"), tmp)[2]
                      for n in ("reflection", "reflective", "stderror", "roughness"))
    first = lambda img: img[next(iter(img))]
    # At half resolution the hit AOV is the trace's (half) size; its hits are in full pixels.
    hitShift = 1 if len(H["R"]) < h else 0
    rough, refl, err = first(G), first(K), first(E)
    clamp = lambda v: min(max(v * scale, 0.0), 1.0)
    classes, blocks, total = {}, {}, [0.0, 0]
    bands = {}  # (method, roughness tenth): squared error, pixels, our level, the reference's

    def add(table, key, se, ours=0.0, ref=0.0):
        c = table.setdefault(key, [0.0, 0, 0.0, 0.0])
        c[0] += se
        c[1] += 1
        c[2] += ours
        c[3] += ref

    roughBand = [0.0, 0]  # the rough band's squared error and pixels, for its one line
    for y in range(h):
        for x in range(w):
            if refl[y][x] <= 0.5 or not (0.0 <= err[y][x] <= cut):
                continue
            if rough[y][x] >= MIRROR:
                roughBand[0] += sum((clamp(T[c][y][x]) - clamp(R[c][y][x])) ** 2 for c in "RGB") / 3
                roughBand[1] += 1
                continue
            se = sum((clamp(T[c][y][x]) - clamp(R[c][y][x])) ** 2 for c in "RGB") / 3
            m = [M[c][y][x] for c in "RGBA"]
            key = ("ssr" if m[0] > 0.5 else "cmo" if m[3] > 0.5 else "probe" if m[1] > 0.5
                   else "env" if m[2] > 0.5 else "mix")
            if key == "ssr":
                hx, hy = int(H["R"][y >> hitShift][x >> hitShift]), int(H["G"][y >> hitShift][x >> hitShift])
                if 0 <= hx < w and 0 <= hy < h and refl[hy][hx] > 0.5:
                    key += " hit-mirror" if rough[hy][hx] < MIRROR else " hit-glossy"
                else:
                    key += " hit-diffuse"
            add(classes, key, se, sum(T[c][y][x] for c in "RGB"), sum(R[c][y][x] for c in "RGB"))
            add(blocks, (x // 32, y // 30), se)
            b = bands.setdefault((key.split()[0], int(rough[y][x] * 10)), [0.0, 0, 0.0, 0.0])
            b[0] += se
            b[1] += 1
            b[2] += sum(T[c][y][x] for c in "RGB")
            b[3] += sum(R[c][y][x] for c in "RGB")
            total[0] += se
            total[1] += 1
    if not total[1]:
        sys.exit(f"error_sources.py: {a.view} has no converged mirror-band pixels")
    db = lambda s, n: 10 * math.log10(n / s) if s > 0 else float("inf")
    print(f"{a.view} {' '.join(a.set)}: mirror band {db(*total):.2f} dB on {total[1]} px, rough band "
          f"{db(*roughBand) if roughBand[1] else float('nan'):.2f} dB on {roughBand[1]} px against {ref_dir.name} "
          f"(capture in {out})")
    print("| class | pixels | share of squared error | PSNR dB | level (ours / reference) |\n|---|---|---|---|---|")
    for k, (s, n, ours, ref) in sorted(classes.items(), key=lambda kv: -kv[1][0]):
        print(f"| {k} | {n} | {100 * s / total[0]:.1f}% | {db(s, n):.2f} | {ours / ref if ref > 0 else float('nan'):.2f} |")
    # A level far from 1 is a bias, not detail: plain_metals' sky lookups at roughness 0.2-0.3 at
    # 0.45 (its metals reflected the sky's ground where their floor is) are how probes.auto_probe
    # was found; its cone hits there at 0.44 were the cone's missing lobe tail, which
    # resolve.comp's kConeTailShare now leaves to the chain (MEASUREMENTS.md, stop 62).
    print("\n| method | roughness | pixels | share | PSNR dB | level (ours / reference) |\n|---|---|---|---|---|---|")
    for (k, t), (s, n, ours, ref) in sorted(bands.items()):
        print(f"| {k} | {t / 10:.1f}-{(t + 1) / 10:.1f} | {n} | {100 * s / total[0]:.1f}% | {db(s, n):.2f} | "
              f"{ours / ref if ref > 0 else float('nan'):.2f} |")
    print(f"\nblocks (32x30) with the most error:")
    for (bx, by), (s, n, _, _) in sorted(blocks.items(), key=lambda kv: -kv[1][0])[:a.blocks]:
        print(f"  x {bx * 32}-{bx * 32 + 31}, y {by * 30}-{by * 30 + 29}: {n} px, {100 * s / total[0]:.1f}%")


if __name__ == "__main__":
    main()
