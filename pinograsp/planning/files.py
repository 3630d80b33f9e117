"""Plans as a GRASPS.yaml (docs/batch.md): ``pinograsp batch`` re-scores them to the same numbers.

Each plan is one explicit grasp (its object pose, closed configuration ``q`` and preload
command), and the file's ``score`` block names the planner's
:class:`~pinograsp.batch.disturbances.DisturbanceScore` options. Floats are written with their
shortest round-trip representation, so the file holds the plans bit for bit.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from ..batch.grasps import GraspSpec
from .records import GraspPlans

#: GraspSpec fields written only when they differ from these defaults.
_DEFAULTS = {
    f: GraspSpec.__dataclass_fields__[f].default for f in ("description", "tolerance", "max_penetration")
}


def _object(spec: GraspSpec) -> dict[str, Any]:
    o = spec.object
    out: dict[str, Any] = {"shape": o.shape}
    for key in ("size", "radius", "length"):
        if getattr(o, key) is not None:
            v = getattr(o, key)
            out[key] = list(v) if isinstance(v, tuple) else v
    if o.file is not None:
        out.update(file=str(Path(o.file).resolve()), scale=o.scale)
        if o.convex is not None:
            out["convex"] = o.convex
    out["pose"] = {"xyz": list(o.xyz), "rpy": list(o.rpy)}
    if o.name is not None:
        out["name"] = o.name
    return out


def grasp_entry(spec: GraspSpec) -> dict[str, Any]:
    """One plan as a GRASPS.yaml grasp (plain data)."""
    d = spec.to_dict()
    hand = d["hand"]
    out: dict[str, Any] = {"id": d["id"], "hand": str(Path(hand).resolve()) if os.sep in hand else hand}
    out["object"] = _object(spec)
    for key in ("q", "command", "mu", "stiffness", "step", "max_steps", "max_command", "preload_method"):
        out[key] = d[key]
    out["preload_method"] = str(getattr(spec.preload_method, "value", spec.preload_method))
    if d["q_open"] is not None:
        out["q_open"] = d["q_open"]
    for key, default in _DEFAULTS.items():
        if d[key] != default:
            out[key] = str(Path(d[key]).resolve()) if key == "description" else d[key]
    if d["package_dirs"]:
        out["package_dirs"] = [str(Path(p).resolve()) for p in d["package_dirs"]]
    return out


def write_grasps(plans: GraspPlans, path: str | os.PathLike[str]) -> Path:
    """Write the plans as a GRASPS.yaml (``score`` block: the planner's score) and return the path."""
    import yaml

    doc = {"score": dict(plans.score_options), "grasps": [grasp_entry(p.spec) for p in plans.plans]}
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    header = f"# {len(plans.plans)} grasp plans of {plans.hand}: pinograsp batch {p.name} re-scores them\n"
    p.write_text(header + yaml.safe_dump(doc, sort_keys=False))
    return p
