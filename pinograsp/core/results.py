"""Typed, immutable results of pinograsp analyses: the one import path of every result record.

Each record owns its plain data (``to_dict``), text (``summary``) and compact ``repr``:
:class:`MaxWrench` and :class:`ResistanceProfile` here (with their table rows, columns
:data:`PROFILE_COLUMNS`), :class:`~pinograsp.core.response_result.PassiveResponse` and
:class:`~pinograsp.core.audit.Audit` / :class:`~pinograsp.core.audit.EnergyCheck` below this
module (re-exported). :mod:`pinograsp.core.serialize` holds only the record-free helpers
(``jsonable``, values printed to their resolution, CSV writing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from ..errors import InvalidInputError, plural
from .audit import Audit, EnergyCheck
from .axes import WRENCH_AXES, direction_text, wrench_unit
from .giveway import GiveWay
from .response_result import (
    ContactState,
    MethodName,
    PassiveResponse,
    ResponseStatus,
    forces_text,
    states_text,
)
from .serialize import (
    format_magnitude,
    jsonable,
    real_number,
    require_pandas,
    runs_text,
    unbounded_runs,
    write_csv,
)

__all__ = [
    "DIRECTION_ATOL",
    "PROFILE_COLUMNS",
    "RESULT_FIELDS",
    "Audit",
    "ContactState",
    "EnergyCheck",
    "MaxWrench",
    "MaxWrenchStatus",
    "MethodName",
    "PassiveResponse",
    "ResistanceProfile",
    "ResponseStatus",
    "format_max_wrench",
]

#: Largest per-component difference between two unit wrench directions (6,) that are taken to
#: be the same (:meth:`ResistanceProfile.result_along`). A profile's directions
#: ``cos(a) b1 + sin(a) b2`` and a reference parsed from an axis name or vector agree to
#: rounding (~1e-16) when they are the same direction, while two distinct directions of an
#: ``n``-direction profile differ by ``2 sin(pi / n)`` (above 1e-9 for any ``n`` below 6e9): every
#: tolerance between those picks the same direction. 1e-9 also admits a reference written with
#: nine significant digits (a vector in a scene file).
DIRECTION_ATOL = 1e-9


#: Columns that describe one max-wrench result (:meth:`MaxWrench.row`), shared by the profile
#: and batch tables (:data:`pinograsp.core.tables.RESULT_COLUMNS`).
RESULT_FIELDS = (
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
#: Columns of :meth:`ResistanceProfile.rows` (and of the profile CSV), in order. ``fx`` ... ``mz``:
#: the unit direction; ``normalized``: magnitude / the profile's ``normalized_by`` (NaN, an empty
#: CSV cell, when the profile is not normalised).
PROFILE_COLUMNS = ("angle_deg", "label", *WRENCH_AXES, "magnitude", "normalized", *RESULT_FIELDS)


def _num(x: float) -> str:
    return f"{float(x):.4g}"


#: How a max-wrench search ended (see :class:`MaxWrench`).
MaxWrenchStatus = Literal[
    "finite", "unbounded", "above_limit", "below_resolution", "failed", "no_solution", "segment_limit"
]


@dataclass(frozen=True, repr=False)
class MaxWrench:
    """Largest resistible wrench magnitude along one direction.

    Attributes:
        direction: Unit direction in wrench space, (6,) (torques in [N·m] per unit).
        magnitude: Largest magnitude verified resistible [N or N·m along ``direction``];
            ``inf`` when ``unbounded``; ``upper`` (a lower bound) when ``"above_limit"``; ``0``
            when ``"below_resolution"`` (the limit is below ``resolution``); the load reached (a
            lower bound) for the quasi-static path's ``"no_solution"`` / ``"segment_limit"``.
        unbounded: Passively resisted without bound under this model: resisted at ``upper``
            *and* in the limit of an infinite load (the load under a zero preload, by the
            model's homogeneity; docs/accuracy.md). ``magnitude`` is then ``inf``.
        status: ``"finite"``, ``"unbounded"``, ``"above_limit"`` (resisted at ``upper`` but
            not without bound: the limit is ``>= upper``) or ``"below_resolution"`` (the
            magnitude is below ``floor``: indistinguishable from zero); from
            :func:`~pinograsp.quasistatic_max_wrench` also ``"no_solution"`` and
            ``"segment_limit"`` (the path stopped without a verdict; ``magnitude`` is the load
            reached, a lower bound). Through ``method="quasistatic"`` those two raise a
            :class:`~pinograsp.SolverError` instead (a failed direction of profiles, sets and
            batches, as for the other methods).
        floor: Smallest magnitude distinguishable from zero [N or N·m]: the resolution, and for
            the iterative method at least its equilibrium tolerance ``eps`` along the direction.
        upper: Upper limit of the search.
        resolution: Bisection resolution ``upper / 2**steps`` (the true limit lies in
            ``[magnitude, magnitude + resolution]`` if resistibility is monotone along the ray).
        evidence: Every magnitude tried and its verdict, in order.
        method: ``"prp"``, ``"iterative"``, ``"energetic"`` or ``"quasistatic"``.
        solve_time: Total solver wall time [s] (including the preload check).
        wall_time: Total wall time of the query [s].
        n_solves: Complementarity problems solved.
        response: The passive response at ``magnitude`` (or at ``upper`` when unbounded).
        search: ``"bisection"``, ``"secant"`` (iterative), ``"direct"`` (one load-factor
            complementarity problem, PRP and energetic) or ``"path"`` (quasi-static: the limit
            load of the loading path, exact; ``upper`` is then ``inf`` and ``resolution`` and
            ``floor`` 0: neither the query's ``upper`` nor its ``steps`` apply).
        audit_failures: Resisted magnitudes whose solution fails the audit (energy balance or
            displacement size; ``inf`` for the zero-preload limit test), ascending. Non-empty
            means, for the PRP, that its wedging artefact carries the verdict above
            ``min(audit_failures)`` (the iterative and energetic methods have none: there the
            warning names the path or the solver's tolerance); one
            :class:`~pinograsp.errors.AuditWarning` says so.
        note: Why the answer is what it is when the model explains it (e.g. a
            ``below_resolution`` direction that loads a motion no contact resists:
            :meth:`GraspModel.free_motions`), else ``""``.
        giveway: (``method="quasistatic"``) where and why the grasp gave way, with the path's
            first limit λ*, the snaps survived, the contact stiffness and the thresholds
            (:class:`~pinograsp.core.giveway.GiveWay`); None for the other methods and with
            ``Settings(limit="first")``.
    """

    direction: np.ndarray
    magnitude: float
    unbounded: bool
    status: MaxWrenchStatus
    floor: float
    upper: float
    resolution: float
    evidence: tuple[tuple[float, bool], ...]
    method: MethodName
    solve_time: float
    wall_time: float
    n_solves: int
    response: PassiveResponse | None = field(default=None, repr=False)
    search: str = "bisection"
    audit_failures: tuple[float, ...] = ()
    note: str = ""
    giveway: GiveWay | None = field(default=None, repr=False)

    @property
    def first_limit(self) -> float:
        """The quasi-static path's first limit load λ* [N or N·m] (``inf`` when it has none);
        for the other methods (and ``Settings(limit="first")``) the magnitude itself."""
        return self.magnitude if self.giveway is None else self.giveway.first_limit

    @property
    def physically_audited(self) -> bool:
        """No resisted verdict of the search rests on a solution that fails the audit."""
        return not self.audit_failures

    @property
    def monotone(self) -> bool:
        """No tried magnitude was resisted above one that was not (bisection's assumption)."""
        bad = [m for m, ok in self.evidence if not ok]
        good = [m for m, ok in self.evidence if ok]
        return not bad or not good or max(good) < min(bad)

    def as_reference(self, name: str = "normalize") -> float:
        """This magnitude as the reference of a normalisation [N or N·m].

        Raises:
            InvalidInputError: (named ``name``) the direction is unbounded or not resisted
                (nothing to divide by).
        """
        if self.unbounded or not self.magnitude > 0:
            why = "unbounded" if self.unbounded else "not resisted"
            raise InvalidInputError(
                name, f"the reference direction {direction_text(self.direction)} is {why}"
            )
        return float(self.magnitude)

    def to_dict(self, label: str | None = None, *, response: bool = True) -> dict[str, Any]:
        """Plain JSON-ready data, the ``pinograsp max-wrench --json`` schema (``docs/cli.md``):
        ``magnitude`` [N or N·m] is ``None`` when unbounded.

        Args:
            label: Direction label (default ``"+fy"``-style text of the direction).
            response: Include ``"response"`` (:meth:`PassiveResponse.to_dict` at the limit).
        """
        out = {
            "direction": self.direction,
            "label": label or direction_text(self.direction),
            "magnitude": None if self.unbounded else self.magnitude,
            "unbounded": self.unbounded,
            "status": self.status,
            "unit": wrench_unit(self.direction),
            "upper": self.upper,
            "resolution": self.resolution,
            "method": self.method,
            "monotone": self.monotone,
            "audit_failures": [None if np.isinf(m) else m for m in self.audit_failures],
            "note": self.note,
            "giveway": None if self.giveway is None else self.giveway.to_dict(),
            "evidence": [[m, ok] for m, ok in self.evidence],
            "n_solves": self.n_solves,
            "solve_time": self.solve_time,
            "wall_time": self.wall_time,
        }
        if response:
            out["response"] = None if self.response is None else self.response.to_dict()
        return jsonable(out)

    def summary(self, label: str | None = None) -> str:
        """Status and magnitude to the resolution with its unit, the search, and the normal
        contact forces [N] at the limit, as text."""
        unit = wrench_unit(self.direction)
        head = (
            f"max resistible wrench along {label or direction_text(self.direction)}: "
            f"{format_max_wrench(self, unit=unit)} ({self.status}"
        )
        if self.status == "finite" and self.search == "path":
            head += ", exact"
        elif self.status == "finite":
            head += f", resolution {self.resolution:.2g} {unit}"
        elif self.status == "above_limit":
            head += f": the upper limit {self.upper:g} {unit} is resisted"
        lines = [
            head + ")",
            f"method {self.method}, {self.search}: {plural('magnitude', len(self.evidence))} tried, monotone "
            f"{'yes' if self.monotone else 'NO'}; {self.n_solves} solves, {self.wall_time:.3g} s",
        ]
        if self.response is not None and self.response.resistible:
            # the load the response was solved at (an unbounded search's is its last load)
            at = f"at {float(np.linalg.norm(self.response.wrench)):.6g} {unit}"
            lines.append(f"normal contact forces {at}: {forces_text(self.response)}")
            if states := states_text(self.response):
                lines.append(f"contact states {at}: {states}")
        if self.giveway is not None:
            lines.append(self.giveway.text(unit))
        if self.audit_failures:
            lines.append(f"audit failures at {', '.join(f'{m:.6g}' for m in self.audit_failures)}")
        if self.note:
            lines.append(f"note: {self.note}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return (
            f"MaxWrench(direction={direction_text(self.direction)!r}, magnitude={_num(self.magnitude)}, "
            f"status={self.status!r}, resolution={self.resolution:.3g}, upper={self.upper:g}, "
            f"method={self.method!r}, search={self.search!r}, n_solves={self.n_solves}, "
            f"audit_failures={len(self.audit_failures)})"
        )

    def row(self) -> dict[str, Any]:
        """This result as one table row: ``label``, the unit direction ``fx`` ... ``mz``,
        ``magnitude`` [N or N·m] and the search record (:data:`RESULT_FIELDS`)."""
        d = np.asarray(self.direction, dtype=float)
        return {
            "label": direction_text(d),
            **{ax: float(v) for ax, v in zip(WRENCH_AXES, d)},
            "magnitude": float(self.magnitude),
            "unit": wrench_unit(d),
            "status": self.status,
            "unbounded": bool(self.unbounded),
            "monotone": bool(self.monotone),
            "upper": float(self.upper),
            "resolution": float(self.resolution),
            "floor": float(self.floor),
            "n_solves": int(self.n_solves),
            "solve_time": float(self.solve_time),
            "wall_time": float(self.wall_time),
            "method": self.method,
            "search": self.search,
        }


@dataclass(frozen=True, repr=False)
class ResistanceProfile:
    """Maximum resistible magnitude over directions in a plane of wrench space.

    Attributes:
        plane: Names (or labels) of the two spanning wrench directions.
        basis: The two unit spanning directions, (2, 6).
        angles: Direction angles from the first basis vector [rad], (n,).
        directions: Unit wrench directions, (n, 6).
        magnitudes: Max resistible magnitude per direction (``inf`` where unbounded), (n,).
        unbounded: (n,) bool.
        normalized_by: Magnitude the profile was divided by (``None``: not normalised).
        results: The per-direction :class:`MaxWrench` records (status ``"failed"``, magnitude
            NaN, where the direction's query raised).
        wall_time: Total wall time [s].
        failures: ``(index, message, status)`` of each direction whose query raised a
            :class:`~pinograsp.SolverError` (a node limit, a timeout): recorded, not fatal.
    """

    plane: tuple[str, str]
    basis: np.ndarray
    angles: np.ndarray
    directions: np.ndarray
    magnitudes: np.ndarray
    unbounded: np.ndarray
    normalized_by: float | None
    results: tuple[MaxWrench, ...] = field(repr=False)
    wall_time: float = 0.0
    failures: tuple[tuple[int, str, str], ...] = ()

    @property
    def points(self) -> np.ndarray:
        """Finite profile points in plane coordinates, (n, 2) (``nan`` where unbounded)."""
        m = np.where(self.unbounded, np.nan, self.magnitudes)
        return np.column_stack([m * np.cos(self.angles), m * np.sin(self.angles)])

    @property
    def statuses(self) -> tuple[str, ...]:
        """:attr:`MaxWrench.status` per direction, (n,)."""
        return tuple(r.status for r in self.results)

    def index_along(self, direction: np.ndarray, atol: float = DIRECTION_ATOL) -> int | None:
        """Index of the first sampled direction within ``atol`` of the unit ``direction`` (6,) in
        every component (:data:`DIRECTION_ATOL`), or None when the profile has no such direction."""
        ref = np.asarray(direction, dtype=float)
        for i, d in enumerate(self.directions):
            if np.allclose(d, ref, rtol=0.0, atol=atol):
                return i
        return None

    def result_along(self, direction: np.ndarray, atol: float = DIRECTION_ATOL) -> MaxWrench | None:
        """The profile's own result along the unit ``direction`` (6,) (:meth:`index_along`), or
        None. With :meth:`MaxWrench.as_reference`, the value a profile is normalised by (e.g.
        along ``+b2``: ``result_along(basis[1])``)."""
        i = self.index_along(direction, atol)
        return None if i is None or i >= len(self.results) else self.results[i]

    def to_dict(self, normalized_by: float | None = None, *, results: bool = False) -> dict[str, Any]:
        """Plain JSON-ready data, the profile part of ``pinograsp profile --json``
        (``docs/cli.md``): absolute ``magnitudes`` [N or N·m] (``None`` where unbounded),
        ``normalized``, ``unbounded_runs_deg``, ...

        Args:
            normalized_by: Reference magnitude for ``"normalized"`` (default: the profile's own).
            results: Also list every direction's :meth:`MaxWrench.to_dict` (without responses).
        """
        ref = normalized_by if normalized_by is not None else self.normalized_by
        mags = self.absolute_magnitudes()
        deg = np.degrees(self.angles)
        out = {
            "plane": list(self.plane),
            "basis": self.basis,
            "n": len(self.angles),
            "angles_deg": deg,
            "directions": self.directions,
            "magnitudes": mags,
            "unbounded": self.unbounded,
            "monotone": [r.monotone for r in self.results],
            "n_solves": [r.n_solves for r in self.results],
            "normalized_by": ref,
            "normalized": None if ref is None else mags / ref,
            "wall_time": self.wall_time,
            "unbounded_runs_deg": unbounded_runs(deg, self.unbounded),
        }
        if results:
            out["results"] = [r.to_dict(response=False) for r in self.results]
        return jsonable(out)

    def absolute_magnitudes(self) -> np.ndarray:
        """The magnitudes before any normalisation, (n,) [N or N·m] (``inf``: unbounded)."""
        if len(self.results) == len(self.magnitudes):
            return np.array([r.magnitude for r in self.results], dtype=float)
        m = np.asarray(self.magnitudes, dtype=float)
        return m * self.normalized_by if self.normalized_by else m

    def _status_counts(self) -> dict[str, int]:
        counts = {"finite": 0, "unbounded": 0, "above_limit": 0, "below_resolution": 0}
        if len(self.results) == len(self.magnitudes):
            for r in self.results:
                counts[r.status] = counts.get(r.status, 0) + 1
        else:
            counts["unbounded"] = int(np.sum(self.unbounded))
            counts["finite"] = len(self.magnitudes) - counts["unbounded"]
        return counts

    def summary(self) -> str:
        """Plane, directions per status, the finite range to the resolution, unbounded runs."""
        unit = wrench_unit(self.basis[0] + self.basis[1]) if len(self.basis) == 2 else ""
        mags = self.absolute_magnitudes()
        res = max((r.resolution for r in self.results), default=float("nan"))
        fin = (
            np.array([r.status == "finite" for r in self.results], bool) if self.results else ~self.unbounded
        )
        b1, b2 = (direction_text(b) for b in self.basis)
        method = self.results[0].method if self.results else "?"
        counts = self._status_counts()
        lines = [
            f"resistance profile in the plane ({b1}, {b2}): {len(self.angles)} directions, method {method}",
            ", ".join(f"{k} {v}" for k, v in counts.items() if v or k in ("finite", "unbounded")),
        ]
        if fin.any():
            lo, hi = float(mags[fin].min()), float(mags[fin].max())
            exact = f"(resolution {res:.2g} {unit})" if res > 0 else "(exact)"
            lines.append(
                f"finite magnitudes {format_magnitude(lo, res)}–{format_magnitude(hi, res, unit)} {exact}"
            )
        runs = unbounded_runs(np.degrees(self.angles), self.unbounded)
        lines.append("unbounded at " + runs_text(runs) if runs else "no direction unbounded")
        if self.normalized_by is not None:
            lines.append(f"normalised by {self.normalized_by:.4g} {unit}")
        lines.append(f"{sum(r.n_solves for r in self.results)} solves, {self.wall_time:.3g} s")
        return "\n".join(lines)

    def __repr__(self) -> str:
        method = self.results[0].method if self.results else None
        if len(self.results) == len(self.magnitudes):
            fin = np.array([r.status == "finite" for r in self.results], bool)
        else:
            fin = ~np.asarray(self.unbounded, bool) & np.isfinite(self.magnitudes)
        m = self.magnitudes
        rng = f"({_num(np.min(m[fin]))}, {_num(np.max(m[fin]))})" if fin.any() else "None"
        norm = None if self.normalized_by is None else _num(self.normalized_by)
        return (
            f"ResistanceProfile(plane={tuple(self.plane)!r}, n={len(self.angles)}, method={method!r}, "
            + ", ".join(f"{k}={v}" for k, v in self._status_counts().items())
            + f", range={rng}, normalized_by={norm}, wall_time={self.wall_time:.3g})"
        )

    def rows(self) -> list[dict[str, Any]]:
        """One dict per direction with the keys :data:`PROFILE_COLUMNS`; ``magnitude`` [N or
        N·m] absolute (``inf`` where unbounded), ``normalized`` NaN when not normalised."""
        mags = self.absolute_magnitudes()
        ref = self.normalized_by
        rows = []
        for i, mw in enumerate(self.results):
            row = {"angle_deg": float(np.degrees(self.angles[i])), **mw.row()}
            row["magnitude"] = float(mags[i])
            row["normalized"] = float(mags[i] / ref) if ref else float("nan")
            rows.append({k: row[k] for k in PROFILE_COLUMNS})
        return rows

    def to_csv(self, path: object, *, name: str = "path") -> Path:
        """Write :meth:`rows` to a CSV file (standard library ``csv``; header
        :data:`PROFILE_COLUMNS`; ``inf`` where unbounded, an empty cell for a missing
        ``normalized``); returns the :class:`~pathlib.Path` written.

        Args:
            path: The CSV file (``str`` or ``os.PathLike``); parent folders are created.
            name: How errors name ``path`` (e.g. ``"--csv"``).

        Raises:
            InvalidInputError: ``path`` is not a file path or cannot be written.
        """
        return write_csv(path, PROFILE_COLUMNS, self.rows(), name)

    def to_dataframe(self) -> Any:
        """:meth:`rows` as a ``pandas.DataFrame`` (columns :data:`PROFILE_COLUMNS`).

        Raises:
            MissingDependencyError: pandas is not installed (``pip install "pinograsp[tables]"``).
        """
        pd = require_pandas("ResistanceProfile.to_dataframe")
        return pd.DataFrame(self.rows(), columns=list(PROFILE_COLUMNS))


def format_max_wrench(mw: MaxWrench, scale: float = 1.0, unit: str | None = None) -> str:
    """A :class:`MaxWrench` magnitude as text, by its status: ``unbounded``, ``>= upper``,
    ``< floor`` or the magnitude to its resolution, all divided by ``scale`` (e.g. a
    normalisation reference), followed by ``unit`` when given."""
    if not isinstance(mw, MaxWrench):
        raise InvalidInputError("mw", f"expected a MaxWrench, got {type(mw).__name__}")
    scale = real_number("scale", scale)
    if not (math.isfinite(scale) and scale > 0):
        raise InvalidInputError("scale", f"must be finite and > 0, got {scale!r}")
    if mw.status == "unbounded":
        return "unbounded"
    if mw.status == "above_limit":
        text = f">= {mw.upper / scale:.4g}"
    elif mw.status == "below_resolution":
        text = f"< {mw.floor / scale:.2g}"
    else:
        return format_magnitude(mw.magnitude / scale, mw.resolution / scale, unit)
    return f"{text} {unit}" if unit else text
