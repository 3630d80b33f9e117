"""The quasi-static loading path (docs/methods.md, "Quasi-static loading path"): the equilibrium
of the preloaded grasp followed exactly, event by event, as the load ``λ d`` grows from 0 —
tangential contact springs with Coulomb slip on the model's friction polygon, ratchets and
couplings, each segment's rates from a small LCP (:mod:`pinograsp.analysis.quasistatic`).

A registry row that is not built from complementarity stages: no problem kinds, one search
(``"path"``: the limit load λ* of the path, no bisection; ``steps`` does not apply and is
ignored, ``upper`` does not decide unboundedness — the path's last segment does, exactly).
Variants: the preload is a path of its own first, the object held (``"preload-first"``, the
default; the simulation's ``preload="held"``) or free (``"settled-preload"``);
``"single-step"`` does not apply (a typed refusal). The paths' preloaded states are kept per
model, settings and command (``quasistatic.api``), so every direction of a profile's or set's
block — one session, one model — follows the preload path once.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from ..core.methods import method_variant
from ..core.results import MaxWrench, PassiveResponse
from ..core.settings import Method, Settings, Variant
from ..errors import PreloadNotInEquilibriumError, SolverError
from .method_base import MethodBase
from .protocols import LimitQuery, SessionLike
from .quasistatic.answers import NO_VERDICT, max_wrench_prepared, response_prepared
from .quasistatic.api import unit_again
from .quasistatic.preload import PRELOAD_PATHS
from .quasistatic.prepared import Prepared


def path_variant(settings: Settings) -> tuple[Variant, str]:
    """The variant under ``settings`` and the preload path it names (``"held"``/``"settled"``).

    Raises:
        InvalidInputError: A variant the method's row does not accept (``"single-step"``: the
            path starts from the preloaded grasp), as every entry point refuses it
            (:func:`~pinograsp.core.methods.method_variant`).
    """
    v = method_variant(Method.QUASISTATIC, settings.variant)
    return v, PRELOAD_PATHS[v]


def no_preload_response(
    session: SessionLike, fc: np.ndarray, w6: np.ndarray, variant: Variant, residual: object = None
) -> PassiveResponse:
    """``"not_resisted"``: the preload path itself ends before the commands are reached (as the
    staged methods answer a preload without equilibrium). The path has no state at the load, so
    every force and displacement is NaN; ``net_wrench`` is the preload path's residual (6,)
    [N, N·m] when its error carries one (else NaN), so that
    :func:`~pinograsp.analysis.max_wrench.check_preload` names it. :func:`pinograsp.loading_path`
    raises :class:`~pinograsp.PreloadNotInEquilibriumError` with where the preload path stopped."""
    m = session.model
    return PassiveResponse.unsolved(
        m,
        "not_resisted",
        method="quasistatic",
        variant=variant.value,
        wrench=np.asarray(w6, float),
        command=np.asarray(fc, float),
        contact_modes=("separated",) * m.nc,
        actuator_modes=("holding",) * m.na,
        net_wrench=np.full(6, np.nan) if residual is None else np.asarray(residual, float).reshape(6),
        iterations=0,
        solver="lemke",
    )


def _prepared(session: SessionLike, fc: object) -> tuple[Variant, Prepared]:
    """The variant and the prepared grasp (preloaded state) of the commands ``fc`` on
    ``session``: the session keeps it per command (:meth:`~pinograsp.Session.loading_grasp`).

    Raises:
        PreloadNotInEquilibriumError: The preload path does not reach its end.
    """
    v, path = path_variant(session.settings)
    return v, session.loading_grasp(session.model.command_vector(fc), path)


class QuasistaticMethod(MethodBase):
    """Rules of ``method="quasistatic"`` where it differs from
    :class:`~pinograsp.analysis.method_base.MethodBase`: no complementarity stages (its LCPs are
    its own, solvers/lcp.py), a path for a search, its own preload account."""

    preload_kept = True  # the preload verdict: a pure function of model, settings and commands
    preload_by_error = True  # the preload path reaches its end, or says why not

    def response(self, session: SessionLike, fc: np.ndarray, w6: np.ndarray) -> PassiveResponse:
        """The state reached on the path at ``w6`` (``"resisted"``), or at the limit load when
        the path ends before it (``"not_resisted"``; ``"failed"`` without a verdict)."""
        try:
            v, p = _prepared(session, fc)
        except PreloadNotInEquilibriumError as exc:
            v = path_variant(session.settings)[0]
            return no_preload_response(session, fc, w6, v, exc.residual)
        r = response_prepared(p, w6, session.settings, time.perf_counter())
        return replace(r, variant=v.value)

    def preload_error(self, session: SessionLike, command: object) -> PreloadNotInEquilibriumError | None:
        """Why the preload path of ``command`` does not reach its end (the error
        :func:`pinograsp.loading_path` raises: which stage stopped, where and why), or None."""
        try:
            _prepared(session, command)
        except PreloadNotInEquilibriumError as exc:
            return exc
        return None

    def max_load(self, session: SessionLike, query: LimitQuery) -> MaxWrench:
        """The limit load λ* of the path along ``query.direction`` (no bisection).

        Raises:
            SolverError: The path stopped without a verdict (status ``"no_solution"`` or
                ``"segment_limit"``; the load reached is in the message).
        """
        # quasistatic_max_wrench on the session's validated settings and direction, the
        # response labelled with the registry's variant
        v, p = _prepared(session, query.command)
        mw = max_wrench_prepared(
            p,
            unit_again(query.direction),
            session.settings,
            time.perf_counter(),
            label=v.value,
            upper=query.upper,
        )
        if mw.status in NO_VERDICT:
            raise SolverError(
                f"the quasi-static loading path stopped at load {mw.magnitude:.6g} without a verdict "
                f"({mw.status}: "
                + (
                    "the segment-count limit"
                    if mw.status == "segment_limit"
                    else "the local rate problem has no unique continuation"
                )
                + ("; " + mw.note if mw.note else "")
                + "); that load is a lower "
                "bound of the limit. pg.loading_path(model, command, direction) shows the path",
                solver="lemke",
                status=str(mw.status),
            )
        tally = query.tally
        note = mw.note or (
            session.model.free_motion_note(query.direction) if mw.status == "below_resolution" else ""
        )  # the searching methods' note: a load that drives a free motion of the object
        return replace(
            mw,
            note=note,
            solve_time=mw.solve_time + tally.solve_time,
            n_solves=mw.n_solves,  # the path's LCPs, its preload path's included (once)
            wall_time=time.perf_counter() - query.t0,
        )
