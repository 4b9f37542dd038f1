#!/usr/bin/env python3
"""The trace skips what the resolve's fades would weigh by zero (modules/reflections/shaders/trace.comp):
rays the camera fade zeroes are not traced, and rays end where the distance fade reaches 0
(miss code -5). Checked on the gallery at 320x180 through the `hit` and `method` AOVs:

- defaults: most reflective pixels trace a ray and many hit (the scene still tests this);
- distance_fade_end at 1 cm: no hit at all, rays end with miss code -5, coverage 0 everywhere;
- camera fade over dot(ray, view) 0.999 .. 1 (every ray but those leaving straight away from
  the eye is zeroed): almost no ray is traced, and coverage is 0 wherever none was.

usage: trace_fades_test.py CAPTURE SCENE OUTDIR"""
import os, subprocess, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from stripes_test import load, without_planar_probes  # noqa: E402
from capture_verdict import verdict  # noqa: E402

W, H = 320, 180


def run(exe, scene, out, settings, tmp):
    args = [exe, "--scene", scene, "--camera", "main", "--size", f"{W}x{H}", "--warmup", "1",
            "--aov", "hit,method", "--out", out]
    for kv in settings:
        args += ["--set", kv]
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
    hit = load(os.path.join(out, "hit.0000.exr"), tmp)[2]
    method = load(os.path.join(out, "method.0000.exr"), tmp)[2]
    pixels = [(x, y) for y in range(H) for x in range(W)]
    # The chain's weights (screen space, probes, sky, CMOs) sum to 1 on reflective pixels, 0 elsewhere.
    reflective = [(x, y) for x, y in pixels if sum(method[c][y][x] for c in "RGBA") > 0.5]
    traced = [(x, y) for x, y in reflective if hit["A"][y][x] > 0.0]
    return {
        "reflective": len(reflective),
        "traced": len(traced),
        "hits": sum(hit["B"][y][x] > 0.0 for x, y in traced),
        # Rays whose fade end lies within their first pixel do no cell test (0 iterations).
        "faded": sum(hit["B"][y][x] == -5.0 for x, y in reflective),
        "covered": sum(method["R"][y][x] > 0.0 for x, y in pixels),
        "covered_untraced": sum(method["R"][y][x] > 0.0 and hit["A"][y][x] <= 0.0 for x, y in pixels),
    }


def main():
    exe, scene, outdir = sys.argv[1:4]
    # The tracer's fades, not a planar probe's plane (whose pixels trace no ray): without them.
    scene = without_planar_probes(scene, outdir)
    failures = []

    def check(ok, what):
        print(("ok: " if ok else "FAIL: ") + what)
        if not ok:
            failures.append(what)

    with tempfile.TemporaryDirectory() as tmp:
        d = run(exe, scene, os.path.join(outdir, "defaults"), [], tmp)
        print(f"defaults: {d}")
        check(d["traced"] > d["reflective"] // 2 and d["hits"] > d["traced"] // 2,
              "with the defaults most reflective pixels trace a ray and most of those hit")
        check(d["covered_untraced"] == 0, "with the defaults no untraced pixel has screen-space coverage")

        f = run(exe, scene, os.path.join(outdir, "distance"),
                ["reflections.distance_fade_start=0", "reflections.distance_fade_end=0.01"], tmp)
        print(f"distance fade ending at 1 cm: {f}")
        check(f["hits"] == 0, "no hit past the distance fade's end")
        check(f["faded"] > d["hits"] // 2, "rays end at the distance fade's end with miss code -5")
        check(f["covered"] == 0, "no screen-space coverage past the distance fade's end")

        c = run(exe, scene, os.path.join(outdir, "camera"),
                ["reflections.camera_fade_start=1", "reflections.camera_fade_end=0.999"], tmp)
        print(f"camera fade over 0.999 .. 1: {c}")
        check(c["traced"] <= d["traced"] // 100, "rays the camera fade zeroes are not traced")
        check(c["covered_untraced"] == 0, "no untraced pixel has screen-space coverage")
    return verdict(failures, "trace fades wrong: ", "; ")


if __name__ == "__main__":
    sys.exit(main())
