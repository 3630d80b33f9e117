"""``pinograsp`` with a slow default score, for the fault tests of tests/test_batch_faults.py.

Usage: ``python tests/batch_faults_cli.py SECONDS batch GRASPS.yaml ...``: the CLI, with every
``WorstAxisScore`` call lasting at least SECONDS longer (a custom grasp evaluator: the tests need
a batch that is still running when they interrupt it). The numbers are the real score's.
"""

import sys
import time

from pinograsp.batch import evaluate
from pinograsp.cli import main

_score = evaluate.WorstAxisScore.__call__


def _slow_score(self, model, command):
    values = _score(self, model, command)
    time.sleep(DELAY)
    return values


if __name__ == "__main__":
    DELAY = float(sys.argv[1])
    evaluate.WorstAxisScore.__call__ = _slow_score
    sys.exit(main(sys.argv[2:]))
