"""Output files that never destroy data.

Every file the command line writes goes through :func:`plan` *before* the computation starts
and through :meth:`Planned.write` after it:

* the target is refused at once when it is an input file, a directory or a device, when its
  directory is missing or not writable, or when it exists and ``--force`` was not given;
* the content is written to a temporary file in the target's directory and renamed over the
  target (atomic on POSIX): a write that fails midway (disk full, ``ulimit -f``) leaves the
  old file untouched and no partial file behind;
* the path actually written is returned (a plot path without a known image extension is
  written as PNG to exactly that path, not to ``path + ".png"``).
"""

from __future__ import annotations

import os
import stat
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Callable, Iterable

from .exact.arguments import check_public
from .errors import OutputError

#: image formats matplotlib writes, by extension; any other extension is written as PNG
IMAGE_FORMATS = ("png", "pdf", "svg", "svgz", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp", "pgf")


@dataclass(frozen=True)
class Planned:
    """A checked output target: ``path`` named by the command-line ``option``."""

    path: Path
    option: str

    @property
    def image_format(self) -> str:
        """The image format of :attr:`path` (its extension when matplotlib knows it, else png)."""
        suffix = self.path.suffix.lower().lstrip(".")
        return suffix if suffix in IMAGE_FORMATS else "png"

    def write(self, fill: Callable[[IO[bytes]], None]) -> Path:
        """Write what ``fill`` writes to a binary file object into :attr:`path`, atomically."""
        directory = self.path.parent
        fd, tmp = tempfile.mkstemp(dir=directory, prefix=f".{self.path.name}.", suffix=".part")
        try:
            with os.fdopen(fd, "wb") as f:
                fill(f)
                f.flush()
                os.fsync(f.fileno())
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
            os.replace(tmp, self.path)
        except OSError as exc:
            Path(tmp).unlink(missing_ok=True)
            raise OutputError(f"{self.option} {self.path}: cannot write ({exc.strerror or exc}); "
                              "the previous file, if any, is unchanged") from None
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        return self.path

    def write_text(self, text: str) -> Path:
        """Write ``text`` (UTF-8) into :attr:`path`, atomically."""
        return self.write(lambda f: f.write(text.encode("utf-8")))


def plan(path: str | os.PathLike, option: str, *, inputs: Iterable[str | os.PathLike] = (),
         force: bool = False) -> Planned:
    """Check ``path`` as the target of ``option`` before any work is done (module docstring)."""
    target = Path(path)
    where = f"{option} {target}"
    for source in inputs:
        if _same(target, Path(source)):
            raise OutputError(f"{where}: is the input file {source}; refusing to overwrite an input")
    try:  # a name too long, or a component that is not a directory, fails the probe itself
        present = target.exists() or target.is_symlink()
    except OSError as exc:
        raise OutputError(f"{where}: not a usable path ({exc.strerror or exc})") from None
    if present:
        mode = target.stat().st_mode if target.exists() else 0
        if not stat.S_ISREG(mode):
            raise OutputError(f"{where}: exists and is not a regular file")
        if not force:
            raise OutputError(f"{where}: exists; pass --force to replace it")
    directory = target.parent
    if not directory.is_dir():
        raise OutputError(f"{where}: the directory {directory} does not exist")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise OutputError(f"{where}: the directory {directory} is not writable")
    return Planned(target, option)


def plan_directory(path: str | os.PathLike, option: str) -> Path:
    """Check (and create) the output directory of ``option`` before any work is done."""
    directory = Path(path)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{option} {directory}: cannot create the directory ({exc.strerror or exc})") from None
    if not os.access(directory, os.W_OK | os.X_OK):
        raise OutputError(f"{option} {directory}: the directory is not writable")
    return directory


def _same(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return a.resolve() == b.resolve()

check_public(globals())
