"""Decay rates of P(R_N(i)) and the M matrix (Sui-You-Fu eqs. 33-36, Theorem 9).

``rho_i = lim sup P(R_N(i))^(1/N)`` (eq. 36).  With ``g`` the block's
projection period and ``H`` ranging over the maximal rank-deficient element
sets (hyperplanes, :mod:`symkf.engine.rows`):

* i.i.d. losses: ``rho_i^g = max_H prod_{(j, r) not in H} loss_j`` -- the
  probability that every element outside ``H`` is lost for a whole period;
* Markov losses (a first-order :class:`~symkf.model.loss.LossChain`):
  ``rho_i^g = max_H rho(M_H)`` with ``M_H`` the one-period transfer matrix of
  the chain restricted to steps whose received elements lie in ``H``; these
  are the diagonal blocks ``E_ii`` of M for the maximal deficient patterns, so
  this is eq. (36) without building M.  It holds for aperiodic blocks as well
  (symkf's extension, docs/sui.md): an element received infinitely often spans
  its class projections, the other receptions are boundedly many and add
  polynomial factors only; with every class a single eigenvalue (rotations by
  irrational angles) ``g = 1`` and the decisive ``H`` is typically empty, the
  rate of the chain restricted to "everything lost".

Neither maximum lists every hyperplane when a screen applies: :func:`outside_counts` (i.i.d.),
:func:`markov_search` (Markov losses, per independent factor of the model) and
:func:`least_iid_bound` (critical loss rates along a ray or of one sensor) reduce them to
:meth:`~symkf.engine.rows.BlockRows.heaviest`, each with its no-miss argument.

The full M (eqs. 33-34) over (projected pattern, chain state) is built only
for checking ``P(R_{Ng}) = u M^N v`` (eq. 35) against enumeration.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import flint
import numpy as np  # outside counts from BlockRows.inside
import sympy as sp
from sympy.polys.matrices import DomainMatrix

from .. import budget
from . import generic_hyperplanes
from ..errors import AperiodicError, InputError
from ..exact import perron
from ..exact.algebraic import AlgebraicNumber
from ..arguments import check_public
from ..exact.numbers import sympify
from ..model.gilbert_elliott import GilbertElliott
from ..model.loss import Factor, LossModel, checked
from ..model.system import System
from .rows import BlockRows, _set
from .blocks import block_deficient
from .blocks import block_rows


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


def _el(br: BlockRows, j: int, phase: int):
    return br.elements[j * br.class_period + phase]


def outside_counts(br: BlockRows, weights: Sequence[float] | None = None) -> dict[tuple[int, ...], frozenset[int]]:
    """Per distinct exponent vector ``(k_1, ..., k_d)`` -- the number of sensor ``j``'s elements
    outside a hyperplane ``H`` -- one such ``H``.  Under i.i.d. losses ``H`` decays at
    ``prod_j loss_j^(k_j)`` per period, so hyperplanes sharing a vector are interchangeable.

    ``weights`` (per sensor, floats >= 0): only the hyperplanes that may maximise ``sum_{e in H}
    weights[sensor e]`` (:meth:`BlockRows.heaviest`), which is all a caller minimising ``prod_j
    c_j^(k_j)`` with ``c_j = exp(-weights[j])`` needs; every hyperplane when the screen does not
    apply or every hyperplane is already known (cached: counting is then cheaper than the
    screen).  The screen's sets in lexicographic order keep the enumeration's tie-break (the
    first maximiser)."""
    if weights is not None and "inside" not in br.__dict__:
        heaviest = br.heaviest([weights[e.sensor] for e in br.elements])
        if heaviest is not None:
            return _outside_vectors(br, sorted(heaviest, key=sorted))
    return _outside_vectors(br, listed_hyperplanes(br))


def listed_hyperplanes(br: BlockRows) -> np.ndarray | list[frozenset[int]]:
    """Every hyperplane: with elements of several generators the search through their flats at
    floor 0 (:meth:`BlockRows.heaviest`, refused up front by its work estimate; index sets in
    lexicographic order), else :attr:`BlockRows.inside`, refused up front when their estimated
    number (:meth:`BlockRows.listing_estimate`) exceeds ``budget.Limits.max_hyperplanes``."""
    if br.several_generators and "inside" not in br.__dict__:
        sets = br.heaviest([0.0] * len(br.elements), floor=0.0)
        if sets is not None:
            return sorted(sets, key=sorted)
    if "inside" not in br.__dict__ and br.size > 1:
        estimate, formula = br.listing_estimate()
        if estimate > budget.LIMITS.max_hyperplanes:  # the modulus named only then
            budget.check("max_hyperplanes", estimate, f"eigen-block of modulus {br.block.modulus}",
                         f"the estimated number of hyperplanes to list ({formula}; no screen applies)")
    return br.inside


def capped_hyperplanes(br: BlockRows) -> tuple[frozenset[int], ...]:
    """Every hyperplane as index sets, by :func:`listed_hyperplanes` (refused up front as it is)."""
    listed = listed_hyperplanes(br)
    return br.hyperplanes if isinstance(listed, np.ndarray) else tuple(listed)


def _outside_vectors(br: BlockRows, inside) -> dict[tuple[int, ...], frozenset[int]]:
    """:func:`outside_counts` of the hyperplanes ``inside`` (boolean rows or index sets, in
    lexicographic order: the first hyperplane of each vector is kept)."""
    if not isinstance(inside, np.ndarray):
        rows = np.zeros((len(inside), len(br.elements)), dtype=bool)
        for h, H in enumerate(inside):
            rows[h, list(H)] = True
        inside = rows
    sensor = np.array([e.sensor for e in br.elements])
    per_sensor = (sensor[:, None] == np.arange(sensor.max() + 1)).astype(np.int64)  # elements x d
    outside = (~inside).astype(np.int64) @ per_sensor                               # hyperplanes x d
    _, first = np.unique(outside, axis=0, return_index=True)
    return {tuple(outside[h].tolist()): _set(inside[h]) for h in sorted(first.tolist())}


def _weights(loss: LossModel) -> list[float] | None:
    """``-log loss_j`` per sensor of i.i.d. losses: the slowest-decaying hyperplane maximises ``sum_{e
    in H} -log loss_(sensor e)``; None when a loss is 0 or symbolic (then every hyperplane is compared)."""
    if loss.symbols or any(e == 0 for e in loss.bernoulli):
        return None
    return [-float(sp.log(e).evalf(20)) for e in loss.bernoulli]


def block_rate(br: BlockRows, loss: LossModel) -> BlockRate:
    """``rho_i^g`` (per projection period) for one block, exactly (eq. 36).

    i.i.d. losses: the heaviest hyperplanes (:func:`outside_counts`).  Markov losses: the
    product over the model's independent factors of their restricted transfers' Perron roots,
    maximised by :func:`markov_search` (aperiodic blocks too: their elements' generators are
    class projections, docs/sui.md)."""
    if loss.bernoulli is not None:   # i.i.d.: the rate depends on the exponent vector only
        counts = outside_counts(br, _weights(loss))
        cands = [(H, sp.Mul(*[e ** k for e, k in zip(loss.bernoulli, ks)])) for ks, H in counts.items()]
        H, best = _maximum(cands)
        return BlockRate(best, H, tuple(cands))
    if loss.symbols:
        raise _symbolic()
    return markov_search(br, factor_rates(br, loss))


def _symbolic() -> InputError:
    return InputError("loss: symbolic loss parameters have no numeric decay rate; "
                      "use symkf.stability_conditions for the stability region as conditions")


def _maximum(candidates: list[tuple[frozenset[int], sp.Expr]]) -> tuple[frozenset[int], sp.Expr]:
    if any(v.free_symbols for _, v in candidates):
        raise _symbolic()
    return max(candidates, key=lambda hv: AlgebraicNumber.from_expr(hv[1]))


def least_iid_bound(br: BlockRows, losses: Callable[[AlgebraicNumber], Sequence[sp.Expr]],
                    bound: Callable[[tuple[int, ...]], Any], start: AlgebraicNumber,
                    growth: sp.Expr, least: Callable[[list], AlgebraicNumber],
                    safe: AlgebraicNumber | None = None) -> AlgebraicNumber | None:
    """``min(start, min_H x_H)`` without listing every hyperplane, or None when the screen
    declines (then list them: :func:`outside_counts`).

    ``losses(x)`` are the i.i.d. losses at the parameter ``x`` (each non-decreasing in ``x``, at
    most 1 up to ``safe``, default ``start``); ``bound(k)`` is ``x_H`` for a hyperplane whose
    exponent vector is ``k``: the ``x`` at which its margin ``growth * prod_j loss_j(x)^(k_j)``
    reaches 1 (None when it never does), in any form that ``least`` takes: ``least(bounds)`` is
    their least value, or ``start`` when none is below it (the caller's, which may compare
    certified balls before making any value exact: an exact root of high degree is costly, and
    there may be hundreds).

    Why no hyperplane is missed.  With weights ``w_e(x) = -log loss_(sensor e)(x)`` the margin of
    ``H`` is ``log growth - T(x) + sum_(e in H) w_e(x)`` (``T`` the total weight of the elements
    with a generator; the others lie in every hyperplane), and it increases with ``x``; so ``x_H
    <= x`` iff that margin is ``>= 0`` at ``x``, i.e. iff ``H`` weighs at least ``T(x) - log
    growth``.  Take ``x`` = the least ``x_H`` over a few hyperplanes spanned by the heaviest
    generators (:meth:`BlockRows.spanned`; exact) or, when none lies below ``start``, one step of
    Dinkelbach's iteration at ``safe`` (the heaviest hyperplanes there: their least ``x_H``, or
    ``start`` when none lies below it, is an upper bound of the answer).  Then ``heaviest(w(x),
    floor=T(x) - log growth)`` returns every hyperplane with ``x_H <= x`` (its no-miss argument
    for a floor), and the least of their ``x_H`` is the minimum: one screen when the guess is
    good.  Weights the screen cannot take directly are made admissible without losing a set:

    * a loss of 0 (weight infinite): the weight ``B = T_finite + |log growth| + 1``.  A hyperplane
      missing such an element has rate 0 and never binds; one holding all ``Z`` of them weighs
      ``Z B`` plus its finite weight, and every set missing one weighs less than ``Z B``, so the
      floor ``Z B + T_finite - log growth`` keeps exactly the hyperplanes that may bind (and the
      heaviest hold them all when any does);
    * a loss above 1 (``x`` above ``safe``, weight negative): every weight is raised by ``c``, the
      most negative's size; a hyperplane holds at least ``n - 1`` elements with a generator (it has
      rank ``n - 1``), so its raised weight is at least its weight plus ``c (n - 1)``, and the
      floor raised by ``c (n - 1)`` still keeps it (with more sets, rated exactly and discarded).

    Declines (None) when a loss is symbolic or the screen does not apply."""
    live = br.live
    log_growth = float(sp.log(growth).evalf(20))

    def weights(x: AlgebraicNumber) -> tuple[list[float], float, float] | None:
        """The admissible weights at ``x``, the floor of the hyperplanes binding at ``x`` and the
        raise ``c`` (above)."""
        values = [sympify(v) for v in losses(x)]
        if any(v.free_symbols or not v.is_real or v < 0 for v in values):
            return None
        raw = [np.inf if v == 0 else -float(sp.log(v).evalf(20)) for v in values]
        finite = [raw[br.elements[e].sensor] for e in live if raw[br.elements[e].sensor] < np.inf]
        zeros = len(live) - len(finite)
        c = max(0.0, -min(finite, default=0.0))
        big = 2 * sum(v + c for v in finite) + abs(sum(finite)) + 2 * abs(log_growth) + 1
        w = [big if raw[e.sensor] == np.inf else raw[e.sensor] + c for e in br.elements]
        return w, sum(finite) - log_growth + zeros * big + c * max(0, br.size - 1 - zeros), c

    def least_of(sets) -> AlgebraicNumber | None:
        found = [b for b in (bound(ks) for ks in _outside_vectors(br, sorted(sets, key=sorted))) if b is not None]
        return least(found) if found else None

    at = start if safe is None or not safe < start else safe
    first = weights(start)
    if first is None:
        return None
    x = least_of(br.spanned(first[0]))
    if x is None or not x < start:
        step = weights(at)
        if step is None or step[2] > 0:   # Dinkelbach needs losses <= 1: the heaviest bind first
            return None
        sets = br.heaviest(step[0])
        if sets is None:
            return None
        x = least_of(sets)
        if x is None or not x < start:
            if at == start:   # every margin is at most 1 at start
                return start
            x = start
    final = weights(x)
    if final is None:
        return None
    w, floor, _ = final
    sets = br.heaviest(w, floor=floor - 1e-9 * (1 + abs(floor)))
    if sets is None:
        return None
    found = least_of(sets)
    return x if found is None or not found < x else found


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
            else:
                rho = perron_root(self.transfer(pattern))
                hit = flint.fmpq(int(rho.p), int(rho.q)) if self.rational and rho.is_Rational else rho
            self._patterns[pattern] = hit
        return hit

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

    def gain_bound(self, elements: int) -> tuple[float, list[float]]:
        """``(C, b)`` with ``log rho(M) <= C + sum_(elements (j, r) inside) b[j]`` for every pattern,
        ``b >= 0``: of three proved bounds (floats rounded outwards) the least at ``elements``
        elements inside.  With ``a_l = (P^l)_(z, z)``, a word of length ``l - 1`` is at most
        ``a_l`` (``D_r <= I``); ``n`` phases with a non-zero mask hold at least ``n`` elements.

        * Lost runs: ``rho(M) <= c^(g - n)``, ``c = max_(l <= g) a_l``: ``C = g log c``,
          ``b_j = -log c``.
        * Run lengths: ``rho(M) <= prod_segments a_l <= a_1^g kappa^n`` with ``kappa`` the largest
          of ``(a_l / a_1^l)^(1/(l - 1))`` and ``1 / a_1`` (no zero mask: ``rho <= 1``):
          ``C = g log a_1``, ``b_j = log kappa``.
        * Row sums: ``rho(M) <= ||M||_inf <= prod_r mu(m_r)`` with ``mu(m) = max_s sum_(t allowed
          by m) P_(s, t)``, and ``log mu(m) <= log mu(0) + sum_(j in m) b_j`` with ``b_j`` the
          largest increase of ``log mu`` from adding ``j`` to a mask (telescoping).
        """
        pad, k, g = 1 + 4 * self.error(1), len(self.factor.sensors), self.g
        a, Pl = [], np.eye(self.S)
        for _ in range(g):
            Pl = Pl @ self.Pf
            a.append(min(1.0, Pl[self.z, self.z] * pad))
        mu = [min(1.0, pad * max(self.Pf[s, [t for t in range(self.S) if self.received[t] & ~m == 0]].sum()
                                 for s in range(self.S))) for m in range(1 << k)]
        if min(a[0], min(mu)) <= 0:
            return -np.inf, [np.inf] * k
        a1 = a[0] / pad ** 2
        # a1^l may fall below float64 (g = 3465): kappa is then inf, and its bound is never the least
        with np.errstate(over="ignore", divide="ignore"):
            kappa = max([1 / a1] + [(a[l - 1] / a1 ** l) ** (1 / (l - 1)) for l in range(2, g + 1)]) * pad
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


def _exact(value: Any) -> sp.Expr:
    return sp.Rational(int(value.p), int(value.q)) if isinstance(value, flint.fmpq) else sympify(value)


def markov_search(br: BlockRows, rates: Sequence[FactorRates]) -> BlockRate:
    """``max_H prod_f rho(M_(H, f))`` over the hyperplanes ``H``, exactly, without listing them
    when every factor is in the segment form (:class:`FactorRates`) and the block's elements
    admit the screen (:meth:`BlockRows.heaviest`; elements of several generators through its
    additive bound).

    Why no maximiser is missed.  ``rho(M_H)`` is monotone in ``H`` (a larger set allows more
    states: the restricted transfer grows entrywise), so the maximum over rank-deficient sets
    is attained at hyperplanes.  Two screens:

    1. ``heaviest(gamma)`` with ``gamma_e = log rho({e}) - log rho({})``, the gain of ``e``
       alone (>= 0 by monotonicity): its sets are hyperplanes, rated exactly; the largest
       gives a proved lower bound ``tau`` of the maximum (float log less its error bound).
    2. Per factor ``f``, ``rho_f(H) <= c_f^(g - n_f(H)) <= c_f^g prod_(e in H, e of f) c_f^(-1)``
       with ``c_f = max_l (P^l)_(z, z)`` (:meth:`FactorRates.lost_bound`) and ``n_f(H) <= |H_f|``
       the phases where ``H`` holds an element of ``f``: an additive upper bound with weights
       ``beta_e = -log c_f >= 0``.  A maximiser ``H*`` has ``C + sum_(e in H*) beta_e >= log
       rho(H*) >= tau`` (``C = sum_f g log c_f``), so ``heaviest(beta, floor=tau - C)``, which
       returns every hyperplane whose weight reaches the floor (its no-miss argument), holds it.

    Every returned hyperplane is rated; those whose float log is within the proved errors of the
    largest are compared exactly (rationals), and the first maximum in lexicographic order is
    the enumeration's.  Otherwise (or when a screen declines) every hyperplane is listed
    (:func:`listed_hyperplanes`, capped) and screened the same way in floats when the factors
    have twins, else compared exactly.
    """
    patterns = Patterns(br, rates)
    sets = _screened(br, rates, patterns) if all(r.screened for r in rates) else None
    if sets is None:
        sets = _beyond_listing(br, rates, patterns)
    if sets is None:
        sets = list(capped_hyperplanes(br))
    return _decide(sets, patterns)


def _beyond_listing(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns) -> list[frozenset[int]] | None:
    """Where listing the hyperplanes would be refused (their estimated number above
    ``budget.Limits.max_hyperplanes``): the special ones (at least ``n`` elements with a
    generator: the screen with unit weights and a strict floor) and, when it is larger than all of
    theirs, the best rate of ``n - 1`` such elements, attained by generic hyperplanes
    (:mod:`symkf.engine.generic_hyperplanes`, which also says why no maximiser is missed), the first of
    them in lexicographic order.  None when that does not apply (the caller lists, refused by the
    estimate)."""
    if "inside" in br.__dict__ or br.cylinders or br.size < 2 or br.several_generators \
            or br.listing_estimate()[0] <= budget.LIMITS.max_hyperplanes:
        return None
    generic = generic_hyperplanes.best_elements(br, rates)
    if generic is None:
        return None
    special = br.heaviest([1.0 if gs else 0.0 for gs in br.generators], floor=br.size - 0.5, strict=True)
    if special is None:
        return None
    rate, S = generic
    top = max((patterns.rate(H) for H in special), default=None)
    # larger than every special one: S is a generic hyperplane; equal: it is one of the maxima (the
    # list's first may be generic) if it is a hyperplane, else its rate is some special one's
    if top is None or rate > top or (rate == top and generic_hyperplanes.is_hyperplane(br, S)):
        return special + [S]
    return special


def _screened(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns) -> list[frozenset[int]] | None:
    """The hyperplanes of :func:`markov_search`'s two screens; None when a screen declines or the
    bound cannot rule out the generic hyperplanes (through ``n - 1`` elements of one generator in
    general position, :meth:`BlockRows.generic_weight`: then listing is cheaper)."""
    if br.cylinders:
        return _through_cylinders(br, rates, patterns)
    first = _first_screen(br, rates, patterns)
    if first is None:
        return None
    tau = max(lg - err for lg, err in map(patterns.log_rate, first))
    second = _reaching(br, rates, patterns, tau)
    return None if second is None else list({*first, *second})


def _through_cylinders(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns) -> list[frozenset[int]] | None:
    """The sets of :func:`markov_search` for a block over several parts (:mod:`symkf.engine.cylinders`):
    each cylinder's own search (the sub-system's rows over its own, smaller field, with the same
    factors at its class period), its candidates lifted; their largest rate, less its proved
    error, is ``tau``, and every hyperplane meeting every part is ruled out by the additive bound
    of screen 2 (``log rho(M_H) <= C + sum_(e in H) beta_e``) when the fibres bound its weight
    below ``tau - C``.  Each lifted set is rated over this block's period (a pattern repeated
    ``g / g_S`` times); None when the bound does not rule those hyperplanes out."""
    beta, C = _additive_bound(br, rates, patterns)
    tol = 1e-9 * (1 + abs(C))
    # tau <= C + the heaviest cylinder's beta: when the fibres cannot put every full-support
    # hyperplane below that (heaviest declines), they never will, and the cylinders' own searches
    # are not run (2R(2pi/5) + ... + 2R(2pi/11) with two sensors: a refusal of a three-part screen
    # estimated at 1.5e9, which ran past 15 min when allowed)
    if not np.isfinite(C) or br.heaviest(beta) is None:
        return None
    sets = {br.lift(rows, H) for rows in br.cylinders
            for H, _ in markov_search(rows, [FactorRates(r.factor, rows.class_period) for r in rates]).candidates}
    tau = max(lg - err for lg, err in map(patterns.log_rate, sets))
    floor = tau - C
    return list(sets) if np.isfinite(tau) and br.meet_every_part_below(beta, floor - tol - 1e-9 * abs(floor)) else None


def _additive_bound(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns) -> tuple[list[float], float]:
    """``(beta, C)`` of screen 2 of :func:`markov_search`: ``log rho(M_H) <= C + sum_(e in H)
    beta_e`` for every set ``H`` (:meth:`FactorRates.gain_bound`, per factor, at ``n - 1``
    elements inside); ``C`` is -inf or NaN where a factor has no finite bound."""
    bounds = [r.gain_bound(br.size - 1) for r in rates]
    beta = [bounds[f][1][rates[f].factor.sensors.index(br.elements[e].sensor)] for e, (f, _, _) in enumerate(patterns.of)]
    return beta, sum(C for C, _ in bounds)


def _first_screen(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns) -> list[frozenset[int]] | None:
    """Screen 1 of :func:`markov_search`: the hyperplanes heaviest in the gains of single elements."""
    empty = [r.log_rate({}) for r in rates]
    gains = [max(0.0, rates[f].log_rate({phase: bit}) - empty[f]) for f, bit, phase in patterns.of]
    return br.heaviest(gains) if all(np.isfinite(gains)) else None


def _reaching(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns, tau: float
              ) -> list[frozenset[int]] | None:
    """Every hyperplane whose rate may reach ``exp(tau)`` (screen 2 of :func:`markov_search`);
    None when the additive bound cannot rule out the generic hyperplanes or a screen declines."""
    beta, C = _additive_bound(br, rates, patterns)
    if not np.isfinite(tau) or not np.isfinite(C):
        return None
    floor = tau - C
    if not br.several_generators and br.generic_weight(beta) >= floor:
        return None
    return br.heaviest(beta, floor=floor - 1e-9 * (1 + abs(floor) + abs(C)))


def first_screen(br: BlockRows, loss: LossModel) -> list[frozenset[int]]:
    """Hyperplanes of large rate under ``loss`` (screen 1 of :func:`markov_search`, no claim of
    the maximum); empty when the screen declines."""
    rates = factor_rates(br, loss)
    if not all(r.screened for r in rates):
        return []
    return _first_screen(br, rates, Patterns(br, rates)) or []


def rates_reaching(br: BlockRows, loss: LossModel, floor: AlgebraicNumber) -> list[tuple[frozenset[int], sp.Rational]] | None:
    """Every hyperplane ``H`` with ``rho(M_H) >= floor`` (exact, > 0) and its exact rate, without listing the
    hyperplanes: screen 2 of :func:`markov_search` with ``tau`` the float log of ``floor`` less a
    margin (an additive upper bound rules out every set it leaves), then each returned set rated
    exactly; when a screen declines, every hyperplane (:func:`listed_hyperplanes`, capped).  None
    when the factors are not in the segment form."""
    rates = factor_rates(br, loss)
    if not all(r.screened for r in rates) or not floor > 0:
        return None
    patterns = Patterns(br, rates)
    low, _ = floor.interval
    tau = math.log(low.numerator) - math.log(low.denominator) if low > 0 else math.log(float(floor))
    tau -= 1e-6 * (1 + abs(tau))
    sets = _reaching(br, rates, patterns, tau)
    if sets is None:
        sets = list(capped_hyperplanes(br))
    sets = [H for H in sets if sum(patterns.log_rate(H)) >= tau]  # float log plus its proved error
    rated = ((H, _exact(patterns.rate(H))) for H in sets)
    return [(H, v) for H, v in rated if not floor > v]


def _decide(sets: list[frozenset[int]], patterns: Patterns) -> BlockRate:
    """The first exact maximum (lexicographic order) of the rates of ``sets``; with float twins
    only the sets within the proved errors of the largest float are compared exactly."""
    sets = sorted(sets, key=sorted)
    if np.isfinite(patterns.word_error):
        rated = [patterns.log_rate(H) for H in sets]
        top = max(lg - err for lg, err in rated)
        sets = [H for H, (lg, err) in zip(sets, rated) if lg + err >= top]
    cands = [(H, patterns.rate(H)) for H in sets]
    if all(isinstance(v, flint.fmpq) for _, v in cands):
        H, best = max(cands, key=lambda hv: hv[1])
        return BlockRate(_exact(best), H, tuple((H, _exact(v)) for H, v in cands))
    cands = [(H, _exact(v)) for H, v in cands]
    H, best = _maximum(cands)
    return BlockRate(best, H, tuple(cands))


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
    return sp.expand(_exact(cache[key][1].rate(H)))


def _aperiodic(br: BlockRows) -> AperiodicError:
    return AperiodicError(f"the eigen-block of modulus {br.block.modulus} is aperiodic ({br.block.proof})",
                          assumption="eq. (35) (Sui-You-Fu): M over projected patterns needs a periodic block",
                          applies_instead="symkf.engine.rates.block_rate, which decides aperiodic blocks")


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
    checked(loss, system)
    budget.check("max_patterns", 2 ** (loss.d * N), "N", "the number of receival patterns 2^(d N) to "
                 "enumerate (m_matrix computes the same probabilities without enumerating)")
    totals = [sp.Integer(0)] * len(block_rows(system))
    for pattern in itertools.product(itertools.product((1, 0), repeat=loss.d), repeat=N):
        flags = block_deficient(system, pattern) if N else (True,) * len(totals)
        if any(flags):
            p = loss.sequence_probability(pattern)
            totals = [t + p if f else t for t, f in zip(totals, flags)]
    return tuple(sympify(sp.expand(t)) for t in totals)

check_public(globals())
