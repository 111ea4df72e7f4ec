"""One row of the atlas: a published result's claim about the stable parameter set, beside the exact one.

Every result is read as a claim about the set of stable values of one channel parameter ``t``
in ``(0, 1)``: the common i.i.d. loss probability ``eps`` (the engine's set is ``(0, eps_c)``)
or the common Gilbert-Elliott recovery probability ``q`` at the file's failure rates (a union
of open intervals, not always ``(q_c, 1)``).  A result is

* ``exact``: its set is the stable set;
* ``sufficient``: its set lies inside the stable set (a lower bound on ``eps_c``);
* ``necessary``: the stable set lies inside its set (an upper bound on ``eps_c``);
* ``other``: a statement about another estimator, shown beside the exact set, not compared.

The relation is decided exactly (end points are algebraic numbers): ``equal``, ``holds``
(with the gap: the difference of the sets' lengths, exact, with certified rational bounds),
``violated`` (a finding: the result's hypotheses hold and its claim fails), or, for a value
known only through a certified bracket (an LMI bisection), ``inside bracket`` when the exact
value falls between the two certificates.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Callable, Sequence

import sympy as sp

from ..arguments import check_public
from ..errors import AssumptionError, BudgetError
from ..exact.algebraic import AlgebraicNumber
from ..exact.numbers import to_exact

Interval = tuple[AlgebraicNumber, AlgebraicNumber]

EXACT, SUFFICIENT, NECESSARY, OTHER = "exact", "sufficient", "necessary", "other"
EQUAL, HOLDS, VIOLATED, INSIDE, NOT_APPLICABLE, NOT_COMPARED, REFUSED = (
    "equal", "holds", "violated", "inside bracket", "does not apply", "not compared", "refused")


def number(value: Any) -> AlgebraicNumber:
    """An exact value as an :class:`AlgebraicNumber` (radicals simplified first); anything but a
    sympy expression goes through the safe parser (:func:`symkf.exact.numbers.to_exact`)."""
    if isinstance(value, AlgebraicNumber):
        return value
    expr = value if isinstance(value, sp.Basic) else to_exact(value, "value")
    return AlgebraicNumber.from_expr(sp.radsimp(expr))


@dataclass(frozen=True)
class Quantity:
    """The varied parameter and its exact stable set (from the engine).

    ``kind`` is ``"iid"`` (common loss ``eps``, stable set ``(0, eps_c)``) or
    ``"gilbert-elliott"`` (common recovery ``q`` at failure rates ``fail``)."""

    kind: str
    symbol: str
    words: str
    stable: tuple[Interval, ...]
    critical: AlgebraicNumber | None      # eps_c, or q_c when the stable set is (q_c, 1)
    fail: tuple[sp.Expr, ...] = ()
    rates: tuple[sp.Expr, ...] = ()       # an i.i.d. model's own per-sensor loss rates, if given

    @property
    def iid(self) -> bool:
        return self.kind == "iid"

    def below(self, value: Any) -> tuple[Interval, ...]:
        """``{t in (0, 1) : t < value}``."""
        v = number(value)
        return () if v <= 0 else ((number(0), v if v < 1 else number(1)),)

    def above(self, value: Any) -> tuple[Interval, ...]:
        """``{t in (0, 1) : t > value}``."""
        v = number(value)
        return () if v >= 1 else ((v if v > 0 else number(0), number(1)),)


@dataclass(frozen=True)
class Hypothesis:
    """One hypothesis of a result, checked exactly: ``holds`` and what was found; ``refused`` when a
    cap refused its check (it does not hold then, and the row is refused, the cap named in ``detail``)."""

    name: str
    holds: bool
    detail: str = ""
    refused: bool = False

    def __str__(self) -> str:
        word = "NOT CHECKED" if self.refused else "holds" if self.holds else "FAILS"
        return f"{self.name}: {word}" + (f" ({self.detail})" if self.detail else "")


@dataclass(frozen=True)
class Row:
    """A result's reading on one system (module docstring)."""

    key: str
    result: str                       # "Sinopoli et al. 2004, LMI (Thm. 5)"
    citation: str
    statement: str                    # the claim, in the row's words
    claim: str                        # exact | sufficient | necessary | other
    hypotheses: tuple[Hypothesis, ...]
    stable: tuple[Interval, ...] | None = None    # the result's set of t
    value: AlgebraicNumber | None = None          # its threshold, when the set is (0, v) or (v, 1)
    bracket: tuple[sp.Expr, sp.Expr] | None = None  # certified bracket of the threshold
    relation: str = NOT_APPLICABLE
    gap: dict[str, Any] | None = None
    note: str = ""
    certificate: tuple[str, ...] = field(default=())

    @property
    def applies(self) -> bool:
        return all(h.holds for h in self.hypotheses)

    @property
    def failed(self) -> Hypothesis | None:
        """The first hypothesis that fails, or None."""
        return next((h for h in self.hypotheses if not h.holds), None)


def _inside(inner: Sequence[Interval], outer: Sequence[Interval]) -> bool:
    return all(any(c <= a and b <= d for c, d in outer) for a, b in inner)


def _length(intervals: Sequence[Interval]) -> sp.Expr:
    return sp.Add(*[hi.exact - lo.exact for lo, hi in intervals])


def _length_bounds(intervals: Sequence[Interval]) -> tuple[Fraction, Fraction]:
    return (sum((hi.interval[0] - lo.interval[1] for lo, hi in intervals), Fraction(0)),
            sum((hi.interval[1] - lo.interval[0] for lo, hi in intervals), Fraction(0)))


def _gap(big: Sequence[Interval], small: Sequence[Interval]) -> dict[str, Any]:
    """Length of ``big`` minus length of ``small``: exact, with certified rational bounds."""
    b, s = _length_bounds(big), _length_bounds(small)
    return {"exact": sp.radsimp(_length(big) - _length(small)),
            "interval": (max(b[0] - s[1], Fraction(0)), b[1] - s[0])}


def _same(a: Sequence[Interval], b: Sequence[Interval]) -> bool:
    return len(a) == len(b) and all(x[0] == y[0] and x[1] == y[1] for x, y in zip(a, b))


def compare(claim: str, stable: Sequence[Interval], exact: Sequence[Interval]) -> tuple[str, dict | None]:
    """The relation of a result's set to the exact stable set (module docstring)."""
    if claim == OTHER:
        return NOT_COMPARED, None
    if _same(stable, exact):
        return EQUAL, None
    if claim == SUFFICIENT and _inside(stable, exact):
        return HOLDS, _gap(exact, stable)
    if claim == NECESSARY and _inside(exact, stable):
        return HOLDS, _gap(stable, exact)
    return VIOLATED, None


def compare_bracket(lo: sp.Expr, hi: sp.Expr, exact: AlgebraicNumber) -> tuple[str, dict | None]:
    """A sufficient threshold known to lie in ``[lo, hi]``, certified stable at ``lo``, against ``eps_c``.

    ``violated`` when ``eps_c <= lo`` (the certificate at ``lo`` proves stability there),
    ``holds`` when ``eps_c >= hi``, else ``inside bracket``."""
    a, b = number(lo), number(hi)
    if exact <= a:
        return VIOLATED, None
    gap = {"exact": None, "interval": (max(Fraction(exact.interval[0]) - b.interval[1], Fraction(0)),
                                       exact.interval[1] - a.interval[0])}
    return (HOLDS if exact >= b else INSIDE), gap


def row(key: str, result: str, citation: str, statement: str, claim: str,
        hypotheses: Sequence[Hypothesis], quantity: Quantity,
        evaluate: Callable[[], tuple[tuple[Interval, ...], AlgebraicNumber | None]], note: str = "") -> Row:
    """A row whose result gives a set of ``t``: evaluated (and compared) only when every hypothesis holds.

    ``evaluate`` returns the result's stable set and its threshold (or None); an
    :class:`AssumptionError` it raises is a hypothesis that fails (named by the error), a
    :class:`BudgetError` a computation refused (relation ``refused``, the cap named in the note)."""
    hyps = tuple(hypotheses)
    base = dict(key=key, result=result, citation=citation, statement=statement, claim=claim, note=note)
    refused = next((h for h in hyps if h.refused), None)
    if refused is not None:   # a cap refused a hypothesis's check: the row is refused, not the atlas
        return Row(**{**base, "note": refused.detail}, hypotheses=hyps, relation=REFUSED)
    if not all(h.holds for h in hyps):
        return Row(**base, hypotheses=hyps)
    try:
        stable, value = evaluate()
    except AssumptionError as exc:
        return Row(**base, hypotheses=hyps + (Hypothesis(exc.assumption, False, str(exc)),))
    except BudgetError as exc:   # a cap refuses this row's computation, not the atlas; its message is the note
        return Row(**{**base, "note": str(exc)}, hypotheses=hyps, relation=REFUSED)
    relation, gap = compare(claim, stable, quantity.stable)
    return Row(**base, hypotheses=hyps, stable=tuple(stable), value=value, relation=relation, gap=gap)


check_public(globals())
