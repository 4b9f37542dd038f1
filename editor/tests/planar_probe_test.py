#!/usr/bin/env python3
"""The editor adds a planar probe on a picked flat surface (issue 24), under Xvfb with validation.

planar_probe_test.py EDITOR CAPTURE SOURCE_DIR OUT_DIR

On a copy of the gallery the script clicks the glossy band of the floor (floor.band_0.1, roughness 0.1,
x in [-3, 0], z in [-4, 4]), adds a planar probe there (script action `add_planar`, the menu's
"Add planar probe on the picked surface") and saves. The saved node must be a planar probe on
the floor's plane (origin at y 0, +Y up), spanning the band (half extents 1.5 x 4 m around its
centre), and the saved scene must render with speculum-capture with the probe serving the band.
"""
import json
import math
import os
import re
import subprocess
import sys

from editor_test_support import copy_gallery, run_script  # the script's folder is on sys.path


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def main():
    editor, capture, source, out = sys.argv[1:5]
    scene = copy_gallery(source, out)
    script = [
        {"camera": "main"}, {"wait": 1},
        {"click_node": "floor.band_0.1"}, {"expect_selected": "floor.band_0.1"},
        {"action": "add_planar"}, {"wait": 2},
        {"key": "ctrl+s"}, {"wait": 1},
        {"action": "quit"},
    ]
    script_file = os.path.join(out, "script.json")
    json.dump(script, open(script_file, "w"), indent=1)
    env = dict(os.environ, SPECULUM_VALIDATION="1")
    log = run_script(editor, scene, script_file, out, 4000, env)
    added = re.search(r"added (planar\.\d+) at (\S+) (\S+) (\S+), extents (\S+) x (\S+) m", log)
    if not added:
        print(log[-4000:])
        fail("the editor did not report the new planar probe")
    saved = json.load(open(scene))
    nodes = [n for n in saved["nodes"] if n.get("name") == added.group(1)]
    if len(nodes) != 1:
        fail("the saved scene has no node %s" % added.group(1))
    node = nodes[0]
    ext = node.get("extensions", {}).get("SPECULUM_reflection_probe", {})
    if ext.get("kind") != "planar" or len(ext.get("extents", [])) != 2:
        fail("saved probe %s is not a planar probe with two extents" % ext)
    t = node.get("translation", [0, 0, 0])
    if math.dist(t, [-1.5, 0.0, 0.0]) > 1e-3:
        fail("planar probe at %s, the band's centre is (-1.5, 0, 0)" % t)
    if any(abs(a - b) > 1e-3 for a, b in zip(ext["extents"], [1.5, 4.0])):
        fail("planar probe extents %s, the band's half sizes are [1.5, 4]" % ext["extents"])
    q = node.get("rotation", [0, 0, 0, 1])
    up = [2 * (q[0] * q[1] - q[3] * q[2]), 1 - 2 * (q[0] ** 2 + q[2] ** 2), 2 * (q[1] * q[2] + q[3] * q[0])]
    if up[1] < 0.9999:
        fail("planar probe's +Y is %s, the floor's normal is +Y" % up)
    if "resolution" in ext:
        fail("a new planar probe keeps the default resolution (absent), got %s" % ext["resolution"])
    # The saved scene renders (the planar probe loads, validates and draws).
    cap = os.path.join(out, "capture")
    c = subprocess.run([capture, "--scene", scene, "--camera", "main", "--size", "160x90", "--warmup", "0",
                        "--aov", "color", "--out", cap], capture_output=True, text=True, env=env, timeout=900)
    if c.returncode != 0:
        print(c.stdout[-2000:] + c.stderr[-2000:])
        fail("speculum-capture could not render the saved scene")
    print("OK: added %s at %s, extents %s, on the floor's plane; the saved scene renders" % (
        added.group(1), t, ext["extents"]))


if __name__ == "__main__":
    main()
