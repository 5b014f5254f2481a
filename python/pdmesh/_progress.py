"""Progress of a run: the state handed to a progress callable, and the bar that ``progress=True`` draws."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import Any, Callable


@dataclass(frozen=True)
class Progress:
    """Where a run is, as given to a ``progress`` callable (about every 0.1 s, and after the last
    iteration of each step). Return False from the callable to cancel the run."""

    iteration: int        #: iterations done, counted from the start of the run
    iterations: int       #: the total this step runs to
    average_force: float  #: average |F| over the moving nodes (history.csv's column)
    max_force: float      #: largest |F|
    dt: float             #: the global maximum time step dt_GM of this iteration
    seconds: float        #: time since this step began
    converged: bool = False  #: the stopping rule ended the run here, before ``iterations`` (the last report)

    @property
    def fraction(self) -> float:
        return self.iteration / self.iterations if self.iterations else 1.0


class Bar:
    """A one-line progress bar on stderr: redrawn in place on a terminal and in Jupyter; in a log
    (not a terminal) one line every 5 s and the last one, as the command does."""

    LOG_INTERVAL = 5.0

    def __init__(self, stream=None, width: int = 30):
        self.stream = stream or sys.stderr
        self.width = width
        self.drawn = False
        isatty = getattr(self.stream, "isatty", None)
        # ipykernel's streams are no terminals but redraw "\r" lines like one.
        self.in_place = bool(isatty and isatty()) or type(self.stream).__module__.startswith("ipykernel")
        self.logged_at = None

    def __call__(self, p: Progress) -> None:
        # A converged run is complete: a full bar, and the iteration it stopped at.
        filled = self.width if p.converged else int(round(self.width * p.fraction))
        count = f"{p.iteration}/{p.iterations}" + (" converged" if p.converged else "")
        line = (f"pdmesh: [{'#' * filled}{'.' * (self.width - filled)}] {count} "
                f"avg |F| {p.average_force:.3g}  dt {p.dt:.3g}  {p.seconds:.1f} s")
        if self.in_place:
            self.stream.write("\r" + line)
            self.drawn = True
        elif (p.converged or p.iteration == p.iterations or self.logged_at is None
              or p.seconds - self.logged_at >= self.LOG_INTERVAL):
            self.stream.write(line + "\n")
            self.logged_at = p.seconds
        self.stream.flush()

    def close(self) -> None:
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()
            self.drawn = False


def callback(progress: Any) -> tuple[Callable | None, Bar | None]:
    """(the callable the core calls with its six numbers, the bar to close afterwards)."""
    if progress is None or progress is False:
        return None, None
    bar = Bar() if progress is True else None
    user = bar if bar is not None else progress
    if not callable(user):
        raise TypeError(f"progress: expected True, False or a callable, got {type(progress).__name__}")

    def report(iteration, iterations, average_force, max_force, dt, seconds, converged=False):
        return user(Progress(int(iteration), int(iterations), average_force, max_force, dt, seconds, bool(converged)))

    return report, bar
