"""Unit tests of the user corpus' evaluator (tools/eval/pdmesh_eval/corpus.py): the measures against
closed forms, the constraint check on meshes with and without a constraint's edges, Triangle's .poly
semantics on the corpus' face.poly and la.poly, the free boundary's breaks, and the projection.
Run by ctest (eval_corpus) with an interpreter that has numpy and shapely (tools/.venv-anchors);
exit 77 (skipped) without them."""

import math
import os
import sys
import unittest

try:
    import numpy  # noqa: F401
    import shapely  # noqa: F401
except ImportError:
    print("eval_corpus: needs numpy and shapely (tools/eval/setup_anchors.sh)")
    sys.exit(77)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tools", "eval"))

from pdmesh_eval import corpus  # noqa: E402
from pdmesh_eval.common import read_case  # noqa: E402


def square_input(constraints=(), points=()):
    from shapely.geometry import Polygon
    inp = corpus.Input("pslg")
    inp.domain = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    inp.constraints, inp.points = [list(c) for c in constraints], list(points)
    return inp


class Measures(unittest.TestCase):
    def test_equilateral(self):
        m = corpus.measures([(0, 0), (1, 0), (0.5, math.sqrt(3) / 2), (9, 9)], [(0, 1, 2)])
        self.assertEqual(m["nodes"], 3)  # the unused point is not counted
        self.assertAlmostEqual(m["min_angle"], 60.0, places=9)
        self.assertAlmostEqual(m["mean_aspect_ratio"], 1.0, places=9)
        self.assertEqual(m["share_below_30"], 0.0)

    def test_right_triangle_and_sliver(self):
        pts = [(0, 0), (1, 0), (0, 1), (2, 0.1)]
        m = corpus.measures(pts, [(0, 1, 2), (0, 3, 1)])

        def corner(a, b, c):  # the angle at a, from the cross and dot products
            u, v = (b[0] - a[0], b[1] - a[1]), (c[0] - a[0], c[1] - a[1])
            return math.degrees(math.atan2(abs(u[0] * v[1] - u[1] * v[0]), u[0] * v[0] + u[1] * v[1]))

        a, b, c = pts[0], pts[3], pts[1]
        self.assertAlmostEqual(m["min_angle"], min(corner(a, b, c), corner(b, c, a), corner(c, a, b)), places=9)
        self.assertEqual(m["share_below_30"], 0.5)
        # R/(2r) with R = l1 l2 l3 / (4 A) and r = A / s
        l1, l2, l3 = math.dist(a, b), math.dist(b, c), math.dist(c, a)
        area, s = 0.05, 0.5 * (l1 + l2 + l3)
        sliver = (l1 * l2 * l3 / (4 * area)) / (2 * area / s)
        right = (math.sqrt(2) / 2) / (2 * (2 - math.sqrt(2)) / 2)
        self.assertAlmostEqual(m["mean_aspect_ratio"], 0.5 * (right + sliver), places=9)


class Constraints(unittest.TestCase):
    # Two triangles sharing the diagonal (0,0)-(1,1), and a constraint along that diagonal.
    points = [(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5)]

    def test_present_as_a_chain_of_edges(self):
        tris = [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]
        inp = square_input(constraints=[[(0, 0), (1, 1)]], points=[(0.5, 0.5)])
        self.assertEqual(corpus.constraint_check(inp, self.points, tris), (2, 0))

    def test_missing_when_an_edge_crosses_it(self):
        tris = [(0, 1, 3), (1, 2, 3)]  # the other diagonal: no edge on (0,0)-(1,1)
        inp = square_input(constraints=[[(0, 0), (1, 1)]], points=[(0.25, 0.75)])
        self.assertEqual(corpus.constraint_check(inp, self.points[:4], tris), (0, 2))


class PolySemantics(unittest.TestCase):
    def read(self, name):
        return corpus.read_input(read_case(os.path.join(REPO, "cases", "user_corpus", name)))

    def test_face(self):
        inp = self.read("face")
        self.assertEqual(len(inp.domain.interiors), 3)  # mouth and eyes: the faces with hole points
        self.assertEqual(len(inp.constraints), 2)       # the nostrils
        self.assertEqual(len(inp.points), 2)            # the isolated vertices

    def test_la_keeps_region_boundaries_as_constraints(self):
        inp = self.read("la")
        self.assertEqual(inp.domain.geom_type, "Polygon")
        self.assertEqual(len(inp.domain.interiors), 0)
        self.assertEqual(sum(len(c) - 1 for c in inp.constraints), 133)

    def test_box_is_its_convex_hull_minus_the_hole(self):
        inp = self.read("box")
        self.assertAlmostEqual(inp.domain.area, 9.0 - 1.0)


class FreeBoundary(unittest.TestCase):
    def geo(self, ring):
        from shapely.geometry import Polygon
        inp = corpus.Input("pslg")
        inp.domain = Polygon(ring)
        return corpus.write_free_geo(inp, 30.0)

    def test_square_breaks_at_its_four_corners(self):
        text = self.geo([(0, 0), (1, 0), (1, 1), (0, 1)])
        self.assertEqual(text.count("Line("), 4)
        self.assertNotIn("Compound Curve", text)

    def test_smooth_loop_is_one_compound_curve(self):
        ring = [(math.cos(2 * math.pi * k / 64), math.sin(2 * math.pi * k / 64)) for k in range(64)]
        text = self.geo(ring)
        self.assertEqual(text.count("Compound Curve"), 1)
        self.assertEqual(text.count("Line("), 64)


class SharpestCorner(unittest.TestCase):
    def test_measured_on_the_domain_side(self):
        from shapely.geometry import Polygon
        inp = corpus.Input("pslg")
        # a square with a 20-deg notch cut into its top side: the notch's tip is 20 deg seen from
        # outside the domain, so the domain sees 340 deg there; the notch mouth corners are
        # 180 - 80 = 100 deg; the square's corners 90 deg
        h = 0.5 / math.tan(math.radians(10))
        inp.domain = Polygon([(0, 0), (4, 0), (4, 4), (2.5, 4), (2, 4 - h), (1.5, 4), (0, 4)], [[(1, 1), (1, 1.5), (1.5, 1)]])
        self.assertAlmostEqual(corpus.sharpest_corner(inp), 90.0, places=9)
        inp.domain = Polygon([(0, 0), (4, 0), (2, h)])
        self.assertAlmostEqual(corpus.sharpest_corner(inp), math.degrees(math.atan2(h, 2)), places=9)

    def test_from_the_mesh_after_healing(self):
        # The unit square's input with a 10-deg spike on its top side; a mesh of the square alone (the
        # spike healed away, a node added on the bottom side, 180 deg there): the corner is the
        # mesh's 90 deg, not the spike's.
        from shapely.geometry import Polygon
        inp = corpus.Input("pslg")
        t = math.tan(math.radians(5))
        inp.domain = Polygon([(0, 0), (1, 0), (1, 1), (0.5 + 0.05 * t, 1), (0.5, 1.05), (0.5 - 0.05 * t, 1), (0, 1)])
        self.assertLess(corpus.sharpest_corner(inp), 11.0)
        points = [(0, 0), (0.5, 0), (1, 0), (1, 1), (0, 1), (9, 9)]
        triangles = [(0, 1, 4), (1, 3, 4), (1, 2, 3)]
        self.assertAlmostEqual(corpus.sharpest_mesh_corner(points, triangles), 90.0, places=9)
        self.assertAlmostEqual(corpus.sharpest_corner(inp, mesh=(points, triangles)), 90.0, places=9)


class Projection(unittest.TestCase):
    def test_lonlat_square_at_60_degrees_is_half_as_wide(self):
        from shapely.geometry import Polygon
        inp = corpus.Input("gis")
        inp.domain = Polygon([(10, 59), (12, 59), (12, 61), (10, 61)])
        corpus.project(inp)
        x0, y0, x1, y1 = inp.domain.bounds
        self.assertEqual(inp.projection, (11.0, 60.0))
        self.assertAlmostEqual((x1 - x0) / (y1 - y0), 0.5, places=12)
        self.assertAlmostEqual(y1 - y0, 2 * corpus.EARTH_RADIUS * math.pi / 180, places=6)


if __name__ == "__main__":
    unittest.main()
