"""The critical recovery rate of Gilbert-Elliott channels (common, or one sensor's) without listing every hyperplane.

With ``P = [[1 - f, f], [q, 1 - q]]`` (received, lost), ``lambda = 1 - f - q`` and a run of
``l >= 1`` phases from lost to lost (:class:`symkf.engine.rates.FactorRates`),

    T_l(q) = (P^l)_(lost, lost) = (f + q lambda^l) / (f + q),
    dT_l/dq = (f (lambda^l - 1) - q l (f + q) lambda^(l - 1)) / (f + q)^2.

Monotone range.  For ``0 < q <= 1 - f`` (``lambda >= 0``, the chain stochastically monotone) and
``f > 0`` both terms of the numerator are <= 0 and the first is < 0: ``T_l`` is positive and
strictly decreasing.  A hyperplane's rate is a product over sensors of such terms (a sensor
entirely inside ``H`` contributes 1) and holds at least one (a hyperplane misses an element),
so every margin ``m_H(q) = alpha^(2g) rho(M_H)(q)`` is strictly decreasing on ``(0, q_max]``,
``q_max = 1 - max_j f_j``.

Above it.  For ``1 - f <= q < 1``, ``-f < lambda <= 0``: ``T_1 = 1 - q <= f``, ``T_l <= f/(f + q) <= f``
for odd ``l``, and ``T_l <= f`` for even ``l >= 2`` too (``T_l <= f`` iff ``q lambda^l <= f |lambda|``,
and ``q |lambda|^l <= |lambda| f^(l - 1) <= f |lambda|``; equality at ``q = 1 - f`` and at ``q = 1``).
For ``q_max <= q <= 1 - f`` (a sensor whose ``f`` is below the largest), ``lambda >= 0`` and ``T_l <=
T_1 = 1 - q <= 1 - q_max``.  So every term is at most ``c = 1 - q_max``, the largest ``f``.  A
hyperplane's rate is a product of one term per lost run and of ``1 - q`` per further lost phase, so
it is at most the i.i.d. rate ``prod_j c^(phases of j outside H)``: if the filter is stable under
i.i.d. losses ``c`` (decided by the screened search), it is stable on all of ``[q_max, 1)``.

Then the stable set is ``(q_c, 1)`` and ``q_c = max_H r_H``, ``r_H`` the crossing of ``m_H = 1``.
The search: at the rational ``t = q_max / 2`` the screened Markov search
(:func:`symkf.engine.search.block_rate`) gives per block a decisive hyperplane; its exact polynomial
``m_H(q)`` (the run terms ``T_l`` in ``fmpq_poly``, for that one hyperplane) crosses 1 at ``r``
(in ``(0, t)`` if ``m_H(t) < 1``, in ``[t, q_max)`` if not), and ``q_c >= r``.  Certificate: at a
rational ``a`` just below the largest ``r``, ``m_H(a) > 1``, and every hyperplane with ``m_H(a) >= 1``
is found by screen 2 of the Markov search with that floor (:func:`symkf.engine.search.rates_reaching`,
no-miss by its additive upper bound); a hyperplane it leaves has ``m_H(a) < 1`` and, decreasing,
stays below 1 after ``a``; each found one crosses exactly once in ``[a, q_max)`` (``m_H(a) >= 1 >
m_H(q_max)``).  So ``q_c``, the largest of these crossings, is exact: every ``q > q_c`` is stable,
and ``q_c`` itself and every ``q < q_c`` are not (some margin is >= 1 there).
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache
from typing import Any, Sequence

import flint
import numpy as np
import sympy as sp

from ..arguments import check_public
from ..errors import AssumptionError, InputError
from .rates import FactorRates, Patterns, factor_rates
from .search import block_rate, first_screen, listed_hyperplanes, price_margins, rates_reaching
from ..exact.algebraic import AlgebraicNumber, crossings_in_unit, decreasing_root, exceeds, narrowed, root_between, sign_at
from ..exact.numbers import sympify
from ..model.gilbert_elliott import GilbertElliott
from ..model.loss import LossModel
from ..model.system import System
from .rows import BlockRows, _set, _as_rows
from .blocks import block_rows
from .region import ge_margins, simplest, stable_intervals, stable_set
from .stability import _check_loss, stability

_GAP = Fraction(1, 10 ** 12)  # how far the rational point sits below the crossing


def _threshold(br: BlockRows) -> AlgebraicNumber:
    """``gamma = alpha^(-2g)``: a margin ``alpha^(2g) rho_H(q)`` reaches 1 iff ``rho_H(q) >= gamma``
    (exact; algebraic for the irrational moduli of dense systems)."""
    return br.block.modulus ** (-2 * br.class_period)


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


def _rate_poly(br: BlockRows, H: frozenset[int], fail: Sequence[Fraction], varying: frozenset[int],
               patterns: Patterns) -> flint.fmpq_poly:
    """``rho(M_H)(q)``: per varying sensor a ``T_(m+1)`` per run of ``m`` phases inside ``H``
    between lost phases and a ``T_1`` per further lost phase, per fixed sensor its exact rate
    (:class:`symkf.engine.rates.FactorRates`); the margin is ``alpha^(2g)`` times it."""
    out = flint.fmpq_poly([1])
    for rates, masks in zip(patterns.rates, patterns.of_set(H)):
        j = rates.factor.sensors[0]
        if j not in varying:
            out *= rates.rate(masks)
            continue
        runs = rates.runs(masks)
        if runs is None:  # the sensor is inside H at every phase: rate 1
            continue
        f = fail[j]
        out *= _run_term(f, 1) ** (br.class_period - len(masks) - len(runs))
        for w in runs:
            out *= _run_term(f, len(w) + 1)
    return out


def _shape(rates: FactorRates, masks: dict[int, int]) -> tuple:
    """What a factor's rate depends on: its phases inside ``H`` and its runs, sorted (the segment
    form), or its whole pattern; hyperplanes whose factors have one shape each have one rate."""
    runs = rates.runs(masks)
    return (len(masks), tuple(sorted(runs))) if runs is not None else tuple(sorted(masks.items()))


def _classes(matrix: np.ndarray) -> tuple[np.ndarray, list[int]]:
    """Per row the index of its class of equal rows (numbered by first appearance), and each
    class's first row (``np.unique`` by rows sorts them as records: ten times slower)."""
    keys: dict[bytes, int] = {}
    first = []
    which = np.empty(len(matrix), dtype=np.int64)
    for h, row in enumerate(np.ascontiguousarray(matrix)):
        k = keys.setdefault(row.tobytes(), len(keys))
        if k == len(first):
            first.append(h)
        which[h] = k
    return which, first


def _at(rho: flint.fmpq_poly, q: Fraction) -> Fraction:
    v = rho(_fmpq(q))
    return Fraction(int(v.p), int(v.q))


def _zero(blocks: Sequence[BlockRows], model, fail: Sequence[sp.Rational], varying: frozenset[int]
          ) -> AlgebraicNumber | None:
    """0 when every margin at ``q = 0`` is below 1, else None.  At ``q = 0`` a varying channel,
    once lost, stays lost: ``T_l(0) = 1``, its factor of every rate is 1, the rate of a channel
    with fail 1 and recovery 0 (a Gilbert-Elliott factor in the segment form, decided by the
    screened search without Assumption 2's positivity, which only the verdict asks).  With ``m_H(0)
    < 1`` and ``m_H`` non-increasing, every ``q`` in ``(0, q_max]`` is stable (a common rate has
    ``m_H(0) = alpha^(2g) > 1``: never 0)."""
    stuck = GilbertElliott([1 if i in varying else f for i, f in enumerate(fail)],
                           [0 if i in varying else r for i, r in enumerate(model(0).recover)])
    for br in blocks:
        if not _threshold(br) > block_rate(br, stuck).per_period:
            return None
    return AlgebraicNumber.from_expr(0)


class _Unstable(Exception):
    """A margin that does not depend on the varying recovery rate is at least 1: no rate is stable."""


def _rational(values: Sequence[sp.Expr]) -> list[Fraction] | None:
    if not all(v.is_Rational and 0 < v < 1 for v in values):
        return None
    return [Fraction(int(v.p), int(v.q)) for v in values]


class _Channels:
    """Gilbert-Elliott channels whose recovery probability is the variable ``q`` on the ``varying``
    sensors (all, or one), the others' fixed at ``fixed``; every rate rational."""

    def __init__(self, fail: Sequence[sp.Expr], varying: frozenset[int], rational: list[Fraction],
                 fixed: list[sp.Expr]):
        self.original, self.varying, self.fail, self.fixed = list(fail), varying, rational, fixed

    @classmethod
    def of(cls, d: int, fail: Sequence[sp.Expr], recover: Sequence[sp.Expr] | None,
           sensor: int | None) -> "_Channels | None":
        """The channels of a query (``sensor``: the one varying; else all), None when a rate that
        enters a margin is not a rational in (0, 1)."""
        varying = frozenset(range(d)) if sensor is None else frozenset({sensor})
        fr = _rational(fail)
        fixed = [sp.Rational(1, 2)] * d if sensor is None else [sympify(r) for r in recover]
        if fr is None or _rational([r for i, r in enumerate(fixed) if i not in varying]) is None:
            return None
        return cls(fail, varying, fr, fixed)

    def model(self, q) -> GilbertElliott:
        return GilbertElliott(self.original, [q if i in self.varying else r for i, r in enumerate(self.fixed)])

    def rates(self, br: BlockRows, sets) -> list[flint.fmpq_poly]:
        """The distinct ``rho(M_H)(q)`` of the hyperplanes ``sets`` (shifted and tied hyperplanes share
        one: each is solved once), built once per combination of the factors' :func:`_shape` (tens of
        thousands of listed hyperplanes have a few hundred); a pattern's runs do not depend on ``q``."""
        patterns = Patterns(br, factor_rates(br, self.model(sp.Rational(1, 2))))
        rows = _as_rows(sets, len(br.elements))
        # per factor, the shape of each of its distinct patterns; then one hyperplane per combination
        # of shapes (numpy, not a set per hyperplane: 135 568 listed ones of four sensors at period 24)
        ids = []
        for k, rates in enumerate(patterns.rates):
            columns = np.array([e for e, (f, _, _) in enumerate(patterns.of) if f == k], dtype=np.int64)
            which, first = _classes(np.packbits(rows[:, columns], axis=1))
            shapes: dict[tuple, int] = {}
            shape = [shapes.setdefault(_shape(rates, patterns.of_set(columns[rows[h, columns]].tolist())[k]), len(shapes))
                     for h in first]
            ids.append(np.array(shape, dtype=np.int64)[which])
        _, first = _classes(np.column_stack(ids))
        polys = (_rate_poly(br, _set(rows[h]), self.fail, self.varying, patterns) for h in first)
        distinct = {str(m): m for m in polys}
        return list(distinct.values())


def listed_margins(system: System, fail: Sequence[sp.Rational], recover: Sequence[sp.Rational] | None,
                   sensor: int | None) -> list[tuple[AlgebraicNumber, list[flint.fmpq_poly]]] | None:
    """Per block ``(gamma, rates)``: the threshold ``gamma = alpha^(-2g)`` and every hyperplane's
    ``rho_H(q)`` (the hyperplanes listed, capped: :func:`symkf.engine.search.listed_hyperplanes`),
    the distinct ones once, built in flint (sympy's expansion of the same products is far slower
    with a few two-row sensors of a long period: docs/performance.md); the margin ``alpha^(2g)
    rho_H(q)`` is below 1 iff ``rho_H(q) < gamma``.  None when a rate is not rational (then
    :func:`symkf.engine.region.ge_margins`)."""
    channels = _Channels.of(system.d, fail, recover, sensor)
    if channels is None:
        return None
    out = []
    for br in block_rows(system):
        price_margins(br, "the margin polynomial")
        out.append((_threshold(br), channels.rates(br, listed_hyperplanes(br))))
    return out


def listed_intervals(margins: Sequence[tuple[AlgebraicNumber, Sequence[flint.fmpq_poly]]]
                     ) -> tuple[tuple[AlgebraicNumber, AlgebraicNumber], ...]:
    """``{q in (0, 1) : rho(q) < gamma for every (gamma, rates) and rate rho}`` (:func:`listed_margins`)
    as disjoint open intervals, exactly.

    The verdict changes only where some ``rho`` meets its ``gamma``: a real root of ``mu(rho(q))``
    in ``(0, 1)`` (:func:`symkf.exact.algebraic.crossings_in_unit`: isolating intervals by Descartes'
    rule, no complex root isolated), and only where no rate is above its threshold around it: a root
    whose interval, narrowed to ``2^-40``, has some ``rho > gamma`` on all of it (ball arithmetic)
    is not a boundary.  The others become exact numbers (:func:`symkf.exact.algebraic.root_between`),
    and the gaps between them are decided at rationals by exact rates
    (:func:`symkf.engine.region.stable_set`).  Each margin's roots used to be isolated among all its
    complex roots, and its rates expanded in sympy: 67 CPU-s for four sensors of the period-24 block
    at fail (3/5, 1/2, 3/5, 9/10), 135 568 hyperplanes and 39 distinct rates of degree up to 96."""
    rates = [(gamma, rho) for gamma, polys in margins for rho in polys]
    kept = []
    for gamma, rho in rates:
        for part, lo, hi in crossings_in_unit(rho, gamma):
            lo, hi = narrowed(part, lo, hi, Fraction(1, 2 ** 40))
            if not any(exceeds(other, bound, lo, hi) for bound, other in rates):
                kept.append(root_between(part, lo, hi))

    def stable_at(v: Any) -> bool:
        x = AlgebraicNumber.from_expr(v)
        return all(sign_at(rho, x, gamma) < 0 for gamma, rho in rates)
    return stable_set(kept, stable_at)


def monotone_critical_recovery(system: System, fail: Sequence[sp.Rational],
                               recover: Sequence[sp.Rational] | None = None,
                               sensor: int | None = None) -> AlgebraicNumber | None:
    """``q_c`` with the filter stable iff the recovery rate exceeds it, by the argument of this
    module; None when the argument does not apply (a fail or fixed recovery rate not rational in
    (0, 1), the bound above ``q_max`` unstable, no crossing below
    ``q_max / 2``): then the caller lists every hyperplane.  An irrational ``alpha^(2g)`` (a dense
    ``A``) is exact here: crossings are roots of ``rho_H(q) = alpha^(-2g)``
    (:func:`symkf.exact.algebraic.decreasing_root`).

    The rate is common to all sensors, or (``sensor = j``) only sensor ``j``'s, the others'
    given by ``recover`` (entry ``j`` ignored).  A margin then holds the fixed channels' exact
    rates as constant factors: it is still non-increasing in ``q`` on ``(0, q_max]`` (``q_max = 1
    - fail_j``), strictly where sensor ``j`` has a lost phase outside ``H``, and constant where
    ``H`` holds every element of ``j``; above ``q_max`` sensor ``j``'s factor is at most that of
    i.i.d. losses ``fail_j = 1 - q_max``, a Gilbert-Elliott channel with ``fail + recover = 1``
    beside the fixed ones.  A constant margin at least 1 (found by the search at ``q_max / 2`` or
    by the certificate's screen) is unstable at every ``q``: the answer is 1, as with the listing."""
    channels = _Channels.of(system.d, fail, recover, sensor)
    if channels is None:
        return None
    varying, fr, fixed, model = channels.varying, channels.fail, channels.fixed, channels.model
    blocks = block_rows(system)
    gamma = {br: _threshold(br) for br in blocks}

    def margins(q: Fraction, br: BlockRows, sets) -> list[flint.fmpq_poly]:
        polys = channels.rates(br, sets)
        if any(m.degree() < 1 and not gamma[br] > _at(m, Fraction(0)) for m in polys):
            raise _Unstable
        return [m for m in polys if m.degree() >= 1]

    qmax = 1 - max(fr[j] for j in varying)
    t = qmax / 2
    try:
        lower = []
        for br in blocks:
            loss = model(sp.Rational(t.numerator, t.denominator))
            for m in margins(t, br, first_screen(br, loss) or [block_rate(br, loss).hyperplane]):
                r = decreasing_root(m, gamma[br], Fraction(0), t) if gamma[br] > _at(m, t) else decreasing_root(m, gamma[br], t, qmax)
                if r is not None:
                    lower.append(r)
        c = 1 - sp.Rational(qmax.numerator, qmax.denominator)   # the largest varying fail
        iid = GilbertElliott([c if i in varying else f for i, f in enumerate(fail)],
                             [1 - c if i in varying else r for i, r in enumerate(fixed)])
        if not stability(system, iid).stable:
            return None
        if not lower:
            return _zero(blocks, model, fail, varying)
        lo, _ = max(lower).refine(sp.Rational(_GAP) / 4).interval
        a = simplest(lo - _GAP, lo)
        if a <= 0:
            return None
        crossings = []
        for br in blocks:
            found = rates_reaching(br, model(sp.Rational(a.numerator, a.denominator)), gamma[br])
            if found is None:
                return None
            for m in margins(a, br, [H for H, _ in found]):
                r = decreasing_root(m, gamma[br], a, qmax)
                if r is None:
                    return None
                crossings.append(r)
    except _Unstable:
        return AlgebraicNumber.from_expr(1)
    return max(crossings)



def _recovery_model(system: System, fail: Sequence[Any], recover: Sequence[Any] | None,
                    sensor: str | None, q: sp.Symbol) -> GilbertElliott:
    """Gilbert-Elliott channels with the varying recovery probability replaced by the symbol ``q``."""
    if len(fail) != system.d:
        raise InputError(f"fail: {len(fail)} values for {system.d} sensors")
    if sensor is None:
        return GilbertElliott(fail, [q] * system.d)
    j = system.sensor_index(sensor)
    if recover is None or len(recover) != system.d:
        raise InputError(f"recover: give the {system.d} recovery probabilities of all sensors (entry {j} is ignored)")
    return GilbertElliott(fail, [q if i == j else r for i, r in enumerate(recover)])


def _monotone_recovery(system: System, fail: Sequence[Any], recover: Sequence[Any] | None,
                       sensor: str | None) -> tuple[GilbertElliott, sp.Symbol, Any, AlgebraicNumber | None]:
    """The checked model with symbol ``q``, a function giving the stable intervals from every
    hyperplane's margin, and ``q_c`` by :mod:`symkf.engine.recovery`'s argument (stable exactly for ``q >
    q_c``), None where that argument does not apply."""
    q = sp.Symbol("q", positive=True)
    if isinstance(fail, LossModel):   # a model as the template: its channels' fail probabilities
        if fail.channel_fail is None:
            raise AssumptionError(f"fail: the loss model is {fail.words()}, not Gilbert-Elliott channels",
                                  assumption="independent two-state channels (a recovery probability to vary)",
                                  applies_instead="symkf.critical_loss_rate for i.i.d. losses")
        if sensor is not None and recover is None:   # the other channels keep the model's recovery
            recover = fail.channel_recover
        fail = list(fail.channel_fail)
    model = _recovery_model(system, fail, recover, sensor, q)
    _check_loss(system, model.subs({q: sp.Rational(1, 2)}))
    j = None if sensor is None else system.sensor_index(sensor)
    fixed = None if j is None else model.recover

    def listed() -> tuple[tuple[AlgebraicNumber, AlgebraicNumber], ...]:
        margins = listed_margins(system, model.fail, fixed, j)
        return stable_intervals(ge_margins(system, model), q) if margins is None else listed_intervals(margins)
    return model, q, listed, monotone_critical_recovery(system, model.fail, fixed, j)


def stable_recovery_intervals(system: System, fail: Sequence[Any] | LossModel, *, recover: Sequence[Any] | None = None,
                              sensor: str | None = None) -> tuple[tuple[AlgebraicNumber, AlgebraicNumber], ...]:
    """The recovery probabilities ``q in (0, 1)`` that make Gilbert-Elliott channels stable, exactly.

    ``q`` is common to all sensors, or only sensor ``sensor``'s with the others' ``recover``
    fixed.  Each block and hyperplane gives the polynomial condition
    ``alpha^(2g) prod_j tr(M_{H,j}(q)) < 1`` (:func:`symkf.engine.region.ge_margins`); the set is a
    union of open intervals with algebraic end points.  Where the argument of
    :mod:`symkf.engine.recovery` applies (rational rates) the set is ``(q_c, 1)`` with ``q_c`` found
    without listing the hyperplanes; otherwise every hyperplane's condition is solved.  It need not be an up-set: a channel
    that recovers faster also alternates more, which can lock its receptions onto one phase of
    the period (``proofs/sui_engine_ge_recovery_nonmonotone.py``).

    Parameters
    ----------
    system : System
    fail : sequence
        ``P(lost | received last)`` per sensor (exact numbers).
    recover : sequence, optional
        The other sensors' recovery probabilities, with ``sensor`` (that entry is ignored).
    sensor : str, optional
        Vary only this sensor's recovery probability.

    Returns
    -------
    tuple of (AlgebraicNumber, AlgebraicNumber)
        The disjoint open intervals ``(lo, hi)`` of stable ``q``, ascending; empty when no ``q``
        in (0, 1) is stable.

    Raises
    ------
    InputError
        ``fail`` or ``recover`` has the wrong length, or ``sensor`` names no sensor.
    AssumptionError
        A theorem's assumption fails for the system.

    Examples
    --------
    A scalar ``A = 2`` with one sensor: the only decisive pattern is a run of losses, which
    continues with probability ``1 - q`` per step whatever ``fail`` is, so the filter is stable
    iff ``4 (1 - q) < 1``, i.e. ``q > 3/4`` (by hand; the classical Gilbert-Elliott condition
    ``q > 1 - 1/|a|^2``):

    >>> import symkf as sk
    >>> S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])])
    >>> [(lo.exact, hi.exact) for lo, hi in sk.stable_recovery_intervals(S, fail=["1/4"])]
    [(3/4, 1)]
    """
    _, _, listed, qc = _monotone_recovery(system, fail, recover, sensor)
    if qc is None:
        return listed()
    return () if qc == 1 else ((qc, AlgebraicNumber.from_expr(1)),)


def critical_recovery_rate(system: System, fail: Sequence[Any] | LossModel, *, recover: Sequence[Any] | None = None,
                           sensor: str | None = None) -> AlgebraicNumber:
    """The critical recovery probability ``q_c`` of Gilbert-Elliott channels: stable iff ``recover > q_c``.

    ``fail[j] = P(lost | received last)`` is fixed (``fail`` may be the channels' model itself,
    :class:`~symkf.model.gilbert_elliott.GilbertElliott`: its recovery probabilities are then
    the ones varied, and with ``sensor`` the others' stay the model's); the recovery probability ``P(received | lost last)`` is common to all sensors, or (``sensor=NAME``) only that sensor's, the others given
    by ``recover``.  Returns 0 when every ``q`` in (0, 1) is stable and 1 when none is.  Raises
    :class:`AssumptionError` when the stable set is not an interval ``(q_c, 1)`` (stability is not
    monotone in ``q`` in general; :func:`stable_recovery_intervals` gives the set).  Certified:
    the verdict of :func:`stability` is checked at rationals just outside the isolating interval.

    With rational ``fail`` (and fixed ``recover``) in (0, 1), the common
    ``q`` and one sensor's ``q`` first take the path of :mod:`symkf.engine.recovery`, which lists no
    hyperplane: every margin is non-increasing for ``q <= 1 - max fail`` of the varying sensors
    (their chains are stochastically monotone there), and ``q`` above it is proved stable only
    through an i.i.d. bound; where that bound or a screen fails, every hyperplane is listed as
    before (capped by ``budget.Limits``).

    Parameters
    ----------
    system : System
    fail : sequence
        ``P(lost | received last)`` per sensor (exact numbers).
    recover : sequence, optional
        The other sensors' recovery probabilities, with ``sensor``.
    sensor : str, optional
        Vary only this sensor's recovery probability.

    Returns
    -------
    AlgebraicNumber

    Examples
    --------
    The two sensors of :func:`stability` on channels that fail with probability 1/4; the verdicts
    on either side of the critical value agree with it:

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> q = sk.critical_recovery_rate(S, fail=["1/4", "1/4"])
    >>> q.minpoly.as_expr(), round(float(q), 6)
    (16*x**4 - 60*x**3 + 88*x**2 - 60*x + 15, 0.565084)
    >>> [sk.stability(S, sk.GilbertElliott(["1/4"] * 2, [r] * 2)).stable for r in ("1/2", "3/4")]
    [False, True]
    """
    model, q, listed, qc = _monotone_recovery(system, fail, recover, sensor)
    if qc is not None:
        return qc
    intervals = listed()
    if not intervals:
        return AlgebraicNumber.from_expr(1)
    if len(intervals) != 1 or intervals[0][1] != 1:
        shown = ", ".join(f"({float(a):.6g}, {float(b):.6g})" for a, b in intervals)
        raise AssumptionError(f"the filter is stable exactly for recover in {shown}, not on an interval (q_c, 1)",
                              assumption="stability monotone in the recovery probability",
                              applies_instead="symkf.stable_recovery_intervals")
    qc = intervals[0][0]
    if qc > 0:
        lo, hi = qc.refine(min(sp.Rational(1, 10 ** 12), sp.Rational(qc.interval[0]) / 4 or 1)).interval
        while lo <= 0:
            lo, hi = qc.refine(sp.Rational(hi - lo) / 4).interval
        width = min(sp.Rational(hi - lo), sp.Rational(lo) / 2) or min(sp.Rational(1, 10 ** 12), sp.Rational(lo) / 2)
        # the simplest rationals there: the end points of a refined root of degree 48 have
        # 4000-digit terms, and the verdict's exact rates at them grow with their height
        below = sp.Rational(simplest(Fraction(sp.Rational(lo) - width), Fraction(lo)))
        above = sp.Rational(simplest(Fraction(hi), Fraction(sp.Rational(hi) + width)))
        if stability(system, model.subs({q: below})).stable or not stability(system, model.subs({q: above})).stable:
            raise AssertionError(f"certificate failed around q_c = {qc}")  # pragma: no cover
    return qc

check_public(globals())
