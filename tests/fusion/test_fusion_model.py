"""The fusion set-up (symkf.fusion.model; arXiv:2012.04896, Section 2): Q and the arrival rates
validated, Assumption 2's exact value."""

import pytest
import sympy as sp

from symkf import Sensor
from symkf.errors import AssumptionError, ProbabilityError
from symkf.fusion import FusionModel

from conftest import FUSION_A3, small_fusion_model


def test_singular_uncontrollable_Q_and_bad_rates():
    with pytest.raises(AssumptionError, match="Q > 0"):
        FusionModel.discrete(FUSION_A3, [[0, 0, 0], [0, 0, 0], [0, 0, 1]], [Sensor([[1, 0, 0]]), Sensor([[0, 0, 1]])],
                             ["1/2", "1/2"])
    with pytest.raises(ProbabilityError, match=r"arrival\[1\]"):
        small_fusion_model(arrival=("1/2", "3/2", "1/2"))


def test_assumption2_exact_values():
    a2 = small_fusion_model().assumption2                       # (1 - 1/2) * (11/10)^2
    assert a2.exact == sp.Rational(121, 200) and a2.holds
    assert small_fusion_model(arrival=("1/10", "1", "1")).assumption2.holds is False   # 9/10 * 121/100 > 1
