"""The path's stage description and state records."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .model import QSModel


@dataclass(frozen=True)
class StageSpec:
    """One stage of the path: object load ``w0 + t dw`` (reduced, [N, N·m]), commands
    ``fc0 + t dfc`` (na,), for ``t`` from its start to ``t_end``; ``held``: the object is
    held still (its holder takes any wrench); ``friction``: tangential springs and friction on."""

    w0: np.ndarray
    dw: np.ndarray
    fc0: np.ndarray
    dfc: np.ndarray
    t_end: float
    held: bool
    friction: bool

    def command(self, t: float) -> np.ndarray:
        """Commands at ``t`` (na,)."""
        return self.fc0 + t * self.dfc


@dataclass
class State:
    """A point of the path (scaled displacements, physical forces).

    Attributes:
        vs: Scaled displacements ``(x, q)`` (nv,) [m].
        c: Contact forces, contact frames (nc*d,) [N].
        f: Actuator forces (na,); lam_c: coupling reactions (ncp,); hold: holder wrench (nx,).
        slip: Accumulated tangential slip ``a`` (nc*d,; normal rows 0) [m].
        t: Path parameter of the stage (the load factor in the load stage).
        geo: The model with updated geometry whose segment reached this state (None: the
            model's own geometry; ``geometry.moved``), read by the audits.
    """

    vs: np.ndarray
    c: np.ndarray
    f: np.ndarray
    lam_c: np.ndarray
    hold: np.ndarray
    slip: np.ndarray
    t: float = 0.0
    geo: QSModel | None = None

    def copy(self) -> State:
        """An independent copy."""
        return State(
            self.vs.copy(),
            self.c.copy(),
            self.f.copy(),
            self.lam_c.copy(),
            self.hold.copy(),
            self.slip.copy(),
            self.t,
            self.geo,
        )


__all__ = ["StageSpec", "State"]
