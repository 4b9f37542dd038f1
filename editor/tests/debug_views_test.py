#!/usr/bin/env python3
"""Every debug view of every module the editor hosts (what its Debug view menu lists, from each
module's ModuleInfo) renders in the viewport with validation on, and each one that is not
`none` changes the picture; `none` gives the plain picture back. Debug views are not saved.

debug_views_test.py EDITOR SOURCE_DIR OUT_DIR
"""
import json
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from editor_test_support import copy_gallery, run_script  # noqa: E402


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def differs(a, b):
    # idiff: 0 same within -fail on all but -failpercent of the pixels, 1 warning, 2 failure.
    r = subprocess.run(["idiff", "-fail", "0.05", "-failpercent", "1", a, b], capture_output=True, text=True)
    return r.returncode >= 2


def main():
    editor, source, out = sys.argv[1:4]
    scene = copy_gallery(source, out)
    plain = os.path.join(out, "plain.png")
    views = os.path.join(out, "views")
    script = [{"camera": "main"}, {"wait": 2}, {"screenshot": plain}, {"each_debug_view": views},
              {"action": "pixel_inspector"}, {"hover": [590, 270]}, {"wait": 1}, {"action": "save"},
              {"action": "quit"}]
    path = os.path.join(out, "script.json")
    json.dump(script, open(path, "w"))
    log = run_script(editor, scene, path, out, 3000)
    shots = re.findall(r"written to (\S+/views/(\S+)\.(\S+)\.png)", log)
    names = ["%s.%s" % (m, v) for _, m, v in shots]
    for want in ("reflections.none", "reflections.method", "reflections.coverage", "probes.influence", "probes.winner"):
        if want not in names:
            fail("no picture of the debug view %s (got %s)" % (want, names))
    for file, module, view in shots:
        if view == "none":
            if differs(plain, file):
                fail("%s: the view 'none' is not the plain picture" % file)
        elif not differs(plain, file):
            fail("%s: the debug view %s.%s does not change the picture" % (file, module, view))
    if os.path.exists(os.path.join(out, "scenes", "gallery.settings.json")):
        fail("a debug view was saved with the scene")
    print("OK: %d debug views: %s" % (len(names), ", ".join(names)))


if __name__ == "__main__":
    main()
