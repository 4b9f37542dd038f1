#!/usr/bin/env python3
"""The speed bench of issue 23: per bench view, every configuration in one run, alternating
rounds so that the machine's noise falls on all of them alike (GPU timestamp medians from
speculum-capture's timings.json; medians over rounds).

    speed_bench.py [--build build] [--views gallery.main,closed_room.main,...] [--size 960x540]
                   [--rounds 2] [--frames 4] [--config NAME=KEY=VALUE,KEY=VALUE|@FILE ...] [--json OUT]

Configurations: `engine` (reflections off: the engine's own frame), `default` (the default
chain, every probe and CMO of the scene), `no_cmos`, `half`, `quarter` (reflections.ray_budget), `tiles_off` (reflections.tiles
off: every per-pixel pass over the whole screen), the presets `low`, `medium`, `high`
(assets/settings), and any --config. Per view it prints the frame, the module (the sum of the
reflections.* passes), the module's share of the frame, the probes module's passes (planar
probes render each frame), the screen-space rays traced (pixels of the trace's hit AOV with an
iteration) and the trace's and the module's cost per traced ray; then the targets' ratios and
every pass's ms for each configuration. Timing only: never an assertion."""
import argparse, json, os, statistics, struct, subprocess, sys, tempfile, zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "capture"))
from stripes_test import load  # uncompressed-EXR reader

CONFIGS = {
    "engine": ["reflections.enabled=false"],
    "default": [],
    "no_cmos": ["reflections.cmos=false"],
    "half": ["reflections.resolution=half"],
    "quarter": ["reflections.ray_budget=quarter"],
    "tiles_off": ["reflections.tiles=false"],
    "low": ["@assets/settings/low.json"],
    "medium": ["@assets/settings/medium.json"],
    "high": ["@assets/settings/high.json"],
}


def capture(a, scene, camera, sets, out, aov):
    cmd = [os.path.join(a.build, "tools", "capture", "speculum-capture"), "--scene", f"assets/scenes/{scene}.gltf",
           "--camera", camera, "--size", a.size, "--warmup", "3", "--frames", str(a.frames), "--aov", aov,
           "--out", out]
    for s in sets:
        cmd += ["--settings", s[1:]] if s.startswith("@") else ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT)
    t = json.load(open(os.path.join(out, "timings.json")))
    passes = {}
    stat = f"{a.stat}_ms"
    for p in t["passes"]:
        stem, _, last = p["name"].rpartition(".")
        key = stem if last.isdigit() else p["name"]  # pyramid levels summed per pyramid
        passes[key] = passes.get(key, 0.0) + p[stat]
    rays = None
    hit = os.path.join(out, f"hit.{a.frames - 1:04d}.exr")
    if os.path.exists(hit):
        w, h, ch = load(hit, out)
        rays = sum(1 for row in ch["A"] for v in row if v > 0)
    return {"frame": t["frame"][stat], "passes": passes, "rays": rays}


def module_ms(passes):
    """The module's time in one run: its passes (reflections.*) summed."""
    return sum(v for k, v in passes.items() if k.startswith("reflections."))


def ms(v):
    """Milliseconds with the digits a GPU's sub-millisecond passes need (lavapipe's are tens of ms)."""
    return "-" if v is None else f"{v:.1f}" if v >= 10 else f"{v:.2f}" if v >= 0.1 else f"{v:.3f}"


STAT = "median"


def med(xs):
    """Over rounds: the median, or the least with --stat min."""
    xs = [x for x in xs if x is not None]
    return (min(xs) if STAT == "min" else statistics.median(xs)) if xs else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--views", default="gallery.main,closed_room.main,cornell_mirrors.main,failure_cases.main")
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--config", action="append", default=[])
    ap.add_argument("--only", default="", help="comma list of configurations to run (default: all)")
    ap.add_argument("--json", default="")
    ap.add_argument("--stat", choices=["median", "min"], default="median",
                    help="per pass: the median frame of each capture and the median over rounds, or the "
                         "fastest of each (another process's load only adds time)")
    a = ap.parse_args()
    global STAT
    STAT = a.stat
    a.build = os.path.abspath(a.build)
    configs = dict(CONFIGS)
    for c in a.config:
        name, _, sets = c.partition("=")
        configs[name] = [s for s in sets.split(",") if s]
    if a.only:
        configs = {k: v for k, v in configs.items() if k in a.only.split(",")}
    views = [v.split(".", 1) for v in a.views.split(",")]
    steps, done = len(views) * a.rounds * len(configs), 0
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for scene, camera in views:
            for r in range(a.rounds):
                for name, sets in configs.items():
                    done += 1
                    print(f"[speed {done}/{steps}] {scene}.{camera} round {r + 1} {name}", file=sys.stderr, flush=True)
                    aov = "color" if name == "engine" else "hit"
                    res = capture(a, scene, camera, sets, os.path.join(tmp, f"{scene}.{camera}.{name}.{r}"), aov)
                    results.setdefault((scene, camera, name), []).append(res)
    print(f"\nspeed bench {a.size}, {a.rounds} rounds of {a.frames} frames alternating, load average "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores\n")
    rows = {}
    for scene, camera in views:
        print(f"### {scene}.{camera}\n")
        print("| config | frame ms | module ms | module share | probes ms | rays traced | trace us/ray | module us/ray |")
        print("|---|---|---|---|---|---|---|---|")
        for name in configs:
            rs = results[(scene, camera, name)]
            frame = med(r["frame"] for r in rs)
            module = med(module_ms(r["passes"]) for r in rs)
            probes = med(sum(v for k, v in r["passes"].items() if k.startswith("probes.")) for r in rs)
            trace = med(r["passes"].get("reflections.trace") for r in rs)
            rays = med(r["rays"] for r in rs)
            rows[(scene, camera, name)] = {"frame": frame, "module": module, "probes": probes, "rays": rays,
                                           "trace": trace}
            per = lambda t: f"{1000 * t / rays:.3g}" if rays and t else "-"
            print(f"| {name} | {ms(frame)} | {ms(module)} | {module / frame:.0%} | {ms(probes)} | "
                  f"{'-' if rays is None else f'{rays:.0f}'} | {per(trace)} | {per(module)} |")
        print()
        g = lambda n, k: rows.get((scene, camera, n), {}).get(k)
        lines = []
        if g("engine", "frame") and g("default", "module"):
            lines.append(f"module / (engine frame + module) {g('default', 'module') / (g('engine', 'frame') + g('default', 'module')):.0%} "
                         f"(engine alone {ms(g('engine', 'frame'))} ms)")
        if g("no_cmos", "module") and g("default", "module"):
            lines.append(f"the scene's CMOs add {g('default', 'module') / g('no_cmos', 'module') - 1:+.0%} to the module")
        if g("half", "module"):
            lines.append(f"half is {g('default', 'module') / g('half', 'module'):.2f}x cheaper than full (module)")
        if g("tiles_off", "module"):
            lines.append(f"tiles save {1 - g('default', 'module') / g('tiles_off', 'module'):.0%} of the module")
        if all(g(p, "module") for p in ("low", "medium", "high")):
            lo, me, hi = (g(p, "module") for p in ("low", "medium", "high"))
            lines.append(f"presets low {ms(lo)} < medium {ms(me)} < high {ms(hi)}: {'yes' if lo < me < hi else 'NO'}; "
                         f"low / default {lo / g('default', 'module'):.2f}")
        for l in lines:
            print(f"- {l}")
        print()
        print("| pass (median ms) | " + " | ".join(configs) + " |")
        print("|---|" + "---|" * len(configs))
        names = sorted({k for n in configs for r in results[(scene, camera, n)] for k in r["passes"]
                        if k.startswith(("reflections.", "probes."))})
        for k in names:
            cells = [med(r["passes"].get(k) for r in results[(scene, camera, n)]) for n in configs]
            print(f"| {k} | " + " | ".join(ms(c) for c in cells) + " |")
        print()
    if a.json:
        json.dump({f"{s}.{c}.{n}": v for (s, c, n), v in rows.items()}, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
