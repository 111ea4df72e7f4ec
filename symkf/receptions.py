"""Receival sequences drawn per independent factor of a loss model (float64, simulation only).

A loss model (:mod:`symkf.losses`) is a product of independent factors: one two-state chain
(received, lost) per i.i.d. or Gilbert-Elliott sensor, one joint chain for a joint Markov or
network model.  Sampling them one by one keeps memory linear in the number of sensors ``d``:
the joint chain of ``d`` independent sensors has ``2^d`` states (34 GB of float64 at
``d = 16``) and is never built here.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .exact.arguments import check_public


@dataclass(frozen=True)
class LossFactor:
    """An independent piece of a loss model: a chain on ``P`` (float) driving ``sensors``.

    i.i.d. and Gilbert-Elliott sensors are independent, one two-state factor each
    (state 0 = received, 1 = lost); joint Markov and network losses are one factor on
    their :class:`~symkf.losses.LossChain`.  ``emit[s]`` are the factor's sensors'
    receivals in state ``s``.
    """

    sensors: tuple[int, ...]
    P: np.ndarray
    init: np.ndarray
    emit: np.ndarray

    @property
    def two_state(self) -> bool:
        """One sensor on states (received, lost): sampled together with the other such sensors."""
        return len(self.P) == 2 and len(self.sensors) == 1


def cumulative(P: np.ndarray) -> np.ndarray:
    """Cumulative laws along the last axis, the last entry ``inf`` (inverse-CDF draws never overrun)."""
    cum = np.cumsum(P, axis=-1)
    cum[..., -1] = np.inf
    return cum


def groups(factors: Sequence[LossFactor]) -> list[list[LossFactor]]:
    """The factors in sampling groups: every two-state sensor together, each joint chain alone."""
    two = [f for f in factors if f.two_state]
    return ([two] if two else []) + [[f] for f in factors if not f.two_state]


def chain_states(first: np.ndarray, step: np.ndarray, table: np.ndarray | None, rng: np.random.Generator,
                 shape: tuple[int, int, int]) -> np.ndarray:
    """States (K, paths, chains) of independent chains by inverse CDFs: ``first[t, j]`` and
    ``step[t, j, x]`` are cumulative laws under law ``t`` (``table[k, p]``; None: law 0 always).
    The uniforms are drawn one step at a time (the same stream as one (K, paths, chains) draw,
    without holding it: 26 MB per thousand paths at K = 100, d = 16)."""
    K, m, J = shape
    j = np.arange(J)[None, :]
    if step.shape[-1] == 2:         # two states: one comparison with P(state 0), states as uint8
        x = np.empty((K, m, J), np.uint8)
        if table is None and np.array_equal(step[0, :, :, 0], np.broadcast_to(first[0, :, :1], (J, 2))):
            for k in range(K):                                               # i.i.d.: no dependence
                np.greater_equal(rng.random((m, J)), first[0, :, 0], out=x[k].view(bool))
            return x
        x[0] = rng.random((m, J)) >= first[0 if table is None else table[0][:, None], j, 0]
        u = np.empty((m, J))
        if table is None:   # one law: P(next state 0) from state 0 / 1 per chain, chosen elementwise
            from0, from1 = step[0, :, 0, 0], step[0, :, 1, 0]
            for k in range(1, K):
                rng.random(out=u)
                np.greater_equal(u, np.where(x[k - 1].view(bool), from1, from0), out=x[k].view(bool))
            return x
        # P(next state 0) under law t, of chain j, from state s, at flat index (t J + j) 2 + s:
        # one take per step (multi-array fancy indexing costs twice as much)
        stay = np.ascontiguousarray(step[..., 0]).ravel()
        for k in range(1, K):
            rng.random(out=u)
            np.greater_equal(u, stay.take(2 * (table[k][:, None] * J + j) + x[k - 1]), out=x[k].view(bool))
        return x
    x = np.empty((K, m, J), np.intp)
    t = np.zeros((m, 1), np.intp) if table is None else None
    x[0] = (rng.random((m, J))[..., None] >= first[t if table is None else table[0][:, None], j]).sum(axis=-1)
    for k in range(1, K):
        tk = t if table is None else table[k][:, None]
        x[k] = (rng.random((m, J))[..., None] >= step[tk, j, x[k - 1]]).sum(axis=-1)
    return x


def emit_into(received: np.ndarray, group: Sequence[LossFactor], x: np.ndarray) -> None:
    """Write the receivals of ``group``'s states ``x`` (K, paths, chains) into ``received`` (K, paths, d)."""
    if all(f.two_state for f in group):   # state 0 = received
        cols = [f.sensors[0] for f in group]
        if cols == list(range(received.shape[2])):
            np.equal(x, 0, out=received)
        else:
            received[:, :, cols] = x == 0
        return
    for j, f in enumerate(group):
        received[:, :, list(f.sensors)] = f.emit[x[:, :, j]]


def _thresholds(p: np.ndarray) -> np.ndarray:
    """``round(p 2^32)`` as uint32 (``2^32 - 1`` for ``p = 1``): 32 random bits below it have
    probability ``p`` within ``2^-32``."""
    return np.minimum(np.round(np.asarray(p, float) * 2.0 ** 32), 2.0 ** 32 - 1).astype(np.uint32)


def _two_state(group: Sequence[LossFactor], horizon: int, paths: int, rng: np.random.Generator) -> np.ndarray:
    """Receptions (horizon, paths, sensors) of independent two-state sensors, written directly:
    ``received_k = bits_k < T(P(received | received_{k-1}))`` with 32 random bits per draw (two per
    64-bit output of the generator: the draws cost half of float64 uniforms, the law is exact
    within ``2^-32`` per step)."""
    J = len(group)
    start = _thresholds([f.init[0] for f in group])
    stay, back = (_thresholds([f.P[s, 0] for f in group]) for s in (0, 1))
    iid = np.array_equal(stay, back)
    out = np.empty((horizon, paths, J), bool)
    bits = rng.bit_generator

    def draw() -> np.ndarray:
        return bits.random_raw(-(-paths * J // 2)).view(np.uint32)[:paths * J].reshape(paths, J)
    np.less(draw(), start, out=out[0])
    step = None if iid else _markov_step()
    for k in range(1, horizon):
        bits_k = draw()
        if iid:
            np.less(bits_k, stay, out=out[k])
        else:   # received after a reception: bits < stay; after a loss: bits < back
            step(bits_k, out[k - 1], stay, back, out[k])
    return out


def _markov_step_py(bits: np.ndarray, prev: np.ndarray, stay: np.ndarray, back: np.ndarray, out: np.ndarray) -> None:
    """``out = bits < (stay if prev else back)`` entrywise (per sensor thresholds), one pass: the
    threshold chosen by a mask, not a branch, so that the loop vectorises (3x a select on bools).
    The vectorised loop runs along the sensors, or along the paths for up to 3 sensors (with one
    sensor: 1.15 -> 0.06 ns a draw; from 4 on, along the sensors is faster)."""
    m, J = bits.shape
    was, now = prev.view(np.uint8), out.view(np.uint8)
    if J <= 3:
        for j in range(J):
            flip = stay[j] ^ back[j]
            for p in range(m):
                now[p, j] = np.uint8(bits[p, j] < (back[j] ^ (flip & (np.uint32(0) - np.uint32(was[p, j])))))
        return
    for p in range(m):
        for j in range(J):
            threshold = back[j] ^ ((stay[j] ^ back[j]) & (np.uint32(0) - np.uint32(was[p, j])))
            now[p, j] = np.uint8(bits[p, j] < threshold)


@functools.lru_cache(maxsize=None)
def _markov_step():
    """:func:`_markov_step_py` compiled (numba, cached; imported only when a simulation samples)."""
    from numba import njit
    return njit(cache=True, nogil=True)(_markov_step_py)


def sample(factors: Sequence[LossFactor], horizon: int, paths: int, d: int,
           rng: np.random.Generator) -> np.ndarray:
    """Receptions (horizon, paths, d) bool, 1 = received, each factor drawn from its own chain:
    the two-state sensors together (:func:`_two_state`), a joint chain by :func:`chain_states`."""
    received = np.empty((horizon, paths, d), bool)
    for group in groups(factors):
        if group[0].two_state:
            cols = [f.sensors[0] for f in group]
            if cols == list(range(d)):
                received = _two_state(group, horizon, paths, rng)
            else:
                received[:, :, cols] = _two_state(group, horizon, paths, rng)
            continue
        first = np.stack([cumulative(f.init) for f in group])[None]
        step = np.stack([cumulative(f.P) for f in group])[None]
        emit_into(received, group, chain_states(first, step, None, rng, (horizon, paths, len(group))))
    return received


check_public(globals())
