"""The Python API reads airfoil, GeoJSON and shapefile geometry through the command's readers."""

from __future__ import annotations

import math

import pytest

import pdmesh
from conftest import SOURCE_DIR

DATA = SOURCE_DIR / "tests" / "data" / "geometry"


@pytest.mark.parametrize("name, curves", [
    ("gis/lake.geojson", {"islet", "lake_shore", "lake_shore_hole1"}),
    ("gis/lake.shp", {"islet", "lake_shore", "lake_shore_hole1"}),
    ("airfoils/naca2412_lednicer.dat", {"upper", "lower", "te"}),
])
def test_from_file_meshes_the_new_formats_with_their_curve_names(name, curves):
    mesh = pdmesh.generate(pdmesh.Geometry.from_file(DATA / name), device="host", iterations=0)
    assert len(mesh.triangles) > 50
    assert set(mesh.curve_names) == curves


def test_projection_meshes_lonlat_in_metres():
    geo = pdmesh.Geometry.from_file(DATA / "gis" / "lonlat_square.geojson")
    mesh = pdmesh.generate(geo, device="host", iterations=0,
                           settings={"geometry.projection": "equirectangular", "spacing.expression": "1000"})
    # 0.1 degree of longitude about 50.05 degrees north (the box's centre); the Mesh stays in metres.
    width = mesh.points[:, 0].max() - mesh.points[:, 0].min()
    assert width == pytest.approx(6371008.8 * math.cos(math.radians(50.05)) * math.radians(0.1), rel=1e-12)


def test_malformed_geojson_is_an_input_error_naming_line_and_column():
    with pytest.raises(pdmesh.InputError, match=r"malformed\.geojson:4:2: malformed JSON"):
        pdmesh.generate(pdmesh.Geometry.from_file(SOURCE_DIR / "tests" / "data" / "bad" / "malformed.geojson"))
