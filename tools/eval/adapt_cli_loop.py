#!/usr/bin/env python3
"""The adaptation loop of examples/adapt_poisson.py driven by the command line: -Δu = f on the unit
square, P1 solution by scikit-fem (the example's `solve` and `Layer`), written as a .vtu, re-meshed by
`pdmesh adapt SQUARE --solution u.vtu --array u --complexity C --hmin 1e-5 --hmax 0.3`, the mesh read
back from the output's mesh.msh. With --mmg the same loop re-meshed by mmg2d instead: the L2-optimal
metric of the P1 solution's Hessian (a least-squares quadratic fit over each vertex's ring of
neighbours, as pdmesh's recover_hessians fits it; D by the P1 rule over the mesh; the same C, hmin,
hmax), written as a Medit .sol at the current mesh's vertices and handed to mmg2d_O3 (-hgrad -1: no
gradation, as pdmesh's default metric_gradation 0). Each loop prints N_v, e_L2 (against the exact
solution), e_L2·N_v, the smallest angle and the smallest mean-ratio quality Q in the exact solution's
L2-optimal metric at the same C (pdmesh_eval/metric.py, for k = 100 only).

Run from the repository root (scikit-fem and mmg2d from tools/eval/setup_anchors.sh):
    tools/.venv-anchors/bin/python tools/eval/adapt_cli_loop.py --pdmesh build/pdmesh [--k 100]
        [--complexity 2000] [--loops 5] [--mmg] [--warm]
"""

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import time
import types

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

from pdmesh_eval import aniso_tools as at  # noqa: E402
from pdmesh_eval import metric as mt  # noqa: E402

SQUARE = os.path.join(ROOT, "tests", "data", "geometry", "unit_square.crv")
HMIN, HMAX = 1e-5, 0.3


def example():
    """examples/adapt_poisson.py's Layer and solve. The example imports the pdmesh package (the Python
    binding) at its top for its own re-meshing, which this loop does through the command instead: a
    stand-in module takes its place, so the example's solver is used as written."""
    stand_in = types.ModuleType("pdmesh")
    stand_in.metric = types.ModuleType("pdmesh.metric")
    stand_in.metric.write_vtu = write_vtu
    sys.modules.setdefault("pdmesh", stand_in)
    sys.modules.setdefault("pdmesh.metric", stand_in.metric)
    spec = importlib.util.spec_from_file_location("adapt_poisson", os.path.join(ROOT, "examples", "adapt_poisson.py"))
    module = importlib.util.module_from_spec(spec)
    sys.modules["adapt_poisson"] = module
    spec.loader.exec_module(module)
    return module


def write_vtu(path, points, triangles, point_data):
    """An ASCII .vtu of a triangle mesh with scalar point arrays."""
    p = np.asarray(points, float)
    t = np.asarray(triangles, np.int64)
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">\n'
                f'<UnstructuredGrid>\n<Piece NumberOfPoints="{len(p)}" NumberOfCells="{len(t)}">\n<Points>\n'
                '<DataArray type="Float64" NumberOfComponents="3" format="ascii">\n')
        f.write(" ".join(f"{float(x)!r} {float(y)!r} 0" for x, y in p) + "\n</DataArray>\n</Points>\n<Cells>\n")
        f.write('<DataArray type="Int64" Name="connectivity" format="ascii">\n'
                + " ".join(map(str, t.ravel())) + "\n</DataArray>\n")
        f.write('<DataArray type="Int64" Name="offsets" format="ascii">\n'
                + " ".join(str(3 * (i + 1)) for i in range(len(t))) + "\n</DataArray>\n")
        f.write('<DataArray type="UInt8" Name="types" format="ascii">\n' + " ".join("5" * len(t)) + "\n</DataArray>\n")
        f.write("</Cells>\n<PointData>\n")
        for name, values in point_data.items():
            f.write(f'<DataArray type="Float64" Name="{name}" format="ascii">\n'
                    + " ".join(repr(float(v)) for v in values) + "\n</DataArray>\n")
        f.write("</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n")


def pdmesh_run(binary, arguments):
    began = time.perf_counter()
    out = subprocess.run([binary, *arguments], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(f"pdmesh {' '.join(arguments)}: exit {out.returncode}\n{out.stderr}")
    return time.perf_counter() - began


def pdmesh_start(binary, directory):
    """The uniform start mesh of size 0.05, as the example's."""
    out = os.path.join(directory, "start")
    pdmesh_run(binary, ["mesh", SQUARE, "--size", "0.05", "--device", "host", "--seed", "1", "--formats", "msh",
                        "--out", out, "-q"])
    return at.read_mesh_file(os.path.join(out, "mesh.msh"))


def pdmesh_adapt(binary, points, triangles, u, complexity, directory, loop, warm):
    sol = os.path.join(directory, f"u{loop}.vtu")
    write_vtu(sol, points, triangles, {"u": u})
    out = os.path.join(directory, f"adapt{loop}")
    arguments = ["adapt", SQUARE, "--solution", sol, "--array", "u", "--complexity", str(complexity), "--hmin",
                 str(HMIN), "--hmax", str(HMAX), "--device", "host", "--seed", "1", "--formats", "msh", "--out", out,
                 "-q"]
    if warm:
        arguments += ["--start", os.path.join(directory, f"adapt{loop - 1}", "mesh.msh")]
    seconds = pdmesh_run(binary, arguments)
    points, triangles = at.read_mesh_file(os.path.join(out, "mesh.msh"))
    return points, triangles, seconds


# ---- mmg2d: the same metric from the P1 solution ----------------------------------------------------

def neighbours(n, triangles):
    ring = [set() for _ in range(n)]
    for a, b, c in triangles:
        ring[a].update((b, c))
        ring[b].update((a, c))
        ring[c].update((a, b))
    return ring


def recovered_hessians(points, triangles, u):
    """(u_xx, u_xy, u_yy) at every vertex: the least-squares quadratic through the values at the vertex
    and its neighbours, the ring grown while it has fewer than 7 points (centred and scaled at the
    vertex), as pdmesh's recover_hessians grows it."""
    ring = neighbours(len(points), triangles)
    h = np.zeros((len(points), 3))
    for i in range(len(points)):
        patch = set(ring[i]) | {i}
        while len(patch) < 7:
            grown = set(patch)
            for j in patch:
                grown |= ring[j]
            if len(grown) == len(patch):
                break
            patch = grown
        idx = np.fromiter(patch, int)
        d = points[idx] - points[i]
        s = np.max(np.abs(d)) or 1.0
        x, y = d[:, 0] / s, d[:, 1] / s
        a = np.column_stack([np.ones_like(x), x, y, x * x, x * y, y * y])
        c = np.linalg.lstsq(a, u[idx], rcond=None)[0]
        h[i] = (2 * c[3] / s ** 2, c[4] / s ** 2, 2 * c[5] / s ** 2)
    return h


def l2_metric_at_vertices(points, triangles, u, complexity):
    h = mt.abs_clipped(recovered_hessians(points, triangles, u), mt.HESSIAN_FLOOR)
    det = np.abs(h[:, 0] * h[:, 2] - h[:, 1] ** 2)
    density = det ** (1.0 / 3.0)
    t = np.asarray(triangles, int)
    a, b, c = points[t[:, 0]], points[t[:, 1]], points[t[:, 2]]
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    scale = complexity / np.sum(area * density[t].mean(axis=1))
    return mt.abs_clipped(h * (scale * det ** (-1.0 / 6.0))[:, None], 1.0 / HMAX ** 2, 1.0 / HMIN ** 2)


def boundary_of(points, triangles):
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    key, count = np.unique(np.sort(e, axis=1), axis=0, return_counts=True)
    corners = [int(np.argmin(np.sum((points - c) ** 2, axis=1))) for c in ((0, 0), (1, 0), (1, 1), (0, 1))]
    # Each boundary edge's reference: the square's side it lies on (bottom, right, top, left), so that
    # mmg2d keeps the sides straight and the corners.
    edges = []
    for a, b in key[count == 1]:
        m = 0.5 * (points[a] + points[b])
        side = int(np.argmin([abs(m[1]), abs(m[0] - 1), abs(m[1] - 1), abs(m[0])])) + 1
        edges.append((int(a), int(b), side))
    return edges, corners


def mmg_adapt(points, triangles, u, complexity):
    metric = l2_metric_at_vertices(points, triangles, u, complexity)
    edges, corners = boundary_of(points, triangles)
    began = time.perf_counter()
    p, t, _ = at.run_mmg2d((points, triangles, edges, corners), lambda _: metric, passes=1,
                           options=["-hgrad", "-1", "-hausd", "1", "-v", "-1"])
    return p, t, time.perf_counter() - began


# ---- the loop ---------------------------------------------------------------------------------------

def min_angle(points, triangles):
    t = np.asarray(triangles, int)
    angles = []
    for k in range(3):
        a, b, c = points[t[:, k]], points[t[:, (k + 1) % 3]], points[t[:, (k + 2) % 3]]
        u, v = b - a, c - a
        cos = np.sum(u * v, axis=1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return float(np.min(angles))


def loop(tool, binary, k, complexity, loops, warm, exact_metric):
    ex = example()
    layer = ex.Layer(k)
    rows = []
    with tempfile.TemporaryDirectory(prefix="pdmesh-adapt-cli-") as directory:
        points, triangles = pdmesh_start(binary, directory)
        seconds = 0.0
        for i in range(loops + 1):
            u, error = ex.solve(points, triangles, layer)
            q = mt.qualities(points, triangles, exact_metric(points)) if exact_metric else None
            row = {"tool": tool, "loop": i, "N_v": len(points), "e_L2": error, "e_L2_Nv": error * len(points),
                   "min_angle": min_angle(points, triangles), "Q_min": float(np.min(q)) if q is not None else None,
                   "Q_mean": float(np.mean(q)) if q is not None else None, "remesh_s": seconds}
            rows.append(row)
            print(f"{tool} loop {i}: N_v {row['N_v']:6d}  e_L2 {error:.3e}  e_L2*N_v {row['e_L2_Nv']:8.3f}  "
                  f"min angle {row['min_angle']:5.2f}" + (f"  Q min {row['Q_min']:.3f} mean {row['Q_mean']:.3f}"
                                                          if q is not None else "") + f"  re-mesh {seconds:.2f} s",
                  flush=True)
            if i == loops:
                break
            if tool == "pdmesh":
                points, triangles, seconds = pdmesh_adapt(binary, points, triangles, u, complexity, directory, i + 1,
                                                          warm and i >= 1)
            else:
                points, triangles, seconds = mmg_adapt(points, triangles, u, complexity)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pdmesh", default=os.path.join(ROOT, "build", "pdmesh"))
    ap.add_argument("--k", type=float, default=100.0)
    ap.add_argument("--complexity", type=float, default=2000.0)
    ap.add_argument("--loops", type=int, default=5)
    ap.add_argument("--mmg", action="store_true", help="also the loop with mmg2d as the re-mesher")
    ap.add_argument("--warm", action="store_true", help="pdmesh adapt --start the previous mesh from loop 2 on")
    ap.add_argument("--json", help="write the rows here")
    args = ap.parse_args(argv)
    exact = None
    if args.k == mt.TANH_A:
        exact = mt.l2_optimal_metric(mt.tanh_hessian, mt.l2_optimal_scale(mt.tanh_hessian, args.complexity), HMIN,
                                     HMAX)
    rows = loop("pdmesh", args.pdmesh, args.k, args.complexity, args.loops, args.warm, exact)
    if args.mmg:
        rows += loop("mmg2d", args.pdmesh, args.k, args.complexity, args.loops, False, exact)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
