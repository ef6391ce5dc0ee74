#!/usr/bin/env python3
"""Checks that core/src includes in one direction: no file includes a header of a higher layer, and
no two modules (X.c and X.h together) include each other, directly or round a loop.

The layers are read from the table between the `layers begin` and `layers end` markers of
docs/architecture.md (the one place they are written); a file belongs to the layer of the longest
pattern that matches its path under core/src.  Includes within one layer are free, loops aside.

allowed.txt (beside this script) lists known violations, one include edge a line
("sky.h -> transport/path.h"), while they are being removed: an entry is accepted only while it is
still a violation (an upward include, or an include inside a loop), so the list can only shrink.

Usage: check_layers.py [ROOT]  (ROOT: the repository, default two levels above this script).
Prints each violation on one line and exits 1 if there is any."""

import fnmatch
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PUBLIC = {"firmament/firmament.h"}  # the library's public header (core/include): below every layer
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def read_layers(doc):
    """[(rank, name, [patterns])] from the table between the markers, lowest layer first."""
    text = open(doc, encoding="utf-8").read()
    m = re.search(r"<!-- layers begin -->(.*?)<!-- layers end -->", text, re.S)
    if not m:
        sys.exit(f"{doc}: no '<!-- layers begin -->' ... '<!-- layers end -->' table")
    layers = []
    for line in m.group(1).splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 3 or not cells[0].isdigit():
            continue  # header, rule or blank
        layers.append((int(cells[0]), cells[1], re.findall(r"`([^`]+)`", cells[2])))
    return layers


def layer_of(path, layers):
    best = None
    for rank, name, patterns in layers:
        for p in patterns:
            if fnmatch.fnmatchcase(path, p) and (best is None or len(p) > best[2]):
                best = (rank, name, len(p))
    return best


def module(path):
    return os.path.splitext(path)[0]


def strongly_connected(nodes, succ):
    """Tarjan's components of the graph (iterative), each a set of nodes."""
    index, low, on, stack, comps, n = {}, {}, set(), [], [], 0
    for root in sorted(nodes):
        if root in index:
            continue
        work = [(root, iter(sorted(succ.get(root, ()))))]
        index[root] = low[root] = n
        n += 1
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = n
                    n += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(succ.get(w, ())))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = set()
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.add(w)
                    if w == v:
                        break
                comps.append(comp)
    return comps


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", ".."))
    src = os.path.join(root, "core", "src")
    layers = read_layers(os.path.join(root, "docs", "architecture.md"))
    problems = []

    files = []
    for d, _, names in os.walk(src):
        for f in names:
            if f.endswith((".c", ".h", ".cpp")):
                files.append(os.path.relpath(os.path.join(d, f), src).replace(os.sep, "/"))
    files.sort()
    layer = {}
    for f in files:
        layer[f] = layer_of(f, layers)
        if layer[f] is None:
            problems.append(f"{f}: in no layer of docs/architecture.md")

    edges = set()
    for f in files:
        for inc in INCLUDE.findall(open(os.path.join(src, f), encoding="utf-8", errors="replace").read()):
            if inc in PUBLIC:
                continue
            if inc not in layer:
                problems.append(f"{f}: includes \"{inc}\", which is not a file of core/src")
                continue
            edges.add((f, inc))

    allowed = set()
    allow_path = os.path.join(HERE, "allowed.txt")
    for n, line in enumerate(open(allow_path, encoding="utf-8"), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        a, sep, b = (s.strip() for s in line.partition("->"))
        if not sep:
            problems.append(f"allowed.txt:{n}: not 'FILE -> INCLUDED FILE': {line}")
        allowed.add((a, b))

    def upward(e):
        a, b = e
        return layer[a] and layer[b] and layer[b][0] > layer[a][0]

    # loops between modules, over every include edge
    succ = {}
    for a, b in edges:
        if module(a) != module(b):
            succ.setdefault(module(a), set()).add(module(b))
    comp_of = {}
    for comp in strongly_connected({module(f) for f in files}, succ):
        for v in comp:
            comp_of[v] = comp if len(comp) > 1 else None

    def in_loop(e):
        a, b = module(e[0]), module(e[1])
        return a != b and comp_of.get(a) is not None and b in comp_of[a]

    for e in sorted(allowed):
        if e not in edges:
            problems.append(f"allowed.txt: {e[0]} -> {e[1]}: no such include any more: delete the line")
        elif not upward(e) and not in_loop(e):
            problems.append(f"allowed.txt: {e[0]} -> {e[1]}: no longer a violation: delete the line")

    for a, b in sorted(edges - allowed):
        if upward((a, b)):
            problems.append(f"{a} ({layer[a][1]}) includes {b} ({layer[b][1]}), a higher layer")

    # loops that remain once the allowed edges are taken out
    succ = {}
    for a, b in edges - allowed:
        if module(a) != module(b):
            succ.setdefault(module(a), set()).add(module(b))
    for comp in strongly_connected({module(f) for f in files}, succ):
        if len(comp) > 1:
            loop = sorted((a, b) for a, b in edges - allowed if module(a) in comp and module(b) in comp
                          and module(a) != module(b))
            problems.append("include loop between " + ", ".join(sorted(comp)) + ": " +
                            "; ".join(f"{a} -> {b}" for a, b in loop))

    for p in problems:
        print("layers: " + p)
    if problems:
        return 1
    print(f"layers: {len(files)} files, {len(edges)} includes in one direction "
          f"({len(allowed)} known violations allowed, tests/layers/allowed.txt)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
