#!/usr/bin/env python3
"""Checks that a pdmesh mesh.msh reads back in Gmsh (the PyPI `gmsh` module, 4.15.2 in
tools/.venv-anchors) with the physical groups a re-meshed file keeps (docs/mesh-formats.md, "Physical
tags"):

    tools/.venv-anchors/bin/python tools/eval/check_msh_groups.py MESH.msh --groups 1:5:walls,2:11:steel

Gmsh's physical groups (dimension, tag) must be exactly those given, each with its name, and every
line element must lie in a dimension-1 group. Exit status 0 when every check passed, 1 otherwise, 77
when gmsh cannot be imported (ctest's skip)."""
import argparse
import sys


def check(ok, what, failures):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    if not ok:
        failures.append(what)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("--groups", required=True, help="DIM:TAG:NAME, comma-separated")
    args = parser.parse_args()
    try:
        import gmsh
    except ImportError as e:
        print(f"skipped: no gmsh module ({e})")
        return 77
    want = {}
    for item in args.groups.split(","):
        dim, tag, name = item.split(":", 2)
        want[(int(dim), int(tag))] = name
    failures = []
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(args.mesh)
        groups = {(d, t): gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
        check(groups == want, f"gmsh {gmsh.__version__}: physical groups {sorted(groups.items())} "
              f"(want {sorted(want.items())})", failures)
        lines = set(int(t) for t in gmsh.model.mesh.getElementsByType(1)[0])
        in_groups = set()
        for d, t in gmsh.model.getPhysicalGroups(1):
            for entity in gmsh.model.getEntitiesForPhysicalGroup(d, t):
                in_groups.update(int(e) for e in gmsh.model.mesh.getElementsByType(1, entity)[0])
        check(lines and lines == in_groups, f"all {len(lines)} line elements lie in a dimension-1 group", failures)
    finally:
        gmsh.finalize()
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
