"""Shared by the editor's Python tests."""
import os
import shutil
import subprocess


def copy_gallery(source, out):
    """A fresh OUT with a copy of the gallery scene (scenes/) and its sky (env/), so that the
    editor may save and autosave beside it; returns the scene's path."""
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.join(out, "scenes"))
    os.makedirs(os.path.join(out, "env"))
    shutil.copy(os.path.join(source, "assets/env/sunset.exr"), os.path.join(out, "env"))
    for f in ("gallery.gltf", "gallery.bin"):
        shutil.copy(os.path.join(source, "assets/scenes", f), os.path.join(out, "scenes"))
    return os.path.join(out, "scenes", "gallery.gltf")


def run_script(editor, scene, script_file, out, tail, env=None):
    """The editor on `scene` under a virtual X server, playing `script_file`; returns its log, also
    kept as OUT/editor.log. A failed run prints the log's last `tail` characters and exits 1 (the
    caller's fail() prints the same FAIL line)."""
    r = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x720x24", editor, "--scene", scene,
                        "--script", script_file], capture_output=True, text=True, env=env, timeout=900)
    log = r.stdout + r.stderr
    open(os.path.join(out, "editor.log"), "w").write(log)
    if r.returncode != 0:
        print(log[-tail:])
        print("FAIL: the editor exited %d" % r.returncode)
        raise SystemExit(1)
    return log
