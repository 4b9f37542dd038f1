"""Planar probe proposals (issue 24): the large flat reflectors, each a plane with the rectangle
its triangles span, proposed before any CMO is tried there (PLACEMENT.md, "PLANAR")."""

import math

from speculum_py.enums import KIND, PROBE_EXT
from speculum_py.gltf import mat_point, world_matrices
from speculum_py.vec import cross, dot, length, mul, sub

from .candidates import sample_step
from .scene import material_weight, normalize

MIN_AREA = 1.0        # m^2: a flat reflector smaller than this is left to the CMOs
# material_weight: glossy enough that its reflections show a scene. A dielectric counts to
# roughness 0.37 (0.25 (1 - r)^2), a metal to 0.68. It was 0.25, which no dielectric reaches: the
# closed room's glossy tile floor (0.1, 47% of its reflected weight) was never proposed, and its
# planar probe lifts that room's mirror band by 4.4 dB (modules/reflections/MEASUREMENTS.md).
MIN_WEIGHT = 0.1


def _frame(n):
    """Unit axes (x, z) on the plane of unit normal n, x as near the world's x as the plane allows."""
    ref = (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 0.0, 1.0)
    x = normalize(sub(ref, mul(n, dot(ref, n))))
    return x, cross(x, n)


def _quat(x, y, z):
    """The glTF rotation [x, y, z, w] of the matrix whose columns are x, y, z."""
    m00, m11, m22 = x[0], y[1], z[2]
    tr = m00 + m11 + m22
    if tr > 0.0:
        s = math.sqrt(tr + 1.0) * 2.0
        q = ((y[2] - z[1]) / s, (z[0] - x[2]) / s, (x[1] - y[0]) / s, 0.25 * s)
    elif m00 > m11 and m00 > m22:
        s = math.sqrt(1.0 + m00 - m11 - m22) * 2.0
        q = (0.25 * s, (y[0] + x[1]) / s, (z[0] + x[2]) / s, (y[2] - z[1]) / s)
    elif m11 > m22:
        s = math.sqrt(1.0 + m11 - m00 - m22) * 2.0
        q = ((y[0] + x[1]) / s, 0.25 * s, (z[1] + y[2]) / s, (z[0] - x[2]) / s)
    else:
        s = math.sqrt(1.0 + m22 - m00 - m11) * 2.0
        q = ((z[0] + x[2]) / s, (z[1] + y[2]) / s, 0.25 * s, (x[1] - y[0]) / s)
    return [round(c, 6) for c in q]


def on_plane(p, n, plane, tol=1e-3):
    return abs(dot(plane["normal"], p) - plane["offset"]) <= tol and dot(n, plane["normal"]) >= 0.999


def existing_planes(doc):
    """[(unit normal, offset)]: the planes of the planar probes the scene already has (world space)."""
    world = world_matrices(doc)
    out = []
    for i, n in enumerate(doc.get("nodes", [])):
        ext = n.get("extensions", {}).get(PROBE_EXT) if isinstance(n, dict) and isinstance(n.get("extensions"), dict) else None
        if world[i] is None or not isinstance(ext, dict) or ext.get("kind") != KIND.planar:
            continue
        origin = mat_point(world[i], (0.0, 0.0, 0.0))
        normal = normalize(sub(mat_point(world[i], (0.0, 1.0, 0.0)), origin))
        out.append((normal, dot(normal, origin)))
    return out


def flat_reflectors(geo, doc, samples, min_area=MIN_AREA):
    """Planes of reflective triangles (coplanar within 1 cm and 0.6 degrees) covering at least
    min_area, with the reflected samples that land on them; largest reflected weight first. A
    plane that one of the scene's planar probes already lies on is left out (it is served)."""
    served = existing_planes(doc)
    mats = doc.get("materials", [])
    weight = {}
    groups = {}
    for a, e1, e2, n, mat in geo.tris:
        if mat not in weight:
            weight[mat] = material_weight(mats[mat] if isinstance(mat, int) and 0 <= mat < len(mats) else {})
        if weight[mat] < MIN_WEIGHT:
            continue
        key = tuple(round(c, 2) for c in n) + (round(dot(n, a), 2),)
        g = groups.setdefault(key, {"normal": n, "offset": dot(n, a), "area": 0.0, "points": []})
        g["area"] += 0.5 * length(cross(e1, e2))
        g["points"] += [a, tuple(a[k] + e1[k] for k in range(3)), tuple(a[k] + e2[k] for k in range(3))]
    out = []
    for g in groups.values():
        n = g["normal"]
        if g["area"] < min_area or any(dot(n, m) >= 0.999 and abs(g["offset"] - o) <= 0.01 for m, o in served):
            continue
        x, z = _frame(n)
        us = [dot(p, x) for p in g["points"]]
        vs = [dot(p, z) for p in g["points"]]
        cu, cv = 0.5 * (min(us) + max(us)), 0.5 * (min(vs) + max(vs))
        origin = tuple(x[k] * cu + z[k] * cv + n[k] * g["offset"] for k in range(3))
        plane = {"normal": n, "offset": g["offset"], "origin": [round(c, 6) for c in origin],
                 "rotation": _quat(x, n, z), "area": g["area"],
                 "extents": [round(0.5 * (max(us) - min(us)) + 0.01, 6), round(0.5 * (max(vs) - min(vs)) + 0.01, 6)]}
        on = [on_plane(s["p"], s["n"], plane) for s in samples]
        step = sample_step(samples)  # the candidates' subset: `covered` indexes it as their `seen` does
        plane["covered"] = {i for i, k in enumerate(range(0, len(samples), step)) if on[k]}
        plane["weight"] = sum(s["w"] for s, o in zip(samples, on) if o)
        if plane["weight"] > 0.0:
            out.append(plane)
    out.sort(key=lambda p: -p["weight"])
    for r, p in enumerate(out):
        p["rank"] = r
    return out


def planar_nodes(planars):
    """The glTF nodes of the accepted planar probes (edit.edited_document appends them)."""
    return [{"name": f"planar.{i}", "translation": p["origin"], "rotation": p["rotation"],
             "extensions": {"SPECULUM_reflection_probe": {"kind": "planar", "extents": p["extents"]}}}
            for i, p in enumerate(planars)]
