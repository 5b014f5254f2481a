"""generate(), Case and Mesh: a circle in a square from rings, from a file and from a case file,
the same points as the command for the same case and seed, zero-copy arrays, boundary edges by
curve name, quality, writers."""

from __future__ import annotations

import gc

import numpy as np
import pytest

import pdmesh
from conftest import read_nodes, write_crv

SETTINGS = dict(device="host", seed=3, iterations=60)


def test_rings_mesh_the_domain(rings):
    mesh = pdmesh.generate(pdmesh.Geometry(rings, names=["outer", "hole"]), **SETTINGS)
    assert mesh.points.shape[1] == 2 and mesh.points.dtype == np.float64
    assert mesh.triangles.shape[1] == 3 and mesh.triangles.dtype == np.int32
    assert mesh.triangles.min() == 0 and mesh.triangles.max() == len(mesh.points) - 1
    # Counter-clockwise triangles covering the square minus the hole.
    p = mesh.points[mesh.triangles]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                  - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    assert (area > 0).all()
    # The domain is the square minus the polygon through the hole's boundary nodes (placed along its
    # 24 segments by the field, and split onto them by the cleanup).
    assert set(mesh.boundary_edges) == {"outer", "hole"}

    def enclosed(edges):
        a, b = mesh.points[edges[:, 0]], mesh.points[edges[:, 1]]
        return abs(0.5 * (a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]).sum())

    assert enclosed(mesh.boundary_edges["outer"]) == pytest.approx(4.0, rel=1e-12)
    assert area.sum() == pytest.approx(4.0 - enclosed(mesh.boundary_edges["hole"]), rel=1e-12)
    hole = mesh.boundary_edges["hole"]
    assert hole.dtype == np.int32 and hole.shape[1] == 2
    r = np.hypot(*mesh.points[hole.ravel()].T)  # on the hole's segments: between chord and circle
    assert (r <= 0.3 + 1e-12).all() and (r >= 0.3 * np.cos(np.pi / 24) - 1e-12).all()
    assert np.abs(mesh.points[mesh.boundary_edges["outer"].ravel()]).max(axis=1).min() == 1.0


def test_file_and_rings_give_the_same_mesh(rings, tmp_path):
    crv = write_crv(tmp_path / "shape.crv", rings)
    from_file = pdmesh.generate(pdmesh.Geometry.from_file(crv), **SETTINGS)
    from_rings = pdmesh.generate(pdmesh.Geometry(rings), **SETTINGS)
    assert np.array_equal(from_file.points, from_rings.points)
    assert np.array_equal(from_file.triangles, from_rings.triangles)
    assert list(from_file.boundary_edges) == ["curve0", "curve1"]


def test_case_file_gives_the_commands_points(rings, tmp_path, command):
    write_crv(tmp_path / "shape.crv", rings)
    case = tmp_path / "case.toml"
    case.write_text('name = "cis"\n[geometry]\nfiles = ["shape.crv"]\ncurve_names = ["outer", "hole"]\n'
                    '[init]\nmethod = "random"\nseed = 7\n[simulation]\niterations = 80\ndevice = "host"\n')
    mesh = pdmesh.Case.from_toml(case).run()
    command("mesh", case, "--out", tmp_path / "out", "--quiet", "--formats", "msh")
    # The nodes of the (cleaned) mesh: the command's mesh.nodes, bit for bit.
    assert np.array_equal(mesh.points, read_nodes(tmp_path / "out" / "mesh.nodes"))
    written = pdmesh.Mesh.read(tmp_path / "out" / "mesh.msh")
    assert np.array_equal(mesh.triangles, written.triangles)
    assert mesh.curve_names == written.curve_names == ["outer", "hole"]
    # generate() with a case-file path and the seed given in Python: the command with --seed.
    other = pdmesh.generate(str(case), seed=11)
    command("mesh", case, "--out", tmp_path / "out11", "--quiet", "--formats", "msh", "--seed", 11)
    assert np.array_equal(other.points, read_nodes(tmp_path / "out11" / "mesh.nodes"))
    assert not np.array_equal(other.points, mesh.points)


def test_thesis_case_file_runs_its_preset():
    case = pdmesh.Case.from_toml(pdmesh_case("circle_circle"), iterations=5)
    assert case.preset == "thesis" and case.iterations == 5 and case.name == "circle_circle"
    mesh = case.run(device="host")
    assert len(mesh.triangles) > 100


def test_case_reports_its_fill_method():
    for method in ("structured", "random", "hexagonal", "hybrid"):
        case = pdmesh.Case.from_toml(pdmesh_case("circle_circle"), method=method)
        assert case.method == method


def pdmesh_case(name: str):
    from conftest import SOURCE_DIR
    return SOURCE_DIR / "cases" / name / "case.toml"


def test_arrays_are_views_without_copies(rings):
    mesh = pdmesh.generate(rings, **SETTINGS)
    p1, p2 = mesh.points, mesh.points
    assert p1.ctypes.data == p2.ctypes.data  # the same memory every time: nothing is copied
    assert not p1.flags.owndata and not p1.flags.writeable
    base = p1.base
    while isinstance(base, np.ndarray):
        base = base.base
    assert isinstance(base, memoryview)  # the exporter's buffer, owned by the C++ mesh
    t = mesh.triangles
    assert not t.flags.owndata and not t.flags.writeable
    with pytest.raises(ValueError):
        p1[0, 0] = 5.0
    expected = p1.copy()
    del mesh, p2
    gc.collect()
    assert np.array_equal(p1, expected)  # the view keeps the mesh's memory alive


def test_quality_write_and_read_back(rings, tmp_path):
    mesh = pdmesh.generate(rings, **SETTINGS)
    q = mesh.quality()
    assert q["triangles"] == len(mesh.triangles) and q["points"] == len(mesh.points)
    per = q["per_triangle"]
    assert per["min_angle"].shape == (len(mesh.triangles),)
    assert per["min_angle"].min() == pytest.approx(q["included_angle"]["min"])
    assert 0.5 < q["spacing_conformance"]["mean"] < 1.5
    for name in ("m.msh", "m.vtu", "m.su2", "m.ele", "m.mesh"):
        mesh.write(tmp_path / name)
        back = pdmesh.Mesh.read(tmp_path / name)
        assert np.allclose(back.points, mesh.points, rtol=0, atol=1e-12)
        assert np.array_equal(back.triangles, mesh.triangles)
    # Medit .mesh: the curves by name (its "# ref N: curve NAME" comments) with their edges.
    back = pdmesh.Mesh.read(tmp_path / "m.mesh")
    assert list(back.boundary_edges) == list(mesh.boundary_edges)
    for name, edges in mesh.boundary_edges.items():
        assert np.array_equal(back.boundary_edges[name], edges), name
    mesh.write(tmp_path / "m22.msh", format="msh22")
    assert (tmp_path / "m22.msh").read_text().startswith("$MeshFormat\n2.2")
    mesh.write(tmp_path / "m.png")
    assert (tmp_path / "m.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    mesh.picture(tmp_path / "q.png", color_by="min_angle", window=(-0.5, -0.5, 0.5, 0.5))
    assert (tmp_path / "q.png").stat().st_size > 1000
    # A mesh without regions filled by region: every triangle grey as "no region", not an error.
    mesh.picture(tmp_path / "r.png", color_by="region")
    assert (tmp_path / "r.png").stat().st_size > 1000
    with pytest.raises(pdmesh.InputError, match="unknown metric 'angle'"):
        mesh.picture(tmp_path / "bad.png", color_by="angle")
    assert mesh._repr_png_()[:4] == b"\x89PNG"
    assert "<svg" in mesh._repr_svg_()
    with pytest.raises(pdmesh.InputError, match="unknown mesh suffix"):
        mesh.write(tmp_path / "m.xyz")


def test_coastal_formats(rings, tmp_path):
    """fort.14 and .2dm: every node and triangle, the square an open or land string, the hole an island."""
    mesh = pdmesh.generate(rings, **SETTINGS)
    names = list(mesh.boundary_edges)
    mesh.write(tmp_path / "m.14", open_boundaries=[names[0]])
    lines = (tmp_path / "m.14").read_text().splitlines()
    assert lines[1].split() == [str(len(mesh.triangles)), str(len(mesh.points))]
    rest = lines[2 + len(mesh.points) + len(mesh.triangles):]
    assert rest[0] == "1 = Number of open boundaries"
    assert rest[int(rest[2].split()[0]) + 3] == "1 = Number of land boundaries"
    assert rest[int(rest[2].split()[0]) + 5].split()[1] == "1"  # the hole: an island
    mesh.write(tmp_path / "m.2dm")
    text = (tmp_path / "m.2dm").read_text()
    assert text.count("\nE3T ") == len(mesh.triangles) and text.count("\nND ") == len(mesh.points)
    ns = [line.split()[1:] for line in text.splitlines() if line.startswith("NS ")]
    assert sum(1 for words in ns for w in words if w.startswith("-")) == 2  # two strings, each ending in a negated id
    with pytest.raises(pdmesh.InputError, match="unknown curve 'ocean'"):
        mesh.write(tmp_path / "x.14", open_boundaries=["ocean"])


def test_geo_interface_round_trip(rings):
    geo = pdmesh.Geometry(rings)
    gi = geo.__geo_interface__
    assert gi["type"] == "Polygon" and len(gi["coordinates"]) == 2  # the square and its hole
    again = pdmesh.Geometry(type("Shape", (), {"__geo_interface__": gi})())
    assert again.area == pytest.approx(geo.area, rel=1e-12)
    two = {"type": "MultiPolygon", "coordinates": [gi["coordinates"],
                                                   [[(3, 0), (4, 0), (4, 1), (3, 1), (3, 0)]]]}
    both = pdmesh.Geometry.from_geo_interface(two)
    assert both.area == pytest.approx(geo.area + 1.0)
    assert both.__geo_interface__["type"] == "MultiPolygon"


def test_read_keeps_regions_and_corners(tmp_path):
    # A .mesh as mmg2d writes pdmesh's back: triangle references without pdmesh's comments, Corners.
    (tmp_path / "mmg.mesh").write_text(
        "MeshVersionFormatted 2\nDimension 2\nVertices\n6\n0 0 1\n1 0 1\n2 0 1\n0 1 1\n1 1 1\n2 1 1\n"
        "Corners\n4\n1\n3\n4\n6\nEdges\n6\n1 2 1\n2 3 1\n3 6 2\n6 5 3\n5 4 3\n4 1 4\n"
        "Triangles\n4\n1 2 5 1\n1 5 4 1\n2 3 6 2\n2 6 5 2\nEnd\n")
    mesh = pdmesh.Mesh.read(tmp_path / "mmg.mesh")
    assert mesh.regions.tolist() == [1, 1, 2, 2]
    assert mesh.kinds.tolist() == [0, 1, 0, 0, 1, 0]
    assert mesh.curve_names == ["ref1", "ref2", "ref3", "ref4"]
    # Written and read again in every format that carries regions: the same regions per triangle.
    for name in ("m.msh", "m.vtu", "m.ele", "m.mesh"):
        mesh.write(tmp_path / name)
        back = pdmesh.Mesh.read(tmp_path / name)
        by_triangle = {tuple(sorted(t)): r for t, r in zip(back.triangles.tolist(), back.regions.tolist())}
        assert by_triangle == {tuple(sorted(t)): r for t, r in zip(mesh.triangles.tolist(), mesh.regions.tolist())}
    assert '"region_1"' in (tmp_path / "m.msh").read_text()
    assert "Corners\n4\n1\n3\n4\n6\n" in (tmp_path / "m.mesh").read_text()
    assert pdmesh.Mesh.read(tmp_path / "m.vtu").kinds.tolist() == mesh.kinds.tolist()
    assert mesh.region_names == {}


def test_read_keeps_region_names(tmp_path):
    # A .mesh whose comments name its references, as pdmesh writes them: the names come back per
    # attribute and are written again by the formats that carry them.
    (tmp_path / "named.mesh").write_text(
        "MeshVersionFormatted 2\nDimension 2\n# ref 1: region fluid\n# ref 2: region solid\n"
        "Vertices\n6\n0 0 1\n1 0 1\n2 0 1\n0 1 1\n1 1 1\n2 1 1\n"
        "Edges\n6\n1 2 1\n2 3 1\n3 6 2\n6 5 3\n5 4 3\n4 1 4\n"
        "Triangles\n4\n1 2 5 1\n1 5 4 1\n2 3 6 2\n2 6 5 2\nEnd\n")
    mesh = pdmesh.Mesh.read(tmp_path / "named.mesh")
    assert mesh.regions.tolist() == [1, 1, 2, 2]
    assert mesh.region_names == {1.0: "fluid", 2.0: "solid"}
    for name in ("m.msh", "m.vtu", "m.mesh"):
        mesh.write(tmp_path / name)
        back = pdmesh.Mesh.read(tmp_path / name)
        named = [back.region_names[r] for r in back.regions.tolist()]
        assert named == ["fluid", "fluid", "solid", "solid"], name
    assert '"fluid"' in (tmp_path / "m.msh").read_text()
