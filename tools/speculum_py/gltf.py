"""Reading glTF 2.0 (.gltf and .glb): the document, its buffers, accessors, the active scene's
world transforms and a primitive's triangles. The scene checks and speculum-probes read through
this one reader, so a file the checks pass is the file the placement tool sees."""

import base64
import json
import struct
import urllib.parse
from pathlib import Path

from .vec import mat_from_trs, mat_mul, mat_point


class CheckError(Exception):
    """A file that is not what it should be; the message names what and where."""


def require(cond, msg):
    if not cond:
        raise CheckError(msg)


def load_document(path):
    """(doc, buffers, glb_bin): the JSON and every buffer's bytes (.gltf with files or data: uris, or
    .glb); CheckError, one line naming the file, on anything unreadable."""
    p = Path(path)
    if not p.exists():
        raise CheckError(f"{path}: no such file")
    if not p.is_file():
        raise CheckError(f"{path}: is a folder" if p.is_dir() else f"{path}: is not a regular file")
    try:
        data = p.read_bytes()
    except OSError as e:
        raise CheckError(f"{path}: cannot read: {e.strerror}")
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
        raise CheckError(f"{path}: JSON nests too deeply")
    except (ValueError, UnicodeDecodeError, struct.error) as e:
        raise CheckError(f"{path}: not a glTF file: {str(e)[:200]}")
    if not isinstance(doc, dict):
        raise CheckError(f"{path}: the glTF must be a JSON object")
    for key in ("nodes", "meshes", "accessors", "bufferViews", "buffers", "materials", "cameras", "scenes"):
        if key in doc and not isinstance(doc[key], list):
            raise CheckError(f"{path}: '{key}' must be an array")
    buffers = []
    for i, b in enumerate(doc.get("buffers", [])):
        uri = b.get("uri") if isinstance(b, dict) else None
        if uri is None:
            if glb_bin is None:
                raise CheckError(f"{path}: buffers[{i}] has no uri and there is no GLB BIN chunk")
            buffers.append(glb_bin)
        elif not isinstance(uri, str):
            raise CheckError(f"{path}: buffers[{i}].uri must be a string")
        elif uri.startswith("data:"):
            try:
                buffers.append(base64.b64decode(uri.split(",", 1)[1]))
            except (IndexError, ValueError):
                raise CheckError(f"{path}: buffers[{i}]: a data: uri that is not base64")
        else:
            f = p.parent / urllib.parse.unquote(uri)
            if not f.is_file():
                raise CheckError(f"{path}: buffers[{i}]: buffer file '{uri}' is missing")
            buffers.append(f.read_bytes())
    return doc, buffers, glb_bin



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


def read_values(doc, buffers, ai):
    acc = doc["accessors"][ai]
    if "bufferView" not in acc:  # all zeros (sparse accessors without a base view)
        n = NCOMP[acc["type"]]
        return [tuple([0.0] * n) if n > 1 else 0 for _ in range(acc["count"])]
    vals = read_accessor(doc, buffers, ai)
    if acc.get("normalized"):
        scale = {5120: 127.0, 5121: 255.0, 5122: 32767.0, 5123: 65535.0}.get(acc["componentType"], 1.0)
        vals = [tuple(max(c / scale, -1.0) for c in v) if isinstance(v, tuple) else max(v / scale, -1.0)
                for v in vals]
    return vals


def triangle_indices(idx, mode):
    """Index triples of a primitive's triangles (mode 4 list, 5 strip, 6 fan), strips with the
    odd triangles' first two swapped so every one keeps the strip's winding."""
    if mode == 5:
        return [(idx[k], idx[k + 1], idx[k + 2]) if k % 2 == 0 else (idx[k + 1], idx[k], idx[k + 2])
                for k in range(len(idx) - 2)]
    if mode == 6:
        return [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
    return [(idx[k], idx[k + 1], idx[k + 2]) for k in range(0, len(idx) - 2, 3)]


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
            m = mat_from_trs(n.get("translation", [0, 0, 0]), n.get("rotation", [0, 0, 0, 1]),
                                n.get("scale", [1, 1, 1]))
        world[i] = mat_mul(parent, m)
        for c in n.get("children", []):
            visit(c, world[i], depth + 1)

    for r in scene_roots(doc)[0]:
        visit(r, IDENT, 0)
    return world


def world_triangles(doc, buffers, world):
    """(a, b, c, material) in world space for every triangle of the nodes that `world` (from
    world_matrices) places; points and lines are skipped, they reflect nothing."""
    meshes = doc.get("meshes", [])
    for i, n in enumerate(doc.get("nodes", [])):
        if world[i] is None or not isinstance(n.get("mesh"), int):
            continue
        m = world[i]
        for prim in meshes[n["mesh"]].get("primitives", []):
            mode = prim.get("mode", 4)
            if mode not in (4, 5, 6) or "POSITION" not in prim.get("attributes", {}):
                continue
            pos = [mat_point(m, p) for p in read_values(doc, buffers, prim["attributes"]["POSITION"])]
            idx = read_values(doc, buffers, prim["indices"]) if "indices" in prim else list(range(len(pos)))
            mat = prim.get("material", -1)
            for a, b, c in triangle_indices(idx, mode):
                if max(a, b, c) >= len(pos):
                    raise CheckError(f"meshes[{n['mesh']}]: index out of range")
                yield pos[a], pos[b], pos[c], mat
