"""Candidates from geometry alone: the potentially reflected area (seed 000 section 3.8) and CMO
centres near the reflectors that see most of it."""

import math

from speculum_py.vec import add, dot, mat_dir, mat_point, mul, sub

from .scene import dist, material_weight, normalize


def reflection_samples(geo, doc, views, size, grid=48):
    """Rays from each camera through a grid of pixels: at each reflective hit (p, n, weight) the
    mirror ray's hit q. A reflection that screen space can resolve (q seen by the camera) counts
    less; one that leaves the scene (the sky) needs no CMO and is counted apart."""
    mats = doc.get("materials", [])
    weight_of = {}
    w_px, h_px = size
    gx = grid
    gy = max(2, round(grid * h_px / w_px))
    samples, sky = [], 0.0
    for name, m, yfov in views:
        eye = mat_point(m, (0.0, 0.0, 0.0))
        right = normalize(mat_dir(m, (1.0, 0.0, 0.0)))
        up = normalize(mat_dir(m, (0.0, 1.0, 0.0)))
        fwd = normalize(mat_dir(m, (0.0, 0.0, -1.0)))
        th = math.tan(yfov / 2.0)
        aspect = w_px / h_px
        for j in range(gy):
            for i in range(gx):
                sx = ((i + 0.5) / gx * 2.0 - 1.0) * th * aspect
                sy = (1.0 - (j + 0.5) / gy * 2.0) * th
                d = normalize(add(fwd, add(mul(right, sx), mul(up, sy))))
                hit = geo.cast(eye, d)
                if hit is None:
                    continue
                t, tri = hit
                mat = tri[4]
                if mat not in weight_of:
                    weight_of[mat] = material_weight(mats[mat] if isinstance(mat, int) and 0 <= mat < len(mats) else {})
                w = weight_of[mat]
                if w <= 0.0:
                    continue
                n = tri[3] if dot(tri[3], d) < 0.0 else mul(tri[3], -1.0)
                p = add(eye, mul(d, t))
                r = sub(d, mul(n, 2.0 * dot(d, n)))
                o = add(p, mul(n, 1e-4 * max(geo.diagonal, 1.0)))
                rh = geo.cast(o, r)
                if rh is None:
                    sky += w
                    continue
                q = add(o, mul(r, rh[0]))
                # on screen and unoccluded: the screen-space tracer can find it
                rel = sub(q, eye)
                z = dot(rel, fwd)
                on_screen = (z > 0 and abs(dot(rel, right)) < z * th * aspect and abs(dot(rel, up)) < z * th
                             and geo.visible(eye, q))
                samples.append({"p": p, "n": n, "q": q, "w": w * (0.35 if on_screen else 1.0), "view": name})
    return samples, sky


def clusters(samples, k, diagonal):
    """Farthest-point seeds over reflector points (position, plus normal disagreement), then each
    sample to its nearest seed."""
    if not samples:
        return []
    scale = 0.25 * max(diagonal, 1e-3)

    def metric(a, b):
        return dist(a["p"], b["p"]) + scale * (1.0 - dot(a["n"], b["n"]))

    seeds = [max(range(len(samples)), key=lambda i: samples[i]["w"])]
    best = [metric(s, samples[seeds[0]]) for s in samples]
    while len(seeds) < min(k, len(samples)):
        i = max(range(len(samples)), key=lambda j: best[j] * samples[j]["w"])
        if best[i] <= 1e-9:
            break
        seeds.append(i)
        best = [min(best[j], metric(samples[j], samples[i])) for j in range(len(samples))]
    groups = [[] for _ in seeds]
    for s in samples:
        groups[min(range(len(seeds)), key=lambda g: metric(s, samples[seeds[g]]))].append(s)
    return [g for g in groups if g]


def place_off_surface(geo, p, n, offset, min_offset):
    """p + n * offset, shortened so it stays off whatever is in front of the surface, or None
    (too close to other geometry, or enclosed by it)."""
    o = add(p, mul(n, 1e-4 * max(geo.diagonal, 1.0)))
    h = geo.cast(o, n, offset * 2.0)
    if h is not None:
        offset = min(offset, h[0] * 0.5)
    if offset < min_offset:
        return None
    c = add(p, mul(n, offset))
    if geo.inside(c):
        return None
    return c


MAX_Q = 192  # reflected samples the candidates' visibility is tested against (a subset)


def sample_step(samples, max_q=MAX_Q):
    """The stride of the subset samples[::step] whose indices the candidates' `seen` sets use."""
    return max(1, len(samples) // max_q)


def candidates(geo, samples, max_candidates=16, offset=None, max_q=MAX_Q):
    """CMO centre candidates near the reflectors, each with the reflected sample points it sees;
    ranked by a greedy set cover of the reflected area (weighted), so later ones add what the
    earlier ones miss (which spreads them apart)."""
    if not samples:
        return []
    diag = max(geo.diagonal, 1e-3)
    offset = offset if offset is not None else min(max(0.04 * diag, 0.05), 0.6)
    min_offset = 0.15 * offset
    qs = samples[::sample_step(samples, max_q)]
    out = []
    for group in clusters(samples, max_candidates, diag):
        wsum = sum(s["w"] for s in group)
        cen = mul(tuple(sum(s["p"][k] * s["w"] for s in group) for k in range(3)), 1.0 / wsum)
        nrm = normalize(tuple(sum(s["n"][k] * s["w"] for s in group) for k in range(3)))
        # the sample nearest the weighted centre whose normal agrees with the cluster's
        med = min(group, key=lambda s: dist(s["p"], cen) + 0.5 * offset * (1.0 - dot(s["n"], nrm)))
        c = place_off_surface(geo, med["p"], med["n"], offset, min_offset)
        if c is None:
            continue
        variants = []
        for f in (0.5, 2.0):
            v = place_off_surface(geo, med["p"], med["n"], offset * f, min_offset)
            if v is not None and dist(v, c) > 1e-3:
                variants.append(v)
        seen = [i for i, s in enumerate(qs) if geo.visible(c, s["q"])]
        dq = sorted(dist(c, qs[i]["q"]) for i in seen) or [offset * 4]
        radius = max(dq[len(dq) // 2], max(dist(c, s["p"]) for s in group) + offset)
        out.append({"pos": c, "surface": med["p"], "normal": med["n"], "variants": variants, "seen": set(seen),
                    "qw": [s["w"] for s in qs],
                    "area": sum(qs[i]["w"] for i in seen), "cluster_weight": wsum, "radius": radius})
    # spread apart: of two candidates closer than the offset, the one that sees more stays
    kept = []
    for c in sorted(out, key=lambda c: -c["area"]):
        if all(dist(c["pos"], k["pos"]) >= offset for k in kept):
            kept.append(c)
    # greedy set cover: rank by the reflected area not yet seen by the ones ranked before
    ranked, covered = [], set()
    pool = kept
    while pool:
        best = max(pool, key=lambda c: (sum(qs[i]["w"] for i in c["seen"] - covered), c["cluster_weight"]))
        best["gain"] = sum(qs[i]["w"] for i in best["seen"] - covered)
        ranked.append(best)
        covered |= best["seen"]
        pool.remove(best)
    for r, c in enumerate(ranked):
        c["rank"] = r
    return ranked


def marginal_rank(cands, chosen_seen, used_ids):
    """Unused candidates by the reflected area (weighted) they add to what the chosen ones see."""
    pool = [c for c in cands if c["rank"] not in used_ids]
    return sorted(pool, key=lambda c: (-sum(c["qw"][i] for i in c["seen"] - chosen_seen), -c["area"], c["rank"]))
