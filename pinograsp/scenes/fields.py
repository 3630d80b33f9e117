"""Reading the values of a YAML file: every check raises a :class:`~pinograsp.errors.SceneError`
naming the file and the key path (``case1.yaml: object.pose.xyz: expected 3 numbers, got 2``).

Shared by the scene files (:mod:`pinograsp.scenes.loading`) and the grasp batches
(:mod:`pinograsp.batch.files`); the file format itself is in docs/scenes.md.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..core.paths import ALLOWED_PATHS_ENV, allowed_roots, inside
from ..core.poses import rotation_rpy
from ..errors import InvalidInputError, SceneError

#: An angle written in degrees: ``"60 deg"``.
_DEG = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*deg\s*$")


def show(value: object) -> str:
    """A value's type and (shortened) repr, for error messages: ``"list ['fx']"``."""
    text = repr(value)
    kind = type(value).__name__
    return f"{kind} {text if len(text) <= 60 else text[:57] + '...'}"


def mtime(path: Path) -> float:
    """Modification time of a file [s], ``-1.0`` if it cannot be read (cache keys)."""
    try:
        return path.stat().st_mtime
    except OSError:
        return -1.0


class SceneFile:
    """The values of one YAML file, checked one key at a time.

    Every method takes the key path of the value it checks (``"object.pose.xyz"``) and raises
    :class:`~pinograsp.errors.SceneError` naming the file and that key.

    Attributes:
        path: The file (relative paths inside it are relative to its folder).
    """

    def __init__(self, path: Path) -> None:
        self.path = path

    def error(self, key: str, detail: str) -> SceneError:
        """The error for ``key`` (``""``: the file as a whole)."""
        return SceneError(self.path, key, detail)

    def mapping(self, value: object, key: str, what: str = "a mapping") -> Mapping:
        """``value`` if it is a mapping."""
        if not isinstance(value, Mapping):
            raise self.error(key, f"expected {what}, got {show(value)}")
        return value

    def keys(self, value: Mapping, valid: Sequence[str], key: str) -> None:
        """Refuse a key of the mapping ``value`` that is not in ``valid``."""
        for k in value:
            if k not in valid:
                where = f"{key}.{k}" if key else str(k)
                raise self.error(where, f"unknown key; valid keys: {', '.join(valid)}")

    def require(self, value: Mapping, name: str, key: str) -> object:
        """``value[name]``, which must be present and not null."""
        if name not in value or value[name] is None:
            raise self.error(f"{key}.{name}" if key else name, "missing required key")
        return value[name]

    def number(
        self, value: object, key: str, *, positive: bool = False, nonneg: bool = False, angle: bool = False
    ) -> float:
        """A finite number (``angle``: ``"60 deg"`` accepted, returned in [rad])."""
        if isinstance(value, bool):
            raise self.error(key, f"expected a number, got {show(value)}")
        if angle and isinstance(value, str):
            m = _DEG.match(value)
            if m:
                return math.radians(float(m.group(1)))
        try:
            v = float(value)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            hint = " (angles may be written '60 deg')" if angle else ""
            raise self.error(key, f"expected a number, got {show(value)}{hint}") from None
        if not math.isfinite(v):
            raise self.error(key, f"must be finite, got {value!r}")
        if positive and v <= 0:
            raise self.error(key, f"must be > 0, got {value!r}")
        if nonneg and v < 0:
            raise self.error(key, f"must be >= 0, got {value!r}")
        return v

    def domain(self, check: Callable[[str, object], Any], value: object, key: str) -> Any:  # noqa: ANN401
        """``check(key, value)`` (a :mod:`pinograsp.core.validate` domain check); its
        :class:`~pinograsp.errors.InvalidInputError` becomes this file's error for ``key``."""
        try:
            return check(key, value)
        except InvalidInputError as exc:
            detail = str(exc)
            raise self.error(
                key, detail[len(key) + 2 :] if detail.startswith(key + ": ") else detail
            ) from None

    def integer(self, value: object, key: str, minimum: int = 1) -> int:
        """An integer ``>= minimum`` (``true`` and ``2.5`` are not)."""
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise self.error(key, f"expected an integer, got {show(value)}")
        if value < minimum:
            raise self.error(key, f"must be >= {minimum}, got {value}")
        return int(value)

    def boolean(self, value: object, key: str) -> bool:
        """``true`` or ``false``."""
        if not isinstance(value, bool):
            raise self.error(key, f"expected true or false, got {show(value)}")
        return value

    def string(self, value: object, key: str) -> str:
        """A non-empty string."""
        if not isinstance(value, str) or not value:
            raise self.error(key, f"expected a non-empty string, got {show(value)}")
        return value

    def vector(self, value: object, n: int | Sequence[int], key: str, *, angle: bool = False) -> np.ndarray:
        """A list of ``n`` numbers (``n``: a size or the accepted sizes), (n,)."""
        sizes = (n,) if isinstance(n, int) else tuple(n)
        want = " or ".join(str(s) for s in sizes)
        if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Sequence):
            raise self.error(key, f"expected {want} numbers, got {show(value)}")
        if len(value) not in sizes:
            raise self.error(key, f"expected {want} numbers, got {len(value)}")
        return np.array([self.number(v, f"{key}[{i}]", angle=angle) for i, v in enumerate(value)])

    def names(self, value: object, key: str) -> list[str]:
        """A list of non-empty strings."""
        if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
            raise self.error(key, f"expected a list of names, got {show(value)}")
        return [self.string(v, f"{key}[{i}]") for i, v in enumerate(value)]

    def relpath(self, value: object, key: str) -> Path:
        """A path, relative to the file's folder unless absolute (``~`` expanded), confined to
        that folder or the allowed roots (:mod:`pinograsp.core.paths`)."""
        text = self.string(value, key)
        p = Path(text).expanduser()
        p = p if p.is_absolute() else (self.path.parent / p)
        if not inside(p, allowed_roots(self.path.parent)):
            raise self.error(
                key,
                f"{text!r} is outside the folder of {self.path.name} ({self.path.parent}): references "
                f"stay inside it (docs/scenes.md, 'Paths'); list other folders in {ALLOWED_PATHS_ENV}",
            )
        return p

    def pose(self, value: object, key: str) -> np.ndarray:
        """``{xyz: [m], rpy: [rad or 'N deg']}`` (URDF convention; each optional) -> 4×4."""
        T = np.eye(4)
        if value is None:
            return T
        v = self.mapping(value, key, "a mapping with 'xyz' and/or 'rpy'")
        self.keys(v, ("xyz", "rpy"), key)
        if "xyz" in v:
            T[:3, 3] = self.vector(v["xyz"], 3, f"{key}.xyz")
        if "rpy" in v:
            T[:3, :3] = rotation_rpy(self.vector(v["rpy"], 3, f"{key}.rpy", angle=True))
        return T

    def per_name(
        self, value: object, key: str, names: Sequence[str], default: float, **kw: bool
    ) -> float | dict[str, float]:
        """A number, or ``{default: x, <name>: y}`` -> ``{name: value}`` over ``names``
        (``kw``: the checks of :meth:`number`)."""
        if value is None:
            return default
        if not isinstance(value, Mapping):
            return self.number(value, key, **kw)
        out = {}
        dflt = default
        for k, x in value.items():
            if k == "default":
                dflt = self.number(x, f"{key}.default", **kw)
            elif k not in names:
                raise self.error(f"{key}.{k}", f"unknown name; valid: default, {', '.join(names)}")
            else:
                out[str(k)] = self.number(x, f"{key}.{k}", **kw)
        return {n: out.get(n, dflt) for n in names}
