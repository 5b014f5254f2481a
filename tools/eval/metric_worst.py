#!/usr/bin/env python3
"""The worst triangles of a mesh of one of issue 37's metric cases (cases/aniso), measured as
`pdmesh` measures them (mesh/metric_quality: the mean ratio in the metric of the corner of largest
det M; the edge length with a geometric length element), with their vertices (boundary or interior,
the radius r = |(x, y)|) and metric edge lengths.

  tools/.venv-anchors/bin/python tools/eval/metric_worst.py DIR/mesh.msh --case polar1 --below 0.35

Needs numpy (the anchors' environment, tools/eval/setup_anchors.sh)."""

import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pdmesh_eval.meshfiles import read_msh  # noqa: E402
from pdmesh_eval.metric import _polar, linear_metric, polar1_metric, polar2_metric  # noqa: E402

METRICS = {"linear": linear_metric, "polar1": polar1_metric, "polar2": polar2_metric}


def length(ma, mb, v):
    """spacing/metric.hpp's edge_length."""
    def norm(m):
        return math.sqrt(m[0] * v[0] * v[0] + 2.0 * m[1] * v[0] * v[1] + m[2] * v[1] * v[1])
    la, lb = norm(ma), norm(mb)
    return 0.5 * (la + lb) if abs(la - lb) <= 1e-3 else (la - lb) / math.log(la / lb)


def quality(p, m):
    """cleanup/metric_evaluator's quality: the mean ratio in the corner metric of largest det."""
    det = [mi[0] * mi[2] - mi[1] * mi[1] for mi in m]
    k = max(range(3), key=lambda i: (det[i], -i))
    mk = m[k]
    area = 0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]))
    quad = 0.0
    for i in range(3):
        v = p[(i + 1) % 3] - p[i]
        quad += mk[0] * v[0] * v[0] + 2.0 * mk[1] * v[0] * v[1] + mk[2] * v[1] * v[1]
    return 4.0 * math.sqrt(3.0) * area * math.sqrt(det[k]) / quad


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("mesh", help="a .msh file")
    ap.add_argument("--case", choices=sorted(METRICS), required=True)
    ap.add_argument("--below", type=float, default=0.35, help="list the triangles with Q below this")
    ap.add_argument("--h-t", type=float, default=None,
                    help="polar1 only: its tangential size instead of 0.1 (a run with --set spacing.h2)")
    args = ap.parse_args()
    points, triangles = read_msh(args.mesh)
    p = np.array(points, float)
    t = np.array(triangles, int)
    if args.h_t is not None and args.case != "polar1":
        ap.error("--h-t is for --case polar1")
    if args.h_t is not None:
        metric = _polar(p, lambda r: np.full_like(r, args.h_t))
    else:
        metric = METRICS[args.case](p)
    edge_count = {}
    for tri in t:
        for i in range(3):
            e = tuple(sorted((int(tri[i]), int(tri[(i + 1) % 3]))))
            edge_count[e] = edge_count.get(e, 0) + 1
    boundary = {v for e, c in edge_count.items() if c == 1 for v in e}
    q = np.array([quality(p[tri], metric[tri]) for tri in t])
    order = np.argsort(q)
    print(f"{len(p)} nodes, {len(t)} triangles, Q min {q.min():.4f}, mean {q.mean():.4f}; "
          f"{int((q < args.below).sum())} below {args.below}")
    for k in order:
        if q[k] >= args.below:
            break
        tri = t[k]
        print(f"triangle {k}: Q {q[k]:.4f}")
        for i, v in enumerate(tri):
            x, y = p[v]
            kind = "boundary" if int(v) in boundary else "interior"
            print(f"  node {int(v)} ({x:.6f}, {y:.6f}) r {math.hypot(x, y):.6f} {kind}")
        for i in range(3):
            a, b = int(tri[i]), int(tri[(i + 1) % 3])
            e = tuple(sorted((a, b)))
            where = "boundary edge" if edge_count[e] == 1 else "interior edge"
            print(f"  edge {a}-{b}: L {length(metric[a], metric[b], p[b] - p[a]):.4f} ({where})")


if __name__ == "__main__":
    main()
