"""Linear-compliance baseline (Bicchi): ``c = c_0 - G_K^+ w``, solved as a ProxSuite QP.

The particular solution is the compliance-weighted minimum-energy distribution of the wrench
over rigidly held contacts with linear springs — normal stiffness ``k``, tangential stiffness
``k_t`` (default ``mu k``, as in the seed paper's Fig. 1) — and rigid joints:

    minimise ½ Δcᵀ K⁻¹ Δc   subject to   G Δc = -w,

whose solution is ``Δc = -K Gᵀ (G K Gᵀ)⁻¹ w`` (the object moves ``x = (G K Gᵀ)⁻¹ w``). Added to
the internal (preload) forces ``c_0``, it shows where the linear model is wrong: contacts that
would have to pull, or leave their friction cones (seed Fig. 1).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import proxsuite

from ..core.model import GraspModel
from ..core.serialize import format_magnitude, jsonable
from ..core.validate import STIFFNESS, finite_array, finite_number, positive_number
from ..errors import InvalidInputError, SolverError


@dataclass(frozen=True)
class LinearComplianceResult:
    """Contact forces predicted by the linear-compliance model.

    Attributes:
        contact_forces: ``c_0 + Δc`` in contact frames ``(c_n, c_t1, c_t2)``, (nc, 3) [N].
        contact_forces_world: The same in the world frame, (nc, 3) [N].
        particular: ``Δc``, the wrench's share, (nc, 3) [N].
        internal: ``c_0``, the preload (homogeneous) forces, (nc, 3) [N].
        object_displacement: ``(G K Gᵀ)⁻¹ w`` (6,) [m, rad].
        push_violations: Names of contacts whose normal force is negative (would pull).
        friction_violations: Names of contacts outside their friction cone ``|c_t| <= mu c_n``.
        friction_ratio: ``|c_t| / (mu c_n)`` per contact (inf where ``c_n <= 0`` and ``c_t != 0``).
        contact_names: Labels of the rows above, (nc,).
    """

    contact_forces: np.ndarray
    contact_forces_world: np.ndarray
    particular: np.ndarray
    internal: np.ndarray
    object_displacement: np.ndarray
    push_violations: tuple[str, ...]
    friction_violations: tuple[str, ...]
    friction_ratio: np.ndarray
    contact_names: tuple[str, ...] = ()

    @property
    def valid(self) -> bool:
        """No contact pulls and every contact is inside its friction cone."""
        return not self.push_violations and not self.friction_violations

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: ``valid``, the forces [N] as lists (nc, 3), the object
        displacement [m, rad], the violations and ``friction_ratio`` (``None`` where infinite)."""
        return jsonable(
            {
                "valid": self.valid,
                "contact_names": list(self.contact_names),
                "contact_forces": self.contact_forces,
                "contact_forces_world": self.contact_forces_world,
                "particular": self.particular,
                "internal": self.internal,
                "object_displacement": self.object_displacement,
                "push_violations": list(self.push_violations),
                "friction_violations": list(self.friction_violations),
                "friction_ratio": self.friction_ratio,
            }
        )

    def summary(self) -> str:
        """Validity, the violating contacts, normal forces [N] and friction use, as text."""
        names = self.contact_names or tuple(f"#{i}" for i in range(len(self.contact_forces)))
        normal = ", ".join(
            f"{nm} {format_magnitude(f, 1e-6, 'N')}" for nm, f in zip(names, self.contact_forces[:, 0])
        )
        lines = [
            f"linear compliance: {'valid' if self.valid else 'INVALID'}"
            f" (pulls: {', '.join(self.push_violations) or 'none'};"
            f" outside the friction cone: {', '.join(self.friction_violations) or 'none'})",
            "normal contact forces: " + normal,
            "|c_t| / mu c_n: " + ", ".join(f"{nm} {x:.3g}" for nm, x in zip(names, self.friction_ratio)),
        ]
        return "\n".join(lines)


def _tangential_stiffness(m: GraspModel, tangential_stiffness: object | None) -> np.ndarray:
    """Tangential stiffness per contact (nc,) [N/m] (default ``mu * k``)."""
    if tangential_stiffness is None:
        kt = m.mu * m.k
    elif isinstance(tangential_stiffness, (int, float, np.number)):  # a ragged list is no scalar
        kt = np.full(m.nc, finite_number("tangential_stiffness", tangential_stiffness))
    else:
        kt = finite_array("tangential_stiffness", tangential_stiffness, (m.nc,))
    if np.any(kt < 0) or np.any(kt > STIFFNESS[1]):
        raise InvalidInputError(
            "tangential_stiffness", f"expected {m.nc} values in [0, {STIFFNESS[1]:g}] N/m (docs/errors.md)"
        )
    return kt


def _spring_forces(m: GraspModel, w: np.ndarray, kdiag: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The least-spring-energy contact forces ``Δc`` (nc*d,) [N] balancing the reduced wrench
    ``w`` (``G Δc = -w``, stiffness ``kdiag`` (nc*d,); a zero stiffness carries no force) and
    the multipliers of the balance (the object displacement)."""
    free = kdiag > 0
    Gf = m.G[:, free]
    n = int(free.sum())
    H = np.diag(1.0 / kdiag[free])
    qp = proxsuite.proxqp.dense.QP(n, m.nw, 0)
    qp.settings.eps_abs = 1e-12
    qp.settings.eps_rel = 0.0
    qp.settings.verbose = False
    qp.init(H, np.zeros(n), Gf, -w, None, None, None)
    qp.solve()
    dc = np.zeros(m.nc * m.d)
    dc[free] = qp.results.x
    res = np.abs(m.G @ dc + w).max()
    if qp.results.info.status != proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED or res > 1e-8 * max(
        1.0, np.abs(w).max()
    ):
        raise SolverError(
            f"the contacts cannot balance this wrench with linear springs (residual {res:.3g})",
            solver="proxsuite",
            status=str(qp.results.info.status),
        )
    return dc, np.array(qp.results.y)  # multipliers of G Δc = -w are the object displacement


def linear_compliance(
    model: GraspModel,
    wrench: object,
    internal_forces: object | None = None,
    *,
    tangential_stiffness: object | None = None,
    tol: float = 1e-9,
) -> LinearComplianceResult:
    """Linear-compliance contact forces for ``wrench`` on top of ``internal_forces``.

    Args:
        model: The grasp (joints are taken rigid, as in the seed paper's Fig. 1).
        wrench: External wrench on the object (6,) [N, N·m] (planar models: 3 also accepted).
        internal_forces: Preload contact forces ``c_0`` in contact frames, (nc, 3) [N]; e.g.
            ``passive_response(model, command, 0).contact_forces``. Default zero.
        tangential_stiffness: Tangential spring stiffness per contact (nc,) or one for all [N/m]; default
            ``mu * k``. Zero means that direction carries no force.
        tol: Tolerance [N] of the push and friction checks.
    """
    m = model
    w6 = m.wrench_vector(wrench)
    w = m.reduce_wrench(w6)
    nc, d = m.nc, m.d
    tol = positive_number("tol", tol)
    c0 = (
        np.zeros((nc, 3))
        if internal_forces is None
        else finite_array("internal_forces", internal_forces, (nc, 3))
    )
    kt = _tangential_stiffness(m, tangential_stiffness)
    kdiag = np.column_stack([m.k] + [kt] * (d - 1)).reshape(-1)  # (nc*d,)
    dc, x = _spring_forces(m, w, kdiag)
    part = np.zeros((nc, 3))
    part[:, :d] = dc.reshape(nc, d)
    c = c0 + part
    cw = np.einsum("ijk,ik->ij", m.frames, c)
    ct = np.linalg.norm(c[:, 1:], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(ct <= tol, 0.0, ct / (m.mu * np.maximum(c[:, 0], 0.0)))
    push = tuple(nm for nm, cn in zip(m.contact_names, c[:, 0]) if cn < -tol)
    fric = tuple(
        nm for nm, cn, t, mu in zip(m.contact_names, c[:, 0], ct, m.mu) if t > mu * max(cn, 0.0) + tol
    )
    xs = np.zeros(m.nw)
    xs[:] = x[: m.nw] if x.size >= m.nw else 0.0
    return LinearComplianceResult(
        contact_forces=c,
        contact_forces_world=cw,
        particular=part,
        internal=c0,
        object_displacement=m.expand_twist(xs),
        push_violations=push,
        friction_violations=fric,
        friction_ratio=ratio,
        contact_names=tuple(m.contact_names),
    )
