"""Typed, immutable results of pinograsp analyses."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from ..errors import InvalidInputError
from . import serialize as _ser
from . import summaries as _sum
from .audit import EnergyCheck
from .axes import direction_text

#: Largest per-component difference between two unit wrench directions (6,) that are taken to
#: be the same (:meth:`ResistanceProfile.result_along`). A profile's directions
#: ``cos(a) b1 + sin(a) b2`` and a reference parsed from an axis name or vector agree to
#: rounding (~1e-16) when they are the same direction, while two distinct directions of an
#: ``n``-direction profile differ by ``2 sin(pi / n)`` (above 1e-9 for any ``n`` below 6e9): every
#: tolerance between those picks the same direction. 1e-9 also admits a reference written with
#: nine significant digits (a vector in a scene file).
DIRECTION_ATOL = 1e-9


#: Verdict of one passive response: the model's (``resisted``, ``not_resisted``), the iterative
#: scheme's cap (``not_converged``), or a solver's limit or failure (the values of
#: ``pinograsp.solvers.base.SolveStatus`` that are not optimal or infeasible).
ResponseStatus = Literal["resisted", "not_resisted", "not_converged", "timeout", "node_limit", "failed"]
#: Name of an analysis method (the values of :class:`~pinograsp.core.settings.Method`).
MethodName = Literal["prp", "iterative", "energetic", "quasistatic"]
#: State of a contact in a solution: ``"separated"`` (no force), ``"sticking"`` (touching, no
#: slip) or ``"sliding"`` (touching and slipping; for ``method="energetic"`` its force then sits
#: on the pyramid's boundary, pointing most against the slip).
ContactState = Literal["sticking", "sliding", "separated"]


@dataclass(frozen=True)
class Audit:
    """Post-solve check of a solution, in physical force units [N] (torques divided by the
    model's length scale, joint torques by their lever).

    Attributes:
        equilibrium: Norm of the object's net wrench ``w + G c`` [N]. Zero (to solver accuracy)
            for an equilibrium; for the iterative scheme this is the final residual.
        hand: Largest joint-torque imbalance ``|J^T c - R f - C^T lambda| / lever`` [N].
        complementarity: Largest ``min(a, b)`` over every complementary pair (contact force /
            spring gap, actuator motion / over-force) [N]: zero when complementarity holds.
        friction: Largest violation of the friction pyramid (negative edge weight) [N].
        bigm_ratio: Largest big-M-bounded quantity as a fraction of its bound (0 without MIQP).
        bigm_retries: How many times the big-M bounds had to be enlarged.
        polished: Whether the solution was polished by the exact fixed-mode QP.
        tolerance: Tolerance the residuals are compared with [N].
        energy: Energy balance and displacement size of an equilibrium (None when the load is
            not resisted): :class:`~pinograsp.core.audit.EnergyCheck`.
    """

    equilibrium: float
    hand: float
    complementarity: float
    friction: float
    bigm_ratio: float = 0.0
    bigm_retries: int = 0
    polished: bool = False
    tolerance: float = 1e-6
    energy: EnergyCheck | None = None

    @property
    def ok(self) -> bool:
        """All hand/complementarity/friction residuals within tolerance, no big-M saturation,
        and (for an equilibrium) the energy balance and displacement size hold."""
        physical = self.energy is None or (self.energy.energy_ok and self.energy.displacement_ok)
        return (
            self.hand <= self.tolerance
            and self.complementarity <= self.tolerance
            and self.friction <= self.tolerance
            and self.bigm_ratio < 0.1
            and physical
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: ``ok``, the residuals [N], big-M use and ``energy``."""
        return _ser.audit_dict(self)

    def summary(self) -> str:
        """The verdict and residuals [N] as text (and the energy balance [J] when checked)."""
        return _sum.audit_summary(self)


@dataclass(frozen=True, repr=False)
class PassiveResponse:
    """Passive response of a preloaded grasp to one external wrench.

    Shapes: ``nc`` contacts, ``nq`` joints, ``na`` actuators, ``ncp`` couplings (of the pruned
    model). Forces in [N], torques in [N·m], displacements in [m] / [rad] (virtual, from the
    touching-without-force configuration; scaled by the contact stiffness).

    Attributes:
        resistible: Whether the wrench is resisted passively (PRP: feasible; iterative:
            converged to equilibrium below ``eps``).
        status: ``"resisted"``, ``"not_resisted"`` (infeasible / converged above ``eps``),
            ``"not_converged"`` (iteration cap), ``"timeout"``, ``"node_limit"`` or ``"failed"``.
        method: ``"prp"``, ``"iterative"`` or ``"energetic"``.
        variant: ``"single-step"``, ``"preload-first"`` or ``"settled-preload"``.
        wrench: Applied wrench ``(fx, fy, fz, mx, my, mz)`` about the object reference point.
        command: Actuator commands of the kept actuators (na,).
        contact_forces: Contact-frame forces ``(c_n, c_t1, c_t2)`` on the object, (nc, 3).
        contact_forces_world: World-frame forces on the object, (nc, 3).
        joint_torques: ``tau = J^T c``, (nq,).
        actuator_forces: (na,).
        coupling_forces: Coupling reactions ``lambda``, (ncp,).
        object_displacement: ``(translation, rotation)``, (6,).
        joint_displacements: (nq,).
        actuator_displacements: ``u = R^T q``, (na,).
        contact_modes: ``"touching"`` / ``"separated"`` per contact.
        actuator_modes: ``"moving"`` / ``"holding"`` (non-backdrivable), ``"backdrivable"``,
            ``"locked"``.
        net_wrench: ``w + G c`` (6,): zero at equilibrium.
        audit: Residual checks of the returned solution.
        iterations: Movement-constrained solves of the iterative scheme (1 for PRP).
        residual_history: Net-wrench norm after each iteration [N] (empty for PRP).
        converged: The iteration met ``eps`` (PRP: same as ``resistible``).
        solver: Backend(s) used.
        solve_time: Wall time of the solver calls [s].
        n_solves: Complementarity problems solved (branch-and-bound searches or reference
            MIQPs; one per PRP, one per iteration step, plus the subspace jumps).
        contact_names, joint_names, actuator_names: Labels of the rows above.
        friction_use: ``|c_t| / (mu c_n)`` per contact (nc,): NaN for a separated contact or one
            touching with no normal force (above the audit tolerance).
        contact_mu: Friction coefficient per contact (nc,) (``None``: not recorded).
        actuator_kinds: Kind of each actuator (``"non-backdrivable"``, ...), (na,).
        contact_states: :data:`ContactState` per contact (nc,): ``"sliding"`` where the slip
            exceeds the audit tolerance (in spring-force units ``k |s|``).
        contact_slip: Slip of the object over the hand at each contact, world frame, (nc, 3)
            [m] (tangential; virtual, scaled by the stiffness like every displacement).
        edge_counts: Friction pyramid edges per contact (nc,) (``Settings.cone_tolerance``
            refines them where loaded).
    """

    resistible: bool
    status: ResponseStatus
    method: MethodName
    variant: str
    wrench: np.ndarray
    command: np.ndarray
    contact_forces: np.ndarray
    contact_forces_world: np.ndarray
    joint_torques: np.ndarray
    actuator_forces: np.ndarray
    coupling_forces: np.ndarray
    object_displacement: np.ndarray
    joint_displacements: np.ndarray
    actuator_displacements: np.ndarray
    contact_modes: tuple[str, ...]
    actuator_modes: tuple[str, ...]
    net_wrench: np.ndarray
    audit: Audit | None
    iterations: int = 1
    residual_history: tuple[float, ...] = ()
    converged: bool = False
    solver: str = ""
    solve_time: float = 0.0
    n_solves: int = 0
    contact_names: tuple[str, ...] = ()
    joint_names: tuple[str, ...] = ()
    actuator_names: tuple[str, ...] = ()
    friction_use: np.ndarray | None = None
    contact_mu: np.ndarray | None = None
    actuator_kinds: tuple[str, ...] = ()
    contact_states: tuple[ContactState, ...] = ()
    contact_slip: np.ndarray | None = None
    edge_counts: tuple[int, ...] = ()

    @property
    def normal_forces(self) -> np.ndarray:
        """Normal contact forces ``c_n`` (nc,) [N]."""
        return self.contact_forces[:, 0]

    def to_dict(self, model: Any = None) -> dict[str, Any]:
        """Plain JSON-ready data, the ``pinograsp analyze --json`` schema (``docs/cli.md``):
        forces [N] as lists, ``None`` for NaN/inf.

        Args:
            model: Optional :class:`~pinograsp.GraspModel` to take ``mu`` and actuator ``kind``
                from (default: the record's ``contact_mu`` and ``actuator_kinds``).
        """
        return _ser.response_dict(self, model)

    def summary(self) -> str:
        """Status, wrench, normal contact forces [N], actuator modes and the audit, as text."""
        return _sum.response_summary(self)

    def __repr__(self) -> str:
        return _sum.response_repr(self)


#: How a max-wrench search ended (see :class:`MaxWrench`).
MaxWrenchStatus = Literal[
    "finite", "unbounded", "above_limit", "below_resolution", "no_solution", "segment_limit"
]


@dataclass(frozen=True, repr=False)
class MaxWrench:
    """Largest resistible wrench magnitude along one direction (bisection).

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
            magnitude is below ``floor``: indistinguishable from zero).
        floor: Smallest magnitude distinguishable from zero [N or N·m]: the resolution, and for
            the iterative method at least its equilibrium tolerance ``eps`` along the direction.
        upper: Upper limit of the search.
        resolution: Bisection resolution ``upper / 2**steps`` (the true limit lies in
            ``[magnitude, magnitude + resolution]`` if resistibility is monotone along the ray).
        evidence: Every magnitude tried and its verdict, in order.
        method: ``"prp"``, ``"iterative"`` or ``"energetic"``.
        solve_time: Total solver wall time [s] (including the preload check).
        wall_time: Total wall time of the query [s].
        n_solves: Complementarity problems solved.
        response: The passive response at ``magnitude`` (or at ``upper`` when unbounded).
        search: ``"bisection"``, ``"secant"`` (iterative) or ``"direct"`` (one load-factor
            complementarity problem, PRP only).
        audit_failures: Resisted magnitudes whose solution fails the audit (energy balance or
            displacement size; ``inf`` for the zero-preload limit test), ascending. Non-empty
            means the PRP's wedging artefact carries the verdict above ``min(audit_failures)``;
            one :class:`~pinograsp.errors.AuditWarning` says so.
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
        return _ser.max_wrench_dict(self, label, response=response)

    def summary(self, label: str | None = None) -> str:
        """Status and magnitude to the resolution with its unit, the search, and the normal
        contact forces [N] at the limit, as text."""
        return _sum.max_wrench_summary(self, label)

    def __repr__(self) -> str:
        return _sum.max_wrench_repr(self)


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
        results: The per-direction :class:`MaxWrench` records.
        wall_time: Total wall time [s].
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
        return _ser.profile_dict(self, normalized_by, results=results)

    def summary(self) -> str:
        """Plane, directions per status, the finite range to the resolution, unbounded runs."""
        return _sum.profile_summary(self)

    def __repr__(self) -> str:
        return _sum.profile_repr(self)

    def rows(self) -> list[dict[str, Any]]:
        """One dict per direction (the CSV columns, :data:`pinograsp.core.tables.PROFILE_COLUMNS`)."""
        from .tables import profile_rows

        return profile_rows(self)

    def to_csv(self, path: object) -> object:
        """Write one row per direction to a CSV file (standard library ``csv``); returns the
        :class:`~pathlib.Path` written. Columns: :data:`pinograsp.core.tables.PROFILE_COLUMNS`."""
        from .tables import profile_to_csv

        return profile_to_csv(self, path)

    def to_dataframe(self) -> Any:
        """The rows as a ``pandas.DataFrame`` (needs ``pip install "pinograsp[tables]"``)."""
        from .tables import profile_to_dataframe

        return profile_to_dataframe(self)
