"""Wrench axes, directions and planes: the one home of axis names, direction parsing and plane
parsing (docs/design.md).

Wrench 6-vectors are ``(fx, fy, fz [N], mx, my, mz [N·m])`` in world axes, torques about the
object reference point. A direction is an axis name (``"fx"``, ``"-fy"``, ``"mz"``; ``tx`` …
accepted for ``mx`` …) or a vector; a plane is two of them.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np

from ..errors import InvalidInputError, UnknownNameError
from .validate import whole_number


class WrenchSpace(Protocol):
    """What these functions read of a :class:`~pinograsp.core.model.GraspModel` (model.py imports
    this module, so the model is described, not imported)."""

    @property
    def planar(self) -> bool: ...

    def wrench_vector(self, wrench: object, name: str = "wrench") -> np.ndarray: ...


#: Wrench component names, world axes, torques about the object reference point.
WRENCH_AXES = ("fx", "fy", "fz", "mx", "my", "mz")
_AXIS_ALIASES = {"tx": "mx", "ty": "my", "tz": "mz"}
#: What to pass instead of an unknown axis name (the message of :class:`UnknownNameError`).
AXIS_HINT = (
    "pass an axis with an optional sign ('fx', '-fy', '+mz'; 'tx' … 'tz' for 'mx' … 'mz') "
    "or a wrench vector (fx, fy, fz, mx, my, mz) [N, N·m]"
)
#: Indices of the planar components ``(fx, fy, mz)`` inside a 6-vector.
PLANAR_AXES = (0, 1, 5)


def axis_index(name: str) -> int:
    """Index of a wrench component name (``fx … mz``; ``tx …`` accepted) in a 6-vector."""
    key = _AXIS_ALIASES.get(str(name).lower(), str(name).lower())
    if key not in WRENCH_AXES:
        raise UnknownNameError("wrench axis", name, WRENCH_AXES, AXIS_HINT)
    return WRENCH_AXES.index(key)


def wrench_direction(model: WrenchSpace, direction: object, name: str = "direction") -> np.ndarray:
    """A unit 6-vector from an axis name (``"fx"``, ``"-fy"``, ``"mz"``) or a wrench vector.

    The norm is the plain Euclidean norm of ``(force [N], torque [N·m])`` as given.
    """
    if isinstance(direction, str):
        sign = -1.0 if direction.startswith("-") else 1.0
        d = np.zeros(6)
        body = direction[1:] if direction[:1] in ("+", "-") else direction  # one sign at most
        if body[:1] in ("+", "-"):
            raise UnknownNameError("wrench axis", direction, WRENCH_AXES, AXIS_HINT)  # '+-fy', '--fy'
        d[axis_index(body)] = sign
    else:
        d = model.wrench_vector(direction, name)
    big = float(np.abs(d).max())
    if not big > 0:
        raise InvalidInputError(
            name,
            "zero-length direction: give a nonzero wrench vector (fx, fy, fz, mx, my, mz) "
            "or an axis such as 'fy'",
            d,
        )
    d = d / big  # first to the largest entry: no overflow (1e200) or underflow (1e-200) in the norm
    d = d / float(np.linalg.norm(d))
    return model.wrench_vector(d, name)


def wrench_unit(direction: Sequence[float] | np.ndarray) -> str:
    """Unit of a magnitude along a wrench direction (6,): ``"N"``, ``"N·m"`` or ``"N, N·m"``."""
    d = np.asarray(direction, dtype=float)
    force = np.linalg.norm(d[:3]) > 1e-12
    torque = np.linalg.norm(d[3:]) > 1e-12
    return "N" if force and not torque else ("N·m" if torque and not force else "N, N·m")


def direction_label(direction: object) -> str:
    """Short label of a wrench direction: ``"+fx"``, ``"−mz"``, or ``"(0.71 fx + 0.71 fy)"``
    (the minus sign is U+2212; :func:`direction_text` gives an ASCII ``-``)."""
    d = np.asarray(direction, dtype=float).reshape(-1)
    if d.shape != (6,):
        return str(direction)
    nz = np.flatnonzero(np.abs(d) > 1e-9)
    if nz.size == 1:
        return f"{'+' if d[nz[0]] > 0 else '−'}{WRENCH_AXES[nz[0]]}"
    terms = [f"{d[i]:+.2f} {WRENCH_AXES[i]}" for i in nz]
    return "(" + " ".join(terms).lstrip("+") + ")"


def direction_text(direction: object) -> str:
    """:func:`direction_label` with an ASCII minus (``"-fy"``)."""
    return direction_label(direction).replace("−", "-")


def plane_basis(model: WrenchSpace, plane: Sequence[object]) -> tuple[np.ndarray, tuple[str, str]]:
    """An orthonormal basis (2, 6) of a plane of wrench space given by two axis names or vectors
    (the second is orthogonalised against the first), and the plane's two labels."""
    given = plane
    try:  # a single name or vector is not a plane
        flat = isinstance(plane, (str, bytes)) or (isinstance(plane, np.ndarray) and plane.ndim != 2)
        plane = [] if flat else list(plane)
    except (TypeError, ValueError):
        plane = []
    if len(plane) != 2:
        raise InvalidInputError(
            "plane", f"expected two wrench axes (e.g. ('fx', 'fy')) or two vectors, got {given!r}"
        )
    b = [wrench_direction(model, p, f"plane[{i}]") for i, p in enumerate(plane)]
    b2 = b[1] - (b[1] @ b[0]) * b[0]
    if np.linalg.norm(b2) < 1e-9:
        raise InvalidInputError(
            "plane", "the two directions are parallel: give two different axes, e.g. ('fx', 'fy')"
        )
    labels = tuple(p if isinstance(p, str) else f"d{i}" for i, p in enumerate(plane))
    return np.vstack([b[0], b2 / np.linalg.norm(b2)]), labels  # type: ignore[return-value]


def circle_directions(basis: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Angles ``2πi/n`` [rad], (n,), and directions ``cos(a) b1 + sin(a) b2``, (n, 6)."""
    angles = 2.0 * np.pi * np.arange(int(n)) / int(n)
    return angles, np.cos(angles)[:, None] * basis[0] + np.sin(angles)[:, None] * basis[1]


def plane_directions(model: WrenchSpace, plane: Sequence[object] = ("fx", "fy"), n: int = 72) -> np.ndarray:
    """The ``n`` directions of :func:`resistance_profile` in ``plane``, (n, 6): bit-identical
    to ``resistance_profile(...).directions`` (e.g. for ``pg.resistance_set(directions=...)``)."""
    n = whole_number("n", n)
    basis, _ = plane_basis(model, plane)
    return circle_directions(basis, n)[1]


def cube_directions() -> tuple[tuple[str, ...], np.ndarray]:
    """The 26 unit force directions of a cube's faces, edges and corners, ``(i, j, k) / |(i, j,
    k)|`` with ``i, j, k`` in ``{-1, 0, 1}`` not all 0, in ``itertools.product`` order.

    Returns:
        ``(labels, directions)``: labels such as ``"+fx"``, ``"+fx-fy"``, ``"-fx+fy+fz"``
        (26,) and the unit wrenches (26, 6) (zero torque).
    """
    labels, rows = [], []
    for ijk in ((i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)):
        if not any(ijk):
            continue
        v = np.zeros(6)
        v[:3] = ijk
        rows.append(v / np.linalg.norm(v))
        labels.append("".join(f"{'+' if s > 0 else '-'}f{a}" for s, a in zip(ijk, "xyz") if s))
    return tuple(labels), np.array(rows)


def sphere_directions(n: int) -> np.ndarray:
    """``n`` unit force directions spread evenly over the sphere (a Fibonacci lattice: heights
    ``1 - (2 i + 1) / n``, longitudes turning by the golden angle), deterministic.

    Returns:
        The unit wrenches, (n, 6) (zero torque), the first nearest ``+z``.
    """
    i = np.arange(n, dtype=float)
    z = 1.0 - (2.0 * i + 1.0) / n
    r = np.sqrt(1.0 - z * z)
    phi = i * (np.pi * (3.0 - np.sqrt(5.0)))
    out = np.zeros((n, 6))
    out[:, 0], out[:, 1], out[:, 2] = r * np.cos(phi), r * np.sin(phi), z
    return out
