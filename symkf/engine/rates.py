"""Decay rates of loss patterns and the M matrix (Sui-You-Fu eqs. 33-36, Theorem 9).

``rho_i = lim sup P(R_N(i))^(1/N)`` (eq. 36).  With ``g`` the block's projection period and
``H`` a maximal rank-deficient element set (a hyperplane, :mod:`symkf.engine.rows`), the rate
of "received only inside ``H``" is

* i.i.d. losses: ``prod_{(j, r) not in H} loss_j``, the probability that every element
  outside ``H`` is lost for a whole period;
* Markov losses (a first-order :class:`~symkf.model.loss.LossChain`): ``rho(M_H)``, ``M_H`` the
  one-period transfer matrix of the chain restricted to steps whose received elements lie in
  ``H``: the diagonal blocks ``E_ii`` of M for the maximal deficient patterns, so this is
  eq. (36) without building M.  It holds for aperiodic blocks as well (symkf's extension,
  docs/sui.md): an element received infinitely often spans its class projections, the other
  receptions are boundedly many and add polynomial factors only; with every class a single
  eigenvalue (rotations by irrational angles) ``g = 1`` and the decisive ``H`` is typically
  empty, the rate of the chain restricted to "everything lost".

A loss model's rate is computed from what it is, factor by factor (:class:`FactorRates`:
per independent factor, from the runs of its phases inside ``H``); :func:`hyperplane_rate` is
the engine's rate of one hyperplane, :func:`restricted_transfer` and :func:`perron_root` the
joint chain's reference.  Which hyperplane decides a block is the search's question
(:mod:`symkf.engine.search`).  The full M (eqs. 33-34) over (projected pattern, chain state) is
built only for checking ``P(R_{Ng}) = u M^N v`` (eq. 35) against enumeration.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any, Sequence

import flint
import numpy as np
import sympy as sp
from sympy.polys.matrices import DomainMatrix

from .. import budget
from ..arguments import check_public
from ..errors import AperiodicError
from ..exact import perron
from ..exact.numbers import sympify
from ..model.loss import Factor, LossModel, checked
from ..model.system import System
from .blocks import block_deficient, block_rows
from .rows import BlockRows


@dataclass(frozen=True)
class BlockRate:
    """``rho_i^g`` for one block: the exact value, the decisive hyperplane and the candidates compared
    exactly (under i.i.d. losses only the near-heaviest hyperplanes when :meth:`BlockRows.heaviest`
    applies, else one hyperplane per exponent vector; under Markov losses the hyperplanes whose
    float rate is within its proved error of the largest, :func:`markov_search`)."""

    per_period: sp.Expr
    hyperplane: frozenset[int]
    candidates: tuple[tuple[frozenset[int], sp.Expr], ...]


def perron_root(M: sp.MatrixBase) -> sp.Expr:
    """Spectral radius of a non-negative exact matrix (Perron-Frobenius: its largest real eigenvalue).

    Rational matrices go through :func:`symkf.exact.perron.perron_root` (sparse: strongly
    connected components, merged identical rows, flint characteristic polynomials)."""
    if M.shape == (1, 1):
        return sympify(M[0, 0])
    dm = DomainMatrix.from_Matrix(M).to_sparse()
    if dm.domain.is_QQ or dm.domain.is_ZZ:
        K = dm.domain
        rows = {r: {c: flint.fmpq(int(K.numer(v)), int(K.denom(v))) for c, v in row.items()}
                for r, row in dm.rep.items()}
    else:
        rows = {}
        for (r, c), v in M.todok().items():
            rows.setdefault(r, {})[c] = v
    return perron.perron_root(rows, M.shape[0]).exact


# -- restricted transfers per independent factor ----------------------------------------
_U = 2.0 ** -53  # unit roundoff of float64


class FactorRates:
    """Perron roots of one factor's one-period transfers restricted to phase patterns, cached.

    A pattern gives per phase ``r`` the mask of the factor's sensors whose element ``(j, r)``
    lies in ``H``; a state may be visited at phase ``r`` iff every sensor it receives is in the
    mask: ``M = prod_r P D_r`` (the phases in cyclic order; a rotation has the same spectrum).
    When one state ``z`` emits "everything lost" (a Gilbert-Elliott channel's lost state, the
    all-zero receival vector of a joint chain), ``D_r = e_z e_z^T`` at every phase with mask 0,
    so ``M`` is a product of rank-one factors and ``rho(M) = prod_segments e_z^T (prod_{r in
    segment} P D_r) P e_z``, one scalar per run of non-zero masks ("word") between consecutive
    zero masks: the probability of passing the run inside ``H`` from lost to lost.  Words are
    cached; for a Gilbert-Elliott channel a run of length ``m`` gives ``(P^(m+1))_(lost, lost)``.
    Rational chains compute in flint's ``fmpq`` (exact) with a float64 twin whose error is
    proved (:meth:`error`); other chains (several all-lost states, algebraic or symbolic
    probabilities, or a pattern without a zero mask) go through the exact transfer and
    :func:`perron_root`.
    """

    def __init__(self, factor: Factor, period: int):
        ch = factor.chain
        self.factor, self.g, self.S = factor, period, len(ch.states)
        self.received = [sum(1 << i for i, x in enumerate(v) if x) for v in ch.emit]
        lost = [s for s, m in enumerate(self.received) if m == 0]
        # the domain's elements, not sympy's: a lifted chain has hundreds of states, and indexing it
        # entry by entry as sympy Rationals would be a large share of a network stability call
        exact = DomainMatrix.from_Matrix(ch.P)
        self.rational = exact.domain.is_QQ or exact.domain.is_ZZ
        self.z = lost[0] if len(lost) == 1 else None
        self.P, self.Pf = ch.P, None
        if self.rational:
            self.P, self.Pf = flint.fmpq_mat(self.S, self.S), np.zeros((self.S, self.S))
            for (i, j), v in exact.to_sparse().to_dok().items():  # lifted chains are sparse
                p, q = int(v.numerator), int(v.denominator)
                self.P[i, j], self.Pf[i, j] = flint.fmpq(p, q), p / q
        self._words: dict[tuple[int, ...], tuple[Any, float]] = {}
        self._patterns: dict[tuple[int, ...], Any] = {}  # patterns without a zero mask
        self._blocks: dict[tuple[int, int], Any] = {}  # P from the states allowed by one mask to the next's

    @property
    def screened(self) -> bool:
        """Whether rates come as exact rationals with a proved float twin (the segment form)."""
        return self.rational and self.z is not None

    def _word(self, word: tuple[int, ...]) -> tuple[Any, float]:
        hit = self._words.get(word)
        if hit is None:
            z, S = self.z, self.S
            if self.rational:
                row = flint.fmpq_mat(1, S, [1 if s == z else 0 for s in range(S)])
                rowf = np.zeros(S)
                rowf[z] = 1.0
                for m in word:
                    keep = [s for s in range(S) if self.received[s] & ~m == 0]
                    row, rowf = row * self.P, rowf @ self.Pf
                    row = flint.fmpq_mat(1, S, [row[0, s] if s in keep else 0 for s in range(S)])
                    rowf = np.where(np.isin(np.arange(S), keep), rowf, 0.0)
                exact, value = (row * self.P)[0, z], float(rowf @ self.Pf[:, z])
            else:
                row = sp.Matrix([[1 if s == z else 0 for s in range(S)]])
                for m in word:
                    row = (row * self.P).applyfunc(sp.expand)
                    row = sp.Matrix([[row[s] if self.received[s] & ~m == 0 else 0 for s in range(S)]])
                exact, value = sp.expand((row * self.P)[z]), np.nan
            hit = self._words[word] = (exact, np.log(value) if value > 0 else -np.inf)
        return hit

    def runs(self, masks: dict[int, int]) -> list[tuple[int, ...]] | None:
        """The words (runs of non-zero masks, cyclically) of a pattern given by its non-zero
        masks ``{phase: mask}``; None when no mask is zero (or no single all-lost state)."""
        return self._runs(masks)

    def _runs(self, masks: dict[int, int]) -> list[tuple[int, ...]] | None:  # unchecked: per hyperplane
        if self.z is None or len(masks) == self.g:
            return None
        out = []
        for p in masks:
            if (p - 1) % self.g not in masks:
                word, q = [], p
                while q in masks:
                    word.append(masks[q])
                    q = (q + 1) % self.g
                out.append(tuple(word))
        return out

    def log_rate(self, masks: dict[int, int]) -> float:
        """``log rho(M)`` in float64 (NaN without a twin); error at most :meth:`error` of its
        ``g - len(masks)`` words."""
        if not self.rational:
            return np.nan
        runs = self._runs(masks)
        if runs is None:
            rate = self.rate(masks)
            return float(np.log(_to_float(rate))) if rate else -np.inf
        return (self.g - len(masks) - len(runs)) * self._word(())[1] + sum(self._word(w)[1] for w in runs)

    def rate(self, masks: dict[int, int]) -> Any:
        """``rho(M)`` exactly (``fmpq`` for rational chains, else sympy) of the pattern given by
        its non-zero masks ``{phase: mask}``."""
        runs = self._runs(masks)
        if runs is not None:
            out = self._word(())[0] ** (self.g - len(masks) - len(runs))
            for w in runs:
                out *= self._word(w)[0]
            return out if self.rational else sp.expand(out)
        pattern = tuple(masks.get(r, 0) for r in range(self.g))
        hit = self._patterns.get(pattern)
        if hit is None:
            if all(self.received[s] & ~m == 0 for m in pattern for s in range(self.S)):  # P^g: stochastic
                hit = flint.fmpq(1) if self.rational else sp.Integer(1)
            elif self.rational:
                rho = perron.perron_root(*self._rational_transfer(pattern)).exact
                hit = flint.fmpq(int(rho.p), int(rho.q)) if rho.is_Rational else rho
            else:
                rho = perron_root(self.transfer(pattern))
                hit = flint.fmpq(int(rho.p), int(rho.q)) if self.rational and rho.is_Rational else rho
            self._patterns[pattern] = hit
        return hit

    def _rational_transfer(self, pattern: tuple[int, ...]) -> tuple[dict[int, dict[int, flint.fmpq]], int]:
        """A matrix with the Perron root of :meth:`transfer` for a rational chain, in flint, and its
        size: ``M = prod_r P D_r`` has the non-zero spectrum of ``D_0 M D_0``, which lives on the
        states ``A_r`` allowed at each phase: the product of the blocks ``P[A_(r-1), A_r]`` (cached per
        pair of masks), ``|A_0|`` square.  Few states are allowed under a mask of few sensors: a
        256-state chain's full products took 0.7 CPU-s a pattern, sympy's sparse ones of a 64-state
        chain 0.6.  Given as the rows of its non-zero entries (:func:`symkf.exact.perron.perron_root`)."""
        g = self.g
        allowed = {m: [s for s in range(self.S) if self.received[s] & ~m == 0] for m in set(pattern)}
        first = allowed[pattern[0]]
        M = flint.fmpq_mat(len(first), len(first), [int(i == j) for i in range(len(first)) for j in range(len(first))])
        for phase in range(1, g + 1):
            key = (pattern[phase - 1], pattern[phase % g])
            if key not in self._blocks:
                rows, cols = allowed[key[0]], allowed[key[1]]
                self._blocks[key] = flint.fmpq_mat(len(rows), len(cols), [self.P[i, j] for i in rows for j in cols])
            M = M * self._blocks[key]
        n = len(first)
        return {i: row for i in range(n) if (row := {j: M[i, j] for j in range(n) if M[i, j] != 0})}, n

    def transfer(self, pattern: tuple[int, ...]) -> sp.Matrix:
        """The exact one-period transfer ``prod_r P D_r`` (sparse: lifted chains have hundreds of states)."""
        ch = self.factor.chain
        P = DomainMatrix.from_Matrix(ch.P).to_sparse()
        K = P.domain
        M = DomainMatrix.eye(self.S, K).to_sparse()
        for r in range(1, self.g + 1):
            m = pattern[r % self.g]
            D = DomainMatrix.diag([K.one if self.received[s] & ~m == 0 else K.zero for s in range(self.S)], K)
            M = M * P * D.to_sparse()
        return M.to_Matrix()

    def error(self, terms: int) -> float:
        """A bound on ``|log rho - float log|`` summed over ``terms`` words: a word is a sum of
        products of at most ``g + 1`` entries of P, all non-negative, so its float value has
        relative error at most ``gamma_k = k u / (1 - k u)`` with ``k = (g + 1)(S + 1)`` (each
        entry rounded once, each dot product of S terms), the log adds ``u |log|``, and the sum
        of ``terms`` logs ``terms u`` times their magnitude (at most ``-log`` of the least word)."""
        k = (self.g + 1) * (self.S + 1)
        gamma = k * _U / (1 - k * _U)
        return terms * (2 * gamma + 4 * _U * (1 + self.g * (1 + abs(np.log(max(self.Pf.min(initial=1.0), 1e-300))))))

    def gain_bound(self, elements: int, longest: int | None = None) -> tuple[float, list[float]]:
        """``(C, b)`` with ``log rho(M) <= C + sum_(elements (j, r) inside) b[j]`` for every pattern,
        ``b >= 0``: of three proved bounds (floats rounded outwards) the least at ``elements``
        elements inside.  With ``a_l = (P^l)_(z, z)``, a word of length ``l - 1`` is at most
        ``a_l`` (``D_r <= I``); ``n`` phases with a non-zero mask hold at least ``n`` elements.
        ``longest``: the longest word (run of non-zero masks) of the patterns bounded, when the
        caller knows one below ``g`` (a hyperplane holds at most ``n - 1`` consecutive phases of a
        sensor: :meth:`symkf.engine.rows.BlockRows.longest_run`); None: any.

        * Lost runs: ``rho(M) <= c^(g - n)``, ``c = max_(l <= g) a_l``: ``C = g log c``,
          ``b_j = -log c``.
        * Run lengths: ``rho(M) <= prod_segments a_l <= a_1^g kappa^n`` with ``kappa`` the largest
          of ``(a_l / a_1^l)^(1/(l - 1))`` over the words' lengths ``l - 1 <= longest`` and, unless
          ``longest < g`` (then every pattern has a zero mask), ``1 / a_1`` (no zero mask: ``rho <=
          1``): ``C = g log a_1``, ``b_j = log kappa``.  On a Gilbert-Elliott channel (fail 1/10,
          recover 1/2) ``kappa`` is 2 for any lengths, 1.61 for words of at most 5.
        * Row sums: ``rho(M) <= ||M||_inf <= prod_r mu(m_r)`` with ``mu(m) = max_s sum_(t allowed
          by m) P_(s, t)``, and ``log mu(m) <= log mu(0) + sum_(j in m) b_j`` with ``b_j`` the
          largest increase of ``log mu`` from adding ``j`` to a mask (telescoping).
        """
        pad, k, g = 1 + 4 * self.error(1), len(self.factor.sensors), self.g
        a, Pl = [], np.eye(self.S)
        for _ in range(g):
            Pl = Pl @ self.Pf
            a.append(min(1.0, Pl[self.z, self.z] * pad))
        allowed = np.array([[self.received[t] & ~m == 0 for m in range(1 << k)] for t in range(self.S)], dtype=float)
        mu = np.minimum(1.0, pad * (self.Pf @ allowed).max(axis=0)).tolist()   # per mask, the largest row sum
        if min(a[0], min(mu)) <= 0:
            return -np.inf, [np.inf] * k
        a1 = a[0] / pad ** 2
        # a1^l may fall below float64 (g = 3465): kappa is then inf, and its bound is never the least
        short = longest is not None and longest < g
        with np.errstate(over="ignore", divide="ignore"):
            kappa = max(([] if short else [1 / a1]) + [(a[l - 1] / a1 ** l) ** (1 / (l - 1))
                                                       for l in range(2, (longest + 2) if short else g + 1)],
                        default=1.0) * pad
        rows = [max(np.log(mu[m]) - np.log(mu[m & ~(1 << j)]) for m in range(1 << k) if m >> j & 1) * pad
                for j in range(k)]
        bounds = [(g * np.log(max(a)), [-np.log(max(a))] * k), (g * np.log(a1), [np.log(kappa)] * k),
                  (g * np.log(mu[0]), rows)]
        return min(bounds, key=lambda cb: cb[0] + elements * max(cb[1]))


def factor_rates(br: BlockRows, loss: LossModel) -> tuple[FactorRates, ...]:
    """One :class:`FactorRates` per independent factor of ``loss`` for the block's period."""
    return tuple(FactorRates(f, br.class_period) for f in loss.factors)


class Patterns:
    """The phase patterns of hyperplanes, per factor: ``{phase: mask}`` of its non-zero masks."""

    def __init__(self, br: BlockRows, rates: Sequence[FactorRates]):
        self.g, self.rates = br.class_period, rates
        where = {j: (f, i) for f, r in enumerate(rates) for i, j in enumerate(r.factor.sensors)}
        self.of = [(where[e.sensor][0], 1 << where[e.sensor][1], e.phase) for e in br.elements]
        self.word_error = 2 * max(r.error(1) for r in rates) if all(r.screened for r in rates) else np.nan

    def of_set(self, H) -> list[dict[int, int]]:
        masks: list[dict[int, int]] = [{} for _ in self.rates]
        for e in H:
            f, bit, phase = self.of[e]
            masks[f][phase] = masks[f].get(phase, 0) | bit
        return masks

    def log_rate(self, H) -> tuple[float, float]:
        """``log rho(M_H)`` in float64 and a proved bound on its error (NaN without twins)."""
        masks = self.of_set(H)
        log = sum(r.log_rate(m) for r, m in zip(self.rates, masks))
        return log, self.word_error * (1 + sum(self.g - len(m) for m in masks))

    def rate(self, H) -> Any:
        out = 1
        for r, m in zip(self.rates, self.of_set(H)):
            out = out * r.rate(m)
        return out


def _to_float(value: Any) -> float:
    """float64 of an exact rate (python-flint 0.7's ``fmpq`` has no ``__float__``; the integer
    quotient is correctly rounded)."""
    return int(value.p) / int(value.q) if isinstance(value, flint.fmpq) else float(value)


def exact_rate(value: Any) -> sp.Expr:
    """A rate of :class:`FactorRates` (a flint rational or a sympy expression) as a sympy value."""
    return sp.Rational(int(value.p), int(value.q)) if isinstance(value, flint.fmpq) else sympify(value)


def hyperplane_rate(br: BlockRows, H: frozenset[int], loss: LossModel) -> sp.Expr:
    """``rho(M_H)`` (Sui-You-Fu eq. 36), the decay rate per period of "received only inside ``H``",
    as the engine computes it: per independent factor of ``loss`` from its runs of phases inside
    ``H`` (:class:`FactorRates`), the factors' rates multiplied. For i.i.d. sensors this is
    ``prod_j loss_j^(k_j)`` (``k_j`` sensor ``j``'s elements outside ``H``); for Gilbert-Elliott
    channels the product of the sensors' 2x2 restricted transfers' Perron roots, a polynomial in
    (fail, recover); a sensor entirely inside ``H`` has rate 1."""
    key = ("hyperplane_rates", id(loss))
    cache = br.__dict__.setdefault("_rates", {})
    if cache.get(key, (None,))[0] is not loss:
        cache[key] = (loss, Patterns(br, factor_rates(br, loss)))
    return sp.expand(exact_rate(cache[key][1].rate(H)))


def _aperiodic(br: BlockRows) -> AperiodicError:
    return AperiodicError(f"the eigen-block of modulus {br.block.modulus} is aperiodic ({br.block.proof})",
                          assumption="eq. (35) (Sui-You-Fu): M over projected patterns needs a periodic block",
                          applies_instead="symkf.engine.search.block_rate, which decides aperiodic blocks")


def _el(br: BlockRows, j: int, phase: int):
    return br.elements[j * br.class_period + phase]


def restricted_transfer(br: BlockRows, H: frozenset[int], loss: LossModel) -> sp.Matrix:
    """One-period transfer of the loss chain restricted to steps received inside ``H``."""
    rates = FactorRates(Factor(tuple(range(loss.d)), loss.chain), br.class_period)
    masks = Patterns(br, [rates]).of_set(H)[0]
    return rates.transfer(tuple(masks.get(r, 0) for r in range(br.class_period)))


# -- the full M matrix and brute force ------------------------------------------------


def m_matrix(br: BlockRows, loss: LossModel) -> tuple[sp.Matrix, list]:
    """M (eqs. 33-34) over (deficient projected pattern, chain state); column convention.

    State ``(frozenset(), None)`` is the start (before time 0).  ``P(R_{Ng}(i)) =
    sum of M^N`` applied to the start vector (eq. 35).
    """
    if not br.block.is_periodic:
        raise _aperiodic(br)
    ch = loss.chain
    S = len(ch.states)
    start = (frozenset(), None)
    index = {start: 0}
    order = [start]
    cols: dict[tuple, dict[tuple, sp.Expr]] = {}
    frontier = [start]
    while frontier:
        state = frontier.pop()
        dist = {state: sp.Integer(1)}
        for phase in range(br.class_period):
            nxt: dict[tuple, sp.Expr] = {}
            for (pat, x), p in dist.items():
                row = ch.initial.row(0) if x is None else ch.P.row(x)
                for y in range(S):
                    if row[y] == 0:
                        continue
                    new = pat | {br.elements.index(_el(br, j, phase)) for j, g in enumerate(ch.emit[y]) if g}
                    new = frozenset(new)
                    if br.deficient(new):
                        key = (new, y)
                        nxt[key] = nxt.get(key, 0) + p * row[y]
            dist = nxt
        cols[state] = dist
        for key in dist:
            if key not in index:
                index[key] = len(order)
                order.append(key)
                frontier.append(key)
    M = sp.zeros(len(order), len(order))
    for src, dist in cols.items():
        for dst, p in dist.items():
            M[index[dst], index[src]] += p
    return M, order


def probability_rank_deficient(system: System, loss: LossModel, N: int) -> tuple[sp.Expr, ...]:
    """``P(R_N(i))`` per eigen-block by enumerating all ``2^(dN)`` receival patterns (brute force)."""
    loss = checked(loss, system)
    budget.check_power("max_patterns", 2, loss.d * N, "N", "the number of receival patterns 2^(d N) to "
                       "enumerate (m_matrix computes the same probabilities without enumerating)")
    totals = [sp.Integer(0)] * len(block_rows(system))
    for pattern in itertools.product(itertools.product((1, 0), repeat=loss.d), repeat=N):
        flags = block_deficient(system, pattern) if N else (True,) * len(totals)
        if any(flags):
            p = loss.sequence_probability(pattern)
            totals = [t + p if f else t for t, f in zip(totals, flags)]
    return tuple(sympify(sp.expand(t)) for t in totals)


check_public(globals())
