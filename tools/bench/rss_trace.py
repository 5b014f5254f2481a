#!/usr/bin/env python3
"""Peak resident memory of a command, phase by phase.

Usage: rss_trace.py [--every SECONDS] [--trace FILE] -- COMMAND ARGS...

Runs COMMAND, samples its resident set (VmRSS of /proc/PID/status, the process and its threads) every
SECONDS (default 0.05), and reads its stderr line by line. Each progress line of `pdmesh mesh` closes
an interval: the table printed at the end gives, for every line, the peak RSS seen since the line
before it and the RSS when it came, so that the phase that sets the peak shows (a phase's lines come
at its end). The child's maximum resident set from getrusage (exact, not sampled) is printed last,
with the wall and CPU time. With --trace every sample goes to FILE as "seconds rss_bytes".
"""
import argparse
import resource
import subprocess
import sys
import threading
import time


def status_field(pid, key):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith(key):
                    return int(line.split()[1]) * 1024
    except (FileNotFoundError, ProcessLookupError):
        return None
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--every", type=float, default=0.05)
    ap.add_argument("--trace")
    ap.add_argument("command", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.command[1:] if a.command and a.command[0] == "--" else a.command
    if not cmd:
        ap.error("no command")
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, bufsize=1)
    samples = []  # (seconds, rss)
    lock = threading.Lock()

    def sample():
        while proc.poll() is None:
            rss = status_field(proc.pid, "VmRSS:")
            if rss is not None:
                with lock:
                    samples.append((time.monotonic() - t0, rss))
            time.sleep(a.every)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    marks = []  # (seconds, line)
    for line in proc.stderr:
        marks.append((time.monotonic() - t0, line.rstrip("\n")))
    proc.wait()
    wall = time.monotonic() - t0
    sampler.join()
    marks.append((wall, "(end)"))
    if a.trace:
        with open(a.trace, "w") as f:
            for t, r in samples:
                f.write(f"{t:.3f} {r}\n")
    print(f"{'t s':>8} {'peak MB':>8} {'rss MB':>8}  line (peak since the line before)")
    i = 0
    overall = 0
    for t, line in marks:
        peak = 0
        last = 0
        while i < len(samples) and samples[i][0] <= t:
            peak = max(peak, samples[i][1])
            last = samples[i][1]
            i += 1
        overall = max(overall, peak)
        print(f"{t:8.2f} {peak / 1e6:8.0f} {last / 1e6:8.0f}  {line[:110]}")
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    print(f"exit {proc.returncode}; wall {wall:.2f} s; CPU {ru.ru_utime + ru.ru_stime:.2f} s (user {ru.ru_utime:.2f}, "
          f"sys {ru.ru_stime:.2f}); sampled peak {overall / 1e6:.0f} MB; max RSS (getrusage) {ru.ru_maxrss * 1024 / 1e6:.0f} MB")
    return proc.returncode


if __name__ == "__main__":
    sys.exit(main())
