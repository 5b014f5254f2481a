#!/usr/bin/env python3
"""pdmesh beside Gmsh 4.15.2 on the user corpus (cases/user_corpus/, tools/cases/make_user_corpus.py).

For each input: `pdmesh mesh CASE --device host --formats msh` with the case's defaults; then Gmsh
Frontal-Delaunay (Mesh.Algorithm 6, one thread) on the same input with a free boundary (one compound
curve per run of input points between corners turning by more than --corner-deg, so Gmsh places its
own boundary nodes; constraints as embedded curves, isolated vertices as embedded points) and pdmesh's
spacing field as its only size source (a background view of mesh.nodes' q on pdmesh's mesh, as
tools/eval/compare does); both meshes measured by one evaluator (pdmesh_eval.corpus.measures, in the
projected plane for lon/lat data). Prints a Markdown table: nodes, min angle, share of triangles
below 30 deg, mean aspect ratio, constraint segments and points present, wall time, the sharpest
corner of the domain pdmesh meshed (its mesh's boundary corners, after healing; the input's where
pdmesh made no mesh), and a check of pdmesh's mesh against issue 39's targets (min angle >= 30 deg on
clean data, >= 20 deg on GIS data; every constraint present; a miss names that corner when it is
sharper than the target). An input pdmesh refuses gets a row with pdmesh's message (the reader or
option it lacks) and no Gmsh run unless --gmsh-own-sizes.

    tools/eval/setup_anchors.sh
    tools/.venv-anchors/bin/python tools/eval/corpus_anchors.py [NAME...] [--set KEY=VALUE]...
        [--pdmesh build/pdmesh] [--out out/corpus_anchors] [--markdown FILE] [--reuse]

Evaluation only: needs numpy, shapely and gmsh (the anchors' virtual environment)."""

import argparse
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from pdmesh_eval.common import fail, fmt, git_description, log, machine_description, read_case, write_atomically  # noqa: E402
from pdmesh_eval.corpus import (Unsupported, constraint_check, lonlat_to_xy, measures, read_input,  # noqa: E402
                                run_gmsh_child, sharpest_corner, write_free_geo)
from pdmesh_eval.gmsh import write_pos  # noqa: E402
from pdmesh_eval.meshfiles import read_msh, read_node_file  # noqa: E402
from pdmesh_eval.runs import RunError, run_mesh  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CORPUS = os.path.join(REPO, "cases", "user_corpus")
TARGET_DEG = {"airfoil": 30.0, "pslg": 30.0, "gis": 20.0}


def corpus_names(corpus):
    return sorted(d for d in os.listdir(corpus) if os.path.exists(os.path.join(corpus, d, "case.toml")))


def kind_of(case):
    files = case.get("geometry", {}).get("files", [""])
    ext = os.path.splitext(files[0])[1].lower()
    if "farfield" in case:
        return "airfoil"
    return {".dat": "airfoil", ".poly": "pslg"}.get(ext, "gis")


def pdmesh_error(message):
    """The first `pdmesh: error:` line of a failed run's messages, or its last line."""
    m = re.search(r"^pdmesh: error: (.*)$", message, re.M)
    return m.group(1) if m else message.strip().splitlines()[-1]


def project_points(points, inp):
    """pdmesh writes lon/lat data's meshes back in lon/lat: map them into the plane the evaluator and
    Gmsh use (the same projection as pdmesh's)."""
    if inp.projection is None:
        return points
    f = lonlat_to_xy(inp.projection)
    return [f(x, y) for x, y in points]


def one_input(args, name):
    case_dir = os.path.join(args.corpus, name)
    case = read_case(case_dir)
    work = os.path.join(args.out, name)
    os.makedirs(work, exist_ok=True)
    row = {"input": name, "kind": kind_of(case), "pdmesh": None, "gmsh": None, "notes": [], "sharpest_corner": None}
    try:
        inp = read_input(case)
        row["sharpest_corner"] = sharpest_corner(inp)
    except Unsupported as e:
        inp = None
        row["notes"].append(f"evaluator: {e}")
    # pdmesh with the case's defaults
    pd_out = os.path.join(work, "pdmesh")
    sets = [a for s in args.set for a in ("--set", s)]
    try:
        record = run_mesh(args.pdmesh, [case_dir, "--device", "host", "--formats", "msh", *sets], pd_out, name,
                          reuse=args.reuse)
    except RunError as e:
        record = None
        row["notes"].append(f"pdmesh: {pdmesh_error(str(e))}")
    background = size_max = None
    if record is not None:
        points, triangles = read_msh(os.path.join(pd_out, "mesh.msh"))
        row["pdmesh"] = {"wall_seconds": record["wall_seconds"]}
        if inp is not None:
            xy = project_points(points, inp)
            row["pdmesh"].update(measures(xy, triangles))
            row["sharpest_corner"] = sharpest_corner(inp, mesh=(xy, triangles))
            row["pdmesh"]["constraints"] = constraint_check(inp, xy, triangles)
            nodes, _ = read_node_file(os.path.join(pd_out, "mesh.nodes"))
            if len(nodes) == len(points) and all((n[0], n[1]) == p for n, p in zip(nodes, points)):
                q = [n[4] for n in nodes]
                write_atomically(os.path.join(work, "q.pos"), write_pos(xy, triangles, q))
                background, size_max = "q.pos", max(q)
            else:
                row["notes"].append("mesh.msh and mesh.nodes list different points: no background field")
        else:
            row["pdmesh"].update(measures(points, triangles))
    # Gmsh on the input with a free boundary
    if inp is not None and (background is not None or args.gmsh_own_sizes):
        geo = os.path.join(work, "gmsh_fd.geo")
        write_atomically(geo, write_free_geo(inp, args.corner_deg, background=background, size_max=size_max))
        msh = os.path.join(work, "gmsh_fd.msh")
        if os.path.exists(msh):
            os.remove(msh)
        log(f"{name}: Gmsh {geo}")
        seconds, message = run_gmsh_child(args.python, geo, msh, args.gmsh_timeout)
        if seconds is None:
            row["notes"].append(f"Gmsh failed: {message.strip().splitlines()[-1] if message.strip() else '?'}")
        else:
            points, triangles = read_msh(msh)
            row["gmsh"] = {"wall_seconds": seconds, **measures(points, triangles),
                           "constraints": constraint_check(inp, points, triangles),
                           "size": "pdmesh's field" if background else "Gmsh's own (from the boundary)"}
    row["check"] = check(row, inp)
    return row


def check(row, inp):
    pd = row["pdmesh"]
    if pd is None:
        return "not meshed"
    if pd.get("min_angle") is None:
        return "not measured"
    problems = []
    target = TARGET_DEG[row["kind"]]
    if pd["min_angle"] < target:
        corner = row.get("sharpest_corner")
        kept = f" (domain corner {corner:.2f}°)" if corner is not None and corner < target else ""
        problems.append(f"min angle < {target:.0f}°{kept}")
    present, missing = pd.get("constraints", (0, 0))
    if missing:
        problems.append(f"{missing} constraints missing")
    return "ok" if not problems else "; ".join(problems)


def constraints_cell(m):
    if m is None or "constraints" not in m:
        return "—"
    present, missing = m["constraints"]
    if present + missing == 0:
        return "none"
    return f"all {present}" if not missing else f"{missing} of {present + missing} missing"


def table(rows):
    def pair(key, decimals, scale=1.0):
        def cell(m):
            v = None if m is None else m.get(key)
            return fmt(None if v is None else v * scale, decimals)
        return lambda r: f"{cell(r['pdmesh'])} / {cell(r['gmsh'])}"

    cols = [("input", lambda r: r["input"]), ("kind", lambda r: r["kind"]),
            ("nodes", pair("nodes", 0)), ("min angle °", pair("min_angle", 2)),
            ("< 30° %", pair("share_below_30", 2, 100.0)), ("mean AR", pair("mean_aspect_ratio", 3)),
            ("constraints", lambda r: f"{constraints_cell(r['pdmesh'])} / {constraints_cell(r['gmsh'])}"),
            ("wall s", pair("wall_seconds", 2)),
            ("sharpest corner °", lambda r: fmt(r.get("sharpest_corner"), 2)),
            ("target", lambda r: f"≥ {TARGET_DEG[r['kind']]:.0f}°"), ("check (pdmesh)", lambda r: r["check"])]
    out = ["| " + " | ".join(c for c, _ in cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        out.append("| " + " | ".join(f(r) for _, f in cols) + " |")
    notes = [f"- {r['input']}: {n.replace(REPO + os.sep, '')}" for r in rows for n in r["notes"]]
    return "\n".join(out) + "\n" + ("\n" + "\n".join(notes) + "\n" if notes else "")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("names", nargs="*", help="inputs (directories under cases/user_corpus/); default all")
    ap.add_argument("--pdmesh", default=os.path.join(REPO, "build", "pdmesh"))
    ap.add_argument("--python", default=sys.executable, help="a Python with the gmsh module (default: this one)")
    ap.add_argument("--out", default=os.path.join(REPO, "out", "corpus_anchors"))
    ap.add_argument("--corpus", default=CORPUS, help="the directory of input directories (default: %(default)s)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="passed to pdmesh mesh")
    ap.add_argument("--corner-deg", type=float, default=30.0,
                    help="a boundary vertex where the input turns by more than this ends Gmsh's curve (default 30)")
    ap.add_argument("--gmsh-timeout", type=float, default=600.0)
    ap.add_argument("--gmsh-own-sizes", action="store_true",
                    help="mesh an input pdmesh refuses with Gmsh's sizes from the boundary (no comparison)")
    ap.add_argument("--markdown", help="also write the table (with the commands and machine) to this file")
    ap.add_argument("--reuse", action="store_true", help="reuse a pdmesh run made by the same command")
    args = ap.parse_args()
    args.corpus = os.path.abspath(args.corpus)
    if not os.access(args.pdmesh, os.X_OK):
        fail(f"{args.pdmesh}: no pdmesh executable (build it, or pass --pdmesh)")
    names = args.names or corpus_names(args.corpus)
    for n in names:
        if not os.path.exists(os.path.join(args.corpus, n, "case.toml")):
            fail(f"'{n}' is not an input under {args.corpus} ({', '.join(corpus_names(args.corpus))})")
    args.pdmesh, args.out = os.path.abspath(args.pdmesh), os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)
    rows = [one_input(args, n) for n in names]
    text = table(rows)
    print(text, end="")
    write_atomically(os.path.join(args.out, "results.json"), json.dumps(rows, indent=1))
    if args.markdown:
        head = (f"Cells are pdmesh / Gmsh 4.15.2 Frontal-Delaunay. Commit {git_description(REPO, args.out)}; "
                f"{machine_description()}. Command: `{' '.join(sys.argv)}`. Wall s: pdmesh's whole run "
                "(reading to writing), Gmsh's meshing (generate) alone.\n\n")
        write_atomically(args.markdown, head + text)


if __name__ == "__main__":
    main()
