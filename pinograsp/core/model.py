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

from ..errors import InvalidInputError, UnknownNameError, plural
from .actuation import Actuator, Coupling
from .axes import PLANAR_AXES
from .build import PruneRecord, build_model, readonly
from .cones import edge_counts, with_normal_uncertainty
from .contact import Contact
from .validate import MAX_FORCE, MIN_FORCE, finite_number

#: Indices of the out-of-plane components ``(fz, mx, my)`` inside a 6-vector.
_OUT_OF_PLANE = np.delete(np.arange(6), PLANAR_AXES)


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
        normal_uncertainty: Worst-case contact-normal uncertainty [rad] the pyramids were
            shrunk for (:meth:`with_normal_uncertainty`; 0 for a nominal model).
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
    normal_uncertainty: float = 0.0

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
    def wrench_weights(self) -> np.ndarray:
        """The wrench metric of every residual and scaled formulation, (nw,): 1 on the force
        rows, ``1 / length_scale`` [1/m] on the torque rows (a torque as the force at the
        length scale)."""
        w = np.ones(self.nw)
        w[self.d :] = 1.0 / float(self.length_scale)
        return w

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
            out = _OUT_OF_PLANE
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

    def free_motions(self) -> np.ndarray:
        """Object motions no contact resists to first order, (k, 6) twists ``(translation [m],
        rotation [rad])`` in the base frame about the reference point, each with a unit rotation
        (or a unit translation if it has none); ``k = 0`` for a grasp that constrains every motion.

        They span the null space of ``G^T``: no contact point moves along any axis of its frame.
        Two point contacts leave the rotation about the line through them (the contact chord):
        a load with a moment about it is resisted by nothing, so every direction is
        ``below_resolution``. Point contacts carry no torsional friction; add a contact off the
        chord (or model the patch with several points) to hold it.
        """
        scale = self.wrench_weights  # rotations in length units
        A = self.G.T * scale[None, :]
        _, sv, vt = np.linalg.svd(A)
        rank = int(np.sum(sv > 1e-9 * max(float(sv.max(initial=0.0)), 1e-300)))
        out = []
        for v in vt[rank:]:
            x = self.expand_twist(v * scale)
            size = (
                np.linalg.norm(x[3:])
                if np.linalg.norm(x[3:]) > 1e-12 * np.abs(x).max()
                else np.linalg.norm(x)
            )
            out.append(x / size)
        return np.array(out).reshape(-1, 6)

    def free_motion_note(self, d: np.ndarray) -> str:
        """Why the unit direction ``d`` (6,) resists nothing when the contacts leave the object a
        free motion (:meth:`GraspModel.free_motions`) that the load drives (does work on): ``""``
        otherwise."""
        for t in self.free_motions():
            power = float(d[:3] @ t[:3] + d[3:] @ t[3:])
            size = float(
                np.linalg.norm(d[:3]) * np.linalg.norm(t[:3]) + np.linalg.norm(d[3:]) * np.linalg.norm(t[3:])
            )
            if abs(power) <= 1e-6 * max(size, 1e-300):
                continue
            if np.linalg.norm(t[3:]) > 0:
                motion = f"rotate about {self._axis_text(t)}"
                if self.nc == 2:
                    motion += " (the line through the two contacts)"
            else:
                motion = "translate along (" + ", ".join(f"{c:.3g}" for c in t[:3]) + ")"
            return (
                f"no contact resists this load: the contacts leave the object free to {motion}, and the "
                "load drives that motion (point contacts carry no torsional friction); add a contact "
                "off that axis, or model the contact patch with several points"
            )
        return ""

    def _axis_text(self, t: np.ndarray) -> str:
        """The axis of a rotating twist ``t`` (6,) as text: its direction and a point on it [mm]."""
        w, v = t[3:], t[:3]
        p = self.reference_point + np.cross(w, v) / float(w @ w)  # a point on the axis
        axis = ", ".join(f"{c:.3g}" for c in w)
        return f"the axis ({axis}) through (" + ", ".join(f"{1e3 * c:.1f}" for c in p) + ") mm"

    def held_free_motion_note(self) -> str:
        """For an answer that holds: the object motion no contact resists (a spin about the chord
        of two point contacts, :meth:`free_motions`), which holds only while nothing drives it;
        ``""`` for a grasp that constrains every motion."""
        free = self.free_motions()
        if not len(free) or not np.linalg.norm(free[0, 3:]) > 0:
            return ""
        return (
            f"held while nothing drives the free rotation about {self._axis_text(free[0])} "
            "that the contacts leave (point contacts carry no torsional friction): a load with a "
            "moment about it, or a slowly ramped simulation's spin, gives way (docs/hands.md, "
            "'Free motions under load, and buckling')"
        )

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
        if command is None:
            raise InvalidInputError(
                "command",
                "is None: give the actuator commands [N·m or N] (a number, one per actuator, or "
                "{actuator: value}). equilibrium_preload returns command=None when no preload "
                "exists (status 'infeasible'; its .reason says why)",
            )
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
            scalar = np.ndim(command) == 0  # type: ignore[arg-type]  # any object: 0-d unless a sequence
            if raw.size == 1 and (scalar or len(names_all) == 1):
                raw = np.full(len(names_all), float(raw[0]))
            if raw.size == len(names_all):
                full = True
            elif raw.size == self.na:
                full = False
            else:
                raise InvalidInputError(
                    "command",
                    f"expected {plural('value', len(names_all))} (actuators {list(names_all)}), "
                    f"got {raw.size}",
                )
        if not np.all(np.isfinite(raw)):
            raise InvalidInputError("command", "contains NaN or inf", raw)
        if np.any(np.abs(raw) > MAX_FORCE):  # domain: docs/errors.md
            raise InvalidInputError("command", f"must be within ±{MAX_FORCE:g} [N·m or N]", raw)
        if 0 < np.abs(raw).max(initial=0.0) < MIN_FORCE:  # domain: docs/errors.md
            raise InvalidInputError(
                "command",
                f"the largest command must be 0 or at least {MIN_FORCE:g} [N·m or N] (the loading path "
                "resolves 1e-9 of a unit load of 1 N or N·m): give the commands in larger units",
                raw,
            )
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
        return replace(self, R=readonly(self.R * sg[None, :]))

    def with_normal_uncertainty(self, angle: float) -> GraspModel:
        """The same grasp with every contact normal uncertain by ``angle`` [rad], in the worst
        case: friction ``mu -> tan(atan(mu) - angle)`` and, for the energetic method, a slipping
        contact loses ``tan(angle)`` of compression per unit slip (:mod:`pinograsp.core.cones`)."""
        return with_normal_uncertainty(self, angle)

    @property
    def edge_counts(self) -> tuple[int, ...]:
        """Friction pyramid edges of every contact, (nc,) (refined pyramids differ per contact)."""
        return edge_counts(self)

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
        return build_model(
            cls,
            contacts,
            actuators,
            couplings,
            planar,
            reference_point=reference_point,
            joint_names=joint_names,
            edges=edges,
            circumscribed=circumscribed,
            prune=prune,
            length_scale=length_scale,
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
