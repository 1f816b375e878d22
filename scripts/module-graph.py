#!/usr/bin/env python3
"""The import graph of monitor-host/src between its rooms (top-level modules), from the source.

Reads every `.rs` file under monitor-host/src, takes the paths of `use crate::...`, `use super::...`
and inline `crate::a::b`, `super::a::b` and `self::a::b` mentions in code (comments, strings and `#[cfg(test)]` modules left out),
resolves each to the file that defines it (following `pub use` re-exports, lib.rs's included, and
re-exports of re-exports), and prints:

- the room-level graph (room -> rooms it imports, with the number of file edges);
- cycles: strongly connected components of more than one node, at room level (between stages,
  and inside one stage) and at file level (across folders, and inside one folder: a folder's
  mod.rs with its own children, or two sibling files such as `cli/args.rs` <-> `cli/watch.rs`);
- upward imports: file edges whose target room comes later in the stage order than the source
  room (the order is below; `lib.rs` is the crate root and is left out);
- imports through the crate root (`crate::Report` inside the crate): a module names the defining
  path, so that its edge in this graph is the real one.

    scripts/module-graph.py [--src monitor-host/src] [--edges] [--check]

`--edges` also lists every file edge; `--check` exits 1 on any import cycle (between rooms, inside
a stage, across folders or inside one folder), on any import through the crate root, or on more
than `--max-upward` (0) upward imports.
"""

import argparse
import os
import re
import sys
from collections import defaultdict

# Lower stages first. Rooms in one tuple share a stage (imports between them are not upward).
STAGES = [
    ("named",),  # the enum-naming macro (imports nothing)
    ("input",),  # the readers, and the warnings made of input facts (input/warning.rs)
    ("settings", "provenance"),  # settings name input policies; provenance digests settings
    ("geometry",),
    ("reference",),  # the batch reference the replay checks itself against (docs/SCORE.md §11)
    ("pipeline",),
    ("route",),
    ("aggregate",),  # one run's aggregates
    ("model",),  # what the renderings read: the Report, a route's frames, a watch round's status
    ("stats", "merge"),  # several reports: compared (stats) or merged into one (merge)
    ("report",),  # renderings
    ("write",),  # the rules of writing files: atomic, links and inputs refused, a set all or nothing
    ("live_link",),  # the doer's side of the live link: byte streams, fault injection (core only)
    ("app", "error", "error_kind"),  # the run-level doors every front end calls, the errors they
    # return, and each error's kind
    ("demo",),
]


def stage_of(room):
    for i, rooms in enumerate(STAGES):
        if room in rooms:
            return i
    return None


def strip_code(text):
    """Source without comments, string/char literals and `#[cfg(test)]` items."""
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
                    i += 1
        elif c == "r" and re.match(r'r#*"', text[i:i + 10]) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'r(#*)"', text[i:])
            end = '"' + m.group(1)
            j = text.find(end, i + len(m.group(0)))
            i = n if j < 0 else j + len(end)
            out.append('""')
        elif c == '"':
            i += 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            i += 1
            out.append('""')
        elif c == "'" and re.match(r"'(\\.|[^\\'])'", text[i:i + 4]) or c == "'" and re.match(r"'\\u\{[0-9a-fA-F]+\}'", text[i:i + 12]):
            m = re.match(r"'(\\u\{[0-9a-fA-F]+\}|\\.|[^\\'])'", text[i:])
            i += len(m.group(0))
            out.append("' '")
        else:
            out.append(c)
            i += 1
    code = "".join(out)
    # Drop `#[cfg(test)]` items (test modules): the attribute, then the item to its closing brace.
    while True:
        m = re.search(r"#\[cfg\(test\)\]", code)
        if not m:
            break
        j = code.find("{", m.end())
        k = code.find(";", m.end())
        if j < 0 or (0 <= k < j):
            code = code[:m.start()] + code[(k + 1 if k >= 0 else len(code)):]
            continue
        depth, p = 0, j
        while p < len(code):
            if code[p] == "{":
                depth += 1
            elif code[p] == "}":
                depth -= 1
                if depth == 0:
                    break
            p += 1
        code = code[:m.start()] + code[p + 1:]
    return code


IDENT = r"[A-Za-z_][A-Za-z0-9_]*"


def parse_tree(s, i):
    """Parse a use tree at s[i:]: returns (list of paths (lists of idents), end index)."""
    paths = []
    prefix = []
    while True:
        while i < len(s) and s[i].isspace():
            i += 1
        if i < len(s) and s[i] == "{":
            i += 1
            while True:
                while i < len(s) and (s[i].isspace() or s[i] == ","):
                    i += 1
                if i >= len(s) or s[i] == "}":
                    i += 1
                    break
                sub, i = parse_tree(s, i)
                paths.extend(prefix + p for p in sub)
            return paths, i
        if i < len(s) and s[i] == "*":
            return [prefix], i + 1
        m = re.compile(IDENT).match(s, i)
        if not m:
            return [prefix] if prefix else [], i
        prefix = prefix + [m.group(0)]
        i = m.end()
        j = i
        while j < len(s) and s[j].isspace():
            j += 1
        if s.startswith("::", j):
            i = j + 2
            continue
        # `as alias`
        m2 = re.compile(r"\s+as\s+" + IDENT).match(s, i)
        if m2:
            i = m2.end()
        return [prefix], i


def module_of(rel):
    """monitor-host/src relative file -> module path tuple."""
    parts = rel[:-3].split(os.sep)
    if parts[-1] in ("mod", "lib"):
        parts = parts[:-1]
    if parts and parts[0] == "bin":
        return None
    return tuple(parts)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--src", default=os.path.join(root, "monitor-host", "src"))
    ap.add_argument("--edges", action="store_true", help="list every file edge")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 on any cycle or on more than --max-upward upward imports")
    ap.add_argument("--max-upward", type=int, default=0,
                    help="upward imports --check allows (default 0)")
    a = ap.parse_args()

    files = {}  # module tuple -> rel path
    code = {}
    for dp, _, fns in os.walk(a.src):
        for fn in fns:
            if fn.endswith(".rs"):
                rel = os.path.relpath(os.path.join(dp, fn), a.src)
                mod = module_of(rel)
                if mod is None:
                    continue
                files[mod] = rel
                with open(os.path.join(a.src, rel), encoding="utf-8") as f:
                    code[mod] = strip_code(f.read())

    def uses(mod):
        """(kind, path) pairs: kind 'use' for use items, 'path' for inline crate:: paths."""
        src = code[mod]
        res = []
        for m in re.finditer(r"\b(pub(\([^)]*\))?\s+)?use\s+", src):
            pub = bool(m.group(1))
            paths, _ = parse_tree(src, m.end())
            for p in paths:
                res.append((pub, p))
        for m in re.finditer(r"(?<![A-Za-z0-9_:])(crate|super|self)::", src):
            # inline paths (use items are found again here; harmless, edges are a set)
            paths, _ = parse_tree(src, m.start())
            for p in paths:
                res.append((False, p))
        return res

    def absolute(mod, path):
        """A use path seen in module `mod` -> absolute module path list, or None if external."""
        if not path:
            return None
        if path[0] == "crate":
            return list(path[1:])
        if path[0] == "self":
            return list(mod) + path[1:]
        if path[0] == "super":
            base = list(mod)
            # a non-mod.rs file's `super` is its parent module
            k = 0
            while k < len(path) and path[k] == "super":
                base = base[:-1]
                k += 1
            return base + path[k:]
        # a child module of this one (`use args::Cli` in cli/mod.rs)
        if tuple(list(mod) + [path[0]]) in files:
            return list(mod) + path
        # a name this module re-exports (`pub use run::{...}` after `pub use app::run` in lib.rs)
        if (mod, path[0]) in reexports and reexports[(mod, path[0])] != list(mod) + path[:1]:
            return reexports[(mod, path[0])] + path[1:]
        return None

    # Re-exports: (module, name) -> absolute path. A re-export may name an earlier one
    # (`pub use run::X` after `pub use app::run`): read again until nothing new is found.
    reexports = {}
    while True:
        before = dict(reexports)
        for mod in files:
            for pub, p in uses(mod):
                if pub and p:
                    ab = absolute(mod, p)
                    if ab is not None and ab:
                        reexports[(mod, p[-1])] = ab
        if reexports == before:
            break

    def resolve(ab, depth=0):
        """Absolute path -> module tuple of the file defining it."""
        best = ()
        for k in range(len(ab), -1, -1):
            if tuple(ab[:k]) in files:
                best = tuple(ab[:k])
                break
        rest = ab[len(best):]
        if rest and (best, rest[0]) in reexports and depth < 10:
            target = reexports[(best, rest[0])]
            if target != ab:
                return resolve(target + rest[1:], depth + 1)
        return best

    edges = set()
    # Imports through the crate root that no re-export explains: the root is no room, so such an
    # import would hide an edge; each is listed and counted as upward.
    unresolved = set()
    # Imports of a name the crate root re-exports (`crate::Report`): for the library's users;
    # inside the crate a module names the defining path, so that its edge is the real one.
    via_root = set()
    for mod in files:
        for _, p in uses(mod):
            ab = absolute(mod, p)
            if ab is None:
                continue
            t = resolve(ab)
            if mod != () and p[0] == "crate" and len(p) > 1 and ((), p[1]) in reexports:
                via_root.add((mod, "::".join(p)))
            if t == () and mod != () and ab and p[0] == "crate":
                unresolved.add((mod, "::".join(p)))
            elif t != mod and t != ():
                edges.add((mod, t))

    room = lambda m: m[0] if m else "lib"
    fname = lambda m: files[m]

    room_edges = defaultdict(int)
    for s, t in edges:
        if room(s) != room(t):
            room_edges[(room(s), room(t))] += 1

    def sccs(nodes, adj):
        index, low, on, stack, out = {}, {}, set(), [], []
        counter = [0]
        sys.setrecursionlimit(10000)

        def visit(v):
            index[v] = low[v] = counter[0]
            counter[0] += 1
            stack.append(v)
            on.add(v)
            for w in adj.get(v, ()):
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
                if len(comp) > 1:
                    out.append(sorted(comp))

        for v in sorted(nodes):
            if v not in index:
                visit(v)
        return out

    file_adj = defaultdict(set)
    for s, t in edges:
        file_adj[s].add(t)
    room_adj = defaultdict(set)
    for (s, t) in room_edges:
        room_adj[s].add(t)
    rooms = sorted({room(m) for m in files})

    print(f"monitor-host/src: {len(files)} files, {len(edges)} file edges, "
          f"{len(room_edges)} room edges")
    print("\nroom graph (room -> room: file edges):")
    for s in rooms:
        outs = sorted((t, c) for (ss, t), c in room_edges.items() if ss == s)
        if outs:
            print(f"  {s:10} -> " + ", ".join(f"{t} ({c})" for t, c in outs))

    room_cycles = sccs(rooms, room_adj)
    file_cycles = sccs(list(files), file_adj)
    # Rooms that share a stage (input and warning) may import each other.
    same_stage = [c for c in room_cycles if len({stage_of(r) for r in c}) == 1]
    room_cycles = [c for c in room_cycles if c not in same_stage]
    print(f"\nroom-level cycles between stages: {len(room_cycles)}")
    for c in room_cycles:
        print("  " + " <-> ".join(c))
    print(f"room-level cycles inside one stage: {len(same_stage)}")
    for c in same_stage:
        print("  " + " <-> ".join(c))
    # A folder's mod.rs defining types its own child files use (and using theirs) is a
    # cycle inside one module: counted apart from cycles between folders or rooms.
    inner = [c for c in file_cycles if len({os.path.dirname(fname(m)) for m in c}) == 1]
    cross = [c for c in file_cycles if c not in inner]
    print(f"file-level cycles across folders: {len(cross)} "
          f"({sum(len(c) for c in cross)} files)")
    for c in cross:
        print("  " + " <-> ".join(fname(m) for m in c))
    print(f"file-level cycles inside one folder: {len(inner)}")
    for c in inner:
        print("  " + " <-> ".join(fname(m) for m in c))

    up = []
    for s, t in sorted(edges):
        if room(s) == "lib":
            continue
        ss, st = stage_of(room(s)), stage_of(room(t))
        if ss is None or st is None:
            up.append((s, t, "room not in the stage order"))
        elif st > ss:
            up.append((s, t, ""))
    for s, path in sorted(unresolved):
        up.append((s, (), f"{path}: through the crate root, no re-export found"))
    order = " < ".join("/".join(r) for r in STAGES)
    print(f"upward imports (stage order {order}): {len(up)}")
    for s, t, why in up:
        print(f"  {fname(s)} -> {fname(t) if t else 'lib.rs'}" + (f"  [{why}]" if why else ""))

    print(f"imports through the crate root's re-exports: {len(via_root)}")
    for s, path in sorted(via_root):
        print(f"  {fname(s)}: {path}")

    if a.edges:
        print("\nfile edges:")
        for s, t in sorted(edges):
            print(f"  {fname(s)} -> {fname(t)}")

    print(f"\nsummary: room cycles {len(room_cycles)}, file cycles across folders {len(cross)}, "
          f"inside one folder {len(inner)}, upward imports {len(up)}, "
          f"through the crate root {len(via_root)}")
    if a.check:
        problems = []
        if room_cycles or same_stage or cross or inner:
            problems.append(f"{len(room_cycles) + len(same_stage) + len(cross) + len(inner)} import cycle(s)")
        if len(up) > a.max_upward:
            problems.append(f"{len(up)} upward imports (at most {a.max_upward})")
        if via_root:
            problems.append(f"{len(via_root)} import(s) through the crate root (name the defining path)")
        if problems:
            print("module-graph --check: FAILED: " + ", ".join(problems), file=sys.stderr)
            sys.exit(1)
        print("module-graph --check: no import cycle, "
              f"{len(up)} upward import(s) (at most {a.max_upward})")


if __name__ == "__main__":
    main()
