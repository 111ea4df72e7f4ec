"""Exceptions raised on purpose by symkf.

Every error names the entry that caused it, the assumption that failed and,
where one exists, what applies instead.  The command line turns each of them
into a one-line message with exit status 2 (bad input) or 3 (a theorem's
assumptions fail for the given system).
"""

from __future__ import annotations

import importlib
import reprlib
from types import ModuleType


class SymkfError(Exception):
    """Base of every error symkf raises on purpose."""

    exit_status = 2

    def __reduce__(self):
        # rebuilt from the final message and attributes: subclasses' __init__ (e.g.
        # AssumptionError's keyword-only arguments) cannot be replayed from ``args``
        return _rebuild_error, (type(self), self.args, dict(self.__dict__))


class InputError(SymkfError, ValueError):
    """Malformed input: wrong type, shape, or value of a named entry."""


class ArgumentError(InputError, TypeError):
    """A public function called with arguments its signature does not take (one missing, unknown
    or given twice); the message names the function and its signature.  Also a TypeError, as
    Python's own is."""


class InexactInputError(InputError):
    """A binary float that is not exactly its printed decimal reached an exact path (pass
    ``rationalize=True`` or ``rationalize="nearby"`` to the constructor to convert it)."""


class BudgetError(InputError):
    """An input would exceed a resource cap (symkf.budget); the message names the option raising it."""


class OutputError(InputError):
    """An output path cannot be written safely (an input file, a symbolic link, a missing directory, a
    file another run wrote meanwhile, an error of the operating system); the message names it."""


class SchedulerError(InputError):
    """A Dask scheduler cannot be used: unreachable, silent, not a scheduler, without workers, or
    lost mid-run; the message names its address."""


class ShapeError(InputError):
    """Matrix dimensions do not fit together."""


class NotPositiveDefiniteError(InputError):
    """A covariance (Q, R or P0) is not symmetric positive definite."""


class ProbabilityError(InputError):
    """A probability is outside [0, 1] or a transition row does not sum to 1."""


class AssumptionError(SymkfError):
    """A theorem's hypothesis fails for the given system or loss model.

    ``assumption`` names the hypothesis (e.g. "Assumption 6 (Sui-You-Fu)"),
    ``applies_instead`` the entry point that does apply, if any.
    """

    exit_status = 3

    def __init__(self, message: str, *, assumption: str, applies_instead: str | None = None):
        text = f"{assumption} fails: {message}"
        if applies_instead:
            text += f". What applies instead: {applies_instead}"
        super().__init__(text)
        self.assumption = assumption
        self.applies_instead = applies_instead


class UnobservableError(AssumptionError):
    """(A, C) is not detectable: a mode with ``|lambda| >= 1`` that no sensor sees; the mode is named."""


class UncontrollableError(AssumptionError):
    """(A, B) is not stabilizable: a mode with ``|lambda| >= 1`` that no actuator reaches; the mode is named."""


class SingularSystemError(AssumptionError):
    """A is singular where a theorem needs it invertible (Lemma 2, Sui-You-Fu)."""


class AperiodicError(AssumptionError):
    """A computation needs a periodic eigen-block and the block is proved aperiodic."""


class FileFormatError(InputError):
    """A system file (TOML) is malformed; the message names file and key."""


class NumericalBreakdownError(SymkfError):
    """The float64 covariance of a simulated filter lost positive semidefiniteness or overflowed."""


class ExtraNotInstalledError(SymkfError, ImportError):
    """An optional dependency (a pip extra of symkf) is not installed."""


def require_extra(module: str, extra: str, needed_for: str) -> ModuleType:
    """Import and return ``module``, or raise :class:`ExtraNotInstalledError` naming the extra."""
    if not all(isinstance(a, str) and a for a in (module, extra, needed_for)):
        raise InputError("require_extra: module, extra and needed_for must be non-empty strings, got "
                         + ", ".join(reprlib.repr(a) for a in (module, extra, needed_for)))
    try:
        return importlib.import_module(module)
    except ImportError:
        raise ExtraNotInstalledError(f"{needed_for} needs {module.split('.')[0]}: "
                                     f"pip install 'symkf[{extra}]'") from None


def _rebuild_error(cls: type, args: tuple, state: dict) -> SymkfError:
    error = cls.__new__(cls)
    error.args = args
    error.__dict__.update(state)
    return error
