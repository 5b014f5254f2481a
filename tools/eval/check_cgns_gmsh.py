#!/usr/bin/env python3
"""Checks that a pdmesh run's mesh.cgns opens in Gmsh (the PyPI `gmsh` module, 4.15.2 in
tools/.venv-anchors) with the run's mesh: the same counts of nodes, triangles, quadrangles and line
elements as the run's mesh.su2, one dimension-1 physical group per SU2 marker with edges (same name,
same number of lines) and the regions as dimension-2 physical groups:

    tools/.venv-anchors/bin/python tools/eval/check_cgns_gmsh.py RUN_DIR --regions domain,boundary_layer

Every element must lie in a physical group. Exit status 0 when every check passed, 1 otherwise, 77
when gmsh cannot be imported (ctest's skip)."""
import argparse
import os
import sys


def check(ok, what, failures):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    if not ok:
        failures.append(what)


def su2_counts(path):
    """Nodes, triangles, quadrangles and {marker: lines} of an SU2 file as pdmesh writes it."""
    with open(path) as f:
        lines = [line.split() for line in f if line.strip() and not line.startswith("%")]
    nodes = tris = quads = 0
    markers = {}
    i = 0
    while i < len(lines):
        key = lines[i][0]
        if key == "NELEM=":
            n = int(lines[i][1])
            for row in lines[i + 1:i + 1 + n]:
                tris += row[0] == "5"
                quads += row[0] == "9"
            i += n
        elif key == "NPOIN=":
            nodes = int(lines[i][1])
            i += nodes
        elif key == "MARKER_TAG=":
            name, n = lines[i][1], int(lines[i + 1][1])
            markers[name] = n
            i += 1 + n
        i += 1
    return nodes, tris, quads, markers


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("--regions", required=True, help="the dimension-2 groups' names, comma-separated")
    args = parser.parse_args()
    try:
        import gmsh
    except ImportError as e:
        print(f"skipped: no gmsh module ({e})")
        return 77
    nodes, tris, quads, markers = su2_counts(os.path.join(args.run_dir, "mesh.su2"))
    markers = {name: n for name, n in markers.items() if n > 0}  # a curve without edges has no elements
    failures = []
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(os.path.join(args.run_dir, "mesh.cgns"))
        version = gmsh.__version__
        tags, _, _ = gmsh.model.mesh.getNodes()
        check(len(tags) == nodes, f"gmsh {version}: {len(tags)} nodes (su2: {nodes})", failures)
        count = {t: len(gmsh.model.mesh.getElementsByType(t)[0]) for t in (1, 2, 3)}
        check(count[2] == tris, f"{count[2]} triangles (su2: {tris})", failures)
        check(count[3] == quads, f"{count[3]} quadrangles (su2: {quads})", failures)
        check(count[1] == sum(markers.values()), f"{count[1]} lines (su2 markers: {sum(markers.values())})", failures)
        lines_in = {}
        cells_in = {}
        for d, t in gmsh.model.getPhysicalGroups():
            name = gmsh.model.getPhysicalName(d, t)
            n = 0
            for entity in gmsh.model.getEntitiesForPhysicalGroup(d, t):
                for etype in ((1,) if d == 1 else (2, 3)):
                    n += len(gmsh.model.mesh.getElementsByType(etype, entity)[0])
            (lines_in if d == 1 else cells_in)[name] = n
        check(lines_in == markers, f"dimension-1 groups {sorted(lines_in.items())} (su2 markers {sorted(markers.items())})",
              failures)
        want = args.regions.split(",")
        check(sorted(cells_in) == sorted(want), f"dimension-2 groups {sorted(cells_in.items())} (want {sorted(want)})",
              failures)
        check(sum(cells_in.values()) == tris + quads, f"every cell in a dimension-2 group ({sum(cells_in.values())} "
              f"of {tris + quads})", failures)
    finally:
        gmsh.finalize()
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
