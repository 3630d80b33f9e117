"""Point contacts with friction: geometry, stiffness and the linearised friction pyramid.

Conventions (docs/design.md): the unit normal ``n`` points **from the hand into the object** (the
direction in which the hand pushes); tangents ``t1, t2`` complete a right-handed frame with
``t1 × t2 = n``. The contact force on the object in the contact frame is ``(c_n, c_t1, c_t2)``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from ..errors import InvalidInputError
from .validate import MAX_JOINTS, MAX_MU, STIFFNESS, check_name, count, number_in, vector

#: Tolerance on ``|n| = 1`` and ``t1 ⟂ n`` for user-supplied normals and tangents.
UNIT_TOL = 1e-6


def default_tangent(normal: np.ndarray) -> np.ndarray:
    """A deterministic unit tangent ``t1`` for ``normal``.

    For normals in the XY plane this is ``e_z × n`` (so ``t2 = e_z`` and planar scenes keep
    ``t1`` in their plane); otherwise ``e_x × n``.
    """
    axis = np.array([0.0, 0.0, 1.0]) if abs(normal[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    t1 = np.cross(axis, normal)
    return t1 / np.linalg.norm(t1)


@dataclass(frozen=True)
class Contact:
    """One hand–object point contact.

    Attributes:
        point: Contact point ``p`` in the world (hand base) frame [m], shape (3,).
        normal: Unit normal ``n`` from the hand into the object, shape (3,).
        mu: Coulomb friction coefficient, in [0, 100] (docs/errors.md, "Input domains").
        jacobian: World-frame linear velocity of the **hand** point at ``p`` per unit closing
            joint velocity, shape (3, nq) [m/rad]. ``None`` means the point is on a part that
            cannot move (e.g. the palm): a zero Jacobian.
        tangent: Unit tangent ``t1`` orthogonal to ``normal``; ``None`` picks
            :func:`default_tangent`.
        stiffness: Normal stiffness ``k`` of the virtual contact spring [N/m], in [1e-6, 1e12].
        name: Label used in results and error messages (e.g. the hand link's name).
    """

    point: np.ndarray
    normal: np.ndarray
    mu: float = 0.5
    jacobian: np.ndarray | None = None
    tangent: np.ndarray | None = None
    stiffness: float = 1.0
    name: str | None = None
    t2: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        check_name("contact", self.name)
        label = f"contact {self.name!r}" if self.name is not None else "contact"
        point = vector(f"{label}.point", self.point, 3)
        normal = vector(f"{label}.normal", self.normal, 3)
        if abs(np.linalg.norm(normal) - 1.0) > UNIT_TOL:
            raise InvalidInputError(
                f"{label}.normal", f"must be a unit vector, |n| = {np.linalg.norm(normal):.9g}"
            )
        normal = normal / np.linalg.norm(normal)
        mu = number_in(f"{label}.mu", self.mu, 0.0, MAX_MU)  # domains: docs/errors.md
        k = number_in(f"{label}.stiffness", self.stiffness, *STIFFNESS, "N/m")
        if self.tangent is None:
            t1 = default_tangent(normal)
        else:
            t1 = vector(f"{label}.tangent", self.tangent, 3)
            if abs(np.linalg.norm(t1) - 1.0) > UNIT_TOL or abs(t1 @ normal) > UNIT_TOL:
                raise InvalidInputError(f"{label}.tangent", "must be a unit vector orthogonal to the normal")
            t1 = t1 - (t1 @ normal) * normal
            t1 /= np.linalg.norm(t1)
        jac = None
        if self.jacobian is not None:
            try:
                jac = np.array(self.jacobian, dtype=float, ndmin=2)
            except (TypeError, ValueError, OverflowError) as exc:
                raise InvalidInputError(f"{label}.jacobian", "not a numeric array") from exc
            if jac.ndim != 2 or jac.shape[0] != 3:
                raise InvalidInputError(f"{label}.jacobian", f"expected shape (3, nq), got {jac.shape}")
            if not np.all(np.isfinite(jac)):
                raise InvalidInputError(f"{label}.jacobian", "contains NaN or inf")
        object.__setattr__(self, "point", point)
        object.__setattr__(self, "normal", normal)
        object.__setattr__(self, "tangent", t1)
        object.__setattr__(self, "t2", np.cross(normal, t1))
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "jacobian", jac)

    @property
    def frame(self) -> np.ndarray:
        """Rotation from the contact frame to the world: columns ``(n, t1, t2)``, shape (3, 3)."""
        return np.column_stack([self.normal, cast(np.ndarray, self.tangent), self.t2])  # set by __post_init__

    @staticmethod
    def revolute(
        point: object,
        normal: object,
        pivots: dict[int, tuple[object, object]] | None = None,
        nq: int = 0,
        **kwargs: object,
    ) -> Contact:
        """A contact on a link moved by revolute joints, with the Jacobian built from pivots.

        Args:
            point: Contact point [m], (3,).
            normal: Unit normal, hand into object, (3,).
            pivots: ``{joint_index: (pivot_point, closing_axis)}``: each joint upstream of the
                contact, a point on its axis [m] and its unit axis oriented so that positive
                rotation closes the hand. The Jacobian column is ``axis × (p − pivot)``.
            nq: Number of joints of the hand, in [0, 10000].
            **kwargs: Passed to :class:`Contact` (``mu``, ``stiffness``, ``name``, ...).
        """
        p = vector("point", point, 3)
        nq = count("nq", nq, MAX_JOINTS, minimum=0, what="joints of a hand; checked before allocating")
        if pivots is None:
            pivots = {}
        if not isinstance(pivots, Mapping):
            raise InvalidInputError(
                "pivots", f"expected a mapping joint index -> (pivot, axis), got {pivots!r}"
            )
        jac = np.zeros((3, nq))
        for j, spec in pivots.items():
            if isinstance(j, (bool, np.bool_)) or not isinstance(j, (int, np.integer)) or not 0 <= j < nq:
                raise InvalidInputError("pivots", f"joint index {j!r} is not an integer in 0..{nq - 1}")
            if (
                isinstance(spec, (str, bytes))
                or not isinstance(spec, (Sequence, np.ndarray))
                or len(spec) != 2
            ):
                raise InvalidInputError(f"pivots[{j}]", f"expected (pivot_point, closing_axis), got {spec!r}")
            pivot, axis = spec
            a = vector(f"pivots[{j}].axis", axis, 3)
            norm = np.linalg.norm(a)
            if not norm > 0 or not np.isfinite(norm):
                raise InvalidInputError(
                    f"pivots[{j}].axis", f"must be a non-zero finite vector, got {axis!r}"
                )
            jac[:, int(j)] = np.cross(a / norm, p - vector(f"pivots[{j}].pivot", pivot, 3))
        if not np.all(np.isfinite(jac)):
            raise InvalidInputError("pivots", "the Jacobian overflows (coordinates too large)")
        return Contact(point=p, normal=normal, jacobian=jac, **kwargs)  # type: ignore[arg-type]


def friction_edges(mu: float, m: int, circumscribed: bool = False) -> np.ndarray:
    """Edges of the linearised friction pyramid in the contact frame.

    Edge ``k`` is ``n + mu' (cos(2πk/m) t1 + sin(2πk/m) t2)`` with ``mu' = mu`` for the
    inscribed pyramid (edges on the cone: conservative) or ``mu / cos(π/m)`` for the
    circumscribed one (faces tangent to the cone: optimistic). With ``mu = 0`` the pyramid
    collapses to the normal alone: one edge.

    Returns:
        Array of shape (3, m) (or (3, 1) when ``mu == 0``), columns are edges with unit normal
        component, so that ``c_n = sum(beta)``.
    """
    if mu == 0.0:
        return np.array([[1.0], [0.0], [0.0]])
    mu_eff = mu / np.cos(np.pi / m) if circumscribed else mu
    ang = 2.0 * np.pi * np.arange(m) / m
    return np.vstack([np.ones(m), mu_eff * np.cos(ang), mu_eff * np.sin(ang)])
