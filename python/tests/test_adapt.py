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
    """mesh is the command's output in `out`: its nodes bit for bit and its mesh.msh byte for byte,
    followed in Python's file by one $NodeData view per transferred array (the command writes the
    solution to solution.vtu instead)."""
    assert np.array_equal(mesh.points, read_nodes(out / "mesh.nodes"))
    written = pdmesh.Mesh.read(out / "mesh.msh")
    assert np.array_equal(mesh.points, written.points)
    assert np.array_equal(mesh.triangles, written.triangles)
    mesh.write(tmp_path / "python.msh")
    ours, command = (tmp_path / "python.msh").read_bytes(), (out / "mesh.msh").read_bytes()
    assert ours[:len(command)] == command
    views = ours[len(command):].decode().split("$EndNodeData\n")
    assert views[-1] == "" and len(views) - 1 == len(mesh.point_data)
    for view, name in zip(views, mesh.point_data):
        assert view.startswith(f'$NodeData\n1\n"{name}"\n')
    back = pdmesh.Mesh.read(tmp_path / "python.msh")
    assert back.point_data.keys() == mesh.point_data.keys()
    for name, values in mesh.point_data.items():
        assert np.array_equal(back.point_data[name], values)


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


@pytest.mark.parametrize("transfer", [True, False], ids=["transfer", "no-transfer"])
def test_out_writes_the_commands_files(problem, tmp_path, command, transfer):
    case, solution, _, _ = problem
    flags = [] if transfer else ["--no-transfer"]
    command("adapt", case, "--solution", solution, "--array", "u,v", "--complexity", 120, "--out", tmp_path / "cmd",
            "--quiet", *flags)
    mesh = pdmesh.adapt(case, solution, "u,v", complexity=120, transfer=transfer, out=tmp_path / "py")
    written = sorted(p.name for p in (tmp_path / "cmd").iterdir())
    assert ("solution.vtu" in written) == transfer and "mesh.msh" in written and "quality.json" in written
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == written
    # Every file byte for byte: the same run, the same writers (quality.json holds no timings).
    for name in written:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cmd" / name).read_bytes(), name
    assert np.array_equal(mesh.points, pdmesh.Mesh.read(tmp_path / "cmd" / "mesh.msh").points)
    assert sorted(mesh.point_data) == (["u", "v"] if transfer else [])


def test_the_transferred_values_are_the_commands_solution_vtu(problem, tmp_path, command):
    case, solution, coarse, data = problem
    command("adapt", case, "--solution", solution, "--array", "v", "--complexity", 100, "--out", tmp_path / "cmd",
            "--quiet", "--formats", "vtu")
    written = pdmesh.adapt(case, solution, "v", complexity=100, out=tmp_path / "py", output={"formats": ["vtu"]})
    assert (tmp_path / "py" / "solution.vtu").read_bytes() == (tmp_path / "cmd" / "solution.vtu").read_bytes()
    # Without out, the values on the mesh in memory are those of solution.vtu (whose mesh is the run's
    # mesh file read back) bit for bit; the file's arrays all come over (u too), one component each.
    mesh = pdmesh.adapt(case, solution, "v", complexity=100)
    assert np.array_equal(mesh.points, written.points)
    assert sorted(mesh.point_data) == ["u", "v"]
    for name in ("u", "v"):
        assert mesh.point_data[name].shape == (len(mesh.points),)
        assert np.array_equal(mesh.point_data[name], written.point_data[name])
        assert not mesh.point_data[name].flags.writeable
        # pdmesh.transfer from the file, from the solution's Mesh and from its arrays: the same values.
        assert np.array_equal(pdmesh.transfer(solution, name, mesh), mesh.point_data[name])
        assert np.array_equal(pdmesh.transfer(coarse, data[name], mesh.points), mesh.point_data[name])
        assert np.array_equal(pdmesh.transfer((coarse.points, coarse.triangles), data[name], mesh.points),
                              mesh.point_data[name])
    # A solution in memory comes over the same way, its values' keys as the arrays.
    pair = pdmesh.adapt(case, (coarse.points, coarse.triangles), "v", values=data, complexity=100)
    assert np.array_equal(pair.points, mesh.points)
    assert all(np.array_equal(pair.point_data[k], mesh.point_data[k]) for k in ("u", "v"))
    one = pdmesh.adapt(case, coarse, "v", values=data["v"], complexity=100)
    assert list(one.point_data) == ["v"] and np.array_equal(one.point_data["v"], mesh.point_data["v"])
    # A .vtu of the mesh holds them as point data.
    mesh.write(tmp_path / "m.vtu")
    assert {"u", "v"} <= set(pdmesh._core.point_array_names(str(tmp_path / "m.vtu")))


def test_transfer_takes_what_adapt_takes(problem):
    _, solution, coarse, data = problem
    at = coarse.points[::7] * 0.9
    both = np.c_[data["u"], data["v"]]
    pair = (coarse.points, coarse.triangles)
    from_mesh = pdmesh.transfer(coarse, both, at)
    assert from_mesh.shape == (len(at), 2)
    assert np.array_equal(pdmesh.transfer(pair, both, at), from_mesh)
    # Names of a file's arrays: all (None) or a list give a dict, one name its array.
    assert sorted(pdmesh.transfer(solution, None, at)) == ["u", "v"]
    moved = pdmesh.transfer(solution, ["v", "u"], at)
    assert np.array_equal(moved["u"], from_mesh[:, 0]) and np.array_equal(moved["v"], from_mesh[:, 1])
    # A dict of values gives a dict, from a Mesh and from a pair.
    for source in (coarse, pair):
        d = pdmesh.transfer(source, data, at)
        assert np.array_equal(d["u"], from_mesh[:, 0]) and np.array_equal(d["v"], from_mesh[:, 1])
    # A Mesh's own point_data by name.
    carried = pdmesh.Mesh(coarse._core.with_point_data([("u", data["u"].reshape(-1, 1))]))
    assert np.array_equal(pdmesh.transfer(carried, "u", at), from_mesh[:, 0])
    assert np.array_equal(pdmesh.transfer(carried, None, at)["u"], from_mesh[:, 0])


def test_array_is_split_at_commas(problem):
    case, solution, coarse, data = problem
    listed = pdmesh.adapt(case, solution, ["u", "v"], complexity=100, transfer=False)
    joined = pdmesh.adapt(case, solution, "u,v", complexity=100, transfer=False)
    assert np.array_equal(joined.points, listed.points) and np.array_equal(joined.triangles, listed.triangles)
    assert joined.point_data == {}
    pair = pdmesh.adapt(case, coarse, "u,v", values=data, complexity=100, transfer=False)
    assert np.array_equal(pair.points, listed.points)
    for bad in ("u,,v", "u,", ",v"):
        with pytest.raises(pdmesh.InputError, match=rf"array='{bad}': has an empty name between or beside its commas"):
            pdmesh.adapt(case, solution, bad, complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"array='': is empty"):
        pdmesh.adapt(case, solution, "", complexity=100)
    with pytest.raises(pdmesh.InputError, match=r"values: one array of values needs its name as array='NAME', got "
                                                r"array='u,v'"):
        pdmesh.adapt(case, coarse, "u,v", values=data["u"], complexity=100)


def test_out_and_transfer_errors_name_the_argument(problem, tmp_path):
    case, solution, coarse, data = problem
    # Refused before anything is written, as the command refuses them.
    out = tmp_path / "out"
    with pytest.raises(pdmesh.InputError, match=r"output.formats = \[png\] writes no mesh file .* give transfer=False"):
        pdmesh.adapt(case, solution, "u", complexity=100, out=out, output={"formats": ["png"]})
    assert not out.exists()
    (tmp_path / "again").mkdir()
    again = tmp_path / "again" / "solution.vtu"
    again.write_bytes(solution.read_bytes())
    with pytest.raises(pdmesh.InputError, match=r"solution=.*again/solution\.vtu is .*again/solution\.vtu, which this "
                                                r"run writes: give another out"):
        pdmesh.adapt(case, again, "u", complexity=100, out=tmp_path / "again")
    assert [p.name for p in (tmp_path / "again").iterdir()] == ["solution.vtu"]
    mesh_only = tmp_path / "mesh.vtu"
    coarse.write(mesh_only)
    with pytest.raises(pdmesh.InputError, match=r"solution: .*mesh\.vtu has no point data to transfer \(point arrays: "
                                                r"kind, q; .*give transfer=False"):
        pdmesh.adapt(case, mesh_only, "q", complexity=100)
    at = coarse.points[:5]
    with pytest.raises(pdmesh.InputError, match=r"no point array 'w' \(point arrays: u, v\)"):
        pdmesh.transfer(solution, "w", at)
    with pytest.raises(pdmesh.InputError, match=r"source: cannot read '.*missing\.vtu': no such file"):
        pdmesh.transfer(tmp_path / "missing.vtu", "u", at)
    with pytest.raises(pdmesh.InputError, match=r"values: a source file .* brings its own point data"):
        pdmesh.transfer(solution, data["u"], at)
    n = len(coarse.points)
    with pytest.raises(pdmesh.InputError, match=rf"values: one row per point of the source, shape \({n},\) .*got shape "
                                                rf"\({n - 1},\)"):
        pdmesh.transfer((coarse.points, coarse.triangles), data["u"][:-1], at)
    with pytest.raises(pdmesh.InputError, match=rf"values\['v'\]: one row per point .*got shape \(3,\)"):
        pdmesh.transfer(coarse, {"u": data["u"], "v": [1.0, 2.0, 3.0]}, at)
    with pytest.raises(pdmesh.InputError, match=r"values='u': the source Mesh has no point array 'u' \(point_data: "
                                                r"none\)"):
        pdmesh.transfer(coarse, "u", at)
    with pytest.raises(pdmesh.InputError, match=r"values: a \(points, triangles\) source needs the values"):
        pdmesh.transfer((coarse.points, coarse.triangles), "u", at)
    with pytest.raises(pdmesh.InputError, match=r"source: expected a pdmesh.Mesh, a \(points, triangles\) pair .*got "
                                                r"dict"):
        pdmesh.transfer({"u": 1}, data["u"], at)
    with pytest.raises(pdmesh.InputError, match=r"points: an \(M, 2\) array of points \(or a Mesh\) is needed, got "
                                                r"shape \(5, 3\)"):
        pdmesh.transfer(coarse, data["u"], np.c_[at, at[:, :1]])


def test_a_layered_mesh_carries_the_solution_too(problem, tmp_path, command):
    # With [[boundary_layer]] the command's solution.vtu is made on the mixed mesh (quads too).
    case, solution, _, _ = problem
    layered = tmp_path / "layered.toml"
    layered.write_text(case.read_text() + '[[boundary_layer]]\ncurves = ["hole"]\nfirst_height = 0.01\n'
                       'growth = 1.3\nthickness = 0.06\nelements = "quads"\n')
    command("adapt", layered, "--solution", solution, "--array", "u", "--complexity", 120, "--out", tmp_path / "cmd",
            "--quiet")
    written = pdmesh.adapt(layered, solution, "u", complexity=120, out=tmp_path / "py")
    assert len(written.quads) > 0
    names = sorted(p.name for p in (tmp_path / "cmd").iterdir())
    assert "solution.vtu" in names and sorted(p.name for p in (tmp_path / "py").iterdir()) == names
    for name in names:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cmd" / name).read_bytes(), name
    mesh = pdmesh.adapt(layered, solution, "u", complexity=120)
    assert all(np.array_equal(mesh.point_data[k], written.point_data[k]) for k in ("u", "v"))
