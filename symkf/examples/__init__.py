"""The papers' example system files and parameter families, shipped inside the package.

They are package data, read with :mod:`importlib.resources`, so a wheel install has them too::

    >>> from symkf import examples
    >>> examples.system("ge-two-sensors").name
    'ge-two-sensors.toml'
    >>> "rotation-periods" in [p.stem for p in examples.families()]
    True

``systems/*.toml`` are single systems (``symkf demo`` and :func:`symkf.tables.verdict_table`
read them), ``systems/network/`` and ``systems/fusion/`` the sensor-network and fusion files,
``families/*.toml`` the parameter families of ``symkf table``.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

from ..exact.arguments import check_public
from ..errors import InputError

__all__ = ["directory", "systems", "families", "system", "family"]


def directory() -> Path:
    """The directory holding ``systems/`` and ``families/`` (a real directory: wheels install unzipped)."""
    return Path(str(files(__name__)))


def systems(subdir: str = "") -> list[Path]:
    """The system files in ``systems/`` (or ``systems/<subdir>``, e.g. ``"network"``), sorted."""
    return sorted((directory() / "systems" / subdir).glob("*.toml"))


def families() -> list[Path]:
    """The family files in ``families/``, sorted."""
    return sorted((directory() / "families").glob("*.toml"))


def system(name: str) -> Path:
    """The system file ``name`` (stem, optionally ``network/<stem>`` or ``fusion/<stem>``)."""
    return _named(directory() / "systems", name)


def family(name: str) -> Path:
    """The family file ``name`` (its stem, e.g. ``"rotation-periods"``)."""
    return _named(directory() / "families", name)


def _named(folder: Path, name: str) -> Path:
    path = folder / f"{name}.toml"
    if not path.is_file():
        known = sorted(str(p.relative_to(folder).with_suffix("")) for p in folder.rglob("*.toml"))
        raise InputError(f"no example {name!r} in {folder.name}/; known: {', '.join(known)}")
    return path


check_public(globals())
