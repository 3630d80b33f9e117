"""Actuators (with their transmission to the joints) and rigid joint couplings.

Model (docs/design.md): actuator forces ``f`` (na) reach the joints through the transmission
``R`` (nq × na), ``tau = R f + C^T lambda``, with rigid couplings ``C q = 0`` and actuator
displacement ``u = R^T q``. Each actuator has one of three kinds:

* ``"non-backdrivable"`` (default): ``u >= 0 ⟂ f - f_c >= 0`` — it closes at exactly the
  commanded force or holds still with any larger (passive) force;
* ``"backdrivable"``: ``f = f_c``, ``u`` free;
* ``"locked"``: ``u = 0``, ``f`` free (e.g. the Barrett spread joint, modelled rigid).

Commands are closing forces ``f_c >= 0``. An actuator declared ``bidirectional`` also takes
``f_c < 0``: it then drives the opposite way, i.e. it is the same actuator with its transmission
column negated and the command ``|f_c|`` (docs/hands.md, "Bidirectional actuators").
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import InvalidInputError
from .validate import ARM, check_name, choice, finite_number

#: The actuator kinds (see the module docstring).
NON_BACKDRIVABLE, BACKDRIVABLE, LOCKED = "non-backdrivable", "backdrivable", "locked"
#: Valid actuator kinds.
ACTUATOR_KINDS = (NON_BACKDRIVABLE, BACKDRIVABLE, LOCKED)


def _joint_key(owner: str, joint: object) -> int | str:
    if isinstance(joint, (bool, np.bool_)) or not isinstance(joint, (int, np.integer, str)):
        raise InvalidInputError(owner, f"joint keys must be indices or names, got {joint!r}")
    return joint if isinstance(joint, str) else int(joint)


def _check_weights(owner: str, weights: Mapping[int | str, float]) -> dict[int | str, float]:
    if not isinstance(weights, Mapping) or not weights:
        raise InvalidInputError(owner, f"expected a non-empty mapping joint -> value, got {weights!r}")
    out: dict[int | str, float] = {}
    for joint, value in weights.items():
        key = _joint_key(owner, joint)
        v = finite_number(f"{owner}[{joint!r}]", value)
        if v != 0 and not ARM[0] <= abs(v) <= ARM[1]:  # domain: docs/errors.md
            raise InvalidInputError(
                f"{owner}[{joint!r}]",
                f"a moment arm, ratio or coefficient must be 0 or within {ARM[0]:g} … {ARM[1]:g} in "
                f"magnitude, got {value!r} (give the commands in other units instead)",
            )
        out[key] = out.get(key, 0.0) + v
    return out


@dataclass(frozen=True)
class Actuator:
    """A motor (or tendon) acting on one or several joints.

    Attributes:
        transmission: ``{joint: moment_arm}`` — the actuator's column of ``R``; joint given by
            index or by name (names need ``joint_names`` on the model). For direct drive use
            ``{j: 1.0}`` (force = joint torque [N·m]); for a tendon, the moment arm [m] of every
            joint it crosses (force in [N]).
        kind: ``"non-backdrivable"``, ``"backdrivable"`` or ``"locked"``.
        name: Label used in results, commands given as dicts, and error messages.
        bidirectional: Whether a negative command (driving the other way) is valid; without it
            a negative command is an :class:`InvalidInputError`.
    """

    transmission: Mapping[int | str, float]
    kind: str = "non-backdrivable"
    name: str | None = None
    bidirectional: bool = False

    def __post_init__(self) -> None:
        check_name("actuator", self.name)
        label = f"actuator {self.name!r}" if self.name is not None else "actuator"
        object.__setattr__(self, "transmission", _check_weights(f"{label}.transmission", self.transmission))
        choice(f"{label}.kind", self.kind, ACTUATOR_KINDS)
        if not isinstance(self.bidirectional, (bool, np.bool_)):
            raise InvalidInputError(
                f"{label}.bidirectional", f"expected True or False, got {self.bidirectional!r}"
            )


@dataclass(frozen=True)
class Coupling:
    """A rigid linear motion coupling between joints: ``sum_j weights[j] * q_j = 0``.

    Attributes:
        weights: ``{joint: coefficient}`` (joint by index or name).
        name: Label used in results and error messages.
    """

    weights: Mapping[int | str, float]
    name: str | None = None

    def __post_init__(self) -> None:
        check_name("coupling", self.name)
        label = f"coupling {self.name!r}" if self.name is not None else "coupling"
        object.__setattr__(self, "weights", _check_weights(f"{label}.weights", self.weights))

    @staticmethod
    def follow(follower: int | str, leader: int | str, ratio: float, name: str | None = None) -> Coupling:
        """``q_follower = ratio * q_leader`` (e.g. a Barrett distal joint at 1/3 of proximal)."""
        f = _joint_key("coupling follower", follower)
        lead = _joint_key("coupling leader", leader)
        if f == lead:
            raise InvalidInputError("coupling", f"joint {follower!r} cannot follow itself")
        return Coupling({f: 1.0, lead: -finite_number("coupling ratio", ratio)}, name=name)
