"""Worker processes die with their parent: the one home of this rule for every process pool
pinograsp starts (the batch pool, :mod:`pinograsp.batch.pool`, and the direction pools of
profiles, resistance sets and the demo, :mod:`pinograsp.analysis.directions`).

:func:`die_with_parent` runs first in a worker: ``prctl(PR_SET_PDEATHSIG, SIGKILL)`` on Linux
(the kernel kills the worker when its parent dies, also by SIGKILL), plus a watchdog thread that
checks ``os.getppid()`` every :data:`WATCHDOG_PERIOD` seconds (other systems, and a parent that
died before the prctl took effect).
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time

#: Seconds between two checks of a worker's parent (the watchdog thread).
WATCHDOG_PERIOD = 0.5
_PR_SET_PDEATHSIG = 1


def die_with_parent(parent: int) -> None:
    """Make this process die when ``parent`` (a process id) does: a pool's ``initializer``."""
    if sys.platform.startswith("linux"):
        with contextlib.suppress(Exception):
            import ctypes

            ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL))
    if os.getppid() != parent:  # the parent died before prctl took effect
        os._exit(1)

    def watch() -> None:
        while True:
            time.sleep(WATCHDOG_PERIOD)
            if os.getppid() != parent:
                os._exit(1)

    threading.Thread(target=watch, name="pinograsp-parent-watchdog", daemon=True).start()
