"""Speculum's procedural test scenes (glTF 2.0) and camera paths, written and checked by
tools/make_scenes.py. Split by what changes together: mesh.py and document.py are the glTF
building kit, materials.py the shared looks, halls.py, rooms.py, stages.py and blender.py one
family of scenes each, checks.py what every written scene must pass."""
