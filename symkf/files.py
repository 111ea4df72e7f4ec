"""System files (TOML) as specified in DESIGN.md; errors name the file and the key."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

from .errors import FileFormatError, SymkfError
from .losses import IID, GilbertElliott, LossModel
from .model import Sensor, System


def _get(table: dict, key: str, where: str, required: bool = True) -> Any:
    if key not in table:
        if required:
            raise FileFormatError(f"{where}: missing key '{key}'")
        return None
    return table[key]


def load(path: str | Path) -> tuple[System, LossModel | None]:
    """Read a system file; returns the system and its loss model (None when absent)."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileFormatError(f"{path}: no such file") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise FileFormatError(f"{path}: not valid TOML ({exc})") from None
    rationalize = data.get("rationalize", False)
    if not isinstance(rationalize, bool):
        raise FileFormatError(f"{path}: key 'rationalize' must be true or false")
    try:
        sysdata = _get(data, "system", str(path))
        if not isinstance(sysdata, dict):
            raise FileFormatError(f"{path}: [system] must be a table")
        sensors_data = _get(data, "sensors", str(path))
        if not isinstance(sensors_data, list) or not sensors_data:
            raise FileFormatError(f"{path}: [[sensors]] must list at least one sensor")
        sensors = []
        for i, s in enumerate(sensors_data):
            if not isinstance(s, dict):
                raise FileFormatError(f"{path}: sensors[{i}] must be a table")
            sensors.append(Sensor(C=_get(s, "C", f"{path}: sensors[{i}]"), R=s.get("R"),
                                  name=s.get("name"), rationalize=rationalize))
        system = System(A=_get(sysdata, "A", f"{path}: [system]"), sensors=sensors, Q=sysdata.get("Q"),
                        P0=sysdata.get("P0"), rationalize=rationalize, name=sysdata.get("name", path.stem))
        loss = _loss(data.get("loss"), path, system)
    except FileFormatError:
        raise
    except SymkfError as exc:
        raise _located(exc, path) from None
    return system, loss


def _located(exc: SymkfError, path: Path) -> SymkfError:
    exc.args = (f"{path}: {exc.args[0] if exc.args else exc}",)
    return exc


def _loss(table: Any, path: Path, system: System) -> LossModel | None:
    if table is None:
        return None
    if not isinstance(table, dict):
        raise FileFormatError(f"{path}: [loss] must be a table")
    kind = table.get("kind", "iid")
    if kind == "iid":
        model: LossModel = IID(_get(table, "loss", f"{path}: [loss]"))
    elif kind == "gilbert-elliott":
        model = GilbertElliott(_get(table, "fail", f"{path}: [loss]"), _get(table, "recover", f"{path}: [loss]"))
    else:
        raise FileFormatError(f"{path}: [loss] kind {kind!r} is not one of 'iid', 'gilbert-elliott'")
    if model.d != system.d:
        raise FileFormatError(f"{path}: [loss] gives {model.d} value(s) for {system.d} sensor(s)")
    return model
