"""The stress catalogue: its cases, read from ``tests/data/stress_catalogue.yaml``, and their judge.

Every case is a grasp with a closed-form answer (docs/analytic_cases.md; the new geometries in
``tests/support/grasps.py``), a stress parameter pushed to an extreme, and a query:

* ``response`` — ``pg.passive_response`` at a given load: verdict and normal forces;
* ``max`` — ``pg.max_resistible_wrench`` along a direction: magnitude or ``unbounded``.

An outcome is **ok** (the answer matches the nominal closed form within the stated tolerance),
**flagged** (it does not, but pinograsp raised a ``PinograspError``, warned, or marked the result:
``audit.ok`` false, status ``timeout``/``failed``/``not_converged``, non-monotone bisection) or
**WRONG** (a silently wrong number). Tolerances (docs/accuracy.md): PRP forces ``1e-6`` relative
to the largest force; iterative forces ``2 eps`` absolute plus that; PRP magnitudes
``[nominal - upper / 2**steps, nominal]``; iterative magnitudes ``± (upper / 2**steps + 2 eps')``
with ``eps' = eps / |(d_force, d_torque / ℓ)|`` along the unit direction ``d``.

Cases marked ``known`` are silent errors whose fix lives outside the solvers; the tests mark
them ``xfail``. ``tests/test_stability.py`` runs the cases, ``tests/support/stability.py`` writes
the report ``docs/stability.md``.
"""

from __future__ import annotations

import math
import re
import time
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import numpy as np
import yaml

import pinograsp as pg
from pinograsp import examples

from .grasps import COUPLED_CN, MU, TAU, A, L, double_pinch, pinch_variant, pyramid_fmax, ring, ring_fy
from .grasps import with_stiffness as _with_stiffness

CATALOGUE = Path(__file__).resolve().parents[1] / "data" / "stress_catalogue.yaml"
EPS = pg.Settings().eps
#: Relative part of the iterative tolerance, ``eps + eps_rel F``.
EPS_REL = pg.Settings().eps_rel
#: The catalogue's ``grasp`` names.
GRASPS = {
    "pinch": examples.pinch,
    "palm_pinch": examples.palm_pinch,
    "coupled_finger": examples.coupled_finger,
    "pinch_variant": pinch_variant,
    "double_pinch": double_pinch,
    "ring": ring,
}


@dataclass(frozen=True)
class Case:
    """One stress case (fields: see the head of ``tests/data/stress_catalogue.yaml``)."""

    group: str
    name: str
    parameter: str
    grasp: str
    query: str  # "response" or "max"
    method: str
    load: object  # wrench (response) or direction (max)
    expected: object  # (resisted, normal forces) for response; magnitude (inf: unbounded) for max
    params: dict = field(default_factory=dict)
    stiffness: tuple | None = None
    command: float = TAU
    upper: float = 100.0
    steps: int = 12
    settings: dict = field(default_factory=dict)
    quick: bool = False
    known: str = ""  # a known silent error, fix outside the solvers
    force_tol: float = 0.0  # extra absolute force tolerance (continuity cases) [N]
    mag_tol: float = 0.0  # extra magnitude tolerance (continuity cases)
    scale: float = 1.0  # forces of the answer are compared after dividing by this

    def build(self) -> pg.GraspModel:
        """The case's grasp model."""
        model = GRASPS[self.grasp](**self.params)
        return model if self.stiffness is None else _with_stiffness(model, self.stiffness)


@dataclass(frozen=True)
class Outcome:
    """Result of one case."""

    case: str
    group: str
    parameter: str
    method: str
    query: str
    nominal: str
    answer: str
    deviation: float
    verdict: str  # "ok", "flagged", "WRONG"
    notes: str
    time: float
    known: str = ""

    def as_dict(self) -> dict:
        return dict(self.__dict__)


# ---------------------------------------------------------------------------- reading the catalogue
class _Loader(yaml.SafeLoader):
    """YAML with the floats of YAML 1.2 (``1e-3``, ``1e6``: PyYAML reads them as strings)."""


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


def log_uniform(seed: int, low: float, high: float, n: int) -> np.ndarray:
    """``n`` values ``10**u``, ``u`` uniform in ``[low, high)`` drawn with ``default_rng(seed)``."""
    return 10 ** np.random.default_rng(seed).uniform(low, high, n)


#: Names the catalogue's expressions may use.
NAMES = dict(
    A=A, L=L, MU=MU, TAU=TAU, COUPLED_CN=COUPLED_CN, EPS=EPS, EPS_REL=EPS_REL, ring_fy=ring_fy,
    pyramid_fmax=pyramid_fmax, log_uniform=log_uniform, pi=np.pi, inf=math.inf, cos=np.cos, sin=np.sin,
    hypot=math.hypot, max=max, len=len,
)  # fmt: skip
_TEMPLATES = ("group", "name", "parameter")
_CONTROL = ("for", "let", "cases")


def _value(v: object, env: dict) -> object:
    """``v`` with every ``"=expression"`` in it evaluated over ``env``."""
    if isinstance(v, str) and v.startswith("="):
        return eval(v[1:], {"__builtins__": {}, **NAMES, **env})
    if isinstance(v, list):
        return [_value(x, env) for x in v]
    if isinstance(v, dict):
        return {k: _value(x, env) for k, x in v.items()}
    return v


def _loops(loops: dict, env: dict) -> Iterator[dict]:
    """The variables of every pass of the nested ``for`` loops, in order."""
    if not loops:
        yield {}
        return
    (key, values), *rest = loops.items()
    names = [k.strip() for k in key.split(",")]
    for item in _value(values, env):
        row = dict(zip(names, item)) if len(names) > 1 else {key: item}
        for more in _loops(dict(rest), {**env, **row}):
            yield {**row, **more}


def _expand(node: dict, defaults: dict, env: dict, known: dict) -> Iterator[Case]:
    fields = {**defaults, **{k: v for k, v in node.items() if k not in _CONTROL}}
    for row in _loops(node.get("for", {}), env):
        scope = {**env, **row}
        for k, v in node.get("let", {}).items():
            scope[k] = _value(v, scope)
        if "cases" in node:
            for child in node["cases"]:
                yield from _expand(child, fields, scope, known)
        else:
            yield _case(fields, scope, known)


def _case(fields: dict, scope: dict, known: dict) -> Case:
    f = {k: v.format(**scope) if k in _TEMPLATES else _value(v, scope) for k, v in fields.items()}
    f.setdefault("method", scope.get("method"))
    f["known"] = known[f["known"]]["summary"] if f.get("known") else ""
    if f["query"] == "response":
        e = f["expected"]
        f["expected"] = (e["resisted"], e.get("forces"))
    else:
        f["expected"] = float(f["expected"])
    if f.get("stiffness") is not None:
        f["stiffness"] = tuple(f["stiffness"])
    return Case(**f)


@cache
def read_catalogue(path: Path = CATALOGUE) -> dict:
    """The catalogue file as read: ``{"known": {key: {summary, fix}}, "cases": [nodes]}``."""
    with open(path, encoding="utf-8") as fh:
        return yaml.load(fh, Loader=_Loader)  # a SafeLoader


def catalogue(path: Path = CATALOGUE) -> list[Case]:
    """Every stress case (``quick`` ones run in the default test session)."""
    data = read_catalogue(path)
    return [c for node in data["cases"] for c in _expand(node, {}, {}, data["known"])]


def known_fixes(path: Path = CATALOGUE) -> dict[str, str]:
    """Summary of each known silent error -> the proposed fix."""
    return {k["summary"]: " ".join(k["fix"].split()) for k in read_catalogue(path)["known"].values()}


# ---------------------------------------------------------------------------- judging a case
def fmt(x: float) -> str:
    """A number as the report prints it (``∞`` for infinity)."""
    if isinstance(x, float) and math.isinf(x):
        return "∞"
    return f"{x:.6g}"


def _fmt_forces(c) -> str:
    return "[" + ", ".join(fmt(float(v)) for v in np.atleast_1d(c)) + "]"


def _solve(case: Case, model: pg.GraspModel) -> tuple[bool, float, str, list[str]]:
    if case.query == "response":
        r = pg.passive_response(model, case.command, case.load, method=case.method, **case.settings)
        return _judge_response(case, r)
    r = pg.max_resistible_wrench(
        model,
        case.command,
        case.load,
        method=case.method,
        upper=case.upper,
        steps=case.steps,
        **case.settings,
    )
    return _judge_max(case, model, r)


def run_case(case: Case) -> Outcome:
    """Run one case and judge it against its nominal answer."""
    notes: list[str] = []
    t0 = time.perf_counter()
    answer, deviation, match, flagged = "", float("nan"), False, False
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            match, deviation, answer, flag_notes = _solve(case, case.build())
            notes += flag_notes
            flagged = bool(flag_notes)
        except pg.PinograspError as exc:
            answer = f"{type(exc).__name__}"
            notes.append(f"raised {type(exc).__name__}: {str(exc)[:90]}")
            flagged = True
    for w in caught:
        if issubclass(w.category, pg.PinograspWarning):
            notes.append(f"{w.category.__name__}: {str(w.message)[:70]}")
            flagged = True
    elapsed = time.perf_counter() - t0
    verdict = "ok" if match else ("flagged" if flagged else "WRONG")
    return Outcome(
        case.name,
        case.group,
        case.parameter,
        case.method,
        case.query,
        _nominal(case),
        answer,
        deviation,
        verdict,
        "; ".join(dict.fromkeys(notes)),
        elapsed,
        case.known,
    )


def _nominal(case: Case) -> str:
    if case.query == "response":
        resisted, forces = case.expected
        return _fmt_forces(forces) if resisted else "not resisted"
    return fmt(float(case.expected))


def _judge_response(case: Case, r) -> tuple[bool, float, str, list[str]]:
    resisted, expected = case.expected
    notes = []
    if r.status in ("timeout", "failed", "not_converged"):
        notes.append(f"status {r.status}")
    if r.audit is not None and not r.audit.ok:
        notes.append(
            f"audit not ok (complementarity {r.audit.complementarity:.2g}, "
            f"big-M ratio {r.audit.bigm_ratio:.2g})"
        )
    if not r.resistible:
        answer = f"not resisted ({r.status})"
        return (not resisted), (0.0 if not resisted else float("inf")), answer, notes
    c = r.normal_forces / case.scale
    answer = _fmt_forces(c)
    if not resisted:
        return False, float("inf"), answer, notes
    expected = np.asarray(expected, float)
    if c.shape != expected.shape:  # coincident contacts: compare left and the right sum
        c = np.array([c[0], c[1:].sum()])
        answer += " (right summed)"
    err = float(np.abs(c - expected).max())
    big = float(np.abs(expected).max())
    tol = 1e-6 * big + 1e-12 + case.force_tol
    if case.method == "iterative":
        eps = case.settings.get("eps", EPS) + case.settings.get("eps_rel", EPS_REL) * big * case.scale
        tol += 2 * eps / case.scale
    return err <= tol, err / big, answer, notes


def _iterative_eps(case: Case, load: float) -> float:
    """The iterative scheme's tolerance on the net wrench, ``eps + eps_rel F`` [N], with ``F`` at
    least the load and the preload contact force ``tau0 / L``."""
    command = case.command if np.isscalar(case.command) else 1.0
    F = max(load, abs(float(command)) / L)
    return case.settings.get("eps", EPS) + case.settings.get("eps_rel", EPS_REL) * F


def _judge_max(case: Case, model: pg.GraspModel, r) -> tuple[bool, float, str, list[str]]:
    notes = []
    if not r.monotone:
        notes.append("non-monotone evidence")
    exp = float(case.expected)
    if r.unbounded:
        answer = "unbounded"
        if math.isinf(exp):
            return True, 0.0, answer, notes
        return False, float("inf"), answer, notes
    answer = fmt(r.magnitude)
    if math.isinf(exp):
        return False, float("inf"), answer, notes
    res = case.upper / 2**case.steps
    dev = abs(r.magnitude - exp) / exp if exp > 0 else abs(r.magnitude - exp)
    if case.method == "prp":
        ok = exp - res - case.mag_tol - 1e-12 <= r.magnitude <= exp * (1 + 1e-9) + case.mag_tol + 1e-12
    else:
        d = pg.wrench_direction(model, case.load)  # unit 6-vector (force, torque)
        metric = np.linalg.norm(np.concatenate([d[:3], d[3:] / model.length_scale]))
        eps = _iterative_eps(case, exp * metric) / metric
        ok = abs(r.magnitude - exp) <= res + 2 * eps + case.mag_tol
    return ok, dev, answer, notes
