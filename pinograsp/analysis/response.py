"""Passive response of a preloaded grasp to an external wrench (seed Alg. 1, 2 and 3).

* ``method="prp"`` — Alg. 1: one mixed-integer QP, minimise the spring energy ``|c_n|^2``
  subject to equilibrium, friction, springs and actuation. Admits the *wedging artefact*.
* ``method="iterative"`` — Alg. 2 inside Alg. 3: the object may only move along the current
  net wrench (step in ``[0, gamma]``), each step minimises the net wrench, repeat until it
  falls below ``eps`` (resisted) or stops improving (not resisted).
* ``method="energetic"`` — maximum dissipation (docs/methods.md): Alg. 1's problem plus one
  slip magnitude per contact and the pairs that let a friction edge carry force only if it
  points most against the slip; one mixed-integer problem, no wedging artefact.

Three variants (:class:`~pinograsp.core.settings.Variant`, docs/design.md):

* ``"single-step"`` (the paper): preload and load are solved together from the
  touching-without-force configuration;
* ``"preload-first"`` (the authors' released code): first the preload alone (``w = 0``), then
  ``w`` on top, with the preload normal forces as spring pre-compression and displacements
  counted from the preloaded state — so a finger that closed during preloading may hold still
  afterwards. Default for ``"iterative"`` and ``"energetic"`` (whose preload stage is the
  iterative scheme's: the object held still while the hand closes); the paper's single-step
  is the default for ``"prp"``.
  In the iterative method the object cannot move while the preload is applied (the first
  step has no movement direction and ``w = 0`` leaves no net wrench to follow).
* ``"settled-preload"``: as ``"preload-first"``, but the preload stage is Alg. 1 at ``w = 0``
  for both methods, so the object is free to settle into the least-spring-energy equilibrium
  of the preload before the load is applied (a hand closing on a free object). It differs from
  ``"preload-first"`` only when the held-still preload leaves some contacts unloaded that a
  settling object would load (seed case 3 with the distal tendon alone, see docs/results.md).

The stages themselves are in :mod:`pinograsp.analysis.stages`, their assembly into a
:class:`~pinograsp.core.results.PassiveResponse` in :mod:`pinograsp.analysis.assemble`.
"""

from __future__ import annotations

import time
import warnings
import weakref
from dataclasses import dataclass, replace

import numpy as np

from ..core.model import GraspModel
from ..core.results import PassiveResponse
from ..core.settings import METHODS, Method, Settings, Variant, make_settings
from ..core.validate import choice, load_within
from ..errors import ConditioningWarning, InvalidInputError
from ..solvers import OPTIMAL, Formulation, ScaledData, resolve_solver
from ..solvers.base import INFEASIBLE, Mode, RawSolution, SolveStatus
from ..solvers.bnb import BranchAndBound
from ..solvers.problem import ProblemKind, build_problem
from ..solvers.solve import Backend, BackendOptions, single_threaded
from ..solvers.solve import solve as solve_problem
from .assemble import build_response, layout_of
from .refine import refine
from .stages import Stage, iterative_stage, prp_stage

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
        model: The refined model the answer was found on (``Settings.cone_tolerance``), or None.
        response: ``method="energetic"``: the equilibrium at the limit (the load-factor
            problem's own point, at ``magnitude`` or at ``upper``), else None.
    """

    status: SolveStatus
    magnitude: float
    solve_time: float
    model: GraspModel | None = None
    response: PassiveResponse | None = None


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
        self.settings = (settings or Settings()).validated()
        #: the model analysed: ``model`` with the settings' normal uncertainty (core/cones.py)
        self.model = model = model.with_normal_uncertainty(self.settings.normal_uncertainty)
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
        self._preload: dict[tuple, Stage] = {}
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

    @staticmethod
    def _preload_key(command: np.ndarray, method: str) -> tuple:
        return (Method(method), tuple(np.asarray(command, float).tolist()))

    def preload_stage(self, command: np.ndarray, method: str) -> Stage:
        """The preload alone (``w = 0``) solved by ``method``, kept per command (a pure function
        of it)."""
        key = self._preload_key(command, method)
        if key not in self._preload:
            zero = np.zeros(self.model.nw)
            nop = np.zeros(self.model.nc)
            stage = prp_stage if method == Method.PRP else iterative_stage
            self._preload[key] = stage(self, zero, command, nop)
        return self._preload[key]

    def _precompression(self, pre: Stage, method: str) -> np.ndarray:
        """Spring pre-compression [N] (nc,) left by a converged preload stage of ``method``."""
        return self.form.E @ pre.raw.z[layout_of(self, method)["beta"]] * pre.data.F

    # ------------------------------------------------------------ refinement
    def _refines(self, method: str) -> bool:
        """Whether queries of ``method`` refine the pyramids (``Settings.cone_tolerance``)."""
        if self.settings.cone_tolerance is None:
            return False
        if method == Method.ITERATIVE:
            raise InvalidInputError(
                "cone_tolerance", "cone refinement applies to method='prp' or 'energetic', not 'iterative'"
            )
        return not self.model.planar

    def plain(self, model: GraspModel) -> PassiveSolver:
        """A solver of ``model`` (a refinement of this one's) with these settings but no
        further refinement."""
        with warnings.catch_warnings():  # the same contacts: warned by this session already
            warnings.simplefilter("ignore", ConditioningWarning)
            return PassiveSolver(model, replace(self.settings, cone_tolerance=None))

    def _refined_response(self, command: object, wrench: object, method: str) -> PassiveResponse:
        """:meth:`response` on pyramids refined where the answer loads them (analysis/refine.py);
        a load not resisted is refined where its direction's largest resisted load sits."""
        w6 = self.model.wrench_vector(wrench)
        size = float(np.linalg.norm(w6))

        def run(mr: GraspModel) -> tuple[PassiveResponse, PassiveResponse | None]:
            sub = self.plain(mr)
            r = sub.response(command, w6, method)
            if r.resistible or size == 0.0 or r.status != "not_resisted":
                return r, (r if r.resistible else None)
            lf = sub.max_load_factor(command, w6 / size, size, method)
            if lf.status is not SolveStatus.OPTIMAL or not 0.0 < lf.magnitude < size:
                return r, None
            probe = sub.response(command, w6 * (lf.magnitude * (1.0 - 1e-6) / size), method)
            return r, (probe if probe.resistible else None)

        return refine(self.model, float(self.settings.cone_tolerance), run)[0]

    def _refined_load_factor(
        self, command: object, direction: np.ndarray, upper: float, method: str
    ) -> LoadFactor:
        """:meth:`max_load_factor` on pyramids refined where its limit loads them."""

        def run(mr: GraspModel) -> tuple[LoadFactor, PassiveResponse | None]:
            sub = self.plain(mr)
            lf = replace(sub.max_load_factor(command, direction, upper, method), model=mr)
            if lf.status is not SolveStatus.OPTIMAL or not lf.magnitude > 0.0:
                return lf, None
            probe = lf.response
            if probe is None:
                at = float(upper) if np.isinf(lf.magnitude) else lf.magnitude * (1.0 - 1e-6)
                probe = sub.response(command, at * np.asarray(direction, float), method)
            return lf, (probe if probe.resistible else None)

        return refine(self.model, float(self.settings.cone_tolerance), run)[0]

    def _pre_method(self, method: str, variant: Variant) -> Method:
        """``Method`` of the preload stage of ``method`` under ``variant``."""
        if variant is Variant.SETTLED_PRELOAD:
            return Method.PRP
        return Method.ITERATIVE if method == Method.ENERGETIC else Method(method)

    def _carried(self, pre: Stage, pre_method: str, method: str) -> np.ndarray:
        """Energetic load stages balance the load on top of the preload stage's own net wrench
        (reduced, [N, N·m]): the held-still preload (the iterative scheme's) is an equilibrium
        only to its tolerance ``eps``, and an exact balance of that residual would have to slip
        the contacts. Zero for the other methods and for an exact (PRP) preload."""
        if method != Method.ENERGETIC or pre_method != Method.ITERATIVE:
            return np.zeros(self.model.nw)
        m = self.model
        beta = pre.raw.z[layout_of(self, pre_method)["beta"]] * pre.data.F
        return -(m.G @ (m.D @ beta))

    # ------------------------------------------------------- direct search
    def max_load_factor(
        self, command: object, direction: np.ndarray, upper: float, method: str = Method.PRP
    ) -> LoadFactor:
        """The largest resistible magnitude along a unit ``direction`` in one complementarity
        solve (:attr:`ProblemKind.LOAD`, or :attr:`ProblemKind.ENERGETIC_LOAD` for
        ``method="energetic"``, by the settings' backend).

        Returns:
            A :class:`LoadFactor`: status ``"optimal"`` (magnitude in [N] or [N·m] along the
            direction; ``inf`` when ``upper`` is reached), ``"infeasible"`` (not even
            ``w = 0``), ``"node_limit"``, ``"timeout"`` or ``"failed"``.
        """
        if self._refines(method):
            return self._refined_load_factor(command, direction, upper, method)
        m, f, s = self.model, self.form, self.settings
        fc = m.command_vector(command)
        mirror = self._mirror(fc)
        if mirror is not None:
            return replace(mirror[0].max_load_factor(np.abs(fc), direction, upper, method), response=None)
        p = np.zeros(m.nc)
        pre_time = 0.0
        pre, pre_method, fresh = None, None, True
        variant = s.variant_for(method)
        if variant is not Variant.SINGLE_STEP:
            pre_method = self._pre_method(method, variant)
            fresh = self._preload_key(fc, pre_method) not in self._preload
            pre = self.preload_stage(fc, pre_method)
            pre_time = pre.solve_time
            if not pre.converged:
                return LoadFactor(INFEASIBLE, float("nan"), pre_time)
            p = self._precompression(pre, pre_method)
            w0 = self._carried(pre, pre_method, method)
        else:
            w0 = np.zeros(m.nw)
        d = m.reduce_wrench(np.asarray(direction, float)) * f.wscale
        data = f.scale_data(w0, fc, p)
        data = ScaledData(data.F, data.w, data.fc, data.p, data.x0, d)
        tmax = float(upper) / data.F
        kind = ProblemKind.ENERGETIC_LOAD if method == Method.ENERGETIC else ProblemKind.LOAD
        t0 = time.perf_counter()
        raw = self._load_factor(kind, data, tmax)
        raw = replace(raw, solve_time=time.perf_counter() - t0)
        dt = raw.solve_time + pre_time
        if raw.status != OPTIMAL:
            return LoadFactor(raw.status, float("nan"), dt)
        t = max(float(raw.z[-1]), 0.0)
        at_upper = t >= tmax * (1.0 - 1e-9)
        magnitude = float("inf") if at_upper else t * data.F
        if method != Method.ENERGETIC:
            return LoadFactor(OPTIMAL, magnitude, dt)
        # the load-factor problem's point is an equilibrium of the energetic problem at t d
        stage = Stage(
            raw,
            replace(data, w=data.w + t * d),
            raw.z[self.form.layout("energetic")["obj"]],
            "resisted",
            True,
            1,
            (),
            raw.solve_time,
            1,
        )
        w6 = (float(upper) if at_upper else magnitude) * np.asarray(direction, float)
        resp = build_response(self, method, variant, w6, fc, stage, pre, pre_fresh=fresh, pre_kind=pre_method)
        return LoadFactor(OPTIMAL, magnitude, dt, response=resp)

    def _load_factor(self, kind: ProblemKind, data: ScaledData, tmax: float) -> RawSolution:
        if self.options.backend is Backend.BNB:
            problem = build_problem(self.form, kind, data, t_max=tmax)
            return BranchAndBound(problem, self.options.max_nodes).solve()
        from ..solvers.miqp import CvxpyMIQP  # cvxpy: loaded only for the reference backend

        s = self.settings
        miqp = CvxpyMIQP(
            self.form,
            kind.value,
            solver=s.solver,
            time_limit=s.time_limit,
            options=dict(self.options.miqp_options),
        )
        return miqp.solve(data, s.bigm * max(1.0, 10.0 * tmax), t_max=tmax)

    # ------------------------------------------------------------- response
    @single_threaded
    def response(self, command: object, wrench: object, method: str = "iterative") -> PassiveResponse:
        """Passive response to ``wrench`` under ``command`` (see :func:`passive_response`)."""
        choice("method", method, METHODS)
        if self._refines(method):
            return self._refined_response(command, wrench, method)
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
        if variant is Variant.SINGLE_STEP:
            stage = self._load_stage(method, w, fc, np.zeros(m.nc), None)
            return build_response(self, method, variant, w6, fc, stage, None)
        pre_method = self._pre_method(method, variant)
        fresh = self._preload_key(fc, pre_method) not in self._preload
        pre = self.preload_stage(fc, pre_method)
        if not pre.converged:
            failed = pre if pre_method == method else replace(pre, raw=None)
            note = "preload not in equilibrium"
            return build_response(self, method, variant, w6, fc, failed, None, note=note)
        p = self._precompression(pre, pre_method)
        stage = self._load_stage(method, w + self._carried(pre, pre_method, method), fc, p, pre.raw.mode)
        return build_response(self, method, variant, w6, fc, stage, pre, pre_fresh=fresh, pre_kind=pre_method)

    def _load_stage(
        self, method: str, w: np.ndarray, fc: np.ndarray, p: np.ndarray, start: Mode | None
    ) -> Stage:
        """The load stage of ``method`` (``start``: the preload's mode, the iterative scheme's
        first incumbent)."""
        if method == Method.PRP:
            return prp_stage(self, w, fc, p)
        if method == Method.ENERGETIC:
            return prp_stage(self, w, fc, p, ProblemKind.ENERGETIC)
        return iterative_stage(self, w, fc, p, start=start)


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
            every analysis, the CLI and the scenes), ``"energetic"`` (maximum dissipation in
            one mixed-integer problem, docs/methods.md) or ``"prp"`` (Alg. 1, by explicit
            choice: it admits the wedging artefact).
        settings: Base :class:`Settings`; keyword ``overrides`` replace single fields
            (e.g. ``solver="gurobi"``, ``gamma=2.0``, ``variant="single-step"``).

    Returns:
        A :class:`~pinograsp.core.results.PassiveResponse`; ``resistible`` says whether the wrench is
        resisted, ``status`` why not (``"timeout"``/``"failed"`` are never reported as resisted).
    """
    choice("method", method, METHODS)
    solver = solver_for(model, settings, **overrides)
    if isinstance(model, GraspModel):  # the load within the grasp's force scale (docs/errors.md)
        load_within(model, model.command_vector(command), "wrench", model.wrench_vector(wrench))
    return solver.response(command, wrench, method)


__all__ = ["LoadFactor", "PassiveSolver", "Session", "passive_response", "solver_for"]
