"""The validation kit: every public function checks its arguments with these helpers, so a bad
input is an :class:`~pinograsp.errors.InvalidInputError` naming the argument and, for choices,
the valid values (docs/errors.md)."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping
from enum import Enum
from pathlib import Path
from typing import TypeVar

import numpy as np

from ..errors import InvalidInputError

E = TypeVar("E", bound=Enum)


def vector(name: str, value: object, size: int) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(name, f"expected {size} numbers, got {value!r}") from exc
    if arr.shape != (size,):
        raise InvalidInputError(name, f"expected {size} numbers, got shape {arr.shape}", value)
    if not np.all(np.isfinite(arr)):
        raise InvalidInputError(name, "contains NaN or inf", value)
    return arr


def finite_array(name: str, value: object, shape: tuple[int, ...]) -> np.ndarray:
    """``value`` as a finite float array of ``shape`` (a flat sequence of the right size is
    reshaped), else :class:`InvalidInputError` naming ``name``."""
    if isinstance(value, (str, bytes)):
        raise InvalidInputError(name, f"expected an array of shape {shape}, got {value!r}")
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(name, f"expected an array of shape {shape}, got {value!r}") from exc
    if arr.size != int(np.prod(shape)):
        raise InvalidInputError(name, f"expected an array of shape {shape}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InvalidInputError(name, "contains NaN or inf")
    return arr.reshape(shape)


def writing(path: object, write: Callable[[Path], object], *, name: str = "path") -> Path:
    """Write a file through ``write(Path)``: the path must be a ``str`` or ``os.PathLike`` naming
    a file (not a folder), its parent folders are created, and an ``OSError`` (permissions, a
    full disk, a file where a folder should be) becomes an :class:`InvalidInputError` naming
    ``name``. Returns the written path."""
    if not isinstance(path, (str, os.PathLike)) or isinstance(path, bytes):
        raise InvalidInputError(name, f"expected a file path (str or os.PathLike), got {path!r}")
    p = Path(path)
    if str(path) == "" or p.is_dir():
        raise InvalidInputError(name, f"{str(path)!r} is a folder, not a file")
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        write(p)
    except OSError as exc:
        raise InvalidInputError(name, f"cannot write {str(p)!r}: {exc.strerror or exc}") from exc
    return p


def finite_number(name: str, value: object) -> float:
    """``float(value)`` if it is a finite real number, else :class:`InvalidInputError` naming ``name``."""
    if isinstance(value, (str, bytes)):
        raise InvalidInputError(name, f"expected a number, got {value!r}")
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(name, f"expected a number, got {value!r}") from exc
    if not np.isfinite(v):
        raise InvalidInputError(name, f"must be finite, got {value!r}")
    return v


def choice(name: str, value: object, valid: tuple[str, ...] | list[str]) -> str:
    """``value`` if it is one of the strings ``valid``, else :class:`InvalidInputError` naming
    ``name`` and the valid choices (arrays, lists and other unhashable values included)."""
    if not isinstance(value, str) or value not in valid:
        raise InvalidInputError(name, f"must be one of {tuple(valid)}, got {value!r}")
    return value


def whole_number(name: str, value: object, minimum: int = 1) -> int:
    """``int(value)`` if it is an integer ``>= minimum`` (``bool``, ``2.5`` and ``"20"`` are
    not), else :class:`InvalidInputError` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InvalidInputError(name, f"expected an integer >= {minimum}, got {value!r}")
    if value < minimum:
        raise InvalidInputError(name, f"must be an integer >= {minimum}, got {value!r}")
    return int(value)


def positive_number(name: str, value: object) -> float:
    """A finite real number ``> 0`` (not a string or bool), else :class:`InvalidInputError`."""
    if isinstance(value, bool):
        raise InvalidInputError(name, f"expected a number, got {value!r}")
    v = finite_number(name, value)
    if not v > 0:
        raise InvalidInputError(name, f"must be a finite number > 0, got {value!r}")
    return v


def check_name(owner: str, name: object) -> str | None:
    """A label: ``None`` or a string (anything else raises :class:`InvalidInputError`)."""
    if name is not None and not isinstance(name, str):
        raise InvalidInputError(f"{owner}.name", f"expected a string or None, got {name!r}")
    return name


def sequence(name: str, value: object) -> list:
    """``list(value)`` for a list-like argument; strings, mappings and scalars are refused."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Iterable):
        raise InvalidInputError(name, f"expected a sequence, got {value!r}")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        raise InvalidInputError(name, f"expected a sequence, got {value!r}")
    return list(value)


def flag(name: str, value: object) -> bool:
    """A boolean argument (``bool``, ``numpy.bool_`` or the integers 0/1)."""
    if isinstance(value, (bool, np.bool_)) or (isinstance(value, (int, np.integer)) and value in (0, 1)):
        return bool(value)
    raise InvalidInputError(name, f"expected True or False, got {value!r}")


# ------------------------------------------------------------------------------ input domains
# Every numeric input has a valid range derived from the physics and from double precision; the
# table of docs/errors.md ("Input domains") lists them. Each is checked once, at the public
# boundary, by the helpers below: an InvalidInputError naming the argument and the range.

#: Largest force [N], torque [N·m] or command anywhere (loads, ``upper``, commands, bounds,
#: budgets, grips): squared in spring energies (``c_n^2 / 2k``) it stays far from overflow, and
#: it is 1e4 times the largest press ever built.
MAX_FORCE = 1e12
#: Smallest nonzero force, torque or command magnitude (the largest command of a preload,
#: ``upper``, bounds, budgets, grips): the loading path resolves 1e-9 of the unit load (1 N or
#: N·m per unit λ), so commands of 1e-10 left every contact "at zero force" (a ``SolverError``)
#: and a budget of 1e-300 divided by zero; the answer is exactly homogeneous from 1e-8 up.
MIN_FORCE = 1e-6
#: Largest moment arm, gear ratio or coupling coefficient (``Actuator.transmission``,
#: ``Coupling.weights``) in magnitude, and the smallest nonzero one: a transmission of 1e300
#: overflowed the path's actuator rows (an ``IndexError`` in Lemke's method).
ARM = (1e-6, 1e6)
#: The quasi-static method's tangential / normal contact stiffness (``Settings.tangential_ratio``):
#: below 3e-8 the tangential springs fall under the rank tolerance (a 10 N pinch reported
#: ``below_resolution`` 0 N), above 1e8 the rate problems lose their solution (``SolverError``).
TANGENTIAL_RATIO = (1e-6, 1e6)
#: Give-way thresholds [m or rad] (``Settings.giveway_*``, ``LoadingPath.load_at_displacement``).
GIVEWAY = (1e-9, 1e3)
#: A physical contact stiffness [N/m] (``Settings.contact_stiffness``, ``load_at_displacement``).
PHYSICAL_STIFFNESS = (1.0, 1e10)
#: Largest load (a wrench, ``upper``) relative to the grasp's own force scale (the contact force
#: its commands press, :func:`grasp_force_scale`): the solvers resolve 1e-9 of the largest force,
#: so beyond 1e6 the preload's forces drown in the load's rounding (a "push-only" force of
#: -5.9 N under a 1e12 N wrench on a 10 N pinch).
LOAD_RATIO = 1e6
#: Largest number of bisection halvings: ``upper / 2**52`` is already the resolution of a double.
MAX_STEPS = 60
#: Largest number of directions of a profile, resistance set or grasp score (one search each).
MAX_DIRECTIONS = 100_000
#: Largest segment-count limit of a quasi-static loading path (each segment one LCP).
MAX_PATH_SEGMENTS = 1_000_000
#: Largest number of sampled grasps (``sample_grasps``, batch files).
MAX_SAMPLES = 1_000_000
#: Largest number of joints of a contact Jacobian (``Contact.revolute(nq=...)``, a hand has ~30).
MAX_JOINTS = 10_000
#: Most contacts of one grasp model (a count limit: each contact adds LCP/MIQP variables; 400
#: random contacts took 113 s per direction, 800 no answer in 300 s; hands make at most tens).
MAX_CONTACTS = 256
#: Largest friction coefficient: rubber on rubber is ~2; beyond 100 the friction pyramid's edges
#: are 1e-2 from the contact plane and the normal force a rounding of the tangential ones.
MAX_MU = 100.0
#: Contact spring stiffness range [N/m] (relative stiffness 1 by default); the ratio between
#: contacts is checked separately (ConditioningWarning above 1e5).
STIFFNESS = (1e-6, 1e12)
#: Lengths [m] (object sizes, radii, the length converting torques to forces) and, relative to
#: the grasp size, ``length`` arguments: 1e-6 .. 1e6 times the model's length scale.
LENGTH = (1e-6, 1e6)
#: Audit tolerance (relative to the solve's force scale): a residual below 1e-12 is rounding,
#: one above 1e-2 is no check.
TOLERANCE = (1e-12, 1e-2)
#: The iterative tolerance ``eps`` [N] of a search: at most 1e-2 of the larger of the grasp's
#: force scale and ``upper`` (beyond, a 10 N limit becomes "unbounded": every net wrench
#: counts as equilibrium).
EPS_RATIO = 1e-2


def number_in(
    name: str, value: object, low: float, high: float, unit: str = "", *, open_low: bool = False
) -> float:
    """A finite real number in ``[low, high]`` (``(low, high]`` with ``open_low``), else an
    :class:`InvalidInputError` stating the range and its unit."""
    if isinstance(value, bool):
        raise InvalidInputError(name, f"expected a number, got {value!r}")
    v = finite_number(name, value)
    if not ((v > low) if open_low else (v >= low)) or not v <= high:
        lo = f"({low:g}" if open_low else f"[{low:g}"
        raise InvalidInputError(
            name, f"must be in {lo}, {high:g}]{' ' + unit if unit else ''}, got {value!r}"
        )
    return v


def count(name: str, value: object, maximum: int, minimum: int = 1, what: str = "") -> int:
    """An integer in ``[minimum, maximum]`` (``what``: why the maximum), refused before any work
    with the whole range in the message."""
    why = f" ({what})" if what else ""
    allowed = f"an integer in [{minimum}, {maximum}]{why}"
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InvalidInputError(name, f"expected {allowed}, got {value!r}")
    if not minimum <= value <= maximum:
        raise InvalidInputError(name, f"must be {allowed}, got {value!r}")
    return int(value)


def steps(value: object, name: str = "steps", *, bounded: bool = True) -> int:
    """Bisection halvings in ``[1, MAX_STEPS]``; with ``bounded=False`` (a method that does not
    bisect, a row of :mod:`pinograsp.core.methods` that is not ``bounded``: the value is ignored) any whole
    number >= 1."""
    if not bounded:
        return whole_number(name, value)
    return count(name, value, MAX_STEPS, what="upper / 2**52 is already below double resolution")


def directions(value: object, name: str = "n") -> int:
    """A number of directions in ``[1, MAX_DIRECTIONS]``."""
    return count(name, value, MAX_DIRECTIONS, what="one search per direction")


def force(name: str, value: object, unit: str = "N") -> float:
    """A force, torque or command magnitude in ``[MIN_FORCE, MAX_FORCE]``."""
    return number_in(name, value, MIN_FORCE, MAX_FORCE, unit)


def grasp_force_scale(model: object, command: np.ndarray) -> float:
    """The contact force [N] the commands ``command`` (na,) press through the shortest contact
    lever: ``max |R| |f_c| / min ||J_n||``; 0 without a preload (or without joints)."""
    J, R = model.J, model.R  # type: ignore[attr-defined]
    if not J.size or not R.size or not len(command):
        return 0.0
    levers = np.linalg.norm(J[model.normal_rows], axis=1)  # type: ignore[attr-defined]
    levers = levers[levers > 0]
    torque = float(np.max(np.abs(R) @ np.abs(np.asarray(command, float)), initial=0.0))
    return torque / float(levers.min()) if len(levers) and torque > 0 else 0.0


def load_within(
    model: object, command: np.ndarray, name: str, wrench: np.ndarray, *, eps: float | None = None
) -> None:
    """A load (a wrench (6,) [N, N·m], or ``upper`` times a unit direction) within
    :data:`LOAD_RATIO` of the grasp's force scale (:func:`grasp_force_scale`) and
    :data:`MAX_FORCE`; ``eps`` (the iterative tolerance [N]) within :data:`EPS_RATIO` of the
    larger of it and the load. Without a preload the analysis is homogeneous in the load: only
    the absolute bound holds."""
    w = np.asarray(wrench, float)
    ell = float(model.length_scale)  # type: ignore[attr-defined]
    size = max(float(np.linalg.norm(w[:3])), float(np.linalg.norm(w[3:])) / ell)
    if size > MAX_FORCE:
        raise InvalidInputError(name, f"{size:.3g} N (torques / length scale) exceeds {MAX_FORCE:g} N")
    scale = grasp_force_scale(model, command)
    if scale > 0 and size > LOAD_RATIO * scale:
        raise InvalidInputError(
            name,
            f"{size:.3g} N (torques / length scale {ell:.3g} m) is more than {LOAD_RATIO:g} times the "
            f"grasp's force scale {scale:.3g} N (the contact force its commands press): beyond it the "
            "preload's forces are below the solvers' rounding; lower it (or raise the commands)",
        )
    if eps is not None and eps > EPS_RATIO * max(scale, size):
        raise InvalidInputError(
            "eps",
            f"{eps:g} N is more than {EPS_RATIO:g} times the larger of the grasp's force scale "
            f"{scale:.3g} N and the load {size:.3g} N: every net wrench would count as equilibrium; "
            "lower eps",
        )


def search_bounds(
    model: object, command: object, upper: object, n_steps: object, eps: float | None = None
) -> tuple[float, int]:
    """``upper`` [N or N·m] and ``steps`` of a max-wrench search, checked against their domains
    and the grasp (``upper`` along a force axis within :data:`LOAD_RATIO` of the grasp's force
    scale; ``eps`` of the iterative method within :data:`EPS_RATIO`): ``(upper, steps)``."""
    up, st = force("upper", upper, "N or N·m"), steps(n_steps)
    fc = model.command_vector(command)  # type: ignore[attr-defined]
    load_within(model, fc, "upper", np.array([up, 0.0, 0.0, 0.0, 0.0, 0.0]), eps=eps)
    return up, st


def relative_length(name: str, value: object, scale: float) -> float:
    """A length [m] within :data:`LENGTH` times the grasp's length scale ``scale`` (torques are
    divided by it: beyond, one half of wrench space vanishes in double precision)."""
    lo, hi = LENGTH[0] * scale, LENGTH[1] * scale
    return number_in(name, value, lo, hi, f"m ({LENGTH[0]:g} to {LENGTH[1]:g} times the length scale)")


#: Object and link sizes [m] (box sides, radii, lengths): a micro-gripper's 1 µm to a 1 km
#: structure; beyond, Coal's distance tolerances (1e-9 m) or the contact tolerance lose meaning.
SIZE = (1e-6, 1e3)


def size(name: str, value: object) -> float:
    """A length [m] in :data:`SIZE`."""
    return number_in(name, value, *SIZE, "m")


#: Contact detection tolerance [m]: a link within it of the object touches. Above 5 cm links that
#: do not touch would count as contacts (``close_on(tolerance=1e300)`` stopped at q = 0).
CONTACT_TOLERANCE = (0.0, 0.05)
#: Largest joint value [rad or m] and object position [m]: beyond 1e3, angles lose their
#: sub-micro-radian resolution and positions leave any workspace.
MAX_COORDINATE = 1e3


def contact_tolerance(name: str, value: object, *, positive: bool = False) -> float:
    """A contact tolerance [m] in :data:`CONTACT_TOLERANCE` (``positive``: above 0)."""
    return number_in(name, value, *CONTACT_TOLERANCE, "m", open_low=positive)


def coordinates(name: str, values: np.ndarray, unit: str = "rad or m") -> np.ndarray:
    """Finite values within ±:data:`MAX_COORDINATE` (joint values, positions)."""
    if np.any(np.abs(values) > MAX_COORDINATE):
        raise InvalidInputError(name, f"must be within ±{MAX_COORDINATE:g} {unit}", values)
    return values
