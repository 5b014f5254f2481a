"""Unit tests of tools/bench/paired_runs.py: two commands whose CPU work (done in a grandchild, so
that the descendants' accounting is what is measured) differs 2:1, a failing command, the time bound."""

import os
import shlex
import subprocess
import sys
import unittest

SCRIPT = os.path.join(os.environ.get("PYTHONPATH", "").split(os.pathsep)[0], "paired_runs.py")


def busy(seconds):
    """A shell whose child burns `seconds` of its own CPU time; the `; true` keeps the shell from
    exec-ing it, so the work is in the shell's child, the timed command's grandchild."""
    code = f"import time\nwhile time.process_time() < {seconds}: pass"
    return ["sh", "-c", f"{shlex.quote(sys.executable)} -c {shlex.quote(code)}; true"]


def run(args):
    p = subprocess.run([sys.executable, SCRIPT] + args, capture_output=True, text=True, timeout=120)
    return p.returncode, p.stdout


def rows(out):
    """{label: (min, median, max)} of the table."""
    table = {}
    for line in out.splitlines():
        parts = line.rsplit(None, 3)
        if len(parts) == 4:
            try:
                table[parts[0]] = tuple(float(x) for x in parts[1:])
            except ValueError:
                pass
    return table


class PairedRunsTest(unittest.TestCase):
    def test_pairs_and_ratios(self):
        rc, out = run(["-n", "3", "--warmup", "1", "--vs", shlex.join(busy(0.1)), "--"] + busy(0.2))
        self.assertEqual(rc, 0, out)
        self.assertIn("3 pairs counted after 1 warm-up", out)
        table = rows(out)
        for key in ("A", "B"):
            for m in ("wall s", "user s", "sys s", "cpu s", "peak MiB"):
                self.assertIn(f"{key} {m}", table)
        for m in ("wall", "user", "cpu"):
            self.assertIn(f"A/B {m}", table)
        # The grandchildren's CPU is counted: at least what they burnt, whatever the load.
        self.assertGreaterEqual(table["A cpu s"][0], 0.2)
        self.assertGreaterEqual(table["B cpu s"][0], 0.1)
        self.assertGreater(table["A/B cpu"][1], 1.3)
        lo, med, hi = table["A/B cpu"]
        self.assertTrue(lo <= med <= hi)

    def test_one_command_has_no_ratios(self):
        rc, out = run(["-n", "2", "--warmup", "0", "--", "true"])
        self.assertEqual(rc, 0, out)
        self.assertIn("2 runs counted after 0 warm-up", out)
        self.assertIn("A cpu s", rows(out))
        self.assertNotIn("A/B", out)

    def test_failing_command_exits_1_and_is_named(self):
        rc, out = run(["-n", "2", "--warmup", "0", "--vs", "sh -c 'exit 3'", "--", "true"])
        self.assertEqual(rc, 1, out)
        self.assertIn("B run 1 failed: exited 3", out)
        rc, out = run(["-n", "1", "--", "/nonexistent/command"])
        self.assertEqual(rc, 1, out)
        self.assertIn("could not be started", out)

    def test_time_bound_prints_the_finished_runs(self):
        # 20 runs of 0.3 s cannot fit in 1 s under any load: the call stops early and still reports.
        rc, out = run(["-n", "20", "--warmup", "0", "--timeout", "1", "--", "sleep", "0.3"])
        self.assertEqual(rc, 0, out)
        self.assertIn("stopped at the time bound", out)
        counted = int(out.split(" runs counted")[0].split()[-1])
        self.assertLess(counted, 20)


if __name__ == "__main__":
    unittest.main()
