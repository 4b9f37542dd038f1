#!/usr/bin/env python3
"""probe_costs.py: what the local cubemap probes cost, and how noisy the reference is
(issue 11's "Performance and accuracy"; results go to modules/probes/MEASUREMENTS.md).

    probe_costs.py lookup   [--rounds 3]   probes on/off, alternating: reflections.resolve medians
    probe_costs.py bake     [--rounds 2]   seconds per face, per prefilter, per probe bake
    probe_costs.py sliced   [--rounds 3]   time-sliced update against once: wall time of every frame
    probe_costs.py refnoise                two 32-spp references per suite view, compared

Common options: --build DIR (default build), --out DIR (default /tmp/probe_costs). Timings are
wall clock or GPU timestamp medians on whatever machine runs it: quote the load average with them.

speculum-capture's timings.json counts only the main frame's passes and the tool does not print
Probes::captureMs(), so bake and time-sliced costs come from its progress lines on stderr, time
stamped as they arrive: "probe bake (faces): k/N" (one line per face; the line after a probe's
sixth face also holds its prefilter) and "capture: i/N" (one line per frame when N <= 10, every
ceil(N/10)-th frame otherwise; on a terminal every frame, which `sliced` gives it with a pty).
"""
import argparse
import json
import os
import pty
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2]
SCENES = SOURCE / "assets" / "scenes"
VIEWS = ["gallery.main", "gallery.floor_grazing", "cornell_mirrors.main", "failure_cases.main", "closed_room.main",
         "plain_metals.main"]


def load():
    return float(open("/proc/loadavg").read().split()[0])


def run_stamped(cmd, tty=False):
    """Runs cmd; returns (wall seconds, [(seconds since start, stderr line)]). With tty, stderr is
    a pseudo-terminal, where app::progress prints every step (a '\r' line) instead of every tenth."""
    t0 = time.monotonic()
    if tty:
        master, slave = pty.openpty()
        p = subprocess.Popen(cmd, stderr=slave, stdout=subprocess.DEVNULL)
        os.close(slave)
        lines, pending = [], b""
        while True:
            try:
                chunk = os.read(master, 4096)
            except OSError:  # EIO: the child closed the terminal
                break
            if not chunk:
                break
            pending += chunk
            *done, pending = re.split(rb"[\r\n]", pending)
            lines += [(time.monotonic() - t0, d.decode(errors="replace").strip()) for d in done if d.strip()]
        os.close(master)
    else:
        p = subprocess.Popen(cmd, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True, bufsize=1)
        lines = [(time.monotonic() - t0, line.rstrip()) for line in p.stderr]
    if p.wait() != 0:
        sys.exit(f"probe_costs: failed ({p.returncode}): {' '.join(map(str, cmd))}\n" + "\n".join(l for _, l in lines[-10:]))
    return time.monotonic() - t0, lines


def progress(lines, label):
    return [(t, int(m.group(1)), int(m.group(2))) for t, line in lines
            if (m := re.match(re.escape(label) + r": (\d+)/(\d+)", line))]


def scene_copy(out, scene, **probe):
    """A copy of assets/scenes/SCENE.gltf beside its files (links) with the probes' fields changed."""
    folder = out / "scenes" / "scenes"
    folder.mkdir(parents=True, exist_ok=True)
    env = out / "scenes" / "env"
    env.mkdir(exist_ok=True)
    doc = json.loads((SCENES / f"{scene}.gltf").read_text())
    for b in doc.get("buffers", []):
        link = folder / b["uri"]
        if not link.exists():
            link.symlink_to(SCENES / b["uri"])
    for f in (SOURCE / "assets" / "env").iterdir():
        if not (env / f.name).exists():
            (env / f.name).symlink_to(f)
    for n in doc["nodes"]:
        ext = n.get("extensions", {}).get("SPECULUM_reflection_probe")
        if ext:
            ext.update(probe)
    name = scene + "".join(f"_{k}_{v}" for k, v in probe.items())
    path = folder / f"{name}.gltf"
    path.write_text(json.dumps(doc))
    return path


def lookup(args, capture, out):
    rows = []
    for rep in range(args.rounds):
        for scene in ("gallery", "closed_room"):
            for probes in ("true", "false"):
                d = out / "lookup" / f"{scene}.{probes}.{rep}"
                subprocess.run([capture, "--scene", SCENES / f"{scene}.gltf", "--camera", "main", "--size", args.size,
                                "--warmup", "2", "--frames", "5", "--aov", "reflection", "--set", "reflections.trace=hiz",
                                "--set", f"reflections.probes={probes}", "--out", d],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
                t = json.loads((d / "timings.json").read_text())
                p = {x["name"]: x["median_ms"] for x in t["passes"]}
                rows.append({"scene": scene, "probes": probes, "rep": rep, "resolve_ms": p["reflections.resolve"],
                             "module_ms": sum(v for k, v in p.items() if k.startswith("reflections.")), "load": load()})
                print(rows[-1], flush=True)
    print(f"\nprobe lookup = reflections.resolve with probes - without ({args.size}, medians of {args.rounds} alternating runs)")
    for scene in ("gallery", "closed_room"):
        on = [r for r in rows if r["scene"] == scene and r["probes"] == "true"]
        off = [r for r in rows if r["scene"] == scene and r["probes"] == "false"]
        med = lambda rs, k: statistics.median(r[k] for r in rs)
        ms = med(on, "resolve_ms") - med(off, "resolve_ms")
        print(f"{scene}.main: resolve {med(on, 'resolve_ms'):.1f} / {med(off, 'resolve_ms'):.1f} ms, lookup {ms:.1f} ms "
              f"of {med(on, 'module_ms'):.1f} ms = {100 * ms / med(on, 'module_ms'):.1f}%; paired "
              f"{[round(a['resolve_ms'] - b['resolve_ms'], 1) for a, b in zip(on, off)]}")
    return rows


def bake(args, capture, out):
    rows = []
    cases = [("closed_room 128", scene_copy(out, "closed_room", resolution=128)),
             ("closed_room 256", scene_copy(out, "closed_room", resolution=256)),
             ("gallery 256", SCENES / "gallery.gltf")]
    for rep in range(args.rounds):
        for tag, scene in cases:
            _, lines = run_stamped([capture, "--scene", scene, "--camera", "main", "--size", "320x180", "--warmup", "1",
                                    "--frames", "1", "--aov", "reflection", "--out", out / "bake"])
            f = progress(lines, "probe bake (faces)")
            t = [x[0] for x in f]
            d = [b - a for a, b in zip(t, t[1:])]
            # deltas ending on faces 2..6, 8..12 of each probe are faces; 7, 13, ... also hold a prefilter
            faces = [x for i, x in enumerate(d) if (i + 1) % 6 != 0]
            face = statistics.median(faces)
            pre = statistics.median([x for i, x in enumerate(d) if (i + 1) % 6 == 0]) - face
            rows.append({"case": tag, "faces": len(f), "face_ms": 1000 * face, "prefilter_s": pre,
                         "probe_bake_s": 6 * face + pre, "first_update_s": (t[-1] - t[0]) + face + pre, "load": load()})
            print(rows[-1], flush=True)
    return rows


def sliced(args, capture, out):
    """Wall time of every frame (a pseudo-terminal makes the capture print each one), once against
    time_sliced: the mean is the cost a cycle spreads over its frames, the max the worst frame."""
    rows = []
    for rep in range(args.rounds):
        for res in (128, 256):
            for mode in ("once", "time_sliced"):
                scene = scene_copy(out, "closed_room", resolution=res, update=mode)
                _, lines = run_stamped([capture, "--scene", scene, "--camera", "main", "--size", args.size, "--warmup", "3",
                                        "--frames", str(args.frames), "--aov", "reflection", "--out", out / "sliced"],
                                       tty=True)
                c = progress(lines, "capture")
                per = [(b[0] - a[0]) / (b[1] - a[1]) for a, b in zip(c, c[1:])]
                rows.append({"res": res, "mode": mode, "rep": rep, "frames": len(per),
                             "mean_ms": 1000 * sum(per) / len(per), "median_ms": 1000 * statistics.median(per),
                             "p90_ms": 1000 * sorted(per)[int(0.9 * (len(per) - 1))], "max_ms": 1000 * max(per),
                             "load": load()})
                print(rows[-1], flush=True)
    print(f"\nwall ms per frame at {args.size} (medians over rounds of each run's mean, p90 and max)")
    for res in (128, 256):
        m = {mode: [r for r in rows if r["res"] == res and r["mode"] == mode] for mode in ("once", "time_sliced")}
        med = lambda mode, k: statistics.median(r[k] for r in m[mode])
        print(f"{res}^2: once {med('once', 'mean_ms'):.1f}, time-sliced {med('time_sliced', 'mean_ms'):.1f} "
              f"(+{med('time_sliced', 'mean_ms') - med('once', 'mean_ms'):.1f} on average, "
              f"+{med('time_sliced', 'p90_ms') - med('once', 'p90_ms'):.1f} at p90, "
              f"+{med('time_sliced', 'max_ms') - med('once', 'median_ms'):.1f} on the worst frame)")
    return rows


def refnoise(args, build, out):
    reference = build / "tests" / "reference" / "speculum-reference"
    metrics = build / "tests" / "metrics" / "speculum-metrics"
    rows = []
    for view in VIEWS:
        scene, camera = view.split(".", 1)
        dirs = []
        for seed in (1, 2):
            d = out / "refnoise" / f"{view}.{args.refsize}.s{args.spp}.seed{seed}"
            if not (d / "reference.json").exists():
                subprocess.run([reference, "--scene", SCENES / f"{scene}.gltf", "--camera", camera, "--size", args.refsize,
                                "--spp", str(args.spp), "--bounces", "2", "--seed", str(seed),
                                "--aov", "linear,reflection,reflective", "--out", d],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
            dirs.append(d)
        exposure = json.loads((dirs[0] / "reference.json").read_text())["exposure"]
        r = subprocess.run([metrics, "compare", "--test", dirs[1] / "reflection.0000.exr",
                            "--ref", dirs[0] / "reflection.0000.exr", "--ref-mask", dirs[0] / "reflective.0000.exr",
                            "--scale", str(exposure)], capture_output=True, text=True, check=True)
        rows.append({"view": view, **json.loads(r.stdout)})
        print(f"{view}: seed 2 against seed 1, {args.spp} spp {args.refsize}: PSNR {rows[-1]['psnr_db']:.2f} dB, "
              f"gross {rows[-1]['gross_share']:.3f} (a perfect engine scores about 3 dB more)", flush=True)
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("what", choices=["lookup", "bake", "sliced", "refnoise"])
    p.add_argument("--build", default=str(SOURCE / "build"))
    p.add_argument("--out", default="/tmp/probe_costs")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--size", default=None, help="lookup: 960x540; sliced: 64x36 (small, so that the slice dominates)")
    p.add_argument("--frames", type=int, default=48, help="sliced: timed frames (two 256^2 cycles)")
    p.add_argument("--spp", type=int, default=32, help="refnoise: samples per pixel")
    p.add_argument("--refsize", default="320x180", help="refnoise: size")
    args = p.parse_args()
    build, out = Path(args.build), Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    capture = build / "tools" / "capture" / "speculum-capture"
    if args.size is None:
        args.size = "960x540" if args.what == "lookup" else "64x36"
    print(f"probe_costs {args.what}: load average {load()}", flush=True)
    rows = {"lookup": lookup, "bake": bake, "sliced": sliced}[args.what](args, capture, out) \
        if args.what != "refnoise" else refnoise(args, build, out)
    (out / f"{args.what}.json").write_text(json.dumps(rows, indent=1, default=str))


if __name__ == "__main__":
    main()
