"""Network-state processes (symkf.network.state; Quevedo et al., Sec. III-A and VII-A): Markov and
semi-Markov states validated, holding laws and the stationary initial law."""

from __future__ import annotations

import pytest
import sympy as sp

from symkf.errors import InputError, ProbabilityError
from symkf.network import MarkovNetworkState, SemiMarkovNetworkState

R = sp.Rational


def test_state_validation():
    with pytest.raises(ProbabilityError, match="row 1 sums to"):
        MarkovNetworkState([["1/2", "1/3"], ["1/2", "1/2"]])
    with pytest.raises(ProbabilityError, match="holding"):
        SemiMarkovNetworkState([[1]], [{1: "1/2", 2: "1/3"}])
    with pytest.raises(InputError, match="positive integer"):
        SemiMarkovNetworkState([[1]], [{0: 1}])
    with pytest.raises(InputError, match="stationary"):
        MarkovNetworkState([[1, 0], [0, 1]])
    s = SemiMarkovNetworkState([[0, 1], [1, 0]], [[R(1, 5)] * 5, {7: 1}])
    assert s.sigma == 7 and s.psi(1, 3) == R(1, 5) and s.psi(1, 6) == 0
    assert list(s.initial) == [R(1, 2), R(1, 2)]
