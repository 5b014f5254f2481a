#!/usr/bin/env python3
"""Reads pdmesh's fort.14 and .2dm back with third-party readers and compares them with the same
run's Triangle files (the .node/.ele/.poly that pdmesh's own tests read back): the same nodes, the same
triangles, and per curve the same boundary edges. fort.14 through adcircpy's parser
(adcircpy/mesh/parsers/grd.py, loaded by path so that the package's heavy __init__ is not needed),
.2dm through py2dm. Exits 1 on a difference, printing it.

    tools/eval/setup_anchors.sh
    build/pdmesh mesh CASE --out DIR --set 'output.formats=["fort14","2dm","triangle"]' \\
        --set 'output.open_boundaries=["ocean"]'
    tools/.venv-anchors/bin/python tools/eval/check_coastal_formats.py DIR --open ocean
"""
import argparse
import warnings
import importlib.util
import os
import sys

import py2dm


def adcirc_parser():
    spec = importlib.util.find_spec("adcircpy")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("check_coastal_formats: adcircpy is not installed (tools/eval/setup_anchors.sh)")
    path = os.path.join(list(spec.submodule_search_locations)[0], "mesh", "parsers", "grd.py")
    module_spec = importlib.util.spec_from_file_location("adcircpy_grd", path)
    module = importlib.util.module_from_spec(module_spec)
    module_spec.loader.exec_module(module)
    return module


def data_lines(path):
    with open(path) as f:
        for line in f:
            words = line.split("#", 1)[0].split()
            if words:
                yield words


def read_triangle(stem):
    """Points, triangles (1-based point ids) and {curve name: set of undirected edges} of pdmesh's
    Triangle files."""
    lines = list(data_lines(stem + ".node"))
    points = {int(w[0]): (float(w[1]), float(w[2])) for w in lines[1:]}
    triangles = [tuple(int(v) for v in w[1:4]) for w in list(data_lines(stem + ".ele"))[1:]]
    names = {}
    with open(stem + ".poly") as f:
        for line in f:
            if line.startswith("# pdmesh curve "):
                marker, name = line.split()[3:5]
                names[int(marker)] = name
    poly = list(data_lines(stem + ".poly"))
    count = int(poly[1][0])
    edges = {}
    for w in poly[2:2 + count]:
        edges.setdefault(names[int(w[3])], set()).add(frozenset((int(w[1]), int(w[2]))))
    return points, triangles, edges


def string_edges(nodes):
    return {frozenset((int(a), int(b))) for a, b in zip(nodes, nodes[1:])}


def compare(what, got, want, problems):
    if got != want:
        problems.append(f"{what}: differs ({len(got) if hasattr(got, '__len__') else got} against "
                        f"{len(want) if hasattr(want, '__len__') else want})")


def compare_points(what, got, want, problems):
    """Same ids and coordinates to the last bits or so: pandas' default float parser (adcircpy's) is
    not correctly rounded, so a 17-digit number may read back one or two units in the last place off."""
    if got.keys() != want.keys():
        problems.append(f"{what}: {len(got)} node ids against {len(want)}")
        return
    scale = max(max(abs(v) for p in want.values() for v in p), 1e-300)
    worst = max(abs(a - b) for i in want for a, b in zip(got[i], want[i]))
    if worst > 1e-14 * scale:
        problems.append(f"{what}: coordinates differ by up to {worst:.3g}")


def check_fort14(path, points, triangles, edges, open_names, problems):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FutureWarning)  # adcircpy's delim_whitespace
        grid = adcirc_parser().read_fort14(path)
    nodes = grid["nodes"]
    got_points = {int(i): (float(r["x"]), float(r["y"])) for i, r in nodes.iterrows()}
    compare_points("fort.14 nodes", got_points, points, problems)
    elements = grid["elements"]
    got_tris = [tuple(int(r[f"node_{k}"]) for k in (1, 2, 3)) for _, r in elements.iterrows()]
    compare("fort.14 elements", got_tris, triangles, problems)
    boundaries = grid["boundaries"]
    open_strings = boundaries.get(None, [])
    land = [s for key, strings in boundaries.items() if key is not None for s in strings]
    got_open = set().union(*[string_edges(s["node_id"]) for s in open_strings]) if open_strings else set()
    want_open = set().union(*[edges[n] for n in open_names]) if open_names else set()
    compare("fort.14 open boundary edges", got_open, want_open, problems)
    got_land = set().union(*[string_edges(s["node_id"]) for s in land]) if land else set()
    want_land = set().union(*[e for n, e in edges.items() if n not in open_names])
    # Embedded constraints are in the .poly but are not boundaries of fort.14.
    compare("fort.14 land boundary edges", got_land, want_land & boundary_edges(triangles), problems)
    return len(got_points), len(got_tris), len(open_strings), len(land)


def boundary_edges(triangles):
    count = {}
    for t in triangles:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            key = frozenset((a, b))
            count[key] = count.get(key, 0) + 1
    return {e for e, c in count.items() if c == 1}


def check_2dm(path, points, triangles, edges, problems):
    with py2dm.Reader(path) as mesh:
        got_points = {n.id: (n.pos[0], n.pos[1]) for n in mesh.iter_nodes()}
        got_tris = [tuple(e.nodes) for e in mesh.iter_elements()]
        strings = {s.name: string_edges(s.nodes) for s in mesh.iter_node_strings()}
    compare_points("2dm nodes", got_points, points, problems)
    compare("2dm elements", got_tris, triangles, problems)
    outer = boundary_edges(triangles)
    want = {n: e & outer for n, e in edges.items() if e & outer}
    compare("2dm node strings", strings, want, problems)
    return len(strings)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dir", help="a pdmesh output directory with mesh.14, mesh.2dm and mesh.node/.ele/.poly")
    parser.add_argument("--open", default="", help="comma-separated curves written as open boundaries")
    args = parser.parse_args()
    open_names = [n for n in args.open.split(",") if n]
    points, triangles, edges = read_triangle(os.path.join(args.dir, "mesh"))
    problems = []
    n, t, opened, land = check_fort14(os.path.join(args.dir, "mesh.14"), points, triangles, edges, open_names,
                                      problems)
    strings = check_2dm(os.path.join(args.dir, "mesh.2dm"), points, triangles, edges, problems)
    print(f"{args.dir}: fort.14 (adcircpy) {n} nodes, {t} triangles, {opened} open and {land} land boundaries; "
          f".2dm (py2dm) {strings} node strings")
    for p in problems:
        print("  DIFFERENT:", p)
    print("same nodes, elements and boundaries" if not problems else f"{len(problems)} difference(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
