"""``pinograsp simulate``: the MuJoCo cross-check of a scene's prediction (docs/cli.md,
docs/simulation.md). MuJoCo and the simulation layer load inside the command."""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from ..core.serialize import vector_text
from . import options as opt
from .report import Output, preload_line, scene_header, scene_line

#: ``--flag`` -> keyword of :func:`pinograsp.simulate_max_wrench` (passed when given).
_SIM_OPTIONS = (
    "stiffness",
    "timestep",
    "ramp_time",
    "release_time",
    "finger_mass",
    "slip",
    "rotation",
    "tolerance",
    "friction",
)


def _sim_options(args: argparse.Namespace) -> dict[str, Any]:
    """The simulation options given on the command line (the API's defaults otherwise)."""
    kw = {k: getattr(args, k) for k in _SIM_OPTIONS if getattr(args, k) is not None}
    if args.settled:
        kw["preload"] = "settled"
    return kw


def _to_resolution(value: float, resolution: float) -> str:
    """``value`` with as many decimals as ``resolution`` resolves (at most 6)."""
    if not resolution > 0:
        return f"{value:.4g}"
    return f"{value:.{min(6, max(0, math.ceil(-math.log10(resolution))))}f}"


def _preload_text(r: Any) -> str:
    """How the preload was applied: held or settled, and how a held object was released."""
    if r.preload != "held":
        return f"{r.preload} preload"
    return "held preload released " + (f"over {r.release_time:g} s" if r.release_time > 0 else "at once")


def give_way_text(r: Any) -> str:
    """The simulated give-way load in words, by status [N or N·m]."""
    u = r.unit
    if r.status == "held":
        return f"none: held up to the upper load {r.upper:g} {u}"
    if r.load == 0.0:
        return f"< {r.upper * r.start:.3g} {u} (gave way under the first load of the ramp)"
    res = r.tolerance * r.load
    load = f"{_to_resolution(r.load, res)} {u} (resolution {res:.2g} {u})"
    if r.status == "gradual":
        return f"gradual, from {r.onset_load:.4g} to {load}: no sharp break"
    return load


def prediction_text(r: Any, method: str) -> str:
    """The prediction, its status and the relative difference to the simulation."""
    u = r.unit
    if r.predicted_status == "unbounded":
        pred = "unbounded"
    elif r.predicted_status == "above_limit":
        pred = f">= {r.upper:g} {u} (above_limit)"
    else:
        pred = f"{r.predicted:.4g} {u} ({r.predicted_status})"
    same = "agrees" if r.same_class else "DIFFERS"
    text = f"predicted ({method}): {pred}; class {same}"
    if r.agreement is not None:
        text += f"; simulated / predicted - 1 = {100 * r.agreement:+.2f} %"
    return text


def cmd_simulate(args: argparse.Namespace) -> int:
    """``pinograsp simulate SCENE -d D``: simulate the preloaded grasp in MuJoCo and ramp a load
    along D until the object gives way (with ``--compare``, next to the prediction)."""
    from ..sim.mjcf import import_mujoco
    from ..sim.simulate import simulate_command

    import_mujoco()  # MissingDependencyError naming pinograsp[mujoco], before the scene loads
    scene = opt.load_scene(args.scene)
    out = Output(args)
    command, preload_name = opt.preload(args, scene)
    direction, label = opt.parse_direction(scene, args.direction)
    method = opt.method(args, scene)
    r = simulate_command(
        scene, direction, compare=args.compare, method=method, command=command, upper=args.upper,
        **_sim_options(args),
    )  # fmt: skip
    data = {
        **scene_header(scene),
        "preload_name": preload_name,
        "label": label,
        "method": method if args.compare else None,
        "actuators": list(scene.model.actuator_names),
        **r.to_dict(),
    }
    lines = [
        scene_line(scene),
        preload_line(command, preload_name),
        f"direction: {label} = {vector_text(r.direction)}; upper {r.upper:g} {r.unit}",
        f"simulation: contact stiffness {r.stiffness:g} N/m, {r.friction} friction, step {r.timestep:g} s, "
        f"ramp time {r.ramp_time:g} s, {_preload_text(r)}, finger mass {r.finger_mass:g} x the object's "
        f"{r.mass:.3g} kg",
        "",
        f"status: {r.status}",
        f"give-way load: {give_way_text(r)}",
    ]
    if r.predicted_status is not None:
        lines.append(prediction_text(r, method))
    lines += [
        "",
        f"thresholds: {r.slip_threshold * 1e3:.3g} mm, {np.degrees(r.rotation_threshold):.3g}°; {r.steps} "
        f"steps ({r.sim_time:.2f} s simulated), {r.wall_time:.2f} s wall",
    ]
    out.print(*lines)
    out.finish(data)
    return 0
