"""Unit tests of tools/bench/partition_halo.py (the halo counts behind docs/scaling.md), against brute force."""

import unittest

import numpy as np

import partition_halo as ph


def graded_points(n, seed=42):
    """Points in [0, 1]^2 with q growing 8x from left to right, a few of them boundary nodes on a chain."""
    rng = np.random.default_rng(seed)
    x, y = rng.random(n), rng.random(n)
    q = 0.02 * (1 + 7 * x)
    kind = np.full(n, ph.KIND["interior"], dtype=np.int8)
    chain = np.arange(0, 40)
    kind[chain[1:-1]] = ph.KIND["boundary"]
    kind[chain[[0, -1]]] = ph.KIND["fixed"]
    return x, y, q, kind, [chain]


class HilbertTest(unittest.TestCase):
    def test_keys_visit_every_cell_once_and_step_to_a_neighbour(self):
        side = 8
        gx, gy = np.meshgrid(np.arange(side), np.arange(side), indexing="ij")
        x, y = (gx.ravel() + 0.5) / side, (gy.ravel() + 0.5) / side
        keys = ph.hilbert_keys(x, y, (0.0, 0.0, 1.0), bits=3)
        self.assertEqual(sorted(keys.tolist()), list(range(side * side)))
        order = np.argsort(keys)
        steps = np.abs(np.diff(gx.ravel()[order])) + np.abs(np.diff(gy.ravel()[order]))
        self.assertTrue(np.all(steps == 1), steps)


class PartitionTest(unittest.TestCase):
    def test_parts_are_contiguous_ranges_of_equal_size(self):
        n = 1003
        order = np.random.default_rng(7).permutation(n)
        part = ph.partition(order, np.ones(n), 4)
        sizes = np.bincount(part)
        self.assertEqual(sizes.sum(), n)
        self.assertLessEqual(sizes.max() - sizes.min(), 1)
        self.assertTrue(np.all(np.diff(part[order]) >= 0))


class PairScanTest(unittest.TestCase):
    def brute(self, x, y, q, kind, radius):
        d2 = (x[:, None] - x[None, :]) ** 2 + (y[:, None] - y[None, :]) ** 2
        within = d2 <= (radius * q[:, None]) ** 2
        np.fill_diagonal(within, False)
        within[kind != ph.KIND["interior"], :] = False
        return within

    def test_scan_finds_exactly_the_pairs_within_radius_q_i(self):
        x, y, q, kind, _ = graded_points(700)
        query = np.flatnonzero(kind == ph.KIND["interior"])
        for radius in (1.5, 2.7):
            found = np.zeros((len(x), len(x)), dtype=bool)
            count = 0
            for i, j in ph.PairScan(x, y, q, query).pairs(radius, chunk=5000):
                found[i, j] = True
                count += len(i)
            expected = self.brute(x, y, q, kind, radius)
            self.assertEqual(count, int(expected.sum()), "a pair found twice or missed")
            np.testing.assert_array_equal(found, expected)

    def test_ghosts_and_messages_match_brute_force(self):
        x, y, q, kind, chains = graded_points(600)
        query = np.flatnonzero(kind == ph.KIND["interior"])
        frame = ph.square_frame(x, y)
        order = np.lexsort((np.arange(len(x)), ph.hilbert_keys(x, y, frame)))
        parts = [ph.partition(order, np.ones(len(x)), p) for p in (2, 5)]
        total, rows = ph.scan_radius(ph.PairScan(x, y, q, query), 1.5, parts, chains, kind)
        need = self.brute(x, y, q, kind, 1.5)
        ci, cj = ph.chain_pairs(chains, kind)
        need[ci, cj] = True
        self.assertEqual(total, int(self.brute(x, y, q, kind, 1.5).sum()))
        for part, row in zip(parts, rows):
            for p in range(part.max() + 1):
                ghosts = np.flatnonzero(need[part == p].any(axis=0) & (part != p))
                self.assertEqual(row["ghosts"][p], len(ghosts), f"part {p}")
                self.assertEqual(row["messages"][p], len(np.unique(part[ghosts])), f"part {p}")
                self.assertEqual(row["pairs"][p], int(self.brute(x, y, q, kind, 1.5)[part == p].sum()))


class InterfaceTest(unittest.TestCase):
    def test_crossing_and_corner_sharing_triangles(self):
        # A strip of 4 triangles over nodes 0..5: (0 1 2) (1 3 2) (2 3 4) (3 5 4); nodes 4, 5 in part 1.
        tri = np.array([[0, 1, 2], [1, 3, 2], [2, 3, 4], [3, 5, 4]])
        part = np.array([0, 0, 0, 0, 1, 1])
        crossing, frozen = ph.interface_triangles(tri, part)
        self.assertEqual(crossing, 2)
        self.assertEqual(frozen, 4)


if __name__ == "__main__":
    unittest.main()
