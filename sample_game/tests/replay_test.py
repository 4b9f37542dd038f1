#!/usr/bin/env python3
"""replay_test.py GAME SESSION GOLDEN_DIR OUT [--regenerate]

Replays the checked-in session under Xvfb with validation on: the player must hit a wall, collect
every item and reach the win screen, with no validation message; the frames at fixed points
(the colour before the HUD) must match the goldens within the capture tolerances of
tests/capture/golden_test.sh (idiff -fail 0.02 -failpercent 0.5 -hardfail 0.25). Goldens are
assets/goldens/game.hall_of_mirrors.frame.NNNN.png; --regenerate writes them (say why in the
commit)."""
import os
import re
import shutil
import subprocess
import sys

# start, after the wall hit, at half resolution, by the ball, CMOs off in the method view, on the win screen
SHOTS = (5, 40, 60, 110, 155, 199)


def main():
    game, session, goldens, out = sys.argv[1:5]
    regenerate = "--regenerate" in sys.argv[5:]
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    env = dict(os.environ, SPECULUM_VALIDATION="1")
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 640x480x24", game, "--replay", session,
           "--shots", out, "--shot-frames", ",".join(str(f) for f in SHOTS)]
    p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    log = p.stdout
    with open(os.path.join(out, "log.txt"), "w") as f:
        f.write(log)
    failures = []
    if p.returncode != 0:
        failures.append("exit status %d" % p.returncode)
    if "VUID" in log or "validation messages" in log or "Validation Error" in log:
        failures.append("validation messages")
    walls = re.findall(r"frame (\d+): wall hit at \(([-\d.]+), ([-\d.]+)\)", log)
    collected = re.findall(r"frame (\d+): collected (\S+)", log)
    won = re.search(r"frame (\d+): won: all (\d+) found", log)
    if not walls:
        failures.append("no wall hit")
    elif not any(abs(float(z) - (4.0 - 0.3)) < 0.02 for _, _, z in walls):
        # The session walks north into the south wall (z = 4): the capsule (r = 0.3) stops at 3.70.
        failures.append("no stop at the south wall: wall hits at %s" % [(x, z) for _, x, z in walls])
    if len({c[1] for c in collected}) != 3:
        failures.append("collected %s, expected collectible.0-2" % sorted({c[1] for c in collected}))
    sets = re.findall(r"frame (\d+): set (\S+)", log)
    if [s[1] for s in sets] != ["reflections.cmos=false", "reflections.debug_view=method", "reflections.debug_view=none",
                                "reflections.cmos=true"]:
        failures.append("the recorded HUD changes were not replayed: %s" % sets)
    if not won:
        failures.append("no win")
    elif int(won.group(1)) >= SHOTS[-1]:
        failures.append("won at frame %s, after the last shot" % won.group(1))
    for f in SHOTS:
        name = "frame.%04d.png" % f
        shot = os.path.join(out, name)
        golden = os.path.join(goldens, "game.hall_of_mirrors." + name)
        if not os.path.isfile(shot):
            failures.append("no image for frame %d" % f)
            continue
        if regenerate:
            shutil.copyfile(shot, golden)
            continue
        if not os.path.isfile(golden):
            failures.append("missing golden %s (run with --regenerate and review)" % golden)
            continue
        d = subprocess.run(["idiff", "-fail", "0.02", "-failpercent", "0.5", "-hardfail", "0.25", "-o",
                            os.path.join(out, "diff." + name.replace(".png", ".exr")), "-abs", "-scale", "10",
                            golden, shot], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if d.returncode >= 2:
            failures.append("frame %d differs from its golden (idiff exit %d): %s" % (f, d.returncode, shot))
    print("\n".join(l for l in log.splitlines() if "wall hit" in l or "collected" in l or "won" in l
                    or "speculum-game:" in l))
    if failures:
        print("FAILED: " + "; ".join(failures) + " (log: %s)" % os.path.join(out, "log.txt"))
        return 1
    print("ok: wall hit, 3 collected, won; %d frames %s" % (len(SHOTS), "written" if regenerate else "match"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
