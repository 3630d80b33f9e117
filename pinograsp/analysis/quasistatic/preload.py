"""The preload as a path (QUASISTATIC.md, "The preload as a path").

* ``"held"`` (default, the simulation's ``preload="held"``): from the touching configuration
  the commands ramp ``f = s f_c``, ``s: 0 -> 1``, with the object held still and friction off
  (the model's friction is free inside the cone, not wound up by the closing); then friction
  is switched on with every anchor at the contact's current position (no tangential force
  stored) and the object is released: the holder's wrench is removed gradually, one more
  stage of the path, which must reach its end (else the preload is not an equilibrium).
* ``"settled"``: the object is free and friction is on while the commands ramp.

Both start from zero force, where the problem is positively homogeneous, so the closing is
usually one segment; the release can have events.
"""

from __future__ import annotations

import numpy as np

from ...core.axes import WRENCH_AXES
from ...errors import PreloadNotInEquilibriumError
from .model import QSModel
from .path import StageRun, follow
from .rates import EVENT_RTOL, StageSpec, State, force_scale

#: The preload variants.
PRELOAD_VARIANTS = ("held", "settled")


def zero_state(qm: QSModel) -> State:
    """The touching configuration without force."""
    return State(
        np.zeros(qm.nv),
        np.zeros(qm.ncd),
        np.zeros(qm.na),
        np.zeros(qm.ncp),
        np.zeros(qm.nx),
        np.zeros(qm.ncd),
    )


def _fail(
    fc: np.ndarray, stage: str, run: StageRun, residual: np.ndarray | None = None
) -> PreloadNotInEquilibriumError:
    """``residual``: the net wrench (6,) [N, N·m] the preload leaves on the held object."""
    st = run.states[-1]
    net = ""
    if residual is not None:
        shown = ", ".join(f"{a}={v:.3g}" for a, v in zip(WRENCH_AXES, residual) if abs(v) > 0)
        net = f"; net wrench left on the held object: {shown or '0'} [N, N·m]"
    return PreloadNotInEquilibriumError(
        fc.tolist(),
        f"quasi-static {stage} path stopped at {st.t:.6g} of the way ({run.status}: "
        + ("the grasp gives way under the preload" if run.status == "limit" else "no continuation")
        + ")"
        + net,
        residual,
    )


def preload_path(
    qm: QSModel, fc: np.ndarray, variant: str, max_segments: int
) -> tuple[State, list[StageRun]]:
    """The preloaded state (``t = 0``, ``slip = 0``) and the stages that led to it.

    Raises:
        PreloadNotInEquilibriumError: The closing or the release reaches a limit or finds no
            continuation before its end.
    """
    z = np.zeros(qm.nx)
    zero_a = np.zeros(qm.na)
    runs = []
    if variant == "settled":
        spec = StageSpec(z, z, zero_a, fc, 1.0, held=False, friction=True)
        run = follow(qm, zero_state(qm), spec, max_segments)
        runs.append(run)
        if run.status != "end":
            raise _fail(fc, "closing (settled)", run)
        st = run.states[-1].copy()
    else:
        spec = StageSpec(z, z, zero_a, fc, 1.0, held=True, friction=False)
        run = follow(qm, zero_state(qm), spec, max_segments)
        runs.append(run)
        if run.status != "end":
            raise _fail(fc, "closing (held)", run)
        st = run.states[-1].copy()
        wh = st.hold.copy()
        st.hold[:] = 0.0
        st.t = 0.0
        tol = EVENT_RTOL * force_scale(qm, st, StageSpec(z, z, fc, zero_a, 0.0, False, True))
        if np.abs(qm.w_scaled(wh)).max(initial=0.0) > tol:
            spec = StageSpec(wh, -wh, fc, zero_a, 1.0, held=False, friction=True)
            run = follow(qm, st, spec, max_segments)
            runs.append(run)
            if run.status != "end":  # the contacts' net wrench on the held object, unbalanced
                raise _fail(fc, "release", run, qm.model.expand_wrench(qm.model.G @ runs[0].states[-1].c))
            st = run.states[-1].copy()
    st.t = 0.0
    st.slip[:] = 0.0
    st.hold[:] = 0.0
    return st, runs
