"""Settings as case-file keys: Python values written as TOML values, handed to the command's own
validator (the same one as ``pdmesh mesh --set KEY=VALUE``), so that every error is the command's."""

from __future__ import annotations

import json
import math
import os
import re
from typing import Any, Iterable, Mapping

from .errors import InputError

SECTIONS = ("geometry", "spacing", "init", "simulation", "output")

# Keyword shortcuts, as the command's direct options (--iterations, --seed, ...).
SHORTCUTS = {
    "iterations": "simulation.iterations",
    "dt": "simulation.dt_initial",
    "cutoff": "simulation.cutoff",
    "method": "init.method",
    "seed": "init.seed",
    "total": "init.total",
    "device": "simulation.device",
    "precision": "simulation.precision",
    "r0_rule": "simulation.r0_rule",
    "formats": "output.formats",
    "color_by": "output.color_by",
}

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def toml_value(value: Any, key: str) -> str:
    """The TOML text of a Python value (bool, int, float, str, path, list, dict, numpy scalars)."""
    if hasattr(value, "item") and not isinstance(value, (list, tuple, dict, str)):
        value = value.item()  # numpy scalars and 0-d arrays
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, (str, os.PathLike)):
        return json.dumps(os.fspath(value))  # a TOML basic string: JSON's escapes are TOML's
    if isinstance(value, Mapping):
        items = []
        for k, v in value.items():
            name = str(k) if _BARE_KEY.match(str(k)) else json.dumps(str(k))
            items.append(f"{name} = {toml_value(v, f'{key}.{k}')}")
        return "{ " + ", ".join(items) + " }"
    if isinstance(value, (list, tuple)) or hasattr(value, "tolist"):
        seq = value.tolist() if hasattr(value, "tolist") else value
        return "[" + ", ".join(toml_value(v, f"{key}[{i}]") for i, v in enumerate(seq)) + "]"
    raise InputError(f"{key}: a {type(value).__name__} ({value!r}) cannot be a case-file value")


def flatten(settings: Mapping[str, Any] | None) -> list[tuple[str, Any]]:
    """Dotted keys from ``{"simulation.iterations": 5}``, ``{"simulation": {"iterations": 5}}`` or
    shortcuts such as ``{"iterations": 5}``, in the order given. ``farfield=("circle", 20)`` is
    ``farfield={"shape": "circle", "size": 20}`` (the command's ``--farfield circle:20``)."""
    out: list[tuple[str, Any]] = []
    for key, value in (settings or {}).items():
        key = str(key)
        if key == "farfield" and isinstance(value, (tuple, list)) and len(value) == 2:
            out.extend((("farfield.shape", value[0]), ("farfield.size", value[1])))
        elif key in SECTIONS and isinstance(value, Mapping):
            out.extend((f"{key}.{k}", v) for k, v in value.items())
        else:
            out.append((SHORTCUTS.get(key, key), value))
    return out


def overrides(pairs: Iterable[tuple[str, Any]]) -> list[tuple[str, str, str]]:
    """(key, TOML value, label) triples; the label is how messages name the setting: ``key=value``."""
    result = []
    for key, value in pairs:
        if value is None:
            continue
        text = toml_value(value, key)
        result.append((key, text, f"{key}={text}"))
    return result
