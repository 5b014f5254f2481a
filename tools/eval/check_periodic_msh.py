#!/usr/bin/env python3
"""Checks that the $Periodic section of a pdmesh mesh.msh reads back in Gmsh (the PyPI `gmsh` module,
4.15.2 in tools/.venv-anchors) with the pairs pdmesh meant ([[periodic]], docs/mesh-formats.md):

    tools/.venv-anchors/bin/python tools/eval/check_periodic_msh.py MESH.msh --pairs left:right,bottom:top

For each SOURCE:IMAGE pair, gmsh.model.mesh.getPeriodicNodes on the image curve's entity must name
the source curve's entity as its master, list one pair per node of the image curve, and map every
master node onto its node by the affine transform it returns to 1e-12 of the mesh's extent. Exit
status 0 when every check passed, 1 otherwise, 77 when gmsh cannot be imported (ctest's skip)."""
import argparse
import math
import sys


def check(ok, what, failures):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    if not ok:
        failures.append(what)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("--pairs", required=True, help="SOURCE:IMAGE curve names, comma-separated")
    args = parser.parse_args()
    try:
        import gmsh
    except ImportError as e:
        print(f"skipped: no gmsh module ({e})")
        return 77
    failures = []
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(args.mesh)
        names = {gmsh.model.getPhysicalName(d, t): t for d, t in gmsh.model.getPhysicalGroups(1)}
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        xy = {int(t): (coords[3 * k], coords[3 * k + 1]) for k, t in enumerate(node_tags)}
        extent = max(max(abs(c) for c in p) for p in xy.values())
        for pair in args.pairs.split(","):
            source, image = pair.split(":")
            # pdmesh writes curve c as entity c + 1 with physical tag c + 1.
            image_tag, source_tag = names[image], names[source]
            master, tags, master_tags, affine = gmsh.model.mesh.getPeriodicNodes(1, image_tag)
            check(master == source_tag, f"gmsh {gmsh.__version__}: '{image}' (entity {image_tag}) has master "
                  f"{master} (want '{source}', entity {source_tag})", failures)
            _, _, edge_nodes = gmsh.model.mesh.getElements(1, image_tag)
            on_image = set(int(t) for t in edge_nodes[0]) if len(edge_nodes) else set()
            check(set(int(t) for t in tags) == on_image and len(tags) == len(on_image),
                  f"'{image}': {len(tags)} pairs for its {len(on_image)} nodes", failures)
            check(len(affine) == 16, f"'{image}': an affine transform of {len(affine)} values", failures)
            worst = 0.0
            for t, m in zip(tags, master_tags):
                mx, my = xy[int(m)]
                x = affine[0] * mx + affine[1] * my + affine[3]
                y = affine[4] * mx + affine[5] * my + affine[7]
                worst = max(worst, math.hypot(x - xy[int(t)][0], y - xy[int(t)][1]))
            check(worst <= 1e-12 * extent, f"'{source}' -> '{image}': largest |A p_master - p| {worst:.3g}", failures)
    finally:
        gmsh.finalize()
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
