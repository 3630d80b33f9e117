"""The validation kit: every public function checks its arguments with these helpers, so a bad
input is an :class:`~pinograsp.errors.InvalidInputError` naming the argument and, for choices,
the valid values (docs/errors.md)."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping
from enum import Enum
from pathlib import Path
from typing import TypeVar

import numpy as np

from ..errors import InvalidInputError

E = TypeVar("E", bound=Enum)


def vector(name: str, value: object, size: int) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(name, f"expected {size} numbers, got {value!r}") from exc
    if arr.shape != (size,):
        raise InvalidInputError(name, f"expected {size} numbers, got shape {arr.shape}", value)
    if not np.all(np.isfinite(arr)):
        raise InvalidInputError(name, "contains NaN or inf", value)
    return arr


def finite_array(name: str, value: object, shape: tuple[int, ...]) -> np.ndarray:
    """``value`` as a finite float array of ``shape`` (a flat sequence of the right size is
    reshaped), else :class:`InvalidInputError` naming ``name``."""
    if isinstance(value, (str, bytes)):
        raise InvalidInputError(name, f"expected an array of shape {shape}, got {value!r}")
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(name, f"expected an array of shape {shape}, got {value!r}") from exc
    if arr.size != int(np.prod(shape)):
        raise InvalidInputError(name, f"expected an array of shape {shape}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InvalidInputError(name, "contains NaN or inf")
    return arr.reshape(shape)


def writing(path: object, write: Callable[[Path], object], *, name: str = "path") -> Path:
    """Write a file through ``write(Path)``: the path must be a ``str`` or ``os.PathLike`` naming
    a file (not a folder), its parent folders are created, and an ``OSError`` (permissions, a
    full disk, a file where a folder should be) becomes an :class:`InvalidInputError` naming
    ``name``. Returns the written path."""
    if not isinstance(path, (str, os.PathLike)) or isinstance(path, bytes):
        raise InvalidInputError(name, f"expected a file path (str or os.PathLike), got {path!r}")
    p = Path(path)
    if str(path) == "" or p.is_dir():
        raise InvalidInputError(name, f"{str(path)!r} is a folder, not a file")
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        write(p)
    except OSError as exc:
        raise InvalidInputError(name, f"cannot write {str(p)!r}: {exc.strerror or exc}") from exc
    return p


def finite_number(name: str, value: object) -> float:
    """``float(value)`` if it is a finite real number, else :class:`InvalidInputError` naming ``name``."""
    if isinstance(value, (str, bytes)):
        raise InvalidInputError(name, f"expected a number, got {value!r}")
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(name, f"expected a number, got {value!r}") from exc
    if not np.isfinite(v):
        raise InvalidInputError(name, f"must be finite, got {value!r}")
    return v


def choice(name: str, value: object, valid: tuple[str, ...] | list[str]) -> str:
    """``value`` if it is one of the strings ``valid``, else :class:`InvalidInputError` naming
    ``name`` and the valid choices (arrays, lists and other unhashable values included)."""
    if not isinstance(value, str) or value not in valid:
        raise InvalidInputError(name, f"must be one of {tuple(valid)}, got {value!r}")
    return value


def whole_number(name: str, value: object, minimum: int = 1) -> int:
    """``int(value)`` if it is an integer ``>= minimum`` (``bool``, ``2.5`` and ``"20"`` are
    not), else :class:`InvalidInputError` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InvalidInputError(name, f"expected an integer >= {minimum}, got {value!r}")
    if value < minimum:
        raise InvalidInputError(name, f"must be an integer >= {minimum}, got {value!r}")
    return int(value)


def positive_number(name: str, value: object) -> float:
    """A finite real number ``> 0`` (not a string or bool), else :class:`InvalidInputError`."""
    if isinstance(value, bool):
        raise InvalidInputError(name, f"expected a number, got {value!r}")
    v = finite_number(name, value)
    if not v > 0:
        raise InvalidInputError(name, f"must be a finite number > 0, got {value!r}")
    return v


def check_name(owner: str, name: object) -> str | None:
    """A label: ``None`` or a string (anything else raises :class:`InvalidInputError`)."""
    if name is not None and not isinstance(name, str):
        raise InvalidInputError(f"{owner}.name", f"expected a string or None, got {name!r}")
    return name


def sequence(name: str, value: object) -> list:
    """``list(value)`` for a list-like argument; strings, mappings and scalars are refused."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Iterable):
        raise InvalidInputError(name, f"expected a sequence, got {value!r}")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        raise InvalidInputError(name, f"expected a sequence, got {value!r}")
    return list(value)


def flag(name: str, value: object) -> bool:
    """A boolean argument (``bool``, ``numpy.bool_`` or the integers 0/1)."""
    if isinstance(value, (bool, np.bool_)) or (isinstance(value, (int, np.integer)) and value in (0, 1)):
        return bool(value)
    raise InvalidInputError(name, f"expected True or False, got {value!r}")
