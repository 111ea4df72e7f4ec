"""Parameter families of systems (TOML), the input of ``symkf table``.

A family file is a system file (:mod:`symkf.io.files`, the docs' formats page) whose string entries may name
parameters, plus a grid of exact parameter values::

    [family]
    name = "rotation-periods"          # optional, default: the file name
    description = "$A = 2R(\\pi/g)$, $C_j = [1, 0]$"   # LaTeX, goes into the caption
    kind = "rotation"                  # "template" (default) or "rotation"
    compute = "critical_loss_rate"     # one query, or a list of them: one column each (QUERIES)
    digits = 6                         # significant digits of the decimals
    labels = { period = "governing period $g$" }     # optional axis headings (LaTeX)

    [grid]                             # one or two axes: rows, then columns
    period = { from = 2, to = 12 }     # or a list of ints / exact strings
    sensors = [1, 2, 3, 4]             # reserved: copies of the [[sensors]] list

    [constants]                        # parameters fixed over the family
    alpha = "2"

``kind = "template"`` takes ``[system]``, ``[[sensors]]``, ``[[actuators]]`` (optional: the plant's
inputs, for ``compute = "critical_arrival_rate"``) and ``[loss]`` as in a system file, e.g. ``A = [["alpha*cos(theta)", "-alpha*sin(theta)"], ...]``; every
parameter is substituted as an exact parenthesised value into the text of each
entry before it is parsed, so the member's numbers are exactly those of the
equivalent system file.  ``kind = "rotation"`` builds ``A = alpha R(theta)`` with
``theta = angle`` or ``theta = pi/period`` (then ``period`` is the governing period:
``R(pi/g)^g = -I``) and defaults to one sensor ``C = [1, 0]``.

Bad files raise :class:`~symkf.errors.FileFormatError` (or another
:class:`~symkf.errors.InputError`) naming file, key and problem in one line.

``compute`` names one query of :data:`QUERIES` (rows the first axis, columns the second), or a
list of them: then each query is a column (a per-sensor query one column per sensor), and each
member a row.

From Python a family needs no file: :func:`grid_family` calls a builder at every point of a
grid, :func:`systems_family` takes a list of systems; both give a :class:`Family` that
:func:`symkf.reports.tables.family_table` and :func:`symkf.io.family_verification.verify_family` take like a path.
"""

from __future__ import annotations

import functools
import itertools
import math
import re
from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Sequence

import sympy as sp

from ..arguments import check_public
from .. import budget
from . import files
from ..errors import AssumptionError, FileFormatError, InputError, SymkfError
from ..exact.algebraic import AlgebraicNumber
from ..exact.numbers import RESERVED, field_cost, parse_exact, to_exact, to_exact_matrix
from ..model.system import System
from ..engine.blocks import block_rows
from ..design.selection import select_sensors
from ..engine.recovery import critical_recovery_rate
from ..engine.stability import Verdict, critical_loss_rate, stability
from ..run.sweep import sweep
from ..control import critical_arrival_rate

COMPUTE = ("critical_loss_rate", "stability", "critical_recovery_rate", "fewest_sensors",
           "critical_loss_rate_per_sensor", "critical_recovery_rate_per_sensor", "stability_margin", "bounds",
           "critical_arrival_rate")
KINDS = ("template", "rotation")
_FAMILY_KEYS = {"name", "description", "kind", "compute", "digits", "labels"}
_ROTATION_A = [["alpha*cos(THETA)", "-alpha*sin(THETA)"], ["alpha*sin(THETA)", "alpha*cos(THETA)"]]
_DEFAULT_LABELS = {"sensors": "identical sensors $d$", "period": "governing period $g$",
                   "angle": r"angle $\theta$", "alpha": r"$\alpha$"}
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


@dataclass(frozen=True)
class Axis:
    """One grid axis: the parameter name, its exact values, their source text, a LaTeX heading."""

    name: str
    values: tuple[sp.Expr, ...]
    texts: tuple[str, ...]
    label: str


@dataclass(frozen=True)
class Member:
    """One system of the family: its grid point and its system-file tables after substitution."""

    label: str                               # "period = 3, sensors = 2"
    point: tuple[tuple[str, sp.Expr], ...]   # grid coordinates, exact
    tables: dict                             # {"system": ..., "sensors": [...], "actuators": [...] or None,
                                             #  "loss": ... or None}
    source: str                              # file name, for error messages
    rationalize: bool
    compute: str | tuple[str, ...]

    def system(self) -> tuple[System, Any]:
        """The member's System (its actuators included) and loss model (None without ``[loss]``), read
        by :func:`symkf.io.files.parse`, so a member is validated exactly like a system file; errors
        name the family file and the grid point.
        """
        data = {"rationalize": self.rationalize, "system": {**self.tables["system"], "name": self.label},
                **{key: table for key, table in self.tables.items() if key != "system" and table is not None}}
        return files.parse(data, f"{self.source}: at {self.label}")

    @property
    def has_loss(self) -> bool:
        return self.tables["loss"] is not None


@dataclass(frozen=True)
class BuiltMember:
    """A member built in memory: ``build(**point)`` returns its System or ``(System, loss)``."""

    label: str
    point: tuple[tuple[str, Any], ...]
    build: Callable[..., Any]
    compute: str | tuple[str, ...]

    def system(self) -> tuple[System, Any]:
        out = self.build(**dict(self.point))
        system, loss = out if isinstance(out, tuple) else (out, None)
        if not isinstance(system, System):
            raise InputError(f"family member {self.label}: the builder returned {type(system).__name__}, "
                             "expected a System or (System, loss)")
        return system, loss

    @property
    def has_loss(self) -> bool:
        return self.system()[1] is not None


@dataclass(frozen=True)
class Column:
    """A column of a family table: its heading as text and as LaTeX, and the sensor it is about
    (per-sensor queries; the heading then names it)."""

    plain: str
    latex: str
    sensor: str | None = None


@dataclass(frozen=True)
class Query:
    """What a family computes (one entry of ``compute``): ``columns(system, loss)`` gives one
    ``(Column, value)`` pair per column, ``needs_loss`` whether the member needs ``[loss]``, and
    ``caption`` (LaTeX, text) what the values are.  A value is an
    :class:`~symkf.exact.algebraic.AlgebraicNumber`, a :class:`~symkf.engine.stability.Verdict`,
    a :class:`~symkf.design.selection.Selection`, an :class:`Inapplicable` or, from a layer that
    renders its own, a table cell (the published bounds of :mod:`symkf.bounds`)."""

    name: str
    columns: Callable[[System, Any], tuple[tuple[Column, Any], ...]]
    needs_loss: bool
    caption: tuple[str, str]
    heading: Column


@dataclass(frozen=True)
class Inapplicable:
    """A member for which the theorem's assumptions fail (shown as --- in tables)."""

    reason: str


@dataclass(frozen=True)
class Outcome:
    """What one member evaluates to, with the class periods (one per eigen-block) the engine used:
    ``columns`` pairs each :class:`Column` of the member's queries with its value, ``value`` is
    the first column's (a family of one single-column query has just that one)."""

    value: AlgebraicNumber | Verdict | Inapplicable | Any
    periods: tuple[int, ...]
    columns: tuple[tuple[Column, Any], ...] = ()


@dataclass(frozen=True)
class Family:
    """A loaded family file: its metadata, axes, constants and members (row-major over the axes)."""
    path: str
    name: str
    description: str
    kind: str
    compute: str | tuple[str, ...]
    digits: int
    axes: tuple[Axis, ...]
    constants: tuple[tuple[str, str], ...]
    members: tuple[Member, ...]   # row-major over the axes

    @property
    def queries(self) -> tuple[Query, ...]:
        """The queries of ``compute``, in its order (:func:`query`)."""
        return tuple(query(name) for name in _names(self.compute))

    @property
    def by_columns(self) -> bool:
        """Whether each query is a column and each member a row: ``compute`` is a list, or its one
        query has a column per sensor or per published result."""
        return not isinstance(self.compute, str) or self.compute not in _ONE_COLUMN

    def evaluate(self, *, jobs: int = 1, scheduler: Any = None, progress: bool | None = None) -> list[Outcome]:
        """Evaluate every member (see :func:`symkf.run.sweep.sweep` for ``jobs`` and ``scheduler``)."""
        # the queries go with the tasks: a worker unpickling one imports the module that defines it
        return sweep(functools.partial(evaluate, queries=self.queries), self.members, jobs=jobs,
                     scheduler=scheduler, progress=progress, desc=f"family {self.name}", cost=_cost)


def evaluate(member: Member | BuiltMember, queries: Sequence[Query] | None = None) -> Outcome:
    """The queries of ``member.compute`` (or ``queries``) for one member (runs on workers): the
    columns of each, in order (:data:`QUERIES`).  A query whose theorem's assumptions fail gives
    :class:`Inapplicable` in its column; a member that fails to build, in every column."""
    queries = tuple(query(name) for name in _names(member.compute)) if queries is None else tuple(queries)
    try:
        system, loss = member.system()
    except AssumptionError as exc:
        return Outcome(Inapplicable(str(exc)), (), tuple((q.heading, Inapplicable(str(exc))) for q in queries))
    columns: list[tuple[Column, Any]] = []
    for q in queries:
        if q.needs_loss and loss is None:
            raise InputError(f"family member {member.label}: compute = \"{q.name}\" needs a loss model; build the "
                             "member as (System, loss)")
        try:
            columns += q.columns(system, loss)
        except AssumptionError as exc:
            columns.append((q.heading, Inapplicable(str(exc))))
    try:
        periods = tuple(br.class_period for br in block_rows(system))
    except AssumptionError:
        periods = ()
    return Outcome(columns[0][1], periods, tuple(columns))


def _names(compute: str | Sequence[str]) -> tuple[str, ...]:
    return (compute,) if isinstance(compute, str) else tuple(compute)


#: the queries whose one column fits the grid layout (rows the first axis, columns the second)
_ONE_COLUMN = ("critical_loss_rate", "stability", "critical_recovery_rate", "fewest_sensors", "stability_margin",
               "critical_arrival_rate")


def _needs(loss: Any, capability: str, name: str, kind: str) -> tuple:
    """The loss model's ``capability`` (its per-sensor rates) that query ``name`` holds fixed."""
    value = getattr(loss, capability)
    if value is None:
        raise InputError(f"[loss]: compute = \"{name}\" needs {kind}, not {loss.words()}")
    return value


def _critical_loss_rate(system: System, loss: Any) -> tuple[tuple[Column, Any], ...]:
    return ((QUERIES["critical_loss_rate"].heading, critical_loss_rate(system)),)


def _critical_arrival_rate(system: System, loss: Any) -> tuple[tuple[Column, Any], ...]:
    if not system.actuators:
        raise InputError("compute = \"critical_arrival_rate\" needs actuators: [[actuators]] in the family file, "
                         "or System(..., actuators=[Actuator(B=...)]) from the builder")
    return ((QUERIES["critical_arrival_rate"].heading, critical_arrival_rate(system)),)


def _stability(system: System, loss: Any) -> tuple[tuple[Column, Any], ...]:
    return ((QUERIES["stability"].heading, stability(system, loss)),)


def _stability_margin(system: System, loss: Any) -> tuple[tuple[Column, Any], ...]:
    return ((QUERIES["stability_margin"].heading, stability(system, loss).limiting_margin),)


def _critical_recovery_rate(system: System, loss: Any) -> tuple[tuple[Column, Any], ...]:
    fail = _needs(loss, "channel_fail", "critical_recovery_rate", _GE)
    return ((QUERIES["critical_recovery_rate"].heading, critical_recovery_rate(system, fail)),)


def _fewest_sensors(system: System, loss: Any) -> tuple[tuple[Column, Any], ...]:
    return ((QUERIES["fewest_sensors"].heading, select_sensors(system, loss)),)


def _loss_per_sensor(system: System, loss: Any) -> tuple[tuple[Column, Any], ...]:
    others = list(_needs(loss, "bernoulli", "critical_loss_rate_per_sensor", "i.i.d. losses (kind = \"iid\")"))
    return _each_sensor(system, "critical_loss_rate_per_sensor",
                        lambda sensor: critical_loss_rate(system, sensor, others=others))


def _recovery_per_sensor(system: System, loss: Any) -> tuple[tuple[Column, Any], ...]:
    _needs(loss, "channel_fail", "critical_recovery_rate_per_sensor", _GE)
    return _each_sensor(system, "critical_recovery_rate_per_sensor",
                        lambda sensor: critical_recovery_rate(system, loss, sensor=sensor))


def _each_sensor(system: System, name: str, value: Callable[[str], Any]) -> tuple[tuple[Column, Any], ...]:
    """One column per sensor of query ``name``: ``value(sensor)``, or :class:`Inapplicable` where the
    theorem's assumptions fail for that sensor."""
    head = QUERIES[name].heading
    out = []
    for sensor in system.sensor_names:
        try:
            result = value(sensor)
        except AssumptionError as exc:
            result = Inapplicable(str(exc))
        out.append((Column(f"{head.plain}({sensor})", head.latex, sensor), result))
    return tuple(out)


_GE = "Gilbert-Elliott channels (kind = \"gilbert-elliott\")"

#: the queries of ``compute``, by name; :func:`register_query` adds one from a layer above (the
#: published bounds: :mod:`symkf.bounds`)
QUERIES: dict[str, Query] = {q.name: q for q in (
    Query("critical_loss_rate", _critical_loss_rate, False,
          (r"exact critical i.i.d.\ loss probability $\varepsilon_c$ common to all sensors (mean-square stable "
           r"iff $\varepsilon < \varepsilon_c$)",
           "exact critical i.i.d. loss probability eps_c common to all sensors (mean-square stable iff eps < eps_c)"),
          Column("critical loss rate", r"$\varepsilon_c$")),
    Query("stability", _stability, True,
          (r"mean-square stability verdicts and limiting margins $\alpha_i^2\rho_i$ (stable iff every margin is "
           "below 1)",
           "mean-square stability verdicts and limiting margins alpha_i^2 rho_i (stable iff every margin is below 1)"),
          Column("verdict", "verdict")),
    Query("stability_margin", _stability_margin, True,
          (r"exact limiting margin $\max_i \alpha_i^2\rho_i$ under the member's losses (stable iff below 1)",
           "exact limiting margin max_i alpha_i^2 rho_i under the member's losses (stable iff below 1)"),
          Column("margin", r"$\max_i \alpha_i^2\rho_i$")),
    Query("critical_recovery_rate", _critical_recovery_rate, True,
          (r"exact critical recovery probability $q_c$ common to all Gilbert--Elliott channels, their fail "
           r"probabilities fixed (mean-square stable iff $q > q_c$)",
           "exact critical recovery probability q_c common to all Gilbert-Elliott channels, their fail "
           "probabilities fixed (mean-square stable iff q > q_c)"),
          Column("critical recovery rate", "$q_c$")),
    Query("fewest_sensors", _fewest_sensors, True,
          (r"the fewest sensors whose filter is mean-square stable under the member's losses, with one such set "
           r"(exact: every smaller set ruled out, \texttt{symkf.design})",
           "the fewest sensors whose filter is mean-square stable under the member's losses, with one such set "
           "(exact: every smaller set ruled out, symkf.design)"),
          Column("fewest sensors", "fewest sensors")),
    Query("critical_loss_rate_per_sensor", _loss_per_sensor, True,
          (r"exact critical i.i.d.\ loss probability $\varepsilon_c(s)$ of each sensor $s$, the others' fixed at "
           r"the member's (stable iff $\varepsilon_s < \varepsilon_c(s)$)",
           "exact critical i.i.d. loss probability eps_c(s) of each sensor s, the others' fixed at the member's "
           "(stable iff eps_s < eps_c(s))"),
          Column("eps_c", r"$\varepsilon_c$")),
    Query("critical_recovery_rate_per_sensor", _recovery_per_sensor, True,
          (r"exact critical recovery probability $q_c(s)$ of each sensor's Gilbert--Elliott channel, the fail "
           r"probabilities and the other channels' recovery fixed at the member's (stable iff $q_s > q_c(s)$)",
           "exact critical recovery probability q_c(s) of each sensor's Gilbert-Elliott channel, the fail "
           "probabilities and the other channels' recovery fixed at the member's (stable iff q_s > q_c(s))"),
          Column("q_c", "$q_c$")),
    Query("critical_arrival_rate", _critical_arrival_rate, False,
          (r"critical control-packet arrival rate $\nu_c$ of TCP-like LQG control, every input on one i.i.d.\ "
           r"channel (bounded cost iff $\nu > \nu_c$; Schenato et al.\ 2007, Section~IV): exact where a closed "
           r"form applies, else a certified bracket $[\underline{\nu}, \overline{\nu}]$ (the quotient bound and a "
           r"rate at which a rational gain is verified to stabilise the loop)",
           "critical control-packet arrival rate nu_c of TCP-like LQG control, every input on one i.i.d. channel "
           "(bounded cost iff nu > nu_c; Schenato et al. 2007, Section IV): exact where a closed form applies, "
           "else a certified bracket [lower, upper] (the quotient bound and a rate at which a rational gain is "
           "verified to stabilise the loop)"),
          Column("critical arrival rate", r"$\nu_c$")),
)}


def register_query(q: Query) -> None:
    """Add ``q`` to :data:`QUERIES` (a layer above this one defines it; its name must be in
    :data:`COMPUTE`, which files are checked against)."""
    if q.name not in COMPUTE:
        raise InputError(f"q: query {q.name!r} is not one of COMPUTE")
    QUERIES[q.name] = q


def query(name: str) -> Query:
    """The query ``name`` of :data:`QUERIES`; ``"bounds"`` is registered by :mod:`symkf.bounds`
    (imported by ``symkf.tables`` and the command line)."""
    if name not in QUERIES:
        raise InputError(f"compute: {name!r} is not available: import symkf.bounds first (the published bounds "
                         "register their query there; `import symkf; symkf.tables` does)"
                         if name == "bounds" else f"compute: {name!r} is not one of {', '.join(COMPUTE)}")
    return QUERIES[name]


def _cost(member: Member | BuiltMember) -> int:
    """An a-priori proxy for a member's work, to start the costliest first: the degree bound of
    its A's entries' field (:func:`symkf.exact.numbers.field_cost`) times n times the sensors;
    0 when A does not parse (the member then fails quickly) or the member is built in memory."""
    if not isinstance(member, Member):
        return 0
    try:
        A = to_exact_matrix(member.tables["system"].get("A"), "A")
    except SymkfError:
        return 0
    cost = field_cost(A)
    return cost.radical * cost.cyclotomic * A.rows * len(member.tables["sensors"])


def _fail(path: Path, message: str) -> FileFormatError:
    return FileFormatError(f"{path}: {message}")


def load_family(path: str | Path) -> Family:
    """Read and validate a family file; members are built (and checked) when evaluated.

    The file format (``[family]``, ``[grid]``, ``[constants]`` and a system template or
    ``kind = "rotation"``) is described in the docs' formats page; :func:`symkf.reports.tables.family_table`
    turns a family into a LaTeX table.

    Parameters
    ----------
    path : str or pathlib.Path
        A family file (TOML); :func:`symkf.io.examples.family` gives the shipped ones.

    Returns
    -------
    Family
        Its name, description, ``compute`` (a name of :data:`COMPUTE`, or a tuple of them),
        grid ``axes`` and ``members`` (row-major over the axes); ``Family.evaluate`` evaluates
        them all (:func:`symkf.run.sweep.sweep`).

    Raises
    ------
    FileFormatError
        The file is missing, not TOML, or a key or value is invalid; the message names the file
        and the key.

    Examples
    --------
    ``rotation-periods``: ``A = 2R(pi/g)`` watched by ``d`` identical sensors ``[1, 0]``.  The
    file derives ``eps_c = 2^(-2g / (d (g - 1)))`` by hand: 1/16 for ``g = 2, d = 1``, 1/4 for
    ``g = 2, d = 2`` and 1/8 for ``g = 3, d = 1``:

    >>> import symkf as sk
    >>> from symkf import examples
    >>> from symkf.io.families import evaluate
    >>> family = sk.load_family(examples.family("rotation-periods"))
    >>> family.compute, [(axis.name, len(axis.values)) for axis in family.axes], len(family.members)
    ('critical_loss_rate', [('period', 11), ('sensors', 4)], 44)
    >>> [(m.label, evaluate(m).value.exact) for m in (family.members[0], family.members[1], family.members[4])]
    [('period = 2, sensors = 1', 1/16), ('period = 2, sensors = 2', 1/4), ('period = 3, sensors = 1', 1/8)]
    >>> sk.load_family("no-such-family.toml")
    Traceback (most recent call last):
    ...
    symkf.errors.FileFormatError: no-such-family.toml: no such file
    """
    path = Path(path)
    data = files.read_toml(path)
    fam = data.get("family")
    if not isinstance(fam, dict):
        raise _fail(path, "missing table [family] (a family file needs [family] and [grid])")
    unknown = sorted(set(fam) - _FAMILY_KEYS)
    if unknown:
        raise _fail(path, f"[family] unknown key(s) {unknown}; allowed: {sorted(_FAMILY_KEYS)}")
    rationalize = data.get("rationalize", False)
    if not isinstance(rationalize, bool):
        raise _fail(path, "key 'rationalize' must be true or false")
    kind = _choice(fam.get("kind", "template"), KINDS, path, "[family] kind")
    compute = _compute(fam.get("compute", "critical_loss_rate"), path, "[family] compute")
    digits = fam.get("digits", 6)
    if isinstance(digits, bool) or not isinstance(digits, int) or not 1 <= digits <= 50:
        raise _fail(path, f"[family] digits must be an integer from 1 to 50, got {digits!r}")
    name, description = _text(fam, "name", path, path.stem), _text(fam, "description", path, "")
    labels = fam.get("labels", {})
    if not isinstance(labels, dict) or not all(isinstance(v, str) for v in labels.values()):
        raise _fail(path, "[family] labels must be a table of strings, e.g. labels = { g = \"period $g$\" }")

    grid = data.get("grid")
    if not isinstance(grid, dict) or not 1 <= len(grid) <= 2:
        raise _fail(path, "[grid] must be a table with one or two parameters (rows, then columns)")
    constants = data.get("constants", {})
    if not isinstance(constants, dict):
        raise _fail(path, "[constants] must be a table of parameter = value")
    for key in grid.keys() & constants.keys():
        raise _fail(path, f"parameter {key!r} is in both [grid] and [constants]")
    axes = tuple(Axis(key, *_axis_values(key, vals, path, rationalize),
                      labels.get(key, _DEFAULT_LABELS.get(key, f"${sp.latex(sp.Symbol(key))}$")))
                 for key, vals in grid.items())
    fixed = {key: _value_text(key, v, f"[constants] {key}", path, rationalize)[1] for key, v in constants.items()}

    template = _template(data, kind, compute, fixed, grid, path)
    used = _strings(template)
    for key in [*grid, *fixed]:
        if key != "sensors" and not any(re.search(rf"\b{key}\b", s) for s in used):
            raise _fail(path, f"parameter {key!r} appears in no entry of [system], [[sensors]], [[actuators]] "
                              "or [loss]")

    budget.check("max_members", math.prod(len(a.values) for a in axes), str(path), "the number of family members")
    members = []
    for combo in itertools.product(*[range(len(a.values)) for a in axes]):
        texts = dict(fixed)
        texts.update({a.name: a.texts[i] for a, i in zip(axes, combo)})
        label = ", ".join(f"{a.name} = {a.texts[i]}" for a, i in zip(axes, combo))
        members.append(Member(label, tuple((a.name, a.values[i]) for a, i in zip(axes, combo)),
                              _substitute(template, texts), str(path), rationalize, compute))
    return Family(str(path), name, description, kind, compute, digits, axes, tuple(fixed.items()),
                  tuple(members))


def grid_family(build: Callable[..., Any], grid: Mapping[str, Iterable[Any]], *, name: str = "family",
                compute: str | Sequence[str] = "critical_loss_rate", description: str = "", digits: int = 6,
                labels: Mapping[str, str] | None = None) -> Family:
    """A family from a builder: ``build(**point)`` (a System, or ``(System, loss)`` for
    ``compute = "stability"`` and verify) at every point of ``grid`` (one or two axes: rows,
    then columns; values taken exactly).  For ``jobs > 1`` the builder must be picklable
    (a module-level function).

    >>> import symkf as sk, sympy as sp
    >>> from symkf import tables
    >>> def rotation(g):
    ...     c, s = sp.cos(sp.pi / g), sp.sin(sp.pi / g)
    ...     return sk.System(A=[[2 * c, -2 * s], [2 * s, 2 * c]], sensors=[sk.Sensor(C=[[1, 0]])])
    >>> table = tables.family_table(grid_family(rotation, {"g": [2, 3]}), progress=False)
    >>> [row["cells"][0]["exact"] for row in table.to_dict()["rows"]]
    ['1/16', '1/8']
    """
    compute = _compute(compute if isinstance(compute, str) else list(compute), Path(name), "compute")
    if not 1 <= len(grid) <= 2:
        raise InputError(f"grid: one or two parameters (rows, then columns), got {len(grid)}")
    axes = []
    for key, values in grid.items():
        size = len(values) if hasattr(values, "__len__") else None
        if size is None:
            raise InputError(f"grid {key}: expected a list or range of values, got {type(values).__name__}")
        if size > budget.LIMITS.max_members:   # measured before any value is converted
            budget.check("max_members", size, name, f"the number of values of grid {key}")
        exact = tuple(to_exact(v, f"grid {key}[{i}]") for i, v in enumerate(values))
        if not exact:
            raise InputError(f"grid {key}: no values")
        axes.append(Axis(key, exact, tuple(str(v) for v in exact),
                         (labels or {}).get(key, _DEFAULT_LABELS.get(key, f"${sp.latex(sp.Symbol(key))}$"))))
    budget.check("max_members", math.prod(len(a.values) for a in axes), name, "the number of family members")
    members = tuple(BuiltMember(", ".join(f"{a.name} = {a.texts[i]}" for a, i in zip(axes, combo)),
                                tuple((a.name, a.values[i]) for a, i in zip(axes, combo)), build, compute)
                    for combo in itertools.product(*[range(len(a.values)) for a in axes]))
    return Family(name, name, description, "template", compute, digits, tuple(axes), (), members)


def systems_family(systems: Sequence[Any], *, name: str = "systems", compute: str | Sequence[str] = "critical_loss_rate",
                   description: str = "", digits: int = 6) -> Family:
    """A one-column family of the given systems (each a System, or ``(System, loss)``), one row
    each, labelled by the row number."""
    items = tuple(systems)
    return grid_family(_Listed(items), {"system": list(range(1, len(items) + 1))}, name=name, compute=compute,
                       description=description, digits=digits, labels={"system": "system"})


@dataclass(frozen=True)
class _Listed:
    """The builder of :func:`systems_family`: member ``system = i`` is the ``i``-th item."""

    items: tuple[Any, ...]

    def __call__(self, system: Any) -> Any:
        return self.items[int(system) - 1]


def _choice(value: Any, allowed: Sequence[str], path: Path, key: str) -> str:
    if value not in allowed:
        raise _fail(path, f"{key} {value!r} is not one of {', '.join(map(repr, allowed))}")
    return value


def _compute(value: Any, path: Path, key: str) -> str | tuple[str, ...]:
    """``compute``: one name of :data:`COMPUTE`, or a non-empty list of distinct ones (a tuple)."""
    if isinstance(value, str):
        return _choice(value, COMPUTE, path, key)
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise _fail(path, f"{key} must be a query name or a non-empty list of them, got {value!r}")
    if len(set(value)) != len(value):
        raise _fail(path, f"{key}: queries repeat in {value!r}")
    return tuple(_choice(v, COMPUTE, path, key) for v in value)


def _text(table: dict, key: str, path: Path, default: str) -> str:
    value = table.get(key, default)
    if not isinstance(value, str):
        raise _fail(path, f"[family] {key} must be a string")
    return value


def _check_name(key: str, path: Path, where: str) -> None:
    if not _NAME.match(key) or key in RESERVED:
        raise _fail(path, f"{where}: parameter name {key!r} must be an identifier other than "
                          f"{', '.join(sorted(RESERVED))}")


def _value_text(key: str, value: Any, entry: str, path: Path, rationalize: bool) -> tuple[sp.Expr, str]:
    """Validate one exact parameter value; returns it and the text substituted into entries.

    A parameter need not be algebraic itself (an angle ``pi/5``); the entries it produces are
    checked exact and algebraic when the member is built.
    """
    _check_name(key, path, entry)
    if key == "sensors":
        if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 64:
            raise _fail(path, f"{entry}: the number of sensor copies must be an integer from 1 to 64, got {value!r}")
        return sp.Integer(value), str(value)
    try:
        if isinstance(value, str):
            exact = parse_exact(value, entry)
            if exact.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
                raise _fail(path, f"{entry}: {value!r} is not a finite number")
            return exact, value
        if isinstance(value, (int, float, Decimal)) and not isinstance(value, bool):
            exact = to_exact(value, entry, rationalize=rationalize)
            return exact, str(exact)
    except SymkfError as exc:
        raise _fail(path, str(exc)) from None
    raise _fail(path, f"{entry}: expected an exact number (integer or string such as \"5/4\"), got {value!r}")


def _axis_values(key: str, vals: Any, path: Path, rationalize: bool) -> tuple[tuple[sp.Expr, ...], tuple[str, ...]]:
    where = f"[grid] {key}"
    if isinstance(vals, dict):
        bad = sorted(set(vals) - {"from", "to", "step"})
        lo, hi, step = vals.get("from"), vals.get("to"), vals.get("step", 1)
        if bad or not all(isinstance(v, int) and not isinstance(v, bool) for v in (lo, hi, step)) \
                or step < 1 or hi < lo:
            raise _fail(path, f"{where}: a range is {{ from = INT, to = INT, step = INT }} with from <= to "
                              "and step >= 1")
        if (hi - lo) // step + 1 > 1000:   # counted, never built: to = 10**9 would take gigabytes first
            raise _fail(path, f"{where}: the range has {(hi - lo) // step + 1} values, more than 1000 "
                              "(at most 1000 values per axis)")
        vals = list(range(lo, hi + 1, step))
    if not isinstance(vals, list) or not vals or len(vals) > 1000:
        raise _fail(path, f"{where}: expected a non-empty list (at most 1000 values) or a range table")
    values, texts = zip(*[_value_text(key, v, f"{where}[{i}]", path, rationalize) for i, v in enumerate(vals)])
    if len(set(values)) != len(values):
        raise _fail(path, f"{where}: values repeat")
    return values, texts


def _template(data: dict, kind: str, compute: str | tuple[str, ...], fixed: dict, grid: dict, path: Path) -> dict:
    system = data.get("system", {})
    if not isinstance(system, dict):
        raise _fail(path, "[system] must be a table")
    sensors = data.get("sensors")
    actuators = data.get("actuators")
    loss = data.get("loss")
    if kind == "rotation":
        params = set(grid) | set(fixed)
        if "A" in system:
            raise _fail(path, "[system] A: kind = \"rotation\" builds A = alpha R(theta) itself; "
                              "remove A or use kind = \"template\"")
        if "alpha" not in params or ("angle" in params) == ("period" in params):
            raise _fail(path, "kind = \"rotation\" needs parameter 'alpha' and exactly one of 'angle' "
                              "(theta = angle) or 'period' (theta = pi/period), in [grid] or [constants]")
        theta = "angle" if "angle" in params else "pi/period"
        system = {**system, "A": [[e.replace("THETA", theta) for e in row] for row in _ROTATION_A]}
        sensors = [{"name": "s", "C": [["1", "0"]]}] if sensors is None else sensors
    elif "A" not in system:
        raise _fail(path, "[system]: missing key 'A' (kind = \"template\")")
    if not isinstance(sensors, list) or not sensors or not all(isinstance(s, dict) for s in sensors):
        raise _fail(path, "[[sensors]] must list at least one sensor table")
    if actuators is not None and (not isinstance(actuators, list) or not all(isinstance(a, dict) for a in actuators)):
        raise _fail(path, "[[actuators]] must list tables, one per actuator")
    if loss is not None and not isinstance(loss, dict):
        raise _fail(path, "[loss] must be a table")
    if "critical_arrival_rate" in _names(compute) and not actuators:
        raise _fail(path, "[[actuators]]: compute = \"critical_arrival_rate\" needs actuators")
    needing = [name for name in _names(compute) if name in QUERIES and QUERIES[name].needs_loss]
    if needing and loss is None:
        raise _fail(path, f"[loss]: compute = \"{needing[0]}\" needs a loss model")
    return {"system": system, "sensors": sensors, "actuators": actuators, "loss": loss}


def _strings(value: Any) -> list[str]:
    if isinstance(value, str):
        return [value]
    if isinstance(value, dict):
        return [s for v in value.values() for s in _strings(v)]
    if isinstance(value, list):
        return [s for v in value for s in _strings(v)]
    return []


def _replace(value: Any, pattern: re.Pattern | None, texts: dict[str, str]) -> Any:
    if isinstance(value, str) and pattern is not None:
        return pattern.sub(lambda m: f"({texts[m.group(0)]})", value)
    if isinstance(value, dict):
        return {k: _replace(v, pattern, texts) for k, v in value.items()}
    if isinstance(value, list):
        return [_replace(v, pattern, texts) for v in value]
    return value


def _substitute(template: dict, texts: dict[str, str]) -> dict:
    """The member's tables: parameters replaced by their values, sensors copied ``sensors`` times."""
    names = [k for k in texts if k != "sensors"]
    pattern = re.compile(r"\b(" + "|".join(map(re.escape, names)) + r")\b") if names else None
    out = _replace(template, pattern, texts)
    copies = int(texts.get("sensors", 1))
    if copies > 1:
        out["sensors"] = [{**s, "name": f"{s['name']}_{j}"} if "name" in s else dict(s)
                          for j in range(1, copies + 1) for s in out["sensors"]]
        if out["loss"] is not None:
            out["loss"] = {k: v * copies if isinstance(v, list) else v for k, v in out["loss"].items()}
    return out

check_public(globals())
