"""LaTeX tables (booktabs) of exact critical loss rates and stability verdicts.

:class:`Table` renders as a complete ``table`` environment needing only
``\\usepackage{booktabs}`` (:meth:`Table.to_latex`), as plain text for terminals
(``str``), as a MathJax array in Jupyter (``_repr_latex_``) and as JSON
(:meth:`Table.to_dict`).  Numeric cells keep the exact value (sympy LaTeX, or the
minimal polynomial where no radical form exists) with a decimal read off a
certified isolating interval.

* :func:`family_table` -- the queries of a parameter family (a TOML family file or one built in
  memory, see :mod:`symkf.io.families`): critical loss and recovery rates, common or per sensor,
  verdicts, margins, the fewest stable sensors, the published bounds, the critical control-packet
  arrival rate of LQG control (exact, or its certified bracket ``[lower, upper]``), evaluated with
  :func:`symkf.run.sweep.sweep`;
* :func:`verdict_table` -- the stability verdicts of system files with a ``[loss]``
  (by default the papers' examples, ``symkf/io/examples/systems/``).

The engine is Sui-You-Fu Theorems 4 and 7 with eq. (36) in hyperplane form
(:mod:`symkf.engine.stability`), with the rows ``C_j A^k`` grouped over each eigen-block's
class period (its governing period, the least ``k`` with ``A_i^k`` a scalar multiple of ``I``,
when the block is periodic).
"""

from __future__ import annotations

import re
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import sympy as sp

from ..output import JsonDocument
from ..arguments import check_public
from ..io import examples
from .. import output
from ..errors import InputError
from ..exact.algebraic import AlgebraicNumber, terminating_decimal
from ..exact.text import algebraic_text, number_text
from ..io.families import Column, Family, Inapplicable, Member, Outcome, load_family
from ..design.selection import Selection
from ..engine.stability import Verdict
from ..control import ControlThreshold
from ..run.sweep import sweep

_ENGINE = ("symkf (Sui--You--Fu Theorems~4 and~7 with eq.~(36), hyperplane form; the rows "
           "$C_jA^k$ of each eigen-block are grouped over its class period $g$ (the governing period, the least "
           "$k$ with $A_i^k$ a scalar multiple of $I$, when the block is periodic), and margins are compared with~1 exactly)")
_LATEX_SPECIAL = {"&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_", "{": r"\{", "}": r"\}",
                  "~": r"\textasciitilde{}", "^": r"\textasciicircum{}", "\\": r"\textbackslash{}"}


def escape(text: str) -> str:
    """``text`` as literal LaTeX text."""
    return "".join(_LATEX_SPECIAL.get(c, c) for c in text)


@dataclass(frozen=True)
class Cell:
    """One table entry in its three renderings, plus JSON data."""

    plain: str
    latex: str    # LaTeX text mode (inside a tabular)
    math: str     # LaTeX math mode (inside a MathJax array)
    data: Any = None

    @classmethod
    def text(cls, text: str) -> "Cell":
        """A cell of literal text (escaped for LaTeX)."""
        return cls(text, escape(text), rf"\text{{{escape(text)}}}", text)

    @classmethod
    def formula(cls, latex: str, plain: str) -> "Cell":
        """A cell holding the LaTeX formula ``latex``, shown as ``plain`` in terminals."""
        return cls(plain, f"${latex}$", latex, plain)

    @classmethod
    def number(cls, value: AlgebraicNumber, digits: int = 6) -> "Cell":
        """Exact value over its decimal (``digits`` significant digits, certified)."""
        decimal = _decimal(value, digits)
        lo, hi = value.refine(sp.Rational(1, 10 ** (digits + 2))).interval
        data = {"exact": str(value.exact), "latex": sp.latex(value.exact), "decimal": decimal,
                "interval": [str(lo), str(hi)], "minpoly": str(value.minpoly.as_expr())}
        if value.exact.has(sp.CRootOf):  # no radical form: name the root by its minimal polynomial
            exact_text = f"root of ${sp.latex(value.minpoly.as_expr())}$"
            exact_math = rf"\text{{root of }} {sp.latex(value.minpoly.as_expr())}"
        else:
            exact_text, exact_math = f"${sp.latex(value.exact)}$", sp.latex(value.exact)
        if len(exact_math) > MAX_EXACT_LATEX:  # too wide for a cell: decimal only, exact form in to_dict()
            return cls(f"≈ {decimal}", rf"$\approx {decimal}$\textsuperscript{{*}}",
                       rf"\approx {decimal}^{{*}}", data)
        if value.exact.is_Integer:
            return cls(str(value.exact), exact_text, exact_math, data)
        relation = "=" if value.is_rational and sp.Rational(decimal) == value.exact else r"\approx"
        plain = f"{number_text(value.exact) or value.exact} = {decimal}" if relation == "=" else algebraic_text(value, digits)
        return cls(plain,
                   _stack(exact_text, f"${relation} {decimal}$"), rf"{exact_math} {relation} {decimal}", data)


#: a family table with more query columns than this, and fewer members, has its members as columns
MAX_COLUMNS = 6
#: longer exact forms are shown as a starred decimal (the exact form stays in the JSON)
MAX_EXACT_LATEX = 60


def _decimal(value: AlgebraicNumber, digits: int) -> str:
    text = str(value.evalf(digits))
    mantissa, _, exponent = text.partition("e")
    if "." in mantissa:
        mantissa = mantissa.rstrip("0").rstrip(".")
    return mantissa + (f"e{exponent}" if exponent else "")


def _stack(top: str, bottom: str) -> str:
    """Two lines in one cell with core LaTeX only."""
    return rf"\begin{{tabular}}[c]{{@{{}}c@{{}}}}{top}\\ {{\footnotesize {bottom}}}\end{{tabular}}"


@dataclass(frozen=True)
class Table(JsonDocument):
    """A booktabs table: row labels (``stub`` heading), columns, optional ``spanner`` over the columns."""

    caption: str                 # LaTeX
    caption_text: str            # plain text
    stub: Cell
    columns: tuple[Cell, ...]
    rows: tuple[tuple[Cell, tuple[Cell, ...]], ...]
    spanner: Cell | None = None
    label: str | None = None
    metadata: dict = field(default_factory=dict)
    size: str = ""               # a LaTeX size command for wide tables, e.g. "\\small"
    notes: tuple[tuple[str, str], ...] = ()   # (LaTeX, plain) lines under the table
    spec: str = ""               # the tabular's column specification (default: l, then c per column)

    def to_latex(self) -> str:
        """A complete ``table`` environment (needs ``\\usepackage{booktabs}`` only)."""
        n = len(self.columns)
        head = []
        if self.spanner is not None:
            head.append(rf" & \multicolumn{{{n}}}{{c}}{{{self.spanner.latex}}} \\")
            head.append(rf"\cmidrule(l){{2-{n + 1}}}")
        head.append(" & ".join([self.stub.latex, *(c.latex for c in self.columns)]) + r" \\")
        body = [" & ".join([r.latex, *(c.latex for c in cells)]) + r" \\" for r, cells in self.rows]
        lines = [r"\begin{table}[htbp]", r"\centering",
                 rf"\caption{{{self.caption}}}"]
        if self.label:
            lines.append(rf"\label{{{self.label}}}")
        if self.size:
            lines.append(self.size)
        lines += [rf"\begin{{tabular}}{{{self.spec or 'l' + 'c' * n}}}", r"\toprule", *head, r"\midrule", *body,
                  r"\bottomrule", r"\end{tabular}"]
        if self.notes:   # as wide as the text, under the table
            lines += [r"\par\smallskip", r"{\footnotesize\raggedright " + r"\par ".join(n for n, _ in self.notes) + "}"]
        lines.append(r"\end{table}")
        return "\n".join(lines) + "\n"

    def _repr_latex_(self) -> str:
        stub = self.stub.math + (rf" \;\backslash\; {self.spanner.math}" if self.spanner else "")
        rows = [" & ".join([stub, *(c.math for c in self.columns)]) + r" \\ \hline"]
        rows += [" & ".join([r.math, *(c.math for c in cells)]) + r" \\" for r, cells in self.rows]
        return rf"$$\begin{{array}}{{l|{'c' * len(self.columns)}}} " + " ".join(rows) + r" \end{array}$$"

    def __str__(self) -> str:
        stub = self.stub.plain + (f" \\ {self.spanner.plain}" if self.spanner else "")
        grid = [[stub, *(c.plain for c in self.columns)]] + [[r.plain, *(c.plain for c in cells)]
                                                            for r, cells in self.rows]
        widths = [max(len(row[j]) for row in grid) for j in range(len(grid[0]))]
        lines = ["  ".join(v.ljust(w) for v, w in zip(row, widths)).rstrip() for row in grid]
        lines.insert(1, "  ".join("-" * w for w in widths))
        notes = "".join("\n" + textwrap.fill(plain, 100) for _, plain in self.notes)
        return textwrap.fill(self.caption_text, 100) + "\n\n" + "\n".join(lines) + notes

    def to_dict(self) -> dict[str, Any]:
        """A JSON-serialisable dict: caption, headings, and each cell's exact data."""
        return {**self.metadata, "caption": self.caption_text,
                "stub": self.stub.plain, "spanner": self.spanner.plain if self.spanner else None,
                "columns": [c.plain for c in self.columns],
                "rows": [{"label": r.plain, "cells": [c.data for c in cells]} for r, cells in self.rows],
                **({"notes": [plain for _, plain in self.notes]} if self.notes else {})}

    def write(self, path: str | Path) -> Path:
        """Write :meth:`to_latex` to ``path`` atomically (:mod:`symkf.output`: never over the
        table's input files); returns the path."""
        inputs = [self.metadata["file"]] if "file" in self.metadata else self.metadata.get("files", [])
        return output.plan(path, "path", inputs=inputs).put_text(self.to_latex())


# -- families -------------------------------------------------------------------------------

def _value_cell(value: Any, member: Member, periods: Sequence[int], digits: int) -> Cell:
    """A family cell; its JSON data also records the grid point and the periods the engine used."""
    where = {"point": {k: str(v) for k, v in member.point}, "class_periods": list(periods)}
    if isinstance(value, Cell):   # rendered by the layer that computed it (the published bounds)
        return Cell(value.plain, value.latex, value.math,
                    {**where, **(value.data if isinstance(value.data, dict) else {"value": value.data})})
    if isinstance(value, Inapplicable):
        return Cell("---", "---", r"\text{---}", {**where, "inapplicable": value.reason})
    if isinstance(value, Verdict):
        margin = Cell.number(value.limiting_margin, digits)
        word = "stable" if value.stable else "unstable"
        return Cell(f"{word}, {margin.plain}", _stack(word, margin.latex), rf"\text{{{word}}},\ {margin.math}",
                    {**where, "stable": value.stable, "margin": margin.data, "theorem": value.theorem})
    if isinstance(value, ControlThreshold):
        cell = _threshold_cell(value, digits)
        return Cell(cell.plain, cell.latex, cell.math, {**where, **cell.data})
    if isinstance(value, Selection):
        if value.indices is None:
            return Cell("none", "none", r"\text{none}", {**where, "sensors": None})
        names = ", ".join(value.sensors)
        return Cell(f"{len(value.indices)} ({names})", f"{len(value.indices)} ({escape(names)})",
                    rf"{len(value.indices)}\ (\text{{{escape(names)}}})", {**where, "sensors": list(value.sensors)})
    cell = Cell.number(value, digits)
    return Cell(cell.plain, cell.latex, cell.math, {**where, **cell.data})


def _threshold_cell(value: ControlThreshold, digits: int) -> Cell:
    """The critical control-packet arrival rate ``nu_c`` (:func:`symkf.control.critical_arrival_rate`):
    where a closed form applies, its exact value as every exact cell; else the certified bracket
    ``[lower, upper]``, ``lower`` the exact quotient bound and ``upper`` the exact rational at which
    a gain is verified (in decimal when it terminates, as the certificate's rates do).  The JSON
    data of a bracket has ``lower`` (an exact number), ``upper`` and ``width_at_most`` (exact
    rationals) and ``reached`` (the tolerance)."""
    if value.exact is not None:
        return Cell.number(value.exact, digits)
    lower = Cell.number(value.lower, digits)
    upper = terminating_decimal(value.upper)
    upper_text = str(value.upper) if upper is None else format(upper, "f")
    upper_latex = sp.latex(sp.Rational(value.upper.numerator, value.upper.denominator)) if upper is None \
        else upper_text
    low = value.lower.exact
    math = rf"[{sp.latex(low)},\, {upper_latex}]"
    return Cell(f"[{number_text(low) or low}, {upper_text}]", f"${math}$", math,
                {"lower": lower.data, "upper": str(value.upper), "width_at_most": str(value.width),
                 "reached": value.reached})


def _axis_cell(value: sp.Expr, text: str) -> Cell:
    return Cell.formula(sp.latex(value), text)


def _periods_summary(outcomes: Sequence[Outcome]) -> str:
    periods = sorted({p for o in outcomes for p in o.periods})
    return ", ".join(map(str, periods)) if periods else "none"


def family_table(path: str | Path | Family, *, jobs: int = 1, scheduler: Any = None,
                 progress: bool | None = None) -> Table:
    """The table of a family file: rows the first grid axis, columns the second (if any); or, for
    a list of queries (or one with a column per sensor or per published result), one row per
    member and one column per query's column (:func:`family_table_of`).

    ``jobs`` local processes or a Dask ``scheduler`` evaluate the members (:func:`symkf.run.sweep.sweep`).

    Parameters
    ----------
    path : str, pathlib.Path or Family
        A family file (:func:`symkf.io.families.load_family`), or a family built in memory
        (:func:`symkf.io.families.grid_family`, :func:`symkf.io.families.systems_family`).
    jobs : int, default 1
        Local worker processes.
    scheduler : str or distributed.Client, optional
        A Dask scheduler instead of local processes.
    progress : bool, optional
        Show a progress bar (default as in :func:`symkf.run.sweep.sweep`).

    Returns
    -------
    Table
        ``str(table)`` for terminals, :meth:`Table.to_latex` (booktabs), :meth:`Table.write`
        and :meth:`Table.to_dict`; members whose assumptions fail show as ``---``.

    Raises
    ------
    FileFormatError
        The family file is missing or invalid; the message names the file and key.

    Examples
    --------
    A two-by-two excerpt of ``rotation-periods`` (``A = 2R(pi/g)``, ``d`` identical sensors
    ``[1, 0]``), whose file derives ``eps_c = 2^(-2g / (d (g - 1)))`` by hand: 1/16, 1/4 for
    ``g = 2`` and 1/8, ``2^(-3/2) = sqrt(2)/4`` for ``g = 3``:

    >>> import pathlib, tempfile
    >>> from symkf import tables
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "small.toml"
    >>> _ = path.write_text('''
    ... [family]
    ... name = "small"
    ... kind = "rotation"
    ... [grid]
    ... period = [2, 3]
    ... sensors = [1, 2]
    ... [constants]
    ... alpha = "2"
    ... ''')
    >>> table = tables.family_table(path, progress=False)
    >>> [(row["label"], [cell["exact"] for cell in row["cells"]]) for row in table.to_dict()["rows"]]
    [('2', ['1/16', '1/4']), ('3', ['1/8', 'sqrt(2)/4'])]
    >>> all(word in table.to_latex() for word in ("toprule", "midrule", "bottomrule"))
    True
    >>> tmp.cleanup()
    """
    family = path if isinstance(path, Family) else load_family(path)
    return family_table_of(family, family.evaluate(jobs=jobs, scheduler=scheduler, progress=progress))


def family_table_of(family: Family, outcomes: Sequence[Outcome]) -> Table:
    """Arrange already evaluated ``outcomes`` (row-major, as ``family.members``) into a table:
    rows the first axis and columns the second for one single-column query, else one row per
    member and one column per query's column (:attr:`symkf.io.families.Family.by_columns`)."""
    rows_axis = family.axes[0]
    cols_axis = family.axes[1] if len(family.axes) > 1 else None
    queries = family.queries
    if family.by_columns:
        stub, columns, rows, notes = _member_rows(family, outcomes)
        spanner: Cell | None = None
        layout = "members as rows"
        if len(columns) > MAX_COLUMNS and len(rows) < len(columns):   # too wide for a page: members as columns
            spanner = stub
            stub, columns, rows = Cell("", "", ""), tuple(label for label, _ in rows), tuple(
                (head, tuple(cells[j] for _, cells in rows)) for j, head in enumerate(columns))
            layout = "members as columns"
    else:
        ncols = len(cols_axis.values) if cols_axis else 1
        cells = [_value_cell(o.value, m, o.periods, family.digits) for o, m in zip(outcomes, family.members)]
        rows = tuple((_axis_cell(v, t), tuple(cells[i * ncols:(i + 1) * ncols]))
                     for i, (v, t) in enumerate(zip(rows_axis.values, rows_axis.texts)))
        if cols_axis:
            columns = tuple(_axis_cell(v, t) for v, t in zip(cols_axis.values, cols_axis.texts))
            spanner = Cell(_plain_label(cols_axis.label), cols_axis.label, _math_label(cols_axis.label))
        else:
            columns = (Cell.text(queries[0].heading.plain),)
            spanner = None
        notes, layout = (), "grid"
        stub = Cell(_plain_label(rows_axis.label), rows_axis.label, _math_label(rows_axis.label))
    what_latex = "; ".join(q.caption[0] for q in queries)
    what_text = "; ".join(q.caption[1] for q in queries)
    what_latex, what_text = what_latex[0].upper() + what_latex[1:], what_text[0].upper() + what_text[1:]
    constants = "; ".join(f"{k} = {v}" for k, v in family.constants)
    periods = _periods_summary(outcomes)
    missing = sorted({c.data["inapplicable"] for _, cells in rows for c in cells
                      if isinstance(c.data, dict) and "inapplicable" in c.data})
    caption = (f"{what_latex} for the family \\texttt{{{escape(family.name)}}}"
               + (f": {family.description}" if family.description else "")
               + (f" (fixed: {escape(constants)})" if constants else "")
               + f". Computed exactly by {_ENGINE}; class periods occurring: {periods}. "
               + f"Each cell: the exact value and its decimal to {family.digits} significant digits."
               + (f" ---: the theorem's assumptions fail ({escape(missing[0])}"
                  + (f"; and {len(missing) - 1} more, see the JSON output" if len(missing) > 1 else "") + ")."
                  if missing else ""))
    caption_text = (f"{what_text} for the family {family.name}"
                    + (f": {family.description}" if family.description else "")
                    + (f" (fixed: {constants})" if constants else "")
                    + ". Computed exactly by symkf (Sui-You-Fu Theorems 4 and 7 with eq. (36), hyperplane "
                    "form; rows C_j A^k grouped over each eigen-block's class period g, its governing period "
                    f"when the block is periodic); class periods occurring: {periods}."
                    + (" ---: assumptions fail (see JSON)." if missing else ""))
    metadata = {"table": "family", "family": family.name, "file": family.path,
                "compute": family.compute if isinstance(family.compute, str) else list(family.compute),
                "engine": "Sui-You-Fu Theorems 4/7 with eq. (36), hyperplane form, class periods",
                "axes": [a.name for a in family.axes], "constants": dict(family.constants), "layout": layout}
    return Table(caption, caption_text, stub, columns, rows, spanner,
                 f"tab:{re.sub(r'[^A-Za-z0-9:-]', '-', family.name)}", metadata,
                 r"\small" if len(columns) > 6 else "", notes)


def _member_rows(family: Family, outcomes: Sequence[Outcome]) -> tuple[Cell, tuple[Cell, ...], tuple, tuple]:
    """The stub, the columns (every member's, each after the one before it in the members that have it), one row per member
    and the notes of a family whose queries are its columns; a column a member lacks (a sensor it
    does not have) is left empty."""
    order: list[Column] = []
    for o in outcomes:   # a column new in this member goes after its predecessor there, or its query's others
        at = 0
        for c, _ in o.columns:
            if c not in order:
                kin = [i for i, d in enumerate(order) if d.latex == c.latex]
                order.insert(max(at, kin[-1] + 1) if kin else at, c)
            at = order.index(c) + 1
    # a column whose theorem applies to no member (most published bounds on a given family) is
    # named in a note under the table instead
    useful = tuple(c for c in order if any(not isinstance(v, Inapplicable) for o in outcomes
                                           for d, v in o.columns if d == c))
    columns = useful or tuple(order)
    dropped = [c.plain for c in order if c not in columns]
    rows = []
    for o, m in zip(outcomes, family.members):
        values = dict(o.columns)
        label = ", ".join(_text_of(a, m) for a in family.axes)
        rows.append((Cell.formula(r",\ ".join(sp.latex(v) for _, v in m.point), label),
                     tuple(_value_cell(values[c], m, o.periods, family.digits) if c in values else Cell("", "", "", None)
                           for c in columns)))
    labels = [a.label for a in family.axes]
    stub = Cell(", ".join(map(_plain_label, labels)), ", ".join(labels), r",\ ".join(map(_math_label, labels)))
    note = f"Left out, their assumptions failing for every member: {', '.join(dropped)}." if dropped else ""
    return stub, tuple(_column_cell(c) for c in columns), tuple(rows), ((escape(note), note),) if note else ()


def _text_of(axis: Any, member: Member) -> str:
    """The text of ``member``'s value on ``axis``, as the family gives it."""
    value = dict(member.point)[axis.name]
    return axis.texts[axis.values.index(value)]


def _column_cell(column: Column) -> Cell:
    if column.sensor is None:
        return Cell(column.plain, column.latex, _math_label(column.latex))
    return Cell(column.plain, f"{column.latex} ({escape(column.sensor)})",
                rf"{_math_label(column.latex)}\ (\text{{{escape(column.sensor)}}})")


def _plain_label(label: str) -> str:
    return label.replace("$", "").replace("\\", "")


def _math_label(label: str) -> str:
    """A LaTeX heading with inline math, for a MathJax array cell."""
    parts = label.split("$")
    return " ".join(rf"\text{{{p}}}" if i % 2 == 0 else p for i, p in enumerate(parts) if p.strip())


# -- the papers' example verdicts -------------------------------------------------------------

def _file_verdict(path: str) -> tuple[str, Any, Verdict | None, tuple[int, ...]]:
    """(system name, loss model's table cell, verdict, class periods) of one system file."""
    from ..io.files import load
    from ..engine.blocks import block_rows
    from ..engine.stability import stability
    system, loss = load(path)
    periods = tuple(br.class_period for br in block_rows(system))
    if loss is None:
        return system.name, None, None, periods
    return system.name, _loss_cell(loss), stability(system, loss), periods


def _loss_cell(loss: Any) -> Cell:
    """A loss model's name and parameters (:meth:`LossModel.fields <symkf.model.loss.LossModel.fields>`),
    one vector per field (a scalar when all sensors share it); its data is the model's file form."""
    def show(values: tuple[sp.Expr, ...], fmt: Any) -> str:
        """``= v``, ``= (v_1, ..., v_d)``, or for many sensors ``in [min, max]`` to 3 digits (all in to_dict())."""
        if len(set(values)) == 1:
            return f"= {fmt(values[0])}"
        if len(values) > 4:
            lo, hi = (f"{float(v):.3g}" for v in (min(values), max(values)))
            return rf"\in [{lo},\ {hi}]" if fmt is sp.latex else f"in [{lo}, {hi}]"
        return "= (" + ", ".join(map(fmt, values)) + ")"
    fields = loss.fields()
    math = r",\ ".join(f"{symbol} {show(v, sp.latex)}" for _, symbol, v in fields)
    plain = ", ".join(f"{k} {show(v, str)}" for k, _, v in fields)
    latex_name, plain_name = loss.label
    data = loss.to_table()
    return Cell(f"{plain_name}: {plain}", _stack(latex_name, f"${math}$"),
                rf"\text{{{plain_name}: }} {math}", data)


def verdict_table(paths: Sequence[str | Path] | None = None, *, jobs: int = 1, scheduler: Any = None,
                  digits: int = 6, progress: bool | None = None) -> Table:
    """Verdicts of system files that have a ``[loss]`` (default: the example systems, :func:`symkf.io.examples.systems`).

    Parameters
    ----------
    paths : sequence of str or pathlib.Path, optional
        System files; those without a ``[loss]`` table are left out.
    jobs : int, default 1
        Local worker processes.
    scheduler : str or distributed.Client, optional
        A Dask scheduler instead of local processes.
    digits : int, default 6
        Significant digits of the decimal margins.
    progress : bool, optional
        Show a progress bar (default as in :func:`symkf.run.sweep.sweep`).

    Returns
    -------
    Table
        One row per system: loss model, verdict, class period of the limiting block, its
        margin ``alpha_i^2 rho_i`` and the theorem.

    Raises
    ------
    InputError
        None of the files has a ``[loss]`` table.
    FileFormatError
        A file is missing or invalid.

    Examples
    --------
    ``ge-two-sensors``: ``A = 2R(pi/2)``, sensors ``[1, 0]``, ``[1, 1]`` on channels with
    ``fail = 1/4``, ``recover = 1/2``.  By hand: a decisive pattern receives at most one packet
    per period ``g = 2``, say ``s1``'s at phase 0 (the four choices tie).  Per period, ``s2``
    stays lost with probability ``(1 - 1/2)^2 = 1/4``; ``s1``, lost at phase 1 and free at
    phase 0, continues with probability ``recover * fail + (1 - recover)^2 = 1/8 + 1/4 = 3/8``.  So
    ``alpha^4 rho^2 = 16 * 3/32 = 3/2`` and the margin is ``sqrt(3/2) = sqrt(6)/2 > 1``:

    >>> from symkf import examples, tables
    >>> table = tables.verdict_table([examples.system("ge-two-sensors")], progress=False)
    >>> (row,) = table.to_dict()["rows"]
    >>> row["label"], row["cells"][1], row["cells"][2], row["cells"][3]["exact"]
    ('ge-two-sensors', 'unstable', '2', 'sqrt(6)/2')
    """
    if paths is None:
        paths = examples.systems()
    results = sweep(_file_verdict, [str(p) for p in paths], jobs=jobs, scheduler=scheduler,
                    progress=progress, desc="verdicts")
    results = [r for r in results if r[2] is not None]
    if not results:
        raise InputError("verdict_table: none of the system files has a [loss] table")
    rows = []
    for name, cell, verdict, periods in results:
        period = "-" if verdict.limiting_block is None else periods[verdict.limiting_block]
        rows.append((Cell.text(name), (
            cell,
            Cell.text("stable" if verdict.stable else "unstable"),
            Cell.formula(str(period), str(period)),
            Cell.number(verdict.limiting_margin, digits),
            Cell.text(verdict.theorem.split()[1] if verdict.theorem.startswith("Theorem") else "-"))))
        # "Theorem 4 with eq. (36)" -> "4"; "-" when no block decides
    columns = (Cell.text("loss model"), Cell.text("verdict"), Cell.formula("g", "g"),
               Cell("margin alpha^2 rho", r"$\alpha_i^2\rho_i$", r"\alpha_i^2\rho_i", "margin alpha^2 rho"),
               Cell.text("Thm."))
    caption = (r"Mean-square stability of the example systems with their loss models: the limiting "
               r"eigen-block's margin $\alpha_i^2\rho_i$ (stable iff every margin is below~1) and its class "
               r"period $g$; i.i.d.\ loss probabilities $\varepsilon$, Gilbert--Elliott failure $f$ and recovery "
               r"$q$ probabilities (one value when all sensors share it), joint Markov chains by their order $\nu$ "
               r"and receival vectors $|\Upsilon|$, network losses by their link success probabilities $\phi$ and "
               r"network states $|B|$; theorem: Sui--You--Fu Theorem~4 (one "
               rf"eigen-block) or~7. Computed exactly by {_ENGINE}. Margins: exact value and decimal to {digits} "
               "significant digits; a starred decimal marks an exact form too long to print (it is in the JSON "
               "output).")
    caption_text = ("Mean-square stability of the example systems with their loss models: the limiting "
                    "eigen-block's margin alpha_i^2 rho_i (stable iff every margin is below 1) and its class "
                    "period g; theorem: Sui-You-Fu Theorem 4 (one eigen-block) or 7. Computed exactly by symkf "
                    "(Sui-You-Fu Theorems 4 and 7 with eq. (36), hyperplane form, class periods).")
    metadata = {"table": "verdicts", "files": [str(p) for p in paths],
                "engine": "Sui-You-Fu Theorems 4/7 with eq. (36), hyperplane form, class periods"}
    return Table(caption, caption_text, Cell.text("system"), columns, tuple(rows), None, "tab:verdicts", metadata,
                 r"\small\setlength{\tabcolsep}{4pt}")

check_public(globals())
