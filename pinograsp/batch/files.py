"""GRASPS.yaml: a batch of grasps in one file (schema: ``docs/batch.md``).

``load_grasps(path)`` validates the file and returns a :class:`GraspBatch`: the grasp records
(:class:`~pinograsp.batch.grasps.GraspSpec` and scene references, in file order, sampled grasps
last) and the default score's options. Every error is a :class:`~pinograsp.errors.SceneError`
naming the file and the key path (``grasps.yaml: grasps[2].object.size[1]: must be > 0``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..core.methods import bounded as limits_bound
from ..core.methods import method_name, method_names
from ..core.settings import DEFAULT_METHOD
from ..core.validate import force
from ..core.validate import steps as n_steps
from ..errors import PinograspError
from ..scenes.loading import SceneFile, read_yaml
from .disturbances import disturbance_set, gravity_of
from .grasps import SHAPES, GraspSpec, ObjectSpec, sample_grasps

#: Keys of one grasp (and of ``defaults``).
GRASP_KEYS = (
    "id",
    "hand",
    "description",
    "package_dirs",
    "object",
    "q",
    "q_open",
    "step",
    "tolerance",
    "max_penetration",
    "max_steps",
    "mu",
    "stiffness",
    "patches",
    "edges",
    "command",
    "max_command",
    "preload_method",
)
#: Extra keys of a ``sample`` entry.
SAMPLE_KEYS = ("n", "seed", "translation", "rotation", "include_nominal")
#: Keys of the ``score`` block (options of :class:`~pinograsp.batch.evaluate.WorstAxisScore`;
#: with ``disturbances``, of :class:`~pinograsp.batch.disturbances.DisturbanceScore`).
SCORE_KEYS = ("upper", "steps", "method", "disturbances")
_TOP_KEYS = ("defaults", "grasps", "sample", "score")


@dataclass(frozen=True)
class GraspBatch:
    """A loaded GRASPS.yaml.

    Attributes:
        path: The file.
        grasps: Records for :func:`pinograsp.evaluate_grasps` (``GraspSpec`` or
            ``{"scene": path_or_name, "id": ...}``), in file order, then the sampled ones.
        score: Options of the default score (``upper``, ``steps``, ``method``).
    """

    path: Path
    grasps: tuple[Any, ...]
    score: dict[str, Any]


def _object(f: SceneFile, value: object, key: str) -> ObjectSpec:
    s = f.mapping(value, key)
    shape = f.string(f.require(s, "shape", key), f"{key}.shape")
    if shape not in SHAPES:
        raise f.error(f"{key}.shape", f"unknown shape {shape!r}; valid shapes: {', '.join(SHAPES)}")
    extra = {"box": ("size",), "sphere": ("radius",), "cylinder": ("radius", "length")}
    f.keys(s, ("shape", "pose", "name", *extra.get(shape, ("file", "scale", "convex"))), key)
    kw: dict[str, Any] = {"shape": shape}
    if shape == "box":
        kw["size"] = tuple(f.vector(f.require(s, "size", key), 3, f"{key}.size"))
    for k in extra.get(shape, ()):
        if k != "size":
            kw[k] = f.number(f.require(s, k, key), f"{key}.{k}", positive=True)
    if shape == "mesh":
        kw["file"] = str(f.relpath(f.require(s, "file", key), f"{key}.file"))
        kw["scale"] = f.number(s.get("scale", 1.0), f"{key}.scale", positive=True)
        kw["convex"] = None if s.get("convex") is None else f.boolean(s["convex"], f"{key}.convex")
    pose = f.mapping(s.get("pose") or {}, f"{key}.pose", "a mapping with 'xyz' and/or 'rpy'")
    f.keys(pose, ("xyz", "rpy"), f"{key}.pose")
    if "xyz" in pose:
        kw["xyz"] = tuple(f.vector(pose["xyz"], 3, f"{key}.pose.xyz"))
    if "rpy" in pose:
        kw["rpy"] = tuple(f.vector(pose["rpy"], 3, f"{key}.pose.rpy", angle=True))
    if "name" in s:
        kw["name"] = f.string(s["name"], f"{key}.name")
    try:
        return ObjectSpec(**kw)
    except PinograspError as exc:
        raise f.error(f"{key}.{getattr(exc, 'name', '')}".rstrip("."), str(exc).split(": ", 1)[-1]) from exc


def _values(f: SceneFile, value: object, key: str) -> dict[str, float] | list[float]:
    """``{joint: value}`` (angles may be 'N deg') or a list of values."""
    if isinstance(value, Mapping):
        return {str(k): f.number(v, f"{key}.{k}", angle=True) for k, v in value.items()}
    if not isinstance(value, list):
        raise f.error(key, "expected a mapping joint -> value or a list of values [rad or m]")
    return [f.number(v, f"{key}[{i}]", angle=True) for i, v in enumerate(value)]


def _hand_path(f: SceneFile, value: str) -> str:
    """A built-in name stays; anything that looks like a file is resolved against the file's folder."""
    if "/" in value or "\\" in value or value.endswith(".urdf"):
        return str(f.relpath(value, "hand"))
    return value


def _grasp_fields(f: SceneFile, g: Mapping, key: str) -> dict[str, Any]:
    kw: dict[str, Any] = {}
    for k, v in g.items():
        kk = f"{key}.{k}" if key else str(k)
        if k == "id":
            kw[k] = str(v)
        elif k == "hand":
            kw[k] = _hand_path(f, f.string(v, kk))
        elif k == "description":
            kw[k] = str(f.relpath(v, kk))
        elif k == "package_dirs":
            kw[k] = tuple(str(f.relpath(d, f"{kk}[{i}]")) for i, d in enumerate(f.names(v, kk)))
        elif k == "object":
            kw[k] = _object(f, v, kk)
        elif k in ("q", "q_open"):
            kw[k] = _values(f, v, kk)
            if k == "q_open" and not isinstance(v, Mapping):
                raise f.error(kk, "expected a mapping joint -> value [rad or m]")
        elif k in ("step", "stiffness", "max_command", "tolerance"):
            kw[k] = f.number(v, kk, positive=True)
        elif k == "max_penetration":
            kw[k] = f.number(v, kk, nonneg=True)
        elif k in ("max_steps", "edges"):
            kw[k] = f.integer(v, kk)
        elif k == "patches":
            kw[k] = f.boolean(v, kk)
        elif k == "mu":
            kw[k] = f.number(v, kk, nonneg=True)
        elif k == "command":
            if isinstance(v, Mapping):
                kw[k] = {str(a): f.number(x, f"{kk}.{a}") for a, x in v.items()}
            else:
                kw[k] = v if v == "auto" else f.number(v, kk)
        elif k == "preload_method":
            kw[k] = f.string(v, kk)
    return kw


def _spec(f: SceneFile, fields: dict[str, Any], key: str) -> GraspSpec:
    for need in ("hand", "object"):
        if need not in fields:
            raise f.error(f"{key}.{need}", "missing required key (here or in 'defaults')")
    try:
        return GraspSpec(**fields)
    except PinograspError as exc:
        raise f.error(f"{key}.{getattr(exc, 'name', '')}".rstrip("."), str(exc).split(": ", 1)[-1]) from exc


def _samples(f: SceneFile, value: object, defaults: dict[str, Any]) -> list[GraspSpec]:
    if not isinstance(value, list):
        raise f.error("sample", "expected a list of sample blocks")
    out: list[GraspSpec] = []
    for i, s in enumerate(value):
        key = f"sample[{i}]"
        s = f.mapping(s, key)
        f.keys(s, tuple(k for k in GRASP_KEYS if k != "id") + SAMPLE_KEYS, key)
        fields = {**defaults, **_grasp_fields(f, {k: v for k, v in s.items() if k in GRASP_KEYS}, key)}
        n = f.integer(f.require(s, "n", key), f"{key}.n")
        seed = f.integer(s.get("seed", 0), f"{key}.seed", minimum=0)
        kw: dict[str, Any] = {}
        if "translation" in s:
            t = s["translation"]
            kw["translation"] = (
                tuple(f.vector(t, 3, f"{key}.translation"))
                if isinstance(t, list)
                else f.number(t, f"{key}.translation", nonneg=True)
            )
        if "rotation" in s:
            kw["rotation"] = f.number(s["rotation"], f"{key}.rotation", nonneg=True, angle=True)
        if "include_nominal" in s:
            kw["include_nominal"] = f.boolean(s["include_nominal"], f"{key}.include_nominal")
        spec = _spec(f, fields, key)
        fields.pop("id", None)
        hand, obj = fields.pop("hand"), spec.object
        fields.pop("object")
        try:
            out += sample_grasps(hand, obj, n, seed, **kw, **fields)
        except PinograspError as exc:
            raise f.error(
                f"{key}.{getattr(exc, 'name', '')}".rstrip("."), str(exc).split(": ", 1)[-1]
            ) from exc
    return out


def load_grasps(path: str | Path) -> GraspBatch:
    """Read and validate a GRASPS.yaml (schema: ``docs/batch.md``).

    Raises:
        SceneError: The file is missing or malformed (the message names the file and key).
    """
    p = Path(path)
    f = SceneFile(p)
    data = read_yaml(p)
    f.keys(data, _TOP_KEYS, "")
    d = f.mapping(data.get("defaults") or {}, "defaults")
    f.keys(d, tuple(k for k in GRASP_KEYS if k != "id"), "defaults")
    defaults = _grasp_fields(f, d, "defaults")
    score = _score(f, data)
    if "method" in score:  # "auto" preloads are verified by the method that scores them
        defaults.setdefault("preload_method", score["method"].value)
    grasps: list[Any] = []
    raw = data.get("grasps") or []
    if not isinstance(raw, list):
        raise f.error("grasps", "expected a list of grasps")
    for i, g in enumerate(raw):
        key = f"grasps[{i}]"
        g = f.mapping(g, key)
        if "scene" in g:
            f.keys(g, ("scene", "id"), key)
            ref = f.string(g["scene"], f"{key}.scene")
            local = f.relpath(ref, f"{key}.scene")
            entry = {"scene": str(local) if local.is_file() else ref}
            grasps.append(entry | ({"id": str(g["id"])} if "id" in g else {}))
            continue
        f.keys(g, GRASP_KEYS, key)
        grasps.append(_spec(f, {**defaults, **_grasp_fields(f, g, key)}, key))
    grasps += _samples(f, data.get("sample") or [], defaults)
    if not grasps:
        raise f.error("grasps", "no grasps: give 'grasps' and/or 'sample'")
    return GraspBatch(p, tuple(grasps), score)


def _score(f: SceneFile, data: dict[str, Any]) -> dict[str, Any]:
    """The validated ``score`` block (options of the default score)."""
    s = f.mapping(data.get("score") or {}, "score")
    f.keys(s, SCORE_KEYS, "score")
    score: dict[str, Any] = {}
    if "upper" in s:
        score["upper"] = f.domain(lambda k, v: force(k, v, "N or N·m"), s["upper"], "score.upper")
    if "method" in s:
        if not isinstance(s["method"], str) or s["method"] not in method_names():
            raise f.error("score.method", f"must be one of {', '.join(method_names())}, got {s['method']!r}")
        score["method"] = method_name(s["method"])
    if "steps" in s:  # domains checked before any grasp runs (docs/errors.md); a path ignores steps
        bounded = limits_bound(score.get("method", DEFAULT_METHOD))
        score["steps"] = f.domain(lambda k, v: n_steps(v, k, bounded=bounded), s["steps"], "score.steps")
    if "disturbances" in s:  # "cube26", {gravity: {mass: ...}} or a list of wrenches (k, 6)
        _, w = f.domain(lambda k, v: disturbance_set(v, k), s["disturbances"], "score.disturbances")
        d = s["disturbances"]
        gravity = gravity_of(d)
        if gravity is not None:
            score["disturbances"] = {"gravity": gravity.to_dict()}
        else:
            score["disturbances"] = (
                d if isinstance(d, str) else tuple(tuple(float(v) for v in row) for row in w)
            )
    return score
