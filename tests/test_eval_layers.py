"""Unit tests of the boundary-layer measures (tools/eval/pdmesh_eval/layers.py) on layers built here
with known heights: a flat wall with quads at h1 g^k under a row of core triangles, the same split
into triangles, a wrong first row, and a jump at the junction. Run by ctest (eval_layers) with
tools/eval/ on the module path; needs numpy."""

import math
import unittest

import numpy as np

from pdmesh_eval import layers as bl

H1, G, LAYERS = 1e-3, 1.2, 6
THICKNESS = H1 * (G ** LAYERS - 1) / (G - 1)


def flat_layers(columns=11, first=H1, junction=None, split=False):
    """Points and cells of LAYERS quads on y = 0 (x in [0, 1]) with heights first, H1 g, ..., then
    one row of core nodes at `junction` above the top (default: the next height, g times the last
    layer), joined by triangles."""
    heights = [first] + [H1 * G ** k for k in range(1, LAYERS)]
    ys = np.concatenate([[0.0], np.cumsum(heights)])
    top = ys[-1] + (junction if junction is not None else H1 * G ** LAYERS)
    xs = np.linspace(0.0, 1.0, columns)
    points = [(x, y) for y in ys for x in xs] + [(x, top) for x in xs]
    node = lambda row, col: row * columns + col  # noqa: E731
    quads, triangles = [], []
    for row in range(len(ys) - 1):
        for col in range(columns - 1):
            q = (node(row, col), node(row, col + 1), node(row + 1, col + 1), node(row + 1, col))
            if split:
                triangles += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
            else:
                quads.append(q)
    last = len(ys) - 1
    for col in range(columns - 1):
        a, b = node(last, col), node(last, col + 1)
        c, d = node(last + 1, col), node(last + 1, col + 1)
        triangles += [(a, b, d), (a, d, c)]
    wall = np.array([[(0.0, 0.0), (1.0, 0.0)]])
    return np.array(points), triangles, quads, wall


class LayerMeasures(unittest.TestCase):
    def test_exact_layers(self):
        points, triangles, quads, wall = flat_layers()
        m = bl.layer_measures(points, triangles, quads, wall, H1, THICKNESS)
        self.assertEqual(m["wall_cells"], 10)
        self.assertEqual(m["first_height_within_2pct"], 100.0)
        self.assertAlmostEqual(m["first_height_median"], H1, delta=1e-15)
        self.assertAlmostEqual(m["growth_median"], G, delta=1e-9)
        self.assertAlmostEqual(m["growth_max"], G, delta=1e-9)
        self.assertAlmostEqual(m["max_angle"], 90.0, delta=1e-9)
        self.assertEqual(m["quads"], 10 * LAYERS)

    def test_split_quads_are_measured_alike(self):
        points, triangles, quads, wall = flat_layers(split=True)
        m = bl.layer_measures(points, triangles, quads, wall, H1, THICKNESS)
        self.assertEqual(m["quads"], 0)
        self.assertEqual(m["first_height_within_2pct"], 100.0)
        self.assertAlmostEqual(m["growth_median"], G, delta=1e-9)
        self.assertEqual(m["triangles"], 2 * 10 * LAYERS + 20)
        self.assertAlmostEqual(m["max_angle"], 90.0, delta=1e-9)  # right triangles: the diagonal is skipped

    def test_a_wrong_first_row_is_seen(self):
        points, triangles, quads, wall = flat_layers(first=1.05 * H1)
        m = bl.layer_measures(points, triangles, quads, wall, H1, THICKNESS)
        self.assertEqual(m["first_height_within_2pct"], 0.0)
        self.assertAlmostEqual(m["first_height_max_error"], 0.05, delta=1e-9)

    def test_the_junction_counts_in_the_growth(self):
        jump = 3.0 * H1 * G ** (LAYERS - 1)
        points, triangles, quads, wall = flat_layers(junction=jump)
        m = bl.layer_measures(points, triangles, quads, wall, H1, THICKNESS)
        self.assertAlmostEqual(m["growth_max"], 3.0, delta=1e-9)
        self.assertAlmostEqual(m["growth_max_at_distance"], THICKNESS, delta=1e-12)
        self.assertAlmostEqual(m["growth_median"], G, delta=1e-9)

    def test_core_triangles_are_those_beyond_the_thickness(self):
        points, triangles, quads, wall = flat_layers()
        m = bl.layer_measures(points, triangles, quads, wall, H1, THICKNESS)
        # The core row touches the layer's top: no triangle lies wholly beyond the thickness.
        self.assertEqual(m["core_triangles"], 0)
        self.assertTrue(math.isnan(m["core_min_angle"]))

    def test_thickness_jumps_between_neighbouring_wall_nodes(self):
        points, triangles, quads, wall = flat_layers()
        # The top quad of the last column (x in [0.9, 1]) is not the layer's: the wall node at x = 1
        # has one layer less than its neighbour at x = 0.9, whose column goes up the quads on its left.
        top_last = max(range(len(quads)), key=lambda k: (points[quads[k][0]][1], points[quads[k][0]][0]))
        layer = [False] * len(triangles) + [k != top_last for k in range(len(quads))]
        regions = {"left": (0.0, -1.0, 0.5, 1.0), "right": (0.85, -1.0, 1.0, 1.0)}
        m = bl.layer_measures(points, triangles, quads, wall, H1, THICKNESS, layer_cells=layer, regions=regions)
        jumps = m["thickness_jumps"]
        expected = THICKNESS / (H1 * (G ** (LAYERS - 1) - 1) / (G - 1))
        self.assertEqual(jumps["all"]["edges"], 10)
        self.assertAlmostEqual(jumps["all"]["max"], expected, delta=1e-9)
        self.assertEqual(jumps["all"]["above_1_3"], 1)
        self.assertAlmostEqual(jumps["all"]["at"][0], 0.95, delta=1e-12)
        self.assertEqual(jumps["left"]["edges"], 5)
        self.assertEqual(jumps["left"]["max"], 1.0)
        self.assertAlmostEqual(jumps["right"]["max"], expected, delta=1e-9)
        # Without the layer cells, no jumps are measured.
        self.assertIsNone(bl.layer_measures(points, triangles, quads, wall, H1, THICKNESS)["thickness_jumps"])


if __name__ == "__main__":
    unittest.main()
