#!/usr/bin/env python3
"""cmo_costs.py: what CMO tracing costs (issue 12's "Performance and accuracy"; results go to
modules/probes/MEASUREMENTS.md).

    cmo_costs.py [--size 960x540] [--rounds 2] [--res 256] [--views cornell_mirrors.main,...]

For each view: CMOs on and off, alternating `--rounds` times (GPU timestamp medians from
speculum-capture's timings.json): reflections.cmo_trace ms, the module's ms (the sum of the
reflections.* passes) and the trace's share of it, the pixels it traced (the `cmo` AOV: any
iteration) and its time per traced pixel in microseconds (seed 000 Table 5.2's measure, which
divides by mirror pixels), the mean iterations per traced pixel, hierarchical and linear.
`--res` rewrites every CMO of the scene to that resolution first (a copy in --out): the issue's
target is for two CMOs of 256 px. Quote the load average printed with the numbers.
"""
import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(SOURCE / "tests" / "capture"))
from stripes_test import load as load_exr  # noqa: E402


def loadavg():
    return float(open("/proc/loadavg").read().split()[0])


def scene_with_resolution(scene, res, out):
    """A copy of the scene with every CMO at `res` px, in OUT/scenes beside links to its buffers
    (the loader takes uris relative to the file) and OUT/env to the skies."""
    doc = json.loads(scene.read_text())
    for n in doc.get("nodes", []):
        ext = n.get("extensions", {}).get("SPECULUM_reflection_probe")
        if ext and ext.get("kind") == "cmo":
            ext["resolution"] = res
    folder = out / "scenes"
    folder.mkdir(parents=True, exist_ok=True)
    for b in doc.get("buffers", []):
        uri = b.get("uri", "data:")
        if not uri.startswith("data:") and not (folder / uri).exists():
            (folder / uri).symlink_to(scene.parent / uri)
    if not (out / "env").exists():
        (out / "env").symlink_to(SOURCE / "assets" / "env")
    path = folder / f"{scene.stem}.cmo{res}.gltf"
    path.write_text(json.dumps(doc))
    return path


def capture(build, scene, camera, size, sets, out, aov=None):
    cmd = [str(build / "tools" / "capture" / "speculum-capture"), "--scene", str(scene), "--camera", camera, "--size", size,
           "--warmup", "3", "--frames", "5", "--out", str(out)]
    if aov:
        cmd += ["--aov", aov]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)
    t = json.loads((out / "timings.json").read_text())
    return {p["name"]: p["median_ms"] for p in t["passes"]}


def traced(path):
    with tempfile.TemporaryDirectory() as tmp:
        w, h, c = load_exr(str(path), tmp)
    its = [c["R"][y][x] for y in range(h) for x in range(w) if c["R"][y][x] > 0]
    return len(its), (sum(its) / len(its) if its else 0.0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=str(SOURCE / "build"))
    ap.add_argument("--out", default="/tmp/cmo_costs")
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--res", type=int, default=256)
    ap.add_argument("--views", default="cornell_mirrors.main,cornell_mirrors.sphere_close,gallery.main,mirror_hall.facing")
    a = ap.parse_args()
    build, out = Path(a.build), Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"load average {loadavg():.2f} at the start")
    print("| view | cmo_trace ms | module ms with / without CMOs | share | traced px | us per traced px | "
          "iterations (hierarchical / linear) |")
    print("|---|---|---|---|---|---|---|")
    for key in a.views.split(","):
        name, camera = key.split(".", 1)
        scene = scene_with_resolution(SOURCE / "assets" / "scenes" / f"{name}.gltf", a.res, out)
        on, off, trace = [], [], []
        for r in range(a.rounds):
            p_on = capture(build, scene, camera, a.size, [], out / f"{key}.on")
            p_off = capture(build, scene, camera, a.size, ["reflections.cmos=false"], out / f"{key}.off")
            on.append(sum(v for k, v in p_on.items() if k.startswith("reflections.")))
            off.append(sum(v for k, v in p_off.items() if k.startswith("reflections.")))
            trace.append(p_on.get("reflections.cmo_trace", 0.0))
        capture(build, scene, camera, a.size, [], out / f"{key}.aov", aov="cmo")
        capture(build, scene, camera, a.size, ["reflections.cmo_trace=linear"], out / f"{key}.aovlin", aov="cmo")
        n, it = traced(sorted((out / f"{key}.aov").glob("cmo.*.exr"))[-1])
        _, itl = traced(sorted((out / f"{key}.aovlin").glob("cmo.*.exr"))[-1])
        t, m_on, m_off = statistics.median(trace), statistics.median(on), statistics.median(off)
        print(f"| {key} | {t:.1f} | {m_on:.1f} / {m_off:.1f} | {100 * t / m_on:.0f}% | {n} | "
              f"{1000 * t / max(n, 1):.2f} | {it:.1f} / {itl:.1f} |")
    print(f"load average {loadavg():.2f} at the end")


if __name__ == "__main__":
    main()
