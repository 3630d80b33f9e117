"""Grasp quality numbers: the passive-resistance score and the Ferrari–Canny epsilon
(``docs/metrics.md``).

* :func:`ferrari_canny` — radius of the largest ball around the origin inside the convex hull
  of the primitive contact wrenches (linearised cones, unit normal forces, torques divided by a
  characteristic length): a property of the contact geometry and friction only.
* :func:`grasp_score` — what the preloaded hand resists *passively*: a low quantile (default
  5 %) of the resistible magnitude over the unit wrench sphere
  (:func:`pinograsp.resistance_set`), the worst case (``quantile=0``), or the fraction of a
  given sample of disturbances that is resisted.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from ..core.model import GraspModel
from ..core.serialize import format_magnitude, jsonable
from ..core.settings import DEFAULT_METHOD
from ..core.validate import finite_array, relative_length
from ..errors import InvalidInputError
from .resistance_set import ResistanceSet, resistance_set, wrench_rows

#: How a :class:`GraspScore` was defined.
ScoreKind = Literal["quantile", "worst", "disturbances"]


def primitive_wrenches(model: GraspModel, length: float | None = None) -> np.ndarray:
    """Wrenches on the object of every pyramid edge with unit normal force, torques divided by
    ``length`` [m] (default ``model.length_scale``), (nb, nw) [N] (``nw`` 6, or 3 planar)."""
    length = (
        float(model.length_scale) if length is None else relative_length("length", length, model.length_scale)
    )
    W = (np.asarray(model.G) @ np.asarray(model.D)).T.copy()  # (nb, nw): G c with c = D beta
    W[:, model.d :] /= length
    return W


def ferrari_canny(model: GraspModel, length: float | None = None) -> float:
    """The Ferrari–Canny epsilon: radius [N per N of total normal force] of the largest ball
    around the origin inside the convex hull of :func:`primitive_wrenches`.

    ``0`` when the origin is not strictly inside the hull (no force closure), including when the
    primitive wrenches span less than the whole wrench space (e.g. a 3D pinch: no torque about
    the line through the contacts). Inscribed pyramids as in the model (``model.edges``).

    Args:
        model: The grasp (only its contacts: points, frames, friction pyramids).
        length: Characteristic length [m] dividing torques (default ``model.length_scale``).
    """
    from scipy.spatial import ConvexHull, QhullError

    W = primitive_wrenches(model, length)
    if W.shape[0] <= W.shape[1] or np.linalg.matrix_rank(W) < W.shape[1]:
        return 0.0
    try:
        hull = ConvexHull(W)
    except QhullError:
        return 0.0
    # facets: normal . x + offset <= 0 inside, |normal| = 1: distance origin -> facet = -offset
    eps = float(np.min(-hull.equations[:, -1]))
    return max(eps, 0.0)


def hull_reach(model: GraspModel, points: object, length: float | None = None) -> np.ndarray:
    """Per-direction Ferrari–Canny: how far the hull of :func:`primitive_wrenches` reaches along
    each unit direction ``u`` of the scaled wrench space ``(f, tau / length)`` [N per N of total
    normal force], (n,). Its minimum over all directions is :func:`ferrari_canny`.

    Args:
        points: Unit directions in the scaled space, (n, 6) (e.g. ``ResistanceSet.sphere``; the
            planar components are taken for planar models).
        length: As :func:`ferrari_canny`.
    """
    from scipy.spatial import ConvexHull, QhullError

    try:
        u = None if isinstance(points, (str, bytes)) else np.array(points, dtype=float)
    except (TypeError, ValueError, OverflowError):
        u = None
    if u is None or u.ndim != 2 or u.shape[1] != 6:
        raise InvalidInputError("points", f"expected an array of shape (n, 6), got {points!r}")
    u = finite_array("points", u, u.shape)
    u = u[:, [0, 1, 5]] if model.planar else u
    W = primitive_wrenches(model, length)
    if W.shape[0] <= W.shape[1] or np.linalg.matrix_rank(W) < W.shape[1]:
        return np.zeros(len(u))
    try:
        eq = ConvexHull(W).equations
    except QhullError:
        return np.zeros(len(u))
    dots = u @ eq[:, :-1].T  # (n, facets)
    with np.errstate(divide="ignore"):
        t = np.where(dots > 1e-15, -eq[:, -1][None, :] / dots, np.inf)
    return np.maximum(t.min(axis=1), 0.0)


@dataclass(frozen=True, repr=False)
class GraspScore:
    """A passive-resistance score and the set it came from.

    Attributes:
        value: The score: [N] (scaled wrench norm ``sqrt(|f|² + |tau / length|²)``) for
            ``"quantile"`` and ``"worst"``; the resisted fraction (dimensionless, 0–1) for
            ``"disturbances"``.
        unit: ``"N"`` or ``"1"``.
        kind: :data:`ScoreKind`.
        quantile: The quantile used (``0`` for ``"worst"``; ``None`` for ``"disturbances"``).
        definition: The definition in one sentence.
        rset: The :class:`~pinograsp.analysis.resistance_set.ResistanceSet` it was computed from.
        ferrari_canny: :func:`ferrari_canny` of the same contacts with the same ``length``.
        length: Characteristic length [m].
    """

    value: float
    unit: str
    kind: ScoreKind
    quantile: float | None
    definition: str
    rset: ResistanceSet
    ferrari_canny: float
    length: float

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: the score, its definition, ``ferrari_canny`` and the set."""
        return jsonable(
            {
                "value": self.value,
                "unit": self.unit,
                "kind": self.kind,
                "quantile": self.quantile,
                "definition": self.definition,
                "ferrari_canny": self.ferrari_canny,
                "length": self.length,
                "set": self.rset.to_dict(),
            }
        )

    def summary(self) -> str:
        """The score with its definition, the Ferrari–Canny epsilon and the set's summary."""
        res = self.rset.resolution()
        v = f"{self.value:.1%}" if self.unit == "1" else format_magnitude(self.value, res, "N")
        return "\n".join(
            [
                f"passive-resistance score ({self.kind}): {v}",
                f"  {self.definition}",
                f"Ferrari–Canny epsilon {self.ferrari_canny:.4g} (same contacts, length {self.length:.4g} m)",
                self.rset.summary(),
            ]
        )

    def __repr__(self) -> str:
        return (
            f"GraspScore(value={self.value:.4g}, unit={self.unit!r}, kind={self.kind!r}, "
            f"quantile={self.quantile}, ferrari_canny={self.ferrari_canny:.4g}, n={self.rset.n})"
        )


def _resisted_fraction(rset: ResistanceSet, loads: np.ndarray) -> float:
    """Fraction of the loads (k, 6) whose Euclidean norm is at most the limit along their own
    direction (``above_limit``: only up to ``upper``; failed directions: not resisted)."""
    norms = np.linalg.norm(loads, axis=1)
    ok = np.array([s != "failed" for s in rset.statuses])
    limit = np.where(ok, rset.magnitudes, -np.inf)
    return float(np.mean(norms <= limit))


def grasp_score(
    model: GraspModel,
    command: object,
    *,
    n: int = 200,
    quantile: float = 0.05,
    disturbances: object = None,
    method: str = DEFAULT_METHOD,
    length: float | None = None,
    seed: int = 0,
    workers: int | None = None,
    upper: float = 1e3,
    steps: int = 20,
    settings: Any = None,
    **overrides: Any,
) -> GraspScore:
    """Passive-resistance score of a preloaded grasp (``docs/metrics.md``).

    Default: the ``quantile`` (5 %) of the resistible magnitude over ``n`` directions spread
    evenly on the unit wrench sphere, in the scaled norm ``sqrt(|f|² + |tau / length|²)`` [N],
    with unbounded directions counted as the search's upper limit: "95 % of the disturbance
    directions are resisted up to at least this magnitude". ``quantile=0``: the worst direction.
    With ``disturbances`` (a sample of wrenches, (k, 6), planar also (k, 3)): the fraction of
    them that the grasp resists (an expectation under that distribution; the set is computed
    along their directions).

    Args:
        model, command: The grasp and its actuator commands.
        n: Directions on the sphere (ignored with ``disturbances``).
        quantile: In ``[0, 1)``.
        disturbances: Optional sample of disturbance wrenches [N, N·m], (k, 6).
        method, length, seed, workers, upper, steps, settings, overrides: As
            :func:`pinograsp.resistance_set`.
    """
    if isinstance(quantile, bool) or not isinstance(quantile, (int, float, np.floating)):
        raise InvalidInputError("quantile", f"expected a number in [0, 1), got {quantile!r}")
    if not 0.0 <= float(quantile) < 1.0:
        raise InvalidInputError("quantile", f"must be in [0, 1), got {quantile!r}")
    kw: dict[str, Any] = dict(
        method=method, length=length, workers=workers, upper=upper, steps=steps, settings=settings
    )
    if disturbances is not None:
        loads = wrench_rows(model, disturbances, "disturbances")
        if np.any(np.abs(loads).max(axis=1) == 0):
            raise InvalidInputError("disturbances", "contains a zero wrench")
        rset = resistance_set(model, command, directions=loads, **kw, **overrides)
        value, kind, q = _resisted_fraction(rset, loads), "disturbances", None
        definition = f"fraction of the {len(loads)} given disturbance wrenches resisted passively"
    else:
        rset = resistance_set(model, command, n, seed=seed, **kw, **overrides)
        q = float(quantile)
        kind = "worst" if q == 0.0 else "quantile"
        value = rset.quantile(q, capped=True)
        definition = (
            f"{'smallest' if q == 0 else f'{q:.0%} quantile of the'} resistible magnitude "
            f"sqrt(|f|² + |tau/L|²) [N] over {rset.n} directions evenly spread on the unit wrench "
            f"sphere (L = {rset.length:.4g} m), unbounded directions counted as upper"
        )
    return GraspScore(
        value=value,
        unit="1" if kind == "disturbances" else "N",
        kind=kind,  # type: ignore[arg-type]
        quantile=q,
        definition=definition,
        rset=rset,
        ferrari_canny=ferrari_canny(model, rset.length),
        length=rset.length,
    )
