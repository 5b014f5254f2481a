"""Unit tests of tools/bench/cl_trace_summary.py: builds cut out of a PoCL text trace, times per command."""

import os
import tempfile
import unittest

import cl_trace_summary as ts


def trace_lines(events):
    """PoCL's text trace lines for (event id, command type, name or size, running ns, complete ns)."""
    lines = []
    for ev, kind, what, start, end in events:
        tail = f"KERNEL ID 1 | name={what}" if kind == "ndrange_kernel" else f"MEM ID 2 | size={what}"
        for state, t in (("queued", start - 5), ("submitted", start - 2), ("running", start), ("complete", end)):
            lines.append(f"{t} | EV ID {ev} | DEV 1 | CQ 4 | {kind} | {state} | {tail}\n")
    return lines


class SummaryTest(unittest.TestCase):
    def setUp(self):
        events = [
            (1, "write_buffer", 64, 0, 10),  # before any build: not counted
            (2, "ndrange_kernel", "bin_bounds", 100, 150),
            (3, "fill_buffer", 400, 150, 160),
            (4, "ndrange_kernel", "gather_rows", 200, 500),  # 40 ns idle before it
            (5, "read_buffer", 40, 500, 505),  # after the build's last kernel: not the build's
            (6, "ndrange_kernel", "device_step", 600, 900),
            (7, "ndrange_kernel", "bin_bounds", 1000, 1010),
            (8, "ndrange_kernel", "sort_rows", 1010, 1100),
        ]
        fd, self.path = tempfile.mkstemp(suffix=".log")
        with os.fdopen(fd, "w") as f:
            f.writelines(trace_lines(events))

    def tearDown(self):
        os.remove(self.path)

    def test_builds_run_from_bin_bounds_to_the_last_build_kernel(self):
        events = ts.read_events(self.path)
        self.assertEqual(ts.builds(events), [[2, 3, 4], [7, 8]])
        self.assertEqual(events[3]["name"], "fill_buffer size=400")
        self.assertEqual(events[4]["complete"] - events[4]["running"], 300)

    def test_a_trace_without_builds_is_refused(self):
        with open(self.path, "w") as f:
            f.writelines(trace_lines([(1, "ndrange_kernel", "device_step", 0, 10)]))
        self.assertEqual(ts.builds(ts.read_events(self.path)), [])


if __name__ == "__main__":
    unittest.main()
