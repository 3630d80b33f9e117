"""Friction-pyramid refinement where the grasp loads it (``Settings.cone_tolerance``,
docs/methods.md).

A solution on a pyramid with few edges is the answer of a polygonal friction law. Where a
contact's force sits on the pyramid's boundary, or the contact slides, the polygon limits the
answer; elsewhere it does not. Each round solves the grasp, then bisects, for every such
contact, the sector of adjacent edges that holds the force direction (force on the boundary)
or the direction against the slip (sliding), when it is wider than the tolerance; the new
edges lie on the Coulomb cone, so the inscribed pyramid grows towards the cone. The rounds
stop when no loaded sector is wider than the tolerance; the answer then approaches the
circular cone's. Limits are counts: at most :data:`~pinograsp.core.cones.MAX_REFINED_EDGES`
edges per contact and :data:`MAX_ROUNDS` rounds; hitting either is warned about
(:class:`~pinograsp.errors.RefinementWarning`) and the answer of the last round is returned.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import TypeVar

import numpy as np

from ..core.cones import MAX_REFINED_EDGES, edge_angles, refined, sector_of
from ..core.model import GraspModel
from ..core.results import PassiveResponse
from ..errors import RefinementWarning

#: Refinement rounds of one query (each bisects every loaded sector once).
MAX_ROUNDS = 40
#: A force within this fraction of the pyramid's boundary is on it (a probe just below a limit
#: found by a load-factor problem sits 1e-6 inside it).
BOUNDARY = 1e-4
#: A direction within this angle [rad] of an edge lies on it (both sectors are bisected).
ON_EDGE = 1e-9

T = TypeVar("T")


def _boundary_radius(angles: np.ndarray, mu: float, phi: float) -> tuple[float, tuple[float, float]]:
    """Radius of the pyramid's cross-section (``|c_t| / c_n``) at direction ``phi`` and the
    sector holding ``phi``."""
    a, b = sector_of(angles, phi)
    half = 0.5 * (b - a)
    return mu * np.cos(half) / np.cos(phi - 0.5 * (a + b)), (a, b)


def _sectors(angles: np.ndarray, phi: float) -> list[tuple[float, float]]:
    """The sector holding ``phi``, and its neighbour when ``phi`` lies on an edge."""
    a, b = sector_of(angles, phi)
    out = [(a, b)]
    if abs(np.angle(np.exp(1j * (phi - a)))) <= ON_EDGE:
        out.append(sector_of(angles, a - 2 * ON_EDGE))
    elif abs(np.angle(np.exp(1j * (phi - b)))) <= ON_EDGE:
        out.append(sector_of(angles, b + 2 * ON_EDGE))
    return out


def split_angles(model: GraspModel, resp: PassiveResponse, tol: float) -> tuple[dict[int, list[float]], bool]:
    """New edge angles [rad] per contact for one round, and whether a contact at its edge
    limit still had a sector wider than ``tol`` [rad]."""
    out: dict[int, list[float]] = {}
    capped = False
    for i, state in enumerate(resp.contact_states):
        mu = float(model.mu[i])
        if state == "separated" or mu <= 0:
            continue
        angles = edge_angles(model, i)
        dirs = []
        cn, ct = resp.contact_forces[i, 0], resp.contact_forces[i, 1:3]
        phi_f = float(np.arctan2(ct[1], ct[0]))
        radius, _ = _boundary_radius(angles, mu, phi_f)
        if np.linalg.norm(ct) >= (1.0 - BOUNDARY) * radius * cn:
            dirs.append(phi_f)
        if state == "sliding" and resp.contact_slip is not None:
            s = model.frames[i].T @ resp.contact_slip[i]
            dirs.append(float(np.arctan2(-s[2], -s[1])))
        mids = sorted(
            {
                round(float(np.mod(0.5 * (a + b), 2 * np.pi)), 15)
                for p in dirs
                for a, b in _sectors(angles, p)
                if b - a > tol
            }
        )
        if not mids:
            continue
        if len(angles) + len(mids) > MAX_REFINED_EDGES:
            capped = True
            continue
        out[i] = mids
    return out, capped


def refine(
    model: GraspModel, tol: float, run: Callable[[GraspModel], tuple[T, PassiveResponse | None]]
) -> tuple[T, GraspModel]:
    """Run ``run`` on ever finer pyramids of ``model`` until no loaded sector is wider than
    ``tol`` [rad].

    Args:
        model: The grasp (3D; planar pyramids are exact).
        tol: Angular tolerance [rad].
        run: One solve on a model: its answer and the response whose forces and slips say
            where to refine (None: nothing to refine, the answer stands).

    Returns:
        The last answer and the model it was found on (``model.edge_counts`` per contact).
    """
    m = model
    for _ in range(MAX_ROUNDS):
        out, resp = run(m)
        if resp is None or resp.audit is None:
            return out, m
        add, capped = split_angles(m, resp, tol)
        if capped:
            warnings.warn(
                f"cone refinement reached {MAX_REFINED_EDGES} edges on a contact before its loaded sector "
                f"was narrower than {np.degrees(tol):.3g} deg",
                RefinementWarning,
                stacklevel=4,
            )
        if not add:
            return out, m
        m = refined(m, add)
    warnings.warn(
        f"cone refinement stopped after {MAX_ROUNDS} rounds (tolerance {np.degrees(tol):.3g} deg)",
        RefinementWarning,
        stacklevel=4,
    )
    return out, m
