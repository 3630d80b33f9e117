"""The resistance set: max resistible magnitude over directions spread evenly on the whole unit
wrench sphere (``docs/metrics.md``), not only in one plane.

Directions. Unit vectors ``u`` are spread evenly over the sphere of the *scaled* wrench space
``(f [N], tau / length [N])`` — 6-D, or ``(fx, fy, mz / length)`` for planar models — by
:func:`sphere_points` (seeded Gaussian points, then repelled: same ``seed``, same bits). Each
``u`` is mapped to the wrench ``w = (u_f, length * u_t)`` and normalised as
:func:`pinograsp.wrench_direction` does, giving the unit ``directions`` (Euclidean norm of
``(f [N], tau [N·m])``) that :func:`pinograsp.max_resistible_wrench` searches along.

Magnitudes. ``magnitudes`` are those of :class:`~pinograsp.MaxWrench`: the Euclidean norm of
the limit wrench ``(f [N], tau [N·m])``. ``scaled`` is the same limit in the scaled norm
``sqrt(|f|² + |tau / length|²)`` [N]: the limit wrench is ``scaled * (u_f, length * u_t)``.
The summary, the quantiles and :func:`pinograsp.grasp_score` use ``scaled``.

This module is light (NumPy only); the solver side is imported when a set is computed.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, get_args

import numpy as np

from ..core.axes import PLANAR_AXES, direction_text, wrench_direction
from ..core.methods import search_resolution, search_text
from ..core.model import GraspModel
from ..core.query import Query, make_query
from ..core.results import MaxWrench, ResistanceProfile
from ..core.serialize import format_magnitude, jsonable, vector_text
from ..core.settings import DEFAULT_METHOD
from ..core.validate import directions as n_directions
from ..core.validate import finite_array, relative_length, whole_number
from ..errors import InvalidInputError

if TYPE_CHECKING:
    from .response import Session

#: Outcome per direction: a :data:`~pinograsp.core.results.MaxWrenchStatus`, or ``"failed"`` (the
#: query raised a :class:`~pinograsp.SolverError`; recorded in ``ResistanceSet.failures``).
DirectionStatus = Literal["finite", "unbounded", "above_limit", "below_resolution", "failed"]
_SET_STATUSES: dict[str, DirectionStatus] = {s: s for s in get_args(DirectionStatus)}
#: Direction classes of the summary: resisted up to a finite limit (``finite``, ``above_limit``),
#: without bound, not resistible at all (``below_resolution``), or failed.
CLASSES = ("finite", "unbounded", "not_resistible", "failed")
#: Largest number of sphere directions (the repulsion is O(n²) per step).
MAX_DIRECTIONS = 10_000
#: Quantiles reported by :meth:`ResistanceSet.summary` and ``to_dict``.
QUANTILES = (0.05, 0.25, 0.5)
CSV_COLUMNS: tuple[str, ...] = ("index", "label", "fx", "fy", "fz", "mx", "my", "mz", "u1", "u2", "u3", "u4")
CSV_COLUMNS += ("u5", "u6", "magnitude", "scaled", "status", "unbounded", "n_solves", "wall_time", "error")


def sphere_points(n: int, dim: int, seed: int = 0, iterations: int = 40) -> np.ndarray:
    """``n`` unit vectors spread evenly over the sphere in ``R^dim``, (n, dim).

    Seeded standard-normal points on the sphere, then ``iterations`` steps of a Riesz-energy
    repulsion (kernel ``1 / r^dim``, tangential steps of at most half the mean spacing,
    shrinking), so that no two points are much closer than the spacing ``~ n^(-1/(dim-1))``.
    Deterministic: the same arguments give the same bits.
    """
    n, dim = whole_number("n", n), whole_number("dim", dim, 2)
    if n > MAX_DIRECTIONS:
        raise InvalidInputError("n", f"at most {MAX_DIRECTIONS} directions, got {n}")
    x = np.random.default_rng(whole_number("seed", seed, 0)).standard_normal((n, dim))
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    if n < 2:
        return x
    spacing = (2.0 * np.pi ** (dim / 2) / _gamma(dim / 2) / n) ** (1.0 / (dim - 1))
    for it in range(iterations):
        force = np.vstack([_repulsion(x[i : i + 256], x, i, dim) for i in range(0, n, 256)])
        force -= np.sum(force * x, axis=1, keepdims=True) * x  # tangential part
        big = np.linalg.norm(force, axis=1).max()
        if not big > 0:
            break
        x = x + (0.5 * spacing * (1.0 - it / iterations) / big) * force
        x /= np.linalg.norm(x, axis=1, keepdims=True)
    return x


def _repulsion(rows: np.ndarray, x: np.ndarray, first: int, dim: int) -> np.ndarray:
    """Riesz force ``sum_j (x_i - x_j) / |x_i - x_j|^(dim+2)`` on a block of rows (bounded memory)."""
    diff = rows[:, None, :] - x[None, :, :]
    r2 = np.einsum("ijk,ijk->ij", diff, diff)
    r2[np.arange(len(rows)), first + np.arange(len(rows))] = np.inf
    return np.einsum("ij,ijk->ik", np.maximum(r2, 1e-12) ** (-(dim + 2) / 2.0), diff)


def _gamma(z: float) -> float:
    import math

    return math.gamma(z)


def _scale_of(directions: np.ndarray, length: float) -> np.ndarray:
    """``|(d_f, d_t / length)|`` per unit direction, (n,): Euclidean -> scaled magnitude factor."""
    return np.sqrt(np.sum(directions[:, :3] ** 2, 1) + np.sum(directions[:, 3:] ** 2, 1) / length**2)


@dataclass(frozen=True, repr=False)
class ResistanceSet:
    """Max resistible magnitude over directions spread evenly on the unit wrench sphere.

    Attributes:
        directions: Unit wrench directions searched, (n, 6) (Euclidean norm of (N, N·m)).
        sphere: The points ``u`` on the unit sphere of the scaled space ``(f, tau / length)``,
            (n, 6) (planar: zero ``fz, mx, my``).
        length: Characteristic length [m] that scales torques.
        length_source: ``"model.length_scale"`` or ``"given"``.
        magnitudes: Limit per direction, Euclidean norm of ``(f [N], tau [N·m])``, (n,): ``inf``
            where unbounded, ``upper`` (a lower bound) for ``above_limit``, 0 for
            ``below_resolution``, NaN for ``failed``.
        scaled: The same limits in the scaled norm ``sqrt(|f|² + |tau / length|²)`` [N], (n,).
        statuses: :data:`DirectionStatus` per direction.
        unbounded: (n,) bool.
        failures: ``(index, message, status)`` of each direction whose query raised a
            :class:`~pinograsp.SolverError` (not fatal).
        results: The :class:`~pinograsp.MaxWrench` per direction (``None`` where failed).
        method, upper, steps, seed: How the set was computed (``seed``: ``None`` for given
            directions).
        wall_time: Total wall time [s].
    """

    directions: np.ndarray
    sphere: np.ndarray
    length: float
    length_source: str
    magnitudes: np.ndarray
    scaled: np.ndarray
    statuses: tuple[DirectionStatus, ...]
    unbounded: np.ndarray
    failures: tuple[tuple[int, str, str], ...]
    results: tuple[MaxWrench | None, ...] = field(repr=False)
    method: str = DEFAULT_METHOD
    upper: float = 1e3
    steps: int = 20
    seed: int | None = 0
    wall_time: float = 0.0

    @property
    def n(self) -> int:
        """Number of directions."""
        return len(self.magnitudes)

    @property
    def times(self) -> np.ndarray:
        """Wall time per direction [s], (n,) (NaN where failed)."""
        return np.array([np.nan if r is None else r.wall_time for r in self.results])

    @property
    def capped(self) -> np.ndarray:
        """``scaled`` with unbounded limits replaced by the search's upper limit along the
        direction (``upper * |(d_f, d_t / length)|``) [N], (n,): the score's values."""
        cap = self.upper * _scale_of(self.directions, self.length)
        return np.where(self.unbounded, cap, self.scaled)

    def classes(self) -> dict[str, int]:
        """Directions per class (:data:`CLASSES`)."""
        s = np.array(self.statuses)
        return {
            "finite": int(np.sum((s == "finite") | (s == "above_limit"))),
            "unbounded": int(np.sum(s == "unbounded")),
            "not_resistible": int(np.sum(s == "below_resolution")),
            "failed": int(np.sum(s == "failed")),
        }

    def quantile(self, q: float, *, capped: bool = False) -> float:
        """The empirical ``q``-quantile of ``scaled`` (or :attr:`capped`) over the directions
        that did not fail [N]: the smallest value with at least ``q`` of them at or below it
        (``numpy.quantile(method="inverted_cdf")``; ``inf`` may be returned)."""
        v = (self.capped if capped else self.scaled)[np.array(self.statuses) != "failed"]
        if not 0.0 <= q <= 1.0:
            raise InvalidInputError("quantile", f"must be in [0, 1], got {q!r}")
        return float(np.quantile(v, q, method="inverted_cdf")) if v.size else float("nan")

    def worst(self) -> int | None:
        """Index of the direction with the smallest ``scaled`` limit (``None``: all failed)."""
        ok = np.flatnonzero(np.array(self.statuses) != "failed")
        return None if ok.size == 0 else int(ok[np.argmin(self.scaled[ok])])

    def resolution(self) -> float:
        """Scaled resolution of the searches [N] (largest ``resolution * |(d_f, d_t/length)|``)."""
        res = search_resolution(self.method, self.upper, self.steps)  # 0 for a path: exact
        return float(np.max(res * _scale_of(self.directions, self.length)))

    def to_dict(self, *, results: bool = False) -> dict[str, Any]:
        """Plain JSON-ready data (``pinograsp resistance-set --json``): arrays as lists,
        ``None`` for unbounded (inf) and failed (NaN) magnitudes; ``classes``, ``quantiles``
        (of ``scaled`` [N]), ``worst``; ``results=True`` adds every :meth:`MaxWrench.to_dict`."""
        w = self.worst()
        out: dict[str, Any] = {
            "n": self.n,
            "length": self.length,
            "length_source": self.length_source,
            "method": self.method,
            "upper": self.upper,
            "steps": self.steps,
            "seed": self.seed,
            "directions": self.directions,
            "sphere": self.sphere,
            "magnitudes": self.magnitudes,
            "scaled": self.scaled,
            "statuses": list(self.statuses),
            "unbounded": self.unbounded,
            "classes": self.classes(),
            "fraction_unbounded": float(np.mean(self.unbounded)) if self.n else None,
            "quantiles": {f"{q:g}": self.quantile(q) for q in QUANTILES},
            "worst": None
            if w is None
            else {"index": w, "direction": self.directions[w], "scaled": self.scaled[w]},
            "failures": [list(f) for f in self.failures],
            "times": self.times,
            "wall_time": self.wall_time,
        }
        if results:
            out["results"] = [None if r is None else r.to_dict(response=False) for r in self.results]
        return jsonable(out)

    def summary(self) -> str:
        """Classes, the worst direction, quantiles of ``scaled`` [N], fraction unbounded, timing."""
        n, c = self.n, self.classes()
        res = self.resolution()
        dim = 3 if np.allclose(self.directions[:, [2, 3, 4]], 0.0) else 6
        lines = [
            f"resistance set: {n} directions on the unit {dim}-D wrench sphere, torques scaled by "
            f"{self.length:.4g} m ({self.length_source}); method {self.method}, "
            f"{search_text(self.method, self.upper, self.steps)}",
            "classes: " + ", ".join(f"{k.replace('_', ' ')} {v} ({v / max(n, 1):.1%})" for k, v in c.items()),
        ]
        w = self.worst()
        if w is not None:
            limit = self.scaled[w] * self.sphere[w] * np.r_[1, 1, 1, [self.length] * 3]
            lines.append(
                f"worst direction {direction_text(self.directions[w])}: "
                f"{format_magnitude(self.scaled[w], res, 'N')} (scaled), limit wrench {vector_text(limit)} "
                f"[N, N·m] ({self.statuses[w]})"
            )
            qs = ", ".join(f"{q:.0%} {format_magnitude(self.quantile(q), res, 'N')}" for q in QUANTILES)
            lines.append(f"quantiles of the scaled limit sqrt(|f|² + |tau/length|²): {qs}")
        lines.append(f"fraction unbounded {np.mean(self.unbounded):.1%}")
        t = self.times[np.isfinite(self.times)]
        med = f"median {np.median(t):.3g} s per direction, " if t.size else ""
        lines.append(f"{med}{self.wall_time:.3g} s in total")
        return "\n".join(lines)

    def __repr__(self) -> str:
        c = self.classes()
        return (
            f"ResistanceSet(n={self.n}, length={self.length:.4g}, method={self.method!r}, "
            + ", ".join(f"{k}={v}" for k, v in c.items())
            + f", q5={self.quantile(0.05):.4g}, wall_time={self.wall_time:.3g})"
        )

    def rows(self) -> list[dict[str, Any]]:
        """One dict per direction with the keys :data:`CSV_COLUMNS`."""
        fails = {i: msg for i, msg, _ in self.failures}
        rows = []
        for i in range(self.n):
            r = self.results[i]
            d, u = self.directions[i], self.sphere[i]
            row = {"index": i, "label": direction_text(d)}
            row.update({k: float(v) for k, v in zip(CSV_COLUMNS[2:8], d)})
            row.update({k: float(v) for k, v in zip(CSV_COLUMNS[8:14], u)})
            row.update(
                magnitude=float(self.magnitudes[i]),
                scaled=float(self.scaled[i]),
                status=self.statuses[i],
                unbounded=bool(self.unbounded[i]),
                n_solves=0 if r is None else r.n_solves,
                wall_time=float("nan") if r is None else r.wall_time,
                error=fails.get(i, ""),
            )
            rows.append(row)
        return rows

    def to_csv(self, path: object, *, name: str = "path") -> Path:
        """Write :meth:`rows` to a CSV file (``inf`` where unbounded, empty cells for NaN);
        returns the :class:`~pathlib.Path` written (through :func:`pinograsp.core.validate.writing`)."""
        from ..core.tables import _write_csv

        return _write_csv(path, CSV_COLUMNS, self.rows(), name)

    def project(self, plane: object, *, tol: float = 1e-9) -> ResistanceProfile:
        """The directions of the set that lie in ``plane`` (within ``tol`` of it) as a
        :class:`~pinograsp.ResistanceProfile`, sorted by angle from the plane's first axis.

        A set computed on ``pg.plane_directions(model, plane, n)`` projects to exactly
        ``pg.resistance_profile(model, command, plane, n, ...)`` (bit-identical magnitudes).
        A larger ``tol`` gives an approximate slice of a sphere set (its directions keep their
        out-of-plane components). Failed directions are left out.
        """
        from ..core.axes import plane_basis

        model_like = _PlaneModel(planar=bool(np.allclose(self.directions[:, [2, 3, 4]], 0.0)))
        basis, labels = plane_basis(model_like, plane)  # type: ignore[arg-type]
        coords = self.directions @ basis.T
        off = np.linalg.norm(self.directions - coords @ basis, axis=1)
        keep = [i for i in np.flatnonzero(off <= tol) if self.results[i] is not None]
        if not keep:
            raise InvalidInputError(
                "plane", f"no direction of the set lies within {tol:g} of {plane!r} (use directions=)"
            )
        angles = np.mod(np.arctan2(coords[keep, 1], coords[keep, 0]), 2 * np.pi)
        order = np.argsort(angles, kind="stable")
        idx = np.array(keep)[order]
        return ResistanceProfile(
            plane=labels,
            basis=basis,
            angles=angles[order],
            directions=self.directions[idx],
            magnitudes=self.magnitudes[idx],
            unbounded=self.unbounded[idx],
            normalized_by=None,
            results=tuple(self.results[i] for i in idx),
        )


@dataclass(frozen=True)
class _PlaneModel:
    """The part of a model :func:`pinograsp.core.axes.plane_basis` needs (wrench validation)."""

    planar: bool

    def wrench_vector(self, wrench: object, name: str = "wrench") -> np.ndarray:
        return GraspModel.wrench_vector(self, wrench, name)  # type: ignore[arg-type]


def wrench_rows(model: GraspModel, value: object, name: str) -> np.ndarray:
    """``value`` as validated full wrench 6-vectors, (k, 6) (planar models also take (k, 3));
    anything else is an :class:`InvalidInputError` naming ``name``."""
    try:
        arr = None if isinstance(value, (str, bytes)) else np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        arr = None
    if arr is None or arr.ndim != 2 or arr.shape[0] < 1:
        raise InvalidInputError(name, f"expected an array of shape (k, 6), got {value!r}")
    arr = finite_array(name, arr, arr.shape)
    return np.array([model.wrench_vector(w, f"{name}[{i}]") for i, w in enumerate(arr)])


def _direction_status(r: MaxWrench | None) -> DirectionStatus:
    """A direction's status in a set: ``"failed"`` without a result, and for a path stopped
    without a verdict (``"no_solution"``/``"segment_limit"``; the quasi-static method raises
    for those, so a set never keeps one)."""
    return "failed" if r is None else _SET_STATUSES.get(r.status, "failed")


def _sphere_directions(model: GraspModel, n: int, seed: int, length: float) -> tuple[np.ndarray, np.ndarray]:
    """Raw wrenches ``(u_f, length * u_t)``, (n, 6), of :func:`sphere_points` in the model's space."""
    u = sphere_points(n, model.nw, seed)
    u6 = np.zeros((n, 6))
    u6[:, list(PLANAR_AXES) if model.planar else slice(None)] = u
    return u6 * np.r_[1.0, 1.0, 1.0, length, length, length], u6


def _length(model: GraspModel, length: object) -> tuple[float, str]:
    """The length [m] scaling torques and where it came from: ``model.length_scale`` by default,
    else ``length`` within :data:`~pinograsp.core.validate.LENGTH` times it (docs/errors.md)."""
    if length is None:
        return float(model.length_scale), "model.length_scale"
    return relative_length("length", length, model.length_scale), "given"


def _requested_directions(
    model: GraspModel, n: int | None, seed: int, length: float, directions: object
) -> tuple[np.ndarray, int | None]:
    """The wrenches (k, 6) of :func:`resistance_set`: ``directions`` as given, or ``n`` points
    of the sphere of ``seed`` (then also the seed used)."""
    if directions is None:
        raw, _ = _sphere_directions(model, n_directions(500 if n is None else n), seed, length)
        return raw, whole_number("seed", seed, 0)
    return wrench_rows(model, directions, "directions"), None


def resistance_set(
    model: GraspModel,
    command: object,
    n: int | None = None,
    method: str = DEFAULT_METHOD,
    length: float | None = None,
    seed: int = 0,
    workers: int | None = None,
    upper: float = 1e3,
    steps: int = 20,
    settings: Any = None,
    *,
    directions: object = None,
    progress: Callable[[int, int], None] | None = None,
    search: str = "auto",
    session: Session | None = None,
    query: Query | None = None,
    **overrides: object,
) -> ResistanceSet:
    """Max resistible magnitude over ``n`` directions spread evenly on the unit wrench sphere.

    Args:
        model: The grasp.
        command: Actuator commands (see :func:`pinograsp.passive_response`).
        n: Number of directions (default 500; ignored when ``directions`` is given).
        method: ``"quasistatic"`` (default), ``"iterative"``, ``"prp"`` or ``"energetic"``.
        length: Characteristic length [m] scaling torques (default ``model.length_scale``).
        seed: Seed of :func:`sphere_points` (same seed, same directions, same bits).
        workers: Process-pool size (``0``: one per CPU; ``None``/``1``: in this process).
        upper, steps, settings, search, overrides: As :func:`pinograsp.max_resistible_wrench`.
        directions: Explicit wrench directions, (k, 6) (planar models also (k, 3)), instead of
            the sphere, e.g. ``pg.plane_directions(model, ("fx", "fy"), 24)``.
        progress: Called as ``progress(done, total)``.
        session: A :class:`~pinograsp.Session` of ``model`` the caller owns (its settings
            rule): the directions solved in this process share its preload stages (a pool's
            workers build one per block of directions).
        query: A :class:`~pinograsp.Query` instead of ``method``, ``upper``, ``steps``,
            ``search``.

    Raises:
        PreloadNotInEquilibriumError, InvalidInputError. A :class:`~pinograsp.SolverError` of one
        direction is recorded in ``failures``, not raised.
    """
    from ..solvers.threads import single_threaded_blas
    from .directions import run_directions
    from .max_wrench import check_preload, query_within
    from .response import session_for

    t0 = time.perf_counter()
    q = make_query(query, method, upper, steps, search)
    length, source = _length(model, length)
    raw, seed_used = _requested_directions(model, n, seed, length, directions)
    dirs = np.array([wrench_direction(model, w, f"directions[{i}]") for i, w in enumerate(raw)])
    with single_threaded_blas():  # as every public query: one BLAS thread, one reduction order
        solver = session_for(model, session, settings, overrides)
        fc = query_within(solver, command, q, eps=False)  # domains: docs/errors.md
        check_preload(solver, fc, str(q.method))
        results, failures = run_directions(solver, fc, raw, q, workers=workers, progress=progress, catch=True)
    mags = np.array([np.nan if r is None else r.magnitude for r in results])
    k = _scale_of(dirs, length)
    sphere = np.hstack([dirs[:, :3], dirs[:, 3:] / length]) / k[:, None]
    return ResistanceSet(
        directions=dirs,
        sphere=sphere,
        length=length,
        length_source=source,
        magnitudes=mags,
        scaled=mags * k,
        statuses=tuple(_direction_status(r) for r in results),
        unbounded=np.array([r is not None and r.unbounded for r in results], dtype=bool),
        failures=tuple(failures),
        results=tuple(results),
        method=str(q.method),
        upper=q.upper,
        steps=q.steps,
        seed=seed_used,
        wall_time=time.perf_counter() - t0,
    )
