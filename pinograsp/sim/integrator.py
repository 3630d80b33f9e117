"""The simulation engine: preload the grasp, ramp the load, bracket and refine the give-way.

The procedure and its thresholds are in docs/simulation.md. A run is deterministic: the same
inputs give the same steps and the same numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import PreloadNotInEquilibriumError
from .contacts import ContactLaw, moment
from .mjcf import ReducedModel, build, import_mujoco
from .result import SimulationTrace

if TYPE_CHECKING:
    from ..core.model import GraspModel

PRELOADS = ("held", "settled")
FRICTIONS = ("cone", "pyramid")
#: Motion over the second half of a constant-load test, as a fraction of the threshold, above
#: which the object is still moving (has not come to rest).
CREEP = 1e-3
#: Longest hold at ``upper``, in ``hold_time`` periods: a grasp still creeping after it is not
#: reported as held (the give-way is then refined like a crossing).
MAX_HOLDS = 20


@dataclass(frozen=True)
class SimOptions:
    """Numerical settings of one simulation (defaults: docs/simulation.md).

    Attributes:
        upper: Largest applied load [N or N·m].
        stiffness: Stiffness of the stiffest contact [N/m].
        timestep: Integration step [s].
        ramp_time: e-folding time of the load ramp [s].
        start: First load of the ramp as a fraction of ``upper``.
        hold_time: Time the load stays at ``upper``, and each constant-load test lasts [s].
        slip: Give-way translation threshold [m].
        rotation: Give-way rotation threshold [rad].
        tolerance: Relative resolution of the give-way load.
        mass: Object mass [kg].
        damping: Damping ratio of the contacts, relative to the lighter of the object (``mass``)
            and a finger (``finger_mass * mass``).
        preload: ``"held"`` or ``"settled"``.
        preload_time: Duration of the preload phase (command ramp and settling) [s].
        trace_every: Steps between trace samples.
        filter_time: Time constant of the low-pass filter on the actuator displacement whose
            running maximum is the limit [s] (0: the raw displacement).
        relax: Close the motors without friction (the model's friction is free inside the
            cone, not wound up by the closing; docs/simulation.md).
        friction: ``"cone"`` (exact Coulomb) or ``"pyramid"`` (the model's linearised cone).
        release_time: Duration [s] over which a held object is released: the wrench that held
            it at the end of the closing is applied to it and removed smoothly (the loading
            path's release stage, docs/quasistatic.md); 0: released at once.
        finger_mass: Effective mass of each hand joint at its farthest contact, as a multiple
            of the object's ``mass`` (the joint's armature ``finger_mass * mass * reach**2``).
    """

    upper: float
    stiffness: float
    timestep: float
    ramp_time: float
    start: float
    hold_time: float
    slip: float
    rotation: float
    tolerance: float
    mass: float
    damping: float
    preload: str
    preload_time: float
    trace_every: int
    filter_time: float = 0.0
    relax: bool = True
    friction: str = "cone"
    release_time: float = 0.0
    finger_mass: float = 1.0


class Engine:
    """The state of one simulation: MuJoCo data, contact law, actuator limits."""

    def __init__(self, grasp: GraspModel, command: np.ndarray, opts: SimOptions) -> None:
        self.mj = import_mujoco()
        self.grasp, self.opts = grasp, opts
        # the damping ratio refers to the lighter of the two bodies a contact joins: referred to
        # the object, light fingers (finger_mass < 1) are overdamped past the explicit step's
        # stability and vibrate (docs/simulation.md, "Finger mass"); at finger_mass >= 1 it is the
        # object, as before
        lighter = opts.mass * min(1.0, opts.finger_mass)
        self.law = ContactLaw.from_model(
            grasp, opts.stiffness, opts.damping, lighter, pyramid=opts.friction == "pyramid"
        )
        reach = np.max(np.linalg.norm(self.law.jacobian, axis=1), axis=0)  # (nq,) [m/rad]
        # a joint kept only through a coupling (a motor driving mimics, core/build.py) moves no
        # contact: it gets the length scale, not a zero (massless, unstable) armature
        reach = np.where(reach > 0, reach, grasp.length_scale)
        inertia = opts.mass * grasp.length_scale**2
        self.red: ReducedModel = build(
            grasp,
            mass=opts.mass,
            inertia=inertia,
            armature=opts.finger_mass * opts.mass * reach**2,
            timestep=opts.timestep,
        )
        self.data = self.mj.MjData(self.red.model)
        self.command = command
        limited_actuators = [a for a, kind in enumerate(grasp.kinds) if kind == "non-backdrivable"]
        self.R_lim = np.asarray(grasp.R, dtype=float)[:, limited_actuators]  # (nq, nl)
        self.u_max = np.zeros(len(limited_actuators))
        self.u_slow = np.zeros(len(limited_actuators))  # low-passed actuator displacement
        self.blend = min(1.0, opts.timestep / opts.filter_time) if opts.filter_time > 0 else 1.0
        self.rest = self.data.qpos[:7].copy()
        self.steps = 0
        self.rot = np.eye(3)

    def _rotation(self) -> np.ndarray:
        out = np.empty(9)
        self.mj.mju_quat2Mat(out, self.data.qpos[3:7])
        return out.reshape(3, 3)

    def step(self, scale: float, load: np.ndarray) -> np.ndarray:
        """One step with the motors at ``scale`` × the command and ``load`` (6,) on the object;
        returns the contact wrench on the object about its reference point (6,) [N, N·m]."""
        d, red = self.data, self.red
        self.rot = rot = self._rotation()
        q, qd = d.qpos[red.hand_qpos], d.qvel[red.hand_dof]
        f, arms, _ = self.law.forces(q, qd, d.qpos[:3] - self.rest[:3], rot, d.qvel[:3], rot @ d.qvel[3:6])
        wrench = np.concatenate([f.sum(axis=0), moment(arms, f)])
        d.xfrc_applied[red.object_body] = wrench + load
        d.qfrc_applied[red.hand_dof] = -np.einsum("iaj,ia->j", self.law.jacobian, f)
        d.ctrl[:] = scale * self.command[red.motors]
        self.mj.mj_step(red.model, d)
        self.steps += 1
        if self.u_max.size:
            self.u_slow += self.blend * (self.R_lim.T @ d.qpos[red.hand_qpos] - self.u_slow)
            self.u_max = np.maximum(self.u_max, self.u_slow)
            red.model.tendon_range[red.limited, 0] = self.u_max
        return wrench

    def hold_object(self) -> None:
        """Put the object back at rest (the held preload)."""
        self.data.qpos[:7] = self.rest
        self.data.qvel[:6] = 0.0

    def displacement(self, pos0: np.ndarray, rot0: np.ndarray) -> tuple[float, float]:
        """Translation [m] and rotation angle [rad] of the object from ``(pos0, rot0)``."""
        rel = self.rot @ rot0.T
        cos = min(1.0, max(-1.0, (np.trace(rel) - 1.0) / 2.0))
        return float(np.linalg.norm(self.data.qpos[:3] - pos0)), math.acos(cos)

    def snapshot(self) -> tuple[np.ndarray, ...]:
        """The state a test restarts from: positions, velocities, anchors, actuator limits."""
        d = self.data
        law = self.law
        limits = (self.u_max.copy(), self.u_slow.copy())
        return (d.qpos.copy(), d.qvel.copy(), d.qacc_warmstart.copy(), law.anchors.copy(), *limits)

    def restore(self, state: tuple[np.ndarray, ...]) -> None:
        """Go back to a :meth:`snapshot`."""
        d = self.data
        d.qpos[:], d.qvel[:], d.qacc_warmstart[:] = state[0], state[1], state[2]
        self.law.anchors, self.u_max, self.u_slow = state[3].copy(), state[4].copy(), state[5].copy()
        if self.u_max.size:
            self.red.model.tendon_range[self.red.limited, 0] = self.u_max
        self.rot = self._rotation()


def preload(run: Engine) -> None:
    """Close the motors (smooth ramp over half of ``preload_time``, then steady; without
    friction when ``relax``), release the object when it was held (at once, or over
    ``release_time`` with the holding wrench removed smoothly), settle for half of
    ``preload_time`` with friction and check that the preload alone holds the object."""
    o = run.opts
    n = max(2, round(o.preload_time / o.timestep))
    zero = np.zeros(6)
    held = zero
    for i in range(n):
        s = min(1.0, 2.0 * i / n)
        run.law.relax = o.relax
        held = -run.step(s * s * (3.0 - 2.0 * s), zero)
        if o.preload == "held":
            run.hold_object()
    run.law.relax = o.relax
    if o.preload == "held" and o.release_time > 0.0:  # the holding wrench removed smoothly
        m = max(1, round(o.release_time / o.timestep))
        for i in range(1, m + 1):
            s = i / m
            run.step(1.0, held * (1.0 - s * s * (3.0 - 2.0 * s)))
    for _ in range(n // 2):
        run.step(1.0, zero)
    moved, turned = run.displacement(run.rest[:3], np.eye(3))
    if moved > o.slip or turned > o.rotation:
        raise PreloadNotInEquilibriumError(
            run.command.tolist(),
            f"in simulation the object moved {moved * 1e3:.3g} mm and turned {math.degrees(turned):.3g}° "
            f"under the preload alone (thresholds {o.slip * 1e3:.3g} mm, {math.degrees(o.rotation):.3g}°)",
        )


@dataclass
class Ramp:
    """What the load ramp found.

    Attributes:
        crossed: Whether the object moved past a threshold.
        applied: Applied load when the ramp stopped [N or N·m].
        onset: Applied load when the object had first moved a tenth of a threshold, or None.
        trace: Samples of the ramp.
        snapshots: ``(load, state)`` taken at loads 5 % apart before stepping at that load.
        pose: Preloaded position (3,) [m] and orientation (3, 3) of the object.
    """

    crossed: bool
    applied: float
    onset: float | None
    trace: SimulationTrace
    snapshots: list[tuple[float, tuple[np.ndarray, ...]]]
    pose: tuple[np.ndarray, np.ndarray]


def moved(run: Engine, pose: tuple[np.ndarray, np.ndarray]) -> float:
    """Displacement from ``pose`` as a fraction of its threshold (the larger of translation
    and rotation); 1 means the object gave way."""
    shift, turn = run.displacement(*pose)
    return max(shift / run.opts.slip, turn / run.opts.rotation)


def ramp(run: Engine, direction: np.ndarray, spacing: float = 0.05) -> Ramp:
    """Ramp the load exponentially up to ``upper``, hold it for ``hold_time``; stop when the
    object moves past a threshold."""
    o = run.opts
    pose = (run.data.qpos[:3].copy(), run.rot.copy())
    n_ramp = math.ceil(o.ramp_time * math.log(1.0 / o.start) / o.timestep)
    n_total = n_ramp + math.ceil(o.hold_time / o.timestep)
    samples: list[tuple[float, ...]] = []
    snapshots: list[tuple[float, tuple[np.ndarray, ...]]] = []
    onset, applied, crossed, next_snap = None, 0.0, False, 0.0
    for i in range(n_total):
        applied = o.upper * min(1.0, o.start * math.exp(i * o.timestep / o.ramp_time))
        if applied >= next_snap and applied < o.upper:
            snapshots.append((applied, run.snapshot()))
            next_snap = applied * (1.0 + spacing)
        wrench = run.step(1.0, applied * direction)
        frac = moved(run, pose)
        if onset is None and frac >= 0.1:
            onset = applied
        if i % o.trace_every == 0 or frac >= 1.0:
            samples.append((i * o.timestep, applied, -float(direction @ wrench), *run.displacement(*pose)))
        if frac >= 1.0:
            crossed = True
            break
    if not crossed:
        crossed = not settles(run, direction * applied, pose)
    trace = SimulationTrace(*np.array(samples, dtype=float).reshape(-1, 5).T)
    return Ramp(crossed, applied, onset, trace, snapshots, pose)


def settles(run: Engine, wrench: np.ndarray, pose: tuple) -> bool:
    """Hold ``wrench`` for up to :data:`MAX_HOLDS` periods of ``hold_time`` until the object comes
    to rest (it moves less than :data:`CREEP` of a threshold in one period). False when it crosses
    a threshold or still creeps at the end: a creeping grasp is never reported as held."""
    n_hold = math.ceil(run.opts.hold_time / run.opts.timestep)
    before = moved(run, pose)
    for _ in range(MAX_HOLDS):
        for _ in range(n_hold):
            run.step(1.0, wrench)
        now = moved(run, pose)
        if now >= 1.0:
            return False
        if now - before <= CREEP:
            return True
        before = now
    return False


def holds(
    run: Engine, direction: np.ndarray, start: tuple[float, tuple[np.ndarray, ...]], load: float, pose: tuple
) -> tuple[bool, float]:
    """From a snapshot taken at load ``start[0]``, ramp to ``load`` at the ramp's rate and hold it
    for ``hold_time``. Held when the object stays within the thresholds and has come to rest
    (it moved less than 1e-3 of a threshold over the second half of the hold).

    Returns:
        Whether it held, and the final displacement as a fraction of its threshold.
    """
    o = run.opts
    load0, state = start
    run.restore(state)
    n_up = math.ceil(o.ramp_time * math.log(max(load / load0, 1.0)) / o.timestep)
    n_hold = math.ceil(o.hold_time / o.timestep)
    half = frac = 0.0
    for i in range(n_up + n_hold):
        run.step(1.0, min(load, load0 * math.exp((i + 1) * o.timestep / o.ramp_time)) * direction)
        frac = moved(run, pose)
        if frac >= 1.0:
            return False, frac
        if i == n_up + n_hold // 2:
            half = frac
    return frac - half <= CREEP, frac


def refine(run: Engine, direction: np.ndarray, found: Ramp) -> tuple[float, float, list[tuple[float, bool]]]:
    """The largest load held at rest (:func:`holds`), to ``tolerance``, below the ramp's crossing.

    Gallops down the snapshots from the crossing (1, 2, 4, ... back) to the first that holds
    its own load, bisects the snapshots, then bisects the load (geometric means) from the last
    snapshot that holds. Assumes that holding is monotone along the ray.

    Returns:
        The load [N or N·m] (0 when not even the ramp's first load holds), its displacement as a
        fraction of the threshold, and every test ``(load, held)`` in order.
    """
    snaps, evidence = found.snapshots, []
    lo, hi, frac_lo, step = len(snaps) - 1, len(snaps), 0.0, 1
    while lo >= 0:
        ok, frac = holds(run, direction, snaps[lo], snaps[lo][0], found.pose)
        evidence.append((snaps[lo][0], ok))
        if ok:
            frac_lo = frac
            break
        hi, lo, step = lo, lo - step, 2 * step
    if lo < 0:
        return 0.0, 0.0, evidence
    while hi - lo > 1:
        mid = (lo + hi) // 2
        ok, frac = holds(run, direction, snaps[mid], snaps[mid][0], found.pose)
        evidence.append((snaps[mid][0], ok))
        lo, hi, frac_lo = (mid, hi, frac) if ok else (lo, mid, frac_lo)
    a, b = snaps[lo][0], snaps[hi][0] if hi < len(snaps) else found.applied
    while b / a - 1.0 > run.opts.tolerance:
        m = math.sqrt(a * b)
        ok, frac = holds(run, direction, snaps[lo], m, found.pose)
        evidence.append((m, ok))
        a, b, frac_lo = (m, b, frac) if ok else (a, m, frac_lo)
    return a, frac_lo, evidence
