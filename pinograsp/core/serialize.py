"""Values as plain data and text, below every result record (``docs/results_api.md``).

* :func:`jsonable` — NumPy arrays and scalars to lists and numbers, ``inf``/``nan`` to ``None``.
* :func:`format_magnitude`, :func:`vector_text`, :func:`unbounded_runs`, :func:`runs_text` — a
  value printed to its resolution, a vector, runs of unbounded profile directions.
* :func:`write_csv`, :func:`require_pandas` — the table writers the records share.

Knows no record: each result record owns its ``to_dict()`` / ``summary()`` / ``repr`` and calls
these helpers (:mod:`pinograsp.core.results`, :mod:`pinograsp.core.audit`, and the records of
``analysis/`` and ``robots/``). NumPy and the standard library only.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InvalidInputError, MissingDependencyError
from .axes import direction_text, wrench_unit
from .validate import writing

__all__ = [
    "decimals",
    "direction_text",
    "format_magnitude",
    "jsonable",
    "real_number",
    "require_pandas",
    "runs_text",
    "unbounded_runs",
    "vector_text",
    "wrench_unit",
    "write_csv",
]


# ---------------------------------------------------------------------------- plain data
def jsonable(x: Any) -> Any:
    """``x`` as plain JSON-ready Python: NumPy arrays and scalars become lists, floats, ints and
    bools; tuples become lists; dict keys strings; ``inf`` and ``nan`` become ``None``; paths
    strings. Other objects are returned unchanged."""
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        v = float(x)
        return v if math.isfinite(v) else None
    if isinstance(x, Path):
        return str(x)
    return x


# ---------------------------------------------------------------------------- text of values
def decimals(resolution: float) -> int:
    """Decimals that show a value to its resolution: ``ceil(-log10(resolution))`` clipped to
    0–6 (4 when the resolution is not a positive number)."""
    if not resolution > 0 or not math.isfinite(resolution):
        return 4
    return int(min(6, max(0, math.ceil(-math.log10(resolution)))))


def real_number(name: str, value: object) -> float:
    """``float(value)`` for a real number (``inf`` and ``nan`` accepted), else InvalidInputError."""
    if isinstance(value, (str, bytes, bool)):
        raise InvalidInputError(name, f"expected a number, got {value!r}")
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(name, f"expected a number, got {value!r}") from None


def format_magnitude(value: float, resolution: float, unit: str | None = None) -> str:
    """A magnitude printed to its resolution.

    Args:
        value: The magnitude [N or N·m]; ``inf`` prints as ``"unbounded"``, ``nan`` as ``"nan"``.
        resolution: Its resolution [same unit] (e.g. the bisection's ``upper / 2**steps``).
        unit: Appended after a space when given.

    Examples: ``format_magnitude(1.3672, 0.2, "N")`` is ``"1.4 N"``,
    ``format_magnitude(4.29893, 4.8e-06, "N")`` is ``"4.298930 N"`` (at most 6 decimals).
    """
    v = real_number("value", value)
    resolution = real_number("resolution", resolution)
    if unit is not None and not isinstance(unit, str):
        raise InvalidInputError("unit", f"expected a string or None, got {unit!r}")
    if math.isinf(v):
        text = "unbounded" if v > 0 else "-unbounded"
    elif math.isnan(v):
        text = "nan"
    else:
        text = f"{v:.{decimals(resolution)}f}"
    return f"{text} {unit}" if unit and not math.isinf(v) else text


def signed_text(x: float, decimals: int = 3) -> str:
    """``x`` with a sign and ``decimals`` decimals, never ``-0.000`` (a rounding of 0 has no sign)."""
    return f"{round(float(x), decimals) + 0.0:+.{decimals}f}"


def vector_text(v: Sequence[float] | np.ndarray) -> str:
    """A vector as ``(0, 5, 0)`` with 4 significant digits (values below 1e-9 of the largest: 0)."""
    a = np.asarray(v, dtype=float)
    tiny = 1e-9 * max(1.0, float(np.abs(a).max(initial=0.0)))
    return "(" + ", ".join(f"{0.0 if abs(x) < tiny else x:.4g}" for x in a) + ")"


def unbounded_runs(angles_deg: np.ndarray, unbounded: np.ndarray) -> list[tuple[float, float]]:
    """Circular runs of unbounded directions of a profile as ``(first, last)`` angles [deg].

    Args:
        angles_deg: Direction angles [deg], (n,), ascending around the circle.
        unbounded: (n,) bool.
    """
    u = np.asarray(unbounded, bool)
    n = len(u)
    if n == 0 or not u.any():
        return []
    if u.all():
        return [(float(angles_deg[0]), float(angles_deg[-1]))]
    start = int(np.flatnonzero(~u)[0]) + 1  # begin right after a bounded direction
    runs, cur = [], None
    for k in range(n):
        i = (start + k) % n
        if u[i]:
            cur = (i, i) if cur is None else (cur[0], i)
        elif cur is not None:
            runs.append(cur)
            cur = None
    if cur is not None:
        runs.append(cur)
    return sorted((float(angles_deg[a]), float(angles_deg[b])) for a, b in runs)


def runs_text(runs: Sequence[tuple[float, float]]) -> str:
    """Runs of :func:`unbounded_runs` as ``"0°, 170°–190°"`` (``"none"`` when empty)."""
    if not runs:
        return "none"
    return ", ".join(f"{a:g}°" if a == b else f"{a:g}°–{b:g}°" for a, b in runs)


# ---------------------------------------------------------------------------- tables
def _cell(v: Any) -> Any:
    if isinstance(v, float) and np.isnan(v):
        return ""
    return v


def write_csv(path: object, columns: Sequence[str], rows: list[dict[str, Any]], name: str = "path") -> Path:
    """Write ``rows`` (dicts with the keys ``columns``) to a CSV file with header ``columns``
    (standard library ``csv``; NaN as an empty cell, ``inf`` as ``inf``); returns the path.

    Raises:
        InvalidInputError: (named ``name``) ``path`` is not a file path or cannot be written.
    """

    def write(p: Path) -> None:
        with p.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(columns)
            for row in rows:
                w.writerow([_cell(row[c]) for c in columns])

    return writing(path, write, name=name)


def require_pandas(feature: str) -> Any:
    """The ``pandas`` module, or :class:`~pinograsp.errors.MissingDependencyError` naming
    ``feature`` and the ``tables`` extra."""
    try:
        import pandas
    except ImportError:
        raise MissingDependencyError("pandas", feature, extra="tables") from None
    return pandas
