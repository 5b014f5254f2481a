"""``python -m pdmesh ...`` and the ``pdmesh`` console script: the command line of the C++ binary
(``pdmesh mesh CASE --out DIR``, ``pdmesh quality``, ``pdmesh devices``, ``pdmesh bench``)."""

from __future__ import annotations

import sys


def main(argv: list[str] | None = None) -> int:
    from . import _core

    args = sys.argv[1:] if argv is None else list(argv)
    sys.stdout.flush()
    sys.stderr.flush()
    return _core.main(["pdmesh", *args])


if __name__ == "__main__":
    sys.exit(main())
