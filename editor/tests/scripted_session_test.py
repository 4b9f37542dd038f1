#!/usr/bin/env python3
"""A scripted editor session under Xvfb (issue 14), with validation layers on.

scripted_session_test.py EDITOR CAPTURE SOURCE_DIR OUT_DIR

On a copy of the gallery (with content the engine does not model added to it) the script clicks
the chrome sphere (a pick readback), adds a probe at the clicked point, drags it along x with the
gizmo, widens its box with the +x extents handle, changes the chrome material's roughness, undoes once (Ctrl+Z: the roughness comes back),
saves (Ctrl+S) and takes a viewport screenshot from the camera `main`. The test then checks the
saved glTF against what the editor reported and against the original, and renders the saved
scene with speculum-capture from the same camera at the viewport's size: the two images must
agree within the golden tolerances (tests/capture/golden_test.sh).
"""
import json
import math
import os
import re
import shutil
import subprocess
import sys

from editor_test_support import run_script  # the script's folder is on sys.path


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def vec(text):
    return [float(v) for v in text.split()]


def main():
    editor, capture, source, out = sys.argv[1:5]
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.join(out, "scenes"))
    os.makedirs(os.path.join(out, "env"))
    shutil.copy(os.path.join(source, "assets/env/sunset.exr"), os.path.join(out, "env"))
    shutil.copy(os.path.join(source, "assets/scenes/gallery.bin"), os.path.join(out, "scenes"))
    original = json.load(open(os.path.join(source, "assets/scenes/gallery.gltf")))
    doc = json.loads(json.dumps(original))
    doc["nodes"][0].setdefault("extensions", {})["VENDOR_unknown"] = {"kept": [1, 2, 3]}
    doc["asset"]["extras"] = {"note": "unknown content survives"}
    scene = os.path.join(out, "scenes", "gallery.gltf")
    json.dump(doc, open(scene, "w"), indent=1)

    script = [
        {"camera": "main"}, {"wait": 1},
        {"click_node": "chrome_sphere"}, {"expect_selected": "chrome_sphere"},
        {"action": "add_probe"}, {"wait": 1},
        {"drag_gizmo": {"axis": 0, "pixels": 60, "frames": 4}}, {"wait": 1},
        {"drag_gizmo": {"axis": 4, "pixels": 30, "frames": 4}}, {"wait": 1},
        {"material": "chrome", "field": "material.roughness", "value": 0.3}, {"wait": 1},
        {"key": "ctrl+z"}, {"wait": 1},
        {"key": "ctrl+s"},
        {"camera": "main"}, {"wait": 6},
        {"screenshot": os.path.join(out, "view.png")},
        {"action": "quit"},
    ]
    script_file = os.path.join(out, "script.json")
    json.dump(script, open(script_file, "w"), indent=1)
    env = dict(os.environ, SPECULUM_VALIDATION="1")
    log = run_script(editor, scene, script_file, out, 4000, env)

    picked = re.search(r"picked chrome_sphere at (\S+ \S+ \S+) normal (\S+ \S+ \S+)", log)
    added = re.search(r"added (\S+) at (\S+ \S+ \S+)", log)
    moved = re.search(r"moved (\S+) to (\S+ \S+ \S+)", log)
    shot = re.search(r"viewport (\d+)x(\d+) written to \S+ \(steady frames (\d+)\)", log)
    resized = re.search(r"resized \S+ to extents (\S+ \S+ \S+) blend (\S+)", log)
    if not (picked and added and moved and shot and resized):
        print(log[-4000:])
        fail("the editor did not report the pick, the new probe, the move and the screenshot")
    p, n = vec(picked.group(1)), vec(picked.group(2))
    a, m = vec(added.group(2)), vec(moved.group(2))
    name = added.group(1)

    # The pick is on the sphere's surface (the G-buffer's depth, not the node's centre).
    sphere = next(x for x in original["nodes"] if x.get("name") == "chrome_sphere")
    acc = original["accessors"][original["meshes"][sphere["mesh"]]["primitives"][0]["attributes"]["POSITION"]]
    radius = 0.5 * (acc["max"][0] - acc["min"][0])
    dist = math.dist(p, sphere["translation"])
    if abs(dist - radius) > 0.03 * radius:
        fail("picked point %s is %.4f from the sphere's centre; its radius is %.4f" % (p, dist, radius))
    # Placed one unit (the default half-extent) off the surface along the normal.
    want = [p[i] + n[i] for i in range(3)]
    if math.dist(a, want) > 2e-3:
        fail("probe added at %s, expected %s (pick + normal)" % (a, want))
    # The gizmo dragged it along x only.
    if abs(m[1] - a[1]) > 1e-3 or abs(m[2] - a[2]) > 1e-3 or not m[0] > a[0] + 0.05:
        fail("the x-axis drag moved the probe from %s to %s" % (a, m))

    saved = json.load(open(scene))
    nodes = [x for x in saved["nodes"] if x.get("name") == name]
    if len(saved["nodes"]) != len(original["nodes"]) + 1 or len(nodes) != 1:
        fail("the saved scene should have exactly one node more, named %s" % name)
    probe = nodes[0]
    if math.dist(probe.get("translation", [0, 0, 0]), m) > 1e-3:
        fail("saved probe at %s, the editor moved it to %s" % (probe.get("translation"), m))
    ext = probe.get("extensions", {}).get("SPECULUM_reflection_probe")
    # The extents handle on +x made the box wider along x only.
    extents = vec(resized.group(1))
    if not extents[0] > 1.05 or extents[1:] != [1.0, 1.0]:
        fail("the +x extents handle gave extents %s" % extents)
    if not ext or ext.get("kind") != "local_cubemap" or \
            any(abs(a - b) > 1e-3 for a, b in zip(ext.get("extents", []), extents)):
        fail("saved probe extension %s, the editor resized it to %s" % (ext, extents))
    if "SPECULUM_reflection_probe" not in saved.get("extensionsUsed", []):
        fail("extensionsUsed lacks SPECULUM_reflection_probe")
    idx = saved["nodes"].index(probe)
    if idx not in saved["scenes"][saved.get("scene", 0)]["nodes"]:
        fail("the new probe node is not in the scene's roots")

    def chrome(d):
        return next(x for x in d["materials"] if x.get("name") == "chrome")
    r0 = chrome(original)["pbrMetallicRoughness"].get("roughnessFactor", 1.0)
    r1 = chrome(saved)["pbrMetallicRoughness"].get("roughnessFactor", 1.0)
    if r1 != r0:
        fail("chrome roughness %s after the undo; the file had %s" % (r1, r0))
    if saved["nodes"][0].get("extensions", {}).get("VENDOR_unknown") != {"kept": [1, 2, 3]} or \
            saved["asset"].get("extras") != {"note": "unknown content survives"}:
        fail("unknown glTF content was lost in the edit-save cycle")

    # The saved scene through speculum-capture from the same camera: the editor's viewport.
    # As many frames as the editor's reflections history had seen at the screenshot (the colour
    # pyramid reprojects the previous frame: each frame adds a bounce).
    w, h, steady = shot.group(1), shot.group(2), int(shot.group(3))
    cap = os.path.join(out, "capture")
    c = subprocess.run([capture, "--scene", scene, "--camera", "main", "--size", "%sx%s" % (w, h),
                        "--warmup", str(max(0, steady - 1)),
                        "--frames", "1", "--aov", "color", "--out", cap], capture_output=True, text=True, env=env,
                       timeout=900)
    if c.returncode != 0:
        print(c.stdout[-2000:] + c.stderr[-2000:])
        fail("speculum-capture could not render the saved scene")
    d = subprocess.run(["idiff", "-fail", "0.02", "-failpercent", "0.5", "-hardfail", "0.25", "-abs", "-scale", "10",
                        "-o", os.path.join(out, "diff.exr"), os.path.join(cap, "color.0000.png"),
                        os.path.join(out, "view.png")], capture_output=True, text=True)
    print(d.stdout)
    if d.returncode >= 2:
        fail("the editor's viewport differs from speculum-capture of the saved scene (idiff exit %d)" % d.returncode)
    print("OK: picked %s, added %s at %s, moved to %s, saved, viewport == capture" % (p, name, a, m))


if __name__ == "__main__":
    main()
