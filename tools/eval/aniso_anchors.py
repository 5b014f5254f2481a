#!/usr/bin/env python3
"""Issue 37's anisotropic anchors, judged by one evaluator (pdmesh_eval/metric.py, UGAWG measures):
mmg2d, BAMG (FreeFem++) and Gmsh 4.15.2 algorithm 7 on the analytic metrics linear, polar-1 and
polar-2, and mmg2d's Hessian adaptation to the tanh layer at C = 4000 and 16000. Prints one table per
case and writes JSON; --pdmesh DIR judges pdmesh's meshes of the same cases beside them.

Setup (once): tools/eval/setup_anchors.sh. Run from the repository root:
    tools/.venv-anchors/bin/python tools/eval/aniso_anchors.py [--json out/aniso_anchors.json]
        [--cases linear,polar-1,polar-2,tanh] [--tools mmg2d,bamg,gmsh] [--pdmesh DIR]
        [--wall-segments 160] [--mmg-hausd 0.001]

--pdmesh DIR reads DIR/<case>.msh (or .vtu, .mesh) for <case> in linear, polar-1, polar-2,
tanh-4000, tanh-16000 (whichever exist) and, if present, the run's wall seconds from DIR/<case>.time."""

import argparse
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

from pdmesh_eval import aniso_tools as at  # noqa: E402
from pdmesh_eval import metric as mt  # noqa: E402

TANH_COMPLEXITIES = (4000, 16000)
TANH_PASSES = 6
TANH_START = 128                 # the first mesh: a 128 x 128 grid of the unit square
H_MIN, H_MAX = 1e-5, 0.3


def pdmesh_mesh(directory, name):
    for ext in (".msh", ".vtu", ".mesh"):
        path = os.path.join(directory, name + ext)
        if os.path.exists(path):
            points, triangles = at.read_mesh_file(path)
            wall = None
            if os.path.exists(os.path.join(directory, name + ".time")):
                with open(os.path.join(directory, name + ".time")) as f:
                    wall = float(f.read().split()[0])
            return points, triangles, wall, path
    return None


def metric_rows(case, tools, pdmesh_dir, wall_segments=160, mmg_options=at.MMG_OPTIONS):
    metric = at.METRICS[case]
    c = at.complexity(case)
    rows = []
    for tool in tools:
        print(f"  {case}: {tool} ...", file=sys.stderr, flush=True)
        try:
            if tool == "mmg2d":
                p, t, wall = at.run_mmg2d(at.initial_mesh(at.DOMAIN[case], wall_segments), metric,
                                          options=mmg_options)
            elif tool == "bamg":
                p, t, wall = at.run_bamg(case)
            else:
                p, t, wall = at.run_gmsh(case)
        except Exception as e:  # a failing anchor is a row, not the end of the run
            rows.append({"tool": tool, "error": str(e).splitlines()[0][:200]})
            continue
        rows.append({"tool": tool, "wall_s": wall, **mt.metric_report(p, t, metric, c)})
    if pdmesh_dir:
        found = pdmesh_mesh(pdmesh_dir, case)
        if found:
            p, t, wall, path = found
            rows.append({"tool": "pdmesh", "file": path, "wall_s": wall, **mt.metric_report(p, t, metric, c)})
    return {"case": case, "complexity": c, "ideal_triangles": mt.ideal_triangles(c), "rows": rows}


def tanh_rows(pdmesh_dir):
    rows = []
    for n in (128, 256):
        rows.append({"tool": f"uniform {n}x{n}", "C": None, **at.uniform_reference(n)})
    for c in TANH_COMPLEXITIES:
        print(f"  tanh: mmg2d C = {c} ...", file=sys.stderr, flush=True)
        scale = mt.l2_optimal_scale(mt.tanh_hessian, c)
        metric = mt.l2_optimal_metric(mt.tanh_hessian, scale, H_MIN, H_MAX)
        try:
            p, t, wall = at.run_mmg2d(at.grid_mesh(TANH_START), metric, passes=TANH_PASSES)
        except Exception as e:
            rows.append({"tool": "mmg2d", "C": c, "error": str(e).splitlines()[0][:200]})
            continue
        # The metric's own complexity after the size clipping, by quadrature on the square.
        c_clipped = mt.complexity_square(metric, panels=512)
        report = mt.metric_report(p, t, metric, c_clipped)
        rows.append({"tool": "mmg2d", "C": c, "C_clipped": c_clipped, "D": scale, "wall_s": wall,
                     **at.tanh_error(p, t),
                     "window_percent": report["window_percent"], "Q_min": report["Q_min"],
                     "N_over_ideal": report["N_over_ideal"]})
        if pdmesh_dir:
            found = pdmesh_mesh(pdmesh_dir, f"tanh-{c}")
            if found:
                p, t, wall, path = found
                report = mt.metric_report(p, t, metric, c_clipped)
                rows.append({"tool": "pdmesh", "C": c, "file": path, "wall_s": wall, **at.tanh_error(p, t),
                             "window_percent": report["window_percent"], "Q_min": report["Q_min"],
                             "N_over_ideal": report["N_over_ideal"]})
    return {"case": "tanh", "rows": rows}


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def print_metric_table(block):
    print(f"\n{block['case']}  (C = {block['complexity']:.1f}, ideal N_tri = 4C/sqrt3 = "
          f"{block['ideal_triangles']:.0f})")
    print(f"| {'tool':<7} | N_tri | N/ideal | % L in window | L min | L max | Q min | Q mean | % Q<0.3 | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in block["rows"]:
        if "error" in r:
            print(f"| {r['tool']:<7} | failed: {r['error']} |")
            continue
        print(f"| {r['tool']:<7} | {r['triangles']} | {r['N_over_ideal']:.3f} | {r['window_percent']:.1f} | "
              f"{r['L_min']:.3f} | {r['L_max']:.2f} | {r['Q_min']:.3f} | {r['Q_mean']:.3f} | "
              f"{r['Q_below_0.3_percent']:.1f} | {fmt(r['wall_s'], '.2f')} |")


def print_tanh_table(block):
    print("\ntanh layer  (u = tanh(100(y - 0.5 - 0.25 sin 2πx)), L2-optimal Hessian metric; "
          "N/ideal against the clipped metric's C)")
    print("| tool | C | N_v | e_L2 | e_max | e_L2·N_v | % L in window | Q min | N/ideal | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in block["rows"]:
        if "error" in r:
            print(f"| {r['tool']} | {r['C']} | failed: {r['error']} |")
            continue
        print(f"| {r['tool']} | {fmt(r['C'], 'd')} | {r['vertices']} | {r['e_L2']:.3g} | {r['e_max']:.3g} | "
              f"{r['e_L2_times_Nv']:.3g} | {fmt(r.get('window_percent'), '.1f')} | {fmt(r.get('Q_min'), '.3f')} | "
              f"{fmt(r.get('N_over_ideal'), '.3f')} | {fmt(r.get('wall_s'), '.2f')} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", default="linear,polar-1,polar-2,tanh")
    ap.add_argument("--tools", default="mmg2d,bamg,gmsh")
    ap.add_argument("--pdmesh", metavar="DIR", help="judge DIR/<case>.msh|.vtu|.mesh beside the anchors")
    ap.add_argument("--json", default="out/aniso_anchors.json", help="'' writes none")
    ap.add_argument("--wall-segments", type=int, default=160,
                    help="wall segments of mmg2d's first mesh on the polar cases (even)")
    ap.add_argument("--mmg-hausd", default="0.001", help="mmg2d's -hausd")
    args = ap.parse_args(argv)
    cases = [c for c in args.cases.split(",") if c]
    tools = [t for t in args.tools.split(",") if t]
    for c in cases:
        if c not in at.CASES + ("tanh",):
            ap.error(f"--cases: unknown case '{c}' (linear, polar-1, polar-2, tanh)")
    for t in tools:
        if t not in ("mmg2d", "bamg", "gmsh"):
            ap.error(f"--tools: unknown tool '{t}' (mmg2d, bamg, gmsh)")
    if args.wall_segments < 2 or args.wall_segments % 2:
        ap.error(f"--wall-segments: {args.wall_segments} is not an even number >= 2")
    mmg_options = ["-hgrad", "-1", "-hausd", args.mmg_hausd, "-v", "-1"]
    if args.pdmesh and not os.path.isdir(args.pdmesh):
        ap.error(f"--pdmesh: '{args.pdmesh}' is not a directory")
    versions = {"mmg2d": at.version([at.mmg2d_binary() or "mmg2d_O3", "-val"]).strip(" -"),
                "freefem++ (Debian)": at.version(["dpkg-query", "-W", "-f", "${Version}", "freefem++"])}
    try:
        import gmsh
        versions["gmsh"] = gmsh.__version__
    except ImportError:
        versions["gmsh"] = "not installed"
    result = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "command": " ".join(sys.argv),
              "versions": versions, "wall_segments": args.wall_segments, "mmg_options": mmg_options,
              "cases": []}
    for case in cases:
        try:
            block = tanh_rows(args.pdmesh) if case == "tanh" else metric_rows(case, tools, args.pdmesh,
                                                                                   args.wall_segments, mmg_options)
        except ValueError as e:           # an unreadable --pdmesh file
            print(f"aniso_anchors: {e}", file=sys.stderr)
            return 2
        result["cases"].append(block)
        (print_tanh_table if case == "tanh" else print_metric_table)(block)
        sys.stdout.flush()
    if args.json:
        os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
        tmp = args.json + ".tmp"
        with open(tmp, "w") as f:
            json.dump(result, f, indent=1, default=lambda v: float(v) if isinstance(v, np.floating) else str(v))
        os.replace(tmp, args.json)
        print(f"\nwrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
