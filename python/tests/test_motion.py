"""pdmesh.run_motion and pdmesh.transfer (docs/motion.md): the steps with persistent ids, and a linear
field transferred exactly."""

import numpy as np
import pytest

import pdmesh

CASE = """name = "moving"
[geometry]
files = ["far.crv", "body.crv"]
curve_names = ["far", "upper", "lower"]
[spacing]
expression = "0.12 + 0.1 * sqrt(x*x + y*y)"
[simulation]
iterations = 300
device = "host"
[motion]
curves = ["upper", "lower"]
rotate = "20*t"
pivot = [0.2, 0.0]
steps = 2
"""


@pytest.fixture
def case_file(tmp_path):
    (tmp_path / "far.crv").write_text("5\n-3 -3\n3 -3\n3 3\n-3 3\n-3 -3\n")
    lines = []
    for half in (0, 1):
        lines.append("17")
        for k in range(17):
            a = np.pi * (half + k / 16)
            lines.append(f"{0.8 * np.cos(a):.17g} {0.3 * np.sin(a):.17g}")
    (tmp_path / "body.crv").write_text("\n".join(lines) + "\n")
    (tmp_path / "case.toml").write_text(CASE)
    return tmp_path / "case.toml"


def test_run_motion_keeps_ids_and_writes_the_series(case_file, tmp_path):
    seen = []
    steps = pdmesh.run_motion(case_file, out=tmp_path / "out", on_step=lambda s: seen.append(s.step))
    assert seen == [0, 1, 2]
    assert [s.t for s in steps] == [0.0, 0.5, 1.0]
    for s in steps:
        assert s.node_id.shape == (len(s.mesh.points),)
        assert len(np.unique(s.node_id)) == len(s.node_id)
        assert s.min_angle > 30
    kept = np.intersect1d(steps[0].node_id, steps[1].node_id).size / steps[0].node_id.size
    assert kept == pytest.approx(steps[1].ids_kept)
    assert kept > 0.8
    assert (tmp_path / "out" / "motion.pvd").exists()
    assert (tmp_path / "out" / "step_0002" / "mesh.vtu").exists()


def test_transfer_of_a_linear_field_is_exact(case_file):
    steps = pdmesh.run_motion(case_file)
    a, b = steps[0].mesh, steps[1].mesh
    f = lambda p: 2.0 * p[:, 0] - 3.0 * p[:, 1] + 0.5
    moved = pdmesh.transfer(a, f(a.points), b.points)
    both = pdmesh.transfer(a, np.column_stack([f(a.points), np.ones(len(a.points))]), b.points)
    assert moved.shape == (len(b.points),) and both.shape == (len(b.points), 2)
    # Points of b far from the body lie in a's triangles: exact there.
    far = np.hypot(b.points[:, 0], b.points[:, 1]) > 1.2
    assert np.allclose(moved[far], f(b.points)[far], atol=1e-12)
    assert np.allclose(both[:, 1], 1.0)


def test_a_case_without_motion_is_refused(tmp_path, case_file):
    (tmp_path / "still.toml").write_text(CASE.split("[motion]")[0])
    with pytest.raises(pdmesh.InputError, match="no \\[motion\\] section"):
        pdmesh.run_motion(tmp_path / "still.toml")


LAYERS = """[[boundary_layer]]
curves = ["upper", "lower"]
first_height = 0.005
growth = 1.2
layers = 5
elements = "quads"
"""


def test_run_motion_with_boundary_layers_keeps_the_layer_nodes(case_file, tmp_path):
    (tmp_path / "layers.toml").write_text(CASE.replace("steps = 2", "steps = 1") + LAYERS)
    steps = pdmesh.run_motion(tmp_path / "layers.toml")
    assert [s.step for s in steps] == [0, 1]
    a, b = steps
    for s in steps:
        assert s.node_id.shape == (len(s.mesh.points),)
        assert len(np.unique(s.node_id)) == len(s.node_id)
        assert s.min_angle > 30  # the core's
    # The layer nodes lie within 0.03 of the wall at step 0; each keeps its id and moves rigidly
    # (rotate 20 t degrees about (0.2, 0): 20 degrees at t = 1).
    near = np.abs(np.hypot(a.mesh.points[:, 0] / 0.8, a.mesh.points[:, 1] / 0.3) - 1.0) < 0.01
    ids = a.node_id[near]
    where = {int(i): k for k, i in enumerate(b.node_id)}
    assert all(int(i) in where for i in ids)
    c, s = np.cos(np.radians(20.0)), np.sin(np.radians(20.0))
    p = a.mesh.points[near] - [0.2, 0.0]
    moved = np.column_stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]]) + [0.2, 0.0]
    got = b.mesh.points[[where[int(i)] for i in ids]]
    assert np.abs(got - moved).max() < 1e-9


def assert_valid(mesh):
    """Every triangle counter-clockwise with positive area, every edge in one or two triangles, the
    edges in one triangle exactly the boundary edges, every point in some triangle."""
    p, t = mesh.points, mesh.triangles.astype(np.int64)
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    assert ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0] > 0).all()
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    assert counts.max() <= 2
    boundary = np.sort(np.concatenate(list(mesh.boundary_edges.values())), axis=1)
    assert {tuple(e) for e in unique[counts == 1]} == {tuple(e) for e in boundary}
    assert np.unique(t).size == len(p)


def test_moving_mesher_reproduces_run_motion_for_the_same_poses(case_file, tmp_path):
    steps = pdmesh.run_motion(case_file)
    m = pdmesh.MovingMesher(pdmesh.Case(case_file))  # moving curves and pivot from the case's [motion]
    assert m.pivot == (0.2, 0.0)
    mine = [m.last]
    for k in (1, 2):
        m.move(rotate=20 * k / 2)
        mine.append(m.step(t=k / 2))
    for a, b in zip(mine, steps):
        assert np.array_equal(a.mesh.points, b.mesh.points)
        assert np.array_equal(a.mesh.triangles, b.mesh.triangles)
        assert np.array_equal(a.node_id, b.node_id)
        assert a.ids_kept == b.ids_kept and a.t == b.t
    assert m.pose == (20.0, (0.0, 0.0))


def test_moving_mesher_ids_persist_and_every_mesh_is_valid(case_file, tmp_path):
    geo = pdmesh.Case(case_file).geometry
    m = pdmesh.MovingMesher(geo, moving=["upper", "lower"], pivot=(0.2, 0.0), out=tmp_path / "series",
                            spacing={"expression": "0.12 + 0.1 * sqrt(x*x + y*y)"}, iterations=300, device="host")
    previous = m.last
    top = previous.node_id.max()  # ids are never reused: a new node's is above every earlier one
    for k in range(1, 4):
        m.move(rotate=8.0 * np.sin(2 * np.pi * k / 4), translate=(0.05 * k, 0.0))
        s = m.step()
        assert s.step == k and s.t == float(k)
        assert s.node_id.shape == (len(s.mesh.points),)
        assert len(np.unique(s.node_id)) == len(s.node_id)
        kept = np.intersect1d(previous.node_id, s.node_id).size / previous.node_id.size
        assert kept == pytest.approx(s.ids_kept) and kept > 0.8
        new = np.setdiff1d(s.node_id, previous.node_id)
        assert new.size == 0 or new.min() > top
        top = max(top, s.node_id.max())
        assert s.min_angle >= 30
        assert m.record["inverted"] == 0
        assert_valid(s.mesh)
        previous = s
    assert (tmp_path / "series" / "motion.pvd").read_text().count("<DataSet") == 4
    assert (tmp_path / "series" / "step_0003" / "mesh.vtu").exists()


def test_moving_mesher_errors(case_file):
    case = pdmesh.Case(case_file)
    with pytest.raises(pdmesh.InputError, match="moving: unknown curve 'wing'"):
        pdmesh.MovingMesher(case, moving=["upper", "wing"])
    with pytest.raises(pdmesh.InputError, match="no moving curve"):
        pdmesh.MovingMesher(case.geometry, iterations=50)
    with pytest.raises(pdmesh.InputError, match="pivot"):
        pdmesh.MovingMesher(case, pivot=(0.0, float("nan")))
    with pytest.raises(pdmesh.InputError, match="callable"):
        pdmesh.MovingMesher(case, size=lambda xy: 0.1 + 0 * xy[:, 0])
    m = pdmesh.MovingMesher(case, warm_iterations=5)
    with pytest.raises(pdmesh.InputError, match="rotate"):
        m.move(rotate=float("inf"))
    with pytest.raises(pdmesh.InputError, match="translate"):
        m.move(translate=(0.0, float("nan")))
    # A motion too large for one step (the body pushed to the far field): the carry would fold the mesh
    # and is refused; the mesher stays at step 0 and goes on from there.
    m.move(translate=(2.5, 0.0))
    with pytest.raises(pdmesh.SimulationError, match="carrying the nodes inverts"):
        m.step()
    assert m.last.step == 0
    m.move(rotate=5.0, translate=(0.0, 0.0))
    assert m.step().step == 1
