"""Progress bars (tqdm) for long work: shown on a terminal, quiet otherwise."""

from __future__ import annotations

import sys

from tqdm import tqdm


def progress(total: int, desc: str, *, enabled: bool | None = None) -> tqdm:
    """A tqdm bar over ``total`` steps on stderr: shown when ``enabled``, or (``None``, the
    default) only when stderr is a terminal."""
    show = sys.stderr.isatty() if enabled is None else enabled
    return tqdm(total=total, desc=desc, disable=not show, leave=False)
