"""``python -m benchmarks``: see :mod:`benchmarks` and :mod:`benchmarks.runner`."""

import sys

from .runner import main

sys.exit(main())
