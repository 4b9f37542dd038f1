#!/usr/bin/env python3
"""Fails when a named camera of a scene in assets/scenes is missing from views.json."""
import glob, json, os, sys

root = sys.argv[1]
views = json.load(open(os.path.join(root, "tests/capture/views.json")))["views"]
listed = {(v.get("file", f"assets/scenes/{v['scene']}.gltf"), v["camera"]) for v in views}
missing = []
for path in sorted(glob.glob(os.path.join(root, "assets/scenes/*.gltf")) + glob.glob(os.path.join(root, "assets/blender/*.gltf"))):
    scene = os.path.relpath(path, root)
    doc = json.load(open(path))
    for node in doc.get("nodes", []):
        if "camera" in node and (scene, node.get("name")) not in listed:
            missing.append(f"{scene}.{node.get('name')}")
if missing:
    print("cameras without a capture test (add them to tests/capture/views.json):", ", ".join(missing))
    sys.exit(1)
print(f"all {len(listed)} views listed")
