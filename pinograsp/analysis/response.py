"""Passive response of a preloaded grasp to an external wrench (seed Alg. 1, 2 and 3).

* ``method="prp"`` — Alg. 1: one mixed-integer QP, minimise the spring energy ``|c_n|^2``
  subject to equilibrium, friction, springs and actuation. Admits the *wedging artefact*.
* ``method="iterative"`` — Alg. 2 inside Alg. 3: the object may only move along the current
  net wrench (step in ``[0, gamma]``), each step minimises the net wrench, repeat until it
  falls below ``eps`` (resisted) or stops improving (not resisted).

Two variants (docs/design.md):

* ``"single-step"`` (the paper): preload and load are solved together from the
  touching-without-force configuration;
* ``"preload-first"`` (the authors' released code): first the preload alone (``w = 0``), then
  ``w`` on top, with the preload normal forces as spring pre-compression and displacements
  counted from the preloaded state — so a finger that closed during preloading may hold still
  afterwards. Default for ``"iterative"``; the paper's single-step is the default for ``"prp"``.
  In the iterative method the object cannot move while the preload is applied (the first
  step has no movement direction and ``w = 0`` leaves no net wrench to follow).
* ``"settled-preload"``: as ``"preload-first"``, but the preload stage is Alg. 1 at ``w = 0``
  for both methods, so the object is free to settle into the least-spring-energy equilibrium
  of the preload before the load is applied (a hand closing on a free object). It differs from
  ``"preload-first"`` only when the held-still preload leaves some contacts unloaded that a
  settling object would load (seed case 3 with the distal tendon alone, see docs/results.md).
"""

from __future__ import annotations

import time
import warnings
import weakref
from dataclasses import dataclass, replace

import numpy as np

from ..core.audit import audit_message, energy_check, friction_use
from ..core.model import GraspModel
from ..core.results import Audit, PassiveResponse
from ..core.settings import METHODS, VARIANTS, Settings, make_settings
from ..core.validate import choice
from ..errors import AuditWarning, ConditioningWarning, InvalidInputError
from ..solvers import OPTIMAL, Formulation, ScaledData, resolve_solver
from ..solvers.base import INFEASIBLE, Mode, RawSolution, SolveStatus
from ..solvers.problem import ProblemKind
from ..solvers.solve import Backend, BackendOptions, single_threaded
from ..solvers.solve import solve as solve_problem

#: Subspace jump of the iterative scheme: tried after this many real steps in one mode ...
JUMP_AFTER = 3
#: ... when the last step shrank the net wrench by less than this factor (slow convergence).
JUMP_RATIO = 0.5
#: Contact stiffness ratio above which the branch-and-bound warns (docs/solvers.md).
MAX_STIFFNESS_RATIO = 1e5


def backend_options(settings: Settings, gamma: float) -> BackendOptions:
    """What the solver layer needs of ``settings`` (``gamma`` already scaled)."""
    opts = (("complementarity", settings.complementarity), ("verify_infeasible", settings.verify_infeasible))
    return BackendOptions(
        backend=Backend(settings.backend),
        gamma=gamma,
        max_nodes=int(settings.max_nodes),
        solver=settings.solver,
        time_limit=settings.time_limit,
        bigm=settings.bigm,
        bigm_retries=settings.bigm_retries,
        miqp_options=opts,
    )


@dataclass(frozen=True)
class LoadFactor:
    """Answer of :meth:`PassiveSolver.max_load_factor`.

    Attributes:
        status: :class:`~pinograsp.solvers.base.SolveStatus`.
        magnitude: Largest resistible magnitude [N or N·m] (``inf``: the search limit).
        solve_time: Wall time [s].
    """

    status: SolveStatus
    magnitude: float
    solve_time: float


@dataclass(frozen=True, eq=False)
class _Stage:
    """Internal: one solved stage in scaled coordinates."""

    raw: RawSolution | None
    data: ScaledData
    xh: np.ndarray  # scaled object displacement of the stage's solution (increment)
    status: str
    converged: bool
    iterations: int
    history: tuple[float, ...]
    solve_time: float
    n_solves: int


_FORMS: weakref.WeakKeyDictionary[GraspModel, Formulation] = weakref.WeakKeyDictionary()


def formulation_of(model: GraspModel) -> Formulation:
    """The scaled formulation of ``model`` (a pure function of the immutable model, kept per
    model so that it is built once)."""
    if model not in _FORMS:
        _FORMS[model] = Formulation(model)
    return _FORMS[model]


class PassiveSolver:
    """Passive-response solver of one model and settings: a session the caller owns.

    It carries no state that changes answers: each solve is a function of its inputs. What it
    keeps between calls — the preload stage per command (a pure function of the command) and
    the reference backend's cvxpy objects — only saves time. Warm starts live inside one query
    (the previous step's mode within one iteration trajectory). :func:`solver_for` builds a
    new one for every public query; create one yourself (``pg.Session(model, settings)``) to
    share the preload stages across queries.
    """

    def __init__(self, model: GraspModel, settings: Settings | None = None) -> None:
        if not isinstance(model, GraspModel):
            raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
        self.model = model
        self.settings = (settings or Settings()).validated()
        if self.settings.backend == Backend.MIQP:
            resolve_solver(self.settings.solver)  # installed? (the name was checked by Settings)
        self.form = formulation_of(model)
        #: Step bound in scaled units. ``gamma`` is relative to the stiffest contact; with a
        #: stiffness spread a soft contact would otherwise gain only ``k_min / k_max`` of the
        #: net wrench per step and the 1 % rule would stop the iteration early ("not
        #: resisted"), so the bound is widened by ``k_max / k_min`` (1 for uniform stiffness).
        self.gamma_eff = float(self.settings.gamma * self.form.kx / model.k.min())
        self.options = backend_options(self.settings, self.gamma_eff)
        ratio = float(model.k.max() / model.k.min())
        if ratio > MAX_STIFFNESS_RATIO and self.options.backend is Backend.BNB:
            warnings.warn(
                f"contact stiffness ratio {ratio:.3g} exceeds {MAX_STIFFNESS_RATIO:g}: the default "
                "branch-and-bound may lose solutions of such models; use backend='miqp'",
                ConditioningWarning,
                stacklevel=3,
            )
        self._preload: dict[tuple, tuple[_Stage, str]] = {}
        self._backend_cache: dict = {}
        self._mirrors: dict[tuple[bool, ...], PassiveSolver] = {}

    def _mirror(self, fc: np.ndarray) -> tuple[PassiveSolver, np.ndarray] | None:
        """For negative commands of bidirectional actuators: the solver of the model with those
        actuators' transmissions negated (commanded ``|f_c|``) and the signs (na,); else None."""
        neg = fc < 0
        if not neg.any():
            return None
        signs = np.where(neg, -1.0, 1.0)
        key = tuple(bool(v) for v in neg)
        if key not in self._mirrors:
            with warnings.catch_warnings():  # the same contacts: warned by this session already
                warnings.simplefilter("ignore", ConditioningWarning)
                self._mirrors[key] = PassiveSolver(self.model.with_actuator_signs(signs), self.settings)
        return self._mirrors[key], signs

    def solve(self, kind: str | ProblemKind, data: ScaledData, guess: Mode | None = None) -> RawSolution:
        """Solve one scaled problem with the settings' backend; ``guess`` is an incumbent mode
        (speed only)."""
        return solve_problem(self.form, ProblemKind(kind), data, self.options, guess, self._backend_cache)

    # --------------------------------------------------------------- stages
    def _prp_stage(self, w: np.ndarray, fc: np.ndarray, p: np.ndarray, F: float | None = None) -> _Stage:
        data = self.form.scale_data(w, fc, p, F=F)
        raw = self.solve(ProblemKind.PRP, data)
        ok = raw.status == OPTIMAL
        xh = raw.z[self.form.layout("prp")["obj"]] if ok else np.zeros(self.form.nx)
        status = "resisted" if ok else ("not_resisted" if raw.status == INFEASIBLE else raw.status.value)
        return _Stage(raw, data, xh, status, ok, 1, (), raw.solve_time, 1)

    def _iterative_stage(
        self, w: np.ndarray, fc: np.ndarray, p: np.ndarray, F: float | None = None, start: Mode | None = None
    ) -> _Stage:
        """Alg. 3 from the (pre)loaded state; ``start`` is the mode the grasp is in before the
        first step (the preload's), the first step's incumbent."""
        s = self.settings
        f = self.form
        lay = f.layout("move")
        base = f.scale_data(w, fc, p, F=F)
        tol = s.eps + s.eps_rel * base.F
        xh = np.zeros(f.nx)
        direction = np.zeros(f.nx)
        history: list[float] = []
        total, n = 0.0, 0
        status, converged, raw_best = "not_converged", False, None
        prev, guess = None, start
        streak: list[np.ndarray] = []  # net wrenches of the current mode's real steps
        for _ in range(int(s.max_iterations)):
            data = ScaledData(base.F, base.w, base.fc, base.p, xh, direction)
            raw = self.solve(ProblemKind.MOVE, data, guess)
            total += raw.solve_time
            n += 1
            if raw.status != OPTIMAL:
                status = "not_resisted" if raw.status == INFEASIBLE else raw.status.value
                break
            if raw.mode != guess:
                streak = []
            guess = raw.mode
            r = base.w + f.Gb @ raw.z[lay["beta"]]
            norm = float(np.linalg.norm(r) * base.F)
            history.append(norm)
            xh_next = xh + raw.z[lay["obj"]][0] * direction
            raw_best = (raw, xh_next, data)
            if norm <= tol:
                status, converged = "resisted", True
                break
            if prev is not None and prev - norm < s.improvement * prev:
                status = "not_resisted"
                break
            streak.append(r)
            if s.accelerate and prev is not None and norm > JUMP_RATIO * prev and len(streak) >= JUMP_AFTER:
                jump = self._jump(base, xh_next, streak, raw.mode)
                total += jump[2]
                n += 1
                if jump[0] is not None and np.linalg.norm(jump[1]) * base.F < (1.0 - s.improvement) * norm:
                    xh_next, r = jump[0], jump[1]
                    streak = []
            prev = norm
            xh, direction = xh_next, r
        if raw_best is None:
            return _Stage(None, base, xh, status, False, n, tuple(history), total, n)
        raw, xh_sol, data = raw_best
        return _Stage(raw, data, xh_sol, status, converged, len(history), tuple(history), total, n)

    def _jump(
        self, base: ScaledData, xh: np.ndarray, streak: list[np.ndarray], mode: Mode
    ) -> tuple[np.ndarray | None, np.ndarray, float]:
        """Subspace jump of the iterative scheme (``Settings.accelerate``, docs/solvers.md).

        In a mode that has held for several slow steps, the object moves to the best point of
        ``x + D a`` (``a >= 0``, ``D`` the mode's recent net wrenches, unit length): where the
        step-by-step scheme would creep along a narrow valley. Returns the new displacement,
        the net wrench there (None, ... when the mode admits no such point) and the time [s].
        """
        from ..solvers.bnb import BranchAndBound
        from ..solvers.problem import INF, build_problem

        f = self.form
        recent = streak[-min(len(streak), f.nx) :]
        D = np.column_stack([v / np.linalg.norm(v) for v in recent])
        data = ScaledData(base.F, base.w, base.fc, base.p, xh, D)
        t0 = time.perf_counter()
        problem = build_problem(f, ProblemKind.MOVE, data, INF)
        sol = BranchAndBound(problem, self.options.max_nodes).solve_mode(mode)
        dt = time.perf_counter() - t0
        if sol.status != OPTIMAL:
            return None, np.zeros(f.nx), dt
        a = problem.step_lengths(sol.z)
        r = base.w + f.Gb @ sol.z[f.layout("move")["beta"]]
        return xh + D @ a, r, dt

    @staticmethod
    def _preload_key(command: np.ndarray, method: str) -> tuple:
        return (method, tuple(np.asarray(command, float).tolist()))

    def preload_stage(self, command: np.ndarray, method: str) -> _Stage:
        """The preload alone (``w = 0``), kept per command (a pure function of it)."""
        key = self._preload_key(command, method)
        if key not in self._preload:
            zero = np.zeros(self.model.nw)
            nop = np.zeros(self.model.nc)
            st = (
                self._prp_stage(zero, command, nop)
                if method == "prp"
                else self._iterative_stage(zero, command, nop)
            )
            self._preload[key] = (st, method)
        return self._preload[key][0]

    # ------------------------------------------------------- direct search
    def max_load_factor(self, command: object, direction: np.ndarray, upper: float) -> LoadFactor:
        """Alg. 1's largest resistible magnitude along a unit ``direction`` in one
        complementarity solve (:attr:`ProblemKind.LOAD`, by the settings' backend).

        Returns:
            A :class:`LoadFactor`: status ``"optimal"`` (magnitude in [N] or [N·m] along the
            direction; ``inf`` when ``upper`` is reached), ``"infeasible"`` (not even
            ``w = 0``), ``"node_limit"``, ``"timeout"`` or ``"failed"``.
        """
        m, f, s = self.model, self.form, self.settings
        fc = m.command_vector(command)
        mirror = self._mirror(fc)
        if mirror is not None:
            return mirror[0].max_load_factor(np.abs(fc), direction, upper)
        p = np.zeros(m.nc)
        pre_time = 0.0
        if s.variant_for("prp") != "single-step":
            pre = self.preload_stage(fc, "prp")
            pre_time = pre.solve_time
            if not pre.converged:
                return LoadFactor(INFEASIBLE, float("nan"), pre_time)
            p = f.E @ pre.raw.z[f.layout("prp")["beta"]] * pre.data.F
        d = m.reduce_wrench(np.asarray(direction, float)) * f.wscale
        data = f.scale_data(np.zeros(m.nw), fc, p)
        data = ScaledData(data.F, data.w, data.fc, data.p, data.x0, d)
        tmax = float(upper) / data.F
        raw = self._load_factor(data, tmax)
        dt = raw.solve_time + pre_time
        if raw.status != OPTIMAL:
            return LoadFactor(raw.status, float("nan"), dt)
        t = float(raw.z[-1])
        if t >= tmax * (1.0 - 1e-9):
            return LoadFactor(OPTIMAL, float("inf"), dt)
        return LoadFactor(OPTIMAL, t * data.F, dt)

    def _load_factor(self, data: ScaledData, tmax: float) -> RawSolution:
        from ..solvers.bnb import BranchAndBound
        from ..solvers.problem import build_problem

        if self.options.backend is Backend.BNB:
            problem = build_problem(self.form, ProblemKind.LOAD, data, t_max=tmax)
            return BranchAndBound(problem, self.options.max_nodes).solve()
        from ..solvers.miqp import CvxpyMIQP

        s = self.settings
        miqp = CvxpyMIQP(self.form, "load", solver=s.solver, time_limit=s.time_limit)
        return miqp.solve(data, s.bigm * max(1.0, 10.0 * tmax), t_max=tmax)

    # ------------------------------------------------------------- response
    @single_threaded
    def response(self, command: object, wrench: object, method: str = "iterative") -> PassiveResponse:
        """Passive response to ``wrench`` under ``command`` (see :func:`passive_response`)."""
        choice("method", method, METHODS)
        m = self.model
        fc = m.command_vector(command)
        mirror = self._mirror(fc)
        if mirror is not None:  # bidirectional actuators driving the other way
            solver, sg = mirror
            r = solver.response(np.abs(fc), wrench, method)
            return replace(
                r,
                command=fc,
                actuator_forces=r.actuator_forces * sg,
                actuator_displacements=r.actuator_displacements * sg,
            )
        w6 = m.wrench_vector(wrench)
        w = m.reduce_wrench(w6)
        variant = self.settings.variant_for(method)
        stage_fn = self._prp_stage if method == "prp" else self._iterative_stage
        pre, fresh = None, True
        p = np.zeros(m.nc)
        if variant != "single-step":
            pre_method = "prp" if variant == "settled-preload" else method
            fresh = self._preload_key(fc, pre_method) not in self._preload
            pre = self.preload_stage(fc, pre_method)
            if not pre.converged:
                failed = pre if pre_method == method else replace(pre, raw=None)
                note = "preload not in equilibrium"
                return self._build(method, variant, w6, fc, failed, pre=None, note=note)
            p = self.form.E @ pre.raw.z[self._layout_of(pre_method)["beta"]] * pre.data.F
            st = stage_fn(w, fc, p) if method == "prp" else stage_fn(w, fc, p, start=pre.raw.mode)
            return self._build(method, variant, w6, fc, st, pre=pre, pre_fresh=fresh, pre_kind=pre_method)
        st = stage_fn(w, fc, p)
        return self._build(method, variant, w6, fc, st, pre=pre, pre_fresh=fresh)

    def _layout_of(self, method: str) -> dict:
        return self.form.layout("prp" if method == "prp" else "move")

    def _build(
        self,
        method: str,
        variant: str,
        w6: np.ndarray,
        fc: np.ndarray,
        st: _Stage,
        pre: _Stage | None,
        note: str = "",
        pre_fresh: bool = True,
        pre_kind: str | None = None,
    ) -> PassiveResponse:
        m, f = self.model, self.form
        kind = "prp" if method == "prp" else "move"
        lay = f.layout(kind)
        nc, nq, na = m.nc, m.nq, m.na
        raw = st.raw
        status = st.status
        if note and status == "resisted":
            status = "not_resisted"
        # a cached preload stage costs nothing: count it only where it was solved
        counted = pre if (pre is not None and pre_fresh) else None
        n_solves = st.n_solves + (counted.n_solves if counted is not None else 0)
        solve_time = st.solve_time + (counted.solve_time if counted is not None else 0.0)
        common = dict(
            method=method,
            variant=variant,
            wrench=w6,
            command=fc,
            iterations=st.iterations,
            residual_history=st.history,
            solve_time=solve_time,
            n_solves=n_solves,
            contact_names=m.contact_names,
            joint_names=m.joint_names,
            actuator_names=m.actuator_names,
            contact_mu=np.array(m.mu, dtype=float),
            actuator_kinds=tuple(m.kinds),
        )
        if raw is None or raw.z is None:  # no solution: every quantity is NaN

            def nan(*shape: int) -> np.ndarray:
                return np.full(shape, np.nan)

            return PassiveResponse(
                resistible=False,
                status=status,
                contact_forces=nan(nc, 3),
                contact_forces_world=nan(nc, 3),
                joint_torques=nan(nq),
                actuator_forces=nan(na),
                coupling_forces=nan(m.ncp),
                object_displacement=nan(6),
                joint_displacements=nan(nq),
                actuator_displacements=nan(na),
                contact_modes=(),
                actuator_modes=(),
                net_wrench=nan(6),
                audit=None,
                friction_use=nan(nc),
                converged=False,
                solver=self.settings.backend,
                **common,
            )
        z, F = raw.z, st.data.F
        beta = z[lay["beta"]] * F
        c = m.D @ beta  # (nc*d,)
        cf = np.zeros((nc, 3))
        cf[:, : m.d] = c.reshape(nc, m.d)
        tau = m.J.T @ c
        fa = z[lay["fh"]] * F / f.rho if na else np.zeros(0)
        lam = z[lay["lam"]] * F / f.cl_norm if m.ncp else np.zeros(0)
        qh = z[lay["qh"]]
        q = qh * F / f.qscale if nq else np.zeros(0)
        x = f.unscale_x(st.xh, F)
        x_load = m.expand_twist(x)
        if pre is not None and pre.raw is not None and pre.raw.z is not None:
            play = self._layout_of(pre_kind or method)
            q = q + pre.raw.z[play["qh"]] * pre.data.F / f.qscale
            x = x + f.unscale_x(pre.xh, pre.data.F)
        u = m.R.T @ q
        net = m.G @ c + m.reduce_wrench(w6)
        # audit, in force units
        gap = f.spring_gap(z[lay["beta"]], st.xh, qh, st.data.p) * F
        cn = f.E @ beta
        comp = np.minimum(np.abs(cn), np.abs(gap)).max(initial=0.0)
        if na:
            uh = f.Ru @ qh * F
            over = (z[lay["fh"]] - st.data.fc) * F
            nbd = f.nbd
            comp = max(comp, np.minimum(np.abs(uh[nbd]), np.abs(over[nbd])).max(initial=0.0))
        hand = (
            (m.J.T @ c - m.R @ fa - m.C.T @ lam) / np.where(f.lever > 0, f.lever, 1.0) if nq else np.zeros(0)
        )
        scale = max(F, 1e-300)
        modes_c = tuple("touching" if t else "separated" for t in raw.mode.touching)
        tol = self.settings.tolerance * scale
        energy = None
        if status == "resisted":  # an equilibrium: its energy balance must hold
            energy = energy_check(
                cf[:, 0],
                m.k,
                w6,
                x_load,
                fc,
                u,
                m.expand_twist(x),
                q,
                m.length_scale,
                f.lever,
                m.contact_names,
                # rounding relative to the larger of this stage's and the preload stage's scale
                self.settings.tolerance * max(F, pre.data.F if pre is not None else 0.0),
            )
        audit = Audit(
            equilibrium=float(np.linalg.norm(net * f.wscale)),
            hand=float(np.abs(hand).max(initial=0.0)),
            complementarity=float(comp),
            friction=float(max(0.0, -beta.min(initial=0.0))),
            bigm_ratio=raw.bigm_ratio,
            bigm_retries=raw.bigm_retries,
            polished=raw.polished,
            tolerance=tol,
            energy=energy,
        )
        if energy is not None and not (energy.energy_ok and energy.displacement_ok):
            warnings.warn(audit_message(method, energy), AuditWarning, stacklevel=4)
        modes_a = tuple(
            ("moving" if mv else "holding") if k == "non-backdrivable" else k
            for k, mv in zip(m.kinds, raw.mode.moving)
        )
        resistible = status == "resisted"
        if method == "prp" and resistible and audit.equilibrium > 1e-6 * scale:
            status, resistible = "failed", False
        return PassiveResponse(
            resistible=resistible,
            status=status,
            contact_forces=cf,
            contact_forces_world=m.world_forces(c),
            joint_torques=tau,
            actuator_forces=fa,
            coupling_forces=lam,
            object_displacement=m.expand_twist(x),
            joint_displacements=q,
            actuator_displacements=u,
            contact_modes=modes_c,
            actuator_modes=modes_a,
            net_wrench=m.expand_wrench(net),
            audit=audit,
            friction_use=friction_use(cf, m.mu, raw.mode.touching, tol),
            converged=st.converged,
            solver=raw.backend,
            **common,
        )


def solver_for(model: GraspModel, settings: Settings | None = None, **overrides: object) -> PassiveSolver:
    """A new :class:`PassiveSolver` of ``model`` with these settings (no shared state)."""
    if not isinstance(model, GraspModel):
        raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
    return PassiveSolver(model, make_settings(settings, **overrides))


#: The caller-owned session of one model and settings (the public name of
#: :class:`PassiveSolver`).
Session = PassiveSolver


def passive_response(
    model: GraspModel,
    command: object,
    wrench: object,
    method: str = "iterative",
    *,
    settings: Settings | None = None,
    **overrides: object,
) -> PassiveResponse:
    """Passive response of the grasp ``model`` preloaded with ``command`` to ``wrench``.

    Args:
        model: The grasp.
        command: Actuator commands ``f_c`` (scalar, sequence, or ``{actuator_name: value}``)
            [N·m for direct drive, N for tendons].
        wrench: External wrench on the object ``(fx, fy, fz, mx, my, mz)`` [N, N·m] about the
            object reference point (planar models also take ``(fx, fy, mz)``).
        method: ``"iterative"`` (default: Alg. 2 + 3, the physically validated scheme, as in
            every analysis, the CLI and the scenes) or ``"prp"`` (Alg. 1, by explicit choice:
            it admits the wedging artefact).
        settings: Base :class:`Settings`; keyword ``overrides`` replace single fields
            (e.g. ``solver="gurobi"``, ``gamma=2.0``, ``variant="single-step"``).

    Returns:
        A :class:`~pinograsp.core.results.PassiveResponse`; ``resistible`` says whether the wrench is
        resisted, ``status`` why not (``"timeout"``/``"failed"`` are never reported as resisted).
    """
    choice("method", method, METHODS)
    return solver_for(model, settings, **overrides).response(command, wrench, method)


__all__ = [
    "METHODS",
    "VARIANTS",
    "LoadFactor",
    "PassiveSolver",
    "Session",
    "Settings",
    "make_settings",
    "passive_response",
    "solver_for",
]
