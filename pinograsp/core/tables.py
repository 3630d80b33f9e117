"""Tables of results: one row per profile direction or per max-wrench result, as CSV (standard
library) or a ``pandas.DataFrame`` (``pip install "pinograsp[tables]"``; imported lazily).

* :func:`profile_rows`, :func:`profile_to_csv`, :func:`profile_to_dataframe` — a
  :class:`~pinograsp.core.results.ResistanceProfile` (also its methods ``rows``, ``to_csv``,
  ``to_dataframe``); columns :data:`PROFILE_COLUMNS`.
* :func:`results_rows`, :func:`results_to_csv`, :func:`results_table` — a batch of
  :class:`~pinograsp.core.results.MaxWrench` (a sequence, or a mapping such as ``{preload: result}``
  or ``{(grasp, direction): result}``); columns :data:`RESULT_COLUMNS`.

Magnitudes are absolute [N or N·m]: ``inf`` where unbounded (written ``inf`` in CSV), the upper
limit (a lower bound) for ``"above_limit"``, ``0`` for ``"below_resolution"``; the ``status``
column says which.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InvalidInputError, MissingDependencyError
from .axes import WRENCH_AXES
from .serialize import (
    MAX_WRENCH_FIELDS,
    PROFILE_FIELDS,
    MaxWrench,
    ResistanceProfile,
    absolute_magnitudes,
    direction_text,
    is_record,
    wrench_unit,
)
from .validate import writing

#: Columns that describe one max-wrench result, shared by the profile and batch tables.
_RESULT_FIELDS = (
    "unit",
    "status",
    "unbounded",
    "monotone",
    "upper",
    "resolution",
    "floor",
    "n_solves",
    "solve_time",
    "wall_time",
    "method",
    "search",
)

#: Columns of :func:`profile_rows` (and of the profile CSV), in order. ``fx`` ... ``mz``: the
#: unit direction; ``normalized``: magnitude / the profile's ``normalized_by`` (NaN, an empty
#: CSV cell, when the profile is not normalised).
PROFILE_COLUMNS = ("angle_deg", "label", *WRENCH_AXES, "magnitude", "normalized", *_RESULT_FIELDS)

#: Columns of :func:`results_rows` (and of the batch CSV), in order; ``key``: the mapping key or
#: the position in the sequence; ``audit_failures``: how many resisted magnitudes failed the audit.
RESULT_COLUMNS = ("key", "label", *WRENCH_AXES, "magnitude", *_RESULT_FIELDS, "audit_failures")


def _max_wrench_row(mw: MaxWrench) -> dict[str, Any]:
    d = np.asarray(mw.direction, dtype=float)
    return {
        "label": direction_text(d),
        **{ax: float(v) for ax, v in zip(WRENCH_AXES, d)},
        "magnitude": float(mw.magnitude),
        "unit": wrench_unit(d),
        "status": mw.status,
        "unbounded": bool(mw.unbounded),
        "monotone": bool(mw.monotone),
        "upper": float(mw.upper),
        "resolution": float(mw.resolution),
        "floor": float(mw.floor),
        "n_solves": int(mw.n_solves),
        "solve_time": float(mw.solve_time),
        "wall_time": float(mw.wall_time),
        "method": mw.method,
        "search": mw.search,
    }


def profile_rows(profile: ResistanceProfile) -> list[dict[str, Any]]:
    """One dict per direction of ``profile`` with the keys :data:`PROFILE_COLUMNS`.

    Args:
        profile: A :class:`~pinograsp.core.results.ResistanceProfile` of ``n`` directions.

    Returns:
        ``n`` rows; ``magnitude`` [N or N·m] absolute (``inf`` where unbounded).
    """
    if not is_record(profile, PROFILE_FIELDS):
        raise InvalidInputError("profile", f"expected a ResistanceProfile, got {type(profile).__name__}")
    mags = absolute_magnitudes(profile)
    ref = profile.normalized_by
    rows = []
    for i, mw in enumerate(profile.results):
        row = {"angle_deg": float(np.degrees(profile.angles[i])), **_max_wrench_row(mw)}
        row["magnitude"] = float(mags[i])
        row["normalized"] = float(mags[i] / ref) if ref else float("nan")
        rows.append({k: row[k] for k in PROFILE_COLUMNS})
    return rows


def results_rows(results: Sequence[MaxWrench] | Mapping[Any, MaxWrench]) -> list[dict[str, Any]]:
    """One dict per :class:`~pinograsp.core.results.MaxWrench` with the keys :data:`RESULT_COLUMNS`.

    Args:
        results: A sequence of results (``key`` is the position) or a mapping (``key`` is the
            mapping key, e.g. a preload name or a ``(grasp, direction)`` tuple).
    """
    if isinstance(results, Mapping):
        items = list(results.items())
    elif isinstance(results, Sequence) and not isinstance(results, (str, bytes)):
        items = list(enumerate(results))
    else:
        raise InvalidInputError(
            "results", f"expected a sequence or mapping of MaxWrench, got {type(results).__name__}"
        )
    rows = []
    for key, mw in items:
        if not is_record(mw, MAX_WRENCH_FIELDS):
            raise InvalidInputError(f"results[{key!r}]", f"expected a MaxWrench, got {type(mw).__name__}")
        row = {"key": key, **_max_wrench_row(mw), "audit_failures": len(mw.audit_failures)}
        rows.append({k: row[k] for k in RESULT_COLUMNS})
    return rows


def _cell(v: Any) -> Any:
    if isinstance(v, float) and np.isnan(v):
        return ""
    return v


def _write_csv(path: object, columns: Sequence[str], rows: list[dict[str, Any]], name: str) -> Path:
    def write(p: Path) -> None:
        with p.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(columns)
            for row in rows:
                w.writerow([_cell(row[c]) for c in columns])

    return writing(path, write, name=name)


def profile_to_csv(profile: ResistanceProfile, path: object, *, name: str = "path") -> Path:
    """Write :func:`profile_rows` to a CSV file (header :data:`PROFILE_COLUMNS`; ``inf`` where
    unbounded, an empty cell for a missing ``normalized``). Returns the path written.

    Args:
        profile: The profile.
        path: The CSV file (``str`` or ``os.PathLike``); parent folders are created.
        name: How errors name ``path`` (e.g. ``"--csv"``).

    Raises:
        InvalidInputError: ``path`` is not a file path or cannot be written.
    """
    return _write_csv(path, PROFILE_COLUMNS, profile_rows(profile), name)


def results_to_csv(results: Sequence[MaxWrench] | Mapping[Any, MaxWrench], path: object) -> Path:
    """Write :func:`results_rows` of a batch of max-wrench results to a CSV file (header
    :data:`RESULT_COLUMNS`). Returns the path written."""
    return _write_csv(path, RESULT_COLUMNS, results_rows(results), "path")


def _pandas(feature: str) -> Any:
    try:
        import pandas
    except ImportError:
        raise MissingDependencyError("pandas", feature, extra="tables") from None
    return pandas


def profile_to_dataframe(profile: ResistanceProfile) -> Any:
    """:func:`profile_rows` as a ``pandas.DataFrame`` (columns :data:`PROFILE_COLUMNS`).

    Raises:
        MissingDependencyError: pandas is not installed (``pip install "pinograsp[tables]"``).
    """
    pd = _pandas("ResistanceProfile.to_dataframe")
    return pd.DataFrame(profile_rows(profile), columns=list(PROFILE_COLUMNS))


def results_table(results: Sequence[MaxWrench] | Mapping[Any, MaxWrench]) -> Any:
    """:func:`results_rows` of a batch of max-wrench results as a ``pandas.DataFrame``
    (columns :data:`RESULT_COLUMNS`, one row per result).

    Raises:
        MissingDependencyError: pandas is not installed (``pip install "pinograsp[tables]"``).
    """
    rows = results_rows(results)  # validate before asking for pandas
    pd = _pandas("results_table")
    return pd.DataFrame(rows, columns=list(RESULT_COLUMNS))
