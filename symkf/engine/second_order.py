"""Second-order systems under i.i.d. losses: congruent sets and the Theorem 12 closed form.

Sui-You-Fu, Section 4 (Sui-You-Fu).  ``A`` (2x2) has two distinct eigenvalues of
one modulus ``alpha > 0`` (Assumption 5, up to similarity: ``alpha diag(e^{i
theta_1}, e^{i theta_2})`` and the real rotation ``alpha R(theta)`` alike);
losses are independent Bernoulli with arrival rates ``p_i`` (Assumption 4);
``rank col{C_i, C_j} = 2`` and ``(A, C_i)`` is observable (Assumption 6).

* Definition 1: ``J_i = {j : span C_i = span C_j A^{k_ij} for some 0 <= k_ij < tau}``;
* eq. (37): ``p_i^* = prod_{j in J_i} (1 - p_j)``;
* Theorem 12 as printed, eq. (38): stable iff
  ``alpha^(2 tau) prod_i (1 - p_i)^tau / min_j p_j^* < 1``.

Two corrections, each with a counterexample in ``proofs/sui_theorem12.py``:

1. **Governing period.**  Rows ``C A^k`` and ``C A^(k+g)`` are parallel as soon as
   ``A^g`` is a scalar multiple of ``I`` (the governing period ``g``, which divides
   ``tau``), so the rank-deficient patterns repeat with period ``g``, not ``tau``.
   The correct condition is (38) with ``tau`` replaced by ``g``:
   ``alpha^(2g) prod_i (1 - p_i)^g < min_j p_j^*``, i.e. per period ``g``,
   ``alpha^(2g) max_i prod_j (1 - p_j)^(g - [j in J_i]) < 1`` (the form used here,
   which stays meaningful when some ``p_j = 1``).  ``J_i`` is the same under both
   readings (shifts repeat with period ``g``).  When ``g`` is infinite the
   condition is ``alpha^2 prod_i (1 - p_i) < 1``.  ``A = [[0, -2], [2, 0]]``,
   ``C = [1, 0]``: ``tau = 4``, ``g = 2``; the critical loss rate is ``1/16``
   (engine and enumeration), (38) gives ``2^(-8/3)``.
2. **Rank-one sensors.**  Definition 1 and (38) presuppose ``rank C_i = 1``: a
   sensor with ``rank C_i = 2`` makes ``O_N`` full rank on any reception, so it
   lies in no rank-deficient pattern and must be left out of every ``J_i``
   (literally, Definition 1 puts all rank-2 sensors into one congruent set).
   ``A = 2 R(pi/2)``, ``C = I``: critical loss ``1/4``, (38) gives ``4^(-4/3)``.

``period="tau"`` evaluates the statement as printed (literal Definition 1,
exponent ``tau``); the default ``period="governing"`` is the corrected one.
Remark 11 (sensors whose stacked ``C`` has rank one are merged into one sensor
with arrival ``1 - (1 - p_i)(1 - p_j)``) is applied automatically and reported.
Outside Assumptions 4-6 every function raises :class:`~symkf.errors.AssumptionError`
naming the assumption and pointing to the general engine, :mod:`symkf.engine.stability`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal, Sequence

import sympy as sp

from ..arguments import check_public
from .. import output
from ..errors import AperiodicError, AssumptionError, InputError
from ..exact.algebraic import AlgebraicNumber
from ..exact.field import Elem, NumberField
from ..exact.linalg import field_of, rank_rows
from ..exact.numbers import sympify, to_exact
from ..model.loss import LossModel, checked
from ..model.system import Sensor, System
from ..exact.spectral import eigen_blocks
from .stability import BlockCertificate, Verdict

Period = Literal["governing", "tau"]
ENGINE = "symkf.critical_loss_rate / symkf.stability (the general engine)"
ALPHA = sp.Symbol("alpha", positive=True)


@dataclass(frozen=True)
class CongruentSets:
    """Definition 1 for a second-order system, after Remark 11's merging.

    ``groups[i]`` are the original sensors (indices) merged into sensor ``i``;
    ``sets[i]`` is ``J_i`` (indices of merged sensors) and ``shifts[i][j]`` is
    ``k_ij`` (least shift, ``0 <= k_ij < g``).  ``full_rank`` lists the merged
    sensors with ``rank C_i = 2``; ``sets`` follows Definition 1 literally, so
    they form one congruent set with shifts 0 (the correction drops them).
    """

    names: tuple[str, ...]
    groups: tuple[tuple[int, ...], ...]
    sets: tuple[frozenset[int], ...]
    shifts: tuple[dict[int, int], ...]
    full_rank: frozenset[int]
    alpha: sp.Expr
    tau: int | None
    governing_period: int | None

    @property
    def merges(self) -> tuple[tuple[int, ...], ...]:
        """Remark 11: the groups of two or more original sensors that were merged."""
        return tuple(g for g in self.groups if len(g) > 1)

    def decisive_sets(self, period: Period = "governing") -> tuple[tuple[int, frozenset[int]], ...]:
        """``(i, J_i)`` entering (38): all of them as printed; only rank-one sensors' when corrected."""
        return tuple((i, J) for i, J in enumerate(self.sets) if period == "tau" or i not in self.full_rank)

    def exponent(self, period: Period = "governing") -> int | None:
        """The period in (38): ``tau`` as printed, ``g`` corrected; None when infinite."""
        return self.tau if period == "tau" else self.governing_period

    def p_star(self, arrival: Sequence[Any]) -> tuple[sp.Expr, ...]:
        """eq. (37) for the merged sensors, from the original sensors' arrival rates."""
        d = sum(map(len, self.groups))
        if len(arrival) != d:   # counted before a rate is read
            raise InputError(f"arrival: {len(arrival)} rates for {d} sensors")
        miss = merged_losses(self, [1 - to_exact(p, f"arrival[{i}]", symbols=True) for i, p in enumerate(arrival)])
        return tuple(sp.Mul(*[miss[j] for j in sorted(J)]) for J in self.sets)


def _check_period(period: str) -> None:
    if period not in ("governing", "tau"):
        raise InputError(f"period: expected 'governing' (corrected Theorem 12) or 'tau' (as printed), got {period!r}")


def second_order_form(system: System) -> tuple[sp.Expr, int | None, int | None]:
    """``(alpha, tau, g)`` after checking Assumption 5 (up to similarity)."""
    if not isinstance(system, System):
        raise InputError(f"system: expected a symkf.System, got {type(system).__name__}")
    assumption = "Assumption 5 (Sui-You-Fu)"
    if system.n != 2:
        raise AssumptionError(f"A is {system.n}x{system.n}; Theorem 12 is for second-order systems",
                              assumption=assumption, applies_instead=ENGINE)
    blocks = eigen_blocks(system.A)
    if len(blocks) != 1:
        moduli = ", ".join(str(b.modulus) for b in blocks)
        raise AssumptionError(f"the eigenvalues of A have different moduli ({moduli})",
                              assumption=assumption, applies_instead=ENGINE)
    block = blocks[0]
    if len(block.members) != 2:
        raise AssumptionError(f"A has the repeated eigenvalue {block.eigenvalues[0]} (theta_1 = theta_2)",
                              assumption=assumption, applies_instead=ENGINE)
    return block.modulus.exact, block.period, block.governing_period


def _times(K: NumberField, rows: list[list[Elem]], A: list[list[Elem]]) -> list[list[Elem]]:
    return [K.vecmat(r, A) for r in rows]


def _sensor_groups(system: System, K: NumberField, A: list[list[Elem]]) -> tuple[list[list[int]], list[int]]:
    """Remark 11 merging (rank-one sensors with one row space) and Assumption 6, exactly."""
    Cs = [K.matrix(s.C) for s in system.sensors]
    ranks = [rank_rows(K, C, 2) for C in Cs]
    groups: list[list[int]] = []
    for j, C in enumerate(Cs):
        for g in groups:
            if ranks[j] == ranks[g[0]] == 1 and rank_rows(K, Cs[g[0]] + C, 2) == 1:
                g.append(j)
                break
        else:
            groups.append([j])
    for g in groups:
        C = Cs[g[0]]
        if rank_rows(K, C + _times(K, C, A), 2) < 2:
            name = system.sensor_names[g[0]]
            raise AssumptionError(f"(A, C_{name}) is not observable (C_{name} = {system.sensors[g[0]].C.tolist()})",
                                  assumption="Assumption 6 (Sui-You-Fu)", applies_instead=ENGINE)
    return groups, ranks


def congruent_sets(system: System) -> CongruentSets:
    """Congruent sets ``J_i`` with shifts ``k_ij`` (Definition 1), exactly, after Remark 11.

    Raises :class:`~symkf.errors.AssumptionError` (Assumptions 5, 6) and
    :class:`~symkf.errors.AperiodicError` when ``g`` is infinite (then no
    ``J_i`` enters Theorem 12: use :func:`theorem12`).

    Parameters
    ----------
    system : System
        A 2 x 2 ``A`` with two distinct eigenvalues of one modulus (Assumption 5) and sensors
        satisfying Assumption 6.

    Returns
    -------
    CongruentSets
        ``.names``, ``.groups`` (Remark 11's merging), ``.sets`` (``J_i`` as index sets),
        ``.shifts`` (``k_ij``), ``.full_rank``, ``.alpha``, ``.tau`` and ``.governing_period``.

    Raises
    ------
    AssumptionError
        Assumption 5 or 6 fails; the message points to the general engine.
    AperiodicError
        ``A^k`` is never a scalar multiple of ``I``.

    Examples
    --------
    ``A = 2R(pi/2)`` with sensors ``[1, 0]`` and ``[0, 1]``.  By hand: ``[0, 1] A = [2, 0]``
    spans ``C_1`` and ``[1, 0] A = [0, -2]`` spans ``C_2``, so both sensors form one
    congruent set with shifts ``k_12 = k_21 = 1``; ``g = 2`` (``A^2 = -4I``), ``tau = 4``:

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[0, 1]], name="s2")])
    >>> cs = sk.second_order.congruent_sets(S)
    >>> [sorted(J) for J in cs.sets], cs.shifts, cs.governing_period, cs.tau
    ([[0, 1], [0, 1]], ({0: 0, 1: 1}, {0: 1, 1: 0}), 2, 4)

    Eigenvalues of different moduli are outside Assumption 5:

    >>> sk.second_order.congruent_sets(sk.System(A=[[2, 0], [0, 3]], sensors=[sk.Sensor(C=[[1, 1]])]))
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    symkf.errors.AssumptionError: Assumption 5 (Sui-You-Fu) fails: the eigenvalues of A have different moduli ...
    """
    cs = _analysis(system)[0]
    if cs is None:
        raise AperiodicError("A^k is never a scalar multiple of I (g infinite); Definition 1 needs "
                             "no congruent sets then, Theorem 12 reads alpha^2 prod(1 - p_i) < 1",
                             assumption="Definition 1 (Sui-You-Fu): periodic A",
                             applies_instead="symkf.second_order.theorem12 or " + ENGINE)
    return cs


def _congruent_sets(system: System, K: NumberField, A: list[list[Elem]], groups: list[list[int]],
                    ranks: list[int], alpha: sp.Expr, tau: int | None, g: int) -> CongruentSets:
    """Definition 1 by exact rank tests of ``col{C_i, C_j A^k}``, ``0 <= k < g`` (shifts repeat mod g)."""
    powers = []  # powers[j][k] = C_j A^k, one representative per merged sensor
    for grp in groups:
        rows = K.matrix(system.sensors[grp[0]].C)
        seq = []
        for _ in range(g):
            seq.append(rows)
            rows = _times(K, rows, A)
        powers.append(seq)
    full = frozenset(i for i, grp in enumerate(groups) if ranks[grp[0]] == 2)
    sets, shifts = [], []
    for i in range(len(groups)):
        shift: dict[int, int] = {}
        for j in range(len(groups)):
            if (i in full) != (j in full):
                continue
            for k in range(g):
                if i in full or rank_rows(K, powers[i][0] + powers[j][k], 2) == 1:
                    shift[j] = k
                    break
        sets.append(frozenset(shift))
        shifts.append(shift)
    names = tuple("+".join(system.sensor_names[j] for j in grp) for grp in groups)
    return CongruentSets(names, tuple(tuple(grp) for grp in groups), tuple(sets), tuple(shifts),
                         full, alpha, tau, g)


def merged_losses(cs: CongruentSets, losses: Any) -> list[sp.Expr]:
    """Remark 11: a merged sensor loses a packet iff all its members do."""
    return [sp.Mul(*[to_exact(losses[j], f"losses[{j}]", symbols=True) for j in grp]) for grp in cs.groups]


def _analysis(system: System) -> tuple[CongruentSets | None, sp.Expr, int | None, int | None, int]:
    """Congruent sets (None when g is infinite) and (alpha, tau, g, d), cached on the system."""
    hit = system._cache.get("second_order")
    if hit is None:
        alpha, tau, g = second_order_form(system)
        K = field_of(system.A, *[s.C for s in system.sensors])
        A = K.matrix(system.A)
        groups, ranks = _sensor_groups(system, K, A)
        cs = None if g is None else _congruent_sets(system, K, A, groups, ranks, alpha, tau, g)
        hit = system._cache["second_order"] = (cs, alpha, tau, g, system.d)
    return hit


def _candidates(cs: CongruentSets, miss: list[sp.Expr], P: int, period: Period) \
        -> list[tuple[int | None, sp.Expr]]:
    """Per congruent set ``J_i``: ``(i, prod_j miss_j^(P - [j in J_i]))``, the per-period probability
    that only the elements on the line of ``(i, 0)`` are received; the empty line (``i`` None)
    is always a candidate."""
    out: list[tuple[int | None, sp.Expr]] = [(None, sp.Mul(*[m ** P for m in miss]))]
    for i, J in cs.decisive_sets(period):
        out.append((i, sp.Mul(*[m ** (P - (1 if j in J else 0)) for j, m in enumerate(miss)])))
    return out


def _require_iid(system: System, loss: LossModel) -> tuple[sp.Expr, ...]:
    """The per-sensor loss probabilities of i.i.d. ``loss`` (Assumption 4), checked against ``system``."""
    losses = checked(loss, system).require_bernoulli("Assumption 4 (Sui-You-Fu)", "symkf.stability")
    if loss.symbols:
        raise InputError(f"loss: symbols {sorted(map(str, loss.symbols))} have no value; use threshold(system) "
                         "for the condition in symbols")
    return losses


def theorem12(system: System, loss: LossModel, period: Period = "governing") -> Verdict:
    """Mean-square stability from the closed form of Theorem 12 (eq. 38), exactly.

    Corrected (default): stable iff ``alpha^(2g) max_i prod_j (1 - p_j)^(g - [j in J_i]) < 1``
    over the rank-one sensors' congruent sets, ``alpha^2 prod_j (1 - p_j) < 1`` when
    ``g`` is infinite.  ``period="tau"``: eq. (38) as printed.  Same
    :class:`~symkf.engine.stability.Verdict` as the engine, margin ``alpha^2 rho``.
    """
    _check_period(period)
    losses = _require_iid(system, loss)
    cs, alpha, tau, g, _ = _analysis(system)
    P = tau if period == "tau" else g
    assumptions = ["A similar to alpha diag(e^{i theta_1}, e^{i theta_2}), theta_1 != theta_2 (Assumption 5)",
                   "i.i.d. independent losses (Assumption 4)",
                   "(A, C_i) observable for every sensor (Assumption 6)"]
    if P is None:
        miss = losses
        power, rate, elements, P_cert = alpha ** 2 * sp.Mul(*miss), sp.Mul(*miss), (), 1
    else:
        miss = merged_losses(cs, losses)
        cands = _candidates(cs, miss, P, period)
        i, rate = max(cands, key=lambda c: AlgebraicNumber.from_expr(c[1]))
        names = system.sensor_names
        elements = () if i is None else tuple(
            (names[o], cs.shifts[i][j]) for j in sorted(cs.sets[i]) for o in cs.groups[j])
        power, P_cert = alpha ** (2 * P) * rate, P
        merged = ", ".join(name for name, grp in zip(cs.names, cs.groups) if len(grp) > 1)
        assumptions += [f"Remark 11: merged sensors {merged} (arrival 1 - prod(1 - p_j))"] if cs.merges else []
    power = sympify(power)
    margin = AlgebraicNumber.from_expr(sp.root(power, P_cert) if P_cert > 1 else power)
    cert = BlockCertificate(alpha, P_cert, elements, sympify(rate), power,
                            margin.refine(sp.Rational(1, 10 ** 12)).interval)
    name = ("Theorem 12 (Sui-You-Fu) as printed: period tau" if period == "tau"
            else "Theorem 12 (Sui-You-Fu), corrected: governing period g, rank-one congruent sets")
    return Verdict(margin < 1, (margin,), 0, name, tuple(assumptions), (cert,))


def _exponent_count(cs: CongruentSets, period: Period) -> int:
    """``J = max_i sum_{j in J_i} |group_j|``: the original sensors on the best line."""
    return max((sum(len(cs.groups[j]) for j in J) for _, J in cs.decisive_sets(period)), default=0)


def critical_loss_expr(system: System, period: Period = "governing") -> sp.Expr:
    """The critical common loss probability as a sympy expression in the symbol ``alpha``.

    All ``d`` (original) sensors lose packets with probability ``eps``: stable iff
    ``eps < min(1, alpha^(-2g / (g d - J)))`` with ``J`` the number of original
    sensors on the best line; ``min(1, alpha^(-2/d))`` when ``g`` is infinite.
    """
    _check_period(period)
    cs, _, tau, g, d = _analysis(system)
    P = tau if period == "tau" else g
    if P is None:
        return sp.Min(1, ALPHA ** sp.Rational(-2, d))
    return sp.Min(1, ALPHA ** sp.Rational(-2 * P, P * d - _exponent_count(cs, period)))


def critical_loss_rate(system: System, period: Period = "governing") -> AlgebraicNumber:
    """The critical common i.i.d. loss probability from the closed form (stable iff loss < value).

    Corrected Theorem 12 (default): ``min(1, alpha^(-2g/(g d - J)))``, ``g`` the governing
    period (least ``k`` with ``A^k`` a scalar multiple of ``I``), ``d`` the number of
    sensors and ``J`` the largest number of sensors in one congruent set of rank-one
    sensors (Remark 11 merges count their members); ``min(1, alpha^(-2/d))`` if ``g``
    is infinite.  ``period="tau"`` gives eq. (38) as printed, which is wrong whenever
    ``g < tau`` or a sensor has rank 2 (see the module docstring).

    Parameters
    ----------
    system : System
        Within Assumptions 5 and 6 (see :func:`congruent_sets`).
    period : {"governing", "tau"}, default "governing"
        ``"governing"``: the corrected Theorem 12; ``"tau"``: eq. (38) as printed.

    Returns
    -------
    AlgebraicNumber
        The critical common loss probability; 1 when no loss rate below 1 destabilises.

    Raises
    ------
    AssumptionError
        Assumption 5 or 6 fails; :func:`symkf.engine.stability.critical_loss_rate` applies instead.
    InputError
        ``period`` is neither ``"governing"`` nor ``"tau"``.

    Examples
    --------
    The first counterexample of the module docstring, ``A = 2R(pi/2)``, ``C = [1, 0]``
    (``g = 2``, ``tau = 4``, ``d = J = 1``): the corrected form gives
    ``2^(-4/(2 - 1)) = 1/16``, as the general engine does, while (38) as printed gives
    ``2^(-8/(4 - 1)) = 2^(-8/3)``:

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    >>> sk.second_order.critical_loss_rate(S).exact, sk.critical_loss_rate(S).exact
    (1/16, 1/16)
    >>> sk.second_order.critical_loss_rate(S, period="tau").exact
    2**(1/3)/8

    With the sensors of :func:`congruent_sets` (one set, ``J = 2``, ``d = 2``):
    ``2^(-4/(4 - 2)) = 1/4``:

    >>> S2 = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[0, 1]])])
    >>> sk.second_order.critical_loss_rate(S2).exact
    1/4
    """
    alpha = _analysis(system)[1]
    return AlgebraicNumber.from_expr(sympify(critical_loss_expr(system, period).subs(ALPHA, alpha)))


def arrival_symbols(system: System) -> tuple[sp.Symbol, ...]:
    """``p_1, ..., p_d``: the arrival probabilities of the original sensors."""
    return sp.symbols(f"p_1:{system.d + 1}", positive=True)


def _miss_symbols(cs: CongruentSets | None, system: System) -> list[sp.Expr]:
    p = arrival_symbols(system)
    return [1 - q for q in p] if cs is None else merged_losses(cs, [1 - q for q in p])


def threshold(system: System, period: Period = "governing") -> sp.Basic:
    """The stability condition as a sympy relation in ``alpha`` and ``p_1, ..., p_d``.

    Corrected: ``And`` over the rank-one congruent sets of
    ``alpha^(2g) prod_j (1 - p_j)^(g - [j in J_i]) < 1``.  ``period="tau"``: eq. (38)
    as printed, ``alpha^(2 tau) prod (1 - p_i)^tau / Min(p_1^*, ...) < 1``.
    """
    _check_period(period)
    cs, _, tau, g, _ = _analysis(system)
    miss = _miss_symbols(cs, system)
    P = tau if period == "tau" else g
    if P is None:
        return sp.StrictLessThan(ALPHA ** 2 * sp.Mul(*miss), 1)
    if period == "tau":
        p_star = [sp.Mul(*[miss[j] for j in sorted(J)]) for J in cs.sets]
        return sp.StrictLessThan(ALPHA ** (2 * P) * sp.Mul(*[m ** P for m in miss]) / sp.Min(*p_star), 1)
    return sp.And(*[sp.StrictLessThan(ALPHA ** (2 * P) * r, 1) for _, r in _candidates(cs, miss, P, period)[1:]]
                  or [sp.StrictLessThan(ALPHA ** (2 * P) * sp.Mul(*[m ** P for m in miss]), 1)])


def theorem12_alpha_expr(system: System, period: Period = "governing") -> sp.Expr:
    """The critical modulus as a sympy expression in ``p_1, ..., p_d``: stable iff alpha < value."""
    _check_period(period)
    cs, _, tau, g, _ = _analysis(system)
    miss = _miss_symbols(cs, system)
    P = tau if period == "tau" else g
    if P is None:
        return sp.Mul(*miss) ** sp.Rational(-1, 2)
    rates = [r for _, r in _candidates(cs, miss, P, period)]
    return sp.Min(*[r ** sp.Rational(-1, 2 * P) for r in (rates[1:] or rates)])


def theorem12_alpha(system: System, loss: LossModel, period: Period = "governing") -> AlgebraicNumber:
    """The critical modulus for the given losses, eigen-directions fixed (exact)."""
    losses = _require_iid(system, loss)
    cs, _, tau, g, _ = _analysis(system)
    P = tau if period == "tau" else g
    if P is None:
        rate, P = sp.Mul(*losses), 1
    else:
        rate = max((r for _, r in _candidates(cs, merged_losses(cs, losses), P, period)),
                   key=AlgebraicNumber.from_expr)
    if rate == 0:
        raise InputError("loss: the decisive pattern has probability 0, so no alpha destabilises the filter")
    return AlgebraicNumber.from_expr(sp.root(1 / sympify(rate), 2 * P))


def counterexamples() -> list[tuple[str, System]]:
    """The systems on which (38) as printed fails (see the module docstring and proofs/sui_theorem12.py)."""
    lam = 2 * (3 + 4 * sp.I) / 5
    return [
        ("2R(pi/2), C = [1, 0] (tau = 4, g = 2)", System(A=[[0, -2], [2, 0]], sensors=_sensors([[1, 0]]))),
        ("2diag(e^(i pi/6), e^(7i pi/6)), C = [1, 1] (tau = 12, g = 2)",
         System(A=sp.diag(2 * sp.exp(sp.I * sp.pi / 6), 2 * sp.exp(7 * sp.I * sp.pi / 6)), sensors=_sensors([[1, 1]]))),
        ("diag(2(3+4i)/5, -2(3+4i)/5), C = [1, 1] (tau infinite, g = 2)",
         System(A=sp.diag(lam, -lam), sensors=_sensors([[1, 1]]))),
        ("2R(pi/2), C = I (rank 2)", System(A=[[0, -2], [2, 0]], sensors=_sensors([[1, 0], [0, 1]]))),
    ]


def _sensors(C: Any) -> list[Sensor]:
    return [Sensor(C=C)]


def _number(a: AlgebraicNumber) -> dict:
    return {"exact": str(a.exact), "decimal": str(a.evalf(10))}


def reproduce_sui_theorem12(outdir: str | None = None) -> dict:
    """Theorem 12 as printed and corrected, against the engine: the counterexamples and the
    rotations ``2 R(pi/g)``, ``C = [1, 0]``, ``g = 2..12`` (``tau = 2g``); figure of the critical
    loss rates against ``g`` when ``outdir`` is given.  Where eq. (38) as printed differs from
    the engine, both values are a discrepancy."""
    if outdir is not None:   # refused before the work, not after it
        output.plan_directory(outdir, "outdir")
    from ..reproduction import discrepancy, reproduction
    from .stability import critical_loss_rate as engine

    results: dict[str, Any] = {"counterexamples": {}, "rotations_2R(pi/g)": []}
    checks: dict[str, bool] = {}
    discrepancies = []
    printed_claim = "Theorem 12 (eq. (38) with exponent tau) as printed gives the critical loss rate: "
    for label, S in counterexamples():
        printed, corrected, exact = critical_loss_rate(S, "tau"), critical_loss_rate(S), engine(S)
        _, tau, g = second_order_form(S)
        results["counterexamples"][label] = {"tau": tau, "g": g, "printed": _number(printed),
                                             "corrected": _number(corrected), "engine": _number(exact)}
        checks[f"Theorem 12 corrected (period g) gives the critical loss rate: {label}"] = corrected == exact
        if printed != exact:
            discrepancies.append(discrepancy(printed_claim + label, printed.exact, exact.exact))
    rows = []
    for g in range(2, 13):
        theta = sp.pi / g
        S = System(A=[[2 * sp.cos(theta), -2 * sp.sin(theta)], [2 * sp.sin(theta), 2 * sp.cos(theta)]],
                   sensors=_sensors([[1, 0]]))
        printed, corrected, exact = critical_loss_rate(S, "tau"), critical_loss_rate(S), engine(S)
        rows.append((g, printed, corrected, exact))
        results["rotations_2R(pi/g)"].append({"g": g, "tau": second_order_form(S)[1], "printed": _number(printed),
                                              "corrected": _number(corrected), "engine": _number(exact)})
    discrepancies += [discrepancy(f"{printed_claim}rotations 2R(pi/g), C = [1, 0]: g = {g}, tau = {2 * g}",
                                  p.exact, e.exact) for g, p, _, e in rows if p != e]
    checks["Theorem 12 corrected gives the critical loss rate: 2R(pi/g), g = 2..12"] = all(
        c == e for _, _, c, e in rows)
    if outdir is not None:
        import os

        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5, 3.5))
        gs = [r[0] for r in rows]
        ax.plot(gs, [float(r[3]) for r in rows], "ko", label="exact (engine)")
        ax.plot(gs, [float(r[2]) for r in rows], "C1-", label=r"corrected: $2^{-2g/(g-1)}$")
        ax.plot(gs, [float(r[1]) for r in rows], "C0--", label=r"(38) as printed: $2^{-4g/(2g-1)}$")
        ax.set_xlabel(r"governing period $g$ ($A = 2R(\pi/g)$, $\tau = 2g$)")
        ax.set_ylabel("critical loss rate")
        ax.legend()
        fig.tight_layout()
        path = os.path.join(output.plan_directory(outdir, "outdir"), "sui_theorem12.png")
        results["figure"] = str(output.save_figure(fig, path, "outdir", dpi=120))
        plt.close(fig)
    return reproduction("sui-theorem12", "Sui-You-Fu, Section 4, Definition 1, eqs. (37)-(38), "
                        "Theorem 12", results, checks, discrepancies)

check_public(globals())
