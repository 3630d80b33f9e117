"""Where files named inside pinograsp's files may be: the one home of the path confinement rule
(docs/scenes.md, "Paths"; docs/errors.md).

A reference inside a scene, hand or batch file (``extends``, ``hand.urdf``, ``description``,
``package_dirs``, ``object.file``, a batch's ``scene``) and a collision mesh inside a URDF
resolves inside the folder of the file that names it. Outside it, only these roots are allowed
(:func:`allowed_roots`): pinograsp's own data folder, the folders a caller passes (e.g. a URDF's
``package_dirs``) and the folders listed in the environment variable
:data:`ALLOWED_PATHS_ENV` (separated by ``os.pathsep``). Symbolic links are followed before the
check, so a link cannot lead outside either. A service that loads uploaded files thus reads
nothing but the upload's own folder.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

from ..errors import InvalidInputError

#: Environment variable listing extra folders that references may point into (``os.pathsep``).
ALLOWED_PATHS_ENV = "PINOGRASP_ALLOWED_PATHS"
#: pinograsp's own data folder (built-in scenes, hands, URDFs): always allowed.
DATA_DIR = Path(__file__).resolve().parents[1] / "data"


def _real(path: str | os.PathLike) -> str:
    return os.path.realpath(os.path.expanduser(os.fspath(path)))


def allowed_roots(*bases: str | os.PathLike) -> list[str]:
    """The folders a reference may resolve into: ``bases``, the data folder and the allow-list."""
    extra = [p for p in os.environ.get(ALLOWED_PATHS_ENV, "").split(os.pathsep) if p.strip()]
    return [_real(b) for b in (*bases, DATA_DIR, *extra)]


def inside(path: str | os.PathLike, roots: Iterable[str]) -> bool:
    """Whether ``path`` (links resolved) is one of ``roots`` or below one."""
    p = _real(path)
    return any(p == r or p.startswith(r.rstrip(os.sep) + os.sep) for r in roots)


def escapes(relative: str) -> bool:
    """Whether a relative reference (``a/b.stl``, ``../x``) leaves its base folder by ``..``."""
    norm = os.path.normpath(relative.replace("\\", "/"))
    return os.path.isabs(norm) or norm == ".." or norm.startswith(".." + os.sep) or norm.startswith("../")


def probe_writable(name: str, path: Path, shown: str) -> None:
    """Check, before any work, that a file can be written at ``path``: its folder is made and a
    probe file created and removed there (``shown``: the path as the user gave it, quoted in
    the error).

    Raises:
        InvalidInputError: Naming ``name``: the folder cannot be made or written.
    """
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".probe", dir=path.parent)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise InvalidInputError(
            name, f"cannot write {shown!r}: {exc.strerror or exc}; choose a writable folder"
        ) from None
