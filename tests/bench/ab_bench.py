#!/usr/bin/env python3
"""A/B of two builds of the engine on the same views, alternating, with a sign test.

    ab_bench.py --a BUILD_A --b BUILD_B [--views closed_room.main,gallery.main] [--size 960x540]
                [--rounds 8] [--frames 4] [--set KEY=VALUE ...] [--settings FILE]

On this project's reference machine a capture's pass times move by 20-40% from one run to the
next (another process, the CPU's clock), and by more between bursts of a few seconds. A cut of
5-10% is then invisible in one pair of runs and a guess in three. This alternates the two builds
round by round (A B, then B A, so that a drift favours neither), takes each run's fastest frame
per pass (load only adds time), and reports per pass the median over rounds of A and of B, their
ratio, and in how many rounds B was the faster of its pair, with the two-sided sign test's p: the
chance of a split at least that uneven if the builds cost the same. `--a` and `--b` may be the
same build: that A/A run shows the floor (the ratio's spread, p near 1).

Make the other build with a worktree: `git worktree add /tmp/base COMMIT && cmake -S /tmp/base -B
/tmp/base/build -G Ninja -DCMAKE_BUILD_TYPE=Release && ninja -C /tmp/base/build`.
"""
import argparse
import math
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import speed_bench  # noqa: E402  (capture(): one run's per-pass times; module_ms, ms)

ROOT = speed_bench.ROOT


def fail(message):
    """Bad arguments: exit 2 with one line naming what is wrong (the tools' contract)."""
    print(f"ab_bench.py: {message}", file=sys.stderr)
    sys.exit(2)


def sign_p(wins, n):
    """Two-sided sign test: P(a split at least as uneven as wins of n | p = 1/2)."""
    k = min(wins, n - wins)
    tail = sum(math.comb(n, i) for i in range(k + 1)) / 2 ** n
    return min(1.0, 2 * tail)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--a", required=True, help="build folder A (the base)")
    ap.add_argument("--b", required=True, help="build folder B (the change)")
    ap.add_argument("--views", default="closed_room.main,gallery.main")
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--rounds", type=int, default=8)
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE for both builds")
    ap.add_argument("--settings", help="settings file for both builds")
    ap.add_argument("--min-ms", type=float, default=1.0, help="passes below this in A are left out")
    a = ap.parse_args()
    for b in (a.a, a.b):
        if not os.path.exists(os.path.join(b, "tools", "capture", "speculum-capture")):
            fail(f"{b}: no tools/capture/speculum-capture in this build folder")
    if a.rounds < 2 or a.frames < 1:
        fail("--rounds must be 2 or more and --frames 1 or more")
    views = [v.split(".", 1) for v in a.views.split(",")]
    for v in views:
        if len(v) != 2 or not os.path.exists(os.path.join(ROOT, "assets", "scenes", v[0] + ".gltf")):
            fail(f"{'.'.join(v)}: not SCENE.CAMERA with SCENE in assets/scenes")
    sets = ([f"@{a.settings}"] if a.settings else []) + a.set
    steps, done = len(views) * a.rounds * 2, 0
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for scene, camera in views:
            runs = {"A": [], "B": []}
            for r in range(a.rounds):
                for side in ("A", "B") if r % 2 == 0 else ("B", "A"):
                    done += 1
                    print(f"[ab {done}/{steps}] {scene}.{camera} round {r + 1} {side}", file=sys.stderr, flush=True)
                    args = argparse.Namespace(build=a.a if side == "A" else a.b, size=a.size, frames=a.frames,
                                              stat="min")
                    out = os.path.join(tmp, f"{scene}.{camera}.{side}.{r}")
                    os.makedirs(out)
                    runs[side].append(speed_bench.capture(args, scene, camera, sets, out, "color"))
            results[(scene, camera)] = runs
    print(f"\nA/B {a.size}, {a.rounds} rounds alternating (A B, B A, ...), each run's fastest of {a.frames} "
          f"frames, medians over rounds; load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores\n"
          f"A = {a.a}\nB = {a.b}\n")
    for (scene, camera), runs in results.items():
        print(f"### {scene}.{camera}\n")
        print("| pass | A ms | B ms | B / A | B faster in | sign test p |\n|---|---|---|---|---|---|")
        rows = [("frame", [r["frame"] for r in runs["A"]], [r["frame"] for r in runs["B"]]),
                ("module (reflections.*)", [speed_bench.module_ms(r["passes"]) for r in runs["A"]],
                 [speed_bench.module_ms(r["passes"]) for r in runs["B"]])]
        names = sorted({k for r in runs["A"] for k in r["passes"]},
                       key=lambda k: -statistics.median(r["passes"].get(k, 0.0) for r in runs["A"]))
        for k in names:
            xa = [r["passes"].get(k, 0.0) for r in runs["A"]]
            if statistics.median(xa) >= a.min_ms:
                rows.append((k, xa, [r["passes"].get(k, 0.0) for r in runs["B"]]))
        for name, xa, xb in rows:
            ma, mb = statistics.median(xa), statistics.median(xb)
            wins = sum(1 for p, q in zip(xa, xb) if q < p)
            print(f"| {name} | {speed_bench.ms(ma)} | {speed_bench.ms(mb)} | "
                  f"{mb / ma if ma > 0 else float('nan'):.3f} | {wins} of {len(xa)} | {sign_p(wins, len(xa)):.2f} |")
        print()


if __name__ == "__main__":
    main()
