"""The closed rooms: the Cornell box of mirrors (open at the front) and the sealed room that no
ray from inside, direct or mirrored, may leave."""

import math

from speculum_py.vec import quat_axis_angle
from speculum_py.enums import KIND

from .document import Gltf, add_placed_cmos, write_path
from .materials import LAMP_COLOR, mirror_ext
from .mesh import MeshData, add_room_faces, lapped_room, torus_knot_curve


def blob_radius(base):
    def r(w):
        x, y, z = w
        return base * (1.0 + 0.12 * math.sin(3.0 * x + 0.5) * math.sin(2.0 * y + 1.0)
                       + 0.09 * math.sin(4.0 * z + 2.0 * x)
                       + 0.07 * math.cos(3.0 * y - 2.0 * z))
    return r


def build_cornell():
    """Cornell box 3 m cube, x in [-1.5, 1.5], y in [0, 3], z in [-1.5, 1.5], open towards +z."""
    g = Gltf("cornell_mirrors")
    S, H = 1.5, 3.0
    g.material("cornell.white", (0.73, 0.73, 0.73), 0.0, 0.9)
    g.material("cornell.red", (0.63, 0.065, 0.05), 0.0, 0.9)
    g.material("cornell.green", (0.14, 0.45, 0.091), 0.0, 0.9)
    g.material("area_light.emissive", (0.0, 0.0, 0.0), 0.0, 1.0, emissive=(1.0, 0.85, 0.6), strength=15.0)
    g.material("mirror", (0.95, 0.95, 0.95), 1.0, 0.0, reflections=mirror_ext())
    g.material("blob.mirror", (0.95, 0.93, 0.9), 1.0, 0.0, reflections=mirror_ext(mirrorForSelfReflections=True))
    g.material("knot.gold", (1.0, 0.78, 0.34), 1.0, 0.05, reflections=mirror_ext(mirrorForSelfReflections=True))

    for name, mat, corner, eu, ev, facing in (
            ("wall.floor", "cornell.white", (-S, 0, -S), (2 * S, 0, 0), (0, 0, 2 * S), (0, 1, 0)),
            ("wall.ceiling", "cornell.white", (-S, H, -S), (2 * S, 0, 0), (0, 0, 2 * S), (0, -1, 0)),
            ("wall.back", "cornell.white", (-S, 0, -S), (2 * S, 0, 0), (0, H, 0), (0, 0, 1)),
            ("wall.left", "cornell.red", (-S, 0, -S), (0, 0, 2 * S), (0, H, 0), (1, 0, 0)),
            ("wall.right", "cornell.green", (S, 0, -S), (0, 0, 2 * S), (0, H, 0), (-1, 0, 0))):
        m = MeshData()
        m.quad(corner, eu, ev, facing=facing)
        g.object(name, m, mat)
    m = MeshData()
    m.quad((-0.4, H - 0.005, -0.4), (0.8, 0, 0), (0, 0, 0.8), facing=(0, -1, 0))
    g.object("area_light", m, "area_light.emissive")

    m = MeshData()
    m.uv_sphere(0.45, 80, 40)
    g.object("mirror_sphere", m, "mirror", translation=(-0.95, 0.45, -0.3))

    m = MeshData()
    sag = m.dish(0.6, 0.7, 0.03, 16, 96)
    clearance = sag + 0.03 + 0.6 * math.sin(math.radians(10.0)) + 0.02
    g.object("concave_mirror", m, "mirror", translation=(0.0, 2.05, -S + clearance),
             rotation=quat_axis_angle((1, 0, 0), 10.0))

    m = MeshData()
    m.star_shaped(blob_radius(0.4), 112, 56)
    lo, _ = m.bounds()
    g.object("blob", m, "blob.mirror", translation=(0.95, -lo[1] + 0.005, -0.3),
             rotation=quat_axis_angle((0, 1, 0), 20.0))

    m = MeshData()
    m.torus(0.34, 0.11, 80, 32)
    g.object("mirror_torus", m, "mirror", translation=(0.0, 0.11, 0.4),
             rotation=quat_axis_angle((1, 0, 0), -90.0))  # lying flat

    m = MeshData()
    m.tube(torus_knot_curve(2, 3, 0.15), 0.07, 640, 16)
    g.object("torus_knot", m, "knot.gold", translation=(0.0, 0.75, -0.85))

    g.light("ceiling_lamp", "point", 12.0, LAMP_COLOR, position=(0.0, H - 0.2, 0.0))

    # Probe: the box's interior (3 m cube) as the proxy; the open +z side is the proxy's front
    # face, where rays read the room's outside as the capture saw it. Captured at the box's
    # centre (0, 1.5, 0): 0.26 m above the knot's top (y 1.24), 0.75 m from the knot and 1.3 m
    # from the dish. Blend 0.25 m, not the usual 0.5: the box is only 3 m across, so 0.5 m
    # would be a third of it. 128 texels a face: 2.3 cm a texel on the walls 1.5 m away, and the
    # curved mirrors (all but the dish convex) minify what they show.
    g.box_probe("reflection_probe.box", (0.0, H / 2, 0.0), [S, H / 2, S], 0.25, 128)

    g.camera("main", (0.0, 1.9, 3.0), (0.0, 0.9, -0.5))
    g.camera("sphere_close", (-0.2, 1.1, 0.5), (-0.95, 0.45, -0.3))
    g.camera("concave_close", (0.55, 1.6, -0.3), (0.0, 2.05, -1.45))
    g.camera("knot_close", (0.35, 1.0, 0.55), (0.0, 0.75, -0.85))
    g.camera("blob_close", (0.2, 1.05, 0.45), (0.95, 0.5, -0.3))
    add_placed_cmos(g)
    g.write({"environment": "../env/interior.exr", "exposure": 0.4})

    write_path("cornell_mirrors", [
        ((-1.2, 1.4, 4.6), (0.0, 1.0, 0.0)),
        ((0.0, 1.2, 3.6), (0.0, 0.9, 0.0)),
        ((1.2, 1.4, 4.6), (0.0, 1.0, 0.0)),
    ])


def build_closed_room():
    """Sealed room 8 m (x) x 3 m (y) x 6 m (z): x in [-4, 4], y in [0, 3], z in [-3, 3]."""
    g = Gltf("closed_room")
    W, H, D = 4.0, 3.0, 3.0
    # Each face of the room its own saturated colour, so a reflection that reads the sky (or the
    # wrong wall) instead of the room is a gross error wherever it happens, not a shade off.
    walls = {"back": ("wall.red", (0.7, 0.06, 0.05)), "left": ("wall.green", (0.08, 0.5, 0.1)),
             "right": ("wall.blue", (0.06, 0.12, 0.7)), "front": ("wall.yellow", (0.8, 0.65, 0.06))}
    for mat, rgb in walls.values():
        g.material(mat, rgb, 0.0, 0.8)
    g.material("ceiling.white", (0.8, 0.8, 0.78), 0.0, 0.9)
    # Glossy dielectric floor (roughness 0.1, F0 0.04) in 1 m tiles: the dark tiles show the
    # reflections, the light ones the diffuse shading, and the tile edges show in every mirror
    # where box projection puts the floor.
    g.material("floor.tile_dark", (0.04, 0.04, 0.05), 0.0, 0.1, reflections=mirror_ext())
    g.material("floor.tile_light", (0.55, 0.55, 0.52), 0.0, 0.1, reflections=mirror_ext())
    g.material("chrome", (0.95, 0.95, 0.95), 1.0, 0.0, reflections=mirror_ext())
    g.material("copper.glossy", (0.95, 0.64, 0.54), 1.0, 0.25, reflections=mirror_ext())
    g.material("steel.polished", (0.56, 0.57, 0.58), 1.0, 0.1, reflections=mirror_ext())
    g.material("plastic.orange", (0.9, 0.3, 0.04), 0.0, 0.15, reflections=mirror_ext())
    g.material("pedestal.white", (0.75, 0.75, 0.72), 0.0, 0.7)
    g.material("panel.emissive", (0.0, 0.0, 0.0), 0.0, 1.0, emissive=(1.0, 0.95, 0.85), strength=6.0)

    # Every face runs LAP past the interior's edges (lapped_room): no ray out to the sky at a corner.
    LAP = 0.02
    add_room_faces(g, lapped_room(W, H, D, LAP), [(side, "wall." + side, walls[side][0])
                                                  for side in ("back", "front", "left", "right")]
                   + [("ceiling", "ceiling", "ceiling.white")])
    # floor: 8 x 6 tiles of 1 m, the outer ring stretched by LAP
    xs = [-W - LAP] + [-W + i for i in range(1, 8)] + [W + LAP]
    zs = [-D - LAP] + [-D + i for i in range(1, 6)] + [D + LAP]
    for parity, mat in ((0, "floor.tile_dark"), (1, "floor.tile_light")):
        m = MeshData()
        for i in range(8):
            for j in range(6):
                if (i + j) % 2 == parity:
                    m.quad((xs[i], 0.0, zs[j]), (xs[i + 1] - xs[i], 0, 0), (0, 0, zs[j + 1] - zs[j]),
                           facing=(0, 1, 0))
        g.object(mat, m, mat)
    # lights: an emissive ceiling panel 1.6 x 1 m (5 mm under the ceiling, seen in every mirror)
    # and a 0.3 x 1.4 m light strip on the green wall, plus two 18 cd point lamps that do the
    # shading and shadows (walls 2-3 m away get 2-4 lx, radiance 0.3-0.6 on the coloured walls).
    m = MeshData()
    m.quad((-0.8, H - 0.005, -0.5), (1.6, 0, 0), (0, 0, 1.0), facing=(0, -1, 0))
    g.object("ceiling_panel", m, "panel.emissive")
    m = MeshData()
    m.quad((-W + 0.005, 1.0, -0.15), (0, 0, 0.3), (0, 1.4, 0), facing=(1, 0, 0))
    g.object("wall_strip", m, "panel.emissive")
    g.light("lamp.left", "point", 18.0, LAMP_COLOR, position=(-1.8, 2.7, 0.8))
    g.light("lamp.right", "point", 18.0, LAMP_COLOR, position=(1.8, 2.7, -0.8))

    # things to reflect and to reflect in, all within 2 m of the centre
    m = MeshData()
    m.uv_sphere(0.6, 64, 32)
    g.object("chrome_sphere", m, "chrome", translation=(-1.3, 0.6, -0.9))
    m = MeshData()
    m.uv_sphere(0.45, 48, 24)
    g.object("copper_sphere", m, "copper.glossy", translation=(1.4, 0.45, -1.3))
    m = MeshData()
    m.torus(0.4, 0.12, 64, 24)
    g.object("steel_torus", m, "steel.polished", translation=(0.6, 0.52, 0.2),
             rotation=quat_axis_angle((0, 1, 0), 35.0))
    m = MeshData()
    m.box((0.0, 0.45, 0.0), (0.3, 0.45, 0.3))
    g.object("pedestal", m, "pedestal.white", translation=(0.1, 0.0, -2.0))
    m = MeshData()
    m.uv_sphere(0.3, 48, 24)
    g.object("plastic_sphere", m, "plastic.orange", translation=(0.1, 1.2, -2.0))

    # Probe: the room's interior exactly (half 4 x 1.5 x 3), captured from its centre
    # (0, 1.5, 0): 0.46 m above the torus's top (y 1.04) and 0.7 m from it, 1.2 m from the chrome
    # sphere. Nothing in the room is
    # outside the proxy, so every reflected ray should read room, never sky.
    g.box_probe("reflection_probe.room", (0.0, H / 2, 0.0), [W, H / 2, D], 0.5, 128)
    # A planar probe on the glossy tile floor (issue 24): what `speculum-probes place --budget-db
    # 30 --views main` proposes for it (a 48 m^2 flat reflector, 47% of the reflected weight).
    # The box probe cannot show the floor's reflections of the spheres and the torus (their
    # undersides, which screen space never sees): mirror band 16.2 -> 20.6 dB on main, 18.6 ->
    # 21.7 on sphere_close, 17.1 -> 17.8 on back_corner (modules/reflections/MEASUREMENTS.md).
    g.probe("planar.floor", (0.0, 0.0, 0.0), kind=KIND.planar, extents=[W, D])

    g.camera("main", (0.3, 1.7, 2.6), (-0.3, 0.7, -1.2))
    g.camera("sphere_close", (-0.4, 1.15, 0.45), (-1.3, 0.6, -0.9))
    # from the red wall's corner back towards the yellow wall: what main has behind it
    g.camera("back_corner", (-3.2, 1.6, -2.4), (0.4, 0.6, 0.6))
    # The environment only feeds the SH ambient (both renderers add it); no ray sees it.
    # Exposure: the views averaged 0.58 (main), 0.64 (sphere_close) and 0.85 (back_corner) in
    # linear radiance at exposure 1; 0.5 brings main to 0.29.
    g.write({"environment": "../env/interior.exr", "exposure": 0.5})

    write_path("closed_room", [
        ((2.8, 1.6, 2.4), (-0.6, 0.7, -1.2)),
        ((0.0, 1.5, 2.6), (-0.5, 0.7, -1.2)),
        ((-2.8, 1.6, 2.3), (-0.4, 0.6, -1.2)),
    ])
