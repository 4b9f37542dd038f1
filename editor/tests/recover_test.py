#!/usr/bin/env python3
"""Unsaved edits come back (issue 14): an editor closed with unsaved edits keeps them in the side
file; the next start says so (scripted runs print a line) and --recover yes loads them, with the
scene itself untouched until the user saves.

recover_test.py EDITOR SOURCE_DIR OUT_DIR
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from editor_test_support import copy_gallery  # noqa: E402


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def run(editor, scene, script, out, name, extra=()):
    path = os.path.join(out, name + ".json")
    json.dump(script, open(path, "w"))
    r = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x720x24", editor, "--scene", scene, "--script", path,
                        *extra], capture_output=True, text=True, timeout=600)
    log = r.stdout + r.stderr
    open(os.path.join(out, name + ".log"), "w").write(log)
    if r.returncode != 0:
        print(log[-3000:])
        fail("%s: the editor exited %d" % (name, r.returncode))
    return log


def main():
    editor, source, out = sys.argv[1:4]
    scene = copy_gallery(source, out)
    side = os.path.join(out, "scenes", "gallery.autosave.glb")
    before = open(scene, "rb").read()

    # Edit without saving, then quit: the edits go to the side file, the scene stays as it was.
    log = run(editor, scene, [{"camera": "main"}, {"click_node": "chrome_sphere"}, {"action": "add_probe"},
                              {"action": "quit"}], out, "edit")
    if not os.path.isfile(side) or "unsaved edits kept in" not in log:
        fail("quitting with unsaved edits wrote no autosave")
    if open(scene, "rb").read() != before:
        fail("the scene changed without a save")

    # The next scripted start says a newer autosave is there, and does not load it by itself.
    log = run(editor, scene, [{"select": "probe.2"}, {"expect_selected": "(nothing)"}, {"action": "quit"}], out, "offer")
    if "is newer than the scene; start with --recover yes" not in log:
        fail("the start did not mention the newer autosave")

    # --recover yes loads it: the probe is back, the document is dirty (unsaved) until a save.
    log = run(editor, scene, [{"select": "probe.2"}, {"expect_selected": "probe.2"}, {"action": "save"},
                              {"action": "quit"}], out, "recover", ["--recover", "yes"])
    if "recovered the autosave" not in log:
        fail("--recover yes did not recover")
    saved = json.load(open(scene))
    if not any(n.get("name") == "probe.2" for n in saved["nodes"]):
        fail("the recovered probe is not in the saved scene")
    if os.path.exists(side):
        fail("the autosave outlived the save")
    print("OK: edits kept on quit, offered on start, recovered and saved")


if __name__ == "__main__":
    main()
