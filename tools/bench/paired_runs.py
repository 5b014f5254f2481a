#!/usr/bin/env python3
"""Whole-process time of a command, or of two commands run in turn (paired runs).

Usage: paired_runs.py [-n RUNS] [--warmup W] [--timeout S] [--vs 'COMMAND_B'] -- COMMAND_A ARGS...

Runs COMMAND_A W times (default 1) without counting them, then RUNS times (default 5). With --vs
(one string, split as a shell splits words; neither command is given a shell: write a pipe or a
redirection as sh -c '...'), B gets the same warm-up and the counted runs alternate A B A B ..., so
that each A/B ratio is taken from two neighbouring runs and a drift of the machine's speed during
the call moves both sides of it.

Each run is timed from outside, start-up included: wall is time.monotonic() read just before the
child is spawned and just after it is reaped; user and sys are the kernel's accounting of the
child as os.wait4 returns it, which includes every descendant the child (or a descendant) waited
for; cpu is user + sys. peak is ru_maxrss of that same accounting: the largest resident set of ONE
process among the child and those descendants, not their sum; it cannot read below this script's
own resident set (the kernel carries the spawning process's peak into the child's count at exec),
about 15 MiB, so small peaks say nothing. A descendant that was never waited
for is not counted. The child runs in a process group of its own; whatever it leaves running in it
is killed after the run and reported. Children read /dev/null and write to /dev/null.

Printed: for each command and measure, min / median / max over the counted runs; with --vs, the
pair-by-pair ratios A/B of wall, user and cpu, min / median / max. Quote the medians: one slow or one
lucky run does not move them, and min-max says how noisy the machine was.

--timeout S bounds the whole call (warm-up included): at S the running command's group is killed
and the finished runs (with --vs, the finished pairs) are printed. Without it there is no bound.

Exit status: 0 when every run exited 0; 1 when a run failed (exited non-zero, was killed by a signal
or could not be started): the report names it, and the call stops there; 2 for unusable arguments.
"""
import argparse
import os
import shlex
import signal
import statistics
import sys
import time


class Deadline(Exception):
    pass


def run_once(argv, deadline):
    """Spawn argv in its own process group, wait for it; return a dict of its measures.

    Raises Deadline when the bound passed (the group is killed first)."""
    remaining = None if deadline is None else deadline - time.monotonic()
    if remaining is not None and remaining <= 0:
        raise Deadline()
    devnull = os.open(os.devnull, os.O_RDWR)
    actions = [(os.POSIX_SPAWN_DUP2, devnull, 0), (os.POSIX_SPAWN_DUP2, devnull, 1),
               (os.POSIX_SPAWN_DUP2, devnull, 2), (os.POSIX_SPAWN_CLOSE, devnull)]
    timed_out = []

    def on_alarm(signum, frame):
        timed_out.append(True)
        try:
            os.killpg(pid, signal.SIGKILL)
        except (ProcessLookupError, NameError):
            pass

    old = signal.signal(signal.SIGALRM, on_alarm)
    try:
        start = time.monotonic()
        try:
            pid = os.posix_spawnp(argv[0], argv, os.environ, file_actions=actions, setpgroup=0)
        except OSError as e:
            return {"error": f"could not be started: {e.strerror}"}
        finally:
            os.close(devnull)
        if remaining is not None:
            signal.setitimer(signal.ITIMER_REAL, remaining)
        _, status, ru = os.wait4(pid, 0)
        wall = time.monotonic() - start
        signal.setitimer(signal.ITIMER_REAL, 0)
    finally:
        signal.signal(signal.SIGALRM, old)
    leftovers = False
    try:
        os.killpg(pid, signal.SIGKILL)  # the group still has members: the command left them running
        leftovers = True
    except ProcessLookupError:
        pass
    if timed_out:
        raise Deadline()
    result = {"wall": wall, "user": ru.ru_utime, "sys": ru.ru_stime, "cpu": ru.ru_utime + ru.ru_stime,
              "peak": ru.ru_maxrss / 1024.0, "leftovers": leftovers}  # ru_maxrss is in KiB on Linux
    if os.WIFSIGNALED(status):
        result["error"] = f"killed by signal {os.WTERMSIG(status)}"
    elif os.WEXITSTATUS(status) != 0:
        result["error"] = f"exited {os.WEXITSTATUS(status)}"
    return result


MEASURES = [("wall", "s"), ("user", "s"), ("sys", "s"), ("cpu", "s"), ("peak", "MiB")]
RATIOS = ["wall", "user", "cpu"]


def row(label, values, fmt):
    return f"{label:<14} {fmt.format(min(values)):>10} {fmt.format(statistics.median(values)):>10} " \
           f"{fmt.format(max(values)):>10}"


def report(names, runs, warmup, out):
    """Print the min / median / max table of the counted runs (and the A/B ratios with two commands)."""
    count = min(len(r) for r in runs.values()) if len(names) > 1 else len(runs["A"])
    for key, argv in names.items():
        print(f"{key}: {shlex.join(argv)}", file=out)
    what = "pairs" if len(names) > 1 else "runs"
    print(f"{count} {what} counted after {warmup} warm-up run(s) of each command; whole process", file=out)
    if count == 0:
        return
    print(f"{'':<14} {'min':>10} {'median':>10} {'max':>10}", file=out)
    for key in names:
        for m, unit in MEASURES:
            fmt = "{:.1f}" if unit == "MiB" else "{:.3f}"
            print(row(f"{key} {m} {unit}", [r[m] for r in runs[key][:count]], fmt), file=out)
    if len(names) > 1:
        for m in RATIOS:
            ratios = [a[m] / b[m] if b[m] > 0 else float("inf")
                      for a, b in zip(runs["A"][:count], runs["B"][:count])]
            print(row(f"A/B {m}", ratios, "{:.3f}"), file=out)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if "--" in argv:
        cut = argv.index("--")
        opts, command = argv[:cut], argv[cut + 1:]
    else:
        opts, command = argv, []
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                usage="%(prog)s [-n RUNS] [--warmup W] [--timeout S] [--vs 'COMMAND_B'] "
                                      "-- COMMAND_A ARGS...")
    p.add_argument("-n", type=int, default=5, metavar="RUNS", help="counted runs of each command (default 5)")
    p.add_argument("--warmup", type=int, default=1, metavar="W", help="uncounted runs of each first (default 1)")
    p.add_argument("--timeout", type=float, default=None, metavar="S", help="bound on the whole call, seconds")
    p.add_argument("--vs", default=None, metavar="COMMAND_B", help="the second command, one string")
    args = p.parse_args(opts)
    if not command:
        p.error("no command: give it after --")
    if args.n < 1 or args.warmup < 0 or (args.timeout is not None and args.timeout <= 0):
        p.error("-n must be at least 1, --warmup at least 0, --timeout above 0")
    names = {"A": command}
    if args.vs is not None:
        names["B"] = shlex.split(args.vs)
        if not names["B"]:
            p.error("--vs is empty")
    deadline = None if args.timeout is None else time.monotonic() + args.timeout
    runs = {key: [] for key in names}
    failure = None
    note = None
    try:
        for i in range(args.warmup + args.n):
            counted = i >= args.warmup
            for key, cmd in names.items():
                r = run_once(cmd, deadline)
                label = f"{key} run {i - args.warmup + 1}" if counted else f"{key} warm-up {i + 1}"
                if r.get("leftovers"):
                    print(f"note: {label} left processes running in its group; they were killed", file=sys.stderr)
                if "error" in r:
                    failure = f"{label} failed: {r['error']}"
                    raise StopIteration
                if counted:
                    runs[key].append(r)
    except Deadline:
        note = f"stopped at the time bound ({args.timeout:g} s); the finished runs follow"
    except StopIteration:
        pass
    if note:
        print(note)
    report(names, runs, args.warmup, sys.stdout)
    if failure:
        print(failure)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
