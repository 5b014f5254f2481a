#!/usr/bin/env python3
"""Where the device neighbour builds' time goes, from PoCL's text trace of a run on a profiling queue:

    PDMESH_KERNEL_PROFILE=/dev/null POCL_TRACING=text POCL_TRACING_OPT=/tmp/trace.log \\
        build/pdmesh mesh CASE --out DIR -q --timings DIR/t.json
    tools/bench/cl_trace_summary.py /tmp/trace.log

A build is the run of commands from a `bin_bounds` launch (kernels/binning.cl, the first of a build)
to the last neighbour-build kernel before the next other kernel (device_step, ...). Per command name
(kernel, or the command type and its size for transfers and fills) it prints the builds' device
seconds (each command's `running` to `complete`), the count and the share of the builds' span; the
span is the first command's start to the last one's end, and what is left of it is the device idle
between commands (the host's work and round trips: a build's waits). Standard library only.
"""
import argparse
import collections
import sys

BUILD_KERNELS = {
    "bin_bounds", "bin_rmin", "bin_levels", "bin_plan", "bin_count", "bucket_scan", "row_block_offsets",
    "bucket_offsets_add", "bin_fill", "row_capacity_scan", "row_offsets_add", "gather_rows", "row_level_tally",
    "sort_rows", "relocate_rows", "place_spilled", "apply_row_moves"
}


def read_events(path):
    """{event id: {'name', 'kernel', state: ns}} from a POCL_TRACING=text log."""
    events = {}
    with open(path) as f:
        for line in f:
            parts = [p.strip() for p in line.split("|")]
            if len(parts) < 6 or not parts[1].startswith("EV ID"):
                continue
            ev = int(parts[1].split()[2])
            e = events.setdefault(ev, {"kernel": False, "name": parts[4]})
            e[parts[5]] = int(parts[0])
            for p in parts[6:]:
                if p.startswith("name="):
                    e["name"], e["kernel"] = p[5:], True
                elif p.startswith("size=") and not e["kernel"]:
                    e["name"] = f"{parts[4]} {p}"
    return events


def builds(events):
    """Lists of event ids, one per build (see the top)."""
    out, cur, last_kernel = [], None, 0
    for ev in sorted(events):
        e = events[ev]
        if e["kernel"] and e["name"] == "bin_bounds":
            if cur:
                out.append(cur[:last_kernel])
            cur, last_kernel = [], 0
        if cur is None:
            continue
        if e["kernel"] and e["name"] not in BUILD_KERNELS:
            out.append(cur[:last_kernel])
            cur = None
            continue
        cur.append(ev)
        if e["kernel"]:
            last_kernel = len(cur)
    if cur:
        out.append(cur[:last_kernel])
    return [b for b in out if b]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("trace")
    ap.add_argument("--per-build", action="store_true", help="one line per build: span, busy, commands")
    args = ap.parse_args()
    events = read_events(args.trace)
    bs = builds(events)
    if not bs:
        sys.exit("no neighbour build in the trace (was the queue a profiling one: PDMESH_KERNEL_PROFILE=FILE?)")
    busy, count = collections.Counter(), collections.Counter()
    span_total = 0
    for k, b in enumerate(bs):
        timed = [events[ev] for ev in b if "running" in events[ev] and "complete" in events[ev]]
        if not timed:
            continue
        span = max(e["complete"] for e in timed) - min(e["running"] for e in timed)
        span_total += span
        b_busy = 0
        for e in timed:
            busy[e["name"]] += e["complete"] - e["running"]
            count[e["name"]] += 1
            b_busy += e["complete"] - e["running"]
        if args.per_build:
            print(f"build {k}: span {span / 1e9:.4f} s, device busy {b_busy / 1e9:.4f} s, {len(b)} commands")
    total_busy = sum(busy.values())
    print(f"{len(bs)} builds: span {span_total / 1e9:.3f} s ({span_total / 1e9 / len(bs):.4f} s per build), "
          f"device busy {total_busy / 1e9:.3f} s, idle between commands {(span_total - total_busy) / 1e9:.3f} s")
    print(f"{'command':<40} {'seconds':>9} {'count':>6} {'share':>7}")
    for name, ns in busy.most_common():
        print(f"{name:<40} {ns / 1e9:9.4f} {count[name]:6d} {100 * ns / span_total:6.1f}%")


if __name__ == "__main__":
    main()
