"""Batch rows are answers: a row's ``status`` and typed ``reason``, and their tabulation.

Every grasp of a batch ends as one row with a ``status``:

- ``"ok"``: scored;
- ``"partial"``: scored in some directions only: a direction raised an ``error`` (a solver
  failure, ...), the others answered (the score's ``status_<direction>`` columns say which;
  ``reason`` is the first failing direction's, ``error_message`` lists each);
- ``"no_grasp"``: the record is not a grasp — nothing touches, a link is deep inside the
  object, no preload exists, the given preload does not balance — an answer about the grasp,
  scored as such (the score's ``no_grasp`` values: 0 for the default score);
- ``"timeout"``: the opt-in per-grasp wall-clock limit was hit (no score: NaN);
- ``"error"``: a real error (a solver failure, bad input, a missing file, a worker that died
  on every attempt, a bug; no score: NaN).

``reason`` names the cause (:data:`REASONS`, first match by exception class); the exception's
class and message stay in ``error_type`` and ``error_message``. :func:`reason_counts`
tabulates any batch table by status and reason.
"""

from __future__ import annotations

from typing import Any, Literal

from ..errors import (
    InvalidInputError,
    MissingDependencyError,
    ModelError,
    ModelFileError,
    NoContactError,
    NoPreloadError,
    PenetrationError,
    PinograspError,
    PreloadNotInEquilibriumError,
    SolverError,
    SolverNotAvailableError,
    SolverTimeoutError,
    UnknownNameError,
)

#: Row status, coarse: scored, scored in some directions, not a grasp (an answer), the opt-in
#: time limit, a real error.
Status = Literal["ok", "partial", "no_grasp", "timeout", "error"]
STATUSES: tuple[str, ...] = ("ok", "partial", "no_grasp", "timeout", "error")

#: ``(exception class, status, reason)``: the first class the exception is an instance of wins.
REASONS: tuple[tuple[type[BaseException], str, str], ...] = (
    (NoContactError, "no_grasp", "no_contact"),
    (PenetrationError, "no_grasp", "penetration"),
    (NoPreloadError, "no_grasp", "no_preload"),
    (PreloadNotInEquilibriumError, "no_grasp", "not_in_equilibrium"),
    (SolverTimeoutError, "error", "solver_limit"),
    (SolverNotAvailableError, "error", "missing_dependency"),
    (SolverError, "error", "solver_error"),
    (MissingDependencyError, "error", "missing_dependency"),
    (UnknownNameError, "error", "unknown_name"),
    (ModelFileError, "error", "bad_file"),
    (ModelError, "error", "model_error"),
    (InvalidInputError, "error", "invalid_input"),
    (PinograspError, "error", "pinograsp_error"),
    (Exception, "error", "exception"),
)

#: Reasons of rows made by the batch itself (not by an exception of the grasp).
POOL_REASONS = {
    "worker_crashed": "error",  # the worker process died on each of its attempts
    "timeout": "timeout",  # the opt-in per-grasp wall-clock limit
    "exception": "error",  # the evaluation itself raised outside the grasp (a bug)
}


def classify(exc: BaseException) -> tuple[str, str]:
    """``(status, reason)`` of a grasp that raised ``exc``."""
    for cls, status, reason in REASONS:
        if isinstance(exc, cls):
            return status, reason
    return "error", "exception"


def reason_counts(table: Any) -> Any:
    """Rows per ``(status, reason)`` of a batch table, with one example message each.

    Returns:
        A ``pandas.DataFrame`` with columns ``status``, ``reason``, ``rows``, ``fraction``
        (of the batch) and ``example`` (the first row's ``error_message``), ordered by status
        (ok, partial, no_grasp, timeout, error) then by count.
    """
    import pandas as pd

    columns = ["status", "reason", "rows", "fraction", "example"]
    if len(table) == 0:
        return pd.DataFrame(columns=columns)
    groups = table.groupby(["status", "reason"], sort=False)
    out = groups.size().rename("rows").reset_index()
    out["fraction"] = out["rows"] / len(table)
    out["example"] = [str(g["error_message"].iloc[0]) for _, g in groups]
    rank = {s: k for k, s in enumerate(STATUSES)}
    out["_rank"] = out["status"].map(lambda s: rank.get(s, len(rank)))
    out = out.sort_values(["_rank", "rows", "reason"], ascending=[True, False, True], kind="stable")
    return out.drop(columns="_rank").reset_index(drop=True)[columns]
