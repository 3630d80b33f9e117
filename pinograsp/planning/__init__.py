"""Grasp planning: sample approach poses on an object's surface, close the hand, score the passive
resistance over a disturbance set on the batch executors, refine the best by a local search,
and return ranked plans (``pg.plan_grasps``; docs/planning.md).

It sits above ``batch/`` (the scoring runs as batches) and ``sim/`` (``verify``), below ``viz/``
and ``cli/``.
"""
