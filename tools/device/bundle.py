#!/usr/bin/env python3
"""bundle.py OUTDIR BIN...: copies the shared libraries BIN needs into OUTDIR/lib, replacing the
image-format plugins OIIO links but the benchmarks never call by stubs (stub.py)."""
import os, re, shutil, subprocess, sys, tempfile
out, bins = sys.argv[1], sys.argv[2:]
lib = os.path.join(out, "lib"); os.makedirs(lib, exist_ok=True)
SYSTEM = {"libc.so.6", "libm.so.6", "libgcc_s.so.1", "ld-linux-x86-64.so.2", "libpthread.so.0", "libdl.so.2", "librt.so.1"}
STUB = re.compile(r"lib(opencv_|dcm|oflog|ofstd|av|swscale|swresample|gif|heif|openjp2|openvdb|raw|webp|freetype|tiff|jxl|Ptex|ssl|crypto)")
def path_of(name):
    for d in ("/lib/x86_64-linux-gnu", "/usr/lib/x86_64-linux-gnu", "/usr/lib"):
        p = os.path.join(d, name)
        if os.path.exists(p): return p
    raise SystemExit(f"not found: {name}")
def needed(p):
    return re.findall(r"NEEDED.*\[(.*)\]", subprocess.run(["readelf", "-d", p], capture_output=True, text=True).stdout)
def undefined(p):
    return {l.split()[-1].split("@")[0] for l in subprocess.run(["nm", "-D", "--undefined-only", p], capture_output=True, text=True).stdout.splitlines() if l.strip()}
seen, todo, stubs = set(), [n for b in bins for n in needed(b)], []
wanted = set().union(*(undefined(b) for b in bins))
while todo:
    n = todo.pop()
    if n in seen or n in SYSTEM: continue
    seen.add(n)
    if STUB.match(n):
        stubs.append(n)
    else:
        shutil.copy(path_of(n), os.path.join(lib, n)); todo += needed(path_of(n)); wanted |= undefined(path_of(n))
# Each stub exports only what the copied libraries import from it.
with tempfile.NamedTemporaryFile("w", suffix=".txt") as f:
    f.write("\n".join(sorted(wanted))); f.flush()
    for n in stubs:
        subprocess.run([sys.executable, os.path.join(os.path.dirname(__file__), "stub.py"), path_of(n), lib, f.name],
                       check=True, stdout=subprocess.DEVNULL)
print(len(seen), "libraries")
