"""Batch output that loses nothing: a row journal written as grasps finish, and atomic tables.

- :func:`check_output` checks the table path before any work starts (suffix, a file not a
  folder, its folder creatable and writable).
- :class:`Journal` is ``<out>.partial.jsonl`` next to the table: a header line (the batch's
  fingerprint), then one JSON line per finished grasp, appended and flushed as it finishes. A
  kill loses at most the line being written (a cut last line is dropped on resume). Floats
  survive JSON bit for bit (``repr`` round trip, ``Infinity``/``NaN`` literals).
- :func:`write_table` writes a temporary file in the same folder and renames it over the table
  (``os.replace``): a reader sees the old table or the new one, never half of one.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any, Literal

from ..core.paths import probe_writable
from ..errors import InvalidInputError, MissingDependencyError

#: Suffix of the journal next to the table.
JOURNAL_SUFFIX = ".partial.jsonl"
_MAGIC = "pinograsp-batch-journal"
_VERSION = 1


def output_format(path: object) -> Literal["csv", "parquet"]:
    """The table format of ``path`` by its suffix (checked before a long batch starts).

    Raises:
        InvalidInputError: Not a ``.csv``, ``.parquet`` or ``.pq`` path.
        MissingDependencyError: Parquet without pyarrow (``pip install "pinograsp[parquet]"``).
    """
    suffix = Path(str(path)).suffix.lower() if isinstance(path, (str, os.PathLike)) else ""
    if suffix == ".csv":
        return "csv"
    if suffix in (".parquet", ".pq"):
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            raise MissingDependencyError("pyarrow", "Parquet output", extra="parquet") from None
        return "parquet"
    raise InvalidInputError("path", f"expected a .csv or .parquet file, got {path!r}")


def check_output(path: object, name: str = "out") -> Path:
    """The table path, checked before any work: ``.csv``/``.parquet``, not a folder, its folder
    created if missing and writable (a temporary file is created and removed there).

    Raises:
        InvalidInputError: Naming ``name``: a bad suffix or a path that cannot be written.
        MissingDependencyError: Parquet without pyarrow.
    """
    if not isinstance(path, (str, os.PathLike)) or isinstance(path, bytes) or str(path) == "":
        raise InvalidInputError(name, f"expected a file path (str or os.PathLike), got {path!r}")
    p = Path(path)
    try:
        output_format(p)
    except InvalidInputError as exc:
        raise InvalidInputError(name, str(exc).split(": ", 1)[-1]) from None
    if p.is_dir():
        raise InvalidInputError(name, f"{str(p)!r} is a folder, not a file")
    probe_writable(name, p, str(p))
    return p


def write_table(table: Any, path: object, name: str = "path") -> Path:
    """Write ``table`` (a DataFrame) to ``.csv`` or ``.parquet`` atomically (temporary file in the
    same folder, then ``os.replace``). Returns the path.

    Raises:
        InvalidInputError: A bad suffix, or the path cannot be written (naming ``name``).
    """
    p = check_output(path, name)
    fmt = output_format(p)
    tmp = ""
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=p.parent)
        os.close(fd)
        if fmt == "csv":
            table.to_csv(tmp, index=False)
        else:
            table.to_parquet(tmp, index=False)
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        os.replace(tmp, p)
    except OSError as exc:
        raise InvalidInputError(name, f"cannot write {str(p)!r}: {exc.strerror or exc}") from None
    finally:
        if tmp:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
    return p


def read_table(path: Path, text_columns: Sequence[str]) -> Any:
    """A table written by :func:`write_table`, floats exactly as written (``text_columns`` as
    strings, ``""`` where empty)."""
    import pandas as pd

    if output_format(path) == "parquet":
        df = pd.read_parquet(path)
    else:
        exact = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}
        df = pd.read_csv(path, dtype=dict.fromkeys(text_columns, str), **exact)
    return df.fillna(dict.fromkeys([c for c in text_columns if c in df], ""))


def _row_key(record: object, row_keys: tuple[str, ...]) -> tuple[int, str] | None:
    """``(index, id)`` of a journal row with every key, or None."""
    if not isinstance(record, dict) or any(k not in record for k in row_keys):
        return None
    index, gid, scores = record.get("index"), record.get("id"), record.get("scores", {})
    if isinstance(index, bool) or not isinstance(index, int) or not isinstance(gid, str):
        return None
    if not isinstance(scores, dict) or not all(isinstance(v, (int, float)) for v in scores.values()):
        return None
    return index, gid


class Journal:
    """The rows of a batch as they finish: ``<table>.partial.jsonl``.

    Attributes:
        table: The table file.
        path: The journal file.
    """

    def __init__(self, table: Path) -> None:
        self.table = table
        self.path = table.with_name(table.name + JOURNAL_SUFFIX)
        self._file: Any = None

    def start(
        self, digest: str, total: int, resume: bool, row_keys: Sequence[str] = ("index", "id", "scores")
    ) -> dict[tuple[int, str], dict]:
        """Open the journal; with ``resume``, the finished rows it holds ``{(index, id): row}``
        (a missing journal: none); without, a fresh journal. ``row_keys``: the keys every row has.

        Raises:
            InvalidInputError: ``resume``: the journal belongs to another batch (another
                fingerprint), is not a journal, or has a damaged line before its last (the file
                is left as it is).
        """
        try:
            self._file = open(self.path, "a+", encoding="utf-8")  # noqa: SIM115 - kept open
        except OSError as exc:
            raise InvalidInputError(
                "out", f"cannot write {str(self.path)!r}: {exc.strerror or exc}"
            ) from None
        self._lock()
        rows: dict[tuple[int, str], dict] = {}
        good = 0
        if resume:
            try:
                rows, good = self._read(digest, tuple(row_keys))
            except BaseException:
                self.close()
                raise
        self._file.truncate(good)  # a fresh journal, or the good lines (a line cut by a kill dropped)
        if not good:
            header = {"journal": _MAGIC, "version": _VERSION, "fingerprint": digest, "grasps": total}
            self._write([header])
        return rows

    def _lock(self) -> None:
        """An exclusive advisory lock (POSIX): two batches never write one journal."""
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX
            return
        try:
            fcntl.flock(self._file.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self.close()
            raise InvalidInputError(
                "out",
                f"another pinograsp batch is writing {str(self.path)!r}: wait for it, or choose another path",
            ) from None

    def _read(self, digest: str, row_keys: tuple[str, ...]) -> tuple[dict[tuple[int, str], dict], int]:
        rows: dict[tuple[int, str], dict] = {}
        try:
            lines = self.path.read_bytes().splitlines(keepends=True)
        except OSError as exc:
            raise InvalidInputError(
                "resume", f"cannot read {str(self.path)!r}: {exc.strerror or exc}"
            ) from None
        good = 0
        for k, line in enumerate(lines):
            try:
                record = json.loads(line)
            except ValueError:  # also UnicodeDecodeError
                record = None
            if record is None or not line.endswith(b"\n"):
                if k == len(lines) - 1:
                    break  # the last line, cut by a kill: dropped
                raise self._damaged(k, "is not a JSON line")
            if k == 0:
                self._check_header(record, digest)
            else:
                key = _row_key(record, row_keys)
                if key is None:
                    raise self._damaged(k, f"is not a row (a mapping with {', '.join(row_keys)})")
                rows.setdefault(key, record)
            good += len(line)
        return rows, good

    def _damaged(self, k: int, what: str) -> InvalidInputError:
        return InvalidInputError(
            "resume",
            f"{str(self.path)!r} line {k + 1} {what}: the journal is damaged (left as it is); "
            "run without resume to start afresh, or use another output path",
        )

    def _check_header(self, record: object, digest: str) -> None:
        if not isinstance(record, dict) or record.get("journal") != _MAGIC:
            raise InvalidInputError("resume", f"{str(self.path)!r} is not a pinograsp batch journal")
        if record.get("fingerprint") != digest:
            raise InvalidInputError(
                "resume",
                f"{str(self.path)!r} holds rows of another batch (other grasps, referenced files or "
                "score): run without resume to start afresh, or use another output path",
            )

    def _write(self, records: Iterable[dict]) -> None:
        try:
            for r in records:
                self._file.write(json.dumps(r, allow_nan=True) + "\n")
            self._file.flush()
        except OSError as exc:  # a full disk, a removed folder
            raise InvalidInputError(
                "out",
                f"cannot append to {str(self.path)!r}: {exc.strerror or exc}; free space or move it",
            ) from None

    def append(self, rows: Iterable[dict]) -> None:
        """Append finished rows (flushed: a kill of this process keeps them)."""
        if self._file is not None:
            self._write(rows)

    def close(self) -> None:
        """Close the file (kept on disk for a resume). A failed flush was reported by the append
        that met it (a full disk): closing does not raise it again."""
        if self._file is not None:
            f, self._file = self._file, None
            with contextlib.suppress(OSError):
                f.close()

    def finish(self) -> None:
        """Close and remove the journal (the final table is written)."""
        self.close()
        with contextlib.suppress(OSError):
            self.path.unlink()
