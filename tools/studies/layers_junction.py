#!/usr/bin/env python3
"""The junction between a boundary layer and a core mesh made on its front (docs/boundary-layers.md).

    layers_junction.py LAYER_OUT CORE_MESH.msh

LAYER_OUT is the folder layers_prototype wrote (core.crv, front_tops.txt); CORE_MESH.msh is
`pdmesh mesh LAYER_OUT/core.toml`'s mesh.msh (Gmsh 4.1 ASCII). Prints how many front nodes the core
mesh kept exactly, how many front edges are edges of a core triangle, the growth across the junction
(each such triangle's height over its front edge divided by the mean last-layer height at the edge's
two nodes: median, p95, max) and the core's smallest angle. Standard library only.
"""
import math
import sys


def read_curves(path):
    lines = [l for l in open(path).read().split("\n")]
    curves, i = [], 0
    while i < len(lines) and lines[i].strip():
        n = int(lines[i])
        curves.append([tuple(map(float, l.split())) for l in lines[i + 1:i + 1 + n]])
        i += 1 + n
    return curves


def read_msh41(path):
    text = open(path).read()
    sec = text.split("$Nodes")[1].split("$EndNodes")[0].strip().split("\n")
    nodes, j = {}, 1
    while j < len(sec):
        n = int(sec[j].split()[3])
        ids = [int(x) for x in sec[j + 1:j + 1 + n]]
        for tag, line in zip(ids, sec[j + 1 + n:j + 1 + 2 * n]):
            x, y, _ = map(float, line.split())
            nodes[tag] = (x, y)
        j += 1 + 2 * n
    sec = text.split("$Elements")[1].split("$EndElements")[0].strip().split("\n")
    triangles, j = [], 1
    while j < len(sec):
        head = sec[j].split()
        kind, n = int(head[2]), int(head[3])
        if kind == 2:
            for line in sec[j + 1:j + 1 + n]:
                triangles.append([nodes[int(v)] for v in line.split()[1:4]])
        j += 1 + n
    return nodes, triangles


def quantile(values, q):
    v = sorted(values)
    return v[min(len(v) - 1, max(0, math.ceil(q * len(v)) - 1))]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out, mesh = sys.argv[1], sys.argv[2]
    # The fronts are the curves named *_front (closed: the first point repeated at the end).
    toml = open(out + "/core.toml").read()
    names = [x.strip().strip('"') for x in toml.split("curve_names = [")[1].split("]")[0].split(",")]
    fronts = [c[:-1] for c, name in zip(read_curves(out + "/core.crv"), names) if name.endswith("_front")]
    index = {}  # point -> (front, position)
    for f, front in enumerate(fronts):
        for k, p in enumerate(front):
            index[p] = (f, k)
    last = {}
    for line in open(out + "/front_tops.txt"):
        if not line.startswith("#"):
            x, y, h = map(float, line.split())
            last[(x, y)] = h
    nodes, triangles = read_msh41(mesh)
    mesh_points = set(nodes.values())
    kept = sum(1 for p in index if p in mesh_points)
    ratios, smallest = [], 180.0
    n = len(index)
    for t in triangles:
        for a in range(3):
            p, q, r = t[a], t[(a + 1) % 3], t[(a + 2) % 3]
            u, w = (q[0] - p[0], q[1] - p[1]), (r[0] - p[0], r[1] - p[1])
            smallest = min(smallest, math.degrees(math.atan2(abs(u[0] * w[1] - u[1] * w[0]), u[0] * w[0] + u[1] * w[1])))
            ka, kb = index.get(p), index.get(q)
            if ka is None or kb is None or ka[0] != kb[0]:
                continue
            m = len(fronts[ka[0]])
            if (ka[1] - kb[1]) % m not in (1, m - 1):
                continue
            length = math.hypot(*u)
            height = abs(u[0] * w[1] - u[1] * w[0]) / length
            ratios.append(height / (0.5 * (last[p] + last[q])))
    print(f"front nodes kept exactly: {kept} of {n}; front edges with a core triangle: {len(ratios)} of {n}")
    print(f"junction growth (core height / last layer): median {quantile(ratios, 0.5):.3f} "
          f"p95 {quantile(ratios, 0.95):.3f} max {max(ratios):.3f}; below 1: {sum(r < 1 for r in ratios)}")
    print(f"core min angle {smallest:.2f} deg")


if __name__ == "__main__":
    main()
