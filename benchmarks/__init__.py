"""pinograsp's benchmark suite: speed, and what speed costs in accuracy, in printed tables.

Run it from the repository root (``pip install -e .`` or ``PYTHONPATH=.``)::

    python -m benchmarks                      # every benchmark
    python -m benchmarks --quick              # the first value of every parameter (smoke run)
    python -m benchmarks -k methods           # benchmarks whose name matches a pattern
    python -m benchmarks --list               # what there is
    python -m benchmarks --json out.json      # also keep the numbers

A benchmark is a class in a ``bench_*.py`` module of this package, in the shape of scipy's asv
suite: ``params`` (a list of value lists) and ``param_names``; ``setup(*params)`` (not timed;
``NotImplementedError`` skips a combination); ``time_*`` methods (timed after ``warmup`` calls,
default 1; ``repeat`` runs, the median and the fastest reported) and ``track_*`` methods (their
return value reported, with the method's ``unit`` attribute). The runner is
:mod:`benchmarks.runner`.

========================  ===============================================================
module                    measures
========================  ===============================================================
``bench_solves``          one solve and one direction query per method on the analytic models
``bench_error_vs_time``   time against error of the search settings (closed forms as reference)
``bench_methods``         method against method on the paper scenes: time, magnitude, agreement
========================  ===============================================================

Standalone scripts of the quasi-static method (issue 25; docs/performance.md, "Quasi-static
method"): ``python -m benchmarks.quasistatic_ratios`` (speed per grasp size against the
iterative and energetic methods, the case-2 resistance set, where the time goes),
``python -m benchmarks.quasistatic_batch`` (``evaluate_grasps`` on sampled Barrett grasps, 26
directions each), ``python -m benchmarks.quasistatic_bits`` (answers bit for bit: the guard of
speed work) and ``python benchmarks/quasistatic_speed.py``. The give-way answer (issue 31):
``python -m benchmarks.giveway_stiffness`` (the default answer at contact stiffness 1e4-1e7 N/m
on the built-in scenes and hands, λ* beside it; docs/validation_quasistatic.md, "Stiffness").

No benchmark asserts a time (tests never do either, docs/design.md); the tables go into the
docs by hand. The scripts that regenerate the documented numbers (docs/results.md,
docs/validation.md, the README tables) are in ``scripts/reproduce/``.
"""
