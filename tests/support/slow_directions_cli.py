"""``pinograsp`` whose direction pools hang, for tests/test_orphans.py.

Usage: ``python tests/support/slow_directions_cli.py profile pinch -n 8 --workers 2``: the CLI with
every block of directions of a process pool (:mod:`pinograsp.analysis.directions`) waiting
120 s (a hang guard) before it runs, so that the test finds the workers busy when it kills
their parent. Workers are forked: they inherit the patched function.
"""

import sys
import time

from pinograsp.analysis import directions
from pinograsp.cli import main

_block = directions._directions_block


def _hanging_block(job, dirs, session=None):
    time.sleep(120.0)  # the parent is killed long before
    return _block(job, dirs, session)


if __name__ == "__main__":
    directions._directions_block = _hanging_block
    sys.exit(main(sys.argv[1:]))
