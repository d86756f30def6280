"""Tables as records: a sweep's tidy table (the ``sweep.csv`` the CLI writes, read cell by cell)
and any list of dicts as a pandas or polars frame when one of them is installed (neither is
required)."""

from __future__ import annotations

import csv
import io
from typing import Any, Dict, List, Optional

from ._catflip import CatflipError

#: Columns whose cells are words (the rest are numbers, or an axis's values).
_WORDS = {
    "schedule",
    "engine",
    "status",
    "reason",
    "warnings",
    "motor_worst_limit",
    "retimed_from",
    "solver_status",
    "whole_start",
    "rapier_verdict",
}
_COUNTS = {"case", "calibration_evaluations", "rapier_steps"}


def _cell(name: str, text: str) -> Any:
    if name in _WORDS:
        return text
    if text == "":
        return None
    if name in _COUNTS:
        return int(text)
    if name == "within_motors":
        return text == "true"
    try:
        return float(text)
    except ValueError:
        return text  # an axis of words (e.g. manoeuvre.profile)


def records_from_csv(text: str) -> List[Dict[str, Any]]:
    """The rows of a sweep's ``sweep.csv`` as dicts: empty cells are ``None`` (the quantity does
    not exist for that row), numbers are the very floats the CLI wrote (shortest round-trip)."""
    return [{k: _cell(k, v) for k, v in row.items()} for row in csv.DictReader(io.StringIO(text))]


def frame(records: List[Dict[str, Any]], backend: Optional[str] = None) -> Any:
    """``records`` as a data frame: pandas when installed (or ``backend="pandas"``), else polars
    (or ``backend="polars"``). Raises ``ImportError`` naming both when neither is installed."""
    if backend not in (None, "pandas", "polars"):
        raise CatflipError(f'backend = {backend!r}: must be "pandas" or "polars" (or None: whichever is installed)')
    order = [backend] if backend else ["pandas", "polars"]
    for name in order:
        try:
            module = __import__(name)
        except ImportError:
            continue
        return module.DataFrame(records)
    raise ImportError(f"a data frame needs {' or '.join(order)}; the records are a list of dicts as they are")
