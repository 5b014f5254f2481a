"""Case files with [[periodic]] tables through the Python API: the image curve carries the source's
nodes, transformed exactly, as the command's mesh does; a table whose transform does not map the
curves onto each other is an InputError naming the case file; Mesh.periodic holds the pairs that the
run's mesh.msh writes into its $Periodic section (read back here by meshio, a reader of its own)."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

import pdmesh
from conftest import SOURCE_DIR, circle_in_square

CELL = SOURCE_DIR / "tests" / "data" / "periodic" / "cell.toml"


def side_coordinates(points, axis, value):
    """The other coordinate of the points whose `axis` coordinate is exactly `value`, sorted."""
    other = 1 - axis
    return np.sort(points[points[:, axis] == value][:, other])


def test_a_unit_cell_carries_the_same_nodes_on_opposite_sides(tmp_path, command):
    mesh = pdmesh.Case.from_toml(CELL).run(device="host")
    left, right = side_coordinates(mesh.points, 0, 0.0), side_coordinates(mesh.points, 0, 1.0)
    bottom, top = side_coordinates(mesh.points, 1, 0.0), side_coordinates(mesh.points, 1, 1.0)
    # Several nodes per side (size 0.08 on a unit side), and the same ones, bit for bit, across.
    assert len(left) > 8 and len(bottom) > 8
    assert np.array_equal(left, right)
    assert np.array_equal(bottom, top)
    # The command's mesh of the same case file: the same triangles.
    command("mesh", CELL, "--out", tmp_path / "out", "--quiet", "--formats", "msh", "--device", "host")
    written = pdmesh.Mesh.read(tmp_path / "out" / "mesh.msh")
    assert np.array_equal(mesh.triangles, written.triangles)


def test_a_translation_that_misses_the_image_is_an_input_error(tmp_path):
    shutil.copy(CELL.parent / "cell.crv", tmp_path / "cell.crv")
    text = CELL.read_text().replace("translate = [0, 1]", "translate = [0, 0.9]")
    assert "translate = [0, 0.9]" in text
    case = tmp_path / "case.toml"
    case.write_text(text)
    with pytest.raises(pdmesh.InputError, match=r"case\.toml.*does not map 'bottom' onto 'top'"):
        pdmesh.Case.from_toml(case).run(device="host")


CHANNEL = SOURCE_DIR / "tests" / "data" / "periodic" / "channel.toml"


def test_a_channel_with_layers_carries_the_inlets_nodes_on_the_outlet(tmp_path, command):
    # [[periodic]] with [[boundary_layer]]: the layers' end columns on the inlet and the outlet are
    # the same, and so are the core's nodes above them.
    mesh = pdmesh.Case.from_toml(CHANNEL).run(device="host")
    inlet, outlet = side_coordinates(mesh.points, 0, 0.0), side_coordinates(mesh.points, 0, 2.0)
    assert len(inlet) > 20
    assert np.array_equal(inlet, outlet)
    assert inlet[1] == pytest.approx(0.002)  # the first layer's height over the bottom wall
    command("mesh", CHANNEL, "--out", tmp_path / "out", "--quiet", "--formats", "msh", "--device", "host")
    written = pdmesh.Mesh.read(tmp_path / "out" / "mesh.msh")
    assert np.array_equal(np.sort(mesh.points, axis=0), np.sort(written.points, axis=0))


SECTOR = SOURCE_DIR / "tests" / "data" / "periodic" / "sector.toml"


def msh_periodic(path):
    """The $Periodic links of an MSH 4.1 file as meshio reads them: (image entity tag, source entity
    tag), the 16 affine values and the (image, source) node tags less one, in file order."""
    meshio = pytest.importorskip("meshio")
    m = meshio.read(path)
    assert m.gmsh_periodic is not None, f"{path} has no $Periodic section"
    return m, [((int(tags[0]), int(tags[1])), np.asarray(affine), np.asarray(pairs))
               for _dim, tags, affine, pairs in m.gmsh_periodic]


def check_pairs_against_msh(mesh, path):
    """Mesh.periodic is what the run's mesh.msh holds, bit for bit: the same points, the same pairs
    in the same order, the same affine values; each pair's image point is the transform of its
    source point exactly, and the pairs cover every node of both curves."""
    written, links = msh_periodic(path)
    # meshio's node indices are the file's tags less one; the points are the file's (17 digits).
    assert np.array_equal(written.points[:, :2], mesh.points)
    assert len(mesh.periodic) == len(links)
    names = mesh.curve_names
    for p, ((image_tag, source_tag), affine, pairs) in zip(mesh.periodic, links):
        # The writer's curve entity tags are the curve indices plus one.
        assert (names[image_tag - 1], names[source_tag - 1]) == (p.image, p.source)
        assert p.nodes.dtype == np.int32 and p.nodes.shape == pairs.shape
        assert np.array_equal(p.nodes, pairs)
        assert p.affine.shape == (4, 4)
        assert np.array_equal(p.affine.ravel(), affine)
        assert p.max_mismatch == 0.0
        image, source = mesh.points[p.nodes[:, 0]], mesh.points[p.nodes[:, 1]]
        mapped = source @ p.affine[:2, :2].T + p.affine[:2, 3]
        assert np.allclose(mapped, image, rtol=0, atol=1e-14)
        for curve, column in ((p.image, 0), (p.source, 1)):
            on_curve = np.unique(mesh.boundary_edges[curve])
            assert np.array_equal(np.sort(p.nodes[:, column]), on_curve)
    assert np.array_equal(mesh.periodic_nodes, np.concatenate([p.nodes for p in mesh.periodic]))


def test_the_pairs_of_a_translated_cell_are_the_msh_files(tmp_path):
    mesh = pdmesh.Case.from_toml(CELL).run(device="host", out=tmp_path / "out", formats=["msh"])
    pairs = {(p.source, p.image): p for p in mesh.periodic}
    assert list(pairs) == [("left", "right"), ("bottom", "top")]
    # left -> right is inferred from the curves' ends, bottom -> top given.
    assert pairs["left", "right"].kind == "translate" and pairs["left", "right"].translate == (1.0, 0.0)
    assert pairs["bottom", "top"].kind == "translate" and pairs["bottom", "top"].translate == (0.0, 1.0)
    assert pairs["left", "right"].center is None and pairs["left", "right"].angle_deg is None
    for p in mesh.periodic:
        image, source = mesh.points[p.nodes[:, 0]], mesh.points[p.nodes[:, 1]]
        assert len(p.nodes) > 8
        assert np.array_equal(image, source + np.array(p.translate))
    check_pairs_against_msh(mesh, tmp_path / "out" / "mesh.msh")


def test_the_pairs_of_a_rotated_sector_are_the_msh_files(tmp_path):
    mesh = pdmesh.Case.from_toml(SECTOR).run(device="host", out=tmp_path / "out", formats=["msh"])
    (p,) = mesh.periodic
    assert (p.source, p.image, p.kind) == ("r0", "r60", "rotate")
    assert p.center == (0.0, 0.0) and p.angle_deg == pytest.approx(60.0, abs=1e-12) and p.translate is None
    source = mesh.points[p.nodes[:, 1]]
    assert np.array_equal(source[:, 1], np.zeros(len(source)))  # the side at 0 degrees
    check_pairs_against_msh(mesh, tmp_path / "out" / "mesh.msh")


def test_pairs_written_by_mesh_write_and_read_back(tmp_path):
    mesh = pdmesh.Case.from_toml(SECTOR).run(device="host")
    # Mesh.write's msh files carry the pairs as the run's mesh.msh does.
    mesh.write(tmp_path / "sector.msh")
    check_pairs_against_msh(mesh, tmp_path / "sector.msh")
    # Mesh.read gives them back, the transform read off the file's affine matrix.
    read = pdmesh.Mesh.read(tmp_path / "sector.msh")
    (p,), (q,) = mesh.periodic, read.periodic
    assert (q.source, q.image, q.kind) == (p.source, p.image, "rotate")
    assert np.array_equal(q.nodes, p.nodes) and np.array_equal(q.affine, p.affine)
    assert q.angle_deg == pytest.approx(60.0, abs=1e-12)
    assert q.center == pytest.approx((0.0, 0.0), abs=1e-12)
    # MSH 2.2 ($Periodic with an "Affine" line) as well.
    mesh.write(tmp_path / "sector22.msh", format="msh22")
    (q22,) = pdmesh.Mesh.read(tmp_path / "sector22.msh").periodic
    assert np.array_equal(q22.nodes, p.nodes) and np.array_equal(q22.affine, p.affine)


def test_a_channel_with_layers_has_the_columns_among_its_pairs(tmp_path):
    mesh = pdmesh.Case.from_toml(CHANNEL).run(device="host", out=tmp_path / "out", formats=["msh"])
    (p,) = mesh.periodic
    assert (p.source, p.image, p.kind, p.translate) == ("inlet", "outlet", "translate", (2.0, 0.0))
    image, source = mesh.points[p.nodes[:, 0]], mesh.points[p.nodes[:, 1]]
    assert np.array_equal(image[:, 1], source[:, 1])
    # The first layer's node above the bottom wall is paired, as every layer node on the inlet.
    assert np.any(np.isclose(source[:, 1], 0.002, rtol=0, atol=1e-12))
    check_pairs_against_msh(mesh, tmp_path / "out" / "mesh.msh")


def test_a_mesh_without_tables_has_no_pairs_and_no_error(tmp_path):
    square, circle = circle_in_square()
    mesh = pdmesh.generate([square, circle], iterations=20, seed=1)
    assert mesh.periodic == []
    assert mesh.periodic_nodes.shape == (0, 2) and mesh.periodic_nodes.dtype == np.int32
    mesh.write(tmp_path / "plain.msh")
    assert "$Periodic" not in (tmp_path / "plain.msh").read_text()
    assert pdmesh.Mesh.read(tmp_path / "plain.msh").periodic == []


@pytest.mark.parametrize("case", [CELL, CHANNEL], ids=["cell", "channel_with_layers"])
def test_to_meshio_carries_the_pairs_into_meshio_s_msh(tmp_path, case):
    # meshio.write of Mesh.to_meshio() to .msh keeps $Periodic: the same links as the run's own
    # mesh.msh (entity tags, affine values, (image, source) node tags, in order), in MSH 4.1 and 2.2.
    # meshio's 4.1 writer groups the nodes by entity, so its file lists them in another order under
    # the same tags: meshio's own reader then gives the points in file order (and the pairs by tag),
    # pdmesh's reader maps the tags.
    meshio = pytest.importorskip("meshio")
    mesh = pdmesh.Case.from_toml(case).run(device="host", out=tmp_path / "out", formats=["msh"])
    _, run_links = msh_periodic(tmp_path / "out" / "mesh.msh")
    m = mesh.to_meshio()
    assert len(m.gmsh_periodic) == len(mesh.periodic) > 0
    # meshio 5.3 does not read back the cell data "boundary_layer" of its own ASCII files (its writer
    # formats values by repr, with numpy 2 "np.int32(0)") nor of its binary 2.2 files: meshio reads
    # its binary 4.1 file here, pdmesh's reader (which skips the data) the ASCII ones.
    meshio.write(tmp_path / "binary.msh", m, file_format="gmsh")
    meshio.write(tmp_path / "ascii.msh", m, file_format="gmsh", binary=False)
    meshio.write(tmp_path / "ascii22.msh", m, file_format="gmsh22", binary=False)
    for name in ("binary.msh",):
        back, links = msh_periodic(tmp_path / name)
        assert len(back.points) == len(mesh.points)
        assert len(links) == len(run_links)
        for (tags, affine, pairs), (run_tags, run_affine, run_pairs) in zip(links, run_links):
            assert tags == run_tags
            assert np.array_equal(affine, run_affine)
            assert np.array_equal(pairs, run_pairs)
    # pdmesh reads meshio's ASCII files: the same curves and the same pairs, point for point.
    for name in ("ascii.msh", "ascii22.msh"):
        read = pdmesh.Mesh.read(tmp_path / name)
        assert read.curve_names == mesh.curve_names, name
        assert len(read.triangles) == len(mesh.triangles) and len(read.quads) == len(mesh.quads)
        assert [(q.source, q.image) for q in read.periodic] == [(p.source, p.image) for p in mesh.periodic]
        for q, p in zip(read.periodic, mesh.periodic):
            assert np.array_equal(read.points[q.nodes], mesh.points[p.nodes])
            assert np.array_equal(q.affine, p.affine)
