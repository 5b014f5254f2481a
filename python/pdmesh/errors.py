"""pdmesh's exceptions: the C++ core's typed errors, with the command's messages.

``InputError`` (and its ``GeometryError`` and ``LimitError``) is what the command reports with exit
status 2: bad files, keys, values, geometry, or a case too large. ``DeviceError`` and
``SimulationError`` are its exit status 1. ``Cancelled`` is raised when a progress callable returns
False.
"""

from __future__ import annotations


class Error(Exception):
    """Base of every pdmesh error."""


class InputError(Error, ValueError):
    """Bad input: a file, a case-file key or value, a size; the message names it and the value."""


class GeometryError(InputError):
    """Geometry that cannot mesh: unclosed loops, intersecting curves, repeated points."""


class LimitError(InputError):
    """Valid input that needs unreasonable resources (too many nodes, unresolvable coordinates)."""


class DeviceError(Error, RuntimeError):
    """An OpenCL platform, build or run-time failure."""


class SimulationError(Error, RuntimeError):
    """A simulation that went wrong (non-finite forces, a failed mesh check)."""


class Cancelled(Error):
    """The progress callable returned False. ``mesher`` is the stopped run: it can go on."""

    def __init__(self, message: str, mesher=None):
        super().__init__(message)
        self.mesher = mesher


__all__ = ["Error", "InputError", "GeometryError", "LimitError", "DeviceError", "SimulationError", "Cancelled"]
