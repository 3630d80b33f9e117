"""Friction pyramids as data: worst-case contact-normal uncertainty and refinement of the
pyramid where it is loaded (docs/methods.md).

Both are transformations of a :class:`~pinograsp.core.model.GraspModel` into another one with
other pyramid edges, so every solver reads them like any model:

* :func:`with_normal_uncertainty` — the contact normal is known to within an angle ``u``
  [rad]. In the worst case the true normal leans away from the force, so the cone the force
  must lie in shrinks to the half-angle ``atan(mu) - u`` about the nominal normal:
  ``mu -> tan(max(atan(mu) - u, 0))``. The energetic problem also takes the worst case of the
  spring law: a contact that slips by ``s`` along a surface tilted by ``u`` loses ``tan(u) s``
  of its compression (the model keeps ``u`` for it, :attr:`GraspModel.normal_uncertainty`).
* :func:`refined` — the pyramid of some contacts gets extra edges on the Coulomb cone at given
  angles (the inscribed pyramid grows towards the cone). The analyses bisect the sector a
  contact's force or slip direction lies in until it is narrower than a tolerance
  (:mod:`pinograsp.analysis.refine`).

Edge angles are measured in the contact's tangent plane from ``t1`` towards ``t2`` [rad].
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any, ClassVar, Protocol, TypeVar

import numpy as np

from ..errors import InvalidInputError
from .build import readonly


class ConeModel(Protocol):
    """What the friction-cone functions read from a :class:`~pinograsp.core.model.GraspModel`
    (model.py imports this module, so it is named by its members): ``nc`` contacts, ``d`` rows
    per contact, the pyramid edges ``D`` (nc d, nb) owned by ``beta_contact`` (nb,), ``mu``
    (nc,), ``normal_uncertainty`` [rad]."""

    __dataclass_fields__: ClassVar[dict[str, Any]]

    @property
    def nc(self) -> int: ...
    @property
    def d(self) -> int: ...
    @property
    def planar(self) -> bool: ...
    @property
    def D(self) -> np.ndarray: ...
    @property
    def beta_contact(self) -> np.ndarray: ...
    @property
    def mu(self) -> np.ndarray: ...
    @property
    def normal_uncertainty(self) -> float: ...
    @property
    def contact_names(self) -> tuple[str, ...]: ...


#: A :class:`~pinograsp.core.model.GraspModel` (returned as the same type).
M = TypeVar("M", bound=ConeModel)

#: Largest number of pyramid edges per contact that refinement may create.
MAX_REFINED_EDGES = 100


def check_angle(name: str, value: object, upper: float = np.pi / 2) -> float:
    """``value`` as an angle in ``[0, upper)`` [rad], else :class:`InvalidInputError`."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise InvalidInputError(name, f"expected an angle in radians, got {value!r}")
    v = float(value)
    if not (np.isfinite(v) and 0.0 <= v < upper):
        raise InvalidInputError(name, f"must be an angle in [0, {upper:.6g}) rad, got {value!r}")
    return v


def effective_mu(mu: np.ndarray, uncertainty: float) -> np.ndarray:
    """Friction coefficients of the worst-case cone: ``tan(max(atan(mu) - u, 0))``, (nc,)."""
    return np.tan(np.maximum(np.arctan(np.asarray(mu, float)) - float(uncertainty), 0.0))


def with_normal_uncertainty(model: M, uncertainty: float) -> M:
    """``model`` with every contact normal uncertain by ``uncertainty`` [rad] (worst case).

    The tangential part of every pyramid edge is scaled by ``mu' / mu`` and ``mu`` becomes
    ``mu'`` (:func:`effective_mu`); ``uncertainty = 0`` returns ``model`` itself.
    """
    u = check_angle("normal_uncertainty", uncertainty)
    if u == model.normal_uncertainty:
        return model
    if model.normal_uncertainty != 0.0:
        raise InvalidInputError(
            "normal_uncertainty", "the model already has a normal uncertainty; apply it to the nominal model"
        )
    mu = np.asarray(model.mu, float)
    mu_eff = effective_mu(mu, u)
    ratio = np.divide(mu_eff, mu, out=np.zeros_like(mu), where=mu > 0)
    d = model.d
    D = np.array(model.D)
    for i in range(model.nc):
        D[i * d + 1 : (i + 1) * d] *= ratio[i]
    return replace(model, D=readonly(D), mu=readonly(mu_eff), normal_uncertainty=u)


def edge_angles(model: ConeModel, contact: int) -> np.ndarray:
    """Angles of the pyramid edges of ``contact`` in its tangent plane [rad], in column order."""
    d = model.d
    cols = np.flatnonzero(np.asarray(model.beta_contact) == contact)
    t = model.D[contact * d + 1 : (contact + 1) * d][:, cols]
    if d == 2:
        return np.where(t[0] >= 0, 0.0, np.pi)
    return np.arctan2(t[1], t[0])


def sector_of(angles: np.ndarray, phi: float) -> tuple[float, float]:
    """The sector ``[a, b]`` (``b > a``, ``b - a <= 2π``) of sorted edge ``angles`` that holds
    the direction ``phi`` [rad]."""
    a = np.sort(np.mod(angles, 2 * np.pi))
    p = float(np.mod(phi, 2 * np.pi))
    k = int(np.searchsorted(a, p, side="right")) - 1
    if k < 0 or k == len(a) - 1:
        lo = a[-1]
        hi = a[0] + 2 * np.pi
        return (lo - 2 * np.pi, hi - 2 * np.pi) if k < 0 else (lo, hi)
    return float(a[k]), float(a[k + 1])


def refined(model: M, extra: Mapping[int, list[float]]) -> M:
    """``model`` with edges added on the cone of each contact ``i`` of ``extra`` at the angles
    ``extra[i]`` [rad] (the inscribed pyramid; 3D models only).

    Raises:
        InvalidInputError: a contact without friction, a circumscribed pyramid (its faces
            already touch the cone: edges on the cone would not change it), or more than
            :data:`MAX_REFINED_EDGES` edges on a contact.
    """
    if model.planar:
        raise InvalidInputError("cone_tolerance", "planar pyramids (2 edges) are already exact")
    d = model.d
    blocks_D, owners = [], []
    for i in range(model.nc):
        cols = np.flatnonzero(np.asarray(model.beta_contact) == i)
        block = np.array(model.D[i * d : (i + 1) * d][:, cols])
        add = sorted(set(float(np.mod(a, 2 * np.pi)) for a in extra.get(i, ())))
        if add:
            mu = float(model.mu[i])
            radius = np.linalg.norm(block[1:], axis=0)
            if mu <= 0:
                raise InvalidInputError(
                    "cone_tolerance", f"contact {model.contact_names[i]!r} has no friction"
                )
            if np.any(radius > mu * (1 + 1e-9)):
                raise InvalidInputError(
                    "cone_tolerance", "cone refinement needs the inscribed pyramid (circumscribed=False)"
                )
            new = np.vstack([np.ones(len(add)), mu * np.cos(add), mu * np.sin(add)])
            block = np.hstack([block, new])
            order = np.argsort(np.mod(np.arctan2(block[2], block[1]), 2 * np.pi), kind="stable")
            block = block[:, order]
            if block.shape[1] > MAX_REFINED_EDGES:
                raise InvalidInputError(
                    "cone_tolerance",
                    f"more than {MAX_REFINED_EDGES} edges on contact {model.contact_names[i]!r}",
                )
        blocks_D.append(block)
        owners += [i] * block.shape[1]
    nb = len(owners)
    D = np.zeros((model.nc * d, nb))
    o = 0
    for i, block in enumerate(blocks_D):
        D[i * d : (i + 1) * d, o : o + block.shape[1]] = block
        o += block.shape[1]
    owner = np.array(owners, int)
    owner.setflags(write=False)
    return replace(model, D=readonly(D), beta_contact=owner)


def edge_counts(model: ConeModel) -> tuple[int, ...]:
    """Pyramid edges of every contact, (nc,)."""
    counts = np.bincount(np.asarray(model.beta_contact, int), minlength=model.nc)
    return tuple(int(c) for c in counts)
