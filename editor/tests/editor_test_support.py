"""Shared by the editor's Python tests."""
import os
import shutil


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
