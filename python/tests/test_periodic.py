"""Case files with [[periodic]] tables through the Python API: the image curve carries the source's
nodes, transformed exactly, as the command's mesh does; a table whose transform does not map the
curves onto each other is an InputError naming the case file."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

import pdmesh
from conftest import SOURCE_DIR

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
