"""An oracle for rank deficiency of the regression matrix that shares no code with the engine.

The engine decides ``P(R_N)`` through the modal form, eigen-blocks, generators
and hyperplanes (:mod:`symkf.exact.spectral`, :mod:`symkf.engine.rows`,
:mod:`symkf.engine.rates`).  A wrong modal form would mislead every one of them, and
the engine's own brute force (``observability.block_deficient``) reuses it.
This module checks the engine from the raw data only:

* the rows ``C_j A^k`` of ``O_N = col(C_j A^k : (j, k) received)`` (Sui-You-Fu
  eq. 14) are computed straight from ``A`` and the ``C_j`` over the field of
  their entries (sympy's ``construct_domain(..., extension=True)`` and
  ``DomainMatrix`` ranks; nothing from :mod:`symkf.exact`);
* ``O_N`` restricted to a subspace ``V`` (columns of ``U``) is ``O_N U``; with
  ``V`` the unstable-or-marginal generalized eigenspace, which the caller
  supplies from its own construction of ``A``, rank deficiency of ``O_N U`` is
  the event that the unstable part is not determined by the received rows;
* the received sets ``D`` of pairs ``(k, j)`` with ``O_N U`` rank deficient
  are enumerated by depth-first search (deficiency is inherited by subsets, so
  the search stops at the first full-rank set);
* from them: ``P(O_N U deficient)`` under any probability of receival
  patterns, and, for losses ``eps_j = x^(w_j)``, the least total weight
  ``L(N)`` of the lost pairs of a deficient pattern.  ``P = x^(L(N))`` times a
  polynomial, and the engine's decay rate ``rho = x^e`` predicts the slope
  ``L(N + G) - L(N) = G e`` once ``N`` is large.

The oracle sees the whole ``O_N U``.  In modal coordinates its columns split by
eigen-block, and it is deficient if some block's columns are, or if full-rank
blocks share a column direction; the latter needs rows that the blocks'
different moduli and frequencies separate after boundedly many receptions, so
the whole matrix decays at the slowest block rate ``max_i rho_i``.  For one
unstable block this is that block's ``rho``; for several, the oracle witnesses
``max_i rho_i``, not the weighted margins ``alpha_i^2 rho_i``.
"""

from __future__ import annotations

from functools import cached_property
from typing import Any, Callable, Iterator, Sequence

import sympy as sp
from sympy.polys.constructor import construct_domain
from sympy.polys.matrices import DomainMatrix

from ..arguments import check_public
from .. import budget
from ..errors import InputError
from ..exact.numbers import sympify, to_exact_matrix

Pair = tuple[int, int]  # (time k, sensor j)


class RawRegression:
    """The rows ``C_j A^k U`` for ``k < N`` over the field of the entries of ``A``, ``C_j``, ``U``."""

    def __init__(self, A: Any, Cs: Sequence[Any], N: int, subspace: Any = None):
        A = sp.Matrix(to_exact_matrix(A, "A"))
        Cs = [sp.Matrix(to_exact_matrix(C, f"Cs[{j}]")) for j, C in enumerate(Cs)]
        n = A.shape[0]
        U = sp.eye(n) if subspace is None else sp.Matrix(to_exact_matrix(subspace, "subspace"))
        entries = [*A, *U, *(v for C in Cs for v in C)]
        K, values = construct_domain(entries, extension=True)
        it = iter(values)

        def take(rows: int, cols: int) -> DomainMatrix:
            return DomainMatrix([[next(it) for _ in range(cols)] for _ in range(rows)], (rows, cols), K)
        Ad, Ud = take(n, n), take(n, U.shape[1])
        Cds = [take(C.shape[0], n) for C in Cs]
        self.K, self.N, self.r, self.d = K, N, U.shape[1], len(Cs)
        self.rows: dict[Pair, list[list[Any]]] = {}
        power = Ud  # A^k U
        for k in range(N):
            for j, C in enumerate(Cds):
                self.rows[(k, j)] = (C * power).to_list()
            power = Ad * power

    def rank(self, received: Sequence[Pair]) -> int:
        """Rank of ``O_N U`` for the received pairs."""
        received = [tuple(p) for p in received]
        unknown = [p for p in received if p not in self.rows]
        if unknown:
            raise InputError(f"received: {unknown[0]!r} is not a pair (k, j) with k < N = {self.N} and a sensor j")
        rows = [row for p in received for row in self.rows[p]]
        if not rows:
            return 0
        return DomainMatrix(rows, (len(rows), self.r), self.K).rank()

    @cached_property
    def deficient_sets(self) -> tuple[frozenset[Pair], ...]:
        """Every received set ``D`` (pairs ``(k, j)``, ``k < N``) with ``O_N U`` rank deficient."""
        return tuple(self._search([], 0))

    def _search(self, chosen: list[Pair], start: int) -> Iterator[frozenset[Pair]]:
        yield frozenset(chosen)
        pairs = list(self.rows)
        for i in range(start, len(pairs)):
            trial = chosen + [pairs[i]]
            if self.rank(trial) < self.r:
                yield from self._search(trial, i + 1)

    def probability(self, pattern_probability: Callable[[list[list[int]]], Any]) -> sp.Expr:
        """``P(O_N U deficient)``: the sum of ``pattern_probability`` over deficient patterns.

        ``pattern_probability`` takes the receival vectors ``gamma_k`` (N lists of d 0/1)."""
        total = sp.Integer(0)
        for D in self.deficient_sets:
            total += pattern_probability([[1 if (k, j) in D else 0 for j in range(self.d)] for k in range(self.N)])
        return sp.expand(total)

    def least_lost_weight(self, weights: Sequence[int]) -> int:
        """``L(N)``: the least total weight ``sum w_j`` of the lost pairs of a deficient pattern."""
        if len(weights) != self.d or not all(isinstance(w, int) and not isinstance(w, bool) and w >= 0 for w in weights):
            raise InputError(f"weights: expected {self.d} integers >= 0, one per sensor")
        full = self.N * sum(weights)
        return full - max(sum(weights[j] for _, j in D) for D in self.deficient_sets)


def iid_probability(loss: Sequence[Any]) -> Callable[[list[list[int]]], sp.Expr]:
    """The probability of a receival pattern under independent losses ``loss[j]`` (Assumption 4)."""
    budget.check("max_sensors", len(loss), "loss", "the number of sensors")   # before a loss is read
    eps = [sympify(e, f"loss[{j}]") for j, e in enumerate(loss)]

    def prob(pattern: list[list[int]]) -> sp.Expr:
        return sp.Mul(*[(1 - e) if g else e for vec in pattern for g, e in zip(vec, eps)])
    return prob


def decay_slope(A: Any, Cs: Sequence[Any], weights: Sequence[int], N: int, G: int,
                subspace: Any = None) -> tuple[int, int]:
    """``(L(N + G) - L(N), L(N + 2G) - L(N + G))`` for losses ``eps_j = x^(w_j)``.

    Equal values ``s`` witness a decay rate ``x^(s/G)`` of ``P(O_N U deficient)`` per step."""
    L = [RawRegression(A, Cs, N + t * G, subspace).least_lost_weight(weights) for t in range(3)]
    return L[1] - L[0], L[2] - L[1]

check_public(globals())
