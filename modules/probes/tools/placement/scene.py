"""The scene as placement sees it: the document (through the shared reader), its triangles
in a ray caster, how much each material's reflections matter, and its cameras."""

import struct

from speculum_py import gltf
from speculum_py.enums import MODE, REFLECT_EXT
from speculum_py.gltf import CheckError, world_matrices, world_triangles
from speculum_py.raycast import RayCaster
from speculum_py.vec import length, sub
from speculum_py.vec import normalize as _normalize

from .errors import InputError


def normalize(v):
    return _normalize(v, 1e-20)


def dist(a, b):
    return length(sub(a, b))


def load_document(path):
    """(doc, buffers, glb_bin); InputError 3 on a bad file (the scene's fault, not the arguments')."""
    try:
        return gltf.load_document(path)
    except CheckError as e:
        raise InputError(str(e), 3)


def material_weight(mat):
    """How much a material's reflections matter (0 = none): metals and low roughness most."""
    if not isinstance(mat, dict):
        mat = {}
    ext = mat.get("extensions", {}) if isinstance(mat.get("extensions"), dict) else {}
    if "KHR_materials_unlit" in ext:
        return 0.0
    r = ext.get(REFLECT_EXT, {}) if isinstance(ext.get(REFLECT_EXT), dict) else {}
    if r.get("mode", MODE.screen_space) == MODE.off or r.get("traceCmos", True) is False:
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


class Geometry(RayCaster):
    """World-space triangles of the active scene (the shared BVH caster), with their bounds."""

    def __init__(self, doc, buffers, path="scene"):
        world = world_matrices(doc)
        tris = []  # (a, e1, e2, geometric normal (unit), material index)
        try:
            for a, b, c, mat in world_triangles(doc, buffers, world):
                t = RayCaster.triangle(a, b, c, mat)
                if t is not None:
                    tris.append(t)
        except (CheckError, KeyError, IndexError, TypeError, struct.error) as e:
            raise InputError(f"{path}: cannot read the geometry: {type(e).__name__}: {e}", 3)
        self.lo = tuple(min(min(t[0][k], t[0][k] + t[1][k], t[0][k] + t[2][k]) for t in tris) if tris else 0.0
                        for k in range(3))
        self.hi = tuple(max(max(t[0][k], t[0][k] + t[1][k], t[0][k] + t[2][k]) for t in tris) if tris else 0.0
                        for k in range(3))
        self.diagonal = dist(self.lo, self.hi)
        super().__init__(tris)


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
