#!/usr/bin/env python3
"""--path renders one output frame per path frame, each with the frame number in its name, and
the camera really moves (consecutive colour images differ)."""
import json, os, subprocess, sys, tempfile, filecmp

capture, root = sys.argv[1], sys.argv[2]
path = os.path.join(root, "assets/paths/gallery.json")
frames = json.load(open(path))["frames"]
with tempfile.TemporaryDirectory() as out:
    subprocess.run([capture, "--scene", os.path.join(root, "assets/scenes/gallery.gltf"), "--path", path,
                    "--size", "64x36", "--warmup", "0", "--aov", "color,depth", "--out", out],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for i in range(frames):
        for name in (f"color.{i:04d}.png", f"color.{i:04d}.exr", f"depth.{i:04d}.exr"):
            if not os.path.isfile(os.path.join(out, name)):
                sys.exit(f"missing {name}")
    if filecmp.cmp(os.path.join(out, "color.0000.exr"), os.path.join(out, f"color.{frames - 1:04d}.exr"), shallow=False):
        sys.exit("the first and last path frames are identical: the camera did not move")
    timings = json.load(open(os.path.join(out, "timings.json")))
    if timings["frame"]["frames"] != frames:
        sys.exit(f"timings.json counts {timings['frame']['frames']} frames, the path has {frames}")
print(f"ok: {frames} frames written")
