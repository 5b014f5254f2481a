"""pdmesh.adapt: the command `pdmesh adapt` from Python. The same inputs give the command's mesh.msh
bit for bit (the case's [spacing] replaced, not merged), for one array and two; a solution in memory
(arrays or a Mesh) gives the mesh of the same data in a file; errors name the argument and value."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import pdmesh
from pdmesh.metric import write_vtu

from conftest import circle_in_square, read_nodes, write_crv

# Short runs on the host device: the equalities hold for any iteration count.
RUN = {"device": "host", "iterations": 150}


def layer(points: np.ndarray) -> dict[str, np.ndarray]:
    """Two solutions with layers across the domain: u along a wavy line, v around the hole."""
    x, y = points[:, 0], points[:, 1]
    return {"u": np.tanh(8.0 * (y - 0.3 * np.sin(2.0 * x))), "v": np.tanh(6.0 * (np.hypot(x, y) - 0.6))}


CASE = ('name = "cis"\n[geometry]\nfiles = ["shape.crv"]\ncurve_names = ["outer", "hole"]\n[init]\nseed = 3\n'
        f'[simulation]\niterations = {RUN["iterations"]}\ndevice = "host"\n')
# Two [spacing] tables the adaptation must replace: a uniform size (which the Hessian keys, merged,
# are refused with) and an earlier adaptation's keys (whose hmax, merged, would stay and change the mesh).
SPACINGS = {"size": "[spacing]\nsize = 0.3\n",
            "hessian": '[spacing]\nfield = "hessian"\nfile = "sol.vtu"\narray = "v"\ncomplexity = 40\nhmax = 0.1\n'}


@pytest.fixture
def problem(tmp_path):
    """The circle-in-square case with a uniform size, a solution file on a coarse mesh of it, the
    coarse mesh and the solution's values."""
    write_crv(tmp_path / "shape.crv", circle_in_square())
    coarse = pdmesh.generate(tmp_path / "shape.crv", size=0.15, seed=1, **RUN)
    points, triangles = np.array(coarse.points), np.array(coarse.triangles)
    data = layer(points)
    write_vtu(tmp_path / "sol.vtu", points, triangles, data)
    for name, spacing in SPACINGS.items():
        (tmp_path / f"{name}.toml").write_text(CASE + spacing)
    return tmp_path / "size.toml", tmp_path / "sol.vtu", coarse, data


def assert_same_mesh(mesh: pdmesh.Mesh, out: Path, tmp_path: Path) -> None:
    """mesh is the command's output in `out`: its nodes bit for bit and its mesh.msh byte for byte."""
    assert np.array_equal(mesh.points, read_nodes(out / "mesh.nodes"))
    written = pdmesh.Mesh.read(out / "mesh.msh")
    assert np.array_equal(mesh.points, written.points)
    assert np.array_equal(mesh.triangles, written.triangles)
    mesh.write(tmp_path / "python.msh")
    assert (tmp_path / "python.msh").read_bytes() == (out / "mesh.msh").read_bytes()


@pytest.mark.parametrize("spacing", list(SPACINGS))
@pytest.mark.parametrize("arrays", [["u"], ["u", "v"]], ids=["one-array", "two-arrays"])
def test_adapt_is_the_commands_mesh_with_the_spacing_replaced(problem, tmp_path, command, arrays, spacing):
    _, solution, _, _ = problem
    case = tmp_path / f"{spacing}.toml"
    out = tmp_path / "out"
    command("adapt", case, "--solution", solution, "--array", ",".join(arrays), "--complexity", 120, "--hmin", 0.01,
            "--out", out, "--quiet", "--formats", "msh")
    array = arrays if len(arrays) > 1 else arrays[0]
    mesh = pdmesh.adapt(case, solution, array, complexity=120, hmin=0.01)
    assert_same_mesh(mesh, out, tmp_path)
    # The command's solution.vtu holds the solution on the new mesh's points.
    assert np.array_equal(pdmesh.Mesh.read(out / "solution.vtu").points, mesh.points)
    # The same keys merged into the case's [spacing] (what settings do) are not the command's run.
    keys = {"field": "hessian", "file": str(solution), "array": array, "complexity": 120, "hmin": 0.01}
    if spacing == "size":
        with pytest.raises(pdmesh.InputError, match="spacing.size is set but spacing.field is 'hessian'"):
            pdmesh.generate(case, spacing=keys)
    else:
        merged = pdmesh.generate(case, spacing=keys)
        assert len(merged.points) != len(mesh.points) or not np.array_equal(merged.points, mesh.points)


def test_settings_apply_after_the_commands_keys(problem, tmp_path, command):
    case, solution, _, _ = problem
    out = tmp_path / "out"
    command("adapt", case, "--solution", solution, "--array", "u", "--complexity", 80, "--gradation", 2,
            "--set", "simulation.iterations=60", "--seed", 5, "--out", out, "--quiet", "--formats", "msh")
    mesh = pdmesh.adapt(str(case), str(solution), "u", complexity=80.0, gradation=2, seed=5, iterations=60)
    assert_same_mesh(mesh, out, tmp_path)


def test_a_solution_in_memory_is_the_same_as_its_file(problem, tmp_path):
    case, solution, coarse, data = problem
    from_file = pdmesh.adapt(case, solution, ["u", "v"], complexity=100, hmax=0.4)
    pair = pdmesh.adapt(case, (coarse.points, coarse.triangles), complexity=100, hmax=0.4, values=data)
    assert np.array_equal(pair.points, from_file.points) and np.array_equal(pair.triangles, from_file.triangles)
    # A Mesh with one array of values named by `array`, on a bare geometry (no case).
    one_file = pdmesh.adapt(tmp_path / "shape.crv", solution, "v", complexity=100, hmax=0.4, **RUN)
    one = pdmesh.adapt(pdmesh.Geometry.from_file(tmp_path / "shape.crv"), coarse, "v", values=data["v"],
                       complexity=100, hmax=0.4, **RUN)
    assert np.array_equal(one.points, one_file.points) and np.array_equal(one.triangles, one_file.triangles)
    # The solution carried over to the new mesh (the command's solution.vtu): linear interpolation
    # stays within the old values' range.
    moved = pdmesh.transfer(coarse, data["v"], one.points)
    assert moved.shape == (len(one.points),)
    assert data["v"].min() <= moved.min() and moved.max() <= data["v"].max()


def test_adapt_mesher_steps_the_same_run(problem):
    case, solution, _, _ = problem
    mesher = pdmesh.adapt_mesher(case, solution, "u", complexity=100)
    assert mesher.iteration == 0
    mesher.run()
    mesh = pdmesh.adapt(case, solution, "u", complexity=100)
    assert np.array_equal(mesher.triangulate().points, mesh.points)


def test_adapt_names_the_bad_argument(problem, tmp_path):
    case, solution, coarse, data = problem
    with pytest.raises(pdmesh.InputError, match=r"array='w': .*sol\.vtu has no point array 'w' \(point arrays: u, v\)"):
        pdmesh.adapt(case, solution, "w", complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"array='w': the solution has no point array 'w' \(point arrays: u\)"):
        pdmesh.adapt(case, coarse, "w", values={"u": data["u"]}, complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"solution: cannot read '.*missing\.vtu': no such file"):
        pdmesh.adapt(case, tmp_path / "missing.vtu", "u", complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"array: name the solution's point array"):
        pdmesh.adapt(case, solution, complexity=100)
    n = len(coarse.points)
    with pytest.raises(pdmesh.InputError, match=rf"values\['u'\]: one value per point, shape \({n},\), .*got shape "
                                                rf"\({n - 1},\)"):
        pdmesh.adapt(case, coarse, values={"u": data["u"][:-1]}, complexity=100)
    with pytest.raises(pdmesh.InputError, match=rf"got shape \({n}, 2\)"):
        pdmesh.adapt(case, coarse, "u", values=np.c_[data["u"], data["v"]], complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"values: one array of values needs its name"):
        pdmesh.adapt(case, coarse, values=data["u"], complexity=100)
    with pytest.raises(pdmesh.InputError,
                       match=r"values: a solution given as a Mesh or \(points, triangles\) needs its point values"):
        pdmesh.adapt(case, coarse, "u", complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"values: a solution file .* brings its own point data"):
        pdmesh.adapt(case, solution, "u", values=data, complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"solution: points must be an \(N, 2\) array"):
        pdmesh.adapt(case, (coarse.points[:, :1], coarse.triangles), values=data, complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"solution: triangle 0 .* names a node that is not one of"):
        pdmesh.adapt(case, (coarse.points, coarse.triangles + n), values=data, complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"complexity=0: spacing.complexity must be > 0"):
        pdmesh.adapt(case, solution, "u", complexity=0)
    with pytest.raises(pdmesh.InputError, match=r"complexity=-5.0: spacing.complexity"):
        pdmesh.adapt(case, solution, "u", complexity=-5.0)
