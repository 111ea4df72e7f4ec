"""Cross-checks between issue 18's fast paths and the reference implementations they replace."""

import itertools

import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf.exact.algebraic import sign
from symkf.losses import LossModel

q = sp.Symbol("q", positive=True)
INDEPENDENT = [
    sk.IID(["1/10", "1/3", "2/7"]),
    sk.IID(["0", "1", "1/2"]),
    sk.GilbertElliott(["1/10", "1/5", "1/7"], ["1/2", "1/3", "3/4"]),
    sk.GilbertElliott(["1/10", "0"], ["1/2", "1/3"], initial_received=["1", "1/9"]),
    sk.GilbertElliott(["1/10", "1/4"], [q, "1/3"]),
]


def _joint_positivity_failure(loss: LossModel) -> bool:
    """The reference: every transition of the joint 2^d-state chain, as LossModel checks it."""
    P = loss.chain.P
    return any(not P[r, s].free_symbols and sign(P[r, s]) <= 0
               for r, s in itertools.product(range(P.shape[0]), repeat=2))


@pytest.mark.parametrize("loss", INDEPENDENT, ids=repr)
def test_independent_sensors_agree_with_the_joint_chain(loss):
    assert loss.symbols == LossModel.symbols.fget(loss)
    if isinstance(loss, sk.GilbertElliott):  # i.i.d. losses need no positivity (Theorem 4)
        assert (loss.positivity_failure() is not None) == _joint_positivity_failure(loss)
    if loss.symbols:
        with pytest.raises(sk.SymkfError, match="have no value"):
            loss.numeric()
        return
    fast, ref = loss.numeric(), loss.chain.numeric()
    assert np.array_equal(fast[2], ref[2])
    # Kronecker products round each factor once: d factors, relative error below d ulp
    assert np.allclose(fast[0], ref[0], rtol=4e-16 * loss.d, atol=0)
    assert np.allclose(fast[1], ref[1], rtol=4e-16 * loss.d, atol=0)
