"""The halls: the gallery (roughness bands, curved mirrors, a window and a skylight), the
mirror hall (two facing wall mirrors) and the sample game's hall of mirrors."""

import math

from speculum_py.enums import KIND
from speculum_py.vec import quat_axis_angle, quat_mul

from .document import Gltf, add_placed_cmos, write_path
from .materials import LAMP_COLOR, SUN_COLOR, mirror_ext
from .mesh import MeshData, add_room_faces, lapped_room


def build_gallery():
    """Hall 12 m (x) x 5 m (y) x 8 m (z): x in [-6, 6], y in [0, 5], z in [-4, 4]."""
    g = Gltf("gallery")
    W, H, D = 6.0, 5.0, 4.0
    g.material("wall.white", (0.8, 0.8, 0.78), 0.0, 0.9)
    for band, rough in (("0", 0.0), ("0.1", 0.1), ("0.3", 0.3), ("0.6", 0.6)):
        g.material("floor.band_" + band, (0.6, 0.6, 0.6), 1.0, rough, reflections=mirror_ext())
    g.material("chrome", (0.95, 0.95, 0.95), 1.0, 0.0, reflections=mirror_ext())
    g.material("concave_mirror", (0.95, 0.95, 0.95), 1.0, 0.0, reflections=mirror_ext())
    g.material("mirror_frame.dark", (0.05, 0.05, 0.05), 0.0, 0.5)
    g.material("window.emissive", (0.0, 0.0, 0.0), 0.0, 1.0, emissive=(1.0, 1.0, 0.875), strength=8.0)
    pillar_colors = {"red": (0.8, 0.06, 0.05), "green": (0.08, 0.6, 0.1),
                     "blue": (0.05, 0.12, 0.8), "yellow": (0.85, 0.7, 0.05)}
    for c, rgb in pillar_colors.items():
        g.material("pillar." + c, rgb, 0.0, 0.7)

    _gallery_room(g, W, H, D)

    # chrome sphere resting on the floor, straddling bands 0 and 0.1
    m = MeshData()
    m.uv_sphere(0.8, 96, 48)
    g.object("chrome_sphere", m, "chrome", translation=(-3.0, 0.8, -1.2))

    # chrome torus standing upright, turned 30 degrees
    m = MeshData()
    m.torus(0.55, 0.16, 96, 48)
    g.object("chrome_torus", m, "chrome", translation=(1.6, 0.71, -1.0),
             rotation=quat_axis_angle((0, 1, 0), -30.0))

    # concave paraboloid mirror on the far wall, tilted 8 degrees down towards the room
    m = MeshData()
    sag = m.dish(0.9, 1.4, 0.03, 20, 128)
    # Keep the whole back shell in front of the wall: sag + shell + the tilted rim + 2 cm.
    clearance = sag + 0.03 + 0.9 * math.sin(math.radians(8.0)) + 0.02
    g.object("concave_mirror", m, "concave_mirror", translation=(-0.6, 2.2, -D + clearance),
             rotation=quat_axis_angle((1, 0, 0), 8.0))

    # pillars (floor to ceiling), one shared cylinder geometry
    m = MeshData()
    m.cylinder(0.3, H, 32, caps=False)
    for c, (x, z) in (("red", (-4.8, -3.0)), ("green", (5.2, -3.1)), ("blue", (-4.8, 2.6)), ("yellow", (4.8, 2.6))):
        g.object("pillar." + c, m, "pillar." + c, translation=(x, 0.0, z), geometry_key="pillar")

    # lights: sun through the skylight, two warm ceiling lamps
    g.light("sun", "directional", 4.0, SUN_COLOR, direction=(0.35, -1.0, -0.3))
    g.light("lamp.left", "point", 35.0, LAMP_COLOR, position=(-3.0, 4.3, 1.5))
    g.light("lamp.right", "point", 35.0, LAMP_COLOR, position=(3.0, 4.3, -1.5))

    # Probe: the box proxy is the hall's interior (12 x 5 x 8 m), so box projection puts every
    # wall, the floor and the ceiling where they are; captured from the hall's centre (0, 2.5, 0),
    # 2 m from the nearest object (the torus, top at y 1.42), so none fills a face. The far-wall
    # opening and the skylight are holes in the proxy's faces: rays that leave through them read
    # the sky the capture saw there. No second probe: the hall has no alcove, and a smaller box
    # around the sphere or the dish would put its proxy faces in mid-air (wrong parallax for
    # every wall). 256 texels a face: 0.35 degrees a texel, about one pixel of a 320x180 view
    # (yfov 0.95 rad / 180 = 0.30 degrees), for the mirror floor and sphere.
    g.box_probe("reflection_probe.hall", (0.0, H / 2, 0.0), [W, H / 2, D], 0.5, 256)
    # A planar probe on the whole floor (issue 24): its four bands are one plane, each read at
    # its roughness's mip. The floor's reflection of the chrome sphere's underside, which no
    # camera sees and the box probe puts on the far wall, was a black hole in the main view, and
    # screen space's false hits drew sawtooth streaks beside the pillar's and the torus's.
    g.probe("planar.floor", (0.0, 0.0, 0.0), kind=KIND.planar, extents=[W, D])

    g.camera("main", (0.5, 1.7, 3.6), (-0.8, 0.7, -2.0))
    g.camera("floor_grazing", (3.6, 0.3, 3.0), (-3.0, 0.55, -1.6))
    g.camera("sphere_close", (-1.3, 1.25, 0.9), (-3.0, 0.8, -1.2))
    g.camera("concave_mirror", (0.9, 1.5, -1.8), (-0.6, 2.15, -3.85))
    # Exposures put each main view's mean linear radiance near 0.3 so walls and reflections do
    # not clip in the tonemapper (measured from speculum-capture --aov linear at exposure 1).
    add_placed_cmos(g)
    g.write({"environment": "../env/sunset.exr", "exposure": 0.35})

    write_path("gallery", [
        ((-5.0, 1.1, 2.4), (-3.0, 0.6, -1.2)),
        ((-2.0, 0.9, 1.9), (-3.0, 0.7, -1.2)),
        ((1.0, 0.9, 1.9), (0.0, 0.4, -1.6)),
        ((4.2, 1.2, 2.4), (1.6, 0.6, -1.0)),
    ])


def _gallery_room(g, W, H, D):
    """The hall itself: banded floor, walls with the far opening, the ceiling with its skylight
    and the window."""
    # floor: four roughness bands along x, 3 m each
    for i, band in enumerate(("0", "0.1", "0.3", "0.6")):
        m = MeshData()
        x0 = -W + 3.0 * i
        m.quad((x0, 0.0, -D), (3.0, 0.0, 0.0), (0.0, 0.0, 2 * D), 3, 8, facing=(0, 1, 0))
        g.object("floor.band_" + band, m, "floor.band_" + band)

    # far wall (z = -4) with an opening x in [1.6, 4.6], y in [1.0, 3.6] onto the sky
    ox0, ox1, oy0, oy1 = 1.6, 4.6, 1.0, 3.6
    m = MeshData()
    m.quad((-W, 0.0, -D), (ox0 + W, 0, 0), (0, H, 0), facing=(0, 0, 1))          # left of the opening
    m.quad((ox1, 0.0, -D), (W - ox1, 0, 0), (0, H, 0), facing=(0, 0, 1))         # right of it
    m.quad((ox0, 0.0, -D), (ox1 - ox0, 0, 0), (0, oy0, 0), facing=(0, 0, 1))     # below
    m.quad((ox0, oy1, -D), (ox1 - ox0, 0, 0), (0, H - oy1, 0), facing=(0, 0, 1))  # above
    # reveals (wall thickness 0.25 m) so the opening reads as a hole in a real wall
    t = 0.25
    m.quad((ox0, oy0, -D - t), (0, oy1 - oy0, 0), (0, 0, t), facing=(1, 0, 0))   # left jamb
    m.quad((ox1, oy0, -D - t), (0, oy1 - oy0, 0), (0, 0, t), facing=(-1, 0, 0))  # right jamb
    m.quad((ox0, oy0, -D - t), (ox1 - ox0, 0, 0), (0, 0, t), facing=(0, 1, 0))   # sill
    m.quad((ox0, oy1, -D - t), (ox1 - ox0, 0, 0), (0, 0, t), facing=(0, -1, 0))  # head
    g.object("wall.far", m, "wall.white")
    m = MeshData()
    m.quad((-W, 0.0, D), (2 * W, 0, 0), (0, H, 0), facing=(0, 0, -1))  # near wall (z = +4)
    g.object("wall.near", m, "wall.white")
    m = MeshData()
    m.quad((-W, 0.0, -D), (0, 0, 2 * D), (0, H, 0), facing=(1, 0, 0))  # left wall (x = -6)
    g.object("wall.left", m, "wall.white")
    m = MeshData()
    m.quad((W, 0.0, -D), (0, 0, 2 * D), (0, H, 0), facing=(-1, 0, 0))  # right wall (x = +6)
    g.object("wall.right", m, "wall.white")

    # ceiling (y = 5, faces down) with a skylight x in [-1.5, 1.5], z in [-1, 1]
    sx0, sx1, sz0, sz1 = -1.5, 1.5, -1.0, 1.0
    m = MeshData()

    def ceil(x0, x1, z0, z1):
        m.quad((x0, H, z0), (0, 0, z1 - z0), (x1 - x0, 0, 0), facing=(0, -1, 0))
    ceil(-W, sx0, -D, D)
    ceil(sx1, W, -D, D)
    ceil(sx0, sx1, -D, sz0)
    ceil(sx0, sx1, sz1, D)
    g.object("ceiling", m, "wall.white")

    # window: bright emissive panel on the left wall
    m = MeshData()
    m.quad((-W + 0.02, 1.2, -1.3), (0, 0, 2.6), (0, 2.0, 0), facing=(1, 0, 0))
    g.object("window", m, "window.emissive")


def build_mirror_hall():
    """Hall 6 m (x) x 3 m (y) x 5 m (z): x in [-3, 3], y in [0, 3], z in [-2.5, 2.5], two wall
    mirrors facing each other across x (the nested reflections of CMO self-reflections), a
    glossy red ball and a yellow pillar between them, one CMO and one local probe."""
    g = Gltf("mirror_hall")
    W, H, D = 3.0, 3.0, 2.5
    g.material("hall.floor", (0.45, 0.45, 0.42), 0.0, 0.8)
    g.material("hall.ceiling", (0.8, 0.8, 0.78), 0.0, 0.9)
    g.material("hall.blue", (0.15, 0.25, 0.6), 0.0, 0.85)
    g.material("hall.beige", (0.75, 0.6, 0.4), 0.0, 0.85)
    g.material("hall.frame", (0.2, 0.2, 0.2), 0.0, 0.7)
    g.material("hall.mirror", (0.95, 0.95, 0.95), 1.0, 0.0, reflections=mirror_ext(mirrorForSelfReflections=True))
    g.material("ball.red", (0.8, 0.06, 0.05), 0.0, 0.2, reflections=mirror_ext())
    g.material("pillar.yellow", (0.85, 0.65, 0.08), 0.0, 0.6)
    add_room_faces(g, lapped_room(W, H, D, 0.02), (
        ("floor", "hall.floor", "hall.floor"), ("ceiling", "hall.ceiling", "hall.ceiling"),
        ("back", "hall.back", "hall.blue"), ("front", "hall.front", "hall.beige"),
        ("left", "hall.left", "hall.frame"), ("right", "hall.right", "hall.frame")))
    # The mirrors: 4 m x 2.2 m, 5 cm in front of the side walls.
    for name, x, facing in (("mirror.left", -W + 0.05, (1, 0, 0)), ("mirror.right", W - 0.05, (-1, 0, 0))):
        m = MeshData()
        m.quad((x, 0.4, -2.0), (0, 0, 4.0), (0, 2.2, 0), facing=facing)
        g.object(name, m, "hall.mirror")
    m = MeshData()
    m.uv_sphere(0.35, 64, 32)
    g.object("ball", m, "ball.red", translation=(-0.6, 0.9, 0.8))
    m = MeshData()
    m.box((0.0, 0.0, 0.0), (0.15, 0.6, 0.15))
    g.object("pillar", m, "pillar.yellow", translation=(0.8, 0.6, -1.2))
    g.light("lamp", "point", 10.0, LAMP_COLOR, position=(0.0, H - 0.3, 0.0))
    # The room as one probe (the fallback under the CMO), and one CMO at the hall's centre,
    # 1.5 m from both mirrors, which it sees whole (self-reflections bounce between them).
    g.box_probe("reflection_probe.hall", (0.0, H / 2, 0.0), [W, H / 2, D], 0.25, 128)
    g.box_probe("cmo.hall", (0.0, 1.5, 0.0), [0.5, 0.5, 0.5], 0.0, 256, kind=KIND.cmo, order=1)
    # A planar probe on the right mirror, the one every camera looks into (issue 24): what
    # `speculum-probes place --budget-db 30 --views facing,highlight_a,highlight_b --bounces 4`
    # proposes (8.8 m^2, nearly all the reflected weight), before any CMO, which then gains
    # nothing. Its mirrored view holds the hall with the left mirror's own reflections (the CMO
    # and the local probe there), the nested corridor a bounce deeper than the CMO alone
    # traced: mirror band facing 20.54 -> 24.29 dB, highlight_a 22.20 -> 27.37, highlight_b
    # 22.37 -> 26.50 (modules/reflections/MEASUREMENTS.md). What it gets wrong: the third level
    # of facing's corridor, the left mirror as the mirrored view sees it, is a dark panel (that
    # view's mirrors read the probes' bake a bounce short, probes.cubes_below), where the
    # reference's corridor goes on. The CMO tests (nested self-reflections, the moving
    # highlight) measure the hall without it. Local +Y the mirror's normal (-x), local x along
    # its 4 m (z), local z down its 2.2 m.
    upright = quat_mul(quat_axis_angle((0, 1, 0), -90.0), quat_axis_angle((1, 0, 0), 90.0))
    g.probe("planar.mirror_right", (W - 0.05, 1.5, 0.0), rotation=upright, kind=KIND.planar, extents=[2.0, 1.1])
    g.camera("main", (-2.2, 1.6, 1.8), (2.95, 1.3, -0.5))
    # Straight into the right mirror: the nested corridor of reflections between the two.
    g.camera("facing", (-1.0, 1.5, 0.3), (W, 1.5, 0.0))
    # The ball is behind these two (screen space cannot see it), in the right mirror; the lamp's
    # highlight on it moves as the camera moves 0.5 m sideways.
    g.camera("highlight_a", (1.0, 1.3, 0.5), (W, 1.0, 0.2))
    g.camera("highlight_b", (1.0, 1.3, 0.0), (W, 1.0, -0.3))
    g.write({"environment": "../env/interior.exr", "exposure": 0.5})
    write_path("mirror_hall", [
        ((-2.2, 1.6, 1.8), (2.95, 1.3, -0.5)),
        ((-1.0, 1.5, 0.3), (2.95, 1.5, 0.0)),
        ((1.0, 1.3, 0.5), (2.95, 1.0, 0.2)),
    ])

def build_hall_of_mirrors():
    """The sample game's level (sample_game/README.md): hall 10 m (x) x 3.5 m (y) x 8 m (z), x in
    [-5, 5], y in [0, 3.5], z in [-4, 4]. A flat wall mirror (x = -5), a chrome ball (convex), a
    concave dish on the east wall, a mirror floor, a partition, one local probe over the hall and
    the CMOs speculum-probes place chose, planar probes on the two flat mirrors; three collectibles (`collectible.N`, extras
    speculum_hidden_primary: seen only in reflections, engine/scene/EXTENSIONS.md)."""
    g = Gltf("hall_of_mirrors")
    W, H, D = 5.0, 3.5, 4.0
    g.material("hall.floor", (0.42, 0.4, 0.36), 0.0, 0.75)
    g.material("hall.ceiling", (0.8, 0.8, 0.78), 0.0, 0.9)
    g.material("hall.teal", (0.12, 0.38, 0.4), 0.0, 0.8)
    g.material("hall.plum", (0.45, 0.18, 0.35), 0.0, 0.8)
    g.material("hall.stone", (0.6, 0.55, 0.48), 0.0, 0.85)
    g.material("hall.mirror", (0.95, 0.95, 0.95), 1.0, 0.0, reflections=mirror_ext(mirrorForSelfReflections=True))
    g.material("floor.mirror", (0.9, 0.9, 0.92), 1.0, 0.04, reflections=mirror_ext())
    g.material("ball.chrome", (0.95, 0.93, 0.9), 1.0, 0.02, reflections=mirror_ext())
    g.material("dish.gold", (1.0, 0.8, 0.45), 1.0, 0.05, reflections=mirror_ext())
    g.material("partition.red", (0.7, 0.12, 0.08), 0.0, 0.6)
    for i, color in enumerate(((0.2, 1.0, 0.35), (1.0, 0.45, 0.1), (0.3, 0.5, 1.0))):
        g.material("gem.%d" % i, color, 0.0, 0.3, emissive=color, strength=6.0)
    add_room_faces(g, lapped_room(W, H, D, 0.02), (
        ("floor", "hall.floor", "hall.floor"), ("ceiling", "hall.ceiling", "hall.ceiling"),
        ("back", "hall.north", "hall.teal"), ("front", "hall.south", "hall.plum"),
        ("left", "hall.west", "hall.stone"), ("right", "hall.east", "hall.stone")))
    # The wall mirror: 4 m x 2.4 m, 5 cm in front of the west wall, beside the partition's nook.
    m = MeshData()
    m.quad((-W + 0.05, 0.3, -3.5), (0, 0, 4.0), (0, 2.4, 0), facing=(1, 0, 0))
    g.object("mirror.west", m, "hall.mirror")
    # The mirror floor: 8 m x 7 m, 4 mm above the floor, a matte border around it.
    m = MeshData()
    m.quad((-4.0, 0.004, -3.5), (8.0, 0, 0), (0, 0, 7.0), facing=(0, 1, 0))
    g.object("floor.mirror", m, "floor.mirror")
    m = MeshData()
    m.uv_sphere(0.9, 48, 24)
    g.object("ball.chrome", m, "ball.chrome", translation=(1.5, 0.9, -1.0))
    # The concave mirror faces west (-x) from the east wall.
    m = MeshData()
    m.dish(1.0, 1.2, 0.05, nr=12, nphi=48)
    g.object("dish.concave", m, "dish.gold", translation=(W - 0.15, 1.6, 1.5), rotation=quat_axis_angle((0, 1, 0), -90))
    m = MeshData()
    m.box((0.0, 0.0, 0.0), (0.1, 1.25, 1.0))
    g.object("partition", m, "partition.red", translation=(-2.0, 1.25, 2.0))
    # Collectibles: seen only in the mirrors (drawn into the probe and the CMOs, not the main view).
    gem = MeshData()
    gem.uv_sphere(0.15, 16, 8)
    for i, pos in enumerate(((-3.5, 1.0, -2.5), (3.0, 1.0, -3.0), (3.5, 1.0, 2.5))):
        mi = g.mesh("collectible.%d" % i, gem, "gem.%d" % i, geometry_key="gem")
        g.node("collectible.%d" % i, pos, mesh=mi, extras={"speculum_hidden_primary": True})
    g.light("lamp.west", "point", 12.0, LAMP_COLOR, position=(-2.5, H - 0.3, 0.0))
    g.light("lamp.east", "point", 12.0, LAMP_COLOR, position=(2.5, H - 0.3, 0.0))
    g.box_probe("reflection_probe.hall", (0.0, H / 2, 0.0), [W, H / 2, D], 0.25, 128)
    # The CMOs speculum-probes place chose for the curved mirrors (assets/placement/hall_of_mirrors.*).
    add_placed_cmos(g)
    # Planar probes on the two flat mirrors (the large flat reflectors the placement tool proposes
    # planar probes for; placed by hand here, on the glass: issue 24). Their mirrored views draw
    # the gems (planar.cpp: a reflection, not the primary view), so a gem shows in the wall mirror
    # wherever screen space would have hit the wall behind it, and the floor mirror stops showing
    # screen space's staircases under the partition and the ball (2026-12-07, stop 60,
    # sample_game/README.md). Cost: each renders only the texels its rectangle covers on screen
    # (probes.planar_crop); the game at 480x270 with low measured 15.9 fps against 15.2 without
    # (medians of four runs each). The wall mirror: local +Y its normal (+x), local x along its
    # 4 m (z), local z down its 2.4 m. The floor mirror: 8 x 7 m, 4 mm up.
    upright = quat_mul(quat_axis_angle((0, 1, 0), 90.0), quat_axis_angle((1, 0, 0), 90.0))
    g.probe("planar.mirror_west", (-W + 0.05, 1.5, -1.5), rotation=upright, kind=KIND.planar, extents=[2.0, 1.2])
    g.probe("planar.floor_mirror", (0.0, 0.004, 0.0), kind=KIND.planar, extents=[4.0, 3.5])
    # The player starts by the west wall, south of the wall mirror, facing the ball.
    g.camera("main", (-3.5, 1.6, 0.3), (1.5, 0.9, -1.0))
    g.camera("overview", (4.5, 3.0, 3.5), (-1.0, 0.5, -1.5))
    g.camera("ball", (-1.0, 1.6, 2.5), (1.5, 0.9, -1.0))
    g.write({"environment": "../env/interior.exr", "exposure": 0.5})
    write_path("hall_of_mirrors", [
        ((-3.5, 1.6, 0.3), (1.5, 0.9, -1.0)),
        ((-1.0, 1.6, 2.5), (1.5, 0.9, -1.0)),
        ((4.5, 3.0, 3.5), (-1.0, 0.5, -1.5)),
    ])
