#!/usr/bin/env python3
"""The include rules of docs/architecture.md, checked on the source tree (a CTest test: architecture_layers).

1. Layers: a file of icobrdf/LAYER/ includes only its own layer and the layers below it.
2. core's rooms: a file of icobrdf/core/ROOM/ includes only its own room and the rooms below it.
3. No two modules (a header and its .cpp) of core/ or of pipeline/ depend on each other, directly or in a
   longer cycle.
4. Nothing in icobrdf/pipeline/ downcasts a SOURCE (dynamic_cast, or io's samples_of / merl_table_of).
Prints one line per broken rule and exits 1 when any is broken.
"""
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..', '..'))
# Layers in order; each may include those before it (cluster, plot and lab sit side by side above pipeline).
LAYERS = {'core': 0, 'mesh': 1, 'io': 2, 'pipeline': 3, 'plot': 4, 'cluster': 4, 'lab': 5, 'blas': 6}
LAYER_MAY = {'lab': {'plot', 'blas'}}  # lab draws its figures with plot and times OpenBLAS's kernels (bench project)
# blas (OpenBLAS's dense kernels) sits on core alone: no layer but lab includes it (the program and the Python module
# install it), and it includes nothing but core.
ONLY_BELOW = {'blas': {'core'}}
# core's rooms in order; each may include those before it.
CYCLE_FREE = {'core', 'pipeline'}
ROOMS = ['support', 'grid', 'tables', 'basis', 'spectrum', 'models', 'projection', 'fit']
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"](icobrdf/[^>"]+)[>"]', re.M)


def files_of(layer):
    base = os.path.join(ROOT, 'icobrdf', layer)
    for d, _, names in os.walk(base):
        for n in sorted(names):
            if n.endswith(('.hpp', '.cpp')):
                yield os.path.relpath(os.path.join(d, n), ROOT)


def includes(path):
    with open(os.path.join(ROOT, path), encoding='utf-8') as f:
        return INCLUDE.findall(f.read())


def module(path):
    return os.path.splitext(path)[0]


def main():
    broken = []
    graph = {}
    for layer, rank in LAYERS.items():
        for f in files_of(layer):
            m = module(f)
            graph.setdefault(m, set())
            for inc in includes(f):
                parts = inc.split('/')
                other = parts[1]
                if other not in LAYERS:
                    continue
                if other != layer and LAYERS[other] >= rank and other not in LAYER_MAY.get(layer, set()):
                    broken.append(f'{f}: layer {layer} includes {inc} of layer {other}, which is not below it')
                elif other != layer and layer in ONLY_BELOW and other not in ONLY_BELOW[layer]:
                    broken.append(f'{f}: layer {layer} includes {inc}; it may include only {", ".join(sorted(ONLY_BELOW[layer]))}')
                if layer == 'core' and other == 'core':
                    room, oroom = f.split('/')[2], parts[2]
                    if room not in ROOMS or oroom not in ROOMS:
                        broken.append(f'{f}: {inc}: every core file lives in one of the rooms {", ".join(ROOMS)}')
                    elif ROOMS.index(oroom) > ROOMS.index(room):
                        broken.append(f'{f}: room {room} includes {inc} of room {oroom}, which is above it')
                om = module(inc)
                if other == layer and layer in CYCLE_FREE and om != m:
                    graph[m].add(om)
    # Cycles between modules of one layer (Tarjan's strongly connected components).
    index, low, stack, on, sccs, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in graph:
                continue
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
                sccs.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    for comp in sccs:
        broken.append('modules that depend on each other: ' + ' <-> '.join(comp))
    downcast = re.compile(r'\bdynamic_cast\b|\bsamples_of\s*\(|\bmerl_table_of\s*\(')
    for f in files_of('pipeline'):
        with open(os.path.join(ROOT, f), encoding='utf-8') as fh:
            for no, line in enumerate(fh, 1):
                code = line.split('//')[0]
                if downcast.search(code):
                    broken.append(f'{f}:{no}: pipeline/ asks a SOURCE what it has, never downcasts it: {line.strip()}')
    for b in broken:
        print(b)
    print(f'architecture: {len(graph)} modules checked, {len(broken)} rules broken')
    return 1 if broken else 0


if __name__ == '__main__':
    sys.exit(main())
