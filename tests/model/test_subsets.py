"""The loss process of a subset of the sensors (symkf.model.subsets.Selected)."""

import pytest
import sympy as sp

import symkf as sk
from symkf.errors import InputError
from symkf.model.codec import from_table


def test_selected_iid_and_gilbert_elliott_give_the_restricted_models_verdicts():
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 1]], name="c")])
    ge = sk.GilbertElliott(["1/10", "1/5", "1/4"], ["1/2", "1/3", "1/2"])
    assert sk.stability(S, sk.Selected(ge, [2])).margins == sk.stability(S, sk.GilbertElliott(["1/4"], ["1/2"])).margins
    iid = sk.IID(["1/10", "1/5", "1/4"])
    assert sk.stability(S, sk.Selected(iid, [1])).margins[0].exact == 4 * sp.sqrt(sp.Rational(1, 5))


def test_selected_keeps_a_joint_chain_and_cuts_its_receivals():
    chain = sk.MarkovLoss({(1, 1): {(1, 1): "1/2", (0, 0): "1/2"}, (0, 0): {(1, 1): "1/3", (0, 0): "2/3"}})
    (factor,) = sk.Selected(chain, [1]).factors
    assert factor.chain.emit == ((1,), (0,)) and factor.chain.P == chain.chain.P


def test_selected_round_trips_through_the_codec():
    ge = sk.GilbertElliott(["1/10", "1/5", "1/4"], ["1/2", "1/3", "1/2"])
    table = sk.Selected(ge, [2, 0]).to_table()
    assert table == {"kind": "selected", "sensors": [0, 2], "of": 3, "loss": ge.to_table()}
    assert from_table(table, 2).channel_fail == (sp.Rational(1, 10), sp.Rational(1, 4))


@pytest.mark.parametrize("sensors, message", [
    ([], "at least one sensor"), ([3], "not a sensor index"), ([0, 0], "listed twice"), ("01", "must be a list or tuple of an int"),
])
def test_bad_selections_are_refused(sensors, message):
    with pytest.raises(InputError, match=message):
        sk.Selected(sk.IID(["1/10", "1/5", "1/4"]), sensors)
