"""A Blender-style file: a reproduction of the glTF exporter's output conventions (not a real
export), for the loader's tests of what Blender users will hand it."""

import array
import base64
import json
import os
import struct
import zlib

from speculum_py.gltf import load_document, read_accessor, require

from .catalog import BLENDER_DIR, BLENDER_FILE
from .mesh import MeshData


def png_bytes(w, h, rgb):
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


def check_blender():
    """The Blender-style files load as a plain glTF reader would read them: a camera, embedded
    buffers of the stated length, indices in range and POSITION bounds that match."""
    for fn in sorted(os.listdir(BLENDER_DIR)) if os.path.isdir(BLENDER_DIR) else []:
        if not fn.endswith(".gltf"):
            continue
        d, bufs, _ = load_document(os.path.join(BLENDER_DIR, fn))
        require(d.get("cameras") and any("camera" in n for n in d.get("nodes", [])), fn + ": no camera")
        require(all(b.get("uri", "").startswith("data:") for b in d.get("buffers", [])),
                fn + ": buffers not embedded")
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
