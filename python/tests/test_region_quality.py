"""Quality per region: Mesh.quality() of a mesh with regions has quality.json's "regions" (one dict
per attribute, the top level's figures of that region's triangles); a mesh without regions has none."""

from __future__ import annotations

import numpy as np

import pdmesh
from conftest import SOURCE_DIR

SQUARE = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
INCLUSION = np.array([[0.3, 0.3], [0.7, 0.3], [0.7, 0.7], [0.3, 0.7], [0.3, 0.3]])


def check_regions_add_up(q):
    regions = q["regions"]
    assert [r["attribute"] for r in regions] == sorted(r["attribute"] for r in regions)
    assert sum(r["triangles"] for r in regions) == q["triangles"]
    assert all(r["included_angle"]["min"] >= q["included_angle"]["min"] for r in regions)
    assert any(r["included_angle"]["min"] == q["included_angle"]["min"] for r in regions)


def test_generate_reports_each_region_the_refined_one_finer():
    g = pdmesh.Geometry([SQUARE], constraints=[INCLUSION], regions={"matrix": (0.1, 0.1), "steel": (0.5, 0.5)})
    mesh = pdmesh.generate(g, settings={"spacing.size": 0.1}, refine=[{"shape": "region", "region": "steel",
                                                                       "size": 0.03}], device="host", seed=1)
    q = mesh.quality()
    check_regions_add_up(q)
    matrix, steel = q["regions"]
    assert (matrix["attribute"], matrix["name"]) == (1.0, "matrix")
    assert (steel["attribute"], steel["name"]) == (2.0, "steel")
    # The refined inclusion (0.16 of the area) has the more triangles per area.
    assert steel["triangles"] / 0.16 > 3 * matrix["triangles"] / 0.84
    assert steel["triangles"] == int(np.count_nonzero(mesh.regions == 2.0))
    assert steel["included_angle"]["min"] == min(q["per_triangle"]["min_angle"][mesh.regions == 2.0])
    # The run's field: conformance per region, the interface's edges in both.
    edges = q["spacing_conformance"]["edges"]
    assert matrix["spacing_conformance"]["edges"] + steel["spacing_conformance"]["edges"] > edges
    assert 0.7 < steel["spacing_conformance"]["mean"] < 1.3


def test_a_mesh_file_with_two_physical_surfaces():
    mesh = pdmesh.Mesh.read(SOURCE_DIR / "tests" / "data" / "region_quality" / "two_materials.msh")
    q = mesh.quality()
    check_regions_add_up(q)
    assert [r["name"] for r in q["regions"]] == ["steel", "copper"]
    assert q["regions"][1]["triangles"] > q["regions"][0]["triangles"]


def test_no_regions_no_key():
    mesh = pdmesh.generate(pdmesh.Geometry([SQUARE]), device="host", seed=1)
    assert "regions" not in mesh.quality()
