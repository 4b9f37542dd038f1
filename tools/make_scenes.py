#!/usr/bin/env python3
"""Writes Speculum's procedural test scenes (glTF 2.0) and camera paths.

    python3 tools/make_scenes.py            # write assets/scenes/*.gltf|.bin and assets/paths/*.json
    python3 tools/make_scenes.py --check    # write nothing; validate what is on disk

Standard library only, deterministic (same bytes on every run). Conventions: Y up, meters,
right-handed, counter-clockwise front faces, outward normals; cameras look down local -Z with
+Y up (glTF). Every mesh is built here procedurally; see assets/README.md for the contents.
"""

import argparse
import array
import json
import math
import os
import struct
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENE_DIR = os.path.join(ROOT, "assets", "scenes")
PATH_DIR = os.path.join(ROOT, "assets", "paths")
ENV_DIR = os.path.join(ROOT, "assets", "env")

ENUM_MODE = ("off", "screen_space", "probes_only", "local_cubemap_only")
ENUM_KIND = ("local_cubemap", "cmo")
ENUM_SHAPE = ("box", "sphere")
ENUM_UPDATE = ("once", "on_demand", "every_frame", "time_sliced")

# --------------------------------------------------------------------------------------------
# Small vector / quaternion helpers (tuples of floats).


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    n = length(a)
    return (a[0] / n, a[1] / n, a[2] / n) if n > 0 else (0.0, 0.0, 0.0)


def quat_from_matrix(m):
    """Unit quaternion [x, y, z, w] from a 3x3 rotation matrix given as rows m[r][c]."""
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0.0:
        s = math.sqrt(tr + 1.0) * 2.0
        w, x = 0.25 * s, (m[2][1] - m[1][2]) / s
        y, z = (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2.0
        w, x = (m[2][1] - m[1][2]) / s, 0.25 * s
        y, z = (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s
    elif m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2.0
        w, x = (m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s
        y, z = 0.25 * s, (m[1][2] + m[2][1]) / s
    else:
        s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2.0
        w, x = (m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s
        y, z = (m[1][2] + m[2][1]) / s, 0.25 * s
    q = (x, y, z, w)
    n = math.sqrt(sum(c * c for c in q))
    q = tuple(c / n for c in q)
    if q[3] < 0.0:  # canonical sign: w >= 0
        q = tuple(-c for c in q)
    return q


def quat_look_at(eye, target, up=(0.0, 1.0, 0.0)):
    """Rotation whose local -Z points from eye to target, local +Y as close to up as possible."""
    f = normalize(sub(target, eye))
    zaxis = mul(f, -1.0)
    if abs(dot(f, normalize(up))) > 0.999:
        up = (0.0, 0.0, -1.0) if f[1] < 0 else (0.0, 0.0, 1.0)
    xaxis = normalize(cross(up, zaxis))
    yaxis = cross(zaxis, xaxis)
    m = [[xaxis[0], yaxis[0], zaxis[0]], [xaxis[1], yaxis[1], zaxis[1]], [xaxis[2], yaxis[2], zaxis[2]]]
    return quat_from_matrix(m)


def quat_axis_angle(axis, degrees):
    a = normalize(axis)
    h = math.radians(degrees) * 0.5
    s = math.sin(h)
    return (a[0] * s, a[1] * s, a[2] * s, math.cos(h))


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def quat_rotate(q, v):
    x, y, z, w = q
    u = (x, y, z)
    t = mul(cross(u, v), 2.0)
    return add(add(v, mul(t, w)), cross(u, t))


def mat_from_trs(t, r, s):
    """Column-major 4x4 (glTF order) from translation, rotation [x,y,z,w], scale."""
    x, y, z, w = r
    m = [1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0.0,
         2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0.0,
         2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0.0,
         t[0], t[1], t[2], 1.0]
    for c in range(3):
        for rr in range(3):
            m[c * 4 + rr] *= s[c]
    return m


def mat_mul(a, b):
    out = [0.0] * 16
    for c in range(4):
        for r in range(4):
            out[c * 4 + r] = sum(a[k * 4 + r] * b[c * 4 + k] for k in range(4))
    return out


def mat_point(m, p):
    return (m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12],
            m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13],
            m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14])


def mat_dir(m, d):
    return (m[0] * d[0] + m[4] * d[1] + m[8] * d[2],
            m[1] * d[0] + m[5] * d[1] + m[9] * d[2],
            m[2] * d[0] + m[6] * d[1] + m[10] * d[2])


def f32(x):
    """The float32 value nearest x, as a Python float (what ends up in the .bin)."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def r6(x):
    """Rounded for JSON so the files stay readable and deterministic."""
    v = round(float(x), 6)
    return 0.0 if v == 0.0 else v


def r6v(v):
    return [r6(c) for c in v]


# --------------------------------------------------------------------------------------------
# Mesh building.


class MeshData:
    def __init__(self):
        self.pos = []
        self.nrm = []
        self.uv = []
        self.idx = []

    def vertex(self, p, n, uv):
        self.pos.append(tuple(p))
        self.nrm.append(normalize(n))
        self.uv.append(tuple(uv))
        return len(self.pos) - 1

    def tri(self, a, b, c):
        """Adds triangle a,b,c wound counter-clockwise about the vertex normals; drops degenerates."""
        pa, pb, pc = self.pos[a], self.pos[b], self.pos[c]
        g = cross(sub(pb, pa), sub(pc, pa))
        if length(g) < 1e-12:
            return
        n = add(add(self.nrm[a], self.nrm[b]), self.nrm[c])
        if dot(g, n) < 0.0:
            b, c = c, b
        self.idx.extend((a, b, c))

    def grid(self, nu, nv, fn, wrap_u=False, wrap_v=False):
        """Parametric patch: fn(u, v) -> (position, normal) for u, v in [0, 1]."""
        cu = nu if wrap_u else nu + 1
        cv = nv if wrap_v else nv + 1
        base = len(self.pos)
        for j in range(cv):
            for i in range(cu):
                u, v = i / nu, j / nv
                p, n = fn(u, v)
                self.vertex(p, n, (u, v))

        def vid(i, j):
            return base + (j % cv) * cu + (i % cu)

        for j in range(nv):
            for i in range(nu):
                a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
                self.tri(a, b, c)
                self.tri(a, c, d)

    def quad(self, corner, eu, ev, nu=1, nv=1, facing=None):
        """Rectangle corner + u*eu + v*ev; front face (and normal) along cross(eu, ev), or along
        `facing` when given (which must be perpendicular to the rectangle)."""
        n = normalize(cross(eu, ev))
        if facing is not None:
            require(abs(abs(dot(n, normalize(facing))) - 1.0) < 1e-9, "quad facing not perpendicular")
            if dot(n, facing) < 0.0:
                n = mul(n, -1.0)
        self.grid(nu, nv, lambda u, v: (add(add(corner, mul(eu, u)), mul(ev, v)), n))

    def box(self, center, half):
        cx, cy, cz = center
        hx, hy, hz = half
        c = (cx - hx, cy - hy, cz - hz)
        X, Y, Z = (2 * hx, 0, 0), (0, 2 * hy, 0), (0, 0, 2 * hz)
        self.quad(add(c, Z), X, Y)              # +Z
        self.quad(c, Y, X)                      # -Z
        self.quad(add(c, X), Y, Z)              # +X
        self.quad(c, Z, Y)                      # -X
        self.quad(add(c, Y), Z, X)              # +Y
        self.quad(c, X, Z)                      # -Y

    def uv_sphere(self, radius, nu=64, nv=32, center=(0.0, 0.0, 0.0)):
        def fn(u, v):
            th, ph = v * math.pi, u * 2.0 * math.pi
            n = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            return add(center, mul(n, radius)), n
        self.grid(nu, nv, fn)

    def cylinder(self, radius, height, n=32, caps=True):
        """Axis +Y from y=0 to y=height."""
        def side(u, v):
            a = u * 2.0 * math.pi
            nn = (math.cos(a), 0.0, -math.sin(a))
            return (radius * nn[0], v * height, radius * nn[2]), nn
        self.grid(n, 1, side)
        if caps:
            for y, ny in ((height, 1.0), (0.0, -1.0)):
                def cap(u, v, y=y, ny=ny):
                    a = u * 2.0 * math.pi
                    r = radius * (1.0 - v)
                    return (r * math.cos(a), y, -r * math.sin(a)), (0.0, ny, 0.0)
                self.grid(n, 1, cap)

    def torus(self, R, r, nu=96, nv=48):
        """Ring in the local XY plane around the Z axis (stands upright, faces +Z)."""
        def fn(u, v):
            a, b = u * 2.0 * math.pi, v * 2.0 * math.pi
            ring = (math.cos(a), math.sin(a), 0.0)
            n = add(mul(ring, math.cos(b)), (0.0, 0.0, math.sin(b)))
            return add(mul(ring, R), mul(n, r)), n
        self.grid(nu, nv, fn)

    def dish(self, aperture, focal, thickness, nr=24, nphi=96):
        """Paraboloid mirror z = (x^2+y^2)/(4f) - depth, concave side facing +Z (towards the
        viewer), rim at z = 0, a back shell `thickness` behind it and a rim band between them."""
        depth = aperture * aperture / (4.0 * focal)

        def surf(rho, phi, off):
            x, y = rho * math.cos(phi), rho * math.sin(phi)
            return (x, y, rho * rho / (4.0 * focal) - depth - off)

        def inner(u, v):
            rho, phi = v * aperture, u * 2.0 * math.pi
            n = normalize((-rho * math.cos(phi) / (2 * focal), -rho * math.sin(phi) / (2 * focal), 1.0))
            return surf(rho, phi, 0.0), n

        def outer(u, v):
            p, n = inner(u, v)
            return add(p, mul(n, -thickness)), mul(n, -1.0)

        def rim(u, v):
            phi = u * 2.0 * math.pi
            pi, ni = inner(u, 1.0)
            po = add(pi, mul(ni, -thickness))
            radial = (math.cos(phi), math.sin(phi), 0.0)
            return add(mul(pi, 1.0 - v), mul(po, v)), radial

        self.grid(nphi, nr, inner)
        self.grid(nphi, nr, outer)
        self.grid(nphi, 1, rim)
        return depth

    def star_shaped(self, radius_fn, nu=128, nv=64):
        """Surface p = w * radius_fn(w) for unit directions w; normals by finite differences in
        tangent directions (well defined at the poles)."""
        def point(w):
            return mul(w, radius_fn(w))

        def fn(u, v):
            th, ph = v * math.pi, u * 2.0 * math.pi
            w = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            t1 = normalize(cross(w, (0.0, 0.0, 1.0) if abs(w[2]) < 0.9 else (1.0, 0.0, 0.0)))
            t2 = cross(w, t1)
            e = 1e-4
            d1 = sub(point(normalize(add(w, mul(t1, e)))), point(normalize(sub(w, mul(t1, e)))))
            d2 = sub(point(normalize(add(w, mul(t2, e)))), point(normalize(sub(w, mul(t2, e)))))
            n = normalize(cross(d1, d2))
            if dot(n, w) < 0:
                n = mul(n, -1.0)
            return point(w), n
        self.grid(nu, nv, fn)

    def tube(self, curve, radius, nu, nv):
        """Closed tube of constant radius around a closed curve(t), t in [0, 1); parallel
        transported frame with the holonomy twist spread evenly so the seam closes."""
        pts = [curve(i / nu) for i in range(nu)]
        tan = [normalize(sub(pts[(i + 1) % nu], pts[i - 1])) for i in range(nu)]
        t0 = tan[0]
        n0 = normalize(cross(t0, (0.0, 0.0, 1.0) if abs(t0[2]) < 0.9 else (1.0, 0.0, 0.0)))
        frames = [n0]
        for i in range(1, nu + 1):
            t_prev, t_cur = tan[i - 1], tan[i % nu]
            n = frames[-1]
            n = normalize(sub(n, mul(t_cur, dot(n, t_cur))))  # project onto the new normal plane
            frames.append(n)
        # twist: angle from the transported frame back to n0 around t0
        nn = frames[nu]
        b0 = cross(t0, n0)
        twist = math.atan2(dot(nn, b0), dot(nn, n0))
        normals, binormals = [], []
        for i in range(nu):
            t = tan[i]
            a = -twist * i / nu
            n = frames[i]
            b = cross(t, n)
            n2 = add(mul(n, math.cos(a)), mul(b, math.sin(a)))
            normals.append(n2)
            binormals.append(cross(t, n2))

        def fn(u, v):
            i = int(round(u * nu)) % nu
            b = v * 2.0 * math.pi
            d = add(mul(normals[i], math.cos(b)), mul(binormals[i], math.sin(b)))
            return add(pts[i], mul(d, radius)), d
        self.grid(nu, nv, fn, wrap_u=True, wrap_v=True)

    def bounds(self):
        xs = [[f32(p[k]) for p in self.pos] for k in range(3)]
        return [min(c) for c in xs], [max(c) for c in xs]


def torus_knot_curve(p, q, scale):
    def c(t):
        a = t * 2.0 * math.pi
        r = 2.0 + math.cos(q * a)
        return (scale * r * math.cos(p * a), scale * r * math.sin(p * a), -scale * math.sin(q * a))
    return c


# --------------------------------------------------------------------------------------------
# glTF document builder.


REFLECT_EXT = "SPECULUM_reflections"
PROBE_EXT = "SPECULUM_reflection_probe"


class Gltf:
    def __init__(self, name):
        self.name = name
        self.bin = bytearray()
        self.doc = {
            "asset": {"version": "2.0", "generator": "speculum tools/make_scenes.py"},
            "scene": 0,
            "scenes": [{"name": name, "nodes": []}],
            "nodes": [], "meshes": [], "materials": [], "cameras": [],
            "accessors": [], "bufferViews": [],
            "buffers": [{"uri": name + ".bin", "byteLength": 0}],
        }
        self.lights = []
        self.used = set()
        self.material_ids = {}
        self.geometry = {}  # key -> attributes dict + index accessor, for shared accessors

    # binary data
    def _view(self, data, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        off = len(self.bin)
        self.bin.extend(data)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": off, "byteLength": len(data), "target": target})
        return len(self.doc["bufferViews"]) - 1

    def _accessor(self, values, comps, ctype, typ, target, minmax=False):
        if ctype == 5126:
            arr = array.array("f", [c for v in values for c in v])
        else:
            arr = array.array("I", values)
        if sys.byteorder != "little":
            arr.byteswap()
        view = self._view(arr.tobytes(), target)
        acc = {"bufferView": view, "componentType": ctype, "count": len(values), "type": typ}
        if minmax:
            cols = [[f32(v[k]) for v in values] for k in range(comps)]
            acc["min"] = [min(c) for c in cols]
            acc["max"] = [max(c) for c in cols]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def geometry_of(self, key, mesh):
        if key not in self.geometry:
            attrs = {
                "POSITION": self._accessor(mesh.pos, 3, 5126, "VEC3", 34962, minmax=True),
                "NORMAL": self._accessor(mesh.nrm, 3, 5126, "VEC3", 34962),
                "TEXCOORD_0": self._accessor(mesh.uv, 2, 5126, "VEC2", 34962),
            }
            ind = self._accessor(mesh.idx, 1, 5125, "SCALAR", 34963)
            self.geometry[key] = (attrs, ind)
        return self.geometry[key]

    # objects
    def material(self, name, base=(0.8, 0.8, 0.8), metallic=0.0, roughness=0.9, emissive=None,
                 strength=None, reflections=None, double_sided=False):
        m = {"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": [r6(c) for c in base] + [1.0],
            "metallicFactor": r6(metallic), "roughnessFactor": r6(roughness)}}
        if emissive is not None:
            m["emissiveFactor"] = r6v(emissive)
            if strength is not None and strength != 1.0:
                m.setdefault("extensions", {})["KHR_materials_emissive_strength"] = {"emissiveStrength": r6(strength)}
                self.used.add("KHR_materials_emissive_strength")
        if reflections is not None:
            m.setdefault("extensions", {})[REFLECT_EXT] = reflections
            self.used.add(REFLECT_EXT)
        if double_sided:
            m["doubleSided"] = True
        self.doc["materials"].append(m)
        self.material_ids[name] = len(self.doc["materials"]) - 1
        return self.material_ids[name]

    def mesh(self, name, mesh, material, geometry_key=None):
        attrs, ind = self.geometry_of(geometry_key or name, mesh)
        mat = material if isinstance(material, int) else self.material_ids[material]
        self.doc["meshes"].append({"name": name, "primitives": [
            {"attributes": dict(attrs), "indices": ind, "material": mat, "mode": 4}]})
        return len(self.doc["meshes"]) - 1

    def node(self, name, translation=None, rotation=None, scale=None, root=True, **extra):
        n = {"name": name}
        if translation is not None and any(abs(c) > 0 for c in translation):
            n["translation"] = r6v(translation)
        if rotation is not None and abs(rotation[3]) < 1.0 - 1e-12:
            n["rotation"] = [round(c, 9) for c in rotation]
        if scale is not None and any(abs(c - 1.0) > 0 for c in scale):
            n["scale"] = r6v(scale)
        n.update(extra)
        self.doc["nodes"].append(n)
        idx = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(idx)
        return idx

    def object(self, name, mesh, material, translation=None, rotation=None, geometry_key=None):
        m = self.mesh(name, mesh, material, geometry_key)
        return self.node(name, translation, rotation, mesh=m)

    def camera(self, name, eye, target, yfov=0.95):
        self.doc["cameras"].append({"name": name, "type": "perspective",
                                    "perspective": {"yfov": yfov, "znear": 0.05}})
        return self.node(name, eye, quat_look_at(eye, target), camera=len(self.doc["cameras"]) - 1,
                         extras={"target": r6v(target)})

    def light(self, name, kind, intensity, color=(1.0, 1.0, 1.0), position=None, direction=None):
        self.lights.append({"name": name, "type": kind, "color": r6v(color), "intensity": r6(intensity)})
        self.used.add("KHR_lights_punctual")
        rot = None
        if direction is not None:
            rot = quat_look_at((0.0, 0.0, 0.0), direction)
        return self.node(name, position, rot, extensions={"KHR_lights_punctual": {"light": len(self.lights) - 1}})

    def probe(self, name, center, **fields):
        self.used.add(PROBE_EXT)
        return self.node(name, center, extensions={PROBE_EXT: fields})

    def write(self, extras):
        d = self.doc
        d["scenes"][0]["extras"] = extras
        if self.lights:
            d["extensions"] = {"KHR_lights_punctual": {"lights": self.lights}}
        if self.used:
            d["extensionsUsed"] = sorted(self.used)
        while len(self.bin) % 4:
            self.bin.append(0)
        d["buffers"][0]["byteLength"] = len(self.bin)
        order = ["asset", "extensionsUsed", "extensions", "scene", "scenes", "nodes", "cameras", "meshes",
                 "materials", "accessors", "bufferViews", "buffers"]
        out = {k: d[k] for k in order if k in d}
        os.makedirs(SCENE_DIR, exist_ok=True)
        with open(os.path.join(SCENE_DIR, self.name + ".gltf"), "w", encoding="utf-8", newline="\n") as f:
            json.dump(out, f, indent=1, sort_keys=False)
            f.write("\n")
        with open(os.path.join(SCENE_DIR, self.name + ".bin"), "wb") as f:
            f.write(bytes(self.bin))


PLACEMENT_DIR = os.path.join(ROOT, "assets", "placement")


def add_placed_cmos(g):
    """The CMOs `speculum-probes place` proposed for this scene (assets/placement/NAME.placement.json,
    its report, committed beside its markdown), as nodes: the generator writes what the tool
    measured, so a regenerated scene keeps them."""
    path = os.path.join(PLACEMENT_DIR, g.name + ".placement.json")
    if not os.path.isfile(path):
        return
    with open(path, "r", encoding="utf-8") as f:
        report = json.load(f)
    for i, c in enumerate(report["final"]["cmos"]):
        g.probe("cmo.placed%d" % i, tuple(c["pos"]), kind="cmo", shape="box", extents=[0.25, 0.25, 0.25],
                blendDistance=0.0, resolution=c["resolution"], update="once", order=c["order"])


def mirror_ext(**over):
    e = {"mode": "screen_space", "maxScreenSpaceRoughness": 0.6}
    e.update(over)
    return e


def write_path(name, keys, frames=24, fov_deg=55):
    os.makedirs(PATH_DIR, exist_ok=True)
    doc = {"scene": name, "frames": frames, "fov_deg": fov_deg,
           "keys": [{"eye": r6v(e), "target": r6v(t)} for e, t in keys]}
    with open(os.path.join(PATH_DIR, name + ".json"), "w", encoding="utf-8", newline="\n") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


# --------------------------------------------------------------------------------------------
# Scenes.

SUN_COLOR = (1.0, 0.93, 0.82)
LAMP_COLOR = (1.0, 0.86, 0.7)


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
    g.probe("reflection_probe.hall", (0.0, H / 2, 0.0), kind="local_cubemap", shape="box",
            extents=[W, H / 2, D], blendDistance=0.5, resolution=256, update="once", order=0)

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
    g.probe("reflection_probe.box", (0.0, H / 2, 0.0), kind="local_cubemap", shape="box",
            extents=[S, H / 2, S], blendDistance=0.25, resolution=128, update="once", order=0)

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
    LAP = 0.02
    for name, mat, corner, eu, ev, facing in (
            ("hall.floor", "hall.floor", (-W - LAP, 0, -D - LAP), (2 * W + 2 * LAP, 0, 0), (0, 0, 2 * D + 2 * LAP), (0, 1, 0)),
            ("hall.ceiling", "hall.ceiling", (-W - LAP, H, -D - LAP), (2 * W + 2 * LAP, 0, 0), (0, 0, 2 * D + 2 * LAP), (0, -1, 0)),
            ("hall.back", "hall.blue", (-W - LAP, -LAP, -D), (2 * W + 2 * LAP, 0, 0), (0, H + 2 * LAP, 0), (0, 0, 1)),
            ("hall.front", "hall.beige", (-W - LAP, -LAP, D), (2 * W + 2 * LAP, 0, 0), (0, H + 2 * LAP, 0), (0, 0, -1)),
            ("hall.left", "hall.frame", (-W, -LAP, -D - LAP), (0, 0, 2 * D + 2 * LAP), (0, H + 2 * LAP, 0), (1, 0, 0)),
            ("hall.right", "hall.frame", (W, -LAP, -D - LAP), (0, 0, 2 * D + 2 * LAP), (0, H + 2 * LAP, 0), (-1, 0, 0))):
        m = MeshData()
        m.quad(corner, eu, ev, facing=facing)
        g.object(name, m, mat)
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
    g.probe("reflection_probe.hall", (0.0, H / 2, 0.0), kind="local_cubemap", shape="box",
            extents=[W, H / 2, D], blendDistance=0.25, resolution=128, update="once", order=0)
    g.probe("cmo.hall", (0.0, 1.5, 0.0), kind="cmo", shape="box", extents=[0.5, 0.5, 0.5], blendDistance=0.0,
            resolution=256, update="once", order=1)
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
    the CMOs speculum-probes place chose; three collectibles (`collectible.N`, extras
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
    LAP = 0.02
    for name, mat, corner, eu, ev, facing in (
            ("hall.floor", "hall.floor", (-W - LAP, 0, -D - LAP), (2 * W + 2 * LAP, 0, 0), (0, 0, 2 * D + 2 * LAP), (0, 1, 0)),
            ("hall.ceiling", "hall.ceiling", (-W - LAP, H, -D - LAP), (2 * W + 2 * LAP, 0, 0), (0, 0, 2 * D + 2 * LAP), (0, -1, 0)),
            ("hall.north", "hall.teal", (-W - LAP, -LAP, -D), (2 * W + 2 * LAP, 0, 0), (0, H + 2 * LAP, 0), (0, 0, 1)),
            ("hall.south", "hall.plum", (-W - LAP, -LAP, D), (2 * W + 2 * LAP, 0, 0), (0, H + 2 * LAP, 0), (0, 0, -1)),
            ("hall.west", "hall.stone", (-W, -LAP, -D - LAP), (0, 0, 2 * D + 2 * LAP), (0, H + 2 * LAP, 0), (1, 0, 0)),
            ("hall.east", "hall.stone", (W, -LAP, -D - LAP), (0, 0, 2 * D + 2 * LAP), (0, H + 2 * LAP, 0), (-1, 0, 0))):
        m = MeshData()
        m.quad(corner, eu, ev, facing=facing)
        g.object(name, m, mat)
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
    g.probe("reflection_probe.hall", (0.0, H / 2, 0.0), kind="local_cubemap", shape="box",
            extents=[W, H / 2, D], blendDistance=0.25, resolution=128, update="once", order=0)
    # The CMOs speculum-probes place chose for the curved mirrors (assets/placement/hall_of_mirrors.*).
    add_placed_cmos(g)
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


def build_failure_cases():
    """Open mirror-floor stage, x in [-6, 6], z in [-6, 6], back wall at z = -5.5."""
    g = Gltf("failure_cases")
    g.material("floor.mirror", (0.85, 0.85, 0.85), 1.0, 0.0, reflections=mirror_ext())
    g.material("wall.concrete", (0.45, 0.45, 0.44), 0.0, 0.95)
    g.material("vertical_mirror", (0.95, 0.95, 0.95), 1.0, 0.0, reflections=mirror_ext())
    g.material("post.orange", (1.0, 0.42, 0.05), 0.0, 0.5)
    g.material("occluder.gray", (0.5, 0.5, 0.5), 0.0, 0.8)
    g.material("hidden_box.cyan", (0.05, 0.7, 0.9), 0.0, 0.6)
    g.material("glow.magenta", (0.0, 0.0, 0.0), 0.0, 1.0, emissive=(1.0, 0.2, 0.8), strength=6.0)
    g.material("glow.cyan", (0.0, 0.0, 0.0), 0.0, 1.0, emissive=(0.2, 0.9, 1.0), strength=6.0)
    g.material("glow.warm", (0.0, 0.0, 0.0), 0.0, 1.0, emissive=(1.0, 0.85, 0.55), strength=6.0)
    g.material("glow.overhead", (0.0, 0.0, 0.0), 0.0, 1.0, emissive=(1.0, 0.95, 0.9), strength=10.0)

    m = MeshData()
    m.quad((-6.0, 0.0, -6.0), (12.0, 0, 0), (0, 0, 12.0), 4, 4, facing=(0, 1, 0))
    g.object("floor", m, "floor.mirror")
    m = MeshData()
    m.box((0.0, 1.25, -5.6), (6.0, 1.25, 0.1))
    g.object("wall.back", m, "wall.concrete")

    # vertical mirror facing the main camera
    eye = (0.0, 1.0, 3.2)
    mc = (-2.2, 1.25, -3.0)
    yaw = math.degrees(math.atan2(eye[0] - mc[0], eye[2] - mc[2]))
    m = MeshData()
    m.box((0.0, 0.0, 0.0), (1.0, 1.1, 0.02))
    g.object("vertical_mirror", m, "vertical_mirror", translation=mc, rotation=quat_axis_angle((0, 1, 0), yaw))

    # thin post (5 cm) 0.6 m in front of the back wall
    m = MeshData()
    m.box((0.0, 1.2, 0.0), (0.025, 1.2, 0.025))
    g.object("thin_post", m, "post.orange", translation=(1.0, 0.0, -4.9))

    # occluder hides the cyan box from the main camera; the floor sees it through the gap below
    m = MeshData()
    m.box((2.2, 1.225, -1.0), (0.9, 0.775, 0.06))
    g.object("occluder", m, "occluder.gray")
    m = MeshData()
    m.box((2.3, 0.8, -2.15), (0.3, 0.3, 0.3))
    g.object("hidden_box", m, "hidden_box.cyan")

    # bright objects behind the main camera (seen only in reflections)
    m = MeshData()
    m.box((0.0, 1.0, 0.0), (0.4, 1.0, 0.4))
    for name, mat, x in (("glow_behind.magenta", "glow.magenta", -1.0), ("glow_behind.cyan", "glow.cyan", 0.6),
                         ("glow_behind.warm", "glow.warm", 2.2)):
        g.object(name, m, mat, translation=(x, 0.0, 4.9), geometry_key="glow_totem")
    # bright bar above the top of the main camera's frame; its mirror image is inside the frame
    m = MeshData()
    m.box((0.0, 4.2, -4.8), (2.5, 0.15, 0.15))
    g.object("glow_overhead", m, "glow.overhead")

    g.light("sun", "directional", 3.0, SUN_COLOR, direction=(-0.4, -1.0, -0.3))
    g.light("fill", "point", 25.0, LAMP_COLOR, position=(0.0, 3.0, 1.0))

    # Probe: one box over the stage, the only area there is. Its bottom is the mirror floor
    # (y 0), its back face the back wall's front (z -5.5), its sides the floor's edges (x +-6)
    # and its front face z +5.5, 0.2 m behind the glowing totems (z 4.5..5.3), so the totems
    # that the vertical mirror shows land near where they stand. 5 m high: it holds the
    # overhead bar (y 4.05..4.35) and keeps the centre, the capture point (0, 2.5, 0), clear of
    # everything (0.5 m above the occluder's top and 1.7 m from it, 3.5 m from the mirror).
    # Above 2.5 m the proxy faces are open sky, where box projection only bends the sky a
    # little. No second probe: a smaller box would put proxy faces in the open, and the
    # reflectors (floor, vertical mirror) span the stage.
    g.probe("reflection_probe.stage", (0.0, 2.5, 0.0), kind="local_cubemap", shape="box",
            extents=[6.0, 2.5, 5.5], blendDistance=0.5, resolution=128, update="once", order=0)

    g.camera("main", eye, (0.0, 0.1, -2.0))
    mn = (math.sin(math.radians(yaw)), 0.0, math.cos(math.radians(yaw)))
    g.camera("mirror_front", add(mc, add(mul(mn, 2.6), (0.0, 0.15, 0.0))), mc)
    g.camera("post_grazing", (0.4, 0.3, -2.2), (1.0, 0.7, -4.9))
    g.camera("occluder_side", (4.6, 1.3, 0.6), (2.3, 0.6, -1.6))
    g.write({"environment": "../env/courtyard.exr", "exposure": 0.12})

    write_path("failure_cases", [
        ((0.0, 1.0, 3.2), (0.0, 0.1, -2.0)),
        ((-0.5, 1.1, 1.8), (-2.2, 1.0, -3.0)),
        ((1.0, 0.6, 0.2), (1.0, 0.8, -4.9)),
        ((3.6, 1.0, 0.6), (2.3, 0.6, -1.8)),
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

    # Every face overlaps its neighbours by LAP past the interior's edges (it runs on behind the
    # wall it meets), so no seam or T-junction at a corner lets a ray out to the sky in either
    # renderer; the overlap is behind the other face and never seen from inside.
    LAP = 0.02
    for side, corner, eu, ev, facing in (
            ("back", (-W - LAP, -LAP, -D), (2 * W + 2 * LAP, 0, 0), (0, H + 2 * LAP, 0), (0, 0, 1)),
            ("front", (-W - LAP, -LAP, D), (2 * W + 2 * LAP, 0, 0), (0, H + 2 * LAP, 0), (0, 0, -1)),
            ("left", (-W, -LAP, -D - LAP), (0, 0, 2 * D + 2 * LAP), (0, H + 2 * LAP, 0), (1, 0, 0)),
            ("right", (W, -LAP, -D - LAP), (0, 0, 2 * D + 2 * LAP), (0, H + 2 * LAP, 0), (-1, 0, 0))):
        m = MeshData()
        m.quad(corner, eu, ev, facing=facing)
        g.object("wall." + side, m, walls[side][0])
    m = MeshData()
    m.quad((-W - LAP, H, -D - LAP), (2 * W + 2 * LAP, 0, 0), (0, 0, 2 * D + 2 * LAP), facing=(0, -1, 0))
    g.object("ceiling", m, "ceiling.white")
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
    g.probe("reflection_probe.room", (0.0, H / 2, 0.0), kind="local_cubemap", shape="box",
            extents=[W, H / 2, D], blendDistance=0.5, resolution=128, update="once", order=0)

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


def build_plain_metals():
    """Plain outdoor stand, no Speculum extensions at all: what a Blender user exports. Objects
    on a 16 x 16 m floor (x in [-8, 8], z in [-8, 8]) in front of a low wall at z -3."""
    g = Gltf("plain_metals")
    # Blender's exporter writes doubleSided when backface culling is off, its default.
    ds = dict(double_sided=True)
    g.material("Floor", (0.5, 0.5, 0.5), 0.0, 0.5, **ds)
    g.material("Wall", (0.7, 0.35, 0.2), 0.0, 0.8, **ds)
    g.material("Chrome", (0.95, 0.95, 0.95), 1.0, 0.0, **ds)
    g.material("Gold", (1.0, 0.78, 0.34), 1.0, 0.15, **ds)
    g.material("Copper", (0.95, 0.64, 0.54), 1.0, 0.3, **ds)
    g.material("Aluminium", (0.91, 0.92, 0.92), 1.0, 0.4, **ds)
    g.material("Plastic.Red", (0.8, 0.05, 0.04), 0.0, 0.05, **ds)
    g.material("Plastic.Blue", (0.05, 0.15, 0.7), 0.0, 0.2, **ds)
    g.material("Ceramic.White", (0.85, 0.85, 0.82), 0.0, 0.3, **ds)

    m = MeshData()
    m.quad((-8.0, 0.0, -8.0), (16.0, 0, 0), (0, 0, 16.0), 4, 4, facing=(0, 1, 0))
    g.object("Floor", m, "Floor")
    m = MeshData()
    m.box((0.0, 1.0, -3.1), (4.0, 1.0, 0.1))
    g.object("Wall", m, "Wall")

    m = MeshData()
    m.uv_sphere(0.6, 64, 32)
    g.object("Chrome_Sphere", m, "Chrome", translation=(-0.8, 0.6, 0.0))
    m = MeshData()
    m.uv_sphere(0.45, 48, 24)
    g.object("Gold_Sphere", m, "Gold", translation=(0.7, 0.45, -0.7))
    m = MeshData()
    m.torus(0.45, 0.14, 64, 24)
    g.object("Copper_Torus", m, "Copper", translation=(1.9, 0.59, 0.2),
             rotation=quat_axis_angle((0, 1, 0), -25.0))
    m = MeshData()
    m.cylinder(0.3, 1.2, 32)
    g.object("Aluminium_Cylinder", m, "Aluminium", translation=(-2.3, 0.0, -0.9))
    m = MeshData()
    m.uv_sphere(0.35, 48, 24)
    g.object("Red_Sphere", m, "Plastic.Red", translation=(-1.9, 0.35, 1.0))
    m = MeshData()
    m.box((0.0, 0.25, 0.0), (0.25, 0.25, 0.25))
    g.object("Blue_Cube", m, "Plastic.Blue", translation=(0.2, 0.0, 1.1),
             rotation=quat_axis_angle((0, 1, 0), 20.0))
    m = MeshData()
    m.uv_sphere(0.3, 48, 24)
    g.object("White_Sphere", m, "Ceramic.White", translation=(1.2, 0.3, 1.4))

    g.light("Sun", "directional", 3.0, SUN_COLOR, direction=(-0.5, -1.0, -0.4))

    g.camera("main", (0.3, 1.5, 4.4), (0.0, 0.5, 0.0))
    g.camera("sphere_close", (0.1, 1.0, 1.6), (-0.8, 0.6, 0.0))
    # Exposure: main averaged 1.56 in linear radiance at exposure 1 (speculum-capture --aov
    # linear, 320x180), sphere_close 2.05; 0.18 brings them to 0.28 and 0.37.
    g.write({"environment": "../env/courtyard.exr", "exposure": 0.18})

    write_path("plain_metals", [
        ((-3.0, 1.4, 3.6), (0.0, 0.5, 0.0)),
        ((0.3, 1.5, 4.4), (0.0, 0.5, 0.0)),
        ((3.4, 1.4, 3.4), (0.0, 0.5, 0.0)),
    ])


# --------------------------------------------------------------------------------------------
# Blender-style file (a reproduction of the exporter's output conventions, not a real export).

BLENDER_DIR = os.path.join(ROOT, "assets", "blender")
BLENDER_FILE = "cube_camera_repro.gltf"


def png_bytes(w, h, rgb):
    import zlib

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + bytes(rgb[y * w * 3:(y + 1) * w * 3]) for y in range(h))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def build_blender_repro():
    """Blender 3.6 default scene (Cube, Light, Camera) plus an emissive Plane, written the way
    'Khronos glTF Blender I/O v3.6.27' writes 'glTF Embedded (.gltf)': indent 4 with ' : ',
    Blender's key order, +Y up conversion (x, z, -y), uint16 indices, one tightly packed buffer
    with 4-byte aligned bufferViews carrying targets, custom properties as extras, sampler
    9729/9987, KHR_materials_emissive_strength and KHR_lights_punctual as Blender emits them."""
    import base64
    binbuf = bytearray()
    accessors, views = [], []

    def put(data, target, count, ctype, typ, minmax=None):
        while len(binbuf) % 4:
            binbuf.append(0)
        views.append({"buffer": 0, "byteLength": len(data), "byteOffset": len(binbuf), "target": target})
        binbuf.extend(data)
        a = {"bufferView": len(views) - 1, "componentType": ctype, "count": count}
        if minmax:
            a["max"], a["min"] = minmax[1], minmax[0]
        a["type"] = typ
        accessors.append(a)
        return len(accessors) - 1

    def prim(mesh, material):
        lo, hi = mesh.bounds()
        pos = put(array.array("f", [c for p in mesh.pos for c in p]).tobytes(), 34962, len(mesh.pos), 5126, "VEC3",
                  (lo, hi))
        nrm = put(array.array("f", [c for p in mesh.nrm for c in p]).tobytes(), 34962, len(mesh.nrm), 5126, "VEC3")
        uv = put(array.array("f", [c for p in mesh.uv for c in p]).tobytes(), 34962, len(mesh.uv), 5126, "VEC2")
        ind = put(array.array("H", mesh.idx).tobytes(), 34963, len(mesh.idx), 5123, "SCALAR")
        return {"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}, "indices": ind, "material": material}

    cube = MeshData()
    cube.box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    # Blender's UV unwrap of the default cube is a cross; per-face unit squares are enough here.
    plane = MeshData()
    plane.quad((-1.0, 0.0, -1.0), (2.0, 0, 0), (0, 0, 2.0), facing=(0, 1, 0))
    checker = []
    for y in range(8):
        for x in range(8):
            v = 230 if (x + y) % 2 == 0 else 40
            checker += [v, v, v]
    img = png_bytes(8, 8, checker)

    doc = {
        "asset": {"generator": "Khronos glTF Blender I/O v3.6.27", "version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"color": [1, 1, 1], "intensity": 54.35141306588226, "type": "point", "name": "Light"}]}},
        "scene": 0,
        "scenes": [{"name": "Scene", "nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"extras": {"speculum_reflector": 1, "note": "custom property"}, "mesh": 0, "name": "Cube"},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}, "name": "Light",
             # Blender world rotations converted to Y-up and post-multiplied by the exporter's
             # -90 degrees about X correction for cameras and lights (which look down local -Z).
             "rotation": [-0.28416627645492554, 0.7269423007965088, 0.34203392267227173, 0.5232754945755005],
             "translation": [4.076245307922363, 5.903861999511719, -1.0054539442062378]},
            {"camera": 0, "name": "Camera",
             "rotation": [-0.20997299253940582, 0.3857799470424652, 0.09062844514846802, 0.8937962055206299],
             "translation": [7.358891487121582, 4.958309173583984, 6.925790786743164]},
            {"mesh": 1, "name": "Plane", "translation": [0, -1.0099999904632568, 0], "scale": [4, 4, 4]},
        ],
        "cameras": [{"name": "Camera", "perspective": {
            "aspectRatio": 1.7777777777777777, "yfov": 0.39959652046304894, "zfar": 100,
            "znear": 0.10000000149011612}, "type": "perspective"}],
        "materials": [
            {"doubleSided": True, "name": "Material", "pbrMetallicRoughness": {
                "baseColorTexture": {"index": 0}, "metallicFactor": 1, "roughnessFactor": 0.05000000074505806}},
            {"doubleSided": True, "emissiveFactor": [1, 1, 1],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
             "name": "Emitter", "pbrMetallicRoughness": {
                "baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 0.5}},
        ],
        "meshes": [{"name": "Cube", "primitives": [prim(cube, 0)]},
                   {"name": "Plane", "primitives": [prim(plane, 1)]}],
        "textures": [{"sampler": 0, "source": 0}],
        "images": [{"mimeType": "image/png", "name": "checker",
                    "uri": "data:image/png;base64," + base64.b64encode(img).decode("ascii")}],
        "accessors": accessors,
        "bufferViews": views,
        "samplers": [{"magFilter": 9729, "minFilter": 9987}],
        "buffers": [{"byteLength": len(binbuf),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(binbuf)).decode("ascii")}],
    }
    os.makedirs(BLENDER_DIR, exist_ok=True)
    with open(os.path.join(BLENDER_DIR, BLENDER_FILE), "w", encoding="utf-8", newline="\n") as f:
        f.write(json.dumps(doc, indent=4, separators=(",", " : ")))


# --------------------------------------------------------------------------------------------
# Checks.


class CheckError(Exception):
    pass


def require(cond, msg):
    if not cond:
        raise CheckError(msg)


def finite(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


COMP = {5120: ("b", 1), 5121: ("B", 1), 5122: ("h", 2), 5123: ("H", 2), 5125: ("I", 4), 5126: ("f", 4)}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def read_accessor(doc, buffers, ai):
    acc = doc["accessors"][ai]
    bv = doc["bufferViews"][acc["bufferView"]]
    buf = buffers[bv["buffer"]]
    fmt, size = COMP[acc["componentType"]]
    n = NCOMP[acc["type"]]
    stride = bv.get("byteStride", size * n)
    off = bv.get("byteOffset", 0) + acc.get("byteOffset", 0)
    count = acc["count"]
    need = acc.get("byteOffset", 0) + (stride * (count - 1) + size * n if count else 0)
    require(need <= bv["byteLength"], "accessor %d overruns its bufferView (%d > %d)" % (ai, need, bv["byteLength"]))
    require(bv.get("byteOffset", 0) + bv["byteLength"] <= len(buf), "bufferView overruns buffer")
    require(off % size == 0, "accessor %d misaligned" % ai)
    out = []
    for i in range(count):
        vals = struct.unpack_from("<%d%s" % (n, fmt), buf, off + i * stride)
        out.append(vals if n > 1 else vals[0])
    return out


class Tracer:
    """Brute force ray caster over world-space triangles grouped in boxed chunks."""

    def __init__(self):
        self.chunks = []  # (lo, hi, [(p0, e1, e2, material, normal-ish)])

    def add(self, tris, material):
        for s in range(0, len(tris), 48):
            part = tris[s:s + 48]
            pts = [p for t in part for p in t]
            lo = tuple(min(p[k] for p in pts) - 1e-4 for k in range(3))
            hi = tuple(max(p[k] for p in pts) + 1e-4 for k in range(3))
            self.chunks.append((lo, hi, [(a, sub(b, a), sub(c, a), material) for a, b, c in part]))

    @staticmethod
    def _box(lo, hi, o, inv, tmax):
        t0, t1 = 0.0, tmax
        for k in range(3):
            a = (lo[k] - o[k]) * inv[k]
            b = (hi[k] - o[k]) * inv[k]
            if a > b:
                a, b = b, a
            t0, t1 = max(t0, a), min(t1, b)
            if t0 > t1:
                return False
        return True

    def cast(self, o, d, tmax=1e9):
        inv = tuple(1.0 / c if abs(c) > 1e-12 else 1e12 for c in d)
        best = None
        for lo, hi, tris in self.chunks:
            if not self._box(lo, hi, o, inv, tmax):
                continue
            for p0, e1, e2, mat in tris:
                h = cross(d, e2)
                a = dot(e1, h)
                if abs(a) < 1e-12:
                    continue
                f = 1.0 / a
                s = sub(o, p0)
                u = f * dot(s, h)
                if u < 0.0 or u > 1.0:
                    continue
                q = cross(s, e1)
                v = f * dot(d, q)
                if v < 0.0 or u + v > 1.0:
                    continue
                t = f * dot(e2, q)
                if 1e-5 < t < tmax:
                    tmax = t
                    best = (t, mat, normalize(cross(e1, e2)))
        return best


def check_scene(name, verbose=True):
    path = os.path.join(SCENE_DIR, name + ".gltf")
    with open(path, "r", encoding="utf-8") as f:
        doc = json.load(f)

    def walk(x, where):
        if isinstance(x, float):
            require(math.isfinite(x), "%s: non-finite number at %s" % (name, where))
        elif isinstance(x, dict):
            for k, v in x.items():
                walk(v, where + "." + k)
        elif isinstance(x, list):
            for i, v in enumerate(x):
                walk(v, "%s[%d]" % (where, i))
    walk(doc, "$")
    require(doc["asset"]["version"] == "2.0", "asset.version")
    buffers = []
    for b in doc["buffers"]:
        with open(os.path.join(SCENE_DIR, b["uri"]), "rb") as f:
            data = f.read()
        require(len(data) == b["byteLength"], "%s: buffer length %d != %d" % (name, len(data), b["byteLength"]))
        require(len(data) < 2 * 1024 * 1024, "%s: .bin over 2 MB" % name)
        buffers.append(data)
    mats = doc["materials"]
    for m in mats:
        ext = m.get("extensions", {}).get(REFLECT_EXT)
        if ext is not None:
            require(ext.get("mode", "screen_space") in ENUM_MODE, "bad mode in " + m["name"])
            for k in ("roughnessScale", "roughnessOverride", "maxScreenSpaceRoughness"):
                require(k not in ext or finite(ext[k]), "bad %s in %s" % (k, m["name"]))
            for k in ("traceCmos", "mirrorForSelfReflections"):
                require(k not in ext or isinstance(ext[k], bool), "bad %s in %s" % (k, m["name"]))
    # meshes
    mesh_tris = {}
    for mi, mesh in enumerate(doc["meshes"]):
        tris_by_prim = []
        for prim in mesh["primitives"]:
            pos = read_accessor(doc, buffers, prim["attributes"]["POSITION"])
            nrm = read_accessor(doc, buffers, prim["attributes"]["NORMAL"])
            uv = read_accessor(doc, buffers, prim["attributes"]["TEXCOORD_0"])
            idx = read_accessor(doc, buffers, prim["indices"])
            require(len(pos) == len(nrm) == len(uv), "%s: attribute counts differ" % mesh["name"])
            require(len(idx) % 3 == 0 and len(idx) > 0, "%s: index count" % mesh["name"])
            require(max(idx) < len(pos), "%s: index out of range" % mesh["name"])
            acc = doc["accessors"][prim["attributes"]["POSITION"]]
            for k in range(3):
                require(acc["min"][k] == min(p[k] for p in pos) and acc["max"][k] == max(p[k] for p in pos),
                        "%s: POSITION min/max wrong" % mesh["name"])
            for n in nrm:
                require(abs(length(n) - 1.0) < 1e-3, "%s: normal not unit" % mesh["name"])
            bad = 0
            tris = []
            for t in range(0, len(idx), 3):
                a, b, c = pos[idx[t]], pos[idx[t + 1]], pos[idx[t + 2]]
                gn = cross(sub(b, a), sub(c, a))
                vn = add(add(nrm[idx[t]], nrm[idx[t + 1]]), nrm[idx[t + 2]])
                if dot(gn, vn) <= 0.0:
                    bad += 1
                tris.append((a, b, c))
            require(bad <= len(idx) // 3 // 1000, "%s: %d triangles wound against their normals" % (mesh["name"], bad))
            tris_by_prim.append((tris, prim.get("material", -1)))
        mesh_tris[mi] = tris_by_prim

    # world transforms
    nodes = doc["nodes"]
    world = [None] * len(nodes)

    def visit(i, parent):
        n = nodes[i]
        m = n.get("matrix") or mat_from_trs(n.get("translation", [0, 0, 0]), n.get("rotation", [0, 0, 0, 1]),
                                            n.get("scale", [1, 1, 1]))
        world[i] = mat_mul(parent, m)
        for c in n.get("children", []):
            visit(c, world[i])
    ident = [1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0]
    for r in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        visit(r, ident)

    tracer = Tracer()
    lo, hi = [1e30] * 3, [-1e30] * 3
    ntris = 0
    probes = []
    for i, n in enumerate(nodes):
        ext = n.get("extensions", {}).get(PROBE_EXT)
        if ext is not None:
            require(ext["kind"] in ENUM_KIND and ext["shape"] in ENUM_SHAPE and ext["update"] in ENUM_UPDATE,
                    "bad probe enum on " + n["name"])
            require(len(ext["extents"]) == 3 and all(finite(c) and c > 0 for c in ext["extents"]), "probe extents")
            res = ext["resolution"]
            require(isinstance(res, int) and 8 <= res <= 4096 and res & (res - 1) == 0,
                    "probe %s: resolution %r is not a power of two in [8, 4096]" % (n["name"], res))
            require(finite(ext["blendDistance"]) and ext["blendDistance"] >= 0, "probe %s: blendDistance" % n["name"])
            # the extents are in the node's space; ours are unrotated and unscaled, so the box is
            # world-aligned and the checks below can work in world space
            require("rotation" not in n and "scale" not in n and "matrix" not in n,
                    "probe %s: rotated or scaled" % n["name"])
            probes.append((n["name"], i, ext))
        if "mesh" not in n:
            continue
        require(world[i] is not None, "node %s not in scene" % n["name"])
        for tris, mat in mesh_tris[n["mesh"]]:
            wt = [tuple(mat_point(world[i], p) for p in t) for t in tris]
            for t in wt:
                for p in t:
                    for k in range(3):
                        lo[k] = min(lo[k], p[k])
                        hi[k] = max(hi[k], p[k])
            tracer.add(wt, mat)
            ntris += len(wt)

    def inside(p, pad=0.01):
        return all(lo[k] - pad <= p[k] <= hi[k] + pad for k in range(3))

    # A probe's capture point (its centre) must be in the open: a back face first along any axis
    # means it sits inside a closed object and would capture that object's inside.
    probe_report = []
    sealed = name in SEALED
    for pn, pi, ext in probes:
        c = (world[pi][12], world[pi][13], world[pi][14])
        require(inside(c), "probe %s: centre outside the scene" % pn)
        nearest = 1e30
        for k in range(3):
            for sgn in (1.0, -1.0):
                d = tuple(sgn if j == k else 0.0 for j in range(3))
                h = tracer.cast(c, d)
                if h is None:
                    continue
                require(dot(h[2], d) < 0.0, "probe %s: capture point inside an object" % pn)
                nearest = min(nearest, h[0])
                # In a sealed room the box proxy is the interior: along each axis the first hit is
                # the room's face at the box's face (1 cm: the 5 mm ceiling panel).
                if sealed and ext["shape"] == "box":
                    require(abs(h[0] - ext["extents"][k]) <= 0.01,
                            "probe %s: proxy face %s%s at %.3f m, the room's at %.3f m" % (
                                pn, "+" if sgn > 0 else "-", "xyz"[k], ext["extents"][k], h[0]))
        if sealed:
            # every direction from the capture point hits the room inside the proxy box
            for j in range(16):
                for i in range(32):
                    th, ph = (j + 0.5) / 16 * math.pi, (i + 0.5) / 32 * 2.0 * math.pi
                    d = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
                    h = tracer.cast(c, d)
                    require(h is not None, "probe %s: the capture sees the sky along %s" % (pn, r6v(d)))
                    q = add(c, mul(d, h[0]))
                    require(all(abs(q[k] - c[k]) <= ext["extents"][k] + 0.01 for k in range(3)),
                            "probe %s: a surface outside the proxy box at %s" % (pn, r6v(q)))
        probe_report.append((pn, c, ext, nearest))

    def reflective(mat):
        if mat < 0:
            return False
        pbr = mats[mat].get("pbrMetallicRoughness", {})
        return pbr.get("metallicFactor", 1.0) >= 0.5 and pbr.get("roughnessFactor", 1.0) <= 0.6

    def emissive(mat):
        return mat >= 0 and any(c > 0 for c in mats[mat].get("emissiveFactor", [0, 0, 0]))

    cams = [(i, n) for i, n in enumerate(nodes) if "camera" in n]
    require(len(cams) >= 2, "%s: fewer than two cameras" % name)
    require(cams[0][1]["name"] == "main", "%s: first camera is not 'main'" % name)
    env = doc["scenes"][0].get("extras", {}).get("environment")
    require(env and os.path.isfile(os.path.normpath(os.path.join(SCENE_DIR, env))), "%s: environment missing" % name)

    report = {"triangles": ntris, "bounds": (lo, hi), "cameras": {}}
    W, H = 48, 27
    for ci, n in cams:
        cam = doc["cameras"][n["camera"]]
        require(cam["type"] == "perspective" and 0.9 <= cam["perspective"]["yfov"] <= 1.0, "camera fov")
        require(cam["perspective"]["znear"] == 0.05 and "zfar" not in cam["perspective"], "camera near/far")
        m = world[ci]
        eye = (m[12], m[13], m[14])
        fwd = normalize(mat_dir(m, (0, 0, -1)))
        right = normalize(mat_dir(m, (1, 0, 0)))
        up = normalize(mat_dir(m, (0, 1, 0)))
        require(up[1] > 0.0, "camera %s upside down" % n["name"])
        target = n.get("extras", {}).get("target")
        require(target is not None and inside(target), "camera %s: target outside the scene" % n["name"])
        require(abs(dot(normalize(sub(target, eye)), fwd) - 1.0) < 1e-5, "camera %s: rotation != look-at" % n["name"])
        hit = tracer.cast(eye, fwd)
        require(hit is not None and inside(add(eye, mul(fwd, hit[0]))), "camera %s looks at nothing" % n["name"])
        th = math.tan(cam["perspective"]["yfov"] / 2.0)
        tw = th * 16.0 / 9.0
        stats = {"backfaces": 0, "reflective": 0, "reflect_hits_emissive": 0, "escapes": 0, "direct": {},
                 "reflected": {}}
        for py in range(H):
            for px in range(W):
                sx = ((px + 0.5) / W * 2.0 - 1.0) * tw
                sy = (1.0 - (py + 0.5) / H * 2.0) * th
                d = normalize(add(fwd, add(mul(right, sx), mul(up, sy))))
                h = tracer.cast(eye, d)
                if h is None:
                    stats["escapes"] += 1
                    continue
                stats["direct"][h[1]] = stats["direct"].get(h[1], 0) + 1
                if sealed:  # the mirror bounce of every surface must stay in the room too
                    p = add(eye, mul(d, h[0]))
                    nn = h[2] if dot(h[2], d) < 0 else mul(h[2], -1.0)
                    if tracer.cast(add(p, mul(nn, 1e-4)), sub(d, mul(nn, 2.0 * dot(d, nn)))) is None:
                        stats["escapes"] += 1
                if dot(h[2], d) > 0.0:
                    stats["backfaces"] += 1
                if reflective(h[1]):
                    stats["reflective"] += 1
                    p = add(eye, mul(d, h[0]))
                    nn = h[2] if dot(h[2], d) < 0 else mul(h[2], -1.0)
                    r = sub(d, mul(nn, 2.0 * dot(d, nn)))
                    h2 = tracer.cast(add(p, mul(nn, 1e-4)), r)
                    if h2 is not None:
                        stats["reflected"][h2[1]] = stats["reflected"].get(h2[1], 0) + 1
                        if emissive(h2[1]):
                            stats["reflect_hits_emissive"] += 1
        require(stats["backfaces"] <= W * H // 100, "camera %s sees %d back faces" % (n["name"], stats["backfaces"]))
        require(not sealed or stats["escapes"] == 0,
                "camera %s: %d rays or their mirror bounces reach the sky" % (n["name"], stats["escapes"]))
        frac = stats["reflective"] / float(W * H)
        require(frac >= 0.05, "camera %s sees little reflective surface (%.1f%%)" % (n["name"], 100 * frac))
        stats["reflective_fraction"] = frac
        report["cameras"][n["name"]] = stats

    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    if sealed:
        require(probes, "%s: sealed room without a probe" % name)
        require(all(lt["type"] != "directional" for lt in lights), "%s: a sun in a sealed room" % name)
    if name in PLAIN:
        # what a plain exporter writes: no Speculum extension anywhere, by any name
        with open(path, "r", encoding="utf-8") as f:
            require("SPECULUM_" not in f.read(), "%s: uses a Speculum extension" % name)
        require(any(lt["type"] == "directional" for lt in lights), "%s: no sun" % name)

        def has(metal, r0, r1):
            return any(m["pbrMetallicRoughness"]["metallicFactor"] == metal
                       and r0 <= m["pbrMetallicRoughness"]["roughnessFactor"] <= r1 for m in mats)
        require(has(1.0, 0.0, 0.0), "%s: no chrome (metallic 1, roughness 0)" % name)
        require(has(1.0, 0.15, 0.4), "%s: no glossy metal (roughness 0.15-0.4)" % name)
        require(has(0.0, 0.05, 0.3), "%s: no glossy dielectric (roughness 0.05-0.3)" % name)

    if name == "failure_cases":
        main = report["cameras"]["main"]
        matid = {m["name"]: i for i, m in enumerate(mats)}
        hid = matid["hidden_box.cyan"]
        require(main["direct"].get(hid, 0) == 0, "hidden box is directly visible from main")
        require(main["reflected"].get(hid, 0) > 0, "hidden box is not seen in the floor from main")
        for g in ("glow.magenta", "glow.cyan", "glow.warm", "glow.overhead"):
            require(main["direct"].get(matid[g], 0) == 0, "%s directly visible from main" % g)
        require(sum(main["reflected"].get(matid[g], 0) for g in ("glow.magenta", "glow.cyan", "glow.warm")) > 0,
                "emissive objects behind the camera are not reflected")
        require(main["reflected"].get(matid["glow.overhead"], 0) > 0, "overhead glow not reflected by the floor")

    if verbose:
        print("%s: %d triangles, bin %d bytes, bounds %s..%s" % (name, ntris, len(buffers[0]),
              [round(c, 2) for c in lo], [round(c, 2) for c in hi]))
        for pn, c, ext, nearest in probe_report:
            print("  probe  %-24s %s at %s, extents %s, blend %g, %d^2, order %d; first hit along the axes"
                  " %.2f m" % (pn, ext["shape"], r6v(c), ext["extents"], ext["blendDistance"], ext["resolution"],
                               ext["order"], nearest))
        for cn, st in report["cameras"].items():
            refl = sorted(((c, mats[k]["name"]) for k, c in st["reflected"].items()), reverse=True)[:4]
            print("  camera %-16s reflective %4.1f%%  reflections show: %s" % (
                cn, 100 * st["reflective_fraction"], ", ".join("%s %d" % (nm, c) for c, nm in refl)))
    return lo, hi


def check_path(name, lo, hi):
    with open(os.path.join(PATH_DIR, name + ".json"), "r", encoding="utf-8") as f:
        p = json.load(f)
    require(p["scene"] == name and p["frames"] >= 2 and finite(p["fov_deg"]), "path header " + name)
    require(len(p["keys"]) >= 2, "path keys " + name)
    for k in p["keys"]:
        for what in ("eye", "target"):
            v = k[what]
            require(len(v) == 3 and all(finite(c) for c in v), "path %s %s" % (name, what))
            pad = 0.01 if what == "target" else 5.0  # eyes may stand in front of an open box
            require(all(lo[i] - pad <= v[i] <= hi[i] + pad for i in range(3)), "path %s %s outside scene" % (name, what))
        require(length(sub(k["target"], k["eye"])) > 0.1, "path %s: eye == target" % name)


SCENES = ("gallery", "cornell_mirrors", "failure_cases", "closed_room", "plain_metals", "mirror_hall",
          "hall_of_mirrors")
SEALED = ("closed_room",)  # no ray from inside, direct or mirrored, may reach the sky
PLAIN = ("plain_metals",)  # no Speculum extension at all, like a plain Blender export


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="validate the scenes on disk instead of writing")
    args = ap.parse_args()
    if not args.check:
        build_gallery()
        build_cornell()
        build_failure_cases()
        build_closed_room()
        build_plain_metals()
        build_blender_repro()
        build_mirror_hall()
        build_hall_of_mirrors()
        for n in SCENES:
            print("wrote assets/scenes/%s.gltf, .bin and assets/paths/%s.json" % (n, n))
        print("wrote assets/blender/" + BLENDER_FILE)
        return 0
    try:
        for n in SCENES:
            lo, hi = check_scene(n)
            check_path(n, lo, hi)
        bl = os.path.join(ROOT, "assets", "blender")
        for fn in sorted(os.listdir(bl)) if os.path.isdir(bl) else []:
            if fn.endswith(".gltf"):
                with open(os.path.join(bl, fn), "r", encoding="utf-8") as f:
                    d = json.load(f)
                require(d.get("cameras") and any("camera" in n for n in d.get("nodes", [])), fn + ": no camera")
                require(all(b.get("uri", "").startswith("data:") for b in d.get("buffers", [])),
                        fn + ": buffers not embedded")
                import base64
                bufs = [base64.b64decode(b["uri"].split(",", 1)[1]) for b in d["buffers"]]
                for b, data in zip(d["buffers"], bufs):
                    require(len(data) == b["byteLength"], fn + ": buffer length")
                for mesh in d["meshes"]:
                    for pr in mesh["primitives"]:
                        pos = read_accessor(d, bufs, pr["attributes"]["POSITION"])
                        idx = read_accessor(d, bufs, pr["indices"])
                        require(max(idx) < len(pos), fn + ": index out of range")
                        acc = d["accessors"][pr["attributes"]["POSITION"]]
                        require(all(acc["min"][k] == min(q[k] for q in pos) and acc["max"][k] == max(q[k] for q in pos)
                                    for k in range(3)), fn + ": POSITION min/max")
                print("blender/%s: %s, %d cameras" % (fn, d["asset"].get("generator"), len(d["cameras"])))
    except (CheckError, OSError, KeyError, ValueError, IndexError, TypeError) as e:
        print("check failed: %s" % e, file=sys.stderr)
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
