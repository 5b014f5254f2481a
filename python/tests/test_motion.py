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
