"""A scene's preload and its ``analysis`` block -> commands, :class:`SceneAnalysis` and
:class:`~pinograsp.core.settings.Settings` (docs/scenes.md).

Axis names, directions and planes are read with :mod:`pinograsp.core.axes`, commands are checked
by :meth:`~pinograsp.core.model.GraspModel.command_vector` and settings by
:func:`~pinograsp.core.settings.make_settings`; their errors become
:class:`~pinograsp.errors.SceneError` naming the key. No solver is imported.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..core.axes import WRENCH_AXES, plane_basis, wrench_direction
from ..core.methods import bounded as limits_bound
from ..core.methods import method_name, method_names
from ..core.model import GraspModel
from ..core.settings import DEFAULT_METHOD, Settings, make_settings
from ..core.validate import directions as n_directions
from ..core.validate import force
from ..core.validate import steps as n_steps
from ..errors import InvalidInputError, PinograspError, SolverNotAvailableError, UnknownNameError, plural
from .fields import SceneFile, show
from .schema import ANALYSIS_KEYS, ANGLE_SETTINGS_KEYS, SETTINGS_KEYS, Plane, SceneAnalysis

#: Settings written as text, as ``true``/``false`` and as counts (checked here for their YAML
#: type; every other setting is a number); :func:`make_settings` checks their values.
_TEXT_SETTINGS = ("solver", "variant", "backend", "complementarity", "limit")
#: Numbers that may be ``null`` (the default rule).
_OPTIONAL_SETTINGS = ("giveway_slip", "giveway_rotation", "giveway_joint")
_FLAG_SETTINGS = ("accelerate", "verify_infeasible")
_COUNT_SETTINGS = ("bigm_retries", "max_iterations", "max_nodes")


def command(f: SceneFile, model: GraspModel, value: object, key: str) -> dict[str, float]:
    """A command: a number (every actuator), a list over ``model.all_actuator_names`` or
    ``{actuator: value}`` (others 0) -> ``{actuator: value}`` over every actuator [N·m or N]."""
    names = model.all_actuator_names
    if isinstance(value, Mapping):
        given = {a: f.number(v, f"{key}.{a}") for a, v in value.items()}
    elif isinstance(value, Sequence) and not isinstance(value, (str, bytes)):
        # the file's list form covers every actuator, pruned ones included
        if len(value) != len(names):
            raise f.error(
                key,
                f"expected {plural('value', len(names))} (actuators {', '.join(names)}), got {len(value)}",
            )
        given = {a: f.number(v, f"{key}[{i}]") for i, (a, v) in enumerate(zip(names, value))}
    else:
        given = dict.fromkeys(names, f.number(value, key))
    try:
        model.command_vector(given)
    except UnknownNameError as exc:
        valid = ", ".join(map(str, exc.valid))
        raise f.error(f"{key}.{exc.name}", f"unknown actuator; actuators: {valid}") from exc
    except PinograspError as exc:
        raise f.error(key, str(exc)) from exc
    return {a: given.get(a, 0.0) for a in names}


def _wrench(f: SceneFile, model: GraspModel, value: object, key: str, unit: bool) -> np.ndarray:
    """A wrench (6,) [N, N·m] from an axis name (``"-fy"``) or a vector (6 numbers, or 3 for a
    planar model); ``unit``: a direction, scaled to unit length."""
    w = value.strip() if isinstance(value, str) else f.vector(value, (3, 6) if model.planar else 6, key)
    try:
        if unit or isinstance(w, str):
            return wrench_direction(model, w, key)
        return model.wrench_vector(w, key)
    except UnknownNameError as exc:
        raise f.error(key, f"unknown wrench axis {value!r}; axes: {', '.join(WRENCH_AXES)}") from exc
    except InvalidInputError as exc:
        raise f.error(key, str(exc).removeprefix(f"{exc.name}: ")) from exc


def _plane(f: SceneFile, model: GraspModel, value: object, key: str) -> Plane:
    """A plane: two axis names (a list, or ``"fx, fy"``) or vectors; vectors are kept as unit
    6-vectors."""
    if isinstance(value, str):
        value = [v.strip() for v in value.split(",")]
    if isinstance(value, (bytes, Mapping)) or not isinstance(value, Sequence) or len(value) != 2:
        raise f.error(key, f"expected two wrench axes (e.g. [fx, fy]) or two vectors, got {show(value)}")
    b = [_wrench(f, model, v, f"{key}[{i}]", unit=True) for i, v in enumerate(value)]
    try:
        plane_basis(model, b)
    except InvalidInputError as exc:
        raise f.error(key, str(exc).removeprefix(f"{exc.name}: ")) from exc
    kept = [v if isinstance(v, str) else tuple(float(x) for x in b[i]) for i, v in enumerate(value)]
    return kept[0], kept[1]


def _named(f: SceneFile, value: object, key: str, what: str) -> Mapping:
    """A mapping ``name -> what`` (``None``: empty)."""
    return f.mapping(value or {}, key, f"a mapping name -> {what}")


def _block(f: SceneFile, model: GraspModel, a: Mapping) -> SceneAnalysis:
    """The analysis keys of an ``analysis`` block (its settings aside)."""
    method = a.get("method", DEFAULT_METHOD)
    if not isinstance(method, str) or method not in method_names():
        raise f.error("analysis.method", f"must be one of {', '.join(method_names())}, got {method!r}")
    upper = f.domain(lambda k, v: force(k, v, "N or N·m"), a.get("upper", 1e3), "analysis.upper")
    bounded = limits_bound(method)  # an exact limit (the loading path) does not bisect: steps ignored
    steps = f.domain(lambda k, v: n_steps(v, k, bounded=bounded), a.get("steps", 20), "analysis.steps")
    n = f.domain(lambda k, v: n_directions(v, k), a.get("n", 72), "analysis.n")
    planes: dict[str, Plane] = {}
    if a.get("planes") is not None:
        pm = f.mapping(a["planes"], "analysis.planes", "a mapping name -> [axis, axis]")
        planes = {str(k): _plane(f, model, v, f"analysis.planes.{k}") for k, v in pm.items()}
    if a.get("plane") is not None:
        plane = _plane(f, model, a["plane"], "analysis.plane")
    else:
        plane = next(iter(planes.values())) if planes else ("fx", "fy")
    norm = a.get("normalize", None)
    if norm is not None and not isinstance(norm, bool):
        _wrench(f, model, norm, "analysis.normalize", unit=True)
    dirs = _named(f, a.get("directions"), "analysis.directions", "axis or vector")
    directions = {str(k): _wrench(f, model, v, f"analysis.directions.{k}", True) for k, v in dirs.items()}
    wr = _named(f, a.get("wrenches"), "analysis.wrenches", "wrench vector")
    wrenches = {str(k): _wrench(f, model, v, f"analysis.wrenches.{k}", False) for k, v in wr.items()}
    pre = _named(f, a.get("preloads"), "analysis.preloads", "command")
    return SceneAnalysis(
        method=method_name(method),
        upper=upper,
        steps=steps,
        n=n,
        plane=plane,
        planes=planes or {"default": plane},
        normalize=norm,
        directions=directions,
        wrenches=wrenches,
        preloads={str(k): command(f, model, v, f"analysis.preloads.{k}") for k, v in pre.items()},
    )


def _blamed_setting(exc: PinograspError) -> str:
    """The setting a :func:`make_settings` error is about, from the error's attributes."""
    if isinstance(exc, SolverNotAvailableError):
        return "solver"
    if isinstance(exc, (InvalidInputError, UnknownNameError)):
        return str(exc.name)
    return ""


def _angle_settings(f: SceneFile, a: Mapping) -> dict[str, float | None]:
    """The settings given in degrees (:data:`ANGLE_SETTINGS_KEYS`) as their fields in [rad];
    ``cone_tolerance_deg: null`` is ``None``."""
    out: dict[str, float | None] = {}
    for key, name in ANGLE_SETTINGS_KEYS.items():
        if key not in a:
            continue
        v = a[key]
        if v is None and name in ("cone_tolerance", "giveway_rotation", "giveway_joint"):
            out[name] = None
        else:
            out[name] = float(np.radians(f.number(v, f"analysis.{key}")))
    return out


def _settings(f: SceneFile, a: Mapping) -> Settings:
    """The solver settings of an ``analysis`` block (angles given in [deg] stored in [rad])."""
    overrides: dict[str, Any] = {k: a[k] for k in SETTINGS_KEYS if k in a}
    for k, v in overrides.items():
        if k in _TEXT_SETTINGS:
            if v is not None and not isinstance(v, str):
                raise f.error(f"analysis.{k}", f"expected a string, got {show(v)}")
        elif k in _FLAG_SETTINGS:
            f.boolean(v, f"analysis.{k}")
        elif k in _COUNT_SETTINGS:
            f.integer(v, f"analysis.{k}", minimum=0)
        elif k in _OPTIONAL_SETTINGS and v is None:
            continue
        else:
            overrides[k] = f.number(v, f"analysis.{k}")
    overrides.update(_angle_settings(f, a))
    try:
        return make_settings(**overrides)
    except PinograspError as exc:
        bad = _blamed_setting(exc)
        if bad not in overrides:
            raise f.error("analysis", str(exc)) from exc
        why = str(exc).removeprefix(f"{bad}: ")
        deg = {name: key for key, name in ANGLE_SETTINGS_KEYS.items()}.get(bad)
        if deg is not None:  # the file gave degrees: say so next to the [rad] rule
            why = f"{why.split(', got ')[0]}; got {a[deg]!r} deg"
            bad = deg
        raise f.error(f"analysis.{bad}", why) from exc


def analysis(f: SceneFile, model: GraspModel, value: object) -> tuple[SceneAnalysis, Settings]:
    """A scene's ``analysis`` block (``None``: every default)."""
    a = f.mapping(value if value is not None else {}, "analysis")
    f.keys(a, ANALYSIS_KEYS, "analysis")
    return _block(f, model, a), _settings(f, a)
