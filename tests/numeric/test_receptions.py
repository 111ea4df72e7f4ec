"""Receptions drawn per factor of a loss model (symkf.numeric.receptions): the compiled Markov step is
its definition, draw by draw, several steps in one call as one call each, and probabilities 0 and 1
hold exactly.  (Each loss model's sampled
law against exact enumeration: tests/model/test_loss.py.)"""

from __future__ import annotations

import numpy as np
import pytest

from symkf.model.gilbert_elliott import GilbertElliott
from symkf.model.iid import IID
from symkf.numeric.receptions import draw


@pytest.mark.parametrize("sensors", [1, 2, 3, 4, 7, 300])
def test_the_compiled_markov_step_is_its_definition(sensors):
    # received_k = (u, v) < T(stay if received_{k-1} else back) per sensor, T = round(p 2^32) in
    # 16-bit halves: v is the next spare draw, taken only where u ties with T's high part; spares
    # running out stop the step at a whole pass, from which it resumes.  Thresholds at both ends
    # (p = 0 and p = 1, the latter above every draw) and draws on both sides of every tie.
    from symkf.numeric.receptions import _TILE, _markov_step, _thresholds
    rng = np.random.default_rng(sensors)
    m = 3 * _TILE // sensors + 5
    stay_p, back_p = rng.random(sensors), rng.random(sensors)
    stay_p[0], back_p[-1] = 0.0, 1.0
    (sh, sl), (bh, bl) = _thresholds(stay_p), _thresholds(back_p)
    prev = rng.random((m, sensors)) < 0.5
    high = np.where(prev, sh, bh)
    u = rng.integers(0, 2 ** 16, (m, sensors)).astype(np.uint16)
    u[::3] = np.minimum(high[::3], 2 ** 16 - 1)                      # a third of the rows tie
    spare = rng.integers(0, 2 ** 16, m * sensors, dtype=np.uint16)
    T = (np.where(prev, sh, bh).astype(np.int64) << 16) + np.where(prev, sl, bl)
    expected, used = np.empty_like(prev), 0
    for e in np.ndindex(m, sensors):
        v = 0
        if u[e] == high[e]:
            v, used = spare[used], used + 1
        expected[e] = (int(u[e]) << 16) + int(v) < T[e]
    rows = max(1, _TILE // sensors)
    tiled = [np.tile(t, rows) for t in (sh, sl, bh, bl)]
    out, step = np.empty_like(prev), _markov_step()
    done, taken, chunks = 0, 0, 0
    while done < m * sensors:
        chunks += 1
        lent = spare[taken:taken + 200 * chunks]                     # a few spares at a time: resumes
        done, k = step(u.ravel(), prev.ravel(), *tiled, out.reshape(-1), lent, done, 0)
        assert done % (rows * sensors) == 0 or done == m * sensors
        taken += k
    np.testing.assert_array_equal(out, expected)
    assert taken == used and chunks > 1


@pytest.mark.parametrize("sensors", [1, 3, 300])
def test_steps_in_one_call_of_the_markov_step_equal_the_steps_one_call_each(sensors):
    # out may hold several steps: after the first (against prev) each entry follows the entry one
    # step back in out itself; a pass never straddles two steps, so the thresholds stay aligned
    from symkf.numeric.receptions import _TILE, _markov_step, _thresholds
    rng = np.random.default_rng(sensors)
    size, steps = (_TILE // sensors + 3) * sensors, 5
    (sh, sl), (bh, bl) = _thresholds(rng.random(sensors)), _thresholds(rng.random(sensors))
    rows = max(1, _TILE // sensors)
    tiled = [np.tile(t, rows) for t in (sh, sl, bh, bl)]
    u = rng.integers(0, 2 ** 16, steps * size).astype(np.uint16)
    u[::7] = np.tile(sh, steps * size // sensors)[::7]                 # ties, each taking a spare
    spare = rng.integers(0, 2 ** 16, steps * size, dtype=np.uint16)
    prev = rng.random(size) < 0.5
    step = _markov_step()
    together = np.empty(steps * size, bool)
    assert step(u, prev, *tiled, together, spare, 0, 0)[0] == steps * size
    alone, used, was = np.empty((steps, size), bool), 0, prev
    for k in range(steps):
        done, taken = step(u[k * size:(k + 1) * size], was, *tiled, alone[k], spare[used:], 0, 0)
        assert done == size
        used, was = used + taken, alone[k]
    np.testing.assert_array_equal(together.reshape(steps, size), alone)
    assert 0 < used < spare.size


def test_certain_transitions_are_sampled_exactly():
    # probabilities 0 and 1 hold exactly, not within 2^-32: a channel that always recovers never
    # loses twice in a row, one that never fails never loses after a reception, i.i.d. losses 0
    # and 1 give all and none; 8.4 million draws each (a 2^-32 leak shows up with odds 1 in 500)
    ge = GilbertElliott(["1/3", 0, 1], [1, "1/2", 1])
    gamma = draw(ge, 64, 2 ** 17, np.random.default_rng(5))
    lost = ~gamma
    assert not (lost[1:, :, 0] & lost[:-1, :, 0]).any()
    assert not (gamma[:-1, :, 1] & lost[1:, :, 1]).any() and gamma[:, :, 1].mean() > 0.99
    assert not (lost[:-1, :, 2] & lost[1:, :, 2]).any() and not (gamma[:-1, :, 2] & gamma[1:, :, 2]).any()
    iid = draw(IID([0, 1]), 64, 2 ** 17, np.random.default_rng(6))
    assert iid[:, :, 0].all() and not iid[:, :, 1].any()
