"""Arguments checked against their annotations before the body runs (symkf.arguments): a call that
does not fit a public function's signature is an ArgumentError naming the function and the
signature it takes, and mappings are checked key by key and value by value."""

from __future__ import annotations

import pytest

import symkf as sk
from symkf.errors import InputError

PUBLIC_CALLABLES = sorted(name for name in dir(sk) if not name.startswith("_") and callable(getattr(sk, name))
                          and not isinstance(getattr(sk, name), type(sk)) and name != "SymkfError")


@pytest.mark.parametrize("name", PUBLIC_CALLABLES)
def test_calls_that_do_not_fit_a_signature_are_argument_errors(name):
    # Python's TypeError for a missing, unknown or repeated argument becomes symkf's ArgumentError
    # (still a TypeError), naming the function and the signature it takes
    from symkf.errors import ArgumentError
    fn = getattr(sk, name)
    with pytest.raises(ArgumentError) as unknown:
        fn(not_an_argument_of_any_symkf_function=1)
    assert isinstance(unknown.value, TypeError) and isinstance(unknown.value, sk.SymkfError)
    assert str(unknown.value).startswith(f"{name}(" if not isinstance(fn, type) else f"{name}.__init__(self")


def test_mappings_are_checked_key_by_key_and_value_by_value():
    # a dict argument was checked only for being a mapping: its keys and values reached the
    # function (span_key(basis={'a': 'b'}) raised AttributeError: found by the payload walk)
    import flint

    from symkf.exact.linalg import span_key
    with pytest.raises(InputError, match=r"span_key: argument 'basis' must be a mapping of an int to a list or tuple "
                                         r"of a fmpq_poly, got dict"):
        span_key({"a": "b"})
    with pytest.raises(InputError, match="mapping of an int"):
        span_key({0: ["__import__('os')"]})
    assert span_key({0: [flint.fmpq_poly([1]), flint.fmpq_poly([0, 2])]}) == ((0, ((1, 1), (1, 0, 2))),)


def test_a_common_loss_rate_takes_the_sensors_of_the_system_beside_it():
    # every public function given a system and IID("1/10") reads it as IID("1/10", d=3), however
    # it reaches the model (Yang et al.'s bounds and Theorem 7 read its Bernoulli losses directly)
    import numpy as np

    from symkf.capacity.theorems import theorem7_necessary
    from symkf.reports.plots import yang_bounds

    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]]), sk.Sensor(C=[[0, 1]])])
    common, listed = sk.IID("1/10"), sk.IID("1/10", d=3)
    assert all(np.array_equal(a, b) for a, b in zip(yang_bounds(S, common, 6), yang_bounds(S, listed, 6)))
    assert theorem7_necessary(S, common) == theorem7_necessary(S, listed)
    assert sk.stability(loss=common, system=S) == sk.stability(S, listed)


def test_a_long_list_of_sympy_numbers_is_refused_before_one_is_priced():
    # each radical was priced at the boundary (150 us each) before IID counted the sensors: ten
    # thousand took 1.5 s, a million minutes
    import sympy as sp

    from conftest import limited, refused_at_once
    radicals = [sp.sqrt(k) / k for k in range(2, 10 ** 4)]
    code, err = limited(refused_at_once, lambda: sk.IID(radicals), "max_priced_items")
    assert code == 0 and "loss: the number of sympy numbers of the list is 9998, above the cap 4096" in err, err
    # long lists of anything else are left to the function, at once: a list of floats is not walked
    code, err = limited(refused_at_once, lambda: sk.IID([0.5] * 10 ** 6), "max_sensors")
    assert code == 0, err
    with sk.budget.limits(max_priced_items=10 ** 4):   # raised, the list is priced
        with pytest.raises(InputError, match=r"loss\[0\]: sqrt\(2\)/2 \+ 1 is not a probability"):
            sk.IID([sp.sqrt(2) / 2 + 1] + radicals[1:100])
