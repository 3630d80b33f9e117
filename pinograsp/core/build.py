"""Building a grasp model from explicit contacts, one small step per function.

:meth:`GraspModel.from_contacts <pinograsp.core.model.GraspModel.from_contacts>` calls
:func:`build_model`, which runs, in this order (each step raises on bad input, naming the
argument — docs/errors.md):

1. check the contacts and name them and the joints (:func:`_checked_contacts`,
   :func:`_joint_names`, :func:`_contact_names`);
2. the reference point, the pyramid edge count and, for planar models, that everything lies in
   the XY plane (:func:`_reference_point`, :func:`_edge_count`, :func:`_check_planar`);
3. the actuation over all joints: transmission ``R`` and couplings ``C`` (:func:`_actuation`);
4. pruning of what no contact needs (:func:`_prune`);
5. the contact-frame matrices ``G``, ``J`` and ``D`` (:func:`_grasp_and_hand_maps`,
   :func:`_friction_pyramids`);
6. the length scale and a last finiteness check (:func:`_length_scale`, :func:`_check_finite`).

This module never imports :mod:`pinograsp.core.model` (the model imports it): the model class is
passed to :func:`build_model`. Shapes as in :mod:`pinograsp.core.model`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TypeVar

import numpy as np

from ..errors import InvalidInputError, ModelError, UnknownNameError
from .actuation import Actuator, Coupling
from .contact import Contact, friction_edges
from .validate import MAX_CONTACTS, finite_number, flag, sequence

#: The model being built (:class:`~pinograsp.core.model.GraspModel`, whose constructor
#: ``build_model`` is given: model.py imports this module).
M = TypeVar("M")

#: Relative threshold below which Jacobian entries count as zero (pruning).
ZERO_TOL = 1e-12

#: Largest number of friction pyramid edges accepted (32 edges already approximate the cone
#: to 1 - cos(pi/32) = 0.5 %).
MAX_EDGES = 256


@dataclass(frozen=True)
class PruneRecord:
    """What :meth:`GraspModel.from_contacts` removed because the scene does not need it."""

    joints: tuple[str, ...] = ()
    actuators: tuple[str, ...] = ()
    couplings: tuple[str, ...] = ()
    tangential: tuple[str, ...] = ()
    dropped_transmission: tuple[tuple[str, str], ...] = ()

    def __bool__(self) -> bool:
        return any((self.joints, self.actuators, self.couplings, self.tangential))


def readonly(a: np.ndarray) -> np.ndarray:
    """A C-contiguous float copy (or view) of ``a`` that cannot be written to."""
    a = np.ascontiguousarray(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class _Actuation:
    """Transmission and couplings over all joints, before pruning."""

    R: np.ndarray  # (nq, na)
    C: np.ndarray  # (ncp, nq)
    actuators: tuple[Actuator, ...]
    actuator_names: tuple[str, ...]
    coupling_names: tuple[str, ...]


@dataclass(frozen=True)
class _Kept:
    """What survives pruning; ``record`` lacks the tangential variables (found later)."""

    joints: np.ndarray  # (nq,) bool
    R: np.ndarray  # (nq_kept, na_kept)
    C: np.ndarray  # (ncp_kept, nq_kept)
    joint_names: tuple[str, ...]
    actuator_names: tuple[str, ...]
    coupling_names: tuple[str, ...]
    kinds: tuple[str, ...]
    record: PruneRecord


# ----------------------------------------------------------------------- 1. contacts, names
def _checked_contacts(contacts: object) -> list[Contact]:
    """The contacts as a list, at least one, all :class:`Contact`."""
    contacts = sequence("contacts", contacts)
    if not contacts:
        raise ModelError("a grasp needs at least one contact", argument="contacts")
    if len(contacts) > MAX_CONTACTS:
        raise InvalidInputError(
            "contacts",
            f"{len(contacts)} contacts, more than the {MAX_CONTACTS} a grasp may have (MAX_CONTACTS: "
            "400 took 113 s per direction); merge nearby contacts or use coarser contact geometry",
        )
    for i, c in enumerate(contacts):
        if not isinstance(c, Contact):
            raise InvalidInputError(f"contacts[{i}]", f"expected pinograsp.Contact, got {type(c).__name__}")
    return contacts


def _jacobian_columns(contacts: list[Contact]) -> int | None:
    """The number of joints ``nq`` the contact Jacobians agree on (``None``: no Jacobian)."""
    nqs = {c.jacobian.shape[1] for c in contacts if c.jacobian is not None}
    if len(nqs) > 1:
        detail = ", ".join(
            f"{c.name or i}: {c.jacobian.shape[1]}" for i, c in enumerate(contacts) if c.jacobian is not None
        )
        raise ModelError(
            f"contact Jacobians disagree on the number of joints ({detail})", argument="contacts"
        )
    return nqs.pop() if nqs else None


def _checked_joint_names(joint_names: object) -> list[str] | None:
    """The user's joint labels as a list of strings (``None`` stays ``None``)."""
    if joint_names is None:
        return None
    joint_names = sequence("joint_names", joint_names)
    for n in joint_names:
        if not isinstance(n, str):
            raise InvalidInputError("joint_names", f"expected strings, got {n!r}")
    return joint_names


def _joint_names(joint_names: list[str] | None, nq_jacobian: int | None) -> tuple[str, ...]:
    """One unique label per joint (default ``q0, q1, …``)."""
    if nq_jacobian is not None:
        nq = nq_jacobian
    else:
        nq = len(joint_names) if joint_names is not None else 0
    if joint_names is None:
        joint_names = [f"q{j}" for j in range(nq)]
    names = tuple(str(n) for n in joint_names)
    if len(names) != nq:
        raise ModelError(f"{len(names)} joint names for {nq} Jacobian columns", argument="joint_names")
    if len(set(names)) != nq:
        raise ModelError(f"duplicate joint names in {names}", argument="joint_names")
    return names


def _contact_names(contacts: list[Contact]) -> tuple[str, ...]:
    """The contacts' names (default ``c0, c1, …``), made unique with ``#index`` if needed."""
    names = [c.name if c.name is not None else f"c{i}" for i, c in enumerate(contacts)]
    if len(set(names)) != len(names):
        names = [f"{n}#{i}" for i, n in enumerate(names)]
    return tuple(names)


# ------------------------------------------------------- 2. reference point, edges, plane
def _reference_point(reference_point: object) -> np.ndarray:
    """The object reference point ``o`` [m], (3,); default the origin."""
    try:
        o = np.zeros(3) if reference_point is None else np.asarray(reference_point, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError("reference_point", f"expected 3 numbers, got {reference_point!r}") from exc
    if o.shape != (3,) or not np.all(np.isfinite(o)):
        raise InvalidInputError("reference_point", f"expected 3 finite numbers, got {reference_point!r}")
    return o


def _edge_count(edges: object, planar: bool) -> int:
    """Friction pyramid edges per contact: default 8, at most :data:`MAX_EDGES`, 2 when planar."""
    if edges is None:
        m = 8
    elif isinstance(edges, (bool, np.bool_)) or not isinstance(edges, (int, np.integer)):
        raise InvalidInputError("edges", f"expected an integer number of pyramid edges, got {edges!r}")
    else:
        m = int(edges)
    if m > MAX_EDGES:
        raise InvalidInputError("edges", f"at most {MAX_EDGES} pyramid edges, got {m}")
    if planar:
        return 2
    if m < 3:
        raise InvalidInputError("edges", f"a 3D friction pyramid needs at least 3 edges, got {m}")
    return m


def _world_jacobians(contacts: list[Contact], nq: int) -> np.ndarray:
    """The contacts' world Jacobians, (nc, 3, nq) [m/rad]; at least one must be non-zero."""
    jw = np.array([c.jacobian if c.jacobian is not None else np.zeros((3, nq)) for c in contacts])
    if nq == 0 or not np.any(jw):
        raise ModelError(
            "no contact moves with a joint (every contact is fixed): passive reaction needs at "
            f"least one finger joint that reaches a contact; contacts: {[c.name for c in contacts]}",
            argument="contacts",
        )
    return jw


def _check_planar(
    contacts: list[Contact], names: tuple[str, ...], points: np.ndarray, o: np.ndarray, jw: np.ndarray
) -> None:
    """Every contact point, normal, tangent and Jacobian lies in the plane ``z = o[2]``."""
    scale = max(np.abs(points - o).max(), 1e-300)
    jscale = max(np.abs(jw).max(), 1e-300)
    for i, c in enumerate(contacts):
        if abs(c.point[2] - o[2]) > 1e-9 * scale or abs(c.normal[2]) > 1e-9 or abs(c.frame[2, 1]) > 1e-9:
            raise ModelError(
                f"contact {names[i]!r} is not in the XY plane (point z, normal z or tangent z "
                "non-zero); use planar=False",
                argument="planar",
            )
        if np.any(np.abs(jw[i, 2]) > 1e-9 * jscale):
            raise ModelError(
                f"contact {names[i]!r}: its Jacobian moves it out of the XY plane; use planar=False",
                argument="planar",
            )


# ------------------------------------------------------------------------- 3. actuation
def _joint_index(joint_names: tuple[str, ...], key: int | str) -> int:
    """The index of a joint given by index or name."""
    if isinstance(key, str):
        if key not in joint_names:
            raise UnknownNameError("joint", key, joint_names)
        return joint_names.index(key)
    if not 0 <= key < len(joint_names):
        raise UnknownNameError("joint", key, list(range(len(joint_names))) + list(joint_names))
    return key


def _transmission(
    actuators: object, joint_names: tuple[str, ...]
) -> tuple[tuple[Actuator, ...], tuple[str, ...], np.ndarray]:
    """The actuators (default one direct drive per joint), their names and ``R``, (nq, na)."""
    if actuators is None:
        actuators = [Actuator({j: 1.0}, name=name) for j, name in enumerate(joint_names)]
    actuators = sequence("actuators", actuators)
    names = []
    for i, a in enumerate(actuators):
        if not isinstance(a, Actuator):
            raise InvalidInputError(f"actuators[{i}]", f"expected pinograsp.Actuator, got {type(a).__name__}")
        names.append(a.name if a.name is not None else f"a{i}")
    if len(set(names)) != len(names):
        raise ModelError(f"duplicate actuator names in {names}", argument="actuators")
    R = np.zeros((len(joint_names), len(actuators)))
    for i, a in enumerate(actuators):
        for key, arm in a.transmission.items():
            R[_joint_index(joint_names, key), i] += arm
    return tuple(actuators), tuple(names), R


def _coupling_matrix(couplings: object, joint_names: tuple[str, ...]) -> tuple[np.ndarray, tuple[str, ...]]:
    """``C``, (ncp, nq), and the couplings' names (default ``k0, k1, …``)."""
    nq = len(joint_names)
    if couplings is None:
        return np.zeros((0, nq)), ()
    if isinstance(couplings, np.ndarray):
        try:
            C = np.array(couplings, dtype=float, ndmin=2)
        except (TypeError, ValueError, OverflowError) as exc:
            raise InvalidInputError("couplings", f"expected a numeric (ncp, {nq}) array: {exc}") from exc
        if C.size == 0:
            C = np.zeros((0, nq))
        if C.ndim != 2 or C.shape[1] != nq or not np.all(np.isfinite(C)):
            raise InvalidInputError("couplings", f"expected a finite (ncp, {nq}) array, got shape {C.shape}")
        return C, tuple(f"k{r}" for r in range(C.shape[0]))
    couplings = sequence("couplings", couplings)
    C = np.zeros((len(couplings), nq))
    names = []
    for r, cp in enumerate(couplings):
        if not isinstance(cp, Coupling):
            raise InvalidInputError(
                f"couplings[{r}]", f"expected pinograsp.Coupling, got {type(cp).__name__}"
            )
        names.append(cp.name if cp.name is not None else f"k{r}")
        for key, v in cp.weights.items():
            C[r, _joint_index(joint_names, key)] += v
    return C, tuple(names)


def _actuation(actuators: object, couplings: object, joint_names: tuple[str, ...]) -> _Actuation:
    """Transmission and couplings over all joints."""
    actuators, actuator_names, R = _transmission(actuators, joint_names)
    C, coupling_names = _coupling_matrix(couplings, joint_names)
    if C.shape[0] and np.any(np.all(C == 0, axis=1)):
        raise ModelError("a coupling has all-zero weights", argument="couplings")
    return _Actuation(R, C, actuators, actuator_names, coupling_names)


# --------------------------------------------------------------------------- 4. pruning
def coupled_closure(reaches: np.ndarray, C: np.ndarray) -> np.ndarray:
    """The joints that reach a contact, plus every joint rigidly coupled to one, (nq,) bool.

    A coupling row touching a kept joint keeps all its joints, repeated until nothing changes:
    a motor whose own link touches nothing but that drives touching joints through ``<mimic>``
    couplings (the Talos gripper's ``gripper_left_joint``) keeps its joint, so its actuator and
    couplings survive and its torque balances the contact forces through the coupling ratios.
    """
    keep = np.array(reaches, dtype=bool)
    rows = C != 0
    changed = bool(rows.size)
    while changed:
        changed = False
        for row in rows:
            if np.any(keep & row) and not np.all(keep[row]):
                keep |= row
                changed = True
    return keep


def _prune(act: _Actuation, jw: np.ndarray, joint_names: tuple[str, ...], prune: bool) -> _Kept:
    """Drop joints that reach no contact and are coupled to none that does, then actuators that reach
    no kept joint and couplings through a dropped joint (everything is kept when ``prune`` is false)."""
    nq = len(joint_names)
    reaches = np.any(np.abs(jw) > ZERO_TOL * max(np.abs(jw).max(), 1e-300), axis=(0, 1))
    keep_j = coupled_closure(reaches, act.C) if prune else np.ones(nq, bool)
    dropped = tuple(
        (act.actuator_names[a], joint_names[j])
        for a in range(act.R.shape[1])
        for j in range(nq)
        if not keep_j[j] and act.R[j, a] != 0
    )
    keep_cp = ~np.any(act.C[:, ~keep_j] != 0, axis=1) if act.C.shape[0] else np.zeros(0, bool)
    R = act.R[keep_j]
    keep_a = np.any(R != 0, axis=0) if prune else np.ones(R.shape[1], bool)
    record = PruneRecord(
        joints=tuple(n for n, keep in zip(joint_names, keep_j) if not keep),
        actuators=tuple(n for n, keep in zip(act.actuator_names, keep_a) if not keep),
        couplings=tuple(n for n, keep in zip(act.coupling_names, keep_cp) if not keep),
        dropped_transmission=dropped,
    )
    return _Kept(
        joints=keep_j,
        R=R[:, keep_a],
        C=act.C[keep_cp][:, keep_j],
        joint_names=tuple(n for n, keep in zip(joint_names, keep_j) if keep),
        actuator_names=tuple(n for n, keep in zip(act.actuator_names, keep_a) if keep),
        coupling_names=tuple(n for n, keep in zip(act.coupling_names, keep_cp) if keep),
        kinds=tuple(a.kind for a, keep in zip(act.actuators, keep_a) if keep),
        record=record,
    )


# -------------------------------------------------------------- 5. contact-frame matrices
def _grasp_and_hand_maps(
    points: np.ndarray, frames: np.ndarray, o: np.ndarray, jw: np.ndarray, planar: bool
) -> tuple[np.ndarray, np.ndarray]:
    """The grasp map ``G``, (nw, nc*d), and the hand Jacobian in contact frames ``J``,
    (nc*d, nq) [m/rad], from the kept joints' world Jacobians ``jw``, (nc, 3, nq)."""
    d = 2 if planar else 3
    nc = len(points)
    G = np.zeros((3 if planar else 6, nc * d))
    J = np.zeros((nc * d, jw.shape[2]))
    for i in range(nc):
        F = frames[i][:, :d]  # (3, d)
        moment = np.cross(points[i] - o, F.T).T  # (3, d)
        if planar:
            G[:, i * d : (i + 1) * d] = np.vstack([F[:2], moment[2:3]])
        else:
            G[:, i * d : (i + 1) * d] = np.vstack([F, moment])
        J[i * d : (i + 1) * d] = F.T @ jw[i]
    return G, J


def _friction_pyramids(
    contacts: list[Contact], names: tuple[str, ...], m: int, planar: bool, circumscribed: bool, prune: bool
) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """The block-diagonal pyramids ``D``, (nc*d, nb), the contact of each weight, (nb,), and the
    contacts whose tangential variables were pruned (``mu = 0``)."""
    d = 2 if planar else 3
    blocks = []
    beta_contact: list[int] = []
    tangential = []
    for i, c in enumerate(contacts):
        if c.mu == 0.0 and prune:
            edges_i = friction_edges(0.0, m)[:d]
            tangential.append(names[i])
        else:
            edges_i = friction_edges(c.mu, m, circumscribed)[:d]
            if c.mu == 0.0:  # kept on request: m zero-friction edges
                edges_i = np.repeat(np.array([[1.0], [0.0], [0.0]])[:d], m, axis=1)
        blocks.append(edges_i)
        beta_contact += [i] * edges_i.shape[1]
    D = np.zeros((len(contacts) * d, sum(b.shape[1] for b in blocks)))
    col = 0
    for i, b in enumerate(blocks):
        D[i * d : (i + 1) * d, col : col + b.shape[1]] = b
        col += b.shape[1]
    return D, np.asarray(beta_contact, dtype=int), tuple(tangential)


# ------------------------------------------------------------ 6. length scale, finiteness
def _length_scale(length_scale: object, points: np.ndarray, o: np.ndarray) -> float:
    """The user's length scale [m], or the RMS distance of the contacts from ``o`` (1 m if 0)."""
    if length_scale is None:
        with np.errstate(over="ignore"):
            rms = float(np.sqrt(np.mean(np.sum((points - o) ** 2, axis=1))))
        return rms if rms > 0 else 1.0
    value = finite_number("length_scale", length_scale)
    if not value > 0:
        raise InvalidInputError("length_scale", f"must be finite and > 0, got {value}")
    return value


def _check_finite(G: np.ndarray, J: np.ndarray, D: np.ndarray, length_scale: float) -> None:
    """Huge coordinates must not have overflowed the matrices or the length scale."""
    for label, arr in (("grasp map", G), ("hand Jacobian", J), ("friction pyramid", D)):
        if not np.all(np.isfinite(arr)):
            raise InvalidInputError(
                "contacts", f"the {label} overflows: contact coordinates or Jacobians too large"
            )
    if not np.isfinite(length_scale):
        raise InvalidInputError("contacts", "the contact points are too far from the reference point")


# ------------------------------------------------------------------------------ all steps
def build_model(
    model_class: Callable[..., M],
    contacts: Sequence[Contact],
    actuators: Sequence[Actuator] | None,
    couplings: Sequence[Coupling] | np.ndarray | None,
    planar: bool,
    *,
    reference_point: object,
    joint_names: Sequence[str] | None,
    edges: int | None,
    circumscribed: bool,
    prune: bool,
    length_scale: float | None,
) -> M:
    """A ``model_class`` built from explicit contacts; arguments and errors as in
    :meth:`GraspModel.from_contacts <pinograsp.core.model.GraspModel.from_contacts>`."""
    contacts = _checked_contacts(contacts)
    nq_jacobian = _jacobian_columns(contacts)
    user_joint_names = _checked_joint_names(joint_names)
    planar = flag("planar", planar)
    circumscribed = flag("circumscribed", circumscribed)
    prune = flag("prune", prune)
    all_joint_names = _joint_names(user_joint_names, nq_jacobian)
    names = _contact_names(contacts)
    o = _reference_point(reference_point)
    m = _edge_count(edges, planar)
    points = np.array([c.point for c in contacts])
    frames = np.array([c.frame for c in contacts])
    jw = _world_jacobians(contacts, len(all_joint_names))
    if planar:
        _check_planar(contacts, names, points, o, jw)
    act = _actuation(actuators, couplings, all_joint_names)
    kept = _prune(act, jw, all_joint_names, prune)
    G, J = _grasp_and_hand_maps(points, frames, o, jw[:, :, kept.joints], planar)
    D, beta_contact, tangential = _friction_pyramids(contacts, names, m, planar, circumscribed, prune)
    scale = _length_scale(length_scale, points, o)
    _check_finite(G, J, D, scale)
    nq = len(kept.joint_names)
    return model_class(
        G=readonly(G),
        J=readonly(J),
        D=readonly(D),
        beta_contact=beta_contact,
        k=readonly(np.array([c.stiffness for c in contacts])),
        mu=readonly(np.array([c.mu for c in contacts])),
        R=readonly(kept.R.reshape(nq, -1)),
        C=readonly(kept.C.reshape(-1, nq)),
        kinds=kept.kinds,
        points=readonly(points),
        frames=readonly(frames),
        reference_point=readonly(o),
        planar=bool(planar),
        edges=m,
        length_scale=float(scale),
        contact_names=names,
        joint_names=kept.joint_names,
        actuator_names=kept.actuator_names,
        coupling_names=kept.coupling_names,
        all_actuator_names=act.actuator_names,
        bidirectional=tuple(n for n, a in zip(act.actuator_names, act.actuators) if a.bidirectional),
        pruned=replace(kept.record, tangential=tangential),
    )
