"""Progress bars (tqdm) for long work: shown on a terminal or in a notebook, quiet otherwise."""

from __future__ import annotations

import os
import sys

from tqdm.auto import tqdm


def progress(total: int, desc: str, *, enabled: bool | None = None) -> tqdm:
    """A tqdm bar over ``total`` steps on stderr (a widget in Jupyter): shown when ``enabled``, or
    (``None``, the default) when stderr is a terminal or a Jupyter kernel runs, unless the
    environment sets ``TQDM_DISABLE`` (as ``symkf --quiet`` does)."""
    show = _interactive() if enabled is None else enabled
    return tqdm(total=total, desc=desc, disable=not show, leave=False)


def _interactive() -> bool:
    if os.environ.get("TQDM_DISABLE", "").strip().lower() not in ("", "0", "false"):
        return False
    return sys.stderr.isatty() or "ipykernel" in sys.modules
