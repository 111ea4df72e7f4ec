"""Output files that never destroy data: the one writer of every file symkf writes.

A target is checked by :func:`plan` (the command line plans its outputs before the computation
starts) and written by :meth:`Planned.write` (:meth:`~Planned.put_text`, :meth:`~Planned.put_figure`;
:func:`write_text` and :func:`save_figure` plan and write at once):

* refused at once: an empty path, a missing or unwritable directory, a directory, device or
  FIFO, a symbolic link (a write never goes through a link, nor replaces one; a linked directory
  on the way is the user's own and followed), a file name longer
  than the file system allows, and any *input* of the run, whatever path names it (compared by
  device and inode, which also catches hard links, and by resolved path);
* an existing output is replaced (rerunning a command overwrites its own result), but not when
  the target appeared or changed after the run started or the target was planned: two
  concurrent runs writing the same file never silently clobber each other (``force=True``,
  ``--force`` on the command line, replaces it anyway);
* the content goes to a temporary file in the target's directory, is flushed to disk and
  renamed over the target (atomic on POSIX); a new file is put in place with :func:`os.link`,
  which fails if the name was taken meanwhile.  A write that fails midway (``EFBIG`` under
  ``ulimit -f``, ``ENOSPC``, ``EACCES``, ...) or is interrupted leaves the previous file as it was
  and no partial file, and raises :class:`~symkf.errors.OutputError` naming the file;
* the path actually written is returned (a plot path without a known image extension is
  written as PNG to exactly that path, not to ``path + ".png"``).

A *run* is the scope of one command (:func:`run`; the command line opens one per command):
the files it reads (:func:`note_input`, called by the TOML reader) are its inputs, and a target
that changed after it started is refused.  Outside a :func:`run` block, the process is one run
whose start is each target's planning.

Every public result and model object is also a JSON document: :class:`JsonDocument` gives it
``to_dict()``, the strict JSON text (:func:`json_text`) of its ``to_dict()``.
"""

from __future__ import annotations

import contextlib
import errno
import gzip
import json
import math
import os
import reprlib
import secrets
import stat
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any, Callable, Iterable, Iterator

from .arguments import check_public
from .errors import InputError, OutputError

def finite(value: Any) -> Any:
    """``value`` with every non-finite float as the string ``"Infinity"``, ``"-Infinity"`` or ``"NaN"``:
    strict JSON has no such numbers (a diverging filter's traces overflow)."""
    if isinstance(value, float) and not math.isfinite(value):
        return "NaN" if math.isnan(value) else ("Infinity" if value > 0 else "-Infinity")
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    return value


def json_text(value: Any, indent: int | None = 2) -> str:
    """``value`` as strict JSON text: non-finite floats as strings (:func:`finite`), any other
    non-JSON value (an exact sympy number) as its ``str``."""
    if indent is not None and (isinstance(indent, bool) or not isinstance(indent, int) or not 0 <= indent <= 16):
        raise InputError(f"indent: expected None or an int from 0 to 16 (spaces), got {indent!r:.60}")
    return json.dumps(finite(value), indent=indent, default=str, allow_nan=False)


class JsonDocument:
    """A public object's JSON forms: ``to_dict()`` (the subclass's, a dict of JSON values) and
    ``to_json(indent=2)``, its text."""

    __slots__ = ()

    def to_dict(self) -> dict[str, Any]:
        raise NotImplementedError

    def to_json(self, indent: int | None = 2) -> str:
        """The JSON text of :meth:`to_dict` (strict JSON: ``json.loads`` reads it back)."""
        return json_text(self.to_dict(), indent)


#: image formats matplotlib writes, by extension; any other extension is written as PNG
IMAGE_FORMATS = ("png", "pdf", "svg", "svgz", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp", "pgf")

#: the metadata that makes matplotlib's vector formats date-free (it writes the time of saving)
UNDATED = {"svg": {"Date": None}, "svgz": {"Date": None}, "pdf": {"CreationDate": None}}

#: errors of os.link meaning "this file system has no hard links", not "the name is taken"
_NO_LINKS = {errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EMLINK, errno.ENOSYS, errno.EXDEV}


@dataclass(frozen=True)
class _Identity:
    """What distinguishes one state of a file from another: its inode, and its change time."""

    dev: int
    ino: int
    ctime_ns: int

    @classmethod
    def of(cls, st: os.stat_result) -> _Identity:
        return cls(st.st_dev, st.st_ino, st.st_ctime_ns)


@dataclass
class _Run:
    """The inputs read, the files written and the start (None: each plan's own time) of a run."""

    started_ns: int | None = None
    inputs: dict[tuple[int, int], str] = field(default_factory=dict)
    resolved_inputs: dict[str, str] = field(default_factory=dict)
    written: set[_Identity] = field(default_factory=set)


_RUN = _Run()


@contextlib.contextmanager
def run(inputs: Iterable[str | os.PathLike] = ()) -> Iterator[None]:
    """One run (a command): ``inputs`` and every file read inside are protected from being
    written over, and a target that appears or changes after the start is refused.  "After" is
    read from the file's change time, which file systems stamp from a coarse clock: a change
    within about a timer tick (1-10 ms on Linux) of the start may pass as before it."""
    global _RUN
    saved, _RUN = _RUN, _Run(started_ns=time.time_ns())
    try:
        for source in inputs:
            note_input(source)
        yield
    finally:
        _RUN = saved


def note_input(path: str | os.PathLike) -> None:
    """Record ``path`` as an input of the current run: no output may be written over it."""
    if not isinstance(path, (str, os.PathLike)):
        return
    with contextlib.suppress(OSError, ValueError, TypeError):
        st = os.stat(path)
        _RUN.inputs[(st.st_dev, st.st_ino)] = str(path)
    with contextlib.suppress(OSError, ValueError, TypeError, RuntimeError):
        _RUN.resolved_inputs[str(Path(path).resolve())] = str(path)


@dataclass(frozen=True)
class Planned:
    """A checked output target: ``path`` named by ``option``; ``before`` is the target as it was
    when planned (None: absent), ``force`` replaces it even if it changed since."""

    path: Path
    option: str
    before: _Identity | None = None
    force: bool = False

    @property
    def image_format(self) -> str:
        """The image format of :attr:`path` (its extension when matplotlib knows it, else png)."""
        suffix = self.path.suffix.lower().lstrip(".")
        return suffix if suffix in IMAGE_FORMATS else "png"

    def write(self, fill: Callable[[IO[bytes]], None]) -> Path:
        """Write what ``fill`` writes to a binary file object into :attr:`path`, atomically."""
        where = f"{self.option} {_shown(self.path)}"
        if not callable(fill):
            raise OutputError(f"{where}: expected a function filling the file, got {type(fill).__name__}")
        try:
            fd, tmp = _temporary(self.path)
        except OSError as exc:
            raise OutputError(f"{where}: cannot write ({_reason(exc)}); nothing was written") from None
        try:
            with os.fdopen(fd, "wb") as f:
                fill(f)
                f.flush()
                os.fsync(f.fileno())
            self._put_in_place(tmp, where)
        except OSError as exc:
            Path(tmp).unlink(missing_ok=True)
            raise OutputError(f"{where}: cannot write ({_reason(exc)}); "
                              "the previous file, if any, is unchanged and no partial file is left") from None
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        _sync_directory(self.path.parent)
        with contextlib.suppress(OSError):
            _RUN.written.add(_Identity.of(os.lstat(self.path)))
        return self.path

    def _put_in_place(self, tmp: str, where: str) -> None:
        """Rename ``tmp`` to :attr:`path`, unless another writer took or changed it since planning."""
        current = _lstat(self.path)
        if not self.force and current is not None and _Identity.of(current) != self.before:
            raise _concurrent(self.option, where,
                              f"{'appeared' if self.before is None else 'changed'} while this run was computing")
        if self.before is None and not self.force:
            try:  # the name is taken atomically: a writer that got there first is never replaced
                os.link(tmp, self.path)
            except FileExistsError:
                raise _concurrent(self.option, where, "appeared while this run was computing") from None
            except OSError as exc:
                if exc.errno not in _NO_LINKS:
                    raise
                os.replace(tmp, self.path)
            else:
                os.unlink(tmp)
        else:
            os.replace(tmp, self.path)

    def put_text(self, text: str) -> Path:
        """Write ``text`` (UTF-8) into :attr:`path`, atomically."""
        if not isinstance(text, str):
            raise OutputError(f"{self.option} {_shown(self.path)}: expected text, got {type(text).__name__}")
        return self.write(lambda f: f.write(text.encode("utf-8")))

    def put_figure(self, figure: Any, **savefig: Any) -> Path:
        """Write a matplotlib ``figure`` into :attr:`path` in :attr:`image_format`, atomically;
        the same figure gives the same bytes: matplotlib's vector formats carry the time of saving
        and random ids, so SVG and PDF are written without a date (:data:`UNDATED`) and with SVG
        ids from a fixed salt, PostScript dated by ``SOURCE_DATE_EPOCH`` (0 unless set: it has no
        other way), compressed SVG with a zero gzip time stamp."""
        if not callable(getattr(figure, "savefig", None)):
            raise OutputError(f"{self.option} {self.path}: expected a matplotlib figure, got {type(figure).__name__}")
        import matplotlib
        fmt = self.image_format
        if fmt in UNDATED:
            savefig["metadata"] = {**UNDATED[fmt], **(savefig.get("metadata") or {})}

        def fill(f: IO[bytes]) -> None:
            if fmt == "svgz":
                with gzip.GzipFile(filename="", fileobj=f, mode="wb", mtime=0) as zipped:
                    figure.savefig(zipped, format="svg", **savefig)
            else:
                figure.savefig(f, format=fmt, **savefig)

        with matplotlib.rc_context({"svg.hashsalt": "symkf"}), _source_date(fmt in ("ps", "eps")):
            return self.write(fill)


@contextlib.contextmanager
def _source_date(needed: bool) -> Iterator[None]:
    """``SOURCE_DATE_EPOCH=0`` while ``needed`` (unless the environment sets it: its date wins)."""
    if not needed or "SOURCE_DATE_EPOCH" in os.environ:
        yield
        return
    os.environ["SOURCE_DATE_EPOCH"] = "0"
    try:
        yield
    finally:
        os.environ.pop("SOURCE_DATE_EPOCH", None)


def plan(path: Any, option: str, *, inputs: Iterable[str | os.PathLike] = (),
         force: bool = False, keep_existing: bool = False) -> Planned:
    """Check ``path`` as the target of ``option`` before any work is done (module docstring);
    ``inputs`` are protected besides the run's own.  ``keep_existing``: the target is a file the
    user edits (a copied example), so an existing one is replaced only with ``force``."""
    target = _path(path, option, "a file path")
    where = f"{option} {_shown(target)}"
    for source in inputs:
        note_input(source)
    try:
        directory = target.parent   # a symbolic link to a directory is the user's own: followed
        if not directory.is_dir():
            raise OutputError(f"{where}: {_not_a_directory(directory)}")
        limit = _name_max(directory)
        if len(os.fsencode(target.name)) > limit:
            raise OutputError(f"{where}: the file name is {len(os.fsencode(target.name))} bytes, "
                              f"above the file system's limit of {limit}")
        current = _lstat(target)
        if current is not None:
            _refuse_existing(target, current, where)
        if not os.access(directory, os.W_OK | os.X_OK):
            raise OutputError(f"{where}: the directory {directory} is not writable")
        source = _RUN.resolved_inputs.get(str(target.resolve()))
    except OSError as exc:
        raise OutputError(f"{where}: cannot use as an output ({_reason(exc)})") from None
    if source is not None:
        raise OutputError(f"{where}: is the input file {source}; refusing to overwrite an input")
    before = None if current is None else _Identity.of(current)
    if before is not None and keep_existing and not force:
        raise OutputError(f"{where}: exists (perhaps edited); {_force(option)} to replace it")
    started = _RUN.started_ns
    if (before is not None and not force and started is not None and before.ctime_ns > started
            and before not in _RUN.written):
        raise _concurrent(option, where, "was created or changed after this run started")
    return Planned(target, option, before, force)


def _force(option: str) -> str:
    """How the caller replaces a file anyway, in its own terms: ``--force`` where the target is a
    command-line option or argument (``--latex``, ``NAME``), ``force=True`` where it is a parameter."""
    return "pass --force" if option.startswith("-") or option.isupper() else "pass force=True"


def _concurrent(option: str, where: str, what: str) -> OutputError:
    return OutputError(f"{where}: {what} (another run writing the same file?); not replaced: {_force(option)} "
                       "to replace it anyway, or choose another path")


def _refuse_existing(target: Path, st: os.stat_result, where: str) -> None:
    """An existing target may be replaced only when it is a regular file and no input of the run."""
    if stat.S_ISLNK(st.st_mode):
        raise OutputError(f"{where}: is a symbolic link (to {os.readlink(target)}); symkf neither writes "
                          "through a link nor replaces one: remove it or choose another path")
    if not stat.S_ISREG(st.st_mode):
        raise OutputError(f"{where}: exists and is not a regular file")
    source = _RUN.inputs.get((st.st_dev, st.st_ino))
    if source is not None:
        linked = st.st_nlink > 1 and os.path.realpath(source) != os.path.realpath(target)
        raise OutputError(f"{where}: is the input file {source}{' (a hard link to it)' if linked else ''}; "
                          "refusing to overwrite an input")


def write_text(path: Any, text: str, option: str = "path", *, force: bool = False) -> Path:
    """:func:`plan` ``path`` and write ``text`` (UTF-8) into it, atomically."""
    return plan(path, option, force=force).put_text(text)


def save_figure(figure: Any, path: Any, option: str = "path", *, force: bool = False,
                **savefig: Any) -> Path:
    """:func:`plan` ``path`` and write the matplotlib ``figure`` into it, atomically (its format
    from the extension, PNG when the extension names no image format)."""
    return plan(path, option, force=force).put_figure(figure, **savefig)


def plan_directory(path: Any, option: str) -> Path:
    """Check (and create) the output directory of ``option`` before any work is done."""
    directory = _path(path, option, "a directory path")
    if os.path.lexists(directory) and not directory.is_dir():
        raise OutputError(f"{option} {directory}: {_not_a_directory(directory)}")
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{option} {directory}: cannot create the directory ({_reason(exc)})") from None
    if not os.access(directory, os.W_OK | os.X_OK):
        raise OutputError(f"{option} {directory}: the directory is not writable")
    return directory


def _not_a_directory(directory: Path) -> str:
    """Why ``directory``, which is not a directory, cannot hold an output."""
    missing = not os.path.exists(directory)
    if os.path.islink(directory):
        shown = f"{directory} (a symbolic link"
        with contextlib.suppress(OSError):   # replaced meanwhile: then its target is not named
            shown += f" to {os.readlink(directory)}"
        return f"the directory {shown}) " + ("does not exist" if missing else "is not a directory")
    return f"the directory {directory} does not exist" if missing else f"{directory} is not a directory"


def _path(path: Any, option: str, what: str) -> Path:
    """``path`` as a Path: a non-empty str or os.PathLike of one, without NUL characters."""
    text = os.fspath(path) if isinstance(path, (str, os.PathLike)) else None
    if not isinstance(text, str) or not text or "\0" in text:
        raise OutputError(f"{option}: expected {what}, got {_shown(reprlib.repr(path))}")
    return Path(text)


def _temporary(path: Path) -> tuple[int, str]:
    """A new file beside ``path``, open for writing, with the permissions of a file the user
    creates (0666 less the umask, applied by the kernel: no process-wide umask juggling)."""
    for _ in range(100):
        name = os.path.join(path.parent, f".{path.name[:32]}.{secrets.token_hex(4)}.part")
        try:
            return os.open(name, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666), name
        except FileExistsError:
            continue
    raise FileExistsError(errno.EEXIST, "no free temporary name", str(path.parent))


def _lstat(path: Path) -> os.stat_result | None:
    try:
        return os.lstat(path)
    except FileNotFoundError:
        return None


def _name_max(directory: Path) -> int:
    """The longest file name (bytes) the file system of ``directory`` takes (255 if it does not say)."""
    try:
        return os.pathconf(directory, "PC_NAME_MAX")
    except (OSError, ValueError):
        return 255


def _shown(path: Path | str) -> str:
    """``path`` for a message: a very long one is cut in the middle."""
    text = str(path)
    return text if len(text) <= 160 else f"{text[:100]}...{text[-40:]} ({len(text)} characters)"


def _sync_directory(directory: Path) -> None:
    """Make the rename durable (a crash right after it keeps the new name); best effort."""
    with contextlib.suppress(OSError):
        fd = os.open(directory, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _reason(exc: OSError) -> str:
    return exc.strerror or type(exc).__name__


# the target path is left to _path, whose refusal names the option (--latex, --outdir)
check_public(globals())
