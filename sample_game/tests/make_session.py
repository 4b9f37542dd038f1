#!/usr/bin/env python3
"""Writes sample_game/tests/data/hall_of_mirrors.session: the checked-in recording the replay test
plays (sample_game/README.md). A person would record it with `speculum-game --record`; this script
writes the same format from a plan, so that it can be rebuilt after the level changes: walk north
into the south wall (a wall hit), then to each collectible in turn (a jump on the way), then stand
on the win screen. Frame times vary between 40 and 60 ms, like a recorded session on lavapipe;
frames 45-79 render at half the internal resolution (the dynamic resolution's resizes, with the
temporal history, under validation); HUD changes as a player makes them: the CMOs off at frame 140,
the method debug view at 150, both back at 160."""
import math
import os

MOUSE = 0.0025  # radians per pixel (game.hpp kMouseRadiansPerPixel)
W, JUMP = 1, 16
SPEED = 3.0

frames = []
SETS = {140: ("reflections.cmos=false",), 150: ("reflections.debug_view=method",),
        160: ("reflections.debug_view=none", "reflections.cmos=true")}
t_rng = 12345


def dt():
    global t_rng
    t_rng = (t_rng * 1103515245 + 12345) % (1 << 31)
    return 0.04 + 0.02 * (t_rng % 1000) / 1000.0


def idle(seconds):
    t = 0.0
    while t < seconds:
        d = dt()
        frames.append((d, 0, 0.0, 0.0))
        t += d


def turn(yaw_from, yaw_to, n=5):
    delta = (yaw_to - yaw_from + math.pi) % (2 * math.pi) - math.pi
    for _ in range(n):
        frames.append((dt(), 0, -delta / MOUSE / n, 0.0))
    return yaw_to


def walk(seconds, jump_at=None):
    t = 0.0
    while t < seconds:
        d = min(dt(), seconds - t)
        keys = W | (JUMP if jump_at is not None and t <= jump_at < t + d else 0)
        frames.append((d, keys, 0.0, 0.0))
        t += d


def yaw_to(a, b):
    return math.atan2(-(b[0] - a[0]), -(b[1] - a[1]))


def main():
    pos = (-3.5, 0.3)
    yaw = math.atan2(-5.0, 1.3)  # the camera `main` looks towards (1.5, 0.9, -1.0)
    idle(0.3)
    yaw = turn(yaw, math.pi)  # north (+z), into the south wall at z = 4
    walk(1.5)
    pos = (-3.5, 4.0 - 0.3)
    for i, target in enumerate(((-3.5, -2.5), (3.0, -3.0), (3.5, 2.5))):
        yaw = turn(yaw, yaw_to(pos, target))
        dist = math.hypot(target[0] - pos[0], target[1] - pos[1])
        walk(dist / SPEED, jump_at=dist / SPEED / 2 if i == 1 else None)
        pos = target
    idle(1.0)
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "hall_of_mirrors.session")
    with open(out, "w", encoding="utf-8", newline="\n") as f:
        f.write("speculum-game recording 1\n")
        f.write("# written by sample_game/tests/make_session.py\n")
        f.write("scene hall_of_mirrors.gltf\nsize 320x180\npreset low\n")
        for i, (d, k, dx, dy) in enumerate(frames):
            for kv in SETS.get(i, ()):
                f.write("s %s\n" % kv)
            f.write("f %.9g %d %.9g %.9g %s\n" % (d, k, dx, dy, "0.5" if 45 <= i < 80 else "1"))
    print("wrote %s: %d frames, %.1f s" % (out, len(frames), sum(f[0] for f in frames)))


if __name__ == "__main__":
    main()
