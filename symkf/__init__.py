"""symkf: exact, certified stability of multi-sensor Kalman filtering over lossy networks.

Every public name is imported on first use (PEP 562 module ``__getattr__``): ``import symkf``
itself loads no sympy, numpy or scipy, so ``symkf --version`` and ``symkf --help`` answer at
once and an application subpackage (``capacity``, ``fusion``, ...) costs only when it is used.
``benchmarks/bench_import.py`` measures both ``import symkf`` and the first use of the core
against ``import sympy``.
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import TYPE_CHECKING, Any

from .errors import SymkfError

if TYPE_CHECKING:
    from . import capacity, control, examples, fusion, montecarlo, network, second_order, tables
    from .bounds import bounds
    from .exact.algebraic import AlgebraicNumber
    from .families import load_family
    from .losses import IID, GilbertElliott, Independent, MarkovLoss
    from .model import Sensor, System
    from .region import StabilityRegion, stability_conditions, stability_region
    from .spectral import eigen_blocks, eigenvalues
    from .stability import (Verdict, critical_alpha, critical_loss_rate, critical_recovery_rate, stability,
                            stable_recovery_intervals)
    from .simulation import Simulation, simulate
    from .sweep import sweep
    from .verify import FamilyVerification, Verification, verify, verify_family

__version__ = "0.1.0"

#: subpackages imported on first attribute access
_SUBMODULES = {"capacity", "control", "examples", "fusion", "montecarlo", "network", "second_order", "tables"}
#: public names imported on first access, with the module that defines them
_LAZY = {"AlgebraicNumber": "exact.algebraic", "IID": "losses", "GilbertElliott": "losses",
         "MarkovLoss": "losses", "Independent": "losses", "Sensor": "model", "System": "model", "eigen_blocks": "spectral",
         "eigenvalues": "spectral", "Verdict": "stability", "critical_alpha": "stability",
         "critical_loss_rate": "stability", "critical_recovery_rate": "stability", "stability": "stability",
         "stable_recovery_intervals": "stability", "load_family": "families", "StabilityRegion": "region",
         "bounds": "bounds",
         "stability_conditions": "region", "stability_region": "region", "sweep": "sweep",
         "verify": "verify", "verify_family": "verify", "Verification": "verify", "FamilyVerification": "verify",
         "simulate": "simulation", "Simulation": "simulation"}

__all__ = ["SymkfError", "System", "Sensor", "IID", "GilbertElliott", "MarkovLoss", "Independent", "AlgebraicNumber",
           "eigen_blocks", "eigenvalues", "stability", "Verdict", "critical_loss_rate", "critical_alpha",
           "critical_recovery_rate", "stable_recovery_intervals", "stability_region", "stability_conditions",
           "StabilityRegion", "sweep", "load_family", "bounds", "verify", "verify_family", "Verification",
           "FamilyVerification", "simulate", "Simulation",
           "capacity", "fusion", "montecarlo", "network", "second_order", "tables"]

def __getattr__(name: str) -> Any:
    if name in _SUBMODULES:
        value = importlib.import_module(f".{name}", __name__)
    elif name in _LAZY:
        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    else:
        raise AttributeError(f"module 'symkf' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The public API only (not this module's own imports)."""
    return sorted({*__all__, *_SUBMODULES, *_LAZY, "__version__"})


class _Package(types.ModuleType):
    """The functions ``stability`` and ``sweep`` share their names with their modules: importing
    ``symkf.stability`` must not rebind ``symkf.stability`` to the module (eager imports used to
    rebind it right after)."""

    def __setattr__(self, name: str, value: Any) -> None:
        if not (isinstance(value, types.ModuleType) and _LAZY.get(name) == name):
            super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
