"""The command line from Python: `python -m pdmesh` and the `pdmesh` console script run the same CLI
as the C++ binary; the package ships its type stubs."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pdmesh
from conftest import write_crv


def test_python_m_pdmesh_help():
    r = subprocess.run([sys.executable, "-m", "pdmesh", "--help"], capture_output=True, text=True)
    assert r.returncode == 0
    assert "mesh" in r.stdout and "quality" in r.stdout and "devices" in r.stdout


def test_python_m_pdmesh_mesh_and_exit_codes(rings, tmp_path):
    crv = write_crv(tmp_path / "shape.crv", rings)
    r = subprocess.run([sys.executable, "-m", "pdmesh", "mesh", str(crv), "--out", str(tmp_path / "o"),
                        "--iterations", "10", "--device", "host", "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "o" / "mesh.msh").exists() and (tmp_path / "o" / "quality.json").exists()
    bad = subprocess.run([sys.executable, "-m", "pdmesh", "mesh", str(crv), "--out", str(tmp_path / "o2"),
                          "--iterations", "-1"], capture_output=True, text=True)
    assert bad.returncode == 2
    assert "pdmesh: error: --iterations -1: simulation.iterations must be >= 0, got -1" in bad.stderr


def test_console_script_when_installed():
    # The venv's `pdmesh` script (tools/setup.sh installs the package); a build-tree run may lack it.
    script = Path(sys.executable).parent / "pdmesh"
    if not script.exists():
        script = shutil.which("pdmesh")
    assert script, "no pdmesh console script next to the interpreter or on PATH"
    r = subprocess.run([str(script), "--version"], capture_output=True, text=True)
    assert r.returncode == 0 and pdmesh.__version__ in r.stdout + r.stderr


def test_stubs_ship_with_the_package():
    stub = Path(pdmesh._core.__file__).with_name("_core.pyi")
    text = stub.read_text()
    for name in ("class Mesher", "class Mesh", "class Config", "def main", "def case_for_curves"):
        assert name in text
    assert Path(pdmesh.__file__).with_name("py.typed").exists()
