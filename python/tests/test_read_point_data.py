"""Mesh.read gives a file's point arrays: a .vtu's PointData in every encoding the reader takes, a
.msh's $NodeData views (2.2 and 4.1, the last time step of a name); q is the spacing, a .vtu's kind
the kinds; Mesh.write then Mesh.read gives the arrays back bit for bit; a malformed array is an
InputError naming the file, the line and the value."""

from __future__ import annotations

import numpy as np
import pytest

import pdmesh
from conftest import SOURCE_DIR

SPACING_DATA = SOURCE_DIR / "tests" / "data" / "spacing"
VTU_FIXTURES = ["vtk_ascii.vtu", "vtk_default.vtu", "vtk_binary_zlib.vtu", "vtk_binary_bigendian.vtu",
                "vtk_appended_raw_u64.vtu", "vtk_appended_raw_zlib.vtu", "meshio_binary_zlib.vtu"]


def expected_q() -> np.ndarray:
    """The fixtures' field q at their 25 points, as expected.txt holds it (x y q, 17 digits)."""
    return np.loadtxt(SPACING_DATA / "expected.txt")[:, 2]


@pytest.mark.parametrize("name", VTU_FIXTURES)
def test_vtu_point_arrays_in_every_encoding(name):
    # VTK's and meshio's writers: q (the spacing) and a 3-component "velocity" = (y, -x, 0).
    m = pdmesh.Mesh.read(SPACING_DATA / name)
    np.testing.assert_array_equal(m.spacing, expected_q())
    if name.startswith("meshio"):
        assert m.point_data == {}  # meshio's fixture holds q alone
        return
    assert list(m.point_data) == ["velocity"]
    p = np.asarray(m.points)
    velocity = m.point_data["velocity"]
    assert velocity.shape == (25, 3) and velocity.dtype == np.float64
    np.testing.assert_array_equal(velocity, np.c_[p[:, 1], -p[:, 0], np.zeros(25)])


@pytest.mark.parametrize("binary", [False, True])
def test_vtu_written_by_meshio(tmp_path, binary):
    meshio = pytest.importorskip("meshio")
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 0.0]])
    triangles = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    u, w = solution(points[:, :2])
    path = tmp_path / "solver.vtu"
    meshio.write(path, meshio.Mesh(points, [("triangle", triangles)], point_data={"u": u, "w": w}), binary=binary)
    m = pdmesh.Mesh.read(path)
    assert list(m.point_data) == ["u", "w"] and len(m.spacing) == 0
    if binary:
        np.testing.assert_array_equal(m.point_data["u"], u)
        np.testing.assert_array_equal(m.point_data["w"], w)
    else:  # meshio's ASCII form prints 12 significant digits
        np.testing.assert_allclose(m.point_data["u"], u, rtol=1e-11, atol=0)
        np.testing.assert_allclose(m.point_data["w"], w, rtol=1e-11, atol=1e-300)


@pytest.mark.parametrize("binary", [False, True])
def test_integer_arrays_stay_integers(tmp_path, binary):
    # A solver's integer point arrays (markers, ids) come back as int64, exact, and are written back
    # as integers: meshio reads them again with an integer type.
    meshio = pytest.importorskip("meshio")
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 0.0]])
    triangles = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    marker = np.array([3, 1, 4, 1, -5], dtype=np.int32)
    ids = np.array([2**40, 7, 0, 1, 2**40 + 1], dtype=np.int64)
    path = tmp_path / "solver.vtu"
    meshio.write(path, meshio.Mesh(points, [("triangle", triangles)],
                                   point_data={"marker": marker, "id": ids, "u": points[:, 0] * 0.5}), binary=binary)
    m = pdmesh.Mesh.read(path)
    assert m.point_data["marker"].dtype == np.int64 and m.point_data["id"].dtype == np.int64
    assert m.point_data["u"].dtype == np.float64
    np.testing.assert_array_equal(m.point_data["marker"], marker)
    np.testing.assert_array_equal(m.point_data["id"], ids)
    m.write(tmp_path / "back.vtu")
    back = meshio.read(tmp_path / "back.vtu")
    assert np.issubdtype(back.point_data["marker"].dtype, np.integer)
    np.testing.assert_array_equal(back.point_data["id"], ids)
    np.testing.assert_array_equal(pdmesh.Mesh.read(tmp_path / "back.vtu").point_data["marker"], marker)


def node_data(name: str, time: float, values: np.ndarray) -> str:
    """A $NodeData view as Gmsh writes it (node tag = point index + 1), values with 17 digits."""
    rows = values.reshape(len(values), -1)
    lines = ["$NodeData", "1", f'"{name}"', "1", repr(time), "3", "0", str(rows.shape[1]), str(len(rows))]
    lines += [f"{i + 1} " + " ".join(f"{v:.17g}" for v in row) for i, row in enumerate(rows)]
    return "\n".join(lines + ["$EndNodeData"]) + "\n"


@pytest.fixture
def square(tmp_path) -> pdmesh.Mesh:
    """A pdmesh mesh of the unit square, read back from its .vtu (no point data of its own)."""
    sq = tmp_path / "square.crv"
    sq.write_text("5\n0 0\n1 0\n1 1\n0 1\n0 0\n")
    mesh = pdmesh.generate(str(sq), size=0.25, device="host", seed=1)
    return mesh


def solution(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A scalar and a 2-component field whose values need all 17 digits."""
    u = np.sin(3.0 * points[:, 0]) * np.exp(points[:, 1]) / 3.0
    w = np.c_[points[:, 0] / 7.0 + 1e-300, -points[:, 1] * np.pi]
    return u, w


@pytest.mark.parametrize("fmt", ["msh", "msh22"])
def test_msh_node_data_scalar_and_two_components_last_time_step(square, tmp_path, fmt):
    path = tmp_path / "m.msh"
    square.write(path, format=fmt)
    p = np.asarray(square.points)
    u, w = solution(p)
    # Two time steps of "u": the second is the one read. "w" has two components.
    text = path.read_text() + node_data("u", 0.0, u + 5.0) + node_data("w", 0.0, w) + node_data("u", 1.0, u)
    path.write_text(text)
    m = pdmesh.Mesh.read(path)
    assert list(m.point_data) == ["u", "w"]
    np.testing.assert_array_equal(m.points, p)
    assert m.point_data["u"].shape == (len(p),)
    np.testing.assert_array_equal(m.point_data["u"], u)
    assert m.point_data["w"].shape == (len(p), 2)
    np.testing.assert_array_equal(m.point_data["w"], w)
    # The run's spacing field, written as the view "q", is the spacing again.
    np.testing.assert_array_equal(m.spacing, square.spacing)


def test_msh_view_of_some_nodes_has_nan_elsewhere(square, tmp_path):
    path = tmp_path / "m.msh"
    square.write(path)
    n = len(square.points)
    text = path.read_text() + "$NodeData\n1\n\"s\"\n1\n0\n3\n0\n1\n2\n1 0.5\n3 -2\n$EndNodeData\n"
    path.write_text(text)
    s = pdmesh.Mesh.read(path).point_data["s"]
    assert s[0] == 0.5 and s[2] == -2.0
    assert np.isnan(np.delete(s, [0, 2])).all() and len(s) == n


@pytest.mark.parametrize("fmt", ["vtu", "msh", "msh22"])
def test_write_then_read_is_a_round_trip(square, tmp_path, fmt):
    p = np.asarray(square.points)
    u, w = solution(p)
    u[3] = np.nan  # a solver's missing value; the .msh keeps it, the .vtu writes +-1e300 for it
    with_data = pdmesh.Mesh(square._core.with_point_data(
        [("u", np.ascontiguousarray(u.reshape(-1, 1))), ("w", np.ascontiguousarray(w))]))
    suffix = ".vtu" if fmt == "vtu" else ".msh"
    path = tmp_path / f"m{suffix}"
    with_data.write(path, format=fmt)
    back = pdmesh.Mesh.read(path)
    np.testing.assert_array_equal(back.spacing, square.spacing)
    if fmt == "vtu":
        np.testing.assert_array_equal(back.kinds, square.kinds)
        u[3] = 1e300
    else:
        assert len(back.kinds) == 0  # MSH has no node kinds
        assert path.read_text().count("$NodeData") == 3  # q, u, w: views Gmsh opens
    assert list(back.point_data) == ["u", "w"]
    np.testing.assert_array_equal(back.point_data["u"], u)  # bit for bit
    np.testing.assert_array_equal(back.point_data["w"], w)
    # Written again, the same file.
    again = tmp_path / f"again{suffix}"
    back.write(again, format=fmt)
    assert again.read_bytes() == path.read_bytes()


def test_adapt_solution_reads_back(tmp_path):
    # pdmesh.adapt's point data is what its solution.vtu holds.
    sq = tmp_path / "square.crv"
    sq.write_text("5\n0 0\n1 0\n1 1\n0 1\n0 0\n")
    source = pdmesh.generate(str(sq), size=0.1, device="host", seed=1)
    p = np.asarray(source.points)
    sol = tmp_path / "sol.vtu"
    pdmesh.Mesh(source._core.with_point_data([("u", np.ascontiguousarray((p[:, 0] ** 2).reshape(-1, 1)))])).write(sol)
    out = tmp_path / "run"
    adapted = pdmesh.adapt(str(sq), str(sol), "u", complexity=200, hmin=1e-3, hmax=0.3, device="host", seed=1,
                           out=out)
    read = pdmesh.Mesh.read(out / "solution.vtu")
    np.testing.assert_array_equal(read.points, adapted.points)
    np.testing.assert_array_equal(read.point_data["u"], adapted.point_data["u"])


def test_transfer_from_a_file_reads_every_array_asked_for(tmp_path):
    sq = tmp_path / "square.crv"
    sq.write_text("5\n0 0\n1 0\n1 1\n0 1\n0 0\n")
    source = pdmesh.generate(str(sq), size=0.2, device="host", seed=1)
    p = np.asarray(source.points)
    u, w = solution(p)
    path = tmp_path / "sol.vtu"
    pdmesh.Mesh(source._core.with_point_data(
        [("u", np.ascontiguousarray(u.reshape(-1, 1))), ("w", np.ascontiguousarray(w))])).write(path)
    target = p * 0.9 + 0.05
    moved = pdmesh.transfer(str(path), ["w", "u"], target)
    assert list(moved) == ["w", "u"]
    # The same values as one array at a time, and as from the mesh in memory.
    for name, values in (("u", u), ("w", w)):
        np.testing.assert_array_equal(moved[name], pdmesh.transfer(str(path), [name], target)[name])
        np.testing.assert_array_equal(moved[name], pdmesh.transfer(source, values, target))
    every = pdmesh.transfer(str(path), None, target)
    assert list(every) == ["u", "w"]
    np.testing.assert_array_equal(every["u"], moved["u"])
    np.testing.assert_array_equal(pdmesh.transfer(str(path), "u", target), moved["u"])


MALFORMED = {
    # file name, text after the mesh, the words the message must hold
    "bad_number.msh": ("$NodeData\n1\n\"u\"\n1\n0\n3\n0\n1\n2\n1 0.5\n2 0.5x\n$EndNodeData\n",
                       ["node value of $NodeData 'u'", "'0.5x'"]),
    "short_count.msh": ("$NodeData\n1\n\"u\"\n1\n0\n3\n0\n1\n3\n1 0.5\n2 0.25\n$EndNodeData\n",
                        ["node tag", "$EndNodeData"]),
}


@pytest.mark.parametrize("name", sorted(MALFORMED))
def test_malformed_node_data_names_file_line_and_value(square, tmp_path, name):
    path = tmp_path / name
    square.write(path)
    text = path.read_text()
    tail, words = MALFORMED[name]
    path.write_text(text + tail)
    with pytest.raises(pdmesh.InputError) as e:
        pdmesh.Mesh.read(path)
    message = str(e.value)
    assert f"{path}:" in message
    line = int(message.split(f"{path}:")[1].split(":")[0])
    assert line > text.count("\n")  # in the appended view
    for word in words:
        assert word in message


def test_malformed_vtu_array_names_file_line_array_and_value(tmp_path):
    text = (SPACING_DATA / "vtk_ascii.vtu").read_text()
    start = text.index('Name="velocity"')
    bad = text[:start] + text[start:].replace("0.25", "0.25e", 1)
    path = tmp_path / "bad.vtu"
    path.write_text(bad)
    with pytest.raises(pdmesh.InputError) as e:
        pdmesh.Mesh.read(path)
    message = str(e.value)
    assert f"{path}:" in message and "DataArray 'velocity'" in message and "'-0.25e'" in message
    # Too few values: the count named.
    short = text[:start] + text[start:].replace("0 -0 0 0 -0.25 0", "0 -0.25 0", 1)
    path.write_text(short)
    with pytest.raises(pdmesh.InputError, match=r"'velocity' holds 72 values, expected 3 components x 25 points"):
        pdmesh.Mesh.read(path)


def test_transfer_command_exits_2_on_a_malformed_view(square, tmp_path, command):
    path = tmp_path / "bad.msh"
    square.write(path)
    path.write_text(path.read_text() + MALFORMED["bad_number.msh"][0])
    target = tmp_path / "target.vtu"
    square.write(target)
    r = command("transfer", path, target, "--out", tmp_path / "moved.vtu", check=False)
    assert r.returncode == 2, r.stderr
    assert f"{path}:" in r.stderr and "'0.5x'" in r.stderr


def test_layered_vtu_round_trip_keeps_every_array(rings, tmp_path):
    # A layered mesh's .vtu (the mixed writer, ASCII with 17 digits) reads back with its arrays bit
    # for bit, q as the spacing (and kept among the arrays the mixed writer writes): written again,
    # the same file.
    geometry = pdmesh.Geometry(rings, names=["box", "hole"])
    table = {"curves": ["hole"], "first_height": 1e-3, "growth": 1.2, "thickness": 0.03, "elements": "quads"}
    mesh = pdmesh.generate(geometry, boundary_layer=table, iterations=20, device="host")
    assert len(mesh.quads) > 0
    u, w = solution(np.asarray(mesh.points))
    q = 0.01 + np.asarray(mesh.points)[:, 0] / 3.0
    with_data = pdmesh.Mesh(mesh._core.with_point_data(
        [("q", q.reshape(-1, 1)), ("u", np.ascontiguousarray(u.reshape(-1, 1))), ("w", np.ascontiguousarray(w))]))
    with_data.write(tmp_path / "m.vtu")
    back = pdmesh.Mesh.read(tmp_path / "m.vtu")
    assert len(back.quads) == len(mesh.quads)
    np.testing.assert_array_equal(back.spacing, q)
    assert list(back.point_data) == ["u", "w"]
    np.testing.assert_array_equal(back.point_data["u"], u)
    np.testing.assert_array_equal(back.point_data["w"], w)
    back.write(tmp_path / "again.vtu")
    assert (tmp_path / "again.vtu").read_bytes() == (tmp_path / "m.vtu").read_bytes()
