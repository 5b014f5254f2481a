#!/usr/bin/env python3
"""What the resident memory is made of at a command's peak.

Usage: smaps_peak.py [--every SECONDS] --out FILE -- COMMAND ARGS...

Runs COMMAND (its stdout discarded, its stderr to FILE.stderr) and reads /proc/PID/smaps every
SECONDS (default 0.1). The reading with the largest total Rss is kept and written to FILE: the
child's maximum resident set from getrusage (exact) beside that sampled peak, then the peak's Rss
grouped by mapping (a file's mappings together; anonymous mappings by their size, so that the heap,
PoCL's large buffers, malloc's thread arenas and thread stacks each show), then every mapping with
more than 1 MiB resident. Two runs' files compared line by line say which kind of memory a change
moved (tools/bench/rss_trace.py says which phase sets the peak).
"""
import argparse
import collections
import resource
import subprocess
import sys
import time

BIG = 64 << 20  # anonymous mappings above this are grouped together (device buffers, large arrays)


def read_smaps(pid):
    """[(name, size, rss, perms)] of every mapping of the process."""
    maps = []
    cur = None
    with open(f"/proc/{pid}/smaps") as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if not parts[0].endswith(":") and "-" in parts[0] and len(parts) >= 5:
                lo, hi = (int(x, 16) for x in parts[0].split("-"))
                cur = [parts[5] if len(parts) > 5 else "[anon]", hi - lo, 0, parts[1]]
                maps.append(cur)
            elif parts[0] == "Rss:" and cur is not None:
                cur[2] = int(parts[1]) * 1024
    return maps


def threads(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("Threads:"):
                return int(line.split()[1])
    return 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--every", type=float, default=0.1)
    ap.add_argument("--out", required=True)
    ap.add_argument("command", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.command[1:] if a.command and a.command[0] == "--" else a.command
    if not cmd:
        ap.error("no command")
    t0 = time.monotonic()
    with open(a.out + ".stderr", "w") as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err)
        best_rss, best_maps, best_t, best_threads = 0, [], 0.0, 0
        while proc.poll() is None:
            try:
                maps = read_smaps(proc.pid)
                n_threads = threads(proc.pid)
            except (FileNotFoundError, ProcessLookupError):
                break
            total = sum(m[2] for m in maps)
            if total > best_rss:
                best_rss, best_maps, best_t, best_threads = total, maps, time.monotonic() - t0, n_threads
            time.sleep(a.every)
        proc.wait()
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    groups = collections.Counter()
    for name, size, rss, perms in best_maps:
        if name == "[anon]":
            name = f"[anon {perms}] " + ("over 64 MiB" if size > BIG else f"size={size}")
        groups[name] += rss
    with open(a.out, "w") as f:
        f.write(f"exit {proc.returncode}; max RSS (getrusage) {ru.ru_maxrss * 1024}; sampled peak {best_rss} at "
                f"{best_t:.2f} s with {best_threads} threads; wall {time.monotonic() - t0:.1f} s; "
                f"CPU {ru.ru_utime + ru.ru_stime:.1f} s\n")
        f.write("--- rss bytes by mapping at the sampled peak ---\n")
        for name, rss in groups.most_common():
            if rss:
                f.write(f"{rss:>14} {name}\n")
        f.write("--- mappings over 1 MiB resident: rss, size, perms, name ---\n")
        for name, size, rss, perms in best_maps:
            if rss > (1 << 20):
                f.write(f"{rss:>14} {size:>14} {perms} {name}\n")
    return proc.returncode


if __name__ == "__main__":
    sys.exit(main())
