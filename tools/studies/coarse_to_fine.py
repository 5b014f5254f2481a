#!/usr/bin/env python3
"""Coarse-to-fine start, prototyped from the command line (issue 41; docs/journal/2026-12-03-fast-start.md).

  tools/studies/coarse_to_fine.py BIN OUTDIR INPUT... [--scale S] [--coarse-iterations N] [--mode mid|sqrt3]
                                  [--set KEY=VALUE ...]

1. Coarse run: `BIN mesh INPUT --set spacing.scale=S --set spacing.gradation=0.2*S`, a fixed number of
   iterations (population control's last event at 75 % of them). The gradation limit is scaled with
   the field because the limit q(x) <= q(y) + g |x - y| does not scale with `spacing.scale` alone:
   without it the 30P30N curves' coarse field kept 0.47 of the nodes instead of 1/3 at S = sqrt(3).
2. Refinement of the coarse final.nodes (scipy's Delaunay of every node): `mid` keeps the interior nodes
   and adds the midpoint of every Delaunay edge that does not join two boundary nodes (S = 2: about 4x
   the nodes, the lattice's orientation kept); `sqrt3` adds the circumcentre of every triangle
   (S = sqrt(3): about 3x, turned by 30 degrees). Boundary nodes are left out: the fine run places its
   own by the true field.
3. Fine run: `BIN mesh INPUT --start OUTDIR/refined.nodes` (init.file, the warm start) with the
   best preset's usual rule, and the extra --set keys.

Needs numpy and scipy. Prints one row per run (iterations, nodes, nodes x iterations, quality).
"""
import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np
from scipy.spatial import Delaunay


def read_nodes(path):
    lines = open(path).read().split("\n")
    count = int(lines[1])
    rows = [line.split() for line in lines[2:2 + count]]
    xy = np.array([[float(r[0]), float(r[1])] for r in rows])
    interior = np.array([r[2] == "interior" for r in rows])
    return xy, interior


def refine(xy, interior, mode):
    tri = Delaunay(xy).simplices
    if mode == "mid":
        edges = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
        edges = np.unique(np.sort(edges, 1), axis=0)
        # An edge of two boundary nodes is (nearly) a boundary segment: the fine run's own boundary
        # placement puts a node there.
        edges = edges[interior[edges[:, 0]] | interior[edges[:, 1]]]
        new = 0.5 * (xy[edges[:, 0]] + xy[edges[:, 1]])
    else:
        a, b, c = xy[tri[:, 0]], xy[tri[:, 1]], xy[tri[:, 2]]
        d = 2 * (a[:, 0] * (b[:, 1] - c[:, 1]) + b[:, 0] * (c[:, 1] - a[:, 1]) + c[:, 0] * (a[:, 1] - b[:, 1]))
        sa, sb, sc = (a**2).sum(1), (b**2).sum(1), (c**2).sum(1)
        ux = (sa * (b[:, 1] - c[:, 1]) + sb * (c[:, 1] - a[:, 1]) + sc * (a[:, 1] - b[:, 1])) / d
        uy = (sa * (c[:, 0] - b[:, 0]) + sb * (a[:, 0] - c[:, 0]) + sc * (b[:, 0] - a[:, 0])) / d
        new = np.stack([ux, uy], 1)
    return np.concatenate([xy[interior], new])


def write_nodes(path, points):
    # Interior points only, with a placeholder q: a warm start reads positions alone (init/warm_points).
    with open(path, "w") as out:
        out.write("# pdmesh nodes v1\n%d\n" % len(points))
        for p in points:
            out.write("%.17g %.17g interior -1 1\n" % (p[0], p[1]))
        out.write("curves 0\n")


def run(binary, inputs, out, sets):
    cmd = [binary, "mesh", *inputs, "--out", out, "--timings", os.path.join(out, "t.json"), "-q"]
    for s in sets:
        cmd += ["--set", s]
    os.makedirs(out, exist_ok=True)
    before = os.times()
    subprocess.run(cmd, check=True)
    after = os.times()
    timings = json.load(open(os.path.join(out, "t.json")))
    quality = json.load(open(os.path.join(out, "quality.json")))
    cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
    print(f"{os.path.basename(out)}: iterations {timings['iterations']} nodes {timings['nodes']} "
          f"nodes x iterations {timings['nodes'] * timings['iterations'] / 1e6:.2f} M "
          f"min angle {quality['included_angle']['min']:.2f} mean AR {quality['aspect_ratio']['average']:.4f} "
          f"edge/q {quality['spacing_conformance']['mean']:.4f} cpu {cpu:.2f} s")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("binary")
    parser.add_argument("outdir")
    parser.add_argument("inputs", nargs="+")
    parser.add_argument("--scale", type=float, default=2.0)
    parser.add_argument("--coarse-iterations", type=int, default=200)
    parser.add_argument("--mode", choices=["mid", "sqrt3"], default="mid")
    parser.add_argument("--set", action="append", default=[])
    args = parser.parse_args()
    if args.mode == "sqrt3" and abs(args.scale - math.sqrt(3)) > 0.2:
        print("coarse_to_fine: --mode sqrt3 triples the nodes; --scale should be about 1.732", file=sys.stderr)
    coarse = os.path.join(args.outdir, "coarse")
    run(args.binary, args.inputs, coarse, [
        f"spacing.scale={args.scale}", f"spacing.gradation={0.2 * args.scale}", "simulation.stop=iterations",
        f"simulation.iterations={args.coarse_iterations}", "population.stop=0.75"
    ])
    xy, interior = read_nodes(os.path.join(coarse, "final.nodes"))
    refined = os.path.join(args.outdir, "refined.nodes")
    points = refine(xy, interior, args.mode)
    write_nodes(refined, points)
    print(f"refined: {len(xy)} coarse nodes -> {len(points)} interior points")
    run(args.binary, args.inputs + ["--start", refined], os.path.join(args.outdir, "fine"), args.set)


if __name__ == "__main__":
    main()
