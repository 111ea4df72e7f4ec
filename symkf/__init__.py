"""symkf: exact, certified stability of multi-sensor Kalman filtering over lossy networks."""

from . import capacity, fusion, montecarlo, network, second_order, tables
from .errors import SymkfError
from .exact.algebraic import AlgebraicNumber
from .families import load_family
from .losses import IID, GilbertElliott, MarkovLoss
from .model import Sensor, System
from .region import StabilityRegion, stability_conditions, stability_region
from .spectral import eigen_blocks, eigenvalues
from .stability import (Verdict, critical_alpha, critical_loss_rate, critical_recovery_rate, stability,
                        stable_recovery_intervals)
from .sweep import sweep

__all__ = ["SymkfError", "System", "Sensor", "IID", "GilbertElliott", "MarkovLoss", "AlgebraicNumber",
           "eigen_blocks", "eigenvalues", "stability", "Verdict", "critical_loss_rate", "critical_alpha",
           "critical_recovery_rate", "stable_recovery_intervals", "stability_region", "stability_conditions",
           "StabilityRegion", "sweep", "load_family",
           "capacity", "fusion", "montecarlo", "network", "second_order", "tables"]
__version__ = "0.1.0"
