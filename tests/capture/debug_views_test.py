#!/usr/bin/env python3
"""The reflections module's debug views (issue 3: iterations heatmap, hit mask, coverage,
method, Hi-Z levels, the reflection alone, CMO tracing, the tile classes), reached from the command line with
`--set reflections.debug_view=NAME`: each view's image must be what the view promises,
computed here from the module's raw AOVs of the same frame (hit, method, reflection, hiz).

The composite divides debug colours by the exposure so that they reach the screen near their
value; the `linear` AOV is compared, times the exposure (the scene's extras.exposure times
render.exposure, left at 1; the default scene's extras, as the renderer reads them). Reflective pixels (method's screen + environment weights sum to
1) show the view; the others show their lit colour's luminance times 0.15 (grey), checked
against the `linear` AOV of a capture without a debug view. The Hi-Z view covers every pixel,
and the reflection view too (black where nothing reflects).

usage: debug_views_test.py CAPTURE SCENE OUTDIR"""
import json, os, subprocess, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from stripes_test import load  # noqa: E402
from capture_verdict import verdict  # noqa: E402

SIZE = (320, 180)
MAX_ITERATIONS = 96  # reflections.max_iterations' default (modules/reflections/settings.cpp)
HIZ_MIP = 3          # reflections.debug_hiz_mip's default
# Half-float AOVs: relative error about 1e-3, and colours reach 2.9 after the exposure.
TOLERANCE = 0.01
# Hi-Z view: its span test (|farthest - closest| > 0.05 in log2 distance / 10) can flip on
# cells right at the threshold, since the hiz AOV holds the distances as half floats.
HIZ_FLIP_SHARE = 0.005


def heat(x):
    x = min(max(x, 0.0), 1.0)
    return tuple(min(max(1.5 - abs(4.0 * x - k), 0.0), 1.0) for k in (3.0, 2.0, 1.0))


def capture(exe, scene, out, view, aovs):
    w, h = SIZE
    subprocess.run([exe, "--scene", scene, "--camera", "main", "--size", f"{w}x{h}", "--warmup", "2",
                    "--set", f"reflections.debug_view={view}", "--aov", aovs, "--out", out], check=True,
                   stdout=subprocess.DEVNULL)


CMO_HUES = ((0.2, 0.9, 0.3), (0.3, 0.5, 1.0), (1.0, 0.8, 0.2), (0.9, 0.3, 0.9))
CMO_MAX_ITERATIONS = 256  # reflections.cmo_max_iterations's default


def expected_cmo(x, y, cmo):
    """The cmo view (composite.comp): hue by the CMO that hit, brightness by iterations; red
    where every CMO left the ray unresolved; 0.05 grey where none was traced."""
    its, which, outcome = cmo["R"][y][x], cmo["G"][y][x], cmo["B"][y][x]
    if outcome > 1.5:
        return (0.9, 0.1, 0.1)
    if outcome > 0.5:
        bright = 0.35 + 0.65 * min(max(its / (CMO_MAX_ITERATIONS * 0.25), 0.0), 1.0)
        return tuple(c * bright for c in CMO_HUES[(int(which) - 1) & 3])
    return (0.05,) * 3


def expected_views(x, y, hit, method, reflection):
    """Each reflective view's colour at pixel (x, y) (composite.comp's debugView)."""
    hit_z, iterations = hit["B"][y][x], hit["A"][y][x]
    return {
        "iterations": heat(iterations / MAX_ITERATIONS),
        "hit_mask": (0.1, 0.9, 0.1) if hit_z > 0.0 else (0.9, 0.1, 0.1),
        "coverage": (method["R"][y][x],) * 3,
        # r screen space, g probes, b sky, CMOs (a) yellow.
        "method": (method["R"][y][x] + method["A"][y][x], method["G"][y][x] + method["A"][y][x], method["B"][y][x]),
        "reflection": tuple(reflection[c][y][x] for c in "RGB"),
    }


def expected_hiz(x, y, hiz):
    import math
    closest = (math.log2(max(hiz["R"][y][x], 1e-6)) + 2.0) / 10.0
    farthest = (math.log2(max(hiz["G"][y][x], 1e-6)) + 2.0) / 10.0
    level = int(hiz["B"][y][x])
    checker = 1.0 if ((x >> level) + (y >> level)) % 2 == 0 else 0.85
    span = 0.6 if abs(farthest - closest) > 0.05 else 1.0
    return tuple(c * checker * span for c in heat(1.0 - closest))


# The tiles view (composite.comp): per 8x8 tile one of four colours, a screen-space ray (green;
# yellow with CMOs) or a lookup only (blue; magenta with CMOs); a ray tile's colour halfway to
# white where none of its rays has a cone (the resolve's mirror variant), a lookup tile's halved
# where none of its lobes is narrow (its rough variant).
TILE_RAY = ((0.1, 0.8, 0.2), (0.9, 0.8, 0.1))
TILE_LOOKUP = ((0.15, 0.3, 0.9), (0.8, 0.2, 0.8))
TILE_MIRROR = tuple(tuple(0.5 * c + 0.5 for c in colour) for colour in TILE_RAY)
TILE_ROUGH = tuple(tuple(0.5 * c for c in colour) for colour in TILE_LOOKUP)
MAX_SS_ROUGHNESS = 0.6  # reflections.max_roughness's default
MIRROR_ROUGHNESS = 0.0372  # brdf.glsl's coneTan is 0 below (its Phong power past 2^20)
NARROW_ROUGHNESS = 0.3  # probe.h's kNarrowLobeMaxRoughness


def expected_tile(x, y, got, lin, exposure, reflective, hit, rough):
    """What the tiles view must show at (x, y): the colour of the tile's first reflective pixel
    (one colour per tile), which is a class colour: a ray's whenever a pixel of the tile traced
    one (the hit AOV's iterations; classify may also list a ray that the camera fade then skips),
    a lookup's when every reflective pixel is rougher than screen space's limit (0.6), and then
    the darkened one (no narrow lobe). A traced ray with a cone makes a ray tile's colour the
    plain one, and reflective pixels all a mirror's the lightened one; a tile with a narrow lobe
    is never the darkened one."""
    tx, ty = x // 8 * 8, y // 8 * 8
    pixels = [(i, j) for j in range(ty, min(ty + 8, len(lin["R"]))) for i in range(tx, min(tx + 8, len(lin["R"][0])))]
    first = next((i, j) for i, j in pixels if reflective[j][i])
    colour = tuple(lin[c][first[1]][first[0]] * exposure for c in "RGB")
    traced = any(hit["A"][j][i] > 0 for i, j in pixels)
    lookup = all(rough[j][i] > MAX_SS_ROUGHNESS + 0.002 for i, j in pixels if reflective[j][i])
    mine = [rough[j][i] for i, j in pixels if reflective[j][i]]
    if traced:
        cone = any(rough[j][i] > MIRROR_ROUGHNESS + 0.002 for i, j in pixels if hit["A"][j][i] > 0)
        mirror = all(r < MIRROR_ROUGHNESS - 0.002 for r in mine)
        allowed = TILE_RAY if cone else TILE_MIRROR if mirror else TILE_RAY + TILE_MIRROR
    elif lookup:  # every lobe rougher than 0.6, so wide
        allowed = TILE_ROUGH
    else:  # a ray the camera fade skipped, or a lookup tile with a planar probe's pixels
        narrow = any(r < NARROW_ROUGHNESS - 0.002 for r in mine)
        allowed = TILE_RAY + TILE_MIRROR + TILE_LOOKUP + (() if narrow else TILE_ROUGH)
    match = next((a for a in allowed if close(colour, a)), None)
    return match if match is not None and close(got, colour) else (-1.0, -1.0, -1.0)


def close(got, want):
    return all(abs(g - v) <= TOLERANCE * max(1.0, abs(v)) for g, v in zip(got, want))


def main():
    exe, scene, outdir = sys.argv[1:4]
    doc = json.load(open(scene))
    extras = doc["scenes"][doc.get("scene", 0)].get("extras", {})
    exposure = float(extras.get("exposure", 1.0))
    w, h = SIZE
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        def aov(run, name):
            return load(os.path.join(outdir, run, f"{name}.0000.exr"), tmp)[2]

        capture(exe, scene, os.path.join(outdir, "none"), "none", "linear,hit,method,reflection,cmo,roughness")
        plain, hit, method, reflection, cmo, rough = (aov("none", n) for n in ("linear", "hit", "method", "reflection",
                                                                               "cmo", "roughness"))
        rough = next(iter(rough.values()))
        # The chain's weights (screen space, probes, sky, CMOs) sum to 1 on reflective pixels, 0 elsewhere.
        reflective = [[sum(method[c][y][x] for c in "RGBA") > 0.5 for x in range(w)] for y in range(h)]
        count = sum(map(sum, reflective))
        if count < w * h // 10:
            failures.append(f"only {count} reflective pixels: the scene no longer tests the views")
        for view in ("iterations", "hit_mask", "coverage", "method", "reflection", "hiz", "cmo", "tiles"):
            print(f"[debug views] {view}", file=sys.stderr, flush=True)
            capture(exe, scene, os.path.join(outdir, view), view, "linear,hiz" if view == "hiz" else "linear")
            lin = aov(view, "linear")
            hiz = aov(view, "hiz") if view == "hiz" else None
            wrong, first = 0, None
            for y in range(h):
                for x in range(w):
                    got = tuple(lin[c][y][x] * exposure for c in "RGB")
                    lum = 0.2126 * plain["R"][y][x] + 0.7152 * plain["G"][y][x] + 0.0722 * plain["B"][y][x]
                    if view == "hiz":
                        want = expected_hiz(x, y, hiz)
                    elif view == "cmo" and reflective[y][x]:
                        want = expected_cmo(x, y, cmo)
                    elif view == "tiles" and reflective[y][x]:
                        want = expected_tile(x, y, got, lin, exposure, reflective, hit, rough)
                    elif reflective[y][x] or view == "reflection":
                        want = expected_views(x, y, hit, method, reflection)[view]
                    else:
                        want = (lum * 0.15,) * 3
                    if not close(got, want):
                        wrong += 1
                        first = first or (x, y, got, want)
            allowed = int(HIZ_FLIP_SHARE * w * h) if view == "hiz" else 0
            print(f"{view}: {wrong} of {w * h} pixels differ from the view's definition (allowed {allowed})"
                  + (f"; first at {first[:2]}: {tuple(round(v, 4) for v in first[2])} instead of "
                     f"{tuple(round(v, 4) for v in first[3])}" if first else ""))
            if wrong > allowed:
                failures.append(view)
    return verdict(failures, "debug views wrong: ")


if __name__ == "__main__":
    sys.exit(main())
