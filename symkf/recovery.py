"""The critical common recovery rate of Gilbert-Elliott channels without listing every hyperplane.

With ``P = [[1 - f, f], [q, 1 - q]]`` (received, lost), ``lambda = 1 - f - q`` and a run of
``l >= 1`` phases from lost to lost (:class:`symkf.decay.FactorRates`),

    T_l(q) = (P^l)_(lost, lost) = (f + q lambda^l) / (f + q),
    dT_l/dq = (f (lambda^l - 1) - q l (f + q) lambda^(l - 1)) / (f + q)^2.

Monotone range.  For ``0 < q <= 1 - f`` (``lambda >= 0``, the chain stochastically monotone) and
``f > 0`` both terms of the numerator are <= 0 and the first is < 0: ``T_l`` is positive and
strictly decreasing.  A hyperplane's rate is a product over sensors of such terms (a sensor
entirely inside ``H`` contributes 1) and holds at least one (a hyperplane misses an element),
so every margin ``m_H(q) = alpha^(2g) rho(M_H)(q)`` is strictly decreasing on ``(0, q_max]``,
``q_max = 1 - max_j f_j``.

Above it.  For ``1 - f <= q < 1``, ``|lambda| <= f``: ``T_1 = 1 - q <= f``, ``T_l <= f/(f + q) <= f``
for odd ``l`` and ``T_l <= f + |lambda|^l <= f (1 + f)`` for even ``l >= 2``.  A hyperplane's rate is
a product of one term per lost run and of ``1 - q`` per further lost phase, so it is at most the
i.i.d. rate ``prod_j (f_j (1 + f_j))^(phases of j outside H)``: if the filter is stable under
i.i.d. losses ``f_j (1 + f_j)`` (decided by the i.i.d. screen), it is stable on all of ``[q_max, 1)``.

Then the stable set is ``(q_c, 1)`` and ``q_c = max_H r_H``, ``r_H`` the crossing of ``m_H = 1``.
The search: at the rational ``t = q_max / 2`` the screened Markov search
(:func:`symkf.decay.block_rate`) gives per block a decisive hyperplane; its exact polynomial
``m_H(q)`` (the run terms ``T_l`` in ``fmpq_poly``, for that one hyperplane) crosses 1 at ``r``
(in ``(0, t)`` if ``m_H(t) < 1``, in ``[t, q_max)`` if not), and ``q_c >= r``.  Certificate: at a
rational ``a`` just below the largest ``r``, ``m_H(a) > 1``, and every hyperplane with ``m_H(a) >= 1``
is found by screen 2 of the Markov search with that floor (:func:`symkf.decay.rates_reaching`,
no-miss by its additive upper bound); a hyperplane it leaves has ``m_H(a) < 1`` and, decreasing,
stays below 1 after ``a``; each found one crosses exactly once in ``[a, q_max)`` (``m_H(a) >= 1 >
m_H(q_max)``).  So ``q_c``, the largest of these crossings, is exact: every ``q > q_c`` is stable,
and ``q_c`` itself and every ``q < q_c`` are not (some margin is >= 1 there).
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache
from typing import Sequence

import flint
import sympy as sp

from .exact.arguments import check_public
from .decay import Patterns, block_rate, factor_rates, first_screen, rates_reaching
from .exact.algebraic import AlgebraicNumber
from .exact.numbers import sympify
from .losses import IID, GilbertElliott
from .model import System
from .observability import BlockRows, block_rows
from .region import simplest

_GAP = Fraction(1, 10 ** 12)  # how far the rational point sits below the crossing


def _growth(br: BlockRows) -> sp.Rational | None:
    g = sp.expand(sympify(br.block.modulus.exact ** (2 * br.class_period)))
    return g if g.is_Rational else None


def _fmpq(x) -> flint.fmpq:
    x = Fraction(x)
    return flint.fmpq(x.numerator, x.denominator)


@lru_cache(maxsize=None)
def _run_term(f: Fraction, ell: int) -> flint.fmpq_poly:
    """``T_l(q) = (P^l)_(lost, lost)`` of ``P = [[1 - f, f], [q, 1 - q]]``, a polynomial in ``q``."""
    one, q = flint.fmpq_poly([1]), flint.fmpq_poly([0, 1])
    P = [[one - _fmpq(f), flint.fmpq_poly([_fmpq(f)])], [q, one - q]]
    row = [flint.fmpq_poly([0]), one]  # e_lost^T
    for _ in range(ell):
        row = [row[0] * P[0][0] + row[1] * P[1][0], row[0] * P[0][1] + row[1] * P[1][1]]
    return row[1]


def _margin_poly(br: BlockRows, H: frozenset[int], fail: Sequence[Fraction], patterns: Patterns) -> flint.fmpq_poly:
    """``m_H(q) = alpha^(2g) rho(M_H)(q)``: per sensor a ``T_(m+1)`` per run of ``m`` phases inside
    ``H`` between lost phases and a ``T_1`` per further lost phase (:class:`symkf.decay.FactorRates`)."""
    out = flint.fmpq_poly([_fmpq(_growth(br))])
    for rates, masks in zip(patterns.rates, patterns.of_set(H)):
        runs = rates.runs(masks)
        if runs is None:  # the sensor is inside H at every phase: rate 1
            continue
        f = fail[rates.factor.sensors[0]]
        out *= _run_term(f, 1) ** (br.class_period - len(masks) - len(runs))
        for w in runs:
            out *= _run_term(f, len(w) + 1)
    return out


def _crossing(poly: flint.fmpq_poly, lo: Fraction, hi: Fraction) -> AlgebraicNumber | None:
    """The one root of ``poly(q) = 1`` in ``[lo, hi)`` (None when there is not exactly one)."""
    num = (poly - 1).numer()
    roots = []
    for g, _ in num.factor()[1]:
        g = g if g.coeffs()[-1] > 0 else -g
        for i, (r, _) in enumerate(g.complex_roots()):
            if r.imag == 0:
                a = AlgebraicNumber(g, i)
                if a >= sp.Rational(lo) and a < sp.Rational(hi):
                    roots.append(a)
    return roots[0] if len(roots) == 1 else None


def monotone_critical_recovery(system: System, fail: Sequence[sp.Rational]) -> AlgebraicNumber | None:
    """``q_c`` with the filter stable iff the common recovery rate exceeds it, by the argument of
    this module; None when the argument does not apply (a fail rate not rational in (0, 1), a
    sensor with several rows, an irrational ``alpha^(2g)``, the i.i.d. bound above ``q_max``
    unstable, no crossing below ``q_max / 2``): then the caller lists every hyperplane."""
    from .stability import stability
    d = system.d
    if not all(f.is_Rational and 0 < f < 1 for f in fail):
        return None
    fr = [Fraction(int(f.p), int(f.q)) for f in fail]
    blocks = block_rows(system)
    if any(_growth(br) is None for br in blocks) or any(s.m != 1 for s in system.sensors):
        return None
    if not stability(system, IID([f * (1 + f) for f in fail])).stable:
        return None
    qmax = 1 - max(fr)
    t = qmax / 2
    loss = GilbertElliott(list(fail), [sp.Rational(t.numerator, t.denominator)] * d)
    lower = []
    for br in blocks:
        patterns = Patterns(br, factor_rates(br, loss))
        for H in first_screen(br, loss) or [block_rate(br, loss).hyperplane]:
            m = _margin_poly(br, H, fr, patterns)
            r = _crossing(m, Fraction(0), t) if m(_fmpq(t)) < 1 else _crossing(m, t, qmax)
            if r is not None:
                lower.append(r)
    if not lower:
        return None
    lo, _ = max(lower).refine(sp.Rational(_GAP) / 4).interval
    a = simplest(lo - _GAP, lo)
    if a <= 0:
        return None
    loss = GilbertElliott(list(fail), [sp.Rational(a.numerator, a.denominator)] * d)
    crossings = []
    for br in blocks:
        found = rates_reaching(br, loss, 1 / _growth(br))
        if found is None:
            return None
        patterns = Patterns(br, factor_rates(br, loss))
        for H, _ in found:
            r = _crossing(_margin_poly(br, H, fr, patterns), a, qmax)
            if r is None:
                return None
            crossings.append(r)
    return max(crossings)


check_public(globals())
