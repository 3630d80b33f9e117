"""Batch evaluation of grasps: one DataFrame row per grasp, on this machine or a cluster.

``pg.evaluate_grasps(grasps, score=..., executor="local" | "ray" | "dask" | client)`` builds each
grasp (a scene, or a :class:`~pinograsp.batch.grasps.GraspSpec` auto-closed and preloaded), scores it
with a pluggable ``score(model, command) -> {name: float}`` and returns a ``pandas.DataFrame``
(columns :data:`BASE_COLUMNS`, the score's keys, :data:`TAIL_COLUMNS`). A grasp that fails is a
row with ``status == "error"`` and the exception's type and message; the batch goes on.

Determinism: each grasp is evaluated from its own record alone, in one BLAS thread, by the
exact (canonical) solvers, and rows are put back in input order, so every column except
:data:`TIMING_COLUMNS` is identical whatever the executor, worker count or completion order.
"""

from __future__ import annotations

import json
import math
import os
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from ..core.query import Query
from ..core.settings import METHODS, Method
from ..core.validate import choice, positive_number, whole_number, writing
from ..errors import InvalidInputError, MissingDependencyError
from .executors import run_chunks
from .grasps import GraspSpec, build_grasp, rpy_of

#: Row status.
Status = Literal["ok", "error"]
#: Score callable: ``score(model, command) -> {name: value}`` (floats; ``inf`` allowed).
Score = Callable[[Any, dict[str, float]], Mapping[str, float]]

#: Columns before the score's.
BASE_COLUMNS = (
    "index",
    "id",
    "source",
    "status",
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


@dataclass(frozen=True)
class WorstAxisScore:
    """Default score: the worst-case max resistible force over the signed force axes.

    For each of ``±fx, ±fy, ±fz`` (``±fx, ±fy`` for planar models), the max resistible wrench
    magnitude [N] (:func:`pinograsp.max_resistible_wrench` with ``upper``, ``steps``, ``method``;
    ``inf`` when unbounded, ``upper`` when above the limit, 0 below the resolution). Returns
    ``score`` (the smallest, [N]), ``unbounded_fraction`` (of the axes, in [0, 1]) and each
    axis as ``max_+fx``, ``max_-fx``, ... [N].

    Attributes:
        upper: Search limit [N].
        steps: Search steps (resolution ``upper / 2**steps``; small for speed).
        method: ``"iterative"``, ``"prp"`` or ``"energetic"`` (maximum dissipation: one
            load-factor solve per axis, ``search="direct"``), kept as a
            :class:`~pinograsp.core.settings.Method`.
    """

    upper: float = 50.0
    steps: int = 6
    method: Method | str = Method.ITERATIVE

    def __post_init__(self) -> None:
        object.__setattr__(self, "upper", positive_number("upper", self.upper))
        object.__setattr__(self, "steps", whole_number("steps", self.steps))
        object.__setattr__(self, "method", Method(choice("method", self.method, METHODS)))

    def __call__(self, model: Any, command: Mapping[str, float]) -> dict[str, float]:
        from ..analysis.max_wrench import max_resistible_wrench
        from ..analysis.response import PassiveSolver

        axes = ("fx", "fy") if model.planar else ("fx", "fy", "fz")
        mags: dict[str, float] = {}
        unbounded = 0
        query = Query(self.method, self.upper, self.steps)
        session = PassiveSolver(model)  # one per grasp: its preload stage is solved once
        for k, direction in enumerate(s + a for a in axes for s in ("+", "-")):
            first = k == 0
            d = direction.lstrip("+")
            mw = max_resistible_wrench(
                model, command, d, session=session, query=query, check_preload_first=first
            )
            unbounded += bool(mw.unbounded)
            mags[f"max_{direction}"] = 0.0 if mw.status == "below_resolution" else float(mw.magnitude)
        return {"score": min(mags.values()), "unbounded_fraction": unbounded / len(mags), **mags}


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
    if type(item).__name__ == "Scene" and hasattr(item, "model") and hasattr(item, "command"):
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


def evaluate_one(task: tuple[int, str, str, Any], score: Score) -> dict[str, Any]:
    """One grasp's row (never raises on a bad grasp: its error is recorded in the row)."""
    from ..solvers.threads import single_threaded_blas

    index, gid, kind, payload = task
    row: dict[str, Any] = {"index": index, "id": gid, "source": "", "status": "error", "n_contacts": 0}
    row.update({"command": "", **_pose_columns(None), "error_type": "", "error_message": ""})
    row.update({"warnings": "", **dict.fromkeys(TIMING_COLUMNS, 0.0), "scores": {}})
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught, single_threaded_blas():
        warnings.simplefilter("always")
        try:
            model, command = _model_of(kind, payload, row)
            row["n_contacts"] = int(model.nc)
            row["command"] = json.dumps({k: float(v) for k, v in command.items()})
            t1 = time.perf_counter()
            row["scores"] = _score_values(score(model, command))
            row["time_score"] = time.perf_counter() - t1
            row["status"] = "ok"
        except Exception as exc:  # one bad grasp never stops the batch
            row["error_type"] = type(exc).__name__
            row["error_message"] = " ".join(str(exc).split())
    seen = dict.fromkeys(f"{w.category.__name__}: {' '.join(str(w.message).split())}" for w in caught)
    row["warnings"] = "; ".join(seen)
    row["time_total"] = time.perf_counter() - t0
    return row


def _evaluate_chunk(chunk: Sequence[tuple], score: Score) -> list[dict[str, Any]]:
    return [evaluate_one(task, score) for task in chunk]


def _pandas() -> Any:
    try:
        import pandas
    except ImportError:
        raise MissingDependencyError("pandas", "evaluate_grasps", extra="tables") from None
    return pandas


def evaluate_grasps(
    grasps: Sequence[object],
    *,
    score: Score | None = None,
    executor: object = "local",
    workers: int | None = None,
    address: str | None = None,
    progress: Callable[[int, int], None] | None = None,
    chunksize: int = 1,
) -> Any:
    """Score a batch of grasps, one row each, on a local process pool, Ray or Dask.

    Args:
        grasps: Grasp records: :class:`~pinograsp.batch.grasps.GraspSpec` (or a mapping of its
            fields), a scene name or YAML path, ``{"scene": ..., "id": ...}``, or a loaded
            :class:`~pinograsp.scenes.loading.Scene` (its model and preload are shipped).
        score: ``score(model, command) -> {name: float}``; default :class:`WorstAxisScore`.
            Must be picklable for Ray, Dask and non-fork process pools (cloudpickle: lambdas
            are fine for Ray and Dask; a local pool on Linux forks and needs nothing).
        executor: ``"local"`` (``concurrent.futures.ProcessPoolExecutor``; ``workers=1``: in
            this process), ``"ray"``, ``"dask"``, a ``dask.distributed.Client`` or any
            ``concurrent.futures.Executor``.
        workers: Local processes, Ray tasks in flight or Dask local workers (``0`` or ``None``:
            one per CPU; on an existing cluster ``None`` uses all of it).
        address: An existing Ray (``"auto"``) or Dask (``"tcp://host:8786"``) cluster.
        progress: ``progress(done, total)`` as grasps finish (in this process).
        chunksize: Grasps per task.

    Returns:
        A ``pandas.DataFrame``, one row per grasp in input order: :data:`BASE_COLUMNS`, the
        score's keys (NaN in error rows), :data:`TAIL_COLUMNS`. ``status`` is ``"ok"`` or
        ``"error"``; ``command`` the preload as JSON ``{actuator: value}`` [N·m or N];
        ``obj_*`` the object pose (hand base frame, [m] and roll-pitch-yaw [rad]).

    Raises:
        InvalidInputError: A malformed record, executor or option.
        MissingDependencyError: pandas, or the chosen executor's package, is not installed.
    """
    pd = _pandas()
    if isinstance(grasps, (str, bytes, Mapping)) or not isinstance(grasps, Sequence):
        raise InvalidInputError("grasps", f"expected a list of grasp records, got {type(grasps).__name__}")
    tasks = [_task(i, g) for i, g in enumerate(grasps)]
    score = WorstAxisScore() if score is None else score
    if not callable(score):
        raise InvalidInputError("score", f"expected a callable score(model, command), got {score!r}")
    size = whole_number("chunksize", chunksize)
    chunks = [tasks[i : i + size] for i in range(0, len(tasks), size)]
    results = run_chunks(
        _evaluate_chunk,
        chunks,
        (score,),
        executor=executor,
        workers=workers,
        address=address,
        progress=progress,
        sizes=[len(c) for c in chunks],
    )
    rows = [r for chunk in results for r in chunk]
    names: dict[str, None] = {}
    for r in rows:
        names.update(dict.fromkeys(r["scores"]))
    table = [{**r, **{k: r["scores"].get(k, math.nan) for k in names}} for r in rows]
    columns = [*BASE_COLUMNS, *names, *TAIL_COLUMNS]
    return pd.DataFrame(table, columns=columns)


def output_format(path: object) -> Literal["csv", "parquet"]:
    """The table format of ``path`` by its suffix (checked before a long batch starts).

    Raises:
        InvalidInputError: Not a ``.csv``, ``.parquet`` or ``.pq`` path.
        MissingDependencyError: Parquet without pyarrow (``pip install "pinograsp[parquet]"``).
    """
    suffix = Path(str(path)).suffix.lower() if isinstance(path, (str, os.PathLike)) else ""
    if suffix == ".csv":
        return "csv"
    if suffix in (".parquet", ".pq"):
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            raise MissingDependencyError("pyarrow", "Parquet output", extra="parquet") from None
        return "parquet"
    raise InvalidInputError("path", f"expected a .csv or .parquet file, got {path!r}")


def save_results(table: Any, path: object) -> Path:
    """Write a batch table to ``.csv`` or ``.parquet`` (by the suffix; no index column).

    Returns:
        The path written (parent folders are created).

    Raises:
        InvalidInputError: Another suffix, or the path cannot be written.
        MissingDependencyError: Parquet without pyarrow (``pip install "pinograsp[parquet]"``).
    """
    if output_format(path) == "csv":
        return writing(path, lambda p: table.to_csv(p, index=False), name="path")
    return writing(path, lambda p: table.to_parquet(p, index=False), name="path")
