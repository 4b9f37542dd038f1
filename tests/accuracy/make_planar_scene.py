#!/usr/bin/env python3
"""Writes the planar probe scene (issue 24 part 2; deterministic, standard library only):

    make_planar_scene.py OUT_DIR   ->  OUT_DIR/mirror_floor.gltf, .bin

A sealed room 6 m (x) x 3 m (y) x 5 m (z) with a saturated unlit colour per wall and a sharp
mirror floor (metallic silver, roughness 0): a sphere standing on it in four unlit latitude bands
(white, yellow, cyan, and a dark blue cap at the bottom: its underside, which no camera sees, is
what the floor reflects right under it; screen space cannot see it, a box probe puts it on the
wrong wall), an unlit box and an emissive ceiling panel. Everything that is not a mirror
is unlit (KHR_materials_unlit), as in the issue's unseen room: both renderers then agree on what
every surface emits, and what is left between them is the reflection itself. One box probe for
the room, and one planar probe on the floor (`reflection_probe.floor`, kind planar, extents the
floor's 3 x 2.5 m half sizes). The accuracy tests remove the planar probe to measure what it
adds, and add a CMO above the sphere to test that it never makes the floor's reflection of the
sphere worse (issue 24 part 3).
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))

from scenes.document import Gltf  # noqa: E402
from scenes.materials import mirror_ext  # noqa: E402
from scenes.mesh import MeshData, add_room_faces, lapped_room  # noqa: E402


def main():
    out = sys.argv[1]
    g = Gltf("mirror_floor", folder=out)
    W, H, D = 3.0, 3.0, 2.5
    walls = {"back": ("wall.red", (0.7, 0.06, 0.05)), "left": ("wall.green", (0.08, 0.5, 0.1)),
             "right": ("wall.blue", (0.06, 0.12, 0.7)), "front": ("wall.yellow", (0.8, 0.65, 0.06))}
    for mat, rgb in walls.values():
        g.material(mat, rgb, 0.0, 0.8)
    g.material("ceiling.white", (0.8, 0.8, 0.78), 0.0, 0.9)
    g.material("floor.mirror", (0.9, 0.9, 0.9), 1.0, 0.0, reflections=mirror_ext())
    bands = (("band.white", (0.85, 0.85, 0.85)), ("band.yellow", (0.85, 0.7, 0.1)), ("band.cyan", (0.1, 0.7, 0.75)),
             ("band.blue", (0.08, 0.1, 0.45)))
    for name, rgb in bands:
        g.material(name, rgb, 0.0, 0.9)
    g.material("box.magenta", (0.7, 0.1, 0.6), 0.0, 0.7)
    g.material("panel.emissive", (0.0, 0.0, 0.0), 0.0, 1.0, emissive=(1.0, 0.95, 0.85), strength=6.0)
    LAP = 0.02
    add_room_faces(g, lapped_room(W, H, D, LAP), [(side, "wall." + side, walls[side][0])
                                                  for side in ("back", "front", "left", "right")]
                   + [("ceiling", "ceiling", "ceiling.white"), ("floor", "floor", "floor.mirror")])
    m = MeshData()
    m.quad((-0.8, H - 0.005, -0.5), (1.6, 0, 0), (0, 0, 1.0), facing=(0, -1, 0))
    g.object("ceiling_panel", m, "panel.emissive")
    # The sphere (radius 0.5, on the floor) in latitude bands: polar angle [0, 50), [50, 100),
    # [100, 150) and [150, 180] degrees, one mesh each.
    edges = (0.0, 50.0, 100.0, 150.0, 180.0)
    for (name, _), th0, th1 in zip(bands, edges, edges[1:]):
        def fn(u, v, th0=th0, th1=th1):
            th, ph = math.radians(th0 + v * (th1 - th0)), u * 2.0 * math.pi
            n = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            return tuple(0.5 * c for c in n), n
        m = MeshData()
        m.grid(64, 9, fn)
        g.object("sphere." + name, m, name, translation=(-0.4, 0.5, -0.6))
    m = MeshData()
    m.box((0.0, 0.35, 0.0), (0.35, 0.35, 0.35))
    g.object("box", m, "box.magenta", translation=(1.1, 0.0, -1.2))
    for m in g.doc["materials"]:
        if m["name"] not in ("floor.mirror", "panel.emissive"):
            m.setdefault("extensions", {})["KHR_materials_unlit"] = {}
    g.used.add("KHR_materials_unlit")
    g.box_probe("reflection_probe.room", (0.0, H / 2, 0.0), [W, H / 2, D], 0.5, 128)
    g.probe("reflection_probe.floor", (0.0, 0.0, 0.0), kind="planar", extents=[W, D], blendDistance=0.0,
            shape="box", update="every_frame", order=0)
    g.camera("main", (0.6, 1.6, 2.3), (-0.4, 0.3, -0.6))
    g.camera("low", (0.9, 0.45, 1.8), (-0.4, 0.25, -0.6))
    # No environment: the room is sealed, and the grey default sky feeds only the SH ambient.
    g.write({"exposure": 0.5})


if __name__ == "__main__":
    main()
