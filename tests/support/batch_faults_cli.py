"""``pinograsp`` with a slow default score, for the fault tests of tests/test_batch_faults.py.

Usage: ``python tests/support/batch_faults_cli.py SECONDS batch GRASPS.yaml ...``: the CLI, with
every ``WorstAxisScore`` call lasting at least SECONDS longer (a custom grasp evaluator: the tests
need a batch that is still running when they interrupt it). The numbers are the real score's.

With ``PINOGRASP_TEST_HOLD_AFTER=K`` in the environment, a score call that ends once the journal
``out.csv.partial.jsonl`` (in the working directory) holds K rows waits until its worker is
killed (at most 120 s, a hang guard): the batch is then certainly still running when the test
interrupts it, however slow the machine — no race between the signal and the batch's end.
"""

import faulthandler
import os
import signal
import sys
import time
from pathlib import Path

from pinograsp.batch import evaluate
from pinograsp.cli import main

_score = evaluate.WorstAxisScore.__call__


def _journal_rows() -> int:
    path = Path("out.csv.partial.jsonl")
    return max(0, len(path.read_text().splitlines()) - 1) if path.is_file() else 0


def _slow_score(self, model, command):
    values = _score(self, model, command)
    time.sleep(DELAY)
    hold = os.environ.get("PINOGRASP_TEST_HOLD_AFTER")
    if hold is not None and _journal_rows() >= int(hold):
        time.sleep(120.0)  # killed long before: the interrupt finds the batch running
    return values


if __name__ == "__main__":
    faulthandler.register(signal.SIGUSR1, all_threads=True)  # a hung test dumps the batch's stacks
    # Ctrl-C as at a terminal: a test run started in the background by a non-interactive shell
    # (a CI script's `cmd &`) inherits SIGINT ignored, which Python keeps, and the batch rightly
    # ignores it then (a background job is not interrupted by Ctrl-C; docs/batch.md)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    DELAY = float(sys.argv[1])
    evaluate.WorstAxisScore.__call__ = _slow_score
    sys.exit(main(sys.argv[2:]))
