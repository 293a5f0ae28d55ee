#!/usr/bin/env python3
"""Import circles between sibling modules of each crate (issue 40: "no import circles").

For every module file of a crate's src/, the paths it names (`crate::a::b`, `super::x`, `self::x`,
grouped `use super::{a, b}`) are resolved to the modules they reach. An edge from module A to
module B counts between the two siblings under their common parent (a::b::c -> a::d becomes
a::b -> a::d); a module reaching its own parent or child is not a circle (Rust's tree). Unit tests
(`#[cfg(test)] mod tests` blocks, `tests.rs`, `*_tests.rs`) are left out: they may reach anything.
Prints each circle (a strongly connected set of siblings) with one edge per pair as evidence, and
exits 1 if there is any.

Usage: scripts/import_cycles.py [CRATE_SRC ...]   (default: src and crates/*/src)
"""
import glob
import os
import re
import sys


def modules(src):
    """module path (tuple) -> file, for every .rs file of the crate under `src`."""
    out = {}
    for path in glob.glob(os.path.join(src, "**", "*.rs"), recursive=True):
        rel = os.path.relpath(path, src)[:-3].split(os.sep)
        if rel[-1] in ("lib", "main") and len(rel) == 1:
            key = ()
        elif rel[-1] == "mod":
            key = tuple(rel[:-1])
        else:
            key = tuple(rel)
        if rel[-1] == "tests" or rel[-1].endswith("_tests") or "bin" in rel[:1]:
            continue
        out[key] = path
    return out


def strip_tests(text):
    m = re.search(r"#\[cfg\(test\)\]\s*(pub(\([^)]*\))?\s+)?mod\s+tests\s*\{", text)
    text = text[: m.start()] if m else text
    # Comments and doc comments name paths that are not imports.
    return re.sub(r"//[^\n]*", "", text)


IDENT = r"[A-Za-z_][A-Za-z0-9_]*"


def referenced(text):
    """Raw paths as lists of segments: crate::…, super::…, self::…, with groups expanded."""
    paths = []
    for m in re.finditer(r"\b((?:crate|super|self)(?:::(?:super))*)::\{([^{}]*(?:\{[^{}]*\}[^{}]*)*)\}", text):
        head = m.group(1).split("::")
        for item in re.split(r",(?![^{]*\})", m.group(2)):
            segs = [s for s in re.findall(IDENT, item.split("{")[0])]
            if segs and segs[0] != "self":
                paths.append(head + segs)
    for m in re.finditer(r"\b((?:crate|super|self)(?:::" + IDENT + r")+)", text):
        paths.append(m.group(1).split("::"))
    return paths


def resolve(segs, here, mods):
    """The module a path reaches (the longest known prefix), or None. `super` is the parent of the
    module the path is written in, `self` that module, `crate` the root."""
    if segs[0] == "crate":
        base, rest = (), segs[1:]
    elif segs[0] == "self":
        base, rest = here, segs[1:]
    else:
        base, rest = here, segs
        while rest and rest[0] == "super":
            base, rest = base[:-1], rest[1:]
    best = None
    for i in range(len(rest) + 1):
        cand = tuple(base) + tuple(rest[:i])
        if cand in mods:
            best = cand
    return best


def sibling_edge(a, b):
    """(parent, a's child, b's child) for an edge a -> b, or None for an ancestor relation."""
    n = 0
    while n < min(len(a), len(b)) and a[n] == b[n]:
        n += 1
    if n == len(a) or n == len(b):
        return None
    return a[:n], a[n], b[n]


def circles(src):
    mods = modules(src)
    edges = {}
    for here, path in mods.items():
        text = strip_tests(open(path, encoding="utf-8").read())
        for segs in referenced(text):
            target = resolve(segs, here, mods)
            if target is None or target == here:
                continue
            e = sibling_edge(here, target)
            if e:
                edges.setdefault((e[0], e[1], e[2]), (here, target))
    found = []
    parents = {p for (p, _, _) in edges}
    for parent in sorted(parents):
        graph = {}
        for (p, a, b), why in edges.items():
            if p == parent:
                graph.setdefault(a, {})[b] = why
        for comp in tarjan(graph):
            if len(comp) > 1:
                evidence = [
                    f"{'::'.join(w[0]) or 'crate'} -> {'::'.join(w[1])}"
                    for a in sorted(comp)
                    for b, w in sorted(graph.get(a, {}).items())
                    if b in comp
                ]
                found.append((parent, sorted(comp), evidence))
    return found


def tarjan(graph):
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]
    nodes = set(graph) | {b for a in graph for b in graph[a]}

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, {}):
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

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return out


def main():
    roots = sys.argv[1:] or ["src"] + sorted(glob.glob("crates/*/src"))
    bad = 0
    for src in roots:
        for parent, comp, evidence in circles(src):
            bad += 1
            where = "::".join(parent) or "crate root"
            print(f"{src}: circle under {where}: {', '.join(comp)}")
            for e in evidence:
                print(f"    {e}")
    if bad:
        print(f"{bad} import circle(s)")
        return 1
    print("no import circles in " + ", ".join(roots))
    return 0


if __name__ == "__main__":
    sys.exit(main())
