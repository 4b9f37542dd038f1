#!/usr/bin/env python3
"""Writes the bad-probe scenes of the capture CLI tests (tests/capture/CMakeLists.txt, probe_*):
one triangle, a camera and nodes with SPECULUM_reflection_probe. Run from anywhere:
    python3 tests/data/bad/make_probe_scenes.py
and commit the .gltf files it writes next to itself."""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def triangle_buffer():
    positions = [(-1.0, 0.0, -1.0), (1.0, 0.0, -1.0), (0.0, 0.0, 1.0)]
    normals = [(0.0, 1.0, 0.0)] * 3
    data = b"".join(struct.pack("<3f", *p) for p in positions)
    data += b"".join(struct.pack("<3f", *n) for n in normals)
    data += struct.pack("<3I", 0, 2, 1)  # counter-clockwise seen from +y
    return data


def cube_buffer():
    """A closed cube [-1, 1]^3, outward counter-clockwise faces (no normals: the loader makes them)."""
    positions = [(x, y, z) for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    indices = []
    for a, b, c, d in quads:
        indices += [a, b, c, a, c, d]
    return positions, indices


def scene(probes, closed_cube=False, probe_at=(0, 1, 0)):
    data = triangle_buffer()
    nodes = [{"name": "triangle", "mesh": 0},
             {"name": "main", "camera": 0, "translation": [0, 2, 4]}]
    for name, ext in probes:
        node = {"name": name, "translation": list(probe_at),
                "extensions": {"SPECULUM_reflection_probe": ext}}
        nodes.append(node)
    doc = {
        "asset": {"version": "2.0", "generator": "speculum tests (make_probe_scenes.py)"},
        "extensionsUsed": ["SPECULUM_reflection_probe"],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 72, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [-1, 0, -1], "max": [1, 0, 1]},
                      {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5125, "count": 3, "type": "SCALAR"}],
        "materials": [{"name": "plain"}],
        "meshes": [{"name": "triangle",
                    "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05}}],
        "nodes": nodes,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "scene": 0,
    }
    if closed_cube:
        # The triangle's buffer replaced by a closed cube's (positions, then indices).
        positions, indices = cube_buffer()
        data = b"".join(struct.pack("<3f", *q) for q in positions) + struct.pack("<%dI" % len(indices), *indices)
        doc["buffers"] = [{"byteLength": len(data),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}]
        doc["bufferViews"] = [{"buffer": 0, "byteOffset": 0, "byteLength": 96},
                              {"buffer": 0, "byteOffset": 96, "byteLength": 4 * len(indices)}]
        doc["accessors"] = [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
                             "min": [-1, -1, -1], "max": [1, 1, 1]},
                            {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"}]
        doc["meshes"] = [{"name": "cube", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}]
    return doc


def probe(**fields):
    ext = {"kind": "local_cubemap", "shape": "box", "extents": [2, 1, 2], "resolution": 8}
    ext.update(fields)
    return ext


def cmo(**fields):
    ext = {"kind": "cmo", "resolution": 16}
    ext.update(fields)
    return ext


def planar(**fields):
    ext = {"kind": "planar", "extents": [2, 2]}
    ext.update(fields)
    return ext


SCENES = {
    # Not a power of two: the loader rejects it, naming the node and `resolution`.
    "probe_resolution_not_pow2.gltf": [("probe.npot", probe(resolution=100))],
    # A zero extent: the loader rejects it, naming the node and `extents`.
    "probe_zero_extent.gltf": [("probe.flat", probe(extents=[2, 0, 2]))],
    # 65 probes: one more than the cube array holds (64).
    "probe_too_many.gltf": [("probe.%02d" % i, probe()) for i in range(65)],
    # Three 4096^2 probes: 3 x 6 faces x 4096^2 x 8 bytes x 4/3 (mips) = 3072 MiB, over 1024 MiB.
    "probe_over_budget.gltf": [("probe.big%d" % i, probe(resolution=4096)) for i in range(3)],
    # A CMO below 16 px (its hierarchy halves it to 1): exit 3 naming the node.
    "cmo_resolution_small.gltf": [("cmo.tiny", cmo(resolution=8))],
    # Nine CMOs: the tracer takes eight.
    "cmo_too_many.gltf": [("cmo.%d" % i, cmo()) for i in range(9)],
    # Planar probes (issue 24): a zero extent, a height out of [16, 4096], five where four fit.
    "planar_zero_extent.gltf": [("planar.flat", planar(extents=[2, 0]))],
    "planar_resolution.gltf": [("planar.tiny", planar(resolution=8))],
    "planar_too_many.gltf": [("planar.%d" % i, planar()) for i in range(5)],
}

# Scenes with their own geometry or placement: name -> (probes, scene() keywords).
SPECIAL = {
    # A CMO at the centre of a closed cube: every ray from it meets a back face first.
    "cmo_inside_box.gltf": ([("cmo.buried", cmo())], {"closed_cube": True, "probe_at": (0, 0, 0)}),
    # A CMO under the single-sided triangle: it sees the triangle's back (culled), so nothing but
    # sky; the documented fallback leaves it out of tracing with a warning.
    "cmo_sees_nothing.gltf": ([("cmo.blind", cmo())], {"probe_at": (0, -1, 0)}),
}

if __name__ == "__main__":
    every = {name: (probes, {}) for name, probes in SCENES.items()}
    every.update(SPECIAL)
    for name, (probes, kw) in every.items():
        with open(os.path.join(HERE, name), "w") as f:
            json.dump(scene(probes, **kw), f, indent=1)
            f.write("\n")
        print("wrote", name)
