"""Verdicts do not depend on coordinates: a change of state basis, a rescaled sensor row and a
renumbering of the sensors leave every exact answer as it was.

``x = T z`` turns ``(A, C_i)`` into ``(T^{-1} A T, C_i T)``: the rows ``C_i A^k`` are those of the
new system times ``T^{-1}``, so every rank, hyperplane and loss pattern of Sui-You-Fu (2014) is
the same, and so are the critical loss rate and every margin ``alpha_i^2 rho_i``.  A row
``c C_i`` (``c != 0``) spans the same lines; renumbering the sensors renumbers their losses.  The
engine sees none of this: block-diagonal ``A`` with rotation blocks becomes a dense matrix over
``Q(sqrt 2, sqrt 3)``, whose eigen-blocks, Jordan chains, modal forms and number fields it finds
afresh.
"""

from __future__ import annotations

from fractions import Fraction

import sympy as sp
from hypothesis import assume, given, settings, strategies as st

import symkf as sk
from conftest import rotation
from symkf.errors import BudgetError, SymkfError
from symkf.exact.algebraic import AlgebraicNumber
from symkf.model.gilbert_elliott import GilbertElliott
from symkf.model.iid import IID

ANGLES = [sp.pi / 2, sp.pi / 3, sp.pi / 4, sp.pi / 6, 2 * sp.pi / 3, 3 * sp.pi / 4]
MODULI = [sp.Rational(3, 2), sp.Integer(2)]
REALS = [sp.Rational(3, 2), sp.Integer(-2), sp.Rational(1, 2)]
SCALES = [sp.Integer(-2), sp.Rational(-1, 2), sp.Rational(1, 3), sp.Integer(3)]
PROBABILITY = st.fractions(Fraction(1, 20), Fraction(9, 10), max_denominator=20).map(str)


@st.composite
def changes_of_coordinates(draw):
    """A detectable system (rotation blocks and perhaps a real eigenvalue, alone or in a Jordan chain
    of length 2; integer sensor rows), a nonsingular integer ``T``, nonzero row scales and a
    permutation of the sensors."""
    blocks = [rotation(scale=draw(st.sampled_from(MODULI)), angle=draw(st.sampled_from(ANGLES)))
              for _ in range(draw(st.integers(1, 2)))]
    blocks += [sp.Matrix([[r, 1], [0, r]]) if draw(st.booleans()) else sp.Matrix([[r]])
               for r in draw(st.lists(st.sampled_from(REALS), max_size=1))]
    A = sp.diag(*blocks)
    n = A.shape[0]
    d = draw(st.integers(1, 3))
    rows = draw(st.lists(st.lists(st.integers(-2, 2), min_size=n, max_size=n).filter(any), min_size=d, max_size=d))
    try:
        system = sk.System(A=A, sensors=[sk.Sensor(C=[r]) for r in rows])
    except SymkfError:   # not detectable: the papers' standing assumption fails
        assume(False)
    T = sp.Matrix(draw(st.lists(st.lists(st.integers(-2, 2), min_size=n, max_size=n), min_size=n, max_size=n)))
    assume(T.det() != 0)
    scales = draw(st.lists(st.sampled_from(SCALES), min_size=d, max_size=d))
    order = draw(st.permutations(range(d)))
    moved = sk.System(A=T.inv() * A * T,
                      sensors=[sk.Sensor(C=[list(scales[i] * sp.Matrix([rows[i]]) * T)]) for i in order])
    return system, moved, order


def exactly_equal(u, v) -> bool:
    return AlgebraicNumber.from_expr(u) == AlgebraicNumber.from_expr(v)


def same_verdict(a: sk.Verdict, b: sk.Verdict) -> bool:
    """The same stability and the same margins (as a multiset: blocks may be found in another order)."""
    ma, mb = (sorted((m.exact for m in v.margins), key=float) for v in (a, b))
    return bool(a) == bool(b) and len(ma) == len(mb) and all(exactly_equal(u, v) for u, v in zip(ma, mb))


@settings(max_examples=12, deadline=None)
@given(changes_of_coordinates(), st.data())
def test_verdicts_do_not_depend_on_coordinates(case, data):
    system, moved, order = case
    d = len(order)
    losses, fail, recover = (data.draw(st.lists(PROBABILITY, min_size=d, max_size=d)) for _ in range(3))
    renumbered = lambda values: [values[i] for i in order]
    iid, ge = IID(losses), GilbertElliott(fail, recover)
    try:
        answers = sk.critical_loss_rate(system), sk.stability(system, iid), sk.stability(system, ge)
    except BudgetError:   # a chain beside rotations of its modulus: hyperplanes listed, some beyond the cap
        assume(False)
    assert exactly_equal(answers[0], sk.critical_loss_rate(moved))
    assert same_verdict(answers[1], sk.stability(moved, IID(renumbered(losses))))
    assert same_verdict(answers[2], sk.stability(moved, GilbertElliott(renumbered(fail), renumbered(recover))))
