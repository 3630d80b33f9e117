"""Simulate a scene's prediction: preload the grasp in MuJoCo, ramp a load, find the give-way.

:func:`simulate_max_wrench` is the public entry point (``pg.simulate_max_wrench``);
:func:`simulate_command` is what the ``pinograsp simulate`` command calls. The method, its
thresholds and their defaults are in docs/simulation.md.
"""

from __future__ import annotations

import math
import os
import time
from typing import Any

import numpy as np

from ..core.axes import wrench_direction, wrench_unit
from ..core.giveway import DEFAULT_CONTACT_STIFFNESS, giveway_thresholds
from ..core.model import GraspModel
from ..core.validate import force, load_within, number_in
from ..errors import InvalidInputError
from ..scenes.schema import Scene
from .integrator import FRICTIONS, PRELOADS, Engine, SimOptions, preload, ramp, refine
from .result import SimulationResult, SimulationStatus


def _inputs(
    scene_or_model: Scene | GraspModel, direction: object, command: object
) -> tuple[GraspModel, np.ndarray, np.ndarray, float]:
    """The GraspModel, unit direction (6,), command (na,) and default upper load of the inputs."""
    if isinstance(scene_or_model, GraspModel):
        grasp, upper = scene_or_model, 1e3
        if command is None:
            raise InvalidInputError("command", "a GraspModel needs a command (a scene has its preload)")
    elif isinstance(scene_or_model, Scene):
        scene = scene_or_model
        grasp, upper = scene.model, float(scene.analysis.upper)
        if command is None or isinstance(command, str):
            command = scene.preload(command)
        if isinstance(direction, str) and direction in scene.analysis.directions:
            direction = scene.direction(direction)
    else:
        raise InvalidInputError("scene_or_model", f"expected a Scene or a GraspModel, got {scene_or_model!r}")
    return grasp, wrench_direction(grasp, direction), grasp.command_vector(command), upper


def _scene_defaults(scene_or_model: Scene | GraspModel) -> dict[str, Any]:
    """A scene's contact stiffness and give-way thresholds (its analysis settings, the ones its
    analysis uses: docs/giveway.md) as simulation options; nothing for a bare model."""
    if not isinstance(scene_or_model, Scene):
        return {}
    settings = scene_or_model.settings
    out: dict[str, Any] = {"stiffness": settings.contact_stiffness}
    if settings.giveway_slip is not None:
        out["slip"] = settings.giveway_slip
    if settings.giveway_rotation is not None:
        out["rotation"] = settings.giveway_rotation
    return out


def _positive(name: str, value: object) -> float:
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(name, f"expected a positive number, got {value!r}") from exc
    if not (math.isfinite(v) and v > 0):
        raise InvalidInputError(name, f"expected a positive number, got {value!r}")
    return v


def _release_time(value: object) -> float:
    """``release_time`` [s] in ``[0, MAX_RELEASE_TIME]``, else an error stating the range and the choice."""
    try:
        return number_in("release_time", value, 0.0, MAX_RELEASE_TIME, "s")
    except InvalidInputError as exc:
        raise InvalidInputError(
            "release_time",
            f"must be a number of seconds in [0, {MAX_RELEASE_TIME:g}], got {value!r}: pass 0 (the default) "
            "to release the held object at once, or a duration such as 0.05 to remove its holding "
            "wrench smoothly (docs/simulation.md, 'The procedure')",
        ) from exc


def _finger_mass(value: object) -> float:
    """``finger_mass`` in :data:`SIM_FINGER_MASS`, else an error stating the range and the choice."""
    lo, hi = SIM_FINGER_MASS
    try:
        return number_in("finger_mass", repr(value) if isinstance(value, bool) else value, lo, hi, "")
    except InvalidInputError as exc:
        raise InvalidInputError(
            "finger_mass",
            f"must be a ratio in [{lo:g}, {hi:g}] (each finger's effective mass at its contacts over "
            f"the object's), got {value!r}: pass 1 (the default) or, e.g., 0.1 for fingers much "
            "lighter than the object (docs/simulation.md, 'Finger mass')",
        ) from exc


def _options(grasp: GraspModel, direction: np.ndarray, upper: float, kw: dict[str, Any]) -> SimOptions:
    """Defaults filled in and validated (docs/simulation.md, "Defaults")."""
    ell = float(grasp.length_scale)
    stiffness = number_in("stiffness", kw.pop("stiffness", DEFAULT_CONTACT_STIFFNESS), *SIM_STIFFNESS, "N/m")
    timestep = number_in("timestep", kw.pop("timestep", 1e-4), *SIM_TIMESTEP, "s")
    ramp = _positive("ramp_time", kw.pop("ramp_time", 0.02))
    # the give-way thresholds, shared with the analysis (core/giveway.py)
    slip, rotation = kw.pop("slip", None), kw.pop("rotation", None)
    slip = None if slip is None else _positive("slip", slip)
    rotation = None if rotation is None else _positive("rotation", rotation)
    slip, rotation = giveway_thresholds(ell, direction, upper, stiffness, slip, rotation)
    mass = kw.pop("mass", None)
    mass = 10.0 * grasp.nc * stiffness * timestep**2 if mass is None else _positive("mass", mass)
    preload = kw.pop("preload", "held")
    if preload not in PRELOADS:
        raise InvalidInputError("preload", f"expected one of {PRELOADS}, got {preload!r}")
    friction = kw.pop("friction", "cone")
    if friction not in FRICTIONS:
        raise InvalidInputError("friction", f"expected one of {FRICTIONS}, got {friction!r}")
    opts = SimOptions(
        upper=upper,
        stiffness=stiffness,
        timestep=timestep,
        ramp_time=ramp,
        start=_positive("start", kw.pop("start", 1e-6)),
        hold_time=_positive("hold_time", kw.pop("hold_time", 5.0 * ramp)),
        slip=slip,
        rotation=rotation,
        tolerance=number_in("tolerance", kw.pop("tolerance", 2e-3), *SIM_TOLERANCE, "(relative)"),
        mass=mass,
        damping=_positive("damping", kw.pop("damping", 0.7)),
        preload=preload,
        preload_time=_positive("preload_time", kw.pop("preload_time", 0.05)),
        trace_every=int(_positive("trace_every", kw.pop("trace_every", 10))),
        filter_time=float(kw.pop("filter_time", 2.0 * math.pi * math.sqrt(mass / stiffness))),
        relax=bool(kw.pop("relax", True)),
        friction=friction,
        release_time=_release_time(kw.pop("release_time", 0.0)),
        finger_mass=_finger_mass(kw.pop("finger_mass", 1.0)),
    )
    if kw:
        raise InvalidInputError("options", f"unknown simulation option(s) {sorted(kw)}")
    if not opts.start < 1.0:
        raise InvalidInputError("start", f"expected a fraction of upper below 1, got {opts.start!r}")
    _step_budget(opts)
    return opts


#: Simulation domains (docs/errors.md): the contact spring [N/m] (below 1 N/m a 1 N preload
#: deflects 1 m; above 1e10 the explicit step needs a mass below rounding), the time step [s]
#: (MuJoCo's stable range for the contact springs), the give-way resolution (relative), and the
#: largest number of integration steps of one run (preload, ramp, hold and refinement).
SIM_STIFFNESS = (1.0, 1e10)
#: Effective finger mass at the contacts as a multiple of the object's mass: below 0.1 the
#: fingers' contact oscillation outruns the default time step (semi-implicit Euler).
SIM_FINGER_MASS = (0.1, 100.0)
SIM_TIMESTEP = (1e-7, 1e-2)
SIM_TOLERANCE = (1e-6, 0.5)
MAX_SIM_STEPS = 10**7
#: Longest release of a held object [s]: 10 s at the default step is already 1e5 steps.
MAX_RELEASE_TIME = 10.0


def _step_budget(o: SimOptions) -> None:
    """Refuse, before any step, options whose run would take more than MAX_SIM_STEPS steps."""
    ramp = o.ramp_time * math.log(1.0 / o.start) + o.hold_time + o.preload_time + o.release_time
    halvings = math.ceil(math.log2(max(math.log(1.0 / o.start) / o.tolerance, 2.0)))
    n = ramp / o.timestep * (1 + halvings)
    if not n <= MAX_SIM_STEPS:
        raise InvalidInputError(
            "timestep",
            f"the run would take ~{n:.3g} integration steps (ramp_time, hold_time, preload_time, "
            f"start and tolerance at timestep {o.timestep:g} s), more than {MAX_SIM_STEPS:g}: "
            "raise timestep or tolerance, or shorten the ramp",
        )


def _upper(grasp: GraspModel, cmd: np.ndarray, d: np.ndarray, upper: object) -> float:
    """The largest load [N or N·m] along ``d``, in (0, MAX_FORCE] and within the grasp's force
    scale under ``cmd`` (docs/errors.md, "Input domains")."""
    up = force("upper", upper, "N or N·m")
    load_within(grasp, cmd, "upper", up * d)
    return up


#: The options a :class:`SimulationResult` records under their own names.
_RECORDED_OPTIONS = (
    *("upper", "start", "tolerance", "stiffness", "mass", "timestep", "ramp_time"),
    *("preload", "friction", "release_time", "finger_mass"),
)


def simulate_max_wrench(
    scene_or_model: Scene | GraspModel,
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
    The object gives way when it has moved ``slip`` or turned ``rotation`` from the preloaded
    pose; the reported load is the largest load the contacts resisted until then.

    Args:
        scene_or_model: A :class:`~pinograsp.Scene` (its preload, ``analysis.upper`` and named
            directions are used) or a :class:`~pinograsp.GraspModel`.
        direction: Axis name (``"fy"``, ``"-mx"``), a scene's named direction or a wrench
            vector, (6,) or (3,) for planar models; normalised with the Euclidean norm.
        command: Actuator commands [N·m or N] as for :func:`pinograsp.max_resistible_wrench`,
            or a scene's named preload; default the scene's preload (required for a model).
        upper: Largest load [N or N·m]; default the scene's ``analysis.upper``, else 1e3.
        **options: Numerical settings and thresholds, with their defaults in
            docs/simulation.md ("Thresholds and defaults"): ``stiffness``, ``timestep``,
            ``ramp_time``, ``start``, ``hold_time``, ``slip`` [m], ``rotation`` [rad],
            ``tolerance``, ``mass`` [kg], ``damping``, ``preload`` (``"held"``/``"settled"``),
            ``relax``, ``friction`` (``"cone"``/``"pyramid"``), ``preload_time``, ``release_time``
            [s], ``finger_mass`` (over the object's mass), ``filter_time``, ``trace_every``.

    Returns:
        The :class:`SimulationResult`.

    Raises:
        MissingDependencyError: MuJoCo is not installed.
        PreloadNotInEquilibriumError: The object moves past a threshold under the preload alone.
        InvalidInputError: A bad direction, command or option.
    """
    t0 = time.perf_counter()
    grasp, d, cmd, default_upper = _inputs(scene_or_model, direction, command)
    up = _upper(grasp, cmd, d, default_upper if upper is None else upper)
    opts = _options(grasp, d, up, {**_scene_defaults(scene_or_model), **options})
    run = Engine(grasp, cmd, opts)
    preload(run)
    found = ramp(run, d)
    status: SimulationStatus = "held"
    load, onset = None, found.onset
    evidence: list[tuple[float, bool]] = []
    if found.crossed:
        load, frac, evidence = refine(run, d, found)
        status = "gradual" if frac >= 0.1 else "gave_way"
        onset = None if onset is None else min(onset, load)
    return SimulationResult(
        status=status,
        load=load,
        onset_load=onset,
        applied_load=found.applied,
        direction=d,
        unit=wrench_unit(d),
        slip_threshold=opts.slip,
        rotation_threshold=opts.rotation,
        **{k: getattr(opts, k) for k in _RECORDED_OPTIONS},
        steps=run.steps,
        sim_time=run.steps * opts.timestep,
        wall_time=time.perf_counter() - t0,
        trace=found.trace,
        evidence=tuple(evidence),
        command=cmd,
    )


def simulate_command(
    scene: Any, direction: object, *, compare: bool = False, method: str | None = None, **opts: Any
) -> SimulationResult:
    """What ``pinograsp simulate SCENE -d DIRECTION`` runs (flags: docs/cli.md).

    Args:
        scene: A :class:`~pinograsp.Scene`, a built-in scene name or a scene YAML file.
        direction: As for :func:`simulate_max_wrench`.
        compare: Also run the scene's own analysis (``scene.max_resistible_wrench``) along the
            same direction, with the same command and upper load, and record it as
            ``predicted``.
        method: The analysis method of the comparison (``"quasistatic"``, ``"iterative"``,
            ``"energetic"`` or ``"prp"``); default the scene's ``analysis.method`` (the package
            default, ``"quasistatic"``, for every built-in scene).
        **opts: ``command`` and the keyword arguments of :func:`simulate_max_wrench`.

    Returns:
        The :class:`SimulationResult` (with ``predicted`` when ``compare``).
    """
    import dataclasses

    from ..scenes.loading import load_scene

    if isinstance(scene, (str, os.PathLike)):
        scene = load_scene(os.fspath(scene))
    command = opts.pop("command", None)
    result = simulate_max_wrench(scene, direction, command, **opts)
    if not compare:
        return result
    over = {} if method is None else {"method": method}
    pred = scene.max_resistible_wrench(result.direction, command, upper=result.upper, **over)
    return dataclasses.replace(result, predicted=float(pred.magnitude), predicted_status=str(pred.status))
