"""Where the generator writes and which scenes it owns: the checks and the regeneration test
walk these lists, so a scene added here is written, checked and compared."""

import os

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCENE_DIR = os.path.join(ROOT, "assets", "scenes")
PATH_DIR = os.path.join(ROOT, "assets", "paths")
ENV_DIR = os.path.join(ROOT, "assets", "env")
PLACEMENT_DIR = os.path.join(ROOT, "assets", "placement")
BLENDER_DIR = os.path.join(ROOT, "assets", "blender")
BLENDER_FILE = "cube_camera_repro.gltf"

SCENES = ("gallery", "cornell_mirrors", "failure_cases", "closed_room", "plain_metals", "mirror_hall",
          "hall_of_mirrors")
SEALED = ("closed_room",)  # no ray from inside, direct or mirrored, may reach the sky
PLAIN = ("plain_metals",)  # no Speculum extension at all, like a plain Blender export
