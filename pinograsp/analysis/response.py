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

Each method's rules are its module (``analysis/method_*.py``) registered in
:mod:`pinograsp.analysis.registry`; the stages are in :mod:`pinograsp.analysis.stages`, their
chaining per variant in :mod:`pinograsp.analysis.staged`, their assembly into a
:class:`~pinograsp.core.results.PassiveResponse` in :mod:`pinograsp.analysis.assemble`. This
module holds the session (:class:`Session`): the state a caller owns and every method
reads through :class:`~pinograsp.analysis.protocols.SessionLike`.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import replace
from functools import cached_property

import numpy as np

from ..core.methods import method_variant
from ..core.model import GraspModel
from ..core.results import PassiveResponse
from ..core.settings import DEFAULT_METHOD, Backend, Settings, make_settings
from ..core.validate import load_within
from ..errors import ConditioningWarning, InvalidInputError
from ..solvers.base import Mode, RawSolution, SolveStatus
from ..solvers.formulation import Formulation, ScaledData
from ..solvers.problem import Problem, ProblemKind, build_problem
from ..solvers.solve import SolverBackend, make_backend
from ..solvers.threads import single_threaded
from .method_base import MethodBase
from .protocols import LoadFactor
from .quasistatic.prepared import Prepared, prepare_analysed
from .refine import refine
from .registry import get_method, refining_methods
from .staged import staged_load_factor
from .stages import Stage

#: Contact stiffness ratio above which the branch-and-bound warns (docs/solvers.md).
MAX_STIFFNESS_RATIO = 1e5


class Session:
    """Passive-response session of one model and settings: the state a caller owns, made as
    ``pg.Session(model, settings, **overrides)`` (the one way; keyword ``overrides`` replace
    single fields of ``settings``, as for every analysis).

    It carries no state that changes answers: each solve is a function of its inputs. What it
    keeps between calls — the preload stage per command and method (a pure function of them),
    the sessions of mirrored commands and the reference backend's cvxpy objects — only saves
    time. Pass one to :func:`~pinograsp.max_resistible_wrench`,
    :func:`~pinograsp.resistance_profile` or :func:`~pinograsp.resistance_set` (``session=``) to
    share the preload stages across queries; profiles and sets share one per worker block.
    """

    def __init__(self, model: GraspModel, settings: Settings | None = None, **overrides: object) -> None:
        if not isinstance(model, GraspModel):
            raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
        self.settings = make_settings(settings, **overrides)  # validated: Settings.validated
        #: the model as given (what ``session=`` arguments are checked against)
        self.source = model
        #: the model analysed: ``model`` with the settings' normal uncertainty (core/cones.py)
        self.model = model = model.with_normal_uncertainty(self.settings.normal_uncertainty)
        ratio = float(model.k.max() / model.k.min())
        if ratio > MAX_STIFFNESS_RATIO and self.settings.backend == Backend.BNB:
            warnings.warn(
                f"contact stiffness ratio {ratio:.3g} exceeds {MAX_STIFFNESS_RATIO:g}: the default "
                "branch-and-bound may lose solutions of such models; use backend='miqp'",
                ConditioningWarning,
                stacklevel=3,
            )
        self._preload: dict[tuple[str, tuple[float, ...]], Stage] = {}
        #: commands whose preload check passed, per method (``MethodBase.preload_kept``)
        self._preload_checked: set[tuple[str, tuple[float, ...]]] = set()
        self._mirrors: dict[tuple[bool, ...], Session] = {}
        #: the quasi-static method's prepared grasps (preloaded states), per variant and command
        self._paths: dict[tuple[str, bytes], Prepared] = {}

    # ------------------------------------------ built on first use (a method that needs them)
    @cached_property
    def form(self) -> Formulation:
        """The complementarity formulation of the model (the staged methods' problems)."""
        return Formulation(self.model)

    @cached_property
    def backend(self) -> SolverBackend:
        """The one path to the solvers: the backend ``settings.backend`` names."""
        return make_backend(self.settings, self.form)

    @cached_property
    def gamma_eff(self) -> float:
        """Step bound in scaled units. ``gamma`` is relative to the stiffest contact; with a
        stiffness spread a soft contact would otherwise gain only ``k_min / k_max`` of the net
        wrench per step and the 1 % rule would stop the iteration early ("not resisted"), so
        the bound is widened by ``k_max / k_min`` (1 for uniform stiffness)."""
        return float(self.settings.gamma * self.form.kx / self.model.k.min())

    def loading_grasp(self, command: np.ndarray, variant: str) -> Prepared:
        """The quasi-static method's prepared grasp — the model ready for loading paths and the
        preloaded state — of the validated ``command`` (na,) and preload path ``variant``
        (``"held"``/``"settled"``), kept per command (a pure function of the session's model,
        settings and ``command``: only time is saved).

        Raises:
            PreloadNotInEquilibriumError: The preload path does not reach its end.
        """
        fc = np.asarray(command, float)
        key = (variant, fc.tobytes())
        hit = self._paths.get(key)
        if hit is None:
            hit = self._paths[key] = prepare_analysed(self.model, fc, self.settings, variant)
        return hit

    # ------------------------------------------------------------ the solvers
    def solve(
        self, kind: ProblemKind, data: ScaledData, guess: Mode | None = None, t_max: float | None = None
    ) -> RawSolution:
        """Solve one scaled problem of ``kind`` with the settings' backend; ``guess`` is an
        incumbent mode (speed only), ``t_max`` the load factor's limit of load kinds. The wall
        time includes building the problem."""
        t0 = time.perf_counter()
        problem = build_problem(self.form, kind, data, self.gamma_eff, 1.0 if t_max is None else t_max)
        raw = self.backend.solve(problem, guess)
        return replace(raw, solve_time=time.perf_counter() - t0)

    def solve_problem(self, problem: Problem) -> RawSolution:
        """Solve a problem built elsewhere (e.g. an optimal-preload program) with the settings'
        backend."""
        return self.backend.solve(problem)

    def solve_fixed_mode(self, problem: Problem, mode: Mode) -> RawSolution:
        """The canonical optimum of ``problem`` in the fixed ``mode`` (the settings' backend)."""
        return self.backend.solve_fixed_mode(problem, mode)

    # ------------------------------------------------------------ methods and preloads
    def rules(self, method: object) -> MethodBase:
        """The registered method named ``method`` (:func:`~pinograsp.analysis.registry.get_method`)."""
        return get_method(method)

    @staticmethod
    def _preload_key(command: np.ndarray, method: object) -> tuple[str, tuple[float, ...]]:
        return (str(method), tuple(np.asarray(command, float).tolist()))

    def has_preload(self, command: np.ndarray, method: object) -> bool:
        """Whether the preload stage of ``method`` under ``command`` is kept already."""
        return self._preload_key(command, method) in self._preload

    def preload_checked(self, command: np.ndarray, method: object, *, passed: bool = False) -> bool:
        """Whether the preload check of ``method`` under ``command`` passed on this session
        already; ``passed=True`` records that it did (for methods whose check is a pure
        function of the session and the commands, ``MethodBase.preload_kept``)."""
        key = self._preload_key(command, method)
        if passed:
            self._preload_checked.add(key)
        return key in self._preload_checked

    def preload_stage(self, command: np.ndarray, method: object) -> Stage:
        """The preload alone (``w = 0``) solved by ``method``, kept per command (a pure function
        of it)."""
        key = self._preload_key(command, method)
        if key not in self._preload:
            zero = np.zeros(self.model.nw)
            nop = np.zeros(self.model.nc)
            self._preload[key] = get_method(method).stage(self, zero, command, nop, None)
        return self._preload[key]

    def _mirror(self, fc: np.ndarray) -> tuple[Session, np.ndarray] | None:
        """For negative commands of bidirectional actuators: the session of the model with
        those actuators' transmissions negated (commanded ``|f_c|``) and the signs (na,); else
        None."""
        neg = fc < 0
        if not neg.any():
            return None
        signs = np.where(neg, -1.0, 1.0)
        key = tuple(bool(v) for v in neg)
        if key not in self._mirrors:
            with warnings.catch_warnings():  # the same contacts: warned by this session already
                warnings.simplefilter("ignore", ConditioningWarning)
                self._mirrors[key] = Session(self.model.with_actuator_signs(signs), self.settings)
        return self._mirrors[key], signs

    # ------------------------------------------------------------ refinement
    def _refines(self, method: MethodBase) -> bool:
        """Whether queries of ``method`` refine the pyramids (``Settings.cone_tolerance``)."""
        if self.settings.cone_tolerance is None:
            return False
        if not method.refines:
            who = " or ".join(repr(n) for n in refining_methods())
            raise InvalidInputError(
                "cone_tolerance", f"cone refinement applies to method={who}, not {method.name!r}"
            )
        return not self.model.planar

    def _cone_tolerance(self) -> float:
        tol = self.settings.cone_tolerance
        if tol is None:
            raise InvalidInputError("cone_tolerance", "refinement needs a tolerance [rad]")
        return float(tol)

    def plain(self, model: GraspModel) -> Session:
        """A session of ``model`` (a refinement of this one's) with these settings but no
        further refinement."""
        with warnings.catch_warnings():  # the same contacts: warned by this session already
            warnings.simplefilter("ignore", ConditioningWarning)
            return Session(model, replace(self.settings, cone_tolerance=None))

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

        return refine(self.model, self._cone_tolerance(), run)[0]

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

        return refine(self.model, self._cone_tolerance(), run)[0]

    # ------------------------------------------------------- direct search
    def max_load_factor(
        self, command: object, direction: np.ndarray, upper: float, method: str = "prp"
    ) -> LoadFactor:
        """The largest resistible magnitude along a unit ``direction`` in one complementarity
        solve of ``method``'s load-factor problem
        (:attr:`~pinograsp.analysis.method_base.MethodBase.load_factor_kind`), by the
        settings' backend.

        Returns:
            A :class:`LoadFactor`: status ``"optimal"`` (magnitude in [N] or [N·m] along the
            direction; ``inf`` when ``upper`` is reached), ``"infeasible"`` (not even
            ``w = 0``), ``"node_limit"``, ``"timeout"`` or ``"failed"``.
        """
        rules = get_method(method)
        if self._refines(rules):
            return self._refined_load_factor(command, direction, upper, rules.name)
        fc = self.model.command_vector(command)
        mirror = self._mirror(fc)
        if mirror is not None:
            return replace(mirror[0].max_load_factor(np.abs(fc), direction, upper, method), response=None)
        return staged_load_factor(self, rules, fc, direction, upper)

    # ------------------------------------------------------------- response
    @single_threaded
    def response(self, command: object, wrench: object, method: str = DEFAULT_METHOD) -> PassiveResponse:
        """Passive response to ``wrench`` under ``command`` (see :func:`passive_response`)."""
        rules = get_method(method)
        method_variant(rules.name, self.settings.variant)  # the one variant rule of every entry point
        if self._refines(rules):
            return self._refined_response(command, wrench, rules.name)
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
        return rules.response(self, fc, m.wrench_vector(wrench))


def session_for(
    model: GraspModel, session: Session | None, settings: Settings | None, overrides: dict[str, object]
) -> Session:
    """The session a public query runs on: the caller's ``session`` (built for ``model``; its
    settings rule, so none may be given besides it), or a new one of ``settings`` and
    ``overrides``.

    Raises:
        InvalidInputError: ``session`` is not a session, was built for another model, or comes
            with settings.
    """
    if session is None:
        return Session(model, settings, **overrides)
    if not isinstance(session, Session):
        raise InvalidInputError(
            "session", f"expected pinograsp.Session or None, got {type(session).__name__}"
        )
    if session.source is not model:
        raise InvalidInputError(
            "session", "was built for another model: pg.Session(model, settings) of this one"
        )
    if settings is not None or overrides:
        raise InvalidInputError(
            "session", "carries its own settings: pass settings to pg.Session(model, settings)"
        )
    return session


def passive_response(
    model: GraspModel,
    command: object,
    wrench: object,
    method: str = DEFAULT_METHOD,
    *,
    settings: Settings | None = None,
    session: Session | None = None,
    **overrides: object,
) -> PassiveResponse:
    """Passive response of the grasp ``model`` preloaded with ``command`` to ``wrench``.

    Args:
        model: The grasp.
        command: Actuator commands ``f_c`` (scalar, sequence, or ``{actuator_name: value}``)
            [N·m for direct drive, N for tendons].
        wrench: External wrench on the object ``(fx, fy, fz, mx, my, mz)`` [N, N·m] about the
            object reference point (planar models also take ``(fx, fy, mz)``).
        method: ``"quasistatic"`` (default, as in every analysis, the CLI, the scenes and
            batches: the state reached on the loading path at ``wrench``, the method that agrees
            with the simulation most often; docs/methods.md), ``"iterative"`` (Alg. 2 + 3, the
            paper's scheme), ``"energetic"`` (maximum dissipation in one mixed-integer problem,
            docs/methods.md) or ``"prp"`` (Alg. 1, by explicit choice: it admits the wedging
            artefact).
        settings: Base :class:`Settings`; keyword ``overrides`` replace single fields
            (e.g. ``solver="gurobi"``, ``gamma=2.0``, ``variant="single-step"``).
        session: A :class:`~pinograsp.Session` of ``model`` the caller owns (its settings rule;
            its preload stages are shared with the caller's other queries).

    Returns:
        A :class:`~pinograsp.core.results.PassiveResponse`; ``resistible`` says whether the wrench is
        resisted, ``status`` why not (``"timeout"``/``"failed"`` are never reported as resisted).
    """
    get_method(method)
    solver = session_for(model, session, settings, overrides)
    # the load within the grasp's force scale, at the public boundary (docs/errors.md)
    load_within(model, model.command_vector(command), "wrench", model.wrench_vector(wrench))
    return solver.response(command, wrench, method)


__all__ = ["LoadFactor", "Session", "passive_response", "session_for"]
