#!/usr/bin/env python3
"""The module import graph of catflip's `src/`: no circles, no upward imports.

Reads every `src/**/*.rs` of the library (not `src/main.rs`, the binary), strips comments and
string literals, and collects the paths each file names: `use` trees (`use crate::a::{b, c::D}`,
`use super::x`, `use child::Y` in a `mod.rs`) and paths written in code (`crate::a::f(…)`,
`super::g`); what a `#[cfg(test)] mod tests { … }` names is left out (a unit test may use
what the library does not). A path is resolved to the module that holds the item, following `pub use`
re-exports, so `use crate::sweep::Case` counts as an import of the file that defines `Case`.

An edge from module S to module T is charged to the two siblings under their lowest common
ancestor (`sweep::evaluate::x` → `sweep::spec` is the edge `evaluate → spec` among the children
of `sweep`); an edge between a module and its own ancestor or descendant is not an edge between
siblings and is not counted. It then reports

  (a) circles: strongly connected sets of two or more siblings, at every level;
  (b) upward imports: a top-level stage importing from a stage below it in the pipeline
      (STAGES, README's Architecture section).

Exit status 1 if either is found, else 0. Stdlib only: `python3 .ci/imports.py [src]`.
"""

import os
import re
import sys
from collections import defaultdict

# The pipeline, top to bottom: a stage may import only from the stages before it. `numeric` is
# the math with no physics in it; `problem` reads a `model::Cylinder`; `exchange` (files in and
# out) sits above the engines; `measure` computes what each command answers (every schedule
# measured into one `engines::measured::Measured`), and `report` only renders it; `sweep` uses
# both; the
# `prelude` only re-exports, and nothing in the library imports it. `compare_models`, like `sweep`,
# runs whole reports (the whole optimum, its verification) for several cats and renders its own
# table with `report`'s plots.
STAGES = [
    "numeric", "model", "problem", "schedule", "engines", "optimize", "exchange", "robust", "measure", "report",
    "sweep", "compare_models", "prelude",
]

# Known upward imports not yet removed, each with the reason and who removes it. The list only
# shrinks: an entry that no longer occurs is an error too, so it is deleted with its fix.
KNOWN_UPWARD = set()

# Known circles not yet removed (the siblings' parent and the set), on the same terms.
KNOWN_CIRCLES = set()


def strip(text):
    """The source with comments, string and char literals blanked (newlines kept)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    if text[i] == "\n":
                        out.append("\n")
                    i += 1
        elif re.match(r'(b?r#*")', text[i:i + 8]) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'b?r(#*)"', text[i:])
            end = '"' + m.group(1)
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif c == '"' or (c == "b" and text.startswith('b"', i) and (i == 0 or not text[i - 1].isalnum())):
            i += 2 if c == "b" else 1
            start = i
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            out.append('""' + "\n" * text.count("\n", start, i))
            i += 1
        elif c == "'":
            # A char literal ('a', '\n', '\u{1F}') or a lifetime ('a): blank only the former.
            m = re.match(r"'(\\[^']{1,10}|[^\\'])'", text[i:])
            if m:
                out.append("' '")
                i += m.end()
            else:
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def module_of(src, path):
    """The module path of a file: src/a/b.rs → ("a", "b"), src/a/mod.rs → ("a",), lib.rs → ()."""
    rel = os.path.relpath(path, src)[:-3].split(os.sep)
    if rel[-1] in ("mod", "lib"):
        rel = rel[:-1]
    return tuple(rel)


def split_tree(tree):
    """Expand a `use` tree `a::{b, c::{D, E as F}, *}` into its leaf paths (lists of segments)."""
    tree = re.sub(r"\s+", "", tree)
    out = []

    def walk(prefix, s):
        depth, start, parts = 0, 0, []
        for k, ch in enumerate(s):
            if ch == "{":
                depth += 1
            elif ch == "}":
                depth -= 1
            elif ch == "," and depth == 0:
                parts.append(s[start:k])
                start = k + 1
        parts.append(s[start:])
        for p in parts:
            if not p:
                continue
            b = p.find("{")
            if b >= 0 and p.endswith("}"):
                head = [x for x in p[:b].split("::") if x]
                walk(prefix + head, p[b + 1:-1])
            else:
                p = p.split("as")[0] if re.search(r"[A-Za-z0-9_]as[A-Za-z_]", p) is None else re.sub(r"as[A-Za-z_][A-Za-z0-9_]*$", "", p)
                out.append(prefix + [x for x in p.split("::") if x])

    walk([], tree)
    return out


USE = re.compile(r"\b(pub(?:\([^)]*\))?\s+)?use\s+([^;]+);")
PATH = re.compile(r"(?<![A-Za-z0-9_:])((?:crate|super|self)(?:::[A-Za-z_][A-Za-z0-9_]*)+)")
INLINE_MOD = re.compile(r"\bmod\s+([a-z_][a-z0-9_]*)\s*\{")
DECL_MOD = re.compile(r"\bmod\s+([a-z_][a-z0-9_]*)\s*;")


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "src")
    files = {}
    for root, _, names in os.walk(src):
        for name in names:
            path = os.path.join(root, name)
            if name.endswith(".rs") and os.path.relpath(path, src) != "main.rs":
                with open(path, encoding="utf-8") as f:
                    files[module_of(src, path)] = (os.path.relpath(path, os.path.dirname(src)), strip(f.read()))
    modules = set(files)

    # Each file's `use` leaves and code paths, tagged with the module they are written in (an
    # inline `mod tests { … }` is a module of its own for `super::`, but its edges are the file's).
    raw = []  # (file module, scope module, segments, is_pub_use)
    for mod, (_, text) in files.items():
        scopes = []  # (inline module name, brace depth inside it, whether it is `#[cfg(test)]`)
        depth = 0
        events = []
        for m in INLINE_MOD.finditer(text):
            test = re.search(r"#\[cfg\(test\)\]\s*(?:#\[[^\]]*\]\s*)*(?:pub(?:\([^)]*\))?\s+)?$", text[: m.start()])
            events.append((m.end() - 1, "mod", (m.group(1), bool(test))))
        for m in USE.finditer(text):
            events.append((m.start(), "use", m))
        for m in PATH.finditer(text):
            events.append((m.start(), "path", m))
        events.sort(key=lambda e: e[0])
        pos = 0
        used_spans = []
        for at, kind, payload in events:
            for ch in text[pos:at]:
                if ch == "{":
                    depth += 1
                elif ch == "}":
                    depth -= 1
                    while scopes and scopes[-1][1] > depth:
                        scopes.pop()
            pos = at
            scope = mod + tuple(s for s, _, _ in scopes)
            if any(t for _, _, t in scopes):
                continue  # inside `#[cfg(test)] mod … { }`: not part of the library's graph
            if kind == "mod":
                scopes.append((payload[0], depth + 1, payload[1]))
            elif kind == "use":
                used_spans.append((payload.start(), payload.end()))
                for leaf in split_tree(payload.group(2)):
                    raw.append((mod, scope, leaf, bool(payload.group(1)) and not scopes))
            elif not any(a <= at < b for a, b in used_spans):
                raw.append((mod, scope, payload.group(1).split("::"), False))

    def absolute(scope, segs):
        """The absolute path of `segs` written in module `scope`, or None (an extern crate)."""
        segs = list(segs)
        if segs[0] == "crate":
            return segs[1:]
        if segs[0] in ("super", "self"):
            base = list(scope)
            while segs and segs[0] in ("super", "self"):
                if segs.pop(0) == "super":
                    base = base[:-1]
            return base + segs
        if tuple(scope) + (segs[0],) in modules:
            return list(scope) + segs
        return None

    # Re-exports: (module, name) → the absolute path it re-exports.
    reexports = {}
    for mod, scope, segs, is_pub in raw:
        if is_pub and segs and segs[-1] not in ("*", "self"):
            target = absolute(scope, segs)
            if target:
                reexports[(mod, segs[-1])] = target

    def resolve(path, hops=0):
        """The module that defines the item at `path` (following re-exports)."""
        best = ()
        for k in range(len(path), 0, -1):
            if tuple(path[:k]) in modules:
                best = tuple(path[:k])
                break
        rest = path[len(best):]
        if rest and hops < 10 and (best, rest[0]) in reexports:
            return resolve(reexports[(best, rest[0])] + rest[1:], hops + 1)
        return best

    # Sibling edges under each common ancestor, with an example of each for the message.
    edges = defaultdict(dict)  # parent → {(child a, child b): example}
    top = {}  # (source module, target module) → file, for the stage check
    for mod, scope, segs, _ in raw:
        target = absolute(scope, segs)
        if target is None:
            continue
        t = resolve(target)
        s = mod
        k = 0
        while k < min(len(s), len(t)) and s[k] == t[k]:
            k += 1
        if k == len(s) or k == len(t):
            continue  # a module and its ancestor: not siblings
        parent = s[:k]
        if k == 0 and (s[0], "::".join(t)) in KNOWN_UPWARD:
            top.setdefault((s[0], "::".join(t)), files[mod][0])
            continue  # reported below as known, and kept out of the circles
        edges[parent].setdefault((s[k], t[k]), (files[mod][0], "::".join(segs) + ("" if list(segs[1:]) == list(t) else " = crate::" + "::".join(t))))
        if k == 0:
            top.setdefault((s[0], "::".join(t)), files[mod][0])

    failures = 0
    seen_circles = set()
    for parent in sorted(edges):
        graph = defaultdict(set)
        for a, b in edges[parent]:
            graph[a].add(b)
        for scc in sccs(graph):
            if len(scc) < 2:
                continue
            where = "::".join(("crate",) + parent)
            if ("::".join(parent), frozenset(scc)) in KNOWN_CIRCLES:
                seen_circles.add(("::".join(parent), frozenset(scc)))
                print(f"known circle (KNOWN_CIRCLES) among the children of {where}: {{{', '.join(sorted(scc))}}}")
                continue
            failures += 1
            print(f"circle among the children of {where}: {{{', '.join(sorted(scc))}}}")
            for (a, b), (f, t) in sorted(edges[parent].items()):
                if a in scc and b in scc:
                    print(f"    {a} → {b}   ({f} uses {t})")

    rank = {s: i for i, s in enumerate(STAGES)}
    seen_known = set()
    for (a, b), f in sorted(top.items()):
        stage = b.split("::")[0]
        if a not in rank or stage not in rank:
            failures += 1
            print(f"{f}: stage {a} or {stage} is not in STAGES (.ci/imports.py)")
        elif rank[stage] > rank[a]:
            if (a, b) in KNOWN_UPWARD:
                seen_known.add((a, b))
                print(f"known upward import (KNOWN_UPWARD): {a} → crate::{b}   ({f})")
                continue
            failures += 1
            print(f"upward import: {a} → crate::{b}   ({f}; {a} is above {stage} in the pipeline)")
    for parent, scc in sorted(KNOWN_CIRCLES - seen_circles, key=str):
        failures += 1
        print(f"KNOWN_CIRCLES lists {{{', '.join(sorted(scc))}}} under crate::{parent}, which is no longer a circle: delete the entry")
    for a, b in sorted(KNOWN_UPWARD - seen_known):
        failures += 1
        print(f"KNOWN_UPWARD lists {a} → crate::{b}, which no longer occurs: delete the entry")

    n = sum(len(e) for e in edges.values())
    print(f"{len(files)} files, {n} sibling edges: {failures} problem(s)")
    return 1 if failures else 0


def sccs(graph):
    """Tarjan's strongly connected components of a dict-of-sets graph."""
    index, low, stack, on, out = {}, {}, [], set(), []
    nodes = set(graph) | {b for bs in graph.values() for b in bs}

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = set()
            while True:
                w = stack.pop()
                on.discard(w)
                comp.add(w)
                if w == v:
                    break
            out.append(comp)

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return out


if __name__ == "__main__":
    sys.exit(main())
