"""Simulate a scene's prediction: preload the grasp in MuJoCo, ramp a load, find the give-way.

:func:`simulate_max_wrench` is the public entry point (``pg.simulate_max_wrench``);
:func:`simulate_command` is what the ``pinograsp simulate`` command calls. The method, its
thresholds and their defaults are in docs/simulation.md.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InvalidInputError, PreloadNotInEquilibriumError
from .contacts import ContactLaw
from .mjcf import ReducedModel, build, import_mujoco
from .result import SimulationResult, SimulationTrace

PRELOADS = ("held", "settled")


@dataclass(frozen=True)
class SimOptions:
    """Numerical settings of one simulation (defaults: docs/simulation.md).

    Attributes:
        upper: Largest applied load [N or N·m].
        stiffness: Stiffness of the stiffest contact [N/m].
        timestep: Integration step [s].
        ramp_time: e-folding time of the load ramp [s].
        start: First load of the ramp as a fraction of ``upper``.
        hold_time: Time the load stays at ``upper`` [s].
        slip: Give-way translation threshold [m].
        rotation: Give-way rotation threshold [rad].
        gradual: ``load / onset_load`` above which a give-way is ``"gradual"``.
        mass: Object mass [kg].
        damping: Damping ratio of the contacts.
        preload: ``"held"`` or ``"settled"``.
        preload_time: Duration of the preload phase (command ramp and settling) [s].
        trace_every: Steps between trace samples.
    """

    upper: float
    stiffness: float
    timestep: float
    ramp_time: float
    start: float
    hold_time: float
    slip: float
    rotation: float
    gradual: float
    mass: float
    damping: float
    preload: str
    preload_time: float
    trace_every: int


class _Run:
    """The state of one simulation: MuJoCo data, contact law, actuator limits."""

    def __init__(self, grasp: Any, command: np.ndarray, opts: SimOptions) -> None:
        self.mj = import_mujoco()
        self.grasp, self.opts = grasp, opts
        self.law = ContactLaw.from_model(grasp, opts.stiffness, opts.damping, opts.mass)
        reach = np.max(np.linalg.norm(self.law.jacobian, axis=1), axis=0)  # (nq,) [m/rad]
        inertia = opts.mass * grasp.length_scale**2
        self.red: ReducedModel = build(
            grasp, mass=opts.mass, inertia=inertia, armature=opts.mass * reach**2, timestep=opts.timestep
        )
        self.data = self.mj.MjData(self.red.model)
        self.command = command
        limited_actuators = [a for a, kind in enumerate(grasp.kinds) if kind == "non-backdrivable"]
        self.R_lim = np.asarray(grasp.R, dtype=float)[:, limited_actuators]  # (nq, nl)
        self.u_max = np.zeros(len(limited_actuators))
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
        wrench = np.concatenate([f.sum(axis=0), np.cross(arms, f).sum(axis=0)])
        d.xfrc_applied[red.object_body] = wrench + load
        d.qfrc_applied[red.hand_dof] = -np.einsum("iaj,ia->j", self.law.jacobian, f)
        d.ctrl[:] = scale * self.command[red.motors]
        self.mj.mj_step(red.model, d)
        self.steps += 1
        if self.u_max.size:
            self.u_max = np.maximum(self.u_max, self.R_lim.T @ d.qpos[red.hand_qpos])
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


def _preload(run: _Run) -> None:
    """Close the motors (smooth ramp over half of ``preload_time``), settle, release the object
    when it was held and check that the preload alone holds it."""
    o = run.opts
    n = max(2, round(o.preload_time / o.timestep))
    zero = np.zeros(6)
    for i in range(n):
        s = min(1.0, 2.0 * i / n)
        run.step(s * s * (3.0 - 2.0 * s), zero)
        if o.preload == "held":
            run.hold_object()
    for _ in range(n // 2):
        run.step(1.0, zero)
    moved, turned = run.displacement(run.rest[:3], np.eye(3))
    if moved > o.slip or turned > o.rotation:
        raise PreloadNotInEquilibriumError(
            run.command.tolist(),
            f"in simulation the object moved {moved * 1e3:.3g} mm and turned {math.degrees(turned):.3g}° "
            f"under the preload alone (thresholds {o.slip * 1e3:.3g} mm, {math.degrees(o.rotation):.3g}°)",
        )


def _load(run: _Run, direction: np.ndarray) -> dict[str, Any]:
    """Ramp the load exponentially up to ``upper``, hold it, stop when the object gives way."""
    o = run.opts
    pos0, rot0 = run.data.qpos[:3].copy(), run.rot.copy()
    n_ramp = math.ceil(o.ramp_time * math.log(1.0 / o.start) / o.timestep)
    n_total = n_ramp + math.ceil(o.hold_time / o.timestep)
    samples: list[tuple[float, ...]] = []
    best, onset, applied, crossed = 0.0, None, 0.0, False
    for i in range(n_total):
        applied = o.upper * min(1.0, o.start * math.exp(i * o.timestep / o.ramp_time))
        wrench = run.step(1.0, applied * direction)
        best = max(best, -float(direction @ wrench))
        moved, turned = run.displacement(pos0, rot0)
        frac = max(moved / o.slip, turned / o.rotation)
        if onset is None and frac >= 0.1:
            onset = best
        if i % o.trace_every == 0 or frac >= 1.0:
            samples.append((i * o.timestep, applied, -float(direction @ wrench), moved, turned))
        if frac >= 1.0:
            crossed = True
            break
    cols = np.array(samples, dtype=float).reshape(-1, 5).T
    trace = SimulationTrace(*cols)
    if not crossed:
        return {"status": "held", "load": None, "onset_load": onset, "applied_load": applied, "trace": trace}
    gradual = onset is not None and onset > 0 and best / onset > o.gradual
    status = "gradual" if gradual else "gave_way"
    return {"status": status, "load": best, "onset_load": onset, "applied_load": applied, "trace": trace}


def _unit(direction: np.ndarray) -> str:
    force, torque = np.linalg.norm(direction[:3]) > 1e-12, np.linalg.norm(direction[3:]) > 1e-12
    return "N" if not torque else ("N·m" if not force else "N, N·m")


def _inputs(
    scene_or_model: Any, direction: object, command: object
) -> tuple[Any, np.ndarray, np.ndarray, float]:
    """The GraspModel, unit direction (6,), command (na,) and default upper load of the inputs."""
    import pinograsp as pg

    if isinstance(scene_or_model, pg.GraspModel):
        grasp, upper = scene_or_model, 1e3
        if command is None:
            raise InvalidInputError("command", "a GraspModel needs a command (a scene has its preload)")
    elif hasattr(scene_or_model, "model") and hasattr(scene_or_model, "analysis"):
        scene = scene_or_model
        grasp, upper = scene.model, float(scene.analysis.upper)
        if command is None or isinstance(command, str):
            command = scene.preload(command)
        if isinstance(direction, str) and direction in scene.analysis.directions:
            direction = scene.direction(direction)
    else:
        raise InvalidInputError("scene_or_model", f"expected a Scene or a GraspModel, got {scene_or_model!r}")
    return grasp, pg.wrench_direction(grasp, direction), grasp.command_vector(command), upper


def _positive(name: str, value: object) -> float:
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(name, f"expected a positive number, got {value!r}") from exc
    if not (math.isfinite(v) and v > 0):
        raise InvalidInputError(name, f"expected a positive number, got {value!r}")
    return v


def _options(grasp: Any, direction: np.ndarray, upper: float, kw: dict[str, Any]) -> SimOptions:
    """Defaults filled in and validated (docs/simulation.md, "Defaults")."""
    ell = float(grasp.length_scale)
    stiffness = _positive("stiffness", kw.pop("stiffness", 1e6))
    timestep = _positive("timestep", kw.pop("timestep", 1e-4))
    ramp = _positive("ramp_time", kw.pop("ramp_time", 0.02))
    # elastic deflection of one contact spring at the upper load (torques as forces at ell)
    elastic = upper * (np.linalg.norm(direction[:3]) + np.linalg.norm(direction[3:]) / ell) / stiffness
    slip = kw.pop("slip", None)
    slip = max(1e-3, 20.0 * elastic) if slip is None else _positive("slip", slip)
    rotation = kw.pop("rotation", None)
    mass = kw.pop("mass", None)
    preload = kw.pop("preload", "held")
    if preload not in PRELOADS:
        raise InvalidInputError("preload", f"expected one of {PRELOADS}, got {preload!r}")
    opts = SimOptions(
        upper=upper,
        stiffness=stiffness,
        timestep=timestep,
        ramp_time=ramp,
        start=_positive("start", kw.pop("start", 1e-6)),
        hold_time=_positive("hold_time", kw.pop("hold_time", 5.0 * ramp)),
        slip=slip,
        rotation=slip / ell if rotation is None else _positive("rotation", rotation),
        gradual=_positive("gradual", kw.pop("gradual", 1.2)),
        mass=10.0 * grasp.nc * stiffness * timestep**2 if mass is None else _positive("mass", mass),
        damping=_positive("damping", kw.pop("damping", 0.7)),
        preload=preload,
        preload_time=_positive("preload_time", kw.pop("preload_time", 0.05)),
        trace_every=int(_positive("trace_every", kw.pop("trace_every", 10))),
    )
    if kw:
        raise InvalidInputError("options", f"unknown simulation option(s) {sorted(kw)}")
    if not opts.start < 1.0:
        raise InvalidInputError("start", f"expected a fraction of upper below 1, got {opts.start!r}")
    return opts


def simulate_max_wrench(
    scene_or_model: Any,
    direction: object,
    command: object = None,
    *,
    upper: float | None = None,
    **options: Any,
) -> SimulationResult:
    """Simulate the preloaded grasp in MuJoCo and ramp a load until the object gives way.

    The reduced model (docs/simulation.md): hand joints and the free object, linearised contact
    kinematics ``J`` and ``G``, non-backdrivable actuators as motors with a one-sided limit at
    their running maximum closing displacement, push-only normal springs and exact Coulomb
    friction. The motors close on the object (held still by default) and settle; then the load
    ``L d`` grows as ``upper * start * exp(t / ramp_time)`` up to ``upper`` and is held there.
    The object gives way when its reference point has moved ``slip`` or it has turned
    ``rotation`` from the preloaded pose; the reported load is the largest load the contacts
    resisted until then.

    Args:
        scene_or_model: A :class:`~pinograsp.Scene` (its preload, ``analysis.upper`` and named
            directions are used) or a :class:`~pinograsp.GraspModel`.
        direction: Axis name (``"fy"``, ``"-mx"``), a scene's named direction or a wrench
            vector, (6,) or (3,) for planar models; normalised with the Euclidean norm.
        command: Actuator commands [N·m or N] as for :func:`pinograsp.max_resistible_wrench`,
            or a scene's named preload; default the scene's preload (required for a model).
        upper: Largest load [N or N·m]; default the scene's ``analysis.upper``, else 1e3.
        **options: ``stiffness`` (1e6 N/m), ``timestep`` (1e-4 s), ``ramp_time`` (0.02 s),
            ``start`` (1e-6), ``hold_time`` (5 ramp times), ``slip`` [m] (1 mm, or 20 × one
            contact's elastic deflection at ``upper`` if larger), ``rotation`` [rad]
            (``slip / length_scale``), ``gradual`` (1.2), ``mass`` [kg]
            (``10 nc stiffness timestep²``), ``damping`` (0.7), ``preload`` (``"held"`` or
            ``"settled"``), ``preload_time`` (0.05 s), ``trace_every`` (10).

    Returns:
        The :class:`SimulationResult`.

    Raises:
        MissingDependencyError: MuJoCo is not installed.
        PreloadNotInEquilibriumError: The object moves past a threshold under the preload alone.
        InvalidInputError: A bad direction, command or option.
    """
    t0 = time.perf_counter()
    grasp, d, cmd, default_upper = _inputs(scene_or_model, direction, command)
    up = default_upper if upper is None else _positive("upper", upper)
    opts = _options(grasp, d, up, dict(options))
    run = _Run(grasp, cmd, opts)
    _preload(run)
    out = _load(run, d)
    return SimulationResult(
        **out,
        direction=d,
        unit=_unit(d),
        upper=opts.upper,
        slip_threshold=opts.slip,
        rotation_threshold=opts.rotation,
        gradual_ratio=opts.gradual,
        stiffness=opts.stiffness,
        mass=opts.mass,
        timestep=opts.timestep,
        ramp_time=opts.ramp_time,
        preload=opts.preload,
        steps=run.steps,
        sim_time=run.steps * opts.timestep,
        wall_time=time.perf_counter() - t0,
        command=cmd,
    )


def simulate_command(
    scene_name: str, direction: object, *, compare: bool = False, **opts: Any
) -> SimulationResult:
    """What ``pinograsp simulate SCENE -d DIRECTION`` runs (flags: docs/simulation.md).

    Args:
        scene_name: A built-in scene name or a scene YAML file.
        direction: As for :func:`simulate_max_wrench`.
        compare: Also run the scene's own analysis (``scene.max_resistible_wrench``) along the
            same direction and command, and record it as ``predicted``.
        **opts: ``command`` and the keyword arguments of :func:`simulate_max_wrench`.

    Returns:
        The :class:`SimulationResult` (with ``predicted`` when ``compare``).
    """
    import dataclasses

    import pinograsp as pg

    scene = pg.load_scene(scene_name)
    command = opts.pop("command", None)
    result = simulate_max_wrench(scene, direction, command, **opts)
    if not compare:
        return result
    pred = scene.max_resistible_wrench(result.direction, command, upper=result.upper)
    return dataclasses.replace(result, predicted=float(pred.magnitude), predicted_status=str(pred.status))
