"""From option values to the arguments of the Python API: the scene, its preload, method,
search limits and settings, and the text syntax of ``--wrench``, ``--direction`` and ``--plane``
(docs/cli.md, "Argument syntax").

Only the text is split here; axis names and vectors are checked by :mod:`pinograsp.core.axes`
and :meth:`pinograsp.GraspModel.wrench_vector`, names by the scene.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

import pinograsp as pg

from ..core.axes import WRENCH_AXES, axis_index
from ..core.methods import bounded as limits_bound
from ..core.settings import Settings, make_settings
from ..core.validate import MAX_FORCE, MAX_STEPS
from ..errors import InvalidInputError, PinograspError, UnknownNameError


def load_scene(name_or_path: str) -> Any:
    """A built-in scene by name or a scene YAML file (:func:`pinograsp.load_scene`)."""
    return pg.load_scene(name_or_path)


def method(args: argparse.Namespace, scene: Any) -> str:
    """``--method``, or the scene's ``analysis.method``."""
    return args.method or scene.analysis.method


def query(args: argparse.Namespace, scene: Any, default_steps: int | None = None) -> Any:
    """The :class:`pinograsp.Query` of ``--method``, ``--upper`` and ``--steps`` (each defaulting
    to the scene's analysis block; ``default_steps`` before the scene's steps)."""
    upper, steps = upper_steps(args, scene, default_steps)
    return pg.Query(pg.Method(method(args, scene)), upper, steps)


def upper_steps(args: argparse.Namespace, scene: Any, default_steps: int | None = None) -> tuple[float, int]:
    """``--upper`` [N or N·m] and ``--steps``, defaulting to ``default_steps`` or the scene's
    (``--steps`` is not bounded by ``MAX_STEPS`` for a loading-path method, which ignores it)."""
    upper = args.upper if args.upper is not None else float(scene.analysis.upper)
    if args.steps is not None:
        steps = args.steps
    elif default_steps is not None:
        steps = default_steps
    else:
        steps = int(scene.analysis.steps)
    if not (math.isfinite(upper) and 0 < upper <= MAX_FORCE):  # domains: docs/errors.md
        raise InvalidInputError("--upper", f"must be in (0, {MAX_FORCE:g}] [N or N·m], got {upper!r}")
    if not limits_bound(method(args, scene)):  # an exact limit (the path) does not bisect: steps ignored
        if steps < 1:
            raise InvalidInputError("--steps", f"must be an integer >= 1, got {steps}")
    elif not 1 <= steps <= MAX_STEPS:
        raise InvalidInputError("--steps", f"must be an integer in [1, {MAX_STEPS}], got {steps}")
    return upper, steps


#: Settings given in degrees on the command line: field of :class:`Settings` [rad] -> option.
ANGLE_OPTIONS = {"normal_uncertainty": "--normal-uncertainty", "cone_tolerance": "--cone-tolerance"}


def settings(args: argparse.Namespace, scene: Any) -> Settings:
    """The scene's settings with ``--solver``, ``--time-limit``, ``--variant``,
    ``--tangential-ratio``, ``--contact-stiffness``, ``--limit`` and the angles
    ``--normal-uncertainty`` / ``--cone-tolerance`` (given in [deg], stored in [rad]) applied.

    A bad angle raises :class:`InvalidInputError` naming the option, with the value in degrees.
    """
    over: dict[str, Any] = {}
    if getattr(args, "solver", None):
        over["solver"] = args.solver
    if getattr(args, "time_limit", None) is not None:
        over["time_limit"] = args.time_limit
    if getattr(args, "variant", None):
        over["variant"] = args.variant
    if getattr(args, "tangential_ratio", None) is not None:
        over["tangential_ratio"] = args.tangential_ratio
    if getattr(args, "contact_stiffness", None) is not None:
        over["contact_stiffness"] = args.contact_stiffness
    if getattr(args, "limit", None):
        over["limit"] = args.limit
    degrees = {k: getattr(args, k, None) for k in ANGLE_OPTIONS}
    over.update({k: math.radians(v) for k, v in degrees.items() if v is not None})
    try:
        return make_settings(scene.settings, **over)
    except InvalidInputError as exc:
        flag = {"tangential_ratio": "--tangential-ratio", "contact_stiffness": "--contact-stiffness"}
        if exc.name in flag and getattr(args, exc.name, None) is not None:
            raise InvalidInputError(flag[exc.name], str(exc).removeprefix(f"{exc.name}: ")) from None
        deg = degrees.get(exc.name) if exc.name in ANGLE_OPTIONS else None
        if deg is None:
            raise
        why = str(exc).removeprefix(f"{exc.name}: ").split(", got ")[0]
        raise InvalidInputError(
            ANGLE_OPTIONS[exc.name], f"{why}; got {deg:g} deg ({math.radians(deg):.4g} rad)"
        ) from None


def preload(args: argparse.Namespace, scene: Any) -> tuple[dict[str, float], str | None]:
    """The commands of ``--preload NAME`` (the scene's preload without it), and the name."""
    name = getattr(args, "preload", None)
    return scene.preload(name), name


def workers(args: argparse.Namespace) -> int | None:
    """``--workers`` (``0``: one per CPU; ``None``: the API's default)."""
    n = getattr(args, "workers", None)
    if n is not None and n < 0:
        raise InvalidInputError("--workers", f"must be >= 0 (0: one per CPU), got {n}")
    return n


def _floats(text: str, what: str) -> list[float]:
    """Comma- (or semicolon-) separated finite numbers."""
    parts = [t.strip() for t in text.replace(";", ",").split(",")]
    try:
        vals = [float(t) for t in parts]
    except ValueError:
        raise InvalidInputError(
            what, f"expected comma-separated numbers like 0,-5,0,0,0,0, got {text!r}"
        ) from None
    if not all(math.isfinite(v) for v in vals):
        raise InvalidInputError(what, f"contains NaN or inf: {text!r}")
    return vals


def _axis_values(text: str, what: str) -> np.ndarray:
    """``fy=-5,mz=0.1`` -> a 6-vector (the other components zero)."""
    w = np.zeros(6)
    for part in text.split(","):
        if "=" not in part:
            raise InvalidInputError(what, f"mix of axis=value and plain numbers in {text!r}")
        key, _, val = part.partition("=")
        i = axis_index(key.strip())
        try:
            w[i] += float(val)
        except ValueError:
            raise InvalidInputError(what, f"{key.strip()}: expected a number, got {val.strip()!r}") from None
        if not math.isfinite(w[i]):
            raise InvalidInputError(what, f"{key.strip()}: must be finite, got {val.strip()!r}")
    return w


def _vector_count(scene: Any, vals: list[float]) -> bool:
    """Whether ``vals`` has 6 numbers, or 3 ``(fx, fy, mz)`` on a planar scene."""
    return len(vals) == 6 or (len(vals) == 3 and scene.model.planar)


def parse_wrench(scene: Any, text: str) -> np.ndarray:
    """``--wrench``: numbers (6, or 3 for planar scenes), ``axis=value`` pairs, or a scene wrench.

    Returns:
        The wrench, (6,) [N, N·m].
    """
    text = text.strip()
    named = scene.analysis.wrenches
    if text in named:
        return np.asarray(named[text], dtype=float)
    if not text:
        raise InvalidInputError("--wrench", "empty wrench")
    if "=" in text:
        w = _axis_values(text, "--wrench")
    else:
        if not any(ch.isdigit() for ch in text):
            hint = f"; the scene's wrenches: {', '.join(named)}" if named else ""
            raise InvalidInputError(
                "--wrench", f"expected fx,fy,fz,mx,my,mz (or axis=value pairs), got {text!r}{hint}"
            )
        vals = _floats(text, "--wrench")
        if not _vector_count(scene, vals):
            want = "6 numbers (fx,fy,fz,mx,my,mz)" + (" or 3 (fx,fy,mz)" if scene.model.planar else "")
            raise InvalidInputError("--wrench", f"expected {want}, got {len(vals)} in {text!r}")
        w = np.asarray(vals, dtype=float)
    return scene.model.wrench_vector(w, "--wrench")


def parse_direction(scene: Any, text: str) -> tuple[object, str]:
    """``--direction``: a scene direction name, a signed axis (``-fy``), or a vector.

    Returns:
        What :func:`pinograsp.max_resistible_wrench` takes as ``direction`` (a signed axis name or
        a 6-vector), and the direction's label.
    """
    text = text.strip()
    named = scene.analysis.directions
    if text in named:
        return np.asarray(named[text], dtype=float), text
    if "," in text or ";" in text:
        vals = _floats(text, "--direction")
        if not _vector_count(scene, vals):
            raise InvalidInputError("--direction", f"expected 6 numbers, got {len(vals)} in {text!r}")
        return scene.model.wrench_vector(vals, "--direction"), text
    try:
        axis_index(text.lstrip("+-"))
    except PinograspError:
        valid = [*(f"{s}{a}" for a in WRENCH_AXES for s in ("", "-")), *named]
        raise UnknownNameError("direction", text, valid) from None
    return text, text if text[0] in "+-" else f"+{text}"


def parse_plane(scene: Any, text: str | None) -> tuple[object, object]:
    """``--plane``: ``fx,fy``, a scene plane name, or two vectors ``'v1;v2'`` (default: the
    scene's plane); the plane argument of :func:`pinograsp.resistance_profile`."""
    if text is None:
        return tuple(scene.analysis.plane)
    text = text.strip()
    planes = scene.analysis.planes
    if text in planes:
        return tuple(planes[text])
    if ";" in text:
        parts = text.split(";")
        if len(parts) != 2:
            raise InvalidInputError("--plane", f"expected two vectors 'v1;v2', got {text!r}")
        return tuple(_floats(p, "--plane") for p in parts)  # type: ignore[return-value]
    parts = [t.strip() for t in text.split(",")]
    if len(parts) != 2:
        hint = f" or a scene plane ({', '.join(planes)})" if planes else ""
        raise InvalidInputError("--plane", f"expected two axes like fx,fy{hint}, got {text!r}")
    for t in parts:
        axis_index(t.lstrip("+-"))
    return parts[0], parts[1]
