"""Physical checks of a solution that the optimisation itself does not impose.

* **Energy** (seed §VI, the wedging artefact): springs cannot store more energy than the load
  and the actuators supply on the solution's own displacements, since friction only dissipates::

      E_spring = sum_i c_n,i^2 / (2 k_i)   <=   W_load + W_act
      W_load = w . x_load      (the load is constant while the object moves by x_load)
      W_act  = f_c . u         (an actuator moves only at its command f_c; holding ones do no work)

  ``x_load`` is the object displacement of the load stage (the whole displacement for the
  single-step variant; after a preload stage the load was not yet applied during the preload).
  A PRP answer that wedges the object between locked fingers breaks it; a physical equilibrium
  reached by the iterative scheme satisfies it (typically ``E ≈ 0.25–0.6 W``).
* **Displacements**: the model is linear in virtual displacements of the size of the spring
  compressions ``c_n / k``; an object or joint displacement more than
  :data:`MAX_DISPLACEMENT_RATIO` times the largest compression is a march towards infinity in a
  null direction, not an answer.
* **Friction use** ``|c_t| / (mu c_n)`` is defined for touching contacts that carry a normal force;
  a separated contact has none (NaN).

The thresholds are documented in ``docs/accuracy.md``. This module is NumPy only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .serialize import jsonable

#: Relative slack of the energy inequality (rounding of the solution's forces and displacements).
ENERGY_RTOL = 1e-6
#: Largest accepted displacement, in multiples of the largest spring compression ``c_n / k``.
MAX_DISPLACEMENT_RATIO = 1e3
#: Share of the spring energy held by the contacts named in a failed energy check.
NAMED_SHARE = 0.9


@dataclass(frozen=True)
class EnergyCheck:
    """The energy balance of one solution (every energy in [J] = [N·m]).

    Attributes:
        spring_energy: ``sum c_n^2 / (2 k)`` over the contacts [J].
        load_work: Work of the constant external wrench on the load stage's object displacement [J].
        actuator_work: Work of the actuators at their commands on their displacements [J].
        displacement_ratio: Largest object translation / rotation x length scale / joint
            displacement x lever, over the largest spring compression ``c_n / k`` (dimensionless).
        contacts: Contacts holding :data:`NAMED_SHARE` of the spring energy, most first (named
            when a check fails).
        tolerance: Absolute slack [J]: the spring energy that forces within the audit's force
            tolerance can carry (``sum (2 c_n + t) t / (2 k)`` for a force tolerance ``t``).
    """

    spring_energy: float
    load_work: float
    actuator_work: float
    displacement_ratio: float
    contacts: tuple[str, ...]
    tolerance: float = 0.0

    @property
    def energy_ok(self) -> bool:
        """Spring energy within the supplied work (friction cannot create energy)."""
        supplied = self.load_work + self.actuator_work
        scale = max(self.spring_energy, abs(self.load_work), abs(self.actuator_work))
        return self.spring_energy <= supplied + ENERGY_RTOL * scale + self.tolerance

    @property
    def displacement_ok(self) -> bool:
        """No displacement beyond :data:`MAX_DISPLACEMENT_RATIO` spring compressions."""
        return bool(self.displacement_ratio <= MAX_DISPLACEMENT_RATIO)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: the energies [J], their verdicts, the displacement ratio and
        the contacts (the ``energy`` block of an audit in ``pinograsp analyze --json``)."""
        return jsonable(
            {
                "spring_energy": self.spring_energy,
                "load_work": self.load_work,
                "actuator_work": self.actuator_work,
                "energy_ok": self.energy_ok,
                "displacement_ratio": self.displacement_ratio,
                "displacement_ok": self.displacement_ok,
                "contacts": list(self.contacts),
            }
        )

    def summary(self) -> str:
        """The energy balance [J] and displacement ratio with their verdicts, on one line."""
        supplied = self.load_work + self.actuator_work
        rel = "<=" if self.energy_ok else "> (WEDGING)"
        text = f"spring energy {self.spring_energy:.4g} J {rel} supplied {supplied:.4g} J"
        if not self.energy_ok and self.contacts:
            text += f" at {', '.join(self.contacts)}"
        ok = "ok" if self.displacement_ok else "ABSURD"
        return text + f"; displacements {self.displacement_ratio:.3g}x the spring compressions ({ok})"


@dataclass(frozen=True)
class Audit:
    """Post-solve check of a solution, in physical force units [N] (torques divided by the
    model's length scale, joint torques by their lever).

    Attributes:
        equilibrium: Norm of the object's net wrench ``w + G c`` [N]. Zero (to solver accuracy)
            for an equilibrium; for the iterative scheme this is the final residual.
        hand: Largest joint-torque imbalance ``|J^T c - R f - C^T lambda| / lever`` [N].
        complementarity: Largest ``min(a, b)`` over every complementary pair (contact force /
            spring gap, actuator motion / over-force) [N]: zero when complementarity holds.
        friction: Largest violation of the friction pyramid (negative edge weight) [N].
        bigm_ratio: Largest big-M-bounded quantity as a fraction of its bound (0 without MIQP).
        bigm_retries: How many times the big-M bounds had to be enlarged.
        polished: Whether the solution was polished by the exact fixed-mode QP.
        tolerance: Tolerance the residuals are compared with [N].
        energy: Energy balance and displacement size of an equilibrium (None when the load is
            not resisted): :class:`EnergyCheck`.
        equilibrium_tolerance: Bound on ``equilibrium`` [N] the method guarantees for an
            equilibrium (``None``: not checked here — the iterative scheme's residual is judged
            by its ``eps``). The exact methods (PRP, energetic) balance the object to ``1e-6``
            of the force scale; an energetic load stage on the iterative (held-still) preload
            carries that preload's own residual (at most ``eps + eps_rel F``) on top. A resisted
            answer above this bound is reported ``status="failed"`` and fails the audit.
        pull: Largest pulling normal force ``max(0, -min c_n)`` [N]: contacts are push-only, so
            beyond ``tolerance`` the numbers cannot be trusted (docs/errors.md).
        finite: Every force, displacement and residual of the solution is finite (no overflow).
    """

    equilibrium: float
    hand: float
    complementarity: float
    friction: float
    bigm_ratio: float = 0.0
    bigm_retries: int = 0
    polished: bool = False
    tolerance: float = 1e-6
    energy: EnergyCheck | None = None
    equilibrium_tolerance: float | None = None
    pull: float = 0.0
    finite: bool = True

    @property
    def ok(self) -> bool:
        """All hand/complementarity/friction residuals within tolerance, the object's net wrench
        within ``equilibrium_tolerance`` (when given), no big-M saturation, no pulling contact,
        every number finite, and (for an equilibrium) the energy balance and displacement size
        hold."""
        physical = self.energy is None or (self.energy.energy_ok and self.energy.displacement_ok)
        return (
            self.finite
            and self.balanced
            and self.pull <= self.tolerance
            and self.hand <= self.tolerance
            and self.complementarity <= self.tolerance
            and self.friction <= self.tolerance
            and self.bigm_ratio < 0.1
            and physical
        )

    @property
    def balanced(self) -> bool:
        """The object's net wrench is within ``equilibrium_tolerance`` (True when not given)."""
        return self.equilibrium_tolerance is None or self.equilibrium <= self.equilibrium_tolerance

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: ``ok``, the residuals [N], big-M use and ``energy``."""
        return jsonable(
            {
                "ok": self.ok,
                "equilibrium": self.equilibrium,
                "hand": self.hand,
                "complementarity": self.complementarity,
                "friction": self.friction,
                "bigm_ratio": self.bigm_ratio,
                "bigm_retries": self.bigm_retries,
                "polished": self.polished,
                "tolerance": self.tolerance,
                "equilibrium_tolerance": self.equilibrium_tolerance,
                "pull": self.pull,
                "finite": self.finite,
                "energy": None if self.energy is None else self.energy.to_dict(),
            }
        )

    def summary(self) -> str:
        """The verdict and residuals [N] as text (and the energy balance [J] when checked)."""
        text = (
            f"audit: {'ok' if self.ok else 'NOT OK'} (equilibrium {self.equilibrium:.2e} N, "
            f"hand {self.hand:.2e} N, complementarity {self.complementarity:.2e} N, "
            f"friction {self.friction:.2e} N, big-M use {self.bigm_ratio:.1%})"
        )
        if self.pull > self.tolerance:
            text += (
                f"\n  a contact PULLS with {self.pull:.3g} N (contacts only push): "
                "the numbers cannot be trusted"
            )
        if not self.finite:
            text += "\n  non-finite numbers (overflow): the solution cannot be trusted"
        return text if self.energy is None else text + "\n  " + self.energy.summary()


def energy_check(
    normal_forces: np.ndarray,
    stiffness: np.ndarray,
    wrench: np.ndarray,
    load_displacement: np.ndarray,
    command: np.ndarray,
    actuator_displacements: np.ndarray,
    object_displacement: np.ndarray,
    joint_displacements: np.ndarray,
    length_scale: float,
    levers: np.ndarray,
    names: tuple[str, ...],
    force_tolerance: float = 0.0,
) -> EnergyCheck:
    """The energy balance and displacement size of a solution.

    Args:
        normal_forces: ``c_n`` (nc,) [N].
        stiffness: ``k`` (nc,) [N/m].
        wrench: External wrench (6,) [N, N·m].
        load_displacement: Object displacement of the load stage (6,) [m, rad].
        command: Actuator commands (na,) [N·m or N].
        actuator_displacements: ``u = R^T q`` (na,) [rad or m].
        object_displacement: Total object displacement (6,) [m, rad].
        joint_displacements: ``q`` (nq,) [rad or m].
        length_scale: Grasp size [m] (rotations x length scale are lengths).
        levers: Joint lever arms (nq,) [m] (joint displacements x lever are lengths).
        names: Contact names (nc,).
        force_tolerance: The audit's force tolerance [N] (forces below it are rounding: a zero
            preload and load store no energy).
    """
    cn = np.asarray(normal_forces, float)
    k = np.asarray(stiffness, float)
    per_contact = cn**2 / (2.0 * k)
    spring = float(per_contact.sum())
    load = float(np.dot(wrench, load_displacement))
    act = float(np.dot(command, actuator_displacements)) if len(command) else 0.0
    x = np.asarray(object_displacement, float)
    sizes = [np.abs(x[:3]).max(initial=0.0), np.abs(x[3:]).max(initial=0.0) * length_scale]
    if len(joint_displacements):
        sizes.append(float(np.max(np.abs(joint_displacements) * levers)))
    compression = float(np.max(np.abs(cn) / k, initial=0.0))
    disp = max(sizes)
    ratio = disp / compression if compression > 0 else (0.0 if disp == 0 else np.inf)
    order = np.argsort(-per_contact, kind="stable")
    named, held = [], 0.0
    for i in order:
        if held >= NAMED_SHARE * spring or per_contact[i] <= 0:
            break
        named.append(names[i])
        held += per_contact[i]
    t = float(force_tolerance)
    slack = float(np.sum((2.0 * np.abs(cn) + t) * t / (2.0 * k)))
    return EnergyCheck(spring, load, act, float(ratio), tuple(named), slack)


def friction_use(
    contact_forces: np.ndarray, mu: np.ndarray, touching: tuple[bool, ...], floor: float
) -> np.ndarray:
    """``|c_t| / (mu c_n)`` (nc,) for touching contacts with ``c_n > floor`` [N]; NaN otherwise
    (a separated contact, or one touching with no normal force, uses no friction)."""
    cf = np.asarray(contact_forces, float)
    out = np.full(len(cf), np.nan)
    for i, (f, m, t) in enumerate(zip(cf, mu, touching)):
        if t and f[0] > floor:
            ct = float(np.linalg.norm(f[1:]))
            # a frictionless contact uses none (its tangential force is zero up to rounding)
            out[i] = ct / (m * f[0]) if m > 0 else (0.0 if ct <= floor else np.inf)
    return out


def audit_message(method: str, check: EnergyCheck) -> str:
    """The warning text of a solution that fails :func:`energy_check`."""
    parts = []
    if not check.energy_ok:
        supplied = check.load_work + check.actuator_work
        cause = (
            "the wedging artefact"
            if method == "prp"
            else "not the PRP's wedging artefact (this method has none): the balance prices the "
            "final state alone, which this method reached along a path (the held-still preload, "
            "the iterative steps), or the solver's tolerance; cross-check with pg.simulate_max_wrench"
        )
        parts.append(
            f"its springs store {check.spring_energy:.4g} J but the load and the actuators supply "
            f"only {supplied:.4g} J on its displacements (contacts {', '.join(check.contacts)}): " + cause
        )
    if not check.displacement_ok:
        parts.append(
            f"its displacements reach {check.displacement_ratio:.3g} times the largest spring "
            f"compression (limit {MAX_DISPLACEMENT_RATIO:g})"
        )
    hint = " (methods 'iterative' and 'energetic' have no wedging artefact)" if method == "prp" else ""
    return f"{method} solution fails the audit: " + "; ".join(parts) + hint
