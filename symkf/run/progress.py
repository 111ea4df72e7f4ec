"""Progress bars (tqdm) for long work: shown on a terminal or in a notebook, quiet otherwise.

In a Jupyter kernel the bar is a widget when ipywidgets is installed; without it there is no
bar at all (tqdm's text fallback would put ``IProgress not found`` warnings and text bars on
the notebook's stderr).
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time
from typing import Callable, Iterator

from tqdm.std import tqdm

from ..arguments import check_public


def progress(total: int, desc: str, *, enabled: bool | None = None) -> tqdm:
    """A tqdm bar over ``total`` steps on stderr (a widget in Jupyter): shown when ``enabled``, or
    (``None``, the default) when stderr is a terminal or a Jupyter kernel runs, unless the
    environment sets ``TQDM_DISABLE`` (as ``symkf --quiet`` does)."""
    show = _interactive() if enabled is None else enabled
    bar = _bar_class()
    return (bar or tqdm)(total=total, desc=desc, disable=not show or bar is None, leave=False)


def _bar_class() -> type[tqdm] | None:
    """The bar for where we run: a widget in a Jupyter kernel with ipywidgets, none in a kernel
    without it, tqdm's text bar elsewhere."""
    if "ipykernel" not in sys.modules:
        return tqdm
    try:
        import ipywidgets  # noqa: F401
    except ImportError:
        return None
    from tqdm.notebook import tqdm as widget
    return widget


def _interactive() -> bool:
    if os.environ.get("TQDM_DISABLE", "").strip().lower() not in ("", "0", "false"):
        return False
    return sys.stderr.isatty() or "ipykernel" in sys.modules


@contextlib.contextmanager
def compiling(what: str, *, after: float = 1.0, enabled: bool | None = None) -> Iterator[None]:
    """Work that is slow only the first time (a compiled kernel: numba compiles it once per
    installation and loads it from its cache after): one line on stderr naming ``what`` when it
    takes longer than ``after`` seconds, so that a first run does not sit silent.  Shown when
    ``enabled``, or (``None``) on a terminal or in a notebook."""
    def report(done: threading.Event) -> None:
        if not done.wait(after):
            print(f"compiling {what} (numba, once per installation; `symkf warm` compiles ahead)...",
                  file=sys.stderr, flush=True)

    with _reporting(report, _interactive() if enabled is None else enabled):
        yield


@contextlib.contextmanager
def still_working(desc: str, *, after: float = 2.0, every: float = 10.0,
                  enabled: bool | None = None) -> Iterator[None]:
    """Long work without natural steps (eigen-blocks, hyperplane enumeration): after ``after``
    seconds, a line on stderr every ``every`` seconds naming ``desc`` and the elapsed time.
    Shown when ``enabled``, or (``None``) when stderr is a terminal."""
    start = time.monotonic()

    def report(done: threading.Event) -> None:
        wait = after
        while not done.wait(wait):
            print(f"{desc}: still working, {time.monotonic() - start:.0f} s", file=sys.stderr, flush=True)
            wait = every

    with _reporting(report, _interactive() if enabled is None else enabled):
        yield


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
