"""Progress bars (tqdm) for long work: shown on a terminal, quiet otherwise."""

from __future__ import annotations

import contextlib
import sys
import threading
import time
from typing import Iterator

from tqdm import tqdm


def progress(total: int, desc: str, *, enabled: bool | None = None) -> tqdm:
    """A tqdm bar over ``total`` steps on stderr: shown when ``enabled``, or (``None``, the
    default) only when stderr is a terminal."""
    show = sys.stderr.isatty() if enabled is None else enabled
    return tqdm(total=total, desc=desc, disable=not show, leave=False)


@contextlib.contextmanager
def still_working(desc: str, *, after: float = 2.0, every: float = 10.0,
                  enabled: bool | None = None) -> Iterator[None]:
    """Long work without natural steps (eigen-blocks, hyperplane enumeration): after ``after``
    seconds, a line on stderr every ``every`` seconds naming ``desc`` and the elapsed time.
    Shown when ``enabled``, or (``None``) when stderr is a terminal."""
    show = sys.stderr.isatty() if enabled is None else enabled
    done = threading.Event()
    start = time.monotonic()

    def report() -> None:
        wait = after
        while not done.wait(wait):
            print(f"{desc}: still working, {time.monotonic() - start:.0f} s", file=sys.stderr, flush=True)
            wait = every

    thread = threading.Thread(target=report, daemon=True) if show else None
    if thread is not None:
        thread.start()
    try:
        yield
    finally:
        done.set()
        if thread is not None:
            thread.join()
