"""Parameter families of systems (TOML), the input of ``symkf table``.

A family file is a system file (:mod:`symkf.io.files`, the docs' formats page) whose string entries may name
parameters, plus a grid of exact parameter values::

    [family]
    name = "rotation-periods"          # optional, default: the file name
    description = "$A = 2R(\\pi/g)$, $C_j = [1, 0]$"   # LaTeX, goes into the caption
    kind = "rotation"                  # "template" (default) or "rotation"
    compute = "critical_loss_rate"     # or (each needs [loss]) "stability", "critical_recovery_rate"
                                       # (Gilbert-Elliott channels), "fewest_sensors" (symkf.design)
    digits = 6                         # significant digits of the decimals
    labels = { period = "governing period $g$" }     # optional axis headings (LaTeX)

    [grid]                             # one or two axes: rows, then columns
    period = { from = 2, to = 12 }     # or a list of ints / exact strings
    sensors = [1, 2, 3, 4]             # reserved: copies of the [[sensors]] list

    [constants]                        # parameters fixed over the family
    alpha = "2"

``kind = "template"`` takes ``[system]``, ``[[sensors]]`` and ``[loss]`` as in a
system file, e.g. ``A = [["alpha*cos(theta)", "-alpha*sin(theta)"], ...]``; every
parameter is substituted as an exact parenthesised value into the text of each
entry before it is parsed, so the member's numbers are exactly those of the
equivalent system file.  ``kind = "rotation"`` builds ``A = alpha R(theta)`` with
``theta = angle`` or ``theta = pi/period`` (then ``period`` is the governing period:
``R(pi/g)^g = -I``) and defaults to one sensor ``C = [1, 0]``.

Bad files raise :class:`~symkf.errors.FileFormatError` (or another
:class:`~symkf.errors.InputError`) naming file, key and problem in one line.

From Python a family needs no file: :func:`grid_family` calls a builder at every point of a
grid, :func:`systems_family` takes a list of systems; both give a :class:`Family` that
:func:`symkf.reports.tables.family_table` and :func:`symkf.io.family_verification.verify_family` take like a path.
"""

from __future__ import annotations

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

COMPUTE = ("critical_loss_rate", "stability", "critical_recovery_rate", "fewest_sensors")
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
    tables: dict                             # {"system": ..., "sensors": [...], "loss": ... or None}
    source: str                              # file name, for error messages
    rationalize: bool
    compute: str

    def system(self) -> tuple[System, Any]:
        """The member's System and loss model (None without ``[loss]``), read by :func:`symkf.io.files.parse`,
        so a member is validated exactly like a system file; errors name the family file and the grid point.
        """
        data = {"rationalize": self.rationalize, "system": {**self.tables["system"], "name": self.label},
                "sensors": self.tables["sensors"]}
        if self.tables["loss"] is not None:
            data["loss"] = self.tables["loss"]
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
    compute: str

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
class Inapplicable:
    """A member for which the theorem's assumptions fail (shown as --- in tables)."""

    reason: str


@dataclass(frozen=True)
class Outcome:
    """What one member evaluates to, with the class periods (one per eigen-block) the engine used."""

    value: AlgebraicNumber | Verdict | Inapplicable
    periods: tuple[int, ...]


@dataclass(frozen=True)
class Family:
    """A loaded family file: its metadata, axes, constants and members (row-major over the axes)."""
    path: str
    name: str
    description: str
    kind: str
    compute: str
    digits: int
    axes: tuple[Axis, ...]
    constants: tuple[tuple[str, str], ...]
    members: tuple[Member, ...]   # row-major over the axes

    def evaluate(self, *, jobs: int = 1, scheduler: Any = None, progress: bool | None = None) -> list[Outcome]:
        """Evaluate every member (see :func:`symkf.run.sweep.sweep` for ``jobs`` and ``scheduler``)."""
        return sweep(evaluate, self.members, jobs=jobs, scheduler=scheduler, progress=progress,
                     desc=f"family {self.name}", cost=_cost)


def evaluate(member: Member) -> Outcome:
    """What ``member.compute`` names, for one member (runs on workers): the critical common i.i.d.
    loss rate, the stability verdict under its ``[loss]``, the critical common recovery rate of
    its Gilbert-Elliott channels (their fail probabilities fixed), or the fewest of its sensors
    stable under its ``[loss]`` (:func:`symkf.design.select_sensors`)."""
    try:
        system, loss = member.system()
        if member.compute == "critical_loss_rate":
            value: Any = critical_loss_rate(system)
        elif member.compute == "stability":
            value = stability(system, loss)
        elif member.compute == "critical_recovery_rate":
            if loss.channel_fail is None:
                raise InputError(f"[loss]: compute = \"critical_recovery_rate\" needs Gilbert-Elliott channels "
                                 f"(kind = \"gilbert-elliott\"), not {loss.words()}")
            value = critical_recovery_rate(system, loss.channel_fail)
        else:
            value = select_sensors(system, loss)
        return Outcome(value, tuple(br.class_period for br in block_rows(system)))
    except AssumptionError as exc:
        return Outcome(Inapplicable(str(exc)), ())


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
        Its name, description, ``compute`` (``"critical_loss_rate"`` or ``"stability"``),
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
    compute = _choice(fam.get("compute", "critical_loss_rate"), COMPUTE, path, "[family] compute")
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
            raise _fail(path, f"parameter {key!r} appears in no entry of [system], [[sensors]] or [loss]")

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
                compute: str = "critical_loss_rate", description: str = "", digits: int = 6,
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
    >>> [row["cells"][0]["exact"] for row in table.to_json()["rows"]]
    ['1/16', '1/8']
    """
    compute = _choice(compute, COMPUTE, Path(name), "compute")
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


def systems_family(systems: Sequence[Any], *, name: str = "systems", compute: str = "critical_loss_rate",
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


def _template(data: dict, kind: str, compute: str, fixed: dict, grid: dict, path: Path) -> dict:
    system = data.get("system", {})
    if not isinstance(system, dict):
        raise _fail(path, "[system] must be a table")
    sensors = data.get("sensors")
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
    if loss is not None and not isinstance(loss, dict):
        raise _fail(path, "[loss] must be a table")
    if compute != "critical_loss_rate" and loss is None:
        raise _fail(path, f"[loss]: compute = \"{compute}\" needs a loss model")
    return {"system": system, "sensors": sensors, "loss": loss}


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
