#!/usr/bin/env python3
"""Measures boundary.nodes (input | spacing) x geometry.curves (polyline | smooth) on geometry files
run alone (the best preset), so that the choice of defaults rests on numbers: min angle, average
aspect ratio, edge/q standard deviation, triangles under 30 degrees and node count per run.

  tools/studies/boundary_modes.py [--pdmesh build/pdmesh] [--cases 30p30n,naca0012] [--methods structured]
                          [--iterations 2000] [--device host] [--geometry NAME=FILE,FILE ...]

Thesis cases are given by name (their geometry files, without the case file); --geometry adds any
other geometry (e.g. the evaluation corpus). Prints one markdown table; Python standard library only.
"""

import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COMBOS = [("input", "polyline"), ("input", "smooth"), ("spacing", "polyline"), ("spacing", "smooth")]


def thesis_geometry(name):
    files = sorted(glob.glob(os.path.join(REPO, "cases", name, "*.crv")))
    # The case files list the geometry files in this order (airfoil/rods before the outer boundary).
    order = {"farfield.crv": 1, "box.crv": 1}
    return sorted(files, key=lambda f: order.get(os.path.basename(f), 0))


def run(pdmesh, files, method, nodes, curves, iterations, device, out):
    cmd = [pdmesh, "mesh", *files, "--out", out, "--method", method, "--iterations", str(iterations),
           "--device", device, "--formats", "msh", "--check", "-q",
           "--set", f"boundary.nodes={nodes}", "--set", f"geometry.curves={curves}"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        return {"error": (p.stderr.strip().splitlines() or ["exit %d" % p.returncode])[-1]}
    with open(os.path.join(out, "quality.json")) as f:
        return json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pdmesh", default=os.path.join(REPO, "build", "pdmesh"))
    ap.add_argument("--cases", default="circle_circle,naca0012,30p30n,rods_coarse,rods_fine")
    ap.add_argument("--geometry", action="append", default=[], help="NAME=FILE[,FILE...]")
    ap.add_argument("--methods", default="structured,random")
    ap.add_argument("--iterations", type=int, default=2000)
    ap.add_argument("--device", default="host")
    args = ap.parse_args()
    geometries = [(c, thesis_geometry(c)) for c in args.cases.split(",") if c]
    for g in args.geometry:
        name, _, files = g.partition("=")
        geometries.append((name, files.split(",")))
    print("| geometry | method | boundary.nodes | geometry.curves | nodes | min angle | AR avg | edge/q std "
          "| < 30 deg |")
    print("|---|---|---|---|---:|---:|---:|---:|---:|")
    for name, files in geometries:
        for method in args.methods.split(","):
            for nodes, curves in COMBOS:
                with tempfile.TemporaryDirectory(prefix="pdmesh_modes_") as out:
                    q = run(args.pdmesh, files, method, nodes, curves, args.iterations, args.device, out)
                if "error" in q:
                    print(f"| {name} | {method} | {nodes} | {curves} | failed: {q['error']} | | | | |")
                else:
                    print(f"| {name} | {method} | {nodes} | {curves} | {q['points']} | "
                          f"{q['included_angle']['min']:.2f} | {q['aspect_ratio']['average']:.4f} | "
                          f"{q['spacing_conformance']['stddev']:.4f} | {q['small_angle']['triangles']} |")
                sys.stdout.flush()


if __name__ == "__main__":
    main()
