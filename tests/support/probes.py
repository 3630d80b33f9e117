"""Which modules a fresh Python process has loaded after running some code (import-cost tests)."""

from __future__ import annotations

import subprocess
import sys


def loaded(code: str, watch: tuple[str, ...]) -> list[str]:
    """The modules of ``watch`` present in ``sys.modules`` after ``code`` ran in a new process."""
    probe = f"{code}\nimport sys\nprint('LOADED:' + ','.join(m for m in {watch!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    line = [x for x in out.stdout.splitlines() if x.startswith("LOADED:")][-1]
    return [m for m in line.removeprefix("LOADED:").split(",") if m]
