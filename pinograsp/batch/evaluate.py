"""Batch evaluation of grasps: one DataFrame row per grasp, on this machine or a cluster.

``pg.evaluate_grasps(grasps, score=..., executor="local" | "ray" | "dask" | client)`` builds each
grasp (a scene, or a :class:`~pinograsp.batch.grasps.GraspSpec` auto-closed and preloaded), scores it
with a pluggable ``score(model, command) -> {name: float}`` and returns a ``pandas.DataFrame``
(columns :data:`BASE_COLUMNS`, the score's columns, :data:`TAIL_COLUMNS`). Every grasp is a row
with a ``status`` and a typed ``reason`` (:mod:`.rows`): a record that is not a grasp (no
contact, no preload, ...) is an answer (``"no_grasp"``, score 0), a real failure an
``"error"`` row; the batch goes on. With ``out=`` rows are journaled as they finish
(:mod:`.journal`), ``resume=True`` skips the finished ones, and the table is written atomically.

Determinism: each grasp is evaluated from its own record alone, in one BLAS thread, by the
exact (canonical) solvers, and rows are put back in input order, so every column except
:data:`TIMING_COLUMNS` is identical whatever the executor, worker count, completion order or
interruptions and resumes.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import threading
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ..core.validate import positive_number, whole_number
from ..errors import InvalidInputError, MissingDependencyError
from .executors import check_executor, run_chunks
from .grasps import GraspSpec, build_grasp, rpy_of
from .journal import Journal, check_output, output_format, write_table
from .pool import Interrupted, TaskFailure, interruptible
from .resume import check_stamp, fingerprint, table_rows, write_stamp
from .rows import POOL_REASONS, Status, classify
from .scores import WorstAxisScore

__all__ = ["Status", "WorstAxisScore", "output_format"]  # re-exported: pg.batch.evaluate.output_format
#: Score callable: ``score(model, command) -> {name: value}`` (floats; ``inf`` allowed).
Score = Callable[[Any, dict[str, float]], Mapping[str, float]]

#: Columns before the score's.
BASE_COLUMNS = (
    "index",
    "id",
    "source",
    "status",
    "reason",
    "n_contacts",
    "command",
    "obj_x",
    "obj_y",
    "obj_z",
    "obj_roll",
    "obj_pitch",
    "obj_yaw",
)
#: Wall times [s]: grasp build (hand, auto-close, contacts), ``"auto"`` preload, score, total.
TIMING_COLUMNS = ("time_build", "time_preload", "time_score", "time_total")
#: Columns after the score's.
TAIL_COLUMNS = ("error_type", "error_message", "warnings", *TIMING_COLUMNS)


def _task(i: int, item: object) -> tuple[int, str, str, Any]:
    """``(index, id, kind, payload)`` shipped to a worker."""
    gid = str(i)
    if isinstance(item, Mapping):
        item = dict(item)
        if "scene" in item:
            if set(item) - {"scene", "id"}:
                raise InvalidInputError(f"grasps[{i}]", "a scene record takes only 'scene' and 'id'")
            gid = str(item.get("id", i))
            item = item["scene"]
            if not isinstance(item, (str, os.PathLike)):
                raise InvalidInputError(f"grasps[{i}].scene", f"expected a scene name or path, got {item!r}")
        else:
            try:
                item = GraspSpec(**item)
            except TypeError as exc:
                raise InvalidInputError(f"grasps[{i}]", str(exc)) from None
    if isinstance(item, GraspSpec):
        return i, item.id or str(i), "spec", item
    if isinstance(item, (str, os.PathLike)):
        return i, gid, "scene", str(item)
    from ..scenes.schema import Scene  # below this layer; imported on use like the scene loader

    if isinstance(item, Scene):
        return i, str(i), "model", (item.name, item.model, dict(item.command), getattr(item, "object", None))
    raise InvalidInputError(
        f"grasps[{i}]", f"expected a GraspSpec, a mapping, a scene name/path or a Scene, got {item!r}"
    )


def _pose_columns(obj: Any) -> dict[str, float]:
    keys = ("obj_x", "obj_y", "obj_z", "obj_roll", "obj_pitch", "obj_yaw")
    if obj is None:
        return dict.fromkeys(keys, math.nan)
    T = obj.pose
    return dict(zip(keys, [*(float(v) for v in T[:3, 3]), *rpy_of(T[:3, :3])]))


def _model_of(kind: str, payload: Any, row: dict[str, Any]) -> tuple[Any, dict[str, float]]:
    if kind == "spec":
        row["source"] = payload.hand
        row.update(_pose_columns(payload.object))
        model, command, times = build_grasp(payload)
        row["time_build"], row["time_preload"] = times["build"], times["preload"]
        return model, command
    if kind == "scene":
        from ..scenes.loading import load_scene

        t0 = time.perf_counter()
        row["source"] = payload
        scene = load_scene(payload)
        row["source"] = scene.name
        row.update(_pose_columns(scene.object))
        row["time_build"] = time.perf_counter() - t0
        return scene.model, dict(scene.command)
    name, model, command, obj = payload
    row["source"] = name
    row.update(_pose_columns(obj))
    return model, command


def _score_values(values: object) -> dict[str, float]:
    if not isinstance(values, Mapping):
        raise InvalidInputError("score", f"must return a mapping name -> float, got {type(values).__name__}")
    out = {}
    for k, v in values.items():
        if not isinstance(k, str) or k in BASE_COLUMNS or k in TAIL_COLUMNS:
            raise InvalidInputError("score", f"returned the key {k!r}: keys are strings not named as columns")
        try:
            out[k] = float(v)
        except (TypeError, ValueError):
            raise InvalidInputError("score", f"returned {k}={v!r}, not a number") from None
    return out


def _empty_row(task: tuple[int, str, str, Any]) -> dict[str, Any]:
    """A row with every column, before the grasp is evaluated (source and pose when known)."""
    index, gid, kind, payload = task
    row: dict[str, Any] = {"index": index, "id": gid, "source": "", "status": "error", "reason": ""}
    row.update({"n_contacts": 0, "command": "", **_pose_columns(None), "error_type": "", "error_message": ""})
    row.update({"warnings": "", **dict.fromkeys(TIMING_COLUMNS, 0.0), "scores": {}, "statuses": {}})
    if kind == "spec":
        row["source"] = payload.hand
        row.update(_pose_columns(payload.object))
    elif kind == "scene":
        row["source"] = payload
    else:
        row["source"] = payload[0]
        row.update(_pose_columns(payload[3]))
    return row


def _no_grasp_values(score: Score) -> dict[str, float]:
    """The score of a record that is not a grasp: the score's ``no_grasp`` (default ``score`` 0)."""
    values = getattr(score, "no_grasp", None)
    return _score_values(values) if isinstance(values, Mapping) else {"score": 0.0}


#: Held by a grasp evaluated outside the main thread (a thread-pool executor), see evaluate_one.
_WARNINGS_LOCK = threading.Lock()


def evaluate_one(task: tuple[int, str, str, Any], score: Score) -> dict[str, Any]:
    """One grasp's row (never raises on a bad grasp: its status, reason and error are in the row)."""
    from ..solvers.threads import single_threaded_blas

    kind, payload = task[2], task[3]
    row = _empty_row(task)
    t0 = time.perf_counter()
    # warnings are caught process-wide: grasps of a thread pool run one at a time, so that each
    # row gets its own grasp's warnings (processes, Ray and Dask workers are unaffected)
    threaded = threading.current_thread() is not threading.main_thread()
    with (
        _WARNINGS_LOCK if threaded else contextlib.nullcontext(),
        warnings.catch_warnings(record=True) as caught,
        single_threaded_blas(),
    ):
        warnings.simplefilter("always")
        try:
            model, command = _model_of(kind, payload, row)
            row["n_contacts"] = int(model.nc)
            row["command"] = json.dumps({k: float(v) for k, v in command.items()})
            t1 = time.perf_counter()
            values = score(model, command)
            row["scores"] = _score_values(values)
            row["time_score"] = time.perf_counter() - t1
            _answered(row, values)
        except Exception as exc:  # one bad grasp never stops the batch
            row["status"], row["reason"] = classify(exc)
            row["error_type"] = type(exc).__name__
            row["error_message"] = " ".join(str(exc).split())
            if row["status"] == "no_grasp":
                row["scores"] = _no_grasp_values(score)
            detected = getattr(exc, "contacts_detected", None)  # no preload, yet contacts
            if detected is not None:
                row["n_contacts"] = int(detected)
    seen = dict.fromkeys(f"{w.category.__name__}: {' '.join(str(w.message).split())}" for w in caught)
    row["warnings"] = "; ".join(seen)
    row["time_total"] = time.perf_counter() - t0
    return row


def _answered(row: dict[str, Any], values: object) -> None:
    """Status of a scored row: ``"ok"``, or ``"partial"`` when some directions of the score did
    not answer (its ``failures``: the first one's reason, every one's error in the row), and the
    score's per-direction ``statuses``."""
    statuses = getattr(values, "statuses", None) or {}
    row["statuses"] = {str(k): str(v) for k, v in statuses.items()}
    failures = tuple(getattr(values, "failures", ()) or ())
    row["status"] = "partial" if failures else "ok"
    if failures:
        row["reason"], row["error_type"] = failures[0].reason, failures[0].error_type
        row["error_message"] = "; ".join(f"{f.direction}: {f.error_type}: {f.message}" for f in failures)


def _evaluate_chunk(chunk: Sequence[tuple], score: Score) -> list[dict[str, Any]]:
    return [evaluate_one(task, score) for task in chunk]


def failure_row(task: tuple[int, str, str, Any], failure: TaskFailure) -> dict[str, Any]:
    """The row of a grasp that produced none: its worker died on every attempt
    (``worker_crashed``), it hit the opt-in time limit (``timeout``) or the evaluation raised."""
    row = _empty_row(task)
    row["status"], row["reason"] = POOL_REASONS[failure.kind], failure.kind
    row["error_type"] = {"worker_crashed": "WorkerCrashed", "timeout": "Timeout"}.get(
        failure.kind, "Exception"
    )
    row["error_message"] = failure.detail
    row["time_total"] = float(failure.seconds)
    return row


def _pandas() -> Any:
    try:
        import pandas
    except ImportError:
        raise MissingDependencyError("pandas", "evaluate_grasps", extra="tables") from None
    return pandas


def score_columns(score: Score, rows: Sequence[dict[str, Any]]) -> list[str]:
    """The score's columns: its ``columns`` attribute if it has one, else ``score`` then the
    keys the rows returned (so ``score`` is a column even when every row is an error)."""
    declared = getattr(score, "columns", None)
    names: dict[str, None] = dict.fromkeys(declared if isinstance(declared, (tuple, list)) else ("score",))
    for r in rows:
        names.update(dict.fromkeys(r["scores"]))
    return list(names)


def status_columns(score: Score, rows: Sequence[dict[str, Any]] = ()) -> list[str]:
    """The score's per-direction status columns: its ``status_columns`` attribute if it has one,
    then the ones the rows returned (text: ``"ok"``, a reason, or ``""``)."""
    declared = getattr(score, "status_columns", None)
    names: dict[str, None] = dict.fromkeys(declared if isinstance(declared, (tuple, list)) else ())
    for r in rows:
        names.update(dict.fromkeys(r.get("statuses") or {}))
    return list(names)


def results_frame(rows: Sequence[dict[str, Any]], score: Score) -> Any:
    """The table of rows (any order): sorted by ``index``, every column present, fixed dtypes."""
    pd = _pandas()
    rows = sorted(rows, key=lambda r: r["index"])
    names = score_columns(score, rows)
    labels = status_columns(score, rows)
    table = []
    for r in rows:
        table.append({k: v for k, v in r.items() if k not in ("scores", "statuses")})
        table[-1].update({k: r["scores"].get(k, math.nan) for k in names})
        table[-1].update({k: (r.get("statuses") or {}).get(k, "") for k in labels})
    columns = [*BASE_COLUMNS, *names, *labels, *TAIL_COLUMNS]
    df = pd.DataFrame(table, columns=columns)
    return df.astype({"index": "int64", "n_contacts": "int64", **dict.fromkeys(names, "float64")})


def _tasks(grasps: object) -> list[tuple[int, str, str, Any]]:
    if isinstance(grasps, (str, bytes, Mapping)) or not isinstance(grasps, Sequence):
        raise InvalidInputError("grasps", f"expected a list of grasp records, got {type(grasps).__name__}")
    return [_task(i, g) for i, g in enumerate(grasps)]


def evaluate_grasps(
    grasps: Sequence[object],
    *,
    score: Score | None = None,
    executor: object = "local",
    workers: int | None = None,
    address: str | None = None,
    progress: Callable[[int, int], None] | None = None,
    chunksize: int = 1,
    out: str | os.PathLike | None = None,
    resume: bool = False,
    timeout: float | None = None,
) -> Any:
    """Score a batch of grasps, one row each, on local processes, Ray or Dask.

    Args:
        grasps: Grasp records: :class:`~pinograsp.batch.grasps.GraspSpec` (or a mapping of its
            fields), a scene name or YAML path, ``{"scene": ..., "id": ...}``, or a loaded
            :class:`~pinograsp.scenes.loading.Scene` (its model and preload are shipped).
        score: ``score(model, command) -> {name: float}``; default :class:`WorstAxisScore`.
            Optional attributes: ``columns`` (the table's score columns, present even when
            every row is an error) and ``no_grasp`` (values of a record that is not a grasp;
            default ``{"score": 0.0}``). Must be picklable for Ray, Dask and non-fork process
            pools (cloudpickle: lambdas are fine for Ray and Dask; the local pool on Linux
            forks and needs nothing).
        executor: ``"local"`` (pinograsp's own process pool, :mod:`.pool`; ``workers=1``
            without ``timeout``: in this process), ``"ray"``, ``"dask"``, a
            ``dask.distributed.Client`` or any ``concurrent.futures.Executor``.
        workers: Local processes, Ray tasks in flight or Dask local workers (``0`` or ``None``:
            one per CPU; on an existing cluster ``None`` uses all of it).
        address: An existing Ray (``"auto"``) or Dask (``"tcp://host:8786"``) cluster.
        progress: ``progress(done, total)`` as grasps finish (in this process).
        chunksize: Grasps per task.
        out: The table file (``.csv`` or ``.parquet``), checked before any work starts; rows
            are journaled to ``<out>.partial.jsonl`` as they finish, and the table is written
            atomically at the end (then the journal is removed).
        resume: Keep the finished rows of ``out``'s journal (same batch and score) and
            evaluate only the others: the same table as an uninterrupted run.
        timeout: Opt-in per-grasp wall-clock limit [s] (local executor): a grasp still running
            after it is a ``"timeout"`` row, never a number. Whether it is hit depends on the
            machine: leave it ``None`` for reproducible tables.

    Returns:
        A ``pandas.DataFrame``, one row per grasp in input order: :data:`BASE_COLUMNS`, the
        score's columns, its status columns (``status_<direction>``, text), :data:`TAIL_COLUMNS`.
        ``status`` is ``"ok"``, ``"partial"`` (some directions did not answer: the others kept,
        :mod:`pinograsp.batch.scores`), ``"no_grasp"`` (an answer: score 0), ``"timeout"`` or
        ``"error"``, ``reason`` the typed cause
        (:mod:`pinograsp.batch.rows`); ``command`` the preload as JSON ``{actuator: value}``
        [N·m or N]; ``obj_*`` the object pose (hand base frame, [m] and roll-pitch-yaw [rad]).

    Raises:
        InvalidInputError: A malformed record, executor or option, or ``out`` not writable.
        MissingDependencyError: pandas, or the chosen executor's package, is not installed.
        Interrupted: Ctrl-C or SIGTERM: pending work cancelled, workers stopped, the finished
            rows kept in the journal (a ``KeyboardInterrupt``; ``exit_code`` 130 or 143).
    """
    _pandas()
    tasks = _tasks(grasps)
    score = _score_of(score)
    size = whole_number("chunksize", chunksize)
    timeout = None if timeout is None else positive_number("timeout", timeout)
    check_executor(executor, address, timeout)
    journal = _journal(out, resume)
    where = {"executor": executor, "workers": workers, "address": address, "timeout": timeout}
    digest = "" if journal is None else fingerprint(tasks, score)
    try:  # the journal is closed (and unlocked) whatever happens
        done = {} if journal is None else _finished(journal, tasks, score, resume, digest)
        rows = _run(tasks, done, score, size, journal, progress, where)
        table = results_frame(rows, score)
        if journal is not None:  # the table, then its stamp, then the journal goes
            write_table(table, journal.table, name="out")
            write_stamp(journal.table, digest)
            journal.finish()
    finally:
        if journal is not None:
            journal.close()
    return table


def _score_of(score: Score | None) -> Score:
    """The batch's score (default :class:`WorstAxisScore`), checked before any work: a
    callable, and its ``no_grasp`` mapping well formed."""
    score = WorstAxisScore() if score is None else score
    if not callable(score):
        raise InvalidInputError("score", f"expected a callable score(model, command), got {score!r}")
    _no_grasp_values(score)
    return score


def _journal(out: object, resume: object) -> Journal | None:
    """The journal of the checked table path ``out`` (None without ``out``)."""
    if not isinstance(resume, bool):
        raise InvalidInputError("resume", f"expected True or False, got {resume!r}")
    if resume and out is None:
        raise InvalidInputError("resume", "needs out=: the table whose journal holds the finished rows")
    return None if out is None else Journal(check_output(out))


def _finished(
    journal: Journal, tasks: list[tuple], score: Score, resume: bool, digest: str
) -> dict[tuple[int, str], dict]:
    """Start the journal; the finished rows ``{(index, id): row}`` of a resume (from the journal,
    or from the stamped table of a batch that finished: :mod:`.resume`)."""
    finished = resume and not journal.path.is_file() and journal.table.is_file()
    if finished:
        check_stamp(journal.table, digest)
    done = journal.start(digest, len(tasks), resume, (*BASE_COLUMNS, *TAIL_COLUMNS, "scores"))
    return (
        table_rows(
            journal.table,
            tasks,
            score,
            (BASE_COLUMNS, TAIL_COLUMNS, TEXT_COLUMNS),
            tuple(status_columns(score)),
        )
        if finished
        else done
    )


#: Text columns of a table.
TEXT_COLUMNS = ("id", "source", "status", "reason", "command", "error_type", "error_message", "warnings")


def _run(
    tasks: list[tuple],
    done: dict[tuple[int, str], dict],
    score: Score,
    size: int,
    journal: Journal | None,
    progress: Callable[[int, int], None] | None,
    where: dict[str, Any],
) -> list[dict[str, Any]]:
    """The rows of every task: the finished ones (``done``) and the others, evaluated in chunks
    of ``size`` on ``where`` (executor options), journaled as they finish."""
    rows = list(done.values())
    todo = [t for t in tasks if (t[0], t[1]) not in done]
    chunks = [todo[i : i + size] for i in range(0, len(todo), size)]

    def arrived(i: int, result: Any) -> None:
        new = [failure_row(t, result) for t in chunks[i]] if isinstance(result, TaskFailure) else result
        rows.extend(new)
        if journal is not None:
            journal.append(new)

    def counted(d: int, t: int) -> None:
        if progress is not None:
            progress(d + len(done), t + len(done))

    try:
        with interruptible():
            run_chunks(
                _evaluate_chunk, chunks, (score,), progress=counted if progress is not None else None,
                sizes=[len(c) for c in chunks], on_result=arrived, **where,
            )  # fmt: skip
    except KeyboardInterrupt as exc:
        if journal is not None:
            journal.close()
        signum = exc.signum if isinstance(exc, Interrupted) else 2
        raise Interrupted(signum, len(rows), len(tasks), journal and journal.path) from None
    return rows


def save_results(table: Any, path: object) -> Path:
    """Write a batch table to ``.csv`` or ``.parquet`` (by the suffix; no index column),
    atomically (a temporary file renamed over ``path``).

    Returns:
        The path written (parent folders are created).

    Raises:
        InvalidInputError: Another suffix, or the path cannot be written.
        MissingDependencyError: Parquet without pyarrow (``pip install "pinograsp[parquet]"``).
    """
    return write_table(table, path, name="path")
