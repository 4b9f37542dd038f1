#!/usr/bin/env python3
"""speculum-probes place: the fewest CMOs, the lowest resolutions and their order that meet an
accuracy budget against the reference renderer (docs/design.md section 4, probes; seed 000 section 3.8).

    speculum-probes place --scene FILE --budget-db D [--views CAM1,CAM2,...] [--size WxH]
                          [--max-cmos N] [--resolutions 64,128,256] [--spp N]
                          --out FILE.gltf [--report FILE.json]

The budget: the configuration must reach a mean PSNR >= D dB over the views, where each view's
PSNR is the bench's score of the engine's `reflection` AOV against speculum-reference's, on
reflective pixels (clamped linear after the scene's exposure; tests/bench/speculum_bench.py).

How (modules/probes/PLACEMENT.md):
1. Candidates, from geometry alone (standard-library ray casting over the glTF's triangles):
   rays from each view's camera find reflective surfaces (every lit material whose
   SPECULUM_reflections mode is not "off"; metals and low roughness weigh most); each reflects
   a sample ray; what it hits is the "potentially reflected area" (seed 000 section 3.8).
   Reflector samples are clustered (farthest-point seeds), and each cluster proposes a CMO
   centre near its reflector, offset along the normal (not at the surface, not inside
   geometry). Candidates are ranked by the reflected area they see (a greedy set cover, so the
   ranking spreads them apart).
2. Measuring: the baseline (the scene as given), then greedily ADD the best of the top
   candidates, MOVE the new one along its normal, DROP any CMO the budget does not need, order
   them by measured contribution (higher "order" is traced first) and lower each resolution
   while the budget holds. Every configuration is a temporary glTF rendered by
   speculum-capture (--aov reflection, warm-up frames) and scored as the bench does.
3. Output: the scene's glTF with the CMO nodes added through SPECULUM_reflection_probe (every
   other key kept), written atomically; a report (JSON and markdown) beside it or at --report.

Exit status: 0 the budget is met (the output is written); 1 it is not met with --max-cmos CMOs
(the best configuration found is written) or a tool failed; 2 bad arguments; 3 bad scene.
"""
import argparse
import base64
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import urllib.parse
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parents[2]
sys.path.insert(0, str(SOURCE / "tools"))
sys.path.insert(0, str(SOURCE / "tests" / "bench"))
import make_scenes as ms  # noqa: E402  (accessor reader, vector and matrix helpers)

PROBE_EXT = "SPECULUM_reflection_probe"
REFLECT_EXT = "SPECULUM_reflections"
IMPROVE_DB = 0.05  # a change must gain this much mean PSNR to be kept (renders are deterministic)


class InputError(Exception):
    """A bad input: message and exit status (2 arguments, 3 scene)."""

    def __init__(self, message, code):
        super().__init__(message)
        self.code = code


# ------------------------------------------------------------------------------------------
# Vector helpers (tuples).

add, sub, mul, dot, cross, length = ms.add, ms.sub, ms.mul, ms.dot, ms.cross, ms.length


def normalize(v):
    n = length(v)
    return (v[0] / n, v[1] / n, v[2] / n) if n > 1e-20 else (0.0, 0.0, 0.0)


def dist(a, b):
    return length(sub(a, b))


# ------------------------------------------------------------------------------------------
# The glTF: JSON, buffers, world transforms, triangles, materials, cameras.


def load_document(path):
    """(doc, buffers, glb_bin): the JSON and every buffer's bytes. InputError 3 on bad files."""
    p = Path(path)
    if not p.exists():
        raise InputError(f"{path}: no such file", 3)
    if not p.is_file():
        raise InputError(f"{path}: is a folder" if p.is_dir() else f"{path}: is not a regular file", 3)
    try:
        data = p.read_bytes()
    except OSError as e:
        raise InputError(f"{path}: cannot read: {e.strerror}", 3)
    glb_bin = None
    try:
        if data[:4] == b"glTF":
            if len(data) < 20:
                raise ValueError("truncated GLB header")
            _, _, total = struct.unpack_from("<III", data, 0)
            off, text = 12, None
            while off + 8 <= min(total, len(data)):
                clen, ctype = struct.unpack_from("<II", data, off)
                chunk = data[off + 8: off + 8 + clen]
                if ctype == 0x4E4F534A:
                    text = chunk.decode("utf-8")
                elif ctype == 0x004E4942 and glb_bin is None:
                    glb_bin = bytes(chunk)
                off += 8 + clen + (-clen % 4)
            if text is None:
                raise ValueError("GLB has no JSON chunk")
        else:
            text = data.decode("utf-8")
        doc = json.loads(text)
    except RecursionError:
        raise InputError(f"{path}: JSON nests too deeply", 3)
    except (ValueError, UnicodeDecodeError, struct.error) as e:
        raise InputError(f"{path}: not a glTF file: {str(e)[:200]}", 3)
    if not isinstance(doc, dict):
        raise InputError(f"{path}: the glTF must be a JSON object", 3)
    for key in ("nodes", "meshes", "accessors", "bufferViews", "buffers", "materials", "cameras", "scenes"):
        if key in doc and not isinstance(doc[key], list):
            raise InputError(f"{path}: '{key}' must be an array", 3)
    buffers = []
    for i, b in enumerate(doc.get("buffers", [])):
        uri = b.get("uri") if isinstance(b, dict) else None
        if uri is None:
            if glb_bin is None:
                raise InputError(f"{path}: buffers[{i}] has no uri and there is no GLB BIN chunk", 3)
            buffers.append(glb_bin)
        elif not isinstance(uri, str):
            raise InputError(f"{path}: buffers[{i}].uri must be a string", 3)
        elif uri.startswith("data:"):
            try:
                buffers.append(base64.b64decode(uri.split(",", 1)[1]))
            except (IndexError, ValueError):
                raise InputError(f"{path}: buffers[{i}]: a data: uri that is not base64", 3)
        else:
            f = p.parent / urllib.parse.unquote(uri)
            if not f.is_file():
                raise InputError(f"{path}: buffers[{i}]: buffer file '{uri}' is missing", 3)
            buffers.append(f.read_bytes())
    return doc, buffers, glb_bin


def scene_roots(doc):
    scenes = doc.get("scenes") or []
    index = doc.get("scene", 0)
    if isinstance(index, int) and 0 <= index < len(scenes) and isinstance(scenes[index], dict):
        return scenes[index].get("nodes", []), index
    children = {c for n in doc.get("nodes", []) if isinstance(n, dict) for c in n.get("children", [])}
    return [i for i in range(len(doc.get("nodes", []))) if i not in children], None


IDENT = [1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0]


def world_matrices(doc):
    """World matrix per node of the active scene (None for the others)."""
    nodes = doc.get("nodes", [])
    world = [None] * len(nodes)

    def visit(i, parent, depth):
        if not isinstance(i, int) or not 0 <= i < len(nodes) or world[i] is not None or depth > 512:
            return
        n = nodes[i]
        m = n.get("matrix")
        if not (isinstance(m, list) and len(m) == 16):
            m = ms.mat_from_trs(n.get("translation", [0, 0, 0]), n.get("rotation", [0, 0, 0, 1]),
                                n.get("scale", [1, 1, 1]))
        world[i] = ms.mat_mul(parent, m)
        for c in n.get("children", []):
            visit(c, world[i], depth + 1)

    for r in scene_roots(doc)[0]:
        visit(r, IDENT, 0)
    return world


def read_values(doc, buffers, ai):
    acc = doc["accessors"][ai]
    if "bufferView" not in acc:  # all zeros (sparse accessors without a base view)
        n = ms.NCOMP[acc["type"]]
        return [tuple([0.0] * n) if n > 1 else 0 for _ in range(acc["count"])]
    vals = ms.read_accessor(doc, buffers, ai)
    if acc.get("normalized"):
        scale = {5120: 127.0, 5121: 255.0, 5122: 32767.0, 5123: 65535.0}.get(acc["componentType"], 1.0)
        vals = [tuple(max(c / scale, -1.0) for c in v) if isinstance(v, tuple) else max(v / scale, -1.0)
                for v in vals]
    return vals


def material_weight(mat):
    """How much a material's reflections matter (0 = none): metals and low roughness most."""
    if not isinstance(mat, dict):
        mat = {}
    ext = mat.get("extensions", {}) if isinstance(mat.get("extensions"), dict) else {}
    if "KHR_materials_unlit" in ext:
        return 0.0
    r = ext.get(REFLECT_EXT, {}) if isinstance(ext.get(REFLECT_EXT), dict) else {}
    if r.get("mode", "screen_space") == "off" or r.get("traceCmos", True) is False:
        return 0.0
    pbr = mat.get("pbrMetallicRoughness", {}) if isinstance(mat.get("pbrMetallicRoughness"), dict) else {}
    metallic = float(pbr.get("metallicFactor", 1.0))
    rough = float(pbr.get("roughnessFactor", 1.0)) * float(r.get("roughnessScale", 1.0))
    if "roughnessOverride" in r:
        rough = float(r["roughnessOverride"])
    rough = min(max(rough, 0.0), 1.0)
    metallic = min(max(metallic, 0.0), 1.0)
    specular = metallic + (1.0 - metallic) * 0.25  # a dielectric's reflection is dimmer (F0 0.04)
    gloss = (1.0 - rough) ** 2
    w = specular * gloss
    return w if w >= 0.01 else 0.0


class Geometry:
    """World-space triangles of the active scene with a small BVH (pure Python)."""

    LEAF = 6

    def __init__(self, doc, buffers, path="scene"):
        self.tris = []  # (a, e1, e2, geometric normal (unit), material index)
        world = world_matrices(doc)
        meshes = doc.get("meshes", [])
        try:
            for i, n in enumerate(doc.get("nodes", [])):
                if world[i] is None or not isinstance(n.get("mesh"), int):
                    continue
                m = world[i]
                for prim in meshes[n["mesh"]].get("primitives", []):
                    mode = prim.get("mode", 4)
                    if mode not in (4, 5, 6) or "POSITION" not in prim.get("attributes", {}):
                        continue
                    pos = [ms.mat_point(m, p) for p in read_values(doc, buffers, prim["attributes"]["POSITION"])]
                    idx = read_values(doc, buffers, prim["indices"]) if "indices" in prim else list(range(len(pos)))
                    if mode == 5:
                        tri_idx = [(idx[k], idx[k + 1], idx[k + 2]) if k % 2 == 0 else (idx[k + 1], idx[k], idx[k + 2])
                                   for k in range(len(idx) - 2)]
                    elif mode == 6:
                        tri_idx = [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
                    else:
                        tri_idx = [(idx[k], idx[k + 1], idx[k + 2]) for k in range(0, len(idx) - 2, 3)]
                    mat = prim.get("material", -1)
                    for a, b, c in tri_idx:
                        if max(a, b, c) >= len(pos):
                            raise ms.CheckError(f"meshes[{n['mesh']}]: index out of range")
                        pa, pb, pc = pos[a], pos[b], pos[c]
                        e1, e2 = sub(pb, pa), sub(pc, pa)
                        g = cross(e1, e2)
                        if length(g) < 1e-14:
                            continue
                        self.tris.append((pa, e1, e2, normalize(g), mat))
        except (ms.CheckError, KeyError, IndexError, TypeError, struct.error) as e:
            raise InputError(f"{path}: cannot read the geometry: {type(e).__name__}: {e}", 3)
        self.lo = tuple(min(min(t[0][k], t[0][k] + t[1][k], t[0][k] + t[2][k]) for t in self.tris) if self.tris else 0.0
                        for k in range(3))
        self.hi = tuple(max(max(t[0][k], t[0][k] + t[1][k], t[0][k] + t[2][k]) for t in self.tris) if self.tris else 0.0
                        for k in range(3))
        self.diagonal = dist(self.lo, self.hi)
        self.nodes = []  # (lo, hi, left, right, first, count)
        if self.tris:
            order = list(range(len(self.tris)))
            boxes = [self._tri_box(t) for t in self.tris]
            self._build(order, boxes, 0, len(order))
            self.tris = [self.tris[i] for i in order]

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


def cameras(doc):
    """[(name, world matrix, yfov)]: the active scene's camera nodes, named as the loader does."""
    world = world_matrices(doc)
    cams = doc.get("cameras", [])
    out = []
    for i, n in enumerate(doc.get("nodes", [])):
        ci = n.get("camera") if isinstance(n, dict) else None
        if world[i] is None or not isinstance(ci, int) or not 0 <= ci < len(cams):
            continue
        cam = cams[ci] if isinstance(cams[ci], dict) else {}
        name = n.get("name") or cam.get("name") or f"camera{i}"
        yfov = float(cam.get("perspective", {}).get("yfov", 0.8)) if cam.get("type", "perspective") == "perspective" else 0.8
        out.append((name, world[i], yfov))
    return out


# ------------------------------------------------------------------------------------------
# Candidates: the potentially reflected area (seed 000 section 3.8).


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
        eye = ms.mat_point(m, (0.0, 0.0, 0.0))
        right = normalize(ms.mat_dir(m, (1.0, 0.0, 0.0)))
        up = normalize(ms.mat_dir(m, (0.0, 1.0, 0.0)))
        fwd = normalize(ms.mat_dir(m, (0.0, 0.0, -1.0)))
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


def candidates(geo, samples, max_candidates=16, offset=None, max_q=192):
    """CMO centre candidates near the reflectors, each with the reflected sample points it sees;
    ranked by a greedy set cover of the reflected area (weighted), so later ones add what the
    earlier ones miss (which spreads them apart)."""
    if not samples:
        return []
    diag = max(geo.diagonal, 1e-3)
    offset = offset if offset is not None else min(max(0.04 * diag, 0.05), 0.6)
    min_offset = 0.15 * offset
    step = max(1, len(samples) // max_q)
    qs = samples[::step]
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


# ------------------------------------------------------------------------------------------
# The glTF edit.


def relocate_uri(uri, src_dir, dst_dir, percent=True):
    """A relative uri of a file next to the source, rewritten for a document in dst_dir."""
    if not isinstance(uri, str) or not uri or uri.startswith("data:") or "://" in uri:
        return uri
    plain = urllib.parse.unquote(uri) if percent else uri
    if os.path.isabs(plain):
        return uri
    target = os.path.normpath(os.path.join(src_dir, plain))
    rel = os.path.relpath(target, dst_dir)
    if os.path.normpath(os.path.join(dst_dir, rel)) == os.path.normpath(os.path.join(dst_dir, plain)):
        return uri  # same place: keep the string exactly
    rel = rel.replace(os.sep, "/")
    return urllib.parse.quote(rel, safe="/._-~") if percent else rel


def edited_document(doc, cmos, src_dir, dst_dir, kind="cmo", bin_uri=None):
    """A deep copy of doc with one node per CMO appended (to "nodes" and to the active scene's
    root list), the extension listed in extensionsUsed, relative file references rewritten for
    dst_dir; every other key is kept. bin_uri: the uri of a GLB's BIN chunk written as a file."""
    out = json.loads(json.dumps(doc))
    for i, b in enumerate(out.get("buffers", [])):
        if isinstance(b, dict):
            if "uri" not in b and bin_uri is not None:
                b["uri"] = bin_uri
            elif "uri" in b:
                b["uri"] = relocate_uri(b["uri"], src_dir, dst_dir)
    for im in out.get("images", []):
        if isinstance(im, dict) and "uri" in im:
            im["uri"] = relocate_uri(im["uri"], src_dir, dst_dir)
    for sc in out.get("scenes", []):
        ex = sc.get("extras") if isinstance(sc, dict) else None
        if isinstance(ex, dict) and isinstance(ex.get("environment"), str):
            ex["environment"] = relocate_uri(ex["environment"], src_dir, dst_dir, percent=False)
    if not cmos:
        return out
    nodes = out.setdefault("nodes", [])
    taken = {n.get("name") for n in nodes if isinstance(n, dict)}
    roots, index = scene_roots(out)
    if index is None:
        if not out.get("scenes"):
            out["scenes"] = [{"nodes": list(roots)}]
            out["scene"] = 0
            index = 0
    k = 0
    for c in cmos:
        while f"cmo.{k}" in taken:
            k += 1
        name = f"cmo.{k}"
        taken.add(name)
        r = float(c.get("radius", 1.0))
        r = r if math.isfinite(r) and r > 0 else 1.0
        node = {"name": name, "translation": [round(float(x), 6) for x in c["pos"]],
                "extensions": {PROBE_EXT: {"kind": kind, "resolution": int(c["res"]), "order": int(c["order"]),
                                           "update": "once", "shape": "sphere", "extents": [round(r, 6)] * 3,
                                           "blendDistance": 0.0}}}
        nodes.append(node)
        if index is not None:
            out["scenes"][index].setdefault("nodes", []).append(len(nodes) - 1)
    used = out.setdefault("extensionsUsed", [])
    if PROBE_EXT not in used:
        used.append(PROBE_EXT)
    return out


def write_atomic(path, text=None, data=None):
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix="." + path.name + ".", suffix=".tmp", dir=str(path.parent))
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data if data is not None else text.encode("utf-8"))
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def dump(doc):
    return json.dumps(doc, indent=1) + "\n"


# ------------------------------------------------------------------------------------------
# Measuring.


class Measurer:
    def __init__(self, args, tools, doc, src, glb_bin, view_names, kind, work, log):
        import speculum_bench as bench
        self.bench, self.args, self.tools, self.doc, self.src = bench, args, tools, doc, src
        self.view_names, self.kind, self.work, self.log = view_names, kind, work, log
        self.count, self.cache = 0, {}
        self.bin_uri = None
        if glb_bin is not None:
            (work / "scene_glb.bin").write_bytes(glb_bin)
            self.bin_uri = "scene_glb.bin"
        self.suite = {"warmup": args.warmup, "frames": args.frames}
        self.ref_settings = {"spp": args.spp, "bounces": args.bounces, "seed": 1}
        self.refs = {}
        for v in view_names:
            view = {"scene": src.stem, "camera": v, "file": str(src)}
            ref_dir, cached = self.guard(lambda: bench.render_reference(tools, view, args.size, self.ref_settings,
                                                                        Path(args.cache)), f"reference {v}")
            info = json.loads((ref_dir / "reference.json").read_text())
            self.refs[v] = (ref_dir, info["exposure"])
            log(f"placement: reference {v} {args.size} {args.spp} spp{' (cached)' if cached else ''}")
        # --max-roughness: score only pixels below it (the roughness AOV does not change with CMOs).
        self.rough = {}
        if args.max_roughness is not None:
            for v in view_names:
                out = work / f"roughness_{v.replace('/', '_')}"
                out.mkdir(parents=True, exist_ok=True)
                cmd = [tools.capture, "--scene", str(src), "--camera", v, "--size", args.size, "--warmup", "0",
                       "--aov", "roughness", "--out", str(out)]
                if bench.run(cmd, out / "log.txt") != 0:
                    raise RuntimeError(f"roughness capture failed for {v}; see {out / 'log.txt'}")
                self.rough[v] = bench.last_frame(out, "roughness")

    def score(self, v, image, ref_dir, exposure, heatmap):
        if v not in self.rough:
            return self.bench.score(self.tools, image, ref_dir, "reflection", exposure, heatmap)
        cmd = [self.tools.metrics, "compare", "--test", str(image), "--ref", str(ref_dir / "reflection.0000.exr"),
               "--ref-mask", str(ref_dir / "reflective.0000.exr"), "--test-mask", str(image),
               "--scale", str(exposure), "--band-image", str(self.rough[v]),
               "--bands", f"0,{self.args.max_roughness:g}"]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"speculum-metrics failed: {r.stderr.strip()}")
        return json.loads(r.stdout)["bands"][0]

    @staticmethod
    def guard(fn, what):
        try:
            return fn()
        except SystemExit as e:  # the bench's fail(): its message is already on stderr
            raise RuntimeError(f"{what} failed (exit {e.code})")

    def key(self, cmos):
        return json.dumps([[[round(x, 5) for x in c["pos"]], c["res"], c["order"]] for c in cmos])

    def measure(self, cmos):
        k = self.key(cmos)
        if k in self.cache:
            return self.cache[k]
        self.count += 1
        folder = self.work / f"m{self.count:03d}"
        folder.mkdir(parents=True, exist_ok=True)
        gltf = folder / "scene.gltf"
        gltf.write_text(dump(edited_document(self.doc, cmos, str(self.src.parent), str(folder), self.kind,
                                             os.path.relpath(self.work / "scene_glb.bin", folder)
                                             if self.bin_uri else None)))
        per_view, ms_sum = {}, 0.0
        t0 = time.monotonic()
        for v in self.view_names:
            view = {"scene": self.src.stem, "camera": v, "file": str(gltf)}
            out = folder / v.replace("/", "_")
            image, refl_ms, _, _ = self.guard(lambda: self.bench.capture(
                self.tools, view, self.args.size, self.args.set, "reflection", self.suite, out), f"capture {v}")
            ref_dir, exposure = self.refs[v]
            m = self.guard(lambda: self.score(v, image, ref_dir, exposure, out / "heatmap.png"), f"score {v}")
            per_view[v] = m["psnr_db"] if m["psnr_db"] is not None else float("nan")
            ms_sum += refl_ms
        vals = list(per_view.values())
        result = {"mean": sum(vals) / len(vals), "per_view": per_view, "ms": ms_sum / len(vals),
                  "seconds": time.monotonic() - t0}
        if not self.args.keep_work:
            shutil.rmtree(folder, ignore_errors=True)
        self.cache[k] = result
        return result


def fmt_pos(p):
    return "(" + ",".join(f"{x:.2f}" for x in p) + ")"


def config_entry(cmos):
    return [{"pos": [round(x, 5) for x in c["pos"]], "resolution": c["res"], "order": c["order"],
             "candidate": c.get("rank")} for c in cmos]


def resolve_views(args, doc, src):
    """The views' names and cameras; InputError for an unknown name or a scene without cameras."""
    cams = cameras(doc)
    names = [c[0] for c in cams]
    if args.views:
        view_names = list(dict.fromkeys(v.strip() for v in args.views.split(",") if v.strip()))
        if not view_names:
            raise InputError("--views: no camera name given", 2)
        for v in view_names:
            if v not in names:
                raise InputError(f"--views: {src}: no camera named '{v}' (cameras: {', '.join(names) or 'none'})", 2)
    else:
        if not names:
            raise InputError(f"{src}: the scene has no camera and no --views was given", 3)
        view_names = names
    views = [c for c in cams if c[0] in view_names]
    return view_names, views


def place(args, tools, log):
    src = Path(args.scene)
    doc, buffers, glb_bin = load_document(src)
    view_names, views = resolve_views(args, doc, src)
    t_start = time.monotonic()
    geo = Geometry(doc, buffers, str(src))
    if not geo.tris:
        raise InputError(f"{src}: the active scene has no triangles", 3)
    samples, sky = reflection_samples(geo, doc, views, args.size_wh, grid=args.grid)
    cands = candidates(geo, samples, max_candidates=args.candidates)
    log(f"placement: {len(geo.tris)} triangles, {len(samples)} reflected samples "
        f"({sky / (sky + sum(s['w'] for s in samples) or 1):.0%} of the weight reflects the sky), "
        f"{len(cands)} candidates in {time.monotonic() - t_start:.1f} s")
    for c in cands[:8]:
        log(f"placement:   candidate {c['rank']}: at {fmt_pos(c['pos'])} off {fmt_pos(c['surface'])}, "
            f"sees {c['area']:.1f} of the reflected area (+{c['gain']:.1f} new)")

    resolutions = sorted(args.resolutions_list)
    top = resolutions[-1]
    work = Path(tempfile.mkdtemp(prefix=".placement-", dir=str(Path(args.out).resolve().parent)))
    steps, step_no = [], 0
    planned = 1 + args.max_cmos * (args.tries + args.move_tries) + args.max_cmos * (1 + len(resolutions))
    try:
        meas = Measurer(args, tools, doc, src, glb_bin, view_names, args.kind, work, log)

        def record(action, detail, cmos, r, accepted, prev):
            nonlocal step_no
            step_no += 1
            delta = "" if prev is None else f" ({r['mean'] - prev:+.1f})"
            log(f"placement: step {step_no}/{max(planned, step_no)} {action} {detail}: {r['mean']:.1f} dB{delta}, "
                f"{r['ms']:.0f} ms{'' if accepted else ' (rejected)'}")
            steps.append({"step": step_no, "action": action, "detail": detail, "count": len(cmos),
                          "resolutions": [c["res"] for c in cmos], "cmos": config_entry(cmos),
                          "mean_psnr_db": r["mean"], "per_view_psnr_db": r["per_view"], "reflection_ms": r["ms"],
                          "accepted": accepted, "seconds": r["seconds"]})
            return steps[-1]

        def meets(r):
            return r["mean"] >= args.budget_db

        def with_orders(cmos):
            # until the ordering step, the earlier-added CMO is traced first
            n = len(cmos)
            return [dict(c, order=n - 1 - i) for i, c in enumerate(cmos)]

        current = []
        cur = meas.measure(current)
        baseline = cur
        record("baseline", "the scene as given (no CMO added)", current, cur, True, None)
        if args.gain_db is not None:
            # The budget as a gain over the scene as given (its own baseline measured first).
            args.budget_db = baseline["mean"] + args.gain_db
            log(f"placement: budget {args.budget_db:.2f} dB (baseline {baseline['mean']:.2f} + {args.gain_db:g})")

        # ADD (and MOVE the one added) until the budget is met
        while not meets(cur) and len(current) < args.max_cmos:
            chosen_seen = set().union(*[c["seen"] for c in current]) if current else set()
            pool = marginal_rank(cands, chosen_seen, {c["rank"] for c in current})[:args.tries]
            if not pool:
                log("placement: no candidate left to add")
                break
            best, best_r, best_step = None, None, None
            for cand in pool:
                trial = with_orders(current + [dict(cand, res=top)])
                r = meas.measure(trial)
                st = record("add", f"cmo at {fmt_pos(cand['pos'])} {top} px (candidate {cand['rank']})", trial, r,
                            False, cur["mean"])
                if best_r is None or r["mean"] > best_r["mean"]:
                    best, best_r, best_step = trial, r, st
                if meets(r):
                    break  # the fewest CMOs is reached: no need to try the others
            if best_r["mean"] < cur["mean"] + IMPROVE_DB:
                log(f"placement: no candidate improves on {cur['mean']:.2f} dB; stopping at {len(current)} CMOs")
                break
            best_step["accepted"] = True
            current, cur = best, best_r
            # MOVE: the new CMO nearer to or farther from its reflector
            newest = current[-1]
            for v in newest["variants"][:args.move_tries]:
                if meets(cur):
                    break
                trial = current[:-1] + [dict(newest, pos=v, variants=[])]
                r = meas.measure(trial)
                ok = r["mean"] >= cur["mean"] + IMPROVE_DB
                record("move", f"cmo {len(current) - 1} to {fmt_pos(v)}", trial, r, ok, cur["mean"])
                if ok:
                    current, cur = trial, r

        # DROP: any CMO the budget does not need; the measured loss of each is its contribution
        gains = {}
        if meets(cur) and len(current) > 1:
            changed = True
            while changed and len(current) > 1:
                changed = False
                for i in range(len(current)):
                    trial = with_orders(current[:i] + current[i + 1:])
                    r = meas.measure(trial)
                    ok = meets(r)
                    record("drop", f"cmo {i} at {fmt_pos(current[i]['pos'])}", trial, r, ok, cur["mean"])
                    gains[current[i]["rank"]] = cur["mean"] - r["mean"]
                    if ok:
                        current, cur = trial, r
                        changed = True
                        gains = {}
                        break
        if len(current) == 1:
            gains = {current[0]["rank"]: cur["mean"] - baseline["mean"]}
        elif len(current) > 1 and not gains:
            for i in range(len(current)):
                r = meas.measure(with_orders(current[:i] + current[i + 1:]))
                gains[current[i]["rank"]] = cur["mean"] - r["mean"]

        # ORDER: the largest measured contribution is traced first (highest order)
        if len(current) > 1:
            ranked = sorted(current, key=lambda c: -gains.get(c["rank"], 0.0))
            trial = [dict(c, order=len(ranked) - 1 - i) for i, c in enumerate(ranked)]
            if meas.key(trial) != meas.key(current):
                r = meas.measure(trial)
                ok = r["mean"] >= cur["mean"] - 1e-9 or (meets(r) and not meets(cur))
                record("order", "by contribution: " + ", ".join(f"{gains.get(c['rank'], 0):+.2f} dB" for c in ranked),
                       trial, r, ok, cur["mean"])
                if ok:
                    current, cur = trial, r

        # RESOLUTION: lower each CMO while the budget holds, the least contributing first
        if meets(cur):
            for c0 in sorted(current, key=lambda c: gains.get(c["rank"], 0.0)):
                i = next(j for j, c in enumerate(current) if c["rank"] == c0["rank"])
                for res in [x for x in reversed(resolutions) if x < current[i]["res"]]:
                    trial = [dict(c, res=res) if j == i else c for j, c in enumerate(current)]
                    r = meas.measure(trial)
                    ok = meets(r)
                    record("resolution", f"cmo {i} {current[i]['res']} -> {res} px", trial, r, ok, cur["mean"])
                    if not ok:
                        break
                    current, cur = trial, r

        met = meets(cur)
        out_path = Path(args.out)
        bin_uri = None
        if glb_bin is not None:
            bin_path = out_path.with_suffix(".bin")
            write_atomic(bin_path, data=glb_bin)
            bin_uri = urllib.parse.quote(bin_path.name, safe="/._-~")
        final_doc = edited_document(doc, current, str(src.resolve().parent), str(out_path.resolve().parent),
                                    args.kind, bin_uri)
        write_atomic(out_path, text=dump(final_doc))
        report = {"scene": str(src), "out": str(out_path), "budget_db": args.budget_db,
                  "budget": "mean PSNR over the views >= budget_db (reflection AOV, reflective pixels" +
                            (f" of roughness below {args.max_roughness:g})" if args.max_roughness is not None else ")"),
                  "views": view_names, "size": args.size, "spp": args.spp, "kind": args.kind, "met": met,
                  "baseline": {"mean_psnr_db": baseline["mean"], "per_view_psnr_db": baseline["per_view"],
                               "reflection_ms": baseline["ms"]},
                  "final": {"count": len(current), "cmos": config_entry(current), "mean_psnr_db": cur["mean"],
                            "per_view_psnr_db": cur["per_view"], "reflection_ms": cur["ms"]},
                  "candidates": [{"rank": c["rank"], "pos": list(c["pos"]), "surface": list(c["surface"]),
                                  "area": c["area"], "gain": c["gain"]} for c in cands],
                  "measurements": meas.count, "seconds": time.monotonic() - t_start, "steps": steps}
        write_report(args, report)
        summary = (f"{len(current)} CMO{'s' if len(current) != 1 else ''} "
                   f"({', '.join(str(c['res']) for c in current) or 'none'} px): {cur['mean']:.2f} dB over "
                   f"{len(view_names)} view(s) against the budget {args.budget_db:g} dB "
                   f"(baseline {baseline['mean']:.2f} dB), {meas.count} measurements in {report['seconds']:.0f} s")
        if met:
            log(f"placement: budget met: {summary}; wrote {out_path}")
            return 0
        log(f"placement: budget NOT met with at most {args.max_cmos} CMOs: {summary}; wrote the best found to {out_path}")
        return 1
    finally:
        if not args.keep_work:
            shutil.rmtree(work, ignore_errors=True)


def report_paths(args):
    if args.report:
        j = Path(args.report)
    else:
        o = Path(args.out)
        j = o.with_name(o.stem + ".placement.json")
    return j, j.with_suffix(".md")


def write_report(args, report):
    j, md = report_paths(args)
    write_atomic(j, text=json.dumps(report, indent=2) + "\n")
    views = report["views"]
    lines = ["# speculum-probes place", "",
             f"Scene `{report['scene']}`, views {', '.join(views)} at {report['size']}, reference {report['spp']} spp; "
             f"budget: mean PSNR >= {report['budget_db']:g} dB; CMO kind `{report['kind']}`; "
             f"{'met' if report['met'] else 'NOT met'} with {report['final']['count']} CMO(s), "
             f"{report['final']['mean_psnr_db']:.2f} dB (baseline {report['baseline']['mean_psnr_db']:.2f} dB); "
             f"{report['measurements']} measurements in {report['seconds']:.0f} s.", "",
             "| step | action | detail | CMOs | resolutions | mean PSNR dB | " + " | ".join(views) +
             " | reflection ms | kept |",
             "|---|---|---|---|---|---|" + "---|" * len(views) + "---|---|"]
    for s in report["steps"]:
        lines.append(f"| {s['step']} | {s['action']} | {s['detail']} | {s['count']} | "
                     f"{','.join(map(str, s['resolutions'])) or '-'} | {s['mean_psnr_db']:.2f} | " +
                     " | ".join(f"{s['per_view_psnr_db'][v]:.2f}" for v in views) +
                     f" | {s['reflection_ms']:.2f} | {'yes' if s['accepted'] else ''} |")
    write_atomic(md, text="\n".join(lines) + "\n")


# ------------------------------------------------------------------------------------------
# Command line.


def parse_size(text):
    try:
        w, h = text.lower().split("x")
        w, h = int(w), int(h)
    except ValueError:
        raise InputError(f"--size {text}: needs WxH with two whole numbers", 2)
    if not (1 <= w <= 16384 and 1 <= h <= 16384):
        raise InputError(f"--size {text}: each side must be in 1..16384", 2)
    return w, h


def check_args(args):
    if (args.budget_db is None) == (args.gain_db is None):
        raise InputError("give one of --budget-db and --gain-db", 2)
    if args.gain_db is not None:
        if not math.isfinite(args.gain_db):
            raise InputError(f"--gain-db {args.gain_db}: must be a finite number of dB", 2)
        args.budget_db = 0.0  # set from the baseline once it is measured
    try:
        args.budget_db = float(args.budget_db)
    except ValueError:
        raise InputError(f"--budget-db {args.budget_db}: not a number", 2)
    if not math.isfinite(args.budget_db):
        raise InputError(f"--budget-db {args.budget_db}: must be a finite number of dB", 2)
    args.size_wh = parse_size(args.size)
    try:
        res = [int(x) for x in args.resolutions.split(",") if x.strip()]
    except ValueError:
        raise InputError(f"--resolutions {args.resolutions}: needs whole numbers separated by commas", 2)
    if not res or any(r < 32 or r > 4096 or r & (r - 1) for r in res):
        raise InputError(f"--resolutions {args.resolutions}: each must be a power of two in [32, 4096]", 2)
    args.resolutions_list = sorted(set(res))
    for name, lo in (("max_cmos", 1), ("spp", 1), ("tries", 1), ("move_tries", 0), ("warmup", 0), ("frames", 1),
                     ("bounces", 1), ("candidates", 1), ("grid", 4)):
        if getattr(args, name) < lo:
            raise InputError(f"--{name.replace('_', '-')} {getattr(args, name)}: must be at least {lo}", 2)
    out = Path(args.out)
    if out.suffix.lower() != ".gltf":
        raise InputError(f"--out {args.out}: must name a .gltf file", 2)
    if out.exists() and not out.is_file():
        raise InputError(f"--out {args.out}: is a folder or a device, not a file", 2)
    parent = out.resolve().parent
    if not parent.is_dir():
        raise InputError(f"--out {args.out}: the folder {parent} does not exist", 2)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"--out {args.out}: the folder {parent} is not writable", 2)
    if args.report:
        rp = Path(args.report)
        if rp.exists() and not rp.is_file():
            raise InputError(f"--report {args.report}: is a folder or a device, not a file", 2)
        if not rp.resolve().parent.is_dir() or not os.access(rp.resolve().parent, os.W_OK | os.X_OK):
            raise InputError(f"--report {args.report}: its folder does not exist or is not writable", 2)
    for s in args.set:
        if "=" not in s:
            raise InputError(f"--set {s}: needs KEY=VALUE", 2)


def probe_capture(args, tools):
    """One tiny render of the scene as given: a bad scene is exit 3 here, in seconds."""
    import speculum_bench as bench
    scratch = Path(tempfile.mkdtemp(prefix=".placement-probe-", dir=str(Path(args.out).resolve().parent)))
    try:
        cmd = [tools.capture, "--scene", str(args.scene), "--size", "32x18", "--warmup", "0", "--aov", "reflection",
               "--out", str(scratch / "out")]
        for s in args.set:
            cmd += ["--set", s]
        rc = bench.run(cmd, scratch / "log.txt")
        text = (scratch / "log.txt").read_text(errors="replace").strip().splitlines()
        last = text[-1] if text else ""
        if rc == 3:
            raise InputError(f"{args.scene}: speculum-capture refuses the scene: {last}", 3)
        if rc == 2:
            raise InputError(f"speculum-capture refuses the arguments (--set, or no reflection AOV): {last}", 2)
        if rc != 0:
            raise RuntimeError(f"speculum-capture failed on {args.scene} (exit {rc}): {last}")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def main(argv=None):
    p = argparse.ArgumentParser(prog="speculum-probes", description=__doc__.split("\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    for hidden in ("--capture", "--reference", "--metrics", "--cache-default"):  # set by the wrapper
        p.add_argument(hidden, help=argparse.SUPPRESS)
    sub_p = p.add_subparsers(dest="command", metavar="place")
    pl = sub_p.add_parser("place", help="propose CMOs that meet an accuracy budget", description=__doc__,
                          formatter_class=argparse.RawDescriptionHelpFormatter)
    pl.add_argument("--scene", required=True, help="glTF scene (.gltf or .glb)")
    pl.add_argument("--gain-db", type=float,
                    help="instead of --budget-db: the budget is the scene's own baseline (as given) plus this")
    pl.add_argument("--budget-db",
                    help="the budget: the configuration must reach a mean PSNR >= D dB over the views "
                         "(each view: the reflection AOV against speculum-reference on reflective pixels)")
    pl.add_argument("--views", help="comma list of camera names (default: every camera of the scene)")
    pl.add_argument("--size", default="240x135", help="render size WxH (default 240x135)")
    pl.add_argument("--max-cmos", type=int, default=4, help="at most this many CMOs (default 4)")
    pl.add_argument("--resolutions", default="64,128,256",
                    help="cube face sizes to choose from, powers of two >= 32 (default 64,128,256); "
                         "CMOs are added at the largest and lowered while the budget holds")
    pl.add_argument("--spp", type=int, default=16, help="reference samples per pixel (default 16)")
    pl.add_argument("--bounces", type=int, default=2, help="reference bounces (default 2, as the bench)")
    pl.add_argument("--warmup", type=int, default=3, help="speculum-capture warm-up frames (default 3)")
    pl.add_argument("--frames", type=int, default=2, help="speculum-capture counted frames (default 2)")
    pl.add_argument("--tries", type=int, default=3, help="candidates measured per ADD step (default 3)")
    pl.add_argument("--move-tries", type=int, default=2, help="positions tried per MOVE step (default 2)")
    pl.add_argument("--candidates", type=int, default=12, help="candidate centres proposed (default 12)")
    pl.add_argument("--grid", type=int, default=48, help="sample rays across each view (default 48)")
    pl.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="engine setting for every capture (repeatable)")
    pl.add_argument("--max-roughness", type=float,
                    help="score only pixels whose roughness is below this (CMOs trace up to "
                         "reflections.cmo_max_roughness; default: every reflective pixel)")
    pl.add_argument("--kind", choices=("cmo", "local_cubemap"), default="cmo",
                    help="probe kind written (default cmo; local_cubemap measures the loop with local "
                         "cubemaps as a stand-in)")
    pl.add_argument("--out", required=True, help="output .gltf (written atomically)")
    pl.add_argument("--report", help="report JSON (default OUT-stem.placement.json; a .md beside it)")
    pl.add_argument("--cache", help="reference image cache (default: a folder beside --out)")
    pl.add_argument("--keep-work", action="store_true", help="keep every measured configuration's files")
    args = p.parse_args(argv)
    if args.command != "place":
        p.print_usage(sys.stderr)
        print("speculum-probes: a command is required: place", file=sys.stderr)
        return 2
    try:
        check_args(args)
        for tool in (args.capture, args.reference, args.metrics):
            if not tool or not os.access(tool, os.X_OK):
                raise InputError(f"{tool}: not built (run the wrapper in the build folder)", 2)
        if args.cache is None:
            args.cache = args.cache_default or str(Path(args.out).resolve().parent / ".placement-cache")
        doc = load_document(args.scene)[0]  # the scene's own problems first, before any device starts
        resolve_views(args, doc, Path(args.scene))
        probe_capture(args, args)
        return place(args, args, lambda line: print(line, flush=True))
    except InputError as e:
        print(f"speculum-probes: {e}", file=sys.stderr)
        return e.code
    except RuntimeError as e:
        print(f"speculum-probes: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
