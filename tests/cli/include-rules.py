#!/usr/bin/env python3
"""The engine's include rules (docs/architecture.md), checked on the source: exit 1 naming each breach.
 - layers: core includes no io/rt/gl/render, no Embree and no GL; io includes no rt/gl/render;
   rt includes no gl/render and no GL header; gl includes no rt/render, no Embree;
 - no include circle among the files of one layer (a .cpp counts with its own header)."""
import os, re, sys

src = os.path.join(sys.argv[1], "engine", "src")
forbidden = {
    "core": ["io/", "rt/", "gl/", "render/", "embree3/", "glad/", "EGL/", "GLFW/"],
    "io": ["rt/", "gl/", "render/", "embree3/", "glad/", "EGL/", "GLFW/"],
    "rt": ["gl/", "render/", "glad/", "EGL/", "GLFW/"],
    "gl": ["rt/", "render/", "embree3/"],
}
include = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')
graph, status = {}, 0
for layer in sorted(os.listdir(src)):
    folder = os.path.join(src, layer)
    if not os.path.isdir(folder):
        continue
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        unit = f"{layer}/{os.path.splitext(name)[0]}"
        for n, line in enumerate(open(path, encoding="utf-8"), 1):
            m = include.match(line)
            if not m:
                continue
            target = m.group(1)
            for bad in forbidden.get(layer, []):
                if target.startswith(bad) or ("/" + bad) in target:
                    print(f"{layer}/{name}:{n}: includes {target}, which the {layer} layer may not")
                    status = 1
            if target.startswith(layer + "/") and os.path.splitext(target)[0] != unit:
                graph.setdefault(unit, set()).add(os.path.splitext(target)[0])

# Cycles: depth-first search with colours.
colour, stack = {}, []
def visit(u):
    global status
    colour[u] = 1
    stack.append(u)
    for v in sorted(graph.get(u, ())):
        if colour.get(v) == 1:
            print("include circle: " + " -> ".join(stack[stack.index(v):] + [v]))
            status = 1
        elif colour.get(v) is None:
            visit(v)
    stack.pop()
    colour[u] = 2
for u in sorted(graph):
    if colour.get(u) is None:
        visit(u)
sys.exit(status)
