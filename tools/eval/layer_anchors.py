#!/usr/bin/env python3
"""Issue 38's boundary-layer anchor, judged by one evaluator (pdmesh_eval/layers.py): Gmsh 4.15.2's
BoundaryLayer field on a case's geometry (point sizes from the input segments, a fan at the sharpest
wall corner of each body, Frontal-Delaunay core), beside pdmesh's mesh of the same case.

Setup (once): tools/eval/setup_anchors.sh. Run from the repository root:
    tools/.venv-anchors/bin/python tools/eval/layer_anchors.py CASE --walls upper,lower
        --first-height 1e-5 --growth 1.2 --thickness 0.05 [--quads] [--pdmesh DIR] [--json FILE]
        [--region NAME=X0,Y0,X1,Y1 ...]

CASE is a case file or folder (cases/naca0012); --walls names its wall curves (geometry.curve_names).
--pdmesh DIR judges DIR/mesh.msh, pdmesh's mesh of the same case with the same layer settings, with
the same evaluator. The layer thickness jumps between neighbouring wall nodes are reported for the
layer cells (Gmsh's quads with --quads; pdmesh's physical group boundary_layer), overall and per
--region. Gmsh's failure (it fails on 30P30N) is reported, not raised."""

import argparse
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

from pdmesh_eval import common, geometry  # noqa: E402
from pdmesh_eval import layers as bl  # noqa: E402


def case_curves(case):
    """{name: [(x, y), ...]} of the case's curves, in the order of geometry.curve_names."""
    curves = []
    for f in case["geometry"]["files"]:
        curves += geometry.read_crv(os.path.join(case["dir"], f))
    names = case["geometry"].get("curve_names") or [f"curve{i}" for i in range(len(curves))]
    if len(names) != len(curves):
        common.fail(f"{case['dir']}: {len(names)} curve names for {len(curves)} curves")
    return dict(zip(names, curves))


def wall_segments(curves, walls):
    segs = []
    for name in walls:
        c = curves[name]
        segs += [(c[k], c[k + 1]) for k in range(len(c) - 1)]
    return np.array(segs, dtype=float)


def mesh_arrays(gmsh, layer_group=None):
    """Points (N, 2), triangles and quads (index tuples) of the model's 2-D mesh, and with
    layer_group (a physical group's name) a bool per cell (triangles, then quads): in that group."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    index = {int(t): k for k, t in enumerate(tags)}
    points = np.asarray(coords, dtype=float).reshape(-1, 3)[:, :2]
    layer_entities = set()
    if layer_group is not None:
        for dim, tag in gmsh.model.getPhysicalGroups(2):
            if gmsh.model.getPhysicalName(dim, tag) == layer_group:
                layer_entities.update(int(e) for e in gmsh.model.getEntitiesForPhysicalGroup(dim, tag))
    triangles, quads, tri_layer, quad_layer = [], [], [], []
    for _, entity in gmsh.model.getEntities(2):
        types, _, nodes = gmsh.model.mesh.getElements(2, entity)
        for etype, enodes in zip(types, nodes):
            width = {2: 3, 3: 4}.get(int(etype))
            if width is None:
                continue
            cells = [tuple(index[int(v)] for v in enodes[k:k + width]) for k in range(0, len(enodes), width)]
            (triangles if width == 3 else quads).extend(cells)
            (tri_layer if width == 3 else quad_layer).extend([entity in layer_entities] * len(cells))
    if layer_group is None:
        return points, triangles, quads
    return points, triangles, quads, tri_layer + quad_layer


def sharpest_corners(curves, walls):
    """Per closed wall loop, the vertex where the wall turns most (the trailing edge)."""
    ends = {}
    for name in walls:
        c = curves[name]
        for k in range(len(c)):
            p = c[k]
            nb = ends.setdefault(p, [])
            if k > 0:
                nb.append(c[k - 1])
            if k < len(c) - 1:
                nb.append(c[k + 1])
    angle = {}
    for p, nb in ends.items():
        if len(nb) == 2:
            u = np.subtract(nb[0], p)
            v = np.subtract(nb[1], p)
            angle[p] = math.degrees(math.acos(np.clip(u @ v / (np.linalg.norm(u) * np.linalg.norm(v)), -1, 1)))
    return [p for p, a in angle.items() if a < 90.0]


def run_gmsh(case, curves, walls, args):
    import gmsh

    files = [os.path.join(case["dir"], f) for f in case["geometry"]["files"]]
    points, segments = geometry.read_segments(files)
    loops = geometry.loops_of(points, segments)
    wall_pairs = {frozenset((c[k], c[k + 1])) for name in walls for c in [curves[name]] for k in range(len(c) - 1)}
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("layers")
        geo = gmsh.model.geo
        size = {}
        for a, b in segments:
            length = math.dist(points[a], points[b])
            for v in (a, b):
                size[v] = min(size.get(v, math.inf), length)
        point_tag = {v: geo.addPoint(points[v][0], points[v][1], 0.0, h) for v, h in size.items()}
        loop_tags, wall_lines = [], []
        outer = max(range(len(loops)), key=lambda k: abs(geometry.signed_area([points[v] for v in loops[k]])))
        for k in [outer] + [k for k in range(len(loops)) if k != outer]:
            loop = loops[k]
            lines = []
            for a, b in zip(loop, loop[1:] + loop[:1]):
                t = geo.addLine(point_tag[a], point_tag[b])
                lines.append(t)
                if frozenset((points[a], points[b])) in wall_pairs:
                    wall_lines.append(t)
            loop_tags.append(geo.addCurveLoop(lines))
        geo.addPlaneSurface(loop_tags)
        geo.synchronize()

        f = gmsh.model.mesh.field.add("BoundaryLayer")
        gmsh.model.mesh.field.setNumbers(f, "CurvesList", wall_lines)
        gmsh.model.mesh.field.setNumber(f, "Size", args.first_height)
        gmsh.model.mesh.field.setNumber(f, "Ratio", args.growth)
        gmsh.model.mesh.field.setNumber(f, "Thickness", args.thickness)
        gmsh.model.mesh.field.setNumber(f, "Quads", 1 if args.quads else 0)
        tag_of_point = {points[v]: t for v, t in point_tag.items()}
        fans = [tag_of_point[p] for p in sharpest_corners(curves, walls) if p in tag_of_point]
        if fans:
            gmsh.model.mesh.field.setNumbers(f, "FanPointsList", fans)
        gmsh.model.mesh.field.setAsBoundaryLayer(f)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        start = time.perf_counter()
        gmsh.model.mesh.generate(2)
        seconds = time.perf_counter() - start
        mesh_points, triangles, quads = mesh_arrays(gmsh)
        return {"version": gmsh.__version__, "seconds": seconds, "fans": len(fans),
                "wall_lines": len(wall_lines)}, mesh_points, triangles, quads
    finally:
        gmsh.finalize()


def read_pdmesh(path):
    """Points, triangles, quads and the layer flags (physical group boundary_layer) of a mesh.msh."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(path)
        return mesh_arrays(gmsh, "boundary_layer")
    finally:
        gmsh.finalize()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("case")
    ap.add_argument("--walls", required=True, help="wall curve names, comma-separated")
    ap.add_argument("--first-height", type=float, required=True)
    ap.add_argument("--growth", type=float, required=True)
    ap.add_argument("--thickness", type=float, required=True)
    ap.add_argument("--quads", action="store_true", help="Gmsh's layers as quads (Quads = 1)")
    ap.add_argument("--pdmesh", help="a pdmesh output folder holding mesh.msh of the same case")
    ap.add_argument("--json", help="write the measures here")
    ap.add_argument("--region", action="append", default=[], metavar="NAME=X0,Y0,X1,Y1",
                    help="a box in which the thickness jumps between neighbouring wall nodes are also "
                         "reported (repeatable)")
    args = ap.parse_args()

    case = common.read_case(args.case)
    curves = case_curves(case)
    walls = args.walls.split(",")
    unknown = [w for w in walls if w not in curves]
    if unknown:
        common.fail(f"--walls: no curve named {unknown} (the case has {list(curves)})")
    segments = wall_segments(curves, walls)
    regions = {}
    for r in args.region:
        name, _, box = r.partition("=")
        try:
            x0, y0, x1, y1 = (float(v) for v in box.split(","))
        except ValueError:
            common.fail(f"--region {r!r}: expected NAME=X0,Y0,X1,Y1")
        regions[name] = (x0, y0, x1, y1)
    out = {"case": case.get("name", args.case), "walls": walls, "first_height": args.first_height,
           "growth": args.growth, "thickness": args.thickness}

    try:
        info, points, triangles, quads = run_gmsh(case, curves, walls, args)
        layer = [False] * len(triangles) + [True] * len(quads) if args.quads else None
        m = bl.layer_measures(points, triangles, quads, segments, args.first_height, args.thickness,
                              layer_cells=layer, regions=regions)
        m.update(info)
        out["gmsh"] = m
        print(bl.format_measures(f"Gmsh {info['version']} BoundaryLayer ({info['seconds']:.2f} s)", m))
    except Exception as e:  # Gmsh raises a plain Exception with its last error
        out["gmsh"] = {"failed": str(e)}
        print(f"Gmsh BoundaryLayer: failed: {e}")

    if args.pdmesh:
        path = os.path.join(args.pdmesh, "mesh.msh")
        points, triangles, quads, layer = read_pdmesh(path)
        m = bl.layer_measures(points, triangles, quads, segments, args.first_height, args.thickness,
                              layer_cells=layer, regions=regions)
        out["pdmesh"] = m
        print(bl.format_measures(f"pdmesh ({path})", m))

    if args.json:
        common.write_atomically(args.json, json.dumps(out, indent=1).encode())


if __name__ == "__main__":
    main()
