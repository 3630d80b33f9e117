"""Shared parts of ``benchmarks/solver_core.py``: single-threaded BLAS, constants, number formats.

Imported first by every part of the benchmark (also by the worker that runs in the old tree):
every measurement runs with single-threaded BLAS unless ``--blas-default`` is given (set before
numpy is imported; a value the caller exported is kept). numpy's OpenBLAS starts one thread per
CPU, and on this 2-core machine its threaded SVDs (the polish and canonical point of every
branch-and-bound solve) were 3-80x slower than single-threaded ones whenever another process
used the other core, which made the new core's times swing 10x with the machine's load. The
default-thread times are measured separately (sections 1, 2).
"""

from __future__ import annotations

import os
import sys

BLAS1 = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
if "--blas-default" not in sys.argv:
    for _k, _v in BLAS1.items():
        os.environ.setdefault(_k, _v)

from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OLD_COMMIT = "fc3d54a"
ANGLES = (0, 30, 45, 60, 90, 135, 180, 270)
PRP_SIZES = ((4, 1), (4, 2), (8, 1), (8, 2), (12, 1), (12, 2))  # (contacts, contacts per finger)
PINCH_DIRS = {"fy": "fy", "(1,1,0)": [1.0, 1.0, 0.0, 0.0, 0.0, 0.0]}
PINCH_CLOSED = {"fy": 10.0, "(1,1,0)": 10.0 * np.sqrt(2.0)}
#: agreement: B&B objective <= SCIP * (1 + REL) + ABS counts as "agree or lower"
REL, ABS = 1e-6, 1e-12
SCIP_TIME_LIMIT = 30.0


def xy(angle: float) -> list[float]:
    a = np.radians(angle)
    return [float(np.cos(a)), float(np.sin(a)), 0.0, 0.0, 0.0, 0.0]


def q(values, p: float) -> float:
    v = np.asarray(values, float)
    return float(np.percentile(v, p)) if len(v) else float("nan")


def status_of(r) -> str:
    """A MaxWrench's status: the new core's ``status`` (finite, unbounded, above_limit,
    below_resolution), the old one's ``unbounded`` flag."""
    st = getattr(r, "status", None)
    return str(st) if st is not None else ("unbounded" if r.unbounded else "finite")


def fmt_mag(mag: float, unbounded: bool, status: str = "") -> str:
    if status == "above_limit":
        return f"≥ {mag:.4g} (above_limit)"
    if status == "below_resolution":
        return "below resolution"
    return "unbounded" if unbounded else f"{mag:.4g}"


def fmt_row(r: dict) -> str:
    return fmt_mag(r["magnitude"], r["unbounded"], r.get("status", ""))
