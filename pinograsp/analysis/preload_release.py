"""The released state of a preload: does it hold? (:func:`pinograsp.equilibrium_preload`'s
verdict beyond equilibrium.)

A preload whose stage ends in equilibrium may still have given while the object was let go: a
contact slid to its friction limit (a small load then makes the grasp give way) or lost its
force, or the object moved far. :func:`released` reads the states and the motion off the
method's response at ``w = 0``; :func:`gives_way` turns them into a verdict.
"""

from __future__ import annotations

import numpy as np

from ..core.model import GraspModel
from ..core.results import PassiveResponse

#: The verdicts of commands that balance but whose released state does not hold everywhere.
GIVES: tuple[str, ...] = ("slides", "separates")
#: Largest motion of the object at a contact on release (``PreloadChoice.released_motion``),
#: relative to the largest contact compression ``c_n / k``, of a preload that holds. An elastic
#: release moves the object by about the springs' compression: 0 on the symmetric pinch, 0.03 on
#: case 1, 0.2 on the wedge, 0.3 on the EZGripper, 1.25 on the SO-101 (a fixed jaw: the object
#: settles into it by its whole compression, and turns); ten times that is a grasp that gave way
#: while it was let go.
MOVED_RATIO = 10.0
#: Methods whose ``"sliding"`` at ``w = 0`` reads the state itself (a contact on its friction
#: limit): the quasi-static one (its preloaded state's forces). The others report a contact
#: ``"sliding"`` when it has slipped since the touch (the held-still closing drags fingers along
#: the object): history, not a limit, so their verdict reads separation and motion only.
LIMIT_STATES = ("quasistatic",)


def released(model: GraspModel, resp: PassiveResponse) -> tuple[tuple[str, ...], float]:
    """The released state of a verification at ``w = 0``: the contact states (nc,) and the
    largest motion of the object at a contact over the largest contact compression ``c_n / k``
    [-] (``PreloadChoice.released_motion``)."""
    x = model.reduce_wrench(np.asarray(resp.object_displacement, float))  # twist: same axes
    at_contacts = (np.asarray(model.G, float).T @ x).reshape(model.nc, model.d)
    compression = np.asarray(resp.normal_forces, float) / np.asarray(model.k, float)
    largest = float(compression.max(initial=0.0))
    moved = float(np.linalg.norm(at_contacts, axis=1).max(initial=0.0))
    return tuple(resp.contact_states), (moved / largest if largest > 0 else float("inf"))


def gives_way(
    model: GraspModel, states: tuple[str, ...], motion: float, method: str = "quasistatic"
) -> tuple[str, str] | None:
    """The verdict (:data:`GIVES`) of a released state that does not hold, and what gives (one
    phrase); None when it holds. ``"sliding"`` counts for the methods of :data:`LIMIT_STATES`."""
    if method not in LIMIT_STATES:
        states = tuple("sticking" if s == "sliding" else s for s in states)
    parts = []
    for word, state in (("slide on their friction limit", "sliding"), ("separate", "separated")):
        names = [n for n, s in zip(model.contact_names, states) if s == state]
        if names:
            parts.append(f"contact(s) {names} {word}")
    if motion > MOVED_RATIO:
        parts.append(f"the object moved {motion:.3g} times the largest contact compression")
    if not parts:
        return None
    slides = "sliding" in states or motion > MOVED_RATIO
    return ("slides" if slides else "separates"), "; ".join(parts)


__all__ = ["GIVES", "LIMIT_STATES", "MOVED_RATIO", "gives_way", "released"]
