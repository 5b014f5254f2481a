#!/usr/bin/env python3
"""The lattice's slow collective drift on a graded run: where the nodes are denser or sparser than the
field's hexagonal packing, and how they move between two node files of one run (issue 41).

  tools/studies/drift_bands.py density NODES... [--centre X Y]
  tools/studies/drift_bands.py motion A B [--centre X Y] [--smooth W]

NODES, A and B are pdmesh node files (initial.nodes, final.nodes: x, y, kind, curve, q; q is the
spacing the nodes relaxed at, spacing.relax_scale x the field). For `motion` A and B must hold the
same nodes in the same order: two runs of one case with `--iterations N --stop iterations --set
population.enabled=false` for two N.

density: per node, the density ratio = the hexagonal-packing area at q (sqrt(3)/2 q^2) over the node's
share of the Delaunay triangles around it (a third of each one's area); its median over the interior
nodes per band of distance from the centre (default 0.5 0, an airfoil of chord 1) and per band of
distance to the closest boundary node in units of the node's q. A relaxed lattice compressed by
relax_scale sits near 1.2; differences between bands are pressure differences that the run evens out
by moving nodes from band to band.

motion: per band, the median displacement over q (its magnitude, its component away from the centre,
its component towards the closest boundary node), and how collective it is (the length of the
displacement averaged over the 20 nearest nodes over the average of their lengths: 1 = all move
together). Then the displacement is split into a smooth part (the Gaussian-weighted mean over the
60 nearest nodes, weight exp(-(r / (W q))^2 / 2), W = 3 by default) and the rest, and the mean aspect
ratio (R / 2r) of the interior Delaunay triangles is printed for A, B, A moved by the smooth part alone
and A moved by the rest alone: which part of the motion the mesh quality follows.

Needs numpy and scipy (Delaunay triangulation, k-d tree).
"""

import argparse
import os
import sys

import numpy as np
from scipy.spatial import Delaunay, cKDTree

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "eval"))
from pdmesh_eval.meshfiles import read_node_file  # noqa: E402

RADIAL_BANDS = [0, 0.3, 0.5, 0.7, 1, 1.4, 2, 2.8, 4, 5.6, 8, 11, 16, 1e300]
WALL_BANDS = [0, 1.5, 3, 5, 8, 12, 20, 40, 1e300]


def read_nodes(path):
    """x, y (n x 2), kind (strings), q of a pdmesh node file."""
    nodes, _ = read_node_file(path)
    xy = np.array([[n[0], n[1]] for n in nodes])
    kind = np.array([n[2] for n in nodes])
    q = np.array([n[4] for n in nodes])
    return xy, kind, q


def density_ratio(xy, q):
    """Per node: sqrt(3)/2 q^2 over a third of the area of its Delaunay triangles."""
    s = Delaunay(xy).simplices
    a = xy[s[:, 1]] - xy[s[:, 0]]
    b = xy[s[:, 2]] - xy[s[:, 0]]
    area = 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    share = np.zeros(len(xy))
    np.add.at(share, s.ravel(), np.repeat(area / 3.0, 3))
    return (np.sqrt(3.0) / 2.0 * q**2) / share


def wall_distance(xy, kind, q):
    """Distance to the closest boundary or fixed node, in units of each node's q."""
    on_wall = kind != "interior"
    dist, _ = cKDTree(xy[on_wall]).query(xy)
    return dist / q


def mean_aspect_ratio(xy, kind):
    """Mean R / 2r of the Delaunay triangles of xy whose three corners are interior nodes."""
    s = Delaunay(xy).simplices
    s = s[(kind[s] == "interior").all(axis=1)]
    p = xy[s]
    la = np.linalg.norm(p[:, 1] - p[:, 2], axis=1)
    lb = np.linalg.norm(p[:, 0] - p[:, 2], axis=1)
    lc = np.linalg.norm(p[:, 0] - p[:, 1], axis=1)
    half = 0.5 * (la + lb + lc)
    area = np.sqrt(np.maximum(half * (half - la) * (half - lb) * (half - lc), 1e-300))
    return float(np.mean((la * lb * lc / (4.0 * area)) / (2.0 * area / half)))


def smooth_part(xy, q, d, width, k=60):
    """The Gaussian-weighted mean of d over each node's k nearest nodes (width in units of its q)."""
    k = min(k, len(xy))
    dist, nb = cKDTree(xy).query(xy, k)
    w = np.exp(-0.5 * (dist / (width * q[:, None]))**2)
    return (d[nb] * w[:, :, None]).sum(axis=1) / w.sum(axis=1)[:, None]


def split_motion(a, kind, q, b, width=3.0):
    """Mean aspect ratios of a, b, a + the smooth part of b - a, a + the rest; the smooth part's share
    of the squared displacement of the interior nodes. Boundary nodes move as they did in both."""
    d = b - a
    smooth = smooth_part(a, q, d, width)
    wall = kind != "interior"
    smooth[wall] = d[wall]
    rest = d - smooth
    rest[wall] = d[wall]
    inner = ~wall
    share = float((smooth[inner]**2).sum() / max((d[inner]**2).sum(), 1e-300))
    return {
        "a": mean_aspect_ratio(a, kind),
        "b": mean_aspect_ratio(b, kind),
        "smooth": mean_aspect_ratio(a + smooth, kind),
        "rest": mean_aspect_ratio(a + rest, kind),
        "smooth_share": share,
    }


def bands(values, edges):
    return np.digitize(values, edges) - 1


def cmd_density(args):
    centre = np.array(args.centre)
    data = [read_nodes(p) for p in args.nodes]
    ratios = [density_ratio(xy, q) for xy, _, q in data]
    print("density ratio (median over interior nodes) by distance from the centre; columns:", *args.nodes)
    for label, per_file in (("r", lambda xy, k, q: np.linalg.norm(xy - centre, axis=1)),
                            ("wall/q", wall_distance)):
        edges = RADIAL_BANDS if label == "r" else WALL_BANDS
        print(f"-- by {label}")
        for i in range(len(edges) - 1):
            cells = []
            for (xy, kind, q), ratio in zip(data, ratios):
                where = bands(per_file(xy, kind, q), edges) == i
                where &= kind == "interior"
                cells.append(f"{np.median(ratio[where]):.3f} ({where.sum()})" if where.sum() else "-")
            if any(c != "-" for c in cells):
                print(f"{label} {edges[i]:g}-{edges[i + 1]:g}: " + "  ".join(cells))


def cmd_motion(args):
    centre = np.array(args.centre)
    a, kind, q = read_nodes(args.a)
    b, kind_b, _ = read_nodes(args.b)
    if len(a) != len(b) or (kind != kind_b).any():
        raise SystemExit("drift_bands.py: A and B do not hold the same nodes (population control on?)")
    d = b - a
    length = np.linalg.norm(d, axis=1)
    out = a - centre
    out /= np.maximum(np.linalg.norm(out, axis=1), 1e-300)[:, None]
    _, nb = cKDTree(a).query(a, min(20, len(a)))
    coherence = np.linalg.norm(d[nb].mean(axis=1), axis=1) / np.maximum(length[nb].mean(axis=1), 1e-300)
    wall = kind != "interior"
    wall_tree = cKDTree(a[wall])
    dist, j = wall_tree.query(a)
    towards = (a[wall][j] - a) / np.maximum(dist, 1e-300)[:, None]
    inner = ~wall
    r = np.linalg.norm(a - centre, axis=1)
    print("by distance from the centre: nodes, median |d|/q, away from the centre /q, coherence")
    for i, band in ((i, bands(r, RADIAL_BANDS) == i) for i in range(len(RADIAL_BANDS) - 1)):
        m = band & inner
        if m.sum():
            print(f"r {RADIAL_BANDS[i]:g}-{RADIAL_BANDS[i + 1]:g}: {m.sum()} {np.median(length[m] / q[m]):.3f} "
                  f"{np.median((d[m] * out[m]).sum(axis=1) / q[m]):+.3f} {np.median(coherence[m]):.2f}")
    print("by distance to the closest boundary node (in q): nodes, median |d|/q, towards it /q, coherence")
    wq = dist / q
    for i in range(len(WALL_BANDS) - 1):
        m = (bands(wq, WALL_BANDS) == i) & inner
        if m.sum():
            print(f"wall/q {WALL_BANDS[i]:g}-{WALL_BANDS[i + 1]:g}: {m.sum()} {np.median(length[m] / q[m]):.3f} "
                  f"{np.median((d[m] * towards[m]).sum(axis=1) / q[m]):+.3f} {np.median(coherence[m]):.2f}")
    s = split_motion(a, kind, q, b, args.smooth)
    print(f"mean aspect ratio: A {s['a']:.6f}, B {s['b']:.6f}, A + smooth part {s['smooth']:.6f}, "
          f"A + the rest {s['rest']:.6f}; smooth part's share of |d|^2 {s['smooth_share']:.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("density")
    p.add_argument("nodes", nargs="+")
    p.add_argument("--centre", nargs=2, type=float, default=(0.5, 0.0))
    p.set_defaults(run=cmd_density)
    p = sub.add_parser("motion")
    p.add_argument("a")
    p.add_argument("b")
    p.add_argument("--centre", nargs=2, type=float, default=(0.5, 0.0))
    p.add_argument("--smooth", type=float, default=3.0)
    p.set_defaults(run=cmd_motion)
    a = ap.parse_args()
    a.run(a)


if __name__ == "__main__":
    main()
