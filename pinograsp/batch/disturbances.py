"""A score over a set of disturbances: the worst case of the passive answers along each.

:class:`DisturbanceScore` is a batch score (``score(model, command) -> {name: float}``) like
:class:`~pinograsp.batch.evaluate.WorstAxisScore`, over any set of disturbance wrenches: the 26
directions of a cube (faces, edges, corners; :func:`~pinograsp.core.axes.cube_directions`) by
default, the object's weight in every orientation with a margin (:class:`Gravity`), or the
user's wrenches. Each is answered by :func:`pinograsp.max_resistible_wrench`
with the chosen method (the package's default one unless told), so the score follows whatever
that method reports. It also returns the Ferrari–Canny epsilon of the same contacts
(:func:`pinograsp.ferrari_canny`), so that a table ranks by either. ``pg.plan_grasps`` scores its
candidates with it; a GRASPS.yaml ``score: {disturbances: cube26}`` block selects it in
``pinograsp batch`` (docs/batch.md, docs/planning.md).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.axes import cube_directions, sphere_directions
from ..core.methods import bounded as limits_bound
from ..core.methods import method_name
from ..core.query import Query
from ..core.settings import DEFAULT_METHOD, Method
from ..core.validate import count, finite_array, force, number_in, vector
from ..core.validate import steps as n_steps
from ..errors import InvalidInputError

#: Named disturbance sets.
DISTURBANCE_SETS = ("cube26",)
#: Standard gravity [m/s²], the default of :attr:`Gravity.g`.
STANDARD_GRAVITY = 9.81
#: Most orientations of a :class:`Gravity` set (each one loading path per grasp).
MAX_ORIENTATIONS = 1000
_GRAVITY_KEYS = ("mass", "margin", "orientations", "offset", "g")


@dataclass(frozen=True)
class Gravity:
    """The object's weight in every orientation of the held grasp, with a safety margin.

    Turning the hand with the object in it turns gravity in the hand base frame: the set is the
    weight ``(1 + margin) mass g`` along each sampled direction ``u``, applied at the centre of
    mass: the wrench ``(1 + margin) mass g (u, offset x u)`` [N, N·m] about the model's
    reference point. A disturbance's value is the largest multiple of it resisted, so a score
    ``>= 1`` says the grasp holds its weight with the margin in every orientation sampled.

    Attributes:
        mass: Object mass [kg], in (0, 1e6].
        margin: Safety margin, in [0, 100]: each disturbance is ``1 + margin`` times the weight.
        orientations: ``"cube26"`` (gravity along the 26 directions of a cube, labels
            ``"g+fx"``, ``"g-fx+fy-fz"``, ...) or a number of directions in [6, 1000] spread over
            the sphere (:func:`~pinograsp.core.axes.sphere_directions`, labels ``"g0"``, ...).
        offset: Centre of mass minus the model's reference point, hand base frame [m], (3,):
            zero where the reference point is the centre of mass (``pg.GraspSpec``'s default and
            every planned grasp).
        g: Gravitational acceleration [m/s²], in (0, 100].
    """

    mass: float
    margin: float = 0.5
    orientations: str | int = "cube26"
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    g: float = STANDARD_GRAVITY

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", number_in("mass", self.mass, 0.0, 1e6, "kg", open_low=True))
        object.__setattr__(self, "margin", number_in("margin", self.margin, 0.0, 100.0))
        if isinstance(self.orientations, str):
            if self.orientations not in DISTURBANCE_SETS:
                raise InvalidInputError(
                    "orientations",
                    f"must be 'cube26' or a number of directions in [6, {MAX_ORIENTATIONS}], "
                    f"got {self.orientations!r}",
                )
        else:
            n = count(
                "orientations", self.orientations, MAX_ORIENTATIONS, 6, "directions, one loading path each"
            )
            object.__setattr__(self, "orientations", n)
        offset = vector("offset", self.offset, 3)
        object.__setattr__(self, "offset", tuple(float(v) for v in offset))
        object.__setattr__(self, "g", number_in("g", self.g, 0.0, 100.0, "m/s²", open_low=True))

    @classmethod
    def of(cls, data: Mapping[str, Any], name: str = "gravity") -> Gravity:
        """From ``{"mass": ..., "margin": ..., ...}`` (:meth:`to_dict`'s form); unknown keys named."""
        if not isinstance(data, Mapping):
            raise InvalidInputError(name, f"expected a mapping with keys {_GRAVITY_KEYS}, got {data!r}")
        unknown = [k for k in data if k not in _GRAVITY_KEYS]
        if unknown or "mass" not in data:
            what = f"unknown key(s) {unknown}" if unknown else "'mass' [kg] is missing"
            raise InvalidInputError(name, f"{what}; the keys are {_GRAVITY_KEYS} ('mass' required)")
        return cls(**{str(k): v for k, v in data.items()})

    @property
    def weight(self) -> float:
        """The disturbance's force magnitude ``(1 + margin) mass g`` [N]."""
        return (1.0 + self.margin) * self.mass * self.g

    @property
    def unit(self) -> str:
        """What a value counts, for tables and axes: ``"1.962 N (the weight x 2)"``."""
        return f"{self.weight:.4g} N (the weight x {1 + self.margin:g})"

    def wrenches(self) -> tuple[tuple[str, ...], np.ndarray]:
        """The labels (k,) and wrenches (k, 6) [N, N·m] of the set."""
        if self.orientations == "cube26":
            names, units = cube_directions()
            labels = tuple(f"g{a}" for a in names)
        else:
            units = sphere_directions(int(self.orientations))
            labels = tuple(f"g{i}" for i in range(len(units)))
        w = self.weight * units
        w[:, 3:] = np.cross(np.asarray(self.offset), w[:, :3])
        return labels, w

    def to_dict(self) -> dict[str, Any]:
        """Plain data: the keys of :meth:`of`."""
        return {"mass": self.mass, "margin": self.margin, "orientations": self.orientations,
                "offset": list(self.offset), "g": self.g}  # fmt: skip


def disturbance_set(disturbances: object, name: str = "disturbances") -> tuple[tuple[str, ...], np.ndarray]:
    """The labels (k,) and wrenches (k, 6) [N, N·m] of a disturbance set.

    Args:
        disturbances: ``"cube26"`` (the 26 unit force directions of a cube: labels ``"+fx"``,
            ``"+fx-fy"``, ...), a :class:`Gravity` (or ``{"gravity": {...}}``, its
            :meth:`Gravity.to_dict` under the key ``gravity``), or wrenches, (k, 6), none zero
            (labels ``"w0"``, ``"w1"``, ...).
        name: Argument name in error messages.

    Raises:
        InvalidInputError: An unknown name, a malformed array or a zero wrench.
    """
    if isinstance(disturbances, str):
        if disturbances not in DISTURBANCE_SETS:
            raise InvalidInputError(
                name,
                f"{disturbances!r} is not a named set; give 'cube26', pg.Gravity(mass, margin=...) (in a "
                "GRASPS file {gravity: {mass: KG}}) or wrenches of shape (k, 6)",
            )
        return cube_directions()
    gravity = gravity_of(disturbances, name)
    if gravity is not None:
        return gravity.wrenches()
    try:
        raw = np.asarray(disturbances, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInputError(
            name, f"expected 'cube26', a Gravity or wrenches of shape (k, 6), got {disturbances!r}"
        ) from None
    if raw.ndim != 2 or raw.shape[1] != 6 or len(raw) == 0:
        raise InvalidInputError(name, f"expected 'cube26' or wrenches of shape (k, 6), got shape {raw.shape}")
    w = finite_array(name, raw, raw.shape)
    zero = [i for i, row in enumerate(w) if not np.any(row)]
    if zero:
        raise InvalidInputError(name, f"row(s) {zero} are zero wrenches; give a nonzero wrench per row")
    return tuple(f"w{i}" for i in range(len(w))), w


def gravity_of(disturbances: object, name: str = "disturbances") -> Gravity | None:
    """``disturbances`` as a :class:`Gravity` (itself, or ``{"gravity": {...}}``), else None."""
    if isinstance(disturbances, Gravity):
        return disturbances
    if isinstance(disturbances, Mapping):
        if list(disturbances) != ["gravity"]:
            raise InvalidInputError(
                name,
                f"a mapping names one set, {{'gravity': {{'mass': ...}}}}; got keys {list(disturbances)}",
            )
        return Gravity.of(disturbances["gravity"], f"{name}.gravity")
    return None


@dataclass(frozen=True)
class DisturbanceScore:
    """Worst case over a disturbance set of the largest multiple of each disturbance resisted.

    For each disturbance ``w_i`` (a unit force direction of the cube, or a user wrench),
    ``pg.max_resistible_wrench(model, command, w_i, method, upper, steps)`` gives the largest
    magnitude along ``w_i / |w_i|``; the value of the disturbance is that magnitude divided by
    ``|w_i|`` (Euclidean norm of ``(f [N], tau [N·m])``): the largest multiple of ``w_i`` resisted
    — for the cube's unit forces the largest force [N]. ``inf`` when unbounded, ``upper / |w_i|``
    above the search limit, 0 below its resolution (as :class:`WorstAxisScore`). On a planar
    model a disturbance with no planar part (``fx, fy, mz``) has no value (NaN) and is skipped.

    Returns ``score`` (the smallest value), ``unbounded_fraction`` (of the disturbances),
    ``epsilon`` (Ferrari–Canny of the contacts, :func:`pinograsp.ferrari_canny`), ``snap_free``
    (the smallest value reached without a snap: where a loading path survived snaps on its way
    to its answer, its first snap's load; docs/giveway.md), one ``max_<label>`` column per
    disturbance (labels of :func:`disturbance_set`) and one ``snap_<label>``: the load (as a
    multiple) of the first snap its answer survived below its value, ``inf`` when none (every
    method but the quasi-static one).

    Attributes:
        disturbances: ``"cube26"``, a :class:`Gravity` (also given as ``{"gravity": {...}}``) or
            wrenches (k, 6) (kept as a tuple of 6-tuples).
        method: The analysis method (default: the package's default method).
        upper: Search limit [N or N·m along the unit direction].
        steps: Search steps (a loading-path method ignores it).
        floor: Stop as soon as one value falls below it (a local search's incumbent score, ``inf``
            for an incumbent unbounded along every disturbance): the
            row then has ``pruned`` 1 and NaN for the disturbances not answered; its ``score`` is
            an upper bound of the true worst case. ``-inf`` (default): every disturbance is
            answered and there is no ``pruned`` column.
        first: Labels answered first, in this order (the incumbent's worst ones), so that a
            pruned row stops early; the others follow in the set's order.
    """

    disturbances: str | Gravity | tuple[tuple[float, ...], ...] = "cube26"
    method: Method | str = Method(DEFAULT_METHOD)
    upper: float = 50.0
    steps: int = 6
    floor: float = -math.inf
    first: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        gravity = gravity_of(self.disturbances)
        if gravity is not None:
            object.__setattr__(self, "disturbances", gravity)
        else:
            _, w = disturbance_set(self.disturbances)
            if not isinstance(self.disturbances, str):
                object.__setattr__(self, "disturbances", tuple(tuple(float(v) for v in row) for row in w))
        object.__setattr__(self, "method", method_name(self.method))
        object.__setattr__(self, "upper", force("upper", self.upper, "N or N·m"))
        bounded = limits_bound(self.method)
        object.__setattr__(self, "steps", n_steps(self.steps, bounded=bounded))
        floor = float(self.floor) if isinstance(self.floor, (int, float)) else math.nan
        if math.isnan(floor):
            raise InvalidInputError("floor", f"expected a number or ±inf, got {self.floor!r}")
        object.__setattr__(self, "floor", floor)
        unknown = [a for a in self.first if a not in self.labels]
        if unknown:
            raise InvalidInputError("first", f"{unknown} are not labels of the set; pick from {self.labels}")
        object.__setattr__(self, "first", tuple(str(a) for a in self.first))

    @property
    def labels(self) -> tuple[str, ...]:
        """The disturbances' labels, (k,)."""
        return disturbance_set(self.disturbances)[0]

    @property
    def wrenches(self) -> np.ndarray:
        """The disturbances, (k, 6) [N, N·m]."""
        return disturbance_set(self.disturbances)[1]

    @property
    def columns(self) -> tuple[str, ...]:
        """The table's score columns."""
        pruned = ("pruned",) if self.floor > -math.inf else ()
        maxima, snaps = (f"max_{a}" for a in self.labels), (f"snap_{a}" for a in self.labels)
        return ("score", "unbounded_fraction", "epsilon", "snap_free", *pruned, *maxima, *snaps)

    @property
    def no_grasp(self) -> dict[str, float]:
        """The values of a record that is not a grasp: it resists nothing."""
        return dict.fromkeys(self.columns, 0.0)

    def __call__(self, model: Any, command: Mapping[str, float]) -> dict[str, float]:
        from ..analysis.max_wrench import max_resistible_wrench
        from ..analysis.metrics import ferrari_canny
        from ..analysis.response import Session

        query = Query(self.method, self.upper, self.steps)
        session = Session(model)  # one per grasp: its preload stage is solved once
        values = dict.fromkeys((f"max_{a}" for a in self.labels), math.nan)
        snaps = dict.fromkeys((f"snap_{a}" for a in self.labels), math.nan)
        labels, wrenches = self.labels, self.wrenches
        order = [labels.index(a) for a in self.first]
        order += [i for i in range(len(labels)) if i not in order]
        first, pruned = True, False
        for i in order:
            w = wrenches[i]
            if model.planar and not np.any(w[[0, 1, 5]]):
                continue
            mw = max_resistible_wrench(
                model, command, w, session=session, query=query, check_preload_first=first
            )
            first = False
            scale = float(np.linalg.norm(w[[0, 1, 5]] if model.planar else w))
            value = 0.0 if mw.status == "below_resolution" else float(mw.magnitude) / scale
            values[f"max_{labels[i]}"] = value
            # the first snap on the way to the answer (a path followed past ``upper`` may snap later)
            survived = [
                s for s, _ in (mw.giveway.snaps if mw.giveway is not None else ()) if s <= mw.magnitude
            ]
            snaps[f"snap_{labels[i]}"] = survived[0] / scale if survived else math.inf
            if value < self.floor:
                pruned = True
                break
        known = [v for v in values.values() if not math.isnan(v)]
        unbounded = sum(v == math.inf for v in known)
        calm = [min(v, s) for v, s in zip(values.values(), snaps.values()) if not math.isnan(v)]
        return {
            "score": min(known),
            "unbounded_fraction": unbounded / len(known),
            "epsilon": ferrari_canny(model),
            "snap_free": min(calm),
            **({"pruned": float(pruned)} if self.floor > -math.inf else {}),
            **values,
            **snaps,
        }
