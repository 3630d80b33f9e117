"""Choosing a preload: actuator commands under which the grasp is in equilibrium at ``w = 0``.

A command vector ``f_c`` is a preload of the grasp when the forces it produces balance on the
object. Under the model (docs/design.md) that means: contact forces ``c = D beta`` in their
friction pyramids, every contact pressing (``c_n >= t > 0``), the object in equilibrium
(``G c = 0``), the hand in equilibrium with every driving actuator at its command
(``J^T c = R f_c + C^T lambda``; locked actuators react freely), normal forces produced by the
springs ``c_n = k n^T (J q - G^T x)`` of a hand displacement ``q`` that the couplings allow
(``C q = 0``) and that closes every non-backdrivable actuator (``R^T q >= 0``), and an object
displacement ``x``. The design problem does not follow a method's path to the equilibrium; the
verification does (``method``: whose preload stage to run; docs/hands.md, "Choosing a preload").

Objectives: ``"balanced"`` maximises the smallest normal force with every command within its
bound (then the least-norm commands at that force); ``"least_norm"`` gives the smallest
commands for which every contact presses with at least ``grip`` [N]. The commands found are
verified by :func:`pinograsp.passive_response` at ``w = 0`` with the method: its preload stage
(for the quasi-static method the preload path: the object held while the hand closes, then
released) must end in equilibrium, and the released state must hold: every contact sticking
(none on its friction limit, none separated) and the object moved on release by at most
:data:`MOVED_RATIO` times the largest contact compression. A design that balances but whose
released state slides or moves is ``"slides"``, one where a contact the design pressed carries
no force at zero load is ``"separates"``: never ``"found"``. Where no preload
exists, the result names the contacts that no preload can load and the actuators that no
preload can balance.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from ..core.methods import preload_method
from ..core.model import GraspModel
from ..core.results import PassiveResponse
from ..core.settings import DEFAULT_METHOD, Settings
from ..core.validate import choice, force
from ..errors import InvalidInputError, ModelError, PinograspError, SolverError, UnknownNameError
from ..solvers.quiet import quiet_stdout
from .preload_release import GIVES, gives_way, released
from .preload_release import MOVED_RATIO as MOVED_RATIO  # re-exported: the verdict's bar
from .registry import get_method
from .response import passive_response
from .staged import SETTLED_PRELOAD_METHOD

Objective = Literal["balanced", "least_norm"]
OBJECTIVES: tuple[str, ...] = ("balanced", "least_norm")
#: Verdict of :func:`equilibrium_preload` (see :class:`PreloadChoice`).
PreloadStatus = Literal["found", "slides", "separates", "unverified", "infeasible"]
#: Smallest normal force, relative to the largest, for a contact to count as loaded.
LOADED = 1e-6


@dataclass(frozen=True)
class PreloadChoice:
    """Result of :func:`equilibrium_preload`.

    Attributes:
        status: ``"found"`` (commands found and verified: the method's preload stage settles
            in equilibrium and its released state holds, every contact sticking and the object
            moved by at most :data:`MOVED_RATIO` compressions), ``"slides"`` (the preload stage
            settles in equilibrium, but in its released state a contact already slides on its
            friction limit, or the object moved more: the commands are a preload, but a small
            load makes the grasp give way; ``reason`` says which), ``"separates"`` (the same,
            no contact slides, but a contact the design pressed carries no force at zero load:
            the preload holds on fewer contacts than designed),
            ``"unverified"`` (found by the design problem, but the method's own preload stage
            does not settle in equilibrium with them) or ``"infeasible"`` (no preload loads
            every contact).
        command: ``{actuator: command}`` [N·m or N] (None when infeasible).
        normal_forces: Normal forces of the design solution (nc,) [N] (None when infeasible).
        method: The method whose preload stage was modelled.
        objective: ``"balanced"`` or ``"least_norm"``.
        response: The verification at ``w = 0`` (None when infeasible).
        unloadable_contacts: Contacts that no preload can press (infeasible results).
        unbalanced_actuators: Actuators whose command no preload can balance (infeasible results).
        reason: One sentence on the outcome (for ``"slides"``: the warning, naming the
            contacts that slide or separate at zero load).
        released_states: State of each contact at zero load (nc,), ``"sticking"``,
            ``"sliding"`` or ``"separated"`` (the verification's ``contact_states``; ``()``
            without a verification or when the method reports no states). Only the
            quasi-static method's ``"sliding"`` means "on its friction limit" and makes the
            verdict ``"slides"``; the other methods' means "slipped since the touch"
            (``preload_release.LIMIT_STATES``).
        released_motion: Largest motion of the object at a contact at zero load (from the
            touching configuration: what the release moved it), over the largest contact
            compression ``c_n / k`` [-] (None without a verification).
    """

    status: PreloadStatus
    command: dict[str, float] | None
    normal_forces: np.ndarray | None
    method: str
    objective: str
    response: PassiveResponse | None
    unloadable_contacts: tuple[str, ...]
    unbalanced_actuators: tuple[str, ...]
    reason: str
    released_states: tuple[str, ...] = ()
    released_motion: float | None = None

    @property
    def found(self) -> bool:
        """Commands found and verified (their released state holds)."""
        return self.status == "found"

    @property
    def in_equilibrium(self) -> bool:
        """The commands are a preload in equilibrium (``"found"``, or :data:`GIVES`: its
        released state slides or separates somewhere, but it balances)."""
        return self.status == "found" or self.status in GIVES

    def _at_zero(self, state: str) -> tuple[str, ...]:
        names = () if self.response is None else self.response.contact_names
        return tuple(n for n, s in zip(names, self.released_states) if s == state)

    @property
    def sliding_at_zero(self) -> tuple[str, ...]:
        """Contacts sliding (on their friction limit) in the released state, at zero load."""
        return self._at_zero("sliding")

    @property
    def separated_at_zero(self) -> tuple[str, ...]:
        """Contacts without normal force in the released state, at zero load."""
        return self._at_zero("separated")

    def to_dict(self) -> dict:
        """Plain JSON-able dictionary."""
        return {
            "status": self.status,
            "command": self.command,
            "normal_forces": None if self.normal_forces is None else self.normal_forces.tolist(),
            "method": self.method,
            "objective": self.objective,
            "resisted_at_zero_load": None if self.response is None else bool(self.response.resistible),
            "unloadable_contacts": list(self.unloadable_contacts),
            "unbalanced_actuators": list(self.unbalanced_actuators),
            "reason": self.reason,
            "released_states": list(self.released_states),
            "released_motion": None
            if self.released_motion is None or not np.isfinite(self.released_motion)
            else self.released_motion,
            "sliding_at_zero": list(self.sliding_at_zero),
            "separated_at_zero": list(self.separated_at_zero),
        }


def command_bounds(model: GraspModel, max_command: object) -> np.ndarray:
    """Per kept actuator upper bounds (na,) from a scalar or ``{name: bound}``."""
    if isinstance(max_command, dict):
        out = np.ones(model.na)
        for key, value in max_command.items():
            if key not in model.all_actuator_names:
                raise UnknownNameError("actuator", key, model.all_actuator_names)
            if key in model.actuator_names:
                out[model.actuator_names.index(key)] = force(f"max_command[{key!r}]", value, "N·m or N")
        return out
    return np.full(model.na, force("max_command", max_command, "N·m or N"))


def force_scale(model: GraspModel, fmax: np.ndarray) -> float:
    """The contact force [N] the strongest actuator at its bound presses through the shortest
    contact lever: ``max |R| fmax / min ||J_n||`` (levers of contacts that joints move)."""
    levers = np.linalg.norm(model.J[model.normal_rows], axis=1)
    levers = levers[levers > 0]
    torque = float(np.max(np.abs(model.R) @ fmax, initial=0.0))
    return torque / float(levers.min()) if len(levers) and torque > 0 else 1.0


def _constraints(
    model: GraspModel, fmax: np.ndarray, signed: bool = False
) -> tuple[list[Any], Any, Any, Any]:
    """The equilibrium constraints of the module docstring: (constraints, f, c, c_n). With
    ``signed`` the commands may be negative (the diagnosis: which actuator would have to pull)."""
    import cvxpy as cp

    m = model
    drive = np.array([kind != "locked" for kind in m.kinds], dtype=bool)
    bidir = np.array([n in m.bidirectional for n in m.actuator_names], dtype=bool)
    nbd = np.array([kind == "non-backdrivable" for kind in m.kinds], dtype=bool) & ~bidir
    beta = cp.Variable(m.nb, nonneg=True)
    f = cp.Variable(m.na)
    q = cp.Variable(m.nq)
    c, cn = m.D @ beta, m.E @ beta
    compression = m.J[m.normal_rows] @ q - m.G.T[m.normal_rows] @ cp.Variable(m.nw)
    tau = m.R @ f  # (nq,): driving actuators at their commands ...
    if (~drive).any():  # ... locked ones react freely (their command is not used)
        tau = m.R[:, drive] @ f[drive] + m.R[:, ~drive] @ cp.Variable(int((~drive).sum()))
    if m.ncp:
        tau = tau + m.C.T @ cp.Variable(m.ncp)
    cons = [
        m.G @ c == 0,
        m.J.T @ c == tau,
        cn == cp.multiply(m.k, compression),
        f >= (-fmax if signed else np.where(bidir, -fmax, 0.0)),
        f <= fmax,
        cn <= 1e6 * force_scale(m, fmax),  # bounded (the diagnosis maximises)
    ]
    if m.ncp:
        cons.append(m.C @ q == 0)
    if nbd.any() and not signed:
        cons.append(m.R[:, nbd].T @ q >= 0)  # every non-backdrivable actuator closed
    if (~drive).any():
        cons.append(f[~drive] == 0)
    return cons, f, c, cn


def _solved(problem: Any, what: str, required: bool = True) -> bool:  # noqa: ANN401 - a cvxpy.Problem
    """Solve; ``True`` for an optimal answer, ``False`` for a proven infeasible one. Clarabel
    first, HiGHS (exact simplex) for a linear program Clarabel cannot settle: a failure or an
    inaccurate status is never a verdict. Without any verdict, a ``required`` solve is a
    :class:`~pinograsp.errors.SolverError` saying what to try; an optional one (a refinement)
    is ``False``."""
    import cvxpy as cp

    linear = problem.objective.expr.is_affine()
    tried = []
    for solver in (cp.CLARABEL, cp.HIGHS) if linear else (cp.CLARABEL,):
        try:
            with quiet_stdout(solver == cp.HIGHS):  # its banner, at the first solve of a process
                problem.solve(solver=solver)
        except (cp.error.SolverError, ArithmeticError, ValueError) as exc:
            tried.append(f"{solver}: {' '.join(str(exc).split())[:200]}")
            continue
        status = problem.status
        if status in ("optimal", "infeasible", "unbounded"):
            return status == "optimal" and problem.value is not None
        tried.append(f"{solver}: status {status}")
    if not required:
        return False
    raise SolverError(
        f"equilibrium_preload: no solver settled the {what} ({'; '.join(tried)}); the model is "
        "probably badly scaled (contact stiffness or lever ratios beyond 1e6, a near-zero contact "
        "Jacobian): check the contacts, or give the commands yourself "
        "(docs/hands.md, 'Choosing a preload')",
        solver="clarabel",
        status="failed",
    )


def _design(model: GraspModel, unit: np.ndarray, objective: str, grip: float, normal_only: bool):
    """Commands (na,) and normal forces (nc,) of the design problem with command bounds
    ``unit`` (largest 1), or None when no preload presses every contact.

    ``"balanced"`` is homogeneous in (commands, forces, displacements): the verdict is the one
    solve maximising the smallest normal force ``t``; the least-norm commands at that force are
    a refinement (when it fails, the first solve's commands are kept), then everything is
    scaled up until a command meets its bound exactly. ``"least_norm"`` (``grip`` in the same
    normalised units) is one solve."""
    import cvxpy as cp

    m = model
    cons, f, c, cn = _constraints(m, unit)
    if normal_only:
        cons.append(c[np.setdiff1d(np.arange(m.nc * m.d), m.normal_rows)] == 0)
    if objective == "balanced":
        t: Any = cp.Variable()  # solved before its value is read
        if not _solved(cp.Problem(cp.Maximize(t), [*cons, cn >= t]), "design problem") or float(
            t.value
        ) <= LOADED * force_scale(m, unit):
            return None  # no force above the solver's noise: nothing presses every contact
        fv, cv = np.asarray(f.value, float), np.asarray(cn.value, float)
        target = float(t.value) * (1.0 - 1e-6)
        least = cp.Problem(cp.Minimize(cp.sum_squares(f)), [*cons, cn >= target])
        if _solved(least, "least-norm refinement", required=False):
            fv, cv = np.asarray(f.value, float), np.asarray(cn.value, float)
    else:
        if not _solved(cp.Problem(cp.Minimize(cp.sum_squares(f)), [*cons, cn >= grip]), "design problem"):
            return None
        fv, cv = np.asarray(f.value, float), np.asarray(cn.value, float)
    drive = np.array([kind != "locked" for kind in m.kinds], dtype=bool)
    bidir = np.array([n in m.bidirectional for n in m.actuator_names], dtype=bool)
    fv = np.where(drive, np.where(bidir, fv, np.maximum(fv, 0.0)), 0.0)
    if objective == "balanced":  # homogeneous: scale up until a command meets its bound exactly
        a = np.abs(fv)
        s = float(np.min(unit[a > 0] / a[a > 0])) if (a > 0).any() else 1.0
        fv, cv = np.clip(fv * s, -unit, unit), cv * s
    return np.round(fv / unit, 6) * unit, cv  # to the design accuracy (1e-6 of the bounds)


def _diagnose(model: GraspModel, unit: np.ndarray) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Why no preload exists: the driving actuators that would have to pull (a negative
    command) for every contact to press, or, if even pulling does not help, the contacts that
    no preload can press (bounds ``unit``, homogeneous: the diagnosis does not depend on their
    scale)."""
    import cvxpy as cp

    m = model
    cons, f, _, cn = _constraints(m, unit, signed=True)
    t: Any = cp.Variable()  # solved before its value is read
    if _solved(cp.Problem(cp.Maximize(t), [*cons, cn >= t]), "diagnosis", required=False) and float(
        t.value
    ) > LOADED * force_scale(m, unit):
        floor = float(t.value) * 0.5  # press every contact; pull as little as possible
        pull = cp.sum(cp.multiply(cp.neg(f), 1.0 / unit))
        if _solved(cp.Problem(cp.Minimize(pull), [*cons, cn >= floor]), "diagnosis", required=False):
            need = np.maximum(-np.asarray(f.value, float), 0.0) / unit
            return (), tuple(n for n, v in zip(m.actuator_names, need) if v > 1e-6)
    cons, f, _, cn = _constraints(m, unit)
    unloadable = []
    for i, name in enumerate(m.contact_names):  # vs the force its finger presses on a held object
        p = cp.Problem(cp.Maximize(cn[i]), cons)
        alone = cp.Problem(cp.Maximize(cn[i]), cons[1:])  # cons[0]: the object's equilibrium
        best = float(p.value) if _solved(p, "diagnosis", required=False) else 0.0
        ref = float(alone.value) if _solved(alone, "diagnosis", required=False) else 0.0
        if best <= LOADED * ref or ref <= 0:
            unloadable.append(name)
    return tuple(unloadable), ()


def _held_still(method: str) -> bool:
    """Whether ``method``'s own preload stage holds the object still (not the settling one)."""
    return get_method(method).preload_method != SETTLED_PRELOAD_METHOD


def _require_actuators(model: GraspModel) -> None:
    """A preload needs a driving actuator: 0 kept (or only locked) actuators is a
    :class:`~pinograsp.errors.ModelError` naming the cause."""
    if model.na == 0 or all(kind == "locked" for kind in model.kinds):
        dropped = [n for n in model.all_actuator_names if n not in model.actuator_names]
        raise ModelError(
            "no actuator reaches a contact: the model has "
            + (f"{model.na} kept actuator(s), all locked" if model.na else "no kept actuator")
            + (f" (pruned: {dropped})" if dropped else "")
            + "; no command can press the contacts. Add an actuator (or a coupling) that drives a "
            "joint moving a contact, or check the contact links (docs/hands.md)",
            argument="actuators",
        )


def _verify(
    model: GraspModel, command: dict[str, float], method: str, settings: Settings | None
) -> tuple[PassiveResponse | None, str | None]:
    """The method's response at ``w = 0`` under ``command``, and None when it is an
    equilibrium whose numbers pass the audit, else what went wrong (one phrase)."""
    try:
        resp = passive_response(model, command, np.zeros(6), method, settings=settings)
    except PinograspError as exc:  # a solver failure of the verification is no equilibrium
        return None, f"could not be solved ({type(exc).__name__}: {exc})"
    if not resp.resistible:
        return resp, f"ends {resp.status!r} with it"
    if resp.audit is None or not resp.audit.ok:
        why = "no audit" if resp.audit is None else resp.audit.summary()
        return resp, f"settles, but its solution fails the audit ({why})"
    return resp, None


def _gave(method: str, objective: str, design: tuple) -> PreloadChoice:
    """The verdict (:data:`GIVES`) of a design that balances but whose released state gives."""
    command, cn, resp, (status, gives), states, motion = design
    consequence = (
        "a small load makes the grasp give way (pinograsp.loading_path from this preload shows where)"
        if status == "slides"
        else "the preload holds on fewer contacts than designed"
    )
    return PreloadChoice(
        status, command, cn, method, objective, resp, (), (),
        f"the {method} preload stage is in equilibrium, but its released state already gives at "
        f"zero load: {gives}; {consequence}: try the other objective, other command bounds, or "
        "move the contacts",
        states, motion,
    )  # fmt: skip


def _verified_design(
    model: GraspModel,
    unit: np.ndarray,
    scale: float,
    objective: str,
    grip: float,
    method: str,
    settings: Settings | None,
) -> PreloadChoice | None:
    """The design with friction, then without, each verified by ``method`` at ``w = 0``: the
    first whose released state holds (``"found"``), else the first that balances but gives
    (:data:`GIVES`), else the last that the preload stage does not settle (``"unverified"``);
    None when no design presses every contact."""
    last, slid = None, None
    for normal_only in (False, True):  # friction allowed first; then pressing without friction
        design = _design(model, unit, objective, grip / scale, normal_only)
        if design is None:
            continue
        f, cn = design[0] * scale, design[1] * scale
        command = {n: 0.0 for n in model.all_actuator_names}
        command.update({n: float(v) for n, v in zip(model.actuator_names, f)})
        resp, failure = _verify(model, command, method, settings)
        if failure is None and resp is not None:
            states, motion = released(model, resp)
            gives = gives_way(model, states, motion, method)
            if gives is None:
                how = "without friction" if normal_only else "with friction"
                return PreloadChoice(
                    "found", command, cn, method, objective, resp, (), (),
                    f"every contact presses (smallest normal force {cn.min():.4g} N, {how}) and the "
                    f"{method} preload stage is in equilibrium, every contact sticking",
                    states, motion,
                )  # fmt: skip
            slid = slid or (command, cn, resp, gives, states, motion)  # the next design may hold
            continue
        last = (command, cn, resp, failure)
    if slid is not None:
        return _gave(method, objective, slid)
    if last is not None:
        command, cn, resp, failure = last
        return PreloadChoice(
            "unverified", command, cn, method, objective, resp, (), (),
            f"the design balances, but the {method} preload stage {failure}"
            + ("; method='prp' lets the object settle" if _held_still(method) else ""),
        )  # fmt: skip
    return None


def equilibrium_preload(
    model: GraspModel,
    method: str = DEFAULT_METHOD,
    *,
    objective: str = "balanced",
    max_command: float | dict[str, float] = 1.0,
    grip: float = 1.0,
    settings: Settings | None = None,
) -> PreloadChoice:
    """Actuator commands under which the grasp is in equilibrium at ``w = 0``.

    Args:
        model: The grasp.
        method: Whose preload stage verifies the commands: ``"quasistatic"`` (default: its
            preload path, the object held), ``"iterative"``, ``"prp"`` or ``"energetic"``.
        objective: ``"balanced"`` (default: the largest smallest normal force within the
            bounds) or ``"least_norm"`` (the smallest commands pressing every contact with at
            least ``grip``).
        max_command: Upper bound of every command, or ``{actuator: bound}`` (others 1)
            [N·m or N], in [1e-6, 1e12]. The design is homogeneous in the commands: a scalar
            bound scales the answer and never changes the verdict.
        grip: Smallest normal force at every contact for ``"least_norm"`` [N].
        settings: Solver settings of the verification.

    Returns:
        A :class:`PreloadChoice`; ``choice.command`` goes straight into every analysis.
        ``"found"`` only when the released state holds (every contact sticking at zero load:
        ``choice.released_states``); ``"slides"`` (``"separates"``) when the commands balance
        but a contact already slides (separates) at zero load (``choice.sliding_at_zero``,
        ``choice.separated_at_zero``), or the object moved on release.

    Raises:
        ModelError: No driving actuator ("no actuator reaches a contact").
        SolverError: No solver settles the design problem (with what to try).
        InvalidInputError: A bad method, objective, bound or grip.
    """
    if not isinstance(model, GraspModel):
        raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
    preload_method(method, "equilibrium_preload")
    choice("objective", objective, OBJECTIVES)
    fmax = command_bounds(model, max_command)
    grip = force("grip", grip)
    _require_actuators(model)
    scale = float(fmax.max())  # homogeneous: one solve with the largest bound 1, then scaled
    unit = fmax / scale
    verdict = _verified_design(model, unit, scale, objective, grip, method, settings)
    if verdict is not None:
        return verdict
    if objective == "least_norm":  # bounded by max_command?
        best = _design(model, unit, "balanced", 1.0, False)
        if best is not None:
            return PreloadChoice(
                "infeasible", None, None, method, objective, None, (), (),
                f"within max_command every contact presses with at most {best[1].min() * scale:.4g} N "
                f"< grip = {grip:g} N: raise max_command or lower grip",
            )  # fmt: skip
    contacts, actuators = _diagnose(model, unit)
    return PreloadChoice(
        "infeasible", None, None, method, objective, None, contacts, actuators,
        _why_none(contacts, actuators),
    )  # fmt: skip


def _why_none(contacts: tuple[str, ...], actuators: tuple[str, ...]) -> str:
    """The reason of an infeasible design, from :func:`_diagnose`."""
    parts = []
    if contacts:
        parts.append(f"no preload presses contact(s) {list(contacts)}")
    if actuators:
        parts.append(
            f"actuator(s) {list(actuators)} would have to pull (a negative command) for every "
            "contact to press: lock them (kind 'locked'), declare them bidirectional, or move "
            "the object or the contacts"
        )
    if contacts:
        parts[-1] += " (no other contact or finger can oppose them)"
    if not parts:
        parts.append("each contact can be pressed, but not all at once")
    return "; ".join(parts)
