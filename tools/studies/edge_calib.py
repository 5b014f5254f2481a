#!/usr/bin/env python3
"""Edge length against the field: runs pdmesh on the geometries behind spacing.relax_scale and prints
one row per case (nodes, mean and std of edge/q, min angle, mean aspect ratio, iterations, CPU s).

  tools/studies/edge_calib.py BIN OUTDIR [--set KEY=VALUE ...] [--factor F] [--cases NAME,...] [-j 2]

--factor F multiplies the reported edge/q (mean and std): with `--set spacing.scale=F` on a binary
without spacing.relax_scale it gives edge/q against the unscaled field, because the quality there is
measured against F x q. Writes OUTDIR/NAME/ and OUTDIR/table.md.
"""
import argparse
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
C = os.path.join(ROOT, "cases")
U = os.path.join(C, "user_corpus")

# Geometries given alone (the thesis cases' curves), the corpus, and UIUC airfoils of the user corpus.
CASES = {
    "30p30n_curves": [f"{C}/30p30n/airfoil.crv", f"{C}/30p30n/farfield.crv"],
    "naca0012_curves": [f"{C}/naca0012/airfoil.crv", f"{C}/naca0012/farfield.crv"],
    "circle_circle_curves": [f"{C}/circle_circle/circles.crv"],
    "rods_coarse_curves": [f"{C}/rods_coarse/box.crv", f"{C}/rods_coarse/rods.crv"],
    "rods_fine_curves": [f"{C}/rods_fine/box.crv", f"{C}/rods_fine/rods.crv"],
    "square200_curves": [f"{C}/square200/square.crv"],
    "shock_curves": [f"{C}/shock/square.crv"],
}
for name in ["bracket", "coastline", "flap_airfoil", "gear", "heatsink_channel", "plate"]:
    CASES[f"corpus_{name}"] = [f"{C}/corpus/{name}/case.toml"]
for name in ["clarky", "e387", "s1223", "fx63137", "sc20714", "naca0012"]:
    CASES[f"uiuc_{name}"] = [f"{U}/{name}/case.toml"]


def run(binary, out, name, files, sets):
    d = os.path.join(out, name)
    cmd = [binary, "mesh", *files, "--out", d, "--formats", "msh", "-q"]
    for s in sets:
        cmd += ["--set", s]
    # wait4 gives this child's own CPU time, also when -j runs several at once.
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    p.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        return name, None, err.strip()[-400:]
    q = json.load(open(os.path.join(d, "quality.json")))
    iterations = 0
    with open(os.path.join(d, "history.csv")) as f:
        iterations = sum(1 for _ in f) - 1
    return name, q, (iterations, usage.ru_utime)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary")
    ap.add_argument("out")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--factor", type=float, default=1.0)
    ap.add_argument("--cases", default="")
    ap.add_argument("-j", type=int, default=2)
    a = ap.parse_args()
    names = a.cases.split(",") if a.cases else list(CASES)
    os.makedirs(a.out, exist_ok=True)
    with ThreadPoolExecutor(a.j) as pool:
        results = list(pool.map(lambda n: run(a.binary, a.out, n, CASES[n], a.set), names))
    lines = ["| case | nodes | triangles | edge/q mean | edge/q std | min angle | AR avg | iterations | user CPU s |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name, q, extra in results:
        if q is None:
            lines.append(f"| {name} | failed: {extra} | | | | | | | |")
            continue
        s = q["spacing_conformance"]
        lines.append(f"| {name} | {q['points']} | {q['triangles']} | {a.factor * s['mean']:.4f} | "
                     f"{a.factor * s['stddev']:.4f} | {q['included_angle']['min']:.2f} | "
                     f"{q['aspect_ratio']['average']:.4f} | {extra[0]} | {extra[1]:.2f} |")
    text = "\n".join(lines) + "\n"
    open(os.path.join(a.out, "table.md"), "w").write(text)
    sys.stdout.write(text)


if __name__ == "__main__":
    main()
