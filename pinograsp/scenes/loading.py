"""Scene files: a grasp, its preload and its analysis settings in one YAML file.

``load_scene(name_or_path)`` reads a scene (a built-in name such as ``"case1"``, or a path),
validates it and returns a :class:`~pinograsp.scenes.schema.Scene`: the
:class:`~pinograsp.core.model.GraspModel`, the preload command, the solver
:class:`~pinograsp.core.settings.Settings` and the analysis settings, so that::

    scene = pg.load_scene("case1")
    pg.max_resistible_wrench(scene.model, scene.command, "-fy", settings=scene.settings)

Two kinds of scenes (schema: ``docs/scenes.md``):

* **URDF scenes** (``hand:`` key; :mod:`pinograsp.scenes.urdf_scene`): a hand (built-in name, or
  URDF + description), a joint configuration (values, or auto-close from an open pose), an
  object (box, cylinder, sphere or mesh) and its pose; contacts come from Coal and Pinocchio.
  An optional ``frame`` re-expresses everything in *analysis axes* (e.g. the paper's X/Y),
  ``hand.lock`` holds joints rigid (removes them from the model), and ``planar`` reduces to the
  XY plane of the analysis frame.
* **Explicit-contact scenes** (``contacts:`` key; :mod:`pinograsp.scenes.explicit_scene`):
  contact points, normals and friction with revolute pivots or Jacobian rows, plus actuators
  and couplings.

Every error is a :class:`~pinograsp.errors.SceneError` naming the file and the key path
(``case1.yaml: object.pose.xyz: expected 3 numbers, got 2``). Loading a scene imports no solver.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..core.model import GraspModel
from ..errors import PinograspError, UnknownNameError
from ..robots.yamlfile import load_file, yaml_problem
from .analysis_block import analysis, command
from .explicit_scene import build_explicit
from .fields import SceneFile, mtime, show
from .schema import GraspParts, Scene
from .urdf_scene import build_urdf

#: Folder of the built-in scenes shipped with pinograsp.
SCENE_DIR = Path(__file__).resolve().parents[1] / "data" / "scenes"

_BUILTIN_CACHE: dict[str, tuple[float, str]] = {}
#: A built-in scene name: letters, digits, ``_``, ``-``, ``.`` (never a folder).
_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*")


def read_yaml(path: Path) -> dict[str, Any]:
    """A YAML file's top-level mapping."""
    import yaml

    f = SceneFile(path)
    if not path.is_file():
        raise f.error("", "scene file not found")
    try:
        data = load_file(path)  # no aliases, bounded size (docs/errors.md)
    except yaml.YAMLError as exc:
        raise f.error("", yaml_problem(exc)) from exc
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise f.error("", f"cannot read the file: {exc}") from exc
    if not isinstance(data, Mapping):
        raise f.error("", f"expected a mapping of keys, got {type(data).__name__} (the file is not quoted)")
    return dict(data)


def _extended(f: SceneFile, data: dict[str, Any], seen: list[Path]) -> dict[str, Any]:
    """Apply ``extends: <scene name or file>``: the base's top-level keys, replaced by ours."""
    if data.get("extends") is None:
        data.pop("extends", None)
        return data
    ref = f.string(data.pop("extends"), "extends")
    local = f.relpath(ref, "extends")  # confined to the file's folder (core.paths)
    builtin = _builtin_file(ref)
    base = local if local.is_file() or builtin is None else builtin
    if not base.is_file():
        raise f.error("extends", f"no scene file {local} and no built-in scene {ref!r}")
    if base.resolve() in seen:
        raise f.error("extends", f"circular 'extends' through {base.name}")
    merged = _extended(SceneFile(base), read_yaml(base), [*seen, base.resolve()])
    merged.update(data)
    return merged


def _builtin_file(name: str) -> Path | None:
    """The file of a built-in scene name (a plain name: no folder, no ``..``), or None."""
    if not _NAME.fullmatch(name) or name.startswith("."):
        return None
    p = SCENE_DIR / f"{name}.yaml"
    return p if p.is_file() else None


def _resolve(name_or_path: str | Path) -> Path:
    """The file of a built-in scene name, or the path as given."""
    if isinstance(name_or_path, Path):
        return name_or_path
    s = str(name_or_path)
    builtin = _builtin_file(s)
    if "/" not in s and "\\" not in s and not s.endswith((".yaml", ".yml")):
        if builtin is not None:
            return builtin
        if not Path(s).is_file():
            raise UnknownNameError("scene", s, list(builtin_scenes()))
    return Path(s)


#: The scene key to blame for a ``from_contacts`` argument at fault.
_MODEL_KEYS = {"planar": "planar", "actuators": "actuators", "couplings": "couplings"}


def _model(f: SceneFile, data: Mapping, parts: GraspParts) -> GraspModel:
    """The grasp model of the parts, with the scene's ``planar``, ``edges`` and ``circumscribed``."""
    planar = f.boolean(data.get("planar", False), "planar")
    edges = None if data.get("edges") is None else f.integer(data["edges"], "edges", minimum=3)
    circ = f.boolean(data.get("circumscribed", False), "circumscribed")
    try:
        return GraspModel.from_contacts(
            parts.contacts,
            actuators=parts.actuators,
            couplings=parts.couplings,
            planar=planar,
            reference_point=parts.reference_point,
            joint_names=parts.joint_names,
            edges=edges,
            circumscribed=circ,
        )
    except PinograspError as exc:
        key = _MODEL_KEYS.get(
            getattr(exc, "argument", None) or str(getattr(exc, "name", "")).split("[")[0], ""
        )
        raise f.error(key, f"cannot build the grasp model: {exc}") from exc


def load_scene(name_or_path: str | Path, **overrides: object) -> Scene:
    """Load a scene: a built-in name (``pg.builtin_scenes()``) or a YAML file.

    Args:
        name_or_path: ``"case1"``, ``"pinch"``, ... or the path of a scene file.
        **overrides: Top-level scene keys replacing the file's (shallow: ``planar=True``,
            ``preload={"f1": 1.0}``, ``analysis={...}`` replaces the whole block).

    Returns:
        The validated :class:`~pinograsp.scenes.schema.Scene`.

    Raises:
        SceneError: The file is missing or malformed (the message names the file and key).
        UnknownNameError: ``name_or_path`` is neither a built-in scene nor a file.
    """
    path = _resolve(name_or_path)
    f = SceneFile(path)
    data = _extended(f, read_yaml(path), [path.resolve()])
    data.update(overrides)
    if "hand" in data and "contacts" in data:
        raise f.error("", "a scene has either 'hand' (URDF scene) or 'contacts' (explicit scene), not both")
    if "hand" not in data and "contacts" not in data:
        raise f.error(
            "hand", "missing required key ('hand' for a URDF scene, or 'contacts' for explicit contacts)"
        )
    name = f.string(data.get("name", path.stem), "name")
    desc = data.get("description", "")
    if not isinstance(desc, str):
        raise f.error("description", f"expected a string, got {show(desc)}")
    parts = build_urdf(f, data) if "hand" in data else build_explicit(f, data)
    model = _model(f, data, parts)
    preload = data["preload"] if data.get("preload") is not None else parts.default_command
    if preload is None:
        raise f.error("preload", "missing required key (actuator command [N·m or N])")
    scene_command = command(f, model, preload, "preload")
    scene_analysis, settings = analysis(f, model, data.get("analysis"))
    return Scene(
        name=name,
        description=" ".join(desc.split()),
        path=path,
        model=model,
        command=scene_command,
        settings=settings,
        analysis=scene_analysis,
        hand=parts.hand,
        q=parts.q,
        object=parts.object,
        frame=parts.frame,
        contacts=parts.contacts,
        data=data,
    )


def builtin_scenes() -> dict[str, str]:
    """Built-in scenes: ``{name: description}`` (files in ``pinograsp/data/scenes``)."""
    import yaml

    out = {}
    for p in sorted(SCENE_DIR.glob("*.yaml")):
        mt = mtime(p)
        hit = _BUILTIN_CACHE.get(str(p))
        if hit is None or hit[0] != mt:
            try:
                data = load_file(p) or {}
                desc = " ".join(str(data.get("description", "")).split())
            except yaml.YAMLError:  # pragma: no cover - shipped files are tested
                desc = "(malformed scene file)"
            _BUILTIN_CACHE[str(p)] = hit = (mt, desc)
        out[p.stem] = hit[1]
    return out
