#!/usr/bin/env python3
"""Dependency cycles between the modules of each crate, every module file counted.

Usage: python3 scripts/module_cycles.py [crates/...]   (default: every crate under crates/)

Every `.rs` file under `src/` is a module (`a.rs` and `a/mod.rs` are `a`, `a/b.rs` is
`a::b`, `lib.rs` the crate root). A module depends on another when its code names it or
one of its items: `use` statements (braces expanded) and paths in code starting with
`crate::`, `super::`, `self::` or a child module's name. A name reached through a
`pub use` re-export is followed to the module that defines it, so a facade (`lib.rs`, a
`mod.rs` that only re-exports) is no dependency of the modules it re-exports: a `pub use`
is a namespace, not code that depends. A module and one that contains it (a folder's
`mod.rs`, the crate root) are not counted as depending on each other: the folder's own
module holds what its children share. Every other pair is: siblings, and modules of
different folders at any depth: the children of every module are checked with
everything inside each child counted as the child (`a::x` using `b::y` while `b::z` uses
`a::w` is a cycle between `a` and `b`). Comments
(doc links) and `#[cfg(test)]` modules are ignored, since a test may use anything.
Prints each strongly connected component of more than one module and exits 1 if any.
"""
import pathlib
import re
import sys

ITEM = r"(?:fn|struct|enum|trait|type|const|static|mod|union|macro_rules!)\s+{}\b"


def strip_tests(text):
    """Drop `#[cfg(test)] mod … { … }` blocks (brace matching)."""
    out, i = [], 0
    for m in re.finditer(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+\w+\s*\{", text):
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


def module_name(src, f):
    parts = list(f.relative_to(src).with_suffix("").parts)
    if parts[-1] in ("lib", "main", "mod"):
        parts = parts[:-1]
    return "::".join(parts)


def load(src):
    """Module path ('' is the crate root) → code without comments or tests."""
    mods = {}
    for f in sorted(src.rglob("*.rs")):
        if f.parent != src and f.name in ("main.rs",) or "bin" in f.relative_to(src).parts:
            continue
        code = re.sub(r"//[^\n]*", "", f.read_text())
        code = re.sub(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+\w+\s*;", "", code)
        mods[module_name(src, f)] = strip_tests(code)
    return mods


def join(parent, child):
    return f"{parent}::{child}" if parent else child


def parent_of(m):
    return m.rsplit("::", 1)[0] if "::" in m else ""


def related(a, b):
    """Whether a and b are the same module or one contains the other (the crate root
    contains every module). A folder's own module (`mod.rs`, `lib.rs`) holds what its
    children share and calls them: that is the folder's structure, not a cycle."""
    return a == b or a == "" or b == "" or b.startswith(a + "::") or a.startswith(b + "::")


def expand_use(tree):
    """`a::{b, c::{d, e as f}}` → [['a','b'], ['a','c','d'], ['a','c','e']]."""
    tree = re.sub(r"\s+", "", tree)
    out = []

    def walk(prefix, t):
        depth, start, items = 0, 0, []
        for i, ch in enumerate(t):
            if ch == "{":
                depth += 1
            elif ch == "}":
                depth -= 1
            elif ch == "," and depth == 0:
                items.append(t[start:i])
                start = i + 1
        items.append(t[start:])
        for item in filter(None, items):
            if "{" in item:
                head, rest = item.split("{", 1)
                walk(prefix + [s for s in head.split("::") if s], rest[: rest.rfind("}")])
            else:
                out.append(prefix + item.split(" as ")[0].split("as")[0:1][0].split("::")
                           if " as " in item else prefix + re.split(r"as(?=[A-Za-z_])", item)[0].split("::")
                           if False else prefix + item.split("::"))

    walk([], tree)
    return [[re.sub(r"as\w+$", "", s) if i == len(p) - 1 and re.search(r"\bas\b", s) else s
             for i, s in enumerate(p)] for p in out]


class Crate:
    def __init__(self, src):
        self.mods = load(src)
        self.reexports = {m: self._reexports(m) for m in self.mods}

    def _reexports(self, m):
        """Name → path (from module m) of every `pub use` in m; '*' → glob sources."""
        out = {}
        for tree in re.findall(r"\bpub(?:\([^)]*\))?\s+use\s+([^;]+);", self.mods[m]):
            tree = re.sub(r"\s+as\s+(\w+)", r" as \1", tree)
            for item in self._split_aliases(tree):
                path, alias = item
                out.setdefault(alias, []).append(path)
        return out

    def _split_aliases(self, tree):
        flat = re.sub(r"\s+as\s+", "@", tree)
        for p in expand_use(flat):
            last = p[-1]
            name, alias = (last.split("@") + [None])[:2]
            yield p[:-1] + [name], alias or name

    def resolve(self, m, path, seen=None):
        """The module that defines what `path` (segments, as written in module m) names."""
        seen = seen or set()
        if not path:
            return None
        head, rest = path[0], path[1:]
        if head == "crate":
            cur = ""
        elif head in ("super", "self"):
            cur = m
            while path and path[0] in ("super", "self"):
                if path[0] == "super":
                    cur = parent_of(cur)
                path = path[1:]
            rest = path
        elif join(m, head) in self.mods:
            cur, rest = join(m, head), rest
        else:
            return None
        for i, seg in enumerate(rest):
            if join(cur, seg) in self.mods:
                cur = join(cur, seg)
                continue
            return self.defining(cur, seg, seen)
        return cur

    def defining(self, m, name, seen):
        key = (m, name)
        if key in seen:
            return m
        seen.add(key)
        if re.search(ITEM.format(re.escape(name)), self.mods[m]):
            return m
        for path in self.reexports[m].get(name, []):
            # re-exported from another crate (None): no module of this one
            return self.resolve(m, path, seen)
        for path in self.reexports[m].get("*", []):
            src = self.resolve(m, path, seen)
            if src is not None and src in self.mods:
                found = self.defining(src, name, seen)
                if found is not None and found != src or re.search(
                        ITEM.format(re.escape(name)), self.mods.get(src, "")):
                    return found
        return m

    def graph(self):
        g = {m: set() for m in self.mods}
        for m, code in self.mods.items():
            paths = []
            # a `pub use` is the module's namespace (a facade), not code that depends
            for tree in re.findall(r"(?<!pub )(?<!\) )\buse\s+([^;]+);", code):
                paths += [p[:-1] + [p[-1].split("@")[0]] for p in expand_use(
                    re.sub(r"\s+as\s+", "@", tree))]
            paths += [p.split("::") for p in re.findall(
                r"\b(?:crate|super|self)(?:::\w+)+", code)]
            children = [c.rsplit("::", 1)[-1] for c in self.mods if parent_of(c) == m and c]
            if children:
                paths += [p.split("::") for p in re.findall(
                    r"(?<![\w:])(?:%s)(?:::\w+)+" % "|".join(map(re.escape, children)), code)]
            for p in paths:
                dep = self.resolve(m, [s for s in p if s])
                if dep is not None and dep in self.mods and not related(m, dep):
                    g[m].add(dep)
        return g


def sccs(g):
    index, low, on, stack, out, n = {}, {}, set(), [], [], [0]

    def visit(v):
        index[v] = low[v] = n[0]
        n[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(g[v]):
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
    for v in sorted(g):
        if v not in index:
            visit(v)
    return [c for c in out if len(c) > 1]


def child_towards(parent, m):
    """The child of `parent` on the way down to module m (m itself or a module inside it)."""
    rest = m[len(parent) + 2:] if parent else m
    return join(parent, rest.split("::")[0])


def folder_graphs(g):
    """Per module with children: its children, each standing for everything inside it, with
    an edge where anything in one uses anything in another."""
    out = {}
    for parent in {parent_of(m) for m in g if m}:
        inside = lambda m: m != parent and (parent == "" or m.startswith(parent + "::"))
        h = {}
        for u, deps in g.items():
            if not inside(u):
                continue
            cu = child_towards(parent, u)
            h.setdefault(cu, set())
            for v in deps:
                if inside(v) and child_towards(parent, v) != cu:
                    h[cu].add(child_towards(parent, v))
                    h.setdefault(child_towards(parent, v), set())
        out[parent] = h
    return out


def main():
    roots = [pathlib.Path(a) for a in sys.argv[1:]] or sorted(pathlib.Path("crates").glob("*"))
    bad = modules = 0
    for root in roots:
        src = root / "src"
        if not src.is_dir():
            continue
        crate = Crate(src)
        modules += len(crate.mods)
        g = crate.graph()
        for parent, h in sorted(folder_graphs(g).items()):
            for comp in sccs(h):
                bad += 1
                names = ", ".join(sorted(comp))
                print(f"{root.name}: cycle among {names}" + (
                    f" (inside {parent}, each with what it contains)" if parent else
                    " (each with what it contains)"))
                for m in sorted(comp):
                    print(f"    {m} -> {', '.join(sorted(d for d in h[m] if d in comp))}")
        for comp in []:
            bad += 1
            names = ", ".join(sorted(c or "(crate root)" for c in comp))
            print(f"{root.name}: cycle among {names}")
            for m in sorted(comp):
                deps = sorted(d or "(crate root)" for d in g[m] if d in comp)
                print(f"    {m or '(crate root)'} -> {', '.join(deps)}")
    if not bad:
        print(f"no module cycles ({modules} module files read)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
