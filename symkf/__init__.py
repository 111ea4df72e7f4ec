"""symkf: exact, certified stability of multi-sensor Kalman filtering over lossy networks."""

from . import capacity, fusion, network
from .errors import SymkfError
from .exact.algebraic import AlgebraicNumber
from .losses import IID, GilbertElliott, MarkovLoss
from .model import Sensor, System
from .spectral import eigen_blocks, eigenvalues
from .stability import Verdict, critical_alpha, critical_loss_rate, stability

__all__ = ["SymkfError", "System", "Sensor", "IID", "GilbertElliott", "MarkovLoss", "AlgebraicNumber",
           "eigen_blocks", "eigenvalues", "stability", "critical_loss_rate", "critical_alpha", "Verdict",
           "capacity", "fusion", "network"]
__version__ = "0.1.0"
