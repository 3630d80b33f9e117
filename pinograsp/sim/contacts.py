"""Contact forces of the simulation: push-only normal springs and exact Coulomb friction.

Each contact ``i`` of the :class:`~pinograsp.GraspModel` joins a point of the hand, displaced by
the linearised kinematics ``J_i q`` (rotated from the contact frame to the world), and the
object's material point at ``p_i``, displaced rigidly with the object. With ``g_i`` the
object point's displacement relative to the hand point (world, [m]) and ``n_i`` the normal
from the hand into the object (docs/design.md, conventions):

- penetration ``delta_i = -n_i · g_i``; normal force ``c_n = max(0, k delta + b d(delta)/dt)``
  when ``delta > 0``, else 0 (push-only spring with a damper; ``k`` as the model's ``k``
  scaled to the simulation stiffness);
- friction: a tangential spring of stiffness ``k`` from an anchor (the stuck position of the
  contact) with a damper, capped at ``mu c_n``; when the spring alone exceeds the cap the anchor
  slides so that the spring force sits exactly on the cone (a spring–slider: exact Coulomb
  friction with the circular cone, not the model's pyramid), and a separated contact forgets
  its anchor.

MuJoCo's own soft contacts are not used: docs/simulation.md explains why.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..core.model import GraspModel


def skew(v: np.ndarray) -> np.ndarray:
    """The matrix ``S`` with ``S @ x = v × x``, (3, 3)."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def moment(arms: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """``sum_i arms_i × forces_i``, (3,), for (n, 3) arrays."""
    a, f = arms, forces
    return np.array(
        [
            a[:, 1] @ f[:, 2] - a[:, 2] @ f[:, 1],
            a[:, 2] @ f[:, 0] - a[:, 0] @ f[:, 2],
            a[:, 0] @ f[:, 1] - a[:, 1] @ f[:, 0],
        ]
    )


def pyramid_polygons(grasp: GraspModel) -> tuple[np.ndarray, np.ndarray]:
    """The model's friction pyramid of each contact as a polygon in its tangent plane.

    Returns:
        Vertices per unit normal force in ``(t1, t2)`` coordinates, counter-clockwise and padded
        by repeating the last one, (nc, m, 2); and whether each polygon has an area (>= 3
        distinct vertices), (nc,).
    """
    D, owner, d = np.asarray(grasp.D, dtype=float), np.asarray(grasp.beta_contact), grasp.d
    blocks = [D[i * d : (i + 1) * d, owner == i] for i in range(grasp.nc)]
    m = max(b.shape[1] for b in blocks)
    out = np.zeros((grasp.nc, m, 2))
    for i, b in enumerate(blocks):
        v = (b[1:] / b[0]).T  # (edges, d - 1)
        out[i, : len(v), : d - 1] = v
        out[i, len(v) :] = out[i, len(v) - 1]
    return out, np.array([len(b.T) >= 3 and d == 3 for b in blocks])


def closest_in_polygons(p: np.ndarray, V: np.ndarray, proper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The point of each convex polygon closest to each point.

    Args:
        p: Points, (n, 2).
        V: Counter-clockwise polygon vertices, (n, m, 2) (a segment or a point when not
            ``proper``).
        proper: Whether each polygon has an area, (n,).

    Returns:
        The closest points, (n, 2), and whether each point was inside, (n,).
    """
    A, E = V, np.roll(V, -1, axis=1) - V
    W = p[:, None, :] - A
    inside = proper & np.all(E[..., 0] * W[..., 1] - E[..., 1] * W[..., 0] >= 0.0, axis=1)
    t = np.clip(np.sum(W * E, axis=2) / np.maximum(np.sum(E * E, axis=2), 1e-300), 0.0, 1.0)
    Q = A + t[..., None] * E
    best = np.argmin(np.sum((p[:, None, :] - Q) ** 2, axis=2), axis=1)
    q = Q[np.arange(len(p)), best]
    inside |= np.sum((p - q) ** 2, axis=1) <= 1e-24 * np.sum(p * p, axis=1)  # on a segment
    return np.where(inside[:, None], p, q), inside


@dataclass
class ContactLaw:
    """Contact state and force law of one simulated grasp.

    Attributes:
        arms: Contact points relative to the reference point ``o``, object frame at rest,
            (nc, 3) [m].
        normals: Unit normals from the hand into the object, world frame, (nc, 3).
        jacobian: World-frame velocity of each hand point per joint velocity, (nc, 3, nq)
            [m/rad].
        k: Normal and tangential stiffness, (nc,) [N/m].
        b: Normal and tangential damping, (nc,) [N·s/m].
        mu: Friction coefficients, (nc,).
        anchors: Stuck position of each contact (tangential ``g`` at which the friction spring
            is relaxed), (nc, 3) [m].
        relax: When set, the next :meth:`forces` first moves every anchor to the contact's
            current tangential position (no friction force is stored), then clears the flag.
        pyramid: ``None`` for the circular cone, else the model's friction pyramids:
            ``(polygons (nc, m, 2), proper (nc,), tangents (nc, 3, 2))`` (:func:`pyramid_polygons`;
            ``tangents`` are the world ``t1, t2`` columns).
    """

    arms: np.ndarray
    normals: np.ndarray
    jacobian: np.ndarray
    k: np.ndarray
    b: np.ndarray
    mu: np.ndarray
    anchors: np.ndarray = field(init=False)
    relax: bool = field(init=False, default=False)
    pyramid: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def __post_init__(self) -> None:
        self.anchors = np.zeros_like(self.arms)

    @classmethod
    def from_model(
        cls, grasp: GraspModel, stiffness: float, damping_ratio: float, mass: float, pyramid: bool = False
    ) -> ContactLaw:
        """The law of a :class:`~pinograsp.GraspModel`.

        Args:
            grasp: The model (its ``J``, ``frames``, ``points``, ``k``, ``mu``).
            stiffness: Stiffness of the model's stiffest contact [N/m]; the others keep their
                ratios ``k_i / max(k)``.
            damping_ratio: Damping of each contact relative to a critically damped spring
                carrying ``mass``.
            mass: Mass the damping ratio refers to [kg].
            pyramid: Cap friction with the model's pyramid instead of the circular cone.
        """
        nc, d = grasp.nc, grasp.d
        J = np.asarray(grasp.J, dtype=float).reshape(nc, d, grasp.nq)
        frames = np.asarray(grasp.frames, dtype=float)[:, :, :d]  # columns n, t1 (, t2)
        k = stiffness * np.asarray(grasp.k, dtype=float) / float(np.max(grasp.k))
        tangents = np.asarray(grasp.frames, dtype=float)[:, :, 1:3]
        return cls(
            arms=np.asarray(grasp.points, dtype=float) - np.asarray(grasp.reference_point, dtype=float),
            normals=np.asarray(grasp.frames, dtype=float)[:, :, 0].copy(),
            jacobian=np.einsum("iad,idj->iaj", frames, J),
            k=k,
            b=2.0 * damping_ratio * np.sqrt(k * mass),
            mu=np.asarray(grasp.mu, dtype=float),
            pyramid=(*pyramid_polygons(grasp), tangents) if pyramid else None,
        )

    def _cap(self, force: np.ndarray, cn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Tangential forces (nc, 3) [N] capped to the cone or pyramid of ``cn`` (nc,); whether
        each was outside."""
        if self.pyramid is None:
            size = np.sqrt(np.einsum("ij,ij->i", force, force))
            cap = self.mu * cn
            outside = size > cap
            return force * np.minimum(1.0, cap / np.maximum(size, 1e-300))[:, None], outside
        poly, proper, T = self.pyramid
        p = np.einsum("iak,ia->ik", T, force)
        q, inside = closest_in_polygons(p, poly * cn[:, None, None], proper & (cn > 0))
        return np.einsum("iak,ik->ia", T, q), ~inside

    def forces(
        self,
        q: np.ndarray,
        qd: np.ndarray,
        shift: np.ndarray,
        rot: np.ndarray,
        vel: np.ndarray,
        omega: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Contact forces on the object for the current state; updates the anchors.

        Args:
            q: Hand joint displacements from the touching configuration, (nq,) [rad or m].
            qd: Hand joint velocities, (nq,).
            shift: Object translation from its rest pose, (3,) [m].
            rot: Object rotation from its rest pose, (3, 3).
            vel: Velocity of the object's reference point, world, (3,) [m/s].
            omega: Object angular velocity, world, (3,) [rad/s].

        Returns:
            ``forces`` on the object at each contact, world, (nc, 3) [N]; the current lever
            arms ``rot @ arms``, (nc, 3) [m]; whether each contact slides, (nc,).
        """
        arms = self.arms @ rot.T
        g = shift + arms - self.arms - self.jacobian @ q
        gd = vel + arms @ skew(omega).T - self.jacobian @ qd
        n = self.normals
        gn = np.einsum("ij,ij->i", n, g)
        gdn = np.einsum("ij,ij->i", n, gd)
        touching = gn < 0.0
        cn = np.where(touching, np.maximum(0.0, -self.k * gn - self.b * gdn), 0.0)
        gt = g - gn[:, None] * n
        gdt = gd - gdn[:, None] * n
        if self.relax:
            self.anchors, self.relax = gt.copy(), False
        spring = -self.k[:, None] * (gt - self.anchors)
        capped, sliding = self._cap(spring, cn)
        ft = np.where(sliding[:, None], capped, self._cap(spring - self.b[:, None] * gdt, cn)[0])
        slid = np.where(sliding[:, None], gt + capped / self.k[:, None], self.anchors)
        self.anchors = np.where(touching[:, None], slid, gt)
        return cn[:, None] * n + ft, arms, sliding & touching
