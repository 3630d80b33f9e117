"""Quiet backend calls: SCIP's LP solver prints ``Cannot set feasibility tolerance to small value
... without GMP`` straight to the process's stderr when it tightens its tolerance on hard
problems, and HiGHS prints a banner at its first solve. :func:`quiet_stdout` runs a call with
file descriptors 1 and 2 redirected; those lines are dropped and any other output is forwarded
to ``sys.stdout`` / ``sys.stderr``.
"""

from __future__ import annotations

import os
import sys
import tempfile
import threading
from contextlib import contextmanager
from typing import IO, TextIO

#: Lines of backend output that carry no information for pinograsp users (dropped when quiet).
NOISE = (
    "without GMP - using",
    "Running HiGHS",  # HiGHS's banner, printed once per process at its first solve
    "Includes third-party software components, see THIRD_PARTY_NOTICES",
)

_FD_LOCK = threading.Lock()


@contextmanager
def quiet_stdout(enabled: bool = True):
    """Redirect file descriptors 1 and 2 around a backend call; drop :data:`NOISE` lines and
    forward the rest to ``sys.stdout`` / ``sys.stderr``.

    Solver libraries write to the C-level streams (SoPlex's "without GMP" line goes to stderr),
    which ``contextlib.redirect_stdout`` cannot catch. A lock makes concurrent threads take turns
    (the redirection is process-wide).
    """
    if not enabled:
        yield
        return
    streams = ((1, sys.stdout), (2, sys.stderr))
    with _FD_LOCK:
        for _, stream in streams:
            try:
                stream.flush()
            except Exception:  # pragma: no cover - a closed or exotic stream
                pass
        saved: list[tuple[int, int, IO[bytes], TextIO]] = []
        try:
            for fd, stream in streams:
                try:
                    keep = os.dup(fd)
                except OSError:  # pragma: no cover - no such descriptor (embedded interpreters)
                    continue
                tmp: IO[bytes] = tempfile.TemporaryFile(mode="w+b")
                os.dup2(tmp.fileno(), fd)
                saved.append((fd, keep, tmp, stream))
            yield
        finally:
            texts = []
            for fd, keep, tmp, stream in saved:
                try:
                    stream.flush()
                except Exception:  # pragma: no cover
                    pass
                os.dup2(keep, fd)
                os.close(keep)
                tmp.seek(0)
                texts.append((tmp.read().decode(errors="replace"), stream))
                tmp.close()
            for text, stream in texts:
                kept = [ln for ln in text.splitlines(keepends=True) if not any(n in ln for n in NOISE)]
                if kept:
                    stream.write("".join(kept))
