"""The heaviest hyperplanes of a vector configuration, screened modulo a prime (Sui-You-Fu
Section IV: the maximal rank-deficient element sets are the hyperplanes of the generators' matroid).

Points are vectors of ``F_p^n`` (the images of the elements' generators under a ring map
``Z_(p)[theta] -> F_p``), each with a weight ``>= 0``; a screened hyperplane is a set of points
``Z + L``: a flat ``Z`` spanned mod p by ``n - 2`` points and one of the lines through it.  The
search goes stage by stage: stage ``o`` fixes one point ``a`` (the representative of orbit ``o``)
and visits the hyperplanes through ``a`` that hold no point of an earlier orbit, in the quotient
``F_p^n / <a>`` (points there are grouped into projective classes, so parallel sensors and
repeated rows cost one class).  Within a stage a hyperplane is visited at its greedy basis: the
flat of its first ``n - 3`` independent classes (in index order), with the line holding the
classes after the last of them.  Why nothing is missed (every hyperplane's screened set contains
it): see :meth:`symkf.observability.BlockRows.heaviest`.

Only sets whose weight is within ``tol`` of the best so far are kept; the caller confirms them
exactly.  Cost at ``n = 4`` and ``V`` points in ``d`` orbits: about ``V^3 / (6 d)`` point-line
incidences, numpy-vectorised per block of flats (all ``C(V, 2)`` flats times ``V`` before).  In
general a stage with ``C`` classes visits about ``C(C, n - 3)`` flats, each tested against the
``C`` classes: :func:`work` estimates this before the search starts.
"""

from __future__ import annotations

import math
from typing import Iterator, Sequence

import numpy as np

from .exact.arguments import check_public

_BLOCK = 1 << 21  # entries of one vectorised block of flats x points (about 16 MB per int64 array)
#: incidences one vectorised pass of :func:`_lines_through_points` costs beyond its own (numpy's
#: per-call overhead and the offers of tied sets: about 1.4 ms against 0.15 us per incidence)
PASS = 10_000


class Screen:
    """Best screened weight so far and the kept sets (frozensets of point indices) at least
    ``bar``: the best less ``tol``, or with ``floor`` ``min(floor, best)`` less ``tol``."""

    def __init__(self, tol: float, floor: float | None = None) -> None:
        self.tol, self.floor, self.best = tol, floor, -np.inf
        self.kept: dict[frozenset[int], float] = {}

    @property
    def bar(self) -> float:
        return (self.best if self.floor is None else min(self.best, self.floor)) - self.tol

    def offer(self, score: float, members) -> None:
        if score < self.bar:
            return
        if score > self.best:
            self.best = score
            self.kept = {S: w for S, w in self.kept.items() if w >= self.bar}
        self.kept[frozenset(members)] = score


def inverses(y: np.ndarray, p: int) -> np.ndarray:
    """Inverses mod p of the nonzero entries of ``y`` (any shape), by Montgomery's batch trick
    over 64 interleaved runs: prefix products, one Fermat power per run position, a backward pass."""
    flat = y.ravel()
    runs = 64
    width = -(-len(flat) // runs)
    Y = np.ones(runs * width, dtype=np.int64)
    Y[:len(flat)] = flat
    Y = Y.reshape(runs, width)
    prefix = np.empty_like(Y)
    prefix[0] = Y[0]
    for j in range(1, runs):
        prefix[j] = prefix[j - 1] * Y[j] % p
    inv_all, base, e = np.ones(width, dtype=np.int64), prefix[-1].copy(), p - 2
    while e:
        if e & 1:
            inv_all = inv_all * base % p
        base = base * base % p
        e >>= 1
    out = np.empty_like(Y)
    for j in range(runs - 1, 0, -1):
        out[j] = inv_all * prefix[j - 1] % p
        inv_all = inv_all * Y[j] % p
    out[0] = inv_all
    return out.ravel()[:len(flat)].reshape(y.shape)


def _quotient(X: np.ndarray, b: np.ndarray, p: int) -> np.ndarray:
    """The images of the rows of ``X`` in ``F_p^m / <b>`` (``b`` nonzero), as ``m - 1`` coordinates."""
    k = int(np.flatnonzero(b)[0])
    coef = X[:, k] * int(pow(int(b[k]), -1, p)) % p
    Q = (X - coef[:, None] * b[None, :]) % p
    return np.delete(Q, k, axis=1)


def _classes(X: np.ndarray, p: int) -> tuple[np.ndarray, list[np.ndarray], np.ndarray]:
    """The projective classes of the rows of ``X``: zero rows, then per class (ordered by its first
    row) a canonical representative and its rows."""
    nonzero = X.any(axis=1)
    rows = np.flatnonzero(nonzero)
    if not len(rows):
        return np.flatnonzero(~nonzero), [], np.zeros((0, X.shape[1]), dtype=np.int64)
    Y = X[rows]
    lead = Y[np.arange(len(rows)), np.argmax(Y != 0, axis=1)]
    canon = Y * inverses(lead, p)[:, None] % p
    _, first, label = np.unique(canon, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    label = rank[label.ravel()]
    by = np.argsort(label, kind="stable")
    members = np.split(rows[by], np.flatnonzero(np.diff(label[by])) + 1)
    return np.flatnonzero(~nonzero), members, canon[first[order]]


def _stages(orbits: Sequence[Sequence[int]], skip: set[int]) -> Iterator[tuple[int, np.ndarray]]:
    """Per orbit not in ``skip``: its first point and the points after it (its own, later orbits')."""
    later = np.concatenate([np.asarray(o, dtype=np.int64) for o in orbits])
    start = 0
    for o, orbit in enumerate(orbits):
        points, start = later[start + 1:], start + len(orbit)
        if o not in skip:
            yield orbit[0], points


def _stage_work(C: int, n: int) -> int:
    """Incidences of one stage with ``C`` classes in ``F_p^n / <a>`` (at most: deeper quotients
    merge classes): ``C(C, n - 3)`` flats each against ``C`` classes, about ``C(C, n - 2)``, and
    ``C(C, n - 4)`` vectorised passes (none without classes)."""
    if n < 4 or not C:
        return C
    return math.comb(C, n - 2) + PASS * math.comb(C, n - 4)


def work(images: np.ndarray, p: int, orbits: Sequence[Sequence[int]], skip: set[int], cap: int) -> int:
    """An upper bound of the incidences :func:`search` tests (:func:`_stage_work` per stage), from
    the stages' numbers of points; when that exceeds ``cap``, from their classes mod the stage's
    point (parallel and collinear points merged; a stage whose point vanishes mod p is left out:
    the search then fails)."""
    n = images.shape[1]
    rough = sum(_stage_work(len(points), n) for _, points in _stages(orbits, skip))
    if rough <= cap:
        return rough
    return sum(_stage_work(len(_classes(_quotient(images[points], images[a], p), p)[1]), n)
               for a, points in _stages(orbits, skip) if images[a].any())


def search(images: np.ndarray, weights: np.ndarray, p: int, orbits: Sequence[Sequence[int]],
           skip: set[int], screen: Screen) -> bool:
    """Offer to ``screen`` every screened hyperplane through each orbit's first point that holds
    no point of an earlier orbit (orbits listed in order, their points ascending; ``skip``: orbits
    with nothing new).  False when a representative vanishes mod p (choose another prime)."""
    for a, points in _stages(orbits, skip):
        if not images[a].any():
            return False
        if weights[a] + weights[points].sum() < screen.bar:
            continue
        zero, classes, reps = _classes(_quotient(images[points], images[a], p), p)
        flat = [a, *points[zero].tolist()]
        members = [points[c] for c in classes]
        _hyperplanes(reps, members, np.array([weights[m].sum() for m in members]), flat,
                     weights[a] + weights[points[zero]].sum(), p, screen)
    return True


def _hyperplanes(reps: np.ndarray, members: list[np.ndarray], w: np.ndarray, flat: list[int],
                 base: float, p: int, screen: Screen) -> None:
    """The screened hyperplanes of ``F_p^m`` (``m = reps.shape[1]``) through the flat ``flat``
    (weight ``base``), over distinct projective classes ``reps`` in greedy order."""
    m = reps.shape[1]
    if m == 1 or not len(reps):  # the flat itself (a hyperplane when m = 1)
        screen.offer(base, flat)
    elif m == 2:  # lines through the origin: one per class
        for c, ms in enumerate(members):
            screen.offer(base + w[c], [*flat, *ms.tolist()])
    elif m == 3:
        _lines_through_points(reps, members, w, flat, base, p, screen)
    else:  # the greedy basis's next class b; later classes grouped by their image mod b
        for b in range(len(reps)):
            _, groups, sub = _classes(_quotient(reps[b + 1:], reps[b], p), p)
            _hyperplanes(sub, [np.concatenate([members[b + 1 + i] for i in g]) for g in groups],
                         np.array([w[b + 1 + g].sum() for g in groups]), [*flat, *members[b].tolist()],
                         base + w[b], p, screen)


def _lines_through_points(reps: np.ndarray, members: list[np.ndarray], w: np.ndarray, flat: list[int],
                          base: float, p: int, screen: Screen) -> None:
    """``m = 3``: for each class ``b`` (a flat ``flat + b``) the lines through ``b`` among the later
    classes, grouped by their point ``(x : y)`` in ``F_p^3 / <b>``; vectorised over blocks of ``b``."""
    C = len(reps)
    suffix = np.concatenate([np.cumsum(w[::-1])[::-1], [0.0]])
    others = np.array([[1, 2], [0, 2], [0, 1]])
    b0 = 0
    while b0 < C:
        if base + w[b0:].max() + suffix[b0 + 1] < screen.bar:
            return  # no later flat can reach the best
        rows = max(1, min(C - b0, _BLOCK // max(1, C - b0)))
        B = reps[b0:b0 + rows]                                  # rows x 3
        cols = reps[b0 + 1:]                                     # U x 3, class b0 + 1 + j
        U = len(cols)
        k = np.argmax(B != 0, axis=1)
        inv = inverses(B[np.arange(rows), k], p)
        coef = cols[:, k].T * inv[:, None] % p                   # rows x U
        idx = others[k]
        at = np.arange(rows)
        X = (cols[:, idx[:, 0]].T - coef * B[at, idx[:, 0]][:, None]) % p  # the image mod b:
        Y = (cols[:, idx[:, 1]].T - coef * B[at, idx[:, 1]][:, None]) % p  # coordinates other than k
        valid = np.arange(U)[None, :] >= np.arange(rows)[:, None]  # class b0 + 1 + j after b0 + i
        key = np.where(Y != 0, X * inverses(np.where(Y != 0, Y, 1), p) % p, p)
        key[~valid] = p + 1
        order = np.argsort(key, axis=1, kind="stable")
        keys = np.take_along_axis(key, order, axis=1)
        run = np.ones_like(keys, dtype=bool)
        run[:, 1:] = keys[:, 1:] != keys[:, :-1]
        starts = np.flatnonzero(run)
        r, line = starts // max(U, 1), keys.ravel()[starts]
        score = (np.add.reduceat(w[b0 + 1:][order].ravel(), starts) if U else np.zeros(0)) + base + w[b0 + r]
        score[line == p + 1] = -np.inf
        if len(score):  # the block's best first: fewer sets kept on the way
            for i in [int(np.argmax(score)), *np.flatnonzero(score >= screen.bar).tolist()]:
                if score[i] >= screen.bar:
                    on = np.flatnonzero(key[r[i]] == line[i]) + b0 + 1
                    screen.offer(float(score[i]), [*flat, *members[b0 + int(r[i])].tolist(),
                                                   *np.concatenate([members[c] for c in on]).tolist()])
        if b0 + rows == C:  # the last class has no later class: its flat alone
            screen.offer(base + w[C - 1], [*flat, *members[C - 1].tolist()])
        b0 += rows


check_public(globals())
