#!/usr/bin/env python3
"""stub.py LIB OUTDIR [WANTED]: writes OUTDIR/<soname>, a library exporting LIB's dynamic symbols
(those named in the file WANTED, if given) under their versions, so that a binary linked against
LIB loads where LIB and its dependency tree are absent. Each function returns a pointer to 64
zero bytes (OIIO calls its plugins' version functions and reads a string), each object is zeros.
Only for libraries whose code does nothing the caller needs."""
import os, re, subprocess, sys, tempfile
lib, out = sys.argv[1], sys.argv[2]
wanted = set(open(sys.argv[3]).read().split()) if len(sys.argv) > 3 else None
soname = re.search(r"SONAME.*\[(.*)\]", subprocess.run(["readelf", "-d", lib], capture_output=True, text=True).stdout).group(1)
nm = subprocess.run(["nm", "-D", "--defined-only", "-S", "--with-symbol-versions", lib], capture_output=True, text=True).stdout
asm, versions = [".data", "stub_empty: .zero 64", ".text"], set()
for i, line in enumerate(nm.splitlines()):
    parts = line.split()
    if len(parts) == 4: _, size, kind, name = parts
    elif len(parts) == 3: _, kind, name = parts; size = "8"
    else: continue
    base, ver, default = name, None, False
    if wanted is not None and name.split("@")[0] not in wanted and kind != "A": continue
    if "@@" in name: base, ver = name.split("@@"); default = True
    elif "@" in name: base, ver = name.split("@", 1)
    if kind == "A" or (ver and base == ver): versions.add(ver or base); continue
    if ver: versions.add(ver)
    label = f"stub_{i}"
    sz = min(max(int(size, 16), 8), 256)
    if kind in "TtWwi":
        asm += [f".globl {label}", f".type {label},@function", f"{label}: lea stub_empty(%rip),%rax; ret"]
    else:
        asm += [".data", f".globl {label}", f".type {label},@object", f".size {label},{sz}", f"{label}: .zero {sz}", ".text"]
    if ver:
        asm.append(f'.symver {label},{base}{"@@@" if default else "@"}{ver}')
    else:
        asm += [f'.globl {base}', f'.set {base},{label}']
vs = "".join(f"{v} {{ }};\n" for v in sorted(versions)) + "LOCALS { local: stub_*; };\n" if versions else "{ local: stub_*; };\n"
with tempfile.TemporaryDirectory() as tmp:
    src, script = os.path.join(tmp, "stub.s"), os.path.join(tmp, "stub.map")
    open(src, "w").write("\n".join(asm) + "\n")
    open(script, "w").write(vs)
    subprocess.run(["gcc", "-shared", "-nostdlib", f"-Wl,-soname,{soname}", "-o", os.path.join(out, soname), src,
                    f"-Wl,--version-script={script}"], check=True)
print(soname, os.path.getsize(os.path.join(out, soname)))
