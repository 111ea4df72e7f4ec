"""The codec of loss models: ``[loss]`` tables of system files and their JSON objects to models,
with errors that name the file, the table and the key.

Every model reads its own table (:meth:`LossModel.read_table
<symkf.model.loss.LossModel.read_table>`) with the helpers here, which are public so that a
model written in another package gives the same messages as the built-in ones. The kinds are
the ``symkf.losses`` entry-point group: symkf's own models and any installed package's
(``[project.entry-points."symkf.losses"]``, ``kind = "module:Class"``) are found in every
process, by the Python API, the files and the ``symkf`` command alike.
"""

from __future__ import annotations

from importlib.metadata import entry_points
from typing import Any, Callable, Mapping, Sequence

from .. import budget
from ..arguments import check_public
from ..errors import FileFormatError, SymkfError
from ..exact.numbers import to_exact
from .loss import LossModel, checked

#: the entry-point group through which loss kinds register
GROUP = "symkf.losses"

#: kind -> why its entry point could not be loaded (a broken plugin does not stop the others)
_BROKEN: dict[str, str] = {}
_loaded = False


def loss_kinds() -> dict[str, type[LossModel]]:
    """Every loss kind: kind -> model class, the classes defined so far and those of the
    ``symkf.losses`` entry points (loaded once per process)."""
    global _loaded
    if not _loaded:
        _loaded = True
        for point in entry_points(group=GROUP):
            if point.name in LossModel.KINDS:
                continue
            try:
                cls = point.load()
            except Exception as exc:   # a third party's import error is reported, never raised here
                _BROKEN[point.name] = f"its entry point {point.value!r} failed to load ({type(exc).__name__}: {exc})"
                continue
            if not (isinstance(cls, type) and issubclass(cls, LossModel) and cls.kind == point.name):
                _BROKEN[point.name] = (f"its entry point {point.value!r} is not a LossModel subclass with "
                                       f"kind = {point.name!r}")
    return LossModel.KINDS


def entry(table: Mapping[str, Any], key: str, where: str, required: bool = True) -> Any:
    """``table[key]``; a missing required key is a :class:`~symkf.errors.FileFormatError` naming
    ``where`` (the file and table) and the key, a missing optional one None."""
    if key not in table:
        if required:
            raise FileFormatError(f"{where}: missing key '{key}'")
        return None
    return table[key]


def check_keys(table: Mapping[str, Any], allowed: set[str] | frozenset[str], where: str) -> None:
    """Refuse a key outside ``allowed`` (a misspelt optional key would silently take its default)."""
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise FileFormatError(f"{where}: unknown key '{unknown[0]}' (allowed: {', '.join(sorted(allowed))})")


def exact_values(value: Any, entry: str, rationalize: bool | str = False, start: int = 0, *,
                 caps: Sequence[str] = ("max_sensors",)) -> Any:
    """``value`` with every number of its nested lists exact (:func:`symkf.exact.numbers.to_exact`,
    the safe parser); ``entry`` (file, table and key) names it in errors, list positions counted
    from ``start``. Floats need ``rationalize``; symbols are refused.

    ``caps`` names the :mod:`symkf.budget` cap on the length of the lists at each depth (the
    default: a number, or a list of one number per sensor; ``("max_dimension", "max_dimension")``
    for a matrix); the whole shape is checked against them, and a list nested deeper refused,
    before any number is converted (the parser's work is per number: a list a million long costs
    a minute)."""
    _check_shape(value, entry, tuple(caps), start)
    return _converted(value, entry, rationalize, start)


def within(cap: str, size: int, entry: str, what: str, exponent: int = 1) -> None:
    """:func:`symkf.budget.check_power` of ``size ** exponent`` for a file's entry: its refusal is a
    :class:`~symkf.errors.FileFormatError` (it names the file, the table and the key already), as
    the refusals of the numbers that :func:`exact_values` converts are."""
    try:
        budget.check_power(cap, size, exponent, entry, what)
    except SymkfError as exc:
        raise FileFormatError(str(exc)) from None


def _check_shape(value: Any, entry: str, caps: tuple[str, ...], start: int) -> None:
    if not isinstance(value, list):
        return
    if not caps:
        raise FileFormatError(f"{entry}: expected a number, got a list")
    within(caps[0], len(value), entry, "the length of the list")
    for i, v in enumerate(value, start=start):
        _check_shape(v, f"{entry}[{i}]", caps[1:], start)


def _converted(value: Any, entry: str, rationalize: bool | str, start: int) -> Any:
    if isinstance(value, list):
        return [_converted(v, f"{entry}[{i}]", rationalize, start) for i, v in enumerate(value, start=start)]
    try:
        return to_exact(value, entry, rationalize=rationalize)
    except SymkfError as exc:
        raise FileFormatError(str(exc)) from None


def positive_int(value: Any, entry: str) -> int:
    """``value`` if it is an integer >= 1 (not a bool), else a :class:`~symkf.errors.FileFormatError`."""
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise FileFormatError(f"{entry} must be a positive integer, got {value!r}")
    return value


def located(exc: SymkfError, where: str) -> SymkfError:
    """``exc`` with its message prefixed by ``where`` (the file, or the table inside it)."""
    exc.args = (f"{where}: {exc.args[0] if exc.args else exc}",)
    return exc


def built(build: Callable[[], Any], where: str) -> Any:
    """``build()``, its errors (other than a :class:`~symkf.errors.FileFormatError`, which names
    the file already) prefixed by ``where``: the file, or a table or key inside it."""
    try:
        return build()
    except FileFormatError:
        raise
    except SymkfError as exc:
        raise located(exc, where) from None


def read_loss(table: Mapping[str, Any], where: str, d: int, rationalize: bool | str = False, *,
              label: str = "[loss]", channels: str = "sensor") -> LossModel:
    """The loss model of a ``[loss]`` table, or of its JSON object (:meth:`LossModel.to_dict
    <symkf.model.loss.LossModel.to_dict>`: a lifted ``chain`` and the ``words`` of a report are
    derived, and ignored), for ``d`` channels; ``where`` prefixes errors, ``label`` (the table)
    the model's own, and ``channels`` says what the ``d`` channels are (``"actuator"`` for a
    system file's ``[actuator_loss]``)."""
    table = {k: v for k, v in table.items() if k not in ("chain", "words")}
    kinds = loss_kinds()
    known = ", ".join(map(repr, kinds))
    if "kind" not in table:
        raise FileFormatError(f"{where}: key 'kind' missing; it is required, one of {known}")
    kind = table["kind"]
    if isinstance(kind, str) and kind in _BROKEN:
        raise FileFormatError(f"{where} kind {kind!r} is installed but unusable: {_BROKEN[kind]}")
    if not isinstance(kind, str) or kind not in kinds:
        raise FileFormatError(f"{where} kind {kind!r} is not one of {known} (a package may add kinds "
                              f"through the {GROUP!r} entry-point group)")
    check_keys(table, kinds[kind].keys, where)
    model = built(lambda: kinds[kind].read_table(table, where, d, rationalize), label)
    if model.d is not None and model.d != d:
        raise FileFormatError(f"{where} gives {model.d} value(s) for {d} {channels}(s)")
    return checked(model, d)


def from_table(table: Mapping[str, Any], d: int, where: str = "loss") -> LossModel:
    """The loss model of a ``[loss]`` table or its JSON object (:meth:`LossModel.to_dict
    <symkf.model.loss.LossModel.to_dict>`) for ``d`` sensors: files and JSON share this codec."""
    if not isinstance(table, Mapping):
        raise FileFormatError(f"{where}: expected a table (mapping), got {type(table).__name__}")
    return read_loss(dict(table), where, d)


check_public(globals())
