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
it): see :meth:`symkf.engine.rows.BlockRows.heaviest`.

Only sets whose weight is within ``tol`` of the best so far are kept; the caller confirms them
exactly.  Cost at ``n = 4`` and ``V`` points in ``d`` orbits: about ``V^3 / (6 d)`` point-line
incidences, numpy-vectorised per block of flats.  In
general a stage with ``C`` classes visits about ``C(C, n - 3)`` flats, each tested against the
``C`` classes: :func:`work` estimates this before the search starts.  Under a cyclic symmetry
(the phase shift of a periodic block) a known lower bound of the heaviest weight (:func:`lower_bound`)
confines the greedy bases to a window after each stage's point (:func:`_windowed`): ``C(W, n - 3)``
flats for a window of ``W`` classes.
"""

from __future__ import annotations

import itertools
import math
from typing import NamedTuple, Sequence

import flint
import numpy as np

from ..arguments import check_public

_BLOCK = 1 << 21  # entries of one vectorised block of flats x points (about 16 MB per int64 array)
#: incidences one vectorised pass of :func:`_lines_through_points` costs beyond its own (numpy's
#: per-call overhead and the offers of tied sets), in units of one incidence: the ratio of the two
#: measured costs (docs/performance.md)
PASS = 10_000
#: entries per run of :func:`inverses`' batch trick, squared: each run costs a numpy pass and the
#: Fermat power one per run position, so the cheapest count of runs grows as the square root of
#: the entries (docs/performance.md)
RUN = 40
#: quotients :func:`_crowding` may take over all stages to bound a window: choosing a window must
#: stay cheap beside the search it shortens
CROWDING = 10_000


#: bytes a kept set costs per point it holds (a Python int and its slot in a frozenset), for
#: :class:`Screen`'s memory bound
MEMBER_BYTES = 64


class Crowded(Exception):
    """The sets a :class:`Screen` keeps would hold more memory than it was given (a low floor on a
    block of many elements keeps hundreds of thousands of sets of hundreds of points: gigabytes):
    ``.bytes`` their estimate, ``str()`` their count."""

    def __init__(self, sets: int, points: int) -> None:
        super().__init__(f"{sets} sets of {points} points in all")
        self.bytes = points * MEMBER_BYTES


class Screen:
    """Best screened weight so far and the kept sets (frozensets of point indices) at least
    ``bar``: the best less ``tol``, or with ``floor`` ``min(floor, best)`` less ``tol`` (with
    ``strict``, ``floor`` less ``tol`` even when every set is lighter: the best starts there).  With
    ``memory`` (bytes), an offer that makes the kept sets' points cost more (:data:`MEMBER_BYTES`
    each) raises :class:`Crowded`: the caller gives up the screen (its fallback is estimated and
    refused by its own cap) instead of running out of memory."""

    def __init__(self, tol: float, floor: float | None = None, memory: int | None = None, strict: bool = False) -> None:
        self.tol, self.floor, self.memory = tol, floor, memory
        self.best = floor if strict and floor is not None else -np.inf
        self.kept: dict[frozenset[int], float] = {}
        self._points = 0

    @property
    def bar(self) -> float:
        return (self.best if self.floor is None else min(self.best, self.floor)) - self.tol

    def offer(self, score: float, members) -> None:
        if score < self.bar:
            return
        if score > self.best:
            self.best = score
            self.kept = {S: w for S, w in self.kept.items() if w >= self.bar}
            self._points = sum(map(len, self.kept))
        S = frozenset(members)
        if S not in self.kept:
            self._points += len(S)
            if self.memory is not None and self._points * MEMBER_BYTES > self.memory:
                raise Crowded(len(self.kept) + 1, self._points)
        self.kept[S] = score


def inverses(y: np.ndarray, p: int) -> np.ndarray:
    """Inverses mod p of the nonzero entries of ``y`` (any shape): Fermat's ``y^(p - 2)``, for
    larger arrays by Montgomery's batch trick over ``sqrt(entries / RUN)`` interleaved runs, at
    most 64 (prefix products, one Fermat power per run position, a backward pass); below
    ``25 RUN`` entries the power over every entry (the trick's passes cost more)."""
    flat = y.ravel()
    runs = min(64, math.isqrt(len(flat) // RUN))
    if runs < 5:
        return _power(flat % p, p - 2, p).reshape(y.shape)
    width = -(-len(flat) // runs)
    Y = np.ones(runs * width, dtype=np.int64)
    Y[:len(flat)] = flat
    Y = Y.reshape(runs, width)
    prefix = np.empty_like(Y)
    prefix[0] = Y[0]
    for j in range(1, runs):
        prefix[j] = prefix[j - 1] * Y[j] % p
    inv_all = _power(prefix[-1].copy(), p - 2, p)
    out = np.empty_like(Y)
    for j in range(runs - 1, 0, -1):
        out[j] = inv_all * prefix[j - 1] % p
        inv_all = inv_all * Y[j] % p
    out[0] = inv_all
    return out.ravel()[:len(flat)].reshape(y.shape)


def _power(base: np.ndarray, e: int, p: int) -> np.ndarray:
    """``base^e mod p`` entrywise, by squaring."""
    out = np.ones_like(base)
    while e:
        if e & 1:
            out = out * base % p
        base = base * base % p
        e >>= 1
    return out


def _quotient(X: np.ndarray, b: np.ndarray, p: int) -> np.ndarray:
    """The images of the rows of ``X`` in ``F_p^m / <b>`` (``b`` nonzero), as ``m - 1`` coordinates."""
    k = int(np.flatnonzero(b)[0])
    coef = X[:, k] * int(pow(int(b[k]), -1, p)) % p
    Q = (X - coef[:, None] * b[None, :]) % p
    return np.delete(Q, k, axis=1)


def _labels(X: np.ndarray, p: int) -> tuple[np.ndarray, np.ndarray]:
    """The projective classes of the rows of ``X``: per row its class (-1 for a zero row; classes
    numbered in the order of their first rows) and per class a canonical representative."""
    label = np.full(len(X), -1, dtype=np.int64)
    rows = np.flatnonzero(X.any(axis=1))
    if not len(rows):
        return label, np.zeros((0, X.shape[1]), dtype=np.int64)
    Y = X[rows]
    lead = Y[np.arange(len(rows)), np.argmax(Y != 0, axis=1)]
    canon = Y * inverses(lead, p)[:, None] % p
    first, inverse = _groups(canon, p)
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    label[rows] = rank[inverse]
    return label, canon[first[order]]


def _groups(Y: np.ndarray, p: int) -> tuple[np.ndarray, np.ndarray]:
    """``np.unique(Y, axis=0, return_index=True, return_inverse=True)[1:]`` for residues mod p (``Y``
    of one column or more): the first row of each distinct row, and each row's group, groups in
    the rows' lexicographic order.  The residues are packed big-endian, as many to an int64 as fit
    (the order stays lexicographic), and the rows ordered by one stable lexsort of those columns:
    np.unique sorts rows as opaque records, four to six times slower (a fifth of the screens of
    five cyclotomic fields)."""
    bits = max(1, int(p - 1).bit_length())
    per = max(1, 63 // bits)
    cols = []
    for start in range(0, Y.shape[1], per):
        packed = np.zeros(len(Y), dtype=np.int64)
        for c in range(start, min(start + per, Y.shape[1])):
            packed = packed << bits | Y[:, c]
        cols.append(packed)
    order = np.lexsort(cols[::-1])
    ordered = np.stack(cols, axis=1)[order]
    new = np.ones(len(Y), dtype=bool)
    new[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    inverse = np.empty(len(Y), dtype=np.int64)
    inverse[order] = np.cumsum(new) - 1
    return order[new], inverse


def _classes(X: np.ndarray, p: int) -> tuple[np.ndarray, list[np.ndarray], np.ndarray]:
    """The projective classes of the rows of ``X``: zero rows, then per class (ordered by its first
    row) a canonical representative and its rows."""
    label, reps = _labels(X, p)
    rows = np.flatnonzero(label >= 0)
    by = rows[np.argsort(label[rows], kind="stable")]
    members = np.split(by, np.flatnonzero(np.diff(label[by])) + 1) if len(by) else []
    return np.flatnonzero(label < 0), members, reps


def least_visits(orbits: Sequence[Sequence[int]], skip: set[int], cycles: Sequence[Sequence[int]] | None) -> int:
    """The fewest points the stages of :func:`stages` classify, whichever plan they take: the plain
    plan's (per orbit not in ``skip``, the points after its first) or, with ``cycles``, the
    windowed plan's (a stage per cycle over the ``V - 1`` other points), known before
    :func:`lower_bound` chooses between them."""
    total, start, plain = sum(map(len, orbits)), 0, 0
    for o, orbit in enumerate(orbits):
        plain += 0 if o in skip else total - start - 1
        start += len(orbit)
    return plain if cycles is None else min(plain, len(cycles) * (sum(map(len, cycles)) - 1))


def lower_bound(images: np.ndarray, weights: np.ndarray, p: int, cycles: Sequence[Sequence[int]], screen: Screen) -> None:
    """Offer to ``screen`` the points on the span of each coset of shifts: the points ``q`` apart
    along one cycle (``cycles`` as in :func:`_windowed`), or along every cycle, for each proper
    divisor ``q`` of their length, when that span is a proper subspace mod p.  Each is a flat: a
    lower bound of the heaviest hyperplane's weight (the caller confirms what is kept) that lets
    :func:`stages` shorten its windows."""
    g = len(cycles[0])
    seen = set()   # cycles of repeated or parallel sensors span the same flats: each is read once
    for q in (q for q in range(1, g) if g % q == 0):
        for rows in [*(list(c[::q]) for c in cycles), [e for c in cycles for e in c[::q]]]:
            span, rank = flint.nmod_mat(images[rows].tolist(), p).rref()
            key = tuple(int(v) for v in span.entries()[:rank * images.shape[1]])   # the span's basis
            if key in seen:
                continue
            seen.add(key)
            null, nullity = span.nullspace()
            if nullity:
                N = np.array([[int(null[i, j]) for j in range(nullity)] for i in range(images.shape[1])],
                             dtype=np.int64)
                on = np.flatnonzero(~(images @ N % p).any(axis=1))
                screen.offer(float(weights[on].sum()), on.tolist())


class Stage(NamedTuple):
    """One stage of the search: the hyperplanes through ``anchor`` among ``points`` (in greedy
    order), their greedy basis drawn from ``points[:window]`` (all points when None)."""

    anchor: int
    points: np.ndarray
    window: int | None = None


def stages(images: np.ndarray, weights: np.ndarray, p: int, orbits: Sequence[Sequence[int]], skip: set[int],
           bar: float, cycles: Sequence[Sequence[int]] | None = None) -> list[Stage]:
    """The stages of :func:`search`: per orbit not in ``skip`` its first point with the points after
    it (its own, later orbits'), or, with ``cycles`` and a finite ``bar``, the windowed stages of
    :func:`_windowed` when their estimated work is the lower."""
    later = np.concatenate([np.asarray(o, dtype=np.int64) for o in orbits])
    plain, start = [], 0
    for o, orbit in enumerate(orbits):
        points, start = later[start + 1:], start + len(orbit)
        if o not in skip:
            plain.append(Stage(orbit[0], points))
    n = images.shape[1]
    if cycles is None or n < 4 or not np.isfinite(bar):
        return plain
    windowed = _windowed(images, weights, p, cycles, bar)
    rough = sum(_stage_work(len(s.points), n) for s in plain)
    if windowed is None or sum(_stage_work(len(s.points), n, s.window) for s in windowed) >= rough:
        return plain
    return windowed


def _windowed(images: np.ndarray, weights: np.ndarray, p: int, cycles: Sequence[Sequence[int]],
              bar: float) -> list[Stage] | None:
    """Stages that visit every hyperplane of weight at least ``bar`` with its greedy basis in a
    window after the anchor, or None when no window is shorter than the cycle.

    ``cycles``: the orbits of a symmetry of the hyperplanes and the weights (the phase shift),
    each listed along it and all of one length ``g``; the ``V = d g`` points sit on one cycle of
    positions, ``t d + o`` for the ``t``-th point of cycle ``o``, so the shift rotates positions
    by ``d``.  A hyperplane ``H`` of weight ``>= bar`` has ``N >= bar / max weight`` points; its
    gaps from each point to the ``L``-th next one sum to ``L V``, so some point ``x`` of ``H`` has
    its next ``L`` points within ``M = floor(L V / N)`` positions.  The shift taking ``x`` to the
    first point ``a`` of its cycle takes ``H`` to a hyperplane through ``a`` with ``L`` points in
    the window of the ``M`` positions after ``a``.  When no flat of rank ``n - 3`` through ``a``
    holds ``L`` window points (``L`` is raised until this holds), these ``L`` points include
    ``n - 3`` classes independent mod ``a``, so the greedy basis of the shifted hyperplane (points
    in position order from ``a``) lies in the window: the stage of ``a`` over every other point,
    greedy bases from the window, visits it.  Every cycle is a stage (``x`` may lie on any)."""
    n, d, g = images.shape[1], len(cycles), len(cycles[0])
    V, top = d * g, float(weights.max(initial=0.0))
    if any(len(c) != g for c in cycles) or top <= 0 or bar <= 0:
        return None
    need = math.ceil(bar / top * (1 - 1e-12))  # points of a hyperplane of weight >= bar
    position = np.empty(V, dtype=np.int64)
    for o, cycle in enumerate(cycles):
        position[np.arange(g) * d + o] = cycle
    after = [np.roll(position, -o)[1:] for o in range(d)]
    L = 1
    while True:
        M = L * V // need if need > L else V
        if M >= V - 1:
            return None
        crowds = [_crowding(images[points[:M]], images[position[o]], p, n - 4, CROWDING // d)
                  for o, points in enumerate(after)]
        if None in crowds:
            return None
        crowd = max(crowds)
        if crowd < L:
            return [Stage(int(position[o]), points, M) for o, points in enumerate(after)]
        L = crowd + 1


def _crowding(Y: np.ndarray, a: np.ndarray, p: int, k: int, calls: int) -> int | None:
    """The most rows of ``Y`` in one flat of rank ``k + 1`` through ``a`` (rows parallel to ``a``
    in all of them), or None when finding it would take more than ``calls`` quotients."""
    label, reps = _labels(_quotient(Y, a, p), p)
    if k > 1 and math.comb(len(reps), k - 1) > calls:
        return None
    return int((label < 0).sum()) + _most_in_span(reps, np.bincount(label[label >= 0], minlength=len(reps)), k, p)


def _most_in_span(reps: np.ndarray, sizes: np.ndarray, k: int, p: int) -> int:
    """The largest total size of the classes ``reps`` in one ``k``-dimensional subspace (visited at
    its first class)."""
    if k <= 0 or not len(reps):
        return 0
    if k == 1:
        return int(sizes.max())
    best = 0
    for b in range(len(reps)):
        label, sub = _labels(_quotient(reps[b + 1:], reps[b], p), p)
        merged = np.bincount(label, sizes[b + 1:], len(sub)).astype(np.int64)
        best = max(best, int(sizes[b]) + _most_in_span(sub, merged, k - 1, p))
    return best


def _stage_work(C: int, n: int, window: int | None = None) -> int:
    """Incidences of one stage with ``C`` classes in ``F_p^n / <a>`` (at most: deeper quotients
    merge classes): ``C(C, n - 3)`` flats each against the classes after its last, ``C(C, n - 2)``
    in all, and ``C(C, n - 4)`` vectorised passes (none without classes); with a window of ``W``
    classes, ``C(W, n - 3)`` flats (their bases increasing chains in the window: each level's
    window holds the classes after the last chosen) each against at most ``C`` classes, and
    ``C(W, n - 4)`` passes.  (``C(W, n - 4)`` passes of ``W C`` incidences each overcounted by
    ``n - 3``: the three-field block 2R(2 pi/9) + 2R(2 pi/11) + 2R(2 pi/13), 64 CPU-s estimated,
    19 measured.)"""
    if n < 4 or not C:
        return C
    if window is not None:
        W = min(window, C)
        return math.comb(W, n - 3) * C + PASS * math.comb(W, n - 4)
    return math.comb(C, n - 2) + PASS * math.comb(C, n - 4)


def work(images: np.ndarray, p: int, plan: Sequence[Stage], cap: int) -> int:
    """An upper bound of the incidences :func:`search` tests (:func:`_stage_work` per stage), from
    the stages' numbers of points; when that exceeds ``cap``, from their classes mod the stage's
    point (parallel and collinear points merged; a stage whose point vanishes mod p is left out:
    the search then fails).  Counted stage by stage, the sum stops as soon as it passes ``cap``:
    what is returned then is a lower bound of the work, already above the cap (the caller refuses
    without classifying the remaining stages, which costs most at thousands of sensors)."""
    n = images.shape[1]
    rough = sum(_stage_work(len(s.points), n, s.window) for s in plan)
    if rough <= cap:
        return rough
    total = 0
    for s in plan:
        if images[s.anchor].any():
            label, _ = _labels(_quotient(images[s.points], images[s.anchor], p), p)
            classes = int(label.max(initial=-1)) + 1
            window = None if s.window is None else int(label[:s.window].max(initial=-1)) + 1
            total += _stage_work(classes, n, window)
            if total > cap:
                break
    return total


def search(images: np.ndarray, weights: np.ndarray, p: int, plan: Sequence[Stage], screen: Screen) -> bool:
    """Offer to ``screen`` every screened hyperplane of each stage of ``plan`` (:func:`stages`).
    False when a stage's point vanishes mod p (choose another prime)."""
    for a, points, window in plan:
        if not images[a].any():
            return False
        if weights[a] + weights[points].sum() < screen.bar:
            continue
        zero, classes, reps = _classes(_quotient(images[points], images[a], p), p)
        members = [points[c] for c in classes]
        lim = len(reps) if window is None else sum(1 for c in classes if c[0] < window)
        _hyperplanes(reps, np.array([weights[m].sum() for m in members]), np.arange(len(reps)), members,
                     [a, *points[zero].tolist()], weights[a] + weights[points[zero]].sum(), p, screen, lim)
    return True


def _hyperplanes(reps: np.ndarray, w: np.ndarray, owner: np.ndarray, members: list[np.ndarray], flat: list[int],
                 base: float, p: int, screen: Screen, lim: int) -> None:
    """The screened hyperplanes of ``F_p^m`` (``m = reps.shape[1]``) through the flat ``flat``
    (weight ``base``), over distinct projective classes ``reps`` in greedy order, their next basis
    class among the first ``lim``; ``owner``: the class of each of the stage's classes
    (``members``, their points), -1 for those in ``flat`` or before."""
    m = reps.shape[1]
    if m == 1 or not len(reps):  # the flat itself (a hyperplane when m = 1)
        screen.offer(base, flat)
    elif m == 2:  # lines through the origin: one per class
        for c in range(len(reps)):
            screen.offer(base + w[c], _points(flat, members, owner, [c]))
    elif m == 3:
        _lines_through_points(reps, w, owner, members, flat, base, p, screen, lim)
    else:  # the greedy basis's next class b; later classes grouped by their image mod b
        for b in range(min(lim, len(reps))):
            label, sub = _labels(_quotient(reps[b + 1:], reps[b], p), p)
            head = label[:max(lim - b - 1, 0)]
            renumber = np.full(len(reps) + 1, -1, dtype=np.int64)  # index -1 (owner -1) stays -1
            renumber[b + 1:len(reps)] = label
            _hyperplanes(sub, np.bincount(label, w[b + 1:], len(sub)), renumber[owner], members,
                         _points(flat, members, owner, [b]), base + w[b], p, screen, int(head.max(initial=-1)) + 1)


def _points(flat: list[int], members: list[np.ndarray], owner: np.ndarray, classes) -> list[int]:
    """The points of ``flat`` and of the stage's classes owned by ``classes``."""
    return [*flat, *itertools.chain.from_iterable(members[s].tolist() for s in np.flatnonzero(np.isin(owner, classes)))]


def _lines_through_points(reps: np.ndarray, w: np.ndarray, owner: np.ndarray, members: list[np.ndarray],
                          flat: list[int], base: float, p: int, screen: Screen, lim: int) -> None:
    """``m = 3``: for each class ``b`` among the first ``lim`` (a flat ``flat + b``) the lines
    through ``b`` among the later classes, grouped by their point ``(x : y)`` in ``F_p^3 / <b>``;
    vectorised over blocks of ``b``.  With a finite bar only the lines that may reach it are
    grouped: a line's classes share a bucket (its point's low bits), so a line of weight ``v``
    lies in a bucket of weight at least ``v``, and one pass of sums over the buckets (most of
    them a class or none) leaves the few heavy ones, where sorting every point cost a third of
    the screen of three cyclotomic fields (docs/performance.md)."""
    C = len(reps)
    stop = min(C, lim)
    suffix = np.concatenate([np.cumsum(w[::-1])[::-1], [0.0]])
    others = np.array([[1, 2], [0, 2], [0, 1]])
    coords = np.ascontiguousarray(reps.T)                        # 3 x C
    b0 = 0
    while b0 < stop:
        if base + w[b0:].max() + suffix[b0 + 1] < screen.bar:
            return  # no later flat can reach the best
        rows = max(1, min(stop - b0, _BLOCK // max(1, C - b0)))
        at = np.arange(rows)
        B = reps[b0:b0 + rows]                                  # rows x 3
        k = np.argmax(B != 0, axis=1)
        B = B * inverses(B[at, k], p)[:, None] % p               # b_k = 1: c mod b is c - c_k b
        idx = others[k]
        cols = coords[:, b0 + 1:]                                # class b0 + 1 + j
        U = cols.shape[1]
        ck = cols[k]                                             # rows x U
        X = (cols[idx[:, 0]] - ck * B[at, idx[:, 0]][:, None]) % p  # the image mod b:
        Y = (cols[idx[:, 1]] - ck * B[at, idx[:, 1]][:, None]) % p  # coordinates other than k
        valid = np.arange(U)[None, :] >= at[:, None]             # class b0 + 1 + j after b0 + i
        key = np.where(Y != 0, X * inverses(np.where(Y != 0, Y, 1), p) % p, p)
        key[~valid] = p + 1
        later = w[b0 + 1:]
        if np.isfinite(screen.bar) and U:
            size = 1 << U.bit_length()                           # buckets per row, more than U
            cell = (at[:, None] * size + (key & (size - 1))).ravel()
            sums = np.bincount(cell, np.where(valid, later[None, :], 0.0).ravel(), rows * size)
            # what a line through row i's class must weigh, less the tolerance of the float sums
            need = (screen.bar - base - w[b0:b0 + rows] - screen.tol)[:, None]
            heavy = (sums.reshape(rows, size) >= need)[at[:, None], key & (size - 1)] & valid
        else:
            heavy = valid
        r, j = np.nonzero(heavy)
        kb, jb = int(p + 1).bit_length(), max(U - 1, 1).bit_length()
        # (row, point, class) in one int64 (below 2^52): one unstable sort groups the lines row by row
        packed = np.sort(r << (kb + jb) | key[r, j] << jb | j)
        order, keys, r = packed & ((1 << jb) - 1), packed >> jb & ((1 << kb) - 1), packed >> (kb + jb)
        run = np.ones(len(packed), dtype=bool)
        run[1:] = (keys[1:] != keys[:-1]) | (r[1:] != r[:-1])
        starts = np.flatnonzero(run)
        line, r = keys[starts], r[starts]
        score = (np.add.reduceat(later[order], starts) if len(starts) else np.zeros(0)) + base + w[b0 + r]
        if len(score):  # the block's best first: fewer sets kept on the way
            for i in [int(np.argmax(score)), *np.flatnonzero(score >= screen.bar).tolist()]:
                if score[i] >= screen.bar:
                    on = np.flatnonzero(key[r[i]] == line[i]) + b0 + 1
                    screen.offer(float(score[i]), _points(flat, members, owner, [b0 + int(r[i]), *on.tolist()]))
        if b0 + rows == C:  # the last class has no later class: its flat alone
            screen.offer(base + w[C - 1], _points(flat, members, owner, [C - 1]))
        b0 += rows


check_public(globals())
