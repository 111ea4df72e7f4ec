"""The atlas: every implemented published result on one system, beside the exact stable set.

:func:`bounds` builds the :class:`Quantity` (the varied channel parameter and its exact stable
set from the engine) and one :class:`~symkf.bounds.row.Row` per result, in the order of
:data:`RESULTS`.  :class:`Atlas` renders as text, JSON (exact numbers as
:func:`symkf.numeric.verify.number_json` objects) and a booktabs table (:class:`symkf.reports.tables.Table`).
"""

from __future__ import annotations

import math
import textwrap

from dataclasses import dataclass
from typing import Any, Callable

import sympy as sp

from ..output import JsonDocument
from ..arguments import check_public
from ..errors import InputError
from ..exact.algebraic import AlgebraicNumber
from ..exact.text import algebraic_text
from ..model.loss import LossModel, checked
from ..model.system import System
from ..engine.stability import critical_loss_rate
from ..engine.recovery import stable_recovery_intervals
from ..reports.tables import Cell, Table, escape
from ..io.families import Column, Inapplicable, Query, register_query
from ..numeric.verify import number_json
from . import huang_dey, mo_sinopoli, plarre_bullo, sinopoli, sources, you_fu_xie
from .row import EQUAL, HOLDS, INSIDE, NOT_COMPARED, REFUSED, VIOLATED, Quantity, Row, number

#: the results, in the order of the table (each a function (system, quantity) -> Row; the LMI's
#: also takes its bisection steps)
RESULTS: tuple[Callable[[System, Quantity], Row], ...] = (
    *sinopoli.ROWS, *plarre_bullo.ROWS, *mo_sinopoli.ROWS, *you_fu_xie.ROWS, *huang_dey.ROWS, *sources.ROWS)


def quantity(system: System, loss: LossModel | None = None) -> tuple[Quantity, str]:
    """The parameter the rows speak about, with the exact stable set, and a note on ``loss``.

    Independent Gilbert-Elliott channels (the model's ``channel_fail``) select the common recovery
    probability at their failure rates; any other model, or none, the common i.i.d. loss
    probability; i.i.d. losses (the model's ``bernoulli``) keep their rates for the multi-sensor
    LMI's verdict at those rates (every other row is about a threshold)."""
    fail = None if loss is None else loss.channel_fail
    if fail is not None:
        stable = stable_recovery_intervals(system, list(fail))
        one = len(stable) == 1 and stable[0][1] == 1
        return (Quantity("gilbert-elliott", "q", "common Gilbert-Elliott recovery probability q = P(received | "
                         f"lost last), fail {', '.join(map(str, fail))}", stable, stable[0][0] if one else None,
                         tuple(fail)), "")
    eps = critical_loss_rate(system)
    rates = () if loss is None or loss.bernoulli is None else tuple(loss.bernoulli)
    note = "" if loss is None or rates else (
        f"the loss model ({loss.words()}) is neither i.i.d. nor Gilbert-Elliott channels; the atlas compares "
        "the common i.i.d. critical loss probability")
    zero = number(0)
    return Quantity("iid", "eps", "common i.i.d. loss probability eps of every sensor",
                    ((zero, eps),) if eps > 0 else (), eps, rates=rates), note


@dataclass(frozen=True)
class Atlas(JsonDocument):
    """The rows of :func:`bounds` on one system."""

    system: System
    quantity: Quantity
    rows: tuple[Row, ...]
    note: str = ""

    def row(self, key: str) -> Row:
        """The row of result ``key`` (e.g. ``"sinopoli-lmi"``)."""
        for r in self.rows:
            if r.key == key:
                return r
        raise InputError(f"key: no row {key!r}; rows: {', '.join(r.key for r in self.rows)}")

    @property
    def violations(self) -> tuple[Row, ...]:
        """Rows whose hypotheses hold and whose claim fails (findings)."""
        return tuple(r for r in self.rows if r.relation == VIOLATED)

    def to_dict(self) -> dict[str, Any]:
        q = self.quantity
        out = {"system": self.system.name or "", "quantity": {"kind": q.kind, "parameter": q.symbol, "words": q.words,
                                                               "stable_set": _intervals_json(q.stable),
                                                               "critical": _num(q.critical)},
               "rows": [_row_json(r) for r in self.rows], "violations": [r.key for r in self.violations]}
        if self.note:
            out["note"] = self.note
        return out

    def __repr__(self) -> str:
        """One line: the parameter, the exact stable set, how many results apply and hold (the
        rows in full: ``print(atlas)``)."""
        q = self.quantity
        applying = [r for r in self.rows if r.applies]
        return (f"<Atlas {self.system.name or 'system'}: {q.symbol} stable in {_intervals_text(q.stable)}; "
                f"{len(self.rows)} results, {len(applying)} apply, {len(self.violations)} violated>")

    def _repr_latex_(self) -> str:
        """The rows that apply and the exact value, as :meth:`table` shows them (a notebook)."""
        return self.table()._repr_latex_()

    def __str__(self) -> str:
        q = self.quantity
        lines = [f"parameter: {q.words}", f"exact (symkf engine): stable for {q.symbol} in {_intervals_text(q.stable)}"]
        if self.note:
            lines.append(f"note: {self.note}")
        unmet: dict[str, list[str]] = {}   # the results that do not apply, by the hypothesis that fails
        for r in self.rows:
            if not r.applies:
                unmet.setdefault(str(r.failed), []).append(r.result)
                continue
            lines.append(f"- {r.result}: {r.statement}")
            if r.relation == REFUSED:
                lines.append(f"    not evaluated: {r.note}")
                continue
            lines.append(f"    value: {_value_text(r, q)}; relation: {_relation_text(r)}")
        for failed, results in unmet.items():
            lines.append(textwrap.fill(f"- does not apply ({failed}): {'; '.join(results)}", 100,
                                       subsequent_indent="    ", break_long_words=False, break_on_hyphens=False))
        return "\n".join(lines)

    def table(self) -> Table:
        """A booktabs table for a related-work section: result, claim, value, relation; the results
        that do not apply are listed under it, grouped by the hypothesis that fails."""
        q = self.quantity
        name = self.system.name or "the system"
        symbol = _SYMBOLS.get(q.symbol, q.symbol)
        caption_text = (f"Published results on {name} beside the exact stable set of {q.symbol} "
                        f"({q.words}; symkf: {_intervals_text(q.stable)}).")
        caption = (rf"Published results on {escape(name)} beside the exact stable set of ${symbol}$ "
                   rf"({escape(q.words.replace(q.symbol + ' ', '').replace(' ' + q.symbol, ''))}; exact: "
                   rf"${_intervals_latex(q.stable)}$).")
        columns = (Cell.text("claim"), Cell.text("value"), Cell.text("relation"))
        rows = [(Cell.text(r.result), (Cell.text(r.claim), _value_cell(r, q), Cell.text(_relation_short(r))))
                for r in self.rows if r.applies]
        exact = _exact_cell(q)
        rows.append((Cell.text("exact (symkf)"), (Cell.text("exact"), exact, Cell.text(""))))
        groups: dict[str, list[str]] = {}
        for r in self.rows:
            if not r.applies:
                groups.setdefault(r.failed.name, []).append(r.result)
        words = [f"Not applicable here (hypothesis \"{why}\" fails): {'; '.join(names).rstrip('.')}."
                 for why, names in groups.items()]
        notes = tuple((escape(w), w) for w in words)
        return Table(caption, caption_text, Cell.text("result"), columns, tuple(rows),
                     label="tab:bounds-atlas", size=r"\footnotesize", metadata={"system": self.system.name or ""},
                     notes=notes, spec=r"p{0.3\linewidth}cc" + r"p{0.22\linewidth}")

    def to_latex(self) -> str:
        return self.table().to_latex()


def bounds(system: System, loss: LossModel | None = None, *, lmi_steps: int = sinopoli.LMI_STEPS) -> Atlas:
    """Every implemented published result for ``system`` beside the exact critical value.

    Parameters
    ----------
    system : System
    loss : LossModel, optional
        A Gilbert-Elliott model makes the rows speak about the common recovery probability at
        its failure rates; otherwise (default) about the common i.i.d. loss probability.
    lmi_steps : int
        Bisection steps of Sinopoli et al.'s LMI threshold (each halves its certified bracket).

    Returns
    -------
    Atlas
        One :class:`~symkf.bounds.row.Row` per result: hypotheses checked exactly (the first
        failing one named), the result's value (exact, or a certified bracket for the LMI),
        and its relation to the exact value (``equal``, ``holds`` with the gap, ``violated``).

    Examples
    --------
    ``A = 2R(pi/2)``, ``C = [1 0]``: the exact critical loss is ``1/16`` (Sui-You-Fu); Sinopoli
    et al.'s necessary bound ``1/rho(A)^2 = 1/4`` holds with gap ``3/16``, and the system is
    degenerate in Mo and Sinopoli's sense (``p = 2``: ``2^(-4) = 1/16``):

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    >>> atlas = sk.bounds(S, lmi_steps=2)
    >>> atlas.quantity.critical.exact
    1/16
    >>> r = atlas.row("sinopoli-lower"); r.relation, r.gap["exact"]
    ('holds', 3/16)
    >>> atlas.row("mo-sinopoli").failed.name
    'non-degenerate'
    >>> atlas.row("mo-sinopoli-degenerate").relation
    'equal'
    """
    if not isinstance(system, System):
        raise InputError(f"system: expected a symkf.System, got {type(system).__name__}")
    if loss is not None and not isinstance(loss, LossModel):
        raise InputError(f"loss: expected a symkf loss model or None, got {type(loss).__name__}")
    loss = None if loss is None else checked(loss, system)
    if not isinstance(lmi_steps, int) or not 0 <= lmi_steps <= 60:
        raise InputError(f"lmi_steps: expected an integer in [0, 60], got {lmi_steps!r}")
    q, note = quantity(system, loss)
    rows = tuple(result(system, q, lmi_steps) if result is sinopoli.lmi else result(system, q) for result in RESULTS)
    return Atlas(system, q, rows, note)


def bounds_columns(system: System, loss: LossModel | None = None) -> tuple[tuple[Column, Any], ...]:
    """:func:`bounds` as columns of a family table (``compute = ["bounds"]``): one per published
    result, its value where its hypotheses hold (a cell as in :meth:`Atlas.table`, with the row's
    relation to the exact value in its JSON data), :class:`~symkf.io.families.Inapplicable` naming
    the failed hypothesis where they do not; then the exact value."""
    atlas = bounds(system, loss)
    q = atlas.quantity
    out: list[tuple[Column, Any]] = []
    for r in atlas.rows:
        column = Column(r.key, escape(r.result))
        if not r.applies:
            out.append((column, Inapplicable(f"{r.result}: hypothesis \"{r.failed.name}\" fails")))
            continue
        cell = _value_cell(r, q)
        out.append((column, Cell(cell.plain, cell.latex, cell.math, {
            "result": r.key, "parameter": q.symbol, "relation": r.relation, "value": _num(r.value),
            "bracket": None if r.bracket is None else [str(v) for v in r.bracket]})))
    exact = _exact_cell(q)
    out.append((Column(f"exact {q.symbol}", "exact"), Cell(exact.plain, exact.latex, exact.math, {
        "parameter": q.symbol, "critical": _num(q.critical), "stable_set": _intervals_json(q.stable)})))
    return tuple(out)


register_query(Query(
    "bounds", bounds_columns, False,
    (r"the published results on the critical common i.i.d.\ loss probability $\varepsilon$ (for Gilbert--Elliott "
     r"channels: the common recovery probability $q$), each where its hypotheses hold, beside the exact value "
     r"(\texttt{symkf bounds})",
     "the published results on the critical common i.i.d. loss probability eps (for Gilbert-Elliott channels: the "
     "common recovery probability q), each where its hypotheses hold, beside the exact value (symkf bounds)"),
    Column("bounds", "published bounds")))


def _num(a: AlgebraicNumber | None) -> dict | None:
    return None if a is None else number_json(a)


def _intervals_json(intervals: Any) -> list | None:
    return None if intervals is None else [[number_json(lo), number_json(hi)] for lo, hi in intervals]


#: the LaTeX of the atlas's parameters
_SYMBOLS = {"eps": r"\varepsilon", "q": "q"}


def _intervals_latex(intervals: Any) -> str:
    if not intervals:
        return r"\emptyset"
    return r" \cup ".join(rf"({_short_latex(lo)},\ {_short_latex(hi)})" for lo, hi in intervals)


def _short_latex(value: AlgebraicNumber) -> str:
    """The exact value when its LaTeX is short, else its decimal."""
    if value.exact.has(sp.CRootOf) or len(sp.latex(value.exact)) > MAX_EXACT_CELL:
        return rf"\approx {value.evalf(4)}"
    return sp.latex(value.exact)


def _intervals_text(intervals: Any) -> str:
    if not intervals:
        return "no value in (0, 1)"
    return " u ".join(f"({algebraic_text(lo)}, {algebraic_text(hi)})" for lo, hi in intervals)


def _row_json(r: Row) -> dict[str, Any]:
    failed = r.failed
    return {"key": r.key, "result": r.result, "citation": r.citation, "statement": r.statement, "claim": r.claim,
            "applies": r.applies, "hypotheses": [{"name": h.name, "holds": h.holds, "detail": h.detail, "refused": h.refused}
                                                 for h in r.hypotheses],
            "failed": None if failed is None else {"name": failed.name, "detail": failed.detail},
            "value": _num(r.value), "stable_set": _intervals_json(r.stable),
            "bracket": None if r.bracket is None else [str(v) for v in r.bracket],
            "relation": r.relation,
            "gap": None if r.gap is None else {"exact": None if r.gap["exact"] is None else str(r.gap["exact"]),
                                               "interval": [str(v) for v in r.gap["interval"]]},
            "certificate": list(r.certificate), "note": r.note}


def _value_text(r: Row, q: Quantity) -> str:
    if r.bracket is not None:
        lo, hi = r.bracket
        return f"threshold in [{lo}, {hi}] (certified) ~ [{float(lo):.6g}, {float(hi):.6g}]"
    if r.value is not None and r.stable is not None and len(r.stable) <= 1:
        side = "<" if q.iid else ">"
        return f"stable for {q.symbol} {side} {algebraic_text(r.value)}"
    if not r.stable:
        return f"stable for no {q.symbol} in (0, 1)"
    return f"stable for {q.symbol} in {_intervals_text(r.stable)}"


def _gap_text(r: Row) -> str:
    """The gap in words: exact when it is rational, else a decimal read off its certified bounds."""
    if not r.gap:
        return ""
    lo, hi = r.gap["interval"]
    exact = r.gap["exact"]
    if exact is not None and exact.is_Rational:
        return f", gap {exact}"
    if exact is not None:
        return f", gap approx. {float((lo + hi) / 2):.4g}"
    return f", gap in [{float(lo):.4g}, {float(hi):.4g}]"


def _relation_text(r: Row) -> str:
    words = {EQUAL: "equal to the exact value", HOLDS: f"{r.claim} condition holds", VIOLATED: "VIOLATED (a finding)",
             INSIDE: "the exact value lies inside the certified bracket", NOT_COMPARED: f"not compared: {r.note}"}
    return words.get(r.relation, r.relation) + _gap_text(r)


def _relation_short(r: Row) -> str:
    if not r.applies:
        return f"n/a: {r.failed.name.split(' (')[0]}"
    if r.relation == HOLDS and r.gap["exact"] is None:
        return f"holds, gap <= {float(r.gap['interval'][1]):.3g}"
    if r.relation == HOLDS:
        return "holds" + _gap_text(r)
    return {NOT_COMPARED: "another estimator", INSIDE: "brackets the exact value",
            REFUSED: "not evaluated (a symkf.budget cap)"}.get(r.relation, r.relation)


def _value_cell(r: Row, q: Quantity) -> Cell:
    if not r.applies or r.relation == REFUSED:
        return Cell.text("---")
    if r.bracket is not None:
        lo, hi = r.bracket
        if len(sp.latex(lo)) + len(sp.latex(hi)) > MAX_EXACT_CELL:   # decimals, outward (exact in the JSON)
            low, high = math.floor(float(lo) * 1e4) / 1e4, math.ceil(float(hi) * 1e4) / 1e4
            return Cell.formula(rf"[{low:.4f},\ {high:.4f}]", f"[{low:.4f}, {high:.4f}]")
        return Cell.formula(rf"[{sp.latex(lo)},\ {sp.latex(hi)}]", f"[{lo}, {hi}]")
    if r.value is not None and r.stable is not None and len(r.stable) <= 1:
        return _number_cell(r.value)
    return Cell.text(_intervals_text(r.stable) if r.stable else "empty")


def _number_cell(value: AlgebraicNumber) -> Cell:
    """Exact over its decimal when the exact form is short; else the decimal (exact in the JSON)."""
    if value.exact.has(sp.CRootOf) or len(sp.latex(value.exact)) > MAX_EXACT_CELL:
        decimal = str(value.evalf(4))
        return Cell.formula(rf"\approx {decimal}", f"~ {decimal}")
    return Cell.number(value, 4)


#: longer exact forms than this (LaTeX characters) are shown as decimals in the table
MAX_EXACT_CELL = 24


def _exact_cell(q: Quantity) -> Cell:
    if q.critical is not None:
        return _number_cell(q.critical)
    return Cell.text(_intervals_text(q.stable))


__all__ = ["Atlas", "bounds", "bounds_columns", "quantity", "RESULTS"]


check_public(globals())
