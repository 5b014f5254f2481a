"""Unit tests of tools/bench/smaps_peak.py: the peak's resident bytes by mapping, on a child whose
allocation is known."""

import os
import subprocess
import sys
import tempfile
import unittest

import smaps_peak

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(smaps_peak.__file__)), "smaps_peak.py")
MIB = 1 << 20


class SmapsPeakTest(unittest.TestCase):
    def test_own_mappings_parsed(self):
        maps = smaps_peak.read_smaps(os.getpid())
        names = {m[0] for m in maps}
        self.assertIn("[stack]", names)
        self.assertTrue(all(m[1] > 0 and m[2] <= m[1] for m in maps))  # rss within the mapping's size

    def test_peak_holds_the_childs_block(self):
        # The child touches 200 MiB in one block (an anonymous mmap by its size), holds it, exits.
        child = "import time; b = bytearray(200 << 20); b[::4096] = b'x' * len(b[::4096]); time.sleep(1.0)"
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "peak.txt")
            rc = subprocess.run([sys.executable, SCRIPT, "--every", "0.05", "--out", out, "--", sys.executable, "-c",
                                 child]).returncode
            self.assertEqual(rc, 0)
            lines = open(out).read().splitlines()
        first = lines[0].split()
        maxrss = int(first[first.index("(getrusage)") + 1].rstrip(";"))
        sampled = int(first[first.index("peak") + 1])
        self.assertGreaterEqual(maxrss, 200 * MIB)
        self.assertGreaterEqual(sampled, 200 * MIB)
        self.assertLessEqual(sampled, maxrss + MIB)
        grouped = {}
        section = None
        for line in lines[1:]:
            if line.startswith("---"):
                section = line
                continue
            if section and "by mapping" in section:
                rss, name = line.strip().split(" ", 1)
                grouped[name] = int(rss)
        self.assertGreaterEqual(grouped.get("[anon rw-p] over 64 MiB", 0), 200 * MIB)


if __name__ == "__main__":
    unittest.main()
