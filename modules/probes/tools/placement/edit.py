"""The glTF edit: the scene with CMO nodes added and every other key kept, written atomically."""

import json
import math
import os
import tempfile
import urllib.parse
from pathlib import Path

from speculum_py.enums import KIND, PROBE_EXT, SHAPE, UPDATE
from speculum_py.gltf import scene_roots



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


def edited_document(doc, cmos, src_dir, dst_dir, kind=KIND.cmo, bin_uri=None, extra_nodes=()):
    """A deep copy of doc with one node per CMO appended (to "nodes" and to the active scene's
    root list), the extension listed in extensionsUsed, relative file references rewritten for
    dst_dir; every other key is kept. bin_uri: the uri of a GLB's BIN chunk written as a file.
    extra_nodes: whole nodes appended first (the planar probes, placement/planar.py)."""
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
    if not cmos and not extra_nodes:
        return out
    nodes = out.setdefault("nodes", [])
    taken = {n.get("name") for n in nodes if isinstance(n, dict)}
    roots, index = scene_roots(out)
    if index is None:
        if not out.get("scenes"):
            out["scenes"] = [{"nodes": list(roots)}]
            out["scene"] = 0
            index = 0
    for extra in extra_nodes:
        node = json.loads(json.dumps(extra))
        while node["name"] in taken:
            node["name"] += "_"
        taken.add(node["name"])
        nodes.append(node)
        if index is not None:
            out["scenes"][index].setdefault("nodes", []).append(len(nodes) - 1)
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
                                           "update": UPDATE.once, "shape": SHAPE.sphere, "extents": [round(r, 6)] * 3,
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
