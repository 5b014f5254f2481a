"""Unit tests of tools/studies/drift_bands.py (the drift study of docs/journal/2026-12-05g-drift.md)."""

import unittest

import numpy as np

import drift_bands as db


def hex_lattice(h, rows=24, cols=24):
    """An equilateral lattice of spacing h; its outer ring marked as boundary nodes."""
    pts, kind = [], []
    for j in range(rows):
        for i in range(cols):
            pts.append(((i + 0.5 * (j % 2)) * h, j * np.sqrt(3.0) / 2.0 * h))
            rim = i in (0, cols - 1) or j in (0, rows - 1)
            kind.append("boundary" if rim else "interior")
    return np.array(pts), np.array(kind)


class DensityTest(unittest.TestCase):
    def test_a_lattice_at_q_has_ratio_one_and_a_compressed_one_more(self):
        xy, kind = hex_lattice(0.1)
        inner = kind == "interior"
        ratio = db.density_ratio(xy, np.full(len(xy), 0.1))
        np.testing.assert_allclose(ratio[inner], 1.0, rtol=1e-9)
        # Spacing 0.1 against q = 0.11: 1.21 x the nodes the field's hexagonal packing asks for.
        ratio = db.density_ratio(xy, np.full(len(xy), 0.11))
        np.testing.assert_allclose(ratio[inner], 1.21, rtol=1e-9)

    def test_wall_distance_is_in_units_of_q(self):
        xy, kind = hex_lattice(0.1)
        d = db.wall_distance(xy, kind, np.full(len(xy), 0.05))
        self.assertTrue((d[kind != "interior"] == 0).all())
        # The rim is one of the six neighbours at the lattice spacing: 0.1 / 0.05.
        self.assertAlmostEqual(float(d[kind == "interior"].min()), 2.0, places=9)


class SplitTest(unittest.TestCase):
    def setUp(self):
        self.a, self.kind = hex_lattice(0.1)
        self.q = np.full(len(self.a), 0.1)

    def test_a_translation_is_all_smooth_and_leaves_the_aspect_ratio(self):
        b = self.a + np.array([0.013, -0.007])
        s = db.split_motion(self.a, self.kind, self.q, b)
        self.assertAlmostEqual(s["smooth_share"], 1.0, places=9)
        self.assertAlmostEqual(s["smooth"], s["a"], places=9)
        self.assertAlmostEqual(s["rest"], s["a"], places=9)
        self.assertAlmostEqual(s["b"], s["a"], places=9)

    def test_node_by_node_jitter_is_in_the_rest(self):
        rng = np.random.default_rng(3)
        b = self.a + np.where((self.kind == "interior")[:, None], rng.normal(0.0, 0.01, self.a.shape), 0.0)
        s = db.split_motion(self.a, self.kind, self.q, b)
        self.assertLess(s["smooth_share"], 0.1)
        self.assertGreater(s["b"], s["a"] + 1e-3)
        # The quality follows the jitter: moved by the rest alone the lattice is almost as distorted as b,
        # by the smooth part alone almost as regular as a.
        self.assertLess(abs(s["rest"] - s["b"]), 0.2 * (s["b"] - s["a"]))
        self.assertLess(s["smooth"] - s["a"], 0.2 * (s["b"] - s["a"]))


if __name__ == "__main__":
    unittest.main()
