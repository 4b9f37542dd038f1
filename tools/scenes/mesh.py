"""Procedural meshes: positions, unit normals, UVs and counter-clockwise triangles, built in
Python so every scene is reproducible from this repository alone."""

import math

from speculum_py.gltf import require
from speculum_py.vec import add, cross, dot, length, mul, normalize, sub

from .numbers import f32


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


def lapped_room(W, H, D, lap):
    """The inward faces of the box room x in [-W, W], y in [0, H], z in [-D, D] as
    (corner, eu, ev, facing) by side. Each runs on `lap` past the room's edges, behind the face it
    meets, so no seam or T-junction at a corner lets a ray out to the sky in either renderer;
    the overlap is never seen from inside."""
    return {
        "floor": ((-W - lap, 0, -D - lap), (2 * W + 2 * lap, 0, 0), (0, 0, 2 * D + 2 * lap), (0, 1, 0)),
        "ceiling": ((-W - lap, H, -D - lap), (2 * W + 2 * lap, 0, 0), (0, 0, 2 * D + 2 * lap), (0, -1, 0)),
        "back": ((-W - lap, -lap, -D), (2 * W + 2 * lap, 0, 0), (0, H + 2 * lap, 0), (0, 0, 1)),
        "front": ((-W - lap, -lap, D), (2 * W + 2 * lap, 0, 0), (0, H + 2 * lap, 0), (0, 0, -1)),
        "left": ((-W, -lap, -D - lap), (0, 0, 2 * D + 2 * lap), (0, H + 2 * lap, 0), (1, 0, 0)),
        "right": ((W, -lap, -D - lap), (0, 0, 2 * D + 2 * lap), (0, H + 2 * lap, 0), (-1, 0, 0)),
    }


def add_room_faces(g, faces, parts):
    """One object per (side, name, material) of `faces` (lapped_room), in the order given: the
    order is the node order in the file."""
    for side, name, material in parts:
        corner, eu, ev, facing = faces[side]
        m = MeshData()
        m.quad(corner, eu, ev, facing=facing)
        g.object(name, m, material)
