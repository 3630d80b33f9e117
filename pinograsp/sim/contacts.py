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

import numpy as np


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
    """

    arms: np.ndarray
    normals: np.ndarray
    jacobian: np.ndarray
    k: np.ndarray
    b: np.ndarray
    mu: np.ndarray
    anchors: np.ndarray = field(init=False)
    relax: bool = field(init=False, default=False)

    def __post_init__(self) -> None:
        self.anchors = np.zeros_like(self.arms)

    @classmethod
    def from_model(cls, grasp: object, stiffness: float, damping_ratio: float, mass: float) -> ContactLaw:
        """The law of a :class:`~pinograsp.GraspModel`.

        Args:
            grasp: The model (its ``J``, ``frames``, ``points``, ``k``, ``mu``).
            stiffness: Stiffness of the model's stiffest contact [N/m]; the others keep their
                ratios ``k_i / max(k)``.
            damping_ratio: Damping of each contact relative to a critically damped spring
                carrying ``mass``.
            mass: Mass the damping ratio refers to [kg].
        """
        nc, d = grasp.nc, grasp.d
        J = np.asarray(grasp.J, dtype=float).reshape(nc, d, grasp.nq)
        frames = np.asarray(grasp.frames, dtype=float)[:, :, :d]  # columns n, t1 (, t2)
        k = stiffness * np.asarray(grasp.k, dtype=float) / float(np.max(grasp.k))
        return cls(
            arms=np.asarray(grasp.points, dtype=float) - np.asarray(grasp.reference_point, dtype=float),
            normals=np.asarray(grasp.frames, dtype=float)[:, :, 0].copy(),
            jacobian=np.einsum("iad,idj->iaj", frames, J),
            k=k,
            b=2.0 * damping_ratio * np.sqrt(k * mass),
            mu=np.asarray(grasp.mu, dtype=float),
        )

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
        cap = self.mu * cn
        size = np.sqrt(np.einsum("ij,ij->i", spring, spring))
        sliding = size > cap
        unit = spring / np.maximum(size, 1e-300)[:, None]
        ft = np.where(sliding[:, None], cap[:, None] * unit, spring - self.b[:, None] * gdt)
        size_t = np.sqrt(np.einsum("ij,ij->i", ft, ft))
        ft *= np.minimum(1.0, cap / np.maximum(size_t, 1e-300))[:, None]
        slid = np.where(sliding[:, None], gt + (cap / self.k)[:, None] * unit, self.anchors)
        self.anchors = np.where(touching[:, None], slid, gt)
        return cn[:, None] * n + ft, arms, sliding & touching
