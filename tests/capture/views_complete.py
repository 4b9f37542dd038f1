#!/usr/bin/env python3
"""Fails when a named camera of a scene in assets/scenes is missing from views.json."""
import glob, json, os, sys

root = sys.argv[1]
listed = {(v["scene"], v["camera"]) for v in json.load(open(os.path.join(root, "tests/capture/views.json")))["views"]}
missing = []
for path in sorted(glob.glob(os.path.join(root, "assets/scenes/*.gltf"))):
    scene = os.path.splitext(os.path.basename(path))[0]
    doc = json.load(open(path))
    for node in doc.get("nodes", []):
        if "camera" in node and (scene, node.get("name")) not in listed:
            missing.append(f"{scene}.{node.get('name')}")
if missing:
    print("cameras without a capture test (add them to tests/capture/views.json):", ", ".join(missing))
    sys.exit(1)
print(f"all {len(listed)} views listed")
