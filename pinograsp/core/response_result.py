"""The passive response of a preloaded grasp to one wrench (:class:`PassiveResponse`): the record,
its plain data (``to_dict``, the ``pinograsp analyze --json`` schema) and its text (``summary``,
a compact ``repr``). Re-exported by :mod:`pinograsp.core.results`. NumPy only."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from .audit import Audit
from .serialize import format_magnitude, jsonable, vector_text

if TYPE_CHECKING:
    from .model import GraspModel


#: Verdict of one passive response: the model's (``resisted``, ``not_resisted``), the iterative
#: scheme's cap (``not_converged``), or a solver's limit or failure (the values of
#: ``pinograsp.solvers.base.SolveStatus`` that are not optimal or infeasible).
ResponseStatus = Literal["resisted", "not_resisted", "not_converged", "timeout", "node_limit", "failed"]
#: Name of an analysis method: a name of the method table (:func:`pinograsp.core.methods.method_names`;
#: a ``str``, since methods may be registered at run time).
MethodName = str
#: State of a contact in a solution: ``"separated"`` (no force), ``"sticking"`` (touching, no
#: slip) or ``"sliding"`` (touching and slipping; for ``method="energetic"`` its force then sits
#: on the pyramid's boundary, pointing most against the slip).
ContactState = Literal["sticking", "sliding", "separated"]


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
        method: ``"prp"``, ``"iterative"``, ``"energetic"`` or ``"quasistatic"``.
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

    @classmethod
    def of_model(cls, model: GraspModel, **fields: Any) -> PassiveResponse:
        """The response of ``model`` (the one factory of every method's responses): the fields
        that come from the model — contact, joint and actuator names, ``mu`` per contact (what
        was analysed), actuator kinds, pyramid edges — filled from it, the rest from
        ``fields``."""
        labels: dict[str, Any] = dict(
            contact_names=model.contact_names,
            joint_names=model.joint_names,
            actuator_names=model.actuator_names,
            contact_mu=np.array(model.mu, dtype=float),
            actuator_kinds=tuple(model.kinds),
            edge_counts=model.edge_counts,
        )
        return cls(**{**labels, **fields})

    @classmethod
    def unsolved(cls, model: GraspModel, status: ResponseStatus, **fields: Any) -> PassiveResponse:
        """A response with no state (no solution, or no preload to load): every force and
        displacement NaN (shapes of ``model``), not resistible, no audit; ``fields`` override
        (e.g. ``net_wrench`` when a residual is known, the modes, the solver)."""

        def nan(*shape: int) -> np.ndarray:
            return np.full(shape, np.nan)

        base: dict[str, Any] = dict(
            resistible=False,
            status=status,
            contact_forces=nan(model.nc, 3),
            contact_forces_world=nan(model.nc, 3),
            joint_torques=nan(model.nq),
            actuator_forces=nan(model.na),
            coupling_forces=nan(model.ncp),
            object_displacement=nan(6),
            joint_displacements=nan(model.nq),
            actuator_displacements=nan(model.na),
            contact_modes=(),
            actuator_modes=(),
            net_wrench=nan(6),
            audit=None,
            converged=False,
        )
        return cls.of_model(model, **{**base, **fields})

    @property
    def normal_forces(self) -> np.ndarray:
        """Normal contact forces ``c_n`` (nc,) [N]."""
        return self.contact_forces[:, 0]

    def to_dict(self, model: GraspModel | None = None) -> dict[str, Any]:
        """Plain JSON-ready data, the ``pinograsp analyze --json`` schema (``docs/cli.md``):
        forces [N] as lists, ``None`` for NaN/inf.

        Args:
            model: Optional :class:`~pinograsp.GraspModel` to take ``mu`` and actuator ``kind``
                from (default: the record's ``contact_mu`` and ``actuator_kinds``).
        """
        mus = _labels(self, model, "contact_names", "contact_mu", "mu")
        kinds = _labels(self, model, "actuator_names", "actuator_kinds", "kinds")
        return jsonable(
            {
                "resistible": self.resistible,
                "status": self.status,
                "method": self.method,
                "variant": self.variant,
                "wrench": self.wrench,
                "contacts": _contact_rows(self, mus),
                "actuators": _actuator_rows(self, kinds),
                "joints": [
                    {
                        "name": name,
                        "torque": self.joint_torques[i],
                        "displacement": self.joint_displacements[i],
                    }
                    for i, name in enumerate(self.joint_names)
                ],
                "coupling_forces": self.coupling_forces,
                "object_displacement": self.object_displacement,
                "net_wrench": self.net_wrench,
                "audit": None if self.audit is None else self.audit.to_dict(),
                "iterations": self.iterations,
                "residual_history": list(self.residual_history),
                "solver": self.solver,
                "solve_time": self.solve_time,
                "n_solves": self.n_solves,
            }
        )

    def summary(self) -> str:
        """Status, wrench, normal contact forces [N], actuator modes and the audit, as text."""
        r = self
        lines = [
            f"passive response ({r.method}, {r.variant}): {'RESISTED' if r.resistible else 'NOT RESISTED'}"
            f" (status {r.status}; {r.iterations} iteration(s), {r.n_solves} solve(s), {r.solve_time:.3g} s)",
            f"wrench {vector_text(r.wrench)} [N, N·m] (fx, fy, fz, mx, my, mz)",
        ]
        if r.resistible:
            lines.append(f"normal contact forces: {forces_text(r)}")
            if states := states_text(r):
                lines.append(f"contact states: {states}")
            acts = [f"{nm} {md}" for nm, md in zip(r.actuator_names, r.actuator_modes)]
            if acts:
                lines.append("actuators: " + ", ".join(acts))
        else:
            lines.append(f"net wrench |w + G c|: {np.linalg.norm(r.net_wrench):.3e}")
        if r.audit is not None:
            lines.append(r.audit.summary())
        return "\n".join(lines)

    def __repr__(self) -> str:
        cn = self.contact_forces[:, 0] if len(self.contact_forces) else np.zeros(0)
        ok = None if self.audit is None else self.audit.ok
        return (
            f"PassiveResponse(status={self.status!r}, resistible={self.resistible}, method={self.method!r}, "
            f"variant={self.variant!r}, wrench={vector_text(self.wrench)}, normal_forces={vector_text(cn)}, "
            f"nc={len(self.contact_names)}, audit_ok={ok}, iterations={self.iterations}, "
            f"n_solves={self.n_solves})"
        )


def _labels(
    r: PassiveResponse, model: GraspModel | None, names: str, values: str, model_values: str
) -> list[Any]:
    """Per-row model data (``mu`` per contact, ``kind`` per actuator) by name: the record's own
    (what was analysed: a normal uncertainty reduces ``mu``), else from ``model`` when given
    (``None`` where unknown)."""
    rows = getattr(r, names)
    own = getattr(r, values)  # a declared field of the record (None where unknown)
    if own is not None and len(own) == len(rows):
        return list(own)
    if model is not None:
        table = dict(zip(getattr(model, names), getattr(model, model_values)))
        return [table.get(nm) for nm in rows]
    return [None] * len(rows)


def _contact_rows(r: PassiveResponse, mus: list[Any]) -> list[dict[str, Any]]:
    """One dict per contact: name, mode, ``mu``, forces [N] (contact and world frame), friction
    use, state, slip [m] and pyramid edges."""
    fu = r.friction_use
    return [
        {
            "name": name,
            "mode": r.contact_modes[i] if i < len(r.contact_modes) else None,
            "mu": mus[i],
            "force": r.contact_forces[i],
            "force_world": r.contact_forces_world[i],
            "friction_use": None if fu is None or np.isnan(fu[i]) else float(fu[i]),
            "state": r.contact_states[i] if i < len(r.contact_states) else None,
            "slip": None if r.contact_slip is None else r.contact_slip[i],
            "edges": r.edge_counts[i] if i < len(r.edge_counts) else None,
        }
        for i, name in enumerate(r.contact_names)
    ]


def _actuator_rows(r: PassiveResponse, kinds: list[Any]) -> list[dict[str, Any]]:
    """One dict per actuator: name, kind, command, force [N], mode and displacement."""
    return [
        {
            "name": name,
            "kind": kinds[i],
            "command": r.command[i],
            "force": r.actuator_forces[i],
            "mode": r.actuator_modes[i] if i < len(r.actuator_modes) else None,
            "displacement": r.actuator_displacements[i],
        }
        for i, name in enumerate(r.actuator_names)
    ]


def forces_text(r: PassiveResponse) -> str:
    """``left 10 N, right 10 N`` — the normal contact forces [N] to the audit tolerance."""
    res = r.audit.tolerance if r.audit is not None else 1e-6
    cn = r.contact_forces[:, 0] if len(r.contact_forces) else np.zeros(0)
    return ", ".join(f"{nm} {format_magnitude(f, res, 'N')}" for nm, f in zip(r.contact_names, cn)) or "none"


def states_text(r: PassiveResponse) -> str:
    """``left sliding (slip direction (0.342, -0.9397, 0)), right sticking`` — the state of each
    contact and the unit slip direction (world frame) of the sliding ones; ``""`` when the
    response reports no states."""
    states = tuple(r.contact_states or ())
    if not states or len(states) != len(r.contact_names):
        return ""
    slip = (
        None if r.contact_slip is None else np.asarray(r.contact_slip, dtype=float).reshape(len(states), -1)
    )
    parts = []
    for i, (name, state) in enumerate(zip(r.contact_names, states)):
        text = f"{name} {state}"
        norm = 0.0 if slip is None else float(np.linalg.norm(slip[i]))
        if slip is not None and state == "sliding" and np.isfinite(norm) and norm > 0.0:
            text += f" (slip direction {vector_text(slip[i] / norm)})"
        parts.append(text)
    return ", ".join(parts)
