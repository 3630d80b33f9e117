"""Test grasps that ``pinograsp.examples`` does not build, and their closed forms.

* :func:`pinch_contacts`, :func:`pinch_variant` — ``examples.pinch_contacts`` / ``examples.pinch``
  with this module's constants (tests move, rescale and reorder the contacts);
* :func:`with_stiffness` — any model with other contact stiffnesses;
* :func:`double_pinch` and :func:`ring` — the stress catalogue's own geometries;
* :func:`stored_grasp` / :func:`store_grasp` — a grasp kept in ``tests/data`` as its
  :class:`~pinograsp.GraspModel` arrays and command (planned grasps, without the planner).

The pinch: half width ``A`` [m], finger length ``L`` [m], friction ``MU``, preload ``TAU``
[N·m] (docs/analytic_cases.md).
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

import pinograsp as pg

EZ = np.array([0.0, 0.0, 1.0])
A, L, MU, TAU = 0.05, 0.1, 0.5, 1.0
#: Preload normal force of ``examples.coupled_finger`` [N]: ``TAU`` over its moment arm.
COUPLED_CN = TAU / (0.06 + 4 * 0.04 / 3)


def pinch_contacts(h: float = 0.0, mu: float = MU, tilt: float = 0.0, right=None) -> list[pg.Contact]:
    """The contacts of ``examples.pinch(h=h, mu=mu, tilt=tilt, right=right)``."""
    return pg.examples.pinch_contacts(A, L, mu, 1.0, h, tilt=tilt, right=right)


def pinch_variant(
    planar: bool = True, edges: int | None = None, circumscribed: bool = False, **kw
) -> pg.GraspModel:
    """``examples.pinch`` with ``edges`` pyramid edges and the variants of :func:`pinch_contacts`."""
    return pg.examples.pinch(planar=planar, edges=edges, circumscribed=circumscribed, **kw)


def with_stiffness(model: pg.GraspModel, stiffness) -> pg.GraspModel:
    """``model`` with the normal stiffness of its contacts replaced, (nc,) [N/m]."""
    k = np.array(stiffness, dtype=float)
    k.flags.writeable = False
    return dataclasses.replace(model, k=k)


def double_pinch(delta: float) -> pg.GraspModel:
    """3D double pinch: fingers at (∓A, 0, ±delta); G's smallest singular value ~ delta.

    A torque about x is resisted only by tangential (y) forces with lever ``delta``:
    ``mx_max = 4 delta MU TAU / L``.
    """
    cs, j = [], 0
    for z in (delta, -delta):
        for x, n, axis in ((-A, 1.0, -EZ), (A, -1.0, EZ)):
            name = f"{'l' if x < 0 else 'r'}{j}"
            cs.append(
                pg.Contact.revolute([x, 0, z], [n, 0, 0], {j: ([x, -L, z], axis)}, nq=4, mu=MU, name=name)
            )
            j += 1
    return pg.GraspModel.from_contacts(cs)


def ring(n=20, kind="non-backdrivable", planar=True, edges=None, ks=None, r=0.05) -> pg.GraspModel:
    """``n`` fingers around a disc of radius ``r`` [m], each pushing radially inward with ``TAU / L``.

    Closed forms (every finger's Jacobian is along its normal): ``mz_max = n MU (TAU/L) r``;
    non-backdrivable: every force direction is resisted without bound (the fingers hold);
    backdrivable (normal forces fixed at ``TAU/L``): ``F_max(y) = MU (TAU/L) sum_i |cos a_i|``
    (:func:`ring_fy`). ``ks``: contact stiffnesses, (n,) [N/m] (default 1).
    """
    cs = []
    for i in range(n):
        ang = 2 * np.pi * i / n
        p = r * np.array([np.cos(ang), np.sin(ang), 0.0])
        nrm = -p / r
        piv = p + L * np.array([-np.sin(ang), np.cos(ang), 0.0])
        axis = EZ if np.cross(EZ, p - piv) @ nrm > 0 else -EZ
        k = 1.0 if ks is None else float(ks[i])
        cs.append(pg.Contact.revolute(p, nrm, {i: (piv, axis)}, nq=n, mu=MU, stiffness=k, name=f"c{i}"))
    acts = [pg.Actuator({i: 1.0}, kind=kind, name=f"a{i}") for i in range(n)]
    return pg.GraspModel.from_contacts(cs, acts, planar=planar, edges=edges)


def ring_fy(n: int) -> float:
    """Largest force along y [N] that the backdrivable :func:`ring` of ``n`` fingers resists."""
    ang = 2 * np.pi * np.arange(n) / n
    return float(MU * TAU / L * np.abs(np.cos(ang)).sum())


def pyramid_fmax(m: int, phi: float, circumscribed: bool) -> float:
    """3D pinch with ``m``-edge pyramids, load along (0, cos phi, sin phi): the limit [N].

    Twice the pyramid's reach along ``phi`` times ``TAU / L``.
    """
    half = np.pi / m
    k = np.floor(phi / (2 * half))
    mid = (k + 0.5) * 2 * half
    mu_v = MU / np.cos(half) if circumscribed else MU
    return float(2 * TAU / L * mu_v * np.cos(half) / np.cos(phi - mid))


#: The text fields of a stored grasp (the rest are arrays or scalars).
_TEXT = (
    "kinds",
    "contact_names",
    "joint_names",
    "actuator_names",
    "coupling_names",
    "all_actuator_names",
    "bidirectional",
)
_SCALARS = ("planar", "edges", "length_scale", "normal_uncertainty")
_ARRAYS = ("G", "J", "D", "beta_contact", "k", "mu", "R", "C", "points", "frames", "reference_point")


def stored_grasp(path: Path) -> tuple[pg.GraspModel, dict[str, float]]:
    """The model and command of a grasp written by :func:`store_grasp`."""
    raw = json.loads(Path(path).read_text())
    m = raw["model"]
    arrays = {k: np.asarray(m[k], dtype=float) for k in _ARRAYS if k != "beta_contact"}
    beta = np.asarray(m["beta_contact"], dtype=int)
    texts = {k: tuple(m[k]) for k in _TEXT}
    scalars = {k: m[k] for k in _SCALARS}
    return pg.GraspModel(**{**arrays, "beta_contact": beta, **texts, **scalars}), raw["command"]


def store_grasp(path: Path, model: pg.GraspModel, command: dict[str, float], source: str) -> None:
    """Write ``model`` and ``command`` as JSON (``source``: where the grasp comes from)."""
    m = {k: np.asarray(getattr(model, k)).tolist() for k in _ARRAYS}
    m.update({k: list(getattr(model, k)) for k in _TEXT})
    m.update({k: getattr(model, k) for k in _SCALARS})
    Path(path).write_text(json.dumps({"source": source, "command": command, "model": m}))
