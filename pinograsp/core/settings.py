"""Settings of every analysis and the typed vocabularies of their options (docs/design.md).

The option vocabularies are ``str`` enums: a member equals its value, so ``method="prp"`` and
``method=Method.PRP`` are the same argument, and code compares members, never free text.
This module imports no solver: scenes validate their analysis blocks with it at load time.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from enum import Enum

import numpy as np

from ..errors import InvalidInputError, SolverNotAvailableError, UnknownNameError
from .cones import check_angle
from .giveway import DEFAULT_CONTACT_STIFFNESS
from .validate import (
    GIVEWAY,
    PHYSICAL_STIFFNESS,
    TANGENTIAL_RATIO,
    choice,
    count,
    number_in,
    positive_number,
    whole_number,
)


class Vocabulary(str, Enum):
    """A ``str`` enum that prints as its value (``f"{Method.PRP}"`` is ``"prp"``) on every Python."""

    def __str__(self) -> str:
        return str(self.value)

    def __format__(self, spec: str) -> str:
        return format(str(self.value), spec)


class Method(Vocabulary):
    """Which passive-response algorithm (docs/design.md; the default: :data:`DEFAULT_METHOD`)."""

    #: Seed Alg. 1: one mixed-integer problem; admits the wedging artefact.
    PRP = "prp"
    #: Seed Alg. 2 inside Alg. 3: the movement-constrained iterative scheme (the paper's results).
    ITERATIVE = "iterative"
    #: Maximum dissipation (docs/methods.md): the PRP plus slip variables, friction opposing
    #: slip and sliding contacts on the pyramid's boundary; one mixed-integer problem.
    ENERGETIC = "energetic"
    #: The quasi-static loading path (docs/methods.md): the equilibrium of the preloaded grasp
    #: followed exactly, event by event, as the load grows (tangential contact springs with
    #: Coulomb slip); the limit load without bisection. The default (:data:`DEFAULT_METHOD`).
    QUASISTATIC = "quasistatic"


class Variant(Vocabulary):
    """How the preload and the load are applied (see :mod:`pinograsp.analysis.response`)."""

    #: The paper's: preload and load solved together from the touching configuration.
    SINGLE_STEP = "single-step"
    #: The authors' released code: the preload alone first, the load on top (object held still).
    PRELOAD_FIRST = "preload-first"
    #: As ``PRELOAD_FIRST`` but the object settles freely under the preload (Alg. 1 at w = 0).
    SETTLED_PRELOAD = "settled-preload"


class Backend(Vocabulary):
    """Which solver answers the complementarity problems."""

    #: pinograsp's exact branch-and-bound over the complementarity pairs (DAQP node QPs).
    BNB = "bnb"
    #: The reference cvxpy MIQP (``Settings.solver`` names the MIQP solver).
    MIQP = "miqp"


class Complementarity(Vocabulary):
    """How the reference MIQP backend writes complementarity."""

    #: Big-M constraints (any MIQP solver).
    BIGM = "bigm"
    #: SCIP indicator constraints (no big-M constant; SCIP only).
    INDICATOR = "indicator"


class Search(Vocabulary):
    """How :func:`~pinograsp.max_resistible_wrench` searches the magnitude."""

    #: The method's default (its registry row): secant for the iterative method, one
    #: load-factor problem for the energetic one, bisection for the PRP, the path for the
    #: quasi-static one.
    AUTO = "auto"
    #: The seed paper's bisection.
    BISECTION = "bisection"
    #: Grid-snapped secant (iterative method only).
    SECANT = "secant"
    #: One load-factor complementarity problem (PRP and energetic).
    DIRECT = "direct"
    #: Follow the loading path to its end (quasi-static only): no bisection, the limit is
    #: exact; ``steps`` does not apply and ``upper`` does not decide unboundedness.
    PATH = "path"


#: The method every analysis, scene, batch file and CLI command uses when none is named: the
#: quasi-static loading path, which has the simulation's class in 250 of 254 validated
#: directions (the iterative scheme: 170 of 239; docs/validation_quasistatic.md). The paper's
#: methods stay selectable by name.
DEFAULT_METHOD: str = Method.QUASISTATIC.value
VARIANTS = tuple(v.value for v in Variant)
BACKENDS = tuple(b.value for b in Backend)
COMPLEMENTARITIES = tuple(c.value for c in Complementarity)

#: MIQP solvers of the reference backend (cvxpy names) and the package that provides each.
MIQP_SOLVERS = {
    "SCIP": "pyscipopt (installed with pinograsp)",
    "GUROBI": "gurobipy (pip install 'pinograsp[gurobi]')",
    "MOSEK": "mosek",
    "CPLEX": "cplex",
    "XPRESS": "xpress",
    "COPT": "coptpy",
}

#: Default node limit of one branch-and-bound search (a count, never a time).
MAX_NODES = 20000


@dataclass(frozen=True)
class Settings:
    """Solver and iteration settings (all analyses accept them as keyword overrides).

    Attributes:
        backend: ``"bnb"`` (default): pinograsp's exact, deterministic branch-and-bound over
            the complementarity pairs (``docs/solvers.md``); ``"miqp"``: the reference
            mixed-integer QP through cvxpy with the solver named by ``solver``.
        max_nodes: Node limit of one branch-and-bound search (a count, never a time); hitting
            it gives status ``"node_limit"``.
        solver: MIQP solver of the reference backend: ``"scip"`` (open source) or any installed
            cvxpy MIQP solver (``"gurobi"`` with ``pinograsp[gurobi]``).
        time_limit: Per-MIQP time limit [s] of the reference backend; hitting it gives status
            ``"timeout"``.
        bigm: Initial big-M constant of the reference backend in scaled force units.
        bigm_retries: Enlargements (x100 each) when a MIQP solution reaches 10 % of big-M.
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
        variant: ``"single-step"``, ``"preload-first"`` or ``"settled-preload"`` (see
            :mod:`pinograsp.analysis.response`); ``None`` picks the method's default (its
            registry row, :mod:`pinograsp.analysis.registry`).
        tolerance: Audit tolerance on hand/complementarity/friction residuals, relative to the
            data scale.
        accelerate: Let the iterative scheme jump ahead in a mode that has held for
            :data:`JUMP_AFTER` slow steps: the object moves to the best point of the cone of
            that mode's recent net wrenches (``docs/solvers.md``); the stop rules apply to real
            steps only. ``False``: the paper's scheme step by step (it can stall under the 1 %
            rule in narrow valleys where the net wrench still decreases).
        complementarity: ``"bigm"`` (default) or ``"indicator"`` (SCIP indicator constraints,
            no big-M constant; SCIP only).
        verify_infeasible: Re-solve an infeasible big-M MIQP once with ``M x 100`` before
            trusting the infeasibility (an ``M`` that cuts off every solution is otherwise
            indistinguishable from a load that is not resisted).
        normal_uncertainty: Worst-case uncertainty of every contact normal [rad] (default 0):
            friction ``mu -> tan(atan(mu) - u)`` in every method, and for ``"energetic"`` a
            slipping contact loses ``tan(u)`` of compression per unit slip (docs/methods.md).
        cone_tolerance: ``"prp"`` and ``"energetic"``: refine each loaded contact's friction
            pyramid (edges added on the Coulomb cone) until the sector holding its force or
            slip direction is at most this wide [rad]; ``None`` (default) keeps the model's
            pyramid. At most 100 edges per contact; planar pyramids are exact already.
        tangential_ratio: ``"quasistatic"``: tangential contact stiffness as a multiple of the
            normal stiffness ``k`` (default 1, the simulation's; in [1e-6, 1e6]; large values
            approach the paper's rigid friction).
        contact_stiffness: ``"quasistatic"``: normal stiffness of the stiffest contact [N/m]
            (default 1e6, the simulation's; the model's ``k`` give the other contacts in
            proportion; in [1, 1e10]). It sets the physical displacements of the loading path
            and so where the give-way thresholds are reached (docs/giveway.md).
        giveway_slip: Give-way translation of the object [m] (``None``: the simulation's
            default, ``max(1 mm, 20 x`` one contact spring's deflection at ``upper``)).
        giveway_rotation: Give-way rotation of the object [rad] (``None``: ``giveway_slip``
            over the model's length scale).
        giveway_joint: Give-way rotation of any finger joint from the preloaded configuration
            [rad] (``None``, the default: no joint criterion, as the simulation).
        limit: What ``method="quasistatic"`` reports as the max resistible wrench:
            ``"giveway"`` (default: the load at which the object gives way by the thresholds
            above, snaps that land followed) or ``"first"`` (the path's first limit load λ*,
            an idealised quantity; it is on every answer as ``giveway.first_limit``).
    """

    backend: str = "bnb"
    max_nodes: int = MAX_NODES
    solver: str = "scip"
    time_limit: float = 60.0
    bigm: float = 1e3
    bigm_retries: int = 2
    gamma: float = 1.0
    eps: float = 1e-3
    eps_rel: float = 1e-5
    improvement: float = 1e-2
    max_iterations: int = 100
    variant: str | None = None
    tolerance: float = 1e-6
    accelerate: bool = True
    complementarity: str = "bigm"
    verify_infeasible: bool = True
    normal_uncertainty: float = 0.0
    cone_tolerance: float | None = None
    tangential_ratio: float = 1.0
    contact_stiffness: float = DEFAULT_CONTACT_STIFFNESS
    giveway_slip: float | None = None
    giveway_rotation: float | None = None
    giveway_joint: float | None = None
    limit: str = "giveway"

    def validated(self) -> Settings:
        """Check every field; raise :class:`InvalidInputError` naming the bad one."""
        choice("backend", self.backend, BACKENDS)
        if str(self.solver).upper() not in MIQP_SOLVERS:  # installed or not: the solver layer tells
            raise SolverNotAvailableError(
                f"unknown MIQP solver {self.solver!r}; supported: {[s.lower() for s in MIQP_SOLVERS]}",
                solver=str(self.solver),
            )
        for name in ("time_limit", "bigm", "gamma", "eps", "tolerance"):
            positive_number(name, getattr(self, name))
        for name, (lo, hi, unit) in SETTING_DOMAINS.items():  # docs/errors.md, "Input domains"
            number_in(name, getattr(self, name), lo, hi, unit)
        for name in ("max_iterations", "max_nodes"):
            count(name, getattr(self, name), MAX_COUNTS[name], what="a count limit, not a hang")
        whole_number("bigm_retries", self.bigm_retries, minimum=0)
        for name in ("accelerate", "verify_infeasible"):
            if not isinstance(getattr(self, name), bool):
                raise InvalidInputError(name, f"expected True or False, got {getattr(self, name)!r}")
        choice("complementarity", self.complementarity, COMPLEMENTARITIES)
        if (
            self.backend == Backend.MIQP.value
            and self.complementarity == "indicator"
            and str(self.solver).upper() != "SCIP"
        ):
            raise InvalidInputError("complementarity", "indicator constraints need solver='scip'")
        if isinstance(self.eps_rel, bool) or not (
            isinstance(self.eps_rel, (int, float)) and 0 <= self.eps_rel < 1
        ):
            raise InvalidInputError("eps_rel", f"must be a number in [0, 1), got {self.eps_rel!r}")
        if isinstance(self.improvement, bool) or not (
            isinstance(self.improvement, (int, float)) and 0 <= self.improvement < 1
        ):
            raise InvalidInputError("improvement", f"must be in [0, 1), got {self.improvement!r}")
        if self.variant is not None:
            choice("variant", self.variant, VARIANTS)
        check_angle("normal_uncertainty", self.normal_uncertainty)
        number_in("tangential_ratio", self.tangential_ratio, *TANGENTIAL_RATIO, "(tangential / normal)")
        number_in("contact_stiffness", self.contact_stiffness, *PHYSICAL_STIFFNESS, "N/m")
        for name in ("giveway_slip", "giveway_rotation", "giveway_joint"):
            if getattr(self, name) is not None:
                number_in(name, getattr(self, name), *GIVEWAY, "m" if name == "giveway_slip" else "rad")
        choice("limit", self.limit, LIMITS)
        if self.cone_tolerance is not None:
            check_angle("cone_tolerance", self.cone_tolerance, np.pi / 4)
            if self.cone_tolerance <= 0:
                raise InvalidInputError("cone_tolerance", "must be a positive angle [rad] or None")
        return self


#: What the quasi-static method reports (:attr:`Settings.limit`).
LIMITS = ("giveway", "first")

#: Ranges of the numeric settings (docs/errors.md): the audit tolerance is relative (below 1e-12
#: it is rounding, above 1e-2 no check), ``eps`` [N] is at most MAX_FORCE (and, in a search, 1e-2
#: of the grasp's force scale or upper), a step bound ``gamma`` above 1e3 no bound.
SETTING_DOMAINS = {
    "tolerance": (1e-12, 1e-2, "(relative)"),
    "eps": (1e-12, 1e12, "N"),
    "gamma": (1e-6, 1e3, ""),
    "bigm": (1.0, 1e12, "(scaled force units)"),
    "time_limit": (1e-9, 1e6, "s"),
}
#: Largest count limits: iterations of the iterative scheme, nodes of one branch-and-bound.
MAX_COUNTS = {"max_iterations": 1_000_000, "max_nodes": 10**9}


def make_settings(settings: Settings | None = None, **overrides: object) -> Settings:
    """A validated :class:`Settings` from a base and keyword overrides."""
    if settings is not None and not isinstance(settings, Settings):
        raise InvalidInputError(
            "settings",
            f"expected pinograsp.Settings or None, got {type(settings).__name__}; "
            "pass single fields as keywords (e.g. eps=1e-3) or build pg.Settings(...)",
        )
    base = settings or Settings()
    if overrides:
        unknown = set(overrides) - set(Settings.__dataclass_fields__)
        if unknown:
            raise UnknownNameError("setting", sorted(unknown)[0], list(Settings.__dataclass_fields__))
        base = replace(base, **overrides)  # type: ignore[arg-type]
    return base.validated()
