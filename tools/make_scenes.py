#!/usr/bin/env python3
"""Writes Speculum's procedural test scenes (glTF 2.0) and camera paths.

    python3 tools/make_scenes.py            # write assets/scenes/*.gltf|.bin and assets/paths/*.json
    python3 tools/make_scenes.py --check    # write nothing; validate what is on disk

Standard library only, deterministic (same bytes on every run). Conventions: Y up, meters,
right-handed, counter-clockwise front faces, outward normals; cameras look down local -Z with
+Y up (glTF). Every mesh is built here procedurally; see assets/README.md for the contents.
The code is in tools/scenes/ (the scenes) and tools/speculum_py/ (what the probes tool shares).
"""

import argparse
import sys

# Run as a script, this file's folder (tools/) is on sys.path: both packages import from there.
from scenes.blender import build_blender_repro, check_blender
from scenes.catalog import BLENDER_FILE, SCENES
from scenes.checks import CheckError, check_path, check_scene
from scenes.halls import build_gallery, build_hall_of_mirrors, build_mirror_hall
from scenes.rooms import build_closed_room, build_cornell
from scenes.stages import build_failure_cases, build_plain_metals

# The order the files were always written in (the printout below follows SCENES).
BUILDERS = (build_gallery, build_cornell, build_failure_cases, build_closed_room, build_plain_metals,
            build_blender_repro, build_mirror_hall, build_hall_of_mirrors)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="validate the scenes on disk instead of writing")
    args = ap.parse_args()
    if not args.check:
        for build in BUILDERS:
            build()
        for n in SCENES:
            print("wrote assets/scenes/%s.gltf, .bin and assets/paths/%s.json" % (n, n))
        print("wrote assets/blender/" + BLENDER_FILE)
        return 0
    try:
        for n in SCENES:
            lo, hi = check_scene(n)
            check_path(n, lo, hi)
        check_blender()
    except (CheckError, OSError, KeyError, ValueError, IndexError, TypeError) as e:
        print("check failed: %s" % e, file=sys.stderr)
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
