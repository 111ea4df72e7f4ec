"""Simulated E[tr P_k] as a result object (symkf.numeric.simulation, ``sk.simulate``): no interval
where the data cannot support one, the importance-sampled curve says where and why it stops, and a
stable simulation is resolved throughout (fixed seeds, decisive on each of 20)."""

from __future__ import annotations

import numpy as np
import sympy as sp

import symkf as sk

QUARTER_TURN = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")])
#: the aperiodic rotation (3/2) R(theta), cos theta = 3/5, on a Gilbert-Elliott channel: every
#: reception resets the rank, so rho = P(stay lost) = 1/2 and the margin is 9/4 * 1/2 = 9/8
#: (tests/engine/test_stability.py): E[tr P_k] diverges by 9/8 per step
DIVERGING = (sk.System(A=[["9/10", "-6/5"], ["6/5", "9/10"]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")]),
             sk.GilbertElliott(["1/4"], ["1/2"]))


def test_simulate_never_prints_an_interval_the_data_cannot_support():
    # a filter diverging by 9/8 per step: plain Monte Carlo loses the mean to rare bursts early;
    # no interval is given from there on, every given one is positive, and the text says why
    system, loss = DIVERGING
    for seed in range(20):   # decisive on each of 20 seeds (checked before landing)
        sim = sk.simulate(system, loss, horizon=60, paths=300, seed=seed)
        r = sim.resolved_until
        assert sim.stable is False and sim.growth_rate.exact == sp.Rational(9, 8)
        assert 1 <= r < 40 and not sim.resolved[r:].any()       # seen: 9 to 11 at 300 paths
        assert all(sim.interval(k)[0] > 0 for k in range(r)) and sim.interval(r) is None
    doc = sim.to_dict()
    assert doc["low"][r:] == [None] * (60 - r) and doc["resolved_until"] == r
    # computed once per simulation (per call, to_dict was quadratic in the horizon), and read-only
    assert sim.resolved is sim.resolved and not sim.resolved.flags.writeable
    assert "the filter diverges (exact growth 9/8 ≈ 1.125 per step)" in doc["notes"][0]
    assert "not resolved" in str(sim) and "[-" not in str(sim)


def test_simulate_says_where_and_why_the_curve_stops(capsys):
    system, loss = DIVERGING
    sim = sk.simulate(system, loss, horizon=200, paths=200, seed=0, curve=True)
    stop = sim.curve.stop_reason
    assert sim.curve.float_cap is not None and sim.curve.ks[-1] < 200
    assert stop.startswith(f"the importance-sampled curve stops at k = {sim.curve.ks[-1]} of 200: beyond k = ")
    assert stop in sim.to_dict()["notes"] and "montecarlo.float_horizon" in str(sim)
    assert repr(sim).startswith("<Simulation of E[tr P_k]: 200 paths x 200 steps, seed 0")
    assert "not resolved" in sim._repr_html_() and r"\text{not resolved}" in sim._repr_latex_()


def test_a_stable_simulation_is_resolved_throughout():
    # losses 1/1000: a path carrying 10 % of the sum needs three alternating losses (the period-2
    # blind pattern, tr P x 4^3), 8e-9 per path, 3e-4 over these 20 x 2000 paths; at 1/100 it is
    # 8e-6 per path, 27 % over 20 seeds (seeds 14 and 19 of the per-sensor sampler have one)
    for seed in range(20):
        sim = sk.simulate(QUARTER_TURN, sk.IID(["1/1000"]), horizon=12, paths=2000, seed=seed)
        assert sim.resolved_until == 12 and sim.notes() == []
        assert np.all(sim.estimate.low > 0) and np.all(sim.estimate.low <= sim.estimate.mean)
