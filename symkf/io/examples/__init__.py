"""The papers' example system files and parameter families, shipped inside the package.

They are package data, read with :mod:`importlib.resources`, so a wheel install has them too::

    >>> from symkf import examples
    >>> examples.system("ge-two-sensors").name
    'ge-two-sensors.toml'
    >>> "rotation-periods" in [p.stem for p in examples.families()]
    True

``systems/*.toml`` are single systems (``symkf demo`` and :func:`symkf.reports.tables.verdict_table`
read them), ``systems/network/`` and ``systems/fusion/`` the sensor-network and fusion files,
``families/*.toml`` the parameter families of ``symkf table``.  Every command of ``symkf``
takes an example's name where it takes a file (:func:`resolve`), and ``symkf examples NAME``
copies one into the working directory to be edited::

    >>> resolve("ge-recovery") == family("ge-recovery")
    True
    >>> catalog()[0].name, catalog()[0].kind
    ('aperiodic-rotation', 'system')
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path
from typing import Any

from ...arguments import check_public, described
from ...errors import InputError

__all__ = ["directory", "systems", "families", "system", "family", "Example", "catalog", "resolve"]


def directory() -> Path:
    """The directory holding ``systems/`` and ``families/`` (a real directory: wheels install unzipped)."""
    return Path(str(files(__name__)))


def systems(subdir: str = "") -> list[Path]:
    """The system files in ``systems/`` (or ``systems/<subdir>``, e.g. ``"network"``), sorted."""
    if subdir not in ("", "network", "fusion"):
        raise InputError(f"subdir: expected '', 'network' or 'fusion', got {described(subdir)}")
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
    if not _NAME.fullmatch(name) or not path.is_file():
        known = sorted(str(p.relative_to(folder).with_suffix("")) for p in folder.rglob("*.toml"))
        raise InputError(f"no example {name!r} in {folder.name}/; known: {', '.join(known)}")
    return path


#: an example's name: a file stem, optionally under ``network/`` or ``fusion/``
_NAME = re.compile(r"(?:(?:network|fusion)/)?[A-Za-z0-9][A-Za-z0-9_.-]{0,99}")


def _exists(path: Path, file: Any) -> bool:
    """Whether ``path`` exists; a name the system cannot look up (too long, a loop of links) is
    the caller's file named with the system's reason."""
    try:
        return path.exists()
    except OSError as exc:
        raise InputError(f"{described(file)}: cannot be looked up ({exc.strerror})") from None


@dataclass(frozen=True)
class Example:
    """A shipped example: its ``name`` (the file's stem), ``kind`` ("system", "network", "fusion"
    or "family"), ``path`` and ``summary`` (the first line of the file's leading comment)."""

    name: str
    kind: str
    path: Path
    summary: str


def catalog() -> list[Example]:
    """Every shipped example, systems first, then network and fusion files, then families."""
    groups = [("system", systems()), ("network", systems("network")), ("fusion", systems("fusion")),
              ("family", families())]
    return [Example(p.stem, kind, p, _summary(p)) for kind, paths in groups for p in paths]


def resolve(file: str | os.PathLike) -> Path:
    """``file`` itself when it exists; else ``file.toml`` when that exists (the copy ``symkf
    examples NAME`` writes, perhaps edited, wins over the shipped file it came from); else the
    shipped example of that name (with or without ``.toml``, optionally as ``network/<name>``);
    an input error lists the names otherwise."""
    path = Path(file)
    if _exists(path, file):
        return path
    local = path.with_name(path.name + ".toml")
    if not path.name.endswith(".toml") and _exists(local, file):
        return local
    stem = path.name[:-len(".toml")] if path.name.endswith(".toml") else path.name
    found = [e.path for e in catalog() if e.name == stem]
    if len(found) == 1:
        return found[0]
    raise InputError(f"{file}: no such file, and no shipped example of that name "
                     "(symkf examples lists them)")


#: words whose period ends an abbreviation, not a sentence ("Sec. V", "Yang et al. Theorem 2")
_ABBREVIATIONS = frozenset({"Sec", "al", "e.g", "i.e", "Fig", "Eq", "Thm", "cf", "vs", "resp", "Ex"})


def _summary(path: Path) -> str:
    """The first sentence of the file's leading comment, whole (its lines joined): a listing
    wraps it, never cuts it."""
    comment = []
    for line in path.read_text(encoding="utf-8").splitlines():
        if not line.startswith("#"):
            break
        comment.append(line.lstrip("#").strip())
    text = " ".join(comment)
    for end in re.finditer(r"[.!?](?=\s+[A-Z(\"]|$)", text):
        if text[:end.start()].rsplit(" ", 1)[-1] not in _ABBREVIATIONS:
            return text[:end.end()]
    return text


check_public(globals())
