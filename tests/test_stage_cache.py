"""The stage cache of the rate problems (pinograsp/analysis/quasistatic/system.py): what it keeps
between segments — the reduced stiffness's factor and the springs' rows per actuator flow, per
set of touching contacts — changes no bit of an answer, and a re-linearised geometry starts
without them."""

from __future__ import annotations

import dataclasses

import numpy as np

import pinograsp as pg
from pinograsp.analysis.quasistatic import system
from pinograsp.analysis.quasistatic.model import build_qs_model
from pinograsp.analysis.quasistatic.state import StageSpec


def _plain(d):
    """A record's ``to_dict()`` without its timings."""
    if isinstance(d, dict):
        return {k: _plain(v) for k, v in d.items() if "time" not in k}
    if isinstance(d, (list, tuple)):
        return [_plain(x) for x in d]
    return d


def _answers(model, dirs):
    session = pg.Session(model)
    return [_plain(pg.max_resistible_wrench(model, 1.0, d, session=session).to_dict()) for d in dirs]


def test_kept_factors_change_no_bit(monkeypatch):
    """A 16-contact grasp whose paths turn the object, snap and land (about 150 segments per
    direction): the answers with the kept factors equal, bit for bit, those with every factor
    computed again; and the kept ones were read."""
    model = pg.examples.random_grasp(1, 4, contacts_per_finger=2)
    rng = np.random.default_rng(1001)
    dirs = [rng.normal(size=6) for _ in range(2)]
    hits = []
    factor = system._factor

    def counted(qm, sc, ks):
        hits.append(sc.factors is not None and ks.tobytes() in sc.factors)
        return factor(qm, sc, ks)

    monkeypatch.setattr(system, "_factor", counted)
    kept = _answers(model, dirs)
    assert sum(hits) > 0.2 * len(hits)

    of, rebased = system.StageCache.of.__func__, system.StageCache.rebased

    def of_without(cls, qm, spec):
        return dataclasses.replace(of(cls, qm, spec), factors=None, springs=None)

    def rebased_without(self, qm, spec):
        return dataclasses.replace(rebased(self, qm, spec), factors=None, springs=None)

    monkeypatch.setattr(system.StageCache, "of", classmethod(of_without))
    monkeypatch.setattr(system.StageCache, "rebased", rebased_without)
    hits.clear()
    assert _answers(model, dirs) == kept
    assert not any(hits)


def test_a_new_geometry_starts_without_kept_factors():
    """``rebased`` (the same model re-linearised at a turned object) keeps nothing computed for
    the old contact arms: its factor and spring-row caches are new and empty."""
    model = pg.examples.random_grasp(1, 2, contacts_per_finger=2)
    qm = build_qs_model(model)
    spec = StageSpec(
        np.zeros(qm.nx), np.eye(qm.nx)[0], np.ones(qm.na), np.zeros(qm.na), float("inf"), False, True
    )
    sc = system.StageCache.of(qm, spec)
    ks = sc.k_rows.copy()
    first = system._factor(qm, sc, ks)
    assert first is not None and sc.factors[ks.tobytes()] is first
    assert system._factor(qm, sc, ks) is first  # read back, not computed again
    system.spring_act(sc, ks, qm.k_ref)
    again = sc.rebased(qm, spec)
    assert again.factors == {} and again.factors is not sc.factors
    assert again.springs == {} and again.springs is not sc.springs
