"""Receival sequences drawn per independent factor of a loss model (float64, simulation only).

A loss model (:mod:`symkf.model.loss`) is a product of independent factors: one two-state chain
(received, lost) per i.i.d. or Gilbert-Elliott sensor, one joint chain for a joint Markov or
network model.  Sampling them one by one keeps memory linear in the number of sensors ``d``:
the joint chain of ``d`` independent sensors has ``2^d`` states (34 GB of float64 at
``d = 16``) and is never built here.
"""

from __future__ import annotations

import functools
from typing import Sequence

import numpy as np

from ..arguments import check_public
from ..errors import InputError
from ..model.loss import LossFactor, LossModel, checked


def cumulative(P: np.ndarray) -> np.ndarray:
    """Cumulative laws along the last axis, the last entry ``inf`` (inverse-CDF draws never overrun)."""
    if P.ndim < 1 or P.shape[-1] == 0 or not np.all(np.isfinite(P)) or np.any(P < 0):
        raise InputError(f"P: expected laws of finite probabilities along a non-empty last axis, got shape {P.shape}")
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


def _thresholds(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``T = round(p 2^32)`` split into its high part ``T >> 16`` (0..2^16, uint32: ``p = 1`` is
    2^16, above every 16-bit draw) and its low 16 bits: a 16-bit draw ``u`` below the high part,
    or equal to it and a second 16-bit draw below the low bits, has probability ``T / 2^32``,
    ``p`` within ``2^-33`` and exactly 0 or 1 for ``p = 0`` or 1."""
    T = np.round(np.asarray(p, float) * 2.0 ** 32).astype(np.uint64)
    return (T >> 16).astype(np.uint32), (T & 0xFFFF).astype(np.uint16)


#: entries of one pass of the compiled step: a whole number of rows of sensors, thresholds tiled
#: to it so that its loop runs contiguously (vectorised) for any number of sensors
_TILE = 1024
#: 16-bit draws per call of the compiled step (128 KiB, within the L2 cache): steps are drawn together, so that the
#: generator and the step are called once per batch of steps, not once per step
_BATCH = 2 ** 16


def _two_state(group: Sequence[LossFactor], horizon: int, paths: int, rng: np.random.Generator) -> np.ndarray:
    """Receptions (horizon, paths, sensors) of independent two-state sensors, written directly:
    ``received_k = bits_k < T(P(received | received_{k-1}))`` (:func:`_thresholds`) with 16 random
    bits per draw (four per 64-bit output of the generator) and 16 more where the first 16 tie with
    ``T``'s high part (probability ``2^-16``): the law of 32-bit draws at half their cost (a
    quarter of float64 uniforms').  The generator's outputs are its cost: a draw costs more than
    the compiled step that uses it (docs/performance.md).  The draws of a batch of steps are taken
    at once and the compiled step runs through the batch, each step after the one it depends on."""
    J = len(group)
    rows = max(1, _TILE // J)
    tile = lambda t: np.tile(t, rows)   # noqa: E731
    start, stay, back = (tuple(map(tile, _thresholds(q))) for q in
                         ([f.init[0] for f in group], [f.P[0, 0] for f in group], [f.P[1, 0] for f in group]))
    out = np.empty((horizon, paths, J), bool)
    flat = out.reshape(horizon, paths * J)
    bits = rng.bit_generator
    step = _markov_step()
    size = paths * J
    spare = np.empty(0, np.uint16)
    batch = max(1, _BATCH // size)
    for k in range(0, horizon, batch):
        m = min(batch, horizon - k)
        u = bits.random_raw(-(-m * size // 4)).view(np.uint16)[:m * size]
        # step 0 follows the initial law from either state; later steps from step k - 1's receptions
        parts = [(u[:size], flat[0], start, start, flat[0]), (u[size:], flat[0], stay, back, flat[1:m])] \
            if k == 0 else [(u, flat[k - 1], stay, back, flat[k:k + m])]
        for draws, prev, s, b, into in parts:
            done = used = 0
            while True:     # more spare draws only when the ties outnumber them (about 2^-16 per draw)
                done, used = step(draws, prev, *s, *b, into.reshape(-1), spare, done, used)
                if done == draws.size:
                    break
                spare = np.concatenate([spare[used:], bits.random_raw(8 + draws.size // 2 ** 16).view(np.uint16)])
                used = 0
            spare = spare[used:]
    return out


def _markov_step_py(u: np.ndarray, prev: np.ndarray, stay_hi: np.ndarray, stay_lo: np.ndarray,
                    back_hi: np.ndarray, back_lo: np.ndarray, out: np.ndarray, spare: np.ndarray,
                    done: int, used: int) -> tuple[int, int]:
    """``out = (u, v) < (stay if was else back)`` entrywise, in 16-bit halves: ``u`` against the
    high half, and where they tie a spare draw ``v`` against the low half.  ``was`` is ``prev``
    for the first ``len(prev)`` entries and ``out`` itself ``len(prev)`` entries back for the
    rest: ``out`` may hold several steps of ``len(prev)`` entries, each after the one before.
    Thresholds are tiled over a pass of ``len(stay_hi)`` entries (whole rows of sensors) and
    chosen by a mask, not a branch, so that each pass's loop vectorises.  Runs from entry ``done``
    and spare ``used``; returns where it stopped (``len(u)`` unless the spares ran out) and the
    spares used."""
    n, B, size = len(u), len(stay_hi), len(prev)
    before, now = prev.view(np.uint8), out.view(np.uint8)
    flip = stay_hi ^ back_hi
    while done < n:
        width = min(B, n - done, size - done) if done < size else min(B, n - done)
        uu, nn = u[done:done + width], now[done:done + width]
        ww = before[done:done + width] if done < size else now[done - size:done - size + width]
        ties = 0
        for i in range(width):
            high = back_hi[i] ^ (flip[i] & (np.uint32(0) - np.uint32(ww[i])))
            nn[i] = np.uint8(uu[i] < high)
            ties += np.int32(uu[i] == high)
        if ties:
            if used + ties > len(spare):
                return done, used
            for i in range(width):
                on = ww[i] != 0
                if uu[i] == (stay_hi[i] if on else back_hi[i]):
                    nn[i] = np.uint8(spare[used] < (stay_lo[i] if on else back_lo[i]))
                    used += 1
        done += width
    return done, used


@functools.lru_cache(maxsize=None)
def _markov_step():
    """:func:`_markov_step_py` compiled (numba, cached; imported only when a simulation samples)."""
    from numba import njit
    return njit(cache=True, nogil=True)(_markov_step_py)


def draw(loss: LossModel, horizon: int, paths: int, rng: np.random.Generator) -> np.ndarray:
    """Receptions (horizon, paths, d) bool, 1 = received, of the loss model ``loss`` (exact
    numbers, no symbols), each of its independent factors drawn from its own chain (:func:`sample`)."""
    checked(loss, numbers=True)
    return sample([f.numeric() for f in loss.factors], horizon, paths, loss.d, rng)


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
