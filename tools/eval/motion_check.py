#!/usr/bin/env python3
"""Checks a `pdmesh mesh` run with [motion] (docs/motion.md): motion.json's figures per step and over the
run, and that a third-party reader opens every step of motion.pvd (pyvista's PVD reader over VTK,
and meshio reading each .vtu the .pvd lists), with node_id on every step.

    tools/.venv-anchors/bin/python tools/eval/motion_check.py DIR [--cold-wall SECONDS]
"""
import argparse
import json
import math
import os
import sys
import xml.etree.ElementTree as ET


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--cold-wall", type=float, help="wall time of a cold `pdmesh mesh` of the same geometry")
    a = ap.parse_args()
    rows = json.load(open(os.path.join(a.dir, "motion.json")))
    warm = rows[1:]
    print("| step | t | nodes | ids kept | min angle | inverted | sub-steps | wall s |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['step']} | {r['t']:.3f} | {r['nodes']} | {100 * r['ids_kept']:.2f} % | {r['min_angle']:.2f} | "
              f"{r['inverted']} | {r['carry_substeps']} | {r['wall_s']:.3f} |")
    mean = lambda k: sum(r[k] for r in warm) / len(warm)
    print()
    print(f"steps {len(rows)}; min angle over all steps {min(r['min_angle'] for r in rows):.2f} deg; "
          f"inverted {sum(r['inverted'] for r in rows)}; ids kept min {100 * min(r['ids_kept'] for r in warm):.2f} %, "
          f"mean {100 * mean('ids_kept'):.2f} %")
    print(f"step 0 (cold, in the run) wall {rows[0]['wall_s']:.3f} s; mean warm step wall {mean('wall_s'):.3f} s "
          f"(spacing {mean('spacing_s'):.3f}, simulation {mean('simulation_s'):.3f}, mesh and cleanup {mean('cleanup_s'):.3f}); "
          f"ratio to step 0 {mean('wall_s') / rows[0]['wall_s']:.3f}")
    if a.cold_wall:
        print(f"ratio of the mean warm step to the cold pdmesh mesh ({a.cold_wall:.3f} s): {mean('wall_s') / a.cold_wall:.3f}")
    # Third-party readers.
    pvd = os.path.join(a.dir, "motion.pvd")
    files = [(float(d.get("timestep")), d.get("file")) for d in ET.parse(pvd).getroot().iter("DataSet")]
    ok = len(files) == len(rows)
    try:
        import pyvista
        reader = pyvista.get_reader(pvd)
        times = list(reader.time_values)
        n = 0
        for i, t in enumerate(times):
            reader.set_active_time_value(t)
            mesh = reader.read()[0]
            ids = mesh.point_data["node_id"]
            n += 1
            if mesh.n_points != rows[i]["nodes"] or len(set(ids.tolist())) != mesh.n_points:
                ok = False
                print(f"pyvista: step {i}: {mesh.n_points} points, {len(set(ids.tolist()))} ids; motion.json {rows[i]['nodes']}")
        print(f"pyvista {pyvista.__version__} (vtk {pyvista.vtk_version_info}): read {n} of {len(files)} steps of {pvd}")
        ok = ok and n == len(files) and all(math.isclose(t, f[0]) for t, f in zip(times, files))
    except ImportError as e:
        print(f"pyvista: not installed ({e})")
    try:
        import meshio
        n = 0
        for i, (t, f) in enumerate(files):
            m = meshio.read(os.path.join(a.dir, f))
            if len(m.points) != rows[i]["nodes"] or "node_id" not in m.point_data:
                ok = False
            n += 1
        print(f"meshio {meshio.__version__}: read {n} of {len(files)} .vtu files listed in {pvd}, each with node_id")
    except ImportError as e:
        print(f"meshio: not installed ({e})")
    print("readers:", "ok" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
