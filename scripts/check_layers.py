#!/usr/bin/env python3
"""No import circle between the workspace's source files: prints each circle and exits 1.

usage: scripts/check_layers.py [name=src_dir ...]   (default: the root binary and crates/*/src)
An edge a -> b: file a names a path into the module defined by file b: `crate::`, `super::`,
`self::`, another listed crate's name, or a child module's bare name. `mod x;` lines and
`pub use` re-exports in a module's own file are structure, not imports. Unit-test modules
(`#[cfg(test)]` and below) are skipped: a test may use anything above it."""
import os, re, sys
from collections import defaultdict

def module_files(src_root, crate):
    mods = {}
    for dp, _, fns in os.walk(src_root):
        for f in fns:
            if f.endswith('.rs'):
                p = os.path.join(dp, f)
                rel = os.path.relpath(p, src_root)[:-3].split(os.sep)
                if rel[-1] in ('mod', 'lib', 'main'):
                    rel = rel[:-1]
                mods[(crate,) + tuple(rel)] = p
    return mods

def clean(s):
    s = re.sub(r'/\*.*?\*/', '', s, flags=re.S)
    s = re.sub(r'//[^\n]*', '', s)
    s = re.sub(r'"(\\.|[^"\\])*"', '""', s)
    s = re.sub(r"'(\\.|[^'\\])'", "''", s)
    i = s.find('#[cfg(test)]')
    return s if i < 0 else s[:i]

def expand(tree):
    """`a::{b, c::{d, e}}` -> ['a::b', 'a::c::d', 'a::c::e']"""
    tree = tree.replace(' ', '').replace('\n', '')
    i = tree.find('{')
    if i < 0:
        return [tree]
    prefix, body = tree[:i], tree[i + 1:tree.rfind('}')]
    parts, depth, cur = [], 0, ''
    for ch in body:
        if ch == ',' and depth == 0:
            parts.append(cur); cur = ''
            continue
        depth += ch == '{'; depth -= ch == '}'
        cur += ch
    parts.append(cur)
    return [x for p in parts if p for x in expand(prefix + p)]

def main():
    mods = {}
    crates = set()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    args = sys.argv[1:] or [f'softgrip={root}/src'] + [
        f"{c.replace('-', '_')}={root}/crates/{c}/src" for c in sorted(os.listdir(f'{root}/crates'))]
    for r in args:
        name, d = r.split('=')
        crates.add(name)
        mods.update(module_files(d, name))
    file2mod = {v: k for k, v in mods.items()}
    edges = defaultdict(set)
    for f, m in file2mod.items():
        own = f.endswith(('mod.rs', 'lib.rs', 'main.rs'))
        here = m                      # the module this file defines
        txt = clean(open(f).read())
        paths = []
        for u in re.finditer(r'(pub(\([^)]*\))?\s+)?use\s+([^;]+);', txt):
            if u.group(1) and own:
                continue              # a facade's re-export
            paths += expand(u.group(3))
        body = re.sub(r'(pub(\([^)]*\))?\s+)?use\s+[^;]+;', '', txt)
        body = re.sub(r'(pub(\([^)]*\))?\s+)?mod\s+\w+\s*;', '', body)
        paths += [x.group(0) for x in re.finditer(r'\b\w+(?:::\w+)+', body)]
        for p in paths:
            seg = [s for s in p.split('::') if s]
            if not seg:
                continue
            head = seg[0]
            if head == 'crate':
                base, rest = (m[0],), seg[1:]
            elif head == 'self':
                base, rest = here, seg[1:]
            elif head == 'super':
                base, rest = here[:-1], seg[1:]
                while rest and rest[0] == 'super':
                    base, rest = base[:-1], rest[1:]
            elif head.replace('-', '_') in crates:
                base, rest = (head,), seg[1:]
            elif here + (head,) in mods:
                base, rest = here, seg
            else:
                continue
            path = base + tuple(rest)
            for k in range(len(path), 0, -1):
                if path[:k] in mods:
                    if mods[path[:k]] != f:
                        edges[f].add(mods[path[:k]])
                    break
    index, low, st, on, sccs, c = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(10000)
    def visit(v):
        index[v] = low[v] = c[0]; c[0] += 1; st.append(v); on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w); low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = st.pop(); on.discard(w); comp.append(w)
                if w == v: break
            if len(comp) > 1: sccs.append(comp)
    for v in sorted(file2mod):
        if v not in index: visit(v)
    for comp in sccs:
        s = set(comp)
        print(f'circle of {len(comp)} files:')
        for a in sorted(comp):
            rel = lambda p: os.path.relpath(p, root)
            print('   ', rel(a), '->', ', '.join(sorted(rel(b) for b in edges[a] if b in s)))
    print(f'{len(sccs)} circles; {sum(len(e) for e in edges.values())} edges between {len(file2mod)} files')
    return 1 if sccs else 0

sys.exit(main())
