"""Passive response of a preloaded grasp to an external wrench (seed Alg. 1, 2 and 3).

* ``method="prp"`` — Alg. 1: one mixed-integer QP, minimise the spring energy ``|c_n|^2``
  subject to equilibrium, friction, springs and actuation. Admits the *wedging artefact*.
* ``method="iterative"`` — Alg. 2 inside Alg. 3: the object may only move along the current
  net wrench (step in ``[0, gamma]``), each step minimises the net wrench, repeat until it
  falls below ``eps`` (resisted) or stops improving (not resisted).

Two variants (DESIGN §4.2):

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

import weakref
from dataclasses import dataclass, replace

import numpy as np

from .errors import InvalidInputError
from .model import GraspModel
from .results import Audit, PassiveResponse
from .solvers import OPTIMAL, ExactSolver, FixedModeQP, Formulation, ScaledData, resolve_solver
from .solvers.base import INFEASIBLE, Mode, RawSolution
from .solvers.fast import FastStats, ModeGuessSolver

METHODS = ("prp", "iterative")
VARIANTS = ("single-step", "preload-first", "settled-preload")
#: Relative gap (on the squared net wrench) at which a certificate MIQP may stop: the optimum's
#: net wrench is then at least ``1 / sqrt(1 + CERTIFY_GAP)`` (0.99995) of the point found.
CERTIFY_GAP = 1e-4


@dataclass(frozen=True)
class Settings:
    """Solver and iteration settings (all analyses accept them as keyword overrides).

    Attributes:
        solver: MIQP backend: ``"scip"`` (default, open source) or any installed cvxpy MIQP
            solver (``"gurobi"`` with ``pinograsp[gurobi]``).
        time_limit: Per-MIQP time limit [s]; hitting it gives status ``"timeout"``.
        bigm: Initial big-M constant in scaled force units (multiples of the data scale).
        bigm_retries: Enlargements (x100 each) when a solution reaches 10 % of big-M.
        polish: Polish every MIQP solution with the exact fixed-mode QP (ProxSuite).
        gamma: Step bound of Alg. 2, dimensionless: one step changes the spring force of the
            stiffest contact by at most ``gamma`` times the current net wrench.
        eps: Equilibrium tolerance of the iterative scheme [N] on the net wrench norm
            (torques divided by the model's length scale). Paper: 1e-3 N.
        eps_rel: Relative part of the equilibrium tolerance: the iteration is resisted when
            ``|r| <= eps + eps_rel * F`` with ``F`` the solve's force scale (largest of the
            load, the commands as contact forces and the pre-compression) [N]. The paper's
            absolute 1e-3 N alone asks 2e-6 relative accuracy of a 500 N load, where the
            scheme's linear convergence stalls under the 1 % improvement rule (passively
            resisted directions then come out "not resisted" at a random magnitude), and it
            breaks the homogeneity of the model (scaling preload and load by ``s`` scales every
            force by ``s``). Default 1e-5; ``0`` restores the paper's rule.
        improvement: The iteration stops (not resisted) when the net wrench norm improves by
            less than this fraction in one step (authors' code: 1 %).
        max_iterations: Iteration cap (authors' code: 100); hitting it gives
            ``"not_converged"``.
        variant: ``"single-step"``, ``"preload-first"`` or ``"settled-preload"`` (see the
            module docstring); ``None`` picks the method's default.
        tolerance: Audit tolerance on hand/complementarity/friction residuals, relative to the
            data scale.
        fast: Use the mode-guess fast path (:mod:`pinograsp.solvers.fast`): solve the convex
            QP of the previous solution's complementarity mode with ProxSuite, accept it when
            it is feasible and strongly stationary, else fall back to the exact MIQP.
            ``False`` solves every problem with the MIQP (the reference path).
        certify: With ``fast``, certify every "stopped improving" verdict of the iterative
            scheme reached on a guessed mode with one exact MIQP of that step (a locally optimal
            mode can stall where another mode still improves). ``False`` trusts the guess:
            faster, and measured in ``docs/error_vs_runtime.md``.
        verify: With ``fast``, confirm the final bracket ``[magnitude, magnitude + resolution]``
            of every iterative max-wrench bisection (and every "unbounded" verdict) with the
            exact MIQP path, and continue the bisection with the exact path where it disagrees:
            the magnitude is then the exact path's; the fast path only saved the steps the
            bracket confirms. ``False`` returns the fast path's bracket (error in
            ``docs/error_vs_runtime.md``).
        complementarity: ``"bigm"`` (default) or ``"indicator"`` (SCIP indicator constraints,
            no big-M constant; SCIP only).
        verify_infeasible: Re-solve an infeasible big-M MIQP once with ``M x 100`` before
            trusting the infeasibility (an ``M`` that cuts off every solution is otherwise
            indistinguishable from a load that is not resisted).
    """

    solver: str = "scip"
    time_limit: float = 60.0
    bigm: float = 1e3
    bigm_retries: int = 2
    polish: bool = True
    gamma: float = 1.0
    eps: float = 1e-3
    eps_rel: float = 1e-5
    improvement: float = 1e-2
    max_iterations: int = 100
    variant: str | None = None
    tolerance: float = 1e-6
    fast: bool = True
    certify: bool = True
    verify: bool = False
    complementarity: str = "bigm"
    verify_infeasible: bool = True

    def validated(self) -> Settings:
        """Check every field; raise :class:`InvalidInputError` naming the bad one."""
        resolve_solver(self.solver)
        for name in ("time_limit", "bigm", "gamma", "eps", "tolerance"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and np.isfinite(v) and v > 0):
                raise InvalidInputError(name, f"must be a finite number > 0, got {v!r}")
        if self.complementarity not in ("bigm", "indicator"):
            raise InvalidInputError(
                "complementarity", f"must be 'bigm' or 'indicator', got {self.complementarity!r}"
            )
        if self.complementarity == "indicator" and resolve_solver(self.solver) != "SCIP":
            raise InvalidInputError("complementarity", "indicator constraints need solver='scip'")
        if not (isinstance(self.eps_rel, (int, float)) and 0 <= self.eps_rel < 1):
            raise InvalidInputError("eps_rel", f"must be a number in [0, 1), got {self.eps_rel!r}")
        if not 0 <= self.improvement < 1:
            raise InvalidInputError("improvement", f"must be in [0, 1), got {self.improvement!r}")
        if int(self.max_iterations) < 1:
            raise InvalidInputError("max_iterations", f"must be >= 1, got {self.max_iterations!r}")
        if self.variant is not None and self.variant not in VARIANTS:
            raise InvalidInputError("variant", f"must be one of {VARIANTS}, got {self.variant!r}")
        return self

    def variant_for(self, method: str) -> str:
        """The variant used for ``method``."""
        if self.variant is not None:
            return self.variant
        return "single-step" if method == "prp" else "preload-first"


def make_settings(settings: Settings | None = None, **overrides: object) -> Settings:
    """A validated :class:`Settings` from a base and keyword overrides."""
    base = settings or Settings()
    if overrides:
        unknown = set(overrides) - set(Settings.__dataclass_fields__)
        if unknown:
            from .errors import UnknownNameError

            raise UnknownNameError("setting", sorted(unknown)[0], list(Settings.__dataclass_fields__))
        base = replace(base, **overrides)  # type: ignore[arg-type]
    return base.validated()


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
    n_miqp: int = 0


class PassiveSolver:
    """Passive-response solver of one model: builds each optimisation problem once and
    re-solves it with new data (bisections and profiles call it thousands of times).

    Use :func:`solver_for` to get the cached instance of a model and settings.
    """

    def __init__(self, model: GraspModel, settings: Settings | None = None) -> None:
        if not isinstance(model, GraspModel):
            raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
        self.model = model
        self.settings = (settings or Settings()).validated()
        self.form = Formulation(model)
        #: Step bound in scaled units. ``gamma`` is relative to the stiffest contact; with a
        #: stiffness spread a soft contact would otherwise gain only ``k_min / k_max`` of the
        #: net wrench per step and the 1 % rule would stop the iteration early ("not
        #: resisted"), so the bound is widened by ``k_max / k_min`` (1 for uniform stiffness).
        self.gamma_eff = float(self.settings.gamma * self.form.kx / model.k.min())
        self._exact: dict[str, ExactSolver] = {}
        self._fast: dict[str, ModeGuessSolver] = {}
        self._guess: dict[str, Mode] = {}
        self._preload: dict[tuple, tuple[_Stage, str]] = {}

    def _new_exact(self, kind: str, **options: object) -> ExactSolver:
        s = self.settings
        opts = {"complementarity": s.complementarity, "verify_infeasible": s.verify_infeasible, **options}
        return ExactSolver(
            self.form,
            kind,
            solver=s.solver,
            gamma=self.gamma_eff,
            bigm=s.bigm,
            bigm_retries=s.bigm_retries,
            time_limit=s.time_limit,
            polish=s.polish,
            options=opts,
        )

    def exact(self, kind: str) -> ExactSolver:
        """The exact (MIQP + polish) solver of problem ``kind`` (``"prp"``/``"move"``), built once."""
        if kind not in self._exact:
            self._exact[kind] = self._new_exact(kind)
        return self._exact[kind]

    def certifier(self) -> ExactSolver:
        """The exact movement-step solver used to certify stalls, built once: the same MIQP as
        :meth:`exact` ``("move")`` but allowed to stop at a relative gap of
        :data:`CERTIFY_GAP` (a stall only needs to know whether some mode improves the net
        wrench by the ``improvement`` fraction, not the optimum to solver precision)."""
        if "certify" not in self._exact:
            self._exact["certify"] = self._new_exact("move", rel_gap=CERTIFY_GAP)
        return self._exact["certify"]

    def fast(self, kind: str) -> ModeGuessSolver:
        """The mode-guess fast path of problem ``kind``, built once."""
        if kind not in self._fast:
            ex = self.exact(kind)
            qp = ex.qp if ex.qp is not None else FixedModeQP(self.form, kind, gamma=self.gamma_eff)
            self._fast[kind] = ModeGuessSolver(ex, qp)
        return self._fast[kind]

    @property
    def stats(self) -> dict[str, FastStats]:
        """Fast-path counters per problem kind (``"prp"``, ``"move"``)."""
        return {k: v.stats for k, v in self._fast.items()}

    def solve(self, kind: str, data: ScaledData, guess: Mode | None = None) -> RawSolution:
        """Solve one scaled problem: fast path with ``guess`` (default: the mode of this
        solver's last solution of ``kind``) when ``settings.fast``, else exactly."""
        if not self.settings.fast:
            return self.exact(kind).solve(data)
        raw = self.fast(kind).solve(data, guess if guess is not None else self._guess.get(kind))
        if raw.status == OPTIMAL and raw.mode is not None:
            self._guess[kind] = raw.mode
        return raw

    def solve_exact(self, kind: str, data: ScaledData, solver: ExactSolver | None = None) -> RawSolution:
        """Solve one scaled problem with the exact MIQP path (updates the mode guess).

        ``solver`` replaces :meth:`exact` ``(kind)``, e.g. with :meth:`certifier`."""
        raw = (solver or self.exact(kind)).solve(data)
        if self.settings.fast:
            self.fast(kind).stats.exact += 1
        if raw.status == OPTIMAL and raw.mode is not None:
            self._guess[kind] = raw.mode
        return raw

    @staticmethod
    def _count(raw: RawSolution) -> tuple[int, int]:
        """(problems solved, MIQPs solved) by one :meth:`solve` call."""
        if raw.path == "guess":
            return 1, 0
        nm = 1 + raw.bigm_retries
        return nm + (1 if raw.path == "fallback" else 0), nm

    # --------------------------------------------------------------- stages
    def _prp_stage(self, w: np.ndarray, fc: np.ndarray, p: np.ndarray, F: float | None = None) -> _Stage:
        data = self.form.scale_data(w, fc, p, F=F)
        raw = self.solve("prp", data)
        ok = raw.status == OPTIMAL
        xh = raw.z[self.form.layout("prp")["obj"]] if ok else np.zeros(self.form.nx)
        status = "resisted" if ok else ("not_resisted" if raw.status == INFEASIBLE else raw.status)
        n, nm = self._count(raw)
        return _Stage(raw, data, xh, status, ok, 1, (), raw.solve_time, n, nm)

    def _iterative_stage(
        self, w: np.ndarray, fc: np.ndarray, p: np.ndarray, F: float | None = None
    ) -> _Stage:
        s = self.settings
        f = self.form
        lay = f.layout("move")
        base = f.scale_data(w, fc, p, F=F)
        tol = s.eps + s.eps_rel * base.F
        xh = np.zeros(f.nx)
        direction = np.zeros(f.nx)
        history: list[float] = []
        total, n, nm = 0.0, 0, 0
        status, converged, raw_best = "not_converged", False, None
        prev = None
        for _ in range(int(s.max_iterations)):
            data = ScaledData(base.F, base.w, base.fc, base.p, xh, direction)
            raw = self.solve("move", data)
            total += raw.solve_time
            dn, dm = self._count(raw)
            n, nm = n + dn, nm + dm
            if raw.status != OPTIMAL:
                status = "not_resisted" if raw.status == INFEASIBLE else raw.status
                break
            r = base.w + f.Gb @ raw.z[lay["beta"]]
            norm = float(np.linalg.norm(r) * base.F)
            stalls = prev is not None and prev - norm < s.improvement * prev
            if raw.path == "guess" and norm > tol and stalls and s.certify:
                # about to stop on a guessed mode: the stop must be certified by the exact
                # solve (a locally optimal mode can stall where another mode still improves)
                threshold = (1.0 - s.improvement) * prev
                for solver in (self.certifier(), self.exact("move")):
                    ex = self.solve_exact("move", data, solver)
                    total += ex.solve_time
                    dn, dm = self._count(ex)
                    n, nm = n + dn, nm + dm
                    if ex.status != OPTIMAL:
                        break
                    r_ex = base.w + f.Gb @ ex.z[lay["beta"]]
                    norm_ex = float(np.linalg.norm(r_ex) * base.F)
                    gap = CERTIFY_GAP if "gaplimit" in ex.message else 0.0
                    lower = norm_ex / np.sqrt(1.0 + gap)  # no mode reaches below this
                    if norm_ex < norm:
                        raw, r, norm = ex, r_ex, norm_ex
                    if lower >= threshold or norm_ex <= threshold:
                        break  # decided: a certified stall, or an improving step
                    # undecided within the gap: solve to optimality
                if ex.status not in (OPTIMAL, INFEASIBLE):
                    # the certificate itself failed (time-out, solver error): so does the stop
                    history.append(norm)
                    status = ex.status
                    break
            history.append(norm)
            xh_next = xh + raw.z[lay["obj"]][0] * direction
            raw_best = (raw, xh_next, data)
            if norm <= tol:
                status, converged = "resisted", True
                break
            if prev is not None and prev - norm < s.improvement * prev:
                status = "not_resisted"
                break
            prev = norm
            xh, direction = xh_next, r
        if raw_best is None:
            return _Stage(None, base, xh, status, False, n, tuple(history), total, n, nm)
        raw, xh_sol, data = raw_best
        return _Stage(raw, data, xh_sol, status, converged, len(history), tuple(history), total, n, nm)

    @staticmethod
    def _preload_key(command: np.ndarray, method: str) -> tuple:
        return (method, tuple(np.round(command, 15)))

    def preload_stage(self, command: np.ndarray, method: str) -> _Stage:
        """The preload alone (``w = 0``), cached per command."""
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
    def max_load_factor(
        self, command: object, direction: np.ndarray, upper: float
    ) -> tuple[str, float, float]:
        """Alg. 1's largest resistible magnitude along a unit ``direction`` in one MILP
        (:mod:`pinograsp.solvers.load_factor`).

        Returns:
            ``(status, magnitude, solve_time)``: status ``"optimal"`` (magnitude in [N] or
            [N·m] along the direction; ``inf`` when ``upper`` is reached), ``"infeasible"``
            (not even ``w = 0``), ``"timeout"`` or ``"failed"``.
        """
        from .solvers.load_factor import LoadFactorMIQP

        m, f, s = self.model, self.form, self.settings
        fc = m.command_vector(command)
        p = np.zeros(m.nc)
        pre_time = 0.0
        if s.variant_for("prp") != "single-step":
            pre = self.preload_stage(fc, "prp")
            pre_time = pre.solve_time
            if not pre.converged:
                return INFEASIBLE, float("nan"), pre_time
            p = f.E @ pre.raw.z[f.layout("prp")["beta"]] * pre.data.F
        data = f.scale_data(np.zeros(m.nw), fc, p)
        F = data.F
        d = m.reduce_wrench(np.asarray(direction, float)) * f.wscale
        if "load" not in self._exact:
            self._load = LoadFactorMIQP(f, solver=s.solver, time_limit=s.time_limit)
            self._exact["load"] = self._load  # type: ignore[assignment]
        tmax = float(upper) / F
        M = s.bigm * max(1.0, 10.0 * tmax)
        out = self._load.solve(data, d, tmax, M)
        dt = out["solve_time"] + pre_time
        if out["status"] != OPTIMAL:
            return out["status"], float("nan"), dt
        t = out["t"]
        if t >= tmax * (1.0 - 1e-9):
            return OPTIMAL, float("inf"), dt
        return OPTIMAL, t * F, dt

    # ------------------------------------------------------------- response
    def response(self, command: object, wrench: object, method: str = "prp") -> PassiveResponse:
        """Passive response to ``wrench`` under ``command`` (see :func:`passive_response`)."""
        if method not in METHODS:
            raise InvalidInputError("method", f"must be one of {METHODS}, got {method!r}")
        m = self.model
        fc = m.command_vector(command)
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
            st = stage_fn(w, fc, p)
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
        n_miqp = st.n_miqp + (counted.n_miqp if counted is not None else 0)
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
            n_miqp=n_miqp,
            contact_names=m.contact_names,
            joint_names=m.joint_names,
            actuator_names=m.actuator_names,
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
                converged=False,
                solver=self.settings.solver,
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
        audit = Audit(
            equilibrium=float(np.linalg.norm(net * f.wscale)),
            hand=float(np.abs(hand).max(initial=0.0)),
            complementarity=float(comp),
            friction=float(max(0.0, -beta.min(initial=0.0))),
            bigm_ratio=raw.bigm_ratio,
            bigm_retries=raw.bigm_retries,
            polished=raw.polished,
            tolerance=self.settings.tolerance * scale,
        )
        modes_c = tuple("touching" if t else "separated" for t in raw.mode.touching)
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
            converged=st.converged,
            solver=raw.backend,
            **common,
        )


_CACHE: weakref.WeakKeyDictionary[GraspModel, dict[Settings, PassiveSolver]] = weakref.WeakKeyDictionary()


def solver_for(model: GraspModel, settings: Settings | None = None, **overrides: object) -> PassiveSolver:
    """The cached :class:`PassiveSolver` of ``model`` with these settings (built on first use)."""
    if not isinstance(model, GraspModel):
        raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
    s = make_settings(settings, **overrides)
    per_model = _CACHE.setdefault(model, {})
    if s not in per_model:
        per_model[s] = PassiveSolver(model, s)
    return per_model[s]


def passive_response(
    model: GraspModel,
    command: object,
    wrench: object,
    method: str = "prp",
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
        method: ``"prp"`` (Alg. 1) or ``"iterative"`` (Alg. 2 + 3).
        settings: Base :class:`Settings`; keyword ``overrides`` replace single fields
            (e.g. ``solver="gurobi"``, ``gamma=2.0``, ``variant="single-step"``).

    Returns:
        A :class:`~pinograsp.results.PassiveResponse`; ``resistible`` says whether the wrench is
        resisted, ``status`` why not (``"timeout"``/``"failed"`` are never reported as resisted).
    """
    if method not in METHODS:
        raise InvalidInputError("method", f"must be one of {METHODS}, got {method!r}")
    return solver_for(model, settings, **overrides).response(command, wrench, method)


__all__ = [
    "METHODS",
    "VARIANTS",
    "PassiveSolver",
    "Settings",
    "make_settings",
    "passive_response",
    "solver_for",
]
