"""Unit tests of tools/bench/scale_vs_gmsh.py's parts that need no Gmsh: the size factor chosen for a
node count, the .crv reader, and the table."""

import os
import tempfile
import unittest

import scale_vs_gmsh as svg


class FactorTest(unittest.TestCase):
    def test_a_power_law_through_two_samples_gives_the_factor_for_the_count(self):
        law = lambda f: 5000.0 * f ** -1.8  # noqa: E731
        samples = [(3.0, law(3.0)), (1.8, law(1.8))]
        self.assertAlmostEqual(svg.factor_for(samples, law(0.9)), 0.9, places=12)
        self.assertAlmostEqual(svg.factor_for(samples, law(1.25)), 1.25, places=12)

    def test_equal_counts_fall_back_to_the_interior_law(self):
        # Two runs that made the same count say nothing of the slope: nodes ~ 1 / factor^2.
        self.assertAlmostEqual(svg.factor_for([(3.0, 1000.0), (2.0, 1000.0)], 4000.0), 1.0, places=12)


class CrvTest(unittest.TestCase):
    def test_a_closed_curve_loses_its_repeated_first_point(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "c.crv")
            with open(path, "w") as f:
                f.write("4\n1 0\n0 1\n-1 0\n1 0\n")
            self.assertEqual(svg.read_crv(path), [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0)])


class TableTest(unittest.TestCase):
    def test_the_ratio_row_divides_pdmesh_by_gmsh(self):
        tool = {"points": 1000, "wall_seconds": 10.0, "cpu_seconds": 20.0, "peak_rss_bytes": 5e8,
                "min_angle": 40.0, "mean_aspect_ratio": 1.01, "edge_over_q_mean": 1.0, "edge_over_q_std": 0.05}
        gmsh = dict(tool, points=800, wall_seconds=40.0, cpu_seconds=40.0, generate_seconds=35.0)
        r = {"case": "annulus_1k", "pdmesh": tool, "gmsh": gmsh, "node_ratio": 1.25, "wall_ratio": 0.25,
             "cpu_ratio": 0.5}
        text = svg.table([r])
        self.assertIn("| annulus_1k | pdmesh / Gmsh | 1.250 | 0.25x | 0.50x |", text)
        self.assertIn("| annulus_1k | gmsh | 800 | 40.0 (35.0 meshing) | 40.0 | 500 | 625000 |", text)


if __name__ == "__main__":
    unittest.main()
