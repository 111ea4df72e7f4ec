"""Theory against simulation as a result object (symkf.numeric.verify, ``sk.verify``): the exact
verdict beside the Monte Carlo test, its JSON, repr, LaTeX and HTML.  (The ``verify`` command:
tests/test_cli.py; families: tests/io/test_family_verification.py.)"""

from __future__ import annotations

import json

import sympy as sp

import symkf as sk

QUARTER_TURN = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")])


def test_verify_is_an_object_with_todays_json():
    r = sk.verify(QUARTER_TURN, sk.IID(["1/20"]), paths=3000, seed=0)
    assert isinstance(r, sk.Verification) and r.stable and r.outcome == "consistent"
    assert r.margin.exact == 2 * sp.sqrt(5) / 5 and r.critical_common_loss_rate.exact == sp.Rational(1, 16)
    doc = r.to_dict()
    assert list(doc) == ["theory", "simulation", "outcome", "rate_consistent", "reason"]
    assert doc["theory"]["margins"][0]["exact"] == "2*sqrt(5)/5" and json.loads(json.dumps(doc)) == doc
    assert repr(r).startswith("<Verification consistent: exact margin 2*sqrt(5)/5 ~ 0.894427 (stable)")
    assert r"\frac{2 \sqrt{5}}{5}" in r._repr_latex_() and "CONSISTENT" in r._repr_html_()
    assert str(r).splitlines()[0] == "theory:     stable (Theorem 4 with eq. (36))"


def test_simulation_agrees_on_both_sides_of_the_critical_loss_with_undriven_unstable_modes():
    # Q = 0: neither mode is driven, the critical loss is still 1/4 (proofs/sui_singular_process_noise.py)
    S = sk.System(A=[[2, 0], [0, sp.Rational(6, 5)]], sensors=[sk.Sensor(C=[[1, 1]])], Q=[[0, 0], [0, 0]])
    below, above = (sk.verify(S, sk.IID([e]), paths=4000, seed=0) for e in ["1/5", "3/10"])
    assert below.stable and above.stable is False
    assert below.outcome == above.outcome == "consistent"


def test_simulation_agrees_on_the_tracker_with_white_acceleration_noise():
    G = sp.Matrix([sp.Rational(1, 2), 1])
    S = sk.System(A=[[1, 1], [0, 1]], sensors=[sk.Sensor(C=[[1, 0]])], Q=G * G.T)
    r = sk.verify(S, sk.IID(["9/10"]), paths=4000, seed=0)
    assert r.stable and r.outcome == "consistent"


def test_a_growth_rate_above_the_degree_cap_is_shown_from_its_certified_ball():
    """[[1, 1], [-1, 2]] (eigenvalues of modulus sqrt 3) with C = (0, 1) at loss 77/250: the exact
    growth rate 3 2^(1/6) sqrt(5) 77^(5/6) / 250 has algebraic degree (bound) 72, above the cap
    max_degree = 64 that guards numbers read from outside; the engine's own certified number is
    shown as it is, and the simulation decides (unstable: the margin 1.12438 inside its interval)."""
    S = sk.System(A=[[1, 1], [-1, 2]], sensors=[sk.Sensor(C=[[0, 1]])])
    r = sk.verify(S, sk.IID([sp.Rational(77, 250)]), paths=500, horizon=60)
    assert r.to_dict()["outcome"] == "consistent"
    sim = r.to_dict()["simulation"]
    low, high = sim["rate_interval"]
    assert sim["verdict"] == "unstable" and low < 1.12438 < high
