"""``LoadingPath``: the load–displacement path of a preloaded grasp, breakpoint by breakpoint.

Between breakpoints every quantity is linear in the load factor λ, so the record is exact at
every load: :meth:`LoadingPath.state_at` interpolates, and on an unbounded path the last
segment continues as a ray with the rates in :attr:`LoadingPath.ray`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ...core.axes import WRENCH_AXES, direction_text, wrench_unit
from ...core.serialize import jsonable
from ...core.validate import GIVEWAY, PHYSICAL_STIFFNESS, number_in
from ...errors import InvalidInputError, MissingDependencyError
from .events import PathEvent
from .giveway import Thresholds, Trace, walk

if TYPE_CHECKING:
    from .model import QSModel

#: How a loading path ended: at a limit load (``finite``; ``below_resolution`` when that is
#: 0), with no event ahead (``unbounded``), or stopped without a verdict: the local rate
#: problem has no solution Lemke's method can find (``no_solution``), or the segment-count
#: limit was reached (``segment_limit``). ``reached``: a path to a given load got there.
PathStatus = Literal["finite", "unbounded", "below_resolution", "no_solution", "segment_limit", "reached"]
#: Why a path stopped: a limit (``"limit"``; ``"unstable"``: certified, no continuation), the
#: last segment a ray (``"ray"``), the load asked for (``"load"``), the segment-count limit,
#: a rate problem without a solution (``"ray_termination"``, ``"pivot_limit"``,
#: ``"inaccurate"``, ``"singular"``), a failed audit (``"audit"``); past a limit also
#: ``"unbounded"``, ``"mechanism"``, ``"unloaded"``, ``"landed"``, ``"end"``.
StopReason = Literal[
    "limit",
    "unstable",
    "ray",
    "load",
    "segment_limit",
    "ray_termination",
    "pivot_limit",
    "inaccurate",
    "singular",
    "audit",
    "unbounded",
    "mechanism",
    "unloaded",
    "landed",
    "end",
]

#: Default stiffness of the simulation's stiffest contact [N/m] (``pg.simulate_max_wrench``).
SIM_STIFFNESS = 1e6


@dataclass(frozen=True, repr=False)
class LoadingPath:
    """The quasi-static loading path of a preloaded grasp along one wrench direction.

    ``k`` breakpoints (the preloaded state first, at λ = 0), ``nc`` contacts, ``nq`` joints,
    ``na`` actuators, ``ncp`` couplings. Displacements are the model's virtual displacements
    from the touching configuration (scaled by the contact stiffness ``k``: multiply by
    ``max(k) / K`` for a physical stiffness ``K``).

    Attributes:
        direction: Unit wrench direction (6,); the load is ``λ direction``.
        command: Actuator commands (na,) [N·m or N].
        variant: Preload: ``"held"`` or ``"settled"``.
        tangential_ratio: Tangential contact stiffness / normal stiffness.
        status: :data:`PathStatus`.
        limit: The limit load λ* [N or N·m]: ``inf`` when unbounded, ``0`` when
            ``below_resolution``, the load reached when the path stopped.
        stop_reason: Why the path stopped (``"limit"``, ``"ray"``, ``"ray_termination"``,
            ``"pivot_limit"``, ``"singular"``, ``"segment_limit"``, ``"load"``).
        loads: λ at the breakpoints (k,).
        object_displacements: (k, 6) [m, rad]; joint_displacements: (k, nq);
            actuator_displacements: (k, na); actuator_forces: (k, na);
            coupling_forces: (k, ncp); contact_forces: contact-frame ``(c_n, c_t1, c_t2)``
            (k, nc, 3) [N]; contact_slip: slip of the object over the hand since the preload,
            world frame (k, nc, 3) [m].
        contact_states: Per breakpoint and contact, the state on the segment leaving the
            breakpoint (the last: the state found at the limit, or on the ray), (k, nc).
        sliding_faces: The polygon faces each contact slides on there, (k, nc).
        actuator_modes: (k, na): ``"moving"``, ``"holding"``, ``"backdrivable"``, ``"locked"``.
        stiffness: dλ/ds per segment along the displacement ``s = direction · x`` [N/m or
            N·m/rad] (``inf`` where the object does not move along the direction), (k - 1,)
            (plus the ray's when unbounded).
        events: The typed events (:class:`PathEvent`), in order.
        ray: On an unbounded path the rates of the last segment per unit load, as a dict of
            the arrays above (``object_displacements`` (6,), ...); else None.
        audit: Residuals at every breakpoint and segment: ``equilibrium`` (k,) [N] (object,
            torques over the length scale), ``hand`` (k,) [N] (joint torques over their
            lever), ``friction`` (k,) [N] (largest polygon violation), ``energy`` (k - 1,)
            [J] (work of the load and actuators minus elastic energy change and friction
            dissipation per segment).
        segments, lcp_solves, pivots, largest_lcp: Work: load segments, local LCPs solved
            (the preload included), Lemke pivots, largest LCP.
        preload_segments: Segments of the preload path (closing and release).
        contact_names, joint_names, actuator_names: Labels.
        length_scale: The model's length scale [m]; model_stiffness: its largest ``k`` [N/m].
        wall_time: [s].
        continuation: At a softening limit (``dλ < 0`` past it), the equilibrium path beyond
            it under displacement control (its loads first fall) until the load is back at
            λ* — the *landing* point of the snap a load-controlled grasp makes — and on from
            there under load control to the next limit, snap after snap; its ``status`` is
            that of the last part (``"finite"`` with ``limit`` = λ* when the load falls to
            zero or no stiffness is left: nothing to land on). None at a mechanism limit or
            when the path is not finite. λ* stays the first limit.
        snaps: (continuation only) ``(limit breakpoint, landing breakpoint)`` of each snap.
        ties: Segments whose local LCP had several solutions on the same tight set (e.g. the
            two faces of a vertex with equal rows): the least-norm one was taken (the tie rule,
            docs/methods.md).
    """

    direction: np.ndarray
    command: np.ndarray
    variant: str
    tangential_ratio: float
    status: PathStatus
    limit: float
    stop_reason: StopReason
    loads: np.ndarray
    object_displacements: np.ndarray
    joint_displacements: np.ndarray
    actuator_displacements: np.ndarray
    actuator_forces: np.ndarray
    coupling_forces: np.ndarray
    contact_forces: np.ndarray
    contact_slip: np.ndarray
    contact_states: tuple[tuple[str, ...], ...]
    sliding_faces: tuple[tuple[tuple[int, ...], ...], ...]
    actuator_modes: tuple[tuple[str, ...], ...]
    stiffness: np.ndarray
    events: tuple[PathEvent, ...]
    ray: dict[str, np.ndarray] | None = field(default=None)
    audit: dict[str, np.ndarray] = field(default_factory=dict)
    segments: int = 0
    lcp_solves: int = 0
    pivots: int = 0
    largest_lcp: int = 0
    preload_segments: int = 0
    contact_names: tuple[str, ...] = ()
    joint_names: tuple[str, ...] = ()
    actuator_names: tuple[str, ...] = ()
    length_scale: float = 1.0
    model_stiffness: float = 1.0
    wall_time: float = 0.0
    continuation: LoadingPath | None = field(default=None)
    snaps: tuple[tuple[int, int], ...] = ()
    ties: int = 0
    #: The re-linearised model that reached each breakpoint (``State.geo``; None: the model's
    #: own geometry), read by the audit of a state; not data (not in ``to_dict``).
    geometries: tuple[QSModel | None, ...] = field(default=(), repr=False, compare=False)

    # ----------------------------------------------------------------- views
    @property
    def unbounded(self) -> bool:
        """Whether the load is resisted without bound."""
        return self.status == "unbounded"

    @property
    def displacement_along(self) -> np.ndarray:
        """Object displacement along the direction since the preload, ``direction · (x - x0)``
        at the breakpoints (k,) [m for forces, rad for torques; mixed directions: the work
        per unit load]."""
        x = self.object_displacements - self.object_displacements[0]
        return x @ self.direction

    def _arrays(self) -> dict[str, np.ndarray]:
        return {
            "object_displacements": self.object_displacements,
            "joint_displacements": self.joint_displacements,
            "actuator_displacements": self.actuator_displacements,
            "actuator_forces": self.actuator_forces,
            "coupling_forces": self.coupling_forces,
            "contact_forces": self.contact_forces,
            "contact_slip": self.contact_slip,
        }

    def segment_at(self, load: float) -> int:
        """Index of the breakpoint that starts the segment holding ``load`` (the last
        breakpoint for loads on the ray)."""
        return int(max(np.searchsorted(self.loads, load, side="right") - 1, 0))

    def state_at(self, load: float) -> dict[str, Any] | None:
        """Every quantity at load λ = ``load`` (linear between breakpoints; on the ray of an
        unbounded path beyond the last one), with ``"contact_states"``, ``"sliding_faces"``
        and ``"actuator_modes"`` of the segment holding it; None above the path's reach."""
        lam = float(load)
        if not np.isfinite(lam) or lam < 0:
            raise InvalidInputError("load", f"expected a finite load >= 0, got {load!r}")
        last = self.loads[-1]
        if lam > last and (self.ray is None):
            return None
        j = self.segment_at(lam)
        out: dict[str, Any] = {"load": lam}
        for name, arr in self._arrays().items():
            if lam > last:
                assert self.ray is not None  # beyond the last breakpoint only along a ray
                out[name] = arr[-1] + (lam - last) * self.ray[name]
            elif j + 1 < len(self.loads) and self.loads[j + 1] > self.loads[j]:
                s = (lam - self.loads[j]) / (self.loads[j + 1] - self.loads[j])
                out[name] = (1.0 - s) * arr[j] + s * arr[j + 1]
            else:
                out[name] = arr[j].copy()
        if self.geometries:  # the geometry of the segment the load lies on
            between = lam <= last and j + 1 < len(self.loads) and lam > self.loads[j]
            out["geometry"] = self.geometries[j + 1 if between else j]
        # the states of the segment leaving breakpoint j (at the last one: the state found at
        # the limit, on the ray, or the one that reached it)
        out["contact_states"] = self.contact_states[j]
        out["sliding_faces"] = self.sliding_faces[j]
        out["actuator_modes"] = self.actuator_modes[j]
        return out

    def load_at_displacement(
        self, delta: float, stiffness: float = SIM_STIFFNESS, rotation: float | None = None
    ) -> float:
        """The load at which the object has moved ``delta`` [m] (or turned ``rotation``
        [rad]) since the preload, with the contact springs scaled to a physical stiffness
        (``stiffness`` [N/m] for the stiffest contact, the others in proportion) — the
        simulation's "gave way" threshold (``pg.simulate_max_wrench``: translation of the
        reference point ``slip``, rotation ``rotation``, default ``slip / length_scale``).

        Returns:
            λ [N or N·m]: the first load where the translation reaches ``delta`` or the
            rotation ``rotation``; the limit load when neither is reached before it (a sharp
            give-way); ``inf`` on an unbounded path that never gets there.
        """
        d = number_in("delta", delta, *GIVEWAY, "m")
        k = number_in("stiffness", stiffness, *PHYSICAL_STIFFNESS, "N/m")
        rot = d / self.length_scale if rotation is None else number_in("rotation", rotation, *GIVEWAY, "rad")
        th = Thresholds(d, rot, None, self.model_stiffness / k, self.length_scale, linear=False)
        cont = self.continuation
        follow = self.status == "finite" and cont is not None and bool(cont.snaps)
        point, _ = walk(
            self.trace(), cont.trace() if follow and cont else None, cont.snaps if cont else (), th
        )
        if point is not None:
            return point.load
        return float(cont.limit) if follow and cont is not None else float(self.limit)

    def trace(self) -> Trace:
        """The record's loads and displacements as a :class:`~.giveway.Trace` (with its ray)."""
        ray = self.ray
        return Trace(
            self.loads,
            self.object_displacements,
            self.joint_displacements,
            None if ray is None else ray["object_displacements"],
            None if ray is None else ray["joint_displacements"],
        )

    def state_on(self, index: int, step: float, on_ray: bool = False) -> dict[str, Any]:
        """Every quantity at a point given by breakpoint ``index`` and ``step`` from it (a
        fraction of the segment to the next breakpoint, or on the ray a load increment),
        with the states of the segment leaving ``index`` (as :meth:`state_at`)."""
        j, s = int(index), float(step)
        out: dict[str, Any] = {}
        for name, arr in self._arrays().items():
            if on_ray:
                assert self.ray is not None  # a point on the ray of an unbounded path
                out[name] = arr[j] + s * self.ray[name]
            elif j + 1 < len(self.loads) and s > 0.0:
                out[name] = (1.0 - s) * arr[j] + s * arr[j + 1]
            else:
                out[name] = arr[j].copy()
        load = self.loads[j] + s if on_ray else self.loads[j]
        if not on_ray and j + 1 < len(self.loads) and s > 0.0:
            load = (1.0 - s) * self.loads[j] + s * self.loads[j + 1]
        out["load"] = float(load)
        if self.geometries:  # the geometry of the segment the point lies on
            between = not on_ray and j + 1 < len(self.loads) and s > 0.0
            out["geometry"] = self.geometries[j + 1 if between else j]
        out["contact_states"] = self.contact_states[j]
        out["sliding_faces"] = self.sliding_faces[j]
        out["actuator_modes"] = self.actuator_modes[j]
        return out

    # ------------------------------------------------------------- exports
    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data (arrays as lists, ``inf``/``nan`` as ``None``)."""
        out = {
            "method": "quasistatic",
            "direction": self.direction,
            "label": direction_text(self.direction),
            "command": self.command,
            "variant": self.variant,
            "tangential_ratio": self.tangential_ratio,
            "status": self.status,
            "limit": self.limit,
            "unbounded": self.unbounded,
            "stop_reason": self.stop_reason,
            "loads": self.loads,
            "displacement_along": self.displacement_along,
            **self._arrays(),
            "contact_states": self.contact_states,
            "sliding_faces": self.sliding_faces,
            "actuator_modes": self.actuator_modes,
            "stiffness": self.stiffness,
            "events": [e.to_dict() for e in self.events],
            "ray": self.ray,
            "audit": self.audit,
            "segments": self.segments,
            "lcp_solves": self.lcp_solves,
            "pivots": self.pivots,
            "largest_lcp": self.largest_lcp,
            "preload_segments": self.preload_segments,
            "contact_names": self.contact_names,
            "joint_names": self.joint_names,
            "actuator_names": self.actuator_names,
            "length_scale": self.length_scale,
            "model_stiffness": self.model_stiffness,
            "wall_time": self.wall_time,
            "continuation": None if self.continuation is None else self.continuation.to_dict(),
            "snaps": self.snaps,
            "ties": self.ties,
        }
        return jsonable(out)

    def rows(self) -> list[dict[str, Any]]:
        """One dict per breakpoint: load, displacement along the direction, object
        displacement, normal force and state of every contact, actuator forces and modes."""
        out = []
        s = self.displacement_along
        for j, lam in enumerate(self.loads):
            row: dict[str, Any] = {"breakpoint": j, "load": float(lam), "displacement_along": float(s[j])}
            for a, v in zip(WRENCH_AXES, self.object_displacements[j]):
                row[f"x_{a}"] = float(v)
            for i, name in enumerate(self.contact_names):
                row[f"cn_{name}"] = float(self.contact_forces[j, i, 0])
                row[f"state_{name}"] = self.contact_states[j][i]
            for k, name in enumerate(self.actuator_names):
                row[f"f_{name}"] = float(self.actuator_forces[j, k])
                row[f"mode_{name}"] = self.actuator_modes[j][k]
            out.append(row)
        return out

    def to_dataframe(self) -> Any:
        """:meth:`rows` as a ``pandas.DataFrame`` (needs ``pip install "pinograsp[tables]"``)."""
        try:
            import pandas as pd
        except ImportError as exc:  # pragma: no cover - depends on the environment
            raise MissingDependencyError("pandas", "LoadingPath.to_dataframe", "tables") from exc
        return pd.DataFrame(self.rows())

    def to_csv(self, path: object) -> Any:
        """Write :meth:`rows` to a CSV file (standard library); returns the path."""
        import csv
        from pathlib import Path

        p = Path(str(path))
        rows = self.rows()
        with p.open("w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]) if rows else ["breakpoint"])
            w.writeheader()
            w.writerows(rows)
        return p

    def summary(self) -> str:
        """Status, limit, segments and events as text."""
        unit = wrench_unit(self.direction)
        lim = "unbounded" if self.unbounded else f"{self.limit:.6g} {unit}"
        lines = [
            f"quasi-static loading path along {direction_text(self.direction)}: {lim} ({self.status}, "
            f"{self.stop_reason}); {self.segments} segments, {len(self.events)} events, "
            f"{self.lcp_solves} LCPs (largest {self.largest_lcp}), {self.wall_time * 1e3:.3g} ms",
        ]
        lines += ["  " + e.text() for e in self.events]
        return "\n".join(lines)

    def __repr__(self) -> str:
        lim = "unbounded" if self.unbounded else f"{self.limit:.6g}"
        return (
            f"LoadingPath({direction_text(self.direction)}: {lim}, status={self.status!r}, "
            f"{len(self.loads)} breakpoints, {len(self.events)} events)"
        )


__all__ = ["SIM_STIFFNESS", "LoadingPath", "PathStatus", "StopReason"]
