#!/usr/bin/env python3
"""pdmesh's whole command against Gmsh's meshing on small airfoil cases, back to back (issue 41's
small-case item: "<= 1.0x Gmsh 4.15.2 Frontal-Delaunay's meshing time at pdmesh's field").

Cases: `30p30n` (the 30P30N curves alone, `cases/30p30n/airfoil.crv cases/30p30n/farfield.crv`, the best
preset) and UIUC airfoils of the user corpus in their far field (`clarky`, `e387`, ... :
`cases/user_corpus/NAME`). For each case a first `pdmesh mesh` run (not timed) gives the field: a
background view of mesh.nodes' q on pdmesh's mesh, and a .geo of the input with a free boundary and that
view as Gmsh's only size source, written as tools/eval/corpus_anchors.py writes them. Then --rounds
rounds alternate the two timed commands:
  pdmesh: the whole command `pdmesh mesh ARGS --out DIR -q` (every output and picture), its wall time
          and CPU time (user + sys of the process and its threads, from the kernel);
  Gmsh:   Frontal-Delaunay (Mesh.Algorithm 6, one thread) on the .geo in a child Python process;
          the meshing (generate(2)) alone is timed, wall and process CPU, as the issue asks.
The ratio is pdmesh's whole wall over Gmsh's meshing wall, taken pair by pair (pairing keeps it
meaningful when the machine's speed drifts); the table gives the medians. On a loaded machine the CPU
ratio is the steadier figure.

Run with the anchors' Python (gmsh 4.15.2, shapely: tools/eval/setup_anchors.sh):
  tools/.venv-anchors/bin/python tools/bench/small_vs_gmsh.py --pdmesh build/pdmesh --work W \
      [--rounds 5] [30p30n clarky e387]"""

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "tools", "eval"))

from pdmesh_eval.common import read_case, write_atomically  # noqa: E402
from pdmesh_eval.corpus import Input, read_input, write_free_geo  # noqa: E402
from pdmesh_eval.gmsh import write_pos  # noqa: E402
from pdmesh_eval.meshfiles import read_msh, read_node_file  # noqa: E402

DEFAULT_CASES = ("30p30n", "clarky", "e387")
CORNER_DEG = 30.0  # corpus_anchors.py's default: compound curves break at corners turning by more

# Gmsh's meshing in a child process: wall and process CPU of generate(2) alone.
GMSH_CHILD = """
import sys, time, gmsh
geo, msh = sys.argv[1], sys.argv[2]
gmsh.initialize(["gmsh", "-v", "2"])
gmsh.open(geo)
wall, cpu = time.perf_counter(), time.process_time()
gmsh.model.mesh.generate(2)
wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.write(msh)
print(f"mesh seconds: {wall!r} {cpu!r} {gmsh.__version__}")
gmsh.finalize()
"""


def log(message):
    print(message, file=sys.stderr, flush=True)


def crv_loops(path):
    """The closed loops of a .crv file (blocks of a point count and x y lines): curves are chained end
    to start until each loop closes (cases/30p30n's far field is four open sides)."""
    rows = [ln.split() for ln in open(path).read().splitlines()]
    rows = [r for r in rows if r and not r[0].startswith("#")]
    curves, i = [], 0
    while i < len(rows):
        n = int(rows[i][0])
        curves.append([(float(r[0]), float(r[1])) for r in rows[i + 1:i + 1 + n]])
        i += 1 + n
    loops = []
    while curves:
        loop = curves.pop(0)
        while loop[0] != loop[-1]:
            k = next((k for k, c in enumerate(curves) if c[0] == loop[-1]), None)
            if k is None:
                raise SystemExit(f"{path}: curves that do not close a loop")
            loop += curves.pop(k)[1:]
        loops.append(loop[:-1])
    return loops


def case_input(name):
    """(pdmesh's arguments, the evaluator's Input) of a case name."""
    if name == "30p30n":
        from shapely.geometry import Polygon
        d = os.path.join(REPO, "cases", "30p30n")
        files = [os.path.join(d, "airfoil.crv"), os.path.join(d, "farfield.crv")]
        inp = Input("airfoil")
        inp.domain = Polygon(crv_loops(files[1])[0], crv_loops(files[0]))
        return files, inp
    d = os.path.join(REPO, "cases", "user_corpus", name)
    if not os.path.exists(os.path.join(d, "case.toml")):
        raise SystemExit(f"{name}: neither 30p30n nor a case of cases/user_corpus/")
    return [d], read_input(read_case(d))


def child_times(command):
    """Runs command; returns (wall s, user + sys CPU s of the child and its threads)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(command)} exited with {proc.returncode}:\n{proc.stdout[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, proc.stdout


def prepare(args, name):
    """pdmesh's field as Gmsh's background view, and the .geo that uses it; returns (pdmesh args, geo)."""
    pd_args, inp = case_input(name)
    work = os.path.join(args.work, name)
    first = os.path.join(work, "field")
    os.makedirs(work, exist_ok=True)
    child_times([args.pdmesh, "mesh", *pd_args, "--out", first, "-q"])
    points, triangles = read_msh(os.path.join(first, "mesh.msh"))
    nodes, _ = read_node_file(os.path.join(first, "mesh.nodes"))
    if len(nodes) != len(points) or any((n[0], n[1]) != p for n, p in zip(nodes, points)):
        raise SystemExit(f"{name}: mesh.msh and mesh.nodes list different points")
    q = [n[4] for n in nodes]
    write_atomically(os.path.join(work, "q.pos"), write_pos(points, triangles, q))
    geo = os.path.join(work, "gmsh_fd.geo")
    write_atomically(geo, write_free_geo(inp, CORNER_DEG, background="q.pos", size_max=max(q)))
    return pd_args, geo


def one_case(args, name):
    pd_args, geo = prepare(args, name)
    work = os.path.join(args.work, name)
    pd_out, msh = os.path.join(work, "pdmesh"), os.path.join(work, "gmsh_fd.msh")
    rows = []
    for r in range(args.rounds):
        pd_wall, pd_cpu, _ = child_times([args.pdmesh, "mesh", *pd_args, "--out", pd_out, "-q"])
        _, _, text = child_times([args.python, "-c", GMSH_CHILD, geo, msh])
        line = next(ln for ln in text.splitlines() if ln.startswith("mesh seconds: "))
        g_wall, g_cpu, version = line.split()[2:5]
        rows.append((pd_wall, pd_cpu, float(g_wall), float(g_cpu)))
        log(f"{name} round {r + 1}: pdmesh {pd_wall:.3f} s wall, {pd_cpu:.3f} s CPU; "
            f"Gmsh {version} meshing {float(g_wall):.3f} s wall, {float(g_cpu):.3f} s CPU")
    pd_points, pd_tris = read_msh(os.path.join(pd_out, "mesh.msh"))
    g_points, g_tris = read_msh(msh)
    med = [statistics.median(row[k] for row in rows) for k in range(4)]
    return {"case": name, "pdmesh": (len(pd_points), len(pd_tris)), "gmsh": (len(g_points), len(g_tris)),
            "median": med, "wall_ratio": statistics.median(a / c for a, _, c, _ in rows),
            "cpu_ratio": statistics.median(b / d for _, b, _, d in rows), "version": version,
            "load": os.getloadavg()}


def table(results, rounds):
    out = [f"| case | pdmesh nodes / triangles | Gmsh nodes / triangles | pdmesh whole wall / CPU s | "
           f"Gmsh meshing wall / CPU s | wall ratio | CPU ratio | load after |",
           "|---|---|---|---|---|---:|---:|---|"]
    for r in results:
        m = r["median"]
        out.append(f"| {r['case']} | {r['pdmesh'][0]:,} / {r['pdmesh'][1]:,} | {r['gmsh'][0]:,} / {r['gmsh'][1]:,} | "
                   f"{m[0]:.3f} / {m[1]:.3f} | {m[2]:.3f} / {m[3]:.3f} | {r['wall_ratio']:.2f}x | "
                   f"{r['cpu_ratio']:.2f}x | {r['load'][0]:.1f} |")
    out.append(f"\nMedians of {rounds} alternated rounds; ratios are medians of the pairs' ratios "
               f"(pdmesh's whole command over Gmsh {results[0]['version']}'s meshing).")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cases", nargs="*", default=list(DEFAULT_CASES), help="30p30n or user corpus airfoils")
    ap.add_argument("--pdmesh", required=True, help="the pdmesh binary")
    ap.add_argument("--work", required=True, help="folder for the meshes")
    ap.add_argument("--rounds", type=int, default=5, help="alternated pdmesh / Gmsh rounds per case")
    ap.add_argument("--python", default=sys.executable, help="a Python with gmsh (default: this one)")
    args = ap.parse_args()
    args.pdmesh, args.work = os.path.abspath(args.pdmesh), os.path.abspath(args.work)
    results = [one_case(args, name) for name in args.cases]
    print(table(results, args.rounds))


if __name__ == "__main__":
    main()
