"""Explicit-contact scenes (``contacts:`` key): contact points, normals and friction with revolute
pivots or Jacobian rows, plus actuators and couplings -> the grasp's parts (docs/scenes.md).

The analytic grasps of :mod:`pinograsp.core.examples` are scenes of this kind.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..core.actuation import ACTUATOR_KINDS, Actuator, Coupling
from ..core.contact import Contact
from ..errors import PinograspError
from .fields import SceneFile, show
from .schema import EXPLICIT_KEYS, GraspParts

#: Keys of one entry of ``contacts``.
_CONTACT_KEYS = ("name", "point", "normal", "mu", "stiffness", "tangent", "revolute", "jacobian")


def _actuators(f: SceneFile, value: object, key: str) -> list[Actuator]:
    """The ``actuators`` list: ``{name, kind, transmission: {joint: arm}, bidirectional}``."""
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
        raise f.error(key, f"expected a list of actuators, got {show(value)}")
    out = []
    for i, a in enumerate(value):
        ka = f"{key}[{i}]"
        a = f.mapping(a, ka)
        f.keys(a, ("name", "kind", "transmission", "bidirectional"), ka)
        tr = f.mapping(f.require(a, "transmission", ka), f"{ka}.transmission", "a mapping joint -> arm")
        trv: dict[int | str, float] = {str(j): f.number(v, f"{ka}.transmission.{j}") for j, v in tr.items()}
        kind = str(a.get("kind", "non-backdrivable"))
        if kind not in ACTUATOR_KINDS:
            raise f.error(f"{ka}.kind", f"unknown kind {kind!r}; valid kinds: {', '.join(ACTUATOR_KINDS)}")
        bidir = a.get("bidirectional", False)
        if not isinstance(bidir, bool):
            raise f.error(f"{ka}.bidirectional", f"expected true or false, got {show(bidir)}")
        out.append(Actuator(trv, kind, str(a.get("name", f"a{i}")), bidirectional=bidir))
    return out


def _couplings(f: SceneFile, value: object, key: str) -> list[Coupling]:
    """The ``couplings`` list: ``{name, weights}`` or ``{name, follower, leader, ratio}``."""
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
        raise f.error(key, f"expected a list of couplings, got {show(value)}")
    out = []
    for i, c in enumerate(value):
        kc = f"{key}[{i}]"
        c = f.mapping(c, kc)
        f.keys(c, ("name", "weights", "follower", "leader", "ratio"), kc)
        name = str(c.get("name", f"coupling{i}"))
        if "weights" in c:
            w = f.mapping(c["weights"], f"{kc}.weights")
            out.append(Coupling({str(j): f.number(v, f"{kc}.weights.{j}") for j, v in w.items()}, name))
        elif "follower" in c and "leader" in c:
            ratio = f.number(c.get("ratio", 1.0), f"{kc}.ratio")
            fo, le = f.string(c["follower"], f"{kc}.follower"), f.string(c["leader"], f"{kc}.leader")
            if fo == le:
                raise f.error(kc, f"joint {fo!r} cannot follow itself")
            out.append(Coupling.follow(fo, le, ratio, name=name))
        else:
            raise f.error(kc, "give 'weights', or 'follower', 'leader' and 'ratio'")
    return out


def _pick(value: float | dict[str, float], name: str) -> float:
    """A per-name value (:meth:`SceneFile.per_name`) for ``name``."""
    return float(value[name]) if isinstance(value, dict) else float(value)


def _jacobian(f: SceneFile, c: Mapping, kc: str, joints: list[str], p: np.ndarray) -> np.ndarray:
    """A contact's Jacobian (3, nq) from ``revolute: {joint: {pivot, axis}}`` or ``jacobian`` rows
    (``p``: the contact point [m]); zero without either."""
    nq = len(joints)
    if "revolute" in c and "jacobian" in c:
        raise f.error(kc, "give 'revolute' or 'jacobian', not both")
    jac = np.zeros((3, nq))
    if c.get("revolute") is not None:
        rv = f.mapping(c["revolute"], f"{kc}.revolute", "a mapping joint -> {pivot, axis}")
        for j, spec in rv.items():
            kj = f"{kc}.revolute.{j}"
            if j not in joints:
                raise f.error(kj, f"unknown joint; joints: {', '.join(joints) or '(none declared)'}")
            spec = f.mapping(spec, kj, "a mapping with 'pivot' and 'axis'")
            f.keys(spec, ("pivot", "axis"), kj)
            pivot = f.vector(f.require(spec, "pivot", kj), 3, f"{kj}.pivot")
            axis = f.vector(f.require(spec, "axis", kj), 3, f"{kj}.axis")
            if not np.linalg.norm(axis) > 0:
                raise f.error(f"{kj}.axis", "zero-length axis")
            jac[:, joints.index(str(j))] = np.cross(axis / np.linalg.norm(axis), p - pivot)
    elif c.get("jacobian") is not None:
        rows = c["jacobian"]
        if isinstance(rows, (str, bytes)) or not isinstance(rows, Sequence) or len(rows) != 3:
            raise f.error(f"{kc}.jacobian", f"expected 3 rows of {nq} numbers, got {show(rows)}")
        jac = np.array([f.vector(r, nq, f"{kc}.jacobian[{ri}]") for ri, r in enumerate(rows)])
    return jac


def _contact(
    f: SceneFile,
    c: Mapping,
    kc: str,
    name: str,
    joints: list[str],
    mu: float | dict[str, float],
    stiffness: float | dict[str, float],
) -> Contact:
    """One entry of ``contacts`` (``mu``, ``stiffness``: the scene's per-name defaults)."""
    f.keys(c, _CONTACT_KEYS, kc)
    p = f.vector(f.require(c, "point", kc), 3, f"{kc}.point")
    n = f.vector(f.require(c, "normal", kc), 3, f"{kc}.normal")
    nn = float(np.linalg.norm(n))
    if not nn > 0:
        raise f.error(f"{kc}.normal", "zero-length normal")
    n = n / nn
    mu_i = f.number(c["mu"], f"{kc}.mu", nonneg=True) if "mu" in c else _pick(mu, name)
    k_i = (
        f.number(c["stiffness"], f"{kc}.stiffness", positive=True)
        if "stiffness" in c
        else _pick(stiffness, name)
    )
    t = f.vector(c["tangent"], 3, f"{kc}.tangent") if c.get("tangent") is not None else None
    jac = _jacobian(f, c, kc, joints, p)
    try:
        return Contact(p, n, mu_i, jac, t, k_i, name)
    except PinograspError as exc:
        raise f.error(kc, str(exc)) from exc


def build_explicit(f: SceneFile, d: Mapping) -> GraspParts:
    """The parts of an explicit-contact scene's grasp (``d``: the scene's top-level keys)."""
    f.keys(d, EXPLICIT_KEYS, "")
    joints = f.names(d["joints"], "joints") if d.get("joints") is not None else []
    if len(set(joints)) != len(joints):
        raise f.error("joints", f"duplicate joint names in {joints}")
    raw = d["contacts"]
    if isinstance(raw, (str, bytes)) or not isinstance(raw, Sequence) or not raw:
        raise f.error("contacts", f"expected a non-empty list of contacts, got {show(raw)}")
    entries = [f.mapping(c, f"contacts[{i}]") for i, c in enumerate(raw)]
    cnames = [str(c.get("name", f"c{i}")) for i, c in enumerate(entries)]
    mu = f.per_name(d.get("friction"), "friction", cnames, 0.5, nonneg=True)
    kk = f.per_name(d.get("stiffness"), "stiffness", cnames, 1.0, positive=True)
    contacts = [_contact(f, c, f"contacts[{i}]", cnames[i], joints, mu, kk) for i, c in enumerate(entries)]
    acts = _actuators(f, d["actuators"], "actuators") if d.get("actuators") is not None else None
    cps = _couplings(f, d["couplings"], "couplings") if d.get("couplings") is not None else []
    for key, items, attr in (("actuators", acts or [], "transmission"), ("couplings", cps, "weights")):
        for i, it in enumerate(items):
            for j in getattr(it, attr):
                if j not in joints:
                    raise f.error(
                        f"{key}[{i}].{attr}.{j}", f"unknown joint; joints: {', '.join(joints) or '(none)'}"
                    )
    o = f.vector(d["reference_point"], 3, "reference_point") if d.get("reference_point") is not None else None
    return GraspParts(
        contacts=tuple(contacts),
        actuators=None if acts is None else tuple(acts),
        couplings=tuple(cps),
        joint_names=tuple(joints),
        reference_point=o,
    )
