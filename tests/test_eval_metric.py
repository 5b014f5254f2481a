"""Unit tests of the anisotropic measures (tools/eval/pdmesh_eval/metric.py) against closed forms:
unit edges and Q = 1 for a metric-equilateral triangle, the log edge length, the complexity of
constant and linear metrics, and the P1 interpolation error. Run by ctest (eval_metric) with
tools/eval/ on the module path; needs numpy."""

import importlib.machinery
import importlib.util
import math
import os
import unittest

import numpy as np

from pdmesh_eval import metric as mt

TOOLS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tools")


def load_anchors():
    """tools/eval/aniso_anchors.py as a module."""
    loader = importlib.machinery.SourceFileLoader("aniso_anchors", os.path.join(TOOLS, "eval", "aniso_anchors.py"))
    spec = importlib.util.spec_from_loader("aniso_anchors", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def equilateral_in(m, scale=1.0):
    """A triangle of unit edges in the constant metric m = (m11, m12, m22): the image of the unit
    equilateral triangle under M^(-1/2)."""
    lam, vec = np.linalg.eigh(np.array([[m[0], m[1]], [m[1], m[2]]]))
    inv_sqrt = vec @ np.diag(lam ** -0.5) @ vec.T
    ref = scale * np.array([[0.0, 0.0], [1.0, 0.0], [0.5, math.sqrt(3) / 2]])
    return ref @ inv_sqrt.T + np.array([0.3, 0.2])


class Sizes(unittest.TestCase):
    def test_metric_from_sizes_has_h1_along_the_angle(self):
        m = mt.metric_from_sizes(0.1, 0.001, math.radians(30))[0]
        mat = np.array([[m[0], m[1]], [m[1], m[2]]])
        d = np.array([math.cos(math.radians(30)), math.sin(math.radians(30))])
        n = np.array([-d[1], d[0]])
        self.assertAlmostEqual(d @ mat @ d, 1 / 0.1 ** 2, places=6)
        self.assertAlmostEqual(n @ mat @ n, 1 / 0.001 ** 2, places=3)
        self.assertAlmostEqual(d @ mat @ n, 0.0, places=6)

    def test_polar_cases_size_radius_and_tangent(self):
        p = np.array([[0.6 * math.cos(0.4), 0.6 * math.sin(0.4)]])
        radial = np.array([math.cos(0.4), math.sin(0.4)])
        for metric, h_t in ((mt.polar1_metric, 0.1), (mt.polar2_metric, 0.1)):
            m = metric(p)[0]
            mat = np.array([[m[0], m[1]], [m[1], m[2]]])
            self.assertAlmostEqual(radial @ mat @ radial, 1 / (0.001 + 0.198 * 0.1) ** 2, places=4)
        self.assertAlmostEqual(float(mt.polar2_h_t(np.array(0.5))), 0.025)
        self.assertAlmostEqual(float(mt.polar2_h_t(np.array(0.55))), 0.5 / 40 + 0.5 / 10)
        self.assertAlmostEqual(float(mt.polar2_h_t(np.array(0.7))), 0.1)


class Lengths(unittest.TestCase):
    def test_equilateral_in_metric_has_unit_edges_and_quality_one(self):
        m = mt.metric_from_sizes(0.2, 0.003, 0.7)[0]
        pts = equilateral_in(m)
        tri = np.array([[0, 1, 2]])
        mm = np.tile(m, (3, 1))
        lengths = mt.edge_lengths(pts, mt.edges(tri), mm)
        np.testing.assert_allclose(lengths, 1.0, rtol=1e-9)
        self.assertAlmostEqual(float(mt.qualities(pts, tri, mm)[0]), 1.0, places=9)
        # The same triangle flattened is worse; reversed, it is inverted.
        flat = pts.copy()
        flat[2] = 0.5 * (pts[0] + pts[1]) + 0.3 * (pts[2] - 0.5 * (pts[0] + pts[1]))
        self.assertLess(float(mt.qualities(flat, tri, mm)[0]), 0.7)
        self.assertLess(float(mt.qualities(pts, tri[:, ::-1], mm)[0]), 0.0)

    def test_quality_uses_the_corner_metric_of_largest_det(self):
        pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, math.sqrt(3) / 2]])
        tri = np.array([[0, 1, 2]])
        m = np.array([[1.0, 0.0, 1.0], [4.0, 0.0, 1.0], [1.0, 0.0, 1.0]])   # corner 1: det 4
        big = m[1]
        e = [pts[1] - pts[0], pts[2] - pts[1], pts[0] - pts[2]]
        sum_l2 = sum(big[0] * v[0] ** 2 + 2 * big[1] * v[0] * v[1] + big[2] * v[1] ** 2 for v in e)
        expected = 4 * math.sqrt(3) * (math.sqrt(3) / 4) * 2.0 / sum_l2
        self.assertAlmostEqual(float(mt.qualities(pts, tri, m)[0]), expected, places=12)

    def test_log_formula_is_exact_for_a_geometric_size_and_falls_back_to_the_mean(self):
        # Isotropic size h along the x axis from h_a = 0.01 to h_b = 0.04 over an edge of length 0.3.
        ha, hb, length = 0.01, 0.04, 0.3
        pts = np.array([[0.0, 0.0], [length, 0.0]])
        m = np.array([[1 / ha ** 2, 0, 1 / ha ** 2], [1 / hb ** 2, 0, 1 / hb ** 2]])
        got = float(mt.edge_lengths(pts, np.array([[0, 1]]), m)[0])
        la, lb = length / ha, length / hb
        self.assertAlmostEqual(got, (la - lb) / math.log(la / lb), places=10)
        # = ∫ length/h(t) dt for h(t) = ha^(1-t) hb^t, integrated numerically.
        s, w = mt.gauss01(40)
        self.assertAlmostEqual(got, float(np.sum(w * length / (ha ** (1 - s) * hb ** s))), places=8)
        # For a linearly varying size the exact length is length·ln(hb/ha)/(hb − ha): the log formula
        # lies between it and the two-end mean.
        exact_linear = length * math.log(hb / ha) / (hb - ha)
        self.assertGreater(got, exact_linear)
        self.assertLess(got, 0.5 * (la + lb))
        # |La − Lb| ≤ 1e-3: the mean of the two ends.
        m2 = np.array([[1.0, 0, 1.0], [1.0 / (1 + 2e-3), 0, 1.0 / (1 + 2e-3)]])
        pts2 = np.array([[0.0, 0.0], [1.0, 0.0]])
        la2, lb2 = 1.0, (1 / (1 + 2e-3)) ** 0.5
        self.assertAlmostEqual(float(mt.edge_lengths(pts2, np.array([[0, 1]]), m2)[0]),
                               0.5 * (la2 + lb2), places=14)


class Complexity(unittest.TestCase):
    def test_constant_metric_gives_area_times_sqrt_det(self):
        m = np.array([400.0, 30.0, 9.0])          # det 3600 − 900 = 2700
        const = lambda p: np.tile(m, (len(p), 1))
        self.assertAlmostEqual(mt.complexity_square(const, panels=8), math.sqrt(2700.0), places=8)
        area = 1.0 - math.pi * 0.25 / 4
        self.assertAlmostEqual(mt.complexity_square_minus_disc(const, panels=(20, 40)),
                               area * math.sqrt(2700.0), places=6)
        self.assertAlmostEqual(mt.ideal_triangles(10.0), 40 / math.sqrt(3))

    def test_linear_case_matches_its_closed_form(self):
        # ∫₀¹ 10 / (0.001 + 0.198|y − 0.5|) dy = 2·(10/0.198)·ln(0.1/0.001)
        exact = 2 * 10 / 0.198 * math.log(100.0)
        self.assertAlmostEqual(mt.complexity_square(mt.linear_metric, panels=200) / exact, 1.0, places=6)

    def test_polar1_matches_its_radial_integral(self):
        # √det M = 1/(h_r h_t) depends on r only: C = ∫ f(r) r w(r) dr with w = π/2 for r ≤ 1 and
        # π/2 − 2 arccos(1/r) for 1 < r ≤ √2.
        f = lambda r: 1.0 / ((0.001 + 0.198 * np.abs(r - 0.5)) * 0.1)
        s, w = mt.gauss01(8)
        total = 0.0
        edges_r = np.concatenate([0.5 + 0.5 * (np.arange(2001) / 2000) ** 2,
                                  1 + (math.sqrt(2) - 1) * np.arange(1, 2001) / 2000])
        for lo, hi in zip(edges_r[:-1], edges_r[1:]):
            r = lo + (hi - lo) * s
            wr = np.where(r <= 1, np.pi / 2, np.pi / 2 - 2 * np.arccos(np.minimum(1.0, 1 / r)))
            total += (hi - lo) * float(np.sum(w * f(r) * r * wr))
        self.assertAlmostEqual(mt.complexity_square_minus_disc(mt.polar1_metric) / total, 1.0, places=5)


class Interpolation(unittest.TestCase):
    def test_linear_function_is_interpolated_exactly(self):
        pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [0.4, 0.6]])
        tri = np.array([[0, 1, 4], [1, 3, 4], [3, 2, 4], [2, 0, 4]])
        e2, emax = mt.interpolation_error(pts, tri, lambda p: 3 * p[:, 0] - 2 * p[:, 1] + 0.5)
        self.assertLess(e2, 1e-14)
        self.assertLess(emax, 1e-14)

    def test_x_squared_on_the_reference_triangle(self):
        # Π(x²) = x on (0,0),(1,0),(0,1); ∫(x² − x)² = ∫₀¹ (x² − x)²(1 − x) dx = 1/60.
        pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
        e2, emax = mt.interpolation_error(pts, np.array([[0, 1, 2]]), lambda p: p[:, 0] ** 2)
        self.assertAlmostEqual(e2, math.sqrt(1 / 60), places=13)
        # The largest error, 1/4 at x = 1/2, is sampled at the rule's points only: just below it.
        self.assertTrue(0.2 < emax <= 0.25)
        # Scaled by s and moved: u − Πu scales by s² and the area by s², so the L2 norm by s³.
        s = 0.1
        e2s, _ = mt.interpolation_error(s * pts + 0.5, np.array([[0, 2, 1]]), lambda p: (p[:, 0] - 0.5) ** 2)
        self.assertAlmostEqual(e2s, s ** 3 * math.sqrt(1 / 60), places=15)

    def test_tanh_hessian_matches_finite_differences(self):
        p = np.array([[0.3, 0.72], [0.8, 0.27], [0.1, 0.64]])
        h = mt.tanh_hessian(p)
        d = 1e-5
        ex, ey = np.array([d, 0]), np.array([0, d])
        u = mt.tanh_u
        uxx = (u(p + ex) - 2 * u(p) + u(p - ex)) / d ** 2
        uyy = (u(p + ey) - 2 * u(p) + u(p - ey)) / d ** 2
        uxy = (u(p + ex + ey) - u(p + ex - ey) - u(p - ex + ey) + u(p - ex - ey)) / (4 * d * d)
        np.testing.assert_allclose(h, np.column_stack([uxx, uxy, uyy]), rtol=2e-3, atol=1e-2)

    def test_l2_optimal_metric_has_the_target_complexity(self):
        scale = mt.l2_optimal_scale(mt.tanh_hessian, 4000.0, grid=512)
        metric = mt.l2_optimal_metric(mt.tanh_hessian, scale)
        c = mt.complexity_square(metric, panels=256)
        self.assertLess(abs(c / 4000.0 - 1.0), 0.02)


class Report(unittest.TestCase):
    def test_window_and_counts(self):
        m = np.array([100.0, 0.0, 100.0])       # h = 0.1
        const = lambda p: np.tile(m, (len(p), 1))
        pts = np.array([[0.0, 0.0], [0.1, 0.0], [0.0, 0.1], [0.1, 0.1]])
        rep = mt.metric_report(pts, np.array([[0, 1, 3], [0, 3, 2]]), const, complexity=1.0)
        # Edges of length 1 (four) and √2 (one diagonal): all in the closed window.
        self.assertEqual(rep["edges"], 5)
        self.assertAlmostEqual(rep["window_percent"], 100.0)
        self.assertAlmostEqual(rep["L_max"], math.sqrt(2))
        self.assertAlmostEqual(rep["N_over_ideal"], 2 / (4 / math.sqrt(3)))
        self.assertEqual(sum(rep["Q_histogram"]["counts"]), 2)


class AnchorInputs(unittest.TestCase):
    """The anchors script's own inputs (tools/eval/pdmesh_eval/aniso_tools.py): the metric strings
    given to Gmsh and FreeFem++ are the cases of metric.py, the start meshes are valid, the Medit files
    round-trip, and --pdmesh judges a mesh file beside the anchors."""

    def sample(self):
        rng = np.random.default_rng(1)
        p = rng.uniform(0, 1, (400, 2))
        return p[np.hypot(p[:, 0], p[:, 1]) > 0.52]

    def test_gmsh_expressions_are_the_cases(self):
        from pdmesh_eval import aniso_tools as at
        p = self.sample()
        env = {"x": p[:, 0], "y": p[:, 1], "Fabs": np.abs, "Sqrt": np.sqrt}
        for case in at.CASES:
            got = np.column_stack([np.broadcast_to(eval(e, env), len(p)) for e in at.GMSH_METRIC[case]])
            np.testing.assert_allclose(got, at.METRICS[case](p), rtol=1e-9, atol=1e-6, err_msg=case)

    def test_freefem_expressions_are_the_cases(self):
        import re
        from pdmesh_eval import aniso_tools as at
        p = self.sample()
        for case in at.CASES:
            text = at.FREEFEM_METRIC[case] + (at.FREEFEM_POLAR if case != "linear" else "")
            env = {"x": p[:, 0], "y": p[:, 1], "abs": np.abs, "sqrt": np.sqrt}
            for name, expr in re.findall(r"func (\w+) = ([^;]+);", text):
                env[name] = eval(expr.replace("^", "**"), env)
            got = np.column_stack([np.broadcast_to(env[k], len(p)) for k in ("m11", "m12", "m22")])
            np.testing.assert_allclose(got, at.METRICS[case](p), rtol=1e-9, atol=1e-6, err_msg=case)

    def test_start_meshes_cover_their_domains(self):
        from pdmesh_eval import aniso_tools as at
        for domain, area in (("square", 1.0), ("square-minus-disc", 1 - math.pi / 16)):
            p, t, edges, corners = at.initial_mesh(domain)
            a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
            signed = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
            self.assertGreater(signed.min(), 0.0, domain)
            self.assertAlmostEqual(signed.sum(), area, delta=2e-5)
            # Every boundary edge is an edge of exactly one triangle.
            all_edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
            _, counts = np.unique(all_edges, axis=0, return_counts=True)
            self.assertEqual(int(np.sum(counts == 1)), len(edges), domain)

    def test_medit_round_trip_and_pdmesh_hook(self):
        import tempfile
        from pdmesh_eval import aniso_tools as at
        anchors = load_anchors()
        p, t, edges, corners = at.grid_mesh(3)
        with tempfile.TemporaryDirectory() as tmp:
            at.write_medit(os.path.join(tmp, "linear.mesh"), p, t, edges, corners)
            q, u = at.read_medit(os.path.join(tmp, "linear.mesh"))
            np.testing.assert_array_equal(q, p)
            np.testing.assert_array_equal(u, t)
            with open(os.path.join(tmp, "linear.time"), "w") as f:
                f.write("0.25\n")
            block = anchors.metric_rows("linear", [], tmp)
        row = block["rows"][0]
        with tempfile.TemporaryDirectory() as tmp:
            vtu = os.path.join(tmp, "m.vtu")
            body = ('<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="3" NumberOfCells="1">'
                    '<Points><DataArray type="Float64" NumberOfComponents="3" format="{f}">0 0 0 1 0 0 0 1 0'
                    '</DataArray></Points><Cells><DataArray type="Int64" Name="connectivity" format="ascii">'
                    '0 1 2</DataArray></Cells></Piece></UnstructuredGrid></VTKFile>')
            with open(vtu, "w") as f:
                f.write(body.format(f="ascii"))
            q, u = at.read_mesh_file(vtu)
            np.testing.assert_array_equal(q, [[0, 0], [1, 0], [0, 1]])
            np.testing.assert_array_equal(u, [[0, 1, 2]])
            # Binary as pdmesh writes it: base64 of a UInt64 byte count, then the data.
            import base64
            b64 = lambda a: base64.b64encode(np.uint64(a.nbytes).tobytes() + a.tobytes()).decode()
            binary = body.replace("0 0 0 1 0 0 0 1 0", b64(np.array([0, 0, 0, 1, 0, 0, 0, 1, 0], "<f8")))
            binary = binary.replace("0 1 2</", b64(np.array([0, 1, 2], "<i8")) + "</")
            binary = binary.replace('"UnstructuredGrid">', '"UnstructuredGrid" header_type="UInt64">', 1)
            with open(vtu, "w") as f:
                f.write(binary.replace('format="ascii"', 'format="binary"').format(f="binary"))
            q, u = at.read_mesh_file(vtu)
            np.testing.assert_array_equal(q, [[0, 0], [1, 0], [0, 1]])
            np.testing.assert_array_equal(u, [[0, 1, 2]])
            with open(vtu, "w") as f:
                f.write(binary.replace('format="ascii"', 'format="binary"').format(f="binary")
                        .replace('header_type="UInt64"', 'header_type="UInt64" compressor="vtkZLibDataCompressor"'))
            with self.assertRaisesRegex(ValueError, "m.vtu: only ASCII or uncompressed"):
                at.read_mesh_file(vtu)
        self.assertEqual(row["tool"], "pdmesh")
        self.assertEqual(row["triangles"], 18)
        self.assertEqual(row["wall_s"], 0.25)
        expected = mt.metric_report(p, t, mt.linear_metric)["Q_min"]
        self.assertAlmostEqual(row["Q_min"], expected)


if __name__ == "__main__":
    unittest.main()
