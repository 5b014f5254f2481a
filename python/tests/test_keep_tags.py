"""A Gmsh file's physical groups through the Python API: Mesh.read gives them, a re-mesh of the file
keeps them, and write gives them back (docs/mesh-formats.md, "Physical tags")."""

from __future__ import annotations

import numpy as np

import pdmesh
from conftest import SOURCE_DIR

FIXTURE = SOURCE_DIR / "tests" / "data" / "keep_tags" / "two_materials.msh"


def test_read_gives_the_files_groups():
    mesh = pdmesh.Mesh.read(FIXTURE)
    assert mesh.curve_groups == {5: ("walls", ["walls"])}
    assert mesh.region_names == {11.0: "steel", 22.0: "copper"}


def test_a_remesh_keeps_the_tags_and_reads_back(tmp_path):
    mesh = pdmesh.generate(pdmesh.Geometry.from_file(FIXTURE), device="host", seed=1)
    assert mesh.curve_groups == {5: ("walls", ["walls", "walls_2"])}
    assert set(mesh.regions.tolist()) == {11.0, 22.0}
    mesh.write(tmp_path / "m.msh")
    back = pdmesh.Mesh.read(tmp_path / "m.msh")
    assert back.curve_groups == {5: ("walls", ["walls"])}
    assert set(back.regions.tolist()) == {11.0, 22.0}
    assert back.region_names == {11.0: "steel", 22.0: "copper"}


LAYERED = SOURCE_DIR / "tests" / "data" / "layer_tags" / "cylinder.msh"
GROUPS = {5: ("wall", ["wall"]), 7: ("farfield", ["farfield", "farfield_2"]), 8: ("slip", ["slip", "slip_2"]),
          9: ("block", ["block"])}


def test_a_layered_mesh_keeps_the_groups_and_regions_and_reads_back(tmp_path):
    table = {"curves": ["wall"], "first_height": 0.005, "growth": 1.3, "thickness": 0.04, "elements": "quads"}
    mesh = pdmesh.generate(pdmesh.Geometry.from_file(LAYERED), boundary_layer=table, size=0.12, iterations=40,
                           device="host", seed=1)
    assert len(mesh.quads) > 0
    assert mesh.curve_groups == GROUPS
    assert set(mesh.regions.tolist()) == {11.0, 22.0}
    assert mesh.region_names == {11.0: "fluid", 22.0: "solid"}
    mesh.write(tmp_path / "m.msh")
    back = pdmesh.Mesh.read(tmp_path / "m.msh")
    assert len(back.quads) == len(mesh.quads)
    assert {tag: name for tag, (name, _) in back.curve_groups.items()} == {5: "wall", 7: "farfield", 8: "slip",
                                                                          9: "block"}
    core = np.asarray(back.triangle_layer) == 0
    assert set(np.asarray(back.regions)[core].tolist()) == {11.0, 22.0}
    assert back.region_names[11.0] == "fluid"
