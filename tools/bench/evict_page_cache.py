#!/usr/bin/env python3
"""Drops files from the page cache (posix_fadvise POSIX_FADV_DONTNEED), so that a benchmark can time a
run that must read them from disk, as one after a pause does: this project's 2-core machine gives
file pages back within minutes (docs/journal/).

    tools/bench/evict_page_cache.py [--pdmesh BIN] [FILE ...]

With --pdmesh, also the binary, every shared library `ldd` lists for it, and PoCL's LLVM and clang
libraries (what the OpenCL backend loads). Pages still mapped by a running process stay. Prints how
many files it advised. Standard library only; no privileges needed. Example (hyperfine runs it
before every timed run):

    hyperfine -N -w 1 -r 10 --prepare 'tools/bench/evict_page_cache.py --pdmesh build/pdmesh' \\
        'build/pdmesh mesh cases/30p30n/airfoil.crv cases/30p30n/farfield.crv --out D -q'
"""
import argparse
import glob
import os
import subprocess
import sys

POCL_LIBRARIES = ["/usr/lib/x86_64-linux-gnu/libLLVM-*.so*", "/usr/lib/llvm-*/lib/libclang-cpp.so*",
                  "/usr/lib/x86_64-linux-gnu/libpocl.so*", "/usr/lib/x86_64-linux-gnu/pocl/*.so"]


def shared_libraries(binary):
    out = subprocess.run(["ldd", binary], capture_output=True, text=True, check=True).stdout
    return [parts[2] for parts in (line.split() for line in out.splitlines())
            if len(parts) >= 3 and parts[1] == "=>" and parts[2].startswith("/")]


def evict(path):
    fd = os.open(path, os.O_RDONLY)
    try:
        os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED)
    finally:
        os.close(fd)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pdmesh", help="a pdmesh binary: it, its shared libraries and PoCL's")
    parser.add_argument("files", nargs="*")
    args = parser.parse_args()
    files = list(args.files)
    if args.pdmesh:
        files += [args.pdmesh] + shared_libraries(args.pdmesh)
        for pattern in POCL_LIBRARIES:
            files += glob.glob(pattern)
    seen = set()
    for path in files:
        real = os.path.realpath(path)
        if real in seen:
            continue
        seen.add(real)
        try:
            evict(real)
        except OSError as e:
            print(f"evict_page_cache: {path}: {e.strerror}", file=sys.stderr)
            return 2
    print(f"evict_page_cache: {len(seen)} files advised", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
