"""One ray caster for the tools: closest hits over world-space triangles through a small
bounding volume hierarchy (pure Python). The scene checks and speculum-probes cast through this,
so both agree on what a ray from a camera or a probe meets."""

from .vec import add, cross, dot, length, mul, normalize, sub


class RayCaster:
    """Triangles as (a, e1, e2, unit geometric normal, material): the edges precomputed once,
    since every cast needs them and a caster serves thousands of rays."""

    LEAF = 6

    def __init__(self, tris):
        self.tris = list(tris)
        self.nodes = []  # (lo, hi, left, right, first, count)
        if self.tris:
            order = list(range(len(self.tris)))
            boxes = [self._tri_box(t) for t in self.tris]
            self._build(order, boxes, 0, len(order))
            self.tris = [self.tris[i] for i in order]

    @staticmethod
    def triangle(a, b, c, material):
        """The caster's form of triangle a, b, c, or None when it has no area (no ray can hit it and
        its normal is undefined)."""
        e1, e2 = sub(b, a), sub(c, a)
        g = cross(e1, e2)
        if length(g) < 1e-14:
            return None
        return (a, e1, e2, normalize(g), material)

    @staticmethod
    def _tri_box(t):
        a, e1, e2 = t[0], t[1], t[2]
        b, c = add(a, e1), add(a, e2)
        return (tuple(min(a[k], b[k], c[k]) for k in range(3)), tuple(max(a[k], b[k], c[k]) for k in range(3)))

    def _build(self, order, boxes, first, count):
        lo = tuple(min(boxes[order[i]][0][k] for i in range(first, first + count)) - 1e-6 for k in range(3))
        hi = tuple(max(boxes[order[i]][1][k] for i in range(first, first + count)) + 1e-6 for k in range(3))
        me = len(self.nodes)
        self.nodes.append(None)
        if count <= self.LEAF:
            self.nodes[me] = (lo, hi, -1, -1, first, count)
            return me
        axis = max(range(3), key=lambda k: hi[k] - lo[k])
        part = sorted(order[first:first + count], key=lambda i: boxes[i][0][axis] + boxes[i][1][axis])
        order[first:first + count] = part
        half = count // 2
        left = self._build(order, boxes, first, half)
        right = self._build(order, boxes, first + half, count - half)
        self.nodes[me] = (lo, hi, left, right, first, 0)
        return me

    def cast(self, o, d, tmax=1e30):
        """Closest hit (t, triangle) of the ray o + t d, t in (1e-5, tmax), or None."""
        if not self.nodes:
            return None
        inv = tuple(1.0 / c if abs(c) > 1e-12 else 1e12 for c in d)
        best = None
        stack = [0]
        nodes, tris = self.nodes, self.tris
        while stack:
            lo, hi, left, right, first, count = nodes[stack.pop()]
            t0, t1 = 0.0, tmax
            for k in range(3):
                a = (lo[k] - o[k]) * inv[k]
                b = (hi[k] - o[k]) * inv[k]
                if a > b:
                    a, b = b, a
                if a > t0:
                    t0 = a
                if b < t1:
                    t1 = b
                if t0 > t1:
                    break
            if t0 > t1:
                continue
            if count == 0:
                stack.append(left)
                stack.append(right)
                continue
            for ti in range(first, first + count):
                p0, e1, e2 = tris[ti][0], tris[ti][1], tris[ti][2]
                h = (d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0])
                a = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2]
                if -1e-14 < a < 1e-14:
                    continue
                f = 1.0 / a
                s = (o[0] - p0[0], o[1] - p0[1], o[2] - p0[2])
                u = f * (s[0] * h[0] + s[1] * h[1] + s[2] * h[2])
                if u < 0.0 or u > 1.0:
                    continue
                q = (s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0])
                v = f * (d[0] * q[0] + d[1] * q[1] + d[2] * q[2])
                if v < 0.0 or u + v > 1.0:
                    continue
                t = f * (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2])
                if 1e-5 < t < tmax:
                    tmax = t
                    best = (t, tris[ti])
        return best

    def visible(self, a, b):
        d = sub(b, a)
        L = length(d)
        if L < 1e-6:
            return True
        return self.cast(a, mul(d, 1.0 / L), L * (1.0 - 1e-3) - 1e-4) is None

    def inside(self, p):
        """True when p is enclosed: most axis rays from it meet a back face first."""
        back = 0
        for d in ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)):
            h = self.cast(p, d)
            if h is not None and dot(d, h[1][3]) > 0.0:
                back += 1
        return back >= 4

