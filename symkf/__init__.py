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
    from . import capacity, control, design, fusion, network
    from .io import examples
    from .numeric import montecarlo
    from .engine import second_order
    from .reports import tables
    from .bounds import bounds
    from .exact.algebraic import AlgebraicNumber
    from .io.families import load_family
    from .model.gilbert_elliott import GilbertElliott
    from .model.iid import IID
    from .model.independent import Independent
    from .model.subsets import Selected
    from .model.markov import MarkovLoss
    from .model.system import Actuator, Sensor, System
    from .engine.region import StabilityRegion, stability_conditions, stability_region
    from .exact.spectral import eigen_blocks, eigenvalues
    from .engine.recovery import critical_recovery_rate, stable_recovery_intervals
    from .engine.stability import Verdict, critical_alpha, critical_loss_rate, stability
    from .numeric.simulation import Simulation, simulate
    from .run.sweep import sweep
    from .io.family_verification import FamilyVerification, verify_family
    from .numeric.verify import Verification, verify

__version__ = "0.1.0"

#: subpackages imported on first attribute access, with their modules
_SUBMODULES = {"capacity": "capacity", "control": "control", "design": "design", "examples": "io.examples", "fusion": "fusion",
               "montecarlo": "numeric.montecarlo", "network": "network", "second_order": "engine.second_order",
               "tables": "reports.tables"}
#: public names imported on first access, with the module that defines them
_LAZY = {"AlgebraicNumber": "exact.algebraic", "IID": "model.iid", "GilbertElliott": "model.gilbert_elliott",
         "MarkovLoss": "model.markov", "Independent": "model.independent", "Selected": "model.subsets", "Sensor": "model.system", "Actuator": "model.system",
         "System": "model.system",
         "eigen_blocks": "exact.spectral", "eigenvalues": "exact.spectral", "Verdict": "engine.stability",
         "critical_alpha": "engine.stability", "critical_loss_rate": "engine.stability",
         "critical_recovery_rate": "engine.recovery", "stability": "engine.stability",
         "stable_recovery_intervals": "engine.recovery", "load_family": "io.families",
         "StabilityRegion": "engine.region", "bounds": "bounds", "stability_conditions": "engine.region",
         "stability_region": "engine.region", "sweep": "run.sweep", "verify": "numeric.verify",
         "verify_family": "io.family_verification", "Verification": "numeric.verify", "FamilyVerification": "io.family_verification",
         "simulate": "numeric.simulation", "Simulation": "numeric.simulation"}

__all__ = ["SymkfError", "System", "Sensor", "Actuator", "IID", "GilbertElliott", "MarkovLoss", "Independent", "Selected", "AlgebraicNumber",
           "eigen_blocks", "eigenvalues", "stability", "Verdict", "critical_loss_rate", "critical_alpha",
           "critical_recovery_rate", "stable_recovery_intervals", "stability_region", "stability_conditions",
           "StabilityRegion", "sweep", "load_family", "bounds", "verify", "verify_family", "Verification",
           "FamilyVerification", "simulate", "Simulation",
           "capacity", "control", "design", "fusion", "montecarlo", "network", "second_order", "tables"]

def __getattr__(name: str) -> Any:
    if name in _SUBMODULES:
        if name == "tables":   # the published bounds register their family query (compute = ["bounds"])
            importlib.import_module(".bounds", __name__)
        value = importlib.import_module(f".{_SUBMODULES[name]}", __name__)
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
    """``symkf.bounds`` is both the atlas function and its subpackage: importing a module of the
    subpackage must not rebind the function to the package."""

    def __setattr__(self, name: str, value: Any) -> None:
        if not (isinstance(value, types.ModuleType) and _LAZY.get(name) == name):
            super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
