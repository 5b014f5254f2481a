"""Small helpers shared by the evaluation tools: messages, atomic writes, JSON lookups, number
formatting for Markdown tables, the machine and commit a report was made on, case files."""

import os
import platform
import re
import subprocess
import sys

TOOL = "tools/eval/" + os.path.basename(sys.argv[0])  # the tools that print through it are in tools/eval/


def fail(message):
    print(f"{TOOL}: error: {message}", file=sys.stderr)
    sys.exit(1)


def log(message):
    print(f"{TOOL}: {message}", file=sys.stderr, flush=True)


def write_atomically(path, data):
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)
    os.replace(tmp, path)


def lookup(obj, path):
    """obj[path[0]][path[1]]...; None where a key is missing."""
    for key in path:
        if not isinstance(obj, dict) or key not in obj:
            return None
        obj = obj[key]
    return obj


def fmt(value, decimals):
    """A table cell: '—' for None, strings as they are, numbers with `decimals` decimals."""
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    if decimals == 0:
        return str(int(round(value)))
    return f"{value:.{decimals}f}"


def machine_description():
    """CPU model and count, OS, and the load average now (timings suffer from other work)."""
    model, cpus = platform.processor() or "unknown CPU", os.cpu_count()
    try:
        text = subprocess.run(["lscpu"], stdout=subprocess.PIPE, text=True).stdout
        m = re.search(r"^Model name:\s*(.+)$", text, re.M)
        if m:
            model = m.group(1).strip()
    except OSError:
        pass
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    return (f"{model}, {cpus} logical CPUs, {platform.system()} {platform.release()}; load average "
            f"{load} when the report was written (timings suffer when other work shares the cores)")


def git_description(repo, out_dir):
    """The short commit, with -dirty when files outside out_dir differ from it."""
    def git(*a):
        return subprocess.run(["git", "-C", repo, *a], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                              text=True).stdout.strip()
    commit = git("rev-parse", "--short", "HEAD") or "unknown"
    rel = os.path.relpath(os.path.abspath(out_dir), repo)
    dirty = git("status", "--porcelain", "--", ".", f":(exclude){rel}")
    return commit + ("-dirty" if dirty else "")


def read_case(path):
    """A case file (or a directory holding case.toml) as a dict, with 'dir' added. Needs Python
    3.11's tomllib."""
    try:
        import tomllib
    except ImportError:
        fail("reading case files needs Python 3.11 or newer (tomllib)")
    if os.path.isdir(path):
        path = os.path.join(path, "case.toml")
    with open(path, "rb") as f:
        case = tomllib.load(f)
    case["dir"] = os.path.dirname(os.path.abspath(path))
    return case
