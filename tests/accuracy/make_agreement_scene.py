#!/usr/bin/env python3
"""Writes the 40 dB agreement scene (Python standard library only, deterministic):

    make_agreement_scene.py OUT_DIR   ->  OUT_DIR/mirror_wall.gltf, .bin, wall.png

A roughness-0 mirror (y = 0, SPECULUM_reflections screen_space) on an unlit grey ground, in front
of an unlit wall (z = -5) textured with a smooth colour gradient, seen by camera `main` at
(0, 0.5, 0) looking straight at the wall. Every mirror pixel reflects a wall point that is itself
on screen, away from the screen's edges where screen-space tracing fades out by design: a planar
mirror keeps a pixel's screen x (the reflected point lies along the same horizontal direction),
so the mirror is a wedge from the camera that covers only the middle 55% of the width, and it
runs from 1.5 to 4 m out, so its reflections meet the wall between y = 0.13 and 1.2 m, in the
lower middle of the wall's image, and no reflected ray is shorter than 1 m (contact reflections,
where a ray hits the wall right at its start, are a failure case of their own, not a question of
definition). Unlit surfaces look the same from every direction, and smooth
colours leave no hard edges whose sub-pixel position would dominate the error: what is left is
the definition of `reflection` itself, which must agree within 40 dB PSNR.
"""
import json
import math
import struct
import sys
import zlib
from pathlib import Path


def png(path, width, height, pixel):
    rows = b"".join(b"\x00" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    Path(path).write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                           + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def wall_texel(x, y, w=128, h=64):
    u, v = (x + 0.5) / w, (y + 0.5) / h
    r = 0.25 + 0.55 * u
    g = 0.3 + 0.5 * (1.0 - v)
    b = 0.45 + 0.3 * math.sin(2.0 * math.pi * u) * math.cos(math.pi * v)
    return tuple(int(round(255 * min(max(c, 0.0), 1.0))) for c in (r, g, b))


def quad(corners, normal, uvs):
    return [(c, normal, t) for c, t in zip(corners, uvs)]


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    png(out / "wall.png", 128, 64, wall_texel)
    tan_half_width = 0.55 * math.tan(0.95 / 2) * 16 / 9
    near, far = 1.5, 4.0
    mirror = quad([(-far * tan_half_width, 0, -far), (-near * tan_half_width, 0, -near),
                   (near * tan_half_width, 0, -near), (far * tan_half_width, 0, -far)], (0, 1, 0),
                  [(0, 0), (0, 1), (1, 1), (1, 0)])
    ground = quad([(-15, -0.01, -5), (-15, -0.01, 5), (15, -0.01, 5), (15, -0.01, -5)], (0, 1, 0),
                  [(0, 0), (0, 1), (1, 1), (1, 0)])
    wall = quad([(-15, 0, -5), (15, 0, -5), (15, 8, -5), (-15, 8, -5)], (0, 0, 1), [(0, 1), (1, 1), (1, 0), (0, 0)])
    blob, views, accessors, meshes = bytearray(), [], [], []
    for index, verts in enumerate((mirror, wall, ground)):
        first = len(accessors)
        for k, (fmt, n, kind) in enumerate((("3f", 3, "VEC3"), ("3f", 3, "VEC3"), ("2f", 2, "VEC2"))):
            data = b"".join(struct.pack("<" + fmt, *v[k]) for v in verts)
            views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
            acc = {"bufferView": len(views) - 1, "componentType": 5126, "count": len(verts), "type": kind}
            if k == 0:
                acc["min"] = [min(v[0][i] for v in verts) for i in range(3)]
                acc["max"] = [max(v[0][i] for v in verts) for i in range(3)]
            accessors.append(acc)
            blob += data
        idx = struct.pack("<6I", 0, 1, 2, 0, 2, 3)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(idx)})
        accessors.append({"bufferView": len(views) - 1, "componentType": 5125, "count": 6, "type": "SCALAR"})
        blob += idx
        meshes.append({"name": ["mirror", "wall", "ground"][index], "primitives": [{
            "attributes": {"POSITION": first, "NORMAL": first + 1, "TEXCOORD_0": first + 2},
            "indices": first + 3, "material": index}]})
    (out / "mirror_wall.bin").write_bytes(bytes(blob))
    doc = {
        "asset": {"version": "2.0", "generator": "tests/accuracy/make_agreement_scene.py"},
        "extensionsUsed": ["SPECULUM_reflections", "KHR_materials_unlit"],
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3], "extras": {"exposure": 1.0}}],
        "nodes": [{"name": "mirror", "mesh": 0}, {"name": "wall", "mesh": 1}, {"name": "ground", "mesh": 2},
                  {"name": "main", "camera": 0, "translation": [0, 0.5, 0]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.95, "znear": 0.05}}],
        "meshes": meshes,
        "materials": [
            {"name": "floor.mirror", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1],
                                                              "metallicFactor": 1.0, "roughnessFactor": 0.0},
             "extensions": {"SPECULUM_reflections": {"mode": "screen_space"}}},
            {"name": "wall.unlit", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
             "extensions": {"KHR_materials_unlit": {}}},
            {"name": "ground.unlit", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.2, 0.2, 1]},
             "extensions": {"KHR_materials_unlit": {}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": "wall.png"}],
        "buffers": [{"uri": "mirror_wall.bin", "byteLength": len(blob)}],
        "bufferViews": views,
        "accessors": accessors,
    }
    (out / "mirror_wall.gltf").write_text(json.dumps(doc, indent=1))


if __name__ == "__main__":
    main()
