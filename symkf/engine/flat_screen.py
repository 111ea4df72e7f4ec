"""The heaviest hyperplanes through the flats of elements of several generators (sensors of
several rows, Jordan chains), screened modulo a prime (Sui-You-Fu Section IV: a rank-deficient
element set lies in a hyperplane, and an element lies in it iff all its generators do).

An element of ``r >= 2`` independent generators spans a flat ``F_e`` of rank ``r``, and a
hyperplane holds it iff it contains ``F_e``: the hyperplanes through ``F_e`` are those of the
quotient ``F_p^m / F_e``, where each other element is the image of its generators.  So the
search recurses through flats instead of single generators: a hyperplane holding a flat element
is visited through the first flat element it holds (in the elements' order, on each level of
quotients; later levels drop the flat elements before the one they go through, which such a
hyperplane does not hold), and one holding none through the points of the elements of rank one
(:func:`symkf.engine.hyperplane_screen._hyperplanes`).  In a plane (``m = 2``) the hyperplanes are the
lines: the elements of rank one grouped by their projective point.  Every score is the exact
mod-p weight of the elements of the current configuration inside the visited hyperplane, so a
hyperplane is offered, at the visit through its first flats, with all its elements (earlier
visits may offer subsets of it, which the caller drops as not maximal).

Each stage fixes the flat of one element ``a`` (the first of its orbit under the phase shift:
every hyperplane holding a flat element is the shift of one through such an ``a`` that holds no
flat element of an earlier orbit).  Cost: a stage visits at most ``C(F, j)`` chains of ``j`` later
flats at level ``j`` for ``F`` flat elements, each a vectorised pass over the elements; :func:`work` bounds
it before the search.
"""

from __future__ import annotations

import math
from typing import Sequence

import flint
import numpy as np

from ..arguments import check_public
from .hyperplane_screen import PASS, Screen, _hyperplanes, _labels, inverses


class Configuration:
    """Elements as mod-p generator images: ``rows`` (G x m), ``owner[k]`` the element of row ``k``
    (each element's rows consecutive, ordered as ``elements``), element weights ``weights``."""

    def __init__(self, rows: np.ndarray, owner: np.ndarray, elements: np.ndarray, weights: np.ndarray):
        self.rows, self.owner, self.elements, self.weights = rows, owner, elements, weights

    def select(self, keep: np.ndarray) -> "Configuration":
        """The elements ``keep`` (a subsequence of :attr:`elements`) with their rows."""
        mask = np.isin(self.owner, keep)
        return Configuration(self.rows[mask], self.owner[mask], keep, self.weights)

    def project(self, normals: np.ndarray, p: int) -> "Configuration":
        return Configuration(self.rows @ normals % p, self.owner, self.elements, self.weights)


def normals(rows: np.ndarray, p: int) -> np.ndarray:
    """A basis (m x k) of the vectors orthogonal mod p to ``rows`` (r x m): coordinates of the quotient
    ``F_p^m / span(rows)``."""
    null, nullity = flint.nmod_mat(rows.tolist(), p).nullspace()
    return np.array([[int(null[i, j]) for j in range(nullity)] for i in range(rows.shape[1])], dtype=np.int64)


def stage(config: Configuration, anchor_rows: np.ndarray, anchor: int, p: int, screen: Screen,
          base: Sequence[int], base_weight: float) -> None:
    """Offer to ``screen`` every hyperplane through the flat of ``anchor`` (its generator images
    ``anchor_rows``) with the elements of ``config`` it holds, and ``base`` (weight ``base_weight``:
    the elements in every hyperplane), as sets of element indices."""
    N = normals(anchor_rows, p)
    if N.shape[1] == 0:   # the element spans F_p^n: no hyperplane holds it
        return
    _search(config.project(N, p), [*base, anchor], base_weight + float(config.weights[anchor]), p, screen)


def points_only(config: Configuration, p: int, screen: Screen, base: Sequence[int], base_weight: float) -> None:
    """Offer the hyperplanes spanned by the elements of ``config`` (all of rank one mod p) with ``base``."""
    if len(config.elements):
        _search(config, list(base), base_weight, p, screen)


def _classify(config: Configuration, p: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per element of ``config``: rank 0 (every row zero), rank one (all nonzero rows on one projective
    point) or more.  Returns the zero elements, the rank-one elements with their point's class,
    the class representatives (none in a plane, where a class is its line key ``x / y``), and the
    flat elements (rank >= 2), each in the configuration's order."""
    rows = config.rows
    if rows.shape[1] == 2:   # one inverse per row, no sort of rows
        x, y = rows[:, 0], rows[:, 1]
        inv = inverses(np.where(y != 0, y, 1), p)
        label = np.where(y != 0, x * inv % p, np.where(x != 0, p, -1))
        reps = np.zeros((0, 2), dtype=np.int64)
    else:
        label, reps = _labels(rows, p)
    E = len(config.elements)
    at = np.searchsorted(config.elements, config.owner)
    big = np.iinfo(np.int64).max
    low = np.full(E, big)
    high = np.full(E, -1)
    np.minimum.at(low, at, np.where(label >= 0, label, big))
    np.maximum.at(high, at, label)
    zero, point, flat = high < 0, (high >= 0) & (low == high), (high >= 0) & (low != high)
    return config.elements[zero], config.elements[point], high[point], reps, config.elements[flat]


def _search(config: Configuration, base: list[int], base_weight: float, p: int, screen: Screen) -> None:
    """The hyperplanes of ``F_p^m`` (``m`` the rows' width) through a flat already holding the
    elements ``base`` (weight ``base_weight``), with the elements of ``config`` they hold."""
    w = config.weights
    zero, point, cls, reps, flat = _classify(config, p)
    base = base + zero.tolist()
    base_weight += float(w[zero].sum())
    m = config.rows.shape[1]
    if base_weight + float(w[point].sum()) + float(w[flat].sum()) < screen.bar:
        return
    if m <= 1:   # the hyperplane {0}: only the elements of rank 0
        screen.offer(base_weight, base)
        return
    order = np.argsort(cls, kind="stable")
    point, cls = point[order], cls[order]
    starts = np.flatnonzero(np.concatenate([[True], cls[1:] != cls[:-1]])) if len(cls) else np.zeros(0, dtype=np.int64)
    weights = np.add.reduceat(w[point], starts) if len(point) else np.zeros(0)
    members = np.split(point, starts[1:])
    if m == 2:   # lines: one per point class; the flat alone when no line holds an element
        for c in np.flatnonzero(base_weight + weights >= screen.bar):
            screen.offer(base_weight + float(weights[c]), base + members[c].tolist())
        if not len(point):
            screen.offer(base_weight, base)
        return
    # hyperplanes holding no flat element of this level: those of the points
    _hyperplanes(reps[cls[starts]], weights, np.arange(len(starts)), members, base, base_weight, p, screen,
                 len(starts))
    for i, f in enumerate(flat):
        later = flat[i + 1:]
        if base_weight + float(w[f]) + float(w[point].sum()) + float(w[later].sum()) < screen.bar:
            continue
        N = normals(config.rows[config.owner == f], p)
        if N.shape[1] == 0:
            continue
        keep = np.sort(np.concatenate([point, later]))
        _search(config.select(keep).project(N, p), base + [int(f)], base_weight + float(w[f]), p, screen)


#: incidences one search call at a plane costs beyond its rows: it offers lines and screens no points
#: (the ratio of a call's measured cost to one incidence's, on a planar tracker beside an
#: oscillator, diag(J_2(2), J_2(2), 2R(pi/3)), with 32 and 64 sensors: docs/performance.md)
CALL = 1_500


def work(n: int, ranks: Sequence[int], stages: int, elements: int) -> int:
    """An upper bound of the incidences (element rows projected, plus :data:`PASS` per call that
    screens points, :data:`CALL` per call at a plane) of ``stages`` stages over ``elements``
    elements in dimension ``n`` whose flat elements have the ranks ``ranks``.  A stage's quotient
    has dimension at most ``n - r`` (``r`` the least rank), and each level below it goes through a
    later flat element of rank at least 2 there, so a plane is reached after ``D = ceil((n - 2 - r)
    / 2)`` levels: at most ``C(F, j)`` calls at level ``j`` for ``F`` flat elements."""
    flats = [r for r in ranks if r >= 2]
    if not flats:
        return 0
    F, depth = len(flats), max(0, math.ceil((n - 2 - min(flats)) / 2))
    rows = elements * max(ranks)
    inner = stages * sum(math.comb(F, j) for j in range(depth))
    return inner * (PASS + rows) + stages * math.comb(F, depth) * (CALL + rows)


check_public(globals())
