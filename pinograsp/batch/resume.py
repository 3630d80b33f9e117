"""What a batch resume checks: the fingerprint of a batch, and the stamp of a finished table.

- :func:`fingerprint` digests everything that decides a row: the score (its options and
  method), every grasp record, the *contents* of every file a record names (the scene file and
  the files it names in turn, ``extends`` bases, hand URDFs and descriptions, the meshes a URDF
  or an object names) and the arrays of in-memory :class:`~pinograsp.scenes.schema.Scene`
  records (model, preload, object pose). Editing any of them between a kill and a resume makes
  the journal another batch's.
- A finished table is resumed only with its stamp ``<out>.batch.json`` (the batch's fingerprint
  and the SHA-256 of the table's bytes, written after the table): another batch, an edited or
  cut table, or a table without stamp is refused with a named error (nothing is overwritten).

Built-in hands are digested by their URDF and description (their meshes belong to the installed
package); the meshes of a user's URDF are digested by content.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import math
import os
import re
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InvalidInputError
from .journal import read_table

#: Suffix of a finished table's stamp (its fingerprint and the digest of its bytes).
STAMP_SUFFIX = ".batch.json"
_STAMP = "pinograsp-batch-table"
#: Most files digested for one batch (a record naming more is refused: a loop of references).
MAX_REFERENCED_FILES = 10_000
_MESH_REF = re.compile(rb"""filename\s*=\s*["']([^"']+)["']""")
_AFRESH = "run without --resume (resume=False) to start afresh, or choose another output path"


def _bytes_digest(path: Path) -> str:
    h = hashlib.sha256()
    try:
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
    except OSError as exc:
        return f"unreadable:{exc.errno}"
    return h.hexdigest()


class _Files:
    """Digests of files and of the files they name, each file read once per fingerprint."""

    def __init__(self) -> None:
        self.seen: dict[Path, str] = {}

    def digest(self, path: Path, dirs: Sequence[str] = (), builtin: bool = False) -> Iterator[str]:
        """``"path=sha256"`` of ``path`` and of every file it names (a missing file: ``missing``)."""
        try:
            p = path.resolve()
        except (OSError, RuntimeError):
            p = path
        if p in self.seen:
            return
        if len(self.seen) >= MAX_REFERENCED_FILES:
            raise InvalidInputError(
                "grasps", f"the records name more than {MAX_REFERENCED_FILES} files (a loop of references?)"
            )
        self.seen[p] = d = _bytes_digest(p) if p.is_file() else "missing"
        yield f"{p}={d}"
        if d == "missing" or d.startswith("unreadable"):
            return
        suffix = p.suffix.lower()
        if suffix in (".yaml", ".yml"):
            yield from self._yaml_refs(p)
        elif suffix in (".urdf", ".xml") and not builtin:
            yield from self._urdf_refs(p, dirs)
            if p.with_suffix(".yaml").is_file():  # the description read by default
                yield from self.digest(p.with_suffix(".yaml"))

    def _yaml_refs(self, path: Path) -> Iterator[str]:
        from ..robots.yamlfile import load_file
        from ..scenes.loading import SCENE_DIR

        try:
            data = load_file(path)
        except Exception:  # malformed: its bytes are digested, the loader will say what is wrong
            return
        strings = list(_strings(data))
        dirs = [str(path.parent / s) for _, s in strings if (path.parent / s).is_dir()]
        for key, s in strings:
            local = path.parent / s
            if key == "extends" and not local.is_file():
                local = SCENE_DIR / f"{s}.yaml"
            with contextlib.suppress(OSError, ValueError):
                if local.is_file():
                    yield from self.digest(local, dirs)
            yield from self.hand(s)

    def _urdf_refs(self, path: Path, dirs: Sequence[str]) -> Iterator[str]:
        from ..robots.urdf import package_folders

        try:
            text = path.read_bytes()
        except OSError:
            return
        folders = [*dirs, *package_folders(path, None)]
        for ref in dict.fromkeys(m.decode("utf-8", "replace") for m in _MESH_REF.findall(text)):
            for candidate in _mesh_candidates(path, ref, folders):
                if candidate.is_file():
                    yield from self.digest(candidate)
                    break
            else:
                yield f"{ref}=missing"

    def hand(self, name: object) -> Iterator[str]:
        """The URDF and description of a built-in hand name (nothing for other strings)."""
        from ..robots.description import BUILTIN_HANDS, DATA_DIR, example_robot_data_dir

        if not isinstance(name, str) or name not in BUILTIN_HANDS:
            return
        urdf, desc = BUILTIN_HANDS[name]
        if urdf.startswith("example-robot-data:"):
            try:
                urdf_path = example_robot_data_dir() / "example-robot-data" / urdf.split(":", 1)[1]
            except Exception:  # not installed: the build will say so
                urdf_path = Path(urdf)
        else:
            urdf_path = DATA_DIR / urdf
        yield from self.digest(urdf_path, builtin=True)
        yield from self.digest(DATA_DIR / desc)


def _mesh_candidates(urdf: Path, ref: str, folders: Sequence[str]) -> list[Path]:
    if ref.startswith("package://"):
        rest = ref[len("package://") :]
        return [Path(d) / rest for d in folders] + [Path(d) / rest.split("/", 1)[-1] for d in folders]
    if ref.startswith("file://"):
        return [Path(ref[len("file://") :])]
    return [urdf.parent / ref]


def _strings(data: object, key: str = "") -> Iterator[tuple[str, str]]:
    """``(key, string)`` of every string leaf of a YAML document (keys are the last mapping key)."""
    if isinstance(data, str):
        if data and len(data) < 4096 and "\n" not in data:
            yield key, data
    elif isinstance(data, Mapping):
        for k, v in data.items():
            yield from _strings(v, str(k))
    elif isinstance(data, list):
        for v in data:
            yield from _strings(v, key)


def _value_text(value: object) -> Iterator[bytes]:
    """A canonical byte form of a model's fields (arrays by dtype, shape and bytes)."""
    if isinstance(value, np.ndarray):
        yield f"{value.dtype.str}{value.shape}".encode()
        yield np.ascontiguousarray(value).tobytes()
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        yield type(value).__qualname__.encode()
        for f in dataclasses.fields(value):
            yield f.name.encode()
            yield from _value_text(getattr(value, f.name))
    elif isinstance(value, Mapping):
        for k, v in value.items():
            yield repr(k).encode()
            yield from _value_text(v)
    elif isinstance(value, (list, tuple)):
        yield f"seq{len(value)}".encode()
        for v in value:
            yield from _value_text(v)
    elif isinstance(value, float) and math.isnan(value):
        yield b"nan"
    else:
        yield repr(value).encode()


def _record(files: _Files, kind: str, payload: Any) -> Iterator[bytes]:
    """The bytes that decide one record's row (its fields and the contents it refers to)."""
    if kind == "model":  # an in-memory Scene: its model, preload and object pose
        name, model, command, obj = payload
        yield from _value_text((name, model, dict(command), None if obj is None else obj.pose))
        return
    if kind == "scene":
        from ..scenes.loading import SCENE_DIR

        yield payload.encode()
        p = Path(payload)
        builtin = SCENE_DIR / f"{payload}.yaml"
        refs = files.digest(p if p.is_file() or not builtin.is_file() else builtin)
    else:
        yield repr(payload).encode()
        dirs = list(payload.package_dirs)
        hand = list(files.hand(payload.hand))
        named = [] if hand else [payload.hand]
        named += [n for n in (payload.description, payload.object.file) if n]
        refs = iter(hand + [r for n in named for r in files.digest(Path(n), dirs)])
    for r in refs:
        yield r.encode()


def fingerprint(tasks: Sequence[tuple], score: object) -> str:
    """A digest of the records, the contents they refer to and the score: a journal or a finished
    table resumes only the same batch (module docstring)."""
    h = hashlib.sha256()
    files = _Files()
    for index, gid, kind, payload in tasks:
        h.update(json.dumps([index, gid, kind]).encode())
        for part in _record(files, kind, payload):
            h.update(len(part).to_bytes(8, "little"))
            h.update(part)
    if dataclasses.is_dataclass(score) and not isinstance(score, type):
        h.update(repr(score).encode())
    else:
        h.update(str(getattr(score, "__qualname__", type(score).__qualname__)).encode())
    return h.hexdigest()[:32]


def stamp_path(table: Path) -> Path:
    """The stamp of ``table``: ``<table>.batch.json``."""
    return table.with_name(table.name + STAMP_SUFFIX)


def write_stamp(table: Path, digest: str) -> None:
    """Stamp a table just written: its batch's fingerprint and the digest of its bytes (atomic).

    Raises:
        InvalidInputError: ``out``: the stamp cannot be written (a full disk).
    """
    p = stamp_path(table)
    text = json.dumps({"table": _STAMP, "fingerprint": digest, "sha256": _bytes_digest(table)})
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=p.parent)
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text + "\n")
        os.replace(tmp, p)
        tmp = None
    except OSError as exc:
        raise InvalidInputError(
            "out", f"cannot write {str(p)!r}: {exc.strerror or exc}; free space"
        ) from None
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)


def check_stamp(table: Path, digest: str) -> None:
    """A finished table may be resumed: its stamp names this batch and the table is unchanged.

    Raises:
        InvalidInputError: ``resume``: no stamp (a table of another version or not written by a
            batch), another batch's stamp, or a table edited or cut since it was written.
    """
    p = stamp_path(table)
    try:
        stamp = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        stamp = None
    if not isinstance(stamp, dict) or stamp.get("table") != _STAMP:
        raise InvalidInputError(
            "resume",
            f"{str(table)!r} has no readable stamp {p.name!r} (written when a batch finishes), so "
            f"its rows cannot be checked: {_AFRESH}",
        )
    if stamp.get("fingerprint") != digest:
        raise InvalidInputError(
            "resume",
            f"{str(table)!r} holds rows of another batch (other grasps, files or score): {_AFRESH}",
        )
    if stamp.get("sha256") != _bytes_digest(table):
        raise InvalidInputError(
            "resume", f"{str(table)!r} was edited, cut or damaged after the batch wrote it: {_AFRESH}"
        )


def table_rows(
    path: Path,
    tasks: list[tuple],
    score: object,
    columns: tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]],
    labels: tuple[str, ...] = (),
) -> dict[tuple[int, str], dict]:
    """The rows of a finished, stamped table ``{(index, id): row}`` for ``resume``
    (``columns``: the base, tail and text columns of a batch table; ``labels``: the score's
    per-direction status columns, text kept as ``row["statuses"]``).

    Raises:
        InvalidInputError: ``resume``: the table is not this batch's, or not readable as one.
    """
    base, tail, text = columns
    try:
        df = read_table(path, (*text, *labels))
    except Exception as exc:  # a damaged file: pandas/pyarrow raise their own types
        raise InvalidInputError(
            "resume", f"cannot read {str(path)!r} ({type(exc).__name__}): {_AFRESH}"
        ) from None
    names = [c for c in list(df.columns)[len(base) : len(df.columns) - len(tail)] if c not in labels]
    declared = getattr(score, "columns", None)
    ends = (list(df.columns[: len(base)]), list(df.columns[len(df.columns) - len(tail) :]))
    ok = ends == (list(base), list(tail))
    if not ok or (isinstance(declared, (tuple, list)) and names[: len(declared)] != list(declared)):
        raise InvalidInputError("resume", f"{str(path)!r} is not a table of this score: {_AFRESH}")
    keys = {(t[0], t[1]) for t in tasks}
    rows: dict[tuple[int, str], dict] = {}
    for rec in df.to_dict("records"):
        try:
            key = (int(rec["index"]), str(rec["id"]))
            row = {c: rec[c] for c in (*base, *tail)}
            row.update(index=key[0], id=key[1], n_contacts=int(rec["n_contacts"]))
            row["scores"] = {k: float(rec[k]) for k in names}
            row["statuses"] = {k: str(rec[k]) for k in labels if k in rec}
        except (TypeError, ValueError, KeyError):
            raise InvalidInputError("resume", f"{str(path)!r} has a damaged row: {_AFRESH}") from None
        if key not in keys:
            raise InvalidInputError(
                "resume", f"{str(path)!r} holds grasp {key[1]!r} (index {key[0]}) of another batch: {_AFRESH}"
            )
        rows[key] = row
    return rows
