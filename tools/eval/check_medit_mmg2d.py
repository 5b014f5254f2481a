#!/usr/bin/env python3
"""Checks pdmesh's Medit .mesh against mmg2d, the tool its users hand it to:

    tools/.venv-anchors/bin/python tools/eval/check_medit_mmg2d.py PDMESH DIR

DIR holds `pdmesh mesh ... --formats mesh`'s mesh.mesh. meshio reads it to the counts pdmesh's
quality.json in DIR gives. mmg2d (the mmg2d_O3 of the interpreter's mmgpy) remeshes it with -hmax
half the mean boundary edge length; its output keeps pdmesh's Corners (the fixed nodes) and every
reference pdmesh wrote on its Edges (the curves). PDMESH's `pdmesh quality` reads mmg2d's output to
the point and triangle counts and the minimum angle meshio's reading of the same file gives. Exit
status 0 when every check passed, 1 otherwise, 77 when meshio, numpy or mmg2d is missing
(ctest's skip)."""
import json
import os
import subprocess
import sys


def check(ok, what, failures):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    if not ok:
        failures.append(what)


def corners(path):
    """The 0-based vertex numbers of a .mesh file's Corners section (meshio reads it over)."""
    tokens = [t for line in open(path, encoding="utf-8") if not line.lstrip().startswith("#") for t in line.split()]
    if "Corners" not in tokens:
        return []
    k = tokens.index("Corners")
    return [int(t) - 1 for t in tokens[k + 2:k + 2 + int(tokens[k + 1])]]


def min_angle(np, points, triangles):
    """The smallest interior angle in degrees over the triangles."""
    p = points[:, :2][triangles]
    worst = 180.0
    for k in range(3):
        a, b, c = p[:, k], p[:, (k + 1) % 3], p[:, (k + 2) % 3]
        u, v = b - a, c - a
        cos = (u * v).sum(axis=1) / np.sqrt((u * u).sum(axis=1) * (v * v).sum(axis=1))
        worst = min(worst, float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))).min()))
    return worst


def main():
    pdmesh, directory = sys.argv[1], sys.argv[2]
    try:
        import meshio
        import numpy as np
    except ImportError as e:
        print(f"{e}: skipped")
        return 77
    mmg2d = os.path.join(os.path.dirname(sys.executable), "mmg2d_O3")
    if not os.path.exists(mmg2d):
        print(f"{mmg2d}: missing (mmgpy is not installed), skipped")
        return 77
    failures = []
    ours = os.path.join(directory, "mesh.mesh")
    with open(os.path.join(directory, "quality.json"), encoding="utf-8") as f:
        run = json.load(f)
    m = meshio.read(ours)
    triangles = sum(len(c.data) for c in m.cells if c.type == "triangle")
    lines = np.concatenate([c.data for c in m.cells if c.type == "line"])
    check(len(m.points) == run["points"] and triangles == run["triangles"],
          f"meshio {meshio.__version__}: {ours}: {len(m.points)} points, {triangles} triangles "
          f"(the run's quality.json: {run['points']}, {run['triangles']})", failures)
    edge_refs = np.concatenate([m.cell_data["medit:ref"][k] for k, c in enumerate(m.cells) if c.type == "line"])
    ours_refs = sorted(set(int(r) for r in edge_refs))
    length = float(np.linalg.norm(m.points[lines[:, 0], :2] - m.points[lines[:, 1], :2], axis=1).mean())

    adapted = os.path.join(directory, "mmg2d.mesh")
    r = subprocess.run([mmg2d, "-in", ours, "-out", adapted, "-hmax", f"{0.5 * length:.6g}", "-v", "0"],
                       capture_output=True, text=True)
    check(r.returncode == 0 and os.path.exists(adapted), f"mmg2d -hmax {0.5 * length:.4g}: exit {r.returncode}",
          failures)
    if failures:
        print(r.stdout + r.stderr)
        return 1
    a = meshio.read(adapted)
    tri = np.concatenate([c.data for c in a.cells if c.type == "triangle"])
    refs = sorted(set(int(x) for k, c in enumerate(a.cells) if c.type == "line" for x in a.cell_data["medit:ref"][k]))
    check(refs == ours_refs, f"mmg2d kept the edge references {ours_refs} (has {refs})", failures)
    check(len(tri) > triangles, f"mmg2d refined {triangles} triangles to {len(tri)}", failures)
    kept = {tuple(a.points[i, :2]) for i in corners(adapted)}
    fixed = [tuple(m.points[i, :2]) for i in corners(ours)]
    check(len(fixed) > 0 and all(p in kept for p in fixed),
          f"mmg2d kept pdmesh's {len(fixed)} Corners among its {len(kept)}", failures)
    quality = os.path.join(directory, "mmg2d_quality.json")
    q = subprocess.run([pdmesh, "quality", adapted, "--json", quality], capture_output=True, text=True)
    check(q.returncode == 0, f"pdmesh quality {adapted}: exit {q.returncode}", failures)
    if q.returncode != 0:
        print(q.stdout + q.stderr)
        return 1
    with open(quality, encoding="utf-8") as f:
        got = json.load(f)
    want_angle = min_angle(np, a.points, tri)
    check(got["points"] == len(a.points) and got["triangles"] == len(tri),
          f"pdmesh quality: {got['points']} points, {got['triangles']} triangles (meshio: {len(a.points)}, {len(tri)})",
          failures)
    check(abs(got["included_angle"]["min"] - want_angle) < 1e-6,
          f"pdmesh quality: min angle {got['included_angle']['min']:.6f} (meshio's points: {want_angle:.6f})", failures)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
