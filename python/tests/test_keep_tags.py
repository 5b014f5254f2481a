"""A Gmsh file's physical groups through the Python API: Mesh.read gives them, a re-mesh of the file
keeps them, and write gives them back (docs/mesh-formats.md, "Physical tags")."""

from __future__ import annotations

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
