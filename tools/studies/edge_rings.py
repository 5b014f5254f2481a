#!/usr/bin/env python3
"""Edge length over q by distance from a centre: where a mesh's edge/q spread comes from (issue 41).

  tools/studies/edge_rings.py OUTDIR [--centre X Y] [--bins 20]

OUTDIR is a `pdmesh mesh ... --formats triangle` output folder (mesh.nodes for x, y and q; mesh.ele for
the triangles, in mesh.nodes' order). Each unique edge's ratio is its length over the mean of its two
end nodes' q (mesh.nodes' q: the relaxed spacing; the ratio's level differs from quality.json's
spacing conformance, its spread does not). The edges are split into equal-count bins of their
midpoint's distance from the centre (default: the origin, the annulus cases' centre); per bin the
mean and std of the ratio and the mean q. The last line splits the overall variance into the part
within the bins and the part between their means: rings of a start that the relaxation kept show up
as the second.

Needs numpy (tools/.venv-anchors has it).
"""

import argparse
import os

import numpy as np


def read_nodes(path):
    with open(path) as f:
        lines = f.read().splitlines()
    n = int(lines[1])
    rows = [line.split() for line in lines[2:2 + n]]
    xy = np.array([[float(r[0]), float(r[1])] for r in rows])
    q = np.array([float(r[4]) for r in rows])
    return xy, q


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outdir")
    ap.add_argument("--centre", nargs=2, type=float, default=(0.0, 0.0))
    ap.add_argument("--bins", type=int, default=20)
    a = ap.parse_args()
    xy, q = read_nodes(os.path.join(a.outdir, "mesh.nodes"))
    # Triangle's .ele: a comment line, the header line, then "index a b c" with 1-based indices.
    tri = np.loadtxt(os.path.join(a.outdir, "mesh.ele"), comments="#", skiprows=2, dtype=np.int64)[:, 1:4] - 1
    edges = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    edges.sort(axis=1)
    edges = np.unique(edges, axis=0)
    length = np.linalg.norm(xy[edges[:, 0]] - xy[edges[:, 1]], axis=1)
    q_edge = 0.5 * (q[edges[:, 0]] + q[edges[:, 1]])
    ratio = length / q_edge
    mid = 0.5 * (xy[edges[:, 0]] + xy[edges[:, 1]])
    radius = np.hypot(mid[:, 0] - a.centre[0], mid[:, 1] - a.centre[1])
    print(f"edges {len(ratio)}: length/q mean {ratio.mean():.4f}, std {ratio.std():.4f}")
    bounds = np.quantile(radius, np.linspace(0.0, 1.0, a.bins + 1))
    which = np.clip(np.digitize(radius, bounds) - 1, 0, a.bins - 1)
    within = 0.0
    print("| radius | edges | length/q mean | std | mean q |")
    print("|---|---:|---:|---:|---:|")
    for b in range(a.bins):
        m = which == b
        within += ratio[m].var() * m.sum()
        print(f"| {bounds[b]:.3f}-{bounds[b + 1]:.3f} | {m.sum()} | {ratio[m].mean():.4f} | {ratio[m].std():.4f} "
              f"| {q_edge[m].mean():.5f} |")
    within /= len(ratio)
    print(f"std within the bins {np.sqrt(within):.4f}; std of the bins' means {np.sqrt(max(ratio.var() - within, 0.0)):.4f}")


if __name__ == "__main__":
    main()
