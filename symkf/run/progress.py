"""Progress of long work: one reporter per piece of work, drawn by tqdm on a terminal (a widget in a
Jupyter kernel with ipywidgets), as plain throttled lines where no bar can be drawn, or not at all.

A reporter opened while another is open in the same thread is its *child*: it draws nothing and
moves its parent through the parent's next step (or through the steps of :meth:`Progress.part`),
so a family's bar advances with each member's simulated paths, not only when a member ends.
Notes (:func:`note`: a "still working" or "compiling" line, a finished worker's task) go on
lines of their own, above a bar that is redrawn after them.  Work running in a worker process (or
a thread of a Dask worker) is :func:`silenced`: only the process that started the work draws,
so no two bars fight over one terminal's cursor.

Where progress shows (``enabled=None``): a bar when stderr is a terminal, a widget in a Jupyter
kernel with ipywidgets, plain lines on stdout in a kernel without it (tqdm's text fallback would
put ``IProgress not found`` warnings and carriage returns into the notebook); nowhere when the
environment sets ``TQDM_DISABLE`` (as ``symkf --quiet`` does) or stderr is a file or a pipe.
``enabled=True`` shows plain lines where no bar can be drawn; plain lines carry no control code.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time
from typing import Any, Callable, Iterator

from tqdm.std import tqdm

from ..arguments import check_public

#: seconds between plain lines (a bar is redrawn every REDRAW seconds, so its elapsed time moves)
EVERY = 10.0
#: seconds before the first plain line: short work stays silent
AFTER = 2.0
REDRAW = 1.0

_local = threading.local()
#: the reporters drawing now, in any thread (notes go above the newest)
_shown: list["Progress"] = []
_shown_lock = threading.Lock()


class Progress:
    """The progress of ``total`` steps labelled ``desc`` (made by :func:`progress`; a context manager).

    ``update(n)`` completes ``n`` steps; ``fraction`` is the part done, children's included;
    ``disable`` says whether this reporter draws nothing itself (a child, or progress not shown).
    """

    def __init__(self, total: float, desc: str, mode: str | None, file: Any,
                 clock: Callable[[], float], every: float) -> None:
        self.total, self.desc, self.mode = total, desc, mode
        self.file, self.clock, self.every = file, clock, every
        self.n = 0.0
        self._pending = 0.0                  # a child's share of the step(s) it runs in
        self._span = 1.0                     # the steps a child opened now runs through
        self._parent: Progress | None = None
        self._view: _Bar | _Lines | None = None
        self._exit = contextlib.ExitStack()

    @property
    def disable(self) -> bool:
        return self.mode in (None, "child")

    @property
    def fraction(self) -> float:
        """The part of the work done, ``0..1`` (a running child's part of its steps included)."""
        return 1.0 if self.total <= 0 else min(1.0, (self.n + self._pending) / self.total)

    def __enter__(self) -> "Progress":
        stack = _stack()
        if self.mode == "child":
            self._parent = stack[-1]
            self._parent._pending = 0.0
        elif self.mode is not None:
            # shown before its view is built (a tqdm bar takes a while to start): a still_working
            # reporter that wakes meanwhile stays quiet, as it does once the bar draws
            with _shown_lock:
                _shown.append(self)
            self._exit.callback(_forget, self)
            try:
                self._view = (_Lines if self.mode == "lines" else _Bar)(self)
            except BaseException:
                self._exit.close()
                raise
            self._exit.enter_context(_reporting(self._tick, True))
        stack.append(self)
        self._exit.callback(stack.remove, self)
        return self

    def __exit__(self, *exc: Any) -> None:
        self._exit.close()
        if self._view is not None:
            self._view.close()

    def update(self, n: float = 1) -> None:
        """``n`` more steps done."""
        self.n += n
        self._pending = 0.0
        self._changed()

    @contextlib.contextmanager
    def part(self, steps: float) -> Iterator[None]:
        """The next ``steps`` steps, run by the block: a reporter opened inside moves this one
        through them, and they are done when the block ends."""
        self._span = steps
        try:
            yield
        finally:
            self._span = 1.0
        self.update(steps)

    def note(self, text: str) -> None:
        """``text`` on a line of its own, where this reporter's root draws (nothing when it does not)."""
        root = self
        while root._parent is not None:
            root = root._parent
        if root._view is not None:
            root._view.note(text)
        elif root.mode not in (None, "child"):   # shown, its view still being built
            print(text, file=root.file, flush=True)

    def _child_moved(self, fraction: float) -> None:
        self._pending = self._span * fraction
        self._changed()

    def _changed(self) -> None:
        if self._parent is not None:
            self._parent._child_moved(self.fraction)
        elif self._view is not None:
            self._view.show(force=False)

    def _tick(self, done: threading.Event) -> None:
        while not done.wait(max(0.05, min(REDRAW, self.every))):
            self._view.show(force=True)

    def __repr__(self) -> str:
        return f"<Progress {self.desc}: {100 * self.fraction:.0f}% of {self.total}, {self.mode or 'hidden'}>"


class _Bar:
    """A tqdm bar (a widget in a Jupyter kernel) showing the fraction done and the times."""

    def __init__(self, p: Progress) -> None:
        self.p, self.lock, self.last = p, threading.Lock(), -1.0
        kind = tqdm
        if p.mode == "widget":
            from tqdm.notebook import tqdm as kind
        self.bar = kind(total=p.total, desc=p.desc, file=p.file, leave=False, dynamic_ncols=True,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]")

    def show(self, force: bool) -> None:
        with self.lock:
            now = self.p.clock()
            if force or now - self.last >= 0.1 or self.p.fraction >= 1:
                self.last = now
                self.bar.n = self.p.fraction * self.p.total
                self.bar.refresh()

    def note(self, text: str) -> None:
        self.bar.write(text, file=self.p.file)

    def close(self) -> None:
        self.bar.close()


class _Lines:
    """Plain lines ``desc: 40% after 12 s``, the first after :data:`AFTER` seconds and then at
    most one every ``every`` seconds, and ``desc: done after 30 s`` when a line was printed."""

    def __init__(self, p: Progress) -> None:
        self.p, self.lock = p, threading.Lock()
        self.start = p.clock()
        self.due = self.start + min(AFTER, p.every)
        self.printed = False

    def show(self, force: bool) -> None:
        with self.lock:
            now = self.p.clock()
            if now >= self.due:
                self.due = now + self.p.every
                self._print(f"{self.p.desc}: {100 * self.p.fraction:.0f}% after {now - self.start:.0f} s")

    def note(self, text: str) -> None:
        with self.lock:
            self._print(text)

    def close(self) -> None:
        if self.printed:
            self._print(f"{self.p.desc}: done after {self.p.clock() - self.start:.0f} s")

    def _print(self, text: str) -> None:
        self.printed = True
        print(text, file=self.p.file, flush=True)


def progress(total: float, desc: str, *, enabled: bool | None = None, file: Any = None,
             clock: Callable[[], float] | None = None, every: float = EVERY) -> Progress:
    """A :class:`Progress` over ``total`` steps labelled ``desc`` (module docstring: where it shows).

    Inside another reporter of this thread it is that reporter's child, whatever ``enabled``
    says.  ``file``: the stream to draw on (default stderr; stdout for lines in a Jupyter kernel);
    ``clock``: seconds (default :func:`time.monotonic`); ``every``: seconds between plain lines.
    """
    stream = file if file is not None else sys.stderr
    if getattr(_local, "silenced", False):
        mode = None
    elif _stack():
        mode = "child"
    elif not (_interactive(stream) if enabled is None else enabled):
        mode = None
    elif "ipykernel" in sys.modules:
        mode = "widget" if _has_widgets() else "lines"
        stream = stream if file is not None or mode == "widget" else sys.stdout
    else:
        mode = "bar" if _isatty(stream) else "lines"
    return Progress(total, desc, mode, stream, clock or time.monotonic, every)


def note(text: str) -> None:
    """``text`` on stderr on a line of its own: above the bar drawn now (redrawn after it), or
    among the plain lines."""
    with _shown_lock:
        current = _shown[-1] if _shown else None
    if current is None:
        print(text, file=sys.stderr, flush=True)
    else:
        current.note(text)


@contextlib.contextmanager
def silenced() -> Iterator[None]:
    """No progress drawn by this thread while the block runs (a worker's task: its parent draws)."""
    before = getattr(_local, "silenced", False)
    _local.silenced = True
    try:
        yield
    finally:
        _local.silenced = before


def _stack() -> list[Progress]:
    if not hasattr(_local, "stack"):
        _local.stack = []
    return _local.stack


def _forget(p: Progress) -> None:
    with _shown_lock:
        _shown.remove(p)


def _has_widgets() -> bool:
    try:
        import ipywidgets  # noqa: F401
    except ImportError:
        return False
    return True


def _isatty(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):   # no isatty, or a closed stream
        return False


def _interactive(stream: Any = None) -> bool:
    if os.environ.get("TQDM_DISABLE", "").strip().lower() not in ("", "0", "false"):
        return False
    return _isatty(sys.stderr if stream is None else stream) or "ipykernel" in sys.modules


@contextlib.contextmanager
def compiling(what: str, *, after: float = 1.0, enabled: bool | None = None) -> Iterator[None]:
    """Work that is slow only the first time (a compiled kernel: numba compiles it once per
    installation and loads it from its cache after): one note (:func:`note`) naming ``what`` when
    it takes longer than ``after`` seconds, so that a first run does not sit silent.  Shown when
    ``enabled``, or (``None``) on a terminal or in a notebook."""
    def report(done: threading.Event) -> None:
        if not done.wait(after):
            note(f"compiling {what} (numba, once per installation; `symkf warm` compiles ahead)...")

    with _reporting(report, _noting(enabled)):
        yield


@contextlib.contextmanager
def still_working(desc: str, *, after: float = 2.0, every: float = 10.0,
                  enabled: bool | None = None) -> Iterator[None]:
    """Long work without natural steps (eigen-blocks, hyperplane enumeration): after ``after``
    seconds, a line on stderr every ``every`` seconds naming ``desc`` and the elapsed time, except
    while a progress reporter draws (its bar or lines show the elapsed time already).  Shown when
    ``enabled``, or (``None``) when stderr is a terminal."""
    start = time.monotonic()

    def report(done: threading.Event) -> None:
        wait = after
        while not done.wait(wait):
            with _shown_lock:
                drawing = bool(_shown)
            if not drawing:
                note(f"{desc}: still working, {time.monotonic() - start:.0f} s")
            wait = every

    with _reporting(report, _noting(enabled)):
        yield


def _noting(enabled: bool | None) -> bool:
    """Whether notes are printed: when ``enabled``, or (``None``) on a terminal or in a notebook;
    never in a worker (:func:`silenced`), whose notes would land on its parent's bar."""
    return not getattr(_local, "silenced", False) and (_interactive() if enabled is None else enabled)


@contextlib.contextmanager
def _reporting(report: Callable[[threading.Event], None], show: bool) -> Iterator[None]:
    """Run ``report(done)`` in a daemon thread while the block runs (when ``show``); ``done`` is
    set when the block ends, and the thread joined."""
    done = threading.Event()
    thread = threading.Thread(target=report, args=(done,), daemon=True) if show else None
    if thread is not None:
        thread.start()
    try:
        yield
    finally:
        done.set()
        if thread is not None:
            thread.join()


check_public(globals())
