"""System files (TOML) as specified in DESIGN.md; errors name the file and the key."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

import sympy as sp

from .errors import FileFormatError, SymkfError
from .exact.numbers import to_exact
from .losses import IID, GilbertElliott, LossModel
from .model import Sensor, System


def _get(table: dict, key: str, where: str, required: bool = True) -> Any:
    if key not in table:
        if required:
            raise FileFormatError(f"{where}: missing key '{key}'")
        return None
    return table[key]


#: the keys each table may hold; any other key is refused (a misspelt optional key would
#: otherwise be silently replaced by its default)
KEYS = {"": {"system", "sensors", "loss", "rationalize"}, "[system]": {"A", "Q", "P0", "name"},
        "sensors": {"name", "C", "R"}, "iid": {"kind", "loss"}, "gilbert-elliott": {"kind", "fail", "recover"}}

def _check_keys(table: dict, allowed: set[str], where: str) -> None:
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise FileFormatError(f"{where}: unknown key '{unknown[0]}' (allowed: {', '.join(sorted(allowed))})")


def _name(value: Any, where: str) -> str | None:
    if value is not None and (not isinstance(value, str) or not value.strip()):
        raise FileFormatError(f"{where}: key 'name' must be a non-empty string, got {value!r}")
    return value


def load(path: str | Path) -> tuple[System, LossModel | None]:
    """Read a system file; returns the system and its loss model (None when absent)."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileFormatError(f"{path}: no such file") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise FileFormatError(f"{path}: not valid TOML ({exc})") from None
    except ValueError as exc:  # e.g. an integer beyond Python's digit limit for str -> int
        raise FileFormatError(f"{path}: not a usable TOML file ({exc})") from None
    except OSError as exc:
        raise FileFormatError(f"{path}: cannot read ({exc.strerror or type(exc).__name__})") from None
    return parse(data, str(path))


def parse(data: dict, source: str) -> tuple[System, LossModel | None]:
    """The system and loss model of already-read TOML ``data``; errors are prefixed by ``source``
    (a file name, or a file and a family grid point).  The system's default name is the last
    path component of ``source``."""
    _check_keys(data, KEYS[""], f"{source}")
    rationalize = data.get("rationalize", False)
    if not isinstance(rationalize, bool):
        raise FileFormatError(f"{source}: key 'rationalize' must be true or false")
    try:
        sysdata = _get(data, "system", source)
        if not isinstance(sysdata, dict):
            raise FileFormatError(f"{source}: [system] must be a table")
        _check_keys(sysdata, KEYS["[system]"], f"{source}: [system]")
        sensors_data = _get(data, "sensors", source)
        if not isinstance(sensors_data, list) or not sensors_data:
            raise FileFormatError(f"{source}: [[sensors]] must list at least one sensor")
        sensors = []
        for i, s in enumerate(sensors_data):
            where = f"{source}: sensors[{i}]"
            if not isinstance(s, dict):
                raise FileFormatError(f"{where} must be a table")
            _check_keys(s, KEYS["sensors"], where)
            C, name = _get(s, "C", where), _name(s.get("name"), where)
            try:
                sensors.append(Sensor(C=C, R=s.get("R"), name=name, rationalize=rationalize))
            except FileFormatError:
                raise
            except SymkfError as exc:
                raise _located(exc, f"sensors[{i}]") from None
        system = System(A=_get(sysdata, "A", f"{source}: [system]"), sensors=sensors, Q=sysdata.get("Q"),
                        P0=sysdata.get("P0"), rationalize=rationalize,
                        name=_name(sysdata.get("name"), f"{source}: [system]") or Path(source).stem)
        loss = _loss(data.get("loss"), source, system, rationalize)
    except FileFormatError:
        raise
    except SymkfError as exc:
        raise _located(exc, source) from None
    return system, loss


def _located(exc: SymkfError, where: str) -> SymkfError:
    """``exc`` with its message prefixed by ``where`` (the file, or the table inside it)."""
    exc.args = (f"{where}: {exc.args[0] if exc.args else exc}",)
    return exc


def _loss(table: Any, source: str, system: System, rationalize: bool) -> LossModel | None:
    if table is None:
        return None
    if not isinstance(table, dict):
        raise FileFormatError(f"{source}: [loss] must be a table")
    where = f"{source}: [loss]"
    kind = table.get("kind", "iid")
    if not isinstance(kind, str) or kind not in ("iid", "gilbert-elliott"):
        raise FileFormatError(f"{where} kind {kind!r} is not one of 'iid', 'gilbert-elliott'")
    _check_keys(table, KEYS[kind], where)
    keys = ("loss",) if kind == "iid" else ("fail", "recover")
    values = [_get(table, key, where) for key in keys]
    if rationalize:
        values = [[to_exact(x, f"{where} {key}[{i}]", rationalize=True) if isinstance(x, float) else x
                   for i, x in enumerate(v)] if isinstance(v, list) else v for key, v in zip(keys, values)]
    try:
        model: LossModel = IID(*values) if kind == "iid" else GilbertElliott(*values)
    except SymkfError as exc:
        raise _located(exc, "[loss]") from None
    if model.d != system.d:
        raise FileFormatError(f"{where} gives {model.d} value(s) for {system.d} sensor(s)")
    for key in keys:
        free = set().union(*(sp.sympify(p).free_symbols for p in getattr(model, key)))
        if free:
            raise FileFormatError(f"{where} key '{key}': symbol(s) {sorted(map(str, free))} have no value; "
                                  "a file gives numbers")
    return model
