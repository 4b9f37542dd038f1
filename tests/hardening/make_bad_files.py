#!/usr/bin/env python3
"""make_bad_files.py OUT_DIR: writes the hostile inputs of issue 15 that are too big or too
odd to keep in the repository (deep JSON, a 12 MB geometry bomb, image headers claiming huge
sizes). Each starts from the same valid one-quad scene; tests/hardening/CMakeLists.txt runs
the tools on them and checks the exit status and the message."""
import base64, json, os, struct, sys

def quad_scene():
    pos = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    idx = [0, 1, 2, 0, 2, 3]
    data = b"".join(struct.pack("<3f", *p) for p in pos) + struct.pack("<6I", *idx)
    return {
        "asset": {"version": "2.0", "generator": "speculum hardening tests"},
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 24}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [-1, -1, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR"}],
        "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"name": "quad", "mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }

def write_json(path, doc):
    with open(path, "w") as f:
        json.dump(doc, f)

def deep(depth, leaf="0"):
    return "[" * depth + leaf + "]" * depth

def main(out):
    os.makedirs(out, exist_ok=True)
    # Deep JSON: 20,000 nested arrays in extras (tinygltf overflowed the stack at ~16,000).
    text = json.dumps(quad_scene())
    with open(os.path.join(out, "deep_extras.gltf"), "w") as f:
        f.write(text[:-1] + ', "extras": ' + deep(20000) + "}")
    with open(os.path.join(out, "deep_settings.json"), "w") as f:
        f.write('{"render.exposure": 1, "x": ' + deep(20000) + "}")
    with open(os.path.join(out, "deep_suite.json"), "w") as f:
        f.write('{"methods": ' + deep(20000) + "}")
    with open(os.path.join(out, "deep_path.json"), "w") as f:
        f.write('{"frames": 2, "keys": ' + deep(20000) + "}")
    # Environment maps: a device, and headers that claim huge images (21-22 bytes each).
    for name, env in [("env_dev_zero", "/dev/zero"), ("env_huge_ppm", "huge.ppm"), ("env_big_hdr", "big.hdr"),
                      ("env_folder", ".")]:
        doc = quad_scene()
        doc["scenes"][0]["extras"] = {"environment": env}
        write_json(os.path.join(out, name + ".gltf"), doc)
    with open(os.path.join(out, "huge.ppm"), "wb") as f:
        f.write(b"P6\n100000 100000\n255\n")
    with open(os.path.join(out, "big.hdr"), "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 10000 +X 20000\n")
    # Geometry bomb: one 1 M-vertex accessor (a 12 MB buffer) used by 48 primitives.
    n = 3 * 349525  # 1,048,575 vertices: whole triangles
    with open(os.path.join(out, "bomb.bin"), "wb") as f:
        f.write(struct.pack("<3f", 0, 0, 0) * n)
    doc = quad_scene()
    doc["buffers"].append({"byteLength": 12 * n, "uri": "bomb.bin"})
    doc["bufferViews"].append({"buffer": 1, "byteOffset": 0, "byteLength": 12 * n})
    doc["accessors"].append({"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC3",
                             "min": [0, 0, 0], "max": [0, 0, 0]})
    doc["meshes"].append({"name": "bomb", "primitives": [{"attributes": {"POSITION": 2}}] * 48})
    doc["nodes"].append({"name": "bomb", "mesh": 1})
    doc["scenes"][0]["nodes"] = [0, 1]
    write_json(os.path.join(out, "geometry_bomb.gltf"), doc)
    # The same mesh once, placed by 4,000 nodes: fine for the engine (instanced draws), too much
    # for the reference renderer, which flattens every placement.
    doc["meshes"][1]["primitives"] = [{"attributes": {"POSITION": 2}}]
    doc["nodes"] = [{"name": "quad", "mesh": 0}] + [
        {"name": "copy%d" % i, "mesh": 1, "translation": [i, 0, 0]} for i in range(4000)]
    doc["scenes"][0]["nodes"] = list(range(len(doc["nodes"])))
    write_json(os.path.join(out, "many_instances.gltf"), doc)
    # Settings: hex numbers, true for a named choice, text after the object.
    write_json(os.path.join(out, "hex_setting.json"), {"render.exposure": "0x10"})
    write_json(os.path.join(out, "bool_for_choice.json"), {"reflections.trace": True})
    with open(os.path.join(out, "trailing_settings.json"), "w") as f:
        f.write('{"render.exposure": 1.0} trailing')

if __name__ == "__main__":
    main(sys.argv[1])
