#!/usr/bin/env python3
"""pdmesh's periodic hill channel with boundary layers (examples/periodic_hill) against Gmsh's
BoundaryLayer field with setPeriodic on the same channel:

    tools/.venv-anchors/bin/python tools/eval/periodic_layers_vs_gmsh.py --pdmesh build/pdmesh --work W

Meshes, each measured by the same code from its mesh.msh (read with the gmsh module):
  pdmesh: `pdmesh mesh examples/periodic_hill/case.toml --formats msh` (the best preset, spacing.size
          0.12, layers on the bottom and the top: h1 0.002, growth 1.2, thickness 0.12, split quads);
  pdmesh free: the same case without its [[periodic]] table (what tying and fixing the sides cost);
  gmsh:   the same polylines in Gmsh's built-in kernel (one line per segment, as
          tools/eval/layer_anchors.py builds them), a BoundaryLayer field on the bottom's and the
          top's lines with the same Size, Ratio and Thickness (Quads 0: triangles), PointsList the
          four corners (where the layers end, so that they run onto the inlet and outlet), the core
          at Mesh.MeshSizeMax = the case's size, and at 1.09 x it (the best preset's
          spacing.relax_scale: about pdmesh's node count); Frontal-Delaunay (Mesh.Algorithm 6);
          setPeriodic outlet <- inlet by the translation (9, 0).
Measures (periodic_vs_gmsh.measure, and here): nodes, triangles, the smallest angle of the core (the
triangles whose centroid is farther than 1.05 x the thickness from both walls), the mean radius ratio
2 r / R of the core, the first height (the height of each triangle on a wall edge over that edge:
min, median, max, over h1), the node pairs gmsh.model.mesh.getPeriodicNodes lists on the outlet and
the largest |A p_master - p| over them, the pairs below the top of the bottom layer (the layer's
column), and the seconds (pdmesh: the whole command; gmsh: generate(2) alone)."""

import argparse
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from periodic_vs_gmsh import generate_and_write, measure, run_pdmesh  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASE = os.path.join(REPO, "examples", "periodic_hill", "case.toml")
CURVES = os.path.join(REPO, "examples", "periodic_hill", "hill.crv")
SIZE = 0.12
RELAX_SCALE = 1.09
FIRST_HEIGHT, GROWTH, THICKNESS = 0.002, 1.2, 0.12
LENGTH = 9.0


def read_curves(path):
    lines = [line for line in open(path).read().split("\n") if line.strip()]
    curves, k = [], 0
    while k < len(lines):
        n = int(lines[k])
        curves.append([tuple(map(float, lines[k + 1 + j].split())) for j in range(n)])
        k += n + 1
    return curves  # bottom, outlet, top, inlet (examples/periodic_hill/case.toml's curve_names)


def segment_distance(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)))
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)


def layer_measures(gmsh, walls):
    """Core min angle and mean 2r/R, the wall triangles' heights, and the column's pairs, of the open mesh."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xy = {int(t): (coords[3 * k], coords[3 * k + 1]) for k, t in enumerate(tags)}
    types, _, nodes = gmsh.model.mesh.getElements(2)
    tri = [list(map(int, n)) for t, n in zip(types, nodes) if int(t) == 2][0]
    wall_segments = [(c[k], c[k + 1]) for c in walls for k in range(len(c) - 1)]
    on_wall = {}
    for k in range(len(tri) // 3):
        t = tri[3 * k:3 * k + 3]
        for j in range(3):
            a, b = sorted((t[j], t[(j + 1) % 3]))
            on_wall.setdefault((a, b), []).append(t[(j + 2) % 3])
    heights, core_min, core_ratio, core_count = [], 180.0, 0.0, 0
    for k in range(len(tri) // 3):
        p = [xy[v] for v in tri[3 * k:3 * k + 3]]
        centroid = (sum(q[0] for q in p) / 3, sum(q[1] for q in p) / 3)
        if min(segment_distance(centroid, a, b) for a, b in wall_segments) <= 1.05 * THICKNESS:
            continue
        e = [math.dist(p[(j + 1) % 3], p[(j + 2) % 3]) for j in range(3)]
        for j in range(3):
            a, b, c = e[j], e[(j + 1) % 3], e[(j + 2) % 3]
            core_min = min(core_min, math.degrees(math.acos(max(-1.0, min(1.0, (b * b + c * c - a * a) / (2 * b * c))))))
        s = 0.5 * sum(e)
        area = max(0.0, s * (s - e[0]) * (s - e[1]) * (s - e[2])) ** 0.5
        core_ratio += 2 * (area / s) / (e[0] * e[1] * e[2] / (4 * area))
        core_count += 1
    # Wall edges: both nodes on a wall segment (within 1e-9), one triangle on them.
    def on_segments(q):
        return any(segment_distance(q, a, b) <= 1e-9 for a, b in wall_segments)
    wall_node = {v: on_segments(q) for v, q in xy.items()}
    for (a, b), opposite in on_wall.items():
        if len(opposite) != 1 or not (wall_node[a] and wall_node[b]):
            continue
        pa, pb, pc = xy[a], xy[b], xy[opposite[0]]
        cross = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0])
        heights.append(abs(cross) / math.dist(pa, pb))
    heights.sort()
    return {"core_min_angle": core_min, "core_mean_ratio": core_ratio / max(1, core_count),
            "first_min": heights[0] / FIRST_HEIGHT, "first_median": heights[len(heights) // 2] / FIRST_HEIGHT,
            "first_max": heights[-1] / FIRST_HEIGHT}


def periodic_pairs(gmsh, bottom_top_at_inlet):
    """The outlet's pairs (the entity with a master) and how many lie at or below the bottom layer's top."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xy = {int(t): (coords[3 * k], coords[3 * k + 1]) for k, t in enumerate(tags)}
    for d, tag in gmsh.model.getEntities(1):
        master, slaves, masters, _ = gmsh.model.mesh.getPeriodicNodes(d, tag)
        if master != tag and len(slaves) > 0:
            column = sum(1 for m in masters if xy[int(m)][1] <= bottom_top_at_inlet + 1e-9)
            return len(slaves), column
    return 0, 0


def free_case(work):
    """The example without its [[periodic]] table, its geometry by absolute path."""
    text = open(CASE).read()
    text = re.sub(r"\[\[periodic\]\]\n(?:[^\[\n].*\n|\n)*", "", text)
    text = text.replace('files = ["hill.crv"]', f'files = ["{CURVES}"]')
    path = os.path.join(work, "free.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def gmsh_channel(gmsh, curves, size, out):
    bottom, _, top, _ = curves
    gmsh.model.add("hill")
    geo = gmsh.model.geo
    bp = [geo.addPoint(x, y, 0, size) for x, y in bottom]
    top_right, top_left = geo.addPoint(top[0][0], top[0][1], 0, size), geo.addPoint(top[-1][0], top[-1][1], 0, size)
    wall = [geo.addLine(bp[k], bp[k + 1]) for k in range(len(bp) - 1)]
    outlet = geo.addLine(bp[-1], top_right)
    top_line = geo.addLine(top_right, top_left)
    inlet = geo.addLine(bp[0], top_left)
    geo.addPlaneSurface([geo.addCurveLoop(wall + [outlet, top_line, -inlet])])
    geo.synchronize()
    gmsh.model.mesh.setPeriodic(1, [outlet], [inlet], [1, 0, 0, LENGTH, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])
    f = gmsh.model.mesh.field.add("BoundaryLayer")
    gmsh.model.mesh.field.setNumbers(f, "CurvesList", wall + [top_line])
    gmsh.model.mesh.field.setNumber(f, "Size", FIRST_HEIGHT)
    gmsh.model.mesh.field.setNumber(f, "Ratio", GROWTH)
    gmsh.model.mesh.field.setNumber(f, "Thickness", THICKNESS)
    gmsh.model.mesh.field.setNumber(f, "Quads", 0)
    gmsh.model.mesh.field.setNumbers(f, "PointsList", [bp[0], bp[-1], top_left, top_right])
    gmsh.model.mesh.field.setAsBoundaryLayer(f)
    return generate_and_write(gmsh, size, out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pdmesh", required=True)
    parser.add_argument("--work", required=True)
    args = parser.parse_args()
    import gmsh

    os.makedirs(args.work, exist_ok=True)
    curves = read_curves(CURVES)
    rows = []
    out = os.path.join(args.work, "pdmesh")
    seconds = run_pdmesh(args.pdmesh, CASE, out)
    rows.append(("pdmesh", os.path.join(out, "mesh.msh"), seconds))
    out = os.path.join(args.work, "pdmesh_free")
    seconds = run_pdmesh(args.pdmesh, free_case(args.work), out)
    rows.append(("pdmesh free", os.path.join(out, "mesh.msh"), seconds))
    gmsh.initialize(["gmsh", "-v", "2"])
    gmsh.option.setNumber("General.NumThreads", 1)
    for size in (SIZE, SIZE * RELAX_SCALE):
        label = f"gmsh {size:g}"
        path = os.path.join(args.work, label.replace(" ", "_") + ".msh")
        rows.append((label, path, gmsh_channel(gmsh, curves, size, path)))
    # The bottom layer's top on the inlet (the hill's crest, y = 1, plus the thickness).
    column_top = curves[0][0][1] + THICKNESS
    print(f"gmsh {gmsh.__version__}; size {SIZE}; layers h1 {FIRST_HEIGHT}, growth {GROWTH}, thickness {THICKNESS}")
    print(f"{'mesh':<12} {'nodes':>6} {'tris':>6} {'core min':>8} {'core 2r/R':>9} {'h/h1 min':>8} {'median':>7} "
          f"{'max':>7} {'pairs':>5} {'column':>6} {'mismatch':>8} {'seconds':>7}")
    for name, path, secs in rows:
        periodic = name != "pdmesh free"
        m = measure(gmsh, path, periodic)
        lm = layer_measures(gmsh, [curves[0], curves[2]])
        pairs, column = periodic_pairs(gmsh, column_top) if periodic else ("-", "-")
        mismatch = "-" if m["mismatch"] is None else f"{m['mismatch']:.2g}"
        print(f"{name:<12} {m['nodes']:>6} {m['triangles']:>6} {lm['core_min_angle']:>8.2f} "
              f"{lm['core_mean_ratio']:>9.4f} {lm['first_min']:>8.3f} {lm['first_median']:>7.3f} "
              f"{lm['first_max']:>7.3f} {pairs:>5} {column:>6} {mismatch:>8} {secs:>7.3f}")
    gmsh.finalize()
    return 0


if __name__ == "__main__":
    sys.exit(main())
