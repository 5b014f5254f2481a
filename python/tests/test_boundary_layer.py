"""generate(..., boundary_layer=...): the case file's [[boundary_layer]] tables from Python (a dict or
a list of dicts), the mixed mesh it returns (quads, the layer's triangles), its files, and bad
settings as typed errors. A circle of 24 segments in a square; few iterations on the host."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

import pdmesh

H1 = 1e-3


def layer(curves, **keys):
    table = {"curves": curves, "first_height": H1, "growth": 1.2, "thickness": 0.03, "elements": "quads"}
    table.update(keys)
    return table


def run(rings, boundary_layer, **keywords):
    geometry = pdmesh.Geometry(rings, names=["box", "hole"])
    return pdmesh.generate(geometry, boundary_layer=boundary_layer, iterations=40, device="host", **keywords)


def wall_quads(mesh, curve):
    """The quads with an edge on the curve's boundary edges, and the heights of their other corners."""
    wall = {frozenset(e) for e in mesh.boundary_edges[curve].tolist()}
    heights = []
    for q in mesh.quads.tolist():
        for k in range(4):
            a, b = q[k], q[(k + 1) % 4]
            if frozenset((a, b)) in wall:
                pa, pb = mesh.points[a], mesh.points[b]
                d = pb - pa
                n = np.array([-d[1], d[0]]) / np.hypot(*d)
                heights += [abs((mesh.points[v] - pa) @ n) for v in q if v not in (a, b)]
    return heights


def test_a_layer_dict_gives_quads_on_the_wall_at_the_first_height(rings):
    mesh = run(rings, layer(["hole"]))
    heights = wall_quads(mesh, "hole")
    # One quad on each wall edge: the circle's 24 segments, split where the rays diverge.
    assert len(mesh.boundary_edges["hole"]) >= 24
    assert len(heights) == 2 * len(mesh.boundary_edges["hole"])
    assert np.allclose(heights, H1, rtol=0.02)
    assert mesh.quads.shape[1] == 4 and len(mesh.quads) > 24
    # Every triangle is tagged; the core's are 0, and the layer's (transitions) are 1.
    assert mesh.triangle_layer.shape == (len(mesh.triangles),)
    assert set(np.unique(mesh.triangle_layer)) <= {0, 1}
    assert (mesh.triangle_layer == 0).sum() > 100
    # The wall curves are kept as boundary curves; the fronts are inside.
    assert len(mesh.boundary_edges["box"]) >= 48  # placed by the core's spacing
    assert "quads" in repr(mesh)


def test_a_list_of_tables_and_triangles(rings):
    mesh = run(rings, [layer(["hole"], elements="triangles"), layer(["box"], thickness=0.02)])
    assert len(wall_quads(mesh, "box")) == 2 * len(mesh.boundary_edges["box"])  # the box's layer as quads
    assert len(wall_quads(mesh, "hole")) == 0      # the hole's split into triangles
    assert mesh.triangle_layer.sum() >= 2 * 24


def test_without_layers_there_are_no_quads(rings):
    mesh = pdmesh.generate(pdmesh.Geometry(rings, names=["box", "hole"]), iterations=5, device="host")
    assert mesh.quads.shape == (0, 4)
    assert len(mesh.triangle_layer) == 0


@pytest.mark.parametrize("table, words", [
    (layer(["nope"]), ["nope", "hole"]),
    (layer(["hole"], growth=0.9), ["growth", "0.9"]),
    (layer(["hole"], first_height=0.1, thickness=0.01), ["first_height", "thickness"]),
    ({**layer(["hole"]), "frist_height": 1e-3}, ["frist_height"]),
    (layer(["hole"], elements="hexagons"), ["elements", "hexagons"]),
    (5, ["boundary_layer"]),
])
def test_bad_settings_are_input_errors(rings, table, words):
    with pytest.raises(pdmesh.InputError) as e:
        run(rings, table)
    for w in words:
        assert w in str(e.value)


def test_the_mixed_files_load_in_meshio(rings, tmp_path):
    meshio = pytest.importorskip("meshio")
    mesh = run(rings, layer(["hole"]))
    mesh.write(tmp_path / "m.msh")
    mesh.write(tmp_path / "m.su2")
    triangles, quads = len(mesh.triangles), len(mesh.quads)

    def count(m, kind):
        return sum(len(c.data) for c in m.cells if c.type == kind)

    msh = meshio.read(tmp_path / "m.msh")
    assert count(msh, "triangle") == triangles and count(msh, "quad") == quads
    assert {"box", "hole", "domain", "boundary_layer"} <= set(msh.field_data)
    layer_tag = msh.field_data["boundary_layer"][0]
    tagged = {c.type: 0 for c in msh.cells}
    for c, tags in zip(msh.cells, msh.cell_data["gmsh:physical"]):
        tagged[c.type] += int((tags == layer_tag).sum())
    assert tagged["quad"] == quads
    assert tagged["triangle"] == int(mesh.triangle_layer.sum())

    su2 = meshio.read(tmp_path / "m.su2")
    assert count(su2, "triangle") == triangles and count(su2, "quad") == quads
    markers = set()
    for c, tags in zip(su2.cells, su2.cell_data["su2:tag"]):
        if c.type == "line":
            markers |= set(tags.tolist())
    assert len(markers) == 2  # box and hole
    assert "MARKER_TAG= hole" in (tmp_path / "m.su2").read_text()

    m = mesh.to_meshio()
    assert [c.type for c in m.cells][:2] == ["triangle", "quad"]
    assert int(m.cell_data["boundary_layer"][1].sum()) == quads
    # meshio's msh writer takes it (it needs the Gmsh tags): the quads in the "boundary_layer" group.
    meshio.write(tmp_path / "via_meshio.msh", m, file_format="gmsh")
    back = meshio.read(tmp_path / "via_meshio.msh")
    assert count(back, "triangle") == triangles and count(back, "quad") == quads
    assert {"box", "hole", "domain", "boundary_layer"} <= set(back.field_data)
    for c, tags in zip(back.cells, back.cell_data["gmsh:physical"]):
        if c.type == "quad":
            assert set(tags.tolist()) == {back.field_data["boundary_layer"][0]}


def test_formats_that_cannot_hold_quads_are_refused(rings, tmp_path):
    mesh = run(rings, layer(["hole"]))
    with pytest.raises(pdmesh.InputError, match="triangle"):
        mesh.write(tmp_path / "m.ele")
    mesh.write(tmp_path / "m.vtu")
    assert (tmp_path / "m.vtu").stat().st_size > 0


def test_a_mesher_with_out_writes_the_command_s_layered_outputs(rings, tmp_path):
    geometry = pdmesh.Geometry(rings, names=["box", "hole"])
    mesher = pdmesh.Mesher(geometry, out=tmp_path, boundary_layer=layer(["hole"]), iterations=20, device="host",
                           formats=["msh", "su2"])
    mesher.run()
    mesh = mesher.triangulate()
    quality = json.loads((tmp_path / "quality.json").read_text())
    assert quality["boundary_layer"]["quads"] == len(mesh.quads)
    assert quality["boundary_layer"]["tables"][0]["first_height_within_2pct"] == 1
    assert "MARKER_TAG= hole" in (tmp_path / "mesh.su2").read_text()
    assert (tmp_path / "mesh.msh").exists() and (tmp_path / "initial.nodes").exists()


def test_mesh_read_gives_the_quads_of_each_format(rings, tmp_path):
    # Mesh.read of the mixed files takes the quads (as `pdmesh quality` does) beside the triangles:
    # the same cells from msh, vtu, su2 and mesh; the layer's triangles where the format names the
    # layer (msh's group, vtu's cell data, mesh's named reference), every quad a layer cell in all four.
    def rows(a):
        return sorted(map(tuple, np.asarray(a).tolist()))

    mesh = run(rings, layer(["hole"]))
    assert len(mesh.quads) > 0
    for suffix in ("msh", "vtu", "su2", "mesh"):
        mesh.write(tmp_path / f"m.{suffix}")
        back = pdmesh.Mesh.read(tmp_path / f"m.{suffix}")
        assert np.array_equal(back.points, mesh.points)
        assert np.array_equal(back.quads, mesh.quads), suffix
        assert rows(back.triangles) == rows(mesh.triangles)
        if suffix == "su2":
            assert not back.triangle_layer.any()
        else:
            assert rows(back.triangles[back.triangle_layer == 1]) == rows(mesh.triangles[mesh.triangle_layer == 1])


def _foam_list(path):
    """An OpenFOAM list file's entries (after the FoamFile header's count and its parenthesis)."""
    body = path.read_text().split("}\n", 1)[1].split()
    count = int(body[0])
    return count, " ".join(body[1:])


def test_openfoam_polymesh_of_a_layered_mesh(rings, tmp_path):
    mesh = run(rings, layer(["hole"]))
    written = mesh.write(tmp_path / "wing", format="openfoam", walls=["box"])
    poly = tmp_path / "wing_openfoam" / "constant" / "polyMesh"
    assert sorted(os.path.basename(p) for p in written) == ["boundary", "faces", "neighbour", "owner", "points"]
    cells = len(mesh.triangles) + len(mesh.quads)
    n_points, _ = _foam_list(poly / "points")
    n_faces, faces = _foam_list(poly / "faces")
    n_owner, _ = _foam_list(poly / "owner")
    n_internal, _ = _foam_list(poly / "neighbour")
    assert n_points == 2 * len(mesh.points)
    assert n_owner == n_faces
    boundary = sum(len(e) for e in mesh.boundary_edges.values())
    assert n_faces == n_internal + boundary + 2 * cells
    # Every quad a hexahedron's two 4-point caps, every triangle a prism's two 3-point caps.
    assert faces.count("3(") == 2 * len(mesh.triangles)
    text = (poly / "boundary").read_text()
    # The layer's wall and the named wall are walls; the front and back one empty patch.
    for name, kind in (("box", "wall"), ("hole", "wall"), ("frontAndBack", "empty")):
        assert f"    {name}\n    {{\n        type            {kind};" in text
    with pytest.raises(pdmesh.InputError, match="walls: unknown curve 'nose'"):
        mesh.write(tmp_path / "bad", format="openfoam", walls=["nose"])
    assert not (tmp_path / "bad_openfoam").exists()


def test_cgns_of_a_layered_mesh(rings, tmp_path):
    # The suffix picks the CGNS writer; the file is HDF5 (its signature), written atomically.
    mesh = run(rings, layer(["hole"]))
    written = mesh.write(tmp_path / "wing.cgns", walls=["box"])
    assert written == [str(tmp_path / "wing.cgns")]
    assert (tmp_path / "wing.cgns").read_bytes()[:8] == b"\x89HDF\r\n\x1a\n"
    assert sorted(os.listdir(tmp_path)) == ["wing.cgns"]
    # The wall names are checked as for OpenFOAM, before anything is written.
    with pytest.raises(pdmesh.InputError, match="walls: unknown curve 'nose'"):
        mesh.write(tmp_path / "bad.cgns", walls=["nose"])
    assert not (tmp_path / "bad.cgns").exists()
