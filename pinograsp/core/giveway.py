"""Give-way: when a preloaded grasp under a slowly growing load stops holding the object.

One definition shared by the analysis (the quasi-static method's default answer) and the
simulation (``pg.simulate_max_wrench``), docs/giveway.md:

* the object *gives way* when its reference point has moved ``slip`` [m] or it has turned
  ``rotation`` [rad] from the preloaded pose, or (when a joint threshold is set) a finger joint
  has turned ``joint`` [rad] from the preloaded configuration;
* the defaults scale the same way in both: ``slip = max(1 mm, 20 x`` the elastic deflection of
  one contact spring of stiffness ``stiffness`` under the largest load of interest ``upper``),
  ``rotation = slip / length_scale``, no joint threshold;
* contact stiffness is physical: ``stiffness`` [N/m] is the normal stiffness of the stiffest
  contact (default :data:`DEFAULT_CONTACT_STIFFNESS`, the simulation's); the model's ``k`` give
  the others in proportion and ``tangential_ratio`` the tangential springs.

:class:`GiveWay` is the record of where the analysis found it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from .serialize import jsonable

#: Normal stiffness of the stiffest contact [N/m] when none is given: the simulation's default
#: (a rubber-padded fingertip is 1e5-1e6 N/m, a metal link on a rigid object 1e7 and more).
DEFAULT_CONTACT_STIFFNESS = 1e6
#: Smallest default translation threshold [m].
MIN_SLIP = 1e-3
#: Default translation threshold as a multiple of one contact spring's elastic deflection at
#: ``upper``: elastic deflection alone is never a give-way.
ELASTIC_FACTOR = 20.0
#: Largest object rotation [rad] and translation [fraction of the length scale] of a resisted
#: path. The load stage re-linearises about the turned object every few milliradians (the
#: contact arms turn and the forces' geometric stiffness enters: docs/quasistatic.md, "Large
#: rotations") up to ``LINEAR_ROTATION``; the hand's kinematics stay linear (as in the
#: simulation), trusted up to ``LINEAR_TRANSLATION`` of the length scale. Past them a path is
#: not "resisted", it ends with a give-way verdict ``"linearisation"`` (docs/giveway.md).
LINEAR_ROTATION = 1.0
LINEAR_TRANSLATION = 0.25

#: Why the grasp gave way where it did: the path reached a limit load and snapped without
#: landing within the thresholds (``"limit"``), the object moved the translation or rotation
#: threshold (``"translation"``, ``"rotation"``), a joint turned its threshold (``"joint"``),
#: the motion left the linearisation's range first (``"linearisation"``), or it did not give
#: way at all (``"held"``: unbounded within the thresholds, or the path's end).
GiveWayReason = Literal["limit", "translation", "rotation", "joint", "linearisation", "held"]
GIVEWAY_REASONS: tuple[str, ...] = ("limit", "translation", "rotation", "joint", "linearisation", "held")


def elastic_deflection(length_scale: float, direction: np.ndarray, upper: float, stiffness: float) -> float:
    """Deflection [m] of one contact spring of ``stiffness`` [N/m] carrying the load ``upper``
    along the unit ``direction`` (6,), torques as forces at the length scale [m]."""
    d = np.asarray(direction, float)
    load = upper * (float(np.linalg.norm(d[:3])) + float(np.linalg.norm(d[3:])) / length_scale)
    return load / stiffness


def giveway_thresholds(
    length_scale: float,
    direction: np.ndarray,
    upper: float,
    stiffness: float,
    slip: float | None = None,
    rotation: float | None = None,
) -> tuple[float, float]:
    """The give-way translation [m] and rotation [rad] thresholds, defaults filled in: ``slip``
    ``max(1 mm, 20 x`` :func:`elastic_deflection` ``)``, ``rotation`` ``slip / length_scale``."""
    s = max(MIN_SLIP, ELASTIC_FACTOR * elastic_deflection(length_scale, direction, upper, stiffness))
    s = s if slip is None else float(slip)
    r = s / length_scale if rotation is None else float(rotation)
    return s, r


@dataclass(frozen=True)
class GiveWay:
    """Where the analysis found the grasp to give way along one direction.

    Attributes:
        load: The give-way load [N or N·m]: ``inf`` when it held (``reason == "held"``).
        reason: :data:`GiveWayReason`.
        first_limit: The loading path's first limit load λ* [N or N·m] (``inf`` when the path
            has none): the idealised quantity the give-way load replaces (a snap at λ* that
            lands on a stable branch is survived).
        first_status: The path's status at its first limit (``"finite"``, ``"unbounded"``,
            ``"below_resolution"``, ...).
        snaps: ``(limit load, landing load)`` [N or N·m] of every snap followed and survived
            before the give-way.
        stiffness: Normal stiffness of the stiffest contact [N/m] (the others in proportion).
        tangential_ratio: Tangential over normal contact stiffness.
        slip: Translation threshold [m]; rotation: rotation threshold [rad]; joint: joint
            threshold [rad] or None (no joint criterion).
        translation: Object translation from the preloaded pose at the give-way [m].
        turned: Object rotation from the preloaded pose at the give-way [rad].
        note: Why the answer is what it is when the path could not decide further, else ``""``.
    """

    load: float
    reason: GiveWayReason
    first_limit: float
    first_status: str
    snaps: tuple[tuple[float, float], ...]
    stiffness: float
    tangential_ratio: float
    slip: float
    rotation: float
    joint: float | None
    translation: float
    turned: float
    note: str = ""

    @property
    def held(self) -> bool:
        """Whether the grasp held (no give-way within the thresholds)."""
        return self.reason == "held"

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data (``inf`` as ``None``)."""
        return jsonable(
            {
                "load": None if math.isinf(self.load) else self.load,
                "reason": self.reason,
                "first_limit": None if math.isinf(self.first_limit) else self.first_limit,
                "first_status": self.first_status,
                "snaps": [list(s) for s in self.snaps],
                "stiffness": self.stiffness,
                "tangential_ratio": self.tangential_ratio,
                "slip": self.slip,
                "rotation": self.rotation,
                "joint": self.joint,
                "translation": self.translation,
                "turned": self.turned,
                "note": self.note,
            }
        )

    def text(self, unit: str) -> str:
        """One line: the reason, the thresholds, the first limit and the snaps survived."""
        first = "none (unbounded)" if math.isinf(self.first_limit) else f"{self.first_limit:.6g} {unit}"
        out = (
            f"give-way: {self.reason} (thresholds {self.slip * 1e3:.3g} mm, "
            f"{math.degrees(self.rotation):.3g} deg at {self.stiffness:.3g} N/m); first limit {first}"
        )
        if self.snaps:
            out += f"; {len(self.snaps)} snap(s) survived"
        return out


__all__ = [
    "DEFAULT_CONTACT_STIFFNESS",
    "ELASTIC_FACTOR",
    "GIVEWAY_REASONS",
    "LINEAR_ROTATION",
    "LINEAR_TRANSLATION",
    "MIN_SLIP",
    "GiveWay",
    "GiveWayReason",
    "elastic_deflection",
    "giveway_thresholds",
]
