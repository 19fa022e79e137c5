#!/usr/bin/env python3
"""Dependency cycles between the modules of each crate.

Usage: python3 scripts/module_cycles.py [crates/...]   (default: every crate under crates/)

A module depends on another when its code names it through `crate::NAME` (in a `use` or a
path); comments (doc links) and `#[cfg(test)]` modules are ignored, since a test may use
anything. Prints each strongly connected component of more than one module
and exits 1 if there is any.
"""
import pathlib
import re
import sys


def strip_tests(text):
    """Drop `#[cfg(test)] mod … { … }` blocks (brace matching)."""
    out, i = [], 0
    for m in re.finditer(r"#\[cfg\(test\)\]\s*mod\s+\w+\s*\{", text):
        if m.start() < i:
            continue
        out.append(text[i:m.start()])
        depth, j = 1, m.end()
        while j < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        i = j
    out.append(text[i:])
    return "".join(out)


def modules(src):
    mods = {}
    for f in sorted(src.glob("*.rs")):
        name = f.stem
        if name in ("lib", "main"):
            continue
        # comments (doc links included) are not dependencies
        code = re.sub(r"//[^\n]*", "", f.read_text())
        mods[name] = strip_tests(code)
    return mods


def graph(mods):
    g = {m: set() for m in mods}
    for m, text in mods.items():
        for dep in re.findall(r"\bcrate::(\w+)", text):
            if dep in mods and dep != m:
                g[m].add(dep)
        for block in re.findall(r"\bcrate::\{([^}]*)\}", text):
            for dep in re.findall(r"(\w+)", block):
                if dep in mods and dep != m:
                    g[m].add(dep)
    return g


def sccs(g):
    index, low, on, stack, out, n = {}, {}, set(), [], [], [0]

    def visit(v):
        index[v] = low[v] = n[0]
        n[0] += 1
        stack.append(v)
        on.add(v)
        for w in g[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(comp)

    sys.setrecursionlimit(10000)
    for v in g:
        if v not in index:
            visit(v)
    return [c for c in out if len(c) > 1]


def main():
    roots = [pathlib.Path(a) for a in sys.argv[1:]] or sorted(pathlib.Path("crates").glob("*"))
    bad = 0
    for root in roots:
        src = root / "src"
        if not src.is_dir():
            continue
        for comp in sccs(graph(modules(src))):
            bad += 1
            print(f"{root.name}: cycle among {', '.join(sorted(comp))}")
    if not bad:
        print("no module cycles")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
