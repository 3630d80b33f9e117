"""A new user's trial on four example-robot-data hands the package does not ship (issue 31).

Run ``python -m scripts.reproduce.ownhands`` (``--report`` rewrites docs/validation_ownhands.md from
the cached ``results.json`` without simulating; ``--hands z1,baxter_left`` limits the run).
"""
