#!/usr/bin/env python3
"""Prints the curve and cell tags of a run's mesh files as Gmsh and meshio read them back (the anchors'
tools/.venv-anchors has both):

    tools/.venv-anchors/bin/python tools/eval/read_back_tags.py DIR

DIR/mesh.msh through Gmsh (physical groups, their entities' element counts) and meshio (field_data,
gmsh:physical per cell block); DIR/mesh.vtu, mesh.su2 and mesh.mesh through meshio (the cell data
and field data that hold the tags). Prints, checks nothing; a file that is missing is skipped."""
import collections
import os
import sys

import numpy as np


def gmsh_groups(path):
    import gmsh
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(path)
        print(f"gmsh {gmsh.__version__} {path}")
        for dim, tag in gmsh.model.getPhysicalGroups():
            counts = collections.Counter()
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                types, tags, _ = gmsh.model.mesh.getElements(dim, entity)
                for t, e in zip(types, tags):
                    counts[gmsh.model.mesh.getElementProperties(t)[0]] += len(e)
            print(f"  ({dim}, {tag}) {gmsh.model.getPhysicalName(dim, tag)!r}: {dict(counts)}")
    finally:
        gmsh.finalize()


def counts(values):
    u, n = np.unique(np.asarray(values), return_counts=True)
    return {v.item(): int(k) for v, k in zip(u, n)}


def meshio_tags(path):
    import meshio
    m = meshio.read(path)
    print(f"meshio {meshio.__version__} {path}")
    if m.field_data:
        print("  field_data:", {k: (np.asarray(v).tolist() if np.asarray(v).size < 8 else f"{np.asarray(v).size} values")
                                for k, v in m.field_data.items()})
    for name, blocks in m.cell_data.items():
        if name in ("gmsh:geometrical",):
            continue
        per_type = collections.defaultdict(collections.Counter)
        for block, data in zip(m.cells, blocks):
            for v, k in counts(data).items():
                per_type[block.type][v] += k
        print(f"  cell_data {name!r}:", {t: dict(c) for t, c in per_type.items()})


def main():
    d = sys.argv[1]
    msh = os.path.join(d, "mesh.msh")
    if os.path.exists(msh):
        gmsh_groups(msh)
    for f in ("mesh.msh", "mesh.vtu", "mesh.su2", "mesh.mesh"):
        if os.path.exists(os.path.join(d, f)):
            meshio_tags(os.path.join(d, f))


if __name__ == "__main__":
    main()
