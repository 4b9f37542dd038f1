"""Vectors, quaternions and column-major 4x4 matrices as tuples of floats: what both the scene
generator and the probes tool compute with, so a point means the same to both."""

import math

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


def normalize(a, eps=0.0):
    """a / |a|, or zero when |a| <= eps (the probes tool passes 1e-20 so near-zero vectors give
    zero rather than huge components; the generator's meshes keep 0, the bytes they were made with)."""
    n = length(a)
    return (a[0] / n, a[1] / n, a[2] / n) if n > eps else (0.0, 0.0, 0.0)


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

