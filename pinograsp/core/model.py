"""``GraspModel``: the plain-array description of a grasp that every solver works on.

The model holds NumPy arrays only — no Pinocchio or Coal objects — so that solvers and
analyses stay independent from the URDF side (docs/design.md). It is built from explicit contacts
(:meth:`GraspModel.from_contacts`, used by analytic cases) or from a URDF scene
(:func:`pinograsp.grasp_model_from_scene`), and pruned to what the scene needs.

Shapes: ``nc`` contacts, ``d`` force components per contact (3, or 2 when planar), ``nw``
wrench components (6, or 3 when planar: ``fx, fy, mz``), ``nb`` pyramid edge weights,
``nq`` joints, ``na`` actuators, ``ncp`` couplings.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InvalidInputError, ModelError, UnknownNameError
from .actuation import Actuator, Coupling
from .axes import PLANAR_AXES
from .contact import Contact, friction_edges
from .validate import finite_number, flag, sequence

#: Relative threshold below which Jacobian entries count as zero (pruning, planar checks).
ZERO_TOL = 1e-12


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


#: Largest number of friction pyramid edges accepted (32 edges already approximate the cone
#: to 1 - cos(pi/32) = 0.5 %).
MAX_EDGES = 256


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class GraspModel:
    """A grasp as plain arrays (see module docstring for shapes).

    Attributes:
        G: Grasp map, ``G c`` = wrench of the contact forces on the object, (nw, nc*d).
        J: Hand Jacobian in contact frames, (nc*d, nq) [m/rad]; ``tau = J^T c``.
        D: Block-diagonal friction pyramids, ``c = D beta``, (nc*d, nb).
        beta_contact: Contact index of each pyramid weight, (nb,).
        k: Normal contact stiffness, (nc,) [N/m].
        mu: Friction coefficients, (nc,).
        R: Transmission, ``tau = R f``, (nq, na).
        C: Rigid couplings, ``C q = 0``, (ncp, nq).
        kinds: Actuator kinds, (na,).
        points: Contact points, world frame, (nc, 3) [m].
        frames: Contact frames, columns ``(n, t1, t2)``, (nc, 3, 3).
        reference_point: Object reference point ``o`` (wrench torques are about it), (3,) [m].
        planar: Whether the model is reduced to the XY plane.
        edges: Pyramid edges per contact with friction (2 when planar).
        length_scale: Characteristic grasp size [m] (RMS distance of contacts from ``o``):
            converts torques to forces in residual norms and object rotations in the iterative
            scheme, so answers do not depend on the unit of length.
        contact_names, joint_names, actuator_names, coupling_names: Labels.
        all_actuator_names: Actuators before pruning (commands may be given for all of them).
        pruned: What the constructor removed.
        bidirectional: Names of the actuators (of ``all_actuator_names``) that take negative
            commands.
    """

    G: np.ndarray
    J: np.ndarray
    D: np.ndarray
    beta_contact: np.ndarray
    k: np.ndarray
    mu: np.ndarray
    R: np.ndarray
    C: np.ndarray
    kinds: tuple[str, ...]
    points: np.ndarray
    frames: np.ndarray
    reference_point: np.ndarray
    planar: bool
    edges: int
    length_scale: float
    contact_names: tuple[str, ...]
    joint_names: tuple[str, ...]
    actuator_names: tuple[str, ...]
    coupling_names: tuple[str, ...]
    all_actuator_names: tuple[str, ...]
    pruned: PruneRecord = field(default_factory=PruneRecord)
    bidirectional: tuple[str, ...] = ()

    # ------------------------------------------------------------------ sizes
    @property
    def nc(self) -> int:
        """Number of contacts."""
        return len(self.contact_names)

    @property
    def d(self) -> int:
        """Force components per contact: 3, or 2 when planar."""
        return 2 if self.planar else 3

    @property
    def nw(self) -> int:
        """Wrench components: 6, or 3 when planar."""
        return 3 if self.planar else 6

    @property
    def nb(self) -> int:
        """Number of pyramid edge weights ``beta``."""
        return self.D.shape[1]

    @property
    def nq(self) -> int:
        """Number of joints kept in the model."""
        return len(self.joint_names)

    @property
    def na(self) -> int:
        """Number of actuators kept in the model."""
        return len(self.actuator_names)

    @property
    def ncp(self) -> int:
        """Number of rigid couplings kept in the model."""
        return self.C.shape[0]

    # ------------------------------------------------------------ derived maps
    @property
    def normal_rows(self) -> np.ndarray:
        """Row indices of the normal components in ``c`` (and in ``J``, ``G^T``), (nc,)."""
        return np.arange(self.nc) * self.d

    @property
    def E(self) -> np.ndarray:
        """Normal-force summation, ``c_n = E beta``, (nc, nb)."""
        E = np.zeros((self.nc, self.nb))
        E[self.beta_contact, np.arange(self.nb)] = 1.0
        return E

    def wrench_vector(self, wrench: object, name: str = "wrench") -> np.ndarray:
        """Validate a wrench and return it as a full 6-vector ``(force [N], torque [N·m])``.

        Planar models also accept ``(fx, fy, mz)``; a 6-vector with out-of-plane components
        is rejected for them.
        """
        if isinstance(wrench, (str, bytes, Mapping)):
            raise InvalidInputError(name, f"expected 6 numbers, got {wrench!r}")
        try:
            w = np.asarray(wrench, dtype=float).reshape(-1)
        except (TypeError, ValueError, OverflowError) as exc:
            raise InvalidInputError(name, f"expected 6 numbers, got {wrench!r}") from exc
        if self.planar and w.shape == (3,):
            full = np.zeros(6)
            full[list(PLANAR_AXES)] = w
            w = full
        if w.shape != (6,):
            raise InvalidInputError(name, f"expected 6 numbers (fx, fy, fz, mx, my, mz), got shape {w.shape}")
        if not np.all(np.isfinite(w)):
            raise InvalidInputError(name, "contains NaN or inf", w)
        if self.planar:
            out = np.delete(np.arange(6), PLANAR_AXES)
            scale = max(np.abs(w).max(), 1e-300)
            if np.any(np.abs(w[out]) > 1e-12 * scale):
                raise InvalidInputError(
                    name,
                    "the model is planar (XY): fz, mx, my must be zero; build it with planar=False "
                    "to analyse out-of-plane wrenches",
                    w,
                )
        return w

    def reduce_wrench(self, w6: np.ndarray) -> np.ndarray:
        """The model's own wrench coordinates (nw,) of a full 6-vector."""
        return w6[list(PLANAR_AXES)] if self.planar else w6

    def expand_wrench(self, w: np.ndarray) -> np.ndarray:
        """Full 6-vector of a wrench in the model's coordinates."""
        if not self.planar:
            return np.asarray(w, dtype=float)
        full = np.zeros(6)
        full[list(PLANAR_AXES)] = w
        return full

    def expand_twist(self, x: np.ndarray) -> np.ndarray:
        """Full 6-vector ``(translation [m], rotation [rad])`` of an object displacement."""
        return self.expand_wrench(x)

    def command_vector(self, command: object) -> np.ndarray:
        """Validate an actuator command and return it for the kept actuators, (na,).

        Accepts a scalar (same command on every actuator), a sequence over all actuators given
        to the constructor (pruned ones are dropped) or over the kept ones, or a mapping
        ``{actuator_name: value}`` (missing actuators get 0). Commands are closing forces or
        torques ``>= 0`` [N·m or N] (negative only for actuators declared ``bidirectional``); a
        sequence of the wrong length (a 1-element list for a 2-actuator model included) or a
        negative value for any other actuator is an :class:`InvalidInputError`.
        """
        names_all = self.all_actuator_names
        if isinstance(command, Mapping):
            vals = dict.fromkeys(names_all, 0.0)
            for key, value in command.items():
                if not isinstance(key, str) or key not in vals:
                    raise UnknownNameError("actuator", key, names_all)
                vals[key] = finite_number(f"command[{key!r}]", value)
            raw = np.array([float(vals[n]) for n in names_all])
            full = True
        else:
            if isinstance(command, (str, bytes)):
                raise InvalidInputError("command", f"expected numbers, got {command!r}")
            try:
                raw = np.asarray(command, dtype=float).reshape(-1)
            except (TypeError, ValueError, OverflowError) as exc:
                raise InvalidInputError("command", f"expected numbers, got {command!r}") from exc
            scalar = np.ndim(command) == 0
            if raw.size == 1 and (scalar or len(names_all) == 1):
                raw = np.full(len(names_all), float(raw[0]))
            if raw.size == len(names_all):
                full = True
            elif raw.size == self.na:
                full = False
            else:
                raise InvalidInputError(
                    "command",
                    f"expected {len(names_all)} values (actuators {list(names_all)}), got {raw.size}",
                )
        if not np.all(np.isfinite(raw)):
            raise InvalidInputError("command", "contains NaN or inf", raw)
        if np.any(raw < 0):
            names = names_all if full else self.actuator_names
            bad = [n for n, v in zip(names, raw) if v < 0 and n not in self.bidirectional]
            if bad:
                raise InvalidInputError(
                    "command",
                    f"negative command for actuator(s) {bad}: a command is the closing force or "
                    "torque an actuator applies (>= 0; declare Actuator(..., bidirectional=True) for "
                    f"one that drives both ways; bidirectional here: {list(self.bidirectional)})",
                    raw,
                )
        if full:
            keep = [names_all.index(n) for n in self.actuator_names]
            raw = raw[keep]
        return raw

    def with_actuator_signs(self, signs: np.ndarray) -> GraspModel:
        """The same grasp with the transmission column of every actuator with ``signs < 0``
        negated, (na,): a bidirectional actuator commanded ``-f`` is this model's actuator
        commanded ``+f``."""
        sg = np.asarray(signs, float)
        return replace(self, R=_readonly(self.R * sg[None, :]))

    def contact_index(self, contact: int | str) -> int:
        """Index of a contact given by index or name."""
        if isinstance(contact, str):
            if contact not in self.contact_names:
                raise UnknownNameError("contact", contact, self.contact_names)
            return self.contact_names.index(contact)
        if not 0 <= int(contact) < self.nc:
            raise UnknownNameError("contact", contact, range(self.nc))
        return int(contact)

    def world_forces(self, c: np.ndarray) -> np.ndarray:
        """World-frame contact forces on the object, (nc, 3), from contact-frame ``c`` (nc*d,)."""
        cc = np.asarray(c, dtype=float).reshape(self.nc, self.d)
        return np.einsum("ijk,ik->ij", self.frames[:, :, : self.d], cc)

    # ------------------------------------------------------------ constructors
    @classmethod
    def from_contacts(
        cls,
        contacts: Sequence[Contact],
        actuators: Sequence[Actuator] | None = None,
        couplings: Sequence[Coupling] | np.ndarray | None = None,
        planar: bool = False,
        *,
        reference_point: object = None,
        joint_names: Sequence[str] | None = None,
        edges: int | None = None,
        circumscribed: bool = False,
        prune: bool = True,
        length_scale: float | None = None,
    ) -> GraspModel:
        """Build a model from explicit contacts.

        Args:
            contacts: The contacts; their Jacobians must all have the same number of columns
                ``nq`` (``None`` = a contact on a part that cannot move, e.g. the palm).
            actuators: Actuators with their transmission columns. ``None``: one
                non-backdrivable direct-drive actuator per joint, named after the joint.
            couplings: Rigid couplings ``C q = 0``, as :class:`Coupling` objects or a
                (ncp, nq) array.
            planar: Reduce to the XY plane: wrench ``(fx, fy, mz)``, contact force
                ``(c_n, c_t)``, object displacement ``(x, y, theta)``. Every contact point must
                lie in the plane ``z = reference_point[2]``, and normals, tangents and Jacobians
                must have no Z component.
            reference_point: Object reference point ``o`` [m]; default the origin.
            joint_names: Joint labels (default ``q0, q1, …``); lets transmissions and couplings
                name joints.
            edges: Friction pyramid edges per contact (default 8; planar always uses 2).
            circumscribed: Use the circumscribed pyramid instead of the inscribed one.
            prune: Remove joints that reach no contact, actuators that then reach no joint,
                couplings through removed joints, and tangential variables where ``mu = 0``.
            length_scale: Characteristic length [m]; default RMS distance of the contact
                points from ``o`` (or 1 m if that is zero).

        Raises:
            InvalidInputError: A malformed argument (the message names it).
            ModelError: Inconsistent sizes, a non-planar element in a planar model, ...
            UnknownNameError: A transmission or coupling names an unknown joint.
        """
        contacts = sequence("contacts", contacts)
        if not contacts:
            raise ModelError("a grasp needs at least one contact")
        for i, c in enumerate(contacts):
            if not isinstance(c, Contact):
                raise InvalidInputError(
                    f"contacts[{i}]", f"expected pinograsp.Contact, got {type(c).__name__}"
                )
        nqs = {c.jacobian.shape[1] for c in contacts if c.jacobian is not None}
        if len(nqs) > 1:
            detail = ", ".join(
                f"{c.name or i}: {c.jacobian.shape[1]}"
                for i, c in enumerate(contacts)
                if c.jacobian is not None
            )
            raise ModelError(f"contact Jacobians disagree on the number of joints ({detail})")
        if joint_names is not None:
            joint_names = sequence("joint_names", joint_names)
            for n in joint_names:
                if not isinstance(n, str):
                    raise InvalidInputError("joint_names", f"expected strings, got {n!r}")
        planar = flag("planar", planar)
        circumscribed = flag("circumscribed", circumscribed)
        prune = flag("prune", prune)
        nq = nqs.pop() if nqs else (len(joint_names) if joint_names is not None else 0)
        if joint_names is None:
            joint_names = tuple(f"q{j}" for j in range(nq))
        joint_names = tuple(str(n) for n in joint_names)
        if len(joint_names) != nq:
            raise ModelError(f"{len(joint_names)} joint names for {nq} Jacobian columns")
        if len(set(joint_names)) != nq:
            raise ModelError(f"duplicate joint names in {joint_names}")

        names = []
        for i, c in enumerate(contacts):
            names.append(c.name if c.name is not None else f"c{i}")
        if len(set(names)) != len(names):
            names = [f"{n}#{i}" for i, n in enumerate(names)]

        try:
            o = (
                np.zeros(3)
                if reference_point is None
                else np.asarray(reference_point, dtype=float).reshape(-1)
            )
        except (TypeError, ValueError, OverflowError) as exc:
            raise InvalidInputError(
                "reference_point", f"expected 3 numbers, got {reference_point!r}"
            ) from exc
        if o.shape != (3,) or not np.all(np.isfinite(o)):
            raise InvalidInputError("reference_point", f"expected 3 finite numbers, got {reference_point!r}")

        if edges is None:
            m = 8
        elif isinstance(edges, (bool, np.bool_)) or not isinstance(edges, (int, np.integer)):
            raise InvalidInputError("edges", f"expected an integer number of pyramid edges, got {edges!r}")
        else:
            m = int(edges)
        if m > MAX_EDGES:
            raise InvalidInputError("edges", f"at most {MAX_EDGES} pyramid edges, got {m}")
        if planar:
            m = 2
        elif m < 3:
            raise InvalidInputError("edges", f"a 3D friction pyramid needs at least 3 edges, got {m}")

        points = np.array([c.point for c in contacts])
        frames = np.array([c.frame for c in contacts])
        jw = np.array([c.jacobian if c.jacobian is not None else np.zeros((3, nq)) for c in contacts])
        if nq == 0 or not np.any(jw):
            raise ModelError(
                "no contact moves with a joint (every contact is fixed): passive reaction needs at "
                f"least one finger joint that reaches a contact; contacts: {[c.name for c in contacts]}"
            )
        if planar:
            scale = max(np.abs(points - o).max(), 1e-300)
            for i, c in enumerate(contacts):
                if (
                    abs(c.point[2] - o[2]) > 1e-9 * scale
                    or abs(c.normal[2]) > 1e-9
                    or abs(c.tangent[2]) > 1e-9
                ):
                    raise ModelError(
                        f"contact {names[i]!r} is not in the XY plane (point z, normal z or tangent z "
                        "non-zero); use planar=False"
                    )
                jscale = max(np.abs(jw).max(), 1e-300)
                if np.any(np.abs(jw[i, 2]) > 1e-9 * jscale):
                    raise ModelError(
                        f"contact {names[i]!r}: its Jacobian moves it out of the XY plane; use planar=False"
                    )

        # --- joints, transmission, couplings (by index, names resolved) --------------
        def joint_idx(owner: str, key: int | str) -> int:
            if isinstance(key, str):
                if key not in joint_names:
                    raise UnknownNameError("joint", key, joint_names)
                return joint_names.index(key)
            if not 0 <= key < nq:
                raise UnknownNameError("joint", key, list(range(nq)) + list(joint_names))
            return key

        if actuators is None:
            actuators = [Actuator({j: 1.0}, name=joint_names[j]) for j in range(nq)]
        actuators = sequence("actuators", actuators)
        act_names = []
        for a_i, a in enumerate(actuators):
            if not isinstance(a, Actuator):
                raise InvalidInputError(
                    f"actuators[{a_i}]", f"expected pinograsp.Actuator, got {type(a).__name__}"
                )
            act_names.append(a.name if a.name is not None else f"a{a_i}")
        if len(set(act_names)) != len(act_names):
            raise ModelError(f"duplicate actuator names in {act_names}")
        R = np.zeros((nq, len(actuators)))
        for a_i, a in enumerate(actuators):
            for key, arm in a.transmission.items():
                R[joint_idx(f"actuator {act_names[a_i]!r}", key), a_i] += arm

        if couplings is None:
            C = np.zeros((0, nq))
            cp_names: list[str] = []
        elif isinstance(couplings, np.ndarray):
            try:
                C = np.array(couplings, dtype=float, ndmin=2)
            except (TypeError, ValueError, OverflowError) as exc:
                raise InvalidInputError("couplings", f"expected a numeric (ncp, {nq}) array: {exc}") from exc
            if C.size == 0:
                C = np.zeros((0, nq))
            if C.ndim != 2 or C.shape[1] != nq or not np.all(np.isfinite(C)):
                raise InvalidInputError(
                    "couplings", f"expected a finite (ncp, {nq}) array, got shape {C.shape}"
                )
            cp_names = [f"k{r}" for r in range(C.shape[0])]
        else:
            couplings = sequence("couplings", couplings)
            C = np.zeros((len(couplings), nq))
            cp_names = []
            for r, cp in enumerate(couplings):
                if not isinstance(cp, Coupling):
                    raise InvalidInputError(
                        f"couplings[{r}]", f"expected pinograsp.Coupling, got {type(cp).__name__}"
                    )
                cp_names.append(cp.name if cp.name is not None else f"k{r}")
                for key, v in cp.weights.items():
                    C[r, joint_idx(f"coupling {cp_names[-1]!r}", key)] += v
        if C.shape[0] and np.any(np.all(C == 0, axis=1)):
            raise ModelError("a coupling has all-zero weights")

        # --- pruning -----------------------------------------------------------------
        jmax = max(np.abs(jw).max(), 1e-300) if jw.size else 1.0
        reaches = np.any(np.abs(jw) > ZERO_TOL * jmax, axis=(0, 1)) if nq else np.zeros(0, bool)
        keep_j = reaches if prune else np.ones(nq, bool)
        pruned_joints = tuple(joint_names[j] for j in range(nq) if not keep_j[j])
        dropped_tr = tuple(
            (act_names[a_i], joint_names[j])
            for a_i in range(R.shape[1])
            for j in range(nq)
            if not keep_j[j] and R[j, a_i] != 0
        )
        keep_cp = ~np.any(C[:, ~keep_j] != 0, axis=1) if C.shape[0] else np.zeros(0, bool)
        pruned_cp = tuple(cp_names[r] for r in range(C.shape[0]) if not keep_cp[r])
        R = R[keep_j]
        keep_a = np.any(R != 0, axis=0) if prune else np.ones(R.shape[1], bool)
        pruned_a = tuple(act_names[a] for a in range(R.shape[1]) if not keep_a[a])
        R = R[:, keep_a]
        C = C[keep_cp][:, keep_j]
        cp_names = [cp_names[r] for r in range(len(cp_names)) if keep_cp[r]]
        jw = jw[:, :, keep_j]
        kept_joint_names = tuple(n for j, n in enumerate(joint_names) if keep_j[j])
        kinds = tuple(a.kind for a, keep in zip(actuators, keep_a) if keep)
        kept_act_names = tuple(n for n, keep in zip(act_names, keep_a) if keep)

        # --- contact-frame matrices ----------------------------------------------------
        d = 2 if planar else 3
        nc = len(contacts)
        nqk = int(keep_j.sum())
        G = np.zeros((3 if planar else 6, nc * d))
        J = np.zeros((nc * d, nqk))
        blocks = []
        beta_contact = []
        tangential = []
        for i, c in enumerate(contacts):
            F = frames[i][:, :d]  # (3, d)
            r = points[i] - o
            moment = np.cross(r, F.T).T  # (3, d)
            if planar:
                G[:, i * d : (i + 1) * d] = np.vstack([F[:2], moment[2:3]])
            else:
                G[:, i * d : (i + 1) * d] = np.vstack([F, moment])
            J[i * d : (i + 1) * d] = F.T @ jw[i]
            mu_i = c.mu
            if mu_i == 0.0 and prune:
                edges_i = friction_edges(0.0, m)[:d]
                tangential.append(names[i])
            else:
                edges_i = friction_edges(mu_i, m, circumscribed)[:d]
                if mu_i == 0.0:  # kept on request: m zero-friction edges
                    edges_i = np.repeat(np.array([[1.0], [0.0], [0.0]])[:d], m, axis=1)
            blocks.append(edges_i)
            beta_contact += [i] * edges_i.shape[1]
        nb = sum(b.shape[1] for b in blocks)
        D = np.zeros((nc * d, nb))
        col = 0
        for i, b in enumerate(blocks):
            D[i * d : (i + 1) * d, col : col + b.shape[1]] = b
            col += b.shape[1]

        if length_scale is None:
            with np.errstate(over="ignore"):
                rms = float(np.sqrt(np.mean(np.sum((points - o) ** 2, axis=1))))
            length_scale = rms if rms > 0 else 1.0
        else:
            length_scale = finite_number("length_scale", length_scale)
            if not length_scale > 0:
                raise InvalidInputError("length_scale", f"must be finite and > 0, got {length_scale}")
        for label, arr in (("grasp map", G), ("hand Jacobian", J), ("friction pyramid", D)):
            if not np.all(np.isfinite(arr)):
                raise InvalidInputError(
                    "contacts", f"the {label} overflows: contact coordinates or Jacobians too large"
                )
        if not np.isfinite(length_scale):
            raise InvalidInputError("contacts", "the contact points are too far from the reference point")

        return cls(
            G=_readonly(G),
            J=_readonly(J),
            D=_readonly(D),
            beta_contact=np.asarray(beta_contact, dtype=int),
            k=_readonly(np.array([c.stiffness for c in contacts])),
            mu=_readonly(np.array([c.mu for c in contacts])),
            R=_readonly(R.reshape(nqk, -1)),
            C=_readonly(C.reshape(-1, nqk)),
            kinds=kinds,
            points=_readonly(points),
            frames=_readonly(frames),
            reference_point=_readonly(o),
            planar=bool(planar),
            edges=m,
            length_scale=float(length_scale),
            contact_names=tuple(names),
            joint_names=kept_joint_names,
            actuator_names=kept_act_names,
            coupling_names=tuple(cp_names),
            all_actuator_names=tuple(act_names),
            bidirectional=tuple(n for n, a in zip(act_names, actuators) if a.bidirectional),
            pruned=PruneRecord(
                joints=pruned_joints,
                actuators=pruned_a,
                couplings=pruned_cp,
                tangential=tuple(tangential),
                dropped_transmission=dropped_tr,
            ),
        )

    def summary(self) -> str:
        """A short human-readable description (sizes, kinds, what was pruned)."""
        kind = "planar" if self.planar else "3D"
        lines = [
            f"GraspModel: {self.nc} contacts ({kind}, {self.edges}-edge pyramids), {self.nq} joints, "
            f"{self.na} actuators, {self.ncp} couplings, length scale {self.length_scale:.4g} m",
            "  actuators: " + ", ".join(f"{n} ({k})" for n, k in zip(self.actuator_names, self.kinds)),
        ]
        if self.pruned:
            p = self.pruned
            lines.append(
                f"  pruned: joints {list(p.joints)}, actuators {list(p.actuators)}, "
                f"couplings {list(p.couplings)}, tangential variables of {list(p.tangential)}"
            )
        return "\n".join(lines)
