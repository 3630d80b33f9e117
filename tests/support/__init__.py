"""Helpers shared by the tests (not tests themselves; pytest collects only ``test_*.py``).

* :mod:`support.clirun` — the ``pinograsp`` command line run in-process;
* :mod:`support.grasps` — test grasps ``pinograsp.examples`` does not build, with closed forms;
* :mod:`support.probes` — which modules a fresh interpreter loaded (import-cost and layer tests);
* :mod:`support.strategies` — hypothesis strategies and profiles for the fuzz tests;
* :mod:`support.stress` — the stress catalogue (``tests/data/stress_catalogue.yaml``) and its judge;
* :mod:`support.stability` — the stress runner writing ``docs/stability.md``
  (``python -m tests.support.stability`` from the repository root), with
  :mod:`support.stability_report`.

The tests import them as ``support.X`` (pytest puts ``tests/`` on ``sys.path``); the runner, a
script, imports them relative to this package.
"""
