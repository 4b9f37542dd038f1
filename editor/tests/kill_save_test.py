#!/usr/bin/env python3
"""Killed mid-save (issue 14): the editor's save routine is killed with SIGKILL while it writes a
large scene over itself; the file on disk must still load, whole, every time.

kill_save_test.py SAVE_LOOP OUT_DIR

For a .glb (one file, written to a temporary name and renamed) and a .gltf (its .bin, then the
.gltf, each written to a temporary name and renamed), the helper speculum-editor-save-loop opens
the scene as the editor does and saves it over itself in a loop, each save adding a probe node;
the test kills it at a random moment of a save, then loads the file: it must load, and hold the
node count of a save that finished (or of the original).
"""
import json
import os
import random
import re
import shutil
import signal
import struct
import subprocess
import sys
import time


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def grid_scene(n):
    """A (n x n)-vertex grid: about 24 n^2 bytes of vertices and 24 n^2 of indices."""
    pos = bytearray()
    for j in range(n):
        row = b"".join(struct.pack("<3f", i / (n - 1) * 10 - 5, 0.0, j / (n - 1) * 10 - 5) for i in range(n))
        pos += row
    nrm = struct.pack("<3f", 0.0, 1.0, 0.0) * (n * n)
    idx = bytearray()
    for j in range(n - 1):
        base = j * n
        idx += b"".join(struct.pack("<6I", base + i, base + i + n, base + i + 1, base + i + 1, base + i + n,
                                    base + i + n + 1) for i in range(n - 1))
    bin_ = bytes(pos) + nrm + bytes(idx)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "grid", "mesh": 0}, {"name": "probe.start", "translation": [0, 1, 0],
                                                "extensions": {"SPECULUM_reflection_probe": {"extents": [2, 1, 2]}}}],
        "extensionsUsed": ["SPECULUM_reflection_probe"],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3", "min": [-5, 0, -5], "max": [5, 0, 5]},
            {"bufferView": 1, "componentType": 5126, "count": n * n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": 6 * (n - 1) * (n - 1), "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(nrm)},
            {"buffer": 0, "byteOffset": len(pos) + len(nrm), "byteLength": len(idx)},
        ],
        "buffers": [{"byteLength": len(bin_)}],
    }
    return doc, bin_


def write_glb(path, doc, bin_):
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    body = bin_ + b"\0" * (-len(bin_) % 4)
    total = 12 + 8 + len(text) + 8 + len(body)
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<I4s", len(text), b"JSON") + text)
        f.write(struct.pack("<I4s", len(body), b"BIN\0") + body)


def check(helper, scene):
    r = subprocess.run([helper, "--check", scene], capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        fail("%s does not load after the kill: %s" % (scene, (r.stdout + r.stderr).strip()))
    return int(re.search(r"nodes (\d+)", r.stdout).group(1))


def kill_rounds(helper, scene, rounds, rng):
    kills_mid_write = 0
    for r in range(rounds):
        start = check(helper, scene)
        p = subprocess.Popen([helper, "--loop", scene], stdout=subprocess.PIPE, text=True)
        skip = rng.randint(0, 2)  # let some saves finish first
        out = ""
        for line in p.stdout:
            out += line
            if line.startswith("saving"):
                if skip == 0:
                    break
                skip -= 1
        time.sleep(rng.uniform(0.0, 0.15))  # somewhere in the write of a large file
        p.send_signal(signal.SIGKILL)
        out += p.stdout.read()
        p.wait()
        # Save i of this round adds one node: the file holds the original's count, or that of a
        # save that got as far as its rename (the last one may have been killed right after it).
        began = out.count("saving")
        last = out.splitlines()[-1] if out else ""
        kills_mid_write += 1 if last.startswith("saving") else 0
        nodes = check(helper, scene)
        if not start <= nodes <= start + began:
            fail("round %d: %s holds %d nodes; it had %d and %d saves began" % (r, scene, nodes, start, began))
        print("round %d: killed after %s, %s loads with %d nodes" % (r, last.strip(), os.path.basename(scene), nodes))
    return kills_mid_write


def main():
    helper, out = sys.argv[1:3]
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    rng = random.Random(14)
    doc, bin_ = grid_scene(700)  # about 24 MB of geometry
    glb = os.path.join(out, "large.glb")
    write_glb(glb, doc, bin_)
    gltf = os.path.join(out, "large.gltf")
    doc2 = json.loads(json.dumps(doc))
    doc2["buffers"][0]["uri"] = "large.bin"
    json.dump(doc2, open(gltf, "w"))
    open(os.path.join(out, "large.bin"), "wb").write(bin_)
    mid = 0
    for scene in (glb, gltf):
        mid += kill_rounds(helper, scene, 4, rng)
    if mid == 0:
        fail("no kill landed inside a save: the test did not test anything")
    print("OK: %d kills inside a save, every scene loaded afterwards" % mid)


if __name__ == "__main__":
    main()
