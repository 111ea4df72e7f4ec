"""You, Fu and Xie's observation (symkf.bounds.counterexample; Automatica 47(12), 2011): the critical
loss rate 1/8 lies strictly between Sinopoli et al.'s bounds."""


import sympy as sp

from symkf.bounds.counterexample import reproduce_you_2011_counterexample

R = sp.Rational


def test_counterexample_reproduces():
    rep = reproduce_you_2011_counterexample(steps=4)
    assert all(rep["checks"].values()), rep["checks"]
    assert rep["results"]["exact_critical_loss"]["exact"] == "1/8"
    lo, hi = (R(v) for v in rep["results"]["sinopoli_lmi_bracket"])
    assert lo <= R(1, 16) <= hi < R(1, 8)
