#!/usr/bin/env python3
"""pdmesh's periodic unit cell (examples/periodic_cell) against Gmsh's setPeriodic on the same cell:

    tools/.venv-anchors/bin/python tools/eval/periodic_vs_gmsh.py --pdmesh build/pdmesh --work W

Four meshes, each measured by the same code from its mesh.msh (read with the gmsh module):
  pdmesh periodic: `pdmesh mesh examples/periodic_cell/case.toml` (the best preset, spacing.size 0.025);
  pdmesh free:     the same case without its [[periodic]] tables (the quality cost of fixing the nodes);
  gmsh periodic:   the cell in Gmsh's built-in kernel (the square, the three fibres as true circles of
                   four arcs each), Mesh.MeshSizeMax = the case's size, the size at a fibre's points
                   min(size, R x 10 degrees) (pdmesh's spacing.curvature_angle; Gmsh 4.15.2's
                   Mesh.MeshSizeFromCurvature did not finish on this cell), Frontal-Delaunay
                   (Mesh.Algorithm 6), and setPeriodic for right <- left and top <- bottom;
  gmsh free:       the same without setPeriodic;
and the two Gmsh meshes again at 1.09 x the size (the best preset's spacing.relax_scale, the size
pdmesh places its nodes at: about pdmesh's node count).
Measures: nodes, triangles, the smallest angle, the mean radius ratio 2 r / R (1 for an equilateral
triangle), the share of triangles with an angle below 30 degrees, the wall time of the whole pdmesh
command (gmsh: generate(2) alone), and for the periodic meshes the largest |A p_master - p| over every
pair gmsh.model.mesh.getPeriodicNodes returns. The pdmesh case's polygons are within 6e-5 of the
circles."""

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASE = os.path.join(REPO, "examples", "periodic_cell", "case.toml")
SIZE = 0.025
RELAX_SCALE = 1.09  # the best preset's spacing.relax_scale: pdmesh places and relaxes its nodes at this x q
CURVATURE_DEG = 10.0  # pdmesh's spacing.curvature_angle in the best preset: q <= R theta on a circle
FIBRES = [(0.28, 0.3, 0.17), (0.72, 0.6, 0.21), (0.25, 0.76, 0.1)]


def measure(gmsh, path, periodic_curves):
    """Nodes, triangles, min angle, mean radius ratio, share below 30 deg, periodic mismatch of a .msh."""
    gmsh.open(path)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xy = {int(t): (coords[3 * k], coords[3 * k + 1]) for k, t in enumerate(tags)}
    types, _, nodes = gmsh.model.mesh.getElements(2)
    tri = [list(map(int, n)) for t, n in zip(types, nodes) if int(t) == 2][0]
    min_angle, ratio_sum, below = 180.0, 0.0, 0
    count = len(tri) // 3
    for k in range(count):
        p = [xy[tri[3 * k + j]] for j in range(3)]
        e = [math.dist(p[(j + 1) % 3], p[(j + 2) % 3]) for j in range(3)]  # e[j] opposite p[j]
        angles = []
        for j in range(3):
            a, b, c = e[j], e[(j + 1) % 3], e[(j + 2) % 3]
            angles.append(math.degrees(math.acos(max(-1.0, min(1.0, (b * b + c * c - a * a) / (2 * b * c))))))
        min_angle = min(min_angle, min(angles))
        below += min(angles) < 30.0
        s = 0.5 * sum(e)
        area = max(0.0, s * (s - e[0]) * (s - e[1]) * (s - e[2])) ** 0.5
        r, big_r = area / s, e[0] * e[1] * e[2] / (4 * area)
        ratio_sum += 2 * r / big_r
    mismatch = None
    if periodic_curves:
        mismatch = 0.0
        for d, tag in gmsh.model.getEntities(1):
            master, slaves, masters, a = gmsh.model.mesh.getPeriodicNodes(d, tag)
            if master == tag or len(slaves) == 0:
                continue
            for s_tag, m_tag in zip(slaves, masters):
                mx, my = xy[int(m_tag)]
                x, y = a[0] * mx + a[1] * my + a[3], a[4] * mx + a[5] * my + a[7]
                mismatch = max(mismatch, math.hypot(x - xy[int(s_tag)][0], y - xy[int(s_tag)][1]))
    return {"nodes": len(xy), "triangles": count, "min_angle": min_angle, "mean_ratio": ratio_sum / count,
            "below_30": 100.0 * below / count, "mismatch": mismatch}


def run_pdmesh(binary, case, out):
    shutil.rmtree(out, ignore_errors=True)
    start = time.perf_counter()
    subprocess.run([binary, "mesh", case, "--out", out, "-q", "--formats", "msh"], check=True)
    return time.perf_counter() - start


def free_case(work):
    """The example without its [[periodic]] tables, its geometry by absolute path."""
    text = open(CASE).read()
    text = re.sub(r"\[\[periodic\]\]\n(?:[^\[\n].*\n|\n)*", "", text)
    text = text.replace('files = ["cell.crv"]', f'files = ["{os.path.join(os.path.dirname(CASE), "cell.crv")}"]')
    path = os.path.join(work, "free.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def generate_and_write(gmsh, size, out):
    """Meshes the current model with Frontal-Delaunay at MeshSizeMax = size, writes MSH 4.1 to out,
    removes the model; returns the meshing seconds."""
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    start = time.perf_counter()
    gmsh.model.mesh.generate(2)
    seconds = time.perf_counter() - start
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(out)
    gmsh.model.remove()
    return seconds


def gmsh_cell(gmsh, periodic, out, size):
    gmsh.model.add("cell")
    geo = gmsh.model.geo
    corners = [geo.addPoint(x, y, 0, size) for x, y in [(0, 0), (1, 0), (1, 1), (0, 1)]]
    bottom, right = geo.addLine(corners[0], corners[1]), geo.addLine(corners[1], corners[2])
    top, left = geo.addLine(corners[3], corners[2]), geo.addLine(corners[0], corners[3])
    loops = [geo.addCurveLoop([bottom, right, -top, -left])]
    for cx, cy, r in FIBRES:
        c = geo.addPoint(cx, cy, 0)
        lc = min(size, r * math.radians(CURVATURE_DEG))
        p = [geo.addPoint(cx + r * math.cos(k * math.pi / 2), cy + r * math.sin(k * math.pi / 2), 0, lc)
             for k in range(4)]
        arcs = [geo.addCircleArc(p[k], c, p[(k + 1) % 4]) for k in range(4)]
        loops.append(geo.addCurveLoop(arcs))
    geo.addPlaneSurface(loops)
    geo.synchronize()
    if periodic:
        gmsh.model.mesh.setPeriodic(1, [right], [left], [1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])
        gmsh.model.mesh.setPeriodic(1, [top], [bottom], [1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 0, 0, 0, 0, 1])
    return generate_and_write(gmsh, size, out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pdmesh", required=True)
    parser.add_argument("--work", required=True)
    args = parser.parse_args()
    import gmsh

    os.makedirs(args.work, exist_ok=True)
    rows = []
    seconds = run_pdmesh(args.pdmesh, CASE, os.path.join(args.work, "pdmesh_periodic"))
    rows.append(("pdmesh periodic", os.path.join(args.work, "pdmesh_periodic", "mesh.msh"), True, seconds))
    seconds = run_pdmesh(args.pdmesh, free_case(args.work), os.path.join(args.work, "pdmesh_free"))
    rows.append(("pdmesh free", os.path.join(args.work, "pdmesh_free", "mesh.msh"), False, seconds))
    gmsh.initialize(["gmsh", "-v", "2"])
    gmsh.option.setNumber("General.NumThreads", 1)
    for size in (SIZE, SIZE * RELAX_SCALE):
        for periodic in (True, False):
            label = f"gmsh {'periodic' if periodic else 'free'} {size:g}"
            out = os.path.join(args.work, label.replace(" ", "_") + ".msh")
            seconds = gmsh_cell(gmsh, periodic, out, size)
            rows.append((label, out, periodic, seconds))
    print(f"gmsh {gmsh.__version__}; size {SIZE} (pdmesh places its nodes at {RELAX_SCALE} x that)")
    print(f"{'mesh':<24} {'nodes':>6} {'tris':>6} {'min angle':>9} {'mean 2r/R':>9} {'<30 deg %':>9} "
          f"{'seconds':>8} {'mismatch':>9}")
    for name, path, periodic, secs in rows:
        m = measure(gmsh, path, periodic)
        mismatch = "-" if m["mismatch"] is None else f"{m['mismatch']:.2g}"
        print(f"{name:<24} {m['nodes']:>6} {m['triangles']:>6} {m['min_angle']:>9.2f} {m['mean_ratio']:>9.4f} "
              f"{m['below_30']:>9.2f} {secs:>8.3f} {mismatch:>9}")
    gmsh.finalize()
    return 0


if __name__ == "__main__":
    sys.exit(main())
