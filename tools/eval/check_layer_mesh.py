#!/usr/bin/env python3
"""Checks that a boundary-layer run's mixed-cell files load in Gmsh (the PyPI `gmsh` module, 4.15.2 in
tools/.venv-anchors) and in meshio with the right cell types and markers (issue 38):

    tools/.venv-anchors/bin/python tools/eval/check_layer_mesh.py DIR --walls upper,lower [--curves ...]

DIR is `pdmesh mesh`'s output folder of a case with [[boundary_layer]] and elements = "quads"
(mesh.msh, and mesh.su2 when written). Gmsh: DIR/mesh.msh has 2-D elements of types 2 (triangles)
and 3 (quadrangles) only, physical groups "domain" and "boundary_layer" (the latter holding every
quadrangle) and one per wall curve with its edges. meshio: the same counts from mesh.msh, and from
mesh.su2 triangles (5), quadrilaterals (9) and one marker (MARKER_TAG) per curve. Gmsh has no SU2
reader. Exit status 0 when every check passed, 1 otherwise, 77 when neither gmsh nor meshio can be
imported (ctest's skip)."""
import argparse
import os
import sys


def check(ok, what, failures):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    if not ok:
        failures.append(what)


def with_gmsh(gmsh, path, walls, failures):
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(path)
        version = gmsh.__version__
        types = sorted(int(t) for t in gmsh.model.mesh.getElementTypes(2))
        check(types == [2, 3], f"gmsh {version}: {path}: 2-D element types {types} (want [2, 3])", failures)
        groups = {gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()}
        for name in ["domain", "boundary_layer"] + walls:
            check(name in groups, f"gmsh: physical group '{name}'", failures)
        quads_total = sum(len(tags) for t, tags in zip(*gmsh.model.mesh.getElements(2)[:2]) if int(t) == 3)
        if "boundary_layer" in groups:
            quads_layer = 0
            for entity in gmsh.model.getEntitiesForPhysicalGroup(*groups["boundary_layer"]):
                etypes, etags, _ = gmsh.model.mesh.getElements(2, int(entity))
                quads_layer += sum(len(tags) for t, tags in zip(etypes, etags) if int(t) == 3)
            check(quads_total > 0 and quads_layer == quads_total,
                  f"gmsh: {quads_layer} of {quads_total} quadrangles in 'boundary_layer'", failures)
        for name in walls:
            if name in groups:
                edges = 0
                for entity in gmsh.model.getEntitiesForPhysicalGroup(*groups[name]):
                    etypes, etags, _ = gmsh.model.mesh.getElements(1, int(entity))
                    edges += sum(len(tags) for t, tags in zip(etypes, etags) if int(t) == 1)
                check(edges > 0, f"gmsh: wall '{name}' has {edges} edges", failures)
        return quads_total
    finally:
        gmsh.finalize()


def with_meshio(meshio, directory, walls, failures):
    def count(m, kind):
        return sum(len(c.data) for c in m.cells if c.type == kind)

    msh = meshio.read(os.path.join(directory, "mesh.msh"))
    triangles, quads = count(msh, "triangle"), count(msh, "quad")
    check(quads > 0 and triangles > 0, f"meshio {meshio.__version__}: mesh.msh: {triangles} triangles, {quads} quads",
          failures)
    for name in ["domain", "boundary_layer"] + walls:
        check(name in msh.field_data, f"meshio: mesh.msh physical name '{name}'", failures)
    if "boundary_layer" in msh.field_data:
        tag = msh.field_data["boundary_layer"][0]
        tagged = sum(int((tags == tag).sum()) for c, tags in zip(msh.cells, msh.cell_data["gmsh:physical"])
                     if c.type == "quad")
        check(tagged == quads, f"meshio: {tagged} of {quads} quads tagged boundary_layer", failures)
    su2_path = os.path.join(directory, "mesh.su2")
    if os.path.exists(su2_path):
        su2 = meshio.read(su2_path)
        check(count(su2, "triangle") == triangles and count(su2, "quad") == quads,
              f"meshio: mesh.su2: {count(su2, 'triangle')} triangles, {count(su2, 'quad')} quads (as mesh.msh)",
              failures)
        with open(su2_path) as f:
            tags = [line.split("=", 1)[1].strip() for line in f if line.startswith("MARKER_TAG=")]
        for name in walls:
            check(name in tags, f"mesh.su2: MARKER_TAG= {name}", failures)
        markers = set()
        for c, t in zip(su2.cells, su2.cell_data["su2:tag"]):
            if c.type == "line":
                markers |= set(t.tolist())
        check(len(markers) == len(tags), f"meshio: mesh.su2: {len(markers)} markers read, {len(tags)} written",
              failures)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--walls", required=True, help="the wall curve names, comma-separated")
    args = ap.parse_args()
    walls = args.walls.split(",")
    failures, tools = [], 0
    try:
        import gmsh
    except ImportError:
        print("gmsh: not importable, skipped")
    else:
        tools += 1
        with_gmsh(gmsh, os.path.join(args.dir, "mesh.msh"), walls, failures)
    try:
        import meshio
    except ImportError:
        print("meshio: not importable, skipped")
    else:
        tools += 1
        with_meshio(meshio, args.dir, walls, failures)
    if tools == 0:
        sys.exit(77)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
