#!/usr/bin/env python3
"""Functions longer than N lines (default 100) in the tracked C++, GLSL and Python files: a rough
scan by brace depth (C++/GLSL) and indentation (Python), for the style rule "functions under about
100 lines". Usage: python3 tools/dev/long_functions.py [N] (from the repository root)."""
import sys,re,subprocess
N=int(sys.argv[1]) if len(sys.argv)>1 else 100
files=subprocess.run(['git','ls-files','*.cpp','*.hpp','*.comp','*.glsl','*.frag','*.vert','*.h'],capture_output=True,text=True).stdout.split()
for f in files:
    try: lines=open(f).read().split('\n')
    except: continue
    depth=0; start=None; name=None
    for i,l in enumerate(lines):
        code=re.sub(r'//.*','',l); code=re.sub(r'"([^"\\]|\\.)*"','""',code)
        if depth<=1 and start is None and re.search(r'\)\s*(const)?\s*(override)?\s*(noexcept)?\s*(->\s*[\w:<>]+)?\s*\{\s*$',code) and not re.match(r'\s*(if|for|while|switch|else)\b',code) and not code.strip().startswith('}'):
            start=i; name=l.strip()[:90]; base=depth
        depth+=code.count('{')-code.count('}')
        if start is not None and depth<=base:
            if i-start>N: print(f"{i-start:4d} {f}:{start+1} {name}")
            start=None
    # py
for f in subprocess.run(['git','ls-files','*.py'],capture_output=True,text=True).stdout.split():
    lines=open(f).read().split('\n')
    for i,l in enumerate(lines):
        m=re.match(r'(\s*)def (\w+)',l)
        if not m: continue
        ind=len(m.group(1)); j=i+1
        while j<len(lines) and (not lines[j].strip() or len(lines[j])-len(lines[j].lstrip())>ind): j+=1
        if j-i>N: print(f"{j-i:4d} {f}:{i+1} def {m.group(2)}")
