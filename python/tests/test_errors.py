"""Bad inputs raise the typed exceptions with the command's messages."""

from __future__ import annotations

import re

import numpy as np
import pytest

import pdmesh
from conftest import write_crv


def command_message(result) -> str:
    """The command's error message without its 'pdmesh: error: ' prefix."""
    lines = [ln for ln in result.stderr.splitlines() if ln.startswith("pdmesh: error: ")]
    assert lines, result.stderr
    return lines[-1][len("pdmesh: error: "):]


def after_label(message: str) -> str:
    """A setting's message without the label that names where the value came from."""
    return message.split(": ", 1)[1]


def test_bad_setting_value_is_an_input_error_with_the_commands_text(rings, tmp_path, command):
    crv = write_crv(tmp_path / "shape.crv", rings)
    with pytest.raises(pdmesh.InputError) as api:
        pdmesh.generate(pdmesh.Geometry.from_file(crv), iterations=-3)
    cli = command("mesh", crv, "--out", tmp_path / "o", "--set", "simulation.iterations=-3", check=False)
    assert cli.returncode == 2
    assert str(api.value) == "simulation.iterations=-3: simulation.iterations must be >= 0, got -3"
    assert after_label(str(api.value)) == after_label(command_message(cli))


def test_unknown_key_suggests_the_nearest(rings):
    with pytest.raises(pdmesh.InputError, match=re.escape("unknown key 'simulation.iteratons'; did you mean "
                                                          "'simulation.iterations'?")):
        pdmesh.generate(rings, simulation={"iteratons": 5})
    with pytest.raises(pdmesh.InputError, match="init.method must be one of structured, random, hexagonal, hybrid, got 'hex'"):
        pdmesh.generate(rings, method="hex")


def test_geometry_errors(tmp_path, command):
    square = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], dtype=float)
    bow_tie = np.array([(0, 0), (1, 1), (1, 0), (0, 1)], dtype=float)
    with pytest.raises(pdmesh.GeometryError, match="intersect"):
        pdmesh.generate([bow_tie])
    open_curve = pdmesh.Geometry.from_curves([square])  # not closed: from_curves keeps curves open
    with pytest.raises(pdmesh.GeometryError) as api:
        pdmesh.generate(open_curve)
    crv = tmp_path / "open.crv"
    crv.write_text("4\n0 0\n1 0\n1 1\n0 1\n")
    cli = command("mesh", crv, "--out", tmp_path / "o", check=False)
    assert cli.returncode == 2
    # The same check and message; only the source differs: "curves[0]:POINT" here, "FILE:LINE" there.
    source = re.compile(r"\([^()]+:\d+\)")
    assert "(curves[0]:0)" in str(api.value)
    assert source.sub("(SOURCE)", str(api.value)) == source.sub("(SOURCE)", command_message(cli))
    with pytest.raises(pdmesh.InputError, match="cannot read|No such file"):
        pdmesh.generate(pdmesh.Geometry.from_file(tmp_path / "missing.crv"))
    with pytest.raises(pdmesh.InputError, match=r"rings\[0\]: expected an \(N, 2\) array"):
        pdmesh.Geometry([np.zeros((4, 5))])


def test_size_errors(rings):
    with pytest.raises(pdmesh.InputError, match="a size must be finite and > 0"):
        pdmesh.generate(rings, size=-1.0)
    with pytest.raises(pdmesh.InputError, match=r"size: the callable returned -0.5 at \("):
        pdmesh.Mesher(rings, size=lambda xy: np.full(len(xy), -0.5))
    with pytest.raises(pdmesh.InputError, match="one size per point"):
        pdmesh.Mesher(rings, size=lambda xy: np.ones(3))
    with pytest.raises(ZeroDivisionError):  # the callable's own errors pass through unchanged
        pdmesh.Mesher(rings, size=lambda xy: 1 / 0)


def test_device_and_limit_errors(rings):
    with pytest.raises(pdmesh.InputError, match="opencl:9:9"):
        pdmesh.generate(rings, device="opencl:9:9")
    with pytest.raises(pdmesh.LimitError, match="more than --max-nodes 100;") as e:
        pdmesh.generate(rings, size=0.02, max_nodes=100)
    assert isinstance(e.value, pdmesh.InputError)


def test_malformed_environment_variable_is_refused_before_anything_is_written(rings, tmp_path, monkeypatch):
    monkeypatch.setenv("PDMESH_MEASURE_OVERLAP", "off")
    out = tmp_path / "o"
    with pytest.raises(pdmesh.InputError, match=re.escape("PDMESH_MEASURE_OVERLAP must be 0, 1 or full, got 'off'")):
        pdmesh.Mesher(rings, out=out)
    assert not out.exists()
