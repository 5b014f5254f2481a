"""Unit tests of tools/bench/small_vs_gmsh.py's parts that need no Gmsh: the .crv loops (open curves
chained into closed loops) and the table's ratios."""

import os
import tempfile
import unittest

import small_vs_gmsh as svg


def write(d, text):
    path = os.path.join(d, "c.crv")
    with open(path, "w") as f:
        f.write(text)
    return path


class CrvLoopsTest(unittest.TestCase):
    def test_open_sides_are_chained_into_one_loop(self):
        # Four sides of a square given out of order, as cases/30p30n/farfield.crv gives its sides.
        with tempfile.TemporaryDirectory() as d:
            path = write(d, "2\n0 0\n1 0\n2\n1 1\n0 1\n2\n1 0\n1 1\n2\n0 1\n0 0\n")
            self.assertEqual(svg.crv_loops(path), [[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]])

    def test_closed_curves_stay_separate_loops(self):
        with tempfile.TemporaryDirectory() as d:
            path = write(d, "4\n0 0\n1 0\n0 1\n0 0\n4\n5 5\n6 5\n5 6\n5 5\n")
            self.assertEqual(len(svg.crv_loops(path)), 2)

    def test_curves_that_do_not_close_are_refused(self):
        with tempfile.TemporaryDirectory() as d:
            path = write(d, "2\n0 0\n1 0\n2\n2 2\n3 3\n")
            with self.assertRaises(SystemExit):
                svg.crv_loops(path)


class TableTest(unittest.TestCase):
    def test_the_ratios_are_pdmesh_over_gmsh_meshing(self):
        r = {"case": "30p30n", "pdmesh": (12677, 24322), "gmsh": (13000, 23000), "median": [2.3, 3.7, 1.15, 1.1],
             "wall_ratio": 2.0, "cpu_ratio": 3.36, "version": "4.15.2", "load": (0.5, 0.5, 0.5)}
        text = svg.table([r], 5)
        self.assertIn("| 30p30n | 12,677 / 24,322 | 13,000 / 23,000 | 2.300 / 3.700 | 1.150 / 1.100 | 2.00x | 3.36x |",
                      text)
        self.assertIn("Medians of 5 alternated rounds", text)


if __name__ == "__main__":
    unittest.main()
