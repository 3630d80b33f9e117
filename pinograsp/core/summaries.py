"""Short human-readable text of result records: ``summary()`` texts and compact ``repr`` strings
that never dump arrays (``docs/results_api.md``).

NumPy and the standard library only; the records are duck-typed, as in
:mod:`pinograsp.core.serialize`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .axes import direction_text, wrench_unit
from .serialize import (
    absolute_magnitudes,
    format_magnitude,
    format_max_wrench,
    runs_text,
    unbounded_runs,
    vector_text,
)

EnergyCheck = Audit = MaxWrench = PassiveResponse = ResistanceProfile = LinearComplianceResult = Any


def contact_report_summary(r: Any) -> str:
    """The contacts found (link, signed distance [mm]) and the closest links without contact."""
    lines = [f"{len(r.contacts)} contact(s) within {r.tolerance * 1e3:g} mm:"]
    lines += [f"  {c.link} ({c.geometry}): {c.distance * 1e3:+.3f} mm" for c in r.contacts]
    touching = set(r.links)
    others = sorted((d, k) for k, d in r.link_distances.items() if k not in touching)
    if others:
        lines.append("closest other links: " + ", ".join(f"{k} {d * 1e3:.3g} mm" for d, k in others[:3]))
    return "\n".join(lines)


# ---------------------------------------------------------------------------- summaries
def _status_counts(p: ResistanceProfile) -> dict[str, int]:
    counts = {"finite": 0, "unbounded": 0, "above_limit": 0, "below_resolution": 0}
    if len(p.results) == len(p.magnitudes):
        for r in p.results:
            counts[r.status] = counts.get(r.status, 0) + 1
    else:
        counts["unbounded"] = int(np.sum(p.unbounded))
        counts["finite"] = len(p.magnitudes) - counts["unbounded"]
    return counts


def energy_summary(e: EnergyCheck) -> str:
    """One line: the energy balance [J] and the displacement ratio, with their verdicts."""
    supplied = e.load_work + e.actuator_work
    rel = "<=" if e.energy_ok else "> (WEDGING)"
    text = f"spring energy {e.spring_energy:.4g} J {rel} supplied {supplied:.4g} J"
    if not e.energy_ok and e.contacts:
        text += f" at {', '.join(e.contacts)}"
    ok = "ok" if e.displacement_ok else "ABSURD"
    return text + f"; displacements {e.displacement_ratio:.3g}x the spring compressions ({ok})"


def audit_summary(a: Audit) -> str:
    """Audit verdict and residuals [N] (one or two lines)."""
    text = (
        f"audit: {'ok' if a.ok else 'NOT OK'} (equilibrium {a.equilibrium:.2e} N, hand {a.hand:.2e} N, "
        f"complementarity {a.complementarity:.2e} N, friction {a.friction:.2e} N, "
        f"big-M use {a.bigm_ratio:.1%})"
    )
    if a.pull > a.tolerance:
        text += f"\n  a contact PULLS with {a.pull:.3g} N (contacts only push): the numbers cannot be trusted"
    if not a.finite:
        text += "\n  non-finite numbers (overflow): the solution cannot be trusted"
    return text if a.energy is None else text + "\n  " + energy_summary(a.energy)


def _forces_text(r: PassiveResponse) -> str:
    res = r.audit.tolerance if r.audit is not None else 1e-6
    cn = r.contact_forces[:, 0] if len(r.contact_forces) else np.zeros(0)
    return ", ".join(f"{nm} {format_magnitude(f, res, 'N')}" for nm, f in zip(r.contact_names, cn)) or "none"


def _states_text(r: PassiveResponse) -> str:
    """``left sliding (slip direction (0.342, -0.9397, 0)), right sticking`` — the state of each
    contact and the unit slip direction (world frame) of the sliding ones; ``""`` when the
    response reports no states."""
    states = tuple(getattr(r, "contact_states", ()) or ())
    if not states or len(states) != len(r.contact_names):
        return ""
    slip = getattr(r, "contact_slip", None)
    slip = None if slip is None else np.asarray(slip, dtype=float).reshape(len(states), -1)
    parts = []
    for i, (name, state) in enumerate(zip(r.contact_names, states)):
        text = f"{name} {state}"
        norm = 0.0 if slip is None else float(np.linalg.norm(slip[i]))
        if state == "sliding" and np.isfinite(norm) and norm > 0.0:
            text += f" (slip direction {vector_text(slip[i] / norm)})"
        parts.append(text)
    return ", ".join(parts)


def response_summary(r: PassiveResponse) -> str:
    """Status, wrench, normal contact forces [N], contact states (with the slip direction of
    sliding contacts) when reported, actuator modes and the audit verdict."""
    lines = [
        f"passive response ({r.method}, {r.variant}): {'RESISTED' if r.resistible else 'NOT RESISTED'}"
        f" (status {r.status}; {r.iterations} iteration(s), {r.n_solves} solve(s), {r.solve_time:.3g} s)",
        f"wrench {vector_text(r.wrench)} [N, N·m] (fx, fy, fz, mx, my, mz)",
    ]
    if r.resistible:
        lines.append(f"normal contact forces: {_forces_text(r)}")
        if states := _states_text(r):
            lines.append(f"contact states: {states}")
        acts = [f"{nm} {md}" for nm, md in zip(r.actuator_names, r.actuator_modes)]
        if acts:
            lines.append("actuators: " + ", ".join(acts))
    else:
        lines.append(f"net wrench |w + G c|: {np.linalg.norm(r.net_wrench):.3e}")
    if r.audit is not None:
        lines.append(audit_summary(r.audit))
    return "\n".join(lines)


def max_wrench_summary(mw: MaxWrench, label: str | None = None) -> str:
    """Status and magnitude to the resolution, with unit, search record, limiting forces and
    contact states."""
    unit = wrench_unit(mw.direction)
    label = label or direction_text(mw.direction)
    head = f"max resistible wrench along {label}: {format_max_wrench(mw, unit=unit)} ({mw.status}"
    if mw.status == "finite":
        head += f", resolution {mw.resolution:.2g} {unit}"
    elif mw.status == "above_limit":
        head += f": the upper limit {mw.upper:g} {unit} is resisted"
    lines = [
        head + ")",
        f"method {mw.method}, {mw.search}: {len(mw.evidence)} magnitudes tried, monotone "
        f"{'yes' if mw.monotone else 'NO'}; {mw.n_solves} solves, {mw.wall_time:.3g} s",
    ]
    if mw.response is not None and mw.response.resistible:
        at = "at the upper limit" if mw.unbounded else "at the limit"
        lines.append(f"normal contact forces {at}: {_forces_text(mw.response)}")
        if states := _states_text(mw.response):
            lines.append(f"contact states {at}: {states}")
    if mw.audit_failures:
        lines.append(f"audit failures at {', '.join(f'{m:.6g}' for m in mw.audit_failures)}")
    return "\n".join(lines)


def profile_summary(p: ResistanceProfile) -> str:
    """Plane, counts per status, finite range to the resolution, unbounded runs, timing."""
    n = len(p.angles)
    unit = wrench_unit(p.basis[0] + p.basis[1]) if len(p.basis) == 2 else ""
    method = p.results[0].method if p.results else "?"
    counts = _status_counts(p)
    mags = absolute_magnitudes(p)
    res = max((r.resolution for r in p.results), default=float("nan"))
    fin = np.array([r.status == "finite" for r in p.results], bool) if p.results else ~p.unbounded
    b1, b2 = (direction_text(b) for b in p.basis)
    lines = [
        f"resistance profile in the plane ({b1}, {b2}): {n} directions, method {method}",
        ", ".join(f"{k} {v}" for k, v in counts.items() if v or k in ("finite", "unbounded")),
    ]
    if fin.any():
        lo, hi = float(mags[fin].min()), float(mags[fin].max())
        lines.append(
            f"finite magnitudes {format_magnitude(lo, res)}–{format_magnitude(hi, res, unit)} "
            f"(resolution {res:.2g} {unit})"
        )
    lines.append("unbounded at " + runs_text(unbounded_runs(np.degrees(p.angles), p.unbounded)))
    if p.normalized_by is not None:
        lines.append(f"normalised by {p.normalized_by:.4g} {unit}")
    solves = sum(r.n_solves for r in p.results)
    lines.append(f"{solves} solves, {p.wall_time:.3g} s")
    return "\n".join(lines)


def linear_compliance_summary(r: LinearComplianceResult) -> str:
    """Validity, violations and the normal forces [N] of the linear-compliance baseline."""
    names = r.contact_names or tuple(f"#{i}" for i in range(len(r.contact_forces)))
    lines = [
        f"linear compliance: {'valid' if r.valid else 'INVALID'}"
        f" (pulls: {', '.join(r.push_violations) or 'none'};"
        f" outside the friction cone: {', '.join(r.friction_violations) or 'none'})",
        "normal contact forces: "
        + ", ".join(f"{nm} {format_magnitude(f, 1e-6, 'N')}" for nm, f in zip(names, r.contact_forces[:, 0])),
        "|c_t| / mu c_n: " + ", ".join(f"{nm} {x:.3g}" for nm, x in zip(names, r.friction_ratio)),
    ]
    return "\n".join(lines)


# ---------------------------------------------------------------------------- compact repr
def _num(x: float) -> str:
    return f"{float(x):.4g}"


def response_repr(r: PassiveResponse) -> str:
    """``PassiveResponse(status=..., method=..., wrench=(...), normal_forces=(...), ...)``."""
    cn = r.contact_forces[:, 0] if len(r.contact_forces) else np.zeros(0)
    ok = None if r.audit is None else r.audit.ok
    return (
        f"PassiveResponse(status={r.status!r}, resistible={r.resistible}, method={r.method!r}, "
        f"variant={r.variant!r}, wrench={vector_text(r.wrench)}, normal_forces={vector_text(cn)}, "
        f"nc={len(r.contact_names)}, audit_ok={ok}, iterations={r.iterations}, n_solves={r.n_solves})"
    )


def max_wrench_repr(mw: MaxWrench) -> str:
    """``MaxWrench(direction='+fy', magnitude=9.96, status='finite', ...)``."""
    return (
        f"MaxWrench(direction={direction_text(mw.direction)!r}, magnitude={_num(mw.magnitude)}, "
        f"status={mw.status!r}, resolution={mw.resolution:.3g}, upper={mw.upper:g}, "
        f"method={mw.method!r}, search={mw.search!r}, n_solves={mw.n_solves}, "
        f"audit_failures={len(mw.audit_failures)})"
    )


def profile_repr(p: ResistanceProfile) -> str:
    """``ResistanceProfile(plane=('fx', 'fy'), n=72, method='iterative', finite=..., ...)``."""
    counts = _status_counts(p)
    method = p.results[0].method if p.results else None
    if len(p.results) == len(p.magnitudes):
        fin = np.array([r.status == "finite" for r in p.results], bool)
    else:
        fin = ~np.asarray(p.unbounded, bool) & np.isfinite(p.magnitudes)
    rng = f"({_num(np.min(p.magnitudes[fin]))}, {_num(np.max(p.magnitudes[fin]))})" if fin.any() else "None"
    norm = None if p.normalized_by is None else _num(p.normalized_by)
    return (
        f"ResistanceProfile(plane={tuple(p.plane)!r}, n={len(p.angles)}, method={method!r}, "
        + ", ".join(f"{k}={v}" for k, v in counts.items())
        + f", range={rng}, normalized_by={norm}, wall_time={p.wall_time:.3g})"
    )
