"""One home for turning results into plain data and text (``docs/results_api.md``).

* :func:`jsonable` — NumPy arrays and scalars to lists and numbers, ``inf``/``nan`` to ``None``.
* ``*_dict`` — each result record as JSON-ready data: the schema of the command line's JSON
  (``docs/cli.md``); the records' ``to_dict()`` methods and ``pinograsp`` CLI call these.
* :func:`format_magnitude`, :func:`format_max_wrench` — a value printed to its resolution.
* ``*_summary`` / ``*_repr`` live in :mod:`pinograsp.core.summaries`: short text
  (``summary()``) and compact ``repr`` strings that never dump arrays.

NumPy and the standard library only; the records are duck-typed (no import of
:mod:`pinograsp.core.results`, which imports this module).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InvalidInputError
from .axes import direction_text, wrench_unit

# The records are read by their attributes: this module sits below results.py, audit.py and
# baseline.py (whose methods call it), so it names their types without importing them.
EnergyCheck = Audit = MaxWrench = PassiveResponse = ResistanceProfile = LinearComplianceResult = Any

#: Attributes that make a record a :class:`~pinograsp.core.results.MaxWrench` here.
MAX_WRENCH_FIELDS = ("direction", "magnitude", "status", "resolution", "upper", "floor", "evidence")
#: Attributes that make a record a :class:`~pinograsp.core.results.ResistanceProfile` here.
PROFILE_FIELDS = ("plane", "angles", "directions", "magnitudes", "unbounded", "results")


def is_record(x: object, fields: tuple[str, ...]) -> bool:
    """Whether ``x`` has every attribute in ``fields`` (a result record of that kind)."""
    return all(hasattr(x, f) for f in fields)


# ---------------------------------------------------------------------------- plain data
def jsonable(x: Any) -> Any:
    """``x`` as plain JSON-ready Python: NumPy arrays and scalars become lists, floats, ints and
    bools; tuples become lists; dict keys strings; ``inf`` and ``nan`` become ``None``; paths
    strings. Other objects are returned unchanged."""
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        v = float(x)
        return v if math.isfinite(v) else None
    if isinstance(x, Path):
        return str(x)
    return x


# ---------------------------------------------------------------------------- text of values
def decimals(resolution: float) -> int:
    """Decimals that show a value to its resolution: ``ceil(-log10(resolution))`` clipped to
    0–6 (4 when the resolution is not a positive number)."""
    if not resolution > 0 or not math.isfinite(resolution):
        return 4
    return int(min(6, max(0, math.ceil(-math.log10(resolution)))))


def _real(name: str, value: object) -> float:
    """``float(value)`` for a real number (``inf`` and ``nan`` accepted), else InvalidInputError."""
    if isinstance(value, (str, bytes, bool)):
        raise InvalidInputError(name, f"expected a number, got {value!r}")
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(name, f"expected a number, got {value!r}") from None


def format_magnitude(value: float, resolution: float, unit: str | None = None) -> str:
    """A magnitude printed to its resolution.

    Args:
        value: The magnitude [N or N·m]; ``inf`` prints as ``"unbounded"``, ``nan`` as ``"nan"``.
        resolution: Its resolution [same unit] (e.g. the bisection's ``upper / 2**steps``).
        unit: Appended after a space when given.

    Examples: ``format_magnitude(1.3672, 0.2, "N")`` is ``"1.4 N"``,
    ``format_magnitude(4.29893, 4.8e-06, "N")`` is ``"4.298930 N"`` (at most 6 decimals).
    """
    v = _real("value", value)
    resolution = _real("resolution", resolution)
    if unit is not None and not isinstance(unit, str):
        raise InvalidInputError("unit", f"expected a string or None, got {unit!r}")
    if math.isinf(v):
        text = "unbounded" if v > 0 else "-unbounded"
    elif math.isnan(v):
        text = "nan"
    else:
        text = f"{v:.{decimals(resolution)}f}"
    return f"{text} {unit}" if unit and not math.isinf(v) else text


def format_max_wrench(mw: MaxWrench, scale: float = 1.0, unit: str | None = None) -> str:
    """A :class:`~pinograsp.core.results.MaxWrench` magnitude as text, by its status: ``unbounded``,
    ``>= upper``, ``< floor`` or the magnitude to its resolution, all divided by ``scale``
    (e.g. a normalisation reference), followed by ``unit`` when given."""
    if not is_record(mw, MAX_WRENCH_FIELDS):
        raise InvalidInputError("mw", f"expected a MaxWrench, got {type(mw).__name__}")
    scale = _real("scale", scale)
    if not (math.isfinite(scale) and scale > 0):
        raise InvalidInputError("scale", f"must be finite and > 0, got {scale!r}")
    if mw.status == "unbounded":
        return "unbounded"
    if mw.status == "above_limit":
        text = f">= {mw.upper / scale:.4g}"
    elif mw.status == "below_resolution":
        text = f"< {mw.floor / scale:.2g}"
    else:
        return format_magnitude(mw.magnitude / scale, mw.resolution / scale, unit)
    return f"{text} {unit}" if unit else text


def vector_text(v: Sequence[float] | np.ndarray) -> str:
    """A vector as ``(0, 5, 0)`` with 4 significant digits (values below 1e-9 of the largest: 0)."""
    a = np.asarray(v, dtype=float)
    tiny = 1e-9 * max(1.0, float(np.abs(a).max(initial=0.0)))
    return "(" + ", ".join(f"{0.0 if abs(x) < tiny else x:.4g}" for x in a) + ")"


def unbounded_runs(angles_deg: np.ndarray, unbounded: np.ndarray) -> list[tuple[float, float]]:
    """Circular runs of unbounded directions of a profile as ``(first, last)`` angles [deg].

    Args:
        angles_deg: Direction angles [deg], (n,), ascending around the circle.
        unbounded: (n,) bool.
    """
    u = np.asarray(unbounded, bool)
    n = len(u)
    if n == 0 or not u.any():
        return []
    if u.all():
        return [(float(angles_deg[0]), float(angles_deg[-1]))]
    start = int(np.flatnonzero(~u)[0]) + 1  # begin right after a bounded direction
    runs, cur = [], None
    for k in range(n):
        i = (start + k) % n
        if u[i]:
            cur = (i, i) if cur is None else (cur[0], i)
        elif cur is not None:
            runs.append(cur)
            cur = None
    if cur is not None:
        runs.append(cur)
    return sorted((float(angles_deg[a]), float(angles_deg[b])) for a, b in runs)


def runs_text(runs: Sequence[tuple[float, float]]) -> str:
    """Runs of :func:`unbounded_runs` as ``"0°, 170°–190°"`` (``"none"`` when empty)."""
    if not runs:
        return "none"
    return ", ".join(f"{a:g}°" if a == b else f"{a:g}°–{b:g}°" for a, b in runs)


# ---------------------------------------------------------------------------- record -> dict
def energy_dict(e: EnergyCheck) -> dict[str, Any]:
    """An :class:`~pinograsp.core.audit.EnergyCheck` as plain data (energies [J])."""
    return jsonable(
        {
            "spring_energy": e.spring_energy,
            "load_work": e.load_work,
            "actuator_work": e.actuator_work,
            "energy_ok": e.energy_ok,
            "displacement_ratio": e.displacement_ratio,
            "displacement_ok": e.displacement_ok,
            "contacts": list(e.contacts),
        }
    )


def audit_dict(a: Audit) -> dict[str, Any]:
    """An :class:`~pinograsp.core.results.Audit` as plain data (residuals [N])."""
    return jsonable(
        {
            "ok": a.ok,
            "equilibrium": a.equilibrium,
            "hand": a.hand,
            "complementarity": a.complementarity,
            "friction": a.friction,
            "bigm_ratio": a.bigm_ratio,
            "bigm_retries": a.bigm_retries,
            "polished": a.polished,
            "tolerance": a.tolerance,
            "pull": a.pull,
            "finite": a.finite,
            "energy": None if a.energy is None else energy_dict(a.energy),
        }
    )


def _labels(r: PassiveResponse, model: Any, names: str, values: str, model_values: str) -> list[Any]:
    """Per-row model data (``mu`` per contact, ``kind`` per actuator) by name: the record's own
    (what was analysed: a normal uncertainty reduces ``mu``), else from ``model`` when given
    (``None`` where unknown)."""
    rows = getattr(r, names)
    own = getattr(r, values, None)
    if own is not None and len(own) == len(rows):
        return list(own)
    if model is not None:
        table = dict(zip(getattr(model, names), getattr(model, model_values)))
        return [table.get(nm) for nm in rows]
    return [None] * len(rows)


def response_dict(r: PassiveResponse, model: Any = None) -> dict[str, Any]:
    """A :class:`~pinograsp.core.results.PassiveResponse` as plain data (the ``analyze`` JSON).

    Args:
        r: The response.
        model: Optional :class:`~pinograsp.GraspModel` to take each contact's ``mu`` and each
            actuator's ``kind`` from (default: the record's own ``contact_mu``/``actuator_kinds``).
    """
    mus = _labels(r, model, "contact_names", "contact_mu", "mu")
    kinds = _labels(r, model, "actuator_names", "actuator_kinds", "kinds")
    fu = r.friction_use
    contacts = [
        {
            "name": name,
            "mode": r.contact_modes[i] if i < len(r.contact_modes) else None,
            "mu": mus[i],
            "force": r.contact_forces[i],
            "force_world": r.contact_forces_world[i],
            "friction_use": None if fu is None or np.isnan(fu[i]) else float(fu[i]),
            "state": r.contact_states[i] if i < len(r.contact_states) else None,
            "slip": None if r.contact_slip is None else r.contact_slip[i],
            "edges": r.edge_counts[i] if i < len(r.edge_counts) else None,
        }
        for i, name in enumerate(r.contact_names)
    ]
    actuators = [
        {
            "name": name,
            "kind": kinds[i],
            "command": r.command[i],
            "force": r.actuator_forces[i],
            "mode": r.actuator_modes[i] if i < len(r.actuator_modes) else None,
            "displacement": r.actuator_displacements[i],
        }
        for i, name in enumerate(r.actuator_names)
    ]
    joints = [
        {"name": name, "torque": r.joint_torques[i], "displacement": r.joint_displacements[i]}
        for i, name in enumerate(r.joint_names)
    ]
    return jsonable(
        {
            "resistible": r.resistible,
            "status": r.status,
            "method": r.method,
            "variant": r.variant,
            "wrench": r.wrench,
            "contacts": contacts,
            "actuators": actuators,
            "joints": joints,
            "coupling_forces": r.coupling_forces,
            "object_displacement": r.object_displacement,
            "net_wrench": r.net_wrench,
            "audit": None if r.audit is None else audit_dict(r.audit),
            "iterations": r.iterations,
            "residual_history": list(r.residual_history),
            "solver": r.solver,
            "solve_time": r.solve_time,
            "n_solves": r.n_solves,
        }
    )


def max_wrench_dict(
    mw: MaxWrench, label: str | None = None, *, response: bool = True, model: Any = None
) -> dict[str, Any]:
    """A :class:`~pinograsp.core.results.MaxWrench` as plain data (the ``max-wrench`` JSON).

    Args:
        mw: The result.
        label: Direction label (default :func:`direction_text` of the direction).
        response: Include ``"response"`` (the passive response at the limit, or ``None``).
        model: Passed to :func:`response_dict`.
    """
    out = {
        "direction": mw.direction,
        "label": label or direction_text(mw.direction),
        "magnitude": None if mw.unbounded else mw.magnitude,
        "unbounded": mw.unbounded,
        "status": mw.status,
        "unit": wrench_unit(mw.direction),
        "upper": mw.upper,
        "resolution": mw.resolution,
        "method": mw.method,
        "monotone": mw.monotone,
        "audit_failures": [None if np.isinf(m) else m for m in mw.audit_failures],
        "evidence": [[m, ok] for m, ok in mw.evidence],
        "n_solves": mw.n_solves,
        "solve_time": mw.solve_time,
        "wall_time": mw.wall_time,
    }
    if response:
        out["response"] = None if mw.response is None else response_dict(mw.response, model)
    return jsonable(out)


def absolute_magnitudes(p: ResistanceProfile) -> np.ndarray:
    """A profile's magnitudes before any normalisation, (n,) [N or N·m] (``inf``: unbounded)."""
    if len(p.results) == len(p.magnitudes):
        return np.array([r.magnitude for r in p.results], dtype=float)
    m = np.asarray(p.magnitudes, dtype=float)
    return m * p.normalized_by if p.normalized_by else m


def profile_dict(
    p: ResistanceProfile, normalized_by: float | None = None, *, results: bool = False
) -> dict[str, Any]:
    """A :class:`~pinograsp.core.results.ResistanceProfile` as plain data (the ``profile`` JSON).

    Args:
        p: The profile.
        normalized_by: Reference magnitude [N or N·m] for ``"normalized"`` (default: the
            profile's own ``normalized_by``; ``None`` for both: not normalised).
        results: Add ``"results"``, the per-direction :func:`max_wrench_dict` without responses.

    ``"magnitudes"`` are always absolute (``None`` where unbounded).
    """
    ref = normalized_by if normalized_by is not None else p.normalized_by
    mags = absolute_magnitudes(p)
    deg = np.degrees(p.angles)
    out = {
        "plane": list(p.plane),
        "basis": p.basis,
        "n": len(p.angles),
        "angles_deg": deg,
        "directions": p.directions,
        "magnitudes": mags,
        "unbounded": p.unbounded,
        "monotone": [r.monotone for r in p.results],
        "n_solves": [r.n_solves for r in p.results],
        "normalized_by": ref,
        "normalized": None if ref is None else mags / ref,
        "wall_time": p.wall_time,
        "unbounded_runs_deg": unbounded_runs(deg, p.unbounded),
    }
    if results:
        out["results"] = [max_wrench_dict(r, response=False) for r in p.results]
    return jsonable(out)


def linear_compliance_dict(r: LinearComplianceResult) -> dict[str, Any]:
    """A :class:`~pinograsp.analysis.baseline.LinearComplianceResult` as plain data (forces [N];
    ``friction_ratio`` ``None`` where infinite)."""
    return jsonable(
        {
            "valid": r.valid,
            "contact_names": list(r.contact_names),
            "contact_forces": r.contact_forces,
            "contact_forces_world": r.contact_forces_world,
            "particular": r.particular,
            "internal": r.internal,
            "object_displacement": r.object_displacement,
            "push_violations": list(r.push_violations),
            "friction_violations": list(r.friction_violations),
            "friction_ratio": r.friction_ratio,
        }
    )


def pair_distance_dict(d: Any) -> dict[str, Any]:
    """A :class:`~pinograsp.robots.collision.PairDistance` as plain data (lengths [m])."""
    return jsonable(
        {
            "link": d.link,
            "geometry": d.geometry,
            "index": d.index,
            "distance": d.distance,
            "point": d.point,
            "point_hand": d.point_hand,
            "point_object": d.point_object,
            "normal": d.normal,
        }
    )


def contact_report_dict(r: Any) -> dict[str, Any]:
    """A :class:`~pinograsp.robots.collision.ContactReport` as plain data (lengths [m])."""
    return jsonable(
        {
            "tolerance": r.tolerance,
            "links": list(r.links),
            "contacts": [pair_distance_dict(c) for c in r.contacts],
            "pairs": [pair_distance_dict(c) for c in r.pairs],
            "link_distances": dict(r.link_distances),
        }
    )
