"""Maintainer scripts, run from the repository root as modules (``python -m scripts.X``).

* :mod:`scripts.reproduce` — regenerate every documented number (docs/*.md reports, the README
  tables); one command: ``python -m scripts.reproduce``.

Speed lives in ``benchmarks/`` (``python -m benchmarks``); the stress catalogue's runner beside
the tests (``python -m tests.support.stability``).
"""
