#!/usr/bin/env python3
"""The classified path equals the unclassified one (issue 23, "tests stay correctness tests"):
reflections.tiles on (reflections.classify's tile lists, indirect dispatch, fill variants for the
tiles that need nothing) and off (every per-pixel pass over the whole screen) must give the same
values in every AOV the module writes, with no NaN, at the stripes test's five odd sizes (tile
edges fall mid-tile on the right and bottom) and in every mode the lists treat differently: full
and half resolution (half also with reflections.full_res_lookups and with reflections.hit_reuse), cone and stochastic glossy,
CMOs, planar probes (the gallery's floor),
temporal accumulation over several frames, screen space off (lookup tiles only). Every scene here
has CMOs (the cmo AOV needs them).

    tiles_test.py CAPTURE OUTDIR

The same values: the same bits, but for two half-float steps (ULPS) where a variant of the
resolve compiled without what its tiles do not run (tiles.h: no cone loop, no narrow-lobe steps)
rounds differently. Its math is the same, but LLVM fuses multiplies and adds by the code around
them, so a texture coordinate can move by a float ulp: on gallery.main at 641x359, 1 value of
the method AOV in 921,000 (0.0136795 against 0.0136719). A tile in the wrong list, or a variant
that drops work its pixels need, is wrong by far more.

Exit 1 names the case, the AOV and the first differing pixel."""
import math, os, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from stripes_test import SIZES, load

# Two steps of a half float (10 stored mantissa bits), relative; and one of its smallest steps.
ULPS = 2.0 ** -9
TINY = 2.0 ** -24
ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
AOVS = ["color", "reflection", "method", "hit", "cmo"]
# (scene, camera, frames, settings): frames > 1 for the temporal case (its history passes through).
CASES = [
    ("gallery", "main", 1, []),
    ("gallery", "main", 1, ["reflections.resolution=half"]),
    ("cornell_mirrors", "main", 1, ["reflections.glossy=stochastic"]),
    ("cornell_mirrors", "main", 4, ["reflections.resolution=half", "reflections.temporal=true",
                                    "reflections.glossy=stochastic"]),
    ("gallery", "floor_grazing", 1, ["reflections.screen_space=false"]),
    # reflections.lookup_full over the reflective footprints against the whole screen.
    ("gallery", "main", 1, ["reflections.resolution=half", "reflections.full_res_lookups=true"]),
    # reflections.hit_reuse (screen space, the sky and the CMOs) over the reflective footprints.
    ("cornell_mirrors", "main", 1, ["reflections.resolution=half", "reflections.hit_reuse=true"]),
]


def capture(exe, scene, camera, size, frames, settings, out):
    args = [exe, "--scene", os.path.join(ROOT, "assets", "scenes", scene + ".gltf"), "--camera", camera,
            "--size", size, "--warmup", "1", "--frames", str(frames), "--aov", ",".join(AOVS), "--out", out]
    for kv in settings:
        args += ["--set", kv]
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)


def main():
    exe, outdir = sys.argv[1:3]
    failures = 0
    for k, (scene, camera, frames, settings) in enumerate(CASES):
        # Each case at one of the five sizes in turn, and the first also at every size.
        sizes = SIZES if k == 0 else [SIZES[k % len(SIZES)]]
        for w, h in sizes:
            size = "%dx%d" % (w, h)
            tag = "%s.%s.%s.%s" % (scene, camera, size, "+".join(s.split(".", 1)[1] for s in settings) or "default")
            dirs = {}
            for tiles in ("true", "false"):
                d = dirs[tiles] = os.path.join(outdir, tag, "tiles_" + tiles)
                os.makedirs(d, exist_ok=True)
                capture(exe, scene, camera, size, frames, settings + ["reflections.tiles=" + tiles], d)
            rounded, before = 0, failures
            for aov in AOVS:
                name = "%s.%04d.exr" % (aov, frames - 1)
                a = load(os.path.join(dirs["true"], name), dirs["true"])[2]
                b = load(os.path.join(dirs["false"], name), dirs["false"])[2]
                bad = None
                for c in sorted(a):
                    for y, (ra, rb) in enumerate(zip(a[c], b[c])):
                        for x, (va, vb) in enumerate(zip(ra, rb)):
                            if math.isnan(va) or math.isnan(vb) or abs(va - vb) > ULPS * max(abs(va), abs(vb)) + TINY:
                                bad = bad or (c, x, y, va, vb)
                            elif va != vb:
                                rounded += 1
                if bad:
                    failures += 1
                    print("FAIL %s %s: %s at (%d, %d) is %r with tiles, %r without" % ((tag, aov) + bad))
            if rounded:
                print("%s: %d values within %g relative" % (tag, rounded, ULPS))
            print("%s: %s" % (tag, "differs" if failures > before else "equal"), flush=True)
    if failures:
        sys.exit(1)
    print("the classified path equals the unclassified one in %d cases" % len(CASES))


if __name__ == "__main__":
    main()
