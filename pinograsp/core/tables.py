"""Tables of results: one row per profile direction or per max-wrench result, as CSV (standard
library) or a ``pandas.DataFrame`` (``pip install "pinograsp[tables]"``; imported lazily).

* :func:`profile_rows`, :func:`profile_to_csv`, :func:`profile_to_dataframe` — a
  :class:`~pinograsp.core.results.ResistanceProfile` (its own methods ``rows``, ``to_csv``,
  ``to_dataframe``); columns :data:`PROFILE_COLUMNS`.
* :func:`results_rows`, :func:`results_to_csv`, :func:`results_table` — a batch of
  :class:`~pinograsp.core.results.MaxWrench` (a sequence, or a mapping such as ``{preload: result}``
  or ``{(grasp, direction): result}``); columns :data:`RESULT_COLUMNS`.

Magnitudes are absolute [N or N·m]: ``inf`` where unbounded (written ``inf`` in CSV), the upper
limit (a lower bound) for ``"above_limit"``, ``0`` for ``"below_resolution"``; the ``status``
column says which.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..errors import InvalidInputError
from .axes import WRENCH_AXES
from .results import PROFILE_COLUMNS, RESULT_FIELDS, MaxWrench, ResistanceProfile
from .serialize import require_pandas, write_csv

__all__ = [
    "PROFILE_COLUMNS",
    "RESULT_COLUMNS",
    "profile_rows",
    "profile_to_csv",
    "profile_to_dataframe",
    "results_rows",
    "results_table",
    "results_to_csv",
]

#: Columns of :func:`results_rows` (and of the batch CSV), in order; ``key``: the mapping key or
#: the position in the sequence; ``audit_failures``: how many resisted magnitudes failed the audit.
RESULT_COLUMNS = ("key", "label", *WRENCH_AXES, "magnitude", *RESULT_FIELDS, "audit_failures")
#: The CSV writer (kept under its old name for callers of this module).
_write_csv = write_csv


def _profile(profile: object) -> ResistanceProfile:
    if not isinstance(profile, ResistanceProfile):
        raise InvalidInputError("profile", f"expected a ResistanceProfile, got {type(profile).__name__}")
    return profile


def profile_rows(profile: ResistanceProfile) -> list[dict[str, Any]]:
    """:meth:`ResistanceProfile.rows <pinograsp.core.results.ResistanceProfile.rows>`: one dict
    per direction with the keys :data:`PROFILE_COLUMNS`; ``magnitude`` [N or N·m] absolute
    (``inf`` where unbounded)."""
    return _profile(profile).rows()


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
    return _profile(profile).to_csv(path, name=name)


def profile_to_dataframe(profile: ResistanceProfile) -> Any:
    """:func:`profile_rows` as a ``pandas.DataFrame`` (columns :data:`PROFILE_COLUMNS`).

    Raises:
        MissingDependencyError: pandas is not installed (``pip install "pinograsp[tables]"``).
    """
    return _profile(profile).to_dataframe()


def results_rows(results: Sequence[MaxWrench] | Mapping[Any, MaxWrench]) -> list[dict[str, Any]]:
    """One dict per :class:`~pinograsp.core.results.MaxWrench` with the keys :data:`RESULT_COLUMNS`.

    Args:
        results: A sequence of results (``key`` is the position) or a mapping (``key`` is the
            mapping key, e.g. a preload name or a ``(grasp, direction)`` tuple).
    """
    items: list[tuple[Any, object]]
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
        if not isinstance(mw, MaxWrench):
            raise InvalidInputError(f"results[{key!r}]", f"expected a MaxWrench, got {type(mw).__name__}")
        row = {"key": key, **mw.row(), "audit_failures": len(mw.audit_failures)}
        rows.append({k: row[k] for k in RESULT_COLUMNS})
    return rows


def results_to_csv(results: Sequence[MaxWrench] | Mapping[Any, MaxWrench], path: object) -> Path:
    """Write :func:`results_rows` of a batch of max-wrench results to a CSV file (header
    :data:`RESULT_COLUMNS`). Returns the path written."""
    return write_csv(path, RESULT_COLUMNS, results_rows(results), "path")


def results_table(results: Sequence[MaxWrench] | Mapping[Any, MaxWrench]) -> Any:
    """:func:`results_rows` of a batch of max-wrench results as a ``pandas.DataFrame``
    (columns :data:`RESULT_COLUMNS`, one row per result).

    Raises:
        MissingDependencyError: pandas is not installed (``pip install "pinograsp[tables]"``).
    """
    rows = results_rows(results)  # validate before asking for pandas
    pd = require_pandas("results_table")
    return pd.DataFrame(rows, columns=list(RESULT_COLUMNS))
