#!/usr/bin/env python3
"""pdmesh smooth on Gmsh meshes (issue 40, "Done when"): each case's geometry meshed by Gmsh's
Frontal-Delaunay (Mesh.Algorithm = 6) with Gmsh's own sizing from the boundary (a mesh size at every
geometry point, the mean of its two segments, extended into the domain), then `pdmesh smooth` of that
mesh, and both measured by `pdmesh quality --json`: smallest angle, node count, mean aspect ratio,
and the largest distance of the smoothed mesh's boundary nodes to the geometry's segments. The
smallest angle is also given "away from sharp input corners": the smallest angle of the triangles
with no vertex at an input vertex whose domain angle is below the target (--target, 38 degrees, the
issue's). A triangle at a corner of angle a < target has an angle <= a there whatever the mesh; every
other triangle, the second row of a narrow inlet included, can reach the target.

Run with the anchors' Python (gmsh 4.15.2, numpy):
  /work/main/tools/.venv-anchors/bin/python tools/eval/smooth_gmsh.py --pdmesh build/pdmesh \\
      --out /tmp/smooth_eval cases/naca0012 cases/corpus/gear ...
Writes OUT/NAME/gmsh.msh, OUT/NAME/smooth/ (pdmesh's outputs), OUT/NAME/*.json, and OUT/table.md."""

import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pdmesh_eval.geometry import domain_corners, loops_of, point_in_polygon, read_segments  # noqa: E402
from pdmesh_eval.meshfiles import read_msh  # noqa: E402


def case_files(case_dir):
    """The geometry files of CASE/case.toml, resolved against it."""
    import tomllib
    with open(os.path.join(case_dir, "case.toml"), "rb") as f:
        case = tomllib.load(f)
    return [os.path.join(case_dir, p) for p in case["geometry"]["files"]]


def gmsh_mesh(files, msh):
    """Meshes the geometry of `files` with Gmsh (Frontal-Delaunay, sizes from the boundary) into msh."""
    import gmsh
    points, segments = read_segments(files)
    loops = loops_of(points, segments)
    polys = [[points[i] for i in loop] for loop in loops]
    depth = [sum(point_in_polygon(*polys[a][0], polys[b]) for b in range(len(loops)) if b != a)
             for a in range(len(loops))]
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 1)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Geometry.Tolerance", 1e-12)
    gmsh.model.add("case")
    geo = gmsh.model.geo
    loop_tags = []
    for loop in loops:
        n = len(loop)
        tags = {}
        for k, i in enumerate(loop):
            a, b, c = points[loop[k - 1]], points[i], points[loop[(k + 1) % n]]
            size = 0.5 * (math.dist(a, b) + math.dist(b, c))
            tags[i] = geo.addPoint(b[0], b[1], 0.0, size)
        lines = [geo.addLine(tags[loop[k]], tags[loop[(k + 1) % n]]) for k in range(n)]
        loop_tags.append(geo.addCurveLoop(lines))
    for a in range(len(loops)):
        if depth[a] % 2:
            continue
        holes = [b for b in range(len(loops)) if depth[b] == depth[a] + 1 and point_in_polygon(*polys[b][0], polys[a])]
        geo.addPlaneSurface([loop_tags[a]] + [loop_tags[b] for b in holes])
    geo.synchronize()
    start = time.perf_counter()
    gmsh.model.mesh.generate(2)
    wall = time.perf_counter() - start
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(msh)
    gmsh.finalize()
    return points, segments, wall


TARGET = 38.0  # issue 40's smallest angle; a domain corner below it bounds the triangles at it


def min_angles(points, triangles, sharp):
    """The smallest angle (degrees) of all triangles, and of those without a vertex at a sharp corner."""
    p = np.array(points)[np.array(triangles)]
    worst = np.full(len(triangles), 180.0)
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        ang = np.degrees(np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), (u * v).sum(1)))
        worst = np.minimum(worst, ang)
    at = np.array([any(tuple(points[i]) in sharp for i in t) for t in triangles])
    away = worst[~at]
    return float(worst.min()), float(away.min()) if away.size else float("nan")


def quality(pdmesh, mesh, out_json):
    subprocess.run([pdmesh, "quality", mesh, "--json", out_json], check=True, stdout=subprocess.DEVNULL)
    with open(out_json) as f:
        return json.load(f)


def boundary_distance(points, segments, mesh_points, triangles):
    """Largest distance of a boundary node (on an edge of one triangle) to the geometry's segments,
    and the same divided by the mean length of the node's boundary edges."""
    count = {}
    for t in triangles:
        for k in range(3):
            e = tuple(sorted((t[k], t[(k + 1) % 3])))
            count[e] = count.get(e, 0) + 1
    length, n = {}, {}
    for (a, b), c in count.items():
        if c == 1:
            d = math.dist(mesh_points[a], mesh_points[b])
            for v in (a, b):
                length[v] = length.get(v, 0.0) + d
                n[v] = n.get(v, 0) + 1
    nodes = sorted(length)
    p = np.array([mesh_points[i] for i in nodes])
    sa = np.array([points[a] for a, _ in segments])
    sb = np.array([points[b] for _, b in segments])
    best = np.full(len(nodes), np.inf)
    for k in range(0, len(segments), 512):
        a, b = sa[k:k + 512], sb[k:k + 512]
        ab = b - a
        t = np.clip(((p[:, None, :] - a[None]) * ab[None]).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300)[None], 0, 1)
        q = a[None] + t[..., None] * ab[None]
        best = np.minimum(best, np.sqrt(((p[:, None, :] - q) ** 2).sum(-1)).min(1))
    rel = best / np.array([length[i] / n[i] for i in nodes])
    return float(best.max()), float(rel.max())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cases", nargs="+", help="case directories (holding case.toml)")
    ap.add_argument("--pdmesh", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--set", action="append", default=[], help="passed to pdmesh smooth")
    ap.add_argument("--target", type=float, default=TARGET,
                    help="degrees: the 'away' minimum leaves out triangles at input corners sharper than this")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for case in args.cases:
        name = os.path.basename(os.path.normpath(case))
        d = os.path.join(args.out, name)
        os.makedirs(d, exist_ok=True)
        msh = os.path.join(d, "gmsh.msh")
        points, segments, gmsh_wall = gmsh_mesh(case_files(case), msh)
        corners = domain_corners(case_files(case))
        sharp = {(x, y) for x, y, a in corners if a < args.target}
        sharpest = min(a for _, _, a in corners)
        g = quality(args.pdmesh, msh, os.path.join(d, "gmsh_quality.json"))
        gp, gt = read_msh(msh)
        g["away"] = min_angles(gp, gt, sharp)[1]
        g["sharpest"] = sharpest
        cmd = [args.pdmesh, "smooth", msh, "--geometry", case, "--out", os.path.join(d, "smooth"), "-q",
               "--formats", "msh,png"] + [x for s in args.set for x in ("--set", s)]
        start = time.perf_counter()
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        wall = time.perf_counter() - start
        if proc.returncode != 0:
            print(f"{name}: pdmesh smooth failed ({proc.returncode}): {proc.stdout}", file=sys.stderr)
            rows.append((name, g, None, None, gmsh_wall, wall))
            continue
        out_msh = os.path.join(d, "smooth", "mesh.msh")
        s = quality(args.pdmesh, out_msh, os.path.join(d, "smooth_quality.json"))
        mp, tris = read_msh(out_msh)
        dist = boundary_distance(points, segments, mp, tris)
        s["away"] = min_angles(mp, tris, sharp)[1]
        rows.append((name, g, s, dist, gmsh_wall, wall))
        print(f"{name}: done in {wall:.1f} s", file=sys.stderr)
    lines = ["| case | Gmsh nodes | smooth nodes | Δ nodes | sharpest corner | Gmsh min ∠ (away) | smooth min ∠ (away) | "
             "Gmsh mean AR | smooth mean AR | boundary max dist (abs / ÷ edge) | smooth wall s |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name, g, s, dist, gw, wall in rows:
        gn, ga, gr = g["points"], g["included_angle"]["min"], g["aspect_ratio"]["average"]
        if s is None:
            lines.append(f"| {name} | {gn} | failed | | {g['sharpest']:.1f} | {ga:.2f} ({g['away']:.2f}) | | {gr:.4f} | | | |")
            continue
        sn, sa, sr = s["points"], s["included_angle"]["min"], s["aspect_ratio"]["average"]
        lines.append(f"| {name} | {gn} | {sn} | {100 * (sn - gn) / gn:+.1f} % | {g['sharpest']:.1f} | "
                     f"{ga:.2f} ({g['away']:.2f}) | {sa:.2f} ({s['away']:.2f}) | {gr:.4f} | "
                     f"{sr:.4f} | {dist[0]:.2e} / {dist[1]:.2e} | {wall:.1f} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(args.out, "table.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
