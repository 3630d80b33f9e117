"""Regenerate the documented numbers: one command, ``python -m scripts.reproduce`` (see
:mod:`scripts.reproduce.__main__` for the targets and ``--smoke``).

Each module is also a script of its own (``python -m scripts.reproduce.<name> --help``) and
imports its siblings relatively; none imports ``tests/`` or ``benchmarks/``.

=====================  ==================================================================
module                 writes
=====================  ==================================================================
``paper_results``      docs/results.md, docs/img/case*.png, README "Results vs the paper"
                       (with ``paper_common``, ``paper_case1``, ``paper_preloads``,
                       ``paper_families``; ``paper_families --write-scenes`` writes the
                       case-2 yaw scene files)
``validate_mujoco``    docs/validation.md (every built-in scene against the MuJoCo simulation)
``error_vs_runtime``   docs/error_vs_runtime.md, docs/img/error_vs_runtime.png, README
                       "Performance" table (with ``error_vs_runtime_report``)
``energetic``          the tables of docs/methods.md, docs/img/energetic_benchmark.png
``resistance_set``     docs/resistance_set.md, docs/img/resistance_set_case1.png
``batch_throughput``   the measured block of docs/batch.md
=====================  ==================================================================
"""
