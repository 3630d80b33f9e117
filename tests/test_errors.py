"""Bad input gives pinograsp errors naming the culprit."""

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples


def test_preload_not_in_equilibrium():
    """One finger pushing an object that nothing holds: no equilibrium at w = 0."""
    c = pg.Contact.revolute(
        [0.05, 0, 0], [-1, 0, 0], {0: ([0.05, -0.1, 0], [0, 0, 1])}, nq=1, mu=0.5, name="lonely"
    )
    m = pg.GraspModel.from_contacts([c], planar=True)
    for method in ("prp", "iterative"):
        with pytest.raises(pg.PreloadNotInEquilibriumError, match="preload not in equilibrium"):
            pg.max_resistible_wrench(m, 1.0, "fy", method=method)
        r = pg.passive_response(m, 1.0, [0, 0, 0], method=method)
        assert not r.resistible


@pytest.mark.parametrize(
    "call, err, match",
    [
        (lambda m: pg.passive_response(m, 1.0, [0, np.nan, 0]), pg.InvalidInputError, "wrench"),
        (lambda m: pg.passive_response(m, [1.0, np.inf], [0, 1, 0]), pg.InvalidInputError, "command"),
        (lambda m: pg.passive_response(m, 1.0, [0, 1, 0], method="magic"), pg.InvalidInputError, "method"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, [0, 0, 0]), pg.InvalidInputError, "zero-length"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, "fw"), pg.UnknownNameError, "wrench axis"),
        (lambda m: pg.max_resistible_wrench(m, 1.0, "fy", upper=-1), pg.InvalidInputError, "upper"),
        (lambda m: pg.passive_response(m, 1.0, [0, 1, 0], gamma=-1.0), pg.InvalidInputError, "gamma"),
        (lambda m: pg.passive_response(m, 1.0, [0, 1, 0], colour="red"), pg.UnknownNameError, "setting"),
        (
            lambda m: pg.passive_response(m, 1.0, [0, 1, 0], variant="two-step"),
            pg.InvalidInputError,
            "variant",
        ),
        (lambda m: pg.resistance_profile(m, 1.0, ("fx", "fx"), n=4), pg.InvalidInputError, "parallel"),
        (lambda m: pg.passive_response("not a model", 1.0, [0, 1, 0]), pg.InvalidInputError, "model"),
    ],
)
def test_bad_input(call, err, match):
    with pytest.raises(err, match=match):
        call(examples.pinch())


def test_every_error_is_a_pinograsp_error():
    for cls in (
        pg.InvalidInputError,
        pg.UnknownNameError,
        pg.ModelError,
        pg.SolverError,
        pg.SolverNotAvailableError,
        pg.SolverTimeoutError,
        pg.PreloadNotInEquilibriumError,
    ):
        assert issubclass(cls, pg.PinograspError)
