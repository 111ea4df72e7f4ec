"""Hypothesis strategies for property tests of multi-sensor Kalman filtering.

Every strategy draws exact data (integers, rationals, ``cos(pi p/q)``) and
validates its arguments up front, raising hypothesis' ``InvalidArgument``
with the argument's name.

A user's own property test, checking simulation against the hand-derived
critical loss rate of a single sensor ``C = [1, 0]`` watching ``A = r R(pi
p/q)``: rows ``C A^k`` are parallel exactly when ``q | k``, so the cheapest
blinding pattern loses ``q - 1`` packets per ``q`` steps while ``P`` grows by
``r^(2q)``, and ``eps_c = r^(-2q/(q-1))`` (``1/16`` for the ``design-rotation`` example
``r = 2``, ``q = 2``)::

    from hypothesis import given, settings
    from symkf import strategies as sks
    from symkf.model.iid import IID
    from symkf.montecarlo import divergence_test

    @settings(derandomize=True, max_examples=10, deadline=None)
    @given(sks.rotation_systems(scale="3/2", max_denominator=4).flatmap(
        lambda rot: sks.loss_rates_near(rot.critical_loss_rate(), "1/4", side="above").map(
            lambda eps: (rot, eps))))
    def test_unstable_above_critical(case):
        rot, eps = case
        q = rot.angle.denominator
        result = divergence_test(rot.system, IID([eps]), seed=0,
                                 pattern=[[0]] * (q - 1) + [[]], growth=rot.scale ** (2 * q))
        assert result.verdict == "unstable"
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any, NamedTuple, Sequence

import sympy as sp

from ..arguments import check_public
from ..errors import InexactInputError, require_extra

require_extra("hypothesis", "strategies", "symkf.model.strategies")
from hypothesis import strategies as st  # noqa: E402
from hypothesis.errors import InvalidArgument  # noqa: E402

from ..exact.linalg import rank  # noqa: E402
from ..exact.numbers import to_exact  # noqa: E402
from .gilbert_elliott import GilbertElliott  # noqa: E402
from .iid import IID  # noqa: E402
from .system import Sensor, System  # noqa: E402


def _exact(value: Any, name: str) -> sp.Expr:
    try:
        return to_exact(value, name)
    except InexactInputError:   # strategies take no rationalize=: say what they do take
        raise InvalidArgument(f"{name}: the float {value!r} is not exact; give the string {str(value)!r}, "
                              "a Fraction or a Decimal") from None
    except Exception as exc:
        text = str(exc)
        raise InvalidArgument(text if text.startswith(f"{name}:") else f"{name}: {text}") from None


def _check_int(value: Any, name: str, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise InvalidArgument(f"{name}={value!r}: expected an integer in [{low}, {high}]")
    return value


def rational_angles(max_denominator: int = 12) -> st.SearchStrategy[Fraction]:
    """Fractions ``p/q`` in (0, 1) in lowest terms with ``q <= max_denominator`` (angle ``pi p/q``)."""
    _check_int(max_denominator, "max_denominator", 2, 360)
    return st.builds(Fraction, st.integers(1, max_denominator - 1),
                     st.integers(2, max_denominator)).filter(
        lambda f: 0 < f < 1 and f.denominator <= max_denominator)


class Rotation(NamedTuple):
    """A drawn rotation system: ``A = scale * R(pi * angle)``, sensor ``C = [1, 0]``."""

    system: System
    scale: sp.Expr
    angle: Fraction

    def critical_loss_rate(self) -> sp.Expr:
        """Hand-derived ``r^(-2q/(q-1))``, ``q`` the angle's denominator (module docstring)."""
        q = self.angle.denominator
        return self.scale ** sp.Rational(-2 * q, q - 1)


def rotation_systems(scale: Any = "3/2", max_denominator: int = 12) -> st.SearchStrategy[Rotation]:
    """Second-order ``A = scale * [[cos t, -sin t], [sin t, cos t]]``, ``t = pi p/q`` in (0, pi), ``C = [1, 0]``."""
    r = _exact(scale, "scale")
    if not r.is_positive:
        raise InvalidArgument(f"scale={scale!r}: expected a positive number")

    def build(f: Fraction) -> Rotation:
        t = sp.pi * sp.Rational(f.numerator, f.denominator)
        S = System(A=[[r * sp.cos(t), -r * sp.sin(t)], [r * sp.sin(t), r * sp.cos(t)]],
                   sensors=[Sensor(C=[[1, 0]])])
        return Rotation(S, r, f)
    return rational_angles(max_denominator).map(build)


def complex_diagonal_systems(n: int = 2, moduli: Sequence[Any] = ("3/2",),
                             max_denominator: int = 12) -> st.SearchStrategy[System]:
    """``A = diag(r_j exp(i pi p_j/q_j))`` with ``r_j`` from ``moduli``, one sensor ``C = [1, ..., 1]``."""
    _check_int(n, "n", 1, 4)
    rs = [_exact(m, f"moduli[{i}]") for i, m in enumerate(moduli)]
    if not rs or any(not r.is_positive for r in rs):
        raise InvalidArgument(f"moduli={moduli!r}: expected a non-empty list of positive numbers")

    def build(parts) -> System:
        diag = [r * sp.exp(sp.I * sp.pi * sp.Rational(f.numerator, f.denominator)) for r, f in parts]
        return System(A=sp.diag(*diag), sensors=[Sensor(C=[[1] * n])])
    entry = st.tuples(st.sampled_from(rs), rational_angles(max_denominator))
    return st.lists(entry, min_size=n, max_size=n).filter(
        lambda parts: len({(r, f) for r, f in parts}) == n).map(build)


def _unimodular(n: int) -> st.SearchStrategy[sp.Matrix]:
    """Integer matrices of determinant 1 (products of elementary shears), so ``T^{-1}`` is integral."""
    shear = st.tuples(st.integers(0, n - 1), st.integers(0, n - 1), st.integers(-2, 2)).filter(
        lambda s: s[0] != s[1])

    def build(shears) -> sp.Matrix:
        T = sp.eye(n)
        for i, j, c in shears:
            E = sp.eye(n)
            E[i, j] = c
            T = T * E
        return T
    return st.lists(shear, min_size=0, max_size=2 * n).map(build)


def diagonalizable_systems(blocks: Sequence[tuple[Any, int]], sensors: int = 1,
                           observable: bool = True) -> st.SearchStrategy[System]:
    """``A = T diag(...) T^{-1}`` with a chosen eigen-block structure, n <= 4, rational entries.

    ``blocks`` lists ``(modulus, size)``: each block holds ``size`` real
    eigenvalues ``+-modulus`` (distinct within the block when ``size = 2``,
    so blocks of equal modulus mix signs).  ``T`` is an integer unimodular
    matrix.  ``sensors`` integer rows are drawn; ``observable=True`` keeps
    draws with ``(A, C)`` observable (the papers' standing assumption),
    ``observable=False`` makes every sensor blind to the first eigenvector,
    violating it (the strategy returns ``(A, [C_i])`` instead; constructing a
    :class:`System` raises ``UnobservableError`` when that eigenvalue has
    ``|lambda| >= 1``, since symkf needs detectability only).
    """
    if not isinstance(blocks, (list, tuple)) or not blocks:
        raise InvalidArgument(f"blocks={blocks!r}: expected a non-empty list of (modulus, size)")
    eig: list[sp.Expr] = []
    for i, b in enumerate(blocks):
        if not isinstance(b, (list, tuple)) or len(b) != 2:
            raise InvalidArgument(f"blocks[{i}]={b!r}: expected (modulus, size)")
        m = _exact(b[0], f"blocks[{i}] modulus")
        if not (m.is_Rational and m > 0):
            raise InvalidArgument(f"blocks[{i}] modulus={b[0]!r}: expected a positive rational")
        size = _check_int(b[1], f"blocks[{i}] size", 1, 2)
        eig += [m, -m][:size]
    n = len(eig)
    if n > 4 or len(set(eig)) != n:
        raise InvalidArgument(f"blocks={blocks!r}: need n <= 4 distinct eigenvalues, got {eig}")
    _check_int(sensors, "sensors", 1, 4)
    row = st.lists(st.integers(-2, 2), min_size=n, max_size=n)

    def build(draw_T, rows):
        T = draw_T
        A = T * sp.diag(*eig) * T.inv()
        Cs = [sp.Matrix([r]) for r in rows]
        if not observable:
            v = T[:, 0]          # the first eigenvector: made invisible to every sensor
            Cs = [C - (C * v)[0, 0] * sp.Matrix([[1 if j == _pivot(v) else 0 for j in range(n)]]) / v[_pivot(v)]
                  for C in Cs]
            return A, Cs
        return System(A=A, sensors=[Sensor(C=C) for C in Cs])

    def keep(T_rows) -> bool:
        T, rows = T_rows
        A = T * sp.diag(*eig) * T.inv()
        C = sp.Matrix(rows)
        if not observable:
            return True
        obs = sp.Matrix.vstack(*[C * A ** k for k in range(n)])
        return rank(obs) == n
    pairs = st.tuples(_unimodular(n), st.lists(row, min_size=sensors, max_size=sensors))
    return pairs.filter(keep).map(lambda tr: build(*tr))


class Drawn(NamedTuple):
    """A drawn system with what its construction knows: ``A = T J T^{-1}`` and the columns of ``T``
    spanning the generalized eigenspace of ``|lambda| >= 1`` (for :mod:`symkf.engine.oracle`)."""

    system: System
    unstable_basis: sp.Matrix


def jordan_systems(chains: Sequence[tuple[Any, int]], sensors: int = 1) -> st.SearchStrategy[Drawn]:
    """Detectable systems ``A = T J T^{-1}`` with Jordan chains, zero and stable eigenvalues, n <= 4.

    ``chains`` lists ``(eigenvalue, length)`` (rational eigenvalues, chain length 1-3); ``J`` is
    block diagonal with one Jordan block per chain, ``T`` integer unimodular.  ``sensors``
    integer rows are drawn and draws with ``(A, C)`` detectable (PBH on ``|lambda| >= 1``) kept:
    stable modes may be unseen, chains may be defective, singular ``A`` is allowed.
    """
    if not isinstance(chains, (list, tuple)) or not chains:
        raise InvalidArgument(f"chains={chains!r}: expected a non-empty list of (eigenvalue, length)")
    lams, lengths = [], []
    for i, c in enumerate(chains):
        if not isinstance(c, (list, tuple)) or len(c) != 2:
            raise InvalidArgument(f"chains[{i}]={c!r}: expected (eigenvalue, length)")
        lam = _exact(c[0], f"chains[{i}] eigenvalue")
        if not lam.is_Rational:
            raise InvalidArgument(f"chains[{i}] eigenvalue={c[0]!r}: expected a rational")
        lams.append(lam)
        lengths.append(_check_int(c[1], f"chains[{i}] length", 1, 3))
    n = sum(lengths)
    if n > 4:
        raise InvalidArgument(f"chains={chains!r}: total length {n} > 4")
    _check_int(sensors, "sensors", 1, 3)
    J = sp.diag(*[sp.Matrix(k, k, lambda i, j: lam if i == j else (1 if j == i + 1 else 0))
                  for lam, k in zip(lams, lengths)])
    unstable = [c for c, lam in enumerate(v for lam, k in zip(lams, lengths) for v in [lam] * k) if abs(lam) >= 1]
    row = st.lists(st.integers(-2, 2), min_size=n, max_size=n)

    def detectable(T_rows) -> bool:
        T, rows = T_rows
        A, C = T * J * T.inv(), sp.Matrix(rows)
        return all(rank(sp.Matrix.vstack(A - lam * sp.eye(n), C)) == n for lam in set(lams) if abs(lam) >= 1)

    def build(T_rows) -> Drawn:
        T, rows = T_rows
        system = System(A=T * J * T.inv(), sensors=[Sensor(C=[r]) for r in rows])
        return Drawn(system, T[:, unstable] if unstable else sp.zeros(n, 0))
    pairs = st.tuples(_unimodular(n), st.lists(row, min_size=sensors, max_size=sensors))
    return pairs.filter(detectable).map(build)


def _pivot(v: sp.Matrix) -> int:
    return next(i for i in range(len(v)) if v[i] != 0)


def iid_losses(d: int, low: Any = 0, high: Any = "9/10", max_denominator: int = 100) -> st.SearchStrategy[IID]:
    """``IID`` models with rational loss probabilities in ``[low, high]``."""
    _check_int(d, "d", 1, 8)
    lo, hi = _exact(low, "low"), _exact(high, "high")
    if not (0 <= lo <= hi <= 1):
        raise InvalidArgument(f"low={low!r}, high={high!r}: need 0 <= low <= high <= 1")
    return st.lists(_rationals_between(lo, hi, max_denominator), min_size=d, max_size=d).map(IID)


def gilbert_elliott_losses(d: int, max_denominator: int = 20) -> st.SearchStrategy[GilbertElliott]:
    """``GilbertElliott`` models with fail and recover probabilities in (0, 1)."""
    _check_int(d, "d", 1, 8)
    _check_int(max_denominator, "max_denominator", 2, 10 ** 6)
    p = _rationals_between(sp.Rational(1, max_denominator), 1 - sp.Rational(1, max_denominator), max_denominator)
    return st.tuples(st.lists(p, min_size=d, max_size=d), st.lists(p, min_size=d, max_size=d)).map(
        lambda fr: GilbertElliott(fail=fr[0], recover=fr[1]))


def _rationals_between(lo: sp.Expr, hi: sp.Expr, max_denominator: int) -> st.SearchStrategy[sp.Rational]:
    """Rationals ``k / max_denominator`` in ``[lo, hi]`` (``lo``, ``hi`` exact; may be algebraic)."""
    _check_int(max_denominator, "max_denominator", 2, 10 ** 6)
    k_lo = int(sp.ceiling(lo * max_denominator))
    k_hi = int(sp.floor(hi * max_denominator))
    if k_lo > k_hi:
        raise InvalidArgument(f"no rational with denominator {max_denominator} in [{lo}, {hi}]; "
                              "raise max_denominator")
    return st.integers(k_lo, k_hi).map(lambda k: sp.Rational(k, max_denominator))


def loss_rates_near(critical: Any, margin: Any, side: str, max_denominator: int = 1000) -> st.SearchStrategy[sp.Rational]:
    """Rational loss rates at relative distance ``margin`` to ``2 margin`` from an exact critical value.

    ``side="below"``: ``eps / critical in [1 - 2 margin, 1 - margin]``
    (stable side of an i.i.d. threshold); ``side="above"``: in ``[1 + margin,
    1 + 2 margin]``, capped below 1.  ``critical`` may be algebraic (e.g. an
    ``AlgebraicNumber``'s ``.exact``).
    """
    c = _exact(getattr(critical, "exact", critical), "critical")
    m = _exact(margin, "margin")
    if not (c.is_positive and (c - 1).is_negative):
        raise InvalidArgument(f"critical={critical!r}: expected a number in (0, 1)")
    if not (m.is_positive and (m - sp.Rational(1, 2)).is_negative):
        raise InvalidArgument(f"margin={margin!r}: expected a number in (0, 1/2)")
    if side == "below":
        lo, hi = c * (1 - 2 * m), c * (1 - m)
    elif side == "above":
        lo, hi = c * (1 + m), sp.Min(c * (1 + 2 * m), 1 - sp.Rational(1, max_denominator))
        if (lo - hi).is_positive:
            raise InvalidArgument(f"critical={critical!r}, margin={margin!r}: critical * (1 + margin) "
                                  "leaves no loss rate below 1")
    else:
        raise InvalidArgument(f"side={side!r}: expected 'below' or 'above'")
    return _rationals_between(lo, hi, max_denominator)


__all__ = ["Drawn", "Rotation", "jordan_systems", "complex_diagonal_systems", "diagonalizable_systems", "gilbert_elliott_losses",
           "iid_losses", "loss_rates_near", "rational_angles", "rotation_systems"]

check_public(globals())
