"""Decay rates of P(R_N(i)) and the M matrix (Sui-You-Fu eqs. 33-36, Theorem 9).

``rho_i = lim sup P(R_N(i))^(1/N)`` (eq. 36).  With ``g`` the block's
projection period and ``H`` ranging over the maximal rank-deficient element
sets (hyperplanes, :mod:`symkf.observability`):

* i.i.d. losses: ``rho_i^g = max_H prod_{(j, r) not in H} loss_j`` -- the
  probability that every element outside ``H`` is lost for a whole period;
* Markov losses (a first-order :class:`~symkf.losses.LossChain`):
  ``rho_i^g = max_H rho(M_H)`` with ``M_H`` the one-period transfer matrix of
  the chain restricted to steps whose received elements lie in ``H``; these
  are the diagonal blocks ``E_ii`` of M for the maximal deficient patterns, so
  this is eq. (36) without building M.  It holds for aperiodic blocks as well
  (symkf's extension, docs/sui.md): an element received infinitely often spans
  its class projections, the other receptions are boundedly many and add
  polynomial factors only; with every class a single eigenvalue (rotations by
  irrational angles) ``g = 1`` and the decisive ``H`` is typically empty, the
  rate of the chain restricted to "everything lost".

The full M (eqs. 33-34) over (projected pattern, chain state) is built only
for checking ``P(R_{Ng}) = u M^N v`` (eq. 35) against enumeration.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any, Sequence

import flint
import numpy as np  # outside counts from BlockRows.inside
import sympy as sp
from sympy.polys.matrices import DomainMatrix

from . import budget
from .errors import AperiodicError, InputError
from .exact import perron
from .exact.algebraic import AlgebraicNumber
from .losses import IID, GilbertElliott, LossChain, LossModel
from .model import System
from .observability import BlockRows, _set, block_deficient, block_rows


@dataclass(frozen=True)
class BlockRate:
    """``rho_i^g`` for one block: the exact value, the decisive hyperplane and the candidates compared
    exactly (under i.i.d. losses only the near-heaviest hyperplanes when :meth:`BlockRows.heaviest`
    applies, else one hyperplane per exponent vector or every hyperplane)."""

    per_period: sp.Expr
    hyperplane: frozenset[int]
    candidates: tuple[tuple[frozenset[int], sp.Expr], ...]


def perron_root(M: sp.MatrixBase) -> sp.Expr:
    """Spectral radius of a non-negative exact matrix (Perron-Frobenius: its largest real eigenvalue).

    Rational matrices go through :func:`symkf.exact.perron.perron_root` (sparse: strongly
    connected components, merged identical rows, flint characteristic polynomials)."""
    if M.shape == (1, 1):
        return sp.sympify(M[0, 0])
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
    return br.elements[j * br.period + phase]


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


def listed_hyperplanes(br: BlockRows) -> np.ndarray:
    """:attr:`BlockRows.inside` (every hyperplane), refused up front when their estimated number
    ``C(V, n - 1)`` (V distinct generators) exceeds ``budget.Limits.max_hyperplanes``."""
    if "inside" not in br.__dict__ and br.size > 1:
        V = len({str([c.coeffs() for c in g]) for gs in br.generators for g in gs})
        budget.check("max_hyperplanes", math.comb(V, br.size - 1), f"eigen-block of modulus {br.block.modulus}",
                     f"the estimated number of hyperplanes to list (C({V}, {br.size - 1}); no screen applies)")
    return br.inside


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


def _weights(loss: IID) -> list[float] | None:
    """``-log loss_j`` per sensor: the slowest-decaying hyperplane maximises ``sum_{e in H} -log
    loss_(sensor e)``; None when a loss is 0 or symbolic (then every hyperplane is compared)."""
    if loss.symbols or any(e == 0 for e in loss.loss):
        return None
    return [-float(sp.log(e).evalf(20)) for e in loss.loss]


def block_rate(br: BlockRows, loss: LossModel) -> BlockRate:
    """``rho_i^g`` (per projection period) for one block, exactly (eq. 36).

    i.i.d. losses: the heaviest hyperplanes (:func:`outside_counts`).  Markov losses: the
    product over the model's independent factors of their restricted transfers' Perron roots,
    maximised by :func:`markov_search` (aperiodic blocks too: their elements' generators are
    class projections, docs/sui.md)."""
    if isinstance(loss, IID):
        counts = outside_counts(br, _weights(loss))
        cands = [(H, sp.Mul(*[e ** k for e, k in zip(loss.loss, ks)])) for ks, H in counts.items()]
        H, best = _maximum(cands)
        return BlockRate(best, H, tuple(cands))
    if loss.symbols:
        raise _symbolic()
    return markov_search(br, factor_rates(br, loss))


def _symbolic() -> InputError:
    return InputError("loss: symbolic loss parameters have no numeric decay rate; "
                      "use symkf.region.stability_conditions for the stability region as conditions")


def _maximum(candidates: list[tuple[frozenset[int], sp.Expr]]) -> tuple[frozenset[int], sp.Expr]:
    if any(v.free_symbols for _, v in candidates):
        raise _symbolic()
    return max(candidates, key=lambda hv: AlgebraicNumber.from_expr(hv[1]))


# -- restricted transfers per independent factor ----------------------------------------
@dataclass(frozen=True)
class Factor:
    """An independent factor of a loss model: a first-order chain whose states emit the
    receptions of ``sensors`` (per-sensor Gilbert-Elliott channels, or one joint chain)."""

    sensors: tuple[int, ...]
    chain: LossChain


def loss_factors(loss: LossModel) -> tuple[Factor, ...]:
    """The independent factors of ``loss``: its transfer restricted to ``H`` is the Kronecker
    product of theirs, so ``rho(M_H)`` is the product of their Perron roots."""
    if isinstance(loss, GilbertElliott):
        return tuple(Factor((j,), LossChain(("received", "lost"), ((1,), (0,)), loss.sensor_matrix(j),
                                            sp.ImmutableMatrix([[1, 0]]))) for j in range(loss.d))
    return (Factor(tuple(range(loss.d)), loss.chain),)


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
        self.rational = all(v.is_Rational for v in ch.P)
        self.z = lost[0] if len(lost) == 1 else None
        self.P = flint.fmpq_mat([[flint.fmpq(int(v.p), int(v.q)) for v in ch.P.row(i)] for i in range(self.S)]) \
            if self.rational else ch.P
        self.Pf = np.array([[float(v) for v in row] for row in self.P.tolist()]) if self.rational else None
        self._words: dict[tuple[int, ...], tuple[Any, float]] = {}
        self._patterns: dict[tuple[int, ...], tuple[Any, float]] = {}

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

    def rate(self, pattern: tuple[int, ...]) -> tuple[Any, float]:
        """``(rho(M), log rho(M) in float64)`` of the pattern (``fmpq`` or sympy exact; the float
        is NaN when there is no twin)."""
        hit = self._patterns.get(pattern)
        if hit is None:
            if self.z is not None and 0 in pattern:
                start = pattern.index(0)
                cyc = pattern[start + 1:] + pattern[:start + 1]  # ends with a zero mask
                exact, log, word = (flint.fmpq(1) if self.rational else sp.Integer(1)), 0.0, []
                for m in cyc:
                    if m:
                        word.append(m)
                        continue
                    s, sl = self._word(tuple(word))
                    exact, log, word = exact * s, log + sl, []
                hit = (exact if self.rational else sp.expand(exact), log if self.rational else np.nan)
            elif all(self.received[s] & ~m == 0 for m in pattern for s in range(self.S)):  # P^g: stochastic
                hit = (flint.fmpq(1) if self.rational else sp.Integer(1), 0.0 if self.rational else np.nan)
            else:
                rho = perron_root(self.transfer(pattern))
                hit = (flint.fmpq(int(rho.p), int(rho.q)) if self.rational and rho.is_Rational else rho, np.nan)
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

    def lost_bound(self) -> float:
        """``c = max_(1 <= l <= g) (P^l)_(z, z)``: every word of length ``l - 1`` is at most
        ``(P^l)_(z, z)`` (``D_r <= I``), so ``rho(M) <= c^(phases with mask 0)``."""
        Pl, best = np.eye(self.S), 0.0
        for _ in range(self.g):
            Pl = Pl @ self.Pf
            best = max(best, Pl[self.z, self.z])
        return min(1.0, best * (1 + 2 * self.error(1)))


def factor_rates(br: BlockRows, loss: LossModel) -> tuple[FactorRates, ...]:
    """One :class:`FactorRates` per independent factor of ``loss`` for the block's period."""
    return tuple(FactorRates(f, br.period) for f in loss_factors(loss))


class _Patterns:
    """The phase patterns of hyperplanes, per factor."""

    def __init__(self, br: BlockRows, rates: Sequence[FactorRates]):
        self.g, self.rates = br.period, rates
        where = {j: (f, i) for f, r in enumerate(rates) for i, j in enumerate(r.factor.sensors)}
        self.of = [(where[e.sensor][0], 1 << where[e.sensor][1], e.phase) for e in br.elements]

    def of_set(self, H) -> list[tuple[int, ...]]:
        masks = [[0] * self.g for _ in self.rates]
        for e in H:
            f, bit, phase = self.of[e]
            masks[f][phase] |= bit
        return [tuple(m) for m in masks]

    def rate(self, H) -> tuple[Any, float, int]:
        """Exact rate, its float log and the number of words (for the error bound)."""
        exact, log, words = 1, 0.0, 0
        for r, pattern in zip(self.rates, self.of_set(H)):
            e, lg = r.rate(pattern)
            exact, log, words = exact * e, log + lg, words + pattern.count(0)
        return exact, log, words


def _exact(value: Any) -> sp.Expr:
    return sp.Rational(int(value.p), int(value.q)) if isinstance(value, flint.fmpq) else sp.sympify(value)


def markov_search(br: BlockRows, rates: Sequence[FactorRates]) -> BlockRate:
    """``max_H prod_f rho(M_(H, f))`` over the hyperplanes ``H``, exactly, without listing them
    when every factor is in the segment form (:class:`FactorRates`) and the block's elements
    have one generator each (:meth:`BlockRows.heaviest` applies).

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
    patterns = _Patterns(br, rates)
    sets = _screened(br, rates, patterns) if all(r.screened for r in rates) else None
    if sets is None:
        sets = [_set(row) for row in listed_hyperplanes(br)]
    return _decide(sets, patterns)


def _screened(br: BlockRows, rates: Sequence[FactorRates], patterns: _Patterns) -> list[frozenset[int]] | None:
    g = br.period
    empty = [r.rate((0,) * g)[1] for r in rates]
    gains = []
    for e, (f, bit, phase) in enumerate(patterns.of):
        alone = [0] * g
        alone[phase] = bit
        gains.append(max(0.0, rates[f].rate(tuple(alone))[1] - empty[f]))
    if not all(np.isfinite(gains)):
        return None
    first = br.heaviest(gains)
    if first is None:
        return None
    rated = [patterns.rate(H) for H in first]
    tau = max(lg - 2 * sum(r.error(1) for r in rates) * (w + 1) for _, lg, w in rated)
    lost = [r.lost_bound() for r in rates]
    if min(lost) <= 0 or not np.isfinite(tau):
        return None
    beta = [-np.log(lost[f]) for f, _, _ in patterns.of]
    C = sum(g * np.log(c) for c in lost)
    floor = tau - C
    second = br.heaviest(beta, floor=floor - 1e-9 * (1 + abs(floor) + abs(C)))
    if second is None:
        return None
    return list({*first, *second})


def _decide(sets: list[frozenset[int]], patterns: _Patterns) -> BlockRate:
    """The first exact maximum (lexicographic order) of the rates of ``sets``; with float twins
    only the sets within the proved error of the largest float are compared exactly."""
    sets = sorted(sets, key=sorted)
    rated = [patterns.rate(H) for H in sets]
    if all(np.isfinite(lg) or lg == -np.inf for _, lg, _ in rated):
        err = [2 * sum(r.error(1) for r in patterns.rates) * (w + 1) for _, _, w in rated]
        top = max(lg - e for (_, lg, _), e in zip(rated, err))
        near = [i for i, ((_, lg, _), e) in enumerate(zip(rated, err)) if lg + e >= top]
    else:
        near = range(len(sets))
    cands = [(sets[i], rated[i][0]) for i in near]
    if all(isinstance(v, flint.fmpq) for _, v in cands):
        H, best = max(cands, key=lambda hv: hv[1])
        return BlockRate(_exact(best), H, tuple((H, _exact(v)) for H, v in cands))
    cands = [(H, _exact(v)) for H, v in cands]
    H, best = _maximum(cands)
    return BlockRate(best, H, tuple(cands))


def ge_rate(br: BlockRows, H: frozenset[int], loss: GilbertElliott) -> sp.Expr:
    """``rho(M_H)`` for independent Gilbert-Elliott channels: the product over sensors of the
    Perron roots of their 2x2 restricted transfers, each a product over the runs of the
    sensor's phases inside ``H`` of ``(P^(m+1))_(lost, lost)`` (:class:`FactorRates`), a
    polynomial in (fail, recover); a sensor entirely inside ``H`` has transfer ``P^g``
    (stochastic), rate 1."""
    key = ("ge_rates", id(loss))
    cache = br.__dict__.setdefault("_rates", {})
    if cache.get(key, (None,))[0] is not loss:
        cache[key] = (loss, _Patterns(br, factor_rates(br, loss)))
    exact, _, _ = cache[key][1].rate(H)
    return sp.expand(_exact(exact))


def _aperiodic(br: BlockRows) -> AperiodicError:
    return AperiodicError(f"the eigen-block of modulus {br.block.modulus} is aperiodic ({br.block.proof})",
                          assumption="eq. (35) (Sui-You-Fu): M over projected patterns needs a periodic block",
                          applies_instead="symkf.decay.block_rate, which decides aperiodic blocks")


def restricted_transfer(br: BlockRows, H: frozenset[int], loss: LossModel) -> sp.Matrix:
    """One-period transfer of the loss chain restricted to steps received inside ``H``."""
    rates = FactorRates(Factor(tuple(range(loss.d)), loss.chain), br.period)
    return rates.transfer(_Patterns(br, [rates]).of_set(H)[0])


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
        for phase in range(br.period):
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
    if loss.d != system.d:
        raise InputError(f"loss model has {loss.d} sensors, the system {system.d}")
    if loss.d * N > 18:
        raise InputError(f"enumeration of 2^{loss.d * N} patterns is too large; use m_matrix")
    totals = [sp.Integer(0)] * len(block_rows(system))
    for pattern in itertools.product(itertools.product((1, 0), repeat=loss.d), repeat=N):
        flags = block_deficient(system, pattern) if N else (True,) * len(totals)
        if any(flags):
            p = loss.chain.sequence_probability(pattern)
            totals = [t + p if f else t for t, f in zip(totals, flags)]
    return tuple(sp.sympify(sp.expand(t)) for t in totals)
